"""The rule-based instruction parser: the embedded, deterministic tier of DESIGN §4.

``parse_instruction("a close-up of the bear on the left, seen from its right, from slightly above",
vocabulary)`` -> one subject ``teddy bear`` (region ``left``, shot ``close-up``, view ``right``),
elevation ``slightly above``.

How a sentence is read:

1. it is normalised (:func:`capframe.translate.vocabulary.words`: lowercase, hyphens split, number
   words as digits, one spelling of British/US pairs);
2. the scene's names and aliases are spotted (longest first) together with the attribute words and
   determiner just before them ("the big red chair") and matched to one scene name each;
3. the phrase tables below are matched against what is left; where matches overlap the longest
   wins ("seen from behind on its left" over "seen from behind");
4. a cue that belongs to a subject (region, shot, view) goes to the subject its possessive or object
   names ("the bear's left"); otherwise to the nearest subject before it ("the bear on the left"),
   or after it for a head ending in "of"/"with" ("a close-up of the bear"); when that subject
   already holds a different value, to the nearest one on the other side ("on the left, the bear;
   on the right, the vase"); a pronoun ("its left") looks back first;
5. words no table explains are returned in ``unparsed`` (normalised, stopwords trimmed from the
   ends of each run), except in a subject's place (right after
   a head such as "a photo of", right before a region, or joined to a subject by "and"): there
   they are a subject when they (partly) name a scene object ("the teddy"), and after a
   determiner they must ("a photo of the giraffe" is an :class:`~capframe.errors.InputError`
   naming the closest names). A sentence with no name spotted tries all its unexplained words.

Mappings that are choices (the phrase tables are the full list):

* shot sizes are close-up / medium / wide (:data:`~capframe.constraints.SHOT_SIZES`, the subject's
  extent in the frame): "extreme close-up", "medium close-up", "tight", "fills the frame" ->
  close-up (more than half the frame); "mid", "full shot" (the whole subject with little room,
  uncropped) -> medium; "long", "extreme wide", "establishing", "small in the frame" -> wide;
* view sides are the subject's own (DESIGN §3): "from the left" is from the subject's left side.
  A subject *facing left in the frame* shows its left side: with the camera at azimuth -90° it
  looks along the subject's right axis ``r`` (z = r, y = -u), so image right is
  x = y × z = -u × r = -f and the subject's front points to image left; "facing right" is view
  ``right``. "Three-quarter"
  alone is either front three-quarter; "left three-quarter" is front-left. "In profile" and
  "side view" do not say which side and stay unparsed;
* elevation: "from above"/"looking down" alone is a high angle, "from below"/"looking up" a low
  angle; both yield to any more specific elevation in the same sentence ("from slightly above,
  looking down at it" is slightly above). "From the ground looking up" is a worm's-eye view.
  A named elevation and explicit degrees together keep the degrees when they fall in the named
  range, else the instruction contradicts itself (an error);
* roll (> 0 clockwise as the photographer sees it, the camera's right side dipping): a dutch angle
  without degrees is :data:`DUTCH_DEFAULT_DEG` clockwise ("slight" and "strong" change the
  magnitude); "rolled 10 degrees" without a direction is clockwise; "tilted" is a roll only with
  a direction or a side ("tilted 10 degrees to the left"): "tilted up/down" is a pitch, read as a
  low/high-angle hint. The *horizon* or picture rotated clockwise means the camera rolled
  counter-clockwise (negative). "Level", "straight horizon" -> 0.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass

from ..constraints import ELEVATIONS
from ..errors import InputError, clip
from .instruction import ParsedInstruction, ParsedSubject
from .vocabulary import ATTRIBUTES, DETERMINERS, PUNCTUATION, Vocabulary, singular, words

# --- phrase tables ------------------------------------------------------------------------------
# Templates are regular expressions over normalised text (single spaces, "close up", "bird 's eye",
# "center", "counterclockwise", digits, "degrees") in which a bare "(" does not capture and
#   {P}    a possessive: its / their / a subject's ("the bear's")
#   {obj}  an object: it / them / a subject
#   {d}    a number with optional "degrees"; {sd} the same, possibly negative
#   {dir}  clockwise | counterclockwise;  {side} left | right (of the camera);  {mod} a dutch-angle size word
#   {FRAME} frame / picture / image / ...
# A template with a {P} or {obj} naming a subject gives its cue to that subject.

FRAME = "(?:frame|picture|image|shot|photo|photograph|composition|viewfinder)"
# Nouns after a shot-size word ("a wide *view* of"), and the words that make it a head.
SHOT_NOUN = "(shot|photo|photograph|picture|image|view|frame|framing|portrait|composition|capture)"
HEAD_LINK = "(of|with|showing|featuring)"

# Heads introduce the subject and ask nothing themselves.
HEADS = [
    "(a |an )?(photo|picture|photograph|shot|image|snapshot|snap|view|portrait|capture|render|rendering) " + HEAD_LINK,
    "(take|get|make|shoot|snap|grab) (a |an )?(photo|picture|photograph|shot|image|snapshot) (of|with)",
    "(frame|capture|photograph|shoot|film|show|picture)",
]

# Shot sizes: terms that stand alone, and adjectives that need a noun ("a wide shot", not "wide").
SHOT_TERMS = {
    "close-up": ["close up", "extreme close up", "medium close up", "tight close up"],
}
SHOT_ADJECTIVES = {
    "close-up": ["tight", "close", "detail", "macro", "extreme close", "very close"],
    "medium": [
        "medium",
        "mid",
        "medium distance",
        "mid distance",
        "mid range",
        "medium range",
        "full",
        "medium full",
        "medium wide",
        "medium long",
        "cowboy",
        "mid length",
    ],
    "wide": ["wide", "long", "distant", "extreme wide", "extreme long", "very wide", "wide angle", "establishing", "far"],
}
# Shot sizes said after the subject ("the bear, filling the frame").
SHOT_CLAUSES = {
    "close-up": [
        "(filling|fills|fill|filling up|fills up) (most of |all of |nearly all of )?the (whole |entire )?{FRAME}",
        "(shot|seen|photographed|taken|framed) (up )?close( up)?",
        "(from )?up close",
        "(from )?close up",
        "(framed|cropped) (very )?(tightly|tight)",
        "(tightly|tight) (framed|cropped)",
        "(large|big|huge) in (the )?{FRAME}",
        "(taking up|occupying) (most of |all of )?the (whole |entire )?{FRAME}",
        "dominating the {FRAME}",
        "zoomed in( on {obj})?",
        "(from )?(very )?close (by|to {obj})",
    ],
    "medium": [
        "(at )?(a )?(medium|moderate) size( in (the )?{FRAME})?",
        "((framed|shot|seen|taken) )?(at|from) (a )?(mid|medium|moderate) (distance|range)",
        "(taking up|occupying|filling) (a )?(moderate|medium) (part|portion|amount|share) of the {FRAME}",
        "(taking up|filling|occupying) (about |roughly |around )?half (of )?the {FRAME}",
        "(medium|moderately) sized( in (the )?{FRAME})?",
        "neither (too )?close nor (too )?far",
    ],
    "wide": [
        "(small|tiny) in (the )?{FRAME}",
        "(from )?(very )?far away",
        "from afar",
        "from (a )?(long |great )?distance",
        "(from )?far (off|back)",
        "with (plenty of|lots of|a lot of|generous|ample|enough) (space|room|breathing room|context) around {obj}",
        "(with )?(lots of|plenty of) (empty |negative )?space",
        "zoomed out",
        "pulled (way )?back",
    ],
}

# Regions: "PREPOSITION the AREA [of the FRAME]", never followed by "of" (relations between
# objects such as "to the left of the vase" are not regions of the frame).
REGION_PREPOSITIONS = "(on|in|at|to|near|towards|within|into|inside|along|across)"
REGION_AREAS = {
    "left": ["left", "left side", "left half", "left hand side", "left part", "left edge", "left hand part"],
    "right": ["right", "right side", "right half", "right hand side", "right part", "right edge", "right hand part"],
    "center": ["center", "middle", "very center", "dead center", "exact center", "very middle"],
    "top": ["top", "top half", "upper half", "upper part", "top part", "top edge", "upper side", "top side"],
    "bottom": ["bottom", "bottom half", "lower half", "lower part", "bottom part", "bottom edge", "lower side", "bottom side"],
    "left third": ["left third", "leftmost third", "first third", "left third line", "left hand third"],
    "center third": ["middle third", "central third", "center third", "middle vertical third"],
    "right third": ["right third", "rightmost third", "last third", "right third line", "right hand third"],
    "upper left": ["upper left( corner| quadrant| quarter)?", "top left( corner| quadrant| quarter)?", "left top corner"],
    "upper right": ["upper right( corner| quadrant| quarter)?", "top right( corner| quadrant| quarter)?", "right top corner"],
    "lower left": ["lower left( corner| quadrant| quarter)?", "bottom left( corner| quadrant| quarter)?", "left bottom corner"],
    "lower right": [
        "lower right( corner| quadrant| quarter)?",
        "bottom right( corner| quadrant| quarter)?",
        "right bottom corner",
    ],
}
REGION_PHRASES = {
    "left": ["(on |at |in )?(the )?{FRAME} left", "left of (the )?{FRAME}"],
    "right": ["(on |at |in )?(the )?{FRAME} right", "right of (the )?{FRAME}"],
    "center": [
        "centered( in (the )?{FRAME})?",
        "centrally( placed| positioned)?( in (the )?{FRAME})?",
        "center {obj}( in (the )?{FRAME})?",
        "(at |in )?(the )?{FRAME} center",
        "center of (the )?{FRAME}",
        "dead center",
    ],
    "top": ["high (up )?in the {FRAME}"],
    "bottom": ["low (down )?in the {FRAME}"],
    "upper left": ["(top|upper) left corner"],
    "upper right": ["(top|upper) right corner"],
    "lower left": ["(bottom|lower) left corner"],
    "lower right": ["(bottom|lower) right corner"],
}

# View sides (the subject's own sides): side words, the frames they go into, and whole phrases.
VIEW_SIDE_WORDS = {
    "front": ["front"],
    "back": ["back", "rear"],
    "left": ["left", "left hand"],
    "right": ["right", "right hand"],
    "front-left": [
        "front left",
        "left front",
        "front and left",
        "front left three quarter",
        "left three quarter",
        "left front three quarter",
    ],
    "front-right": [
        "front right",
        "right front",
        "front and right",
        "front right three quarter",
        "right three quarter",
        "right front three quarter",
    ],
    "back-left": [
        "back left",
        "rear left",
        "left rear",
        "left back",
        "back and left",
        "rear and left",
        "back left three quarter",
        "rear left three quarter",
    ],
    "back-right": [
        "back right",
        "rear right",
        "right rear",
        "right back",
        "back and right",
        "rear and right",
        "back right three quarter",
        "rear right three quarter",
    ],
}
VIEW_FRAMES = [
    "((seen|viewed|shot|photographed|captured|taken|filmed) )?from (the|{P}) {SIDE}( side)?( of {obj})?",
    "showing (the|{P}) {SIDE}( side)?( of {obj})?",
    "with the camera (at|on|to|by) (the|{P}) {SIDE}( side)?( of {obj})?",
    "(with )?(the|{P}) {SIDE}( side)? (towards|to|facing|turned towards|turned to) the (camera|viewer|lens)",
    "(in |from |as )?(a |the )?{SIDE}( side)? (view|profile|angle|shot)",
]
VIEW_PHRASES = {
    "front": [
        "facing (the |towards the )?(camera|viewer|lens|us|me|forward|forwards)",
        "facing front",
        "head on",
        "face on",
        "front on",
        "frontal( view| shot| angle)?",
        "(looking|staring|gazing) (at|into|towards) the (camera|lens)",
        "with the camera in front of {obj}",
        "showing {P} face",
    ],
    "back": [
        "((seen|viewed|shot|photographed|captured|taken|filmed) )?from behind( {obj})?",
        "(facing|turned|looking) away( from the (camera|viewer|lens|us))?",
        "with the camera behind {obj}",
        "with {P} back (turned )?(to|towards) the (camera|viewer|lens|us)",
        "{P} back to the (camera|viewer|lens|us)",
    ],
    "left": ["facing (to the |towards the )?left( in (the )?{FRAME})?", "facing (screen|{FRAME}) left"],
    "right": ["facing (to the |towards the )?right( in (the )?{FRAME})?", "facing (screen|{FRAME}) right"],
    "front-left": ["three quarters? (view |angle )?from (the|{P}) (front )?left( side)?"],
    "front-right": ["three quarters? (view |angle )?from (the|{P}) (front )?right( side)?"],
    "back-left": [
        "((seen|viewed|shot|photographed|taken) )?from behind (and )?(on|to|at) (the|{P}) left( side)?",
        "three quarters? (view |angle )?from (the|{P}) (back|rear) left( side)?",
    ],
    "back-right": [
        "((seen|viewed|shot|photographed|taken) )?from behind (and )?(on|to|at) (the|{P}) right( side)?",
        "three quarters? (view |angle )?from (the|{P}) (back|rear) right( side)?",
    ],
    "three-quarter": [
        "(in |at |from |as )?(a |an )?three quarters?( front)?( (view|angle|profile|shot|position))?",
        "(seen )?at three quarters",
        "(in |at )?(a |an )?(front )?three quarter( front)? (view|angle)",
    ],
}

# Named elevations; the hints yield to any other elevation in the sentence.
ELEVATION_PHRASES = {
    "eye level": [
        "(at |from )?(the )?eye (level|height)( (shot|view|angle|camera))?",
        "with the camera at {P} (height|level|eye level)",
        "(shot )?straight on at {P} height",
        "(at|from) (the )?(same height|same level|height|level) (as|of) {obj}",
        "(at|from) {P} (height|level)",
        "level with {obj}",
        "(from |at )?(a )?(neutral|level|straight) (angle|height)",
    ],
    "slightly above": [
        "(from |with the camera )?(slightly|a little|a bit|just) above( {obj})?",
        "slightly from above",
        "looking (slightly|a little|a bit) down( at {obj})?",
        "(from )?(a )?slightly (high|higher|elevated|raised) (angle|position|viewpoint|vantage point|camera)",
        "slightly elevated( (angle|view|position|viewpoint|camera))?",
        "(a )?(slight|gentle|mild|shallow) high angle( shot)?",
    ],
    "high angle": [
        "(from |in |with )?(a |an )?high angle( (shot|view|position|camera))?",
        "(a |an )?high (shot|view)",
        "with the camera (well|high|far) above {obj}",
        "(from )?(a |an )?(high|elevated|raised) (vantage point|viewpoint|position|perspective)",
        "(from )?(well|high|far) above( {obj})?",
    ],
    "bird's-eye": [
        "(from |in |as )?(a |an )?birds?( 's)? eye( (view|shot|angle|perspective))?",
        "(from )?(directly|straight|right|vertically) (above|overhead)( {obj})?",
        "looking (straight|directly|vertically) down( (at|on) {obj})?",
        "(from |in |as )?(a |an )?overhead( (shot|view|angle|perspective))?",
        "from overhead",
        "(from |in |as )?(a |an )?top down( (view|shot|angle|perspective))?",
        "(from |in |as )?(a |an )?top view",
        "((seen|shot|viewed) )?from the top",
        "(shot |looking )?straight down( at {obj})?",
        "(a )?plan view",
    ],
    "low angle": [
        "(from |in |with )?(a |an )?low angle( (shot|view|position|camera))?",
        "(a |an )?low (shot|view)",
        "with the camera (below|beneath|under|lower than) {obj}( ,? looking up)?",
        "(from )?(a |an )?low (vantage point|viewpoint|position|perspective)",
        "looking (slightly|a little|a bit) up( at {obj})?",
        "(from )?(slightly|a little|a bit|just) below( {obj})?",
    ],
    "worm's-eye": [
        "(from |in |as )?(a |an )?worms?( 's)? eye( (view|shot|angle|perspective))?",
        "looking (straight|directly|steeply|vertically) up( at {obj})?",
        "from the ground( level)?( ,)? looking (steeply |straight )?up( at {obj})?",
        "(from )?(directly|straight|right) (below|beneath|underneath)( {obj})?",
        "straight up at {obj}",
    ],
}
ELEVATION_HINTS = {
    "high angle": [
        "looking down( (at|on) {obj})?",
        "((shot|seen|shooting|taken|viewed|photographed) )?from above",
        "(shooting|pointing|aimed|angled|tilted|tilting) down( (at|on|towards) {obj})?",
    ],
    "low angle": [
        "looking up( at {obj})?",
        "((shot|seen|shooting|taken|viewed|photographed) )?from (below|beneath)",
        "(shooting|pointing|aimed|angled|tilted|tilting) up( (at|towards) {obj})?",
    ],
}
# Explicit elevations, by sign (+ above, - below); {sd} carries its own sign.
EXPLICIT_ELEVATION_PHRASES = {
    1.0: [
        "(from |at )?{d} above( {obj}| the horizon| the horizontal)?",
        "with the camera {d} above {obj}",
        "looking down( at {obj})? from {d} above",
        "looking down( at {obj})? (at|from|by) (an angle of )?{d}",
        "(at |from |with )?(an |a )?(camera )?(elevation|elevation angle) of {sd}",
        "(at |from |with )?(an |a )?{d} (elevation|high angle|downward angle)",
        "elevated (by )?{d}",
        "((seen|shot|viewed|photographed) )?from above( ,)? at (an angle of )?{d}",
    ],
    -1.0: [
        "(from |at )?{d} below( {obj}| the horizon| the horizontal)?",
        "with the camera {d} below {obj}",
        "looking up( at {obj})? from {d} below",
        "looking up( at {obj})? (at|from|by) (an angle of )?{d}",
        "(at |from |with )?(an |a )?{d} (low angle|upward angle)",
        "((seen|shot|viewed|photographed) )?from below( ,)? at (an angle of )?{d}",
    ],
}

# Roll phrases, by how they relate to the camera's roll: +1 they describe the camera, -1 the
# picture (a horizon rotated clockwise means the camera rolled counter-clockwise), 0 a level camera.
ROLL_PHRASES = {
    1.0: [
        "(with )?(a |an )?{d}( {dir})? (dutch|canted) (angle|tilt)",
        "(with )?(a |an )?({dir} )?(dutch|canted) (angle|tilt)( of)? {d}( {dir})?",
        "(with )?(the )?camera (rolled|tilted|rotated|canted|turned|leaning) (by )?{d} {dir}",
        "(rolled|tilted|rotated|canted|turned) (by )?{d} {dir}",
        "(rolled|tilted|rotated|canted|turned) {dir} (by )?{d}",
        "((with )?(the )?camera )?(rolled|tilted|rotated|canted|leaning) (by )?({d} )?(to the )?{side}",
        "(with )?(the )?camera (rolled|rotated|canted) {dir}",
        "(with )?(a |an )?({mod} )?({dir} )?(dutch|canted) (angle|tilt)",
        "(with )?(a |an )?({dir} )?(camera )?roll( of)? {sd}",
        "(camera )?rolled (by )?{sd}",
        "(with )?(the )?camera 's {side} side (dipped|lowered|dipping|down)( by)?( {d})?",
        "(with )?(the )?{side} side (of the (camera|{FRAME}) )?(dipped|lowered|dipping|down)( by)?( {d})?",
        "dipping (to the )?{side}( by {d})?",
    ],
    -1.0: [
        "(with )?(the )?(horizon|picture|image|scene) (tilted|rotated|slanted|sloping|turned|canted) (by )?{d} {dir}",
        "(with )?(the )?(horizon|picture|image|scene) (tilted|rotated|slanted|sloping|turned|canted) {dir}( by {d})?",
    ],
    0.0: [
        "(keeping|keep|with|hold|holding) (the )?horizon (level|straight|flat|horizontal)",
        "(with )?(a |the )?(level|straight|flat|horizontal) horizon",
        "(the )?horizon (level|straight|flat|horizontal)",
        "(with |and )?no (dutch |canted )?(angle|tilt|roll)",
        "(with )?no camera roll",
        "without (any )?((dutch|canted) (angle|tilt)|roll|camera roll|tilt)",
        "((keep|keeping|hold|holding|with) )?(the )?camera (held )?level",
        "(a )?level camera",
    ],
}
DUTCH_DEFAULT_DEG = 15.0  # a dutch angle without degrees: clockwise, inside the generator's 10..30
DUTCH_SIZE_DEG = {
    "slight": 10.0,
    "subtle": 10.0,
    "gentle": 10.0,
    "small": 10.0,
    "mild": 10.0,
    "strong": 30.0,
    "heavy": 30.0,
    "extreme": 30.0,
    "dramatic": 30.0,
    "steep": 30.0,
}

# Words that carry no constraint: left out of ``unparsed`` and never taken as a subject's attribute.
STOPWORDS = frozenset(
    {
        "a",
        "an",
        "the",
        "this",
        "that",
        "these",
        "those",
        "its",
        "it",
        "their",
        "them",
        "his",
        "her",
        "him",
        "my",
        "our",
        "your",
        "'s",
        "of",
        "with",
        "and",
        "or",
        "in",
        "on",
        "at",
        "to",
        "from",
        "by",
        "for",
        "as",
        "so",
        "but",
        "into",
        "onto",
        "about",
        "around",
        "near",
        "towards",
        "within",
        "over",
        "under",
        "then",
        "also",
        "both",
        "while",
        "where",
        "photo",
        "photograph",
        "picture",
        "pic",
        "image",
        "shot",
        "snapshot",
        "frame",
        "capture",
        "take",
        "get",
        "make",
        "shoot",
        "show",
        "showing",
        "film",
        "compose",
        "composed",
        "composition",
        "view",
        "camera",
        "please",
        "i",
        "me",
        "we",
        "us",
        "want",
        "would",
        "like",
        "need",
        "should",
        "be",
        "is",
        "are",
        "being",
        "placed",
        "positioned",
        "put",
        "place",
        "sitting",
        "standing",
        "located",
        "set",
        "keep",
        "kept",
        "appearing",
        "appear",
        "visible",
        "clearly",
        "nicely",
        "scene",
        "subject",
        "just",
        "very",
        "which",
        "can",
        "could",
        "you",
        "let",
        "have",
        "has",
        "there",
        "here",
        "one",
        "whole",
        "entire",
        "framed",
        "seen",
        "taken",
        "shown",
        "featuring",
        "render",
        "rendering",
        "photographed",
        "captured",
        "filmed",
        "pictured",
        "shooting",
        "viewed",
    }
)
# Single words that are photographic vocabulary first: an alias equal to one of them is not
# spotted in running text (it still matches in a subject's place).
RESERVED = frozenset(
    {
        "frame",
        "picture",
        "photo",
        "photograph",
        "shot",
        "image",
        "camera",
        "view",
        "horizon",
        "scene",
        "subject",
        "object",
        "lens",
        "ground",
        "top",
        "front",
        "back",
        "side",
        "left",
        "right",
        "center",
        "middle",
        "bottom",
    }
)
MENTION_DETERMINERS = DETERMINERS - {"its", "their"}
CONJUNCTIONS = frozenset({"and", "or"})
MAX_ATTRIBUTES = 3  # attribute words taken into a mention before its name ("the big fluffy brown bear")

SUBJECT_FIELDS = ("region", "shot", "view")

# --- compiling the tables -------------------------------------------------------------------------

_MACROS = {
    "{FRAME}": FRAME,
    "{d}": r"(?P<d>\d+(?:\.\d+)?)(?: degrees)?",
    "{sd}": r"(?P<d>-?\d+(?:\.\d+)?)(?: degrees)?",
    "{dir}": "(?P<dir>clockwise|counterclockwise)",
    "{side}": "(?P<side>left|right)",
    "{mod}": "(?P<mod>" + "|".join(DUTCH_SIZE_DEG) + ")",
    "{P}": r"(?P<ref>its|it 's|his|her|their|@\d+ 's)",
    "{obj}": r"(?P<ref>it|him|her|them|@\d+)",
}


@dataclass(frozen=True)
class _Rule:
    """One template: the field it sets and its value (for numbers: a sign multiplier)."""

    field: str
    value: object
    pattern: re.Pattern
    weak: bool = False


def _alternatives(options: list[str]) -> str:
    return "(" + "|".join(sorted(options, key=len, reverse=True)) + ")"


def _compile(template: str) -> re.Pattern:
    """A template as a regular expression matching whole words of normalised text."""
    t = re.sub(r"\((?!\?)", "(?:", template)
    for macro, regex in _MACROS.items():
        t = t.replace(macro, regex)
    # A macro may occur twice in a template: number its groups (read back by _groups).
    counter = itertools.count()
    t = re.sub(r"\(\?P<(\w+)>", lambda m: f"(?P<{m[1]}_{next(counter)}>", t)
    return re.compile(f"(?<= )(?:{t})(?= )")


def _groups(m: re.Match) -> dict[str, str]:
    """A match's macro groups by macro name (the first one that matched)."""
    out: dict[str, str] = {}
    for name, value in m.groupdict().items():
        if value is not None:
            out.setdefault(name.rsplit("_", 1)[0], value)
    return out


