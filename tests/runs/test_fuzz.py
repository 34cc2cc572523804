"""Property-based input testing: every registered scene, every parameter, any value, through the CLI and the API.

For each scene in ``mol_shell.SCENES`` and each of its dataclass fields (so new scenes and parameters are
covered without new test code), hypothesis draws values inside, at the edges of and outside the range the
scene's own check states (``mol_shell.ranges``), tiny and huge magnitudes, signed zeros, NaN, infinities,
wrong types and strings. Each value goes through ``mol-shell run`` (in-process, ``cli.main``) and through
``mol_shell.simulate`` (under the ``ci`` profile, a parameter's first value through the one and its second
through the other), on 5 nodes and one leap-frog step (1 us) or the same horizon for an adaptive
integrator. The outcome must be one of:

* it runs (exit 0): a complete file with finite values;
* it is refused (exit 2; ``ParameterError`` in Python) in one line naming a parameter and the allowed
  range; a value outside the stated range must be refused by its own name;
* it stops at a model limit with its data kept (exit 3): a file with ``complete = 0``.

Never a traceback (nor the one-line internal error), never a hang (each example is timed).

Profiles (``HYPOTHESIS_PROFILE``): ``ci`` (default) draws a few values per parameter with a fixed seed;
``long`` thousands in all, for a manual run (counts in the README's status).
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import io
import math
import os
import re
import tempfile
import time
import warnings
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

import mol_shell
from mol_shell.cli.main import main
from mol_shell._core.errors import ParameterError
from mol_shell.results.dataset import read_netcdf
from mol_shell._core.ranges import Choice, Interval
from mol_shell.scenes.ranges import scene_ranges

settings.register_profile("ci", max_examples=2, derandomize=True, deadline=None, database=None,
                          suppress_health_check=[HealthCheck.too_slow], print_blob=True)
settings.register_profile("long", max_examples=30, deadline=None, database=None,
                          suppress_health_check=[HealthCheck.too_slow], print_blob=True)
PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "ci")
settings.load_profile(PROFILE)

#: the run of every example: 5 nodes, saved at 0 and 1 us (one leap-frog step)
RUN = ["--n", "5", "--times", "0,1e-06"]
API_RUN = {"n": 5, "times": [0.0, 1e-6]}
#: the longest any example may take (s): compilation of new kernels included (cvode-bdf's exact Jacobian at
#: n_quad = 32 takes about 110 s, which the long profile draws); a hang fails here
EXAMPLE_LIMIT_S = 120.0 if PROFILE == "ci" else 400.0
#: names a refusal may give besides the fuzzed parameter, for a value inside its stated range (a step
#: outside the stability bound it implies, a computed radius, ...)
DERIVED = {"dt", "integrator", "times", "--times", "t_end", "n", "R", "scene"}
#: the integrators tried for each scene (the unshearable scene takes ida and leapfrog only)
INTEGRATORS = {"unshearable": ("leapfrog", "ida")}

PAIRS = [(name, f.name) for name, cls in sorted(mol_shell.SCENES.items()) for f in dataclasses.fields(cls)]
COUNTS = {"examples": 0, "cli": {}, "api": {}, "slowest": []}
#: examples drawn so far for each (scene, parameter): which route the next one takes under the ci profile; and the
#: turn each example (scene, parameter, value, integrator) took first, which its replays keep
TURNS, ROUTES = {}, {}


@functools.cache
def default_ranges(scene_cls):
    """``scene_ranges`` of a scene class's default instance, read once: each read probes every field's check (a
    points meridian's takes 5-10 ms per field), and the examples ask for it again and again."""
    return scene_ranges(scene_cls)


@pytest.fixture(scope="module", autouse=True)
def fuzz_cache():
    """Kernels compiled for fuzzed values go into a cache of their own, apart from the kernels of real runs. The
    ``ci`` profile draws the same values every time (derandomized): its kernels are a fixed set (about 10 MB), kept
    in ``fuzz-ci-O0`` inside the kernel cache, shared by the workers of a parallel run (the cache's lock) and reused by
    the next run. Other profiles draw new values each time: a temporary cache, removed afterwards. The counts of
    examples and outcomes are printed at the end (for the README's status)."""
    from mol_shell.discretization import compiled

    old = os.environ.get("MOL_SHELL_CACHE")
    start = time.perf_counter()
    kept = contextlib.nullcontext(str(compiled.cache_dir() / "fuzz-ci-O0")) if PROFILE == "ci" else None
    with kept or tempfile.TemporaryDirectory(prefix="mol_shell_fuzz_cache") as tmp, pytest.MonkeyPatch.context() as mp:
        os.environ["MOL_SHELL_CACHE"] = tmp
        mp.setattr(compiled, "run_compiler", _unoptimised(compiled.run_compiler))
        yield
    if old is None:
        os.environ.pop("MOL_SHELL_CACHE", None)
    else:
        os.environ["MOL_SHELL_CACHE"] = old
    print(f"\nfuzz profile {PROFILE}: {COUNTS['examples']} examples in {time.perf_counter() - start:.0f} s; "
          f"CLI exit codes {dict(sorted(COUNTS['cli'].items()))}; API outcomes {COUNTS['api']}")
    for row in COUNTS["slowest"]:
        print("  slowest: %.1f s %s %s=%s %s exit %s, API %s" % row)


def _unoptimised(run_compiler):
    """gcc at ``-O0`` for the fuzzed kernels: each example runs one step, and what is checked is how a value is
    handled (run, refused, stopped), not how fast its kernel is; ``-O0`` builds them about 5 times faster than
    ``-O3`` (the right-hand side) and ``-O1`` (exact Jacobians), which is most of the file's time from a cold cache.
    The cache of fuzzed kernels is apart from the real ones, so no real run ever loads one of them."""
    def build(command, what, source_bytes, flags):
        return run_compiler(["-O0" if arg in ("-O1", "-O2", "-O3", "-Os") else arg for arg in command], what, source_bytes,
                            flags)
    return build


SPECIAL = [0.0, -0.0, 1.0, -1.0, 5e-324, -5e-324, 1e-300, -1e-300, 1e-30, 1e30, 1e300, -1e300,
           1.7976931348623157e308, -1.7976931348623157e308, math.nan, math.inf, -math.inf]
WRONG_TYPES = [None, True, False, "", " ", "abc", "nan", "-inf", "1e400", "0x10", "1_000", " 2 ", "auto", "none",
               [1.0], (1,), {"a": 1}, complex(1, 1), b"1", np.float32(1.5), np.int64(3), np.float64(math.nan),
               Fraction(1, 3), Decimal("0.1"), object()]


def _floats_in(rng):
    lo = rng.low if math.isfinite(rng.low) else -1e308
    hi = rng.high if math.isfinite(rng.high) else 1e308
    return st.floats(min_value=lo, max_value=hi, exclude_min=not rng.low_closed or not math.isfinite(rng.low),
                     exclude_max=not rng.high_closed or not math.isfinite(rng.high), allow_nan=False,
                     allow_infinity=False)


def _edges(rng):
    out = []
    for end in (rng.low, rng.high):
        if math.isfinite(end):
            out += [end, np.nextafter(end, math.inf), np.nextafter(end, -math.inf), end * (1 + 1e-9) + 1e-12,
                    end * (1 - 1e-9) - 1e-12]
    return [float(v) for v in out]


def values_for(scene_cls, name):
    """A strategy of values for parameter ``name``: inside, at the edges, outside, special, of the wrong type."""
    rng = default_ranges(scene_cls)[name]
    parts = [st.sampled_from(SPECIAL), st.sampled_from(WRONG_TYPES),
             st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True)]
    if isinstance(rng, Interval):
        if rng.integer:
            hi = int(rng.high) if math.isfinite(rng.high) else 10**6
            parts += [st.integers(int(rng.low) - 3, hi + 3), st.sampled_from([10**20, -(10**20), 2**63]),
                      st.integers(int(rng.low), hi).map(float)]
        else:
            parts += [_floats_in(rng), _floats_in(rng), st.sampled_from(_edges(rng) or [0.0])]
    elif isinstance(rng, Choice):
        parts += [st.sampled_from(list(rng.values)), st.text(max_size=12)]
    return st.one_of(*parts)


