"""The scene's vocabulary: which words name which labelled object.

Built from the semantic sidecar (:class:`~capframe.scene.directory.SemanticObject`: name, aliases,
symmetric). A *mention* such as "the big red chair" is matched to exactly one object name:

1. **forms**: every name and alias, normalised like the instruction (:func:`words`) and singular
   (:func:`singular`), is a *form*. The objects having a form inside the mention are candidates;
   the longest form wins ("coffee table" over "table"), then the most mention words that appear
   elsewhere in the object's names ("red" picks "red armchair" for "the red chair");
2. **partial**: with no whole form inside the mention, an object matches when the mention's
   content words all belong to one of its forms ("teddy" -> "teddy bear") or end on the same head
   noun ("the big bear" -> "teddy bear");
3. **short form**: with neither, a mention of one content word of three letters or more that
   starts the head word of some names' forms ("tele" of "television") matches all of them, so
   one such name is read and two make the mention ambiguous (:data:`MIN_CLIPPED_LETTERS`);
4. otherwise :class:`~capframe.errors.InputError` names the mention and the closest known names
   (never a kind word of :data:`NAME_KINDS`).

A misspelt name is read as a name only by the parser, and only when a run of the instruction's
words is one edit (:func:`one_edit`) from exactly one name or alias, or the head noun of one, of at
least :data:`MIN_CORRECTED_LETTERS` letters, or two adjacent letters swapped (:func:`transposed`,
Damerau's fourth kind of edit) in one of :data:`MIN_TRANSPOSED_LETTERS` ("bera" for "bear")
(:meth:`Vocabulary.correction`); the parser reports each such reading. :meth:`Vocabulary.match`
itself never corrects.

A colour word in the mention that contradicts the colour words of an object's names excludes that
object ("the blue chair" never matches "red armchair"); one sharing a basic colour term with them
does not (:data:`COLOR_FAMILIES`: "the mustard-yellow settee" of a mustard sofa); objects whose names
carry no colour accept any. Two objects that match equally well make the mention ambiguous (an error naming both).

Near-synonyms that are neither names, aliases nor words of the tables :data:`NAME_SYNONYMS` and
:data:`NAME_KINDS` (everyday names, nicknames and kinds of the catalog's objects) are not guessed: a
small sentence-embedding model ranks them no better than word overlap (it puts "plush toy" nearer
"toy car" than "teddy bear", and "giraffe" nearer "teddy bear" than some true synonyms), so they
are left to the scene's aliases and to the model-tier parser (DESIGN §4).

The text normalisation here is shared with :mod:`capframe.translate.parse`, so a name is spotted in
an instruction exactly when it matches: lowercase, hyphens split ("top-left" -> "top left"), the
possessive "'s" a separate word, one spelling for British/US pairs, number words as digits
("twenty-five" -> "25"), "degree"/"°" as "degrees" and a fraction of something as a percentage
("2/3 of the frame" -> "66.67 percent of the frame"; "3/4" elsewhere is "three quarter").
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass

from ..errors import InputError

# --- text normalisation (shared with the parser) ------------------------------------------------

# One spelling per British/US pair (and a few compounds written as one word or two).
SPELLINGS = {
    "centre": "center",
    "centred": "centered",
    "centring": "centering",
    "centres": "centers",
    "colour": "color",
    "coloured": "colored",
    "grey": "gray",
    "greyish": "grayish",
    "anticlockwise": "counterclockwise",
    "metre": "meter",
    "metres": "meters",
    "closeup": "close up",
    "closeups": "close ups",
    "midshot": "mid shot",
    "birdseye": "bird 's eye",
    "degree": "degrees",
    "deg": "degrees",
    "degs": "degrees",
    "favourite": "favorite",
    "toward": "towards",
    "oclock": "o clock",
    "eyeline": "eye line",
    # Two words run together ("infront", "eyelevel", "abit").
    "infront": "in front",
    "eyelevel": "eye level",
    "topdown": "top down",
    "wormseye": "worm 's eye",
    # Perspective names run together or calqued ("birdview"; German "Vogelperspektive").
    "birdview": "bird view",
    "birdsview": "bird 's view",
    "vogelperspektive": "bird perspective",
    "froschperspektive": "frog perspective",
    "perspektive": "perspective",
    "persp": "perspective",
    "fullframe": "full frame",
    "lefthand": "left hand",
    "righthand": "right hand",
    "abit": "a bit",
    "alittle": "a little",
    "sideon": "side on",
    "headon": "head on",
    "approx": "approximately",
    "appr": "approximately",
    "ca": "circa",
    # Direction words spelt by ear, as children and hurried writers spell them ("looking rite
    # down", "strait above", "from the frunt"); a mistyping by a letter is read by slip_of.
    "foto": "photo",
    "fotos": "photos",
    "rite": "right",
    "strait": "straight",
    "strate": "straight",
    "strayt": "straight",
    "abuv": "above",
    "abuve": "above",
    "frunt": "front",
    "reer": "rear",
    "behine": "behind",
    "behing": "behind",
    "ontop": "on top",
    # Chat spellings and abbreviations ("could u", "pls", "3/4 ccw").
    "u": "you",
    "n": "and",
    "pls": "please",
    "plz": "please",
    "thx": "thanks",
    "teh": "the",
    "cw": "clockwise",
    "ccw": "counterclockwise",
    "acw": "counterclockwise",
    "qtr": "quarter",
    "qtrs": "quarters",
    "kinda": "kind of",
    "sorta": "sort of",
    "lil": "little",
    "lvl": "level",
    "elev": "elevation",
    "med": "medium",
    # Number words misspelt as people often do.
    "fourty": "forty",
    "ninty": "ninety",
    "cam": "camera",
    # Directions said with a "-ward(s)" suffix are the plain direction ("looking upward a little").
    "upward": "up",
    "upwards": "up",
    "downward": "down",
    "downwards": "down",
    # The camera's flying vehicle by its other names: a drone, never a thing of the scene
    # ("UAV hovering over the tree").
    "uav": "drone",
    "uavs": "drones",
    "quadcopter": "drone",
    "quadrocopter": "drone",
    "multicopter": "drone",
}
# Shot-size abbreviations of shot lists and storyboards ("ECU of the bear", "MS, eye level"),
# spelt out so the shot-size tables read them. Two letters are enough: none of these is an
# English word an instruction would use otherwise.
SHOT_ABBREVIATIONS = {
    "ecu": "extreme close up",
    "xcu": "extreme close up",
    "bcu": "extreme close up",
    "cu": "close up",
    "mcu": "medium close up",
    "ms": "medium shot",
    "mls": "medium long shot",
    "mws": "medium wide shot",
    "fs": "full shot",
    "ls": "long shot",
    "ws": "wide shot",
    "els": "extreme long shot",
    "xls": "extreme long shot",
    "ews": "extreme wide shot",
    "xws": "extreme wide shot",
    # Over the shoulder ("OTS right": behind the subject, on that side).
    "ots": "over the shoulder",
}
SPELLINGS.update(SHOT_ABBREVIATIONS)
# A vehicle's sides said as a sailor says them: starboard is its own right, port its own left.
# "port" is read so only before a word naming a side of it ("its port side", "the port flank"):
# alone it is more often a socket ("show me the ports").
SIDE_NAMES = {"starboard": "right", "portside": "left side"}
SPELLINGS.update(SIDE_NAMES)
# A diagonal's end and side written as one word, as quick notes run them together ("backright",
# "frontleft", "rearright"): the two words.
SPELLINGS.update({f"{lon}{lat}": f"{lon} {lat}" for lon in ("front", "back", "rear") for lat in ("left", "right")})
PORT_SIDE_WORDS = ("side", "hand", "flank", "quarter", "end", "bow", "beam", "profile", "three", "rear", "back", "front")
# A side written as its letter, as shot lists and storyboards write it ("L profile", "front 3/4 R",
# "rear L"): read so only beside a word of a view (:data:`SIDE_LETTER_NEIGHBOURS`), since a lone
# letter elsewhere is anything ("size L", "the R key").
SIDE_LETTERS = {"l": "left", "r": "right"}
SIDE_LETTER_NEIGHBOURS = frozenset(
    {"profile", "side", "flank", "quarter", "quarters", "diagonal", "lateral", "view", "angle", "front", "rear", "back", "three"}
    # ... or a word of the frame's areas, as shot lists write a region ("frame R", "lower L", "top R", "R third").
    | {"frame", "top", "bottom", "upper", "lower", "third", "corner", "half"}
)
# Two-word spellings merged into one word, or read as other words.
COMPOUNDS = {("counter", "clockwise"): "counterclockwise", ("anti", "clockwise"): "counterclockwise"}
COMPOUNDS |= {("port", word): f"left {word}" for word in PORT_SIDE_WORDS}
# "Right" spelt by ear as "write", read so only right before a word of a side or of the frame's
# areas ("from its write side", "in the write third"): elsewhere writing is writing. Not before
# "hand": "on the write hand side" would be read as the frame's right, where the words beside it
# may be a view said by ear too ("from be hind comma on the write hand side").
COMPOUNDS |= {("write", word): f"right {word}" for word in ("side", "third", "half", "corner", "edge", "flank", "profile")}
# ... and after a possessive, where no verb "write" can stand ("his write hand side", "its write").
COMPOUNDS |= {(owner, "write"): f"{owner} right" for owner in ("its", "his", "her", "their")}
# "High" clipped to "hi" beside "up" ("from hi up", "up hi"; "hi angle" is a phrase of its own):
# a greeting is never said so.
COMPOUNDS |= {("hi", "up"): "high up", ("up", "hi"): "up high", ("way", "hi"): "way high"}
# The camera said as its rig ("cant the whole rig", "the camera rig"): the camera.
COMPOUNDS |= {("whole", "rig"): "camera", ("camera", "rig"): "camera"}
# Shot sizes as dictation hears them ("clothes up" for close up, "why'd shot" for wide shot):
# parse20s. "why'd" is read so before a noun of the shot only (:func:`_compounds`), where no
# question can stand.
COMPOUNDS |= {("clothes", "up"): "close up"}
SHOT_HOMOPHONES = {("why", "d"): "wide"}
SHOT_HOMOPHONE_NOUNS = frozenset({"shot", "angle", "view", "frame", "framing", "photo", "picture", "one"})

# Words a "-ish" suffix hedges ("high-ish", "lowish", "smallish"): read as "a bit" before the
# word, the slight degree of the scale below; other "-ish" words ("reddish") are left alone.
# The ends a diagonal is said with ("front-right-ish"): a "-ish" after its side hedges the diagonal.
DIAGONAL_ENDS = frozenset({"front", "back", "rear", "behind"})
HEDGED_WORDS = frozenset({"high", "low", "close", "tight", "wide", "small", "big", "large", "far", "near", "left", "right"})

UNITS = {
    "zero": 0,
    "one": 1,
    "two": 2,
    "three": 3,
    "four": 4,
    "five": 5,
    "six": 6,
    "seven": 7,
    "eight": 8,
    "nine": 9,
    "ten": 10,
    "eleven": 11,
    "twelve": 12,
    "thirteen": 13,
    "fourteen": 14,
    "fifteen": 15,
    "sixteen": 16,
    "seventeen": 17,
    "eighteen": 18,
    "nineteen": 19,
}
TENS = {"twenty": 20, "thirty": 30, "forty": 40, "fifty": 50, "sixty": 60, "seventy": 70, "eighty": 80, "ninety": 90}
# A number word before these is not a quantity to convert ("three-quarter view").
FRACTION_WORDS = {"quarter", "quarters", "third", "thirds"}
# "one" is a number only before a unit ("one degree"); elsewhere it is a pronoun ("the one on the left").
NUMBER_UNITS = {"degrees"}
SIGN_WORDS = {"minus", "negative"}

NUMBER = re.compile(r"\d+(?:\.\d+)?")
_TOKEN = re.compile(r"-?\d+(?:\.\d+)?|'s|[a-z]+|[,;:.!?()]")
PUNCTUATION = frozenset(",;:.!?()")
# Abbreviations whose full stop ends no clause ("elevation approx. 35°", "ca. 40 deg. up").
ABBREVIATED = frozenset(k for k, v in SPELLINGS.items() if v in ("approximately", "circa", "degrees"))
_ABBREVIATION_STOP = re.compile(r"\b(" + "|".join(sorted(ABBREVIATED, key=len, reverse=True)) + r")\.")


def words(text: str) -> list[str]:
    """The normalised tokens of ``text``: words, numbers, ``'s`` and punctuation (see module doc)."""
    s = text.lower()
    s = _ABBREVIATION_STOP.sub(r"\1 ", s)
    s = re.sub(r"[\u2018\u2019\u02bc`\u00b4]", "'", s)
    s = re.sub(r"[\u00b0\u00ba]", " degrees ", s)
    s = re.sub(r"%|\bper\s?cent\b", " percent ", s)  # "10%", "10 per cent", "10 percent"
    s = _BY_THE_CLOCK.sub(lambda m: " counterclockwise " if "against" in (m[1], m[2]) else " clockwise ", s)
    s = _TURN_SHARE.sub(lambda m: f" {_turn_degrees(int(m[1]), int(m[2]))} degrees ", s)  # "1/12 of a turn"
    s = s.translate(VULGAR_FRACTIONS)  # "½", "⅔": as words
    s = _FRACTION_OF.sub(lambda m: f" {100 * int(m[1]) / int(m[2]):.4g} percent ", s)  # "2/3 of the frame"
    s = re.sub(r"\b3\s*/\s*4\b", " three quarter ", s)  # "3/4 rear": the view
    s = _ANGLE_ABBREVIATION.sub(lambda m: ANGLE_ABBREVIATIONS[m[1]], s)  # "az 135, el +20": the angles
    s = re.sub(r"\b3(?=[\s-]+quarters?\b)", " three ", s)  # "a rear 3-quarter angle": as "three quarter"
    s = re.sub(r"\s*(?:-+>|=+>|\u2192)\s*", " : ", s)  # an arrow after a label, as a colon ("centre -> mug")
    s = re.sub(r"[\u2013\u2014]|(?<=\s)-+(?=\s)", " , ", s)  # a dash between clauses ("bench - low")
    s = re.sub(r"(?<=\s)[/|\\]+(?=\s)", " , ", s)  # a slash or a bar between clauses ("mug // tight // ...")
    s = re.sub(r"\s*[\u00b7\u2022]\s*", " , ", s)  # a middle dot or a bullet between clauses ("back-L 3/4 \u00b7 low \u00b7 WS")
    s = re.sub(r"\b([a-z])\.(?=[a-z]\b)", r"\1", s)  # letters written with dots ("t.v.", "a.k.a.")
    s = s.replace("&", " and ")  # "mug & kettle", "TV&sofa"
    s = _WHOLE_BY_EAR.sub("whole", s)  # "the hole picture"
    s = re.sub(r"(?<=[a-z])\s*\+\s*(?=[a-z])", " and ", s)  # "toy car + garage"; "+10 degrees" keeps its sign
    s = re.sub(r"(?<=[a-z0-9])-+(?=[a-z0-9])", " ", s)  # hyphenated words; "-20" keeps its sign
    s = re.sub(r"(?<=[a-z])'s\b", " 's", s)
    s = re.sub(r"(?<=s)'(?=\W|$)", " 's", s)  # plural possessive: "the glasses' left"
    s = re.sub(r"\b(i|we|you|they)'d\b", r"\1 would", s)  # "I'd like": not a stray "d"
    s = re.sub(r"'(?!s\b)", " ", s)  # other apostrophes ("don't") only split words
    s = _RESTATED.sub(r" , \1", s)  # "front-left I mean, ...": the restating words a clause of their own
    tokens = []
    for token in _TOKEN.findall(s):
        tokens.extend(SPELLINGS.get(token, token).split())
    return _number_hedges(
        _numbers(
            _turns(_turn_directions(_just(_hedges(_comparatives(_compounds(_side_letters(_proper_sides(_to_up_down(tokens)))))))))
        )
    )


