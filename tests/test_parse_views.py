"""The rule parser's view sides and azimuths as families (issue #15), on wordings no suite holds:
an offset from a named view (a reference, an amount, a direction, in any order), exactness said
apart from the view, the front turned to the lens, a vehicle's or a boat's side names, and a slip
of a view word where only a view word stands. Angles follow DESIGN §3: azimuth 0 is the
subject's front, +90 its own right, -90 its own left, ±180 behind."""

from __future__ import annotations

import pytest

from capframe.constraints import VIEW_SIDES, arc_deg, view_tolerance_deg
from capframe.errors import InputError
from capframe.scene import SemanticObject
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary, words

OBJECTS = [
    SemanticObject(k, name, [], False)
    for k, name in enumerate(("teddy bear", "mug", "toy car", "sofa", "refrigerator", "armchair"))
]
SCENE = Vocabulary.from_semantics(OBJECTS)


def view_of(text: str) -> str | None:
    """The primary subject's view side, every word understood."""
    parsed = parse_instruction(text, SCENE)
    assert parsed.not_understood() == [], parsed.not_understood()
    return parsed.subjects[0].view


def rows(table):
    return [pytest.param(text, want, id=text) for text, want in table]


# --- a small offset from a named view -----------------------------------------------------------

# Off the front or the back towards a side: the slight side of that end (10-40 degrees off it).
SIDEWAYS_OFFSETS = [
    ("the sofa from behind, a wee bit more to the left", "back-slight-left"),
    ("teddy from the back, shifted a touch to its right", "back-slight-right"),
    ("the mug from behind it, nudged a few degrees over to its left", "back-slight-left"),
    ("the sofa from the rear but slightly to the right side", "back-slight-right"),
    ("the toy car seen from the back, a little to the left hand side", "back-slight-left"),
    ("toy car from behind him, tiny bit more to left", "back-slight-left"),
    ("the bear facing the lens, swung a bit to its right", "front-slight-right"),
    ("mug from the front, rotated a couple of degrees to its left", "front-slight-left"),
    ("the toy car head-on but moved a little to the right", "front-slight-right"),
    ("the sofa from dead ahead, a smidge to its left", "front-slight-left"),
    ("teddy bear gazing into the camera but turned a tad towards its right", "front-slight-right"),
    ("the mug, a couple of degrees to the left", "front-slight-left"),  # no reference: the front
    ("the sofa, back view, slightly off to the right", "back-slight-right"),
    ("the sofa, front view but slightly rotated to its left", "front-slight-left"),
    ("the sofa from the front, angled a bit to its right", "front-slight-right"),
    ("the sofa from just left of the front", "front-slight-left"),
    ("the sofa from just right of behind", "back-slight-right"),
    ("the mug from the rear, little to the right", "back-slight-right"),
    ("the sofa from behind, turn right a bit", "back-slight-right"),
    ("the sofa almost from behind, slightly right", "back-slight-right"),
    ("the sofa from the front, but favouring its left side", "front-slight-left"),
    ("the sofa from the front, cheated slightly to the right", "front-slight-right"),
    ("the mug from behind, but closer to its left", "back-slight-left"),
    ("the mug from behind, more to the right", "back-slight-right"),
    ("the toy car from ahead, a bit to the left", "front-slight-left"),
]
# Off a side towards an end: the slight side of that side towards it.
ENDWARD_OFFSETS = [
    ("the mug from its right, a tad towards the back", "right-slight-back"),
    ("sofa: from the left-hand side, nudged slightly toward the rear", "left-slight-back"),
    ("from the right flank of the sofa, a smidge round to the front", "right-slight-front"),
    ("the armchair, left side but a touch towards the front", "left-slight-front"),
    ("a little toward the back from the sofa's right side", "right-slight-back"),
    ("a few degrees to the front of its left side, the toy car", "left-slight-front"),
    ("the toy car from its starboard flank, a couple of degrees towards the bow", "right-slight-front"),
    ("the sofa slightly off its left side towards the rear", "left-slight-back"),
    ("the sofa from its left side, a bit forward", "left-slight-front"),
    ("the sofa from the right, slightly backwards", "right-slight-back"),
    ("teddy bear from its right side, then a few degrees back towards the front", "right-slight-front"),
    ("the mug from the right, a hair closer to the front", "right-slight-front"),
    ("the mug from its right, more toward the back", "right-slight-back"),
    ("the toy car from its left, slightly toward its tail lights", "left-slight-back"),
    ("the toy car from its right, a touch towards the headlights", "right-slight-front"),
]


