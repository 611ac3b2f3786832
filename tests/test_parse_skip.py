"""A word that breaks a phrase the tables know is left out and the rest read
(:meth:`~capframe.translate.parse.RuleParser._skipping_a_word`): the reading of a sentence whose
clause was not understood is tried again without one of its words; it is kept when it keeps
every field read before and adds one (or, for a word the tables do not know, reads a value in
full: "back ... right diagonal" is back-right, not back), and the word left out is reported.

Conventions (DESIGN §3): azimuth 0 is the subject's front, +90 its own right, -90 its own left;
roll > 0 is the camera turned clockwise. None of these wordings is in a suite file."""

from __future__ import annotations

import pytest
from _parse_helpers import parser_of, scene_of

from capframe.errors import InputError
from capframe.translate.parse import shared_parser
from capframe.translate.vocabulary import DETERMINERS, words

NAMES = ["armchair", "sofa", "mug", "teddy bear", "bench", "toy car", "vase", "cushion", "ball"]
SCENE = scene_of(NAMES)
parse = parser_of(SCENE)


# (text, field, value, the word left out): a table word or an unknown one inside a known phrase
BROKEN_PHRASES = [
    ("teddy bear seen from its left flank side", "view", "left", "side"),
    ("toy car, headlights pointed straight glossy at the lens", "view", "front", "glossy"),
    ("the sofa from its back blorp right diagonal", "view", "back-right", "blorp"),
    ("the armchair from its right, slightly quibbly to the front", "view", "right-slight-front", "quibbly"),
    ("the vase small in the shimmering frame", "shot", "wide", "shimmering"),
    ("the cushion in the left hand zanzy third of the image", "region", "left third", "zanzy"),
]


@pytest.mark.parametrize(("text", "field", "value", "word"), BROKEN_PHRASES)
def test_a_word_breaking_a_known_phrase_is_left_out_and_reported(text, field, value, word):
    p = parse(text)
    assert getattr(p.subjects[0], field) == value
    assert word in p.not_understood()


def test_an_unknown_word_inside_a_roll_or_a_pitch_is_left_out():
    rolled = parse("dutch angle, 20 degrees flurbish counterclockwise, the bear in the middle")
    assert rolled.roll_deg == -20.0 and rolled.subjects[0].region == "center"
    pitched = parse("the ball, camera at 40 murky degrees above it")
    assert pitched.elevation_deg == 40.0


# Nothing is left out that says something: a negation, a name's neighbour, a table word that
# would change a value ("almost on the floor" is no eye level).
KEPT = [
    ("the mug, not from above", {"elevation": None}),
    ("Bear up front, the vase visible too", {"view": None}),
    ("camera resting almost on the floor, angled upward at the bear", {"elevation": "low angle"}),
]


@pytest.mark.parametrize(("text", "fields"), KEPT)
def test_a_word_that_says_something_is_never_left_out(text, fields):
    p = parse(text)
    for field, value in fields.items():
        held = getattr(p, field) if field == "elevation" else getattr(p.subjects[0], field)
        assert held == value
    assert p.understood == "partly"


FULLY_READ = [
    "the sofa from its back right diagonal, low",
    "teddy bear from behind on his left, eye level",
    "the armchair from its right, slightly to the front, medium shot",
    "the vase in the left third of the frame, a bit from above",
    "dutch angle, 20 degrees counterclockwise, the bench from the front",
]


@pytest.mark.parametrize("text", FULLY_READ)
def test_an_unknown_word_anywhere_inside_a_clause_changes_no_reading(text):
    """Robustness: one unknown word put between any two words of a fully read sentence leaves
    every field as it was; not beside a name or a comma, and not after a determiner (there it is
    a thing: "the glorp" is refused as a subject the scene lacks)."""
    parser = shared_parser()
    said = words(text)
    names = {w for form in SCENE.forms() for w in form}
    whole = parse(text)
    assert whole.understood == "fully"
    for i in range(1, len(said)):
        if {said[i - 1], said[i]} & (names | {",", "."}) or said[i - 1] in DETERMINERS:
            continue
        broken = parser.parse(" ".join([*said[:i], "glorp", *said[i:]]), SCENE)
        assert broken.constraints() == whole.constraints(), " ".join([*said[:i], "glorp", *said[i:]])


def test_the_parse_only_bench_counts_readings_kept_with_an_unknown_word_inside():
    """:func:`~capframe.bench.parse_only.interruption_kept`: a fully read instruction keeps its
    reading with the word put inside it; one not fully read, or refused, is not counted."""
    import random

    from capframe.bench.parse_only import ParseOutcome, interruption_kept
    from capframe.evaluate.spec import InstructionSpec

    def outcome(text: str) -> ParseOutcome:
        spec = InstructionSpec("x", "s", text, "view", True, None, None)
        try:
            read = parse(text)
            return ParseOutcome(spec, partly=read.not_understood(), constraints=read.constraints())
        except InputError as err:
            return ParseOutcome(spec, refused=str(err))

    rng = random.Random(0)
    assert all(interruption_kept(shared_parser(), SCENE, outcome(t), rng) for t in FULLY_READ)
    assert interruption_kept(shared_parser(), SCENE, outcome("the mug, not from above"), rng) is None
    assert interruption_kept(shared_parser(), SCENE, outcome("the giraffe from the left"), rng) is None