# A turn's way said by the clock's hands ("rotate it 35 degrees against the clock", "turn with the
# clock by 10 degrees"), read so only after the degrees or before "by" and a number: a clock in the
# scene stays one ("the vase against the clock").
_BY_THE_CLOCK = re.compile(r"(?<=degrees)\s+(against|with) the clock\b|\b(against|with) the clock(?= by \d)")


# An angle's name clipped as capture logs and photogrammetry notes write it ("az 135 / el +20",
# "az -90, el 0"), read so only before a number: "el" elsewhere is an article ("El Capitan").
ANGLE_ABBREVIATIONS = {"az": "azimuth", "azi": "azimuth", "el": "elevation", "ele": "elevation"}
_ANGLE_ABBREVIATION = re.compile(r"\b(az|azi|el|ele)\b(?=\s*[:=]?\s*[+-]?\d)")


# "I mean" closing a clause that restates a value ("the front-right, uh, front-left I mean, ...").
_RESTATED = re.compile(r"(?<=[a-z0-9])\s+(i mean|i meant)(?=\s*[,.;:!?]|\s*$)")


# "Whole" spelt by ear before the picture or a word of all of it ("take up the hole picture", "the
# hole thing in frame"); a hole elsewhere stays one.
_WHOLE_BY_EAR = re.compile(
    r"\bhole(?=\s+(?:frame|picture|image|photo|photograph|shot|pic|thing|scene|view|composition|screen)\b)"
)


# A share written as a fraction of something ("2/3 of the frame", "3/4 of the picture", "⅓ of the
# shot"): a percentage, as the frame-share phrases read it; "3/4" before anything else is the
# three-quarter view ("3/4 rear").
VULGAR_FRACTIONS = str.maketrans(
    {"\u00bd": " half ", "\u2153": " a third ", "\u2154": " two thirds ", "\u00bc": " a quarter ", "\u00be": " 3/4 "}
)
_FRACTION_OF = re.compile(r"\b([1-9])\s*/\s*([1-9]|10)\b(?=\s+of\b)")

# Fractions of a full turn said as an angle ("a quarter turn round to its left").
TURN_FRACTIONS = {"quarter": "90", "half": "180"}
# A turn's share said as an ordinal ("a twelfth of a turn", "an eighth of a revolution", "one
# sixteenth of a full rotation"): 360 degrees over the ordinal's number.
TURN_ORDINALS = {
    "half": 2,
    "third": 3,
    "quarter": 4,
    "fifth": 5,
    "sixth": 6,
    "eighth": 8,
    "ninth": 9,
    "tenth": 10,
    "twelfth": 12,
    "sixteenth": 16,
    "eighteenth": 18,
    "twentieth": 20,
    "twenty fourth": 24,
    "thirty sixth": 36,
}
TURN_NOUNS = ("turn", "revolution", "rotation", "circle", "full turn", "full revolution", "full rotation", "full circle")
ONE_ARTICLES = ("a", "an", "one")
# The same share written with digits ("1/12 of a turn", "1/8th of a rotation").
_TURN_SHARE = re.compile(
    r"\b(\d+)\s*/\s*(\d+)(?:st|nd|rd|th)?\s+of\s+(?:a|one)\s+(?:full\s+)?(?:turn|revolution|rotation|circle)\b"
)


def _turn_degrees(numerator: int, denominator: int) -> str:
    """``numerator/denominator`` of a full turn in degrees, as the digits :func:`words` writes."""
    return f"{360.0 * numerator / max(denominator, 1):.4g}"


def _turns(tokens: list[str]) -> list[str]:
    """ "quarter turn" / "half turn" as "90 degrees turn" / "180 degrees turn" (not after "three":
    "three quarter" is a view); "a twelfth of a turn" as "30 degrees" (:data:`TURN_ORDINALS`)."""
    out: list[str] = []
    k = 0
    while k < len(tokens):
        token = tokens[k]
        after, before = tokens[k + 1] if k + 1 < len(tokens) else "", out[-1] if out else ""
        share = _turn_share(tokens, k)
        if share is not None and before != "three":
            degrees, k = share
            if out and out[-1] in ONE_ARTICLES:
                out.pop()
            out += [degrees, "degrees"]
            continue
        if token in TURN_FRACTIONS and after == "turn" and before != "three":
            out += [TURN_FRACTIONS[token], "degrees"]
        else:
            out.append(token)
        k += 1
    return out


def _turn_share(tokens: list[str], k: int) -> tuple[str, int] | None:
    """(degrees, the index after the phrase) when ``tokens[k:]`` open with "<ordinal> of a
    <turn>" (:data:`TURN_ORDINALS`, :data:`TURN_NOUNS`), else None."""
    for ordinal, parts in TURN_ORDINALS.items():
        said = ordinal.split()
        if tokens[k : k + len(said)] != said:
            continue
        rest = k + len(said)
        if tokens[rest : rest + 1] != ["of"] or tokens[rest + 1 : rest + 2] not in (["a"], ["one"]):
            return None
        for noun in sorted(TURN_NOUNS, key=len, reverse=True):
            noun_words = noun.split()
            if tokens[rest + 2 : rest + 2 + len(noun_words)] == noun_words:
                return _turn_degrees(1, parts), rest + 2 + len(noun_words)
        return None
    return None


# Hedges after a number ("50-odd degrees", "30ish", "40 or so"): the number itself, whose
# tolerance already allows for the hedge.
NUMBER_HEDGES = ("odd", "ish", "or so", "or thereabouts")


def _hedges(tokens: list[str]) -> list[str]:
    """A "-ish" suffix on a word of :data:`HEDGED_WORDS` as "a bit" before it ("high ish",
    "highish" -> "a bit high"); after any other word it is dropped ("macro-ish": a shot word's
    own range allows for it), and so it is after a diagonal's side ("front-right-ish", "rear
    left-ish": the diagonal's own tolerance allows for it, it is no slight side)."""
    out: list[str] = []
    for token in tokens:
        if token == "ish" and out[-2:-1] and out[-2] in DIAGONAL_ENDS and out[-1] in ("left", "right"):
            continue
        if token == "ish" and out and out[-1] in HEDGED_WORDS:
            out[-1:] = ["a", "bit", out[-1]]
        elif token == "ish" and out and out[-1].isalpha():
            continue
        elif token.endswith("ish") and _hedged(token[:-3]):
            out += ["a", "bit", _hedged(token[:-3])]
        else:
            out.append(token)
    return out


def _just(tokens: list[str]) -> list[str]:
    """ "Just" dropped before an article-led slight word of :data:`DEGREE_SCALE` that the scale does
    not list with it ("just a wee bit right of front-on", "just a tiny bit to its left" -> "a wee
    bit ...", the same slight amount, as "just a bit" already is); here, not as more table words,
    which every template with a degree word would carry."""
    out: list[str] = []
    for k, token in enumerate(tokens):
        if token == "just" and tokens[k + 1 : k + 2] == ["a"]:
            listed = (" ".join(tokens[k : k + n]) for n in (3, 4, 5))
            hedged = (" ".join(tokens[k + 1 : k + n]) for n in (3, 4, 5))
            if not any(p in _SLIGHT for p in listed) and any(p in _SLIGHT for p in hedged):
                continue
        out.append(token)
    return out


# A direction of turning said round about ("in the clockwise sense", "the anticlockwise way", "to
# the counter-clockwise side", ", going clockwise"): read as the direction alone, here once rather
# than in every roll template (parse18p6 had it in the {dir} macro, which every roll row carried).
# Words said before the direction (longest first; a comma only before a verb) and a noun after it.
TURN_DIRECTIONS = frozenset({"clockwise", "counterclockwise"})
TURN_DIRECTION_LEADS = (
    *((",", verb) for verb in ("going", "turning", "heading")),
    *((prep, article) for prep in ("in", "to", "towards", "toward") for article in ("the", "a")),
    ("going",),
    ("turning",),
    ("heading",),
    ("in",),
    ("to",),
    ("towards",),
    ("toward",),
    ("the",),
)
TURN_DIRECTION_NOUNS = frozenset({"way", "sense", "direction", "side", "fashion", "manner"})


