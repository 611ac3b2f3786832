"""The families of phrasing2's misreadings, each as parts in any order (parse14): "behind" as the
end of a diagonal view, "own" after a possessive, degrees "of elevation", the camera aimed
straight at what the subject stands on, small in a big or empty frame, a small margin round the
whole subject, all of it from end to end beside a size word, two frame regions that nest, and a
broadside.

Conventions (DESIGN §3): azimuth 0 = the subject's front, +90 its own right, -90 its own left;
elevation > 0 = camera above. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest

from capframe.constraints import REGIONS
from capframe.errors import InputError
from capframe.scene.directory import SemanticObject
from capframe.translate.parse import _nested_region, parse_instruction
from capframe.translate.vocabulary import Vocabulary

NAMES = ["teddy bear", "vase", "ball", "toy car", "sofa", "floor lamp", "tree", "bench", "potted plant", "mug"]
SCENE = Vocabulary.from_semantics([SemanticObject(k, n, [], False) for k, n in enumerate(NAMES)])


def first(text: str):
    """The parse and its first subject."""
    p = parse_instruction(text, SCENE)
    return p, p.subjects[0]


BEHIND_DIAGONALS = [
    ("sofa seen from behind-left", "back-left"),
    ("the bench, behind right three-quarter", "back-right"),
    ("BEAR FROM BEHIND LEFT", "back-left"),
    ("the vase from left-behind", "back-left"),
    ("teddy bear, three quarters behind left", "back-left"),
    ("the car photographed from behind-right please", "back-right"),
    ("mug from its behind-left corner", "back-left"),
    ("lamp: behind right", "back-right"),
    ("shoot the tree from behind left, eye level", "back-left"),
    ("from behind right of the bench", "back-right"),
]


@pytest.mark.parametrize("text,view", BEHIND_DIAGONALS)
def test_behind_names_the_back_diagonal(text, view):
    p, s = first(text)
    assert s.view == view
    assert not p.not_understood()


def test_right_behind_stays_directly_behind():
    # "right behind it" is "directly behind", not the back-right diagonal.
    assert first("Vase, right-behind")[1].view == "back-exact"
    assert first("the mug from right behind")[1].view == "back-exact"
    assert first("the tree from behind")[1].view == "back"


OWN_SIDES = [
    ("the bear, from its own left-hand side, thanks", "left"),
    ("the bench from its own right side", "right"),
    ("the car, from its own rear", "back"),
    ("shoot the mug from its own right-hand side", "right"),
    ("THE LAMP FROM ITS OWN LEFT SIDE", "left"),
    ("bench from it's own left", "left"),
    ("tree, seen from its own back", "back"),
    ("the toy car from their own right hand side", "right"),
    ("from the teddy bear's own left, please", "left"),
]


@pytest.mark.parametrize("text,view", OWN_SIDES)
def test_own_after_a_possessive_only_insists(text, view):
    p, s = first(text)
    assert s.view == view
    assert not p.not_understood()


ELEVATION_DEGREES = [
    ("Tree, viewed from thirty degrees of elevation", 30.0),
    ("the vase at 35 degrees of elevation", 35.0),
    ("SOFA AT 60 DEG OF ELEVATION", 60.0),
    ("the lamp seen from 20° in elevation", 20.0),
    ("the bench from minus 20 degrees of elevation", -20.0),
    ("the car, twenty-five degrees of camera elevation", 25.0),
    ("mug, shot from about 45 degrees of elevation", 45.0),
    ("bear photographed at fifty degrees of elevation angle", 50.0),
]


@pytest.mark.parametrize("text,degrees", ELEVATION_DEGREES)
def test_degrees_of_elevation(text, degrees):
    p, _ = first(text)
    assert p.elevation_deg == degrees
    assert not p.not_understood()


AIMED_AT_THE_SUPPORT = [
    "cushion-less: the mug, camera pointing straight at the tabletop",
    "the ball, lens pointed straight at the desk",
    "mug, the lens points squarely at the tabletop",
    "the vase, cam facing straight down at the counter",
    "THE BALL, CAMERA POINTING STRAIGHT AT THE LAWN",
    "the car, camera aimed perpendicularly at the floor",
    "mug, lens pointed straight at the table top surface",
    "the vase with your camera aimed directly at the carpet",
    "the mug, camera pointing dead straight at the desk",
]


@pytest.mark.parametrize("text", AIMED_AT_THE_SUPPORT)
def test_camera_aimed_straight_at_the_support_looks_straight_down(text):
    p, _ = first(text.split(": ", 1)[-1])
    assert p.elevation == "top-down"


def test_camera_aimed_at_a_subject_is_no_height():
    # The bench is a subject here, not what the mug stands on.
    p = parse_instruction("the mug, camera pointing straight at the bench", SCENE)
    assert p.elevation is None


SMALL_IN_A_BIG_FRAME = [
    "Just the teddy, tiny in a huge empty frame",
    "bear, little in a huge empty picture",
    "the mug, tiny in a vast, empty frame",
    "the ball, tiny in an otherwise empty frame",
    "lamp: small in a wide empty shot",
    "the bench, quite small within a large open frame",
    "the vase, wee in a big blank image",
    "tree really tiny inside a spacious composition",
    "the bear, tiny within an enormous empty frame",
]


@pytest.mark.parametrize("text", SMALL_IN_A_BIG_FRAME)
def test_small_in_a_big_or_empty_frame_is_wide(text):
    p, s = first(text)
    assert s.shot == "wide"
    assert not p.not_understood()


SMALL_MARGINS = [
    "the whole bench with some margin around it",
    "the vase, all of it in frame, with a little margin",
    "bear whole in the frame, leave a small margin",
    "the whole car in shot, a bit of margin round it",
    "the lamp, the whole thing, small margin",
    "mug, entire mug in frame plus a little margin",
    "full shot of the sofa with a little bit of margin",
    "the tree whole with a touch of padding",
    "the ball with a thin border all round",
]


@pytest.mark.parametrize("text", SMALL_MARGINS)
def test_a_small_margin_round_the_whole_subject_is_medium(text):
    assert first(text)[1].shot == "medium"


def test_a_generous_margin_stays_wide():
    assert first("the bench with a generous margin")[1].shot == "wide"
    assert first("the mug with lots of room around it")[1].shot == "wide"


FILLED_END_TO_END = [
    "the tree fills the frame from top to bottom",
    "the lamp, fill the frame top to bottom",
    "vase filling the shot from top to bottom",
    "the bear filling the frame, head to toe",
    "bench fills the picture end to end",
    "the lamp fills the frame base to top",
    "sofa filling the image arm to arm",
    "the tree, roots to crown, filling the frame",
    "car fills the whole frame, bumper to bumper",
    "floor lamp filling the frame top to bottom (base to bulb)",
]


@pytest.mark.parametrize("text", FILLED_END_TO_END)
def test_end_to_end_beside_a_size_is_that_size(text):
    assert first(text)[1].shot == "close-up"


def test_end_to_end_alone_is_medium_and_sizes_still_conflict():
    assert first("the lamp, base to shade")[1].shot == "medium"
    assert first("the tree top to bottom, small in the frame")[1].shot == "wide"
    with pytest.raises(InputError, match="conflicting shot"):
        parse_instruction("the mug filling the frame, small in the frame", SCENE)


NESTED_REGIONS = [
    ("bear sits on the right third, empty space to the left", "right third"),
    ("the vase in the left third with negative space on the right", "left third"),
    ("mug on the left third, on the left", "left third"),
    ("the bench in the right third, on the right side of the frame", "right third"),
    ("tree, left third, empty space to the right", "left third"),
    ("lamp in the right third, frame right", "right third"),
    ("ball on the right, in the right third", "right third"),
    ("THE BEAR ON THE LEFT THIRD, ON THE LEFT SIDE OF THE PICTURE", "left third"),
]


@pytest.mark.parametrize("text,region", NESTED_REGIONS)
def test_nested_regions_keep_the_inner_one(text, region):
    assert first(text)[1].region == region


def test_nested_region_by_the_boxes():
    assert _nested_region("left", "left third") == "left third"
    assert _nested_region("right third", "right") == "right third"
    assert _nested_region("left third", "right") is None
    assert _nested_region("center", "top") is None
    # Every answer lies inside both boxes it came from.
    for a in REGIONS:
        for b in REGIONS:
            inner = _nested_region(a, b)
            if inner is not None:
                assert inner in (a, b)
    with pytest.raises(InputError, match="conflicting region"):
        parse_instruction("the mug in the left third, on the right", SCENE)


BROADSIDES = [
    ("car broadside, its left", "left"),
    ("sofa, broadside", "side"),
    ("the bench, broadside view from the left", "left"),
    ("a broadside shot of the car from its right", "right"),
    ("the car broad side on, left", "left"),
    ("BENCH BROADSIDE, FROM THE RIGHT", "right"),
    ("the toy car broadside on", "side"),
    ("broadside of the bench from the left side", "left"),
]


@pytest.mark.parametrize("text,view", BROADSIDES)
def test_broadside_is_the_side_view(text, view):
    assert first(text)[1].view == view


DETAILS_SEEN = [
    ("the television from behind, I'd like to see its wires", "wires"),
    ("TV from the back so the plugs show", "plugs"),
    ("Could you get the teddy bear from behind, so we see the stitching down its back?", "stitching"),
    ("the mug from its left so the logo on the side shows", "logo"),
    ("vase, from its back, where the chip is", "chip"),
    ("the lamp from behind so the switch and the cord show", "switch"),
    ("the bench from the rear, screws and bolts visible", "screws"),
    ("the toy car from behind, the sticker along its bottom", "sticker"),
]


@pytest.mark.parametrize("text,detail", DETAILS_SEEN)
def test_a_detail_of_the_subject_is_no_subject_and_no_typo(text, detail):
    """A small detail said to be seen is neither an object of its own nor a misspelt name
    ("cables" one letter from "table"); it stays reported as not understood."""
    scene = Vocabulary.from_semantics(
        [SemanticObject(k, n, [], False) for k, n in enumerate(["television", "coffee table", "teddy bear", "mug", "vase"])]
        + [SemanticObject(5 + k, n, [], False) for k, n in enumerate(["floor lamp", "bench", "toy car"])]
    )
    p = parse_instruction(text, scene)
    assert len(p.subjects) == 1
    assert p.subjects[0].view is not None
    assert any(detail in run for run in p.not_understood())


def test_an_unknown_object_is_still_refused():
    with pytest.raises(InputError, match="not in this scene"):
        parse_instruction("the harmonica lying by the mug, from the front", SCENE)