def _templates() -> list[tuple[str, object, str, bool]]:
    """Every table row as (field, value, template, weak)."""
    rows: list[tuple[str, object, str, bool]] = [("head", None, t, False) for t in HEADS]
    link = f"( {HEAD_LINK})?"
    for shot, terms in SHOT_TERMS.items():
        rows.append(("shot", shot, f"(a |an )?{_alternatives(terms)}( {SHOT_NOUN})?{link}", False))
    for shot, adjectives in SHOT_ADJECTIVES.items():
        rows.append(("shot", shot, f"(a |an )?{_alternatives(adjectives)} {SHOT_NOUN}{link}", False))
    rows += [("shot", shot, t, False) for shot, ts in SHOT_CLAUSES.items() for t in ts]
    for region, areas in REGION_AREAS.items():
        template = f"{REGION_PREPOSITIONS} the {_alternatives(areas)}( (of|in) (the )?{{FRAME}})?(?! of )"
        rows.append(("region", region, template, False))
    rows += [("region", region, t, False) for region, ts in REGION_PHRASES.items() for t in ts]
    for view, sides in VIEW_SIDE_WORDS.items():
        rows += [("view", view, frame.replace("{SIDE}", _alternatives(sides)), False) for frame in VIEW_FRAMES]
    rows += [("view", view, t, False) for view, ts in VIEW_PHRASES.items() for t in ts]
    rows += [("elevation", e, t, False) for e, ts in ELEVATION_PHRASES.items() for t in ts]
    rows += [("elevation", e, t, True) for e, ts in ELEVATION_HINTS.items() for t in ts]
    rows += [("elevation_deg", sign, t, False) for sign, ts in EXPLICIT_ELEVATION_PHRASES.items() for t in ts]
    rows += [("roll_deg", sign, t, False) for sign, ts in ROLL_PHRASES.items() for t in ts]
    return rows


