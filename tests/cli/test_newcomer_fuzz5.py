"""A new user's fuzzing of the command line (round 5): a scheduler address that is no dask scheduler, the radial
equilibrium under a large inflation, empty option values, a bad --dt blamed on t_end, an unknown option's hint, and
the up-front bounds of end torques, subnormal nu and workers with the serial scheduler."""

import http.server
import re
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.model.equilibrium import equilibrium_radius
from mol_shell.runs import scheduling

STUDY = ["study", "twisted-cylinder", "--vary", "gamma=0.1", "--n", "5", "--t-end", "1e-4"]


def one_error(capsys):
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert len(lines) == 1 and lines[0].startswith("mol-shell: error: ") and "Traceback" not in err, err
    return lines[0][len("mol-shell: error: "):]


# -- 1: a scheduler address where something else listens -------------------------------------------------------
class _Quiet(http.server.BaseHTTPRequestHandler):
    def log_message(self, *args):  # no lines on the test's stderr
        pass


@pytest.fixture
def http_port():
    """An HTTP server (what ``python3 -m http.server`` is) on a free port of this machine."""
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Quiet)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


@pytest.mark.timeout(60)
def test_an_http_server_as_the_scheduler_is_refused_at_once_in_one_line(http_port, tmp_path):
    """``--scheduler tcp://127.0.0.1:18788`` at ``python3 -m http.server`` printed nothing for 170 s (dask's client
    waits for the handshake without end), then a traceback from the half-open client at exit."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "mol_shell", *STUDY, "--scheduler", f"tcp://127.0.0.1:{http_port}",
                           "-o", str(tmp_path / "s.nc")], capture_output=True, text=True, timeout=40, check=False)
    elapsed = time.perf_counter() - start
    err = done.stderr
    assert done.returncode == 2 and elapsed < 10, (elapsed, err)
    assert err.startswith(f"mol-shell: error: scheduler = 'tcp://127.0.0.1:{http_port}' does not answer as a dask "
                          "scheduler; allowed: "), err
    assert len(err.splitlines()) == 1 and "Traceback" not in err and "Exception ignored" not in err, err
    assert not (tmp_path / "s.nc").exists()


@pytest.mark.timeout(30)
def test_a_listener_that_says_nothing_is_refused_within_the_timeout(monkeypatch):
    """A service that accepts the connection and stays silent hung the study: refused when the time is up."""
    pytest.importorskip("distributed")
    monkeypatch.setattr(scheduling, "SCHEDULER_TIMEOUT", 1.0)
    with socket.socket() as sock:  # listening, never answering (the kernel accepts the connection)
        sock.bind(("127.0.0.1", 0))
        sock.listen()
        address = f"tcp://127.0.0.1:{sock.getsockname()[1]}"
        start = time.perf_counter()
        with pytest.raises(ParameterError, match=rf"^scheduler = '{address}' does not answer as a dask scheduler "
                                                 r"within 1 s; .*sends no dask handshake"):
            scheduling.connect(address)
        assert time.perf_counter() - start < 5


@pytest.mark.timeout(60)
def test_a_dask_scheduler_is_taken_and_a_dask_worker_is_not():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                                  protocol="tcp") as cluster:
        client = scheduling.connect(cluster.scheduler_address)
        try:
            assert client.scheduler_info()["type"] == "Scheduler"
        finally:
            client.close()
        worker = next(iter(cluster.scheduler.workers))
        with pytest.raises(ParameterError, match=r"does not answer as a dask scheduler; .*\(it is a dask Worker\)"):
            scheduling.connect(worker)


# -- 2: the radial equilibrium of the inflated cylinder ---------------------------------------------------------
def held_pressure(R, scene):
    """The inflation the twisted cylinder's wall holds at radius ``R`` untwisted, from the law: St Venant-Kirchhoff
    with the director inextensible (``E22 = 0``) and ``z_s = 1``, so a fibre at ``zeta`` has only a hoop Green strain
    ``(lambda^2 - 1)/2``, ``lambda = (R + zeta)/(a + zeta)``, and ``W = C/2 E^2`` with ``C = lambda + 2 mu``; per unit
    reference area ``U = int W (a + zeta)/a dzeta``, and ``-p r^2/(2a)`` is the pressure's potential, so
    ``p = (a/R) dU/dR = (1/R) int C (lambda^2 - 1) lambda / 2 dzeta`` (thin wall: ``h C (lambda^2 - 1)/a``)."""
    E, nu, h, a = scene.E, scene.nu, scene.h, scene.a
    C = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    x, w = np.polynomial.legendre.leggauss(64)
    zeta = scene.zeta1_used() + h * (x + 1)
    R = np.asarray(R, dtype=float)[..., None]
    lam = (R + zeta) / (a + zeta)
    return np.sum(h * w * C * (lam**2 - 1) / 2 * lam, axis=-1) / R[..., 0]


def test_the_radius_under_2_5e5_pa_is_the_one_the_law_gives():
    """``pressure = 2.5e5`` was refused as "outside about (-inf, 1.258e+05] Pa" (Newton from R = a gave up where the
    energy's curvature turned negative), though 1.5e5, 2e5 and 2.2e5 Pa ran."""
    scene = mol_shell.TwistedCylinder(gamma=0.0, pressure=2.5e5)
    lo, hi = 1.0, 3.0
    for _ in range(100):  # the root of the law's balance, by bisection
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if held_pressure(mid, scene) < 2.5e5 else (lo, mid)
    R = equilibrium_radius(scene)
    assert R == pytest.approx(lo, rel=1e-10)
    C = scene.E * (1 - scene.nu) / ((1 + scene.nu) * (1 - 2 * scene.nu))
    assert R == pytest.approx(np.sqrt(1 + 2.5e5 * scene.a / (scene.h * C)), rel=1e-4)  # thin wall: 1.8234 a
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(pressure=2.5e5), n=5, t_end=1e-4)  # twisted, as the user ran
    assert ds.attrs["complete"] and ds.attrs["R"] == pytest.approx(R, rel=0.02)


