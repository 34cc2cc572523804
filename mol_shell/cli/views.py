"""Commands of the views: export (ParaView) and animate; how the views' refusals are said on the command line."""

from __future__ import annotations

import sys
from contextlib import contextmanager

from mol_shell._core.errors import ParameterError
from mol_shell.cli.args import integer_arg, number_arg, plural
from mol_shell.cli.inputs import check_companions
from mol_shell.results.dataset import RUN_FILE, read_run
from mol_shell.views.animate import (
    DEFAULTS,
    MAX_FPS,
    MAX_GIF_FPS,
    MIN_FPS,
    MOVING,
    RANGES,
    SUFFIXES,
    animate,
    default_field,
    gif_rate_note,
)
from mol_shell.views.export import FORMATS, N_PHI, N_PHI_MAX, companion_files, export, h5_renamed
from mol_shell.views.fields import check_run
from mol_shell.views.figures import incomplete_note

#: the keywords of the views' functions, as their refusals name them, and the options that set them here
OPTIONS = {"ds": "FILE", "path": "-o", "field": "--field", "n_phi": "--n-phi", "fibres": "--fibres",
           "width": "--width", "fps": "--fps", "time": "--time", "s": "--at-s", "count": "--fibres",
           "thickness_scale": "--thickness-scale", "response": "--response"}


@contextmanager
def said_as_options(**options):
    """A :class:`ParameterError` of a views function, which names the Python keyword (``n_phi = 2 is outside ...``),
    said with the command line's option instead (``--n-phi = 2 is outside ...``): :data:`OPTIONS`, and ``options``
    over them (a keyword the command sets by another option)."""
    options = OPTIONS | options
    try:
        yield
    except ParameterError as exc:
        option = options.get(exc.name)
        if option is None:
            raise
        text = str(exc)
        said = option + text[len(exc.name):] if text.startswith(exc.name) else text
        raise ParameterError(option, exc.value, exc.range or exc.allowed, message=said) from None


def read_drawable(filename, allowed=RUN_FILE, what="a mol_shell run file"):
    """The run in ``filename``, refused in one line naming the file when it has no saved times or values that are
    not finite (a hand-edited or damaged file), or is not a run (the refusal says ``what`` and ``allowed``). The
    Dataset's ``encoding["source"]`` is ``filename`` as given: a view's refusal of what it lacks (a variable the view
    reads: :func:`mol_shell.views.fields.check_run`) names the file so, as ``FILE`` (:func:`said_as_options`)."""
    ds = read_run(filename, allowed=allowed, what=what)
    ds.encoding["source"] = str(filename)
    check_run(ds, filename)
    return ds


def register_export(subparsers):
    parser = subparsers.add_parser("export", help="the shell in 3-D for ParaView (XDMF or VTU series)")
    parser.add_argument("file", metavar="FILE", help="netCDF file written by mol-shell run")
    parser.add_argument("--n-phi", type=integer_arg("--n-phi", 3, N_PHI_MAX), default=N_PHI,
                        help=f"azimuthal samples, 3 to {N_PHI_MAX} (default {N_PHI})")
    parser.add_argument("--faces", action="store_true", help="also the inner and outer faces (offset along the director)")
    parser.add_argument("-o", "--output", required=True, help="run.xdmf (with run.h5) or run.pvd (with run_NNNN.vtu)")
    parser.set_defaults(func=cmd_export, output_suffixes=set(FORMATS))


def cmd_export(args):
    ds = read_drawable(args.file)
    check_companions(args, companion_files(args.output, ds.sizes["time"]))
    with said_as_options():
        files = export(ds, args.output, args.n_phi, args.faces)
    extra = f" (+ {plural(len(files) - 1, 'file')})"
    print(f"wrote {args.output}{extra}: {plural(ds.sizes['time'], 'step')}, {ds.sizes['s']} nodes x {args.n_phi} "
          f"angles per surface{said_incomplete(ds)}")
    if h5_renamed(args.output):
        print(f"mol-shell: note: {h5_renamed(args.output)}", file=sys.stderr)
    return 0


def said_incomplete(ds):
    """`` [INCOMPLETE: MESSAGE]`` after what a view of a run that stopped early wrote, ``""`` after a complete one."""
    note = incomplete_note(ds.attrs)
    return f" [{note}]" if note else ""


def _range(name):
    low, high = RANGES[name]
    return f"{low} to {high}"


def register_animate(subparsers):
    parser = subparsers.add_parser("animate", help="the deformed shell in 3-D, one frame per saved time (GIF or MP4)")
    parser.add_argument("file", metavar="FILE", help="netCDF file written by mol-shell run")
    parser.add_argument("--field", default=DEFAULTS["field"],
                        help="what colours the shell: a field (chi, r, ...), a displacement (r_displacement, "
                        "z_displacement), a rate, a resultant (axial_torque, ...) or a face stress "
                        f"(von_mises_stress_outer, ...); default: the first of {', '.join(MOVING)} that varies over the "
                        "run beyond round-off (the frames and the command's output say which)")
    parser.add_argument("--n-phi", type=integer_arg("--n-phi", *RANGES["n_phi"]), default=DEFAULTS["n_phi"],
                        help=f"azimuthal samples, {_range('n_phi')} (default {DEFAULTS['n_phi']})")
    parser.add_argument("--fibres", type=integer_arg("--fibres", *RANGES["fibres"]), default=DEFAULTS["fibres"],
                        help=f"material fibres drawn, {_range('fibres')} (default {DEFAULTS['fibres']})")
    parser.add_argument("--fps", type=number_arg("--fps", MIN_FPS, MAX_FPS, low_closed=True, high_closed=True),
                        default=DEFAULTS["fps"], help=f"frames per second, [{MIN_FPS:g}, {MAX_FPS}]; a .gif's at most {MAX_GIF_FPS}, "
                        "its frame delay in whole hundredths of a second, the nearest (default 4)")
    parser.add_argument("--width", type=integer_arg("--width", *RANGES["width"]), default=DEFAULTS["width"],
                        help=f"width in pixels, {_range('width')} (default {DEFAULTS['width']}; height 0.9 of it; an .mp4's "
                        "sides rounded to even numbers)")
    parser.add_argument("-o", "--output", required=True, help="shell.gif or shell.mp4")
    parser.set_defaults(func=cmd_animate, output_suffixes=set(SUFFIXES))


def cmd_animate(args):
    ds = read_drawable(args.file)
    with said_as_options():  # an unknown --field is refused before anything is drawn
        count = animate(ds, args.output, args.field, n_phi=args.n_phi, fibres=args.fibres, fps=args.fps,
                        width=args.width)
    chosen = f", {default_field(ds)[1]}" if args.field is None else f", coloured by {args.field}"  # as asked
    print(f"wrote {args.output}: {plural(count, 'frame')}{chosen}{said_incomplete(ds)}")
    if gif_rate_note(args.fps, args.output):
        print(f"mol-shell: note: {gif_rate_note(args.fps, args.output)}", file=sys.stderr)
    return 0
