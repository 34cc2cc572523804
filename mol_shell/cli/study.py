"""The study command: a scene varied over a grid of parameters, run on processes or dask."""

from __future__ import annotations

import itertools
import re
import sys

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.constants import RTOL_RANGE
from mol_shell._core.errors import ParameterError, by_interrupt
from mol_shell.analysis.path_inputs import STEPS_MAX
from mol_shell.analysis.path_study import path_study
from mol_shell.cli.args import (
    EXIT_INCOMPLETE,
    EXIT_USAGE,
    NETCDF_SUFFIXES,
    RTOL_ALLOWED,
    SCENE_HELP,
    SCENE_METAVAR,
    checked_late,
    integer_arg,
    interrupted_code,
    max_step_arg,
    number_arg,
    option_value,
    parse_atol,
    parse_range_or_list,
    parse_sets,
    plural,
    refuse_late,
    run_settings,
    say_stand_ins,
    scene_and_run,
    unchecked_number_arg,
)
from mol_shell.cli.inputs import reason_with_the_file
from mol_shell.cli.path import as_path_option, parse_param
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.loop import declared, refusal
from mol_shell.results.study_store import cases_folder, check_cases_folder
from mol_shell.runs import resources
from mol_shell.runs.scheduling import SCHEDULER_TIMEOUT, most_workers
from mol_shell.runs.study import study
from mol_shell.runs.study_design import text_parameters
from mol_shell.scenes import with_params
from mol_shell.views.path_study_plot import first_critical_said

#: the keys of a scene file's [run] that are the run's own, not options of its integrator
RUN_OWN = ("integrator", "n", "t_end", "times")
#: the first step of each path of a study of paths is 1/STEPS of its range without --steps
STEPS = 20
#: the steps of each path of a study of paths without --max-steps
MAX_STEPS = 200


def parse_vary(items, n=40, scene=None):
    """``["gamma=0.02:0.2:0.02", "nu=0.3,0.45,0.49"]`` -> ``{"gamma": [...], "nu": [...]}`` (ranges include the stop).

    Each value is read as ``--set`` reads its parameter: a number for a numeric one, and for a string parameter of
    ``scene`` (:func:`mol_shell.runs.study_design.text_parameters`: ``h_profile``, ``material``, a history, ...) the
    text as typed (``h_profile=0.006`` is a constant thickness, an expression of ``s``); a ``START:STOP:STEP`` range
    of numbers on a string parameter gives its numbers as text (``0.005``, ``0.006``, ...), any other text with
    colons is one value (a law's import path, ``module:attr``). A range with more cases than a study on ``n`` nodes
    could hold in memory is refused before it is expanded.
    """
    form = "NAME=START:STOP:STEP or NAME=V1,V2,..."
    text = text_parameters(scene) if scene is not None else {"material", "material_parameters", "layers"}
    vary = {}
    for item in items or []:
        name, sep, spec = (x.strip() for x in item.partition("="))
        if not sep or not name:
            raise ParameterError("--vary", item, form)
        if name in vary:
            raise ParameterError.invalid("--vary", item, f"varies {name} a second time", "each parameter once")
        if ":" in spec and "," not in spec and (name not in text or _numeric_range(spec)):
            # START:STOP:STEP; a list's entries may hold colons (a law's import path, module:attr)
            values = parse_range_or_list(spec, f"--vary {name}", words=("START", "STOP", "STEP"), item="V",
                                         single=True, count_check=lambda count, name=name, spec=spec: resources.check_cases(
                                             count, n, name=f"--vary {name}", value=spec, early=True))
            values = [format(v, ".12g") for v in values] if name in text else values
        else:
            entries = [v.strip() for v in spec.split(",")]
            if not spec or any(not v for v in entries):
                raise ParameterError.invalid("--vary", item, "has an empty entry" if spec else "has no values", form)
            values = entries if name in text else [_number_or_text(v) for v in entries]
        vary[name] = values
    if not vary:
        raise ParameterError.missing("--vary", f"give {form}, at least one")
    return vary


