"""View sides, frame regions and shot sizes in open wording (issue #15), as families tested on
wordings no suite holds: an architect's elevation, "square to it", the view's noun before its side,
"lateral", looking down the lens; a corner as a height, a side and a corner noun in any order
(or a height and a side said apart); the middle and the thirds said otherwise; intensifiers
repeated, a size that fills everything, a small element of a larger whole, "wide on X". Angles
follow DESIGN §3: azimuth 0 is the subject's front, +90 its own right, -90 its own left."""

from __future__ import annotations

import pytest
from test_parse_generalise import BEAR, BENCH, CAR, MUG, SOFA, TV, one, read, rows

from capframe.errors import InputError

ELEVATIONS_AND_SQUARE = [
    # An architect's elevation is the side drawn square on: an end is exact (±15 degrees).
    ("Sofa: front elevation", one(SOFA, view="front-exact")),
    ("the mug, frontal elevation, whole thing", one(MUG, shot="medium", view="front-exact")),
    ("REAR ELEVATION - TELEVISION", one(TV, view="back-exact")),
    ("the bench: back elevation", one(BENCH, view="back-exact")),
    ("left elevation of the toy car", one(CAR, view="left-exact")),
    ("the teddy bear, right side elevation", one(BEAR, view="right-exact")),
    ("bench side elevation", one(BENCH, view="side")),
    ("sofa: elevation from the front", one(SOFA, view="front-exact")),
    ("the mug, the elevation of its left side", one(MUG, view="left-exact")),
    # Square to the subject: its front, exactly.
    ("the sofa, perfectly square to it", one(SOFA, view="front-exact")),
    ("shoot the bench square to it", one(BENCH, view="front-exact")),
    ("toy car - dead square to the car", one(CAR, view="front-exact")),
    ("Photograph the television exactly square to it please", one(TV, view="front-exact")),
]

NOUN_FIRST_AND_LATERAL = [
    # The view's noun before its side, as a caption writes it.
    ("THE BENCH, PROFILE RIGHT, FULL SHOT", one(BENCH, shot="medium", view="right")),
    ("teddy bear profile left", one(BEAR, view="left")),
    ("the mug, profile: left", one(MUG, view="left")),
    ("sofa, view right", one(SOFA, view="right")),
    ("side view left, the toy car", one(CAR, view="left")),
    ("the television - side view, right", one(TV, view="right")),
    # "Lateral" is the side, before or after the side named.
    ("Teddy bear: left lateral view", one(BEAR, view="left")),
    ("the sofa, right lateral view", one(SOFA, view="right")),
    ("bench, lateral view from the left", one(BENCH, view="left")),
    ("mug, lateral view", one(MUG, view="side")),
    ("the toy car, lateral right", one(CAR, view="right")),
    ("sofa, left-lateral", one(SOFA, view="left")),
    ("LATERAL VIEW, RIGHT - BENCH", one(BENCH, view="right")),
    ("toy car, right-side lateral view", one(CAR, view="right")),
    ("teddy bear, profile to the right", one(BEAR, view="right")),
    ("SIDE VIEW (LEFT) OF THE SOFA", one(SOFA, view="left")),
    ("teddy bear, view front-left", one(BEAR, view="front-left")),
    ("the sofa, angle: rear right", one(SOFA, view="back-right")),
]

DOWN_THE_LENS = [
    # Looking down the lens is facing the camera squarely; "right" there is no side.
    ("the teddy looking down the lens", one(BEAR, view="front-exact")),
    ("teddy bear staring straight down the lens", one(BEAR, view="front-exact")),
    ("the bear gazing down the barrel of the lens", one(BEAR, view="front-exact")),
    ("toy car pointing right down the lens", one(CAR, view="front-exact")),
    ("the teddy peering directly down the camera, close", one(BEAR, shot="close-up", view="front-exact")),
    ("the teddy bear gazing right into the lens", one(BEAR, view="front-exact")),
    ("teddy bear, looking right at us", one(BEAR, view="front-exact")),
]

CORNERS = [
    # A height, a side and a corner noun in any order, with any glue words.
    ("the mug is in the right upper corner", one(MUG, region="upper right")),
    ("MUG IN THE LEFT LOWER CORNER", one(MUG, region="lower left")),
    ("the sofa in the upper corner on the left", one(SOFA, region="upper left")),
    ("toy car in the top corner on the right hand side", one(CAR, region="upper right")),
    ("the mug in the left corner at the bottom of the picture", one(MUG, region="lower left")),
    ("the bench in the corner at the top, on the right", one(BENCH, region="upper right")),
    ("mug in the corner, bottom right", one(MUG, region="lower right")),
    ("the teddy in the lower corner to the right", one(BEAR, region="lower right")),
    ("the television in the right bottom quadrant", one(TV, region="lower right")),
    ("mug in the right lower quarter of the picture", one(MUG, region="lower right")),
    ("put the sofa right up in the top left", one(SOFA, region="upper left")),
    ("the toy car in the right-hand top corner", one(CAR, region="upper right")),
    # A height and a side said apart join into the corner between them.
    ("the mug at the bottom, on the left", one(MUG, region="lower left")),
    ("teddy bear on the right, up at the top of the frame", one(BEAR, region="upper right")),
    ("the bench at the bottom, in the right-hand corner", one(BENCH, region="lower right")),
    ("the sofa in the bottom half, right side of the picture", one(SOFA, region="lower right")),
]

