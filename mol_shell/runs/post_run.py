"""A run's work after its integration (its ellipticity check, its stresses), which a Ctrl-C cuts short without losing
the run: the states computed are kept, the work the signal met or had not begun is skipped and said so, and the run
ends ``"interrupted"`` (the command line writes it and exits 130, or 143 for its SIGTERM).

A ``KeyboardInterrupt`` raised there escaped from :func:`~mol_shell.runs.simulate.simulate` and the command line
wrote nothing (a run of 2 s of stepping lost to a Ctrl-C in its stresses' sampling). :func:`simulate` notes the
signal from the run's end on (:func:`mol_shell._core.interrupts.watched`); :func:`cut_short` raises it within one
piece of the work, where it ends that piece (a long sampling of stresses stops at once); :func:`kept` says what was
skipped.
"""

from __future__ import annotations

import contextlib
import signal

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.errors import by_interrupt
from mol_shell.results.cf import variables
from mol_shell.runs.ellipticity import LONG_NAME

#: ``attrs["stresses"]`` of a run interrupted before its stresses were computed (none in the file)
STRESSES_INTERRUPTED = ("skipped: interrupted by the user before they were computed; mol_shell.add_stresses(ds) adds "
                        "them")
#: ``attrs["ellipticity_note"]`` of a run interrupted before its ellipticity was checked (``ellipticity_margin`` NaN)
ELLIPTICITY_INTERRUPTED = "not checked: interrupted by the user before the check (ellipticity_margin is NaN)"


@contextlib.contextmanager
def cut_short(watch):
    """Run the block with a Ctrl-C (and the command line's SIGTERM) raised where it lands, and taken: the block ends
    there and the signal is noted in ``watch`` (:class:`~mol_shell._core.interrupts.Watch`), as is one that a C call
    lost or wrapped (:func:`~mol_shell._core.errors.by_interrupt`). Other errors pass."""
    with interrupts.watched(raising=True) as inner:
        try:
            yield
            inner.raising = False  # the block is done: a signal from here on is noted
        except BaseException as exc:
            inner.raising = False
            if not (inner.caught or by_interrupt(exc)):
                raise
            inner.caught, inner.signum = True, inner.signum or signal.SIGINT
    if inner.caught:
        watch.caught, watch.signum = True, inner.signum


def kept(ds, watch, stresses=True, ellipticity=True):
    """``ds`` as a run that a Ctrl-C noted in ``watch`` stopped after its integration: its states kept, its
    ellipticity check (``ellipticity``: one is made) and stresses (``stresses``: asked for) marked not done where
    they are not (``ellipticity_margin`` NaN, ``attrs["ellipticity_note"]``; ``attrs["stresses"]``), and ``status``
    ``"interrupted"`` with a message saying where; ``ds`` itself where no signal arrived."""
    if not watch.caught:
        return ds
    ds = ds.copy(deep=False)
    skipped = []
    if ellipticity and "ellipticity_margin" not in ds:
        ds = ds.assign(variables({"ellipticity_margin": (("time",), np.full(ds.sizes["time"], np.nan),
                                                         {"units": "1", "long_name": LONG_NAME})}))
        ds.attrs.update(ellipticity_checked_every=0, ellipticity_note=ELLIPTICITY_INTERRUPTED)
        skipped.append("its ellipticity check")
    if stresses and "stresses" not in ds.attrs:
        ds.attrs["stresses"] = STRESSES_INTERRUPTED
        skipped.append("its stresses")
    before = f", before {' and '.join(skipped)}" if skipped else ""
    if ds.attrs.get("status") == "interrupted":  # while it stepped, and again after
        ds.attrs["message"] = f"{ds.attrs['message']}{before}"
        return ds
    t = float(ds.time[-1])
    end = "its end" if ds.attrs.get("status") == "complete" else f"where it stopped ({ds.attrs.get('message')})"
    ds.attrs.update(status="interrupted", complete=0,
                    message=f"interrupted by the user after the run reached {end}, t = {t:.9g} s{before}")
    if not np.isfinite(float(ds.attrs.get("failure_time", np.nan))):
        ds.attrs["failure_time"] = t
    return ds


__all__ = ["ELLIPTICITY_INTERRUPTED", "STRESSES_INTERRUPTED", "cut_short", "kept"]
