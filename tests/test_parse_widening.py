"""The rule parser's wider phrasing (issue #15, item 2): side words in noun phrases, three-quarter
with a side, degree words, two ends of the subject together, zoom and size words, polite forms.
Every row gives the exact structure expected; the negative rows keep side and position words out
of subjects and contradictions as errors."""

from __future__ import annotations

import json

import pytest

from capframe.errors import InputError
from capframe.scene import SemanticObject
from capframe.translate.instruction import JSON_SCHEMA, ParsedInstruction
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary, one_edit

# A living room as the synthetic scenes name it: two chairs told apart by colour, symmetric vase.
SCENE = Vocabulary.from_semantics(
    [
        SemanticObject(0, "teddy bear", ["bear", "plush toy"], False),
        SemanticObject(1, "red armchair", ["chair", "red chair"], False),
        SemanticObject(2, "blue armchair", ["chair", "blue chair"], False),
        SemanticObject(3, "vase", ["flower vase"], True),
        SemanticObject(4, "sofa", ["couch", "settee"], False),
        SemanticObject(5, "television", ["tv", "tv set"], False),
        SemanticObject(6, "refrigerator", ["fridge"], False),
    ]
)


def subject(name: str, region: str | None = None, shot: str | None = None, view: str | None = None) -> dict:
    return {"name": name, "region": region, "shot": shot, "view": view}


def parsed(*subjects: dict, elevation: str | None = None, elevation_deg: float | None = None, unparsed=()) -> dict:
    return {"subjects": list(subjects), "elevation": elevation, "elevation_deg": elevation_deg, "unparsed": list(unparsed)}


def structure(text: str) -> dict:
    p = parse_instruction(text, SCENE)
    subjects = [subject(s.name, s.region, s.shot, s.view) for s in p.subjects]
    return parsed(*subjects, elevation=p.elevation, elevation_deg=p.elevation_deg, unparsed=p.unparsed)


def check(rows: list[tuple[str, dict]]) -> list:
    return [pytest.param(text, want, id=text) for text, want in rows]


BEAR, SOFA, TV, FRIDGE, VASE = "teddy bear", "sofa", "television", "refrigerator", "vase"
RED, BLUE = "red armchair", "blue armchair"

# --- side words in noun phrases: possessives, "the back of the X" --------------------------------

SIDE_NOUNS = [
    ("A photo of the sofa's left side.", parsed(subject(SOFA, view="left"))),
    ("The bear's back, from slightly above.", parsed(subject(BEAR, view="back"), elevation="slightly above")),
    ("Show me the back of the red chair.", parsed(subject(RED, view="back"))),
    ("A close-up of the front of the TV.", parsed(subject(TV, shot="close-up", view="front"))),
    ("The left side of the couch, on the right of the frame.", parsed(subject(SOFA, region="right", view="left"))),
    ("Photograph the fridge's rear.", parsed(subject(FRIDGE, view="back"))),
    ("The bear, its rear to the camera.", parsed(subject(BEAR, view="back"))),
    ("The bear, showing its rear.", parsed(subject(BEAR, view="back"))),
    ("A picture of the teddy bear's face, filling the frame.", parsed(subject(BEAR, shot="close-up", view="front"))),
    ("The blue chair's right-hand side.", parsed(subject(BLUE, view="right"))),
    ("The bear's left profile.", parsed(subject(BEAR, view="left"))),
    ("The side of the sofa.", parsed(subject(SOFA, view="side"))),
    ("The bear in profile.", parsed(subject(BEAR, view="side"))),
    ("A side view of the TV, from the right.", parsed(subject(TV, view="right"))),
    ("The sofa, its back left.", parsed(subject(SOFA, view="back-left"))),
    # Other words for the back.
    ("The sofa's backside, from slightly above.", parsed(subject(SOFA, view="back"), elevation="slightly above")),
    ("Show me the rear end of the fridge.", parsed(subject(FRIDGE, view="back"))),
    ("The bear's behind.", parsed(subject(BEAR, view="back"))),
    # Closing in on a side names the side, not a relation ("on its face" is not "on its left").
    ("The TV, close on its front.", parsed(subject(TV, shot="close-up", view="front"))),
    ("Zoom in on the bear's back.", parsed(subject(BEAR, shot="close-up", view="back"))),
    ("Tight on the sofa's left side.", parsed(subject(SOFA, shot="close-up", view="left"))),
]