MIDDLES_AND_THIRDS = [
    ("the mug in the dead middle", one(MUG, region="center")),
    ("the bench mid frame", one(BENCH, region="center")),
    ("toy car midframe", one(CAR, region="center")),
    ("the teddy slap bang in the middle", one(BEAR, region="center")),
    ("sofa placed on the left vertical third", one(SOFA, region="left third")),
    ("the mug along the right-hand vertical third", one(MUG, region="right third")),
    ("bench on the right vertical third line", one(BENCH, region="right third")),
    ("the television in the central vertical third", one(TV, region="center third")),
    ("mug in the first vertical third", one(MUG, region="left third")),
    ("sofa on the right-hand vertical line of thirds", one(SOFA, region="right third")),
    ("mug smack bang in the middle of the pic", one(MUG, region="center")),
    ("the mug in the midst of the frame", one(MUG, region="center")),
]

SIZES = [
    # So big it fills everything: a close-up ("everything" is no group of subjects there).
    ("the mug, so big it fills everything", one(MUG, shot="close-up")),
    ("make the teddy so large it fills the whole thing", one(BEAR, shot="close-up")),
    ("the toy car so big that it fills the entire frame", one(CAR, shot="close-up")),
    ("the sofa, it should fill up everything", one(SOFA, shot="close-up")),
    # An intensifier repeated grades as once.
    ("the mug very very small", one(MUG, shot="wide")),
    ("the bench super super tiny", one(BENCH, shot="wide")),
    ("the mug really really close", one(MUG, shot="close-up")),
    ("toy car very, very big", one(CAR, shot="close-up")),
    ("the teddy so so small", one(BEAR, shot="wide")),
    ("the mug tiny tiny", one(MUG, shot="wide")),
    ("the teddy bear very, very, very small", one(BEAR, shot="wide")),
    ("Make it really small: the mug", one(MUG, shot="wide")),
    ("the mug teeny-tiny", one(MUG, shot="wide")),
    ("the teddy ginormous in the frame", one(BEAR, shot="close-up")),
    # A small element of a larger whole.
    ("the mug as a small element in the picture", one(MUG, shot="wide")),
    ("the bench as a tiny part of the scene", one(BENCH, shot="wide")),
    ("the teddy, a minor element in the frame", one(BEAR, shot="wide")),
    ("the sofa, just a small element of the composition", one(SOFA, shot="wide")),
    ("toy car as a little feature in the landscape", one(CAR, shot="wide")),
    ("the teddy as a small part of a bigger picture", one(BEAR, shot="wide")),
    # Wide on the subject, as a shot list says it.
    ("wide on the mug, from the left", one(MUG, shot="wide", view="left")),
    ("EXT. PARK - WIDE on the bench", one(BENCH, shot="wide")),
]


@pytest.mark.parametrize(
    ("text", "want"),
    rows(ELEVATIONS_AND_SQUARE + NOUN_FIRST_AND_LATERAL + DOWN_THE_LENS + CORNERS + MIDDLES_AND_THIRDS + SIZES),
)
def test_view_region_and_size_families(text, want):
    assert read(text) == want


@pytest.mark.parametrize(
    "text",
    [
        "the mug on the left, on the right",  # two sides of one axis
        "the sofa in the lower left corner, at the top",  # a corner and the other height
        "the bench in the left third, at the bottom",  # a third is no half
    ],
)
def test_regions_that_name_no_one_corner_still_conflict(text):
    with pytest.raises(InputError, match="conflicting region"):
        read(text)


def test_a_second_subject_still_takes_its_own_region():
    assert read("the mug at the bottom, the bench on the left")["subjects"] == [
        (MUG, "bottom", None, None),
        (BENCH, "left", None, None),
    ]


def test_an_elevation_before_a_number_stays_a_height():
    # "front elevation 20 degrees" is no architect's elevation: the view is the front, the height explicit.
    got = read("the sofa from the front, elevation 20 degrees")
    assert got["subjects"] == [(SOFA, None, None, "front")]
    assert got["elevation_deg"] == 20.0


def test_a_comma_between_other_repeated_words_parts_clauses():
    assert read("the mug, zoomed right in, in the middle of the frame") == one(MUG, region="center", shot="close-up")


def test_a_mid_shot_is_still_a_size():
    assert read("a mid shot of the bench") == one(BENCH, shot="medium")


def test_a_toy_car_answers_to_automobile():
    assert read("the toy automobile from the left") == one(CAR, view="left")
    assert read("automobile, rear view") == one(CAR, view="back")
