"""The families of phrasing3's and heldout16's misreadings of the fields other than the view, read
when they became development sets: heights said as the camera held exactly overhead ("hanging dead
overhead"), exactly on top of it, a bit "from high", from a lofty place, or "it" pointed straight up
into a part; regions said as taking up an area as a purpose ("pushed across to occupy"), hugging the
frame's "right-hand edge", a column of the thirds grid, hard (far) to one side, up (down) and to a
side of the picture; rolls said of the horizon or skyline as what it should do ("the horizon should
slope", "have the skyline dip"), in "the final image", or as a negative number about the lens axis;
sizes said as zooming until nothing else is left, "close in" alone, a small detail of the room, small
on what it rests on, so close a part of it fills or touches the frame, "whole" spelt "hole", a
mistyped "medium", "all sofa inside picture"; and a word of a name never misspelling another name
("little bear" is no "little car").

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.errors import InputError
from capframe.scene.directory import SemanticObject
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary, words

NAMES = [
    "armchair",
    "sofa",
    "mug",
    "teddy bear",
    "bench",
    "toy car",
    "vase",
    "cushion",
    "ball",
    "tree",
    "television",
    "floor lamp",
    "traffic cone",
    "refrigerator",
    "potted plant",
]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


HEIGHTS = [
    # Held exactly overhead, said of the camera hanging or perched there.
    ("the vase, camera hanging dead overhead", "top-down"),
    ("the ball with the lens perched bang overhead", "top-down"),
    ("bench: cam suspended plumb over it", "top-down"),
    ("the mug from dead overhead", "top-down"),
    # The camera exactly on top of it.
    ("the cushion, camera directly on top", "top-down"),
    ("the mug with the lens right on top of it", "top-down"),
    ("traffic cone, camera sitting exactly on top of the cone", "top-down"),
    # A slight word before "from high" (as "from upper").
    ("the sofa, a bit from high", "slightly above"),
    ("teddy bear a little from higher, from behind", "slightly above"),
    ("the vase just a touch from high", "slightly above"),
    # A lofty place.
    ("the bench from a lofty vantage point", "high angle"),
    ("the toy car from a lofty perch", "high angle"),
    ("the armchair, a lofty angle", "high angle"),
]


@pytest.mark.parametrize(("text", "elevation"), HEIGHTS)
def test_heights(text, elevation):
    p = parse(text)
    assert (p.elevation, p.elevation_deg) == (elevation, None)


@pytest.mark.parametrize(
    "text",
    [
        # "It" (the camera) pointed straight up, maybe into a part of the subject.
        "the tree, camera at the roots; point it vertically up into the canopy",
        "floor lamp, aim it straight up into its shade",
        "the bench from under it, point it straight up at it",
    ],
)
def test_it_pointed_straight_up(text):
    p = parse(text)
    assert (p.elevation, p.elevation_deg) == (None, -90.0)
    assert p.understood == "fully"


@pytest.mark.parametrize(
    ("text", "elevation"),
    [
        # Keep-probes: a bare "hanging overhead" stays a high angle, "from high" alone too, and
        # "on top" said of the subject in the frame stays a region.
        ("the mug, camera hanging overhead", "high angle"),
        ("the car from high", "high angle"),
        ("the mug, camera directly overhead", "top-down"),
        ("the ball from a high vantage point", "high angle"),
    ],
)
def test_height_keep_probes(text, elevation):
    assert parse(text).elevation == elevation


def test_a_subject_on_top_of_the_frame_stays_a_region():
    p = parse("the vase on top of the frame")
    assert p.subjects[0].region == "top" and p.elevation is None


REGIONS = [
    # Taking up an area, said as a purpose after a placing verb.
    ("the vase pushed across to occupy the left third", "left third"),
    ("bench, shoved over to cover the right third", "right third"),
    ("the ball nudged so it fills the left third of the frame", "left third"),
    # Hugging (touching) the frame's own edge, "right-hand" or not.
    ("the lamp hugging the picture's left-hand edge", "left"),
    ("the sofa touching the frame's right-hand edge", "right"),
    ("armchair hugging the image's right edge", "right"),
    # A column of the thirds grid.
    ("the mug in the centre column of a thirds grid", "center third"),
    ("the plant in the right column of the rule of thirds grid", "right third"),
    ("cushion in the left column of the thirds grid", "left third"),
    # Hard (far) to one side.
    ("shoot the bench hard right", "right"),
    ("the tree far left", "left"),
    ("the ball placed hard left, from the front", "left"),
    # Up (down) and to a side of the picture, maybe in its corner.
    ("the teddy bear up and to the left of the frame", "upper left"),
    ("vase down and towards the right of the picture, in the corner", "lower right"),
    ("the mug high and to the right of the image", "upper right"),
]


@pytest.mark.parametrize(("text", "region"), REGIONS)
def test_regions(text, region):
    p = parse(text)
    assert p.subjects[0].region == region
    assert p.understood == "fully"


@pytest.mark.parametrize(
    ("text", "region"),
    [
        # Keep-probes: up and to a side without the picture moves no subject in the frame; a
        # centre column without the thirds grid stays the centre; taking up an area as before.
        ("the ball, up and to the right", None),
        ("the vase in the centre column", "center"),
        ("mug taking up the right third", "right third"),
        ("the mug in the frame's right edge", "right"),
    ],
)
def test_region_keep_probes(text, region):
    assert parse(text).subjects[0].region == region


ROLLS = [
    # The horizon or the skyline, with what it should do (the picture turns against the camera).
    ("the sofa; the horizon should slope 10 degrees anticlockwise", 10.0),
    ("bench, have the skyline dip 20 degrees clockwise", -20.0),
    ("the vase, I want the skyline to slant 15 degrees counterclockwise", 15.0),
    ("the mug - the horizon must spin 12 degrees clockwise", -12.0),
    ("teddy bear, skyline tilted 8 degrees clockwise across the frame", -8.0),
    # In the final image.
    ("the armchair, and in the final image the horizon should run 5 degrees clockwise", -5.0),
    ("in the finished picture the horizon slopes 10 degrees anticlockwise, the ball centred", 10.0),
    # A negative number about the lens axis, maybe said again in brackets.
    ("ball, camera turned -15 degrees about its axis (counterclockwise)", -15.0),
    ("the bench: rotate the camera about the lens axis by minus 20 degrees", -20.0),
    ("the cushion, lens spun -10 degrees around its own axis", -10.0),
]


@pytest.mark.parametrize(("text", "roll"), ROLLS)
def test_rolls(text, roll):
    p = parse(text)
    assert p.roll_deg == roll
    assert p.understood == "fully"


@pytest.mark.parametrize(
    "text",
    [
        # Keep-probes: an unsigned number about the axis says no way to turn; a turn without the
        # axis may aim the camera.
        "the mug: camera turned 15 degrees about its axis",
        "the mug: camera turned -15 degrees",
    ],
)
def test_no_roll_without_a_way_to_turn(text):
    assert parse(text).roll_deg is None


def test_the_camera_with_a_modal_still_rolls_its_own_way():
    assert parse("the mug, the camera should tilt 10 degrees anticlockwise").roll_deg == -10.0


def test_the_final_image_is_no_subject():
    p = parse("the sofa from the front; in the final shot it is small")
    assert [s.name for s in p.subjects] == ["sofa"] and p.subjects[0].shot == "wide"


SHOTS = [
    # Zoomed until nothing else is left.
    ("the mug, zoom zoom until there's nothing but mug", "close-up"),
    ("vase: push in till you see nothing except the vase", "close-up"),
    ("the ball, zoom in until all you see is the ball", "close-up"),
    # "Close in" alone as a clause.
    ("the television from the left, close in", "close-up"),
    ("bench, in close, from behind", "close-up"),
    # A small detail of the room (garden, scene).
    ("the cushion as a tiny detail of the room, from above", "wide"),
    ("the bench, a small detail of the garden", "wide"),
    # Small on what it rests on.
    ("toy car from its right, kept small on the rug", "wide"),
    ("the ball, tiny against the wall", "wide"),
    # So close a part of it fills or touches the frame.
    ("the traffic cone so close its sides touch the frame", "close-up"),
    ("the ball so near that its seams fill the whole frame", "close-up"),
    ("the bench so close that the slats touch the edges of the frame", "close-up"),
    # "Whole" spelt by ear.
    ("the sofa so close the armrests take up the hole picture", "close-up"),
    # A mistyped "medium".
    ("the vase, medum shot", "medium"),
    ("the teddy bear from behind, meduim shot", "medium"),
    # "All sofa inside picture", the articles dropped.
    ("bench from its left end, all bench inside picture", "medium"),
    ("the armchair, all armchair in frame", "medium"),
]


@pytest.mark.parametrize(("text", "shot"), SHOTS)
def test_shots(text, shot):
    assert parse(text).subjects[0].shot == shot


@pytest.mark.parametrize(
    ("text", "shot", "region"),
    [
        # Keep-probes: "far" before a side of the frame is how far out it sits; a detail of the
        # subject stays no size; a close-up stays one.
        ("the tree, far on the left", None, "left"),
        ("the lamp, a detail of the room", None, None),
        ("the cone so close", "close-up", None),
        ("the mug close to the left edge of the frame", None, "left"),
    ],
)
def test_shot_keep_probes(text, shot, region):
    s = parse(text).subjects[0]
    assert (s.shot, s.region) == (shot, region)


def test_a_hole_elsewhere_stays_a_hole():
    assert "hole" in words("the ball by the hole in the fence")
    assert words("take up the hole picture")[-2:] == ["whole", "picture"]


@pytest.mark.parametrize(
    ("names", "text", "name"),
    [
        # A word of a name, as written, misspells no other name.
        (["teddy bear", "toy car"], "the little bear from the back", "teddy bear"),
        (["teddy bear", "toy car"], "the littel car from the back", "toy car"),
        (["floor lamp", "mug"], "the floor lamb, wide", "floor lamp"),
    ],
)
def test_a_name_word_misspells_no_other_name(names, text, name):
    scene = Vocabulary.from_semantics([SemanticObject(k, n, [], False) for k, n in enumerate(names)])
    assert [s.name for s in parse_instruction(text, scene).subjects] == [name]


UNKNOWN = [
    # A thing set at its side after "with" is to be seen with it.
    ("the vase, with the pepper grinder beside it", "pepper grinder"),
    ("the bench with a bicycle next to it, from the front", "bicycle"),
    ("teddy bear with the rag doll alongside it", "rag doll"),
    # Family said as names in a subject's place.
    ("Photograph Grandma in the armchair", "grandma"),
    ("a photo of dad on the sofa, from the front", "dad"),
    ("shoot Nana beside the tree", "nana"),
    # A thing introduced by "there is", which the sentence then asks for.
    ("Next to the mug there's a sugar bowl, take it from the front", "sugar bowl"),
    ("behind the bench there is a lawnmower; get it from the left", "lawnmower"),
    ("On the sofa there's a laptop - shoot it close", "laptop"),
]


@pytest.mark.parametrize(("text", "thing"), UNKNOWN)
def test_an_unknown_subject_is_refused(text, thing):
    with pytest.raises(InputError, match=f"subject '{thing}' is not in this scene"):
        parse(text)


@pytest.mark.parametrize(
    ("text", "names"),
    [
        # Keep-probes: behind it is a background, a glow or an amount is no thing, a known thing
        # introduced by "there is" is read.
        ("the bench with a sunset behind it", ["bench"]),
        ("there's a nice glow on the vase, from the front", ["vase"]),
        ("the vase, and there's a bit of space above it", ["vase"]),
        ("there is a bench in the park, get it from behind", ["bench"]),
        ("the mug with the ball beside it", ["mug", "ball"]),
    ],
)
def test_unknown_subject_keep_probes(text, names):
    assert [s.name for s in parse(text).subjects] == names


@pytest.mark.parametrize(
    ("text", "shot"),
    [
        # A size said with "don't" is not asked ("don't zoom in" beside "small" is no conflict).
        ("the mug small in the picture, don't zoom in", "wide"),
        ("the bench, dont go close, from the left", None),
        ("teddy bear far away - do not zoom in on him", "wide"),
        # Keep-probe: "don't crop it" says all of it is in, as before.
        ("the sofa, don't crop it", "medium"),
    ],
)
def test_a_size_said_with_dont_is_not_asked(text, shot):
    assert parse(text).subjects[0].shot == shot
