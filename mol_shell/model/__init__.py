"""The shell model: kinematics, material, balance laws. Backend-agnostic scalar physics."""

from mol_shell.model.kinematics import FIELDS, betas, deformation_gradient, delta, kinetic_energy_density
from mol_shell.model.material import Thickness, centroidal_offset, inertias, lame, shell_energy, svk_energy, svk_stress

__all__ = [
    "FIELDS",
    "Thickness",
    "betas",
    "centroidal_offset",
    "deformation_gradient",
    "delta",
    "inertias",
    "kinetic_energy_density",
    "lame",
    "shell_energy",
    "svk_energy",
    "svk_stress",
]
