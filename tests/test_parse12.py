"""The families of heldout11's misreadings, each as parts in any order (parse12): a roll's
direction said as a side or given to the camera, a corner said with plain heights, held letters
and "please" anywhere, an end-to-end size, looking down straight, a name written by its
consonants or run together, and a subject named by a verb of getting.

Conventions (DESIGN §3): roll > 0 is the camera turned clockwise as the photographer sees it, so
its right side dips: "a right roll" is clockwise; the picture's content turns the other way.
None of these wordings is in a suite file."""

from __future__ import annotations

import pytest

from capframe.errors import InputError
from capframe.scene.directory import SemanticObject
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary, skeleton, unstretched

NAMES = ["teddy bear", "vase", "ball", "toy car", "coffee table", "floor lamp", "tree", "bench", "traffic cone", "mug"]
SCENE = Vocabulary.from_semantics([SemanticObject(k, n, [], False) for k, n in enumerate(NAMES)])


def read(text: str) -> dict:
    """The parse as plain values: the first subject's name, region, shot and view, elevation,
    roll, the words not understood and the words read otherwise."""
    p = parse_instruction(text, SCENE)
    s = p.subjects[0]
    return {
        "name": s.name,
        "region": s.region,
        "shot": s.shot,
        "view": s.view,
        "elevation": p.elevation,
        "roll": p.roll_deg,
        "not_understood": p.not_understood(),
        "corrected": p.corrected,
    }


ROLLS = [
    # A side as the roll's adjective: the camera's top goes that way, right is clockwise.
    ("the mug, hold a 12° left roll", -12.0),
    ("the vase with a 10 degree right roll", 10.0),
    ("the lamp, a twelve degree right-hand tilt", 12.0),
    ("bench with a 25° leftwards roll", -25.0),
    ("the bear with a slight left roll", -10.0),
    ("a right-hand roll of 8 degrees on the bear", 8.0),
    # A side as the direction of turning the camera, its lens axis said or the camera named.
    ("the ball, TILT THE CAM 5 DEGREES LEFT AROUND THE LENS", -5.0),
    ("the mug with the camera rolled fifteen degrees right round the lens axis", 15.0),
    ("Bear centred. Please rotate camera 10 deg to the right about its axis.", 10.0),
    ("the vase, spin the frame 30 degrees left on the lens axis", -30.0),
    ("ball, turn the cam round the lens 25 degrees to the right", 25.0),
    ("the vase, rotate the camera 20 degrees to the right about the lens axis", 20.0),
    ("the bear, camera rolled left 10", -10.0),
    ("the bear, tilt the frame right by 12 degrees", 12.0),
    # Degrees, or a share of a turn, given to the camera.
    ("the tree, give the camera a tenth of a turn to the right", 36.0),
    ("the vase, give the camera 20 degrees counterclockwise", -20.0),
    ("the vase, give the lens a 20 degree clockwise twist", 20.0),
    ("the cone, apply 10 degrees anticlockwise to the camera", -10.0),
    ("the vase, put 10 degrees of clockwise roll on the camera", 10.0),
    ("VASE. GIVE THE CAM AN EIGHTH OF A TURN CCW", -45.0),
    ("the mug, add twenty degrees of roll to the left", -20.0),
    # The picture's content turned to the left is the camera turned clockwise.
    ("bear, rotate the picture 10 degrees to the left around the lens", 10.0),
]


@pytest.mark.parametrize("text, degrees", ROLLS)
def test_roll_direction_as_a_side_or_given(text, degrees):
    parsed = read(text)
    assert parsed["roll"] == degrees
    assert parsed["view"] is None  # a roll to a side is no view side
    assert parsed["not_understood"] == []


@pytest.mark.parametrize(
    "text, view",
    [
        # Turned or swung to the subject's side, with no lens axis: an azimuth, not a roll.
        ("the vase, swung 20 degrees to its left", "front-slight-left"),
        ("the bear from behind, 30 degrees to the left", "back-slight-left"),
        ("turn the camera 30 degrees to the left, the bear", "front-slight-left"),
        ("the vase, swing round 40 degrees to the right", "front-right"),
    ],
)
def test_a_turn_to_a_side_without_the_lens_axis_stays_a_view(text, view):
    parsed = read(text)
    assert parsed["roll"] is None
    assert parsed["view"] == view


