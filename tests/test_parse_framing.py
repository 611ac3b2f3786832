"""Framing in open wording (issue #15): shot sizes, frame regions and a level horizon. Each family
a held-out miss belonged to ("not too zoomed in", "fairly tight", "crammed into the frame", "every
slat in view", "the north-west corner", "horizon true", "10 per cent of the frame") is tested on
other words of the family, none of them a suite's sentence."""

from __future__ import annotations

import pytest
from test_parse_generalise import BEAR, BENCH, CAR, MUG, SOFA, TV, one, read, rows

TEMPERED = [
    # "not too" tempers a size either way: the middle size is left.
    ("the mug from the left, not that zoomed in", one(MUG, shot="medium", view="left")),
    ("sofa, not so zoomed out please", one(SOFA, shot="medium")),
    ("the bench - not overly tight", one(BENCH, shot="medium")),
    ("teddy bear, not too cropped", one(BEAR, shot="medium")),
    ("the television, not super far away", one(TV, shot="medium")),
    ("the toy car, not too near and not too distant", one(CAR, shot="medium")),
    ("the mug is not too small", one(MUG, shot="medium")),
]

GRADED = [
    # A moderate grade keeps the size word's class.
    ("teddy, fairly close", one(BEAR, shot="close-up")),
    ("the bench, pretty wide", one(BENCH, shot="wide")),
    ("mug - quite big", one(MUG, shot="close-up")),
    ("the sofa, rather small, from behind", one(SOFA, shot="wide", view="back")),
    ("toy car, reasonably close", one(CAR, shot="close-up")),
    ("the TV should look moderately small", one(TV, shot="wide")),
]

CRAMMED = [
    # Pressed into the frame: it fills it.
    ("the sofa crammed into the picture", one(SOFA, shot="close-up")),
    ("bench, jammed into the shot", one(BENCH, shot="close-up")),
    ("squeeze the teddy into the picture", one(BEAR, shot="close-up")),
    ("the mug stuffed into the whole frame", one(MUG, shot="close-up")),
    ("wedge the toy car into the image", one(CAR, shot="close-up")),
    ("the television, she has to fill all the image", one(TV, shot="close-up")),
    ("the bench; she should fill all the frame", one(BENCH, shot="close-up")),
]

EVERY_PART = [
    # Every part of it seen: all of it, a medium shot.
    ("the bench, every leg in view", one(BENCH, shot="medium")),
    ("toy car with each wheel visible", one(CAR, shot="medium")),
    ("the sofa, all four cushions in frame", one(SOFA, shot="medium")),
    ("teddy, all of his paws in the picture", one(BEAR, shot="medium")),
    ("the TV from the front, every corner showing", one(TV, shot="medium", view="front")),
]

COMPASS = [
    # The frame as a map, north up.
    ("the mug tucked into the north-west corner of the picture", one(MUG, region="upper left")),
    ("bench in the NE quadrant", one(BENCH, region="upper right")),
    ("the sofa sitting in the south west corner", one(SOFA, region="lower left")),
    ("the teddy, southeast corner of the frame", one(BEAR, region="lower right")),
    ("toy car along the north edge of the shot", one(CAR, region="top")),
    ("the TV towards the west side of the frame", one(TV, region="left")),
]


SIZES_MORE = [
    # More size wordings probed on phrasing of no suite.
    ("a snug framing of the mug", one(MUG, shot="close-up")),
    ("zoom right into the bench", one(BENCH, shot="close-up")),
    ("the teddy up close and personal", one(BEAR, shot="close-up")),
    ("the sofa covering most of the picture", one(SOFA, shot="close-up")),
    ("the bench, not cut off anywhere", one(BENCH, shot="medium")),
    ("the TV with nothing cropped", one(TV, shot="medium")),
    ("zoom out a lot on the mug", one(MUG, shot="wide")),
    ("the toy car, leave loads of space around it", one(CAR, shot="wide")),
    ("the mug should be minuscule", one(MUG, shot="wide")),
]

PLACED = [
    # Areas said film-style, noun-first, with the frame's possessive, or after a placing verb.
    ("the mug screen right", one(MUG, region="right")),
    ("bench, left of screen", one(BENCH, region="left")),
    ("the teddy in the image's top-left", one(BEAR, region="upper left")),
    ("toy car in the corner bottom right", one(CAR, region="lower right")),
    ("the sofa tucked bottom-left", one(SOFA, region="lower left")),
    ("TV parked upper right of the frame", one(TV, region="upper right")),
    ("keep the mug central", one(MUG, region="center")),
    ("the bench, dead central", one(BENCH, region="center")),
    ("the mug at the foot of the picture", one(MUG, region="bottom")),
]

LEVEL = [
    # A level horizon said as a builder would.
    ("the bench, horizon plumb", one(BENCH, roll_deg=0.0)),
    ("teddy from behind, keep the horizon dead flat", one(BEAR, view="back", roll_deg=0.0)),
    ("the sofa with a spirit-level horizon", one(SOFA, roll_deg=0.0)),
    ("mug, the horizon kept even", one(MUG, roll_deg=0.0)),
]

SHARES = [
    # A share of the frame said in words, and the verbs that take it.
    ("the mug at roughly 15 per cent of the picture", one(MUG, shot="wide")),
    ("the bench eating up about 80 percent of the frame", one(BENCH, shot="close-up")),
    ("the sofa using up half the frame", one(SOFA, shot="medium")),
]


@pytest.mark.parametrize(
    "text, want", rows(TEMPERED + GRADED + CRAMMED + EVERY_PART + SIZES_MORE + COMPASS + PLACED + LEVEL + SHARES)
)
def test_sizes_and_regions_in_open_wording(text, want):
    assert read(text) == want


def test_a_compass_side_of_an_object_is_no_frame_region():
    """ "The west side of the sofa" places the mug by the sofa, not in the frame: no region, and
    the words stay reported as not understood."""
    parsed = read("the mug on the west side of the sofa")
    assert [s[1] for s in parsed["subjects"]] == [None, None] and parsed["not_understood"] == ["west side"]


def test_a_crammed_corner_stays_a_region():
    """Squeezed into a corner of the frame is a place, not a size."""
    assert read("the mug squeezed into the top-left corner of the frame") == one(MUG, region="upper left")
