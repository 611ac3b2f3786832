"""Subjects and heights of heldout18's and heldout19's remaining misreadings (sixth session):

* an unknown thing asked for after a sentence's opening ("Not sure I'm doing this right... could
  you find the abacus by the green mug") or put beside a known one by a verb of putting ("my
  grandson left his ukulele next to the armchair") is the subject, so refused, naming the closest
  known objects; a thing doing something there ("our postman having his lunch on the bench") is
  still the one named first, and the camera or a hole dug for it is never a subject;
* one end of the subject denied ("anything but the front", "not from behind", "no shots of its
  back", "I don't want the front of the TV, I want its back") leaves every azimuth outside that
  end's tolerance; two denied ends ask nothing;
* a roll said as a turn about the lens's axis or of "the rig" ("turned on its lens axis 25° in the
  clockwise sense"), a frame kept level (roll 0, but "the frame level with the table" is a height);
* a side's aspect or elevation ("posterior aspect", "side elevation (left)"), the reverse side, a
  right angle to a side's part; clock hours on a dial ("one o'clock", "four on the dial", "his
  face is twelve"); a hedge ("give or take a few"); the height of a lamp's shade;
* the subject said to lie right under the camera, or under it at the sentence's end ("lens ninety
  degrees down, the tree right underneath"), is seen from straight above; the camera said to be
  right underneath stays below.

Conventions (DESIGN §3): elevation > 0 is the camera above the subject. None of these wordings is
in a suite file."""

from __future__ import annotations

import numpy as np
import pytest
from _parse_helpers import parser_of, scene_of

from capframe.constraints import VIEW_SIDES, arc_deg, view_tolerance_deg
from capframe.errors import InputError

NAMES = ["armchair", "mug", "bench", "tree", "toy car", "television"]
parse = parser_of(scene_of(NAMES))
parse_lamp = parser_of(scene_of(["floor lamp", "sofa"]))

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


NEGATED_VIEWS = [
    ("Armchair: anything but the front. Low angle. Close-up.", "not-front"),
    ("the armchair from any side except behind", "not-back"),
    ("the toy car, any angle other than its left", "not-left"),
    ("Not from behind, please; anywhere else round the car is fine.", "not-back"),
    ("Don't show me the car's front; high angle; car in the upper right; small.", "not-front"),
    ("Whatever you do with the armchair, no shots of its back: high up", "not-back"),
    ("I don't want the front of the TV, I want its back.", "back"),
    ("the armchair from its left, anything but the back", "left"),
]


@pytest.mark.parametrize("text,view", NEGATED_VIEWS)
def test_one_end_denied_leaves_every_other_way_round(text, view):
    assert parse(text).subjects[0].view == view


def test_two_ends_denied_ask_no_view():
    """Two denials would each leave the other's end: nothing is asked, and nothing conflicts."""
    p = parse("the armchair, not from the front, not from behind")
    assert p.subjects[0].view is None
    assert p.not_understood()


@pytest.mark.parametrize("end,azimuth", [("front", 0.0), ("back", 180.0), ("left", -90.0), ("right", 90.0)])
def test_a_denied_end_accepts_exactly_the_azimuths_its_end_does_not(end, azimuth):
    denied = f"not-{end}"
    for a in np.arange(-180.0, 180.0, 2.5):
        accepted = arc_deg(a, VIEW_SIDES[denied][0]) <= view_tolerance_deg(denied)
        assert accepted == (arc_deg(a, azimuth) >= view_tolerance_deg(end)), (end, a)


ROLLS = [
    ("the armchair, rear-left angle, and tip the rig ten degrees to clockwise", 10.0),
    ("Mug hugging the left of the shot; the whole camera turned on its lens axis 25° in the clockwise sense", 25.0),
    ("back of the telly, directly behind it, frame kept level", 0.0),
    ("the mug, the picture stays straight", 0.0),
]


@pytest.mark.parametrize("text,roll", ROLLS)
def test_a_turn_about_the_lens_axis_or_a_level_frame_is_a_roll(text, roll):
    assert parse(text).roll_deg == roll


def test_a_frame_level_with_a_thing_is_a_height_not_a_roll():
    p = parse("the mug, the frame is level with the table")
    assert p.roll_deg is None and p.elevation == "eye level"


ASPECTS = [
    ("Posterior aspect of the toy car, please.", "back"),
    ("the television, reverse side, from 45 degrees up", "back"),
    ("Toy car, exhibit C: rear aspect, squarely, no angle.", "back-exact"),
    ("Armchair, left lateral aspect, close", "left"),
    ("Armchair, side elevation (left), full piece in shot", "left"),
    ("the armchair, front elevation", "front-exact"),  # architecture's elevation: square on
    ("car: line the lens up at a perfect right angle to its left-hand doors", "left-exact"),
]


@pytest.mark.parametrize("text,view", ASPECTS)
def test_aspects_elevations_and_right_angles_name_a_side(text, view):
    assert parse(text).subjects[0].view == view


CLOCKS = [
    ("Armchair faces twelve. Camera at its one o'clock, high angle.", 30.0),
    ("If the armchair's seat points at noon, I'd like the camera sitting at about four on the dial", 120.0),
    ("Toy car at seven o'clock (its nose is twelve), low, looking up.", -150.0),
]


@pytest.mark.parametrize("text,azimuth", CLOCKS)
def test_clock_hours_round_the_subject_name_the_nearest_side(text, azimuth):
    """The subject's front at twelve, the hours clockwise seen from above: three is its right."""
    view = parse(text).subjects[0].view
    assert arc_deg(VIEW_SIDES[view][0], azimuth) <= view_tolerance_deg(view), view


def test_a_hedge_on_degrees_names_nothing():
    p = parse("the television: walk about twenty-five degrees off its face toward its own right-hand end, give or take a few")
    assert p.subjects[0].view == "front-slight-right" and not p.not_understood()


def test_the_shade_is_a_lamp_height_and_a_shade_a_degree():
    assert parse_lamp("Lamp: centre frame, camera at the height of the shade").elevation == "eye level"
    assert parse_lamp("the lamp, a shade higher than eye level").elevation == "slightly above"


def test_a_thing_doing_something_by_a_known_one_is_named_by_its_own_head():
    """The head of "the gardener raking leaves" is the gardener, not the leaves (a plant's part)."""
    with pytest.raises(InputError, match="subject 'gardener raking leaves' is not in this scene"):
        parse("the gardener raking leaves by the tree")
    assert parse("the light falling on the bench from the left").subjects[0].name == "bench"


def test_another_first_letter_writes_another_word_not_a_misspelling():
    """A sofa called a "three-seater" is no heater; a swap, a doubled or a dropped letter still is."""
    scene = parser_of(scene_of(["three seater", "television"]))
    with pytest.raises(InputError, match="subject 'space heater' is not in this scene"):
        scene("There should be a space heater next to the three seater; photograph the heater from the front please")
    assert scene("the three saeter from the front").subjects[0].name == "three seater"
    assert scene("the televison from the front").subjects[0].name == "television"
