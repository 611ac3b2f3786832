"""The families of phrasing5's misreadings (a development phrase bank of view clauses): a slight
word after "just" ("just a wee bit right of front-on"); degrees "further" past a side;
a move off a view towards a side with no amount (that view's diagonal) or with its degrees said
after it; where one starts ("begin behind the bench") or goes round behind it first; a diagonal's
side after "quarter" ("rear quarter left"), glued to its end ("backright") or as a letter ("his
L", "R. profile"); "at an angle" said with an end, and any corner of that end, as its
three-quarter; the subject made to face the camera, and an end of it as what we see.

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "cushion", "ball", "bookshelf"]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


VIEWS = [
    # "Just" before an article-led slight word.
    ("the bookshelf from just a tiny bit left of front-on", "front-slight-left"),
    ("the mug from just a little bit to its right", "front-slight-right"),
    ("teddy bear from the front, just a wee bit to his left", "front-slight-left"),
    # Degrees further (farther) past a side.
    ("the sofa from its left side, then 20 degrees further towards the front", "left-slight-front"),
    ("the armchair from its right, 30 degrees farther toward its back", "right-slight-back"),
    ("the car from the front, swung 25 degrees further to its left", "front-slight-left"),
    # A move off a view towards a side, no amount: that view's diagonal.
    ("the sofa from behind, then ease over to its left", "back-left"),
    ("the bench from the rear, edging out toward its left-hand end", "back-left"),
    ("the mug from behind it, swung off to its right", "back-right"),
    ("the toy car from the front, then drifting round to its right side", "front-right"),
    ("teddy bear from behind, and then move toward his left", "back-left"),
    # ... with an amount it stays the slight side ("ease" a verb of moving too).
    ("the vase from behind it, then ease slightly to the left", "back-slight-left"),
    # The degrees said after the move.
    ("the mug from the front, turned to its left by about 30 degrees", "front-slight-left"),
    ("the sofa from behind, swing round to its right, roughly 20 degrees", "back-slight-right"),
    ("the teddy bear, rotated toward his right, 60 degrees", "right-slight-front"),
    # Where one starts, or round behind it said first.
    ("start behind the bench and go 40 degrees toward its left", "back-left"),
    ("Begin behind the armchair, then walk 30 degrees round to its right", "back-slight-right"),
    ("round behind the sofa, then 30 degrees to its right", "back-slight-right"),
    # A diagonal's side after "quarter", glued to its end, or as a letter.
    ("the mug, rear quarter left", "back-left"),
    ("bench: quarter rear right", "back-right"),
    ("the vase, front quarter right", "front-right"),
    ("teddy bear: backleft", "back-left"),
    ("sofa - frontright, wide", "front-right"),
    ("toy car: rearright", "back-right"),
    ("MUG - FRONT QTR - ITS R", "front-right"),
    ("ARMCHAIR / 3/4 FRONT / ITS L", "front-left"),
    ("sofa / L. side", "left"),
    ("BENCH. R. PROFILE. WIDE.", "right"),
    # "At an angle" said with an end: its three-quarter, the side left open.
    ("the mug at an angle from behind", "back-three-quarter"),
    ("the sofa from the back, at an angle", "back-three-quarter"),
    ("the teddy bear seen from behind at an angle, any side", "back-three-quarter"),
    ("the armchair from the front, at an angle", "three-quarter"),
    # ... a side said with it completes it.
    ("the sofa from the back at an angle on its left", "back-left"),
    # Any corner of an end.
    ("go to either rear corner of the bench", "back-three-quarter"),
    ("the toy car from whichever front corner you like", "three-quarter"),
    # The subject made to face the camera; an end of it as what we see.
    ("please let the teddy bear face the camera", "front"),
    ("have the mug face the lens, tight", "front"),
    ("make the toy car face us", "front"),
    ("the teddy bear, so that his face is what we see", "front"),
    ("the armchair so that its backrest is all we see", "back"),
    ("the toy car, its rear bumper is what you get", "back"),
]


@pytest.mark.parametrize(("text", "view"), VIEWS)
def test_views(text, view):
    assert parse(text).subjects[0].view == view


@pytest.mark.parametrize(
    ("text", "view"),
    [
        # Keep-probes: a lone "at an angle" says no side; a lone letter is no side; a move said
        # with no view before it is no side; an explicit angle stays as it was.
        ("the vase at an angle", None),
        ("the mug, size L", None),
        ("the R key of the vase", None),
        ("the mug, move to the left", None),
        ("the car from behind, at an angle of 30 degrees to its left", "back-slight-left"),
        ("the bear from its right, then 30 degrees toward its back", "right-slight-back"),
        ("the mug, rear three-quarter right", "back-right"),
        ("the bench from the rear, edging slightly toward its right end", "back-slight-right"),
        ("the teddy bear with a happy face", None),
        ("the sofa from the front, the vase to its left", "front"),
    ],
)
def test_view_keep_probes(text, view):
    assert parse(text).subjects[0].view == view


def test_a_move_after_a_view_with_its_degrees_is_an_azimuth():
    p = parse("Front of the mug but swung off to its right, maybe 25 degrees?")
    assert p.subjects[0].view == "front-slight-right" and p.understood == "fully"


def test_a_region_said_after_a_move_word_stays_a_region():
    p = parse("the mug to the right, 30 degrees above")
    assert (p.subjects[0].region, p.subjects[0].view, p.elevation_deg) == ("right", None, 30.0)