def _turn_directions(tokens: list[str]) -> list[str]:
    """A direction of turning with the words of :data:`TURN_DIRECTION_LEADS` before it and a noun
    of :data:`TURN_DIRECTION_NOUNS` after it ("in the clockwise sense", "the anticlockwise way")
    as the direction alone."""
    out: list[str] = []
    k = 0
    while k < len(tokens):
        token = tokens[k]
        if token in TURN_DIRECTIONS:
            lead = next((w for w in TURN_DIRECTION_LEADS if len(out) >= len(w) and tuple(out[-len(w) :]) == w), ())
            del out[len(out) - len(lead) :]
            out.append(token)
            k += 2 if tokens[k + 1 : k + 2] and tokens[k + 1] in TURN_DIRECTION_NOUNS else 1
            continue
        out.append(token)
        k += 1
    return out


def _number_hedges(tokens: list[str]) -> list[str]:
    """A hedge of :data:`NUMBER_HEDGES` after a number dropped ("50 odd", "30 ish", "20 or so" ->
    the number)."""
    out: list[str] = []
    k = 0
    while k < len(tokens):
        hedge = next((h.split() for h in NUMBER_HEDGES if tokens[k : k + len(h.split())] == h.split()), None)
        if hedge and out and NUMBER.fullmatch(out[-1]):
            k += len(hedge)
            continue
        out.append(tokens[k])
        k += 1
    return out


def _hedged(stem: str) -> str | None:
    """The word of :data:`HEDGED_WORDS` a "-ish" stem spells, with the final consonant doubled
    ("biggish") or the final "e" dropped ("widish", "closish") as English writes them; else None."""
    for word in (stem, stem[:-1] if stem[-2:-1] == stem[-1:] else "", stem + "e"):
        if word in HEDGED_WORDS:
            return word
    return None


# "more X" said for a short adjective's comparative ("a little more high than", "go more far"),
# as people writing in a second language do: read as the comparative.
COMPARATIVES = {
    "high": "higher",
    "low": "lower",
    "far": "farther",
    "close": "closer",
    "near": "nearer",
    "big": "bigger",
    "large": "larger",
    "small": "smaller",
    "wide": "wider",
    "tight": "tighter",
}


def _comparatives(tokens: list[str]) -> list[str]:
    """ "more high" -> "higher" (:data:`COMPARATIVES`)."""
    out: list[str] = []
    for token in tokens:
        if out and out[-1] == "more" and token in COMPARATIVES:
            out[-1] = COMPARATIVES[token]
        else:
            out.append(token)
    return out


# Words after which "to up" / "to down" is the way the camera looks or points, as other languages
# say it ("look to up", "straight to down"): the "to" is dropped.
LOOK_WORDS = frozenset(
    {"look", "looks", "looking", "straight", "directly", "point", "points", "pointing", "aim", "aiming", "tilt", "tilted"}
)


def _to_up_down(tokens: list[str]) -> list[str]:
    """``tokens`` without a "to" between a word of looking (:data:`LOOK_WORDS`) and "up"/"down"."""
    return [
        t
        for k, t in enumerate(tokens)
        if not (t == "to" and 0 < k < len(tokens) - 1 and tokens[k - 1] in LOOK_WORDS and tokens[k + 1] in ("up", "down"))
    ]


# "Proper right" / "proper left", as museums and heralds say the object's own side ("View: proper
# right side", "the statue's proper left"): after a possessive "own", else "its own" (the article
# before it goes: "from the proper left"); not "a proper right angle".
PROPER_SIDE_AFTER = frozenset({"'s", "its", "his", "her", "their"})


def _proper_sides(tokens: list[str]) -> list[str]:
    """``tokens`` with "proper" before "left"/"right" read as the subject's own (:data:`PROPER_SIDE_AFTER`)."""
    out: list[str] = []
    for k, token in enumerate(tokens):
        after = tokens[k + 1 : k + 3]
        if token != "proper" or after[:1] not in (["left"], ["right"]) or after[1:] in (["angle"], ["angles"]):
            out.append(token)
        elif out and out[-1] in PROPER_SIDE_AFTER:
            out.append("own")
        elif out and out[-1] in ("a", "an"):
            out.append(token)
        else:
            if out and out[-1] == "the":
                out.pop()
            out += ["its", "own"]
    return out


def _side_letters(tokens: list[str]) -> list[str]:
    """``tokens`` with a lone "l" or "r" beside a view word or a word of the frame's areas read as
    the side it abbreviates (:data:`SIDE_LETTERS`: "L profile", "3/4 R", "rear L", "lower L"), also across the full stop of an
    abbreviation ("R. profile"), or after a possessive ending a clause ("3/4 front, his L"); elsewhere
    the letter is left as written."""
    out = list(tokens)
    for k, token in enumerate(tokens):
        if token not in SIDE_LETTERS:
            continue
        dotted = tokens[k + 1 : k + 2] == ["."] and tokens[k + 2 : k + 3] != [] and tokens[k + 2] in SIDE_LETTER_NEIGHBOURS
        neighbours = tokens[max(k - 1, 0) : k] + tokens[k + 1 : k + 2]
        owned = tokens[k - 1 : k] in (["his"], ["her"], ["its"]) and (k + 1 == len(tokens) or tokens[k + 1] in PUNCTUATION)
        if dotted or owned or any(n in SIDE_LETTER_NEIGHBOURS for n in neighbours):
            out[k] = SIDE_LETTERS[token]
            if dotted:  # the abbreviation's full stop ends no sentence
                out[k + 1] = ""
    return [t for t in out if t]


def _compounds(tokens: list[str]) -> list[str]:
    out: list[str] = []
    for k, token in enumerate(tokens):
        if out and (out[-1], token) in SHOT_HOMOPHONES and tokens[k + 1 : k + 2] and tokens[k + 1] in SHOT_HOMOPHONE_NOUNS:
            out[-1:] = [SHOT_HOMOPHONES[(out[-1], token)]]
        elif out and (out[-1], token) in COMPOUNDS:
            out[-1:] = COMPOUNDS[(out[-1], token)].split()
        else:
            out.append(token)
    return out


def _numbers(tokens: list[str]) -> list[str]:
    """Number words as digits: "thirty" -> "30", "twenty five" -> "25", "minus 20" -> "-20", "a dozen" -> "12"."""
    out: list[str] = []
    i = 0
    while i < len(tokens):
        token, after = tokens[i], tokens[i + 1] if i + 1 < len(tokens) else ""
        if token == "dozen" and out and out[-1] in ("a", "one"):
            # "a dozen degrees" (parse18p6), "half a dozen": 12 and 6
            out.pop()
            value, i = 12, i + 1
            if out and out[-1] == "half":
                out.pop()
                value = 6
        elif token in TENS:
            value, i = TENS[token], i + 1
            if after in UNITS and 0 < UNITS[after] < 10:
                value, i = value + UNITS[after], i + 1
        elif token in UNITS and after not in FRACTION_WORDS and (token != "one" or after in NUMBER_UNITS):
            value, i = UNITS[token], i + 1
        else:
            out.append(token)
            i += 1
            continue
        out.append(str(value))
    out = _hundreds(out)
    signed: list[str] = []
    for token in out:
        if signed and signed[-1] in SIGN_WORDS and NUMBER.fullmatch(token):
            signed[-1] = "-" + token
        else:
            signed.append(token)
    return signed


def _hundreds(tokens: list[str]) -> list[str]:
    """Hundreds said in words, the rest already digits: "one hundred and 20" -> "120", "a hundred
    10" -> "110", "2 hundred" -> "200"."""
    out: list[str] = []
    i = 0
    while i < len(tokens):
        if tokens[i] == "hundred" and out and (out[-1] in ("a", "one") or out[-1] in {str(v) for v in range(1, 10)}):
            value = 100 * (1 if out[-1] in ("a", "one") else int(out[-1]))
            step = 3 if tokens[i + 1 : i + 2] == ["and"] else 2
            rest = (tokens[i + step - 1 : i + step] or [""])[0]
            if rest.isdigit() and int(rest) < 100:
                value, i = value + int(rest), i + step
            else:
                i += 1
            out[-1] = str(value)
            continue
        out.append(tokens[i])
        i += 1
    return out


IRREGULAR_PLURALS = {
    "people": "person",
    "children": "child",
    "mice": "mouse",
    "feet": "foot",
    "teeth": "tooth",
    "geese": "goose",
    "knives": "knife",
    "leaves": "leaf",
}


def singular(word: str) -> str:
    """A crude singular, applied alike to names and mentions, so plural and singular agree
    ("bears", "benches", "shelves", "tvs") even where the stem is not a real word."""
    if word in IRREGULAR_PLURALS:
        return IRREGULAR_PLURALS[word]
    if len(word) < 3 or not word.endswith("s") or word.endswith(("ss", "us", "is", "'s")):
        return word
    if word.endswith("ies") and len(word) > 4:
        return word[:-3] + "y"
    if word.endswith("lves"):
        return word[:-3] + "f"
    if word.endswith(("ches", "shes", "xes", "zzes", "sses")):
        return word[:-2]
    return word[:-1]


# Words that ask nothing of the camera: function words, politeness, praise and the nouns for a
# picture. An unparsed run made only of these is filler; any other unparsed word may be a
# constraint the parser missed, so the instruction is only partly understood
# (:meth:`~capframe.translate.instruction.ParsedInstruction.not_understood`).
FILLER_WORDS = frozenset(
    """a an the this that these those it its them their his her my our your me us we i you 's
    of with and or plus in on at to from by for as so but into onto about then also both there here
    is are be being was were am do does did can could would will should shall may might must let
    please kindly thanks thank cheers hey hi hello ok okay maybe perhaps possibly just really
    nice lovely beautiful pretty good great cool neat clean simple cute gorgeous stunning
    classic decent proper quick some one many
    cosy cozy moody atmospheric arty artsy artistic elegant charming pleasing pleasant inviting
    somewhere same together roughly approximately around circa
    photo photograph picture pic image shot snapshot snap frame capture view render rendering
    want like love need have get take make see show give grab gimme try go going looking request
    fancy nothing color colors tones vibe vibes whatsoever sure ensure basically again needs ought gotta
    include including ie namely
    too well visible included until while when because if though""".split()
)


# Words of the phrase tables people often mistype ("eye hight", "from the rigth", "a bit abvoe").
# A word is read as one of these when it is no word the tables or the scene's names use and it is
# the target with two adjacent letters swapped or one letter doubled (4 letters or more), or with
# one letter dropped (5 letters or more: "frnt", "abov", "levl"), unless that makes an ordinary
# word (:data:`DROPPED_INTO_WORDS`: "below" loses a letter into "blow", "close" into "lose");
# :func:`slip_of` decides, the parser reports each reading.
SLIP_TARGETS = (
    "from",
    "height",
    "level",
    "above",
    "below",
    "behind",
    "front",
    "left",
    "right",
    "center",
    "middle",
    # The ends and the side too ("raer", "bakc", "sdie"; "reer" is spelt by ear: SPELLINGS).
    "rear",
    "back",
    "side",
    "close",
    "angle",
    "frame",
    "degrees",
    "clockwise",
    "counterclockwise",
    "overhead",
    "profile",
    "quarter",
    "corner",
    "bottom",
    "straight",
    "slightly",
    "underneath",
    "beneath",
    "vertical",
    "horizon",
    "looking",
    "perspective",
    "horizontal",
    "elevation",
    # Intensifiers and size words, read as emphasis grades a size ("realy big", "hugh").
    "really",
    "little",
    "large",
    # The middle shot size ("medum shot", "meduim").
    "medium",
    # The picture itself ("in the centre of the pictur", "middle of the phto").
    "picture",
    "photo",
)
MIN_SLIP_LETTERS = 4  # a swap or a doubled letter
MIN_DROPPED_LETTERS = 5  # a dropped letter
# Ordinary words a target of 5 letters becomes with one letter dropped: never read as it.
DROPPED_INTO_WORDS = frozenset({"blow", "lose", "font", "fame"})