CORNERS = [
    ("put the vase in the corner down and left of the frame", "lower left"),
    ("the ball in the corner top and right", "upper right"),
    ("mug in the upper and left corner", "upper left"),
    ("ball in the right and upper corner", "upper right"),
    ("the bear in the corner to the right and at the top", "upper right"),
    ("BALL IN CORNER DOWN RIGHT", "lower right"),
    ("the bear at the corner, left and down", "lower left"),
    ("the vase in the up right corner", "upper right"),
    ("the mug in the corner high and to the left", "upper left"),
    ("teddy in the left up corner", "upper left"),
    ("place the ball in the corner of the frame up and to the left", "upper left"),
    ("the bear in the down-left corner", "lower left"),
    ("the vase in the quadrant down and to the right", "lower right"),
    ("the lamp in the corner low and on the right", "lower right"),
    ("THE CONE IN THE UP LEFT CORNER OF THE IMAGE", "upper left"),
]


@pytest.mark.parametrize("text, region", CORNERS)
def test_corner_as_height_and_side_in_any_order(text, region):
    parsed = read(text)
    assert parsed["region"] == region
    assert parsed["not_understood"] == []


def test_a_quarter_before_a_side_and_a_height_is_a_view_not_a_corner():
    """A "quarter" is a view noun ("rear quarter"); only "corner" and "quadrant" join the family."""
    parsed = read("the car from the rear quarter, left side, low")
    assert parsed["region"] is None
    assert parsed["view"] == "back-left"
    assert parsed["elevation"] == "low angle"


def test_corner_words_are_never_a_subject():
    """The words "corner up" were taken for an unknown subject and the instruction refused."""
    parsed = read("I'd like the ball in the corner up and to the right of the picture, the bear in too")
    assert (parsed["name"], parsed["region"]) == ("ball", "upper right")


SIZES = [
    # Held letters, repeated intensifiers and "please" anywhere.
    ("the ball, sooo big in the frame", "close-up"),
    ("the vase biiig in the frame", "close-up"),
    ("the mug really really large please", "close-up"),
    ("make the teddy veeery small", "wide"),
    ("bear, tiiiny in the shot", "wide"),
    ("the mug, sooooo close", "close-up"),
    ("the ball reeeally big", "close-up"),
    ("plz make the mug realy realy big", "close-up"),
    ("make the cone biiiig", "close-up"),
    ("the tree sooo tiny in the picture", "wide"),
    # From one end of it to the other: all of it, little room.
    ("the lamp, base to tip in the shot", "medium"),
    ("the tree from roots to top, all in the shot", "medium"),
    ("the tree from its roots up to its crown in frame", "medium"),
    ("TREE - ROOTS TO CROWN IN SHOT", "medium"),
    ("the car from bumper to bumper, all of it in the frame", "medium"),
    ("the tree, trunk to top, entirely in shot", "medium"),
    ("the bear, head to feet, all in view", "medium"),
    ("the cone base up to tip in frame", "medium"),
    ("the lamp pole to shade all inside the frame", "medium"),
]


@pytest.mark.parametrize("text, shot", SIZES)
def test_size_said_with_emphasis_or_end_to_end(text, shot):
    parsed = read(text)
    assert parsed["shot"] == shot
    assert parsed["not_understood"] == []


def test_held_letters_are_reported_as_read():
    assert {"said": "biiig", "read": "big"} in read("the vase biiig in the frame")["corrected"]


TOP_DOWN = [
    ("the mug: look down straight onto it", None),
    ("the ball, camera looking straight down on it", None),
    ("LOOK DIRECTLY DOWN ON THE BALL", None),
    ("from very high, look down straight at the mug", None),
    ("camera looking right down onto the ball", None),
    ("the bear, look down right on top of it", None),
    ("the mug, camera looks down straight on it", None),
    ("the ball, peer down vertically at it", None),
    ("the mug, gazing straight down onto it", None),
    ("the cone - camera look straight down at it", None),
    # A view said besides keeps its own words.
    ("the mug, look down straight on him from the front", "front"),
]


@pytest.mark.parametrize("text, view", TOP_DOWN)
def test_looking_down_straight_is_top_down_not_a_front_view(text, view):
    parsed = read(text)
    assert parsed["elevation"] == "top-down"
    assert parsed["view"] == view


def test_looking_down_without_an_insisting_word_stays_a_high_angle():
    parsed = read("the ball from above, looking down at it")
    assert (parsed["elevation"], parsed["view"]) == ("high angle", None)