def changes_graph(cls, name, value):
    """True unless ``value`` only changes initial data (the compiled graphs of the default scene are reused)."""
    from mol_shell.scenes import with_params
    from mol_shell.runs.simulate import _graph_key

    changed = False
    def api():
        return dataclasses.replace(cls(), **{name: value})

    def cli():
        return with_params(cls(), {name: as_text(value)})

    for make in (api, cli):
        try:  # as the API takes it, and as the command line reads its text
            changed = changed or _graph_key(make()) != _graph_key(cls())
        except Exception:  # noqa: BLE001 - refused values build nothing
            pass
    return changed


def as_text(value):
    """How a user would type ``value`` after ``--set NAME=``."""
    if isinstance(value, str):
        return value
    if isinstance(value, float):
        return repr(value)
    return str(value)


def outside(rng, value):
    """True if ``value`` is certainly outside the stated range (as a number, or not a number at all)."""
    if rng is None:
        return False
    if isinstance(rng, Choice):
        return isinstance(value, str) and value.strip() not in rng.values and value not in rng.values
    if isinstance(value, str):
        text = value.strip()
        if text.lower() in ("none", "auto"):
            return False
        try:
            value = float(text)
        except ValueError:
            return True
    if isinstance(value, (bool, np.bool_)) or value is None:
        return value is not None
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        return True
    return number not in rng


