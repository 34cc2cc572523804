"""The record of a path as it is traced: its steps (states, loads, stability, energies, reactions) and its critical
points, located between the steps where the count of negative eigenvalues changes (the secant method on the
crossing eigenvalue: :meth:`PathRecord.locate_between`), and the progress line that tells of them.
"""

from __future__ import annotations

import numpy as np

from mol_shell.analysis.path_stability import (
    DEFLATE,
    EIGENVALUES,
    LOCATE_ITER,
    LOCATE_NEWTON,
    LOCATE_RTOL,
    LOCATE_TOL,
    deflation,
    family,
    stability,
)


class PathRecord:
    """Steps and critical points of a path as it is traced."""

    def __init__(self, eq, tracer, bar=None, failed=Exception):
        #: a progress bar or lines (:func:`mol_shell._core.progress.progress_meter`) told of every step (a tqdm bar
        #: is closed by its ``__del__`` when the path ends by an exception); ``failed``:
        #: the exception the tracer's corrector raises (the path's ``PathFailed``)
        self.eq, self.tracer, self.bar, self.failed = eq, tracer, bar, failed
        self.qs, self.lams, self.tls, self.arcs, self.iterations = [], [], [], [], []
        self.eigen, self.negative, self.det_sign = [], [], []
        self.stored, self.phi, self.volume, self.reactions = [], [], [], []
        self.points = []
        #: 0 on the path from start, 1 on the branch switched to (``path(..., branch=K)``)
        self.branch, self.branches = 0, []
        #: on the branch: the farthest (scaled) it has been from the critical point it left
        self.farthest = 0.0
        #: whether a step's critical points are being located (an interruption then leaves them half done)
        self.locating = False

    def add(self, q, lam, t, arc, its):
        w2, _, negative, sign = stability(self.eq, q, lam)
        phi, vol = self.eq.conjugate(q, lam)
        self.reactions.append(self.eq.reactions(q, lam))
        self.qs.append(q)
        self.lams.append(lam)
        self.tls.append(t[1])
        self.branches.append(self.branch)
        self.arcs.append(arc)
        self.iterations.append(its)
        self.eigen.append(np.pad(w2, (0, EIGENVALUES - len(w2)), constant_values=np.nan))
        self.negative.append(negative)
        self.det_sign.append(sign)
        self.stored.append(self.eq.stored_energy(q, lam))
        self.phi.append(phi)
        self.volume.append(vol)
        if self.bar is not None and len(self.lams) > 1:  # the start is no step
            self.show(step=1)

    def truncate(self):
        """Every step's lists cut to the steps recorded whole (an interruption may land inside :meth:`add`), and the
        critical points to those located whole (one inside :meth:`locate_between` drops that step's points)."""
        lists = (self.qs, self.lams, self.tls, self.branches, self.arcs, self.iterations, self.eigen, self.negative,
                 self.det_sign, self.stored, self.phi, self.volume, self.reactions)
        whole = min(len(x) for x in lists)
        for x in lists:
            del x[whole:]
        # the points of steps kept, less those of a step whose locating was cut short (all of them or none)
        last = whole - 2 if self.locating else whole
        self.points = [p for p in self.points if p["step"] < last]

    def show(self, step=0):
        """Tell the progress bar of ``step`` more steps, the load reached and the critical points found so far."""
        if self.bar is not None:
            self.bar.set_postfix_str(f"{self.eq.parameter} = {self.lams[-1]:.4g} {self.eq.units}, "
                                     f"{len(self.points)} critical", refresh=not step)
            self.bar.update(step)

    def work(self):
        """``int lambda dPhi`` along the steps (trapezoidal rule); for an edge displacement ``int R dlambda``."""
        lam, phi = np.asarray(self.lams), np.asarray(self.phi)
        if self.eq.moved is not None:  # an edge displacement: the work of its reaction, int R d(displacement)
            lam, phi = phi, lam
        return np.concatenate([[0.0], np.cumsum((lam[1:] + lam[:-1]) / 2 * np.diff(phi))])

    def locate_between(self, i, j, origin):
        """Critical points between steps ``i`` and ``j``: one per eigenvalue whose sign changes between them."""
        before, after = self.negative[i], self.negative[j]
        if before == after and self.det_sign[i] == self.det_sign[j]:
            return
        kind = "limit" if self.tls[i] * self.tls[j] < 0 else "bifurcation"
        found = len(self.points)
        self.locating = True
        # the eigenvalues (ascending) that cross zero; more than a step keeps: computed again at both ends
        count = max(EIGENVALUES, max(before, after) + 1)
        spectra = {s: self.eigen[s] if count == EIGENVALUES else stability(self.eq, self.qs[s], self.lams[s], count)[0]
                   for s in (i, j)}
        for index in range(min(before, after), max(before, after)):
            self._locate(i, j, origin, index, kind, before, after, spectra, count)
        if kind == "limit":
            self._classify_turn(self.points[found:])
        # in the order the path meets them (the crossings were taken by eigenvalue, ascending: a path whose count of
        # negative eigenvalues falls meets the last one first): by where each was located, the load from step i's
        # towards step j's, or where the load turns the arclength from the step's start (as the secant sought them)
        q0, l0, t = origin
        toward = np.sign(self.lams[j] - self.lams[i])
        self.points[found:] = sorted(self.points[found:], key=lambda p: (
            self.tracer.along(t, q0, l0, p["q"], p["parameter"]) if kind == "limit" else toward * p["parameter"]))
        self.locating = False
        self.show()

    def _locate(self, i, j, origin, index, kind, before, after, spectra, count):
        """Illinois secant on eigenvalue ``index`` (ascending) between steps ``i`` and ``j``, whose ``count``
        eigenvalues nearest zero are ``spectra[i]``, ``spectra[j]``.

        A bifurcation is located in ``lambda``: each trial state by Newton at fixed ``lambda`` from the chord
        between the bracket's two states (one step at least: the chord's residual can be below the tolerance far
        from the path), refused when it lands off that chord by more than a quarter of its length (near a
        bifurcation another branch lies close by, and Newton may slide onto it); a refused trial starts again from
        the bracket's end on the side of step ``i``, along its slope ``dq/dlambda``. Once a trial's crossing
        eigenvalue is within :data:`DEFLATE` of its values at the ends, the next trials' Newton steps leave out its
        mode (:func:`~mol_shell.analysis.path_stability.deflation`; without, where Newton stalls). A
        limit point, where ``lambda`` turns, is located in the arclength from step ``i`` (each trial a corrector
        solve). A point whose bracket did not close to ``LOCATE_RTOL`` is kept with ``located`` false (``LOCATE_RTOL``: :mod:`mol_shell.analysis.path_stability`).
        """
        tr = self.tracer
        q0, l0, t = origin
        qi, qj, li, lj = self.qs[i], self.qs[j], self.lams[i], self.lams[j]
        if kind == "limit":
            a, b = 0.0, tr.along(t, q0, l0, qj, lj)
            width = 1.0

            def trial(x):
                q, lam, _ = tr.correct(q0, l0, t, x, max_iter=LOCATE_NEWTON, tol=LOCATE_TOL)
                return q, lam
        else:
            a, b = li, lj
            width = tr.l_scale
            ends = {"a": (qi, li), "b": (qj, lj), "along": None}

            def trial(x):
                return self.state_at(x, ends["a"], ends["b"], ends["along"]), x
        fa, fb = spectra[i][index], spectra[j][index]
        q, lam = qj, lj
        side, located = 0, False
        for _ in range(LOCATE_ITER):
            if not (np.isfinite(fa) and np.isfinite(fb)) or fa == fb:
                break
            x = b - fb * (b - a) / (fb - fa)
            if not min(a, b) < x < max(a, b):
                x = (a + b) / 2
            try:
                q, lam = trial(x)
            except self.failed:
                break
            spectrum, vectors, _, _ = stability(self.eq, q, lam, count)
            fx = spectrum[index]
            if kind != "limit":  # near the crossing, its mode's round-off is left out of the next trial's Newton
                small = abs(fx) <= DEFLATE * max(abs(spectra[i][index]), abs(spectra[j][index]))
                ends["along"] = deflation(self.eq, q, vectors[:, index]) if small else None
            if fx * fa > 0:
                a, fa = x, fx
                fb = fb / 2 if side == -1 else fb  # Illinois: the end kept twice running counts half
                side = -1
                if kind != "limit":
                    ends["a"] = (q, lam)
            else:
                b, fb = x, fx
                fa = fa / 2 if side == 1 else fa
                side = 1
                if kind != "limit":
                    ends["b"] = (q, lam)
            if abs(b - a) <= LOCATE_RTOL * width or fx == 0:
                located = True
                break
        w2, vectors, _, _ = stability(self.eq, q, lam, count)
        k = index if index < len(w2) else int(np.argmin(np.abs(w2)))
        # a closed bracket on a branch other than the steps' shows no eigenvalue near zero there
        located = located and abs(w2[k]) <= 1e-3 * max(abs(spectra[i][index]), abs(spectra[j][index]))
        mode = vectors[:, k]
        name, share = family(self.eq, q, mode)
        self.points.append({"kind": kind, "parameter": lam, "step": i % len(self.lams), "family": name,
                            "chi_share": share, "eigenvalue": w2[k], "mode": mode, "q": q, "located": located,
                            "reactions": self.eq.reactions(q, lam),
                            "negative_before": before, "negative_after": after})

    def state_at(self, x, end_a, end_b, along=None):
        """The equilibrium at load ``x`` between two states ``end_a = (q, load)`` and ``end_b`` on the path: Newton at
        fixed load from their chord (one step at least: the chord's residual can be below the tolerance far from the
        path), refused when it lands off that chord by more than a quarter of its length (near a critical point
        another branch lies close by, and Newton may slide onto it); a refused trial starts again from ``end_a``
        along its slope ``dq/dlambda``. ``along``: a critical mode's deflation
        (:func:`~mol_shell.analysis.path_stability.deflation`), tried first. Raises the path's exception where
        none converges."""
        tr = self.tracer
        (qa, la), (qb, lb) = end_a, end_b
        chord = qa + (x - la) / (lb - la) * (qb - qa)
        for start in ("chord", "slope"):  # from the end on the side of step i, along its slope
            q = chord if start == "chord" else qa + (x - la) * tr.slope(qa, la)
            for deflate in ([along] if along is not None else []) + [None]:
                try:
                    found = tr.at_load(q, x, deflate)
                except self.failed:  # the critical mode left out, Newton stalls: a state off the symmetry
                    continue
                if start == "slope" or tr.distance(chord, x, found, x) <= 0.25 * tr.distance(qa, la, qb, lb) + 1e-9:
                    return found
        raise self.failed("newton", f"no trial state at {self.eq.parameter} = {x:.6g} {self.eq.units}")

    def _load_work(self, point):
        """``(|phi . F_lambda| / (|phi| |F_lambda|), F_lambda)`` of a critical point: how much its mode works
        against the load."""
        g = np.asarray(self.eq.evaluate(point["q"], point["parameter"])[2], dtype=float).ravel()
        scale = float(np.linalg.norm(g) * np.linalg.norm(point["mode"]))
        return (abs(float(np.dot(g, point["mode"]))) / scale if scale > 0 else 0.0), g

    def _classify_turn(self, points):
        """The critical points of one step where the load turned: at most one is the fold, the one whose mode works
        against the load (at a fold ``F_lambda`` is outside the range of ``K``, so ``phi . F_lambda != 0``); a mode
        orthogonal to it (to :data:`ORTHOGONAL`) and every other crossing is a bifurcation (a vessel whose two heads
        dent at nearly one load: one head first, antisymmetric, beside the fold of both). Points that coincide
        (within :data:`COINCIDENT` of the arclength's scale) share an eigenspace whose computed vectors mix: their
        modes are split, in the eigenspace of the ones nearest zero at the fold, into the one along the load's work
        (the fold's) and those orthogonal to it."""
        if not points:
            return
        works = [self._load_work(p) for p in points]
        fold = int(np.argmax([w for w, _ in works]))
        for k, point in enumerate(points):
            if k != fold or works[k][0] <= ORTHOGONAL:
                point["kind"] = "bifurcation"
        first = points[fold]
        group = [first] + [p for k, p in enumerate(points) if k != fold and self.tracer.distance(
            first["q"], first["parameter"], p["q"], p["parameter"]) <= COINCIDENT]
        if len(group) < 2 or first["kind"] != "limit":
            return
        w2, vectors, _, _ = stability(self.eq, first["q"], first["parameter"])  # one M-orthonormal basis
        basis = vectors[:, np.argsort(np.abs(w2))[:len(group)]]
        along = basis.T @ works[fold][1]  # the load's work in the shared eigenspace
        rotation, _ = np.linalg.qr(np.column_stack([along, np.eye(len(group))]))
        for point, column in zip(group, (basis @ rotation[:, :len(group)]).T):
            point["mode"] = column / np.abs(column).max()
            point["family"], point["chi_share"] = family(self.eq, point["q"], point["mode"])


#: ``|phi . F_lambda| / (|phi| |F_lambda|)`` at or below which a critical mode is orthogonal to the load (round-off:
#: a symmetry's mode gives 1e-15 to 1e-12; a fold's is of order 1e-3 or more)
ORTHOGONAL = 1e-8
#: critical points of one step closer than this in the path's scaled arclength share their eigenspace (the vessel's
#: fold and its heads' antisymmetric bifurcation: 7e-8 and 3e-7 apart, located to 1e-7)
COINCIDENT = 1e-5


__all__ = ["COINCIDENT", "ORTHOGONAL", "PathRecord"]
