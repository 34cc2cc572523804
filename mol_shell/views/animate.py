"""Animations: the deformed shell in 3-D, coloured by a field or stress, with its material fibres.

``mol-shell animate run.nc -o shell.gif`` (Pillow) or ``-o shell.mp4`` (ffmpeg from the
``imageio-ffmpeg`` wheel, so no system ffmpeg is needed); matplotlib renders headless (Agg). One
frame per saved time, the time in the frame. The fibres are material lines of constant reference
azimuth, drawn where they face the viewer: they turn with ``chi`` (twist shows as helices), and the
dashed straight lines are the same fibres in the reference configuration.

Frames are drawn and written one at a time (the GIF by Pillow's frame encoder, the MP4 piped to ffmpeg), so the
memory an animation takes does not grow with its frames (:func:`check_memory` refuses a width that cannot fit), a
long one shows its progress, and Ctrl-C stops it, the encoder too, leaving no file.
"""

from __future__ import annotations

import contextlib
import re
import subprocess
import tempfile
import textwrap

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.atomic import atomic_path
from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell._core.paths import writable_path
from mol_shell._core.progress import progress_meter, progress_mode
from mol_shell.runs.resources import available_memory, show_bytes
from mol_shell.views.fields import SHELL, drawn_rows, field_names, row_means, run_of, surface_points
from mol_shell.views.fields import field as field_values
from mol_shell.views.figures import incomplete_note

SUFFIXES = ("gif", "mp4")
DEFAULTS = {"field": None, "n_phi": 48, "fibres": 12, "fps": 4, "width": 480}
#: what colours the shell when no field is given: the first of these that varies over the run beyond round-off
#: (:func:`default_field`; a pressurised sphere's chi is 0 to 1e-12 rad everywhere, and coloured the shell nothing)
MOVING = ("chi", "r_displacement", "z_displacement", "theta", "psi")
#: a field varies when its values span more than this, relative to 1 rad for angles and to the shell's size for
#: lengths (round-off of a run is 1e-16 to 1e-12 of them)
ROUND_OFF = 1e-9


def default_field(ds):
    """``(name, why)``: the first of :data:`MOVING` that the run ``ds`` offers and whose values over its saved times
    and nodes span more than :data:`ROUND_OFF` (of 1 rad, or of the shell's size for a displacement), and a few words
    saying so for the figure; ``chi`` when none does."""
    size = max(float(np.ptp(ds[name].values)) for name in ("r0", "z0", "r", "z") if name in ds) or 1.0
    offered = set(field_names(ds, derived=True))
    for name in (name for name in MOVING if name in offered):
        values = field_values(ds, name, "nodes")[0]
        scale = size if name.endswith("displacement") else 1.0
        if np.ptp(values) > ROUND_OFF * scale:
            skipped = MOVING[: MOVING.index(name)]
            why = f" ({', '.join(skipped)} {'does' if len(skipped) == 1 else 'do'} not vary)" if skipped else ""
            return name, f"coloured by {name}{why}"
    return "chi", f"coloured by chi (none of {', '.join(MOVING)} varies beyond round-off)"
#: the allowed ranges of the integer options: generous for a picture (a frame of 4096 px at 1024 azimuthal samples
#: and 360 fibres takes seconds), while the time and the memory a frame takes stay bounded (``--width 20000`` ran
#: for minutes, 100000 ran out of memory)
RANGES = {"n_phi": (3, 1024), "fibres": (1, 360), "width": (100, 4096)}


#: font size (points) and lines at most of the note a frame of a run that stopped early carries at its foot
NOTE_FONT, NOTE_LINES = 7, 3


