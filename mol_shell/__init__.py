"""mol_shell: rotationally symmetric motions of Cosserat shells of revolution (Antman & Bourne 2010)."""

__version__ = "0.1.0"

from .scenes import SCENES, Axisymmetric, SpinningRing, TwistedCylinder, get_scene  # noqa: E402
from .simulate import build, simulate  # noqa: E402
from .output import read_netcdf, write_netcdf  # noqa: E402

__all__ = ["SCENES", "Axisymmetric", "SpinningRing", "TwistedCylinder", "build", "get_scene", "read_netcdf", "simulate", "write_netcdf"]
