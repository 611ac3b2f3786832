"""A thing not in the scene placed at a named object is what the sentence is about (parse15):
"<noun phrase> <placing words> <place preposition> <named object>", the placing words a
participle, a relative clause or a verb of resting with adverbs, refused naming the thing; a room
or a garden holding the named object ("a photo of the lounge with the sofa in it") likewise. A
named subject before a landmark or scenery stays the subject. None of these wordings is in a
suite file."""

from __future__ import annotations

import pytest

from capframe.errors import InputError
from capframe.scene.directory import SemanticObject
from capframe.translate.parse import _placed_phrase, _placing, _unplaced, parse_instruction
from capframe.translate.vocabulary import Vocabulary, words

NAMES = [
    "sofa",
    "armchair",
    "floor lamp",
    "coffee table",
    "cushion",
    "bookshelf",
    "mug",
    "teddy bear",
    "bench",
    "tree",
    "vase",
    "toy car",
]
SCENE = Vocabulary.from_semantics([SemanticObject(k, n, [], False) for k, n in enumerate(NAMES)])


def refused_for(text: str) -> str:
    """The thing named by the refusal of ``text`` (it must be refused as not in the scene)."""
    with pytest.raises(InputError, match="is not in this scene") as err:
        parse_instruction(text, SCENE)
    return str(err.value).split("'")[1]


PLACED_UNKNOWN = [
    ("a kitten curled up fast asleep on the sofa", "kitten"),
    ("the goldfish bowl that's sitting on the bookshelf", "goldfish bowl"),
    ("puppy napping quietly under the coffee table", "puppy"),
    ("can you show the radiator which is behind the armchair", "radiator"),
    ("our parrot perched happily on top of the floor lamp", "parrot"),
    ("include the umbrella that is leaning against the bench", "umbrella"),
    ("THE BICYCLE PARKED RIGHT BEHIND THE BENCH", "bicycle"),
    ("a squirrel scampering somewhere near the tree", "squirrel"),
    ("a macro shot of the ring resting inside the vase", "ring"),
    ("photo of a candle burning beside the vase please", "candle"),
    ("the hamster who is hiding behind the cushion", "hamster"),
    ("a detail of the spoon sticking out of the mug", "spoon"),
    ("snail crawling slowly along the bench", "snail"),
    ("a close up of the biscuit dunked in the mug", "biscuit"),
    ("pls frame the kite that's stuck up in the tree", "kite"),
    ("the toaster what is sitting beside the sofa", "toaster"),  # non-native relative
    ("the painting hanging above the sofa", "painting"),  # a noun in -ing is the head
    ("Please could you feature the dehumidifier, which is currently next to the armchair?", "dehumidifier"),
    # Written after the rules: a relative clause with any verb, "from", a count before the thing.
    ("i want photo of cat who sleep on sofa", "cat"),
    ("a candle that's been lit beside the vase", "candle"),
    ("a spider dangling from the floor lamp", "spider"),
    ("two ducks swimming near the bench", "ducks"),
    ("our tortoise, who is hiding under the armchair", "tortoise"),
    ("SNAP THE SCARF DRAPED OVER THE ARMCHAIR", "scarf"),
]


@pytest.mark.parametrize("text,thing", PLACED_UNKNOWN)
def test_unknown_thing_placed_at_a_named_object_is_refused_by_its_name(text, thing):
    assert refused_for(text) == thing


KNOWN_BEFORE_A_LANDMARK = [
    ("the mug on the table", "mug"),
    ("cushion on the sofa", "cushion"),
    ("the bench with a sunset behind it", "bench"),
    ("the vase sitting on the windowsill", "vase"),
    ("teddy bear resting against a pillow on the sofa", "teddy bear"),
    ("the tree with the clouds drifting behind it", "tree"),
    ("the armchair standing next to the fireplace", "armchair"),
    ("close-up of the mug resting on the coffee table", "mug"),
    ("the bench with the sun setting behind the tree", "bench"),
    ("the vase, flowers drooping over its rim", "vase"),
    ("mug photographed from beside the vase", "mug"),
    ("the armchair viewed from behind the sofa", "armchair"),
]


@pytest.mark.parametrize("text,name", KNOWN_BEFORE_A_LANDMARK)
def test_named_subject_before_a_landmark_or_scenery_stays_the_subject(text, name):
    assert parse_instruction(text, SCENE).subjects[0].name == name


NOT_A_THING = [
    # A comparison, the camera or its move, light: never the subject.
    ("like a toddler looking up at the teddy bear", "teddy bear"),
    ("camera sitting low beside the bench", "bench"),
    ("a drone hovering above the tree", "tree"),
    ("the light falling on the vase", "vase"),
    ("orbit paused over the vase, straight down", "vase"),
    ("the sofa seen from behind the armchair", "sofa"),
]


