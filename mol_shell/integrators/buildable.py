"""Option defaults that follow what this machine can build: ``jacobian``'s ``"compiled"`` where a working gcc
builds the Jacobian, else CasADi's virtual machine (``"vm"``), said in one line.

A default is told apart from the same word given by its type (:class:`Default`): a value given is kept as it is
(``jacobian = "compiled"`` that cannot be built is refused naming ``jacobian``,
:func:`mol_shell.integrators.sundials.pieces`). Whether gcc works is
:func:`~mol_shell.discretization.kernel_cache.gcc_problem` (a probe build, once per process and gcc).
"""

from __future__ import annotations

import sys

from mol_shell.discretization import kernel_cache


class Default(str):
    """A word option's default, told apart from the same word given (``isinstance(value, Default)``); it is the word
    itself everywhere else (equal to it, hashed, shown and written as it)."""

    __slots__ = ()


#: ``jacobian``'s default of ``scipy-radau``, ``scipy-bdf`` and the ``sksundae-*`` routes (``"compiled"``): CasADi's
#: virtual machine where no working gcc can build it (:func:`resolve_jacobian`)
JACOBIAN_DEFAULT = Default("compiled")
_SAID = set()


def resolve_jacobian(name, jacobian):
    """``jacobian`` as a run of the integrator ``name`` uses it. The default (:data:`JACOBIAN_DEFAULT`) is
    ``"compiled"`` where gcc builds a library (:func:`~mol_shell.discretization.kernel_cache.gcc_problem`), else
    ``"vm"``, said in one line on stderr (once per process, integrator and reason); a value given is kept."""
    if not isinstance(jacobian, Default):
        return jacobian
    problem = kernel_cache.gcc_problem()
    if problem is None:
        return str(jacobian)
    if (name, problem) not in _SAID:
        _SAID.add((name, problem))
        print(f"mol-shell: {name} takes its Jacobian from CasADi's virtual machine (jacobian=vm): the compiled "
              f"Jacobian cannot be built ({problem})", file=sys.stderr, flush=True)
    return "vm"
