"""Animations: the deformed shell in 3-D, coloured by a field or stress, with its material fibres.

``mol-shell animate run.nc -o shell.gif`` (Pillow) or ``-o shell.mp4`` (ffmpeg from the
``imageio-ffmpeg`` wheel, so no system ffmpeg is needed); matplotlib renders headless (Agg). One
frame per saved time, the time in the frame. The fibres are material lines of constant reference
azimuth, drawn where they face the viewer: they turn with ``chi`` (twist shows as helices), and the
dashed straight lines are the same fibres in the reference configuration.
"""

from __future__ import annotations

import logging
import re
import subprocess

import numpy as np

from mol_shell._core.atomic import atomic_path
from mol_shell._core.errors import ParameterError, is_number
from mol_shell._core.paths import writable_path
from mol_shell.views.fields import field as field_values
from mol_shell.views.fields import field_names, run_of, surface_points

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


#: the largest frame rate (frames per second; the command line's ``--fps`` takes the same)
MAX_FPS = 100
#: the smallest: a frame of 500 s (a GIF stores a frame's duration in hundredths of a second, at most 655.35 s;
#: 0.001 overflowed it)
MIN_FPS = 0.002


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
            fps=DEFAULTS["fps"], width=DEFAULTS["width"], elev=16.0, azim=-62.0):
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
        Frames per second, in (0, :data:`MAX_FPS`].
    width : int
        Width in pixels (height 0.9 of it), in [100, 4096]; an MP4's width and height are rounded to even numbers.
    elev, azim : float
        Viewing angles, degrees (matplotlib's).

    Returns
    -------
    int
        Frames written.

    Raises
    ------
    ParameterError
        Named by its keyword (``field``, ``n_phi``, ...) for a value outside its range; named ``path`` when ffmpeg
        fails to encode the MP4; the file is written under a temporary name and renamed onto
        ``path`` when complete, so a failure leaves no file behind (and a previous one intact).
    """
    import matplotlib.pyplot as plt
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable

    check_integers(n_phi=n_phi, fibres=fibres, width=width)
    if not (is_number(fps) and MIN_FPS <= fps <= MAX_FPS):
        raise ParameterError("fps", fps, f"[{MIN_FPS:g}, {MAX_FPS}] frames per second")
    ds = run_of(ds)
    field, chosen = default_field(ds) if field is None else (field, "")
    values, units, _ = field_values(ds, field, "cells", option="field")
    path = writable_path(path, "path", suffixes=SUFFIXES)  # before the frames: its missing directories created
    suffix = path.suffix.lower().lstrip(".")
    cmap_name, norm = _scale(values)
    cmap = colormaps[cmap_name]
    surface = surface_points(ds, n_phi)
    surface = np.concatenate([surface, surface[:, :, :1]], axis=2)  # closed in phi
    lines = surface_points(ds, fibres) * [1.004, 1.004, 1.0]  # just outside the surface
    r0 = np.asarray(ds["r0"].values) if "r0" in ds else np.ones(ds.sizes["s"])
    z0 = np.asarray(ds["z0"].values) if "z0" in ds else np.asarray(ds["s"].values)
    phi = 2 * np.pi * np.arange(fibres) / fibres
    reference = np.stack([1.004 * r0[:, None] * np.cos(phi), 1.004 * r0[:, None] * np.sin(phi),
                          z0[:, None] + 0 * phi], axis=-1)
    view = np.array([np.cos(np.radians(azim)), np.sin(np.radians(azim))])
    extent = float(np.abs(surface[..., :2]).max()) * 1.02
    zlo, zhi = float(surface[..., 2].min()), float(surface[..., 2].max())

    dpi = 100
    pixels = frame_pixels(width, even=suffix == "mp4")
    # a hair over the pixels: matplotlib truncates inches x dpi, and 29 / 100 * 100 is 28.999999999999996
    fig = plt.figure(figsize=tuple((n + 1e-3) / dpi for n in pixels), dpi=dpi)
    ax = fig.add_axes((0.0, 0.0, 0.78, 0.86), projection="3d", computed_zorder=False)
    cax = fig.add_axes((0.8, 0.15, 0.035, 0.62))
    fig.colorbar(ScalarMappable(norm, cmap), cax=cax).set_label(_short_label(field, units), fontsize=9)
    cax.tick_params(labelsize=8)
    title = fig.text(0.03, 0.96, "", fontsize=9, va="top")

    def front(points):
        """Points whose outward radial direction faces the viewer; the others NaN (hidden behind the shell)."""
        out = points.copy()
        out[(points[..., :2] @ view) < 0] = np.nan
        return out

    def draw(k):
        ax.clear()
        colours = np.zeros((*surface.shape[1:3], 4))
        colours[:-1, :] = cmap(norm(values[k]))[:, None, :]
        x, y, z = (surface[k, ..., i] for i in range(3))
        ax.plot_surface(x, y, z, facecolors=colours, rstride=1, cstride=1, linewidth=0, antialiased=False,
                        shade=True, zorder=1)
        for j in range(fibres):
            ref = front(reference[:, j])
            ax.plot(ref[:, 0], ref[:, 1], ref[:, 2], color="0.3", lw=0.8, ls=(0, (3, 2)), zorder=2)
            fib = front(lines[k, :, j])
            ax.plot(fib[:, 0], fib[:, 1], fib[:, 2], color="k", lw=1.3, zorder=3)
        for i in (0, -1):  # the rims
            ax.plot(surface[k, i, :, 0], surface[k, i, :, 1], surface[k, i, :, 2], color="k", lw=0.8, zorder=3)
        ax.set_xlim(-extent, extent)
        ax.set_ylim(-extent, extent)
        ax.set_zlim(zlo, zhi)
        ax.set_box_aspect((2 * extent, 2 * extent, zhi - zlo), zoom=1.0)
        ax.view_init(elev=elev, azim=azim)
        ax.set_axis_off()
        title.set_text(f"{ds.attrs.get('scene', 'run')}   t = {float(ds['time'][k]):.4g} s\n"
                       "material fibres: black; in the reference state: dashed" + (f"\n{chosen}" if chosen else ""))

    count = ds.sizes["time"]
    try:
        with atomic_path(path) as tmp:
            if suffix == "mp4":
                _write_mp4(tmp, path, fig, draw, count, fps, dpi)
            else:
                _write_gif(tmp, fig, draw, count, fps)
    finally:
        plt.close(fig)
    return count


def _write_mp4(path, target, fig, draw, count, fps, dpi):
    """H.264 by the ffmpeg of ``imageio-ffmpeg`` into ``path``; a failure of the encoder is refused in one line naming
    ``path`` = ``target`` (the file the user asked for)."""
    import imageio_ffmpeg
    import matplotlib
    from matplotlib import animation

    matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    # the container named, whatever the output's name says
    writer = animation.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p", "-f", "mp4"])
    log = logging.getLogger("matplotlib.animation")
    level = log.level
    log.setLevel(logging.ERROR)  # the encoder's own lines: the message below says what matters in one
    try:
        with writer.saving(fig, str(path), dpi):
            for k in range(count):
                draw(k)
                writer.grab_frame()
    except (subprocess.CalledProcessError, OSError) as exc:  # OSError: a pipe broken by an encoder that quit
        said = [line.strip() for line in str(getattr(exc, "stderr", "") or "").splitlines() if line.strip()]
        why = re.sub(r" @ 0x[0-9a-fA-F]+", "", said[0]) if said else str(exc)  # [libx264 @ 0x55d...] -> [libx264]
        width, height = fig.canvas.get_width_height()
        raise ParameterError.invalid("path", str(target), f"could not be encoded ({why})",
                                     f"a .gif, or an .mp4 that ffmpeg can encode ({width} x {height} pixels here)"
                                     ) from None
    finally:
        log.setLevel(level)


def _write_gif(path, fig, draw, count, fps, palette_frames=6):
    """GIF by Pillow with one palette for all frames (built from a few of them), so the colours, and the
    colour bar, do not flicker from frame to frame as with a palette per frame."""
    from PIL import Image

    def render(k):
        draw(k)
        fig.canvas.draw()
        return Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())

    samples = [render(k) for k in np.unique(np.linspace(0, count - 1, min(palette_frames, count)).astype(int))]
    strip = Image.new("RGB", (samples[0].width, samples[0].height * len(samples)))
    for i, frame in enumerate(samples):
        strip.paste(frame, (0, i * frame.height))
    palette = strip.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    frames = [render(k).quantize(palette=palette, dither=Image.Dither.NONE) for k in range(count)]
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:], duration=round(1000 / fps),
                   loop=0)