@pytest.mark.parametrize("text,name", NOT_A_THING)
def test_camera_light_or_simile_before_a_named_object_is_no_subject(text, name):
    assert parse_instruction(text, SCENE).subjects[0].name == name


SETTING_HOLDING = [
    ("a photo of the living room with the sofa in it", "living room"),
    ("the garden with the bench inside it", "garden"),
    ("picture of my bedroom with the teddy bear in there", "bedroom"),
    ("A SHOT OF THE LOUNGE WITH THE ARMCHAIR IN IT", "lounge"),
    ("an image of our study, with the bookshelf in it", "study"),
    ("the backyard with the tree in it please", "backyard"),
    ("a snap of the patio containing the bench inside", "patio"),
    ("photograph the hallway holding the floor lamp in it", "hallway"),
]


@pytest.mark.parametrize("text,setting", SETTING_HOLDING)
def test_setting_holding_a_named_object_is_refused(text, setting):
    # A room or a garden is never one of the scene's objects, even where a name holds its word
    # ("garden" of a "garden bench" alias).
    assert refused_for(text) == setting


SETTING_AS_PLACE = [
    ("a wide view of the lounge with the sofa in the lower left", "sofa", "lower left"),
    ("the sofa in the living room", "sofa", None),
    ("wide establishing of the garden: the bench small", "bench", None),
    ("the armchair in the garden", "armchair", None),
    ("kitchen scene: the mug close up", "mug", None),
]


@pytest.mark.parametrize("text,name,region", SETTING_AS_PLACE)
def test_setting_said_as_where_the_subject_is_stays_understood(text, name, region):
    s = parse_instruction(text, SCENE).subjects[0]
    assert (s.name, s.region) == (name, region)


def test_placed_phrase_finds_the_noun_phrase_before_placing_words():
    # (start, end) of the noun phrase in the words before the named object.
    assert _placed_phrase(words("fountain splashing away somewhere behind")) == (0, 1)
    assert _placed_phrase(words("could you include the fireplace that's behind")) == (4, 5)
    assert _placed_phrase(words("the painting hanging above")) == (1, 2)
    # Adverbs alone, or no preposition before the object, place nothing.
    assert _placed_phrase(words("the kite up in")) is None
    assert _placed_phrase(words("the kite stuck")) is None
    assert _placed_phrase(words("the mug in")) is None


def test_placing_words_and_their_trimming():
    assert _placing("splashing") and _placing("dunked") and _placing("resting") and _placing("stuck")
    assert not _placing("looking") and not _placing("aimed") and not _placing("ring") and not _placing("bed")
    assert _unplaced(["granddaughter", "cuddling"]) == ["granddaughter"]
    assert _unplaced(["cottage", "peeking", "out"]) == ["cottage"]
    assert _unplaced(["painting"]) == ["painting"]  # its first word is kept


# --- view, size and height families (phrasing1's misreadings), over wordings of no suite file ----

DIAGONAL_NOUNS = [
    ("front-left three-quarter on the toy car", "front-left"),
    ("I'd love a rear-right 3/4, nothing fancy, of the sofa", "back-right"),
    ("mug: I want a front-right three quarter, eye level", "front-right"),
    ("a back-left three-quarters view on the armchair", "back-left"),
    ("FRONT LEFT THREE QUARTER ON THE BENCH", "front-left"),
    ("the teddy, we need a left-front 3/4.", "front-left"),
    ("rear left 3/4 for the sofa please", "back-left"),
    ("just get a right front three-quarter, mug small", "front-right"),
    ("give me a rear-right three-quarter of the toy car", "back-right"),
]


@pytest.mark.parametrize("text,view", DIAGONAL_NOUNS)
def test_diagonal_said_as_a_noun_is_that_view(text, view):
    p = parse_instruction(text, SCENE)
    assert p.subjects[0].view == view


NEGATED_VIEWS = [
    ("the mug from the front, not from the side", "front"),
    ("teddy bear facing us, not the back", "front"),
    ("sofa from its left, not from the front", "left"),
    ("the vase from behind rather than the front", "back"),
    ("armchair from the back, instead of the front", "back"),
    ("i want mug front, not from side", "front"),
    ("TREE FROM THE LEFT, NOT FROM THE RIGHT", "left"),
    ("teddy from the front, but not from the front-left", "front"),
]


@pytest.mark.parametrize("text,view", NEGATED_VIEWS)
def test_side_said_not_to_be_wanted_asks_nothing(text, view):
    # Not a second view that would conflict with the one asked.
    assert parse_instruction(text, SCENE).subjects[0].view == view


