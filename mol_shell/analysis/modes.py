"""Natural modes: frequencies and shapes of the linearisation about a scene's initial state at rest.

At a state at rest the exact Jacobian of Hamilton's equations is ``J = [[0, M^-1], [-K, 0]]`` on the free
coordinates (``q_t = M^-1 p``; ``p_t = -dV/dq``, ``dT/dq`` being quadratic in ``p``), so its eigenvalues
are ``+-i omega`` with ``K phi = omega^2 M phi``. We read ``M^-1`` and ``K`` off the exact sparse
Jacobian of :class:`~mol_shell.discretization.system.ShellSystem` and solve the symmetric generalised problem:
dense (LAPACK) up to :data:`DENSE_MAX` free coordinates, else sparse shift-invert (ARPACK) about a small
negative shift (:data:`SHIFT` of the eigenvalues' scale, in s-2) with the rigid motions projected out.

Rigid motions (``omega = 0``: rotation about the axis where both edges leave ``chi`` free, axial
translation where they leave ``z`` free; :func:`mol_shell.runs.statics.rigid_motions`) are counted in
``attrs["zero_modes"]`` (2, 1 or 0, from the edges), not listed. Every other mode keeps its frequency; one whose
``omega^2`` is zero to round-off (:data:`ROUNDOFF` times machine epsilon times the mode's own stiffness terms,
:func:`roundoff_level`: a prestressed state at a critical point) is listed at 0 rad/s, as is a negative one within
the eigensolver's round-off of the largest, and one within a located critical point's band (:mod:`mode_zero`). The eigenvalues' scale is ``max K_ii / M_ii``, Rayleigh quotients
of unit vectors: a lower bound of the largest ``omega^2``, within a few percent of it on the scenes' grids.

A mode's shape is scaled so that its entry of largest magnitude (over all fields, metres and radians alike: the
shape is a dimensionless amplitude times each field's unit) is +1; ``modal_mass`` is ``phi^T M phi`` of the shape as
scaled (kg m2): ``shape / sqrt(modal_mass)`` is mass-normalised.

``energy_fraction(mode, field)`` is each field's share of the mode's kinetic energy
``phi^T M phi / 2``; the mass matrix couples fields of a node (``chi`` and ``psi`` through the
director's rate, ``z, r`` and ``theta`` through ``rhoI``), and each cross term ``M_kl phi_k phi_l`` is
shared half and half between fields ``k`` and ``l``, so the shares sum to 1 (a share can be slightly
negative when a cross term dominates it).
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from mol_shell._core.errors import (
    MaterialWarning,
    ModelLimitError,
    MolShellWarning,
    ParameterError,
    SceneWarning,
    scalar,
)
from mol_shell._core.units import show_seconds
from mol_shell.analysis.grid_modes import mark_grid_modes
from mol_shell.analysis.mode_damping import damping_note, drag_damping_ratios
from mol_shell.analysis.mode_matrices import (
    block_inverse,
    constrained_pairs,
    constrained_size,
    constraint_basis,
    labelled,
)
from mol_shell.analysis.mode_zero import checked_band, floor_note, solver_floor, zero_mask
from mol_shell.analysis.path_inputs import history_loads
from mol_shell.model.kinematics import FIELDS
from mol_shell.results.cf import coordinates, header, variables
from mol_shell.results.dataset import FIELD_META, given_note, given_values, scene_attrs, with_units
from mol_shell.runs import resources
from mol_shell.runs.ellipticity import CONSEQUENCE, sampled_margins
from mol_shell.runs.simulate import as_scene, build, resolve, starting_state
from mol_shell.runs.statics import rigid_motions
from mol_shell.scenes.scene_warnings import say_scene_warnings

#: above this many free coordinates the sparse shift-invert solver is used
DENSE_MAX = 3000
#: ... unless more modes than this share of the free coordinates are asked: ARPACK's cost grows like k^2 and passes the
#: dense solve's near it (sphere, n = 701, 3,497 coordinates, one thread: 0.8, 2.5, 48.7 s for 100, 300, 700 modes,
#: dense 44.2 s; 3,400 modes ran past 180 s and, in one C call, ignored SIGTERM and SIGINT)
DENSE_SHARE = 0.2
#: seconds of modes by the dense route per cubed free coordinate (44.2 s at 3,497 on a busy 2-core machine; LAPACK's
#: generalised eigh alone 0.32 s at 1,000, 1.9 s at 2,000); a longer one than
#: :data:`~mol_shell.runs.resources.LONG_ANALYSIS_BUILD_S` is announced: no signal stops LAPACK's call
DENSE_S_PER_CUBE = 1e-9
#: dense matrices of the free coordinates' size held at once (K, M, the shapes, LAPACK's copies and work)
DENSE_COPIES = 6
#: the initial state counts as an equilibrium when its generalised forces are below this fraction of
#: the forces of a unit strain of each cell (``max diag K`` times the meridian's scale)
EQUILIBRIUM_TOL = 1e-8
#: an omega^2 within this many machine epsilons of its mode's own stiffness terms (:func:`roundoff_level`) is zero to
#: round-off (the rigid motions' come out within one)
ROUNDOFF = 1e3
#: the sparse solver's shift, below zero by this fraction of the eigenvalues' scale: far above round-off (``K - shift M``
#: is regular with rigid motions), far below the lowest frequency of any grid (omega_1^2 / omega_max^2 ~ 1e-11 for a
#: sphere of 50 m at n = 700)
SHIFT = 1e-13
#: ARPACK's attempts: (Lanczos vectors beyond the modes asked, iterations per coordinate)
ARPACK_TRIES = ((12, 10), (60, 100))
#: a state is the natural one (every strain zero) when it differs from the reference by a rigid motion to this
#: fraction of the meridian's scale
NATURAL_TOL = 1e-12


def slack_fibres_note(system, y0):
    """A sentence when ``y0`` is the natural state of a wall with tension-only fibres, else ``""``.

    Tension-only fibres store ``(E_f / 2) max(a.E a, 0)^2``, whose second derivative jumps from 0 to ``E_f`` at zero
    fibre strain; in the natural state every fibre sits there (``y0`` differs from the reference by an axial
    translation and a spin at most). The stiffness is then one-sided and no linear mode exists: the derivative of
    ``max`` at a tie is a convention and the round-off of the zero strains picks the side point by point. Other
    states whose fibre strains vanish at a thickness point exactly are not detected.
    """
    fibres = [system.fibres] + [layer[2] for layer in (system.layer_laws or ())]
    if not any(f is not None and not f.compression for f in fibres):
        return ""
    z, r, chi, theta, psi = system.unpack(np.asarray(y0, dtype=float))[:5]
    z0, r0, theta0 = system.reference
    scale = max(float(np.ptp(z0) + np.max(np.abs(r0))), 1e-300)
    offsets = (z - z0 - np.mean(z - z0), r - r0, (chi - np.mean(chi)) * r0, (theta - theta0) * scale, psi * scale)
    if max(float(np.max(np.abs(x))) for x in offsets) > NATURAL_TOL * scale:
        return ""
    return ("the modes are taken about the natural state of a wall with tension-only fibres (fibre_compression = "
            "false), where every fibre is at zero strain and its stiffness one-sided (E_f when stretched, 0 when "
            "shortened): no linear mode exists there, and these frequencies mix the two sides point by point as "
            "round-off falls; fibre_compression = true gives the taut wall's modes, fibre_E = 0 the slack one's")


def _blocks(system, y0):
    """``(free, Minv, K)`` on the free coordinates, from the exact Jacobian at ``y0`` (sparse CSC)."""
    import scipy.sparse  # optional heavy dependency: 0.17 s of every process's start at module level

    J = system.jac(0, y0)
    sp = J.sparsity()
    Js = scipy.sparse.csc_matrix((np.array(J.nonzeros()).ravel(), sp.row(), sp.colind()), shape=J.shape)
    nf, n = system.nf, system.n
    fixed = system.fixed[:, list(system.active)]  # (n, nf)
    free = [system.ny * i + k for i in range(n) for k in range(nf) if not fixed[i, k]]
    q_idx = np.array(free)
    p_idx = q_idx + nf
    Js = Js.tocsr()
    Minv = Js[q_idx][:, p_idx]
    K = -Js[p_idx][:, q_idx]
    return q_idx, Minv.tocsc(), K.tocsc()


def rigid_vectors(system, q_idx):
    """The rigid motions (:func:`mol_shell.runs.statics.rigid_motions`) on the free coordinates ``q_idx``: a column
    of ones on every free ``z`` (axial translation), one on every free ``chi`` (spin; a pole's tied ``chi`` is no
    free coordinate)."""
    fields = np.array(system.active)[np.asarray(q_idx) % system.ny]
    columns = [(fields == k).astype(float) for k in rigid_motions(system).values()]
    return np.column_stack(columns) if columns else np.zeros((len(q_idx), 0))


def _rigid_deflated(M, w2, phi, cluster, rigid):
    """``(w2, phi)`` with the eigenpairs of ``cluster`` (eigenvalues near zero, at least as many as rigid motions)
    rotated so that the rigid motions are exactly ``rigid.shape[1]`` of them, at ``w2 = 0``, and the others are
    ``M``-orthogonal to them: a Rayleigh-Ritz step within the cluster, which holds the rigid motions (exact null
    vectors of ``K`` at an equilibrium). Near a critical point the solver returns any mix of the rigid motions
    and the critical mode, whose eigenvalues are all zero to round-off: the spin was listed as mode 1."""
    w2, phi = w2.copy(), phi.copy()
    basis = phi[:, cluster]  # M-orthonormal
    U, _, _ = np.linalg.svd(basis.T @ (M @ rigid), full_matrices=True)
    r = rigid.shape[1]
    rest = U[:, r:]
    mu, Y = np.linalg.eigh(rest.T @ (w2[cluster][:, None] * rest))
    phi[:, cluster] = np.column_stack([basis @ U[:, :r], basis @ rest @ Y])
    w2[cluster] = np.concatenate([np.zeros(r), mu])
    return w2, phi


def roundoff_level(K, M, phi):
    """Per mode (column of ``phi``), the round-off of its ``omega^2 = phi' K phi / phi' M phi`` (s-2): :data:`ROUNDOFF`
    machine epsilons of ``|phi|' |K| |phi| / phi' M phi``, the mode's own stiffness terms before they cancel. Against
    the grid's eigenvalue scale (``max K_ii / M_ii``, which grows like 1/h^2 on a thin wall) a converged bending mode of
    a thin ring (omega^2 = 3.3e-4 s-2 at h = 1e-4 m) was called zero."""
    absolute = abs(K) @ np.abs(phi)
    terms = np.einsum("im,im->m", np.abs(phi), np.asarray(absolute))
    return ROUNDOFF * np.finfo(float).eps * terms / np.einsum("im,im->m", phi, np.asarray(M @ phi))


def eigenvalue_scale(K, M):
    """``max K_ii / M_ii`` (s-2): Rayleigh quotients of unit vectors, a lower bound of the largest ``omega^2`` (within a
    few percent of it on a shell's grid, whose stiffest mode lives on one node)."""
    ratio = np.abs(K.diagonal()) / np.abs(M.diagonal())
    return max(float(np.max(ratio[np.isfinite(ratio)], initial=0.0)), 1e-300)


def sparse_modes(K, M, rigid, count, scale):
    """``(w2, phi)``: the ``count`` eigenpairs of ``K phi = omega^2 M phi`` nearest zero (ascending) with the rigid
    motions (columns of ``rigid``) projected out M-orthogonally, by shift-invert about ``-SHIFT * scale``. ARPACK is
    tried again with more Lanczos vectors and iterations when it does not converge; then a ModelLimitError says how
    many converged."""
    import scipy.sparse.linalg  # optional heavy dependency: 0.17 s of every process's start at module level

    size = K.shape[0]
    shift = -SHIFT * scale
    solve = scipy.sparse.linalg.splu((K - shift * M).tocsc()).solve
    MR = M @ rigid
    gram = rigid.T @ MR

    def project(x):
        return x - rigid @ np.linalg.solve(gram, MR.T @ x) if rigid.shape[1] else x

    op = scipy.sparse.linalg.LinearOperator(K.shape, matvec=lambda b: project(solve(np.ravel(b))), dtype=float)
    v0 = project(np.random.default_rng(0).standard_normal(size))
    k = min(count, size - rigid.shape[1] - 2)
    for extra, per in ARPACK_TRIES:
        try:
            w2, phi = scipy.sparse.linalg.eigsh(K, k=k, M=M, sigma=shift, which="LM", OPinv=op, v0=v0,
                                                ncv=min(size - 1, 2 * k + extra), maxiter=per * size)
            break
        except scipy.sparse.linalg.ArpackNoConvergence as exc:
            found = np.sort(exc.eigenvalues.real)
    else:
        lowest = f" (lowest omega^2 {found[0]:.6g} s-2)" if found.size else ""
        raise ModelLimitError(f"the sparse eigensolver (ARPACK, shift-invert about {shift:.3g} s-2) did not converge: "
                              f"{found.size} of the {k} lowest modes of {size} free coordinates{lowest}", 0.0,
                              "the sparse eigensolver")
    order = np.argsort(w2)
    return w2[order], phi[:, order]


def off_equilibrium(system, y0, forces=None):
    """``"residual force F on FIELD at s = S m (R of a unit strain's)"``: the largest generalised force of state ``y0``
    where above :data:`EQUILIBRIUM_TOL` of a unit strain's, else ``""`` (``forces``: its ``|momentum rates|``)."""
    if forces is None:
        f = np.array(system.rhs_newton(0, y0)).ravel()[: system.ny * system.n].reshape(system.n, system.ny)
        forces = np.abs(f[:, system.nf:])
    _, _, K = _blocks(system, y0)
    scale = float(np.abs(K.diagonal()).max()) * max(1.0, float(np.abs(system.reference[:2]).max()))
    if not forces.max() > EQUILIBRIUM_TOL * scale:
        return ""
    i, k = np.unravel_index(int(np.argmax(forces)), forces.shape)
    return (f"residual force {forces.max():.3g} on {FIELDS[system.active[k]]} at s = {system.s[i]:.4g} m "
            f"({forces.max() / scale:.2g} of a unit strain's)")


def check_equilibrium(system, y0, scene, asked=None, given=False):
    """Refuse (ParameterError) a state that is moving or out of equilibrium, saying how far and where, and what
    of the scene (``asked``: as given, ``R`` or ``dilation`` perhaps auto) to change; ``given``: the state is the
    caller's fields (``modes(..., initial=...)``), refused by that name (the scene's initial state is not used)."""
    f = np.array(system.rhs_newton(0, y0)).ravel()[: system.ny * system.n].reshape(system.n, system.ny)
    nf = system.nf
    rates, forces = np.abs(f[:, :nf]), np.abs(f[:, nf:])
    if rates.max() > 0:
        i = int(np.argmax(rates.max(axis=1)))
        where = f"the initial state moves at s = {system.s[i]:.4g} m; modes of a moving state are not computed"
        if getattr(scene, "omega", 0.0):
            raise ParameterError("omega", scene.omega, "0 for modes (a state at rest)", hint=where)
        raise ParameterError("scene", scene.name, "a scene whose initial state is at rest (no spin, no driven "
                             "edge moving at t = 0)", hint=where)
    where = off_equilibrium(system, y0, forces)
    if where:
        if given:  # a path's step is one; a critical point the path did not locate may not be
            error = ParameterError("initial", None, "equilibria at rest under the scene's loads",
                                   hint=f"{where}; a path's step or located critical point is one: "
                                   "mol_shell.analysis.path_start.path_start",
                                   message=f"initial (the fields given) is outside equilibria at rest under the "
                                   f"loads of scene {scene.name!r}")
            error.residual = where  # for a caller that names where the fields came from (modes --from)
            raise error
        asked = scene if asked is None else asked
        if getattr(scene, "gamma", 0.0) and "pole" in system.edges:
            fix = "a twist (gamma) is no equilibrium of a shell closed at a pole: gamma = 0"
        elif getattr(scene, "gamma", 0.0):
            fix = "a twist (gamma) is held only by edges imposing chi: end1=clamped, end2=clamped"
        elif any(getattr(asked, key, None) is not None for key in ("R", "dilation")):  # the value at fault named
            key = "R" if getattr(asked, "R", None) is not None else "dilation"
            raise ParameterError(key, getattr(asked, key), "auto, or a value whose initial state is an equilibrium "
                                 "(the modes are taken about one)", hint=f"{where}; {key} = auto starts from the static "
                                 "equilibrium under the loads; a run (mol-shell run) follows the motion from this "
                                 "state")  # was "scene = 'torus' is outside a scene whose ...", a file's key unnamed
        else:
            fix = "the modes are taken about an equilibrium at rest"
        raise ParameterError("scene", scene.name, "a scene whose initial state is an equilibrium",
                             hint=f"{where}; {fix}")


def _route(size, count, listable, n):
    """``"dense"`` or ``"sparse shift-invert"`` for ``count`` modes of ``size`` free coordinates, ``listable`` of them
    not rigid motions: ``count`` refused (naming its range) before any solve when beyond them, and the dense route
    refused when its matrices do not fit in memory, announced (LongRunWarning) when it takes long."""
    if count > listable:  # known before any solve (a count of 100,000 at n = 601 was refused after 36 s of it)
        raise ParameterError("count", count, f"integers 1..{listable} for n = {n}")
    if size <= DENSE_MAX or count > DENSE_SHARE * size:
        room, source = resources.available_memory()
        if DENSE_COPIES * size * size * resources.BYTES > room:
            sparse_most = min(int(DENSE_SHARE * size), listable)
            if count <= sparse_most:  # the sparse route takes it (a small grid goes dense only as the faster)
                return "sparse shift-invert"
            raise ParameterError("count", count, f"integers 1..{sparse_most} for n = {n}", hint=(
                f"more than {DENSE_SHARE:g} of the {size:,} free coordinates are solved for densely, whose matrices "
                f"({resources.show_bytes(DENSE_COPIES * size * size * resources.BYTES)}) do not fit in "
                f"{resources.show_bytes(room)} available ({source})"))
        seconds = DENSE_S_PER_CUBE * float(size) ** 3
        if seconds > resources.LONG_ANALYSIS_BUILD_S:
            warnings.warn(f"computing the modes of {size:,} free coordinates densely (LAPACK) takes about "
                          f"{show_seconds(seconds)}, most of it in one call that no signal interrupts", resources.LongRunWarning,
                          stacklevel=3)
        return "dense"
    return "sparse shift-invert"


def modes(scene, n=40, count=10, *, initial=None, zero_band=0.0):
    """Natural frequencies and mode shapes of ``scene`` about its initial state (at rest, in equilibrium).

    Parameters
    ----------
    scene : ShellScene or str
        A scene object or a registered name (its initial state must be an equilibrium at rest: the
        natural state, the twisted cylinder at its equilibrium radius between clamped ends, ...).
    n : int
        Nodes in ``s``.
    count : int
        How many of the lowest nonzero frequencies to return.
    initial : array_like, optional
        Fields ``z, r, chi, theta, psi`` at the nodes, ``(5, n)``, at rest, in place of the scene's initial state: an
        equilibrium under the scene's loads, e.g. a path's step (prestressed frequencies).
    zero_band : float
        ``omega^2`` within this of zero (s-2) counts as zero: a path's located critical point's
        (:func:`mol_shell.analysis.mode_zero.located_band`); at most :data:`~mol_shell.analysis.mode_zero.BAND_SHARE`
        of the largest ``K_ii / M_ii`` (a band that swallows real frequencies is refused).

    Returns
    -------
    xarray.Dataset
        ``frequency(mode)`` (rad s-1, ascending; 0 where omega^2 is zero to round-off, not a rigid motion),
        ``omega_squared(mode)``, shapes ``z, r, chi, theta, psi (mode, s)`` (scaled so that the entry of largest
        magnitude of each mode, over all fields, is +1; unit of each field), ``modal_mass(mode)`` (``phi^T M phi`` of
        the scaled shape, kg m2), ``energy_fraction(mode, field)``;
        attrs ``zero_modes``, ``method``, the scene's parameters, and ``ellipticity_margin`` of the state
        (:func:`~mol_shell.runs.ellipticity.sampled_margins`; where it is not positive, a
        :class:`~mol_shell.MaterialWarning` and ``ellipticity_warning``: the lowest modes are then the grid's); the
        scene's warnings as a run's, said and in ``material_warning`` and ``scene_warning``
        (:mod:`mol_shell.scenes.scene_warnings`)."""
    import scipy.linalg  # optional heavy dependency: 0.17 s of every process's start at module level
    import scipy.sparse
    import scipy.sparse.linalg

    asked = as_scene(scene)
    n, count = scalar(n), scalar(count)
    checked_band(scalar(zero_band))  # a number in [0, inf) before the solve; its share of the spectrum after it
    scene = resolve(asked)
    if not isinstance(count, (int, np.integer)) or isinstance(count, bool) or count < 1:
        raise ParameterError("count", count, "integers >= 1")

    # at most one mode per coordinate: a larger count is refused by name below, not blamed on n here
    kept = min(count, 10 * n) if isinstance(n, (int, np.integer)) else count
    resources.check_analysis(n, kept, f"computing {kept} modes", "modes", fields=len(getattr(scene, "fields", range(5))))
    system, _ = build(scene, n)
    y0, _ = starting_state(scene, system, n, initial, asked=asked)
    check_equilibrium(system, y0, scene, asked, given=initial is not None)
    q_idx, Minv, K = _blocks(system, y0)
    basis = constraint_basis(scene, system, q_idx)  # the unshearable scene's chi_s = 0, psi = 0 (mode_matrices)
    size = constrained_size(len(q_idx), basis)
    rigid = rigid_vectors(system, q_idx)
    method = _route(size, count, size - rigid.shape[1], system.n)
    noted = say_scene_warnings(scene, {}, stacklevel=2)  # once refusals are past: before the solve, recorded after
    if method == "dense":
        M = np.linalg.inv(Minv.toarray())
        M = (M + M.T) / 2
        Kd = K.toarray()
        Kd = (Kd + Kd.T) / 2
        scale = eigenvalue_scale(Kd, M)
        w2, phi = constrained_pairs(scipy.linalg.eigh, Kd, M, basis)
    else:
        M = block_inverse(Minv)
        M = (M + M.T) / 2
        Ks = (K + K.T) / 2
        scale = eigenvalue_scale(Ks, M)
        w2, phi = constrained_pairs(lambda K_, M_, R_: sparse_modes(K_, M_, R_, count, scale), Ks, M, basis,
                                    rigid)  # the rigid motions projected out: none among them
    if not np.all(np.isfinite(w2)):  # rho = 1e-300: inertias in the subnormals, their inverse infinite (NaN modes)
        raise ModelLimitError(
            f"the modes of n = {system.n} nodes are not finite in double precision (omega^2 = {w2[~np.isfinite(w2)][0]}"
            f"): the mass matrix (rho = {scene.rho:g} kg m-3) or the stiffness is beyond what doubles hold", 0.0,
            "the mass and stiffness matrices")
    stiffness = Kd if method == "dense" else Ks
    largest = max(float(np.max(np.abs(w2))), scale)  # the sparse solve's are the lowest: the scale bounds the largest
    floor = solver_floor(largest)  # the eigensolver's round-off: a negative omega^2 within it is zero
    zero_band = checked_band(zero_band, largest)
    small = zero_mask(w2, roundoff_level(stiffness, M, phi), floor, zero_band)  # zero to round-off, mode by mode
    zero = np.zeros(len(w2), dtype=bool)
    if method == "dense" and rigid.shape[1]:
        # the rigid motions are the edges' (exact null vectors of K): the eigenpairs most in their span, with any
        # other mode at zero to round-off (a prestressed state at a critical point, which the solver mixes with them)
        # taken out by a Rayleigh-Ritz step, so that it stays listed at frequency ~0
        MR = M @ rigid
        share = np.einsum("im,im->m", phi, MR @ np.linalg.solve(rigid.T @ MR, MR.T @ phi))
        cluster = np.union1d(np.flatnonzero(small), np.argsort(-share)[: rigid.shape[1]])
        w2, phi = _rigid_deflated(M, w2, phi, cluster, rigid)
        zero[cluster[: rigid.shape[1]]] = True
        order = np.argsort(w2)
        w2, phi, zero = w2[order], phi[:, order], zero[order]
        small = zero_mask(w2, roundoff_level(stiffness, M, phi), floor, zero_band)
    n_zero = rigid.shape[1]
    keep = np.flatnonzero(~zero)[:count]  # as many as asked: _route refused more than there are
    start = system.unpack(np.asarray(y0, dtype=float))
    given = given_values(scene, start, system.s, system.reference[1]) if initial is not None else None
    params = scene_attrs(scene, system.edges, system.thickness.zeta1, start[:2], system.reference[:2], asked.params(),
                         given)
    given_said = given_note(params)
    if given_said:  # a path's state, at rest: the scene's omega or gamma are not the start's
        params["initial_data_note"] = given_said
    params.update(noted)  # as a run's: the law's locking, keys without effect (said before the build)
    at_rest = history_loads(scene, why="the modes are taken about a state at rest")
    if at_rest:  # a load on a history acts at t = 0 (a ramp's: not at all), as in a path's states
        params["loads_at_rest"] = "\n".join(at_rest)
    roundoff = floor_note(w2[keep], roundoff_level(stiffness, M, phi[:, keep]), floor, largest)
    if roundoff:
        params["roundoff_warning"] = roundoff
        warnings.warn(roundoff, MolShellWarning, stacklevel=2)
    ratios = drag_damping_ratios(system, scene, q_idx, M, w2[keep], phi[:, keep], start[1]) if scene.drag else None
    damping = damping_note(scene, system, ratios)
    if damping:  # K phi = omega^2 M phi: the drag's and the viscosity's damping are not in it
        warnings.warn(damping, SceneWarning, stacklevel=2)
        params["damping_note"] = damping
    slack = slack_fibres_note(system, y0)
    if slack:
        warnings.warn(slack, MaterialWarning, stacklevel=2)
        params["fibre_warning"] = slack
    margin, _, lost = sampled_margins(system, system.unpack(np.asarray(y0, dtype=float))[None])
    params["ellipticity_margin"] = float(margin[0])  # NaN where no cell could be checked
    if lost is not None:
        params["ellipticity_warning"] = (f"the state the modes are taken about is past the loss of ellipticity at "
                                         f"s = {lost[1]:.6g} m (d2W/d(q_s)2 is not positive definite: {CONSEQUENCE}); "
                                         "its lowest modes are the grid's")
        warnings.warn(params["ellipticity_warning"], MaterialWarning, stacklevel=2)
    unstable = np.flatnonzero((w2[keep] < 0) & ~small[keep])  # a state past a critical point: omega^2 < 0
    if unstable.size:
        params["unstable_modes"] = int(unstable.size)
        count = f"{unstable.size} mode{'s' * (unstable.size != 1)}"
        params["stability_warning"] = (
            f"the state the modes are taken about is unstable: {count} with omega^2 < 0 (lowest {w2[keep][0]:.6g} "
            f"s-2, growing as exp({np.sqrt(-w2[keep][0]):.6g} t / s)); their frequency is NaN")
        warnings.warn(params["stability_warning"], MolShellWarning, stacklevel=2)
    return labelled(mark_grid_modes(_dataset(system, scene, q_idx, M, w2[keep], phi[:, keep], n_zero, method, params,
                                             small[keep], ratios)), basis)


def _dataset(system, scene, q_idx, M, w2, phi, n_zero, method, params, zero, ratios=None):
    n = system.n
    modes_count = phi.shape[1]
    shapes = np.zeros((modes_count, 5, n))
    fractions = np.zeros((modes_count, 5))
    Mphi = M @ phi
    kinetic = np.einsum("im,im->m", phi, Mphi)
    node, local = np.divmod(q_idx, system.ny)
    field = np.array(system.active)[local]
    modal = np.zeros(modes_count)
    for m in range(modes_count):
        shapes[m][field, node] = phi[:, m]
        shapes[m] = system.tie(shapes[m])
        largest = shapes[m].flat[np.argmax(np.abs(shapes[m]))]  # the sign too: that entry is +1
        shapes[m] /= largest
        modal[m] = kinetic[m] / largest**2
        for k in range(5):
            sel = field == k
            fractions[m, k] = float(np.sum(phi[sel, m] * Mphi[sel, m]) / kinetic[m])
    data = {
        "frequency": (("mode",), np.where(zero, 0.0, np.sqrt(np.where(w2 >= 0, w2, np.nan))),
                      {"units": "rad s-1", "long_name": "natural angular frequency (NaN: an unstable mode; 0: omega^2 "
                       "zero to round-off)"}),
        "omega_squared": (("mode",), w2, {"units": "s-2", "long_name": "squared angular frequency, the eigenvalue of "
                                          "K phi = omega^2 M phi (negative: unstable, growing as exp(sqrt(-omega^2) t))"}),
        "energy_fraction": (("mode", "field"), fractions, {"units": "1", "long_name":
                            "share of the mode's kinetic energy per field (cross terms shared half and half)"}),
    }
    data["modal_mass"] = (("mode",), modal, {"units": "kg m2", "long_name": "modal mass phi^T M phi of the shape as "
                                             "scaled (shape / sqrt(modal_mass) is mass-normalised)"})
    if ratios is not None:
        data["drag_damping_ratio"] = (("mode",), ratios, {"units": "1", "long_name": "damping ratio of the mode under "
                                      "the drag, to first order: phi^T C phi / (2 omega phi^T M phi) (NaN: omega^2 <= 0)"})
    for k, name in enumerate(FIELDS):
        units, long_name = FIELD_META[name]
        data[name] = (("mode", "s"), shapes[:, k], {"units": units, "long_name": f"mode shape: {long_name} "
                                                    "(each mode scaled so that its entry of largest magnitude over all "
                                                    "fields, in m or rad, is +1)"})
    z0, r0, theta0 = system.reference
    data["z0"] = (("s",), z0, {"units": "m", "long_name": "axial position of the reference base surface"})
    data["r0"] = (("s",), r0, {"units": "m", "long_name": "radius of the reference base surface"})
    data["theta0"] = (("s",), theta0, {"units": "rad", "long_name": "angle of the reference generator tangent"})
    coords = {"mode": ("mode", np.arange(1, modes_count + 1), {"units": "1",
                                                               "long_name": "mode number (ascending frequency)"}),
              "s": ("s", system.s, {"units": "m", "long_name": "arc length of the reference generator"}),
              "field": ("field", list(FIELDS), {"long_name": "field"})}

    attrs = {**header(f"mol_shell natural modes of scene {scene.name}"), "scene": scene.name, "n": n, "zero_modes": n_zero,
             "method": method, "edge_s0": system.edges[0], "edge_sL": system.edges[1],
             "meridian": system.meridian.describe(), "zeta1_used": system.thickness.zeta1}
    attrs.update(params)  # the scene's parameters with their units_NAME, as a run file has them
    if "ellipticity_margin" in attrs:
        attrs["units_ellipticity_margin"] = "1"
    return xr.Dataset(variables(data), coords=coordinates(coords), attrs=with_units(attrs))
