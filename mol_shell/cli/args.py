"""Argument parsing of the command line: numbers and ranges with their allowed ranges, sets, times, exit codes."""

from __future__ import annotations

import argparse
import re
import sys

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from mol_shell._core import interrupts
from mol_shell._core.constants import ATOL_MIN, FIELDS, RTOL_RANGE
from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.loop import declared, refusal, typed_value
from mol_shell.integrators.tolerances import MAX_STEP_NOTE
from mol_shell.results.dataset import NETCDF_SUFFIXES  # noqa: F401 (the outputs' suffixes, for the commands)
from mol_shell.runs.resources import check_saved_times
from mol_shell.runs.simulate import check_options, integrator_options
from mol_shell.scenes import SCENES, get_scene
from mol_shell.scenes.files import check_run_together, load_scene

#: exit codes: an internal error (a bug), bad input, a run stopped at a model limit, Ctrl-C, and the reader of
#: the output gone (``mol-shell scenes | head -1``: 128 + SIGPIPE, as a command the pipe stopped)
EXIT_INTERNAL, EXIT_USAGE, EXIT_INCOMPLETE, EXIT_INTERRUPTED, EXIT_PIPE = 1, 2, 3, 130, 141
#: exit code of a command that a SIGTERM stopped (a scheduler's at a job's wall-time limit: 128 + SIGTERM), having
#: kept what it had as one Ctrl-C stopped does (:func:`mol_shell._core.interrupts.watched`)
EXIT_TERMINATED = 143


def interrupted_code():
    """The exit code of a command an interrupt stopped: :data:`EXIT_TERMINATED` where it was a SIGTERM, else
    :data:`EXIT_INTERRUPTED` (Ctrl-C)."""
    return EXIT_TERMINATED if interrupts.terminated() else EXIT_INTERRUPTED


def as_stopped(message):
    """A run's (or path's, comparison's) message ``interrupted by the user at t = ...`` as what stopped it says it:
    ``terminated by SIGTERM at t = ...`` where a SIGTERM did (the file's attrs and the line on stderr)."""
    return message.replace("interrupted by the user", "terminated by SIGTERM") if interrupts.terminated() else message


#: what the positional argument of a command that takes a scene is called in its help
SCENE_METAVAR = "SCENE_OR_FILE"
SCENE_HELP = ("a registered scene (" + ", ".join(SCENES) + "; meridian without --set points=FILE runs a built-in dome) "
              "or a scene file FILE.toml")


def plural(count, word, words=None):
    """``1 step``, ``2 steps``: a count and its noun for a summary line (``words``: an irregular plural)."""
    return f"{count} {word if count == 1 else words or word + 's'}"


def say_stand_ins(scene, cases=None):
    """A note on stderr for each built-in stand-in a scene ran with (the meridian scene's dome); said once the
    command has computed, so a refusal stays one line. ``cases``: the scenes a study ran in place of ``scene`` (its
    base, which no case may run), each distinct note once."""
    for text in dict.fromkeys(text for case in ([scene] if cases is None else cases) for text in case.stand_ins()):
        print(f"mol-shell: note: {text}", file=sys.stderr)


def scene_and_run(text, sets=None):
    """The scene a command names, a registered name or a scene file ``FILE.toml``, with ``--set`` values on top,
    and the file's ``[run]`` table (``{}`` for a name): the defaults of the command's own options."""
    if str(text).endswith(".toml"):
        # --set over the file's values, before the scene is made; run_settings checks [run] with our options
        return load_scene(text, with_run=True, together=False, overrides=parse_sets(sets))
    return get_scene(text, **parse_sets(sets)), {}

#: the range of ``--rtol`` as its refusal says it (the scipy peers check a narrower one, :func:`check_options`)
RTOL_ALLOWED = f"[{RTOL_RANGE[0]:g}, {RTOL_RANGE[1]:g})"

#: integrator options the command line has flags for; the others go by --option NAME=VALUE
FLAGS = {"dt": "--dt", "rtol": "--rtol", "atol": "--atol", "max_step": "--max-step", "n": "--n",
         "t_end": "--t-end", "times": "--times", "integrator": "--integrator"}