def test_negated_side_alone_is_every_other_way_round():
    # One end denied alone is the view side "not-back" (every azimuth at least 30 degrees from the
    # back, since f510175; before, no view was asked and the words were reported).
    p = parse_instruction("the bench, just not from behind", SCENE)
    assert p.subjects[0].view == "not-back" and p.not_understood() == []


SIZES = [
    ("vase as big as it can possibly be in the frame", "close-up"),
    ("the mug as large as it could possibly be", "close-up"),
    ("teddy as huge as you can possibly get it", "close-up"),
    ("the bench as small as it can be in the picture", "wide"),
    ("sofa as small as possible", "wide"),
    ("MUG AS BIG AS WE CAN POSSIBLY MAKE IT", "close-up"),
    ("The mug rather small, from the front", "wide"),
    ("vase fairly big, centred", "close-up"),
    ("bench quite small and low", "wide"),
    ("the armchair moderately small", "wide"),
    ("The mug small, with plenty of tabletop visible round it", "wide"),
    ("bench with lots of grass showing around it", "wide"),
    ("teddy, loads of floor in view around him", "wide"),
    ("TREE WITH LOTS OF SKY VISIBLE AROUND IT", "wide"),
]


@pytest.mark.parametrize("text,shot", SIZES)
def test_size_pushed_moderated_or_room_seen_around(text, shot):
    assert parse_instruction(text, SCENE).subjects[0].shot == shot


EYE_PLACES = [
    "camera roughly where his eyes are, teddy from the front",
    "the teddy, lens just about where its face would be",
    "bear, cam right where his nose is",
    "toy car from the left, camera about where its headlights are",
    "teddy: put the camera where his eyes would be",
    "camera roughly where the teddy bear's eyes are",
    "CAMERA WHERE ITS FACE IS, TEDDY",
]


@pytest.mark.parametrize("text", EYE_PLACES)
def test_camera_where_the_subjects_eyes_are_is_eye_level(text):
    assert parse_instruction(text, SCENE).elevation == "eye level"


ABBREVIATED = [
    ("Mug, elevation approx. 35°, tight", 35.0),
    ("bench from approx. 40 deg. above", 40.0),
    ("vase, ca. 30° from above", 30.0),
    ("teddy at an elevation of approx. 20 degrees", 20.0),
    ("the tree, camera approx. 30 deg. below it", -30.0),
    ("ARMCHAIR, APPROX. 25° UP", 25.0),
    ("toy car from appr. 50 degrees above", 50.0),
]


@pytest.mark.parametrize("text,degrees", ABBREVIATED)
def test_abbreviation_full_stop_ends_no_clause(text, degrees):
    assert parse_instruction(text, SCENE).elevation_deg == degrees


def test_abbreviation_stop_is_dropped_but_a_sentence_stop_is_kept():
    assert words("approx. 35°. Cat. no. 12") == ["approximately", "35", "degrees", ".", "cat", ".", "no", ".", "12"]


# Roll said with a particle, by the picture's line, or as a noun before its degrees. DESIGN §3:
# roll > 0 = the camera clockwise; the picture (horizon) turns the other way.
ROLLS = [
    ("Anticlockwise camera twist of thirty degrees, vase as subject", -30.0),
    ("vase, a clockwise twist of 20 degrees", 20.0),
    ("the mug, a lens rotation of 20 degrees, counterclockwise", -20.0),
    ("teddy bear, the frame leaned over 15 degrees clockwise", 15.0),
    ("bench with the horizon line running 10 degrees anticlockwise off level", 10.0),
    ("sofa, horizon sitting 12 degrees clockwise", -12.0),
    ("CAMERA TIPPED OVER 20 DEGREES CLOCKWISE, TREE", 20.0),
    ("the armchair, a counter-clockwise cant of fifteen degrees", -15.0),
    ("mug, camera spin of 25 degrees anti-clockwise", -25.0),
    ("the picture sloped 8 degrees clockwise, vase", -8.0),
    ("a clockwise camera lean of 10°, toy car", 10.0),
]


@pytest.mark.parametrize("text,roll", ROLLS)
def test_roll_with_a_particle_a_line_verb_or_as_a_noun(text, roll):
    assert parse_instruction(text, SCENE).roll_deg == roll


