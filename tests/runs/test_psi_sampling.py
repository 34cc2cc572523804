"""The psi data of ``studies/paper_figures.py`` and ``studies/ring_vs_pde.py`` resolve the shear oscillation psi carries.

Closed form, independent of the package: the uniform transverse-shear mode of the natural cylinder. psi tilts the
director (through the wall, of thickness ``2h``: ``h`` is the half-thickness) towards the circumferential direction;
the shear strain is psi, the stored energy ``mu psi^2 / 2`` per unit volume (``2h`` of it per unit area) and the
director's rotary inertia ``rho (2h)^3 / 12`` per unit area, so ``omega^2 = 3 mu / (rho h^2)``: 5,050 rad/s (804 Hz)
at the paper's ``E, nu, rho, h``. Shorter waves along ``s`` and the ring's stretch and spin raise psi's frequencies a
few per cent (the fastest mode at N = 40 is 5,290 rad/s; the ring's psi 820 Hz), so the sampling must put 10
samples in the period of ``1.25 omega``. Saved every 1 ms, psi aliased to 194 Hz (paper scene, s = 0) and 178 Hz
(ring); the dominant frequency of the scripts' psi data must be the closed form's, to the FFT's resolution
``1 / t_end`` and the few per cent above.
"""

import math

import numpy as np
import pytest
from study_scripts import load_script

import mol_shell


def load_study(name):
    return load_script(name, "study_psi")


def shear_frequency(scene):
    """The closed form above, in Hz."""
    mu = scene.E / (2 * (1 + scene.nu))
    return math.sqrt(3 * mu / scene.rho) / scene.h / (2 * math.pi)


def dominant_frequency(values, step):
    values = np.asarray(values) - np.mean(values)
    return np.fft.rfftfreq(values.size, step)[np.argmax(np.abs(np.fft.rfft(values)))]


def test_shear_frequency_closed_form_is_the_reported_one():
    assert abs(shear_frequency(mol_shell.TwistedCylinder()) - 804) < 1


def test_paper_figures_psi_samples_put_ten_in_the_shear_period_and_find_its_frequency():
    """N = 10, 0.03 s at the paper's dt: psi at the free end s = 0, sampled as the figure samples it."""
    study = load_study("paper_figures")
    scene = mol_shell.TwistedCylinder()
    f0 = shear_frequency(scene)
    times = study.psi_times(0.143)
    assert times[-1] == 0.143 and np.diff(times).max() <= 1 / (1.25 * f0) / 10, np.diff(times).max()
    run = study._simulate_sampled(scene, 10, 1e-6, t_end=0.03)
    step = float(run.time[1] - run.time[0])
    np.testing.assert_allclose(np.diff(run.time.values), step, rtol=1e-6)  # evenly spaced, for the FFT
    peak = study.psi_peak(run.psi.isel(s=0))
    assert peak == dominant_frequency(run.psi.isel(s=0).values, step)
    assert abs(peak - f0) <= 1 / 0.03 + 0.05 * f0, (peak, f0)


def test_ring_vs_pde_samples_put_ten_in_the_shear_period_and_find_its_frequency():
    """The ring ODE over 0.04 s (the --quick t_end) at the script's saved times; they are on every leap-frog step."""
    study = load_study("ring_vs_pde")
    scene = mol_shell.SpinningRing()
    f0 = shear_frequency(scene)
    for t_end in (0.04, 0.1):
        times = study.sample_times(t_end)
        assert times[-1] == t_end and np.diff(times).max() <= 1 / (1.25 * f0) / 10, (t_end, np.diff(times).max())
        for dt in study.STEPS:
            np.testing.assert_allclose(times / dt, np.round(times / dt), atol=1e-6)
    times = study.sample_times(0.04)
    ring = mol_shell.simulate_ring(scene, times)
    peak = dominant_frequency(ring.psi.values, times[1])
    assert abs(peak - f0) <= 1 / 0.04 + 0.05 * f0, (peak, f0)


def test_paper_figures_samples_psi_on_times_leapfrog_lands_on_at_any_dt():
    """A fixed 20 us sampling refused every ``--dt`` that does not divide it (``--dt 5e-5``: "times = 2e-05 is
    outside multiples of dt"); the step is the multiple of dt nearest 20 us, and every sample a multiple of dt."""
    study = load_study("paper_figures")
    for dt, step in ((1e-6, 2e-5), (5e-5, 5e-5), (7e-6, 2.1e-5), (3e-5, 3e-5)):
        assert study.psi_step(dt) == pytest.approx(step, rel=1e-12)
        k = study.psi_times(0.143, study.psi_step(dt)) / dt
        assert np.abs(k - np.round(k)).max() < 1e-6 and study.psi_times(0.143, study.psi_step(dt))[-1] <= 0.143


def test_paper_figures_runs_at_a_dt_that_divides_neither_20_us_nor_the_papers_times(tmp_path):
    """``--dt 3e-5`` gave "times = 0.02 is outside multiples of dt": the paper's times (0.02, 0.07, 0.106, 0.143 s) are
    saved at the steps nearest them (the figures take the nearest saved time)."""
    study = load_study("paper_figures")
    run = study._simulate_sampled(mol_shell.TwistedCylinder(), 5, 3e-5, t_end=0.03)
    k = run.time.values / 3e-5
    assert np.abs(k - np.round(k)).max() < 1e-6 and abs(run.time.values - 0.02).min() <= 1.5e-5
