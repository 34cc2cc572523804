"""The Dataset of an equilibrium path (:func:`mol_shell.analysis.path.path`): steps, critical points, CF attrs."""

from __future__ import annotations

import numpy as np
import xarray as xr

from mol_shell.analysis.equilibria import CONJUGATE_UNITS, REACTIONS
from mol_shell.analysis.path_inputs import loads_at_rest
from mol_shell.analysis.path_modes import NEAR_SHARE, grid_shares, grid_warning, mode_shape, near_message
from mol_shell.analysis.path_stability import LOCATE_RTOL
from mol_shell.model.kinematics import FIELDS
from mol_shell.results.cf import coordinates, header, variables
from mol_shell.results.dataset import FIELD_META, scene_attrs, with_units
from mol_shell.runs.ellipticity import CONSEQUENCE, LONG_NAME, sampled_margins, state_minimum, unchecked_note
from mol_shell.scenes import DESCRIPTIONS

#: what every path file says about its critical loads
SYMMETRY_NOTE = ("critical points are those of rotationally symmetric modes only (the model has no circumferential "
                 "waves): where the real shell buckles into a non-symmetric mode they are upper bounds")


#: the scenes' initial-data parameters that ``None`` leaves to the code (a run's start, not a path's state)
INITIAL_DATA = ("R", "dilation")


