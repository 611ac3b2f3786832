"""The roll family in open wording: a verb or noun of turning about the lens axis, what turns
(the camera or its frame, or the picture's content, which turns the other way), where it turns
("sideways", "about the lens axis"), a number and a direction in any order; a level camera said
as an absence of any roll word. Roll > 0 is the camera turned clockwise (DESIGN §3).

None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from test_parse_generalise import read


def roll(text: str) -> float | None:
    parsed = read(text)
    assert parsed["not_understood"] == [], parsed["not_understood"]
    return parsed["roll_deg"]


CAMERA_ROLLS = [
    # Number and direction around the verb, the camera or the lens named or not.
    ("mug, spin the camera 20 degrees clockwise on its axis", 20.0),
    ("the mug with the camera tipped 20 degrees clockwise", 20.0),
    ("mug, camera twisted 12 degrees anticlockwise", -12.0),
    ("mug, tilt the camera sideways 20 degrees clockwise", 20.0),
    ("mug, rotated about the optical axis by 20 degrees clockwise", 20.0),
    ("mug, turned clockwise 20 degrees around the lens axis", 20.0),
    ("mug, camera swung 10 degrees clockwise around the lens axis", 10.0),
    ("mug, roll it clockwise 15 degrees", 15.0),
    ("mug, angle the camera 20 degrees clockwise", 20.0),
    ("mug, twist the lens twenty degrees anti clockwise", -20.0),
    # Number, direction and noun in any order.
    ("mug, 15 degrees of tilt clockwise", 15.0),
    ("mug, 20 degree clockwise camera rotation", 20.0),
    ("mug, a 30 degree cant clockwise", 30.0),
    ("mug; 12 deg ccw tilt", -12.0),
    ("mug, 30° of roll, anticlockwise", -30.0),
    ("mug, camera at a 20° angle clockwise", 20.0),
    ("mug, roll angle 20", 20.0),
    # To a side, and a dutch angle as a verb.
    ("mug, lean the camera fifteen degrees to the left", -15.0),
    ("mug, dutched 15 degrees", 15.0),
    # The frame is the camera's rectangle: it turns with the camera.
    ("mug, framing rotated 10 degrees counter-clockwise", -10.0),
]

PICTURE_ROLLS = [
    # The picture's content turns against the camera.
    ("mug, image turned 10 degrees clockwise", -10.0),
    ("mug, a tilted horizon of 20 degrees clockwise", -20.0),
    ("mug, horizon sloping down to the right by 10 degrees", -10.0),
]

LEVEL = [
    "mug, no tilt at all",
    "mug, keep the camera level, no rolling",
    "mug, horizon not crooked",
    "mug, camera not rotated",
    "mug with zero roll",
    "mug, no dutch angle at all",
    "mug, not tilted sideways",
    "mug, the frame square to the horizon",
]


@pytest.mark.parametrize("text, deg", [pytest.param(t, d, id=t) for t, d in CAMERA_ROLLS + PICTURE_ROLLS])
def test_a_roll_in_any_word_order_is_read_with_its_sign(text, deg):
    assert roll(text) == deg


@pytest.mark.parametrize("text", [pytest.param(t, id=t) for t in LEVEL])
def test_a_level_camera_said_as_an_absence_is_roll_zero(text):
    assert roll(text) == 0.0


def test_a_negated_crooked_frame_is_level_not_a_dutch_angle():
    """A horizon "not crooked" once read as a crooked frame: a dutch angle of 15 degrees."""
    assert roll("mug, horizon not crooked") == 0.0
    assert read("mug, horizon crooked")["roll_deg"] == 15.0


def test_the_camera_and_the_picture_turned_alike_are_opposite_rolls():
    """Parity: the frame turned with the camera, the image against it."""
    for amount in (10, 25):
        camera = roll(f"mug, camera rotated {amount} degrees clockwise")
        frame = roll(f"mug, frame rotated {amount} degrees clockwise")
        picture = roll(f"mug, picture rotated {amount} degrees clockwise")
        assert camera == frame == -picture == amount
