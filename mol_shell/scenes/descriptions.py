"""What every scene parameter is: its units (CF ``units`` strings) and a few words, for listings, attrs and docs."""

from __future__ import annotations

import inspect

UNITS = {
    "L": "m", "h": "m", "E": "Pa", "nu": "1", "rho": "kg m-3", "R": "m",
    "gamma": "rad m-1", "omega": "rad s-1", "psi0": "rad", "n_quad": "1", "zeta1": "m",
    "eta_lambda": "Pa s", "eta_mu": "Pa s", "material": "1", "material_parameters": "1", "c10": "Pa", "c01": "Pa",
    "fibre_E": "Pa", "fibre_angle": "rad", "fibre_families": "1", "fibre_compression": "1", "law_limit": "1", "ellipticity_limit": "1", "h_profile": "m", "layers": "1", "dR": "m", "a": "m", "b": "m",
    "alpha1": "rad", "alpha2": "rad", "Lc": "m", "crown": "m", "knuckle": "m", "segments": "1", "r1": "m", "r2": "m", "H": "m", "dilation": "1", "end1": "1", "end2": "1",
    "points": "1", "pressure": "Pa", "gravity": "m s-2", "drag": "N s m-3", "end1_force": "N", "end2_force": "N",
    "end1_torque": "N m", "end2_torque": "N m", "end1_spin": "rad s-1", "end2_spin": "rad s-1",
    "end1_axial_speed": "m s-1", "end2_axial_speed": "m s-1", "end_omega": "rad s-1",
    "end1_dz": "m", "end2_dz": "m", "end1_dchi": "rad", "end2_dchi": "rad",
    # integrator options (varied in studies)
    "dt": "s", "rtol": "1", "atol": "1", "max_step": "s",
}
#: what each parameter is (long_name of a study's coordinates)
DESCRIPTIONS = {
    "L": "length of the shell", "h": "half-thickness (the wall is 2h thick)", "E": "Young's modulus", "nu": "Poisson's ratio",
    "rho": "density", "R": "initial radius", "gamma": "initial twist chi_s", "omega": "initial spin rate chi_t",
    "psi0": "initial shear angle psi", "n_quad": "Gauss-Legendre points through the thickness",
    "zeta1": "lower face of the thickness interval from the base surface", "eta_lambda": "Kelvin-Voigt viscosity eta_lambda",
    "eta_mu": "Kelvin-Voigt viscosity eta_mu", "material": "material law",
    "material_parameters": "parameters of a law of one's own changed for this scene: 'name=value ...' ('': the Material's)",
    "c10": "Mooney-Rivlin constant c10 (material = mooney-rivlin)", "c01": "Mooney-Rivlin constant c01 (material = mooney-rivlin)",
    "fibre_E": "fibre modulus (0: no fibres)",
    "fibre_angle": "fibre angle from the meridian towards +phi", "fibre_families": "fibre families: 1 (helix) or 2 (+-angle)",
    "fibre_compression": "whether fibres carry compression (false: tension only)",
    "law_limit": "stop where the law leaves its range (SVK: a compressive stretch of 1/sqrt(3))",
    "ellipticity_limit": "stop where the shell's equations stop being elliptic in s (false: warn after the run)",
    "layers": "layers from the lower face: 'T MATERIAL key=value ...; ...' (T thickness, m; they add up to 2h)",
    "h_profile": "half-thickness along the meridian: 'table s0:h0 s1:h1 ...' or an expression of s ('': h)",
    "dR": "amplitude of the initial radius variation",
    "Lc": "length of the vessel's cylinder", "crown": "crown radius of the vessel's torispherical heads (a: hemispheres)", "knuckle": "knuckle radius of a torispherical head",
    "segments": "meridian from the bottom pole: 'arc R DEG, line L, ...' (overrides a, Lc, crown, knuckle; turning down, it runs backwards from its last point, end1, where it is drawn)",
    "dt": "leap-frog time step", "rtol": "relative tolerance", "atol": "absolute tolerance (m or rad per field)",
    "max_step": "largest step of the adaptive integrator",
    "a": "natural radius (cylinder, sphere), tube radius (torus) or the cylinder's radius (vessel)",
    "b": "radius of the torus' centre circle",
    "alpha1": "polar angle of the edge at s = 0", "alpha2": "polar angle of the edge at s = L",
    "r1": "radius of the cone's edge at s = 0", "r2": "radius of the cone's edge at s = L",
    "H": "axial length of the cone", "dilation": "initial uniform dilation of the natural shell",
    "end1": "edge condition at s = 0", "end2": "edge condition at s = L", "points": "file of meridian points (r, z); '' runs a built-in dome (half ellipsoid, 1 m x 0.6 m)",
    "pressure": "pressure on the base surface (follower, positive inflating)", "gravity": "gravity along -k",
    "drag": "drag coefficient of the ambient fluid", "end1_force": "axial force on the edge at s = 0",
    "end2_force": "axial force on the edge at s = L", "end1_torque": "axial torque on the edge at s = 0",
    "end2_torque": "axial torque on the edge at s = L", "end1_spin": "prescribed spin rate of the edge at s = 0",
    "end2_spin": "prescribed spin rate of the edge at s = L", "end1_axial_speed": "prescribed axial speed of the edge at s = 0",
    "end2_axial_speed": "prescribed axial speed of the edge at s = L", "end_omega": "both ends spun at this rate from t = 0",
    "end1_dz": "prescribed axial displacement of the edge at s = 0 (its z imposed)",
    "end2_dz": "prescribed axial displacement of the edge at s = L (its z imposed)",
    "end1_dchi": "prescribed rotation about the axis of the edge at s = 0 (its chi imposed)",
    "end2_dchi": "prescribed rotation about the axis of the edge at s = L (its chi imposed)",
}