# A side word after a preposition of place is a relation between objects: not understood, and
# never a subject; nor is any other position word.
NOT_SUBJECTS = [
    ("The vase on its left.", parsed(subject(VASE), unparsed=["left"])),
    ("The bear with its back to the wall.", parsed(subject(BEAR), unparsed=["back to the wall"])),
    ("The bear to the left of the vase.", parsed(subject(BEAR), subject(VASE), unparsed=["left"])),
    ("The vase on the sofa's right.", parsed(subject(VASE), subject(SOFA), unparsed=["right"])),
    ("A photo of the top of the red chair.", parsed(subject(RED), unparsed=["top"])),
    ("A close-up of the underside of the bear.", parsed(subject(BEAR, shot="close-up"), unparsed=["underside"])),
    ("A photo of the left, the bear.", parsed(subject(BEAR), unparsed=["left"])),
    ("Frame the bear and the back.", parsed(subject(BEAR), unparsed=["back"])),
    ("Frame the left side and the sofa.", parsed(subject(SOFA), unparsed=["left side"])),
    # A generic noun with attributes names nothing.
    ("The bear and that small thing.", parsed(subject(BEAR), unparsed=["small thing"])),
    ("The big object behind the sofa.", parsed(subject(SOFA), unparsed=["big object behind"])),
]

# --- three-quarter with a side --------------------------------------------------------------------

THREE_QUARTER = [
    ("A three-quarter view of the bear from the left.", parsed(subject(BEAR, view="front-left"))),
    ("A three-quarter view from the left of the bear.", parsed(subject(BEAR, view="front-left"))),
    ("The bear in three-quarter view, seen from its right.", parsed(subject(BEAR, view="front-right"))),
    ("The sofa from its left, at a three-quarter angle.", parsed(subject(SOFA, view="front-left"))),
    ("The TV, three-quarter left view.", parsed(subject(TV, view="front-left"))),
    ("A rear three-quarter view of the sofa from the right.", parsed(subject(SOFA, view="back-right"))),
    ("The sofa, rear three-quarter, from its left.", parsed(subject(SOFA, view="back-left"))),
    ("The bear in a rear three-quarter view.", parsed(subject(BEAR, view="back-three-quarter"))),
    ("The bear in three-quarter view from behind.", parsed(subject(BEAR, view="back-three-quarter"))),
    ("The bear at three-quarters, from behind on its left.", parsed(subject(BEAR, view="back-left"))),
    (
        "A three-quarter view of the bear on the left of the frame, from its left, with the vase on the right.",
        parsed(subject(BEAR, region="left", view="front-left"), subject(VASE, region="right")),
    ),
]

# --- degree words -----------------------------------------------------------------------------------

