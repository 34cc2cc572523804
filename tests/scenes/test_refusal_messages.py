"""Refusals that say where: the range of a value that leaves the numbers non-finite, with both of its ends right;
the place where a vessel's segments reach the axis, on the segments as the user drew them."""

import math
import re

import pytest

from mol_shell import ParameterError
from mol_shell.runs import checks
from mol_shell.scenes import Sphere, TwistedCylinder, Vessel

REASON = "the right-hand side at t = 0 is not finite in double precision"


def test_a_tiny_h_is_refused_with_the_upper_end_a_over_2():
    """``h = 1e-300``: the low end found by bisection, the high end the cylinder's own ``h < a/2`` (the refusal said
    ``[2.007e-104, inf) m`` while ``h = 0.6`` is refused as outside ``(0, a/2) = (0, 0.5) m``). ``bad`` stands in for
    the model: the numbers are finite for ``h >= 1e-100``."""
    scene = TwistedCylinder(h=1e-300, a=1.0)
    error = checks._diagnose(scene, REASON, bad=lambda sc: sc.h < 1e-100)
    assert error.name == "h"
    assert error.range.high == 0.5 and not error.range.high_closed  # a/2, open: h = a/2 is refused
    assert 1e-100 <= error.range.low < 1e-99, error.range  # to the bisection's half decade
    assert str(error).startswith("h = 1e-300 is outside about [") and ", 0.5) m (" in str(error), str(error)


def test_a_shell_whose_h_bound_is_in_words_keeps_them():
    """A sphere's wall has no interval above: its range says inf and the wall's condition (it said inf alone)."""
    error = checks._diagnose(Sphere(h=1e-300), REASON, bad=lambda sc: sc.h < 1e-100)
    assert error.name == "h" and math.isinf(error.range.high)
    assert ", inf) m, and the thickness off the axis (" in str(error), str(error)


@pytest.mark.parametrize("segments, index, at", [
    # from the pole heading out, r = 1 - cos(s) after the turn's start at theta = pi/2: r = 0 at s = pi (half way
    # round), then r < 0; it was said at s = 0.1178 m (1/40 of the arc from the end of the reversed curve)
    ("arc 1 270", 1, math.pi),
    ("arc 1 -300", 1, math.pi),  # the other way round: r = 1 - cos(s) too
    # a quarter turn out to r = 1, down 0.5, a quarter turn of radius 0.2 in to r = 0.8, heading for the axis:
    # 0.8 on, the line ends on it at s = pi/2 + 0.5 + 0.1 pi + 0.8, and the next goes beyond (said at 0.01446 m)
    ("arc 1 90, line 0.5, arc 0.2 90, line 0.8, arc 0.3 -90", 4, math.pi / 2 + 0.5 + 0.1 * math.pi + 0.8),
    # a quarter turn out to r = 1 heading up, 60 degrees more in to r = 1 - (1 - cos 60 deg) = 0.5, then a line at
    # 60 degrees to the axis: r = 0.5 - t sin(60 deg) = 0 at t = 1/sqrt(3)
    ("arc 1 -90, arc 1 -60, line 3, arc 1 -30", 3, math.pi / 2 + math.pi / 3 + 1 / math.sqrt(3)),
])
def test_segments_that_reach_the_axis_are_said_by_segment_and_drawn_arc_length(segments, index, at):
    with pytest.raises(ParameterError) as caught:
        Vessel(segments=segments)
    error = caught.value
    part = segments.split(", ")[index - 1]
    assert error.name == "segments"
    said = re.search(rf"\(segment {index} \('{part}'\) reaches the axis at s = ([0-9.e+-]+) m along the segments as "
                     r"drawn, from the start of the first\)$", str(error))
    assert said and float(said.group(1)) == pytest.approx(at, rel=5e-4), str(error)
