"""mol_shell: rotationally symmetric motions of Cosserat shells of revolution (Antman & Bourne 2010).

The public face of the package; nothing inside the package imports it. Layers, lowest first (each imports
only from those before it): ``_core``, ``model``, ``discretization``, ``integrators``, ``scenes``,
``results``, ``runs``, ``analysis``, ``views``, ``cli``.
"""

from mol_shell._core.interrupts import exit_if_command as _exit_if_command

try:  # the command line's Ctrl-C while these load (about a second) is its Ctrl-C: one line, exit 130
    from mol_shell._core.errors import MaterialWarning, ModelLimitError, MolShellWarning, ParameterError, SceneWarning
    from mol_shell._core.version import __version__
    from mol_shell.analysis.modes import modes
    from mol_shell.analysis.path import path
    from mol_shell.analysis.path_continue import continue_path
    from mol_shell.integrators import INTEGRATORS
    from mol_shell.model.user_laws import Material
    from mol_shell.results.dataset import read_netcdf, write_netcdf
    from mol_shell.results.stresses import add_stresses
    from mol_shell.runs.building import build
    from mol_shell.runs.resources import LongRunWarning
    from mol_shell.runs.ring import simulate_ring
    from mol_shell.runs.simulate import simulate
    from mol_shell.runs.study import study
    from mol_shell.runs.unshearable import simulate_unshearable
    from mol_shell.scenes import (
                                  SCENES,
                                  Axisymmetric,
                                  Cone,
                                  MeridianShell,
                                  ShellScene,
                                  Sphere,
                                  SpinningRing,
                                  Torus,
                                  TwistedCylinder,
                                  Unshearable,
                                  Vessel,
                                  get_scene,
    )
    from mol_shell.scenes.files import load_scene
except KeyboardInterrupt:
    _exit_if_command()
    raise

__all__ = [
    "INTEGRATORS", "SCENES", "Axisymmetric", "add_stresses", "Cone", "LongRunWarning", "Material", "MaterialWarning", "MeridianShell", "ModelLimitError", "MolShellWarning", "ParameterError", "SceneWarning", "ShellScene",
    "SpinningRing", "Sphere", "Torus", "TwistedCylinder", "Unshearable", "Vessel", "__version__", "build", "continue_path", "get_scene",
    "load_scene", "modes", "path", "read_netcdf",
    "simulate", "simulate_ring", "simulate_unshearable", "study", "write_netcdf",
]
