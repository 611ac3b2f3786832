"""The families of heldout12's misreadings, each as parts in any order (parse13): a part of the
subject turned to the camera gives the side seen, named heights that overlap meet, a person's
place beside the subject is eye level, a size word alone as a clause, the setting and the
requester are never subjects, a view across a diagonal corner, and a thing the scene lacks joined
to a named subject is a second subject (refused).

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left,
±180 behind; elevation > 0 above the subject. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest

from capframe.constraints import ELEVATIONS
from capframe.errors import InputError
from capframe.scene.directory import SemanticObject
from capframe.translate.parse import _meeting, parse_instruction
from capframe.translate.vocabulary import words

NAMES = ["toy car", "armchair", "television", "bookshelf", "sofa", "bench", "teddy bear", "mug", "vase", "tree", "ball"]
SCENE_OBJECTS = [SemanticObject(k, n, [], False) for k, n in enumerate(NAMES)]


def _scene():
    from capframe.translate.vocabulary import Vocabulary

    return Vocabulary.from_semantics(SCENE_OBJECTS)


SCENE = _scene()


def read(text: str) -> dict:
    """The parse as plain values: the subjects' names, the first one's view and shot, the
    elevation (named, degrees) and the words not understood."""
    p = parse_instruction(text, SCENE)
    s = p.subjects[0]
    return {
        "names": [x.name for x in p.subjects],
        "view": s.view,
        "shot": s.shot,
        "region": s.region,
        "elevation": p.elevation,
        "elevation_deg": p.elevation_deg,
        "not_understood": p.not_understood(),
    }


FACING = [
    # A part at the back turned to the camera: the back is seen; squared to it, exactly.
    ("toy car, rear bumper pointed at us", "back"),
    ("the toy car with its tail lights toward me", "back"),
    ("the toy car, its boot squarely to the camera", "back-exact"),
    ("ARMCHAIR WITH THE BACKREST TO CAMERA", "back"),
    ("bench, backrest facing the viewer, dead on", "back-exact"),
    # A part at the front: the front; "dead straight", "straight on" after it make it exact.
    ("armchair, seat turned towards us", "front"),
    ("the sofa with its seat cushions facing the lens dead straight", "front-exact"),
    ("tv, screen to camera", "front"),
    ("the television, its display facing towards me", "front"),
    ("bookshelf, shelves toward the viewer", "front"),
    ("bench with its slats to the cam, straight on", "front-exact"),
    ("toy car with its headlights at the lens", "front"),
    # The camera squared to a part: that end, exactly.
    ("the bookshelf photographed dead square to its shelves", "front-exact"),
    ("shoot the sofa squarely facing its seat", "front-exact"),
    ("armchair, camera square on to its backrest", "back-exact"),
]


@pytest.mark.parametrize("text, view", FACING)
def test_part_turned_to_the_camera_gives_the_side_seen(text, view):
    got = read(text)
    assert got["view"] == view, got
    assert got["not_understood"] == [], got


def test_a_part_not_in_the_table_stays_reported_never_guessed():
    got = read("the mug with its handle to camera")
    assert got["view"] is None
    assert any("handle" in w for w in got["not_understood"])


def test_a_part_word_that_is_also_a_name_after_its_own_subject_is_a_part():
    # "screen" and "shelves" are aliases of the television and the bookshelf: after "its" or
    # after a comma and their own subject they are its part, so one subject, not two.
    assert read("the tv, its screen to us")["names"] == ["television"]
    assert read("bookshelf, shelves facing the camera")["names"] == ["bookshelf"]


def test_meeting_of_named_heights():
    # Hand-checked against ELEVATIONS: high angle 25..60 and bird's-eye 60..90 touch at 60;
    # low angle -60..-8 and worm's-eye -90..-50 overlap on -60..-50; slightly above 8..30 and
    # high angle on 25..30; slightly above and bird's-eye lie apart.
    assert ELEVATIONS["high angle"][1] == ELEVATIONS["bird's-eye"][0] == 60.0
    assert _meeting(["bird's-eye", "high angle"]) == (60.0, 60.0)
    assert _meeting(["low angle", "worm's-eye"]) == (-60.0, -50.0)
    assert _meeting(["high angle", "slightly above"]) == (25.0, 30.0)
    assert _meeting(["bird's-eye", "slightly above"]) is None
    assert _meeting(["slightly below", "slightly above"]) is None


@pytest.mark.parametrize(
    "text",
    [
        "the mug from way up, as if from a drone",
        "vase, seen from high up like a drone would",
        "drone shot of the ball, hovering well above it",
        "the bench from a high angle, a bird's-eye view",
    ],
)
def test_heights_that_only_touch_read_as_the_one_farther_from_the_horizontal(text):
    got = read(text)
    assert (got["elevation"], got["elevation_deg"]) == ("bird's-eye", None), got


MEETING = [
    ("tree: low angle, worm's-eye view", -55.0),
    ("the tree from a low angle, like a worms eye", -55.0),
    ("teddy bear a little from above, high angle", 27.5),
    ("the teddy from slightly above - a high-angle shot", 27.5),
    ("Bench, eye level, slightly above", 10.0),
    ("ball: slightly below - eye level", -10.0),
]


@pytest.mark.parametrize("text, degrees", MEETING)
def test_overlapping_heights_meet_in_degrees(text, degrees):
    got = read(text)
    assert got["elevation"] is None and got["elevation_deg"] == pytest.approx(degrees), got


@pytest.mark.parametrize(
    "text",
    [
        "the mug from below, then from above",
        "bench, worm's-eye, slightly above",
        "tree from a high angle, at eye level",
        "the armchair a bit below, worm's eye",
    ],
)
def test_heights_that_lie_apart_stay_a_conflict(text):
    with pytest.raises(InputError, match="conflicting elevations"):
        parse_instruction(text, SCENE)


def test_an_angle_outside_where_heights_meet_is_a_conflict():
    with pytest.raises(InputError, match="conflicting elevations"):
        parse_instruction("the mug at eye level, slightly above, 45 degrees up", SCENE)


@pytest.mark.parametrize(
    "text",
    [
        "the bench from the left, as if sitting beside it",
        "armchair as though standing in front of it",
        "the sofa like you were sat on the floor next to it",
        "the bench as if someone was seated on the grass by it",
        "Teddy bear, as if I'm sitting at the table",
        "the armchair from where a seated person's eyes would be",
        "THE SOFA FROM A STANDING VIEWER'S EYE HEIGHT",
        "the bench like a person sitting on the lawn would see it",
    ],
)
def test_a_persons_place_beside_it_is_eye_level(text):
    got = read(text)
    assert got["elevation"] == "eye level", got
    assert got["not_understood"] == [], got


@pytest.mark.parametrize(
    "text, shot",
    [
        ("vase // tight // from the left", "close-up"),
        ("mug | tight | 10 degrees clockwise", "close-up"),
        ("the sofa, three-quarter front right, complete", "medium"),
        ("armchair from behind, whole.", "medium"),
        ("the bench, uncropped, eye level", "medium"),
        ("bookshelf, books crowding every edge of the frame", "close-up"),
        ("the teddy bear touching all four sides of the picture", "close-up"),
        ("the vase filling the frame edges", "close-up"),
        ("establishing, the tree on the right", "wide"),
    ],
)
def test_a_size_word_alone_as_a_clause(text, shot):
    got = read(text)
    assert got["shot"] == shot, got
    assert got["not_understood"] == [], got


def test_a_slash_between_clauses_parts_them_and_a_slash_inside_a_word_does_not():
    assert words("mug // tight") == ["mug", ",", "tight"]
    assert words("3/4 rear") == ["three", "quarter", "rear"]


@pytest.mark.parametrize(
    "text, names",
    [
        ("a wide of the living room, the sofa on the left", ["sofa"]),
        ("wide establishing of the den: the armchair small in the upper right", ["armchair"]),
        ("kitchen scene - the mug close up", ["mug"]),
        ("the backyard, with the tree on the left third", ["tree"]),
        ("My wife would like the bench in the middle", ["bench"]),
        ("our client wants the tv small in the top left", ["television"]),
        ("The agent has asked for the armchair from above", ["armchair"]),
        ("Grandpa here: the teddy bear close up please", ["teddy bear"]),
        ("a picture of the vase for my granddaughter", ["vase"]),
        ("MY BOSS NEEDS THE SOFA FROM THE FRONT", ["sofa"]),
    ],
)
def test_the_setting_and_the_requester_are_never_subjects(text, names):
    got = read(text)
    assert got["names"] == names, got
    assert got["not_understood"] == [], got


def test_a_setting_word_before_a_name_describes_it_and_a_requester_word_in_a_name_is_no_requester():
    assert read("the garden bench, from the front")["names"] == ["bench"]
    with pytest.raises(InputError, match="'grandmother clock' is not in this scene"):
        parse_instruction("the grandmother clock beside the sofa", SCENE)


@pytest.mark.parametrize(
    "text, view",
    [
        ("armchair seen over its back-left corner", "back-left"),
        ("the sofa, looking across its front right corner", "front-right"),
        ("toy car viewed from over its rear-right corner", "back-right"),
        ("over the bench's front-left corner", "front-left"),
        ("the tv, shot past its left front corner", "front-left"),
        ("Bookshelf photographed across its right-rear edge", "back-right"),
        ("the teddy bear, seen round his back left corner", "back-left"),
        ("the car angled off its front-right corner", "front-right"),
    ],
)
def test_a_view_across_a_diagonal_corner(text, view):
    assert read(text)["view"] == view


@pytest.mark.parametrize(
    "text, thing",
    [
        ("ukulele?? beside the sofa, want both", "ukulele"),
        ("a kazoo next to the mug", "kazoo"),
        ("the armchair and a footstool, both in frame", "footstool"),
        ("mug plus a teaspoon", "teaspoon"),
        ("the tree with a hammock, both visible", "hammock"),
        ("the bench together with a bicycle", "bicycle"),
        ("TV AND SOUNDBAR PLEASE", "soundbar"),
        ("a candle alongside the vase", "candle"),
    ],
)
def test_a_thing_the_scene_lacks_joined_to_a_subject_is_refused(text, thing):
    with pytest.raises(InputError, match=f"subject '{thing}' is not in this scene"):
        parse_instruction(text, SCENE)


@pytest.mark.parametrize(
    "text, thing",
    [
        ("Grandma's rocking horse next to the armchair", "rocking horse"),
        ("dad's slippers under the sofa", "slippers"),
        ("my daughter's doll beside the teddy bear, close up", "doll"),
        ("Rubik's cube by the mug", "rubik 's cube"),
        ("the guitar to the left of the sofa", "guitar"),
        ("a snap of the television plus the speaker beside it", "speaker"),
        ("the bench, with the bicycle leaning against it, both in frame", "bicycle"),
        ("the sofa and a footstool in front of it", "footstool"),
        ("mug & kettle, close-up", "kettle"),
        ("photo: toy car + garage", "garage"),
        ("the mug, the teapot next to it, both sharp", "teapot"),
        ("a floor cushion to the right of the armchair, from above", "floor cushion"),
        ("Grandpa's walking stick leaning on the bench", "walking stick"),
    ],
)
def test_a_thing_owned_or_placed_left_or_right_of_a_subject_is_refused(text, thing):
    """A possessor that is a table word (a requester) is not part of the thing's name, another
    one is; "to the left/right of" places a thing as "beside" does; after "and" or "plus" a thing
    tied back to the subject ("beside it") is a second one, after "with" only when both are asked
    for, or set off by a comma; "&" and "+" are "and"."""
    with pytest.raises(InputError, match=f"subject {thing!r} is not in this scene"):
        parse_instruction(text, SCENE)


@pytest.mark.parametrize(
    "text, names",
    [
        ("the mug next to the vase, want both", ["mug", "vase"]),
        ("the sofa to the left of the bench, both in frame", ["sofa", "bench"]),
        ("slightly to the left of the sofa, eye level", ["sofa"]),
        ("the mug, the vase next to it, both sharp", ["mug", "vase"]),
        ("the bench, the shadow under it, both in frame", ["bench"]),
        ("the sofa with cushions, from the front", ["sofa"]),
        ("the tree with its leaves in frame", ["tree"]),
        ("the bench with plenty of space around it", ["bench"]),
        ("taken at dusk with the bench in the middle", ["bench"]),
        ("the bench with a sunset behind it", ["bench"]),
    ],
)
def test_known_things_parts_and_room_joined_to_a_subject_are_not_refused(text, names):
    assert read(text)["names"] == names


@pytest.mark.parametrize(
    "text, region",
    [
        ("the vase in the left-hand third of the plate", "left third"),
        ("mug, bottom right of the canvas", "lower right"),
        ("the ball at the top of the exposure", "top"),
    ],
)
def test_older_words_for_the_picture_name_the_frame(text, region):
    assert read(text)["region"] == region


@pytest.mark.parametrize(
    "text, shot, elevation",
    [
        ("the vase, tight and centred", "close-up", None),
        ("the sofa, complete and from the front", "medium", None),
        ("mug, small and on the left", "wide", None),
        ("the bench, whole and at eye level", "medium", "eye level"),
        ("vase, high and from the left", None, "high angle"),
        ("The Teddy Bear, Close And Centered", "close-up", None),
    ],
)
def test_a_word_alone_as_a_clause_may_end_before_and(text, shot, elevation):
    got = read(text)
    assert (got["shot"], got["elevation"]) == (shot, elevation), got
    assert got["not_understood"] == [], got


@pytest.mark.parametrize(
    "text, elevation",
    [
        ("tree, almost worm's eye", "worm's-eye"),
        ("the tree from nearly a bird's eye view", "bird's-eye"),
        ("bench from roughly a frog's-eye view", "low angle"),
        ("the mug, kind of an ant's eye view", "worm's-eye"),
    ],
)
def test_a_creatures_eye_view_said_as_roughly_that(text, elevation):
    got = read(text)
    assert got["elevation"] == elevation and got["not_understood"] == [], got