def _lexicon(rows) -> frozenset[str]:
    """Every word the tables use: such a word before a name is not an attribute of the subject."""
    text = " ".join(t for _, _, t, _ in rows) + " " + " ".join(_MACROS.values())
    return frozenset(re.findall(r"[a-z]+", re.sub(r"\{[^}]*\}|\(\?P<\w+>", " ", text))) | STOPWORDS


# --- parsing ------------------------------------------------------------------------------------


@dataclass
class _Mention:
    """A subject mention at token ``at`` of the placeholder text (``@placeholder`` when spotted
    by name, None when matched in a subject's place)."""

    at: int
    text: str
    name: str
    placeholder: int | None = None


@dataclass
class _Run:
    """Words no phrase explains, from token ``at``; ``slot``: in a subject's place;
    ``determiner``: right after "the"/"a"... (a noun phrase)."""

    at: int
    text: str
    slot: bool
    determiner: bool


@dataclass
class _Cue:
    """One matched phrase: tokens ``[start, end)`` of the placeholder text."""

    field: str
    value: object
    start: int
    end: int
    text: str
    ref: int | None = None  # the mention a {P}/{obj} slot names
    pronoun: bool = False  # the slot holds a pronoun
    weak: bool = False
    forward: bool = False  # belongs to the subject after it ("a close-up of ...")