def slip_of(word: str) -> str | None:
    """The word of :data:`SLIP_TARGETS` that ``word`` mistypes (see there), or None."""
    if not word.isalpha() or word in SLIP_TARGETS or len(word) < MIN_SLIP_LETTERS:
        return None
    for target in SLIP_TARGETS:
        if len(target) >= MIN_SLIP_LETTERS and (transposed(word, target) or doubled(word, target)):
            return target
        if len(target) >= MIN_DROPPED_LETTERS and word not in DROPPED_INTO_WORDS and dropped(word, target):
            return target
    return None


# --- graded words (the parser's tables read these) -----------------------------------------------

# How strongly a side, a height or a size is asked, applied alike to all three ("a touch high",
# "a smidge to its right", "kind of from above"; "very high", "way up"; "dead on", "squarely from
# the front"). Multi-word entries are normalised words (:func:`words`: "kinda" is "kind of").
DEGREE_SCALE = {
    # Short of the named side or height: between it and the neighbour (the "slight" classes).
    "slight": (
        "slightly",
        "somewhat",
        "marginally",
        "mildly",
        "gently",
        "a little bit",
        "a tiny bit",
        "a wee bit",
        "just a bit",
        "a bit",
        "a little",
        "a tad",
        "a touch",
        "a smidge",
        "a smidgen",
        "a hair",
        "a shade",
        "a fraction",
        "a notch",
        "one notch",
        "a nudge",
        "a skosh",
        # A hair's width (parse18p6: "from a whisker above it").
        "a whisker",
        "a hair 's breadth",
        "a whisker 's breadth",
        "a teeny bit",
        "a little tiny bit",
        "ever so slightly",
        "just a little",
        "just a touch",
        "just a tad",
        "just slightly",
        "kind of",
        "sort of",
        # Said without the article ("bit above", "little bit to the left"; parse20h: "little higher
        # than it", "little more low", as non-native writers drop it).
        "bit",
        "little bit",
        "tiny bit",
        "little",
    ),
    # More than the plain word: the steeper height class ("very high" is a high angle).
    "strong": ("very", "really", "real", "way", "well", "far", "super", "extremely", "quite", "strongly", "steeply"),
    # Exactly the named side, no offset ("directly from the left", "dead on").
    "exact": (
        "directly",
        "straight",
        "squarely",
        "square",
        "fully",
        "exactly",
        "dead",
        "completely",
        "perfectly",
        "purely",
        "precisely",
        "bang",
        "smack",
    ),
}

_SLIGHT = frozenset(DEGREE_SCALE["slight"])
# A small turn said without a number ("swung a few degrees to its left", "a couple of degrees
# towards the front"): as the slight degree words, 10 to 40 degrees off the side it starts from.
OFFSET_HEDGES = (
    "a few degrees",
    "few degrees",
    "a couple of degrees",
    "a couple degrees",
    "couple of degrees",
    "several degrees",
    "some degrees",
    "a few notches",
    "a couple of notches",
    "a little way",
    "a short way",
    "a small amount",
    "a small angle",
    "a slight angle",
    "a little angle",
    "a few degrees more",
    "a wee way",
    # Steps round, as one walks it ("walk a few steps round to its right").
    "a few steps",
    "few steps",
    "a couple of steps",
    "a couple steps",
    "a step or two",
    "a step",
    "one step",
    # The slight words said bare ("from the rear, little to the right", "just left of the front").
    "little",
    "tad",
    "touch",
    "smidge",
    "hair",
    "just",
    "only just",
    "barely",
    "fractionally",
)
# "X on" said of the camera facing the subject: the front, straight ("dead on", "square on",
# "nose on"); its back end the same way ("tail on").
HEAD_ON_WORDS = (
    "head",
    "face",
    "nose",
    "front",
    "straight",
    "dead",
    "square",
    "squarely",
    "directly",
    "bang",
    "smack",
    "full",
)
TAIL_ON_WORDS = ("tail", "rear", "stern", "butt")
# Parts of a subject that lie on one side of it: naming one names that side ("its left flank",
# "from its right arm end", "the fridge's left-hand side panel").
SIDE_PARTS = (
    "side",
    "profile",
    "flank",
    "end",
    "hand end",
    "hand side",
    "arm",
    "arm end",
    "arm side",
    "side panel",
    "panel",
    "corner",
    "shoulder",
    "quarter",
)
# Parts a subject has on each side: named by its side and turned to the camera, that side is seen
# ("the right armrest end pointed at the lens", "its left-hand doors square to camera"); alone they
# name no side ("a fridge's left door" is on its front).
SIDED_PARTS = (
    "arm",
    "arms",
    "armrest",
    "armrests",
    "arm rest",
    "arm rests",
    "door",
    "doors",
    "wheel",
    "wheels",
    "window",
    "windows",
    "leg",
    "legs",
    "ear",
    "ears",
)
# Parts found only at one end of a subject: naming one names that end ("the bench's backrest
# side", "its tail lights", "the grille of the car").
END_PARTS = {
    "back": (
        "backrest",
        "back rest",
        "back panel",
        "rear panel",
        "tail light",
        "tail lights",
        "taillight",
        "taillights",
        "tailgate",
        "rear window",
        "rear bumper",
        "spine",
        # The back of a cabinet or a screen ("the bookcase's backing board", "its back face").
        "backing board",
        "backing boards",
        "backboard",
        "back board",
        "backing",
        "back face",
        "rear face",
        "back wall",
        "rear wall",
        "back cover",
        "rear cover",
        "back plate",
        "backplate",
    ),
    "front": (
        "headlight",
        "headlights",
        "grille",
        "front bumper",
        "windscreen",
        "windshield",
        "front panel",
        "dial",
        "front face",
        "faceplate",
        "face plate",
        "fascia",
        "front cover",
        # A screen is the front of what carries it ("aim straight at the TV's screen").
        "screen",
        "display",
    ),
}
# Parts that name the end they sit at only when turned to the camera ("its seat to us", "the
# bookcase square to its shelves", "back bumper square to the lens"): alone they may be a height
# or a target ("at seat height", "focus on the shelves"). END_PARTS' parts and the ends' own words
# count too. A part not here stays not understood ("its handle to camera"), never guessed.
FACING_PARTS = {
    "back": (
        "back",
        "rear",
        "backside",
        "back bumper",
        "boot",
        "trunk",
        "tail",
        "tail end",
        "rear end",
        "back end",
        "hind end",
        "bum",
        "butt",
        "behind",
        "back legs",
        "back wheels",
        "rear wheels",
        "exhaust",
    ),
    "front": (
        "front",
        "face",
        "nose",
        "bow",
        "front end",
        "bonnet",
        "hood",
        "front wheels",
        "eyes",
        "belly",
        "tummy",
        "chest",
        "seat",
        "seats",
        "seat cushion",
        "seat cushions",
        "cushions",
        "slats",
        "seat slats",
        # A bookcase's books show their spines at its front ("all the book spines facing out").
        "book spines",
        "books",
        "shelves",
        "shelf",
        "door",
        "doors",
        "door handle",
        "door handles",
        "drawer",
        "drawers",
        "keys",
        "keyboard",
        "controls",
        "buttons",
        "opening",
        "mouth",
        "front legs",
    ),
}
# "<creature>'s-eye view": whose eye the camera takes, by the elevation class it sits at ("a
# god's-eye view" is a bird's-eye one, "an ant's-eye view" a worm's-eye one, "a frog's-eye view"
# a low angle).
# The same creatures name a view without the eye, as other languages do ("bird perspective", German
# Vogelperspektive; "frog perspective", Froschperspektive; "an ant's view", "satellite view"),
# with one of :data:`EYE_VIEW_NOUNS` after them.
EYE_VIEWS = {
    "bird's-eye": (
        "bird",
        "birds",
        "god",
        "gods",
        "eagle",
        "hawk",
        "crow",
        "pigeon",
        "seagull",
        "gull",
        "owl",
        "falcon",
        "vulture",
        "satellite",
        "helicopter",
        "aeroplane",
        "airplane",
        "aircraft",
        "pilot",
    ),
    "worm's-eye": ("worm", "worms", "earthworm", "ant", "ants", "bug", "bugs", "beetle", "insect", "mole", "snail", "slug"),
    "low angle": ("frog", "frogs", "toad", "mouse", "rat", "rabbit", "dog", "cat", "pet"),
}
# Nouns naming a view after its creature ("a bird perspective", "the frog's view", "ant POV").
EYE_VIEW_NOUNS = ("view", "perspective", "angle", "shot", "pov", "point of view", "vantage", "vantage point", "viewpoint")

# Parts of the catalog's kinds of things (capframe.synth.objects builds each kind from them), by
# kind: a camera level with one (or at its height) is level with the subject ("lens level with its
# snout", "at bonnet height", "lens at slat height", "at the height of its leaves"); a part is never
# a subject. Parts at a subject's foot are not here ("roots", "base": HEIGHT_ANCHORS' low angle), nor
# words that also name things of their own ("pot", "mirror", "books", "bulb", "pole", "band": an
# unknown subject stays one).
SUBJECT_PARTS = {
    "vehicle": (
        "bonnet",
        "hood",
        "roof",
        "roofline",
        "roof line",
        "cabin",
        "bumper",
        "bumpers",
        "window",
        "windows",
        "side window",
        "side windows",
        "door",
        "doors",
        "headlight",
        "headlights",
        "headlamp",
        "headlamps",
        "grille",
        "grill",
        "wheel",
        "wheels",
        "tyre",
        "tyres",
        "tire",
        "tires",
        "hubcap",
        "hubcaps",
        "wheel arch",
        "wheel arches",
        "dashboard",
        "trunk lid",
        "number plate",
        "license plate",
        "licence plate",
        "wing mirror",
        "wing mirrors",
        # A vehicle's lamps said plainly ("camera on the height of the lights"); "light" alone also
        # names a lamp, so only the plural and the named ones are parts.
        "lights",
        "front lights",
        "tail lights",
        "taillights",
        "rear lights",
        "brake lights",
        "fog lights",
        "indicators",
        "axle",
        "axles",
    ),
    "creature": (
        "snout",
        "muzzle",
        "ears",
        "ear",
        "paw",
        "paws",
        "tummy",
        "eyes",
        "whiskers",
        "bow tie",
        "arms",
        "legs",
        "body",
        "shoulders",
        "belly button",
    ),
    "furniture": (
        "backrest",
        "back rest",
        "armrest",
        "armrests",
        "arm rest",
        "arm rests",
        "arms",
        "seat cushion",
        "seat cushions",
        "cushions",
        "seat pad",
        "seat pads",
        "headrest",
        "slat",
        "slats",
        "seat slats",
        "tabletop",
        "table top",
        "middle shelf",
    ),
    "appliance": ("handle", "handles", "door", "freezer door", "fridge door", "screen", "bezel"),
    "plant": ("leaf", "leaves", "foliage", "fronds", "frond", "stem", "stems", "stalk", "stalks", "pot rim", "crown", "canopy"),
    "lamp": ("lampshade", "stem"),  # not "shade": "a shade high" is a degree
    "thing": ("lid", "rim", "lip", "brim", "spout", "knob", "dial", "neck", "mouth", "tip", "stripe"),
}