DEGREES = [
    ("The bear, slightly from the left.", parsed(subject(BEAR, view="front-slight-left"))),
    ("The bear, a bit to its left.", parsed(subject(BEAR, view="front-slight-left"))),
    ("The sofa seen a little from its right.", parsed(subject(SOFA, view="front-slight-right"))),
    ("The TV from slightly to the right.", parsed(subject(TV, view="front-slight-right"))),
    ("The fridge, with the camera somewhat to the left of it.", parsed(subject(FRIDGE, view="front-slight-left"))),
    ("The bear facing slightly left.", parsed(subject(BEAR, view="front-slight-left"))),
    ("The bear, directly from the left.", parsed(subject(BEAR, view="left-exact"))),
    ("The sofa, seen squarely from the front.", parsed(subject(SOFA, view="front-exact"))),
    ("The TV from directly behind.", parsed(subject(TV, view="back-exact"))),
    ("The red chair in a full right side view.", parsed(subject(RED, view="right-exact"))),
    ("The bear from straight in front.", parsed(subject(BEAR, view="front-exact"))),
    # A slight word before a front, back or diagonal is not understood: the side stays, the word is reported.
    ("The bear, slightly from behind.", parsed(subject(BEAR, view="back"), unparsed=["slightly"])),
    ("The bear seen slightly to the left.", parsed(subject(BEAR, view="front-slight-left"))),
    ("The bear, shot a bit to the right.", parsed(subject(BEAR, view="front-slight-right"))),
    # "Slightly to the left" naming no subject is where it sits in the frame.
    ("The bear slightly to the left.", parsed(subject(BEAR, region="left"), unparsed=["slightly"])),
    ("The bear a bit to the right.", parsed(subject(BEAR, region="right"), unparsed=["bit"])),
    # Heights.
    ("The bear from straight down.", parsed(subject(BEAR), elevation="top-down")),
    ("The sofa, directly above it.", parsed(subject(SOFA), elevation="top-down")),
    ("A top-down view of the sofa.", parsed(subject(SOFA), elevation="top-down")),
    ("The bear, looking vertically down on it.", parsed(subject(BEAR), elevation="top-down")),
    ("The vase as a flat lay.", parsed(subject(VASE), elevation="top-down")),
    ("The bear from overhead, looking straight down.", parsed(subject(BEAR), elevation="top-down")),
    ("The bear, steeply from above.", parsed(subject(BEAR), elevation="bird's-eye")),
    ("The bear, a bit from above.", parsed(subject(BEAR), elevation="slightly above")),
    ("The bear with the camera a little higher than it.", parsed(subject(BEAR), elevation="slightly above")),
    ("The bear, slightly below it.", parsed(subject(BEAR), elevation="slightly below")),
    ("The bear, looking a bit up at it.", parsed(subject(BEAR), elevation="slightly below")),
    ("The sofa from a low angle, slightly below it.", parsed(subject(SOFA), elevation="slightly below")),
    ("The bear, strongly from below.", parsed(subject(BEAR), elevation="worm's-eye")),
    ("The bear from the top down.", parsed(subject(BEAR), elevation="top-down")),
    ("An aerial view of the sofa.", parsed(subject(SOFA), elevation="bird's-eye")),
    # Hints, as "from above": they yield to anything more specific.
    ("The bear from up high.", parsed(subject(BEAR), elevation="high angle")),
    ("The TV from a lower angle.", parsed(subject(TV), elevation="low angle")),
    ("The TV from a higher angle, slightly above it.", parsed(subject(TV), elevation="slightly above")),
]

# --- two ends together: behind/in front and to one side -------------------------------------------

TWO_ENDS = [
    ("The sofa from behind and to the left.", parsed(subject(SOFA, view="back-left"))),
    ("The sofa, behind and to the left of it.", parsed(subject(SOFA, view="back-left"))),
    ("The sofa from behind, on its right.", parsed(subject(SOFA, view="back-right"))),
    ("Frame the bear from behind on the left.", parsed(subject(BEAR, view="back-left"))),
    ("Show the TV from the rear, on its left.", parsed(subject(TV, view="back-left"))),
    ("The bear, to its right and from behind.", parsed(subject(BEAR, view="back-right"))),
    ("The sofa in front and slightly to the right.", parsed(subject(SOFA, view="front-slight-right"))),
    ("The TV from the front and a little to its left.", parsed(subject(TV, view="front-slight-left"))),
    ("The bear from behind and slightly to the left.", parsed(subject(BEAR, view="back-slight-left"))),
    ("The bear from in front, to its left.", parsed(subject(BEAR, view="front-left"))),
    ("The bear, seen from the front, from its right.", parsed(subject(BEAR, view="front-right"))),
    # Where the camera is put.
    ("Camera positioned to the right of the bear.", parsed(subject(BEAR, view="right"))),
    ("Put the camera behind the sofa.", parsed(subject(SOFA, view="back"))),
    ("The bear, camera to its right.", parsed(subject(BEAR, view="right"))),
    ("The camera slightly to the left of the sofa.", parsed(subject(SOFA, view="front-slight-left"))),
    ("Put the camera in front of the TV, slightly to its right.", parsed(subject(TV, view="front-slight-right"))),
    ("The camera should be behind the sofa and to its left.", parsed(subject(SOFA, view="back-left"))),
    ("Stand behind the bear and shoot.", parsed(subject(BEAR, view="back"))),
    ("Shoot the bear from the far left.", parsed(subject(BEAR, view="left"))),
    ("The sofa viewed from its back-right corner.", parsed(subject(SOFA, view="back-right"))),
    ("The bear, slightly off to the left of it.", parsed(subject(BEAR, view="front-slight-left"))),
    # A side after a comma that names no subject is a region of the frame.
    ("The bear from behind, on the right of the frame.", parsed(subject(BEAR, region="right", view="back"))),
    ("The sofa on the right, seen from its front.", parsed(subject(SOFA, region="right", view="front"))),
    # A view cue that leads into the next subject belongs to it.
    (
        "Seen from the front, the bear; seen from the left, the sofa.",
        parsed(subject(BEAR, view="front"), subject(SOFA, view="left")),
    ),
]