def _numeric_range(spec):
    """Whether ``spec`` is three numbers joined by colons (a range, also on a string parameter)."""
    parts = spec.split(":")
    return len(parts) == 3 and all(isinstance(_number_or_text(part), float) for part in parts)


def _number_or_text(text):
    try:
        return float(text)
    except ValueError:
        return text


def cmd_study(args):
    check_cases_folder(args.output, "-o")  # <stem>.cases beside -o: a name its file system takes, before any work
    for option in ("max_steps", "steps"):  # options of a study of paths: ignored by one of runs
        if args.path is None and getattr(args, option) is not None:
            name = "--" + option.replace("_", "-")
            raise ParameterError(name, getattr(args, option), "an option of a study of paths (--path)",
                                 message=f"{name} is an option of a study of paths (--path), not of one of runs")
    sets = parse_sets(args.set)
    scene, run = scene_and_run(args.scene, args.set)  # a scene file's [run] table gives defaults, the options win
    n = args.n or run.get("n", 40)
    vary = parse_vary(args.vary, n, scene)
    both = [name for name in vary if name in sets]
    if both:
        raise ParameterError.invalid("--set", f"{both[0]}={sets[both[0]]}", f"sets {both[0]}, which --vary varies",
                                     "parameters not in --vary")
    if args.path is not None:
        return _path_study(args, scene, vary, n)
    _check_run_options(args, vary)
    # a scene file's [run] option that --vary varies is replaced by the varied values (the command line's own are
    # refused above): not checked, not passed beside them (it was refused as given twice)
    run = {key: value for key, value in run.items() if key not in vary or key in RUN_OWN}
    times, t_end, integrator, options = run_settings(args, run, scene, n)
    vary = _integer_options(args.vary, integrator, vary)
    return _finish(args, scene, "case", vary, lambda: study(
        scene, vary, integrator, n=n, times=times, t_end=t_end, scheduler=args.scheduler, workers=args.workers,
        output=args.output, progress=None, **options))


def _check_run_options(args, vary):
    """Refuse an option of the run that the command line sets (``--dt``, ``--rtol``, ``--atol``, ``--max-step``,
    ``--option NAME=VALUE``) and ``--vary`` varies, as ``--set`` is refused (the varied values won, silently); a
    scene file's ``[run]`` table gives defaults, which ``--vary`` replaces."""
    for name in ("dt", "rtol", "atol", "max_step"):
        if name in vary and getattr(args, name) is not None:
            raise ParameterError.invalid("--" + name.replace("_", "-"), getattr(args, name),
                                         f"sets {name}, which --vary varies", "options not in --vary")
    options = parse_sets(args.option, name="--option")
    both = [name for name in vary if name in options]
    if both:
        raise ParameterError.invalid("--option", f"{both[0]}={options[both[0]]}", f"sets {both[0]}, which --vary "
                                     "varies", "options not in --vary")


def _integer_options(items, integrator, vary):
    """``vary`` (:func:`parse_vary`'s, numbers as floats) with the values of an integer option of ``integrator`` as
    integers, as the study takes them (``mol_shell.study`` refuses ``chunk = 2000.0`` as ``simulate`` does). A value
    that ``--vary`` gives as a float (``chunk=100,2e3``) is refused, as ``--option chunk=2e3`` is ("is not an integer
    ... write it as the integer 2000"): each entry, and each of a range's START, STOP and STEP, read as ``--option``
    reads its value."""
    specs = declared(INTEGRATORS[integrator]) if integrator in INTEGRATORS else {}
    for item in items or []:
        name, _, spec = (x.strip() for x in item.partition("="))
        option = specs.get(name)
        if option is None or not option.allowed.startswith("integers"):
            continue
        for text in (x.strip() for x in re.split("[,:]", spec)):
            value = option_value(text)
            if isinstance(value, float):
                raise refusal(f"--vary {name}", value, option, typed=text)
        vary = {**vary, name: [int(v) if isinstance(v, float) else v for v in vary[name]]}  # whole: checked above
    return vary


