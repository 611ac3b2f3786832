"""The view families of phrasing3's and heldout16's misreadings, read when they became development
sets: view words misspelt ("reer", "raer", "bakc") and "3-quarter" written with a digit (or
"three-qarter"); "-ish" after a diagonal ("front-right-ish"); "three-quarter rear on the left";
looking or pointing at a camera said without its article ("looking to camera"); a part named by
its side turned to the camera ("right armrest end pointed dead at the lens", "its right-hand
doors square to camera"), and "from that end" naming no thing; the camera square or perpendicular
to a side or a part's face ("perpendicular to the shelves' face", "to its flank"); the side with
an end's part turned to us ("the side with the door handle toward us"); the view someone standing
there would get ("the view a walker behind it would get"); "proper right" / "proper left" (the
object's own side, as museums say it); a side view moved a little towards an end, said with a
view noun, a cheat or the place ("left end view but cheat it a little toward the front", "from
the right side, drifting a bit behind him"); from over its backrest (with a side: that back
diagonal).

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.translate.vocabulary import words

NAMES = [
    "armchair",
    "sofa",
    "mug",
    "teddy bear",
    "bench",
    "toy car",
    "vase",
    "ball",
    "bookshelf",
    "refrigerator",
    "television",
]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


def view(text: str) -> str | None:
    return parse(text).subjects[0].view


VIEWS = [
    # A view word spelt by ear ("reer") or mistyped by a swap ("raer", "bakc", "sdie"), anywhere.
    ("the mug shot from the reer, eye level", "back"),
    ("bench, reer view, wide", "back"),
    ("the vase, raer left three quarter", "back-left"),
    ("the sofa seen from the bakc", "back"),
    ("toy car, from the sdie, close", "side"),
    # "Three-quarter" with a digit ("3-quarter") or its noun mistyped ("three-qarter").
    ("the bench at a rear 3-quarter angle", "back-three-quarter"),
    ("the armchair, 3 quarter view from the left", "front-left"),
    ("bear, back left three-qarter", "back-left"),
    ("the mug from a 3-quarters front right angle", "front-right"),
    # "-ish" after a diagonal hedges the diagonal, it is no slight side.
    ("the sofa, front-left-ish", "front-left"),
    ("teddy bear from the rear right-ish, low", "back-right"),
    ("the mug, back-left-ish view", "back-left"),
    # "Three-quarter rear" in either order, its side said as a place after it.
    ("the sofa, three quarter rear on its right", "back-right"),
    ("bench: 3/4 back on the left side", "back-left"),
    ("the armchair three-quarter rear view on the right", "back-right"),
    # Looking or pointing at a camera said without its article.
    ("the teddy bear, looking to camera", "front"),
    ("the bear is looking at camera, medium shot", "front"),
    ("the toy car, nose pointed at lens", "front"),
    ("the toy car driving towards camera", "front"),
    # A part named by its side turned to the camera: that side (exactly with an exact word).
    ("the sofa with the left armrest turned to us", "left"),
    ("the toy car, its right wheels facing the lens", "right"),
    ("right arm of the armchair pointing at the camera", "right"),
    ("the armchair, left armrest end aimed straight at camera", "left-exact"),
    ("the toy car with its left-hand doors dead square to the lens", "left-exact"),
    ("the bench, its right side square to camera", "right-exact"),
    # Square or perpendicular to a side, or to a part's face: that side, exactly.
    ("the bookshelf, lens perpendicular to its face", "front-exact"),
    ("the television, shot square to the screen's face", "front-exact"),
    ("the sofa, camera perpendicular to its back", "back-exact"),
    ("the toy car perpendicular to its right side, low", "right-exact"),
    ("the armchair, square to its flank", "side"),
    ("the refrigerator in left profile, square to its flank", "left"),
    ("the refrigerator, directly from the left, camera perpendicular to its flank", "left-exact"),
    # The side (end) with an end's part turned to us: that end.
    ("the refrigerator, the side with the door handles facing the lens", "front"),
    ("the bench, the side with the backrest towards me", "back"),
    ("toy car - the end with the headlights to camera", "front"),
    # The view someone standing there would get.
    ("the sofa: the view a dog behind it would have", "back"),
    ("the armchair, what a visitor standing in front of it would see", "front"),
    ("the mug, the angle someone to its left would get", "left"),
    ("teddy bear, the view a child right behind him gets", "back"),
    # "Proper right" / "proper left": the object's own side.
    ("the vase, proper left side", "left"),
    ("the bench from the proper right", "right"),
    ("the armchair's proper left, eye level", "left"),
    ("View - proper right. Sofa, wide.", "right"),
    # A side view moved a little towards an end: with a view noun, a cheat, or the place said.
    ("the sofa, right end view but cheat it slightly toward the back", "right-slight-back"),
    ("armchair, left side view, a touch towards the front", "left-slight-front"),
    ("the mug from its right, cheated a little forward", "right-slight-front"),
    ("the vase from the left side, edging a bit behind it", "left-slight-back"),
    ("teddy bear from his right, a touch in front of him", "right-slight-front"),
    # From over its backrest (or back): from behind; with a side, that back diagonal.
    ("the armchair, shot from over its backrest", "back"),
    ("the bench, from over its back rest on the right", "back-right"),
    ("the sofa, peering over the back of it to the left", "back-left"),
]


@pytest.mark.parametrize(("text", "side"), VIEWS)
def test_views(text, side):
    assert view(text) == side


@pytest.mark.parametrize(
    ("text", "side", "region"),
    [
        # Keep-probes: a side after a comma stays the frame's; "-ish" after a lone side or a
        # height is a slight degree; behind a named object is a relation; a throw over the back
        # is no view; its door to us is its front; the frame's left stays a region.
        ("the toy car, three quarter rear, on the left", "back-three-quarter", "left"),
        ("the mug leftish in the frame", None, "left"),
        ("the teddy bear from the left, a bit behind the vase", "left", None),
        ("the armchair with a blanket over the back of it", None, None),
        ("the refrigerator, its door toward us", "front", None),
        ("the sofa, camera square to the left of the frame", None, "left"),
        ("the bench with the vase behind it", None, None),
        ("the sofa with its left arm facing the camera", "left", None),
        ("the mug from the front, a bit left of centre", "front", "left"),
    ],
)
def test_view_keep_probes(text, side, region):
    s = parse(text).subjects[0]
    assert (s.view, s.region) == (side, region)


def test_high_ish_stays_slightly_above():
    assert parse("the vase, high-ish").elevation == "slightly above"


def test_three_quarters_of_the_frame_is_the_same_share_with_a_digit():
    assert (
        parse("the mug filling 3 quarters of the frame").subjects[0].shot
        == parse("the mug filling three quarters of the frame").subjects[0].shot
    )
    assert words("a rear 3-quarter angle") == words("a rear three-quarter angle")


def test_a_proper_right_angle_is_no_side_word():
    assert words("at a proper right angle") == ["at", "a", "proper", "right", "angle"]


@pytest.mark.parametrize(
    "text", ["the bench, shoot it from that end", "right armrest of the sofa facing us, shoot it from that end"]
)
def test_that_end_is_no_subject(text):
    p = parse(text)
    assert [s.name for s in p.subjects] == [NAMES[4] if "bench" in text else "sofa"]
    assert "end" in p.not_understood()