#: lines that may come before a refusal: progress of a compilation that took more than a few seconds
PROGRESS = re.compile(r"^mol-shell: (compiling|still compiling|compiled) ")


def one_refusal(err):
    """The refusal line of ``err``: exactly one line, after nothing but compile progress lines."""
    lines = [line for line in err.strip().splitlines() if not PROGRESS.match(line)]
    assert len(lines) == 1 and lines[0].startswith("mol-shell: error: "), err
    return lines[0]


REFUSAL = re.compile(r"^mol-shell: error: (?P<name>.+?)(?: = | is (?:missing|not an option))")


def _named(line):
    found = REFUSAL.match(line)
    return found.group("name") if found else None


def run_cli(scene, name, value, integrator, path):
    argv = ["run", scene, "--set", f"{name}={as_text(value)}", *RUN, "--integrator", integrator, "-o", path]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return argv, code, out.getvalue(), err.getvalue()


def check_cli(scene, name, value, integrator, rng):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "x.nc")
        start = time.perf_counter()
        argv, code, out, err = run_cli(scene, name, value, integrator, path)
        elapsed = time.perf_counter() - start
        note(f"argv = {argv}\nexit {code} after {elapsed:.2f} s\nstdout: {out}\nstderr: {err}")
        assert elapsed < EXAMPLE_LIMIT_S
        assert "Traceback" not in out + err and "internal error" not in err
        assert code in (0, 2, 3)
        lines = [line for line in err.splitlines() if line.startswith("mol-shell:")]
        if code == 2:
            refusal = one_refusal(err)
            named = _named(refusal)
            assert named is not None and ("outside" in err or "allowed:" in err), err
            if outside(rng, value):
                assert named == name, f"{name} = {value!r} is outside {rng}, but the refusal names {named}"
            else:
                assert named in {name, *DERIVED, *(f.name for f in dataclasses.fields(mol_shell.SCENES[scene]))}, err
        elif code == 3:
            assert lines and lines[-1].startswith("mol-shell: run stopped: "), err
            ds = read_netcdf(path)
            assert ds.attrs["complete"] == 0 and ds.sizes["time"] >= 1
        else:
            assert not outside(rng, value), f"{name} = {value!r} is outside {rng} and was accepted"
            ds = read_netcdf(path)
            assert ds.attrs["complete"] == 1
            assert all(np.isfinite(ds[v].values).all() for v in ("z", "r", "chi", "theta", "psi", "energy"))
        COUNTS["cli"][code] = COUNTS["cli"].get(code, 0) + 1
    return code