# Heights named by what stands at them, each read as one elevation class of
# :data:`~capframe.constraints.ELEVATIONS`: a body or a surface the subject sits on is level with
# it ("chest height", "at table height", "at its own height"); the ground, the floor, a knee or a
# crouch is below it; a ladder or "up high" above it; a drone far above.
HEIGHT_ANCHORS = {
    "eye level": (
        "eye",
        "chest",
        "shoulder",
        "head",
        "face",
        "waist",
        "hip",
        "belly",
        "seat",
        "table",
        "tabletop",
        "desk",
        "counter",
        "countertop",
        "bench",
        "shelf",
        "bed",
        "sofa",
        "couch",
        "chair",
        "lap",
        "cushion",
        "pillow",
        "armrest",
        "worktop",
        "own",
        "same",
        # A person's own eye height, standing or seated ("at standing height", "sitting height").
        "standing",
        "sitting",
        "seated",
        "its",
        "subject",
        # Parts at a subject's own middle height ("at screen height", "level with its nose").
        "screen",
        "nose",
        "mouth",
        "chin",
        "neck",
        "torso",
        "handle",
        # Its middle ("camera held level with its middle", "from 15 degrees below its centre").
        "middle",
        "center",
        "midpoint",
        "mid point",
        "midsection",
        "mid section",
        # Any part of the subject itself ("lens down at bonnet height", "level with its snout",
        # "crouched down to its roofline"): the camera at the subject's own height.
        *(part for parts in SUBJECT_PARTS.values() for part in parts),
    ),
    # Parts at a subject's foot ("at the height of its base", "from plinth level") are below it.
    "low angle": (
        "ground",
        "floor",
        "knee",
        "shin",
        "ankle",
        "grass",
        "lawn",
        "foot",
        "feet",
        "toe",
        "root",
        "roots",
        "base",
        "plinth",
        "skirting",
        "skirting board",
        "baseboard",
        # What covers the floor or the ground ("from rug level", "at carpet height").
        "rug",
        "carpet",
        "floorboards",
        "pavement",
        "gravel",
        "soil",
    ),
}
# Words saying the camera is at a height, as "level with" does ("even with its head", "flush with
# the seat", "on a par with its roof"); "in line with" is left out: it also aligns things in the frame.
LEVEL_WITH = (
    "level with",
    "level to",
    "even with",
    "flush with",
    "on a level with",
    "on level with",
    "on a par with",
    "on par with",
    # Non-native and spoken forms ("on height with the lights", "at the same level with its seat").
    "levelled with",
    "leveled with",
    "on height with",
    "on a height with",
    "on one height with",
    "on one level with",
    "in level with",
    "at level with",
    "at height with",
    "on the same height with",
    "at the same height with",
    "on the same level with",
    "at the same level with",
)
# Small angles said without a number ("a few degrees above", "a couple of degrees down"): the
# slight height classes, as "a bit" is. Plain words; the parser normalises them as it does text.
FEW_DEGREES = (
    "a few degrees",
    "few degrees",
    "a couple of degrees",
    "a couple degrees",
    "couple of degrees",
    "couple degrees",
    "a degree or two",
    "one or two degrees",
    "two or three degrees",
    "a handful of degrees",
    "several degrees",
    "a few degrees or so",
    # A short way, said as a distance (parse18p6: "a few centimetres under its middle").
    "a few centimeters",
    "a few centimetres",
    "a couple of centimetres",
    "a centimetre or two",
    "a few cm",
    "a few inches",
    "a couple of inches",
    "a couple of centimeters",
    "an inch or two",
    "a centimeter or two",
)
# Places a camera looks down from, higher than anything a scene's subject stands on ("from a
# first-floor window", "from upstairs", "off the rooftop", "from a crane"): a high angle. Plain
# words; the parser normalises them ("2nd floor" is "2 nd floor").
HIGH_PLACES = (
    "first floor",
    "second floor",
    "third floor",
    "top floor",
    "upper floor",
    "upper storey",
    "first storey",
    "second storey",
    "1st floor",
    "2nd floor",
    "3rd floor",
    "upstairs",
    "rooftop",
    "roof top",
    "mezzanine",
    "crane",
    "jib",
    "cherry picker",
    "scaffolding",
    "scaffold",
    "tree house",
    "treehouse",
)
# What such a place is looked out of ("a first-floor window", "the upstairs landing").
HIGH_PLACE_OPENINGS = ("window", "windows", "balcony", "landing", "level", "railing")
# Amounts of height said as a size ("from a fair height", "at a good elevation"): a high angle.
HEIGHT_AMOUNTS = ("fair", "good", "decent", "great", "considerable", "reasonable", "healthy", "respectable", "goodly")


# Single words for a size, said after the subject or alone as a clause ("the cup small, bottom
# right", "sofa tiny in the upper half", "TV big and square on"), or after a verb of being or
# seeming ("it must be big", "make the fridge look massive").
SIZE_WORDS = {
    "close-up": (
        "big",
        "large",
        "huge",
        "massive",
        "enormous",
        "giant",
        "gigantic",
        "ginormous",
        "humongous",
        "colossal",
        "prominent",
        "close",
        "tight",
        "closer",
        "tighter",
        "bigger",
        "larger",
    ),
    "wide": (
        "small",
        "tiny",
        "little",
        "wee",
        "distant",
        "far",
        "wide",
        "smaller",
        "wider",
        "minuscule",
        "teeny",
        "diminutive",
        "teeny tiny",
        "itty bitty",
        "teeny weeny",
        "itsy bitsy",
        "teensy",
        "titchy",
    ),
}
# Size idioms: verbs of moving in or back, and phrases for the whole subject with little room.
SIZE_IDIOMS = {
    "close-up": (
        "punch in",
        "push in",
        "zoom in",
        "move in",
        "get in close",
        "go in close",
        "come in close",
        "get up close",
        "get right up close",
        "dolly in",
        "crop in",
        "cut in",
        "tighten up",
        "headshot",
        "head shot",
        "fill up the frame",
        "macro",
        # Framings named by where the figure is cut: part of it fills the frame, whatever film
        # usage calls the shot ("from the waist up" is a medium shot of a person standing in a
        # scene, but of the subject it is a crop larger than the frame).
        "from the waist up",
        "waist up",
        "from the knees up",
        "knees up",
        "head and shoulders",
        "from the chest up",
        "chest up",
        "from the shoulders up",
        "shoulders up",
    ),
    "medium": (
        "head to toe",
        "head to foot",
        "top to bottom",
        "end to end",
        "full length",
        "full body",
        "full figure",
        "whole thing",
        "whole of it",
        "all of it",
        "the entire thing",
        "uncropped",
        "nothing cut off",
        "nothing cut",
        "nothing cropped off",
        "nothing chopped off",
        "no cropping",
        "nothing cropped",
        "not cropped",
        "without cropping",
    ),
    "wide": (
        "pull back",
        "pull out",
        "back off",
        "back up",
        "back away",
        "stand back",
        "stay back",
        "get back",
        "step back",
        "step away",
        "zoom out",
        "establishing",
        "from a way off",
    ),
}
# Shares of the frame said as fractions ("a third of the frame", "two-thirds of the picture"); a
# percentage is read from its digits ("70% of the frame").
FRAME_FRACTIONS = {
    "a tenth": 0.1,
    "a fifth": 0.2,
    "a quarter": 0.25,
    "one quarter": 0.25,
    "a third": 1 / 3,
    "one third": 1 / 3,
    "half": 0.5,
    "a half": 0.5,
    "one half": 0.5,
    "two thirds": 2 / 3,
    "three quarters": 0.75,
    "four fifths": 0.8,
}
# Words for a camera turned about its lens axis, besides "rolled" and "tilted": verbs said with
# degrees and a direction ("skewed 10 degrees anticlockwise", "banked 15 degrees left") and
# adjectives of a crooked frame ("a bit askew", "a wonky horizon": a dutch angle; "tilted" alone
# stays unread, it may be a pitch).
ROLL_VERBS = (
    "skewed",
    "banked",
    "tipped",
    "leaned",
    "slanted",
    "slanting",
    "angled over",
    "cocked",
    "canted",
    # Tipping the camera about its own axis ("tip the camera ten degrees clockwise").
    "tip",
    "tips",
    # Dutch said as a verb ("dutch it 25 degrees anticlockwise", "dutched 10 degrees left").
    "dutch",
    "dutched",
    "dutching",
)
ROLL_ADJECTIVES = ("askew", "crooked", "wonky", "skewed", "off kilter", "lopsided", "slanted", "canted")
# Lines in the picture that stand for the horizon (parse18p6): the sky line, or where a support
# meets what is behind it ("the table line", "the edge of the table", "the floor line", "the line
# where grass meets sky"). Said level they ask for no roll; said turned, the camera turned the
# other way, as the horizon.
HORIZON_LINES = (
    "horizon",
    "horizon line",
    "line of the horizon",
    "skyline",
    "sky line",
)
HORIZON_SURFACES = (
    "table",
    "tabletop",
    "desk",
    "counter",
    "countertop",
    "worktop",
    "floor",
    "ground",
    "shelf",
    "sea",
    "water",
)
# What a subject seen very small is likened to ("the ball a speck in the middle", "the bench just
# a dot"): wide; never a subject of its own.
SPECK_WORDS = (
    "speck",
    "dot",
    "spot",
    "pinprick",
    "pin prick",
    "blip",
    "pinhead",
    "smudge",
    "blob",
    "dot on the horizon",
    "sliver",
    "postage stamp",
    "thumbnail",
    "stamp",
)
# Nouns for the kind of thing a subject is ("the full vehicle in frame", "the whole animal"):
# the subject itself, wherever a name would stand in a size phrase.
CLASS_NOUNS = (
    "vehicle",
    "animal",
    "creature",
    "object",
    "item",
    "figure",
    "body",
    "subject",
    "appliance",
    "machine",
    "furniture",
    "piece of furniture",
    "structure",
    "thing",
    # A kind named loosely as people name their things ("whole toy in frame", "the entire plant").
    "toy",
    "plant",
    "product",
    "prop",
)
# Room left around the subject ("loads of room around it", "lots of table around it"): wide.
PLENTY_WORDS = ("loads of", "lots of", "plenty of", "a lot of", "heaps of", "tons of", "masses of", "a load of")

