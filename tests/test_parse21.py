"""Subjects and heights of heldout18's and heldout19's remaining misreadings (sixth session):

* an unknown thing asked for after a sentence's opening ("Not sure I'm doing this right... could
  you find the abacus by the green mug") or put beside a known one by a verb of putting ("my
  grandson left his ukulele next to the armchair") is the subject, so refused, naming the closest
  known objects; a thing doing something there ("our postman having his lunch on the bench") is
  still the one named first, and the camera or a hole dug for it is never a subject;
* the subject said to lie right under the camera, or under it at the sentence's end ("lens ninety
  degrees down, the tree right underneath"), is seen from straight above; the camera said to be
  right underneath stays below.

Conventions (DESIGN §3): elevation > 0 is the camera above the subject. None of these wordings is
in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.errors import InputError

NAMES = ["armchair", "mug", "bench", "tree", "toy car", "television"]
parse = parser_of(scene_of(NAMES))

UNKNOWN_THINGS = [
    ("I'm not sure I'm doing this right... could you find the abacus by the green mug and take a photo of it?", "abacus"),
    ("Sorry. Find the hourglass beside the television, close up", "hourglass"),
    ("My grandson left his ukulele next to the armchair - could you get a photo of it?", "ukulele"),
    ("I put the abacus by the mug - photo please", "abacus"),
    ("someone parked a bike by the bench, wide", "bike"),
    ("our postman having his lunch on the bench", "postman having his lunch"),
]


@pytest.mark.parametrize("text,thing", UNKNOWN_THINGS)
def test_an_unknown_thing_asked_for_or_put_beside_a_known_one_is_refused(text, thing):
    with pytest.raises(InputError, match=f"subject '{thing}' is not in this scene"):
        parse(text)


KNOWN_SUBJECTS = [
    ("put the camera by the mug, from the left", "mug"),
    ("the mug I left by the window, from the left", "mug"),
    ("dig a hole under the toy car and shoot it from underground, lens straight up", "toy car"),
    ("Find the mug by the armchair and shoot it from above", "mug"),
]


@pytest.mark.parametrize("text,name", KNOWN_SUBJECTS)
def test_the_camera_a_place_or_a_known_thing_stays_the_subject(text, name):
    assert parse(text).subjects[0].name == name


SUBJECT_UNDER_THE_CAMERA = [
    "the tree right underneath the camera",
    "Treetop from the drone, lens at ninety degrees down, the tree right underneath",
    "the mug directly below the lens",
    "the bench just beneath us",
]


@pytest.mark.parametrize("text", SUBJECT_UNDER_THE_CAMERA)
def test_the_subject_under_the_camera_is_seen_from_straight_above(text):
    low, _ = parse(text).constraints().elevation_range()
    assert low >= 80.0, text


CAMERA_UNDER_THE_SUBJECT = [
    "shoot the tree from right underneath",
    "the mug from directly below",
    "get the mug right underneath, looking up",
]


@pytest.mark.parametrize("text", CAMERA_UNDER_THE_SUBJECT)
def test_the_camera_right_underneath_stays_below(text):
    _, high = parse(text).constraints().elevation_range()
    assert high <= -80.0, text