def case_scenes(scene, vary):
    """The scenes of a study's cases as far as their notes go (:meth:`stand_ins`: the meridian's points, a vessel's
    segments, data given as text): the product of the values of the varied string parameters (``vary``:
    :func:`parse_vary`'s), each once, not of every case (a meridian is rebuilt by each); a case refused by its
    parameters runs none."""
    names = [name for name in vary if name in text_parameters(scene)]
    out = []
    for values in itertools.product(*(vary[name] for name in names)):
        try:
            out.append(with_params(scene, dict(zip(names, values))))
        except ParameterError:
            continue
    return out


def _finish(args, scene, what, vary, run, tail=lambda ds: ""):
    """Run a study (``run()``), say what it wrote in one line (``tail`` adds to it), and the exit code: 130 when
    interrupted, 143 when terminated by a SIGTERM (the finished cases kept for a rerun), 0 when every case ended well,
    EXIT_USAGE when every case was refused (its input out of range; the first reason on stderr), else
    EXIT_INCOMPLETE."""
    try:
        ds = run()
    except BaseException as exc:  # a KeyboardInterrupt, or an error that wraps one (by_interrupt)
        if not by_interrupt(exc):
            raise
        # "terminated by SIGTERM", as a run's, a path's and a comparison's line says it (as_stopped)
        print(f"mol-shell: study {'terminated by SIGTERM' if interrupts.terminated() else 'interrupted'}; finished "
              f"cases are kept in {cases_folder(args.output)}; run the same command again to resume", file=sys.stderr)
        return interrupted_code()
    say_stand_ins(scene, case_scenes(scene, vary))
    statuses = ds.status.values.ravel().tolist()
    counts = ", ".join(f"{statuses.count(s)} {s}" for s in dict.fromkeys(statuses))
    print(f"wrote {args.output}: {plural(int(ds.attrs['n_cases']), what)} ({counts}); ran {ds.attrs['n_executed']}, "
          f"reused {ds.attrs['n_reused']}, in {ds.attrs['study_wall_time_s']:.3g} s{tail(ds)}")
    refused = _say_cases(args, ds, what)
    if refused and refused == len(statuses):
        return EXIT_USAGE  # every case's input is out of range: nothing was computed
    return 0 if ds.attrs["n_failed"] == 0 else EXIT_INCOMPLETE


def _say_cases(args, ds, what):
    """A line on stderr when cases were refused (their input out of range: how many, and the first reason, naming
    the parameter, and the scene file and table of ``args`` where the file set it: :func:`reason_with_the_file`,
    as a single run's refusal says it), and one when cases stopped short (a model limit, an instability, a lost worker: how many, and
    the first one's message, which says where and when); the file's ``message`` holds every case's. Returns the
    number of refused cases."""
    status = ds.status.values.ravel().astype(str)
    messages = ds.message.values.ravel().astype(str) if "message" in ds else np.full(status.shape, "")
    cases = plural(len(status), what)
    reasons = list(dict.fromkeys(reason_with_the_file(args, m) for st, m in zip(status, messages) if st == "refused"))
    refused = int(np.sum(status == "refused"))
    if refused:
        others = len(reasons) - 1
        more = (f"; {others} other reason{'s' * (others > 1)} in the file's variable message" if others > 1 else
                f"; and {reasons[1]}" if others else "")
        print(f"mol-shell: error: {refused} of {cases} refused: {reasons[0]}{more}", file=sys.stderr)
    ended = ("complete", "refused", "max_steps", "returned")  # a path's max_steps and return are ends, not stops
    stopped = [(st, m) for st, m in zip(status, messages) if st not in ended]
    if stopped:
        print(f"mol-shell: {len(stopped)} of {cases} stopped short; the first ({stopped[0][0]}): {stopped[0][1]}",
              file=sys.stderr)
    return refused


