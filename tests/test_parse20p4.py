"""The families of phrasing4's misreadings (a development corpus of instructions written blind by
varied personas), after parse20p4:

* a side said after a view that it completes: after the diagonal's end said last ("three quarter
  rear on his right side"), after a broadside or an over-the-shoulder ("over the shoulder, on its
  left side"), as "the left of it" ("front three-quarter on the right of it"), and as its own clause
  after a view said to the camera ("broadside to the lens, on its right side");
* a view said by turning from the front: an explicit angle with "round" or a turn's noun after it
  and the front said as a part ("a quarter turn round from its face towards its right", "forty
  degrees round from the car's grille ..."), a small turn said as a noun ("with a slight twist to its
  left"), an angle said as an aside after the hedge ("swung a bit, say 30 degrees, to its right"),
  a front part pointed at the lens ("aiming its nose at the camera"). As "looking at the camera
  but swung a few degrees to its left" before, the side named is the side the view moves to;
* a half of the frame said as the side of its middle line ("under the halfway line", "left of the
  vertical midline", "above the centre line of the picture"; a bare "centre line" may be the
  subject's, a height) and the middle said both ways ("centred both horizontally and vertically");
* words said by ear: "hi" for "high" beside "up" ("from hi up", "up hi"), "write" for "right"
  after a possessive ("his write hand side"); the camera said as its rig ("cant the whole rig").

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "cushion", "television", "refrigerator"]
parse = parser_of(scene_of(NAMES))


SIDE_AFTER_A_VIEW = [
    ("the toy car, three quarter rear on his right side, close", "back-right"),
    ("sofa: three-quarter front on its right side", "front-right"),
    ("the teddy bear, front three-quarter on the right of him", "front-right"),
    ("the armchair, rear three quarter on the left of it, wide", "back-left"),
    ("the bench, broadside to the lens, on its right side", "right"),
    ("the sofa with its back to the camera, on its right side", "back-right"),
    ("the armchair, over the shoulder, on its left side", "back-left"),
    ("the teddy bear, over-the-shoulder on his right side", "back-right"),
]


@pytest.mark.parametrize(("text", "view"), SIDE_AFTER_A_VIEW)
def test_a_side_said_after_a_view_completes_it(text, view):
    p = parse(text)
    assert p.subjects[0].view == view
    assert not p.not_understood()


@pytest.mark.parametrize(
    ("text", "view", "region"),
    [
        # Keep-probes: a side said alone "on its left side" may be how it lies, not read; "on the
        # left" after a view is the frame's; one object on the left of another is a relation.
        ("the bench, on its left side", None, None),
        ("the toy car, front three-quarter on the left", "three-quarter", "left"),
        ("the sofa from behind, on the left side", "back", "left"),
        ("the toy car on the left of it", None, None),
    ],
)
def test_side_after_view_keep_probes(text, view, region):
    p = parse(text)
    assert (p.subjects[0].view, p.subjects[0].region) == (view, region)


TURNED_FROM_THE_FRONT = [
    ("the sofa, walk a quarter turn round from its front towards its right, wide", "right-exact"),
    ("the armchair, a quarter turn from its face to its left", "left-exact"),
    ("the refrigerator, camera sixty degrees round from its doors, towards its left", "left-slight-front"),
    ("the television, forty degrees round from its screen towards its right", "front-right"),
    ("toy car, 30 degrees round from the nose to its left", "front-slight-left"),
    ("the armchair facing us with a slight twist towards its right", "front-slight-right"),
    ("the sofa facing the camera, with a small turn to its left", "front-slight-left"),
    ("the teddy bear, face to camera but rotated a bit, say 15 degrees, to his left", "front-slight-left"),
    ("the toy car aiming its nose at the lens but swung a little, maybe 25 degrees, toward its own right", "front-slight-right"),
]


@pytest.mark.parametrize(("text", "view"), TURNED_FROM_THE_FRONT)
def test_a_view_said_by_turning_from_the_front(text, view):
    p = parse(text)
    assert p.subjects[0].view == view
    assert not p.not_understood()


@pytest.mark.parametrize(
    ("text", "view"),
    [
        # Keep-probes: these were read so before.
        ("the toy car, 30 degrees from its nose towards its right", "front-slight-right"),
        ("the toy car, move 40 degrees round to its right from the front", "front-right"),
        ("the armchair facing camera, slightly turned to its left", "front-slight-left"),
        ("the toy car, aiming its nose at the camera", "front-exact"),
    ],
)
def test_turned_from_the_front_keep_probes(text, view):
    assert parse(text).subjects[0].view == view


FRAME_MIDLINES = [
    ("the mug, keep it under the halfway line", "bottom"),
    ("the vase sitting beneath the horizontal centre line, close", "bottom"),
    ("the bench above the midline of the picture", "top"),
    ("the teddy bear over the middle line of the image", "top"),
    ("the sofa to the left of the vertical midline", "left"),
    ("the armchair right of the vertical centre line of the frame", "right"),
    ("the cushion, centred both horizontally and vertically", "center"),
    ("the mug, centered top to bottom and left to right", "center"),
]


@pytest.mark.parametrize(("text", "region"), FRAME_MIDLINES)
def test_a_half_of_the_frame_said_by_its_middle_line(text, region):
    p = parser_of(scene_of(NAMES + ["ball"]))(text)
    assert [s.region for s in p.subjects if s.role == "primary"] == [region]
    assert p.elevation is None


@pytest.mark.parametrize(
    ("text", "elevation"),
    [
        # Keep-probes: a centre line of the subject is a height, not the frame's.
        ("the sofa, camera at the center line of the sofa", "eye level"),
        ("the mug in the top half of the frame", None),
    ],
)
def test_frame_midline_keep_probes(text, elevation):
    assert parse(text).elevation == elevation


SAID_BY_EAR = [
    ("the bench from hi up, from behind", "elevation", "high angle"),
    ("the sofa, shot from way hi up", "elevation", "high angle"),
    ("the mug from up hi", "elevation", "high angle"),
    ("the teddy bear, his write hand side, close", "view", "right"),
    ("the toy car, its write flank", "view", "right"),
]


@pytest.mark.parametrize(("text", "field", "value"), SAID_BY_EAR)
def test_high_and_right_said_by_ear(text, field, value):
    p = parse(text)
    got = p.elevation if field == "elevation" else p.subjects[0].view
    assert got == value
    assert not p.not_understood()


def test_a_greeting_hi_stays_a_greeting():
    p = parse("hi, the mug up close please")
    assert p.elevation is None and p.subjects[0].shot == "close-up"


@pytest.mark.parametrize(
    ("text", "roll"),
    [
        ("the teddy bear, cant the whole rig 10 degrees clockwise", 10.0),
        ("the bench, roll the whole rig 15 degrees counter clockwise", -15.0),
        ("the mug, tilt the camera rig 5 degrees to the right", 5.0),
    ],
)
def test_the_camera_said_as_its_rig(text, roll):
    p = parse(text)
    assert p.roll_deg == roll
    assert not p.not_understood()
