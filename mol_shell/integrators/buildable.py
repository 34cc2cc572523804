"""Option defaults that follow what this machine can have: ``jacobian``'s ``"compiled"`` where the compiled Jacobian
can be had (its library whole in the cache, or a working gcc that builds it), else CasADi's virtual machine
(``"vm"``), said in one line.

A default is told apart from the same word given by its type (:class:`Default`): a value given is kept as it is
(``jacobian = "compiled"`` that cannot be built is refused naming ``jacobian``,
:func:`mol_shell.integrators.sundials.pieces`). Whether gcc works is
:func:`~mol_shell.discretization.kernel_cache.gcc_problem` (a probe build, once per process and gcc). Where it does
not, whether the compiled Jacobian can be had is a question of the graph (its library may be in the cache: built
earlier, or copied from another machine), answered where the graph is known (:class:`Undecided`, settled by
:func:`~mol_shell.integrators.sundials.pieces` with :func:`~mol_shell.discretization.kernel_cache.unavailable`).
"""

from __future__ import annotations

import os
import sys

from mol_shell.discretization import kernel_cache


class Default(str):
    """A word option's default, told apart from the same word given (``isinstance(value, Default)``); it is the word
    itself everywhere else (equal to it, hashed, shown and written as it)."""

    __slots__ = ()


#: ``jacobian``'s default of ``scipy-radau``, ``scipy-bdf`` and the ``sksundae-*`` routes (``"compiled"``): CasADi's
#: virtual machine where the compiled Jacobian can be neither loaded from the cache nor built (:func:`resolve_jacobian`)
JACOBIAN_DEFAULT = Default("compiled")
_SAID = set()
#: the default as last settled for a graph (:meth:`Undecided.settle`), by integrator name, gcc's problem and the cache:
#: what a run's file records (``settings()`` after the run, which knows no graph); keyed by what settled it, so that a
#: settlement with a cached library is not taken where gcc or the cache has changed since (within one process)
_SETTLED = {}


def _settled_key(name):
    return name, kernel_cache.gcc_problem(), os.environ.get("MOL_SHELL_CACHE", "")


class Undecided(Default):
    """``jacobian``'s default where gcc does not work: ``"compiled"`` if the library of the graph's compiled Jacobian is
    in the cache, else ``"vm"`` (:meth:`settle`, by :func:`~mol_shell.integrators.sundials.pieces`, which knows the
    graph). As a word it is the last settlement for the integrator ``name`` in this process (else what gcc alone
    says); ``quiet``: no line when it settles on the VM (the fallback of a route that said its own line). Pickled
    (in a run's attrs) as the plain word."""

    def __reduce__(self):
        return str, (str(self),)

    def settle(self, problem):
        """``"compiled"`` where ``problem`` is ``None`` (the library can be had), else ``"vm"``, said in one line on
        stderr (once per process, integrator and reason) unless quiet; recorded for the run's file."""
        value = "compiled" if problem is None else "vm"
        _SETTLED[_settled_key(self.name)] = value
        if problem is not None and not self.quiet and (self.name, problem) not in _SAID:
            _SAID.add((self.name, problem))
            print(f"mol-shell: {self.name} takes its Jacobian from CasADi's virtual machine (jacobian=vm): the compiled "
                  f"Jacobian cannot be built ({problem})", file=sys.stderr, flush=True)
        return value


def undecided(name, quiet=False):
    """The :class:`Undecided` default of the integrator ``name``."""
    guess = _SETTLED.get(_settled_key(name)) or ("compiled" if kernel_cache.gcc_problem() is None else "vm")
    value = Undecided(guess)
    value.name, value.quiet = name, quiet
    return value


def resolve_jacobian(name, jacobian):
    """``jacobian`` as a run of the integrator ``name`` uses it. The default (:data:`JACOBIAN_DEFAULT`) is
    ``"compiled"`` where gcc builds a library (:func:`~mol_shell.discretization.kernel_cache.gcc_problem`), else
    :func:`undecided` (``"compiled"`` where the graph's compiled Jacobian is in the cache, else ``"vm"``, said in one
    line: settled by :func:`~mol_shell.integrators.sundials.pieces`); a value given is kept, an :class:`Undecided`
    too."""
    if not isinstance(jacobian, Default) or isinstance(jacobian, Undecided):
        return jacobian
    if kernel_cache.gcc_problem() is None:
        return str(jacobian)
    return undecided(name)