def path_dataset(eq, scene, record, status, message, wall_time, start, stop, near=(), noted=None):
    """Assemble the Dataset of a traced path (``record``: the steps and critical points of
    ``mol_shell.analysis.path_record.PathRecord``); ``noted``: the scene's warnings (``material_warning``,
    ``scene_warning``: :mod:`mol_shell.scenes.scene_warnings`), said by :func:`~mol_shell.analysis.path.path` before
    its work, recorded in the attrs. ``near``: the near-critical points (:func:`~mol_shell.analysis.path_modes.near_critical`);
    the grid's critical modes and the near-critical points are said in ``attrs["grid_mode_warning"]`` and
    ``attrs["near_critical_warning"]``."""
    system = eq.system
    steps = len(record.lams)
    fields = np.stack([eq.fields(q, lam) for q, lam in zip(record.qs, record.lams)])
    units = eq.units
    data = {}
    data["parameter"] = (("step",), np.array(record.lams), {
        "units": units, "long_name": f"{DESCRIPTIONS.get(eq.parameter, eq.parameter)} (the continued load)",
        "parameter": eq.parameter})
    for k, name in enumerate(FIELDS):
        u, long_name = FIELD_META[name]
        data[name] = (("step", "s"), fields[:, k], {"units": u, "long_name": long_name})
    data["arclength"] = (("step",), np.array(record.arcs), {"units": "1", "long_name":
                         "pseudo-arclength along the path (scaled load and displacements)"})
    data["branch"] = (("step",), np.array(record.branches, dtype=np.int8), {"units": "1", "long_name":
                      "0 on the path from start, 1 on the branch switched to at a bifurcation (attr branch_point)"})
    data["newton_iterations"] = (("step",), np.array(record.iterations, dtype=np.int32),
                                 {"units": "1", "long_name": "Newton iterations of the step's corrector"})
    data["negative_eigenvalues"] = (("step",), np.array(record.negative, dtype=np.int32), {"units": "1", "long_name":
                                    "number of negative eigenvalues of the tangent stiffness (rigid motions removed)"})
    data["smallest_eigenvalues"] = (("step", "eigenvalue"), np.array(record.eigen), {"units": "s-2", "long_name":
                                    "eigenvalues omega^2 of K phi = omega^2 M phi nearest zero, ascending"})
    data["stiffness_det_sign"] = (("step",), np.array(record.det_sign, dtype=np.int32), {"units": "1", "long_name":
                                  "sign of the determinant of the tangent stiffness (rigid motions removed)"})
    data["stored_energy"] = (("step",), np.array(record.stored), {"units": "J", "long_name": "stored (strain) energy"})
    data["load_work"] = (("step",), record.work(), {"units": "J", "long_name":
                         f"work of the continued load since the first step: int {eq.parameter} dPhi (trapezoidal "
                         "rule over the steps)"})
    data["load_conjugate"] = (("step",), np.array(record.phi), {"units": CONJUGATE_UNITS[eq.parameter], "long_name":
                              "displacement Phi conjugate to the continued load (its work is int load dPhi)" if
                              eq.moved is None else "reaction conjugate to the continued edge displacement (its "
                              "work is int reaction d(displacement))"})
    reactions = np.array(record.reactions)
    at_points = np.array([p["reactions"] for p in record.points]).reshape(-1, len(REACTIONS))
    for k, (name, _, field) in enumerate(REACTIONS):
        if np.isfinite(reactions[:, k]).any():
            what = (f"{'axial force' if field == 0 else 'axial torque'} the support supplies on the imposed "
                    f"{'z' if field == 0 else 'chi'} of the edge at s = {'0' if name.startswith('end1') else 'L'}")
            unit = "N" if field == 0 else "N m"
            data[name] = (("step",), reactions[:, k], {"units": unit, "long_name": what})
            data["point_" + name] = (("point",), at_points[:, k], {"units": unit, "long_name": what +
                                     ", at the critical point"})
    z0 = system.reference[0]
    for name, node in (("end1_dz", 0), ("end2_dz", -1)):  # where the edges are: a response to draw the load against
        data[name.replace("_dz", "_axial_displacement")] = (("step",), fields[:, 0, node] - z0[node], {"units": "m",
                                                              "long_name": f"axial displacement of the edge at s = "
                                                              f"{'0' if node == 0 else 'L'} from the reference"})
    if system.edges == ("pole", "pole"):
        data["volume"] = (("step",), np.array(record.volume), {"units": "m3", "long_name":
                          "volume enclosed by the base surface"})
    points = record.points
    count = len(points)
    shapes = np.zeros((count, 5, eq.n))
    states = (np.stack([eq.fields(p["q"], p["parameter"]) for p in points]) if count
              else np.zeros((0, 5, eq.n)))
    for m, point in enumerate(points):
        shapes[m] = mode_shape(eq, point["mode"])
        shapes[m] /= max(np.abs(shapes[m]).max(), 1e-300)
    data["point_kind"] = (("point",), np.array([p["kind"] for p in points], dtype=str),
                          {"long_name": "kind of critical point: limit (the load turns back) or bifurcation"})
    data["point_parameter"] = (("point",), np.array([p["parameter"] for p in points], dtype=float),
                               {"units": units, "long_name": f"{eq.parameter} at the critical point"})
    data["point_step"] = (("point",), np.array([p["step"] for p in points], dtype=np.int32),
                          {"units": "1", "long_name": "the step after which the critical point lies"})
    data["point_family"] = (("point",), np.array([p["family"] for p in points], dtype=str), {"long_name":
                            "family of the critical mode: torsional when chi carries most of its kinetic energy, "
                            "else axisymmetric"})
    data["point_located"] = (("point",), np.array([p["located"] for p in points], dtype=np.int8), {"units": "1",
                             "long_name": "1 where the crossing was located to the stated tolerance (attr "
                             "locate_tolerance), 0 where the search stopped early (the last estimate kept)"})
    data["point_eigenvalue"] = (("point",), np.array([p["eigenvalue"] for p in points], dtype=float),
                                {"units": "s-2", "long_name": "the crossing eigenvalue where the point was located"})
    point_shares = grid_shares(eq, [(p["q"], p["mode"]) for p in points])
    data["point_grid_mode_share"] = (("point",), point_shares, {"units": "1", "long_name": GRID_SHARE_NAME})
    _near_variables(data, eq, near)
    for k, name in enumerate(FIELDS):
        u, long_name = FIELD_META[name]
        data[f"point_mode_{name}"] = (("point", "s"), shapes[:, k], {"units": u, "long_name":
                                      f"critical mode: {long_name} (each scaled to a largest entry of 1)"})
    for k, name in enumerate(FIELDS):
        u, long_name = FIELD_META[name]
        data[f"point_{name}"] = (("point", "s"), states[:, k], {"units": u, "long_name":
                                 f"equilibrium at the critical point: {long_name}"})
    per_step, every, lost = sampled_margins(system, fields)
    data["ellipticity_margin"] = (("step",), per_step, {"units": "1", "long_name": LONG_NAME})
    point_margins = state_minimum(system.ellipticity_margins(states)) if count else np.zeros(0)
    data["point_ellipticity_margin"] = (("point",), point_margins, {"units": "1", "long_name": f"{LONG_NAME}, at "
                                        "the critical point: where it is not positive, the point is the grid's"})
    z0, r0, theta0 = system.reference
    data["z0"] = (("s",), z0, {"units": "m", "long_name": "axial position of the reference base surface"})
    data["r0"] = (("s",), r0, {"units": "m", "long_name": "radius of the reference base surface"})
    data["theta0"] = (("s",), theta0, {"units": "rad", "long_name": "angle of the reference generator tangent"})
    coords = {"step": ("step", np.arange(steps, dtype=np.int32), {"units": "1", "long_name": "step along the path"}),
              "point": ("point", np.arange(count, dtype=np.int32), {"units": "1", "long_name": "critical point"}),
              "near": ("near", np.arange(len(near), dtype=np.int32), {"units": "1", "long_name":
                       "near-critical point: a local minimum of the lowest eigenvalue without a crossing"}),
              "eigenvalue": ("eigenvalue", np.arange(record.eigen[0].size, dtype=np.int32),
                             {"units": "1", "long_name": "index of the eigenvalue nearest zero, ascending"}),
              "s": ("s", system.s, {"units": "m", "long_name": "arc length of the reference generator"})}
    attrs = {**header(f"mol_shell equilibrium path of scene {scene.name} in {eq.parameter}"),
             "scene": scene.name, "n": eq.n, "parameter": eq.parameter, "parameter_units": units,
             "start": float(start), "units_start": units, "stop": float(stop), "units_stop": units, "status": status,
             "message": message,
             "complete": int(status == "complete"), "critical_points": SYMMETRY_NOTE,
             "rigid_motions": "; ".join(eq.gauge) if eq.gauge else "none (the edges hold the shell)",
             "method": "Keller pseudo-arclength, exact sparse Jacobian, bordered sparse LU; eigenvalues by "
                       "shift-invert about zero",
             "locate_tolerance": "bifurcations and near-critical points: a bracket of LOCATE_RTOL |stop - start| in "
                                 "the parameter; limit points: of LOCATE_RTOL in the scaled arclength".replace("LOCATE_RTOL", f"{LOCATE_RTOL:g}"),
             "branch_point": int(record.branch_point) if record.branch else -1,
             "wall_time_s": float(wall_time), "edge_s0": system.edges[0], "edge_sL": system.edges[1],
             "meridian": system.meridian.describe(), "zeta1_used": system.thickness.zeta1}
    said = grid_warning(eq, [p["kind"] for p in points] + ["near-critical"] * len(near),
                        [p["parameter"] for p in points] + [p["parameter"] for p in near],
                        list(point_shares) + list(data["near_grid_mode_share"][1]))
    if said:
        attrs["grid_mode_warning"] = said
    if near:
        attrs["near_critical_warning"] = near_message(eq, near)
    attrs["ellipticity_checked_every"] = every
    note = unchecked_note(system)
    if note:
        attrs["ellipticity_note"] = note
    if lost is not None:
        step, where = lost
        attrs.update({"ellipticity_lost_step": step, "ellipticity_lost_parameter": float(record.lams[step]),
                      "units_ellipticity_lost_parameter": units,
                      "ellipticity_lost_position": where, "units_ellipticity_lost_position": "m"})
        attrs["ellipticity_warning"] = (
            f"the shell's equations lost ellipticity by step {step} ({eq.parameter} = {record.lams[step]:.6g} "
            f"{units}) at s = {where:.6g} m (cell centre; the first {'step' if every == 1 else 'checked step'} where "
            f"d2W/d(q_s)2 is not positive definite: {CONSEQUENCE}); critical points past it are the grid's")
    params = scene.params()
    for name, value in scene_attrs(scene, system.edges, system.thickness.zeta1).items():
        if name not in (eq.parameter, f"units_{eq.parameter}"):
            attrs[name] = value
    for name in INITIAL_DATA:  # a run's initial data left to the code: no path state is a run's start
        if attrs.get(name, "") is None:
            attrs[name] = "auto"
    history = eq.parameter + "_history"
    if history in params:  # every state is at rest under a constant load (a run or modes --from starts there)
        attrs[history] = "constant"
    if params[eq.parameter]:  # the scene's own value of what the path varies: replaced by the path's values
        attrs["parameter_scene_value"] = float(params[eq.parameter])
        attrs["units_parameter_scene_value"] = units
        attrs["parameter_replaced"] = (
            f"the scene's {eq.parameter} = {params[eq.parameter]:g} {units}"
            + (f" ({history} {params[history]!r})" if params.get(history, "constant") != "constant" else "")
            + " is replaced by the path's values, constant in time")
    notes = loads_at_rest(scene, eq.parameter)
    if notes:  # another load on a history: the states take it at t = 0
        attrs["loads_at_rest"] = "\n".join(notes)
    # the scene's warnings, as a run's (said by path before the work, ``noted``; the continued load's history is
    # replaced, not unused), recorded here
    attrs.update(noted or {})
    return xr.Dataset(variables(data), coords=coordinates(coords), attrs=with_units(attrs))  # zeta1_used's too