#: what a parameter left to the code (``auto``, None) or given as nothing (``''``) stands for; a scene's own
#: ``defaults_mean`` says it where it differs
DEFAULTS_MEAN = {
    "zeta1": "the base surface at the wall's centroid",
    "end1": "a pole on the axis, magnet elsewhere", "end2": "a pole on the axis, magnet elsewhere",
    "R": "the static equilibrium under the loads at t = 0 (the natural radius a without loads)",
    "dilation": "the static equilibrium under the loads at t = 0 (the natural shell without loads)",
    "crown": "2a", "knuckle": "0.2a",
    "material_parameters": "the Material's own", "h_profile": "the uniform wall h", "layers": "one layer of material",
    "points": "a built-in dome (half ellipsoid, 1 m x 0.6 m)",
}


#: values a parameter takes beyond the choices its check lists (``mol-shell scenes NAME``)
BEYOND_CHOICES = {"material": "or a mol_shell.Material: its import path 'package.module:attr'"}


def _scene_own(scene, table, name):
    """``name``'s entry in the class attribute ``table`` of ``scene`` (an instance or a class) or of the nearest base
    class that has one, or None."""
    cls = scene if isinstance(scene, type) else type(scene)
    for base in inspect.getmro(cls):
        entries = vars(base).get(table) or {}
        if name in entries:
            return entries[name]
    return None


def describe(name, scene=None):
    """What parameter ``name`` is, in a few words (``NAME_history``: the time history of ``NAME``); with ``scene``,
    the scene's own words where its ``descriptions`` have them (``a`` of the torus is its tube radius)."""
    if name.endswith("_history"):
        base = name[: -len("_history")]
        return f"time history of {base} (a factor on it): constant, step T0, ramp T1, sine F, table t0:h0 ..."
    own = None if scene is None else _scene_own(scene, "descriptions", name)
    return own or DESCRIPTIONS.get(name, "")


def default_meaning(name, scene=None):
    """What ``auto`` (None) or ``''`` stands for as the value of ``name``, in a few words ('' if nothing is said):
    the scene's own ``defaults_mean`` first."""
    own = None if scene is None else _scene_own(scene, "defaults_mean", name)
    return own or DEFAULTS_MEAN.get(name, "")


def is_numeric(field):
    """Whether a scene's dataclass field holds a number (``float``, ``int``, or one of them or None: auto)."""
    return set(str(field.type).replace(" ", "").split("|")) <= {"float", "int", "None"}


__all__ = ["BEYOND_CHOICES", "DEFAULTS_MEAN", "DESCRIPTIONS", "UNITS", "default_meaning", "describe", "is_numeric"]