# --- zoom and size words ------------------------------------------------------------------------------

SIZES = [
    ("Zoom in on the bear.", parsed(subject(BEAR, shot="close-up"))),
    ("Zoom in close on the bear, from its left.", parsed(subject(BEAR, shot="close-up", view="left"))),
    ("The sofa, zoomed all the way in.", parsed(subject(SOFA, shot="close-up"))),
    ("Fill the frame with the TV.", parsed(subject(TV, shot="close-up"))),
    ("Let the bear fill the frame.", parsed(subject(BEAR, shot="close-up"))),
    ("The bear, as big as possible in the frame.", parsed(subject(BEAR, shot="close-up"))),
    ("The bear, tight.", parsed(subject(BEAR, shot="close-up"))),
    ("Keep it tight on the fridge.", parsed(subject(FRIDGE, shot="close-up"))),
    ("A tight crop of the bear.", parsed(subject(BEAR, shot="close-up"))),
    ("The bear up close.", parsed(subject(BEAR, shot="close-up"))),
    ("Frame the bear tightly.", parsed(subject(BEAR, shot="close-up"))),
    ("The bear nearly filling the frame.", parsed(subject(BEAR, shot="close-up"))),
    ("The sofa from close range.", parsed(subject(SOFA, shot="close-up"))),
    ("Move in close on the sofa.", parsed(subject(SOFA, shot="close-up"))),
    ("The bear, not too close.", parsed(subject(BEAR, shot="medium"))),
    ("The bear zoomed out.", parsed(subject(BEAR, shot="wide"))),
    ("Zoom out from the sofa.", parsed(subject(SOFA, shot="wide"))),
    ("The bear, wide, from the left.", parsed(subject(BEAR, shot="wide", view="left"))),
    ("Go wide on the TV.", parsed(subject(TV, shot="wide"))),
    ("The bear from far away.", parsed(subject(BEAR, shot="wide"))),
    ("Step back from the bear.", parsed(subject(BEAR, shot="wide"))),
    ("The fridge from further back.", parsed(subject(FRIDGE, shot="wide"))),
    ("The bear, quite small in the frame.", parsed(subject(BEAR, shot="wide"))),
    ("The vase, only a small part of the frame.", parsed(subject(VASE, shot="wide"))),
    ("The vase as a tiny dot on the left.", parsed(subject(VASE, region="left", shot="wide"))),
    ("Back off until the TV is just a little speck.", parsed(subject(TV, shot="wide"), unparsed=["until"])),
    # A size word as an attribute is not a shot size.
    ("The wide sofa.", parsed(subject(SOFA), unparsed=["wide"])),
]

# --- polite and chatty forms --------------------------------------------------------------------------