class RuleParser:
    """Deterministic parser of photographic instructions (see the module docstring)."""

    def __init__(self):
        rows = _templates()
        self.rules = [_Rule(field, value, _compile(t), weak) for field, value, t, weak in rows]
        self.lexicon = _lexicon(rows)

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction:
        """``text`` as a :class:`ParsedInstruction` with subjects from ``vocabulary``;
        :class:`InputError` (one line) for an empty instruction, one without a subject, a subject
        not in the scene or an ambiguous one, and contradictory cues."""
        if not text or not text.strip():
            raise InputError(f"the instruction is empty; expected e.g. 'a close-up of the {_example(vocabulary)} on the left'")
        if not len(vocabulary):
            raise InputError("the scene names no objects (no semantic labels), so no subject can be matched")
        tokens, mentions = self._spot(words(text), vocabulary)
        cues = self._cues(tokens)
        unparsed = []
        for run in self._leftovers(tokens, cues):
            # In a subject's place a run names an object if it can; led by a determiner it must.
            if run.slot and (run.determiner or vocabulary.candidates(run.text)):
                mentions.append(_Mention(run.at, run.text, vocabulary.match(run.text)))
            else:
                unparsed.append(run)
        if not mentions:  # the sentence names its subject somewhere: try what was not understood
            for run in unparsed:
                if vocabulary.candidates(run.text):
                    mentions.append(_Mention(run.at, run.text, vocabulary.match(run.text)))
            unparsed = [run for run in unparsed if run.at not in {m.at for m in mentions}]
        unparsed_text = [run.text for run in unparsed]
        if not mentions:
            hint = f" (not understood: {clip(repr(unparsed_text))})" if unparsed else ""
            raise InputError(f"no subject in {clip(text.strip())!r}{hint}; name one of the scene's objects: {vocabulary.names}")
        mentions.sort(key=lambda m: m.at)
        subjects = _attach(cues, mentions, vocabulary)
        elevation, elevation_deg = _elevation(cues)
        return ParsedInstruction(text, subjects, elevation, elevation_deg, _roll(cues), unparsed_text)

    def _spot(self, tokens: list[str], vocabulary: Vocabulary) -> tuple[list[str], list[_Mention]]:
        """Replace each subject mention by a placeholder ``@k``: the longest name or alias at each
        position, with the attribute words and determiner before it."""
        forms = {f for f in vocabulary.forms() if len(f) > 1 or f[0] not in RESERVED}
        longest = max(map(len, forms), default=0)
        keys = [singular(t) for t in tokens]
        out: list[str] = []
        mentions: list[_Mention] = []
        i = 0
        while i < len(tokens):
            n = next((n for n in range(min(longest, len(tokens) - i), 0, -1) if tuple(keys[i : i + n]) in forms), 0)
            if not n:
                out.append(tokens[i])
                i += 1
                continue
            before: list[str] = []
            while out and len(before) < MAX_ATTRIBUTES and self._attribute(out[-1]):
                before.insert(0, out.pop())
            if out and out[-1] in MENTION_DETERMINERS:
                before.insert(0, out.pop())
            mention = " ".join(before + tokens[i : i + n])
            mentions.append(_Mention(len(out), mention, vocabulary.match(mention), len(mentions)))
            out.append(f"@{len(mentions) - 1}")
            i += n
        return out, mentions

    def _attribute(self, token: str) -> bool:
        """Whether ``token`` may describe the subject named after it: a known attribute, or a word
        the tables do not use ("fluffy")."""
        return token in ATTRIBUTES or (token.isalpha() and token not in self.lexicon)

    def _cues(self, tokens: list[str]) -> list[_Cue]:
        """The phrases found in the placeholder text; of overlapping ones the longest (then the first)."""
        text = " " + " ".join(tokens) + " "
        token_at = {}
        position = 1
        for k, token in enumerate(tokens):
            token_at[position] = k
            position += len(token) + 1
        found = []
        for rule in self.rules:
            for m in rule.pattern.finditer(text):
                found.append((rule, m, token_at[m.start()], token_at[m.end() + 1] if m.end() + 1 in token_at else len(tokens)))
        found.sort(key=lambda f: (-(f[3] - f[2]), f[2]))
        taken = [False] * len(tokens)
        cues = []
        for rule, m, start, end in found:
            if any(taken[start:end]):
                continue
            taken[start:end] = [True] * (end - start)
            cues.append(_cue(rule, m, start, end))
        return sorted(cues, key=lambda c: c.start)

    def _leftovers(self, tokens: list[str], cues: list[_Cue]) -> list[_Run]:
        """Runs of words no phrase explains, less stopwords at their ends, each marked whether it
        stands in a subject's place (right after a head, right before a region, or joined to a
        subject by "and"/"or")."""
        covered = [False] * len(tokens)
        for c in cues:
            covered[c.start : c.end] = [True] * (c.end - c.start)
        free = [not covered[k] and tokens[k] not in PUNCTUATION and not tokens[k].startswith("@") for k in range(len(tokens))]
        ends = {c.end: c for c in cues}
        starts = {c.start: c for c in cues}
        runs = []
        for is_free, group in itertools.groupby(range(len(tokens)), key=lambda k: free[k]):
            span = list(group)
            if not is_free:
                continue
            run = [tokens[k] for k in span]
            lo, hi = 0, len(run)
            while lo < hi and run[lo] in STOPWORDS:
                lo += 1
            while hi > lo and run[hi - 1] in STOPWORDS:
                hi -= 1
            if lo == hi:
                continue
            before, after = ends.get(span[0]), starts.get(span[-1] + 1)
            slot = (
                (before is not None and before.forward)
                or (after is not None and after.field == "region")
                or _coordinated(tokens, span)
            )
            runs.append(_Run(span[0], " ".join(run[lo:hi]), slot, lo > 0 and run[lo - 1] in MENTION_DETERMINERS))
        return runs