# Object kinds by their everyday names and nicknames. A scene object whose name or alias is one of a
# group answers to every other word of that group ("telly" for a television, "couch" for a sofa,
# "ted" for a teddy bear), when no other object of the scene already uses that word.
NAME_SYNONYMS = (
    ("television", "tv", "telly", "tv set", "television set", "telie", "flat screen", "flatscreen", "tv screen"),
    ("sofa", "couch", "settee", "loveseat", "love seat", "divan", "sectional"),
    ("refrigerator", "fridge", "icebox", "fridge freezer", "refrigerator freezer"),
    (
        "teddy bear",
        "teddy",
        "ted",
        "stuffed bear",
        "plush bear",
        "soft toy",
        "plushie",
        "plush toy",
        "stuffed toy",
        "cuddly toy",
    ),
    ("potted plant", "plant", "pot plant", "houseplant", "house plant", "plant pot", "indoor plant"),
    ("floor lamp", "lamp", "standing lamp", "standard lamp", "lamp stand", "reading lamp", "floor light"),
    (
        "toy car",
        "car",
        "model car",
        "matchbox car",
        "toy vehicle",
        "little car",
        "miniature car",
        "diecast car",
        "automobile",
        "toy automobile",
        "model automobile",
    ),
    ("traffic cone", "cone", "safety cone", "road cone", "pylon", "traffic pylon"),
    ("armchair", "arm chair", "easy chair", "lounge chair", "chair", "recliner", "club chair", "wingback chair", "wing chair"),
    ("bookshelf", "bookcase", "book shelf", "bookshelves", "shelves", "shelving unit", "book case", "shelf unit", "shelving"),
    ("cushion", "pillow", "throw pillow", "scatter cushion", "throw cushion"),
    ("mug", "cup", "coffee mug", "coffee cup", "tea cup", "teacup"),
    ("coffee table", "low table", "table", "side table", "cocktail table"),
    ("ball", "beach ball", "toy ball", "football", "soccer ball", "rubber ball"),
    ("bench", "park bench", "garden bench"),
    ("vase", "flower vase", "jar"),
    ("tree", "small tree", "sapling", "young tree"),
)
# Longer everyday names of the same objects, as different people write them ("car toy",
# "3 seater", "stuffed animal"). They answer as synonyms do but, like the kinds, are never offered
# as the closest name to a word the scene lacks (a long descriptive name looks a little like too
# many words), and none carries a colour (a colour in a name excludes the object from a mention
# of another colour). A name written as one word ("teddybear", "sofabed") is read by
# Vocabulary.expansion, which reports it.
NAME_VARIANTS = (
    (
        "television",
        "smart tv",
        "led tv",
        "lcd tv",
        "plasma tv",
        "flat screen tv",
        "widescreen tv",
        "television screen",
        "teevee",
        # Slang for it (parse19p7).
        "goggle box",
        "gogglebox",
        "idiot box",
        "boob tube",
    ),
    ("sofa", "sofa bed", "daybed", "chaise longue", "2 seater", "3 seater", "2 seater sofa", "3 seater sofa"),
    ("refrigerator", "ice box", "american fridge", "refrigerator unit"),
    (
        "teddy bear",
        "stuffed animal",
        "plush animal",
        "cuddly bear",
        "toy bear",
        "bear toy",
        "soft bear",
        "stuffie",
        "teddy toy",
    ),
    ("potted plant", "flower pot", "leafy plant", "plant in a pot", "container plant", "potted tree", "tree in a pot"),
    ("floor lamp", "standing light", "tall lamp", "floor standing lamp", "pole lamp", "arc lamp", "torchere"),
    (
        "toy car",
        "toy motor car",
        "motor car",
        "toy auto",
        "car toy",
        "mini car",
        "model vehicle",
        "toy racer",
        "die cast car",
        # What collectors call it (parse19p7).
        "die cast model",
        "diecast model",
        "diecast",
    ),
    ("traffic cone", "witches hat", "hazard cone", "warning cone", "street cone", "highway cone", "safety pylon"),
    ("armchair", "reading chair", "comfy chair", "upholstered chair", "sitting chair", "1 seater", "fauteuil", "la z boy"),
    ("bookshelf", "book stand", "book rack", "book cabinet", "bookshelf unit", "storage shelf", "etagere"),
    (
        "cushion",
        "sofa cushion",
        "couch cushion",
        "couch pillow",
        "decorative pillow",
        "accent pillow",
        "scatter pillow",
        "seat cushion",
    ),
    ("mug", "tea mug", "cuppa", "drinking cup", "travel mug"),
    ("coffee table", "center table", "tea table", "lounge table", "occasional table", "living room table", "sofa table"),
    ("ball", "play ball", "kick ball", "bouncing ball", "plastic ball", "playground ball"),
    ("bench", "garden seat", "park seat", "outdoor bench", "wooden bench", "bench seat"),
    ("vase", "bud vase", "flower holder", "amphora"),
    ("tree", "shade tree", "leafy tree", "big tree", "tall tree", "conifer", "evergreen"),
)
# Kinds of those objects people name instead ("a potted palm", "the fern", "a chesterfield"): the
# first word of each group is the object's name, the others answer to it as synonyms do; they are
# never offered as the closest name to a word the scene lacks ("succulent" looks like "bicycle").
# A kind that is also an object of its own elsewhere ("rubber plant", "rocking chair", "wine
# rack"), a material ("an oak bench", "a pine table") or a part ("the freezer door") is left out:
# the scene lacking it must refuse it, the bench must stay a bench.
NAME_KINDS = (
    ("potted plant", "potted palm", "palm", "fern", "cactus", "succulent", "ficus", "monstera", "yucca", "shrub", "bush"),
    ("potted plant", "planter"),
    ("sofa", "chesterfield", "futon", "davenport"),
    ("floor lamp", "torchiere", "uplighter"),
    ("toy car", "race car", "racing car"),
    ("traffic cone", "marker cone", "construction cone"),
    ("armchair", "wingback", "tub chair", "accent chair", "fireside chair"),
    ("cushion", "bolster"),
    ("mug", "beaker", "tankard"),
    ("ball", "basketball", "volleyball", "bouncy ball"),
    ("bench", "pew"),
    ("vase", "urn"),
    ("tree", "palm tree"),
    # The shade on top of the lamp names it ("the lampshade, close up").
    ("floor lamp", "lampshade", "lamp shade"),
    # Kinds of tree said with "tree" ("the oak tree", "the young sapling"); a bare "oak" or "pine"
    # is as often a material ("the oak bench").
    ("tree", "oak tree", "pine tree", "birch tree", "maple tree", "fir tree", "apple tree", "cherry tree", "sapling"),
    ("ball", "sphere"),
    ("television", "monitor"),
)


# What a thing is told by when it is not named (parse19p7): a word for the class of objects it
# belongs to ("the vehicle", "that wooden seat", "the appliance", "greenery only") or a use or
# property only some kinds have ("the thing you'd put flowers in", "the round one you kick", "the
# little four-wheeled thing", "the bit of furniture with arms"). Each word names the kinds (first
# words of :data:`NAME_SYNONYMS`) it fits; a mention headed by a class word or by a word naming
# nothing in particular (:data:`DESCRIPTION_HEADS`) is the one scene object of a kind every such
# word in it fits (:meth:`Vocabulary.described`), never one of two. Colours are not here (a
# scene's green bench is as green as its plant), nor words that fit most things ("round", "big").
SEATS = ("armchair", "sofa", "bench")
PLANTS = ("potted plant", "tree")
DESCRIPTION_WORDS = {
    # Classes (hypernyms) of the catalog's kinds.
    "vehicle": ("toy car",),
    "drinkware": ("mug",),
    "appliance": ("refrigerator", "television"),
    "seat": SEATS,
    "seating": SEATS,
    "furniture": (*SEATS, "bookshelf", "coffee table"),
    "furnishing": (*SEATS, "bookshelf", "coffee table", "cushion"),
    "plaything": ("teddy bear", "toy car", "ball"),
    "greenery": PLANTS,
    "foliage": PLANTS,
    "vegetation": PLANTS,
    # Uses and properties.
    "flower": ("vase",),
    "wheel": ("toy car",),
    "wheeled": ("toy car",),
    "leafy": PLANTS,
    "leaf": PLANTS,
    "leave": PLANTS,
    "pot": ("potted plant",),
    "potted": ("potted plant",),
    "kick": ("ball",),
    "kicked": ("ball",),
    "inflatable": ("ball",),
    "bouncy": ("ball",),
    "sit": SEATS,
    "sat": SEATS,
    "book": ("bookshelf",),
    "arm": ("armchair", "sofa"),
    "squishy": ("cushion", "teddy bear"),
    "squashy": ("cushion", "teddy bear"),
    "soft": ("cushion", "teddy bear", "sofa", "armchair"),
    "lean": ("cushion", "sofa", "armchair"),
    "cuddly": ("teddy bear",),
    "drink": ("mug",),
    "screen": ("television",),
    "pointy": ("traffic cone",),
}
# Heads of a description that name nothing in particular ("the thing", "the one", "whatever",
# "the bit of furniture"): the description's words tell which object.
DESCRIPTION_HEADS = frozenset({"thing", "one", "whatever", "object", "item", "bit", "piece", "something"})
# What may follow a description's head ("the thing | you'd put flowers in", "the seat | out there",
# "the one | rooted in the ground"); any other word makes the head a modifier of a noun the scene
# may lack ("the seat belt", "a furniture catalogue").
DESCRIPTION_FOLLOWERS = frozenset(
    {"you", "i", "we", "they", "people", "kid", "that", "which", "with", "without", "for", "of", "in", "on", "at"}
    | {"by", "near", "out", "only", "there", "here", "to", "the", "a", "is", "has", "can", "would", "will", "d"}
)


def _description_head(tokens: tuple[str, ...], k: int) -> bool:
    """Whether ``tokens[k]`` heads a description: a class word or a word naming nothing in
    particular, last or followed by a function word, a participle or a description word."""
    if tokens[k] not in DESCRIPTION_HEADS and tokens[k] not in DESCRIPTION_CLASSES:
        return False
    after = tokens[k + 1] if k + 1 < len(tokens) else None
    return after is None or after in DESCRIPTION_FOLLOWERS or after in DESCRIPTION_WORDS or after.endswith(("ed", "ing"))


# The class words of the table, which head a description themselves ("the vehicle", "the only seat").
DESCRIPTION_CLASSES = frozenset(
    {"vehicle", "drinkware", "appliance", "seat", "seating", "furniture", "furnishing", "plaything"}
    | {"greenery", "foliage", "vegetation"}
)


# What a camera below the subject's support is under, or looks up through ("from below the
# floorboards", "underground, looking up through the grass", "pointing up through the wood"):
# the worm's-eye view from under the support.
SUPPORT_SURFACES = (
    "floor",
    "floorboards",
    "floorboard",
    "floor boards",
    "boards",
    "planks",
    "decking",
    "ground",
    "earth",
    "soil",
    "dirt",
    "turf",
    "grass",
    "lawn",
    "pavement",
    "paving",
    "tarmac",
    "concrete",
    "tiles",
    "carpet",
    "rug",
    "tabletop",
    "table top",
    "table surface",
    "surface",
    "wood",
    "glass",
    "sand",
    "snow",
    "gravel",
    "mud",
)
# Labels of a shot list or screenplay that name no constraint: a slate ("SC 12", "SHOT 6",
# "take 3") and a scene heading ("INT. LIVING ROOM - DAY", "EXT. GARDEN").
SLATE_LABELS = ("sc", "scene", "shot", "take", "setup", "set up", "slate", "panel", "board", "storyboard", "no", "number")
SCENE_HEADINGS = ("int", "ext", "int ext", "ext int", "i e", "interior", "exterior")
HEADING_TIMES = ("day", "night", "morning", "evening", "dusk", "dawn", "continuous", "later", "same")
# What a picture is for, said before its noun ("a shop product pic", "listing photo", "real-estate
# shot"): it asks nothing of the camera.
PURPOSES = (
    "product",
    "listing",
    "real estate",
    "property",
    "catalogue",
    "catalog",
    "shop",
    "store",
    "ecommerce",
    "e commerce",
    "marketing",
    "insurance",
    "advert",
    "promo",
    "promotional",
    "instagram",
    "social media",
    "portfolio",
    "inventory",
    "stock",
    "sale",
    "sales",
    "auction",
    "website",
    "web",
    "blog",
)
# Where the picture is taken, never a subject ("a wide establishing of the lounge", "wide shot of
# the yard", "kitchen scene: the mug close up"): the setting, understood and asking nothing.
SETTINGS = (
    "room",
    "living room",
    "sitting room",
    "front room",
    "lounge",
    "den",
    "kitchen",
    "dining room",
    "bedroom",
    "study",
    "office",
    "hall",
    "hallway",
    "studio",
    "garden",
    "back garden",
    "front garden",
    "yard",
    "backyard",
    "back yard",
    "front yard",
    "park",
    "patio",
    "terrace",
    "courtyard",
    "porch",
    "lawn",
    "playground",
    "outdoors",
    "scene",
    "setting",
    "interior",
    "house",
    "apartment",
)
# People a request is made for or by ("my grandson would like ...", "the client wants ...",
# "for my wife"): the requester, never a subject.
REQUESTERS = (
    "grandson",
    "granddaughter",
    "grandchild",
    "grandkids",
    "grandma",
    "grandmother",
    "grandpa",
    "grandfather",
    "gran",
    "nan",
    "nana",
    "granny",
    "wife",
    "husband",
    "partner",
    "son",
    "daughter",
    "mum",
    "mom",
    "mother",
    "dad",
    "father",
    "kid",
    "kids",
    "boss",
    "manager",
    "client",
    "customer",
    "agent",
    "editor",
    "director",
    "producer",
    "team",
    "colleague",
    "friend",
    "brother",
    "sister",
    "boyfriend",
    "girlfriend",
    "landlord",
    "landlady",
    "tenant",
    "buyer",
    "seller",
    "uncle",
    "aunt",
    "auntie",
    "neighbour",
    "neighbor",
    "teacher",
    "designer",
    "owner",
    "user",
    "supervisor",
    "art director",
)
# What a requester does ("would like", "wants", "has asked for").
WANTING = (
    "would like",
    "would love",
    "d like",
    "d love",
    "wants",
    "want",
    "needs",
    "need",
    "asked for",
    "has asked for",
    "is asking for",
    "asks for",
    "requests",
    "requested",
    "wishes",
    "would prefer",
    "prefers",
    "likes",
    "loves",
    "is after",
    "asked",
    "asks",
    "says",
    "said",
    "here",
    "writes",
    "wrote",
    "is hoping for",
    "hopes for",
)
# Words by which a speaker takes back what they just said and says it again ("from its left,
# sorry, I mean its right", "centred. No, put it on the left third", "scratch that, behind on its
# left", "front-right, uh, front-left I mean"): the value said after one replaces the value of the
# same kind said before it (parse's ``_corrected``). A bare "no" corrects only set off by a comma.
CORRECTION_MARKERS = (
    "sorry",
    "no wait",
    "wait",
    "scratch that",
    "strike that",
    "forget that",
    "actually no",
    "actually",
    "i mean",
    "i meant",
    "or rather",
    "make that",
    "correction",
    "my mistake",
    "my bad",
    "oops",
    "uh",
    "um",
    "er",
    "erm",
    "no(?= ,)",
)
# Said after the value it restates ("front-left I mean,"): set off as a clause of its own by words().
RESTATING_AFTER = ("i mean", "i meant")
# Whole phrases of politeness that ask nothing of the camera ("if it isn't too much trouble",
# "thank you so much"), in normalised words, as "please" and "thanks" alone.
COURTESIES = (
    "if it isn t too much trouble",
    "if it is not too much trouble",
    "if it s not too much trouble",
    "if it s no trouble",
    "if you don t mind",
    "if you do not mind",
    "if you wouldn t mind",
    "if possible",
    "if you can",
    "when you get a chance",
    "when you have a moment",
    "thank you so much",
    "thank you very much",
    "thanks so much",
    "thanks very much",
    "thanks a lot",
    "thanks a bunch",
    "many thanks",
    "much appreciated",
    "it would be great",
    "that would be great",
    "that would be lovely",
    "that d be great",
    "no rush",
    "is it possible to",
    "would it be possible to",
    "if that s possible",
    "this time",
)

