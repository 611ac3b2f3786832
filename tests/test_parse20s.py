"""Shot-size families of the development sets' remaining misreadings (parse20s):

* a size word as a verb's complement or before a place ("make small", "tuck it small into the
  lower left", "tucked away small at the top right", "a bit small in the top right"), said in
  parentheses ("the teddy (medium-ish)"), or right after its subject for medium ("chair medium");
* small in a roomy whole other than the frame ("small in a big landscape", "tiny in a vast room");
* a shot name as a label before a colon ("Wide: the couch ...", "Tight: the mug ...");
* the subject filling the frame said as a result clause ("so close it's all you can see", "close
  enough that he fills most of it") or crammed "edge to edge" into the frame;
* shot words as dictation hears them ("clothes up" for close up, "why'd shot" for wide shot);
* the subject said whole after a verb of being ("it must be whole in picture").

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

NAMES = ["sofa", "bench", "armchair", "mug", "vase", "teddy bear", "toy car", "television", "traffic cone", "ball"]
parse = parser_of(scene_of(NAMES))
# A scene with a tree called "small tree": a size word before a place is no mention of it.
parse_tree = parser_of(scene_of(["traffic cone", "bench", "small tree"]))


def _read(text, parser=parse):
    p = parser(text)
    return p, p.subjects[0]


SIZE_AS_COMPLEMENT = [
    ("the sofa from the front please, make small", "wide", None),
    ("the vase, make it tiny", "wide", None),
    ("the mug from above, make big", "close-up", None),
    ("the ball; tuck it small into the upper right", "wide", "upper right"),
    ("the bench, tucked away tiny in the bottom left corner", "wide", "lower left"),
    ("the television, tucked small at the top left of the frame", "wide", "upper left"),
    ("the mug, a bit small in the top right", "wide", "upper right"),
    ("the teddy bear from behind and small-ish in the lower left", "wide", "lower left"),
    ("the armchair, big in the middle", "close-up", "center"),
    ("the toy car, medium-sized at the bottom", "medium", "bottom"),
    ("the vase (medium), from the left", "medium", None),
    ("the bench (wide), from behind", "wide", None),
    ("the teddy bear (small-ish) and from the front", "wide", None),
    ("shoot it from a little above, armchair medium.", "medium", None),
    ("the sofa from its left, sofa medium, eye level", "medium", None),
]


@pytest.mark.parametrize(("text", "shot", "region"), SIZE_AS_COMPLEMENT)
def test_a_size_word_as_a_complement_or_before_a_place(text, shot, region):
    p, s = _read(text)
    assert (s.shot, s.region) == (shot, region)
    assert not p.not_understood()


def test_a_size_word_before_a_place_is_no_mention_of_a_name_holding_it():
    p = parse_tree("the cone, small in the lower left")
    assert [s.name for s in p.subjects] == ["traffic cone"]
    assert (p.subjects[0].shot, p.subjects[0].region) == ("wide", "lower left")


SMALL_IN_A_ROOMY_WHOLE = [
    "the bench, small in a big landscape",
    "teddy bear tiny in a vast landscape, from behind",
    "the sofa, small in a huge room",
    "the traffic cone, little in a wide empty scene",
    "the ball, small within a big open field",
]


@pytest.mark.parametrize("text", SMALL_IN_A_ROOMY_WHOLE)
def test_small_in_a_roomy_whole_is_wide(text):
    p, s = _read(text)
    assert s.shot == "wide"
    assert not p.not_understood()


LABELS = [
    ("Wide: the sofa seen from behind", "wide"),
    ("WIDE: bench, front", "wide"),
    ("Tight: the mug from above", "close-up"),
    ("Close: toy car, its front", "close-up"),
    ("Long shot: the bench from its left", "wide"),
    ("Shot 3. Wide: the armchair, eye level", "wide"),
]


@pytest.mark.parametrize(("text", "shot"), LABELS)
def test_a_shot_name_as_a_label_before_a_colon(text, shot):
    p, s = _read(text)
    assert s.shot == shot
    assert not p.not_understood()


RESULT_CLAUSES = [
    "the vase so close it's all you can see",
    "the mug, near enough that it's all we see",
    "the teddy bear, so close they're all you can see",
    "the sofa, close enough that it fills most of it",
    "the teddy bear from behind, close enough that he fills most of it",
    "the television, big enough that it takes up the whole frame",
    "the toy car, so big it is the only thing you see",
    "the mug crammed edge to edge in the frame",
    "the bench, squeezed side to side into the picture",
]


@pytest.mark.parametrize("text", RESULT_CLAUSES)
def test_the_subject_filling_the_frame_as_a_result_clause(text):
    p, s = _read(text)
    assert s.shot == "close-up"
    assert not p.not_understood()


HOMOPHONES = [
    ("the toy car, clothes up, from the front", "close-up"),
    ("clothes up of the mug please", "close-up"),
    ("a why'd shot of the bench", "wide"),
    ("the sofa from its right and a why'd view", "wide"),
]


@pytest.mark.parametrize(("text", "shot"), HOMOPHONES)
def test_shot_words_as_dictation_hears_them(text, shot):
    p, s = _read(text)
    assert s.shot == shot
    assert not p.not_understood()


WHOLE_AFTER_BEING = [
    "the vase, it must be whole in picture",
    "the bench should be whole in the frame",
    "the teddy bear from the left, it has to stay complete in the shot",
    "the sofa, it should be uncropped",
]


@pytest.mark.parametrize("text", WHOLE_AFTER_BEING)
def test_whole_after_a_verb_of_being_is_medium(text):
    p, s = _read(text)
    assert s.shot == "medium"
    assert not p.not_understood()


@pytest.mark.parametrize(
    ("text", "shot", "region"),
    [
        # Keep-probes: a size word as an attribute is no shot size; "far" / "close" before a place
        # say where it sits, not how big; a relation to another object is none either.
        ("the small vase from the left", None, None),
        ("a small mug in the lower left", None, "lower left"),
        ("the mug close to the left edge of the frame", None, "left"),
        ("the mug, close to the sofa", None, None),
        ("the bench, small", "wide", None),
        ("the sofa, big, from the front", "close-up", None),
        ("the bench in the lower left, small", "wide", "lower left"),
        ("Left: the mug from above", None, None),
        ("the armchair (from the left)", None, None),
    ],
)
def test_size_keep_probes(text, shot, region):
    s = parse(text).subjects[0]
    assert (s.shot, s.region) == (shot, region)


def test_a_question_with_why_d_reads_no_size():
    p = parse("the sofa from the front, why'd you crop it")
    assert p.subjects[0].shot != "wide"


LITTLE_ROOM = [
    # A little room of any kind round the whole subject is a medium shot, as a small margin is;
    # plenty of it stays wide.
    ("the toy car, keep the whole car in frame with a bit of air around it", "medium"),
    ("the vase with a touch of table all round", "medium"),
    ("the whole television, a little wall on each side", "medium"),
    ("the bench with plenty of grass around it", "wide"),
    ("the sofa with lots of room around it", "wide"),
]


@pytest.mark.parametrize(("text", "shot"), LITTLE_ROOM)
def test_a_little_room_round_it_is_medium(text, shot):
    p, s = _read(text)
    assert s.shot == shot
    assert not p.not_understood()


def test_a_shot_with_another_object_in_view_is_the_subjects():
    p = parse("the television from its left side, in a wide shot with the sofa in view")
    assert [(s.name, s.shot) for s in p.subjects] == [("television", "wide"), ("sofa", None)]
    p = parse("the mug from above, a close shot with the vase visible too")
    assert [(s.name, s.shot) for s in p.subjects] == [("mug", "close-up"), ("vase", None)]


def test_the_frame_said_empty_round_its_area_is_wide():
    for text, region in [
        ("a small cone in the lower left of a big empty frame", "lower left"),
        ("the mug in the top right of an otherwise empty picture", "upper right"),
    ]:
        p, s = _read(text)
        assert (s.shot, s.region) == ("wide", region)
        assert not p.not_understood()


OWN_WORDINGS = [
    # Learners' and children's sizes: a distance bare after "from"/"at", a size as a noun
    # phrase, a doubled diminutive, a shot word as a noun, a label of the medium close-up.
    ("take picture of bench from far", "wide"),
    ("take the sofa from little far", "wide"),
    ("photo of the bench from near", "close-up"),
    ("the sofa at a distance", "wide"),
    ("the mug in big size", "close-up"),
    ("the vase in small size", "wide"),
    ("the ball teeny weeny", "wide"),
    ("the mug as a wide", "wide"),
    ("the armchair, a wide, from behind", "wide"),
    ("wide-ish on the bench", "wide"),
    ("Medium close: the mug", "close-up"),
    ("the vase, closer up", "close-up"),
]


@pytest.mark.parametrize(("text", "shot"), OWN_WORDINGS)
def test_more_sizes_said_as_people_say_them(text, shot):
    p, s = _read(text)
    assert s.shot == shot
    assert not p.not_understood()


@pytest.mark.parametrize(
    "text",
    [
        # Keep-probes: "near"/"from near" an object is a relation, no size.
        "the mug near the sofa",
        "the mug from near the sofa",
    ],
)
def test_near_an_object_is_no_size(text):
    assert parse(text).subjects[0].shot is None
