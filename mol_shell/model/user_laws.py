"""Laws of one's own: :class:`Material`, a stored energy ``W(C, parameters)`` written by the user.

``energy(C, p)`` takes ``C``, the 3-D right Cauchy-Green tensor as a CasADi ``SX`` 3x3 matrix in the reference
basis (meridian, director = thickness, circumference), and ``p``, the dict ``parameters``; it returns ``W`` per unit
reference volume as an ``SX`` scalar (``casadi.trace``, ``casadi.det``, ``casadi.log``, ``C[0, 2]``, ... all work).
The law then runs like a built-in one (:mod:`mol_shell.model.laws`): through the thickness with its ``thickness``
treatment (``plane-stress``, ``incompressible`` or ``director``), stresses and Jacobians by automatic
differentiation, fibres on top.

A scene takes it as ``material``:

- the :class:`Material` itself (Python): the scene stores its key, registered in this process: its ``name``, or
  ``name@digest`` (8 hex digits of :meth:`Material.fingerprint`) for a second, different law under a name already
  given to one (:func:`mol_shell.model.laws.law_key`), so that each scene runs the law it was made with;
- an import path ``"package.module:attr"`` (a scene file's ``material = "..."``, the command line's
  ``--set material=...``): the module is imported where the scene is made, and the scene stores the path.

A study's cases carry the laws they name to its worker processes (:func:`mol_shell.runs.study.carried_materials`).

The parameters are numbers in the :class:`Material`; a scene's ``material_parameters`` (``"mu=3e5 k=1e4"`` or a
dict) changes some of them for that scene, so a study varies them like a built-in law's (``vary={"material.mu":
[...]}``; :func:`parameter_text`).
"""

from __future__ import annotations

import hashlib
import math
import sys
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mol_shell._core.errors import ParameterError, by_interrupt
from mol_shell.model.hyperelastic import (
    NATURAL_STATES,
    NEWTON_STEPS,
    ROOT_GRID,
    Law,
    condensed_energy,
    has_root,
    plane_stress_steps,
    plane_stress_thickness,
    with_thickness,
)

#: the thickness treatments a user law may ask for (:mod:`mol_shell.model.hyperelastic`)
USER_TREATMENTS = ("plane-stress", "incompressible", "director")
#: a plane-stress law's solve counts as failed (no root ``C_22 > 0``, or one its steps do not reach: its energy is
#: then NaN, and a run stops there) where it leaves ``|dW/dC_22|`` above this fraction of the stiffness
#: ``|lambda*| + 2 |mu|``: its forces are then off by about as much, relative; a converged solve leaves round-off
#: (1e-15), the steps being chosen for 1e-9 at stretches 0.6 to 2
UNSOLVED = 1e-6


def state_text(state):
    """``(C_11, C_33, C_13)`` as the in-plane stretches (and shear) it is."""
    c11, c33, c13 = state
    shear = f" with C13 = {c13:g}" if c13 else ""
    kind = " (equibiaxial)" if c11 == c33 and not c13 else (" (uniaxial)" if c33 == 1.0 and not c13 else "")
    return f"in-plane stretches {math.sqrt(c11):.3g} and {math.sqrt(c33):.3g}{shear}{kind}"


#: the built-in laws' names (filled in by :mod:`mol_shell.model.laws`): a Material of one of them is refused when it
#: is made, not when a scene first uses it
RESERVED = set()


