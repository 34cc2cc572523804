"""3-D export for ParaView: the revolved shell at every saved time, written by meshio.

``mol-shell export run.nc -o run.xdmf`` (XDMF 3 with one HDF5 file beside it) or ``-o run.pvd``
(a ``.vtu`` file per saved time and the ``.pvd`` collection that ParaView opens as a time
series). The surface is the base surface revolved with ``--n-phi`` azimuthal samples, each material
point placed by the rotationally symmetric map (:func:`mol_shell.views.fields.surface_points`); with
``--faces`` the inner and outer faces (offset along the director) are added to the same mesh. Quads
join the samples, one per cell of the grid and azimuthal interval, so a quad is a cell of the run; at a pole
(a closed shell's end on the axis) the circle of samples is one point, joined to the next circle by triangles
(a second block of cells), so the surface is closed there.

The XDMF series is one mesh, the reference (natural) shell, written once, and per saved time its point
and cell data, among them the 3-vector ``displacement`` from the reference to the position at that time:
ParaView's Warp By Vector (scale 1) and ``meshio.xdmf.TimeSeriesReader`` (points + displacement) show
the motion. A ``.vtu`` of the PVD series holds the moved points themselves, and ``displacement`` too.

Point data: ``displacement`` (m), the fields and their rates, ``phi`` (the reference azimuth, rad),
``zeta`` (the depth of the point from the base surface, m: a graded wall's faces at its own ``-h(s)``, ``+h(s)``)
and, with stresses, the resultants and face stresses averaged to the nodes (face stresses as ``NAME_inner``,
``NAME_outer``). Cell data: the resultants and face stresses exactly as computed per cell. One
step per saved time, at that time. The ``.xdmf`` or ``.pvd`` of a run that stopped early (``attrs["complete"] = 0``)
carries a comment saying so (:func:`mark`).
"""

from __future__ import annotations

import contextlib
import gc
import os
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.atomic import keep_inputs, staged
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import beside, check_lengths, link_target, writable_path
from mol_shell._core.write_aside import WriteAside
from mol_shell.views.fields import (
    REFERENCE,
    SHELL,
    azimuths,
    face_depths,
    field,
    field_names,
    reference_points,
    run_of,
    surface_points,
)
from mol_shell.views.figures import incomplete_note

FORMATS = ("xdmf", "pvd")
#: default azimuthal samples, and the most: 1024 is smooth beyond what a screen shows, while the points, data and
#: files of a step, which grow as nodes x n_phi (41 nodes at 1024 with --faces: about 150 MB and 4 s), stay
#: bounded (``--n-phi 1e9`` ran out of memory)
N_PHI = 64
N_PHI_MAX = 1024