def _path_study(args, scene, vary, n):
    """``mol-shell study ... --path NAME=START:STOP``: one equilibrium path per case, the critical points gathered."""
    for option in ("integrator", "t_end", "times", "dt", "rtol", "atol", "max_step", "option"):
        if getattr(args, option) is not None:
            name = "--" + option.replace("_", "-")
            raise ParameterError(name, getattr(args, option), "options of a study of runs",
                                 message=f"{name} is an option of a study of runs, not of one of paths (--path)")
    refuse_late(args)
    name, start, stop = parse_param(args.path, "--path")

    def trace():
        try:
            return path_study(scene, vary, name, start, stop, n=n, steps=args.steps or STEPS,
                              max_steps=args.max_steps or MAX_STEPS, scheduler=args.scheduler, workers=args.workers,
                              output=args.output)
        except ParameterError as exc:  # max_steps = ... said as --max-steps = ...
            raise as_path_option(exc, args, "--path") from None

    # "none up to 1965.48 Pa (max_steps)" where a path ended short of STOP without one: not "none" below STOP
    return _finish(args, scene, "path", vary, trace,
                   lambda ds: f"; first critical {name}: " + ", ".join(first_critical_said(ds)))


def register_study(subparsers):
    """Add ``mol-shell study`` to the command line."""
    p = subparsers.add_parser("study", help="run a parameter study (product of --vary values) and write one netCDF")
    p.add_argument("scene", metavar=SCENE_METAVAR, help=SCENE_HELP)
    p.add_argument("--vary", action="append", required=True, metavar="NAME=VALUES",
                   help="START:STOP:STEP (stop included) or V1,V2,...; repeat for more dimensions")
    p.add_argument("--integrator", default=None,
                   help="leapfrog, ... (ida for unshearable; default: a scene file's [run] integrator, else leapfrog)")
    p.add_argument("--n", type=integer_arg("--n", 3), default=None,
                   help="nodes in s (default: a scene file's [run] n, else 40)")
    p.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None, help="final time, s")
    p.add_argument("--times", default=None, help="saved times: T0:T1:DT (T1 included) or t1,t2,...")
    p.add_argument("--dt", type=checked_late("--dt", number_arg("--dt", unit="s")), default=None,
                   help="leap-frog step, s (default: a scene file's [run] dt, else 1e-6); adaptive integrators "
                   "refuse it")
    p.add_argument("--rtol", type=checked_late("--rtol", unchecked_number_arg("--rtol", RTOL_ALLOWED)), default=None,
                   help=f"relative tolerance in [{RTOL_RANGE[0]:g}, {RTOL_RANGE[1]:g}) (adaptive integrators)")
    p.add_argument("--atol", type=checked_late("--atol", parse_atol), default=None, help="one value, or per field as r=1e-9,theta=1e-10")
    p.add_argument("--max-step", type=checked_late("--max-step", max_step_arg()), default=None,
                   help="largest step, s (adaptive; 0: unbounded, the default)")
    p.add_argument("--option", action="append", metavar="NAME=VALUE",
                     help="another option of the integrator, repeatable: restart=0 (leapfrog), jac_every=200, "
                     "linsolver=band, iteration=newton, ... (docs/integrators.md; as a scene file's [run] keys)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="base scene parameter, repeatable")
    p.add_argument("--scheduler", default=None,
                   help="dask.distributed scheduler address, or serial (default: local processes); "
                   f"refused if it does not answer within {SCHEDULER_TIMEOUT:g} s")
    p.add_argument("--workers", type=integer_arg("--workers", 1, most_workers()), default=None,
                   help="local processes, this one included, at most this machine's cores (default: all cores)")
    p.add_argument("--path", default=None, metavar="NAME=START:STOP",
                   help="a study of equilibrium paths (mol-shell path) in place of runs: one path per case, their "
                   "critical points gathered (the run options --integrator, --t-end, ... are refused)")
    p.add_argument("--steps", type=checked_late("--steps", integer_arg("--steps", 1, STEPS_MAX)), default=None,
                   help=f"with --path: the first step of each path covers 1/STEPS of the range (default {STEPS})")
    p.add_argument("--max-steps", type=checked_late("--max-steps", integer_arg("--max-steps", 1)), default=None,
                   help=f"with --path only: each path ends after this many steps (default {MAX_STEPS})")
    p.add_argument("-o", "--output", required=True,
                   help="netCDF file, .nc; finished cases kept next to it in <stem>.cases/ (missing directories are "
                   "created)")
    p.set_defaults(func=cmd_study, output_suffixes=NETCDF_SUFFIXES)