class Once(argparse.Action):
    """The store action of :class:`Parser`: an option given at most once (``--n 10 --n 12`` took the last value,
    silently); the options meant to be repeated say so (``action="append"``: ``--set``, ``--vary``)."""

    #: why one, said after "allowed: one" ("": the option's name)
    why = ""

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", {})  # dest: the option as given and its value
        if option_string is not None and self.dest in given:
            first, value = given[self.dest]
            allowed = f"one ({self.why})" if self.why else f"one {first}"
            raise argparse.ArgumentError(self, f"{option_string} = {show(values)} follows {first} = {show(value)}; "
                                         f"allowed: {allowed}")
        given[self.dest] = (option_string, values)
        setattr(namespace, self.dest, values)


#: the options of every command: one of them given to another command is not one cut short (``stability --n`` was
#: told "options spelt in full, as --no-bisect")
EVERY_OPTION = set()


class Parser(argparse.ArgumentParser):
    """argparse's parser with the command line's rules: an option is spelt in full (``--t-en`` was taken as
    ``--t-end``), a single-valued option is given once (:class:`Once`), and a refusal is one line, exit code 2."""

    #: what a command says after the list of its options when it is given one it has not got
    unknown_note = ""
    #: the name a refusal begins with (a study's script: its file's name, :mod:`mol_shell.cli.scripts`)
    said_as = "mol-shell"

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        self.register("action", None, Once)
        self.register("action", "store", Once)

    def add_argument(self, *args, **kwargs):
        action = super().add_argument(*args, **kwargs)
        EVERY_OPTION.update(action.option_strings)
        return action

    def parse_known_args(self, args=None, namespace=None):
        tokens = list(sys.argv[1:] if args is None else args)
        self._tokens = tokens[: tokens.index("--")] if "--" in tokens else tokens  # after it, arguments only
        namespace, extras = super().parse_known_args(args, namespace)
        for token in extras:  # an option cut short: say which ones it begins (argparse only calls it unrecognized)
            cut = self._cut_short(token) or self._not_ours(token)
            if cut:
                self.error(cut)
        return namespace, extras

    def _not_ours(self, token):
        """The refusal of an option this command has not got (``stability --n``), listing the ones it has; ``None``
        for a token that is no option (argparse's own message names it) or where the command has no options."""
        word = str(token).partition("=")[0]
        if not (word.startswith("--") and len(word) > 2) or not self._actions:
            return None
        ours = [" / ".join(a.option_strings) for a in self._actions
                if a.option_strings and "-h" not in a.option_strings]
        if not ours:
            return None
        note = f" ({self.unknown_note})" if self.unknown_note else ""
        return f"{word} is not an option of {self.prog}; allowed: {', '.join(ours)}{note}"

    def _cut_short(self, token):
        """The refusal of ``token`` when it is an option of this parser cut short (``--t-en``), else ``None``."""
        word = str(token).partition("=")[0]
        full = [option for option in self._option_string_actions if option.startswith(word) and option != word]
        if not (word.startswith("--") and full) or word == "--" or word in self._option_string_actions or \
                word in EVERY_OPTION:
            return None
        return (f"{word} is not an option of {self.prog}; allowed: options spelt in full, as "
                + (f"{', '.join(full[:-1])} or {full[-1]}" if len(full) > 1 else full[0]))

    def error(self, message):
        if message.startswith("the following arguments are required"):  # --vers was an option cut short
            tokens = getattr(self, "_tokens", ())
            cut = next(filter(None, map(self._cut_short, tokens)), None)
            # an option the command has not got is named first (run --bogus: argparse said -o was required)
            unknown = next(filter(None, (self._not_ours(token) for token in tokens
                                         if str(token).partition("=")[0] not in self._option_string_actions)), None)
            message = cut or unknown or message
        # "argument --dt: --dt = 0 is outside ..." names the option twice: keep our own message
        found = re.match(r"argument (\S+?): (.*)", message, flags=re.S)
        if found and any(found.group(2).startswith(opt + " ") for opt in found.group(1).split("/")):
            message = found.group(2)
        self.exit(EXIT_USAGE, f"{self.said_as}: error: {message}\n")