def _coordinated(tokens: list[str], span: list[int]) -> bool:
    """Whether the run is joined to a subject by "and"/"or" ("the bear and the giraffe")."""
    first, last = span[0], span[-1]
    return (tokens[first] in CONJUNCTIONS and first > 0 and tokens[first - 1].startswith("@")) or (
        tokens[last] in CONJUNCTIONS and last + 1 < len(tokens) and tokens[last + 1].startswith("@")
    )


def _cue(rule: _Rule, m: re.Match, start: int, end: int) -> _Cue:
    groups = _groups(m)
    slot = groups.get("ref")
    ref = int(slot.split()[0][1:]) if slot and slot.startswith("@") else None
    value, weak = rule.value, rule.weak
    if rule.field == "elevation_deg":
        value = rule.value * float(groups["d"])
    elif rule.field == "roll_deg":
        value, weak = _roll_value(rule.value, groups)
    forward = rule.field == "head" or (rule.field == "shot" and re.search(f" {HEAD_LINK}$", m.group()) is not None)
    return _Cue(rule.field, value, start, end, m.group(), ref, slot is not None and ref is None, weak, forward)


def _roll_value(multiplier: float, groups: dict) -> tuple[float, bool]:
    """Roll in degrees of a roll phrase, and whether its magnitude is a default (a weak cue)."""
    if multiplier == 0:
        return 0.0, False
    sign = -1.0 if groups.get("dir") == "counterclockwise" or groups.get("side") == "left" else 1.0
    if groups.get("d") is not None:
        return multiplier * sign * float(groups["d"]), False
    return multiplier * sign * DUTCH_SIZE_DEG.get(groups.get("mod") or "", DUTCH_DEFAULT_DEG), True


