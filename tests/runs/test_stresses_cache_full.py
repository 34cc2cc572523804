"""A full disk under MOL_SHELL_CACHE, or a failing gcc, while the stresses' kernel is built after a run: the run is
kept."""

import errno
import shutil

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.cli.main import main
from mol_shell.discretization import compiled
from mol_shell.results import stresses


def test_a_full_cache_while_the_stresses_kernel_builds_keeps_the_run(tmp_path, monkeypatch, capsys):
    """``mol-shell run ... --stresses`` (and the default stresses) built the stresses' kernel after the run; ENOSPC
    there was one line naming MOL_SHELL_CACHE, exit code 2, and the run was not written. The run is now written without
    its stresses, attrs["stresses"] says why, one warning line says so, and the exit code is 0 (a complete run: the
    stresses, derived from its fields, are added later by mol_shell.add_stresses, as when they exceed the limit)."""
    scene = mol_shell.TwistedCylinder(nu=0.3)
    whole = mol_shell.simulate(scene, "rk45-c", n=8, t_end=1e-5, stresses=False, progress=False)  # built here
    cache = tmp_path / "cache"
    monkeypatch.setenv("MOL_SHELL_CACHE", str(cache))
    stresses.compiled_kernel.cache_clear()  # built by an earlier test: built again, into the full cache

    def full(command, what, source_bytes, flags):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(compiled, "run_compiler", full)
    out = tmp_path / "run.nc"
    code = main(["run", "twisted-cylinder", "--set", "nu=0.3", "--n", "8", "--t-end", "1e-5", "--integrator", "rk45-c",
                 "--stresses", "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    why = f"no space for the stresses' kernel in MOL_SHELL_CACHE = '{cache}' (no space left on device)"
    assert captured.err.splitlines() == [(f"mol-shell: warning: stresses not computed: {why}; the run is kept without "
                                          "them (mol_shell.add_stresses adds them once there is space)")]
    assert captured.out.startswith(f"wrote {out}: 11 times x 8 nodes") and len(captured.out.splitlines()) == 1
    with xr.open_dataset(out) as ds:
        assert ds.attrs["complete"] == 1 and "von_mises_stress" not in ds
        assert ds.attrs["stresses"] == f"skipped: {why}; mol_shell.add_stresses(ds) adds them once there is space"
        for name in ("z", "r", "chi", "theta", "psi"):
            np.testing.assert_array_equal(ds[name].values, whole[name].values)
    assert [p.name for p in cache.iterdir() if not p.name.endswith(".lock")] == []  # nothing half-written


@pytest.mark.skipif(shutil.which("gcc") is None, reason="the right-hand side is built with gcc first")
def test_a_failing_gcc_while_the_stresses_kernel_builds_keeps_the_run_with_its_stresses(tmp_path, monkeypatch):
    """The right-hand side built, then a gcc that fails: the stresses' kernel after the run ended in gcc's error and
    the run was lost (only a missing gcc fell back to CasADi's virtual machine). They are now evaluated there: the
    values of add_stresses(compiled=False), the same kernel in the virtual machine."""
    scene = mol_shell.TwistedCylinder(nu=0.3)
    whole = mol_shell.simulate(scene, "rk45-c", n=8, t_end=1e-5, stresses=False, progress=False)  # built here
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "gcc").write_text("#!/bin/sh\necho 'cc1: fatal error: out of luck' >&2\nexit 1\n")
    (bin_dir / "gcc").chmod(0o755)
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "cache"))
    stresses.compiled_kernel.cache_clear()  # built by an earlier test: built again, by the failing gcc
    try:
        ds = mol_shell.simulate(scene, "rk45-c", n=8, t_end=1e-5, stresses=True, progress=False)
    finally:
        stresses.compiled_kernel.cache_clear()  # not the VM's kernel for later tests
    expected = stresses.add_stresses(whole, limit=None, compiled=False)
    assert ds.attrs["stresses"] == expected.attrs["stresses"] == "included (mol_shell.add_stresses)"
    for name in ("von_mises_stress", "axial_force", "axial_torque"):
        np.testing.assert_array_equal(ds[name].values, expected[name].values)


def test_an_unshearable_run_is_kept_too_when_the_cache_is_full(tmp_path, monkeypatch):
    """The unshearable scene's route called add_stresses itself, without the keeping of the other routes: a full cache
    under the stresses' kernel lost its run."""
    scene = mol_shell.Unshearable(omega=20.0, nu=0.3)
    whole = mol_shell.simulate(scene, "ida", n=9, t_end=1e-4, stresses=False, progress=False)
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "cache"))
    stresses.compiled_kernel.cache_clear()

    def full(command, what, source_bytes, flags):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(compiled, "run_compiler", full)
    with pytest.warns(UserWarning, match="stresses not computed: no space for the stresses' kernel"):
        ds = mol_shell.simulate(scene, "ida", n=9, t_end=1e-4, stresses=True, progress=False)
    assert ds.attrs["stresses"].startswith("skipped: no space") and "von_mises_stress" not in ds
    np.testing.assert_array_equal(ds["r"].values, whole["r"].values)