def check_api(scene, name, value, integrator, rng):
    cls = mol_shell.SCENES[scene]
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a stopped run warns; its Dataset says so
        try:
            ds = mol_shell.simulate(dataclasses.replace(cls(), **{name: value}), integrator, progress=False, **API_RUN)
        except ParameterError as exc:
            text = str(exc)
            note(f"API: ParameterError {text}")
            assert "\n" not in text and exc.name and ("outside" in text or "allowed:" in text or "missing" in text)
            if outside(rng, value) and not isinstance(value, str):
                assert exc.name == name, f"{name} = {value!r} is outside {rng}, but the refusal names {exc.name}"
            outcome = "refused"
        else:
            outcome = "complete" if ds.attrs["complete"] else "stopped"
            note(f"API: {outcome}: {ds.attrs['message']}")
            assert not (outcome == "complete" and outside(rng, value) and not isinstance(value, str)), \
                f"{name} = {value!r} is outside {rng} and was accepted"
    assert time.perf_counter() - start < EXAMPLE_LIMIT_S
    COUNTS["api"][outcome] = COUNTS["api"].get(outcome, 0) + 1
    return outcome


@pytest.mark.slow
@pytest.mark.parametrize("scene,name", PAIRS, ids=[f"{s}-{n}" for s, n in PAIRS])
@settings(deadline=None)
@given(data=st.data())
def test_any_value_of_any_parameter(scene, name, data):
    cls = mol_shell.SCENES[scene]
    rng = default_ranges(cls)[name]
    value = data.draw(values_for(cls, name), label=name)
    choices = INTEGRATORS.get(scene, ("leapfrog", "cvode-bdf"))
    if PROFILE == "ci" and changes_graph(cls, name, value):
        choices = choices[:1]  # a new graph: its exact Jacobian would cost seconds of gcc (the long profile pays it)
    integrator = data.draw(st.sampled_from(choices), label="integrator")
    COUNTS["examples"] += 1
    start = time.perf_counter()
    key = (scene, name, repr(value), integrator)  # a replayed example (shrinking, the final replay) keeps its route
    if key not in ROUTES:
        ROUTES[key] = TURNS[scene, name] = TURNS.get((scene, name), -1) + 1
    turn = ROUTES[key]
    # the ci profile's two values of a parameter: the first through the command line, the second through Python
    # (each through both took the suite's largest file to 286 s of a 23-minute run); the long profile: both, each
    code = check_cli(scene, name, value, integrator, rng) if PROFILE != "ci" or turn % 2 == 0 else None
    outcome = check_api(scene, name, value, integrator, rng) if PROFILE != "ci" or turn % 2 == 1 else None
    COUNTS["slowest"] = sorted([*COUNTS["slowest"], (time.perf_counter() - start, scene, name, repr(value)[:40],
                                                     integrator, code, outcome)], reverse=True)[:8]


# -- the issue's cases, and the options of a run ----------------------------------------------------------
#: the values the issue found, and how each ends now: refused naming a parameter, stopped (exit 3) or run
ISSUE = [("h=1e-300", "h"), ("rho=1e-300", "stop"), ("rho=1e300", "run"), ("n_quad=64", "n_quad"), ("E=1e300", "stop")]