def _attach(cues: list[_Cue], mentions: list[_Mention], vocabulary: Vocabulary) -> list[ParsedSubject]:
    """Subjects in order of first mention, with the region/shot/view cues given to them."""
    subjects: dict[str, ParsedSubject] = {}
    for m in mentions:
        if m.name not in subjects:
            role = "secondary" if subjects else "primary"
            subjects[m.name] = ParsedSubject(m.text, m.name, role, vocabulary.symmetric(m.name))
    for cue in cues:
        if cue.field not in SUBJECT_FIELDS:
            continue
        for name in _candidates(cue, mentions):
            held = getattr(subjects[name], cue.field)
            if held is None or held == cue.value:
                setattr(subjects[name], cue.field, cue.value)
                break
        else:
            name = _candidates(cue, mentions)[0]
            raise InputError(
                f"conflicting {cue.field} for {name!r}: {getattr(subjects[name], cue.field)!r} and {cue.value!r} ({cue.text!r})"
            )
    return list(subjects.values())


def _candidates(cue: _Cue, mentions: list[_Mention]) -> list[str]:
    """Names a subject cue may belong to, the preferred first (see the module docstring)."""
    if cue.ref is not None:
        return [next(m.name for m in mentions if m.placeholder == cue.ref)]
    before = [m.name for m in mentions if m.at < cue.start]
    after = [m.name for m in mentions if m.at >= cue.end]
    near = [before[-1]] if before else []
    far = [after[0]] if after else []
    return far + near if cue.forward and not cue.pronoun else near + far


