"""What the natural modes leave out: the damping of the ambient drag and of the wall's viscosity.

The modes of :mod:`mol_shell.analysis.modes` solve ``K phi = omega^2 M phi``: they are the undamped shell's. A scene
with ``drag`` or a viscosity (``eta_mu``, ``eta_lambda``) has the same modes, damped; :func:`damping_note` says so in
one line (a :class:`~mol_shell.SceneWarning`, kept in the modes' ``attrs["damping_note"]``).

The drag's damping of each mode is estimated to first order. Its Rayleigh function is
``R = drag/2 sum_i A_i |r_t,i|^2`` (:mod:`mol_shell.discretization.loading`), ``|r_t|^2 = z_t^2 + r_t^2 + (r chi_t)^2``,
so the linearised motion is ``M q'' + C q' + K q = 0`` with the diagonal ``C = drag A_i (1, 1, r_i^2, 0, 0)`` on
node ``i``'s ``(z, r, chi, theta, psi)``. Put ``q = phi exp(lambda t)``, ``lambda = i omega + delta``, into
``(lambda^2 M + lambda C + K) phi = 0``, multiply by ``phi^T`` and keep the first order in ``C``:
``2 i omega delta phi^T M phi + i omega phi^T C phi = 0``, so the mode decays at ``-delta = phi^T C phi / (2 phi^T M
phi)`` and its damping ratio ``zeta = -Re lambda / |lambda|`` is

    ``zeta = phi^T C phi / (2 omega phi^T M phi)``  (``drag_damping_ratio``).

A mode whose kinetic energy is all the base surface's translation, on a wall whose nodal masses are ``rho_A A_i``
(uniform thickness, ``rho_I = 0``), has ``zeta = drag / (2 rho_A omega)``; the director's turning has mass
(``rho_J``) but no drag, so a mode that turns it is damped less. First order: for ``zeta << 1``, and for modes
whose frequencies are not so close that ``C`` couples them. The viscosity's damping (through the strain rates) is
not estimated.
"""

from __future__ import annotations

import numpy as np

from mol_shell.discretization.loading import dual_areas

#: how many modes' damping ratios the note lists (all are in ``drag_damping_ratio``)
LISTED = 5
#: a ratio above this is beyond the first order the estimate keeps (the note says so)
FIRST_ORDER = 0.1


def drag_damping_ratios(system, scene, q_idx, M, w2, phi, r):
    """``zeta`` of each mode (columns of ``phi`` on the free coordinates ``q_idx``, eigenvalues ``w2``, mass
    matrix ``M``) under the scene's drag, to first order; ``r`` the nodal radii of the state. NaN where
    ``omega^2 <= 0`` (no oscillation to damp)."""
    node, local = np.divmod(np.asarray(q_idx), system.ny)
    field = np.array(system.active)[local]
    weight = np.where(field <= 1, 1.0, np.where(field == 2, np.asarray(r)[node] ** 2, 0.0))
    c = scene.drag * dual_areas(system)[node] * weight
    dissipated = np.einsum("im,i,im->m", phi, c, phi)
    kinetic = np.einsum("im,im->m", phi, M @ phi)
    omega = np.sqrt(np.where(w2 > 0, w2, np.nan))
    return dissipated / (2 * omega * kinetic)


def damping_note(scene, system, ratios=None):
    """One line saying that the modes are the undamped shell's, naming the scene's drag and viscosities that are on
    (with the drag's damping ratios ``ratios`` of the first modes); ``""`` where neither is."""
    left = []
    if scene.drag:
        left.append(f"drag = {scene.drag:g} N s m-3")
    if system.viscous:
        left.append(f"eta_mu = {scene.eta_mu:g} Pa s, eta_lambda = {scene.eta_lambda:g} Pa s")
    if not left:
        return ""
    plural = len(left) > 1 or system.viscous
    note = (f"modes are the undamped shell's: {' and '.join(left)} {'are' if plural else 'is'} left out "
            f"({'they damp' if plural else 'it damps'} these modes; docs/shells.md)")
    if ratios is not None and len(ratios):
        shown = ", ".join(f"{z:.3g}" for z in ratios[:LISTED]) + (", ..." if len(ratios) > LISTED else "")
        note += f"; the drag's damping ratio of each mode, to first order (drag_damping_ratio): {shown}"
        if np.nanmax(ratios, initial=0.0) > FIRST_ORDER:
            note += " (not << 1: beyond the first order; from 1 up the mode does not oscillate)"
    return note


__all__ = ["FIRST_ORDER", "LISTED", "damping_note", "drag_damping_ratios"]
