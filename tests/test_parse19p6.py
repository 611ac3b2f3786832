"""parse19p6: the families of phrasing6's misreadings left by parse18p6, and the parser's build.

Families: a corner said with up or high ("the mug up top left", "low and to the right, in the
frame's corner", "in the corner up there on the left"); parts of one end said together
("grille and headlights filling the picture": the front) and the face as all that is wanted
("just the face": the front).

Build: a roll's direction said round about ("in the clockwise sense", "the anticlockwise way", "to
the counter-clockwise side", ", going clockwise") is read by the word pipeline as the direction
alone, not in every roll template; each template is parsed by ``re`` once, its tree giving both
the strings a match needs and the compiled pattern.

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import re

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.translate.parse import _compiled, _expand, _pattern_tree
from capframe.translate.vocabulary import words

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "cushion", "ball", "tree", "bookshelf"]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("tilt it 9 degrees in the anti-clockwise sense", "tilt it 9 degrees counterclockwise"),
        ("roll, turning clockwise, by 5 degrees", "roll clockwise , by 5 degrees"),
        ("a counter clockwise direction roll", "a counterclockwise roll"),
        ("rotate the lens toward the clockwise side", "rotate the lens clockwise"),
        # No direction of turning: the words stay.
        ("in the way of the sofa", "in the way of the sofa"),
    ],
)
def test_a_direction_said_round_about_is_the_direction(text, said):
    assert " ".join(words(text)) == said


@pytest.mark.parametrize(
    ("text", "roll"),
    [
        ("the vase, camera rolled 14 degrees in a counter-clockwise fashion", -14.0),
        ("the mug; cant the camera the clockwise way by 6 degrees", 6.0),
        ("bench, 11 degrees of roll, heading anticlockwise", -11.0),
    ],
)
def test_a_roll_whose_direction_is_said_round_about(text, roll):
    assert parse(text).roll_deg == roll


@pytest.mark.parametrize(
    "template",
    [
        "(?:from )?(?:the )?left side(?: of)?",
        "(?P<d>\\d+) degrees (?P<dir>clockwise|counterclockwise)",
        "(a |an )?{d} {dir} roll",
    ],
)
def test_a_pattern_compiled_from_its_tree_matches_as_its_source(template):
    source = _expand(template)
    ours, theirs = _compiled(_pattern_tree(source)), re.compile(source)
    text = " a 12 degrees clockwise roll from the left side of 7 degrees counterclockwise "
    assert [m.span() for m in ours.finditer(text)] == [m.span() for m in theirs.finditer(text)]
    assert ours.groupindex == theirs.groupindex


CORNERS = [
    # "Up top" before a side.
    ("the mug up top left", "upper left"),
    ("vase up top right, please", "upper right"),
    ("put the bench down bottom left", "lower left"),
    ("the cushion up at the top left", "upper left"),
    ("the teddy bear up top, left side of the picture", "upper left"),
    # Up and to a side, then the picture's corner.
    ("the vase low and to the right, in the frame's corner", "lower right"),
    ("put the mug high and to the right, in the corner of the picture", "upper right"),
    ("the cushion up and to the left, in the image's corner up there", "upper left"),
    # The height pointed at.
    ("the mug in the corner up there on the left", "upper left"),
    ("the ball in the corner down there to the right", "lower right"),
]


@pytest.mark.parametrize(("text", "region"), CORNERS)
def test_a_corner_said_with_up_or_high(text, region):
    p = parse(text)
    assert p.subjects[0].region == region, p.not_understood()
    assert p.elevation is None


@pytest.mark.parametrize(
    ("text", "elevation"),
    [
        # Keep-probes: "from up top" is the camera's height; high and to a side alone is no corner.
        ("shoot the mug from up top", "high angle"),
        ("the mug, shot from up top", "high angle"),
        ("the teddy bear high and to the left", None),
        ("the vase in the top left corner", None),
    ],
)
def test_up_top_as_a_height_stays(text, elevation):
    p = parse(text)
    assert p.elevation == elevation
    assert p.subjects[0].region in (None, "upper left")
    assert ("top left" in text) == (p.subjects[0].region == "upper left")


@pytest.mark.parametrize(
    ("text", "view"),
    [
        ("the toy car, grille and headlights filling the picture", "front"),
        ("a macro of the toy car: the headlights, the grille and the windscreen", "front"),
        ("toy car close-up; windscreen and front bumper fill everything", "front"),
        ("a tight shot of the teddy bear, just the face", "front"),
        ("the teddy bear in close-up, nothing but the face", "front"),
        # Keep-probes: one part as before; a face of something else names no side.
        ("the toy car, its headlights filling the frame", "front"),
        ("the mug, only the face of the clock", None),
    ],
)
def test_parts_of_one_end_said_together(text, view):
    assert parse(text).subjects[0].view == view