def quads(n, n_phi, surfaces=1):
    """Quad connectivity ``(cells, 4)`` of ``surfaces`` stacked grids of ``n x n_phi`` points (node-major),
    closed in ``phi``; ordered so that the normal ``d/dphi x d/ds`` points away from the axis."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n_phi), indexing="ij")
    i, j = i.ravel(), j.ravel()
    jn = (j + 1) % n_phi
    one = np.stack([i * n_phi + j, i * n_phi + jn, (i + 1) * n_phi + jn, (i + 1) * n_phi + j], axis=1)
    return np.concatenate([one + k * n * n_phi for k in range(surfaces)]).astype(np.int64)


def mesh_series(ds, n_phi=N_PHI, faces=False):
    """Cells, the reference points, and the points and data of each saved time (a generator, so one step is in
    memory at a time). ``point_data["displacement"]`` is ``points - reference``.

    The grid of each surface is ``n x n_phi`` points joined by quads (:func:`quads`); an end node whose circle lies on
    the axis in the reference and at every saved time (a pole: :func:`axis_rings`) is one point, joined to its
    neighbouring circle by triangles, so the surface is closed there and no cell has an edge of zero length.

    Returns
    -------
    cells : list of ``(type, ndarray)``
        ``("quad", (quads, 4))`` and, where the shell has a pole, ``("triangle", (triangles, 3))``; meshio's blocks.
    reference : ndarray ``(P, 3)``
    steps : generator of ``(points (P, 3), point_data {name: (P,) or (P, 3)}, cell_data {name: [per block]})``
    """
    n = ds.sizes["s"]
    depths = (np.zeros(n), *face_depths(ds)) if faces else (np.zeros(n),)  # per node: a graded wall's follow h(s)
    surfaces = len(depths)
    nodal = {name: field(ds, name, "nodes")[0] for name in field_names(ds)}
    cellwise = {name: field(ds, name, "cells")[0] for name in field_names(ds)
                if name not in ds or ds[name].dims != ("time", "s")}
    constant = {"phi": np.tile(azimuths(n_phi), n * surfaces),
                "zeta": np.repeat(np.concatenate(depths), n_phi)}
    cells, keep, rows = closed_cells(n, n_phi, surfaces, axis_rings(ds, depths))
    constant = {name: values[keep] for name, values in constant.items()}

    def spread(values):  # per node (or cell) -> per point (or quad) of every surface
        return np.tile(np.repeat(values, n_phi), surfaces)

    reference = np.concatenate([reference_points(ds, n_phi, zeta).reshape(-1, 3) for zeta in depths])[keep]

    def steps():
        for k in range(ds.sizes["time"]):
            points = np.concatenate([surface_points(ds, n_phi, zeta, times=[k])[0].reshape(-1, 3)
                                     for zeta in depths])[keep]
            point_data = {"displacement": points - reference} | {name: spread(v[k])[keep] for name, v in nodal.items()}
            cell_data = {name: [spread(v[k])[r] for r in rows] for name, v in cellwise.items()}
            yield points, point_data | constant, cell_data

    return cells, reference, steps()


#: a circle of points is on the axis (a pole) where its radius is at most this share of the shell's size, in the
#: reference and at every saved time (a pole's base point is at r = 0 exactly; a face's, off it by zeta cos(pi / 2),
#: 1e-17 of the thickness)
ON_AXIS = 1e-12


def axis_rings(ds, depths):
    """``[(surface, node)]``: the end nodes whose circle of points of surface ``surface`` (depth ``depths[surface]``
    along the director) lies on the axis (within :data:`ON_AXIS` of the shell's size) in the reference and at every
    saved time: the poles of a closed shell."""
    r, theta, psi = (np.asarray(ds[name].values, dtype=float) for name in ("r", "theta", "psi"))
    if all(name in ds for name in REFERENCE):
        r = np.concatenate([r, np.asarray(ds["r0"].values, dtype=float)[None]])
        theta = np.concatenate([theta, np.asarray(ds["theta0"].values, dtype=float)[None]])
        psi = np.concatenate([psi, np.zeros((1, psi.shape[1]))])
    size = max(float(np.abs(r).max()), float(np.ptp(ds["z"].values)), float(np.abs(depths).max()))
    rings = []
    for surface, zeta in enumerate(depths):
        radius = np.hypot(r + zeta * np.cos(psi) * np.cos(theta), zeta * np.sin(psi))  # (2.8): |r a2 + zeta d| off k
        rings += [(surface, node) for node in (0, r.shape[1] - 1) if radius[:, node].max() <= ON_AXIS * size]
    return sorted(set(rings))


def closed_cells(n, n_phi, surfaces, rings):
    """The cells of :func:`quads` with each circle of ``rings`` (``(surface, node)``) made one point (its first).

    Returns
    -------
    cells : list of ``(type, ndarray)``
        The quads that keep four corners, and (where there are rings) the triangles of those with two of them on
        a ring's point: each keeps its corners' order, so its normal points as the quad's did.
    keep : ndarray
        The grid points kept, in order (the others: a ring's but its first).
    rows : list of ndarray
        For each block of ``cells``, its rows in :func:`quads` (what a cell's data are taken from).
    """
    full = quads(n, n_phi, surfaces)
    target = np.arange(surfaces * n * n_phi)
    for surface, node in rings:
        ring = (surface * n + node) * n_phi + np.arange(n_phi)
        target[ring] = ring[0]
    kept = target[full]
    first, last = kept[:, 0] == kept[:, 1], kept[:, 2] == kept[:, 3]  # a pole at the cell's first (last) node
    quad_rows = np.flatnonzero(~first & ~last)
    tri_first, tri_last = np.flatnonzero(first & ~last), np.flatnonzero(last & ~first)
    keep = np.unique(target)
    renumber = np.zeros(target.size, dtype=np.int64)
    renumber[keep] = np.arange(keep.size)
    cells, rows = [("quad", renumber[kept[quad_rows]])], [quad_rows]
    if tri_first.size or tri_last.size:
        cells.append(("triangle", renumber[np.concatenate([kept[tri_first][:, [0, 2, 3]],
                                                           kept[tri_last][:, [0, 1, 2]]])]))
        rows.append(np.concatenate([tri_first, tri_last]))
    return cells, keep, rows


#: gzip level of the HDF5 data of an XDMF export (with byte shuffling: the data repeat along each circle of
#: points, so they shrink about 6x; every HDF5 reader, ParaView's included, decompresses them)
H5_GZIP = 4
#: arrays below this many bytes are stored as they are: a compressed (chunked) array costs about 2 kB of
#: HDF5 bookkeeping, more than a small one gains (measured: 40 points per array, 386 kB compressed all, 375 kB
#: so; 512 points, 2.47 MB uncompressed, 1.67 MB so; 2,624 points, 12.3 MB, 1.77 MB)
H5_COMPRESS_FROM = 4096


def _compressing(create_dataset):
    """``h5py`` 's ``create_dataset`` with gzip for arrays of :data:`H5_COMPRESS_FROM` bytes or more."""

    def create(name, shape=None, dtype=None, data=None, **options):
        if data is not None and np.asarray(data).nbytes >= H5_COMPRESS_FROM:
            options.update(compression="gzip", compression_opts=H5_GZIP, shuffle=True)
        return create_dataset(name, shape, dtype, data, **options)

    return create


#: what an XDMF file's HDF5 data cannot have in their file's name, and what stands for it there: XDMF names a data
#: set ``FILE:/PATH``, split at ':' (``run_18:00.h5:/data2`` could not be read back, by meshio nor ParaView)
H5_UNSAFE, H5_SAFE = ":", "_"


def companion_files(path, steps):
    """The files written beside ``path`` for ``steps`` saved times: ``<stem>.h5`` for ``.xdmf`` (each ':' of the stem
    replaced by '_', :data:`H5_UNSAFE`; :func:`h5_renamed`), ``<stem>_NNNN.vtu`` for ``.pvd`` (the writers below name
    theirs so; the command line checks them before the work). ``path`` a symbolic link: beside its target, named by
    the target's stem, as the file written names them (:func:`~mol_shell._core.paths.beside`, ``named_inside``)."""
    path = link_target(Path(os.fspath(path)).expanduser())
    if path.suffix.lower() == ".xdmf":
        return [beside(path, ".h5", path.stem.replace(H5_UNSAFE, H5_SAFE), named_inside=True)]
    return [beside(path, f"_{k:04d}.vtu", named_inside=True) for k in range(steps)]


def h5_renamed(path):
    """A note for an ``.xdmf`` ``path`` whose HDF5 data are not in ``<stem>.h5`` (its stem has a ':',
    :data:`H5_UNSAFE`): the name they are in, and why; ``""`` otherwise."""
    path = link_target(Path(os.fspath(path)).expanduser())  # a link: its target's name, as the file is written
    if path.suffix.lower() != ".xdmf" or H5_UNSAFE not in path.stem:
        return ""
    return (f"the HDF5 data of {path.name} are in {companion_files(path, 0)[0].name} "
            f"(XDMF separates a data file's name from its data set by ':', so its name has none)")


def write_xdmf(path, times, cells, reference, steps, stop=lambda: False):
    """XDMF 3 temporal collection through :class:`meshio.xdmf.TimeSeriesWriter`: the reference mesh once, then
    each step's point and cell data (``displacement`` among them); data in ``<stem>.h5``, compressed.

    The HDF5 file is written through a :class:`~mol_shell._core.write_aside.WriteAside` (what meshio would open by its
    name): on a full disk HDF5 never sees a failed write, so its objects close cleanly (they retried the write at
    every release, thousands of tracebacks, then a segmentation fault at exit), and the failure is raised at the next
    step (the staging, :func:`mol_shell._core.atomic.staged`, says it in one line naming ``-o``).

    ``stop()`` is asked before each step: true (a Ctrl-C noted, :func:`export`), the writing stops there, HDF5 closes its
    file, and ``KeyboardInterrupt`` is raised after (never where h5py calls Python: it printed ``Exception ignored``
    and the process died of a segmentation fault)."""
    import h5py
    import meshio

    path = Path(path).resolve()
    h5_path = companion_files(path, 0)[0]
    writer = meshio.xdmf.TimeSeriesWriter(path)
    with WriteAside(h5_path) as data:
        with h5py.File(data, "w") as h5:
            writer.h5_filename, writer.h5_file = h5_path.name, h5  # as the writer's __enter__ opens it, by name
            # the writer makes its datasets with the file's create_dataset: give the large ones compression
            h5.create_dataset = _compressing(h5.create_dataset)
            writer.write_points_cells(reference, cells)
            data.check()
            for t, (_, point_data, cell_data) in zip(times, steps):
                if stop():
                    break
                writer.write_data(repr(float(t)), point_data=point_data, cell_data=cell_data)
                data.check()  # a full disk ends the export here
        data.check()  # what HDF5 flushed at its close
    if stop():  # the HDF5 file is closed: the staging discards it
        raise KeyboardInterrupt
    writer.__exit__(None, None, None)  # the XDMF file (the HDF5 file is closed already: closing it again is nothing)
    return [path, h5_path]


def write_pvd(path, times, cells, reference, steps):
    """One ``<stem>_NNNN.vtu`` per step (meshio) beside ``path``, and the ``.pvd`` collection that lists them.

    Each ``.vtu`` holds the moved points (and ``displacement`` from the ``reference`` among its point data)."""
    import meshio

    path = Path(path)
    root = ET.Element("VTKFile", type="Collection", version="0.1")
    collection = ET.SubElement(root, "Collection")
    written = []
    for vtu, t, (points, point_data, cell_data) in zip(companion_files(path, len(times)), times, steps):
        mesh = meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data)
        meshio.write(vtu, mesh, file_format="vtu")
        ET.SubElement(collection, "DataSet", timestep=repr(float(t)), part="0", file=vtu.name)
        written.append(vtu)
    ET.ElementTree(root).write(path, xml_declaration=True, encoding="utf-8")
    return [path, *written]


def export(ds, path, n_phi=N_PHI, faces=False):
    """Write the revolved shell of run ``ds`` at every saved time to ``path`` (``.xdmf`` or ``.pvd``).

    Parameters
    ----------
    ds : xarray.Dataset or str or os.PathLike
        A run (with or without stresses), or the path of its netCDF file.
    path : str or os.PathLike
        ``.xdmf`` (plus ``<stem>.h5``, a ':' of the stem as '_': :func:`h5_renamed`) or ``.pvd`` (plus
        ``<stem>_NNNN.vtu``); missing directories are created.
        None of these files may be the run's own file (``ds`` a path, or a Dataset read from one).
    n_phi : int
        Azimuthal samples, in [3, :data:`N_PHI_MAX`].
    faces : bool
        Also the inner and outer faces.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    if not (isinstance(n_phi, (int, np.integer)) and not isinstance(n_phi, bool) and 3 <= n_phi <= N_PHI_MAX):
        raise ParameterError("n_phi", n_phi, f"integers in [3, {N_PHI_MAX}]")
    source = ds if isinstance(ds, (str, os.PathLike)) else getattr(ds, "encoding", {}).get("source")
    ds = run_of(ds, "export" + (" --faces" if faces else ""), SHELL, faces=faces)
    path = writable_path(path, "path", suffixes=FORMATS)  # before the work: its missing directories created
    for companion in companion_files(path, ds.sizes["time"]):
        check_lengths(companion, "path", path, what=f"would write {companion.name!r} beside it")
        if companion.is_dir():
            raise ParameterError.invalid("path", str(path), f"would write {companion.name} where a directory stands",
                                         "a path whose companion files can be written")
    # netCDF4 files are HDF5: a run named run.h5 was replaced by the HDF5 data of run.xdmf
    keep_inputs({"ds": source}, [path, *companion_files(path, ds.sizes["time"])], "path", path)
    suffix = path.suffix.lower().lstrip(".")
    cells, reference, steps = mesh_series(ds, n_phi, faces)
    # XDMF: a Ctrl-C is noted, not raised, while h5py writes (it calls Python, WriteAside, from C and as its objects
    # are released: an interrupt raised there printed "Exception ignored" and ended in a segmentation fault, the
    # staged files left); the writing stops at the next step, and the interrupt is raised once they are discarded
    with interrupts.held() if suffix == "xdmf" else contextlib.nullcontext() as watch:
        with staged(path) as stage:
            if suffix == "xdmf":
                written = write_xdmf(stage / path.name, ds["time"].values, cells, reference, steps,
                                     stop=lambda: watch.caught)
            else:
                written = write_pvd(stage / path.name, ds["time"].values, cells, reference, steps)
            if incomplete_note(ds.attrs):  # the series of a run that stopped early says so, as its figures do
                mark(stage / path.name, f"mol_shell run of scene {ds.attrs.get('scene', '')} "
                     f"[{incomplete_note(ds.attrs)}]: its last saved time is where it stopped")
        interrupts.wrote(path)  # an interrupt from here on: said after writing it (and its steps beside it)
        if suffix == "xdmf":
            gc.collect()  # h5py's objects in reference cycles released here, where an interrupt is held back
    return [path.parent / f.name for f in written]


def mark(path, note):
    """Put ``note`` in the XML file ``path`` (the ``.xdmf`` or ``.pvd`` written) as a comment before its root
    element (after the XML declaration): readers (ParaView, meshio) skip it, a reader of the file sees it; the rest
    of the file is left as written."""
    text = Path(path).read_text(encoding="utf-8")
    comment = "<!-- " + " ".join(note.replace("--", "- -").split()) + " -->\n"
    head, mark_end, rest = text.partition("?>")
    text = f"{head}?>\n{comment}{rest.lstrip()}" if mark_end and head.lstrip().startswith("<?xml") else comment + text
    Path(path).write_text(text, encoding="utf-8")