@pytest.mark.parametrize("text, view", rows(SIDEWAYS_OFFSETS + ENDWARD_OFFSETS))
def test_a_small_offset_from_a_named_view_is_its_slight_side(text, view):
    assert view_of(text) == view


# Explicit angles, hand-checked: (text, the azimuth meant).
EXPLICIT_OFFSETS = [
    ("the toy car 30 degrees off its nose towards its right", 30.0),
    ("the toy car twenty degrees off the front, toward its left", -20.0),
    ("the toy car, swung 40 degrees round to its left from straight on", -40.0),
    ("the sofa turned fifteen degrees to the right of head on", 15.0),
    ("the bear, 25° to its left of straight-on", -25.0),
    ("toy car, seventy degs round to its right from head-on", 70.0),
    ("the toy car from behind, 30 degrees towards its right", 150.0),
    ("the toy car 20 degrees off its tail towards its left", -160.0),
    ("sofa: 15 degrees to the right of dead behind", 165.0),
    ("the mug from behind, then 90 degrees to its left", -90.0),
    ("the sofa from its left side, twenty degrees towards the back", -110.0),
    ("the fridge from its right flank, rotated 30 deg toward the front", 60.0),
    ("the fridge, 10 degrees towards the front from its right side", 80.0),
    ("the sofa, turned 20° left of centre", -20.0),
    ("the sofa from the back, 20 degrees off-axis to the right", 160.0),
    ("the bear, from twenty-five degrees right of its nose", 25.0),
    ("the fridge, 1/8 of a turn towards the back from its left flank", -135.0),
    ("the sofa, back view offset 10 degrees left", -170.0),
    ("the sofa at an angle of 135 degrees to its right", 135.0),
]


@pytest.mark.parametrize("text, azimuth", rows(EXPLICIT_OFFSETS))
def test_an_explicit_offset_is_the_side_nearest_its_angle(text, azimuth):
    """The side read aims within 12.5 degrees of the angle meant (the sides lie at most 25 apart)
    and accepts it."""
    view = view_of(text)
    (centre,) = VIEW_SIDES[view]
    assert arc_deg(centre, azimuth) <= 12.5
    assert arc_deg(centre, azimuth) <= view_tolerance_deg(view)


def test_a_turn_from_the_back_mirrors_the_same_turn_from_the_front():
    """The sign convention: turning towards the subject's left is negative from either end."""
    front = VIEW_SIDES[view_of("the toy car from the front, 50 degrees to its left")][0]
    back = VIEW_SIDES[view_of("the toy car from behind, 50 degrees to its left")][0]
    assert front < 0 and back < 0
    assert arc_deg(front, -50.0) <= 12.5 and arc_deg(back, -130.0) <= 12.5


def test_a_diagonal_is_no_side_to_offset_from():
    """ "rear-right corner" names the back-right, not its right side; the offset after it names no
    side of its own and is reported."""
    parsed = parse_instruction("the sofa, rear-right corner, nudged a little towards the rear", SCENE)
    assert parsed.subjects[0].view == "back-right" and parsed.not_understood() == ["nudged a little towards the rear"]


def test_an_offset_said_sideways_from_a_side_still_conflicts():
    """From its left, turned towards its right, names no side: refused, not guessed."""
    with pytest.raises(InputError, match="conflicting view"):
        parse_instruction("the bear from the left, 20 degrees to its right", SCENE)


@pytest.mark.parametrize(
    "text", ["the mug a bit to the left", "the mug just to the left", "the mug from behind, but closer to the left edge"]
)
def test_a_slight_side_alone_or_a_part_of_the_frame_is_no_offset(text):
    """Without a reference, a verb of turning or degrees, "a bit to the left" is no view; nor is a
    part of the frame after a view."""
    assert parse_instruction(text, SCENE).subjects[0].view in (None, "back")


# --- exactness said apart from its view ---------------------------------------------------------

EXACT = [
    ("the fridge, rear view, dead on", "back-exact"),
    ("the fridge from behind, precisely", "back-exact"),
    ("the mug from its left side, squarely", "left-exact"),
    ("the toy car from the right, straight on to its flank", "right-exact"),
    ("the car's left side, head on", "left-exact"),
    ("bear from the front, exactly", "front-exact"),
    ("the sofa's back, square on", "back-exact"),
    ("sofa, head-on", "front-exact"),  # alone: the front
    ("the toy car, front-left three quarter, dead on", "front-left"),  # a diagonal stays as it is
    ("the bear from exactly its left", "left-exact"),
    ("the sofa, head on to its back", "back-exact"),
    ("the toy car straight on to its left side", "left-exact"),
]