#: the long name of ``point_grid_mode_share`` and ``near_grid_mode_share``
GRID_SHARE_NAME = ("share of the critical mode's amplitude (fields weighted by their kinetic energy) in the "
                   "node-to-node (-1)^i pattern, as modes' grid_mode_share; a wave's (1 - cos k ds) / 2; from 0.5 (a "
                   "half-wavelength under two cells): a grid mode, the load the grid's")


def _near_variables(data, eq, near):
    """The near-critical points' variables (dim ``near``) into ``data``."""
    shares = grid_shares(eq, [(p["q"], p["mode"]) for p in near])
    shapes = np.zeros((len(near), 5, eq.n))
    for m, point in enumerate(near):
        shapes[m] = mode_shape(eq, point["mode"])
        shapes[m] /= max(np.abs(shapes[m]).max(), 1e-300)
    units = eq.units
    data["near_parameter"] = (("near",), np.array([p["parameter"] for p in near], dtype=float), {"units": units,
                              "long_name": f"{eq.parameter} at the near-critical point (where the lowest eigenvalue "
                              "has its local minimum, searched between the steps around it; the step's where "
                              "near_located is 0): an estimate of the perfect shell's critical load"})
    data["near_step"] = (("near",), np.array([p["step"] for p in near], dtype=np.int32), {"units": "1", "long_name":
                         "the step where the lowest eigenvalue is least of the steps (the minimum lies between the "
                         "steps before and after it)"})
    data["near_located"] = (("near",), np.array([p.get("located", False) for p in near], dtype=np.int8),
                            {"units": "1", "long_name": "1 where the minimum was located between the steps to the "
                             "stated tolerance (attr locate_tolerance, in the parameter), 0 where the search failed "
                             "and the step's load and state are kept"})
    data["near_eigenvalue"] = (("near",), np.array([p["eigenvalue"] for p in near], dtype=float), {"units": "s-2",
                               "long_name": "the lowest non-negative eigenvalue there (its local minimum)"})
    data["near_eigenvalue_share"] = (("near",), np.array([p["share"] for p in near], dtype=float), {"units": "1",
                                     "long_name": f"that eigenvalue over its value at the path's start (below "
                                     f"{NEAR_SHARE:g})"})
    data["near_family"] = (("near",), np.array([p["family"] for p in near], dtype=str), {"long_name":
                           "family of the near-critical mode: torsional or axisymmetric"})
    data["near_grid_mode_share"] = (("near",), shares, {"units": "1", "long_name": GRID_SHARE_NAME})
    for k, name in enumerate(FIELDS):
        u, long_name = FIELD_META[name]
        data[f"near_mode_{name}"] = (("near", "s"), shapes[:, k], {"units": u, "long_name":
                                     f"near-critical mode: {long_name} (each scaled to a largest entry of 1)"})


def interrupted_at_end(ds):
    """The path ``ds`` as one that a Ctrl-C (or the command line's SIGTERM) stopped after its last step, as its
    Dataset was assembled: its steps all kept, ``status`` ``"interrupted"`` and the message saying where (a path
    interrupted as it stepped has that already)."""
    if ds.attrs["status"] == "interrupted":
        return ds
    last = float(ds.parameter[-1])
    ds.attrs.update(status="interrupted", complete=0,
                    message=f"interrupted by the user at {ds.attrs['parameter']} = {last:.6g} "
                    f"{ds.attrs['parameter_units']}, after the path's last step ({ds.attrs['message']})")
    return ds
