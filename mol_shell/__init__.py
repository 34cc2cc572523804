"""mol_shell: rotationally symmetric motions of Cosserat shells of revolution (Antman & Bourne 2010)."""

from .version import __version__  # noqa: F401

from .scenes import SCENES, Axisymmetric, SpinningRing, TwistedCylinder, get_scene  # noqa: E402
from .scenes.files import load_scene  # noqa: E402
from .simulate import build, simulate  # noqa: E402
from .output import read_netcdf, write_netcdf  # noqa: E402
from .unshearable import Unshearable, simulate_unshearable  # noqa: E402  (registers the scene)
from .ring import simulate_ring  # noqa: E402
from .study import study  # noqa: E402

__all__ = [
    "SCENES", "Axisymmetric", "SpinningRing", "TwistedCylinder", "Unshearable", "build", "get_scene", "load_scene", "read_netcdf",
    "simulate", "simulate_ring", "simulate_unshearable", "study", "write_netcdf",
]