SHORT_NAMES = [
    # A name word written by its consonants (first letter kept), or two written as one.
    ("coffee tbl from above", "coffee table", {"said": "tbl", "read": "table"}),
    ("the flr lmp from the side", "floor lamp", {"said": "flr", "read": "floor"}),
    ("a shot of the cff tbl", "coffee table", {"said": "cff", "read": "coffee"}),
    ("the tdy br from behind", "teddy bear", {"said": "tdy", "read": "teddy"}),
    ("the bnch, low angle", "bench", {"said": "bnch", "read": "bench"}),
    ("teddybear close up", "teddy bear", {"said": "teddybear", "read": "teddy bear"}),
    ("FLOORLAMP, WIDE", "floor lamp", {"said": "floorlamp", "read": "floor lamp"}),
    ("the trafficcone from above", "traffic cone", {"said": "trafficcone", "read": "traffic cone"}),
    ("the toycar from behind", "toy car", {"said": "toycar", "read": "toy car"}),
    ("the motorcar from the left", "toy car", {"said": "motorcar", "read": "motor car"}),
]


@pytest.mark.parametrize("text, name, reading", SHORT_NAMES)
def test_names_written_short_or_run_together(text, name, reading):
    parsed = read(text)
    assert parsed["name"] == name
    assert reading in parsed["corrected"]


def test_skeleton_and_held_letters():
    assert skeleton("table") == ("tbl",)
    assert skeleton("teddy") == ("tddy", "tdy")
    assert unstretched("pleeease", {"please"}.__contains__) == "please"
    assert unstretched("tooo", {"to", "too"}.__contains__) == "too"  # twice before once
    assert unstretched("sooo", {"so"}.__contains__) == "so"
    assert unstretched("zzz", {"so"}.__contains__) is None
    assert unstretched("ball", {"bal"}.__contains__) is None  # a letter twice is no held one


def test_a_short_form_of_two_names_names_neither():
    """A "bll" could be "ball" or "bell": read as neither, the mention is refused, not guessed."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "ball", [], False), SemanticObject(1, "bell", [], False)])
    assert scene.expansion("bll") is None
    assert scene.expansion("bl") is None  # two letters are too few
    with pytest.raises(InputError, match="bll"):
        parse_instruction("the bll from above", scene)


@pytest.mark.parametrize(
    "text, unknown",
    [
        ("there's a kite by the bench, get the kite from above", "kite"),
        ("grab the frisbee, close up", "frisbee"),
        ("snap the skateboard from the left", "skateboard"),
        ("just grab the kite in the middle of the frame", "kite"),
        ("Get the frisbee please, medium shot", "frisbee"),
        ("get the umbrella close up", "umbrella"),
        ("grab that frisbee by the bench, from above", "frisbee"),
        ("catch the bird on the bench from the left", "bird"),
        ("take the lantern, close-up", "lantern"),
    ],
)
def test_a_thing_got_is_the_subject_and_refused_when_unknown(text, unknown):
    with pytest.raises(InputError, match=f"'{unknown}' is not in this scene"):
        parse_instruction(text, SCENE)


@pytest.mark.parametrize(
    "text, name",
    [
        ("get the bench, mid-size in frame", "bench"),
        ("grab the bear from behind", "teddy bear"),
        ("get a close-up of the vase", "vase"),
        ("take a look at the mug from above", "mug"),
        ("get the camera down low, the bear from the left", "teddy bear"),
        ("get the shot from behind the bench", "bench"),
        ("take my bench from the left", "bench"),
        ("snap the mug nice and close", "mug"),
    ],
)
def test_getting_a_known_thing_or_a_picture_word_is_no_refusal(text, name):
    assert read(text)["name"] == name


@pytest.mark.parametrize(
    "text, view",
    [
        # Which side, said after a side view as "the left one" (the subject's own side).
        ("the car, side view (the right one)", "right"),
        ("the bench seen from a side - the left one", "left"),
        ("the car from one side, the right one, low", "right"),
        ("the car from the side, the left hand one", "left"),
        ("the bench in profile, the right one", "right"),
        ("the car from the side: the left one", "left"),
        ("bench, side on, the right one", "right"),
        ("the toy car from its side; the left side", "left"),
    ],
)
def test_which_side_said_after_a_side_view(text, view):
    parsed = read(text)
    assert parsed["view"] == view
    assert parsed["not_understood"] == []