#: x264's threads and look-ahead, fixed so that its memory does not grow with the machine's cores (a thread per
#: half core, each with frames of its own) and stays near 100 bytes a pixel: 285 MB at 1600 x 1440 (528 MB with its
#: defaults on 2 cores), 1.45 GB at 4096 x 3686 (2.9 GB)
ENCODER_LIMITS = ("-threads", "2", "-rc-lookahead", "10")
#: memory of an animation (bytes): the libraries and the run (a fixed part), per pixel of a frame the canvas and its
#: copies (RGBA, RGB, palette indices, the frame before, what changed; measured 231 MB for a GIF 1600 wide, 298 MB for
#: an MP4 4096 wide) and the MP4 encoder's (:data:`ENCODER_LIMITS`)
MEMORY_FIXED, MEMORY_PER_PIXEL, ENCODER_PER_PIXEL = 250e6, 16.0, 100.0


#: the largest frame rate (frames per second; the command line's ``--fps`` takes the same): an MP4's, which keeps any
MAX_FPS = 100
#: a GIF's: it stores a frame's delay in whole hundredths of a second (cs), and players show one of 1 cs (or none)
#: as 10 cs; 2 cs, 50 frames a second, is the shortest delay they honour
MAX_GIF_FPS = 50
#: a GIF's rate is said (:func:`gif_rate_note`) where its whole hundredths make it differ from the one asked by more
#: than this share
GIF_RATE_SAID = 0.01
#: the smallest: a frame of 500 s (a GIF stores a frame's duration in hundredths of a second, at most 655.35 s;
#: 0.001 overflowed it)
MIN_FPS = 0.002


def gif_delay(fps):
    """A GIF frame's delay for ``fps`` frames a second, in whole hundredths of a second: ``100 / fps`` to the nearest
    (at least 1)."""
    return max(1, int(100 / fps + 0.5))


def gif_rate_note(fps, path):
    """A note on the rate a ``.gif`` ``path`` plays at when its whole hundredths (:func:`gif_delay`) make it differ
    from ``fps`` by more than :data:`GIF_RATE_SAID` (30 fps: 3 cs, 33.3 fps); ``""`` otherwise (or for an .mp4)."""
    if not str(path).lower().endswith(".gif"):
        return ""
    delay = gif_delay(fps)
    if abs(100 / delay - fps) <= GIF_RATE_SAID * fps:
        return ""
    return (f"the GIF plays at {100 / delay:.3g} frames per second, not --fps {fps:g}: a GIF's frame delay is in "
            f"whole hundredths of a second ({delay} here)")


def check_integers(**values):
    """Refuse a value of ``n_phi``, ``fibres`` or ``width`` outside :data:`RANGES`, naming its keyword."""
    for name, value in values.items():
        low, high = RANGES[name]
        if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and low <= value <= high):
            raise ParameterError(name, value, f"integers in [{low}, {high}]")


def frame_pixels(width, even=False):
    """``(width, height)`` of a frame in pixels: the height 0.9 of the width, to the nearest pixel; ``even``: both
    to the nearest even number (H.264 in 4:2:0 colour, as players read it, needs even sizes)."""
    if even:
        return 2 * int(width / 2 + 0.5), 2 * int(0.9 * width / 2 + 0.5)
    return int(width), int(0.9 * width + 0.5)


def _short_label(name, units):
    words = name.replace("_", " ")
    for face in ("inner", "outer"):
        if words.endswith(" " + face):
            words = f"{words[: -len(face) - 1]} ({face} face)"
    return f"{words.replace('von mises', 'von Mises')} [{units}]"


def animation_bytes(width, suffix):
    """Memory an animation ``width`` pixels wide takes (bytes), as :data:`MEMORY_FIXED` and the per-pixel parts say:
    the same for any count of frames (one is in memory at a time)."""
    w, h = frame_pixels(width, even=suffix == "mp4")
    return MEMORY_FIXED + w * h * (MEMORY_PER_PIXEL + (ENCODER_PER_PIXEL if suffix == "mp4" else 0.0))