POLITE = [
    ("Could you show me the bear from the left?", parsed(subject(BEAR, view="left"))),
    ("Could you please take a photo of the sofa?", parsed(subject(SOFA))),
    ("I'd like a picture of the bear.", parsed(subject(BEAR))),
    ("I would like to see the TV from behind, please.", parsed(subject(TV, view="back"))),
    ("Can I get a close-up of the bear?", parsed(subject(BEAR, shot="close-up"))),
    ("Can we have a wide shot of the sofa, please?", parsed(subject(SOFA, shot="wide"))),
    ("Let's see the bear from the left.", parsed(subject(BEAR, view="left"))),
    ("Give me a shot of the fridge.", parsed(subject(FRIDGE))),
    ("I'm looking for a shot of the bear from behind.", parsed(subject(BEAR, view="back"))),
    ("Show me what the sofa looks like from the left.", parsed(subject(SOFA, view="left"))),
    ("Would you mind framing the bear on the left?", parsed(subject(BEAR, region="left"))),
    ("Hey, can you get the bear in the middle? Thanks!", parsed(subject(BEAR, region="center"))),
    ("Maybe a close-up of the bear?", parsed(subject(BEAR, shot="close-up"))),
    ("How about the TV from the front?", parsed(subject(TV, view="front"))),
    ("Take a look at the bear from its left.", parsed(subject(BEAR, view="left"))),
    # Politeness explains nothing else: what is not understood is still reported.
    ("Please photograph the bear with a dreamy mood.", parsed(subject(BEAR), unparsed=["dreamy mood"])),
]


# Heights said the way people move a camera: getting low or high, pointing it up or down,
# heights of surfaces and of the ground, relative to eye level.
HEIGHTS = [
    ("Crouch down low and photograph the sofa.", parsed(subject(SOFA), elevation="low angle")),
    ("Point the camera up towards the fridge.", parsed(subject(FRIDGE), elevation="low angle")),
    ("Aim down at the bear from the left.", parsed(subject(BEAR, view="left"), elevation="high angle")),
    ("Climb up high and frame the TV.", parsed(subject(TV), elevation="high angle")),
    ("Look down onto the vase.", parsed(subject(VASE), elevation="high angle")),
    ("The bear, shot from floor level.", parsed(subject(BEAR), elevation="low angle")),
    # A named elevation still wins over such a hint.
    ("A worm's-eye view of the TV from ground level.", parsed(subject(TV), elevation="worm's-eye")),
    ("The bear with the camera at desk height.", parsed(subject(BEAR), elevation="eye level")),
    ("The vase from counter level, on the right.", parsed(subject(VASE, region="right"), elevation="eye level")),
    ("The TV from just below eye level.", parsed(subject(TV), elevation="slightly below")),
    ("The sofa slightly above eye height.", parsed(subject(SOFA), elevation="slightly above")),
    ("The fridge from well below eye level.", parsed(subject(FRIDGE), elevation="low angle")),
    ("The fridge, shot from low.", parsed(subject(FRIDGE), elevation="low angle")),
    # A height alone as a clause; "low in the frame" stays a region.
    ("The sofa from behind, low.", parsed(subject(SOFA, view="back"), elevation="low angle")),
    ("The bear, high.", parsed(subject(BEAR), elevation="high angle")),
    ("The vase low in the frame.", parsed(subject(VASE, region="bottom"))),
]

# A side named alone as a clause, and a camera place opening the sentence.
CLAUSES = [
    ("Sofa, rear left.", parsed(subject(SOFA, view="back-left"))),
    ("Front right, the bear, close up.", parsed(subject(BEAR, shot="close-up", view="front-right"))),
    ("The TV, three-quarter, front right.", parsed(subject(TV, view="front-right"))),
    ("The fridge, profile.", parsed(subject(FRIDGE, view="side"))),
    ("Right in front of the sofa, high angle.", parsed(subject(SOFA, view="front-exact"), elevation="high angle")),
    ("Squarely behind the TV.", parsed(subject(TV, view="back-exact"))),
    # A lone left or right there stays a region of the frame; a place later relates two objects.
    ("The vase, left.", parsed(subject(VASE), unparsed=["left"])),
    ("The vase with the bear behind it.", parsed(subject(VASE), subject(BEAR), unparsed=["behind"])),
    ("The sofa big in the picture.", parsed(subject(SOFA, shot="close-up"))),
]

