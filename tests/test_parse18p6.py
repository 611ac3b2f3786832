"""The families of phrasing6's misreadings (a phrase bank of elevations, shot sizes, frame regions
and rolls), read as a development corpus: a line standing for the horizon (the table line, the
edge of the desk, the skyline, the line where grass meets sky) kept, got or said to run level, said
not to slope, a camera leaning neither way; such a line said to run or appear turned (the camera
turned the other way); a roll's direction said round about ("in the clockwise sense", "the
anticlockwise way", ", going clockwise", "to the counter-clockwise side"), a comma, a slight word
or a particle between a roll's parts, degrees "on the camera's roll", "a dozen degrees"; the
picture as made or held ("the result", "a handheld feel") is never a subject; pointing N degrees
below the horizontal (looking down, so above), a whisker or a few centimetres (slightly), "hi" and
"lo" angles and the shot list's "HA" / "LA", up in the air (bird's-eye), oneself brought down to
the subject's level (eye level); a third said as a column, strip or band of a frame split in three
or by its place in a row ("the first column on the left"); a subject spilling past every edge, or
too big to fit (close-up); a size word as the shot's noun ("Medium on the armchair", "a tight one");
the upper (lower) edge of the frame as its top (bottom).

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.translate.vocabulary import words

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "cushion", "ball", "tree", "bookshelf"]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


LEVEL = [
    # A line standing for the horizon kept, got or said to run level.
    "the sofa, keep the floor line level",
    "the mug from the front; the edge of the desk must stay perfectly flat",
    "ball in the middle, and get the skyline dead level please",
    "the bench, the sky line behind it should be totally level",
    "the armchair, the horizon line in the background runs straight across the frame",
    "the toy car with the worktop edge nice and straight",
    # Said not to slope.
    "vase; the horizon mustn't tilt at all",
    "teddy bear - the desk edge must not slope whatsoever",
    "the cushion, and the line where the lawn meets the sky shouldn't lean either way",
    # An absence of slanting, a camera leaning neither way.
    "no sloping on the cushion shot, please",
    "the armchair with the camera tilted to neither side",
    "the toy car, camera not leaning either way",
    "the bookshelf, lens not tipping left or right",
]


@pytest.mark.parametrize("text", LEVEL)
def test_a_level_line_or_camera_is_no_roll(text):
    p = parse(text)
    assert p.roll_deg == 0.0, p.not_understood()


ROLLS = [
    # A line in the picture said to run or appear turned: the camera turned the other way.
    ("the sofa; in the photo the floor line should look tilted 12 degrees clockwise", -12.0),
    ("the mug, the edge of the desk behind it should appear to dip eight degrees counterclockwise", 8.0),
    ("bench: the line where the lawn meets the sky runs 20 degrees anticlockwise off level", 20.0),
    ("the ball, the skyline sloping 10 degrees clockwise", -10.0),
    ("the vase, the horizon line tilted by 5 degrees clockwise", -5.0),
    # A comma, a slight word or a particle between a roll's parts.
    ("the ball, roll the camera to the right, twelve degrees or so", 12.0),
    ("tilt the lens to the left, 20 degrees, the teddy bear", -20.0),
    ("lean the lens over by 25 degrees, going clockwise, the sofa", 25.0),
    ("the tree, tip the cam sideways a bit, 7 degrees anticlockwise", -7.0),
    # A direction said round about.
    ("the armchair, cant the camera 10 degrees in the counterclockwise sense", -10.0),
    ("the bench with the camera rotated 15 degrees the clockwise way", 15.0),
    ("the cushion with a 10 degree tilt in the anticlockwise direction", -10.0),
    ("a gentle twelve-degree roll to the counterclockwise side, the vase", -12.0),
    # Degrees said of the camera's roll; a dozen.
    ("the mug, 20 degrees clockwise on the camera's roll", 20.0),
    ("the bookshelf: 6 degrees anticlockwise for the lens's roll", -6.0),
    ("the teddy bear, a dozen degrees of clockwise roll", 12.0),
    ("the sofa, camera canted half a dozen degrees clockwise", 6.0),
]


@pytest.mark.parametrize(("text", "roll"), ROLLS)
def test_rolls(text, roll):
    p = parse(text)
    assert p.roll_deg == roll, p.not_understood()


@pytest.mark.parametrize(
    ("text", "roll"),
    [
        # Keep-probes: the horizon turned, the camera turned, a pitch, a plain lean.
        ("the bench with the horizon tilted 10 degrees clockwise", -10.0),
        ("the tree, rolled 10 degrees clockwise", 10.0),
        ("the cushion, a 10 degree clockwise tilt", 10.0),
        ("the vase, camera leaning to the left", -15.0),
        ("the mug, horizon level", 0.0),
        ("the ball, camera tilted up", None),
        ("the bear, not tilted up", None),
    ],
)
def test_roll_keep_probes(text, roll):
    assert parse(text).roll_deg == roll


def test_a_dozen_is_twelve():
    assert words("a dozen degrees") == ["12", "degrees"]
    assert words("half a dozen degrees") == ["6", "degrees"]


@pytest.mark.parametrize(
    "text",
    [
        "the mug with a handheld, loose feel, camera rolled 10 degrees clockwise",
        "when you look at the result the bench should be on the left",
        "the vase, and in the print the horizon runs level",
    ],
)
def test_the_picture_as_made_or_held_is_no_subject(text):
    assert len(parse(text).subjects) == 1


ELEVATIONS = [
    # Pointing N degrees below (above) the horizontal: looking down (up), so above (below).
    ("the mug, camera pointing twenty degrees below the horizontal", ("deg", 20.0)),
    ("tilt the lens so it aims 30 degrees below the horizon, the bench", ("deg", 30.0)),
    ("the sofa, lens angled 15 degrees above the horizontal", ("deg", -15.0)),
    # A whisker, a few centimetres or an inch or two: slightly.
    ("the vase from a whisker above", ("name", "slightly above")),
    ("the sofa, camera a whisker below its seat", ("name", "slightly below")),
    ("the cushion with the camera a few centimetres above its top", ("name", "slightly above")),
    ("the teddy bear, lens an inch or two below his chin", ("name", "slightly below")),
    # Clipped and abbreviated angles.
    ("hi angle on the mug", ("name", "high angle")),
    ("a hi-angle shot of the bench", ("name", "high angle")),
    ("lo angle on the toy car", ("name", "low angle")),
    ("BENCH / LA / WS", ("name", "low angle")),
    ("Mug, HA, CU", ("name", "high angle")),
    # Up in the air or the sky: a bird's-eye view.
    ("the ball from way up in the air", ("name", "bird's-eye")),
    ("tree, camera high up in the sky looking down", ("name", "bird's-eye")),
    # Oneself brought to the subject's level.
    ("get down to the teddy bear's level", ("name", "eye level")),
    ("come down to the mug's level", ("name", "eye level")),
    ("climb up to the sofa's height", ("name", "eye level")),
    ("kneel down to its level, the vase", ("name", "eye level")),
]


@pytest.mark.parametrize(("text", "expected"), ELEVATIONS)
def test_elevations(text, expected):
    p = parse(text)
    kind, value = expected
    assert (p.elevation_deg if kind == "deg" else p.elevation) == value, p.not_understood()


@pytest.mark.parametrize(
    ("text", "elevation", "degrees"),
    [
        # Keep-probes: degrees below (above) the horizon without a pointing verb are where the
        # camera is; laughter is no angle; getting down low stays a low angle.
        ("the vase, 20 degrees below the horizon", None, -20.0),
        ("the ball from 30 degrees above the horizontal", None, 30.0),
        ("ha, the mug from the left", None, None),
        ("ha ha, the mug from the left", None, None),
        ("get down low, the mug", "low angle", None),
        ("the mug from a high angle", "high angle", None),
    ],
)
def test_elevation_keep_probes(text, elevation, degrees):
    p = parse(text)
    assert (p.elevation, p.elevation_deg) == (elevation, degrees)


REGIONS = [
    # A third said as a column, a strip or a band, with the frame said split in three.
    ("the vase in the right-hand column if the picture is cut into thirds", "right third"),
    ("the mug in the left strip when the frame is split in three", "left third"),
    ("the bench in the middle band if you divide the shot into 3 equal parts", "center third"),
    ("the sofa in the right band of the thirds grid", "right third"),
    # By its place in a row.
    ("ball in the first column on the left", "left third"),
    ("the sofa in the last band on the right", "right third"),
    # "The middle (centre) column" alone stays the centre (a keep-probe of parse18o): its box
    # holds the middle third's centre, and no grid was said.
    ("the bench in the middle column", "center"),
    # The upper (lower) edge is the top (bottom).
    ("the vase hugging the upper edge of the frame", "top"),
    ("the mug along the lower edge", "bottom"),
]


@pytest.mark.parametrize(("text", "region"), REGIONS)
def test_regions(text, region):
    p = parse(text)
    assert p.subjects[0].region == region, p.not_understood()


@pytest.mark.parametrize(
    ("text", "region"),
    [
        # Keep-probes: a side strip without three said stays that side.
        ("the mug in the left strip", "left"),
        ("the mug in the left half of the frame", "left"),
        ("the vase in the right third", "right third"),
    ],
)
def test_region_keep_probes(text, region):
    assert parse(text).subjects[0].region == region


SHOTS = [
    # Spilling or running past every edge.
    ("teddy bear so close his ears spill past the edges", "close-up"),
    ("the cushion so near that it spills over every edge of the frame", "close-up"),
    ("the sofa, its arms running past both sides of the picture", "close-up"),
    # Too big to fit.
    ("the ball so big it won't fit", "close-up"),
    ("the mug so huge it doesn't quite fit in the frame", "close-up"),
    ("the vase too large to fit in the shot", "close-up"),
    ("the tree, too big for the frame", "close-up"),
    # A size word as the shot's noun.
    ("Medium on the sofa, from the front", "medium"),
    ("the bench - a medium, from the left", "medium"),
    ("a medium, the vase, eye level", "medium"),
    ("the mug in a medium", "medium"),
    ("the tree, a tight one", "close-up"),
    ("a tight one of the ball", "close-up"),
]


@pytest.mark.parametrize(("text", "shot"), SHOTS)
def test_shots(text, shot):
    p = parse(text)
    assert p.subjects[0].shot == shot, p.not_understood()


@pytest.mark.parametrize(
    ("text", "shot"),
    [
        # Keep-probes: it fits, so all of it is in.
        ("the bench, it fits in the frame", "medium"),
        ("the sofa so it just fits", "medium"),
        ("the mug filling the frame edge to edge", "close-up"),
        ("a medium close-up of the bench", "close-up"),
        ("a medium shot of the mug", "medium"),
    ],
)
def test_shot_keep_probes(text, shot):
    assert parse(text).subjects[0].shot == shot