def parse_range_or_list(text, name, words=("T0", "T1", "DT"), item="t", count_check=None, single=False):
    """``A:B:STEP`` (``B`` included; ``(B - A)/STEP`` a whole number) or ``v1,v2,...`` into a list of floats.

    Generated values are rounded to 12 significant digits, so ``0:0.009:0.003`` gives values that
    ``ds.sel`` finds as typed. Empty entries are refused. ``count_check(count)``, if given, is called
    with the number of values before a range is expanded (``0:1:1e-12`` would be 1e12 of them). ``single``: a range
    with ``B == A`` is its one value (a study's ``--vary``; saved times are at least two).
    """
    a, b, d = words
    form = f"{a}:{b}:{d} ({b} included, {d} > 0, ({b} - {a})/{d} whole) or {item}1,{item}2,..."
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        try:
            if len(parts) != 3:
                raise ValueError
            start, stop, step = (float(x) for x in parts)
        except ValueError:
            raise ParameterError(name, text, form) from None
        if not (np.isfinite([start, stop, step]).all() and step > 0 and (stop > start or single and stop == start)):
            raise ParameterError(name, text, form)
        count = (stop - start) / step
        if not np.isfinite(count):
            raise ParameterError.invalid(name, text, f"has more values than can be counted (({b} - {a})/{d} = "
                                         f"{count:g})", form)
        whole = round(count)
        if abs(count - whole) > 1e-9 * max(1.0, count):
            raise ParameterError.invalid(name, text, f"does not end on its grid: ({b} - {a})/{d} = {count:.4g} "
                                         f"is not whole ({b} is included)", form)
        if count_check is not None:
            count_check(whole + 1)
        return [float(f"{start + k * step:.12g}") for k in range(whole + 1)]
    items = [x.strip() for x in text.split(",")]
    if not text or any(not x for x in items):
        raise ParameterError.invalid(name, text, "has an empty entry" if text else "is empty", form)
    try:
        return [float(x) for x in items]
    except ValueError:
        raise ParameterError(name, text, form) from None


def parse_times_arg(text, name="--times", n=None):
    """``T0:T1:DT`` (T1 included) or ``t1,t2,...`` into an array of times.

    With ``n`` (nodes), a range whose output would not fit in memory is refused before it is expanded.
    """
    check = (lambda count: check_saved_times(count, n, name=name, value=str(text))) if n is not None else None
    return np.array(parse_range_or_list(text, name, count_check=check))


def parse_sets(items, name="--set"):
    params = {}
    for item in items or []:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ParameterError(name, item, "NAME=VALUE")
        if key in params:
            raise ParameterError.invalid(name, item, f"sets {key} a second time", "each parameter once")
        params[key] = value.strip()
    return params


def _number_text(text):
    """A number as typed, for messages (``0``, not ``'0'``); anything else quoted."""
    try:
        float(text)
        return str(text).strip()
    except ValueError:
        return show(text)


