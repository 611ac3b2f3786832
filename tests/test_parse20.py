"""The families of heldout17's misreadings (a held-out set, blind until the third session of
2026-11-28, a development set since): a side said twice, the second time more precisely ("from
behind, a bit to the left - over its left shoulder"); a side in a sentence of its own after the
subject's ("BENCH. Right flank."); a front part turned to the viewer ("its nose toward us", "snout
right in the lens"); the whole of a generic noun standing for the subject ("the whole model in
frame"); the whole frame rolled as "everything" or "the rig"; a height in degrees said as looked
down (up) on from them; a filler "like" before an emphatic word ("like SUPER close"); "picture" and
"photo" with a letter dropped.

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.errors import InputError

NAMES = ["sofa", "bench", "armchair", "mug", "vase", "teddy bear", "toy car", "television", "cushion"]
parse = parser_of(scene_of(NAMES))


@pytest.mark.parametrize(
    ("text", "view"),
    [
        # The narrower side lies inside the wider one's range: it is the one meant.
        ("the sofa from behind, slightly to its right, over its right shoulder", "back-slight-right"),
        ("the armchair from the rear, a touch to the left, over its left shoulder", "back-slight-left"),
        ("the bench, front left, a little to the left of straight on", "front-slight-left"),
    ],
)
def test_a_side_said_again_more_precisely_is_the_precise_one(text, view):
    assert parse(text).subjects[0].view == view


@pytest.mark.parametrize(
    "text",
    [
        # Keep-probes: sides whose ranges do not hold each other's azimuth still conflict.
        "The sofa, slightly to its left, from its right.",
        "the bench from the front, from behind",
        "the armchair, back left, front right",
    ],
)
def test_sides_apart_still_conflict(text):
    with pytest.raises(InputError, match="conflicting view"):
        parse(text)


@pytest.mark.parametrize(
    ("text", "view"),
    [
        ("SOFA. Left side.", "left"),
        ("Bench. Right flank. Low.", "right"),
        ("armchair. right hand side. medium", "right"),
    ],
)
def test_a_side_in_a_sentence_of_its_own_after_the_subject(text, view):
    p = parse(text)
    assert p.subjects[0].view == view
    assert p.understood == "fully", p.not_understood()


def test_a_side_of_the_frame_in_its_own_sentence_stays_a_region():
    p = parse("The mug. Left side of the frame.")
    assert (p.subjects[0].view, p.subjects[0].region) == (None, "left")


@pytest.mark.parametrize(
    "text",
    [
        "the toy car, its nose toward us",
        "the toy car with its grille towards me",
        "teddy bear, muzzle right in the lens",
        "the teddy bear, its snout straight at the camera",
    ],
)
def test_a_front_part_turned_to_the_viewer_is_the_front(text):
    p = parse(text)
    assert p.subjects[0].view in ("front", "front-exact")
    assert p.understood == "fully", p.not_understood()


@pytest.mark.parametrize(
    "text",
    [
        "the bench, the whole model in frame",
        "the sofa from the left, entire object in view",
        "the armchair, full item visible",
    ],
)
def test_the_whole_of_a_generic_noun_is_all_of_the_subject(text):
    assert parse(text).subjects[0].shot == "medium"


@pytest.mark.parametrize(
    ("text", "roll"),
    [
        ("the mug, cant everything 10 degrees anticlockwise", -10.0),
        ("the vase, tilt the whole rig 20 degrees clockwise", 20.0),
        ("sofa straight on, rotate everything fifteen degrees clockwise", 15.0),
    ],
)
def test_everything_or_the_rig_turned_is_the_camera(text, roll):
    assert parse(text).roll_deg == roll


@pytest.mark.parametrize(
    ("text", "degrees"),
    [
        ("the bench looked down on from about 40 degrees", 40.0),
        ("the cushion, looked down at from 55 degrees", 55.0),
        ("the vase looked up at from twenty degrees", -20.0),
    ],
)
def test_looked_down_on_from_degrees_is_that_elevation(text, degrees):
    assert parse(text).elevation_deg == degrees


@pytest.mark.parametrize(
    ("text", "field", "value"),
    [
        ("the mug like really close", "shot", "close-up"),
        ("can u get the vase like super close pls", "shot", "close-up"),
        ("the bench, camera like really low", "elevation", "low angle"),
    ],
)
def test_a_filler_like_before_an_emphatic_word_is_left_out(text, field, value):
    p = parse(text)
    assert (p.subjects[0].shot if field == "shot" else p.elevation) == value


def test_a_like_that_compares_stays():
    assert "portrait" in " ".join(parse("the sofa, shot like a portrait").not_understood())


@pytest.mark.parametrize(
    ("text", "region"),
    [
        ("the cushion in the middle of the pictur", "center"),
        ("the vase at the top of the phto", "top"),
    ],
)
def test_picture_and_photo_with_a_letter_dropped(text, region):
    assert parse(text).subjects[0].region == region


@pytest.mark.parametrize(
    ("text", "unknown"),
    [
        # A thing the scene lacks, placed at a named object without a verb, is what is asked.
        ("There's a snow globe behind the cushion; photograph it from the front", "snow globe"),
        ("toaster on top of the television", "toaster"),
        ("a lantern beside the bench, low angle", "lantern"),
        # "that" pointing at a thing that a placing word follows, and what a shot closes in on.
        ("Could you zoom right in on that bell sitting next to the mug?", "bell"),
        ("low angle onto the umbrella stand beside the armchair", "umbrella stand"),
        ("close up on the kettle next to the vase", "kettle"),
    ],
)
def test_an_unknown_thing_placed_at_a_named_object_is_refused(text, unknown):
    with pytest.raises(InputError, match=f"subject '{unknown}' is not in this scene"):
        parse(text)


@pytest.mark.parametrize(
    "text",
    [
        # Keep-probes: a known subject before a landmark, a camera or a shot word before a place,
        # and "on" (what a camera does, not where a thing is) keep their readings.
        "the mug behind the vase, close",
        "camera behind the sofa, low",
        "focus on the mug",
        "spotlight on the teddy bear",
        "bench, the armchair behind it",
        "dead centre in front of the sofa",
    ],
)
def test_known_subjects_and_camera_words_before_a_place_stay_read(text):
    assert parse(text).subjects


@pytest.mark.parametrize(
    "text", ["Stand in front of the bench, then shoot it low", "step beside the sofa and shoot its left side"]
)
def test_where_the_photographer_stands_is_no_thing_placed(text):
    assert parse(text).subjects[0].name in ("bench", "sofa")