@pytest.mark.parametrize("setting,named", ISSUE)
def test_the_issue_s_extreme_values_end_in_one_line(setting, named, tmp_path, capsys):
    """``--integrator cvode-bdf`` with the values the issue found: a traceback (h, rho), or minutes of silence
    (n_quad = 64: the exact Jacobian took 767 s to compile). Now: refused, naming the parameter and the range
    over which the numbers are finite; E = 1e300 and rho = 1e-300 have finite spectra (5e150 /s, 1.6e155 /s)
    and stop at t = 0 as the solver fails; rho = 1e300 is a finite model (the mass matrix is factored without
    squaring it) in which nothing moves."""
    start = time.perf_counter()
    code = main(["run", "twisted-cylinder", "--set", setting, "--integrator", "cvode-bdf", "--n", "5",
                 "--t-end", "1e-6", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert time.perf_counter() - start < 60
    assert "Traceback" not in err
    if named == "run":
        ds = read_netcdf(tmp_path / "x.nc")
        assert code == 0 and ds.attrs["complete"] == 1, err
        assert float(abs(ds.r - ds.r.isel(time=0)).max()) < 1e-200  # accelerations ~1e-289 m/s^2 for 1e-6 s
    elif named == "stop":
        assert code == 3 and err.strip().splitlines()[-1].startswith("mol-shell: run stopped: "), err
        assert read_netcdf(tmp_path / "x.nc").attrs["complete"] == 0
    else:
        assert code == 2 and _named(one_refusal(err)) == named, err
        assert "outside" in err


OPTION_VALUES = {
    "--n": st.one_of(st.integers(-5, 60), st.sampled_from(["10**9", "1e30", "5000000", "abc", "", "3.5", "-0"])),
    "--t-end": st.one_of(st.sampled_from([*SPECIAL, 1e-5, 2e-6]), st.floats(1e-9, 1e-4), st.text(max_size=6)),
    "--dt": st.one_of(st.sampled_from(SPECIAL), st.floats(1e-12, 1e-3), st.text(max_size=6)),
    "--times": st.one_of(st.sampled_from(["0:1e300:1e-300", "0:0.001:1e-12", "0:1e-5:1e-6", "0,1e-6", "1e-6,0",
                                          "0:1:0", "0:nan:1", "0,inf", ":", ",", "0", "0:1e-5:3e-6", "-1:0:1"]),
                         st.text(alphabet="0123456789.,:e-+", max_size=12)),
    "--rtol": st.one_of(st.sampled_from(SPECIAL), st.floats(1e-15, 1.0), st.text(max_size=6)),
    "--atol": st.one_of(st.sampled_from(SPECIAL), st.sampled_from(["r=1e-9", "r=0", "psi=1e300,r=1", "q=1", "r=",
                                                                   "=1", "r=1e-9,r=1e-9"]), st.text(max_size=8)),
    "--max-step": st.one_of(st.sampled_from(SPECIAL), st.floats(1e-9, 1e-3), st.text(max_size=6)),
}


@pytest.mark.slow
@pytest.mark.parametrize("option", sorted(OPTION_VALUES))
@settings(deadline=None)
@given(data=st.data())
def test_any_value_of_any_run_option(option, data):
    """The options of ``mol-shell run``: ``--n`` up to 60 and far beyond the machine, horizons up to 0.1 ms and
    far beyond what leap-frog can count (longer runs that are possible but take hours are warned about:
    tests/test_resources.py)."""
    value = data.draw(OPTION_VALUES[option], label=option)
    integrator = data.draw(st.sampled_from(["leapfrog", "cvode-bdf"]), label="integrator")
    base = {"--n": "5", "--times": "0,1e-06"}
    if option == "--t-end":
        base.pop("--times")
    base.pop(option, None)
    args = [a for k, v in base.items() for a in (k, v)]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "x.nc")
        argv = ["run", "twisted-cylinder", *args, f"{option}={as_text(value)}", "--integrator", integrator, "-o", path]
        out, err = io.StringIO(), io.StringIO()
        start = time.perf_counter()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
        err = err.getvalue()
        note(f"argv = {argv}\nexit {code}\nstderr: {err}")
        assert time.perf_counter() - start < EXAMPLE_LIMIT_S
        assert "Traceback" not in err and "internal error" not in err
        assert code in (0, 2, 3)
        if code == 2:
            assert _named(one_refusal(err)) is not None, err
        elif code == 3:
            assert read_netcdf(path).attrs["complete"] == 0
        else:
            assert read_netcdf(path).attrs["complete"] == 1
    COUNTS["examples"] += 1
    COUNTS["cli"][code] = COUNTS["cli"].get(code, 0) + 1


# -- the ranges the checks state, and the ranges the degenerate-value check reports -----------------------------
def test_ranges_are_read_from_every_scene_s_checks():
    """Every field of every registered scene declares a range its check enforces (NaN is outside all):
    the default lies inside it, and a value just beyond a finite end is refused naming that same range."""
    for name, cls in mol_shell.SCENES.items():
        ranges = scene_ranges(cls)
        for f in dataclasses.fields(cls):
            if f.name.endswith("_history") or f.name in ("points", "segments", "h_profile", "layers",
                                                         "material_parameters"):
                continue  # a grammar or a file, not a range (their refusals: tests/test_loads.py, test_meridians.py,
                # tests/model/test_user_laws.py)
            assert ranges[f.name] is not None, f"{name}.{f.name}: its check states no range that can be read"
            default = getattr(cls(), f.name)
            assert default is None or default in ranges[f.name], f"{name}.{f.name} = {default!r} outside its range"
            rng = ranges[f.name]
            if isinstance(rng, Interval):
                for end, closed, away in ((rng.low, rng.low_closed, -math.inf), (rng.high, rng.high_closed, math.inf)):
                    if not math.isfinite(end):
                        continue
                    beyond = (end + (1 if away > 0 else -1)) if rng.integer else (
                        math.nextafter(end, away) if closed else end)
                    with pytest.raises(ParameterError) as info:
                        dataclasses.replace(cls(), **{f.name: int(beyond) if rng.integer else beyond})
                    assert info.value.name == f.name and info.value.range == rng, (name, f.name, beyond, str(info.value))


@pytest.mark.parametrize("name,bad", [("h", 1e-300), ("omega", -1e300), ("L", 1e-300)])
def test_a_degenerate_value_is_refused_with_the_range_where_the_numbers_are_finite(name, bad):
    """The refusal names the parameter and a range found by bisection: 3x inside its edge the numbers are
    finite, 10x beyond it they are not (with the other parameters at their defaults, on 5 nodes)."""
    from mol_shell.runs import checks as degenerate

    scene = mol_shell.TwistedCylinder(**{name: bad})
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(scene, n=5, times=[0, 1e-6])
    text = str(info.value)
    assert info.value.name == name and "is outside about " in text and "double precision" in text, text
    low_side = bad < getattr(mol_shell.TwistedCylinder(), name)  # the edge between the value and the default
    edge = info.value.range.low if low_side else info.value.range.high
    toward_zero = low_side != (edge > 0)  # inside the range lies towards smaller magnitudes than the edge
    inside, beyond = (edge * 3, edge / 10) if not toward_zero else (edge / 3, edge * 10)
    assert degenerate._is_bad(dataclasses.replace(scene, **{name: inside}), 5) is False
    assert degenerate._is_bad(dataclasses.replace(scene, **{name: beyond}), 5) is True


@pytest.mark.slow
@pytest.mark.parametrize("scene", sorted(mol_shell.SCENES))
def test_every_wrong_type_and_special_value_is_refused_or_stored_as_a_plain_number(scene):
    """Every value of WRONG_TYPES and SPECIAL for every field (cheap: no run): the scene refuses it naming the
    field, or stores something the model can compute with (a real number, a known name, or None where the
    code computes the value). A ``Fraction`` once passed the checks and failed inside CasADi."""
    cls = mol_shell.SCENES[scene]
    base = cls()  # scenes are immutable: one default to vary (a meridian scene takes 10-20 ms to build)
    for f in dataclasses.fields(cls):
        for value in [*WRONG_TYPES, *SPECIAL]:
            try:
                stored = getattr(dataclasses.replace(base, **{f.name: value}), f.name)
            except ParameterError as exc:
                assert exc.name == f.name and "\n" not in str(exc), (f.name, value, str(exc))
                continue
            plain = isinstance(stored, (int, float, np.integer, np.floating)) and not isinstance(stored, bool)
            grammar = default_ranges(cls)[f.name] is None  # a history or a file name: checked by its own parser
            flag = isinstance(stored, bool) and stored in default_ranges(cls)[f.name]  # a yes/no parameter
            assert plain and math.isfinite(stored) or flag or stored is None or isinstance(stored, str) and \
                (grammar or stored in default_ranges(cls)[f.name]), (f.name, value, stored)
