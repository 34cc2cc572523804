"""Ctrl-C during a run ends it ``interrupted`` with its saved times, wherever the signal lands: the run loop's own
SIGINT handler notes it and the loop stops at the end of the chunk (mol_shell._core.interrupts.watched).

Python's own handler raised KeyboardInterrupt where the signal landed, and some places lose or wrap it: a C
extension that runs the handler and clears its exception (the run went on to its end, exit 0), ctypes converting an
argument (an ArgumentError: "internal error", exit 1), CasADi's integrators (SUNDIALS' failure: status ``failed``).
Each is reproduced here by sending the signal at that point (``signal.raise_signal`` runs the handler at once).
"""

import importlib
import os
import signal
import threading
import time

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.discretization.stencil import StencilLeapfrog
from mol_shell.integrators import INTEGRATORS, casadi_peers, peers
from mol_shell.integrators.base import Monitor
from mol_shell.integrators.leapfrog import Leapfrog
from mol_shell.results.dataset import read_netcdf
from mol_shell.runs.simulate import build, resolve

simulate_module = importlib.import_module("mol_shell.runs.simulate")

TIMES = np.arange(0, 0.011, 0.001)


@pytest.fixture
def sigint_python():
    """SIGINT as in a Python program (KeyboardInterrupt), whatever the test runner set."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.fixture(scope="module")
def paper():
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 10)
    return system, compiled, system.initial_state(scene)


def _signal_then_lose_it():
    """SIGINT, its KeyboardInterrupt caught and dropped, as code that runs the handler inside its call and clears the
    error does (the tester's run went on to its end, exit 0, the process then in a CasADi call)."""
    try:
        signal.raise_signal(signal.SIGINT)
    except KeyboardInterrupt:
        pass


def test_an_interrupt_a_library_loses_still_ends_the_run(monkeypatch, sigint_python, paper):
    system, compiled, y0 = paper
    checks, real = [], Monitor.check

    def check(self, y, t):
        checks.append(t)
        if len(checks) == 4:  # the start, the first step, then two chunks' checks
            _signal_then_lose_it()
        return real(self, y, t)

    monkeypatch.setattr(Monitor, "check", check)
    traj = Leapfrog(dt=1e-5, chunk=50).integrate(system, compiled, y0, TIMES)
    assert traj.status == "interrupted" and traj.message.startswith("interrupted by the user at t = ")
    assert traj.failure_time == pytest.approx(0.001)  # the end of the chunk the signal arrived in (a saved time)
    assert len(traj.t) == 2 and np.isfinite(traj.y).all()


def _interrupted_conversion(argtype):
    """``argtype`` whose conversion SIGINT interrupts (NumPy's ``ndpointer.from_param`` runs in Python)."""

    class Converted:
        @classmethod
        def from_param(cls, obj):
            signal.raise_signal(signal.SIGINT)
            return argtype.from_param(obj)

    return Converted


def test_an_interrupt_inside_a_ctypes_conversion_ends_the_run_with_its_saved_times(
        monkeypatch, tmp_path, capsys, sigint_python):
    """The tester's ``run twisted-cylinder --option chunk=1``: ctypes raised ArgumentError("argument 1:
    KeyboardInterrupt: "), which the loop did not take for an interruption: "mol-shell: internal error", exit 1,
    no file."""
    chunks, real = [], StencilLeapfrog.leapfrog

    def leapfrog(self, ya, yb, nsteps, dt, t=0.0):
        chunks.append(t)
        if len(chunks) == 30:
            function = self._lib.ms_stencil_leapfrog
            argtypes = function.argtypes
            function.argtypes = [_interrupted_conversion(argtypes[0]), *argtypes[1:]]
            try:
                return real(self, ya, yb, nsteps, dt, t)
            finally:
                function.argtypes = argtypes
        return real(self, ya, yb, nsteps, dt, t)

    monkeypatch.setattr(StencilLeapfrog, "leapfrog", leapfrog)
    out = tmp_path / "run.nc"
    code = main(["run", "twisted-cylinder", "--n", "10", "--dt", "1e-5", "--t-end", "0.001", "--times",
                 "0:0.001:0.0001", "--option", "chunk=1", "--no-stresses", "-o", str(out)])
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    # the chunk the signal arrived in (the 30th, one step from 0.0003 s) is finished, and the run ends there
    said = f"mol-shell: run stopped: interrupted by the user at t = 0.00031 s; wrote 4 saved times to {out}"
    assert code == 130 and err == [said], err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and ds.sizes["time"] == 4


def test_an_interrupt_inside_casadis_integrator_is_an_interruption_not_its_failure(
        monkeypatch, capsys, sigint_python, paper):
    """casadi-cvodes computes every saved time in one CasADi call, which checks for signals as it steps: the
    interrupt failed its right-hand side, said "rhs failed: KeyboardInterrupt" on stderr, and the run ended
    ``failed`` (exit 3). The signal is sent from a thread 0.2 s into that call (4 s to t = 3 s, measured)."""
    system, compiled, y0 = paper
    method = INTEGRATORS["casadi-cvodes"]()
    method.start(system, compiled, y0, TIMES * 300, None)  # the graph built before the signal's clock starts
    real = casadi_peers._CasadiStepper.advance

    def advance(self, target):
        threading.Thread(target=lambda: (time.sleep(0.2), os.kill(os.getpid(), signal.SIGINT))).start()
        return real(self, target)

    monkeypatch.setattr(casadi_peers._CasadiStepper, "advance", advance)
    start = time.perf_counter()
    traj = method.integrate(system, compiled, y0, TIMES * 300)
    assert traj.status == "interrupted" and len(traj.t) == 1, traj.message
    assert time.perf_counter() - start < 5
    assert "KeyboardInterrupt" not in capsys.readouterr().err


def test_an_interrupt_lost_in_the_set_up_stops_the_run_at_its_start(monkeypatch, tmp_path, capsys, sigint_python):
    """The command line notes every SIGINT (its handler raises as Python's does): one whose KeyboardInterrupt a call
    lost before the run began (the build's CasADi calls) stops the run as it starts, where the run went on to its
    end (exit 0)."""
    real = simulate_module.build

    def build(*args, **kwargs):
        _signal_then_lose_it()
        return real(*args, **kwargs)

    monkeypatch.setattr(simulate_module, "build", build)
    out = tmp_path / "run.nc"
    code = main(["run", "twisted-cylinder", "--n", "10", "--t-end", "0.002", "--no-stresses", "-o", str(out)])
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    said = f"mol-shell: run stopped: interrupted by the user at t = 0 s; wrote 1 saved time to {out}"
    assert code == 130 and err == [said], err
    ds = read_netcdf(out)  # the end time asked is recorded (tests/results/test_t_end_requested.py)
    assert ds.attrs["status"] == "interrupted" and ds.attrs["t_end_requested"] == 0.002


def test_an_interrupt_as_the_run_ends_keeps_every_saved_time_and_is_said(monkeypatch, sigint_python, paper):
    """A signal after the loop's last look at its flag (here as the stepper's counters are read, the handler still
    the loop's) ends a complete run ``interrupted`` at its last saved time: it was neither lost (the run said complete
    and the command went on) nor raised out of the run with its data (Python's handler)."""
    system, compiled, y0 = paper
    real = peers._ScipyStepper.stats

    def stats(self):
        signal.raise_signal(signal.SIGINT)
        return real(self)

    monkeypatch.setattr(peers._ScipyStepper, "stats", stats)
    try:
        traj = INTEGRATORS["scipy-rk45"]().integrate(system, compiled, y0, TIMES[:3])
    except KeyboardInterrupt:
        pytest.fail("the interrupt was raised out of the run, and its saved times with it")
    assert traj.status == "interrupted" and len(traj.t) == 3
    assert traj.failure_time == pytest.approx(TIMES[2]) and traj.message.startswith("interrupted by the user at t =")