# Parts of an object and the scene around it are never subjects; they are reported.
PARTS = [
    ("A close-up of the armrest of the red chair.", parsed(subject(RED, shot="close-up"), unparsed=["armrest"])),
    ("Show me the fridge so the door handle is visible.", parsed(subject(FRIDGE), unparsed=["door handle"])),
    ("A wide shot of the whole space, the bear in the middle.", parsed(subject(BEAR, "center", "wide"), unparsed=["space"])),
    ("A view of the background with the vase on the right.", parsed(subject(VASE, region="right"), unparsed=["background"])),
]


ROWS = SIDE_NOUNS + NOT_SUBJECTS + THREE_QUARTER + DEGREES + TWO_ENDS + SIZES + POLITE + HEIGHTS + CLAUSES + PARTS


@pytest.mark.parametrize("text, want", check(ROWS))
def test_phrasing(text, want):
    assert structure(text) == want


@pytest.mark.parametrize(
    "text, message",
    [
        ("The bear from the front, from behind.", r"conflicting view for 'teddy bear': 'front' and 'back'"),
        ("The bear from its left and from its right.", r"conflicting view for 'teddy bear': 'left' and 'right'"),
        ("A three-quarter view of the bear, from the side.", r"conflicting view for 'teddy bear': 'three-quarter' and 'side'"),
        ("The sofa, slightly to its left, from its right.", r"conflicting view for 'sofa': 'front-slight-left' and 'right'"),
        ("Zoom in on the bear, from far away.", r"conflicting shot for 'teddy bear': 'close-up' and 'wide'"),
        ("The bear from a high angle, straight down.", r"conflicting elevations"),
        ("The bear slightly below it, from a worm's-eye view.", r"conflicting elevations"),
        ("The bear, directly above, 30 degrees above.", r"conflicting elevations: 'top-down' is 80 to 90 degrees, not 30"),
        # A side or position word is never the subject: without a subject there is nothing to frame.
        ("A photo of the back, please.", r"no subject in .* \(not understood: \['back'\]\)"),
        ("A photo of the side.", r"no subject in .* \(not understood: \['side'\]\)"),
        # A vague subject is refused with the scene's names, never guessed.
        ("A photo of that little thing on the left.", r"no subject in .*; name one of the scene's objects: \['blue armchair'"),
        ("A photo of the back of the giraffe.", r"subject 'giraffe' is not in this scene"),
        # An unknown thing opening the sentence is its subject: reported, never replaced by a
        # known object named later in it.
        ("The parrot perched on the sofa.", r"subject 'parrot' is not in this scene"),
        ("A hamster next to the bear, close up.", r"subject 'hamster' is not in this scene"),
        ("The parrot beside the sofa.", r"subject 'parrot' is not in this scene"),
        ("A dog basket alongside the red chair.", r"subject 'dog basket' is not in this scene"),
    ],
)
def test_contradictions_are_still_errors(text, message):
    with pytest.raises(InputError, match=message) as err:
        parse_instruction(text, SCENE)
    assert "\n" not in str(err.value)


# --- names one edit away ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, name, said, read",
    [
        ("A close-up of the teddy baer.", BEAR, "teddy baer", "teddy bear"),  # swapped letters
        ("The tedy bear from its left.", BEAR, "tedy bear", "teddy bear"),  # a letter missing
        ("The teddybear on the right.", BEAR, "teddybear", "teddy bear"),  # the space missing
        ("The televison on the left.", TV, "televison", "television"),
        ("Frame the refridgerator.", FRIDGE, "refridgerator", "refrigerator"),  # a letter too many
        ("The red armchiar from behind.", RED, "red armchiar", "red armchair"),
        ("The blue armchiars.", BLUE, "blue armchiars", "blue armchair"),  # plural: read singular
        ("The settea, zoomed out.", SOFA, "settea", "settee"),  # an alias
        # Four-letter names are read from a swap of two adjacent letters only.
        ("The bera on the left.", BEAR, "bera", "bear"),
        ("A photo of the sfoa.", SOFA, "sfoa", "sofa"),
        ("The teddy bera, close up.", BEAR, "teddy bera", "teddy bear"),
    ],
)
def test_a_name_one_edit_away_is_read_and_reported(text, name, said, read):
    p = parse_instruction(text, SCENE)
    assert [s.name for s in p.subjects] == [name] and p.unparsed == []
    assert p.corrected == [{"said": said, "read": read}]