def _elevation(cues: list[_Cue]) -> tuple[str | None, float | None]:
    """The named elevation or explicit degrees asked (hints yield to any other elevation cue)."""
    found = [c for c in cues if c.field in ("elevation", "elevation_deg")]
    found = [c for c in found if not c.weak] or found
    named = sorted({c.value for c in found if c.field == "elevation"})
    degrees = sorted({c.value for c in found if c.field == "elevation_deg"})
    if len(named) > 1 or len(degrees) > 1:
        raise InputError(f"conflicting elevations: {[c.text for c in found]}")
    if degrees and not -90.0 <= degrees[0] <= 90.0:
        raise InputError(f"elevation {degrees[0]:g} degrees is out of range; expected -90 to 90")
    if named and degrees:
        lo, hi = ELEVATIONS[named[0]]
        if not lo <= degrees[0] <= hi:
            raise InputError(f"conflicting elevations: {named[0]!r} is {lo:g} to {hi:g} degrees, not {degrees[0]:g}")
        named = []
    return (named[0] if named else None), (degrees[0] if degrees else None)


def _roll(cues: list[_Cue]) -> float | None:
    """The roll asked, in degrees (a dutch angle without degrees yields to one with)."""
    found = [c for c in cues if c.field == "roll_deg"]
    found = [c for c in found if not c.weak] or found
    values = sorted({c.value for c in found})
    if len(values) > 1:
        raise InputError(f"conflicting roll: {[c.text for c in found]}")
    if values and abs(values[0]) > 90.0:
        raise InputError(f"roll {values[0]:g} degrees is out of range; expected -90 to 90")
    return values[0] if values else None


def _example(vocabulary: Vocabulary) -> str:
    return vocabulary.names[0] if len(vocabulary) else "teddy bear"


_DEFAULT: RuleParser | None = None


def parse_instruction(text: str, vocabulary: Vocabulary) -> ParsedInstruction:
    """Parse ``text`` with a shared :class:`RuleParser` (its tables are compiled once)."""
    global _DEFAULT
    if _DEFAULT is None:
        _DEFAULT = RuleParser()
    return _DEFAULT.parse(text, vocabulary)