def check_memory(width, suffix):
    """Refuse, naming ``width``, an animation whose frames (and encoder) need more memory than is available
    (:func:`mol_shell.runs.resources.available_memory`: the machine's, or ``$MOL_SHELL_MEMORY``), saying the widest
    that fits."""
    need = animation_bytes(width, suffix)
    available, source = available_memory()
    if need <= available:
        return
    low = RANGES["width"][0]
    fits = max((w for w in range(low, width) if animation_bytes(w, suffix) <= available), default=None)
    allowed = f"[{low}, {fits}] pixels here" if fits is not None else "none here (less memory than the smallest frame"
    if fits is None:
        allowed += " needs)"
    raise ParameterError("width", width, allowed, message=(
        f"width = {width} needs about {show_bytes(need)} for a frame of {'x'.join(map(str, frame_pixels(width)))} "
        f"pixels{' and its video encoder' if suffix == 'mp4' else ''}, more than the {show_bytes(available)} "
        f"available ({source}); allowed: {allowed}"))


def _scale(values):
    """Colour map and limits over all frames: diverging and symmetric when the values change sign. NaN (stresses
    past a law's limit: ``attrs["stresses"]``) take no part and are drawn as gaps (the map's transparent "bad")."""
    import matplotlib.colors as mcolors

    finite = values[np.isfinite(values)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    if lo < 0 < hi:
        top = max(-lo, hi)
        return "RdBu_r", mcolors.Normalize(-top, top)
    if hi - lo <= 1e-12 * max(abs(hi), abs(lo), 1e-300):  # a constant: a visible colour, not the map's end
        pad = max(abs(hi) * 1e-3, 1e-12)
        lo, hi = lo - pad, hi + pad
    return "viridis", mcolors.Normalize(lo, hi)


def animate(ds, path, field=DEFAULTS["field"], *, n_phi=DEFAULTS["n_phi"], fibres=DEFAULTS["fibres"],
            fps=DEFAULTS["fps"], width=DEFAULTS["width"], elev=16.0, azim=-62.0, progress=None):
    """Write an animation of run ``ds`` to ``path`` (``.gif`` or ``.mp4``), one frame per saved time.

    Parameters
    ----------
    ds : xarray.Dataset or str or os.PathLike
        A run, or the path of its netCDF file; stresses (:func:`mol_shell.results.stresses.add_stresses`) can colour
        the shell too.
    path : str or os.PathLike
        ``.gif`` or ``.mp4``; missing directories are created.
    field : str, optional
        What colours the shell (:func:`mol_shell.views.fields.field_names`, and ``r_displacement``,
        ``z_displacement``): node fields are averaged to the cells, face stresses are ``NAME_inner`` /
        ``NAME_outer``. One colour scale for all frames. Default: :func:`default_field`, the first of :data:`MOVING`
        that varies over the run, named in the frames' title.
    n_phi : int
        Azimuthal samples of the surface, in [3, 1024].
    fibres : int
        Material fibres drawn (evenly spaced reference azimuths), in [1, 360].
    fps : float
        Frames per second, in [:data:`MIN_FPS`, :data:`MAX_FPS`]; a ``.gif``'s at most :data:`MAX_GIF_FPS`, its
        frame delay ``100 / fps`` hundredths of a second to the nearest whole one (:func:`gif_rate_note`).
    width : int
        Width in pixels (height 0.9 of it), in [100, 4096]; an MP4's width and height are rounded to even numbers.
    elev, azim : float
        Viewing angles, degrees (matplotlib's).
    progress : bool, optional
        As :func:`mol_shell.simulate`'s: a bar of the frames on a terminal, else a line a minute of a longer
        animation (``None``); ``False`` nothing.

    Returns
    -------
    int
        Frames written.

    Raises
    ------
    ParameterError
        Named by its keyword (``field``, ``n_phi``, ...) for a value outside its range; named ``path`` when ffmpeg
        fails to encode the MP4; the file is written under a temporary name and renamed onto
        ``path`` when complete, so a failure, or a Ctrl-C (``KeyboardInterrupt``), leaves no file behind (and a
        previous one intact). Frames are drawn and written one at a time: the memory an animation takes does not
        grow with its frames.
    """
    import matplotlib.pyplot as plt
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable

    check_integers(n_phi=n_phi, fibres=fibres, width=width)
    if not (is_number(fps) and MIN_FPS <= fps <= MAX_FPS):
        raise ParameterError("fps", fps, f"[{MIN_FPS:g}, {MAX_FPS}] frames per second")
    mode = progress_mode(progress)
    ds = run_of(ds, "animate", SHELL)
    field, chosen = default_field(ds) if field is None else (field, "")
    values, units, _ = field_values(ds, field, "cells", option="field")
    path = writable_path(path, "path", suffixes=SUFFIXES)  # before the frames: its missing directories created
    suffix = path.suffix.lower().lstrip(".")
    if suffix == "gif" and fps > MAX_GIF_FPS:  # an .mp4 honours the rate asked: up to MAX_FPS
        allowed = f"[{MIN_FPS:g}, {MAX_GIF_FPS}] frames per second for a .gif"
        shown = f"{fps:g}" if float(f"{fps:g}") == fps else show(fps)  # 50.00000000000001 was said as 50
        raise ParameterError("fps", fps, allowed, message=f"fps = {shown} is outside {allowed}",
                             hint=f"a GIF's delays are whole hundredths of a second; an .mp4 takes up to {MAX_FPS}")
    check_memory(width, suffix)  # before anything is drawn: the frames and the encoder, whatever their count
    cmap_name, norm = _scale(values)
    cmap = colormaps[cmap_name]

    def surface(k):
        """The surface at saved time ``k``, ``(s, n_phi + 1, 3)``: closed in phi (one frame's: the whole run's took
        memory with its saved times, 130 MB for 686 of 81 nodes)."""
        points = surface_points(ds, n_phi, times=[k])[0][rows]
        return np.concatenate([points, points[:, :1]], axis=1)

    r0 = np.asarray(ds["r0"].values) if "r0" in ds else np.ones(ds.sizes["s"])
    z0 = np.asarray(ds["z0"].values) if "z0" in ds else np.asarray(ds["s"].values)
    phi = 2 * np.pi * np.arange(fibres) / fibres
    reference = np.stack([1.004 * r0[:, None] * np.cos(phi), 1.004 * r0[:, None] * np.sin(phi),
                          z0[:, None] + 0 * phi], axis=-1)
    view = np.array([np.cos(np.radians(azim)), np.sin(np.radians(azim))])
    extent, zlo, zhi = _extents(ds, n_phi)

    dpi = 100
    pixels = frame_pixels(width, even=suffix == "mp4")
    rows = drawn_rows(ds.sizes["s"], max(pixels))  # no more bands along s than the frame has pixels
    # a hair over the pixels: matplotlib truncates inches x dpi, and 29 / 100 * 100 is 28.999999999999996
    fig = plt.figure(figsize=tuple((n + 1e-3) / dpi for n in pixels), dpi=dpi)
    note = _incomplete_lines(ds.attrs, pixels[0], dpi)
    foot = (len(note) * NOTE_FONT * 1.3 * dpi / 72 + 6) / pixels[1] if note else 0.0  # the shell drawn above it
    ax = fig.add_axes((0.0, foot, 0.78, 0.86 - foot), projection="3d", computed_zorder=False)
    cax = fig.add_axes((0.8, 0.15, 0.035, 0.62))
    fig.colorbar(ScalarMappable(norm, cmap), cax=cax).set_label(_short_label(field, units), fontsize=9)
    cax.tick_params(labelsize=8)
    title = fig.text(0.03, 0.96, "", fontsize=9, va="top")
    if note:  # every frame says it, as the figures do: the run stopped before its end
        fig.text(0.03, 3 / pixels[1], "\n".join(note), fontsize=NOTE_FONT, va="bottom")

    def front(points):
        """Points whose outward radial direction faces the viewer; the others NaN (hidden behind the shell)."""
        out = points.copy()
        out[(points[..., :2] @ view) < 0] = np.nan
        return out

    def draw(k):
        ax.clear()
        colours = np.zeros((len(rows), n_phi + 1, 4))
        colours[:-1, :] = cmap(norm(row_means(values[k], rows)))[:, None, :]
        shell = surface(k)
        ax.add_collection(_surface(shell, colours))
        lines = surface_points(ds, fibres, times=[k])[0][rows] * [1.004, 1.004, 1.0]  # just outside the surface
        for j in range(fibres):
            ref = front(reference[rows, j])
            ax.plot(ref[:, 0], ref[:, 1], ref[:, 2], color="0.3", lw=0.8, ls=(0, (3, 2)), zorder=2)
            fib = front(lines[:, j])
            ax.plot(fib[:, 0], fib[:, 1], fib[:, 2], color="k", lw=1.3, zorder=3)
        for i in (0, -1):  # the rims
            ax.plot(shell[i, :, 0], shell[i, :, 1], shell[i, :, 2], color="k", lw=0.8, zorder=3)
        ax.set_xlim(-extent, extent)
        ax.set_ylim(-extent, extent)
        ax.set_zlim(zlo, zhi)
        ax.set_box_aspect((2 * extent, 2 * extent, zhi - zlo), zoom=1.0)
        ax.view_init(elev=elev, azim=azim)
        ax.set_axis_off()
        title.set_text(f"{ds.attrs.get('scene', 'run')}   t = {float(ds['time'][k]):.4g} s\n"
                       "material fibres: black; in the reference state: dashed" + (f"\n{chosen}" if chosen else ""))

    count = ds.sizes["time"]

    def render(k):
        """Frame ``k`` as RGBA pixels ``(height, width, 4)`` (a view of the canvas: the next frame overwrites it)."""
        draw(k)
        fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba())

    meter = progress_meter(mode, "animating", count="frame {n} of {total}", total=count,
                           unit="frame")
    try:
        with atomic_path(path) as tmp:
            if suffix == "mp4":
                _write_mp4(tmp, path, render, count, fps, meter)
            else:
                _write_gif(tmp, render, count, fps, meter)
        interrupts.wrote(path)  # an interrupt from here on: said after writing it
    finally:
        plt.close(fig)
        if meter is not None:
            meter.close()
    return count