@dataclass(frozen=True, eq=False)
class Material:
    """A hyperelastic law from its stored energy.

    Use it as a scene's ``material``: ``mol_shell.Sphere(material=rubber)`` (the scene stores its ``name``,
    registered in this process; ``name@digest`` for another law under a name already used), or by its import path
    ``"package.module:attr"`` where a string is needed (a scene
    file's ``material = "mylaws:rubber"``, ``--set material=mylaws:rubber``; ``mylaws``
    importable: on ``PYTHONPATH`` or in the working directory); change its
    parameters for one scene with ``material_parameters`` (``"mu=2e5"``). See docs/materials.md.

    Parameters
    ----------
    name : str
        What runs and files call it (``material`` in their attrs); not the name of a built-in law.
    energy : callable
        ``energy(C, p) -> W``: ``C`` a CasADi ``SX`` 3x3 (index 1 the thickness), ``p`` the parameters.
    parameters : dict
        ``{name: number}`` handed to ``energy``.
    thickness : str
        ``plane-stress`` (default: the thickness stretch minimises ``W``, by the unrolled Newton iteration of
        :func:`~mol_shell.model.hyperelastic.plane_stress_thickness`), ``incompressible`` (``det C = 1``) or
        ``director`` (the paper's inextensible director, thickness stretch 1).
    """

    name: str
    energy: object
    parameters: dict = field(default_factory=dict)
    thickness: str = "plane-stress"

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip() or ":" in self.name or self.name in RESERVED:
            raise ParameterError("name", self.name, "a name of its own (no ':'; not a built-in law's)",
                                 hint="the built-in laws: " + ", ".join(sorted(RESERVED)) if self.name in RESERVED
                                 else "")
        if not callable(self.energy):
            raise ParameterError.not_a("energy", self.energy, "a function energy(C, parameters)",
                                       "a function of C (casadi.SX 3x3) and the parameters")
        if self.thickness not in USER_TREATMENTS:
            raise ParameterError("thickness", self.thickness, "{" + ", ".join(USER_TREATMENTS) + "}")
        if not isinstance(self.parameters, dict):
            raise ParameterError.not_a("parameters", self.parameters, "a dict", "a dict of names and finite numbers")
        for key, value in self.parameters.items():
            if not isinstance(key, str) or isinstance(value, (bool, np.bool_)) \
                    or not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
                raise ParameterError("parameters", f"{key}={value!r}", "a dict of names and finite numbers")
        object.__setattr__(self, "parameters", {k: float(v) for k, v in self.parameters.items()})
        self._check_energy()
        object.__setattr__(self, "steps", NEWTON_STEPS)  # the plane-stress solve's, set by the checks below
        object.__setattr__(self, "solve", "newton")  # and which solve (hyperelastic.SOLVES)
        object.__setattr__(self, "stiffness", None)  # |lambda*| + 2 |mu| (Pa), plane stress: set likewise
        self._check_plane_stress(self._check_natural_state())

    def _check_energy(self):
        """The energy is a CasADi scalar of ``C`` (its natural state is checked by :meth:`_check_natural_state`)."""
        C = ca.SX.sym("C", 3, 3)
        allowed = "a function energy(C, parameters) of casadi.SX returning a CasADi scalar"
        try:
            W = self.energy(C, dict(self.parameters))
        except Exception as exc:  # any failure of the user's function is a refusal of it
            if by_interrupt(exc):  # a Ctrl-C inside a CasADi call of the function (wrapped): not its failure
                raise
            said = " ".join(str(exc).split("\n")[0].split())  # one line: CasADi's messages run over a dozen
            raise ParameterError.invalid("energy", getattr(self.energy, "__name__", repr(self.energy)),
                                         f"of material {self.name} raised {type(exc).__name__}: {said}", allowed
                                         ) from None
        if not isinstance(W, (ca.SX, ca.DM, int, float, np.number, np.ndarray)) or isinstance(W, bool):
            # None or a string: CasADi's SX() refused it in a dozen lines of its prototypes
            raise ParameterError.invalid("energy", self.name, f"returned {type(W).__name__}, not a CasADi expression",
                                         allowed)
        W = ca.SX(W)
        if W.numel() != 1:
            raise ParameterError.not_a("energy", self.name, "a scalar energy", "a function returning one number")

    def _check_natural_state(self):
        """The natural state ``C = I`` is stress-free and stable under the law's thickness treatment: ``W`` finite
        and 0 there (an offset, ``mu/2 (I1 - 3)`` without its -3, was a stored energy at rest), its in-plane derivatives zero (to 1e-9 of the stiffness; a law linear in ``C`` fails here), ``mu >= 0``
        and ``lambda* + mu > 0`` (:meth:`small_strain_pair`; ``mu = 0`` is a fluid-like wall). A law failing one
        was refused at its run, blamed on ``h``, or ran (a stressed or unstable natural state). Returns the
        stiffness scale ``|lambda*| + 2 |mu|`` (Pa)."""
        law, p = self.law(), dict(self.parameters)
        # C11, C33, C13 (meridian, circumference), C12, C23 (with the thickness direction: the director's shear
        # gives C12; a law stressed in C12 at C = I turned the unloaded shell by 0.87 rad in 10 ms)
        x = ca.SX.sym("x", 5)
        C = ((1.0 + x[0], x[3], x[2]), (x[3], 1.0, x[4]), (x[2], x[4], 1.0 + x[1]))
        W = condensed_energy(law, with_thickness(C, C[1][1]), p)
        value, slope = (np.array(v, dtype=float).ravel() for v in ca.Function("w", [x], [W, ca.gradient(W, x)])(0))
        lam, mu = self.small_strain_pair() if np.all(np.isfinite([*value, *slope])) else (math.nan, math.nan)
        scale = abs(lam) + 2 * abs(mu)
        if not math.isfinite(scale):
            reason = "an energy finite near C = I"
        elif np.abs(slope).max() > 1e-9 * scale:
            reason = (f"a stress-free natural state: dW/dC = 0 at C = I (here up to "
                      f"{np.abs(slope).max():.4g} Pa, the stiffness {scale:.4g} Pa)")
        elif abs(value[0]) > 1e-9 * scale:  # an offset moves no stress, but every stored energy and energy balance
            reason = (f"an energy that is 0 at C = I (here W(I) = {value[0]:.4g} J m-3 against the stiffness "
                      f"{scale:.4g} Pa: mu/2 (I1 - 3) written without its -3?)")
        elif not (mu >= 0 and lam + mu > 0):  # mu = 0: a fluid-like wall, whose ellipticity is not checked
            reason = f"a stable natural state: mu >= 0 and lambda* + mu > 0 at C = I (here {mu:.4g} and {lam + mu:.4g} Pa)"
        else:
            return scale
        raise ParameterError.not_a("energy", self.name, reason, "energies finite, zero, stress-free and stable (mu >= "
                                   "0, lambda* + mu > 0) at C = I", hint=f"thickness = {self.thickness}")

    def _check_plane_stress(self, scale):
        """Plane stress: the solve and the fewest of its unrolled steps (2 to 32) that solve ``dW/dC_22 = 0`` to 1e-9
        of the stiffness ``scale`` wherever 32 do, at in-plane stretches 0.6 to 2, in the fewest operations: Newton's
        steps in ``ln C_22``, or fitted third-order ones (:func:`~mol_shell.model.hyperelastic.plane_stress_steps`;
        St Venant-Kirchhoff takes 2 fitted steps, exact up to the edge of its domain, where 8 of Newton's reached it up
        to a stretch of 1.424 only, of 1.472). Refused naming ``thickness``, and saying where and why, when next to the
        natural state (stretches 0.9 and 1.1) the condition has no root ``C_22 > 0`` or 32 steps do not reach it.
        Farther out the law is taken where the solve works: where it does not (no root: St Venant-Kirchhoff's beyond
        an equibiaxial stretch of 1.47 at ``nu = 0.3``; or a root the steps do not reach) the law's energy is NaN
        there (:data:`UNSOLVED`), and a run that gets there stops as at the edge of the law's domain, naming the law,
        time and cell. Six steps were taken for every law, unchecked, until December 6 (an Ogden
        volumetric term, ``J^-9``, left 1e8 Pa of thickness stress, and energies 28 times too high); until December
        7 convergence was asked for at every stretch to 2, and SVK, whose condition has no root there, was refused
        for ``nu >= 0.2`` (blaming the step count)."""
        if self.thickness != "plane-stress":
            return
        energy, p = self.law().energy, dict(self.parameters)
        found = plane_stress_steps(lambda C: energy(C, p), scale)
        allowed = ("plane-stress for laws whose condition dW/dC22 = 0 has a root C22 > 0 next to the natural state "
                   "(in-plane stretches 0.9 and 1.1) that Newton's method (or the fitted solve) from C22 = 1 reaches "
                   "in 32 steps; director or incompressible")
        rootless = [state for state in found.rootless if state in NATURAL_STATES]
        unreached = [(state, r) for state, r in found.unreached if state in NATURAL_STATES]
        if rootless:
            raise ParameterError("thickness", self.thickness, allowed, hint=f"material {self.name}: dW/dC22 = 0 has no "
                                 f"root C22 > 0 at {state_text(rootless[0])}")
        if unreached:
            (state, residual), = unreached[:1]
            left = f"leave dW/dC22 = {residual:.3g} of the stiffness" if math.isfinite(residual) else (
                "leave dW/dC22 not finite")
            raise ParameterError("thickness", self.thickness, allowed, hint=f"material {self.name}: at "
                                 f"{state_text(state)} 32 Newton (and fitted) steps from C22 = 1 {left}")
        object.__setattr__(self, "steps", found.steps)
        object.__setattr__(self, "solve", found.solve)
        object.__setattr__(self, "stiffness", scale)

    def with_parameters(self, changes):
        """This law with some of its parameters changed (``{name: number}``; names it does not have are refused,
        naming ``material_parameters``)."""
        changes = dict(changes)
        if not changes:
            return self
        for key, value in changes.items():
            if key not in self.parameters:
                raise ParameterError("material_parameters", key, "{" + ", ".join(sorted(self.parameters)) + "}",
                                     hint=f"the parameters of material {self.name}")
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) \
                    or not math.isfinite(value):
                raise ParameterError.not_a("material_parameters", f"{key}={value}", "a finite number",
                                           "finite numbers")
        try:
            return Material(self.name, self.energy, {**self.parameters, **changes}, self.thickness)
        except ParameterError as exc:  # the changed law refused (unstable, say): the changes are to blame
            shown = " ".join(f"{k}={v:g}" for k, v in changes.items())
            raise ParameterError("material_parameters", shown, exc.allowed,
                                 message=f"material_parameters = {shown!r} of material {self.name}: {exc}") from None

    def fingerprint(self):
        """A digest of what the law computes: its name, thickness treatment, parameters and the energy's expression
        in a symbolic ``C`` (so an edited energy function, under the same name or import path, is another law)."""
        if "_fingerprint" not in self.__dict__:  # computed once (a scene made with the law asks for it)
            W = ca.SX(self.energy(ca.SX.sym("C", 3, 3), dict(self.parameters)))
            text = f"{self.name}|{self.thickness}|{sorted(self.parameters.items())}|{W}"
            object.__setattr__(self, "_fingerprint", hashlib.sha256(text.encode()).hexdigest()[:16])
        return self._fingerprint

    def import_path(self):
        """``"module:attr"``, the import path of this very object, or ``None``: the path it was imported by (a scene's
        ``material = "my_laws:rubber"``), else the first module-level name bound to it in an imported module (its
        energy's module first; not ``__main__``: a script's or a notebook's law has no path another process can
        import). A run records it (``material_imports``) so that ``mol-shell scenes RUN.nc --toml`` names the law
        as a scene file must; until December 7 a run of the Python API kept the law's name alone."""
        if self.__dict__.get("_import_path"):
            return self._import_path
        if self.__dict__.get("_unfound_among") == len(sys.modules):  # looked for among these modules (20 ms)
            return None
        first = getattr(self.energy, "__module__", None)
        for name in dict.fromkeys([first, *list(sys.modules)]):
            module = sys.modules.get(name) if name not in (None, "__main__", "__mp_main__") else None
            attrs = getattr(module, "__dict__", None)
            if not isinstance(attrs, dict) or getattr(module, "__name__", None) != name:
                continue
            found = next((attr for attr, value in list(attrs.items()) if value is self), None)
            if found is not None:
                self.keep_import_path(f"{name}:{found}")
                return self._import_path
        object.__setattr__(self, "_unfound_among", len(sys.modules))
        return None

    def keep_import_path(self, path):
        """Keep ``path`` (``"module:attr"``) as this law's :meth:`import_path`."""
        object.__setattr__(self, "_import_path", path)

    def law(self):
        """The :class:`~mol_shell.model.laws.Law` that runs it (``C`` handed over as an ``SX`` matrix)."""
        energy = self.energy

        def nested_energy(C, p):
            M = ca.SX(3, 3)
            for i in range(3):
                for j in range(3):
                    M[i, j] = C[i][j]
            return energy(M, p)

        steps, stiffness = getattr(self, "steps", NEWTON_STEPS), getattr(self, "stiffness", None)
        solve = getattr(self, "solve", "newton")
        if self.thickness != "plane-stress" or stiffness is None:  # (the checks of plane stress run without)
            condense = None if self.thickness != "plane-stress" or (steps, solve) == (NEWTON_STEPS, "newton") else (
                lambda C, p: plane_stress_thickness(lambda c: nested_energy(c, p), C, steps=steps, solve=solve))
            return Law(self.name, nested_energy, tuple(self.parameters), self.thickness, condense=condense)
        tol = UNSOLVED * stiffness

        def condense(C, p):
            return plane_stress_thickness(lambda c: nested_energy(c, p), C, steps=steps, residual=True, solve=solve)

        def held(C, values, p):  # NaN where the solve failed: the energy only (the forces, C_22 held, do not see it)
            return nested_energy(with_thickness(C, values[0]), p) + ca.if_else(values[1] <= tol, 0.0, math.nan)

        return Law(self.name, nested_energy, tuple(self.parameters), self.thickness, condense=condense,
                   held_energy=held, unsolved=self.unsolved)

    def unsolved(self, C, p):
        """Why the plane-stress thickness of this law is not found at ``C`` (nested 3x3 of numbers, the parameters
        ``p``), or ``None``: no root ``C_22 > 0`` of ``dW/dC_22 = 0`` (on
        :data:`~mol_shell.model.hyperelastic.ROOT_GRID`), or one that its Newton steps do not reach (to
        :data:`UNSOLVED` of the stiffness)."""
        if self.thickness != "plane-stress" or getattr(self, "stiffness", None) is None:
            return None
        law, x = self.law(), ca.SX.sym("c22")
        g = ca.gradient(law.energy(with_thickness(C, x), p), x)
        with np.errstate(all="ignore"):
            slopes = np.array(ca.Function("slope", [x], [g]).map(len(ROOT_GRID))(ROOT_GRID), dtype=float).ravel()
            left = float(ca.evalf(law.condense(C, p)[1])) / self.stiffness
        if not has_root(np.nan_to_num(slopes, nan=0.0)):
            return "its plane-stress condition dW/dC22 = 0 has no root C22 > 0 there"
        if not left <= UNSOLVED:
            kind = "Newton" if getattr(self, "solve", "newton") == "newton" else "fitted"
            return (f"its {self.steps} {kind} steps from C22 = 1 leave dW/dC22 = {left:.3g} of the stiffness there, "
                    "short of the root of its plane-stress condition")
        return None

    def small_strain_pair(self):
        """``(lambda*, mu)`` of the law at ``C = I``, thickness condensed: ``mu = d2W/dC13^2`` (``C13 = C31``) and
        ``lambda* + 2 mu = 4 d2W/dC11^2`` (the isotropic ``lambda*/2 (tr E)^2 + mu E:E``, ``E = (C - I)/2``). For the
        scales of a run (tolerances, wave speeds), not its energy."""
        x = ca.SX.sym("x")
        law, p = self.law(), dict(self.parameters)

        def second(i, j):
            C = [[x if (a, b) in ((i, j), (j, i)) else (1.0 if a == b and (a, b) != (i, j) else 0.0)
                  for b in range(3)] for a in range(3)]
            if i == j:
                C[i][i] = x
            W = condensed_energy(law, with_thickness(tuple(tuple(r) for r in C), C[1][1]), p)
            d2 = ca.Function("d2", [x], [ca.hessian(W, x)[0]])
            return float(d2(1.0 if i == j else 0.0))

        mu = second(0, 2)
        lam = 4 * second(0, 0) - 2 * mu
        return lam, mu