def test_an_external_pressure_beyond_what_the_wall_holds_is_refused_with_the_true_bound():
    """Under external pressure the wall holds at most the least of ``held_pressure`` over the radii with the inner
    face off the axis; it was said as ``about [-6.043e+04, inf) Pa``, a bound that moved with the value tried."""
    scene = mol_shell.TwistedCylinder(gamma=0.0, pressure=-1.2e5)
    lowest = -scene.zeta1_used()
    least = float(held_pressure(lowest + np.geomspace(1e-9, 1.0, 20001), scene).min())
    for pressure in (-1.2e5, -1e6):
        with pytest.raises(ParameterError, match=r"^pressure = .* is outside about \(-1.07\d*e\+05, inf\) Pa") as info:
            equilibrium_radius(mol_shell.TwistedCylinder(gamma=0.0, pressure=pressure))
        assert info.value.range.low == pytest.approx(least, rel=1e-6)
    inside = mol_shell.TwistedCylinder(gamma=0.0, pressure=least * 0.99)
    R = equilibrium_radius(inside)
    assert held_pressure(R, inside) == pytest.approx(least * 0.99, rel=1e-9) and lowest < R < 0.2


def test_a_rubber_wall_whose_hoop_force_levels_off_is_refused_at_its_limit():
    """Mooney-Rivlin (c01 = 0) held on a thin wall at fixed length: ``p = 4 h c10 (1 - lambda^-4)/a``, at most
    ``4 h c10 / a``; above it there is no radius of equilibrium (the bisection had said 3252 or 2044 Pa)."""
    scene = mol_shell.TwistedCylinder(gamma=0.0, material="mooney-rivlin", pressure=2e5)
    most = 4 * scene.h * scene.c10 / scene.a
    with pytest.raises(ParameterError, match=r"^pressure = 200000.0 is outside about \(-inf, 377\d\) Pa") as info:
        equilibrium_radius(scene)
    assert info.value.range.high == pytest.approx(most, rel=1e-3)
    below = mol_shell.TwistedCylinder(gamma=0.0, material="mooney-rivlin", pressure=0.8 * most)
    assert equilibrium_radius(below) == pytest.approx(0.2 ** -0.25, rel=1e-3)


# -- 3: empty values -------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def path_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("fuzz5") / "path.nc"
    assert main(["path", "sphere", "--param", "pressure=0:1000", "--n", "7", "--max-steps", "2", "-o", str(out)]) == 0
    return out


RUN = ["run", "twisted-cylinder", "--n", "5", "--t-end", "1e-4"]


@pytest.mark.parametrize("argv, said", [
    (RUN + ["--integrator", ""], "integrator = '' is outside {leapfrog, "),
    (["run", "twisted-cylinder", "--n", "5", "--times", ""], "--times = '' is empty; allowed: T0:T1:DT"),
    (STUDY + ["--scheduler", "serial", "--integrator", ""], "integrator = '' is outside {leapfrog, "),
    (STUDY[:-2] + ["--scheduler", "serial", "--times", ""], "--times = '' is empty; allowed: T0:T1:DT"),
    (["modes", "sphere", "--n", "7", "--count", "2", "--png", ""], "--png = '' is empty; allowed: a file path"),
    (["plot", "{path}", "--response", ""], "--response = '' is outside {arclength, "),
])
def test_an_empty_value_is_refused_as_a_blank_one(argv, said, path_file, tmp_path, capsys):
    """``--integrator ''`` ran leapfrog, ``--times ''`` the default times, ``--png ''`` and ``--response ''`` the
    default figure: an empty value was taken as no option at all, while a blank one was refused."""
    out = tmp_path / ("p.png" if argv[0] == "plot" else "o.nc")
    assert main([a.replace("{path}", str(path_file)) for a in argv] + ["-o", str(out)]) == 2
    assert one_error(capsys).startswith(said)
    assert not out.exists() and not (tmp_path / "o.png").exists()