def _incomplete_lines(attrs, width, dpi):
    """The lines of the note at the foot of each frame of a run that stopped early (:data:`NOTE_LINES` at most, the
    last cut short with "..."), ``[]`` for a complete run."""
    if not incomplete_note(attrs):
        return []
    chars = max(20, int(width / (0.6 * NOTE_FONT * dpi / 72)) - 4)
    note = textwrap.wrap(f"[{incomplete_note(attrs)}]", chars)
    if len(note) > NOTE_LINES:
        note = note[:NOTE_LINES - 1] + [note[NOTE_LINES - 1][: chars - 3] + "..."]
    return note


#: the least half-width of the box drawn, and height, as a share of the shell's largest size (:func:`_extents`)
MIN_BOX = 0.05


def _extents(ds, n_phi, points=1_000_000):
    """``(extent, zlo, zhi)``: the half-width of the box drawn (2 % over the largest ``|x|``, ``|y|`` of the surface at
    any saved time) and the surface's lowest and highest ``z``; computed a block of saved times at a time, of about
    ``points`` surface points. Neither the half-width nor the height is below :data:`MIN_BOX` of the larger of them
    (nor 0: a shell on its axis at one height gets a box of its distance from the origin, or of 1 m)."""
    block = max(1, points // (ds.sizes["s"] * n_phi))
    extent, zlo, zhi = 0.0, np.inf, -np.inf
    for start in range(0, ds.sizes["time"], block):
        part = surface_points(ds, n_phi, times=slice(start, start + block))
        extent = max(extent, float(np.abs(part[..., :2]).max()))
        zlo, zhi = min(zlo, float(part[..., 2].min())), max(zhi, float(part[..., 2].max()))
    # a shell on its axis (r = 0 everywhere: a degenerate file, drawable) or flat in z: a box of a size of its own,
    # not of none (matplotlib's projection of an empty range was a singular matrix)
    size = max(extent, zhi - zlo) or max(abs(zlo), 1.0)
    extent = max(extent, MIN_BOX * size)
    if zhi - zlo < MIN_BOX * size:
        middle = (zlo + zhi) / 2
        zlo, zhi = middle - MIN_BOX * size / 2, middle + MIN_BOX * size / 2
    return extent * 1.02, zlo, zhi


def _surface(points, colours):
    """The shell's surface as :meth:`~mpl_toolkits.mplot3d.axes3d.Axes3D.plot_surface` draws it with
    ``facecolors=colours, rstride=1, cstride=1, shade=True`` (a quad per grid cell, its corners in the order
    ``plot_surface`` takes them, shaded by its light), made from arrays: ``plot_surface`` converts a colour per quad
    one at a time, 0.27 s of the 0.35 s a frame of 81 nodes x 48 azimuths took."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    quads = np.stack([points[:-1, :-1], points[:-1, 1:], points[1:, 1:], points[1:, :-1]], axis=2).reshape(-1, 4, 3)
    face = colours[:-1, :-1].reshape(-1, 4)
    return Poly3DCollection(quads, facecolors=face, edgecolors=face, shade=True, linewidth=0, antialiased=False,
                            zorder=1)


def _said_by(log):
    """The first line ffmpeg wrote to ``log`` (a file), without its objects' addresses (``[libx264 @ 0x55d...]`` ->
    ``[libx264]``); ``""`` when it wrote none."""
    log.seek(0)
    said = [line.strip() for line in log.read().decode(errors="replace").splitlines() if line.strip()]
    return re.sub(r" @ 0x[0-9a-fA-F]+", "", said[0]) if said else ""


def _write_mp4(path, target, render, count, fps, meter=None):
    """H.264 by the ffmpeg of ``imageio-ffmpeg`` into ``path``, each frame piped to it as it is drawn (one frame in
    memory; the encoder's own look-ahead is its own). ffmpeg runs in a session of its own, so a Ctrl-C at the
    terminal (SIGINT to the foreground process group) reaches this process alone: its ``KeyboardInterrupt`` stops
    the encoder and leaves no file (an ffmpeg killed by the same signal was said as "could not be encoded", exit
    2); so does the command line's SIGTERM (exit 143), wherever it lands, the encoder's start included. A failure of the encoder is refused in one line naming ``path`` = ``target`` (the file the user asked for)."""
    import imageio_ffmpeg

    first = render(0)
    height, width = first.shape[:2]
    command = [imageio_ffmpeg.get_ffmpeg_exe(), "-f", "rawvideo", "-vcodec", "rawvideo", "-s", f"{width}x{height}",
               "-pix_fmt", "rgba", "-framerate", repr(float(fps)), "-loglevel", "error", "-i", "pipe:",
               "-vcodec", "libx264", *ENCODER_LIMITS, "-pix_fmt", "yuv420p", "-f", "mp4", "-y", str(path)]  # the container named

    def refused(why):
        return ParameterError.invalid("path", str(target), f"could not be encoded ({why})",
                                      f"a .gif, or an .mp4 that ffmpeg can encode ({width} x {height} pixels here)")

    with tempfile.TemporaryFile() as log:  # a file, not a pipe: an encoder that says much never waits on it
        encoder = None
        try:
            # a Ctrl-C or SIGTERM as the encoder starts is raised once it is ours to stop: raised inside Popen, the
            # encoder ran on, unwaited for, and could write its file into the temporary directory as it was removed
            with interrupts.held():
                try:
                    encoder = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log,
                                               start_new_session=True)
                except OSError as exc:
                    raise refused(exc) from None
            for k in range(count):
                frame = first if k == 0 else render(k)
                try:
                    encoder.stdin.write(frame.tobytes())
                except OSError:  # a pipe broken by an encoder that quit: what it said is below
                    break
                if meter is not None:
                    meter.update(1)
            with contextlib.suppress(OSError):
                encoder.stdin.close()
            code = encoder.wait()
        except BaseException:  # Ctrl-C, SIGTERM or a failure while drawing: the encoder stops with us, no file kept
            if encoder is not None:
                encoder.kill()
                encoder.wait()
            raise
        finally:
            if encoder is not None:
                with contextlib.suppress(OSError):
                    encoder.stdin.close()
        if code != 0:
            raise refused(_said_by(log) or f"ffmpeg exited with status {code}")


def _write_gif(path, render, count, fps, meter=None, palette_frames=6, palette_width=640):
    """GIF by Pillow with one palette for all frames (built from a few of them, shrunk to at most ``palette_width``
    pixels across), so the colours, and the colour bar, do not flicker from frame to frame as with a palette per frame.

    Written as the frames are drawn: the header with the palette, then each frame, the part that changed since the
    one before (as Pillow's ``save_all`` writes them), LZW-coded by Pillow's ``GifImagePlugin.getdata``; one frame
    in memory. ``save_all`` keeps every frame until the end (984 MB for 144 frames 1600 pixels wide)."""
    from PIL import GifImagePlugin, Image

    def rgb(k):
        return Image.fromarray(np.ascontiguousarray(render(k)[..., :3]))

    picks = np.unique(np.linspace(0, count - 1, min(palette_frames, count)).astype(int))
    shrink = max(1, int(np.ceil(render(0).shape[1] / palette_width)))
    samples = [rgb(k).reduce(shrink) for k in picks]
    strip = Image.new("RGB", (samples[0].width, samples[0].height * len(samples)))
    for i, frame in enumerate(samples):
        strip.paste(frame, (0, i * frame.height))
    palette = strip.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    del samples, strip
    duration = 10 * gif_delay(fps)  # ms, a whole number of hundredths: Pillow stores duration // 10
    previous = None
    with open(path, "wb") as out:
        for k in range(count):
            frame = rgb(k).quantize(palette=palette, dither=Image.Dither.NONE)
            pixels = np.asarray(frame)
            options = {"duration": duration, "disposal": 1}  # 1: each frame drawn over the one before
            if previous is None:
                header, _ = GifImagePlugin.getheader(frame, info={"loop": 0, "duration": duration, "optimize": False})
                out.write(b"".join(header))
                part, offset = frame, (0, 0)
            else:
                part, offset, clear = _delta(previous, pixels, len(palette.getpalette()) // 3)
                if clear is not None:
                    options["transparency"] = clear
            out.writelines(GifImagePlugin.getdata(part, offset=offset, **options))
            previous = pixels
            if meter is not None:
                meter.update(1)
        out.write(b";")  # the GIF trailer


def _delta(before, after, colours):
    """What of frame ``after`` (palette indices) is written over ``before``: ``(part, offset, clear)``, the box of
    the pixels that changed (one pixel where none did: a frame is written for its time all the same) as a "P" image,
    its corner, and the index of a colour the box's changed pixels do not use, given to the pixels that did not
    change, transparent (``None`` where the ``colours`` of the palette are all used): as Pillow's ``save_all`` writes
    a frame, so that long runs of that index compress."""
    from PIL import Image

    changed = before != after
    rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
    if not rows.size:
        rows, cols = np.zeros(1, int), np.zeros(1, int)
    box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
    part, same = after[box].copy(), ~changed[box]
    unused = np.flatnonzero(np.bincount(part[~same], minlength=256)[:colours] == 0)
    clear = int(unused[0]) if unused.size and same.any() else None
    if clear is not None:
        part[same] = clear
    image = Image.frombytes("P", (part.shape[1], part.shape[0]), np.ascontiguousarray(part).tobytes())
    return image, (int(cols[0]), int(rows[0])), clear