# --- matching ---------------------------------------------------------------------------------

DETERMINERS = frozenset({"a", "an", "the", "this", "that", "these", "those", "my", "our", "your", "its", "their"})
# Each colour word's basic colour terms (Berlin and Kay's eleven). People name one colour many
# ways: a mention's colour agrees with an object's when they share a basic term ("the
# mustard-yellow settee" of a mustard sofa, a "cream" fridge the scene calls white, a "navy"
# chair of a blue one), and "the blue chair" still never matches a red armchair. Shared words
# still rank first: of a red and a maroon chair, "the red chair" is the red one.
COLOR_FAMILIES: dict[str, frozenset[str]] = {
    word: frozenset(terms.split())
    for word, terms in {
        "red": "red",
        "blue": "blue",
        "green": "green",
        "yellow": "yellow",
        "orange": "orange",
        "purple": "purple",
        "pink": "pink",
        "brown": "brown",
        "black": "black",
        "white": "white",
        "gray": "gray",
        "reddish": "red",
        "bluish": "blue",
        "greenish": "green",
        "yellowish": "yellow",
        "orangey": "orange",
        "purplish": "purple",
        "pinkish": "pink",
        "brownish": "brown",
        "blackish": "black",
        "whitish": "white",
        "grayish": "gray",
        "violet": "purple",
        "lilac": "purple pink",
        "lavender": "purple",
        "indigo": "blue purple",
        "navy": "blue",
        "teal": "blue green",
        "turquoise": "blue green",
        "cyan": "blue green",
        "aqua": "blue green",
        "emerald": "green",
        "olive": "green brown yellow",
        "khaki": "brown green yellow",
        "crimson": "red",
        "scarlet": "red",
        "maroon": "red brown purple",
        "burgundy": "red purple",
        "magenta": "pink purple red",
        "coral": "pink orange red",
        "terracotta": "orange red brown",
        "copper": "orange brown",
        "bronze": "brown orange yellow",
        "amber": "orange yellow",
        "ochre": "yellow orange brown",
        "mustard": "yellow brown orange",
        "gold": "yellow orange",
        "golden": "yellow orange",
        "beige": "brown white yellow",
        "tan": "brown yellow orange",
        "cream": "white yellow",
        "ivory": "white yellow",
        "silver": "gray white",
        "charcoal": "gray black",
    }.items()
}
COLORS = frozenset(COLOR_FAMILIES)
# Words that describe rather than name ("the big red chair"): ignored when matching partially.
ATTRIBUTES = COLORS | {
    "big",
    "small",
    "large",
    "little",
    "tiny",
    "huge",
    "giant",
    "enormous",
    "gigantic",
    "massive",
    "tall",
    "short",
    "old",
    "new",
    "wooden",
    "metal",
    "plastic",
    "round",
    "fluffy",
    "soft",
    "cute",
    "nice",
    "dark",
    "light",
    "pale",
    "bright",
}


@dataclass(frozen=True)
class VocabularyEntry:
    """One nameable object.

    Attributes:
        name: its scene name (what subjects are matched to).
        symmetric: whether it has no canonical front.
        aliases: its other names, as given.
        forms: name and aliases, normalised and singular, longest first.
    """

    name: str
    symmetric: bool
    aliases: tuple[str, ...]
    forms: tuple[tuple[str, ...], ...]

    @property
    def words(self) -> frozenset[str]:
        return frozenset(w for form in self.forms for w in form)

    @property
    def colors(self) -> frozenset[str]:
        return self.words & COLORS


def key(text: str) -> tuple[str, ...]:
    """Normalised singular words of a name or mention, without determiners and punctuation."""
    return tuple(singular(w) for w in words(text) if w not in DETERMINERS and w not in PUNCTUATION and w != "'s")


class Vocabulary:
    """The names a scene answers to. See the module docstring for the matching rules."""

    def __init__(self, entries: list[VocabularyEntry]):
        names = [e.name.lower() for e in entries]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise InputError(f"object names {duplicates} are not unique; subjects are matched by name")
        self.entries = tuple(entries)
        self._by_name = {e.name: e for e in entries}
        self._corrections: dict[str, tuple[str, ...] | None] = {}  # the parser asks per run of words
        self._expansions: dict[str, tuple[str, ...] | None] = {}  # and per word it does not know

    @classmethod
    def from_semantics(cls, objects) -> Vocabulary:
        """From the scene's semantic objects (anything with ``name``, ``aliases``, ``symmetric``)."""
        entries = []
        for o in objects:
            forms = {key(n) for n in (o.name, *o.aliases)} - {()}
            if not forms:
                raise InputError(f"object name {o.name!r} has no words to match")
            entries.append((o, forms))
        synonyms = _synonym_forms([forms for _, forms in entries])
        return cls(
            [
                VocabularyEntry(
                    o.name, bool(o.symmetric), tuple(o.aliases), tuple(sorted(forms | extra, key=lambda f: (-len(f), f)))
                )
                for (o, forms), extra in zip(entries, synonyms)
            ]
        )

    @property
    def names(self) -> list[str]:
        """The object names, sorted."""
        return sorted(self._by_name)

    def __contains__(self, name: str) -> bool:
        return name in self._by_name

    def __len__(self) -> int:
        return len(self.entries)

    def symmetric(self, name: str) -> bool:
        """Whether the object called ``name`` has no canonical front."""
        return self._by_name[name].symmetric

    def forms(self) -> frozenset[tuple[str, ...]]:
        """Every name and alias as normalised singular words (the parser spots these in a sentence)."""
        return frozenset(form for e in self.entries for form in e.forms)

    def name_words(self) -> frozenset[str]:
        """Every word of :meth:`forms` ("teddy", "bear", "arm", "chair", ...)."""
        return frozenset(w for e in self.entries for w in e.words)

    def correction(self, words: tuple[str, ...]) -> tuple[str, ...] | None:
        """The one name or alias, or head noun of one ("armchair" of "red armchair", which
        :meth:`match` accepts alone), that ``words`` (normalised, singular) misspell
        (:func:`_near`); None when none or several do."""
        text = " ".join(words)
        if text not in self._corrections:
            found = [f for f in self._targets() if _near(text, " ".join(f))]
            owners = {e.name for e in self.entries for f in found if f in e.forms or any(g[-1:] == f for g in e.forms)}
            # Several forms of one object ("arm chair", "armchair") are one reading: the closest.
            best = min(found, key=lambda f: (edit_distance(text, " ".join(f), 3), f), default=None)
            self._corrections[text] = best if len(found) == 1 or len(owners) == 1 else None
        return self._corrections[text]

    def expansion(self, token: str) -> tuple[str, ...] | None:
        """The name words one written-short ``token`` stands for, or None: the consonant skeleton
        of one name word (:func:`skeleton`: "tbl" is "table", "flr" "floor"), or two consecutive
        words of one name or alias written as one ("teddybear", "motorcar" of "motor car"). A
        token read two ways is read as neither."""
        if token not in self._expansions:
            # Only a word without vowels after its first letter can be a skeleton (most are not).
            consonants = len(token) >= MIN_SKELETON_LETTERS and VOWELS.isdisjoint(token[1:])
            found = set()
            for form in self.forms():
                for k, word in enumerate(form):
                    if consonants and word != token and word[:1] == token[:1] and token in skeleton(word):
                        found.add((word,))
                    if k + 1 < len(form) and token.startswith(word) and token == word + form[k + 1]:
                        found.add(form[k : k + 2])
            self._expansions[token] = found.pop() if len(found) == 1 else None
        return self._expansions[token]

    def _targets(self) -> frozenset[tuple[str, ...]]:
        """Names, aliases and their head nouns: what a misspelling may be read as."""
        return self.forms() | {f[-1:] for f in self.forms()}

    def match(self, mention: str) -> str:
        """The one object name ``mention`` refers to; :class:`InputError` if none or several."""
        found = self.candidates(mention)
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            raise InputError(f"subject {mention!r} is ambiguous in this scene; say which: {found}")
        close = self.closest(mention)
        raise InputError(
            f"subject {mention!r} is not in this scene; " + (f"closest: {close}" if close else f"known: {self.names}")
        )

    def candidates(self, mention: str) -> list[str]:
        """The names ``mention`` matches best (none, one, or several equally well), sorted."""
        tokens = key(mention)
        if not tokens:
            return []
        found = self._by_forms(tokens) or self._by_parts(tokens) or self._by_clipping(tokens)
        return sorted(found or ([d] if (d := self.described(tokens)) else []))

    def described(self, tokens: tuple[str, ...]) -> str | None:
        """The one object a description tells (:data:`DESCRIPTION_WORDS`): ``tokens`` (normalised,
        singular) headed by a class word or a word naming nothing in particular, every
        description word in them fitting its kind ("the thing you'd put flowers in", "the
        only seat", "bit of furniture with arms"); None when no such word is said, or none or
        several of the scene's objects fit."""
        told = [DESCRIPTION_WORDS[t] for t in tokens if t in DESCRIPTION_WORDS]
        if not told or not any(_description_head(tokens, k) for k in range(len(tokens))):
            return None
        kinds = set.intersection(*map(set, told))
        fit = [e.name for e in self.entries if any(key(k) in e.forms for k in kinds)]
        return fit[0] if len(fit) == 1 else None

    def closest(self, mention: str, n: int = 3) -> list[str]:
        """Up to ``n`` object names whose names or aliases look most like ``mention`` (and
        about as much as the closest one)."""
        text = " ".join(key(mention))
        scored: dict[str, float] = {}
        for e in self.entries:
            # Not its kinds nor variants: a kind word ("succulent", "bolster") looks like too many others.
            for form in set(e.forms) - KIND_FORMS:
                ratio = difflib.SequenceMatcher(None, text, " ".join(form)).ratio()
                scored[e.name] = max(scored.get(e.name, 0.0), ratio)
        best = max(scored.values(), default=0.0)
        # Names about as close as the best one: "tedy" names the teddy bear, not also the telly.
        return [name for name, r in sorted(scored.items(), key=lambda kv: (-kv[1], kv[0])) if r >= max(0.5, best - 0.15)][:n]

    def _compatible(self, entry: VocabularyEntry, tokens: tuple[str, ...]) -> bool:
        """False when the mention asks for a colour the object's names contradict: one that
        shares no basic colour term (:data:`COLOR_FAMILIES`) with the object's colours."""
        if not entry.colors:
            return True
        own = frozenset().union(*(COLOR_FAMILIES[c] for c in entry.colors))
        return all(COLOR_FAMILIES[c] & own for c in set(tokens) & COLORS)

    def _by_forms(self, tokens: tuple[str, ...]) -> list[str]:
        scores = {}
        for e in self.entries:
            found = [f for f in e.forms if _contains(tokens, f)]
            if not found:
                continue
            form = found[0]  # forms are longest first
            rest = set(tokens) - set(form)
            if self._compatible(e, tuple(rest)):
                scores[e.name] = (len(form), len(rest & e.words))
        return _best(scores)

    def _by_parts(self, tokens: tuple[str, ...]) -> list[str]:
        content = [t for t in tokens if t not in ATTRIBUTES] or list(tokens)
        scores = {}
        for e in self.entries:
            if not self._compatible(e, tokens):
                continue
            for form in e.forms:
                if set(content) <= set(form) or (content[-1] == form[-1] and self._head_names(e, content)):
                    scores[e.name] = max(scores.get(e.name, (0,)), (len(set(tokens) & e.words),))
        return _best(scores)

    @staticmethod
    def _head_names(entry: VocabularyEntry, content: list[str]) -> bool:
        """Whether a mention's head noun (``content``'s last word) names ``entry`` despite its other
        words: when the head alone is one of its forms ("the reading chair" of an armchair also
        called "chair"), or those words are its own. A head that names it only with its modifier
        ("stand" of "lamp stand") does not: an "umbrella stand" is another thing."""
        return (content[-1],) in entry.forms or set(content[:-1]) <= entry.words

    def _by_clipping(self, tokens: tuple[str, ...]) -> list[str]:
        """The names whose head word (a form's last) ``tokens``' one content word clips: its first
        :data:`MIN_CLIPPED_LETTERS` letters or more, as a short form ("ted" of "teddy", "tele" of
        "television", "cush" of "cushion"); every such name, so that two make the mention
        ambiguous rather than guessed."""
        content = [t for t in tokens if t not in ATTRIBUTES]
        if len(content) != 1 or len(content[0]) < MIN_CLIPPED_LETTERS or not content[0].isalpha():
            return []
        said = content[0]
        return [
            e.name
            for e in self.entries
            if self._compatible(e, tokens) and any(len(f[-1]) > len(said) and f[-1].startswith(said) for f in e.forms)
        ]