def parameter_values(value):
    """``material_parameters`` as a dict ``{name: float}``: from ``"name=value name=value"`` (spaces or commas
    between the pairs) or a dict. ParameterError naming ``material_parameters`` for anything else."""
    if isinstance(value, dict):
        pairs = list(value.items())
    elif isinstance(value, str):
        pairs = []
        for item in value.replace(",", " ").split():
            key, sep, number = item.partition("=")
            if not sep or not key:
                raise ParameterError.not_a("material_parameters", value, "'name=value ...'",
                                           "'name=value name=value' or a dict of numbers", hint=f"at {item!r}")
            pairs.append((key.strip(), number.strip()))
    else:
        raise ParameterError.not_a("material_parameters", value, "'name=value ...'",
                                   "'name=value name=value' or a dict of numbers")
    values = {}
    for key, number in pairs:
        if str(key) in values:  # the last one silently won
            raise ParameterError.invalid("material_parameters", value, f"sets {key} twice", "each parameter once")
        try:
            values[str(key)] = float(number) if not isinstance(number, bool) else math.nan
        except (TypeError, ValueError):
            raise ParameterError.not_a("material_parameters", f"{key}={number}", "a finite number",
                                       "finite numbers") from None
        if not math.isfinite(values[str(key)]):
            raise ParameterError.not_a("material_parameters", f"{key}={number}", "a finite number", "finite numbers")
    return values


def parameter_text(values):
    """The stored form of ``material_parameters``: ``"name=value ..."``, sorted by name, values as ``repr``."""
    return " ".join(f"{k}={float(v)!r}" for k, v in sorted(values.items()))