@pytest.mark.parametrize("text, view", rows(EXACT))
def test_exactness_said_apart_makes_its_end_exact(text, view):
    assert view_of(text) == view


FRONT_TO_LENS = [
    "the toy car nose first towards the camera",
    "the bear face-forward into the lens",
    "sofa, face forwards to the camera",
    "the toy car front-first toward the lens",
    "the mug, head first at the camera",
    "aim dead straight at the television's screen, square on",
]
BACK_TO_LENS = ["the toy car tail-first toward the camera", "the sofa, rear end foremost to the lens"]


@pytest.mark.parametrize("text", FRONT_TO_LENS)
def test_the_front_turned_to_the_lens_is_the_front_exactly(text):
    scene = Vocabulary.from_semantics([*OBJECTS, SemanticObject(9, "television", [], False)])
    parsed = parse_instruction(text, scene)
    assert parsed.not_understood() == [] and parsed.subjects[0].view == "front-exact"


@pytest.mark.parametrize("text", BACK_TO_LENS)
def test_the_back_turned_to_the_lens_first_is_the_back_exactly(text):
    assert view_of(text) == "back-exact"


# --- side names ---------------------------------------------------------------------------------

SIDE_NAMES = [
    ("the toy car from starboard", "right"),
    ("the toy car's starboard side, close", "right"),
    ("toy car, port side, wide", "left"),
    ("the toy car from its port flank", "left"),
    ("the toy car, port-side three-quarter", "front-left"),
    ("the toy car, front three quarter on its starboard side", "front-right"),
    ("the toy car from the stern", "back"),
    ("the toy car seen from aft", "back"),
    ("the toy car from its bow", "front"),
    ("the toy car, starboard bow", "front-right"),
    ("the toy car, from its port bow", "front-left"),
    ("the toy car seen from its nose", "front"),
    ("the toy car from the tail", "back"),
    ("the toy car, rear quarter on its left side", "back-left"),
    ("the toy car's rear left quarter", "back-left"),
    ("the toy car's front quarter on its right", "front-right"),
    ("the sofa's tail-end quarter, left-hand side", "back-left"),
    ("go round the back of the sofa", "back"),
    ("the armchair from around the back", "back"),
    ("swing round to the rear of the toy car", "back"),
]


@pytest.mark.parametrize("text, view", rows(SIDE_NAMES))
def test_side_names_of_vehicles_quarters_and_going_round(text, view):
    assert view_of(text) == view


def test_port_alone_is_no_side():
    """A socket is no side: "port" is the left only before a word naming a side."""
    assert words("its port side") == ["its", "left", "side"]
    assert words("show me the ports") == ["show", "me", "the", "ports"]
    assert "port" in words("the port of the tv")


# --- a slip of a view word where only a view word stands ----------------------------------------

SLIPS = [
    ("the armchair from the font", "front"),
    ("the armchair from the frnt", "front"),
    ("the mug from its rigjt", "right"),
    ("the mug from its lefy side", "left"),
    ("the sofa from the bakc", "back"),
    ("the sofa from the reae", "rear"),
    ("the toy car from its sied", "side"),
]


@pytest.mark.parametrize("text, read", rows(SLIPS))
def test_a_slip_of_a_view_word_after_from_the_is_read_and_reported(text, read):
    parsed = parse_instruction(text, SCENE)
    assert parsed.not_understood() == []
    assert parsed.subjects[0].view is not None
    assert any(c["read"] == read for c in parsed.corrected)


@pytest.mark.parametrize(
    "text, word",
    [
        ("the mug from the bank", "bank"),  # a letter far from the one of "back" on the keyboard: another word
        ("the mug from the light", "light"),
        ("the mug font, from the left", "font"),  # not after "from the": no view word stands there
    ],
)
def test_a_word_that_is_no_slip_stays_not_understood(text, word):
    assert word in " ".join(parse_instruction(text, SCENE).not_understood())


def test_a_slip_near_a_name_of_the_scene_is_no_view_word():
    """ "seat" (an armchair's alias word) is one letter from "reat" as "rear" is: not guessed."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "mug", [], False), SemanticObject(1, "armchair", ["seat"], False)])
    assert parse_instruction("the mug from the reat", scene).subjects[0].view is None


@pytest.mark.parametrize(
    "text, side",
    [
        ("the teddy, left side facing us", "left"),
        ("armchair; back facing the camera", "back"),
        ("sofa, right side to the lens", "right"),
    ],
)
def test_a_side_turned_to_the_camera_needs_no_article_at_a_clause_start(text, side):
    assert view_of(text) == side