LOOKS = [
    ("the vase, peering up at it", "elevation", "low angle"),
    ("floor lamp, gazing upward along it", "elevation", "low angle"),
    ("mug, staring down at it", "elevation", "high angle"),
    ("bench, peering down on it a little", "elevation", "slightly above"),
    ("TEDDY BEAR, GAZING UP AT HIM", "elevation", "low angle"),
    ("the toy car, camera peeking up at it from the floor", "elevation", "low angle"),
    ("armchair, staring straight down", "elevation", "top-down"),
    ("vase, gazing up at it at 30 degrees", "elevation_deg", -30.0),
    ("the tree, gazing straight up into it", "elevation_deg", -90.0),
]


@pytest.mark.parametrize("text,field,value", LOOKS)
def test_other_verbs_of_looking_say_the_height_as_looking_does(text, field, value):
    assert getattr(parse_instruction(text, SCENE), field) == value


FLOOR_COVERS = [
    "vase from rug level",
    "the armchair at carpet height",
    "teddy bear from carpet level, looking up",
    "the bench from pavement level",
    "floor lamp shot at rug height",
    "tree, camera at gravel level",
    "SOFA FROM RUG LEVEL",
    "the mug from floorboards level",
]


@pytest.mark.parametrize("text", FLOOR_COVERS)
def test_the_height_of_what_covers_the_floor_is_a_low_angle(text):
    assert parse_instruction(text, SCENE).elevation == "low angle"


VIEW_FAMILIES = [
    # A side reached "over to" after a view (DESIGN §3: +90 its own right).
    ("sofa photographed from behind it, over to its right", "back-right"),
    ("the bench from behind, over to its left", "back-left"),
    ("ARMCHAIR FROM BEHIND, OVER TO ITS LEFT", "back-left"),
    # "The <side> one" after a view that lacks its side.
    ("sofa, back three-quarter, the right-hand one", "back-right"),
    ("armchair, rear three quarter, the left one", "back-left"),
    ("bench: three-quarter view, the left one", "front-left"),
    ("TEDDY BEAR, REAR 3/4, THE RIGHT ONE", "back-right"),
    # A side turned a little towards an end after a concession word.
    ("bookshelf from its left-hand end, though edging a little round to the front", "left-slight-front"),
    ("sofa from its right side, yet a bit towards the back", "right-slight-back"),
    ("armchair from the left, although slightly toward the front", "left-slight-front"),
    # Turned a little so as to show a side.
    ("teddy bear facing camera, turned just a little to show his left side", "front-slight-left"),
    ("the vase from the front, turned slightly to show its right side", "front-slight-right"),
    ("sofa facing us, rotated a bit to reveal its left side", "front-slight-left"),
    # The camera looking into its eyes: its front, exactly when said so ("right" is no side).
    ("Teddy bear, perfectly frontal, looking right into his glass eyes", "front-exact"),
    ("teddy bear, looking straight into his eyes", "front-exact"),
    ("the teddy bear, camera staring directly into its face", "front-exact"),
    ("teddy bear, gazing into his eyes", "front"),
]


@pytest.mark.parametrize("text,view", VIEW_FAMILIES)
def test_view_families(text, view):
    assert parse_instruction(text, SCENE).subjects[0].view == view


DRAMATIC_UPS = [
    "vase, heroic upward angle with the camera practically touching the table",
    "vase, heroic upward angle",
    "a dramatic up shot of the tree",
    "the armchair, an imposing low angle",
    "MAJESTIC UPWARD VIEW OF THE TREE",
    "the bench, epic upward perspective",
    "teddy bear, heroic upwards camera angle",
    "a menacing upward shot of the teddy bear",
]


@pytest.mark.parametrize("text", DRAMATIC_UPS)
def test_an_upward_angle_with_a_word_of_drama_is_low(text):
    assert parse_instruction(text, SCENE).elevation == "low angle"


def test_negated_height_asks_nothing():
    assert parse_instruction("mug head on, not from above", SCENE).elevation is None
    assert parse_instruction("the mug from above, not from below", SCENE).elevation == "high angle"
    assert parse_instruction("vase, no eye level, from above", SCENE).elevation == "high angle"
    # "not too high" is a degree, not a height refused: still reported as not understood.
    assert parse_instruction("bench, not too high", SCENE).not_understood()


@pytest.mark.parametrize(
    "text,shot",
    [
        ("the bench as small as can be", "wide"),
        ("the toy car as large as you possibly can", "close-up"),
        ("vase as big as it'll possibly go", "close-up"),
        ("sofa fairly tiny", "wide"),
    ],
)
def test_size_pushed_in_other_word_orders(text, shot):
    assert parse_instruction(text, SCENE).subjects[0].shot == shot


def test_picture_line_sloping_turns_against_the_camera():
    assert parse_instruction("sofa, horizon line sloping 5 degrees clockwise", SCENE).roll_deg == -5.0