# -- 4: a bad --dt names dt ------------------------------------------------------------------------------------
@pytest.mark.parametrize("dt, t_end, said", [
    ("1e-320", "1e-4", r"^dt = 1e-320 is outside \(0, inf\) s, normal doubles \(a subnormal step"),
    ("2.5", "1e-4", r"^dt = 2.5 is outside \(0, 0.000\d+\) s \(leap-frog stability bound"),
    ("2.5", "2.5", r"^dt = 2.5 is outside \(0, 0.000\d+\) s \(leap-frog stability bound"),
    ("1e-300", "1e-4", r"^dt = 1e-300 is outside \[1.111e-20, inf\) s at t_end = 0.0001 s"),  # 1e-4 / 2^53
    ("3e-5", "1e-4", r"^--t-end = 0.0001 is outside positive multiples of dt = 3e-05 s"),  # dt fine: t_end it is
])
def test_a_bad_dt_is_named_before_t_end(dt, t_end, said, tmp_path, capsys):
    """``--dt 2.5 --t-end 1e-4`` was told to make t_end a multiple of 2.5 s, which then ran into dt's stability
    bound; ``--dt 1e-320`` was said as ``t_end = 0.0001 is outside (0, 9.007e-305] s``."""
    out = tmp_path / "d.nc"
    assert main(["run", "twisted-cylinder", "--n", "5", "--dt", dt, "--t-end", t_end, "-o", str(out)]) == 2
    assert re.match(said, one_error(capsys))
    assert not out.exists()


# -- 5: an option the command has not got ----------------------------------------------------------------------
def test_an_option_of_another_command_is_answered_with_this_command_s_options(tmp_path, capsys):
    """``stability --n 5`` said "allowed: options spelt in full, as --no-bisect": --n is no --no-bisect cut short."""
    assert main(["stability", "twisted-cylinder", "--n", "5", "--quick", "-o", str(tmp_path / "st.nc")]) == 2
    said = one_error(capsys)
    assert said.startswith("--n is not an option of mol-shell stability; allowed: --set, --quick, --no-bisect, "
                           "-o / --output (the report runs its own cases, each with its own n (40; the grid cases n = "
                           "160, 640, 2560, 10240, --quick to n = 640)"), said
    assert main(["stability", "twisted-cylinder", "--t-end", "1", "-o", str(tmp_path / "st.nc")]) == 2
    assert one_error(capsys).startswith("--t-end is not an option of mol-shell stability; allowed: --set, ")
    assert main(["stability", "twisted-cylinder", "--qu", "-o", str(tmp_path / "st.nc")]) == 2  # cut short
    assert one_error(capsys) == ("--qu is not an option of mol-shell stability; allowed: options spelt in full, as "
                                 "--quick")


# -- 6: end torques bounded up front, subnormal nu, workers with the serial scheduler ---------------------------
def test_an_end_torque_that_overflows_at_the_first_step_is_refused_up_front(tmp_path, capsys):
    """``end2_torque = 1e308`` ran and stopped at its first step (exit 3, non-finite state) where gravity = 1e308 was
    refused: the end's spin momentum is finite at t = 0, its centrifugal forces a step later are not."""
    assert main(RUN + ["--set", "end2_torque=1e308", "-o", str(tmp_path / "t.nc")]) == 2
    said = one_error(capsys)
    assert re.match(r"end2_torque = 1e\+308 is outside about \(-inf, \d\.\d+e\+1\d\d\] N m \(with the other "
                    r"parameters as given: beyond it the right-hand side one stable step after t = 0 is not "
                    r"finite", said), said
    assert not (tmp_path / "t.nc").exists()


@pytest.mark.parametrize("value", [1e-320, -1e-320])
def test_a_subnormal_poisson_ratio_is_refused_as_a_subnormal_modulus_is(value):
    with pytest.raises(ParameterError, match=r"^nu = -?1e-320 is outside \(-1, 0.5\), 0 or at least "
                                             r"2.2250738585072014e-308 in magnitude \(a subnormal number"):
        mol_shell.TwistedCylinder(nu=value)
    assert mol_shell.TwistedCylinder(nu=0.0).nu == 0.0 and mol_shell.TwistedCylinder(nu=1e-300).nu == 1e-300


def test_workers_with_the_serial_scheduler_says_what_workers_is_for(tmp_path, capsys):
    """It said ``workers = 2 is outside None``."""
    assert main(STUDY + ["--workers", "2", "--scheduler", "serial", "-o", str(tmp_path / "w.nc")]) == 2
    assert one_error(capsys) == ("workers = 2 applies to local processes (scheduler None, the default), not to "
                                 "scheduler = 'serial', which runs every case in this process; allowed: 1 or None "
                                 "(left out) with scheduler = 'serial'")


def test_a_stiffness_out_of_the_default_steps_reach_says_the_step_was_the_default(tmp_path, capsys):
    """E = 1e300 was refused as "dt = 1e-06 is outside (0, 2.019e-151) s", a dt the user never gave: the line now
    says it is the default, set against the scene's stiffness, mass and grid."""
    assert main(["run", "sphere", "--n", "9", "--t-end", "1e-4", "--set", "E=1e300", "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mol-shell: error: dt = 1e-06 is outside (0, ") and \
        "the default dt: the scene's stiffness, mass and grid set the bound" in err[0], err