# A word written short by its consonants keeps at least three of them ("tbl", "flr"): two ("tb")
# are too few to name one word.
MIN_SKELETON_LETTERS = 3
VOWELS = frozenset("aeiou")


def skeleton(word: str) -> tuple[str, ...]:
    """How ``word`` is written short by its consonants: its first letter and the consonants after
    it, as written and with a doubled consonant once ("teddy" -> "tddy", "tdy"; "table" -> "tbl")."""
    short = word[:1] + "".join(c for c in word[1:] if c not in VOWELS)
    once = "".join(c for k, c in enumerate(short) if not k or c != short[k - 1])
    return (short, once) if once != short else (short,)


# Letters held for emphasis ("pleeease", "sooo", "biiig"): a letter written three times or more.
STRETCHED = re.compile(r"(.)\1{2,}")


def unstretched(token: str, known) -> str | None:
    """``token`` with its held letters written as the word ``known(word)`` accepts: twice, else
    once ("sooo" -> "so", "tooo" -> "too", "pleeease" -> "please"); None when no letter is held or
    neither is a known word."""
    if not STRETCHED.search(token):
        return None
    for times in (r"\1\1", r"\1"):
        word = STRETCHED.sub(times, token)
        if known(word):
            return word
    return None


def _synonym_forms(forms: list[set[tuple[str, ...]]]) -> list[set[tuple[str, ...]]]:
    """Per object (its forms), the forms :data:`NAME_SYNONYMS`, :data:`NAME_VARIANTS` and
    :data:`NAME_KINDS` add: every
    word of a group one of its forms belongs to, unless another object's forms hold that word or
    the group too."""
    groups = [{key(w) for w in group} for group in (*NAME_SYNONYMS, *NAME_VARIANTS, *NAME_KINDS)]
    owners = [[k for k, f in enumerate(forms) if f & g] for g in groups]
    used = set().union(*forms) if forms else set()
    extra: list[set[tuple[str, ...]]] = [set() for _ in forms]
    for group, owner in zip(groups, owners):
        if len(owner) == 1:
            extra[owner[0]] |= group - used
    return extra


# A short form keeps at least this many letters of the word it clips ("ted", "tele"): two letters
# ("te") start too many words to name anything.
MIN_CLIPPED_LETTERS = 3
# Shorter names are one edit from too many ordinary words ("bear"/"beer", "mug"/"mud").
MIN_CORRECTED_LETTERS = 5
# Long names are read through two edits that keep the first letter ("refridgerator",
# "televishun"): no ordinary word is that close to a name this long.
MIN_TWO_EDIT_LETTERS = 8
# A swap of two adjacent letters seldom turns a four-letter name into another word ("bera",
# "sfoa", "lmap" are none), where a substitution often does; three letters are too few ("arc"
# is "car" swapped).
MIN_TRANSPOSED_LETTERS = 4
# A letter typed twice is a slip of the finger, not another word, even in a three-letter name.
MIN_DOUBLED_LETTERS = 3


def _near(said: str, name: str) -> bool:
    """Whether ``said`` is read as ``name``: one edit from a name of :data:`MIN_CORRECTED_LETTERS`
    letters or more, the first letter kept when one is replaced; one swap or one letter written
    once where the name has it twice from one of
    :data:`MIN_TRANSPOSED_LETTERS` ("bera", "bal" is not "ball"), or its final "y" written "ie"
    (:func:`diminutive`: "teddie"); one letter doubled from one of
    :data:`MIN_DOUBLED_LETTERS` ("sofaa", "mugg"); letters that sound alike swapped in one of
    :data:`MIN_TRANSPOSED_LETTERS` (:func:`sounds_alike`: "vaze", "sopha"); two edits keeping the
    first letter from one of :data:`MIN_TWO_EDIT_LETTERS` (spaces not counted)."""
    letters = len(name.replace(" ", ""))
    if letters >= MIN_TRANSPOSED_LETTERS and (diminutive(said, name) or diminutive(name, said) or sounds_alike(said, name)):
        return True
    if letters >= MIN_DOUBLED_LETTERS and (doubled(said, name) or (" " not in name and sounds_alike(said, name))):
        return True
    if letters >= MIN_TRANSPOSED_LETTERS and (transposed(said, name) or doubled(name, said)):
        return True
    # Not one letter swapped for another at the start: that writes another word ("heater" is no
    # "seater", "camp" no "lamp"), and slips of the first letter are rare.
    if letters >= MIN_CORRECTED_LETTERS and one_edit(said, name) and not (len(said) == len(name) and said[0] != name[0]):
        return True
    return letters >= MIN_TWO_EDIT_LETTERS and said[:1] == name[:1] and edit_distance(said, name, 2) <= 2


# Spellings of one sound, written one for the other by people spelling by ear ("vaze", "sopha",
# "kushion"): each is replaced by the first before two spellings are compared.
SOUND_SPELLINGS = (("ph", "f"), ("ck", "c"), ("k", "c"), ("z", "s"))
# More of them (parse19p7): a soft "c" ("vace"), "ou" said "u" ("moug", "coushion"), "aw"/"au"
# before "l" said "al" ("bawl", "baul"), the unstressed ending after "sh" ("kushin", "cushun"),
# and a final "e" left silent ("vaz"); applied after those above.
SOUND_ENDINGS = ((re.compile(r"sh[aeiou]+n$"), "shn"), (re.compile(r"(?<=[^aeiou])e$"), ""))
SOUND_VOWELS = (("ce", "se"), ("ci", "si"), ("cy", "sy"), ("ou", "u"), ("awl", "all"), ("aul", "all"))


def sounds_alike(a: str, b: str) -> bool:
    """Whether ``a`` and ``b`` differ but are spelt the same once letters that sound alike are
    written one way (:data:`SOUND_SPELLINGS`)."""

    def plain(word: str) -> str:
        for spelt, sound in (*SOUND_SPELLINGS, *SOUND_VOWELS):
            word = word.replace(spelt, sound)
        for ending, sound in SOUND_ENDINGS:
            word = ending.sub(sound, word)
        return word

    return a != b and plain(a) == plain(b)


def diminutive(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with a final "y" written "ie" ("teddie" of "teddy", "tellie" of
    "telly"): two spellings of one diminutive ending."""
    return len(b) > 1 and b.endswith("y") and a == b[:-1] + "ie"


def doubled(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with one letter written twice ("sofaa" of "sofa", "bearr" of "bear")."""
    return len(a) == len(b) + 1 and any(a[i] == a[i + 1] and a[:i] + a[i + 1 :] == b for i in range(len(a) - 1))


def dropped(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with one letter left out ("hight" of "height")."""
    return len(a) + 1 == len(b) and any(b[:i] + b[i + 1 :] == a for i in range(len(b)))


def edit_distance(a: str, b: str, cap: int) -> int:
    """Damerau-Levenshtein distance (insertions, deletions, substitutions, adjacent swaps) of
    ``a`` and ``b``, or ``cap + 1`` once it must exceed ``cap`` (a length gap beyond it)."""
    if abs(len(a) - len(b)) > cap:
        return cap + 1
    before, row = None, list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        current = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            cost = a[i - 1] != b[j - 1]
            current[j] = min(row[j] + 1, current[j - 1] + 1, row[j - 1] + cost)
            if before is not None and i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                current[j] = min(current[j], before[j - 2] + 1)
        if min(current) > cap:
            return cap + 1
        before, row = row, current
    return min(row[-1], cap + 1)


def transposed(a: str, b: str) -> bool:
    """Whether ``a`` becomes ``b`` by swapping two adjacent, different characters ("bera" ->
    "bear")."""
    if len(a) != len(b) or a == b:
        return False
    i = next(k for k in range(len(a)) if a[k] != b[k])
    return a[i : i + 2] == b[i : i + 2][::-1] and a[i + 2 :] == b[i + 2 :]


def one_edit(a: str, b: str) -> bool:
    """Whether ``a`` becomes ``b`` by exactly one insertion, deletion or substitution of a
    character, or by swapping two adjacent ones ("baer" -> "bear")."""
    if a == b or abs(len(a) - len(b)) > 1:
        return False
    if len(a) > len(b):
        a, b = b, a
    i = next((k for k in range(len(a)) if a[k] != b[k]), len(a))
    if len(a) < len(b):
        return a[i:] == b[i + 1 :]
    return a[i + 1 :] == b[i + 1 :] or transposed(a, b)


# The kinds' and the variants' forms (not their objects' names), which :meth:`Vocabulary.closest`
# never offers.
KIND_FORMS = frozenset(key(w) for group in (*NAME_KINDS, *NAME_VARIANTS) for w in group[1:])


def _contains(tokens: tuple[str, ...], form: tuple[str, ...]) -> bool:
    n = len(form)
    return any(tokens[i : i + n] == form for i in range(len(tokens) - n + 1))


def _best(scores: dict[str, tuple]) -> list[str]:
    if not scores:
        return []
    top = max(scores.values())
    return [name for name, score in scores.items() if score == top]