def test_a_head_noun_one_edit_away_is_read():
    """ "plnat" misspells "plant", the head noun of "potted plant", which names it alone."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "potted plant", [], True), SemanticObject(1, "sofa", [], False)])
    p = parse_instruction("The plnat on the left.", scene)
    assert p.subjects[0].name == "potted plant" and p.subjects[0].region == "left"
    assert p.corrected == [{"said": "plnat", "read": "plant"}]


@pytest.mark.parametrize(
    "a, b, near",
    [
        ("baer", "bear", True),  # swap
        ("bear", "bears", True),  # insertion
        ("teddybear", "teddy bear", True),  # the space is a character
        ("beer", "bear", True),  # substitution
        ("bear", "bear", False),  # no edit is not a correction
        ("abcd", "badc", False),  # two swaps
        ("bera", "bear", True),  # a swap at the end
        ("telivison", "television", False),  # two edits
    ],
)
def test_one_edit(a, b, near):
    assert one_edit(a, b) is near and one_edit(b, a) is near


def test_correct_names_report_no_correction():
    assert parse_instruction("The teddy bears and the televisions.", SCENE).corrected == []


@pytest.mark.parametrize(
    "text, message",
    [
        # A four-letter name is not read from a substitution ("beer" is a word of its own), a
        # letter too many or too few, or two swaps.
        ("The beer on the left.", r"subject 'beer' is not in this scene; closest: \['teddy bear'\]"),
        ("A photo of the sofas.", None),
        ("A photo of the sfa.", r"subject 'sfa' is not in this scene"),
        ("A photo of the ebra.", r"subject 'ebra' is not in this scene"),
        # Two edits away is read only in a name of eight letters or more, keeping its first
        # letter (test_long_names_are_read_through_two_edits); a five-letter one is not.
        ("A photo of the sfoaa.", r"subject 'sfoaa' is not in this scene; closest: \['sofa'\]"),
        ("A photo of the delivison.", r"subject 'delivison' is not in this scene; closest: \['television'\]"),
        # Corrected, the name is still ambiguous: the error says so rather than guess.
        ("The armchiar on the left.", r"subject 'the armchair' is ambiguous in this scene; say which"),
    ],
)
def test_misspellings_that_are_not_read(text, message):
    if message is None:  # a plural is the name itself, not a misspelling
        assert parse_instruction(text, SCENE).corrected == []
        return
    with pytest.raises(InputError, match=message):
        parse_instruction(text, SCENE)


def test_three_letter_names_are_not_read_from_a_swap():
    """ "arc" is "car" with two letters swapped, and a word of its own."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "car", [], False), SemanticObject(1, "sofa", [], False)])
    with pytest.raises(InputError, match=r"subject 'arc' is not in this scene"):
        parse_instruction("A photo of the arc.", scene)


def test_a_misspelling_of_two_names_is_not_read():
    """ "sable" is one edit from "table" and from "cable": it is read as neither."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "table", [], True), SemanticObject(1, "cable", [], True)])
    with pytest.raises(InputError, match=r"subject 'sable' is not in this scene"):
        parse_instruction("A photo of the sable.", scene)
    assert parse_instruction("A photo of the tables.", scene).corrected == []


def test_photographic_words_are_never_read_as_names():
    """ "close" is one edit from "closet", "frame" from "flame": the phrase tables' words stay theirs."""
    scene = Vocabulary.from_semantics([SemanticObject(0, "closet", [], False), SemanticObject(1, "flame", [], True)])
    p = parse_instruction("A close shot of the closet, filling the frame.", scene)
    assert [s.name for s in p.subjects] == ["closet"] and p.subjects[0].shot == "close-up" and p.corrected == []


def test_corrections_survive_the_json_form():
    p = parse_instruction("A close-up of the teddy baer.", SCENE)
    data = json.loads(json.dumps(p.to_dict()))
    assert data["corrected"] == [{"said": "teddy baer", "read": "teddy bear"}]
    assert ParsedInstruction.from_dict(data) == p
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(data, JSON_SCHEMA)
