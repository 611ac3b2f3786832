"""The families of phrasing5's remaining misreadings (a development phrase bank of view clauses),
after parse18p5: the clock face said around the subject with its front at twelve ("as on a clock
face with its screen at twelve", "imagine the bear in the middle of a clock") and, where a clock is
said, an hour without "o'clock" ("stand at 7", "from half past four", "the view from one"); "on its
six" as pilots say it; a part of it nearest the camera, or looking out (back) at it ("the left arm
nearest us", "the book spines looking out at us", "tail lights of the car toward us"), the camera
beside a side's part ("Beside the right armrest of the chair"), a side named by its parts ("from
its doors-and-handles side") or by who sits there ("the side people sit on"); the camera
perpendicular to a part said on a side ("perpendicular to the doors on its left-hand side"); whose
side is meant ("on HIS left side, not yours", "the right side as the fridge itself would see it",
"the left of whoever sits in it", "from the end on its left"); hundreds said in words ("one
hundred and twenty degrees"); an end and a side seen together
("the front and its left side both in view", "where its nose meets its right flank").

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.translate.vocabulary import words

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "television", "bookshelf", "refrigerator"]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


VIEWS = [
    # A clock face said around it, its front at twelve: an hour needs no "o'clock" then.
    ("the sofa from 4 o'clock (the clock face laid on the floor, the sofa facing 12)", "right-slight-back"),
    ("picture the mug in the middle of a clock face; shoot from 9", "left-exact"),
    ("the vase from half past four on a clock face, its front at 12", "back-right"),
    ("the toy car's bonnet at 12 on a clock; the camera at 3", "right-exact"),
    ("the teddy bear from a quarter past 1, as on a clock", "front-right"),
    ("the bench at a quarter to 6, clock style", "back-exact"),
    ("imagine the armchair is the centre of a clock, facing twelve. Go to 10.", "left-slight-front"),
    ("think of a clock round the television with its screen at twelve; I want the view from one", "front-slight-right"),
    # "On its six", as pilots say it.
    ("keep the mug on its six", "back-exact"),
    ("the teddy bear, from his six", "back-exact"),
    # A part nearest the camera, or looking out (back) at it; a part "of" the subject.
    ("the armchair, its left arm nearest us", "left"),
    ("a three-quarter of the sofa from the front, the right arm closest to the camera", "front-right"),
    ("the armchair with its backrest the one nearest the camera", "back"),
    ("the bookcase, books facing out toward the camera", "front"),
    ("the bookshelf with the book spines looking out at the lens", "front"),
    ("the armchair, its seat cushions staring right back at us", "front"),
    ("headlights of the toy car toward the lens, cheated a touch to its right", "front-slight-right"),
    ("tail lights of the toy car to camera, cheated a little to its left", "back-slight-left"),
    # The camera beside a side's part, said first; the side (end) named by its parts; the side
    # one sits on.
    ("Next to the left armrest of the sofa, camera low", "left"),
    ("camera right by its right flank, the toy car", "right"),
    ("the refrigerator from its drawers & buttons side", "front"),
    ("the toy car from the headlights end", "front"),
    ("the bench from the side people would sit on", "front"),
    ("the sofa from the side you'd sit on", "front"),
    # Perpendicular (square) to a part said on a side: that side, exactly.
    ("the refrigerator, camera exactly perpendicular to the panel on its right side", "right-exact"),
    ("the sofa: camera square to the cushions along its left-hand side", "left-exact"),
    ("the television, dead square to its front", "front-exact"),
    # Whose side is meant: its own against the camera's, as it would see it, of one sitting in it.
    ("the teddy bear on HIS right side, not yours", "right"),
    ("the mug, its left, mind, not the camera's left", "left"),
    ("the toy car, its right-hand side as the car itself would know it", "right"),
    ("the armchair from its left, the left of someone sitting in it", "left"),
    ("the bench from the end on its right", "right"),
    ("the sofa from the side on its left, the left of whoever sits on it", "left"),
    # An end and a side seen together: their diagonal.
    ("the refrigerator with the front and its right side both in view", "front-right"),
    ("the refrigerator at an angle so we get the doors plus its left side", "front-left"),
    ("the sofa so its right arm and the backrest both show", "back-right"),
    ("get the seat plus the left side of the armchair in one shot", "front-left"),
    ("the teddy bear, his back and his right side", "back-right"),
    ("the bookshelf's shelves together with its right-hand end", "front-right"),
    ("the toy car from where its nose meets its left flank", "front-left"),
    ("aim at the spot where the toy car's tail meets its right side", "back-right"),
]


@pytest.mark.parametrize(("text", "view"), VIEWS)
def test_views(text, view):
    p = parse(text)
    assert p.subjects[0].view == view


@pytest.mark.parametrize(
    ("text", "view"),
    [
        # Keep-probes: an hour with no clock said is no direction; "clockwise" is no clock; a clock
        # face is no "face on"; a clock put otherwise than front at twelve stays unread.
        ("the bench from 5", None),
        ("the mug at 7", None),
        ("the vase, roll 7 degrees clockwise, from 3", None),
        ("the bench at 3 o'clock", "right-exact"),
        ("the mug from the front, 6 of them in a row", "front"),
        ("the sofa, its left arm facing us", "left"),
        ("the armchair, its seat to us", "front"),
        ("the bookshelf, focus on the books", None),
        ("the armchair from the front, the vase nearest the camera", "front"),
        # Beside a part after a subject relates two things; no side of the other.
        ("the vase next to the left arm of the sofa", None),
        # A side said as a relation stays unread; the frame's left is no side of it.
        ("the teddy bear on his left side", None),
        ("the front of the mug and the left of the frame", "front"),
    ],
)
def test_view_keep_probes(text, view):
    assert parse(text).subjects[0].view == view


def test_a_clock_put_otherwise_stays_unread():
    p = parse("the mug on a clock face with its handle at 12, from 3 o'clock")
    assert p.not_understood()


def test_a_clock_setup_is_understood_and_no_face_on():
    p = parse("the teddy bear at 8 o'clock (clock face on the floor, he is looking at 12)")
    assert p.subjects[0].view == "left-slight-back" and p.understood == "fully"


@pytest.mark.parametrize(
    ("text", "said"),
    [
        # Hundreds said in words: the degrees of a long walk round ("one hundred and twenty").
        ("one hundred and twenty degrees", ["120", "degrees"]),
        ("a hundred and five degrees", ["105", "degrees"]),
        ("two hundred degrees", ["200", "degrees"]),
        ("a hundred times", ["100", "times"]),
        ("the one on the left", ["the", "one", "on", "the", "left"]),
    ],
)
def test_hundreds_in_words(text, said):
    assert words(text) == said


def test_a_long_walk_round_in_words():
    p = parse("the sofa from the front, then a hundred and fifty degrees round to its right")
    assert p.subjects[0].view == "back-slight-right"
