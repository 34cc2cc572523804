"""What a work-precision comparison (:mod:`mol_shell.analysis.workprecision`) says of each integrator beyond its
errors and times: what held its steps where it was not the tolerance, and the route its name ran.

* Steps: the notes a run of :func:`~mol_shell.simulate` gets from :mod:`mol_shell.runs.step_limits` (a fixed-point
  ``cvode-adams`` on a stiff viscous wall, BDF orders 3-5 held by an undamped director mode), gathered over an
  integrator's sweep from the runs it makes anyway and said once per integrator (the first point that has one, and
  how many of its points do), as a warning and in the file's ``step_warnings``; the note before a run that
  ``max_steps`` cannot reach ``t_end``, once per integrator before its sweep. A comparison said none of them: an
  integrator slow or inaccurate there came with no reason.
* Route: ``route`` of each integrator as its runs report it (``compiled C``, or ``scikit-sundae`` with the reason
  the compiled SUNDIALS driver is unavailable, ``route_reason``), as a run file records it; ``""`` for an integrator
  that has a single route.
"""

from __future__ import annotations

import warnings

from mol_shell._core.errors import MolShellWarning
from mol_shell.runs import step_limits
from mol_shell.runs.resources import LongRunWarning

#: the file's attribute holding the notes, one line per integrator
ATTR = "step_warnings"


class SweepNotes:
    """The notes and routes of a comparison's integrators, gathered point by point (:meth:`point`) and said once per
    integrator (:meth:`said`); ``omega_max`` and ``damping``: the scene's spectrum at the start (``None`` where no
    integrator compared can get a note, :func:`~mol_shell.runs.step_limits.may_note`)."""

    def __init__(self, system, omega_max=None, damping=None):
        self.system, self.omega_max, self.damping = system, omega_max, damping
        self.first, self.count, self.runs, self.routes, self.reasons = {}, {}, {}, {}, {}
        self.before, self.told = {}, set()

    def start(self, name, method, t_end):
        """Before ``name``'s sweep: the note of :func:`~mol_shell.runs.step_limits.max_steps_note`, warned once."""
        if self.damping is None or name in self.before:
            return
        note = step_limits.max_steps_note(method, t_end, self.damping)
        self.before[name] = note
        if note:
            warnings.warn(f"compare: {note}", LongRunWarning, stacklevel=3)

    def point(self, name, key, value, method, traj):
        """One measured point of ``name`` (``key = value``, the run ``traj`` of ``method``): its route, and its notes
        (:func:`~mol_shell.runs.step_limits.run_notes`; the rate of the shell's motion from its states, only where
        it decides a note)."""
        self.runs[name] = self.runs.get(name, 0) + 1
        route, reason = str(traj.stats.get("route", "")), str(traj.stats.get("route_reason", ""))
        for held, said in ((self.routes, route), (self.reasons, reason)):
            if said and said not in held.setdefault(name, []):
                held[name].append(said)
        if self.omega_max is None or not len(traj.t):
            return
        t_end = float(traj.t[-1])
        notes = step_limits.run_notes(method, traj.stats, traj.message, t_end, self.omega_max, self.damping,
                                      lambda: step_limits.states_rate(self.system, traj.y, traj.t))
        if notes:
            self.first.setdefault(name, (key, value, notes))
            self.count[name] = self.count.get(name, 0) + 1

    def line(self, name):
        """``name``'s notes in one line, or ``""``."""
        if name not in self.first:
            return ""
        key, value, notes = self.first[name]
        more, runs = self.count[name] - 1, self.runs[name]
        where = f"at {key} = {value:g}" + (f" and {more} more of its {runs} points" if more else
                                           f", 1 of its {runs} points" if runs > 1 else "")
        return f"compare, {where}: " + " ".join(notes)

    def said(self, name):
        """Warn ``name``'s notes (:meth:`line`), once: at the end of its sweep, or of a comparison cut short."""
        if name in self.told:
            return
        self.told.add(name)
        line = self.line(name)
        if line:
            warnings.warn(line, MolShellWarning, stacklevel=3)

    def attrs(self, integrators):
        """The file's attributes: :data:`ATTR`, one line per integrator with notes (``""``: none)."""
        lines = [note for name in integrators for note in (self.before.get(name) and f"compare: {self.before[name]}",
                                                           self.line(name)) if note]
        return {ATTR: "\n".join(lines)}

    def route(self, name):
        """``(route, reason)`` of ``name``'s runs (each ``"; "``-joined where its points differ), ``""`` where none."""
        return "; ".join(self.routes.get(name, [])), "; ".join(self.reasons.get(name, []))