def number_arg(name, low=0.0, high=np.inf, *, low_closed=False, high_closed=False, unit="", note=""):
    """An argparse ``type``: a float in the interval, or a one-line error naming ``name`` and the interval (and
    ``note``, what a value means: ``" (0: unbounded)"``)."""
    if low == -np.inf and high == np.inf:
        allowed = "finite numbers" + (f" [{unit}]" if unit else "")
    else:
        allowed = f"{'[' if low_closed else '('}{low:g}, {high:g}{']' if high_closed else ')'}" + (f" {unit}" if unit else "")
    allowed += note

    def convert(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not a number; allowed: {allowed}") from None
        above = value >= low if low_closed else value > low
        below = value <= high if high_closed else value < high
        if not np.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not a finite number; allowed: {allowed}")
        if not (above and below):
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is outside {allowed}")
        return value

    return convert


class Typed(float):
    """A number the command line gave, with its text as typed (``text``) for a refusal found later (``--rtol 1`` was
    said ``--rtol = 1.0``); the options take it as a plain float (:func:`integrator_option_args`)."""

    def __new__(cls, text):
        value = super().__new__(cls, text)
        value.text = str(text).strip()
        return value


def unchecked_number_arg(name, allowed):
    """An argparse ``type``: a number, its range checked once the integrator is known to take the option (``--rtol 5``
    on leap-frog was told rtol's range, then ``--rtol 1e-6`` that leap-frog has no rtol): ``allowed``, said for
    what is not a number."""

    def convert(text):
        try:
            return Typed(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not a number; allowed: {allowed}") from None

    return convert


class Refused:
    """The value of an option that its own check refused (``--atol -1``), kept until the command knows that it takes
    the option: "not an option of leapfrog" (of a study of paths, of a start without ``--from``, of the figure) is
    said before a value's range, whatever the value (``--atol -1`` on leap-frog was told atol's range, then ``--atol
    1e-6`` that leap-frog has no atol). :func:`refuse_late` says the refusal."""

    def __init__(self, option, text, message):
        self.option, self.text, self.message = option, str(text), message

    def __repr__(self):
        return _number_text(self.text)

    def refusal(self):
        return ParameterError(self.option, self.text, "", message=self.message)


def checked_late(option, convert):
    """An argparse ``type``: ``convert``'s value, or where it refuses the text a :class:`Refused` that
    :func:`refuse_late` says once the command has refused the options it does not take."""

    def late(text):
        try:
            return convert(text)
        except argparse.ArgumentTypeError as exc:
            return Refused(option, text, str(exc))

    return late


def refuse_late(args, names=None):
    """Refuse the first option of ``args`` (of ``names`` only, given) whose value its own check refused
    (:func:`checked_late`): called by a command once it has refused the options it does not take."""
    for name, value in vars(args).items():
        if isinstance(value, Refused) and (names is None or name in names):
            raise value.refusal()


def max_step_arg():
    """The argparse ``type`` of ``--max-step``: ``[0, inf) s``, 0 for no bound, as the integrators take it (its
    declared range, :class:`~mol_shell.integrators.tolerances.Tolerances`)."""
    return number_arg("--max-step", 0.0, low_closed=True, unit="s", note=MAX_STEP_NOTE)


def integer_arg(name, low=1, high=None, *, zero=""):
    """An argparse ``type``: an integer ``>= low`` (and ``<= high`` when given); with ``zero`` (what 0 means: "no
    finer grid"), 0 too (``--check-n``: 0 or a grid of 3 nodes or more)."""
    allowed = f"integers >= {low}" if high is None else f"integers in [{low}, {high}]"
    allowed = f"0 ({zero}) or {allowed}" if zero else allowed

    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not an integer; allowed: {allowed}") from None
        if zero and value == 0:
            return value
        if value < low or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"{name} = {value} is outside {allowed}")
        return value

    return convert


def choice_arg(name, options):
    """An argparse ``type``: one of ``options``, or a one-line error naming ``name`` and the options."""

    def convert(text):
        if text not in options:
            raise argparse.ArgumentTypeError(f"{name} = {show(text)} is outside {{{', '.join(options)}}}")
        return text

    return convert


def parse_atol(text):
    """``--atol``: one number, or ``FIELD=VALUE,...`` per field (the others keep the default 1e-9)."""

    allowed = f"[{ATOL_MIN:g}, inf), or FIELD=VALUE,... with FIELD in {{{', '.join(FIELDS)}}}"
    if "=" not in text:
        try:
            return number_arg("--atol", ATOL_MIN, low_closed=True)(text)
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(f"--atol = {_number_text(text)} is outside {allowed}") from None
    out = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        name = name.strip()
        try:
            number = float(value)
        except ValueError:
            number = float("nan")
        if name not in FIELDS or name in out or not (np.isfinite(number) and number >= ATOL_MIN):
            raise argparse.ArgumentTypeError(f"--atol = {text!r} is outside {allowed}, each field once")
        out[name] = number
    return out


def option_value(text):
    """A ``--option`` value as a scene file's TOML reads it (``200``, ``1e-3``, ``true``, ``"band"``); a bare word
    (``band``) is the string it spells."""
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        return text


def option_args(args, integrator, scene=None):
    """``--option NAME=VALUE`` as ``{name: value}``: an option of ``integrator`` beyond the flags, checked against
    its declared range as a scene file's ``[run]`` table is; refused by name otherwise. ``none`` or ``auto`` (any
    case) is ``None`` for an option that takes it (:func:`~mol_shell.integrators.loop.typed_value`). With ``scene``,
    an option ``integrator`` does not take there is refused as such before its value is (ida on the unshearable
    scene: ``jac_reuse=5000`` was told its range, then ``jac_reuse=5`` that it is not an option)."""
    given = parse_sets(getattr(args, "option", None), name="--option")
    out = {}
    for name, text in given.items():
        if name in FLAGS:
            raise ParameterError.invalid("--option", f"{name}={text}", f"sets {name}, which has its own flag",
                                         f"{FLAGS[name]} in its place")
        value = option_value(text)
        spec = declared(INTEGRATORS[integrator]).get(name) if integrator in INTEGRATORS else None
        if scene is not None and integrator in INTEGRATORS and name not in integrator_options(scene, integrator):
            raise _as_option(ParameterError.not_an_option(name, integrator, integrator_options(scene, integrator)),
                             {name})
        if spec is not None:
            value = typed_value(spec, value)  # none (any case) where the option takes None
            if not spec.check(value):
                raise refusal(f"--option {name}", value, spec, typed=text.strip() if is_number(value) else None)
        out[name] = value
    return out


def integrator_option_args(args):
    """``--dt/--rtol/--atol/--max-step`` given on the command line, as options."""
    return {k: float(v) if isinstance(v, Typed) else v
            for k, v in ((k, getattr(args, k, None)) for k in ("dt", "rtol", "atol", "max_step")) if v is not None}


def run_settings(args, run, scene, n):
    """``(times, t_end, integrator, options)`` of a run or a study's cases: the command line's options over a
    scene file's ``[run]`` table (``--t-end`` or ``--times`` replace both of the file's), the options checked."""
    # an empty --times or --integrator ('') is given, and refused as a blank one is (it ran the defaults)
    times = parse_times_arg(args.times, n=n) if args.times is not None else None
    if args.t_end is None and times is None:
        times = run.get("times")
    t_end = args.t_end if args.t_end is not None or args.times is not None else run.get("t_end")
    integrator = args.integrator if args.integrator is not None else run.get("integrator", "leapfrog")
    from_file = {k: v for k, v in run.items() if k not in ("integrator", "n", "t_end", "times")}
    if args.integrator is not None and args.integrator != run.get("integrator", "leapfrog"):
        # the command line's integrator wins, and the file's options for another integrator go with that one
        allowed = integrator_options(scene, integrator) if integrator in INTEGRATORS else set(from_file)
        for key in sorted(set(from_file) - set(allowed)):
            print(f"mol-shell: note: the scene file's [run] {key} = {from_file.pop(key)!r} is not an option of "
                  f"{integrator} (--integrator): left out", file=sys.stderr)
        while integrator in INTEGRATORS and from_file:  # options it has but refuses as set (jac_every without Newton)
            try:
                INTEGRATORS[integrator](**{k: v for k, v in from_file.items() if k in allowed})
                break
            except ParameterError as exc:
                if exc.name not in from_file:
                    break
                print(f"mol-shell: note: the scene file's [run] {exc.name} = {from_file.pop(exc.name)!r} is not "
                      f"taken by {integrator} (--integrator) as it is set ({exc}): left out", file=sys.stderr)
    named = option_args(args, integrator, scene)
    given = named | integrator_option_args(args)
    options = from_file | given
    late = [name for name, value in given.items() if isinstance(value, Refused)]  # said once the integrator takes it
    try:
        check_options(scene, integrator, {k: v for k, v in options.items() if k not in late})
        for name in late:
            if name not in integrator_options(scene, integrator):
                raise ParameterError.not_an_option(name, integrator, integrator_options(scene, integrator))
    except ParameterError as exc:
        if exc.name in from_file and exc.name not in given:  # the file's option: said with the file and table
            raise ParameterError(exc.name, exc.value, exc.allowed, message=f"{args.scene}: [run] {exc}") from None
        raise _as_option(exc, named, args) from None
    refuse_late(args)
    try:  # across each other, ours applied: a file's option blamed is said with the file (check_run_together)
        check_run_together(args.scene, integrator, options, given)
    except ParameterError as exc:
        raise _as_option(exc, named) from None
    return times, t_end, integrator, options


def _as_option(exc, named, args=None):
    """``exc`` about an option the command line set by ``--option NAME=VALUE`` (in ``named``), said so; about one a
    flag set with its range checked late (:class:`Typed`: ``--rtol``), said with the flag and the value as typed."""
    typed = getattr(args, exc.name, None) if isinstance(exc.name, str) and exc.name in FLAGS else None
    said = f"{exc.name} = {show(exc.value)}"
    if isinstance(typed, Typed) and str(exc).startswith(said):
        return ParameterError(FLAGS[exc.name], exc.value, exc.allowed,
                              message=f"{FLAGS[exc.name]} = {typed.text}{str(exc)[len(said):]}")
    if exc.name not in named:
        return exc
    return ParameterError(f"--option {exc.name}", exc.value, exc.allowed, message=f"--option {exc}")
