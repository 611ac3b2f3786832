"""The rule-based instruction parser: the embedded, deterministic tier of DESIGN §4.

``parse_instruction("a close-up of the bear on the left, seen from its right, from slightly above",
vocabulary)`` -> one subject ``teddy bear`` (region ``left``, shot ``close-up``, view ``right``),
elevation ``slightly above``.

How a sentence is read:

1. it is normalised (:func:`capframe.translate.vocabulary.words`: lowercase, hyphens split, number
   words as digits, one spelling of British/US pairs);
2. the scene's names and aliases are spotted (longest first) together with the attribute words and
   determiner just before them ("the big red chair") and matched to one scene name each. Where
   no name is spelt right, a run of words one edit from exactly one name, alias or head noun of
   five letters or more ("teddy baer", "televison"), or two adjacent letters swapped in one of
   four ("bera"), is read as it
   (:meth:`~capframe.translate.vocabulary.Vocabulary.correction`; never a word the phrase tables
   use) and reported in ``corrected``;
3. the phrase tables below are matched against what is left; where matches overlap the longest
   wins ("seen from behind on its left" over "seen from behind");
4. a cue that belongs to a subject (region, shot, view) goes to the subject its possessive or object
   names ("the bear's left"); otherwise to the nearest subject before it ("the bear on the left"),
   or after it for a head ending in "of"/"with" ("a close-up of the bear"); when that subject
   already holds a different value, to the nearest one on the other side ("on the left, the bear;
   on the right, the vase"); a pronoun ("its left") looks back first. A second view cue that
   completes the first one's side (:data:`VIEW_COMBINATIONS`: "a three-quarter view of the bear
   from its left") joins it, unless it leads straight into another subject;
5. words no table explains are returned in ``unparsed`` (normalised, stopwords trimmed from the
   ends of each run), except in a subject's place (right after
   a head such as "a photo of", right before a region, or joined to a subject by "and"): there
   they are a subject when they (partly) name a scene object ("the teddy"), and after a
   determiner they must ("a photo of the giraffe" is an :class:`~capframe.errors.InputError`
   naming the closest names). Words naming only a part or position (:data:`POSITION_WORDS`:
   "the top", "the back"), a degree (:data:`DEGREE_WORDS`: "a bit") or nothing in particular
   (:data:`GENERIC_NOUNS`, with attributes: "that small thing") are never a subject;
   "the top of the X" leaves "X" in the subject's place. A sentence with no name spotted tries
   all its unexplained words. The noun phrase opening the sentence (or following a head) and tied
   to a named object by a place relation (:data:`RELATION_WORDS`: "the wristwatch lying by the
   mug", "skateboard under the bench") is the subject whatever it names: refused by its own words
   when the scene lacks it; the related object, like one asked only to be seen ("the bench in
   the frame too"), takes no cue said after it.

Mappings that are choices (the phrase tables are the full list):

* shot sizes are close-up / medium / wide (:data:`~capframe.constraints.SHOT_SIZES`, the subject's
  extent in the frame): "extreme close-up", "medium close-up", "tight", "fills the frame",
  "zoom in on", "up close", "as big as possible" -> close-up (more than half the frame); "mid",
  "full shot" (the whole subject with little room, uncropped), "not too close" -> medium; "long",
  "extreme wide", "establishing", "zoomed out", "step back", "from far away", "small in the
  frame", "(is) just a small thing", "as a tiny dot" -> wide. "Tight", "close" and "wide" alone
  are a size only as a clause of their own ("the bear, tight."), not as an attribute ("the wide
  sofa"). All of the subject in ("the whole bench in frame", "don't crop it") is medium alone and
  yields to a size word said with it ("the whole sofa, small in frame" is wide);
* what is denied right before it ("not from the side", "rather than from above") asks nothing the
  checker can measure: it is reported as not understood and conflicts with nothing. A noun
  phrase opening the sentence that goes on with a copula, a verb of saying or a colon and then
  names what is wanted is its topic, not a thing ("my preference is rear left for the bench",
  "the plan: the bear, close-up"); placed at a subject it stays a thing ("the lantern is next to
  the bench"), as does one asked alone and then placed as "it" ("Hourglass? It stands by the
  mug");
* polite and chatty openings ("could you show me", "I'd like", "let's see", "how about") are heads:
  they introduce the subject and ask nothing; "please", "thanks", "maybe" are stopwords;
* view sides are the subject's own (DESIGN §3): "from the left" is from the subject's left side.
  A subject *facing left in the frame* shows its left side: with the camera at azimuth -90° it
  looks along the subject's right axis ``r`` (z = r, y = -u), so image right is
  x = y × z = -u × r = -f and the subject's front points to image left; "facing right" is view
  ``right``. A side word in a noun phrase is a view side of the subject it belongs to, never a
  subject: "the sofa's left side", "the back of the chair", "its rear", "its backside", "the
  rear end of", "the bear's face" (front); closing in on one too ("close on its face", "zoom in
  on the bear's back": the close-up and the front or back);
  after a preposition of place ("the vase on its left", "to the left of the bear") it is a
  relation between objects and stays unparsed, as does "with its back to the wall"; said of the
  camera it is the view ("camera positioned to the right of the bear", "put the camera behind
  the sofa").
  "Three-quarter" alone is either front three-quarter, "rear three-quarter" either back one;
  with a side it is that diagonal ("a three-quarter view from the left" is front-left, "rear
  three-quarter from the right" back-right), and "three-quarter ... from behind" is the rear
  three-quarter. "In profile", "side view", "from the side" are ``side``, either profile.
  Two ends together are the diagonal between them: "behind and to the left (of it)", "from
  behind on the left", "from behind, on its right", "from the front, from its left". Degree words: a slight one ("slightly",
  "a bit", "a little", "somewhat", ...) before a lone left/right is the slight side between the
  front and the diagonal ("slightly from the left", "a bit to its left": ``front-slight-left``,
  -20° ± 15°), or between the back and the diagonal with "behind" ("behind and slightly to the
  left": ``back-slight-left``, -160° ± 15°); before a front, back or diagonal it is not understood and stays unparsed ("slightly
  from behind" is the back, with "slightly" unparsed). A strong one ("directly", "straight",
  "squarely", "fully", ...) insists on an end: "directly from the left" is ``left-exact``, "from
  directly behind" ``back-exact`` (the end at half the tolerance, ±15°), and so are an end said
  "X on" ("dead on", "head on", "tail on") and an explicit angle at an end ("a quarter turn to its
  right"); before a diagonal it changes nothing. "Slightly to the left" that names no subject and follows no
  seeing verb or camera ("seen slightly to the left", "the camera a bit to the left") stays a
  region, the degree word unparsed. A side alone as a clause is a view ("bench, rear left"; a
  lone "left" or "right" there stays a region), and so is a place opening the sentence
  ("directly behind the bear, ...");
* elevation: "from above"/"looking down"/"from up high"/"a higher angle" alone is a high angle,
  "from below"/"looking up"/"a lower angle" a low angle; all yield to any more specific elevation
  in the same sentence ("from slightly above, looking down at it" is slightly above). "From the
  ground looking up" is a low angle, looking straight up from there a worm's-eye view, "aerial" a
  bird's-eye one. Moving or pointing the
  camera is a hint too: "get down low", "shoot up at", "from floor level", "shot from low" (low
  angle), "climb up high", "aim down" (high angle); so is "low" or "high" alone as a clause ("the
  car from behind, low"; "low in the frame" is a region). The height of a surface the subject rests or sits on ("at
  table height", "from seat level") is eye level; "a little below / above eye level" is slightly
  below / above, "well below / above" it a low / high angle.
  Slight degree words give slightly above / slightly below ("a bit from below": -30° to -8°);
  "steeply"/"strongly from above" is bird's-eye (60° to 90°); "straight down", "directly above",
  "top-down", "plan view" are top-down (80° to 90°). Of two named elevations one inside the other
  the narrower is kept ("from overhead, looking straight down" is top-down); two that only
  overlap contradict each other (an error). A named elevation and explicit degrees together keep
  the degrees when they fall in the named range, else the instruction contradicts itself (an
  error);
* roll (> 0 clockwise as the photographer sees it, the camera's right side dipping): a dutch angle
  without degrees is :data:`DUTCH_DEFAULT_DEG` clockwise ("slight" and "strong" change the
  magnitude); "rolled 10 degrees" without a direction is clockwise; "tilted" is a roll only with
  a direction or a side ("tilted 10 degrees to the left"): "tilted up/down" is a pitch, read as a
  low/high-angle hint. The *horizon* or picture rotated clockwise means the camera rolled
  counter-clockwise (negative). "Level", "straight horizon" -> 0. Number, direction and noun come
  in any order ("8 degree counter-clockwise roll", "dutch angle 10", "roll 5 degrees CCW");
* word families are tables of :mod:`capframe.translate.vocabulary`, each used wherever it fits:
  the degree scale (``DEGREE_SCALE``: "a touch high", "looking down a bit", "a hair to its right",
  "way up", "square on"), height anchors (``HEIGHT_ANCHORS``: "chest height" is eye level, "knee
  height" a low angle), size words and idioms (``SIZE_WORDS``, ``SIZE_IDIOMS``, ``PLENTY_WORDS``:
  "punch in", "head to toe", "X and all", "loads of room around it", "the cup small, ..."), the
  three-quarter diagonal in any order ("3/4 front-left", "three quarter rear right"), an explicit
  azimuth ("45 degrees round to its right": the side nearest it), a region straight after its
  subject ("bench left third, tree right third") and "the whole group" (every object joins as a
  secondary subject);
* jargon and hedges, as families too: shot-list abbreviations (``SHOT_ABBREVIATIONS``: "ECU",
  "MS", "WS"; "med", "lvl"), a "-ish" suffix as the slight degree ("high-ish": slightly above),
  "a quarter turn" as 90 degrees, whose eye a view is (``EYE_VIEWS``: "god's-eye" bird's-eye,
  "ant's-eye" worm's-eye), the ends said "X on" (``HEAD_ON_WORDS``, ``TAIL_ON_WORDS``: "nose on"
  front, "tail on" back), "over its left shoulder" (back-left), a part on a side naming that side
  (``SIDE_PARTS``: "its right arm end", "the left-hand side panel"), nadir / zenith, a heroic
  angle (low), "N degrees up", an area "of the frame" without a preposition ("bottom right of the
  frame"). Words that ask nothing beyond a subject's being seen are understood and ask nothing:
  where it rests ("the bear on the floor"), "in the same shot", mood words ("a cosy shot");
* more families of the same kind: a turn's share as an angle ("a twelfth of a turn", "1/8 of a
  rotation": 360/N), a comparative said with "more" ("a little more high than it"), a hedged
  number ("50-odd", "30ish", "20 or so"), a part of the subject as its height (``SUBJECT_PARTS``:
  "at bonnet height", "level with its snout", "crouched down to its roofline": eye level), the
  support the subject stands on (``SUPPORT_SURFACES``: "below the floorboards", "underground",
  "through the grass": worm's-eye), a size after a verb of being ("it must be big", "look
  massive") or likened to a speck (``SPECK_WORDS``: "the ball a speck"), the whole of its kind
  (``CLASS_NOUNS``: "full vehicle in frame"), slates and scene headings (``SLATE_LABELS``,
  ``SCENE_HEADINGS``: "SC 12", "INT. LIVING ROOM - WIDE") and courtesies (``COURTESIES``) that
  ask nothing, a roll spun about the lens axis or "N degrees of clockwise roll", a side "off" the
  subject ("off its left-hand flank"), a slight side drifted round to ("back of the bear,
  drifting a little round to its left"), a height joined to a side by "and" ("from above and to
  the left"), a corner said with a height ("low in the right corner"), an azimuth said as such
  ("an azimuth of 30 degrees", "from its left, 15 degrees towards the back"), rolls by other verbs
  or a crooked frame (``ROLL_VERBS``, ``ROLL_ADJECTIVES``: "banked 15 degrees left", "a bit
  askew"; "tilted" alone stays unread), the camera on the subject's support (eye level) or just
  above it (low). Words ending on "of"/"at" right before a named object describe the picture of
  it ("frame a dramatic look at the mug"), and a noun phrase about the camera ("a camera buried
  in the sand") is never the subject;
* views, regions and sizes as families of parts in any order (frame11): an architect's elevation
  is its side square on ("front elevation" front exactly, "side elevation" either profile; never
  a height), "square to it" and "looking (right) down the lens" the front exactly, the view's noun
  before its side ("PROFILE RIGHT", "side view (left)"), "lateral" the side; a corner is a height,
  a side and a corner noun in any order and glue ("right upper corner", "the corner at the top on
  the left"), and a height and a side said apart join into it (:func:`_combined_region`); "dead
  middle", "mid-frame", "the left vertical third"; a word said twice for emphasis counts once
  ("really really tiny"); "so big it fills everything" (no group), "a small element in the
  landscape", "WIDE on X";
* a view offset is a family of a reference view, an amount and a direction, in any order
  (:data:`OFFSET_VIEW_FRAMES`, :data:`SIDE_OFFSET_FRAMES`, :data:`TURN_FRAMES`): "from behind him,
  little bit more to right", "looking at the camera but swung a few degrees to its left", "45 deg
  off its nose towards its left", "from its left flank, a few degrees toward the front", "more
  toward the back". A slight amount (a degree word or ``OFFSET_HEDGES``: "a few degrees") is the
  slight side between the reference and its neighbour, an explicit angle the side nearest it,
  counted from the reference: a sideways turn said apart from its reference is ``("turn",
  degrees)`` until :func:`_combined_view` meets the end it starts from ("60 degs round to its
  right from head-on" is +60, "from behind, 30 degrees to its left" -150; none is the front).
  Exactness said apart from the side ("from the behind, exactly", "the fridge's rear, head-on",
  "straight on to the arm") is :data:`EXACT_ONLY`, which makes the end said with it exact and is
  the front exactly alone; the front or back end first to the lens ("nose-first toward the lens")
  is that end exactly. Side names: starboard / port (before a side word) are the right / left
  (``vocabulary.SIDE_NAMES``), stern / aft / bow the ends, "a rear (tail-end) quarter" the rear
  three-quarter, "round the back" the back; a word one slip from a view word right after "from
  the" / "from its" is read as it ("from the font": :func:`_view_slip`);
* parse12's families: a roll's direction said as a side of the camera ("a 10 degree right roll",
  "rotate the cam 15 degrees to the left around the lens": right is clockwise) where the camera
  or picture is named or the lens axis said ("turn", "swing", "angle" to a side without the axis
  stay aims), or given to the camera ("give the camera a twelfth of a turn clockwise"); a corner
  said with plain heights ("up", "down", "high", "low"), a side and "corner" or "quadrant" in any
  order and glue ("the corner up and right of the picture"); letters held for emphasis
  ("pleeease", "biiig": :func:`~capframe.translate.vocabulary.unstretched`) and "please" dropped
  before the tables are read; one end of the subject to the other in any words ("roots up to
  crown, all in frame": medium); looking or aiming down with "straight", "directly" or "right"
  before or after "down" (top-down, never a front view); a word written by the consonants of one
  name word or two name words run together ("tbl", "teddybear":
  :meth:`~capframe.translate.vocabulary.Vocabulary.expansion`), reported in ``corrected``; a verb
  of getting before a determiner ("get the kite") a head, so the thing got is the subject and
  refused when the scene lacks it; which side after a side view said as "the left one";
* parse20p4's families: a side completing a view said before it ("three quarter front on its
  left side", "over the shoulder, on its right side", "front three-quarter on the left of it",
  "broadside to the lens, on its right side"); an angle "round" from a front part ("a quarter turn
  round from its face towards its left", "sixty degrees round from the fridge doors"), a small
  turn said as a noun ("with a slight twist to its left"), an angle as an aside ("turned a little,
  maybe 20 degrees, toward its right"); a frame half as the side of its middle line
  (:data:`FRAME_MIDLINE`: "below the halfway line of the photo") and "centred both ways";
* heldout17's families: a side said again more precisely is the precise one (:func:`_restated_view`:
  "from behind, a bit to the left - over its left shoulder"); a side in a sentence of its own after
  the subject's ("BENCH. Right side."); a front part turned to the viewer ("its nose toward us");
  the whole of a generic noun ("the whole model in frame"); "everything" rolled; degrees looked
  down on from; a filler "like" before an emphatic word (:func:`_unfilled`: "like SUPER close").
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass, replace

try:  # the regex parser's node tree, read by _required (its modules were renamed in Python 3.11)
    from re import _compiler as _re_compiler
    from re import _constants as _re_nodes
    from re import _parser as _re_parser
except ImportError:
    import sre_compile as _re_compiler
    import sre_constants as _re_nodes
    import sre_parse as _re_parser

from ..constraints import (
    ELEVATIONS,
    EXACT_ENDS,
    EXPLICIT_ELEVATION_TOLERANCE_DEG,
    NEGATED_ENDS,
    REGIONS,
    SHOT_SIZES,
    VIEW_SIDES,
    arc_deg,
    view_tolerance_deg,
)
from ..errors import InputError, clip
from .instruction import ParsedInstruction, ParsedSubject
from .vocabulary import (
    ATTRIBUTES,
    CLASS_NOUNS,
    CORRECTION_MARKERS,
    COURTESIES,
    DEGREE_SCALE,
    DETERMINERS,
    END_PARTS,
    EYE_VIEW_NOUNS,
    EYE_VIEWS,
    FACING_PARTS,
    FEW_DEGREES,
    FILLER_WORDS,
    FRAME_FRACTIONS,
    HEAD_ON_WORDS,
    HEADING_TIMES,
    HEIGHT_AMOUNTS,
    HEIGHT_ANCHORS,
    HIGH_PLACE_OPENINGS,
    HIGH_PLACES,
    HORIZON_LINES,
    HORIZON_SURFACES,
    LEVEL_WITH,
    NUMBER,
    OFFSET_HEDGES,
    PLENTY_WORDS,
    PUNCTUATION,
    PURPOSES,
    REQUESTERS,
    RESTATING_AFTER,
    ROLL_ADJECTIVES,
    ROLL_VERBS,
    SCENE_HEADINGS,
    SETTINGS,
    SIDE_PARTS,
    SIDED_PARTS,
    SIZE_IDIOMS,
    SIZE_WORDS,
    SLATE_LABELS,
    SPECK_WORDS,
    SUBJECT_PARTS,
    SUPPORT_SURFACES,
    TAIL_ON_WORDS,
    TURN_DIRECTION_LEADS,
    TURN_DIRECTION_NOUNS,
    WANTING,
    Vocabulary,
    key,
    one_edit,
    singular,
    slip_of,
    unstretched,
    words,
)

# --- phrase tables ------------------------------------------------------------------------------
# Templates are regular expressions over normalised text (single spaces, "close up", "bird 's eye",
# "center", "counterclockwise", digits, "degrees") in which a bare "(" does not capture and
#   {P}    a possessive: its / their / a subject's ("the bear's")
#   {obj}  an object: it / them / a subject
#   {d}    a number with optional "degrees"; {sd} the same, possibly negative
#   {dir}  clockwise | counterclockwise;  {side} left | right (of the camera);  {mod} a dutch-angle size word
#   {WEAK} a slight degree word ("slightly", "a bit", ...); {STRONG} an insisting one ("directly", "straight", ...);
#   {VERY} an intensifier ("very", "way", ...): the degree scale of vocabulary.DEGREE_SCALE
#   {ANCHOR_<class>} a height anchor of that elevation class ("chest", "seat"; vocabulary.HEIGHT_ANCHORS)
#   {FRAME} frame / picture / image / ...
# A template with a {P} or {obj} naming a subject gives its cue to that subject.

# A photographer's older or painterly words for it too ("the right third of the plate", "the canvas").
FRAME = "(?:frame|picture|image|shot|photo|photograph|composition|viewfinder|pic|snap|plate|canvas|exposure)"
# Nouns after a shot-size word ("a wide *view* of"), and the words that make it a head.
SHOT_NOUN = "(shot|photo|photograph|picture|image|view|frame|framing|portrait|composition|capture|crop|headshot)"
HEAD_LINK = "(of|with|showing|featuring)"

# Heads introduce the subject and ask nothing themselves.
HEADS = [
    "(a |an )?(photo|picture|photograph|shot|image|snapshot|snap|view|portrait|capture|render|rendering) " + HEAD_LINK,
    "(take|get|make|shoot|snap|grab) (a |an )?(photo|picture|photograph|shot|image|snapshot) (of|with)",
    "(frame|capture|photograph|shoot|film|show|picture)",
    # Taking a picture said by a verb of getting, before the thing it gets ("get the kite",
    # "grab that bench"): what follows is the subject, refused by its own words if the scene lacks it.
    "(get|grab|snap|take|nab|catch|bag)(?= (the|this|that|my|our|your|a|an) )",
    # Requests said politely or in passing ("could you show me", "I'd like", "let's see").
    "(show|give|get|find|bring) (me|us)",
    "(i|we) (d|would|should) (really )?(like|love|prefer|want)( to (see|have|get|take))?",
    "(i|we) (m|am|are) (looking for|after|hoping for)",
    "(let 's|lets|let me|let us|can i|could i|can we|could we|may i|may we) (see|view|look at|have|get)",
    "((have|take|get) a )?(look|glance) at",
    "see",
    "(would|do) you mind (taking|getting|showing|framing|photographing|capturing|shooting)",
    "(how|what) about",
    "what {obj} looks? like",
    "what (would|does|do|will|might) {obj} look like",
]

# All of the subject in the picture ("the whole bench in frame", "head to toe", "don't crop it"):
# alone a medium shot (:func:`_said_shot`), as every held-out table reads it, but no size beside a
# size word, which says how big that whole is ("the whole sofa small in the frame" is wide, "a
# close-up of the whole mug" a close-up: :func:`_combined_shot`).
WHOLE = "whole"
# Shot sizes: terms that stand alone, and adjectives that need a noun ("a wide shot", not "wide").
SHOT_TERMS = {
    "close-up": [
        "close up",
        "extreme close up",
        "medium close up",
        "tight close up",
        # The subject filling the frame ("a full-frame shot of", "frame-filling").
        "full frame",
        "frame filling",
        *SIZE_IDIOMS["close-up"],
    ],
    WHOLE: list(SIZE_IDIOMS["medium"]),  # every medium idiom says all of it is in
    "wide": list(SIZE_IDIOMS["wide"]),
}
SHOT_ADJECTIVES = {
    "close-up": ["tight", "close", "detail", "macro", "extreme close", "very close", "snug"],
    "medium": [
        "medium",
        # Not "mid-frame", the middle of the frame (a region).
        "mid(?! (frame|picture|image|photo|photograph|composition|viewfinder|pic)( |$))",
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
    "wide": [
        "wide",
        "long",
        "distant",
        "extreme wide",
        "extreme long",
        "very wide",
        "wide angle",
        "establishing",
        "far",
        "wide establishing",
        "long establishing",
    ],
}
# Shot sizes said after the subject ("the bear, filling the frame").
# A size word alone as a clause ("the bear, tight."): between a comma and the clause's end, so an
# attribute ("the wide sofa") is not read as a shot size.
# A verb of keeping or showing may lead it ("kept small", "staying low"), an intensifier of the
# degree scale may grade it ("real close", "way wide").
# The clause may be joined on by "and" ("far away and small") and end before "with", "so", "but"
# or "and" ("kept small with plenty of wall around it", "tight and centred").
# ... or before what it rests on ("kept tiny on the gravel"); not before a part of the frame, where
# "far on the left" is how far out it sits.
NOT_ON_A_THING = "((the|its|his|her|their) )?(left|right|top|bottom|side|edge|corner|center|middle|far|other|{FRAME})( |$)"
# A verb of making or placing may lead it too, its object dropped or said as "it" ("make small",
# "tucked away small", "tuck it small"): parse20s.
ALONE_VERBS = (
    "(kept|keep it|keeping it|left|leave it|stay|stays|staying|shown|looking|appearing|make|make it|making it|made|have it"
    "|tuck it|tucked|tucked away|tuck it away|tucked in|placed|put it|set)"
)
ALONE = (
    "({CLAUSE}|(?<= and ))(" + ALONE_VERBS + " )?"
    "({VERY} |{WEAK} |{FAIRLY} |extra |nice and |(so )+)?{WORD}"
    "(?= ([,.;:!)]|$|with |so |but |and |against |on (?!" + NOT_ON_A_THING + ")))"
)
# ... and a size adjective so said may come before the area of the frame it sits in ("small in the
# lower left", "tucked away tiny at the top right", "a bit big in the middle"): parse20s. Not
# "far" nor "close", which before a place say how near an edge it sits ("far in the corner").
ALONE_PLACED = ALONE.split("(?= ")[0] + "(?= (in|into|at|towards|toward|up in|down in|over in|off in|out in) the )"
# A shot size named as a label before a colon, as shot lists head a line ("Wide: the couch from
# behind", "Tight: the mug"), and a size said as a noun ("in big size", "at a small size"): parse20s.
SHOT_LABEL = "((?<=^ )|(?<=[.;!?] )){WORD}( shot)? :"
SIZE_NOUN = "((in|at) )?(a )?{WORD} size( in (the )?{FRAME})?"
# A size word after a verb of being or seeming ("it must be big", "make the fridge look massive",
# "so it comes out tiny").
COPULA_SIZE = (
    "(be|being|is|are|look|looks|appear|appears|seem|seems|remain|remains|come out|comes out|show up|shows up|end up|ends up) "
    "(nice and |{FAIRLY} |{VERY} |{WEAK} |(so )+)?{WORD}(?= ([,.;:!]|$|and |with |so |but |in |on ))"
)
# A size word said right after its subject, before a clause's end or a place ("sofa small in the
# upper half", "the toy car tiny, up in the top half"); never before a noun ("the car small
# wheels" stays unparsed).
AFTER_SUBJECT = (
    # Also after the colon of a label opening the sentence ("Tree: massive in frame").
    "((?<=^ ){obj} :|{obj}) (is |looking |kept |staying |nice and |{VERY} |{WEAK} |extra |(so )+)?{WORD}"
    "(?= ([,.;:!)]|$|and |in |into |at |on |up |down |near |towards |by |to |from |with |so |but |against ))"
)

# Small in a frame said to be big or empty ("tiny in a big empty frame", "little in a huge,
# otherwise empty picture", "small within a large open shot"): room all round it, a wide shot.
ROOMY_FRAME = "(big|huge|vast|large|wide|giant|massive|great|spacious|enormous|immense|empty|open|blank|clean|mostly|otherwise)"

SHOT_CLAUSES = {
    "close-up": [
        "((close|near|big|large|tight) enough (to |that it |so it )?)?"
        "(nearly |almost |completely |entirely )?(filling|fills|fill|filling up|fills up) (most of |all of |all |nearly all of )?"
        "the (whole |entire )?{FRAME}( (completely|entirely|fully|totally))?",
        # So big it fills the frame, or everything ("make it SO big it fills up everything", "so
        # close that the mug fills the whole picture").
        "((so |such |{VERY} |{FAIRLY} )?(big|large|huge|close|near|tight|massive) (enough )?(that |so |to )?(it |{obj} )?)?"
        "(nearly |almost |completely |entirely )?(filling|fills|fill|filling up|fills up|fill up|takes up|taking up|take up)"
        " (up )?(everything|it all|the whole thing|all of it)",
        "(so |such |{VERY} |{FAIRLY} )?(big|large|huge|close|near|tight|massive) (enough )?(that |so |to )?(it |{obj} )?"
        "(nearly |almost |completely |entirely )?(filling|fills|fill|filling up|fills up|fill up) "
        "(most of |all of |all |nearly all of )?the (whole |entire )?{FRAME}",
        # ... or so close a part of it does, or touches the frame ("so close its edges touch the
        # frame", "so near that the seat cushions take up the whole picture").
        "(so |such |{VERY} )(big|large|huge|close|near|tight|massive) (that )?(its |the |{P} )([a-z]+ |@\\d+ ){1,2}"
        "(nearly |almost |completely |entirely )?(filling|fills|fill|fill up|fills up|takes up|take up|taking up|touch|touches"
        "|touching|reach|reaches|reaching) (most of |all of |all |nearly all of )?the (whole |entire |edges of the )?{FRAME}"
        "( (edges|sides|borders))?",
        # Pressed into the frame edge to edge ("crammed into the frame", "pack the sofa into the shot").
        "({CRAM})( (edge to edge|side to side|corner to corner))? (in|into|inside) the (whole |entire )?{FRAME}",
        "({CRAM_VERB}) {obj} (in|into|inside) the (whole |entire )?{FRAME}",
        # The whole width or height of the frame ("filling the width of the frame", "spanning the
        # whole frame width").
        "(filling|fills|fill|spanning|spans|covering|covers) the (whole |entire |full )?(width|height) of the {FRAME}",
        "(filling|fills|fill|spanning|spans|covering|covers) the (whole |entire |full )?{FRAME} (width|height)",
        "(shot|seen|photographed|taken|framed) (up )?close( up)?",
        "(from|at) (very |really )?close( range)?",
        "(very )?tightly",
        "(from )?((right|really|very|real) )?up close",
        # ... and near ("photo of the bench from near", "from very near"): parse20s.
        "from ((a )?(little|bit) |very |really |so |quite )?(near|nearby|near by)(?= ([,.;:!)]|$|and |with |so |but ))",
        # A size said as a noun phrase ("in big size", "the vase large size"): parse20s.
        SIZE_NOUN.replace("{WORD}", "(big|large|huge|bigger|larger|full)"),
        # Near enough to touch ("within arm's reach", "at arm's length").
        "(within|at) (an |one )?arm 's (reach|length)",
        "(from )?close up",
        "(framed|cropped) (very )?(tightly|tight|close|closely)",
        "(crop|cropping|frame|framing) (in )?(tight|tightly|close|closely)( (on|to) {obj})?",
        "(tightly|tight) (framed|cropped)",
        "(large|big|huge|tight|close|full|larger|bigger) (in|on|within|inside) (the )?{FRAME}",
        "(as )?(big|large) as possible( in (the )?{FRAME})?",
        "(as )?(big|large|close|tight) as (you can|you can get( it)?|it gets|can be|it can be|it will go"
        "|it ll go|it will get|it ll get|you can make it)( in (the )?{FRAME})?",
        "(as )?(big|large) as the {FRAME} (allows|permits|will allow|lets you)",
        "(taking up|takes up|take up|occupying|occupies|occupy|covering|covers|cover) (most of |all of )?"
        "the (whole |entire )?{FRAME}",
        "(dominating|dominates|dominate|dominated|dominant in) the ({FRAME}|composition)",
        "{obj} (dominates|dominating|dominant)(?= ([,.;!]|$))",
        "zoom(ed|ing)? (way |all the way |right |well )?in( close| tight)?( (on|to|at) {obj})?( (a lot|lots|loads))?",
        "zoom(ed|ing)? (way |all the way |right |well )?into {obj}",
        # Zoomed until nothing else is left ("zoom until there's nothing but the cup", "push in
        # till you see nothing except the mug").
        "(zoom(ed|ing)?( in)?|(push|pushed|pushing|crop|cropped|cropping|move|moving|get|getting|go|going|come|coming"
        "|punch|punching) in)( close| tight| closer| tighter)? (until|till|so|so that|to where) (there 's |there is "
        "|you see |we see |you can see |it 's |it is |all you see is |all we see is )?(nothing )?(but|except|other than"
        "|besides|apart from|else than)? {obj}( (in|inside|within|filling) (the )?{FRAME})?",
        # The idiom ("up close and personal").
        "(up )?close and personal",
        # Right up to it ("get right up to the mug").
        "(get|getting|go|going|come|coming|move|moving|step|stepping|walk|walking) (right |really )?up "
        "(to|close to|next to) {obj}",
        # Moving nearer ("move a bit more close", "step closer to it").
        "(go|going|move|moving|step|stepping|get|getting|come|coming|push|pushing|creep|creeping|lean|leaning) "
        "((a bit|a little|much|way|well|{WEAK}) )?(closer|nearer)( in)?( to {obj})?",
        "(move|moving|come|coming|go|going|push|pushing|pushed|get|getting|punch|punching|punched|dolly|dollying|crop|cropping"
        "|cut|cutting|creep|creeping|lean|leaning) (right |way )?in( close| closer| tight| tighter)?( (on|to|at) {obj})?",
        "(get|getting|go|going|come|coming|move|moving) (right |really )?(up )?close( (to|on) {obj})?",
        "(close|closing) in on {obj}",
        # Close to it, of the camera; "the teddy close to the sofa" relates two objects.
        "(from (very )?close (by|to {obj})|(very )?close (by|to (it|them)))",
        "((keep|keeping) (it |{obj} )?|nice and |really |very )?(tight|close) on {obj}",
        # "close on its face": the possessive and its part stay a cue of their own (a view side).
        "((keep|keeping) (it |{obj} )?|nice and |really |very )?(tight|close) on(?= {P} )",
        "(keep|keeping) (it|{obj}) (nice and |really |very )?tight",
        ALONE.replace("{WORD}", "(tight|close|big|large|huge|closer|tighter|bigger|larger|close in|in close|in tight|closer up)"),
        ALONE_PLACED.replace("{WORD}", "(big|large|huge|bigger|larger|massive|enormous)"),
        COPULA_SIZE.replace("{WORD}", "(" + "|".join(SIZE_WORDS["close-up"]) + ")"),
        # Too big to fit ("so big it doesn't even fit", "too large to fit in the frame"): parse18p6.
        "(so |such |{VERY} )?(big|large|huge|close|near|massive|enormous|giant) (that )?(it |{obj} )?(doesn t|doesnt|does not"
        "|won t|wont|will not|can t|cant|cannot|can not|would not|wouldn t|wouldnt) (even |quite |all )?fit"
        "( (in|into|inside) (the )?{FRAME})?",
        "too (big|large|huge|close|near|massive|enormous) (for (the )?{FRAME}|to fit( (in|into|inside) (the )?{FRAME})?)",
        # Pressing on every edge of the frame ("spines crowding every edge of the frame", "touching
        # all four sides of the picture"): the subject fills it.
        "(([a-z]+ )?(crowding|crowds|crowd|filling|fills|fill|touching|touches|touch|hitting|hits|hit|reaching|reaches"
        "|reach|pressing against|presses against|meeting|meets|spilling over|spilling off|bleeding off|running off"
        "|going off|cut off by|cropped by|cut by"
        # Spilling or running past every edge ("his fur spills past all four edges"): parse18p6.
        "|(spills|spill|spilling|spilt|spilled|runs|run|running|goes|go|going|extends|extend|extending|bleeds|bleed"
        "|bleeding|pokes|poke|poking|sticks|stick|sticking) (past|over|off|beyond|out of|out past|out over)) )"
        "((every|each|all|all four|all the|all 4|both) ({FRAME} )?(edge|edges|side|sides|border|borders)( of (the )?{FRAME})?"
        "|the {FRAME} (edges|borders|sides)|the (edges|borders|sides) of (the )?{FRAME}|the (edges|borders))",
        # Filling the frame from one edge to the other ("filling the frame edge to edge").
        "(filling|fills|fill|filling up|fills up|spanning|spans|covering|covers) (all of |the whole of )?"
        "the (whole |entire )?{FRAME} (from )?(edge to edge|side to side|corner to corner|border to border)",
        "(from )?(edge to edge|side to side|corner to corner|border to border) (in|of|across) the {FRAME}",
        # A size word right after the subject ("TV big and square on", "toy car close, from ...").
        # Not a place near an edge ("the mug close to the left edge of the frame").
        AFTER_SUBJECT.replace("{WORD}", "(" + "|".join(("close up", *SIZE_WORDS["close-up"])) + ")")
        + "(?! to (the )?(left|right|top|bottom|edge|edges|corner|side|center|middle|border|@\\d)( |$))",
        # The subject filling the frame said as a result of the closeness ("so close it's all you
        # can see", "close enough that he fills most of it", "near enough they are all we see"):
        # parse20s.
        "(so |such |{VERY} |{FAIRLY} )?(big|large|huge|close|near|tight|massive) (enough )?(that |so that |so )?"
        "(it 's|it s|it is|he 's|he is|she 's|she is|they re|they 're|they are|{obj} is|{obj} are) (all|everything|the only thing"
        "|the one thing|all that) (that )?(you|we|i|one|the camera|the viewer|anyone) (can |could |will |ll |would |d )?"
        "(see|sees|get|gets)",
        "(so |such |{VERY} |{FAIRLY} )?(big|large|huge|close|near|tight|massive) (enough )?(that |so that |so |to )?"
        "(it|he|she|they|{obj}) (nearly |almost |completely |entirely |just )?(fills|fill|takes up|take up|covers|cover)"
        " (most of |all of |nearly all of |almost all of )?(it|everything|the (whole |entire )?{FRAME})",
        SHOT_LABEL.replace("{WORD}", "(tight|tighter|close|closer|detail|macro|medium close)"),
        # A size as a noun, "one" standing for the shot ("a tight one of the mug"): parse18p6.
        "(a |an )?(tight|tighter|close|closer) one( (of|on) {obj})?",
    ],
    "medium": [
        # The size word as the shot's noun ("Medium on the armchair", "a medium, from the left",
        # "in a medium"): parse18p6.
        "((?<=^ )|{CLAUSE}|(?<=in )|(?<=as ))(a |an )?medium( (of|on) {obj})?(?= ([,.;:!]|$|from |at |with |and ))",
        "(a |an )?medium (of|on) {obj}",
        "(at )?(a )?(medium|moderate) size( in (the )?{FRAME})?",
        "((framed|shot|seen|taken) )?(at|from) (a )?(mid|medium|moderate) (distance|range)",
        "(taking up|occupying|filling) (a )?(moderate|medium) (part|portion|amount|share) of the {FRAME}",
        "(taking up|filling|occupying) (about |roughly |around )?half (of )?the {FRAME}",
        "((at|to) )?(about |roughly |around |some )?half (of )?the {FRAME}( (height|width|high|tall|wide))?",
        "(medium|moderately|mid|middle|moderate) (sized|size)( in (the )?{FRAME})?",
        "neither (too )?close nor (too )?far",
        # Neither size overdone ("not too zoomed in", "not so far away", "not overly tight").
        "not (too |so |that |overly |very |super |too much )({NOT_TOO})"
        "( (and |but |or |, )?not (too |so |that |overly |very |super |too much )({NOT_TOO}))?",
        # A medium size alone as a clause ("the chair from the front, medium, eye level").
        ALONE.replace("{WORD}", "(medium|mid|medium wide|medium long|medium full|mid length|full length)"),
        ALONE_PLACED.replace("{WORD}", "(medium|medium sized|mid sized)"),
        # ... or right after its subject ("shoot from a little above, chair medium"): parse20s.
        AFTER_SUBJECT.replace("{WORD}", "(medium|medium sized|mid sized)"),
        # Just fitting in the frame ("so it just fits in the frame"): all of it, with little room.
        "(so (that )?)?{obj} (just |only just |barely |exactly |neatly )?(fits|fit)( (in|inside|within|into) (the )?{FRAME})?",
    ],
    "wide": [
        "(quite |very |really |rather |fairly )?(small|tiny|smaller) (in|on|within|inside) (the )?{FRAME}",
        "(as |taking up |occupying )?(only )?(a |just a )?(small|little|tiny) (part|portion) of the {FRAME}",
        "(taking up|takes up|occupying|occupies|filling|fills|covering|covers|as) (only |just |barely )?(a )?"
        "(small |tiny |mere )?(fraction|sliver|corner|bit) of the {FRAME}",
        "(way |far |well )off in the distance",
        "(from )?(very )?far away",
        "from afar",
        "from (a )?(long |great )?distance",
        "(from )?far (off|back)",
        # A distance said bare after "from" or "at", as learners say it ("take the bench from far",
        # "from a little far", "the sofa at a distance"): parse20s.
        "from ((a )?(little|bit|bit more|little more|more|very|really|so|quite|too) )?far(?= ([,.;:!)]|$|and |with |so |but ))",
        "at a ((great|good|long|fair|safe|big) )?distance",
        "(from )?(a )?(long|great|good) way (off|away|back)",
        "far (away )?from {obj}",
        "(from )?(much |{WEAK} )?(further|farther) (away|back|off)",
        "with (plenty of|lots of|a lot of|generous|ample|enough) (space|room|breathing room|context) around {obj}",
        "(with )?(lots of|plenty of) (empty |negative )?space",
        SIZE_NOUN.replace("{WORD}", "(small|little|tiny|smaller)"),
        # Room to breathe around it ("with breathing room around it", "some elbow room").
        # Margins or room all round it ("with a generous margin", "space on all sides", "a little room around it").
        "(with )?((a |some |generous |wide |big |ample |decent |a little |a bit of |a little bit of )?)"
        "(margin|margins|border|padding)"
        "( (all round|all around|on all sides|around {obj}|round {obj}))?",
        "(with )?((a good bit of) )?(space|room|air|floor|table|grass|wall)"
        " ((around|round|about) {obj}|(all round|all around|on all sides|on every side))",
        "(with )?((some|a bit of|a little|enough|a lot of|lots of|plenty of|loads of) )?(breathing|elbow|head) (room|space)"
        "( (around|round|about) {obj})?",
        # Room left around it, of whatever kind ("loads of room", "lots of table around it").
        "(with |leave |leaving |give it |giving it )?{PLENTY} ([a-z]+ )?"
        "(space|room|air|context|background|table|floor|grass|sky|ground|wall|scenery)"
        "( (around|round|about) {obj})?",
        "(with )?{PLENTY} ([a-z]+ ){1,2}(around|round|about) {obj}",
        # The subject said to be "just a small thing" ("so the vase is just a small thing").
        "(is|as|be|looks like) (just |only )?(a |an )?(small|tiny|little|distant) (thing|speck|dot|spot)",
        # One small element of a larger picture ("as a small element in the landscape", "a minor
        # part of the scene"): said with "as" or with the whole it is part of.
        # Also a small shape or figure in a big, empty room ("as a small shape in a big empty room").
        "(as |is |be |becomes |looks like )(just |only |merely )?(a |an |one )?(small|tiny|little|minor|minuscule|distant|modest)"
        " (element|part|feature|presence|component|shape|figure|blob)( (in|of|within) (the |a |an )?({WHOLE}|("
        + ROOMY_FRAME
        + " ){0,3}(room|space|expanse)))?",
        "(just |only |merely )?(a |an |one )?(small|tiny|little|minor|minuscule|distant|modest)"
        " (element|part|feature|presence|component|detail) (in|of|within) (the |a |an )?{WHOLE}",
        # Wide on the subject, as a shot list says it ("WIDE on the cone").
        "({WEAK} |a )?(wide|wider|long|extreme wide|very wide) on {obj}",
        # The size word as the shot's noun ("the mug as a wide", "a wide, from behind"): parse20s.
        "((?<=^ )|{CLAUSE}|(?<=in )|(?<=as ))(a |an )(wide|long|extreme wide|very wide|wider)( (of|on) {obj})?"
        "(?= ([,.;:!)]|$|from |at |with |and ))",
        "zoom(ed|ing)? (way |all the way |well )?out( (a lot|lots|loads))?( (from|on) {obj})?",
        # A loose framing: room left around the subject ("framed loosely", "a loose shot", "keep it loose").
        "((framed|shot|cropped|kept|keep it|keeping it) )?(loosely|loose)( (framed|cropped))?"
        "(?= ([,.;!]|$|and |with |from |at ))",
        "(a |an )?(loose|looser|loosely framed) (shot|framing|frame|crop|composition)",
        # Room to breathe around it ("with room to breathe", "give it space to breathe").
        "((with|give it|leave|leaving) )?((some|a bit of|a little|enough|lots of|plenty of|loads of) )?(room|space) to breathe"
        "( (around|round|about) {obj})?",
        "(pull|pulled|pulling|step|stepped|stepping|move|moving) (way |far |well )?back( enough)?( from {obj})?",
        "(go|going|keep it|keeping it|shoot|shooting) wide( on {obj})?",
        ALONE.replace("{WORD}", "(wide|wide angle|small|tiny|little|distant|far|far away|far off|smaller|wider|further|farther)"),
        ALONE_PLACED.replace("{WORD}", "(small|tiny|little|wee|smaller|minuscule|teeny|teensy|titchy|teeny tiny)"),
        COPULA_SIZE.replace("{WORD}", "(" + "|".join(SIZE_WORDS["wide"]) + ")"),
        # Likened to a speck ("the ball a speck in the middle", "the bench just a dot").
        "({obj} )?((is|as|be|like|looks like|reduced to|becomes|becoming|the size of) )?((just|only|no more than|nothing but) )?"
        "(a |an )?((small|tiny|little|distant|mere|wee) )?{SPECK}( (sized|size))?( of (the )?{FRAME})?",
        # Moving back ("go more far", "step a little further away").
        "(go|going|move|moving|step|stepping|get|getting|stand|standing|back|backing|pull|pulling) "
        "((a bit|a little|much|way|well|{WEAK}) )?(further|farther)( (away|back|off|out))?( from {obj})?",
        # The whole of its surroundings around it ("with the whole room around it").
        "(with )?(the )?(whole|entire) (room|scene|surroundings|setting|table|tabletop|floor|lawn|space|wall)"
        " (around|round|about) {obj}",
        AFTER_SUBJECT.replace("{WORD}", "(" + "|".join(SIZE_WORDS["wide"]) + ")"),
    ],
}

# A size said as leaning one way ("kept on the small side", "a bit on the big side").
SHOT_CLAUSES["wide"].append("((kept|keep it|keeping it|{WEAK}) )?on the (small|smaller|little|tiny|wee) side(?! of )")
SHOT_CLAUSES["wide"].append(SHOT_LABEL.replace("{WORD}", "(wide|wider|long|establishing|wide angle|extreme wide|very wide)"))
SHOT_CLAUSES["close-up"].append("((kept|keep it|keeping it|{WEAK}) )?on the (big|bigger|large|larger) side(?! of )")
# The frame said to be empty round the subject after the area it sits in ("in the lower left of a big
# empty frame", "top right of an otherwise blank picture"): room all round it, wide: parse20s.
EMPTY_WORDS = "(a|an) (" + ROOMY_FRAME + "( ,)? ){0,2}(empty|open|blank|spacious|vast)"
EMPTY_FRAME = EMPTY_WORDS + "( ,)? {FRAME}"
EMPTY_FRAME_AFTER = EMPTY_WORDS + " "
SHOT_CLAUSES["wide"] += [
    "(?<= )(of|in|within|inside) " + EMPTY_FRAME,
    "(({FAIRLY}|very|really) )?(small|tiny|little|wee|minuscule|smaller) (in|on|within|inside|against) (a |an |the )?"
    "(" + ROOMY_FRAME + "( ,)? ){1,3}({FRAME}|expanse|space|landscape|scene|setting|room|field|garden|world|vista|panorama)",
]

# All of the subject in the picture, said in a clause ("the whole bench in frame", "fully visible").
SHOT_CLAUSES[WHOLE] = [
    # The whole subject, said alone as a clause ("front-left three-quarters, at seat level, complete").
    ALONE.replace("{WORD}", "(complete|whole|entire|uncropped|in full|in its entirety|all in|all of it|in one piece)"),
    # ... and said alone with the picture it is whole in ("..., complete in the photo, ...").
    "{CLAUSE}(complete|whole|entire|uncropped|all in) (in|inside|within|on) (the )?({FRAME}|view)"
    "(?= ([,.;:!)]|$|and |with |from |at |but ))",
    # The whole subject in the picture ("the whole bench in frame", "slats and all").
    "(the )?(whole|entire|full|complete) (of )?{obj}( (is |fits |sits )?(in|inside|within) (the )?({FRAME}|view))?",
    "(the )?(whole|entire) thing( (in|inside|within) (the )?{FRAME})?{FITS}",
    # A whole dimension or unit of it seen ("full height in frame", "entire height visible",
    # "the whole set in view"), or it said as a generic noun ("the whole model in frame").
    "(the |{P} )?(whole|entire|full) (height|length|width|body|figure|set|unit|piece|model|object|item|thing)( of {obj})?"
    "( (is )?(in|inside|within) (the )?({FRAME}|view))?( visible| in view| showing)?",
    "(all of|every bit of) {obj}( (in|inside|within) (the )?{FRAME})?{FITS}",
    # Nothing of it cropped ("don't crop it", "do not cut it off").
    "(don t|do not|dont|never) (crop|cut off|cut|chop)( {obj}| anything| any of {obj})?( off)?",
    # Nothing of it cut by the frame ("not cut off anywhere", "nothing cropped").
    "(not|nothing|no part|none of it) (cut off|cropped|clipped|chopped off|cut)( anywhere| at all| by the {FRAME})?",
    # All of it seen ("fully visible", "completely in frame").
    "(fully|completely|entirely|wholly) (visible|(in|inside|within) (the )?({FRAME}|view))",
    # The whole of the kind of thing it is ("full vehicle in frame", "the entire animal visible").
    "(the |{P} )?(whole|entire|full|complete) {CLASS}( (is )?(in|inside|within) (the )?({FRAME}|view))?"
    "( visible| in view| showing)?",
    # The subject said whole ("the grey teddy whole in frame", "the bench complete in the shot").
    "{obj} (is |shown |seen |kept )?(whole|complete|entire|uncropped|in full|in its entirety)"
    "( (in|inside|within) (the )?({FRAME}|view))?(?= ([,.;!]|$|and |with |from |at ))",
    "(?<=, )[a-z]+( [a-z]+)? and all(?= ([,.;!]|$))",
    # Every part of it seen ("every slat in view", "each leg visible", "all four wheels in shot").
    "((every|each) |all (of )?({P} |the )?([a-z0-9]+ )?)([a-z]+|@\\d) (in view|visible|showing|in (the )?{FRAME})",
    # All of one's self ("showing his whole self", "all of himself in the picture").
    "(the |{P} )?(whole|entire|full|complete) self",
    # "All sofa inside", the article dropped as non-native writers drop it.
    "(with )?all {obj} ((inside|within|in)( the)? {FRAME}|inside|visible|in view|showing)(?= ([,.;!]|$|and |with |from ))",
    "{obj}( ,)? [a-z]+( [a-z]+)? and all(?= ([,.;!]|$))",
    # Said whole after a verb of being or keeping ("it must be whole in picture", "the tree should
    # stay complete in the frame"): parse20s.
    "(be|being|is|are|stay|stays|remain|remains|kept|keep it|keeping it|appear|appears|come out|comes out|show|shows)"
    " (whole|complete|entire|uncropped|in full|in its entirety|all in)( (in|inside|within|on) (the )?({FRAME}|view))?"
    "(?= ([,.;:!)]|$|and |with |from |at |but ))",
]
# A small margin round the whole subject ("with a bit of margin", "leave a small margin", "a touch
# of padding all round"): all of it with little room, a medium shot; a generous margin stays wide.
SHOT_CLAUSES["medium"] += [
    "((with|leave|leaving|give it|giving it|plus) )?(a little bit of |a little |a bit of |a touch of |some "
    "|(a )?(small|slight|thin|narrow|tiny|minimal) )(margin|margins|border|padding)"
    "( (all round|all around|on all sides|around {obj}|round {obj}))?",
    # ... as is a little room of any kind round it ("with a bit of air around it", "some wall on
    # each side", "a touch of table all round"): parse20s; plenty of it stays wide.
    "((with|leave|leaving|give it|giving it|plus) )?(a little bit of |a little |a bit of |a touch of |a tad of |some "
    "|a small amount of )(space|room|air|floor|table|grass|wall)"
    " ((around|round|about) {obj}|(all round|all around|on all sides|on every side|on each side|on either side|each side))",
]
# From one end of it to the other ("from floor to top in frame", "base to bulb"): all of it is
# in, which alone is a medium shot (:func:`_said_shot`) but says no size beside a size word:
# "filling the frame top to bottom" is a close-up (:func:`_combined_shot`).
WHOLE_SPAN = "end to end"
WHOLE_SPAN_PHRASES = [
    "(from )?(the |{P} )?{END} {END_TO} (the |{P} )?{END}"
    "(( ,)?( all| fully| completely| entirely| wholly)? ((in|inside|within) (the )?({FRAME}|view)|visible|showing))?",
]

# The subject's share of the frame said as a number ("filling about 70% of the frame", "a third of
# the picture high"): the shot size whose range holds it (:func:`_shot_of_share`).
SHARE_PHRASES = [
    "((filling|fills|fill|taking up|takes up|take up|occupying|occupies|covering|covers|eating up|eats up|using up|uses up"
    "|at|to|so it fills) )?"
    "((about|around|roughly|approximately|some|only|just|nearly|almost|maybe) )?"
    "({SHARE}) (of )?(the )?{FRAME}( (height|width|high|tall|wide|across))?",
]

# Regions: "PREPOSITION the AREA [of the FRAME]", never followed by "of" (relations between
# objects such as "to the left of the vase" are not regions of the frame).
REGION_PREPOSITIONS = "(on|in|at|to|near|towards|within|into|inside|along|across)"
# What may lead into a region: a placing verb or a direction ("tucked into the top-left corner",
# "up in the top half").
# Verbs of placing a subject in the frame, before an area said without a preposition.
PLACING = "(tucked|placed|put|positioned|parked|set|kept|nudged|pushed|shoved|squeezed|sat|sitting|framed)"
REGION_LEAD = (
    "((tucked|tuck|pushed|squeezed|nestled|placed|put|sitting|sits|sit|sat|stuck|parked|positioned|kept|shoved|offset|shifted"
    "|lies|lying|stands|resting|rests|appears|appearing|ends up|ending up|stay|stays|staying|remain|remains|remaining|be"
    "|nudged|moved|slid|pulled|set) )?"
    "((up|down|over|across|out|way|right|off|low|high|plumb|slap bang|smack bang|{STRONG}) ){0,2}"
)
# Verbs of a subject taking up an area, maybe said as a purpose ("pushed across to occupy the right
# third", "hugging the frame's right-hand edge").
OCCUPYING = (
    "((so as |in order )?to |so it )?(taking up|takes up|take up|occupying|occupies|occupy|filling|fills|fill|covering"
    "|covers|cover|spanning|spans|span|hugging|hugs|hug|touching|touches|touch)"
)
# A third of the frame said as a column, a strip or a band of it (parse18p6): by a side, only with
# the frame said split in three ("the right-hand column if you split the frame into three", "the
# middle strip when you divide the picture into 3 vertical bands", "left band of the thirds grid");
# by its place in a row ("the first column on the left", "the last column") as it is.
THIRD_COLUMN = "(column|strip|band|slice|section|panel)"
SPLIT_IN_THREE = (
    " ((if|when|once|after|with) ((you |we |i |one )?(split|divide|cut|break|chop|slice|separate)( up)?"
    " (the |this |your )?(frame|picture|image|photo|shot|composition|view)|(the |this |your )?"
    "(frame|picture|image|photo|shot|composition|view) (is |gets |being )?(split|divided|cut|broken|chopped|sliced"
    "|separated)( up)?) (into|in) (3|thirds|3 parts)"
    "( (vertical|upright|equal|even|tall) (bands|strips|columns|parts|sections|slices|pieces))?"
    "|(of|in|on) (the |a )?(rule of )?thirds?( grid)?|(of|in|on) (the |a )?3 (column|by 3) grid)"
)
REGION_AREAS = {
    "left": [
        "left",
        "left side",
        "left half",
        "left hand side",
        "left part",
        "left edge",
        "left hand part",
        "left hand edge",
        "center left",
        "middle left",
    ],
    "right": [
        "right",
        "right side",
        "right half",
        "right hand side",
        "right part",
        "right edge",
        "right hand part",
        "right hand edge",
        "center right",
        "middle right",
    ],
    "center": [
        "center",
        "middle",
        "very center",
        "dead center",
        "exact center",
        "very middle",
        "dead middle",
        "exact middle",
        "midst",
    ],
    # The middle of the top or bottom edge is that half ("bottom-centre", "top middle").
    "top": [
        "top",
        "top half",
        "upper half",
        "upper part",
        "top part",
        "top edge",
        "upper edge",
        "upper side",
        "top side",
        "top third",
        "upper third",
        "top center",
        "top middle",
        "upper center",
    ],
    "bottom": [
        "bottom",
        "bottom half",
        "lower half",
        "lower part",
        "bottom part",
        "bottom edge",
        "lower edge",
        "lower side",
        "bottom side",
        "bottom third",
        "lower third",
        "bottom center",
        "bottom middle",
        "lower center",
        "foot",
    ],
    # A third may be called vertical, or its line ("the left vertical third", "the right-hand third line").
    "left third": [
        "(left|leftmost|first|left hand)( side)?( vertical)? (thirds?( line)?|line of thirds)",
        "(left|leftmost|left hand)( vertical)? " + THIRD_COLUMN + SPLIT_IN_THREE,
        "first( vertical)? " + THIRD_COLUMN + "( (on|from) the left)?(" + SPLIT_IN_THREE + ")?",
    ],
    "center third": [
        "(middle|central|center)( vertical)? third",
        "(middle|central|center)( vertical)? " + THIRD_COLUMN + SPLIT_IN_THREE,
    ],
    "right third": [
        "(right|rightmost|last|right hand)( side)?( vertical)? (thirds?( line)?|line of thirds)",
        "(right|rightmost|right hand)( vertical)? " + THIRD_COLUMN + SPLIT_IN_THREE,
        "(last|third)( vertical)? " + THIRD_COLUMN + "( (on|from) the right)?(" + SPLIT_IN_THREE + ")?",
    ],
    "upper left": [
        "corner (top|upper) left",
        "upper left( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "top left( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "left top corner",
    ],
    "upper right": [
        "corner (top|upper) right",
        "upper right( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "top right( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "right top corner",
    ],
    "lower left": [
        "corner (bottom|lower) left",
        "lower left( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "bottom left( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "left bottom corner",
    ],
    "lower right": [
        "corner (bottom|lower) right",
        "lower right( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "bottom right( hand)?( corner| quadrant| quarter| area| region| part| section| zone)?",
        "right bottom corner",
    ],
}
# A corner is a height, a side and a corner noun in any order, with any glue between them ("right
# upper corner", "the upper corner on the left", "the left-hand corner at the bottom", "the corner
# at the top on the right", "the corner, bottom right"); a height and a side said apart as two
# regions join into it too (_combined_region).
CORNER_NOUN = "(corner|quadrant|quarter)"
CORNER_GLUE = "( ,)? (on|to|at|in|towards) the "
for _vertical, _height in (("upper", "(top|upper)"), ("lower", "(bottom|lower)")):
    for _lat in ("left", "right"):
        _side = f"{_lat}( hand)?"
        REGION_AREAS[f"{_vertical} {_lat}"] += [
            f"{_side} {_height}( hand)? {CORNER_NOUN}",
            f"{_height} {CORNER_NOUN}{CORNER_GLUE}{_side}( side)?",
            f"{_side} {CORNER_NOUN}{CORNER_GLUE}{_height}",
            f"corner{CORNER_GLUE}{_height}( ,)?( (on|to|at|in|towards) the)? {_side}( side)?",
            f"corner{CORNER_GLUE}{_side}( side)?( ,)?( (on|to|at|in|towards) the)? {_height}",
            f"corner( ,)? {_height} {_side}",
            f"corner( ,)? {_side} {_height}",
            # The side said first with no corner noun ("bench in right bottom", "the left top of the
            # picture"), not before a half or a third ("the left top half" is no corner).
            f"{_side} {_height}(?! (half|third|part|edge|side|hand|corner|quadrant|quarter) )",
        ]
# A half said as any part of the frame ("the upper area", "the lower portion", "the left section").
for _region, _words in (
    ("left", "(left|left hand)"),
    ("right", "(right|right hand)"),
    ("top", "(top|upper)"),
    ("bottom", "(bottom|lower)"),
):
    REGION_AREAS[_region].append(f"{_words} (area|region|portion|section|zone|band|strip)")
# The frame read as a map, north up ("the north-west corner", "the NE quadrant", "the south edge").
for _region, _compass in (
    ("upper left", "(north west|northwest|nw)"),
    ("upper right", "(north east|northeast|ne)"),
    ("lower left", "(south west|southwest|sw)"),
    ("lower right", "(south east|southeast|se)"),
):
    REGION_AREAS[_region].append(_compass + " (corner|quadrant|quarter|area|region|part|section|zone)")
for _region, _compass in (("top", "north"), ("bottom", "south"), ("left", "west"), ("right", "east")):
    REGION_AREAS[_region].append(_compass + " (half|edge|side|part|area|end)")
# Room left on one side of the subject ("a bit of space on the left", "headroom above it"): the
# subject sits in the other half.
ROOM_SIDES = {"left": "right", "right": "left", "top": "bottom", "bottom": "top"}
ROOM_PHRASES = [
    "(with )?(({WEAK}|some|a bit of|a little bit of|plenty of|lots of|more) )?(of )?(empty |negative |free |lead |breathing )?"
    "(space|room|headroom|air) (on|to|at|in) the {SIDE}( side| half)?( of (the )?{FRAME})?",
    "(with )?(({WEAK}|some|a bit of|a little bit of|plenty of|lots of|more) )?(of )?(empty |negative |free |lead |breathing )?"
    "(space|room|headroom|air) {BESIDE}( {obj}| the subject)?(?= ([,.;!]|$|and |with ))",
]
ROOM_BESIDE = {
    "left": "(to the )?left of",
    "right": "(to the )?right of",
    "top": "(above|over)",
    "bottom": "(below|beneath|under)",
}
# Off the centre towards a side ("a bit left of centre", "off-centre to the right", "just above
# the middle"): that half of the frame.
OFF_CENTER = [
    "(({WEAK}|just|{VERY}) )?(to the )?{TOWARD} of (the )?({FRAME} )?(center|middle)( of (the )?{FRAME})?",
    "(({WEAK}|just|{VERY}) )?off (the )?(center|middle) (to|towards) the {TOWARD}( of (the )?{FRAME})?",
]
# A half of the frame said as the side of its middle line ("below the halfway line of the photo",
# "above the horizontal midline", "left of the vertical centre line of the frame"): a line said
# of the frame, or by a word only the frame's line has ("halfway", "midline", "horizontal"); a
# bare "centre line" may be the subject's own, so it needs the frame said.
_MID = "(halfway|half way|center|middle|mid|central)"
_OF_FRAME = " (of|across|through|in) (the )?{FRAME}"
FRAME_MIDLINE = {
    axis: f"the (({axis} )?(halfway|half way) line|({axis} )?mid ?line|{axis} {_MID} ?line|{_MID} ?line{_OF_FRAME})"
    + f"({_OF_FRAME})?"
    for axis in ("horizontal", "vertical")
}
# The middle said both ways ("centered left to right and top to bottom"): the centre.
CENTERED_BOTH_WAYS = (
    "centered ((both )?(left to right|side to side|horizontally) (and|,) (top to bottom|up and down|vertically)"
    "|(both )?(top to bottom|up and down|vertically) (and|,) (left to right|side to side|horizontally))"
)
REGION_PHRASES = {
    # "Screen left" is film language for frame left.
    # A corner said by its side alone ("in the right-hand corner"): that side, its height unsaid
    # (said with one, the corner: "low in the right corner", "at the bottom, in the left corner").
    "left": [
        "(on |at |in )?(the )?({FRAME}|screen) left",
        "left of (the )?({FRAME}|screen)",
        "(to the )?left of " + FRAME_MIDLINE["vertical"],
        "(in|into|at|towards|on) the left( hand)? corner( (of|in) (the )?{FRAME})?",
    ],
    "right": [
        "(on |at |in )?(the )?({FRAME}|screen) right",
        "right of (the )?({FRAME}|screen)",
        "(to the )?right of " + FRAME_MIDLINE["vertical"],
        "(in|into|at|towards|on) the right( hand)? corner( (of|in) (the )?{FRAME})?",
    ],
    "center": [
        # Kept central ("keep the mug central", "the bench, dead central").
        "(keep|keeping|kept|placed|positioned|sitting) (it |{obj} )?((dead|right|nicely) )?central(ly)?",
        "{CLAUSE}((dead|right) )?central(?= ([,.;!]|$))",
        "centered( in (the )?{FRAME})?",
        "centrally( placed| positioned)?( in (the )?{FRAME})?",
        "center {obj}( in (the )?{FRAME})?",
        "(at |in )?(the )?{FRAME} center",
        "center of (the )?{FRAME}",
        # The centre said before the frame ("centre frame", "middle of frame").
        "(in |at )?(the )?((dead|exact|very|right) )?(center|middle) (of )?{FRAME}",
        "dead center",
        "(front and|center) (center|stage)",
        # Mid-frame: the middle of the frame ("mug mid-frame", "midframe", "mid-picture").
        "(in |at )?(the )?mid ?{FRAME}",
        "midframe",
        CENTERED_BOTH_WAYS,
    ],
    "top": ["high (up )?in (the )?{FRAME}", "(above|over) " + FRAME_MIDLINE["horizontal"]],
    "bottom": ["low (down )?in (the )?{FRAME}", "(below|under|beneath|underneath) " + FRAME_MIDLINE["horizontal"]],
    "upper left": ["(top|upper) left corner"],
    "upper right": ["(top|upper) right corner"],
    "lower left": ["(bottom|lower) left corner"],
    "lower right": ["(bottom|lower) right corner"],
}

# A corner with plain words of height too ("up", "down", "high", "low") and any glue between the
# two, in either order, the corner noun before or after them ("the corner up and right of the
# picture", "the up-right corner", "the right and upper corner", "the corner, left and down", "the
# corner of the frame up and to the left"): the noun is said, so no height or side alone is
# taken for a corner. "Quarter" is left out: "rear quarter, left side, low" is a view and a height.
CORNER_AND = "( and| &)?( (on|to|at|in|towards) the)? "
CORNER_AFTER = "( ,)?( (of|in) (the )?{FRAME})?( ,)?( (on|to|at|in|towards) the)? "
for _vertical, _height in (("upper", "(top|upper|up|high|higher)"), ("lower", "(bottom|lower|down|low)")):
    for _lat in ("left", "right"):
        _both = f"({_height}{CORNER_AND}{_lat}( hand)?( side)?|{_lat}( hand)?( side)?{CORNER_AND}{_height})"
        REGION_PHRASES[f"{_vertical} {_lat}"].append(
            f"({REGION_PREPOSITIONS} )?(the )?((corner|quadrant){CORNER_AFTER}{_both}|{_both} (corner|quadrant))"
            "( (of|in) (the )?{FRAME})?(?! of )"
        )

# Up (down) and to a side of the picture, maybe in its corner ("up and to the right of the frame, in
# the corner"); without the picture it may move the camera or say where a thing is.
for _vertical, _height in (("upper", "(up|high|higher)"), ("lower", "(down|low|lower)")):
    for _lat in ("left", "right"):
        REGION_PHRASES[f"{_vertical} {_lat}"].append(
            f"{_height} (and|&) (to|towards) the {_lat}( hand)?( side)? (of|in) (the )?{{FRAME}}"
            "(( ,)? (in|into|at|towards) the corner)?"
        )

# A corner said with a height ("low in the right corner of the picture", "up in the left corner").
for _lat in ("left", "right"):
    for _corner, _height in (("upper", "(high|up|higher) (up )?"), ("lower", "(low|down|lower) (down )?")):
        REGION_PHRASES[f"{_corner} {_lat}"].append(
            _height + f"(in|into|at|towards) the {_lat}( hand)? corner( (of|in) (the )?{{FRAME}})?"
        )

# A corner said with up or high (parse19p6): "up top" before a side ("the mug up top left"; "from
# up top" stays the camera's height); up and to a side, then the picture's corner ("high and to
# the left, in the frame's corner", "low and to the right, in the corner of the picture"); the
# height pointed at ("in the corner up there on the left", "the corner down there, right").
for _vertical, _height, _end in (("upper", "(up|high|higher)", "(top|upper)"), ("lower", "(down|low|lower)", "(bottom|lower)")):
    for _lat in ("left", "right"):
        REGION_PHRASES[f"{_vertical} {_lat}"] += [
            f"(?<!from ){_height} (at the |in the )?{_end}( ,)? {_lat}( hand)?( corner| side)?"
            "( (of|in) (the )?{FRAME})?(?! of )",
            f"{_height} (and|&) (to|towards) the {_lat}( hand)?( side)?( ,)? (in|into|at|towards)"
            " (the {FRAME} 's corner|the corner (of|in) (the )?{FRAME})( (up|down) there)?",
            f"(in|into|at|towards) the corner {_height} (there|here)( ,)?( (on|to|at|in|towards) the)? {_lat}( hand)?( side)?"
            "( (of|in) (the )?{FRAME})?(?! of )",
        ]

# View sides (the subject's own sides): side words, the frames they go into, and whole phrases.
SEEN = "((seen|viewed|shot|photographed|captured|taken|filmed|angled) )?"
# A view said as roughly that ("almost from behind", "mostly from the front"): the view's own
# tolerance allows for it.
ALMOST = "({NEARLY} |mostly |roughly )?"
# Where the camera is put: "with the camera", "camera positioned", "place the camera".
CAMERA = (
    "((with|put|place|position|keep|set|move|bring|get|have|hold|mount|park|stand) )?(the )?(camera|lens)"
    "( (is|should be|must be|being))?"
    "( (placed|positioned|located|set|standing|put|kept|parked|sitting|stationed|mounted|perched|hovering))?"
)
# Facing one way in the frame ("facing left", "pointing to the right of the frame", "gazing off to
# screen left", "nose aimed towards the left side of the picture"): the subject's own side on that
# hand is the one seen (VIEW_PHRASES).
FACING_VERBS = (
    "(facing|faces|face|looking|looks|gazing|gazes|staring|stares|pointing|points|pointed|heading|headed|heads|driving|drives)"
)
# Said of its front, or any of these verbs ("its nose aimed left"); "aimed" or "turned" alone may
# be the camera's.
PART_FACING_VERBS = "(pointing|pointed|facing|turned|aimed|aiming)"
FACING_WAY = (
    "(((with )?(the|{P}) (nose|front|face|head) " + PART_FACING_VERBS + ")|((turned|turning) (to )?)?" + FACING_VERBS + ") "
    "((to the |towards the |toward the |off to the |off towards the )?{LAT}( hand)?( side)?( (in|of) (the )?{FRAME})?"
    "|(off )?(to |towards )?(the )?(screen|{FRAME}) {LAT})"
    # "Looking right at the mug": "right" says straight at, no side.
    "(?! (at|into|down|up|over|through|onto|towards|toward)( |$))"
)
# Every way round the subject but one end ("anything but the front", "from any side except behind",
# "any angle other than its back"): that end denied (NEGATED_ENDS).
ALL_BUT = (
    "(from )?(anything|anywhere|any side|any angle|any direction|any view|every side|all sides|all round|all around)"
    "( else)? (but|except|other than|apart from|save|besides) (from )?(the |{P} )?{SIDE}( side| end| view| angle)?( of {obj})?"
)
VIEW_SIDE_WORDS = {
    # A vehicle's or a boat's ends too ("the nose end", "the stern", "aft"); a bare nose or tail is
    # a part ("so its tail shows") but where the camera is seen from (VIEW_PHRASES).
    "front": ["front", "face", "front end", "nose end", "bow", "anterior"],
    # Anatomy's and a coin's words too ("posterior aspect", "the reverse side").
    "back": ["back", "rear", "backside", "rear end", "back end", "behind", "tail end", "hind end", "stern", "aft", "aft end"]
    + ["posterior", "reverse side"],
    # "Lateral" is the side, as anatomy and technical drawing say it ("left lateral view", "lateral
    # right"), before or after the side named.
    "left": ["left", "left hand", "left( hand)?( side)? lateral", "lateral left"],
    "right": ["right", "right hand", "right( hand)?( side)? lateral", "lateral right"],
    "side": ["side", "profile", "lateral"],
    "front-left": ["front left", "left front", "front and left", "front left three quarter", "left three quarter"],
    "front-right": ["front right", "right front", "front and right", "front right three quarter", "right three quarter"],
    "back-left": [
        "back left",
        "rear left",
        "left rear",
        "left back",
        "back and left",
        "rear and left",
        "back left three quarter",
        "rear left three quarter",
        "left rear three quarter",
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
        "right rear three quarter",
    ],
}


def _diagonal_words(lon_words: tuple[str, ...], lat: str, front: bool) -> list[str]:
    """A diagonal's words in any order, with "three quarter(s)" or "diagonal" before, between or
    after them ("3/4 front-left", "three quarter rear right", "left-front three-quarters", "front
    right diagonal"); a front one also as "three quarter left" (the three-quarter view is the
    front one unless told)."""
    three_quarter = "(three quarters?|diagonal)"
    out = [" ".join(order) for lon in lon_words for order in itertools.permutations((three_quarter, lon, lat))]
    # A quarter said without "three" after the end and side ("its rear-left quarter").
    out += [f"{a} {b} quarter" for lon in lon_words for a, b in ((lon, lat), (lat, lon))]
    # ... or with the side after ("rear quarter left", "quarter rear right", "rear qtr R").
    out += [
        f"{a} {b} {lat}" for lon in lon_words if lon in ("front", "back", "rear") for a, b in ((lon, "quarter"), ("quarter", lon))
    ]
    # A front one also by its side alone ("three quarter left", "a left-side three-quarter").
    return out + ([f"{three_quarter} {lat}", f"{lat}( hand)? side {three_quarter}"] if front else [])


for _lat in ("left", "right"):
    VIEW_SIDE_WORDS[f"front-{_lat}"] += _diagonal_words(("front",), _lat, True) + [f"{_lat} bow"]
    VIEW_SIDE_WORDS[f"back-{_lat}"] += _diagonal_words(("back", "rear", "tail end"), _lat, False)
    # Turned three-quarters to a side ("the teddy turned three-quarters to the left").
    VIEW_SIDE_WORDS[f"front-{_lat}"].append(f"(turned )?three quarters? (to|towards) the {_lat}")
    # The side said as a place after the diagonal's end, either side of "three-quarter" ("rear
    # three-quarter on the right", "3/4 rear on the left").
    VIEW_SIDE_WORDS[f"back-{_lat}"].append(
        f"((back|rear) three quarters?|three quarters? (back|rear))( (view|angle|shot))? (on|to|from|at) (the|{{P}}) {_lat}"
        "( hand)?( side)?"
    )
# "Behind" as the end of a diagonal ("from behind-left", "a behind-right three quarter",
# "left-behind"): the back diagonal on that side, in either order, with or without "three
# quarter(s)"; a lone "behind" stays the back view.
for _lat in ("left", "right"):
    VIEW_SIDE_WORDS[f"back-{_lat}"] += _diagonal_words(("behind",), _lat, False) + [f"behind {_lat}"]
# "Left behind" too, but "right behind" is "directly behind".
VIEW_SIDE_WORDS["back-left"].append("left behind")
# A ship's broadside (and "broad side on"): its side turned full to the camera, which side said
# apart ("broadside from its left") or not at all.
VIEW_SIDE_WORDS["side"] += ["broadside", "broadside on", "broad side on"]
# What may follow a diagonal said as a noun phrase (:func:`_templates`): its own 45 degrees, a view
# noun, the clause's end, or a word leading on to the subject or another clause; never a noun it
# describes.
DIAGONAL_END = (
    "( 45( degrees)?)?( (view|angle|shot|perspective|position|vantage|one))?( (on|of|for) {obj})?"
    "(?= ([,.;:!?)]|$|and |with |at |from |on |of @\\d|for |to @\\d|please |low|high|eye|medium|close|wide|tight))"
)
# "X on" words that name no end ("head on", "dead on"): they say only exactly (EXACT_ONLY).
GENERIC_ON_WORDS = tuple(w for w in HEAD_ON_WORDS if w not in VIEW_SIDE_WORDS["front"])
# A side word in a noun phrase ("the back of the chair", "its left side") is a view side, except
# after a preposition of place ("the vase on its left", "to the left of the bear": a relation
# between objects, not understood) or before words that turn it away from the camera ("with its
# back to the wall"). Closing in on a side is no relation ("close on its face", "zoom in on its
# back").
NOT_A_RELATION = (
    "(?:(?<=close on )|(?<=tight on )|(?<=in on )|(?<=focus on )|(?<=focused on )|(?<=looking at )|(?<=look at )"
    "|(?<=aimed at )|(?<=pointing at )|(?<=pointed at )"
    "|(?<!on )(?<!to )(?<!at )(?<!in )(?<!into )(?<!onto )(?<!towards )(?<!near )(?<!by )(?<!beside )"
    "(?<!over )(?<!past )(?<!beyond )(?<!across )(?<!under )(?<!below )(?<!beneath ))"
)
NOT_TURNED_AWAY = "(?! (to|towards|against|facing|turned|pressed|up against) )"
# A front part said to the lens is the front exactly ("nose-to-lens", "face to camera").
FRONT_TO_LENS = ("nose", "face", "head", "snout", "muzzle", "grille")
# The camera looked or pointed at, its article dropped as captions and second-language writers drop
# it ("looking to camera", "nose pointed at lens").
AT_CAMERA = "(the (camera|lens|viewer)|camera|lens|us|me)"
# {PART}: a part on that side ("from its right arm end", "its left flank", "the left-hand side
# panel": vocabulary.SIDE_PARTS) names that side.
VIEW_FRAMES = [
    # The article may be dropped ("from left side", "from front"), as people writing in a second
    # language do.
    SEEN + ALMOST + "({EXACT} )?from ({EXACT} )?(a?round )?((the|{P}) )?(far |extreme )?{SIDE}{PART}( of {obj})?(?! of )",
    # Square on to a side named ("head on to its back", "straight on to the left side").
    "(?P<exact>" + "|".join(GENERIC_ON_WORDS) + "|spot) on (to|towards|at|facing|onto) (the|{P}) {SIDE}{PART}( of {obj})?",
    "showing (the|{P}) {SIDE}{PART}( of {obj})?",
    # The camera put beside a side's part, said first ("Beside the right armrest of the armchair",
    # "camera next to its left flank"); after a subject it may relate two things, so not there.
    "(" + CAMERA + " |(?<=^ ))(beside|next to|alongside|right by|right next to) (the|{P}) {SIDE}( {SIDED})?{PART}"
    "( of {obj})?(?! of )",
    # The camera square to a side, maybe a part's ("perpendicular to its flank", "shot square to
    # the left side", "perpendicular to the shelves' face"), maybe to a part said on that side
    # ("perfectly perpendicular to the doors on its left-hand side"): that side, exactly.
    "((perfectly|precisely|{STRONG}) )?(?P<exact>perpendicular|perpendicularly|square|squarely|at right angles|normal"
    "|at (a |an )?((perfect|exact|true|precise) )?right angle)"
    " (on )?(to|with|onto|on to|facing) ((the|{P}) ([a-z]+ ){1,2}(on|at|along) )?"
    "(the|{P}) ([a-z]+ 's )?{SIDE}{PART}( of {obj})?(?! of )",
    CAMERA + " ({EXACT} |(far|well|way|out) )?(at|on|to|by|off to) (the|{P}) {SIDE}{PART}( of {obj})?",
    # The camera moved round to a side ("the camera swung round to its right").
    CAMERA + " {MOVE} (a?round |over )?(to|towards) (the|{P}) {SIDE}{PART}( of {obj})?",
    # Off a side of it ("camera off its left-hand flank", "front three-quarter off its right side").
    "(" + CAMERA + " )?({EXACT} )?off ({P} {SIDE}{PART}|the {SIDE}{PART} of {obj})",
    # The article may be dropped at a clause's start ("teddy, left side facing us").
    "(with )?((the|{P}) |{CLAUSE}){SIDE}{PART} ({EXACT} )?(towards|to|facing|turned towards|turned to)"
    " (the (camera|viewer|lens)|us|me)",
    # Any part named by its side and turned to the camera names that side ("the right armrest end
    # pointed dead at the lens", "its right-hand doors square to camera", "left armrest of the
    # bench pointing at me"); a front part said to the camera is FRONT_TO_LENS's ("his face to
    # camera": straight on).
    "(with )?(((the|{P}) |{CLAUSE})(?!(" + "|".join(FRONT_TO_LENS) + ") ){SIDE}( {SIDED})?|(?<=^ ){SIDE} {SIDED}){PART}"
    "( of {obj})?( (is|are))?( (pointing|pointed|aimed|aiming|turned|squared|set))? ({EXACT} ({STRONG} )?)?"
    "(towards|to|at|into|facing|turned towards|turned to|(the one )?(nearest|closest)( to)?) " + AT_CAMERA,
    # An end said with it ("left end view", "the right-hand end shot").
    "(in |from |as )?(a |the )?({EXACT} |(?P<exact>full|pure|true|strict) )?{SIDE}( hand)?( side| end)?"
    " (view|profile|angle|shot)",
    # An architect's elevation: the side drawn square on, so an end is exact ("front elevation",
    # "the rear elevation of the sofa", "a left side elevation"); never a height, and not before a
    # number ("from the front, elevation 20 degrees" says a height).
    "(in |from |as )?(a |an |the )?(?P<exact>{SIDE})( side)? elevation( (view|drawing))?( of {obj})?{NOT_A_NUMBER}",
    "(an |the )?elevation( (view|drawing))? (from|of) (the|{P}) (?P<exact>{SIDE})( side)?( of {obj})?{NOT_A_NUMBER}",
    NOT_A_RELATION + "(the|a) {SIDE}{PART} of {obj}",
    # Opening the sentence or a clause the article may be dropped ("back of the fridge, eye level").
    "((?<=^ )|{CLAUSE}){SIDE}{PART} of {obj}",
    NOT_A_RELATION + "{P} {SIDE}{PART}" + NOT_TURNED_AWAY,
]
# A side named alone as a clause ("bench, three-quarter, back right"), between the sentence's
# or a comma's start and the clause's end; a lone left or right there stays a region.
VIEW_CLAUSE = "((?<=^ )|{CLAUSE})(the )?({EXACT} ({STRONG} )?)?{SIDE}( side| view| angle| corner)?(?= ([,.;!]|$))"
# A left or right profile or flank as a clause ("the bear's profile, left side" is its left; a
# bare "left side" there stays a region).
PROFILE_CLAUSE = "((?<=^ )|{CLAUSE})(the |{P} )?{LAT}( hand)? (profile|flank|end|lateral)(?= ([,.;!]|$))"
# A side other than a lone left or right named right after its subject, ending the clause ("tedy
# bear three quarter rear right", "chair front, medium"); not "behind", which says where the
# a later subject stands ("the ball in front, the bench behind"; the first one's "bench behind" is
# its back).
VIEW_AFTER_SUBJECT = "(?<=@\\d )(the )?((?<=@0 )|(?!behind )){SIDE}( view| angle| corner)?(?= ([,.;!]|$))"
# A lone side said right after a side view ("from the side, left", "from its side, the left one",
# "side view (the right one)"): which side.
SIDE_AFTER_SIDE_VIEW = (
    "(?:(?<=side [,:;(] )|(?<=profile [,:;(] )|(?<=lateral [,:;(] )|(?<=side view [,:;(] )|(?<=profile view [,:;(] )"
    "|(?<=lateral view [,:;(] )|(?<=side on [,:;(] )|(?<=side elevation [,:;(] )|(?<=side aspect [,:;(] ))"
    "(the )?{LAT}( hand)?( side| one)?(?= ([,.;!)]|$))"
)
# The view's noun before its side, as a caption or a shot list writes it ("PROFILE RIGHT", "view
# front-left", "side view from the left", "lateral view: right", "angle (rear right)"), as a clause
# of its own or right after its subject.
NOUN_BEFORE_SIDE = (
    "((?<=^ )|{CLAUSE}|(?<=@\\d ))(the |a |{P} )?((side|lateral) )?(profile|view|lateral|angle)( view| shot)?( [,:;(])?"
    " (from |on |to |towards )?(the |{P} )?{SIDE}( side)?(?= ([,.;:!)]|$))"
)
# A left or right side said as the clause right after its subject ("armchair: right side, half the
# frame"): with "side" it is the subject's (the frame's would say "on the right side").
# A side joined to a height ("from above and to the left"): the camera's, not the frame's.
SIDE_AFTER_HEIGHT = (
    "(?:(?<=above )|(?<=below )|(?<=overhead )|(?<=high )|(?<=low )|(?<=up )|(?<=down ))"
    "and (off )?(to|on|from) (the|{P}) {LAT}( hand)?( side)?"
    "(?! (of|in) )"
)
# A side of the subject said right after a view's noun ("a rear three-quarter angle on its right
# side"): it completes that view (:data:`VIEW_COMBINATIONS`).
SIDE_AFTER_VIEW = (
    # Also off to it ("frontal 3/4 off to his left"), after the diagonal's end said last ("three
    # quarter front on its left side"), a broadside or an over-the-shoulder ("broadside on its
    # right"), and "the left of it" ("front three-quarter on the left of it": of the subject).
    "(?:(?<=view )|(?<=angle )|(?<=shot )|(?<=quarter )|(?<=quarters )|(?<=quarter , )|(?<=quarters , )"
    "|(?<=quarter front )|(?<=quarter rear )|(?<=quarter back )|(?<=quarters front )|(?<=quarters rear )"
    "|(?<=broadside )|(?<=broadside , )|(?<=shoulder )|(?<=shoulder , ))((off|over) )?"
    "(on|to|towards|from|at) "
    "({P} {LAT}( hand)?( side)?|the {LAT}( hand)? side of {obj}|the {LAT}( hand)?( side)? of (it|him|her))"
)
# A side said as the clause after the subject's, or as a sentence of its own ("BENCH. Right side.").
SIDE_AFTER_SUBJECT = "(?<=@\\d [,:;.] )(the )?{LAT}( hand)? (side|end|flank)(?= ([,.;!]|$))"
# A side of the subject said as the clause after a view clause ("3/4 rear, right-hand side", "from
# behind, the left flank"): it completes that view (:data:`VIEW_COMBINATIONS`); with "side", "end"
# or "flank" it is the subject's side, not a place in the frame.
SIDE_AFTER_VIEW_CLAUSE = (
    "(?:(?<=view , )|(?<=angle , )|(?<=behind , )|(?<=rear , )|(?<=back , )|(?<=front , )|(?<=on , )|(?<=quarter , )"
    "|(?<=quarters , )|(?<=diagonal , )|(?<=to the camera , )|(?<=to camera , )|(?<=to the lens , )|(?<=to us , ))"
    # Also with "on"/"from" before its own side ("broadside to the camera, on its left side").
    "(the |{P} |(on|from) {P} )?{LAT}( hand)? (side|end|flank)(?= ([,.;!]|$))"
)
# Exactness said of a view without naming its side ("dead on", "head-on", "from behind, exactly",
# "from its left side, straight on to the arm"): a cue of its own, EXACT_ONLY, that makes the end
# it goes with exact (:data:`VIEW_COMBINATIONS`); said alone it is the front exactly ("the car
# head-on").
EXACT_ONLY = "exact"
EXACT_PHRASES = [
    "(a |in )?(" + "|".join(GENERIC_ON_WORDS) + "|spot) on( (view|shot|angle))?",
    # As a clause of its own ("from the behind, exactly", "its screen, dead square").
    "{CLAUSE}((exactly|precisely|squarely|perfectly)( so| square| on)?|{STRONG} (square|on))(?= ([,.;!]|$))",
    # Square to the part of the side already named ("straight on to the arm", "dead on to its end").
    "(" + "|".join(GENERIC_ON_WORDS) + "|spot) on (to|towards|at|facing|onto) (the|{P}) {SIDEPART}( of {obj})?",
]
# A side "on" ("right side on", "left-end on"): that side facing the camera.
SIDE_ON = SEEN + "({STRONG} )?(the |{P} )?{LAT}( hand)? (side|end|flank) on"
VIEW_PHRASES = {
    "front": [
        "facing (the |towards the )?(camera|viewer|lens|us|me|forward|forwards)",
        "facing front",
        # Face to face with it ("the teddy face to face", "nose to nose with the car"): straight on.
        "(?P<exact>face to face|nose to nose|head to head)( with {obj})?",
        "(front|forward|forwards) facing",
        "({EXACT} |(?P<exact>full) )?frontal( view| shot| angle)?",
        # The view word as an adverb ("shown frontally", "photographed head-on frontally").
        "({SEEN_VERB} |shown |presented |displayed )?({EXACT} )?frontally",
        "(looking|staring|gazing|peering) ({EXACT} )?(at|into|towards|to) " + AT_CAMERA,
        # The subject moving or pointing at the camera ("the car driving towards us").
        # Its front pointed at the camera ("with its nose pointing at the camera").
        # "Right at us" is straight at: no side ("nose pointed right at us").
        "(with )?((the|{P}) )?(nose|front|face|head|headlights|grille) (pointing|pointed|facing|turned|aimed) "
        "((straight|right|directly|dead) )?(at|to|towards|into) " + AT_CAMERA,
        "(pointing|pointed|driving|heading|coming|moving|rolling|walking|turned) (straight )?(towards|at|to) " + AT_CAMERA,
        CAMERA + " in front of {obj}",
        SEEN + "({EXACT} )?from (a?round )?(the|{P}) nose( of {obj})?",
        SEEN + "from ({EXACT} |(?P<exact>right) )?in front( of {obj})?",
        # Ahead of it ("from ahead", "from straight ahead of the car": exactly).
        SEEN + ALMOST + "from ({EXACT} |(?P<exact>right) )?ahead( of {obj})?",
        # Opening the sentence, a place names the camera's ("directly in front of the bear, ...");
        # later it may relate two objects ("the cone with the bench in front of it").
        "(?<=^ )({EXACT} |(?P<exact>right) )?in front of {obj}",
    ],
    "back": [
        # Behind it as a clause of its own right after its subject ("armchair, behind it, low"):
        # the camera's place; a named object after "behind" stays a relation ("the mug, behind the vase").
        "(?<=@\\d , )({EXACT} |(?P<exact>right) )?behind (it|him|her|them)(?= ([,.;!]|$))",
        SEEN + ALMOST + "({EXACT} )?from ({EXACT} |(?P<exact>right) )?behind( {obj})?",
        "(rear|back|backward|backwards) facing",
        "(facing|turned|looking|driving|heading|moving|walking|rolling|going|pointing|pointed) away"
        "( from (the (camera|viewer|lens)|us|me))?",
        # Its back to the camera, said without "with" ("the teddy, back turned to the camera").
        "((the|{P}) )?(back|rear|backside|tail end) (turned )?(to|towards|facing) (the (camera|viewer|lens)|us|me)",
        CAMERA + " behind {obj}",
        SEEN + "({EXACT} )?from (a?round )?(the|{P}) tail( of {obj})?",
        # Where one starts counts as where one stands ("begin behind the bench and go 40 degrees
        # toward its left end": the turn is off the back).
        "(stand|standing|go|going|get|getting|move|moving|walk|walking|come|coming|head|step|swing|circle"
        "|begin|beginning|start|starting)( off| out)? (a?round |over )?behind( {obj})?",
        # Gone round behind it, said first ("round behind the armchair you go").
        "(?<=^ )a?round behind {obj}",
        "with {P} back (turned )?(to|towards) the (camera|viewer|lens|us)",
        # Gone round to its back ("round the back", "swing around to the rear of it").
        "(({MOVE}|{GET}) )?a?round (to )?(the|{P}) (back|rear|backside|back side|rear side|tail end)( of {obj})?"
        "(?= ([,.;!]|$|and |with |from |at ))",
        "{P} back to the (camera|viewer|lens|us)",
        "(?<=^ )({EXACT} |(?P<exact>right) )?behind {obj}",
    ],
    # An end said "X on" is that end exactly ("nose on"; "tail on"); "head on", "dead on" say only
    # exactly (:data:`EXACT_ONLY`).
    "front-exact": [
        "(in |from |as )?(a |an |the )?(frontal|facade) elevation( (view|drawing))?( of {obj})?{NOT_A_NUMBER}",
        # Square to the subject ("perfectly square to it", "dead square to the sofa").
        "(({STRONG}) )?(square|squarely) (on )?(to|towards|with|facing|onto|on to) {obj}",
        # Looking right (straight) at the camera; "right" there is no side ("gazing right into the lens").
        "(looking|look|looks|staring|stares|stare|gazing|gazes|gaze|peering|peers|glaring|eyeing)"
        " (right|straight|directly|dead|squarely) (at|into|towards) (the (camera|lens|viewer)|us|me)",
        # Looking (pointing) down the lens: straight at the camera ("looking right down the lens",
        # "staring straight down the barrel").
        "(looking|look|looks|staring|stares|stare|gazing|gazes|gaze|peering|peers|pointing|points|pointed|aimed|facing|faces)"
        " ((right|straight|directly|dead|square|squarely) )?down (the|its|his|her) (lens|camera|barrel)( of the (lens|camera))?",
        "(a |in )?(" + "|".join(w for w in HEAD_ON_WORDS if w not in GENERIC_ON_WORDS) + ") on( (view|shot|angle))?",
        # Its front squared to the camera ("square to the lens", "face it square", "shooting
        # straight at it").
        "({STRONG} )(to|towards|at|into|on to|facing) (the )?(camera|lens|viewer)",
        "(face|faces|facing|faced) ({obj} )?({STRONG}|{STRONG} on)(?= ([,.;!]|$|and |with |from ))",
        "(looking|look|{AIM}) ({STRONG}) (at|into) {obj}",
        # Facing the camera, insisted on after it ("facing the camera dead straight", "squarely").
        "(facing|faces|face|faced|turned|pointing|pointed) (towards |to |at |into )?(the (camera|lens|viewer)|us|me)"
        "( {STRONG})?( {STRONG})( on)?(?= ([,.;!]|$|and |with |at |from ))",
        # Straight in front of it ("a dead-ahead shot", "dead ahead of the car").
        "(from |in |as )?(a )?dead ahead( (view|shot|angle))?( of {obj})?",
        # Its front to the lens ("nose-to-lens", "face to camera", "nose-first toward the lens",
        # "face-forward to the camera", "its nose toward us", "snout right in the lens").
        # Also pointed there ("pointing its nose at the lens", "aiming his face at camera").
        "((pointing|pointed|aiming|aimed|turning|turned) (its |his |her |the )?)?"
        "((" + "|".join(FRONT_TO_LENS) + ")( first| forward| forwards| foremost| on)?"
        "|front (first|forward|forwards|foremost|on)) ((right|straight|directly) )?(to|towards|at|facing|into|in) "
        "((the )?(lens|camera|viewer)|us|me)",
    ],
    "back-exact": [
        "(a |in )?(" + "|".join(TAIL_ON_WORDS) + ") on( (view|shot|angle))?",
        # Its back end first to the lens ("tail-first toward the camera").
        "(tail|rear|back|stern|butt|tail end|rear end) (first|foremost) (to|towards|at|facing|into) (the )?(lens|camera|viewer)",
        # A bare "straight behind" as a clause of its own ("bench backrest side, straight behind").
        "{CLAUSE}({EXACT} |(?P<exact>right) )behind(?= ([,.;!]|$))",
    ],
    # Facing, looking or going one way in the frame, or its front said so ("turned to face left",
    # "gazing off to frame left", "driving towards the right of the frame", "its nose pointing
    # left"): its front points that way, so that side of it is seen (FACING_WAY).
    # The side named after it ("from the side of left", as other languages order it).
    "left": [FACING_WAY.replace("{LAT}", "left"), "(from )?(the )?side of (the )?left"],
    "right": [FACING_WAY.replace("{LAT}", "right"), "(from )?(the )?side of (the )?right"],
    "side": [
        "in profile",
        # Square to its flank (VIEW_FRAMES' square frame; "straight on to its flank" says only exactly).
        "(perpendicular|perpendicularly|square|squarely|at right angles|normal) (to|with|onto|facing) "
        "(the|{P}) ([a-z]+ 's )?flank( of {obj})?",
        # A profile said before the side it is seen from ("profile from its right-hand side").
        "(a |the )?(side )?profile( (view|shot))?(?= (from|on|of) (the|{P}) (left|right) )",
        "(seen )?({STRONG} )?(side|end) on",
        "from (either|one|a) side",
        "(a |the )?(side )?profile( view| shot)? of {obj}",
        # The view word as an adverb ("shown laterally", "photographed in profile, laterally").
        "({SEEN_VERB} |shown |presented |displayed )?laterally(?! (from|on) )",
    ],
    "three-quarter": [
        "(in |at |from |as )?(a |an )?(front )?three quarters?( front)?( (view|angle|profile|shot|position))?",
        "(the |a |{P} )?(front|nose|bow) quarter( (view|angle|shot))?(?! (of|in) (the )?{FRAME})",
        "(seen )?at three quarters",
        # A view across the subject's diagonal said without "three-quarter" ("diagonally from the
        # front left", "an oblique view"): it combines with a side as three-quarter does.
        "(seen |shot |viewed )?(diagonally|obliquely|on the diagonal|on a diagonal)",
        "(from |in |at |as )?(a |an )?(oblique|diagonal|angled) (view|angle|shot|perspective)",
        "(in |at )?(a |an )?(front )?three quarter( front)? (view|angle)",
    ],
    "back-three-quarter": [
        "(an )?over (the|{P}) shoulder( (view|angle|shot))?( of {obj})?",
        # A quarter of its back end ("tail-end quarter", "its rear quarter"); not the frame's.
        "(the |a |{P} )?(back|rear|tail|tail end|stern|aft|hind) quarter( (view|angle|shot))?(?! (of|in) (the )?{FRAME})",
        "(in |at |from |as )?(a |an )?(back|rear) three quarters?( (view|angle|profile|shot|position))?",
        "(in |at |from |as )?(a |an )?three quarters? (back|rear)( (view|angle|profile|shot|position))?",
    ],
}
# A part found only at one end names that end ("bench backrest side", "its tail lights":
# vocabulary.END_PARTS), unless turned away ("with its backrest to the wall").
for _end, _parts in END_PARTS.items():
    VIEW_PHRASES[_end] += [
        NOT_A_RELATION + "((the|{P}) |(?<=@\\d ))(" + "|".join(_parts) + ")( side| end)?( of {obj})?" + NOT_TURNED_AWAY,
        "(looking|look|aim|aimed|aiming|pointing|pointed|point) ({STRONG} )?(straight )?at (the|{P}) ("
        + "|".join(_parts)
        + ")( of {obj})?",
    ]
# Parts of one end said together (parse19p6: "headlights and grille fill the frame", "the screen
# and the display", a clause opening on them) name that end as one part does; the face alone as
# all that is wanted ("only the face", "just the face, close") is the front.
for _end, _parts in END_PARTS.items():
    _one = "(" + "|".join(sorted(_parts, key=len, reverse=True)) + ")"
    VIEW_PHRASES[_end].append(
        NOT_A_RELATION + "((the|{P}) |(?<=@\\d )|{CLAUSE})" + _one + "(( ,)? (and|&|,) (the |{P} )?" + _one + ")+"
        "( of {obj})?" + NOT_TURNED_AWAY
    )
VIEW_PHRASES["front"].append("(only|just|simply|nothing but) (the|{P}) face( of {obj})?(?! (of|to|towards|at) )")
# A part turned to the camera: the end it sits at is seen (vocabulary.FACING_PARTS and END_PARTS:
# "its back bumper square to the lens", "backrest to us", "slats to camera dead straight", "the
# seat facing me straight on"); squared to it, or "dead on" after it, that end exactly. The camera
# squared to a part sees its end exactly ("photographed square to its shelves").
OWN_PARTS = frozenset(p for end in FACING_PARTS for p in (*FACING_PARTS[end], *END_PARTS[end]))
# The camera's sensor (film, image plane) is where it looks from ("its screen parallel to the sensor").
VIEWER = (
    "(us|me|you|the viewer|viewer|the camera|camera|the lens|lens|the cam|cam"
    "|((the|its) )?(camera 's )?(sensor|film|film plane|image plane|focal plane))"
)
SQUARE = "(square|squarely|straight|directly|dead|flush|bang|smack|full|perpendicular|parallel)"
SQUARE_AFTER = (
    "( ,)? (?P<exact>(dead|straight|square|head|face|full|spot|bang|smack) on|dead straight|dead square|squarely"
    "|square on|exactly|precisely|perfectly)"
)
TURNED_TO = (
    "(((turned|pointing|pointed|aimed|angled|squared|set) )?(to|towards|at|into|onto|on to)"
    "|(facing|faces|face)( (to|towards|at))?"
    # Looking out (back) at the camera ("the book spines looking out at us", "its seat staring
    # right back at the lens"), or the part of it nearest the camera ("its backrest nearest us").
    "|(looking|looks|facing|faces|pointing|points|staring|stares|peering|peers)( (right|straight))? (out|back) (at|to|towards)"
    "|(the one )?(nearest|closest)( to)?)"
)
for _end, _parts in FACING_PARTS.items():
    _part = "(" + "|".join(sorted({*_parts, *END_PARTS[_end]} - {*FRONT_TO_LENS, "front"}, key=len, reverse=True)) + ")"
    VIEW_PHRASES[_end] += [
        "((with|pointing|points|pointed|turning|turns|turned|aiming|aims|aimed|having|showing|keeping) )?"
        # Or the side it is on ("the side with the door handle toward us", "the end with the tail lights to camera").
        "((the|{P}) (side|end|face) with (the|{P}) |(the|{P}) |(?<=@\\d )|{CLAUSE}|(?<=^ ))"
        + _part
        + "( of {obj})?( (is|are))?( (?P<exact>"
        + SQUARE[1:]
        + "( on)?)? "
        + TURNED_TO
        + " "
        + VIEWER
        + "("
        + SQUARE_AFTER
        + ")?(?! (side|height|level|edge|corner|bag|case|strap) )",
        "(?P<exact>((dead|perfectly|exactly) )?"
        + SQUARE[1:]
        + "( on)? (to|towards|with|onto|on to|facing|at) (the|{P}) "
        + _part
        + "( of {obj})?",
        # The side (end) named by its parts ("from its doors-and-handles side", "the headlights end").
        "((from|on|at) )?(the|{P}) " + _part + "(( and| &) [a-z]+)? (side|end|face)(?! of )",
    ]
# The side one sits on (or in) is the front ("from the side people sit on", "the side you'd sit in").
VIEW_PHRASES["front"].append(
    "(the|{P}) (side|end) (where )?(people|you|one|we|someone|somebody|they|folk|folks|visitors|guests)"
    "( (would|d|can|will))? (sit|sits)( (on|in|at))?(?= ([,.;:!?]|$|and |with ))"
)
# Between an end and a side: the diagonal ("halfway between its front and its left side"); between
# an end and "the side" either diagonal of that end.
BETWEEN = "(((half|half way|halfway|midway|somewhere) )?between) (the |{P} )?{A}( side| end)? and (the |{P} )?{B}( side| end)?"
for _lon, _lon_words in (("front", "(front|face)"), ("back", "(back|rear)")):
    for _lat in ("left", "right"):
        VIEW_PHRASES.setdefault(f"{_lon}-{_lat}", []).extend(
            BETWEEN.replace("{A}", a).replace("{B}", b) for a, b in ((_lon_words, _lat), (_lat, _lon_words))
        )
    VIEW_PHRASES["three-quarter" if _lon == "front" else "back-three-quarter"].extend(
        BETWEEN.replace("{A}", a).replace("{B}", b) for a, b in ((_lon_words, "side"), ("side", _lon_words))
    )
# The view someone standing there would get ("the view a walker behind it would get", "what a
# visitor in front of it sees", "the angle someone to its left would have"): that side; the one who
# stands there may be any noun.
SOMEONE_THERE = (
    "(the (view|angle|shot|picture|sight)|what) (that )?((a|an|the|some|any) )?([a-z]+ )?"
    "((standing|sitting|walking|stood|sat|passing|waiting|strolling) )?{PLACE}"
    "( (would|might|could|will|does|did|can))?( (get|gets|have|has|see|sees|had|saw|got|catch|catches))"
)
for _view, _place in (
    ("back", "((right|directly|just|straight) )?behind {obj}"),
    ("front", "((right|directly|just|straight) )?in front of {obj}"),
    ("left", "(to|on|at) {P} left( hand)?( side)?"),
    ("right", "(to|on|at) {P} right( hand)?( side)?"),
):
    VIEW_PHRASES[_view].append(SOMEONE_THERE.replace("{PLACE}", _place))
# Looking over its back or a part at its back ("from over its backrest", "peering over the back of
# the sofa"): from behind; with a side said after it, that back diagonal ("from over its backrest on
# the left": LONGITUDINAL). Only with a verb of looking or "from" ("a throw over the back of the
# sofa" says where the throw is).
OVER_BACK = (
    "(from|looking|peering|peeking|gazing|seen|shot) over (the|{P}) "
    + "("
    + "|".join(sorted(("back", "rear", "backside", *END_PARTS["back"]), key=len, reverse=True))
    + ")"
    + "( of {obj})?"
)
VIEW_PHRASES["back"].append(OVER_BACK)
# Over one shoulder of the subject: behind it, on that side ("over its left shoulder").
for _lat in ("left", "right"):
    VIEW_PHRASES.setdefault(f"back-{_lat}", []).append(SEEN + f"(from |looking )?over (the|{{P}}) {_lat} shoulder( of {{obj}})?")
    # An over-the-shoulder shot with its side said after or before it ("OTS right", "left over the
    # shoulder"), as shot lists write it.
    VIEW_PHRASES[f"back-{_lat}"] += [
        f"(an )?over (the|{{P}}) shoulder( (view|angle|shot))?( ,)? (on the |to the |from the )?{_lat}( hand)?( side)?",
        f"(a |an |the )?{_lat}( hand)? over (the|{{P}}) shoulder( (view|angle|shot))?",
    ]

# A camera beside the subject ("to its left", "on the left of it"). "On the left" is also a region
# of the frame: LATERAL is never followed by the frame's words ("on the right of the frame"), and
# where a region reading is likely (after a comma, first in the phrase) only LATERAL_OWN, which
# names the subject, is a side.
LATERAL = (
    "((off|over) )?(to|on|towards|at) (the|{P}) {LAT}( hand)?( side)?( of {obj})?"
    "(?! (of|in|third|half|edge|corner|part|quarter) )"
)
LATERAL_OWN = "((off|over) )?(to|on|towards|at) ({P} {LAT}( hand)?( side)?|the {LAT}( hand)?( side)? of {obj})"
# Where the camera is along the subject's front-back axis, in phrases that combine with a side.
LONGITUDINAL = {
    "front": SEEN + ALMOST + "(from (the|{P}) front|(" + CAMERA + " )?(from )?({STRONG} |right )?in front( of {obj})?)",
    "back": SEEN
    + ALMOST
    + "(from (the|{P}) (back|rear)|("
    + CAMERA
    + " )?(from )?({STRONG} |right )?behind( {obj})?|"
    + OVER_BACK
    + ")",
}
# "behind and to the left", "from behind on the left", "to its left, from behind": the diagonal;
# with a slight degree word ("in front and slightly to the right") the slight side of that end.
COMBINED_VIEW_FRAMES = [
    ("", "{LON} (and )?{LATERAL}"),
    # The side said bare after the end ("camera behind and left", "behind and slightly right").
    ("", "{LON}( ,)? and {LAT}( hand)?( side)?(?= ([,.;!]|$))"),
    ("slight", "{LON}( ,)? (and |but )?{WEAK} (to )?{LAT}( hand)?( side)?(?= ([,.;!]|$))"),
    ("", "{LON}( ,)? (and |but )?{LATERAL_OWN}"),
    ("", "{LATERAL_OWN}( ,)? (and )?{LON}"),
    ("slight", "{LON}( ,)? (and |but )?{WEAK} (more )?{LATERAL}"),
    ("slight", "{WEAK} {LATERAL_OWN}( ,)? (and )?{LON}"),
]
# A slight side alone is off the front: "slightly from the left", "a bit to its left".
# Said of the camera's offset ("offset slightly right") or as a clause right after a view ("rear
# view, slightly left"), it combines with that view's end (:data:`VIEW_COMBINATIONS`).
# The ends of view clauses, and of clauses facing the camera or away from it ("facing away from
# us, slightly to the left").
AFTER_VIEW = (
    "(?:(?<=view , )|(?<=angle , )|(?<=behind , )|(?<=rear , )|(?<=back , )|(?<=front , )|(?<=on , )"
    "|(?<=us , )|(?<=me , )|(?<=camera , )|(?<=lens , )|(?<=viewer , )|(?<=away , ))"
)
SLIGHT_VIEW_FRAMES = [
    "(offset|off set|shifted|moved|off|angled|angling|swung|edging|edged|drifting|veering) {WEAK} (to (the|{P}) )?{LAT}"
    "( hand)?( side)?(?= ([,.;!]|$))",
    AFTER_VIEW + "{WEAK} (to (the|{P}) )?{LAT}( hand)?( side)?(?= ([,.;!]|$))",
    SEEN + "{WEAK} from (the|{P}) {LAT}( hand)?( side)?( of {obj})?",
    SEEN + "from {WEAK} ((to|towards|on) )?(the |{P} )?{LAT}( hand)?( side)?( of {obj})?",
    # Said off the front it starts from ("from slightly to the right of the front").
    SEEN + "(from )?{WEAK} ((to|towards|on) )?(the |{P} )?{LAT}( hand)?( side)? of ((the|{P}) front( of {obj})?|{FRONT_ON})",
    "{WEAK} " + LATERAL_OWN,
    "(seen|viewed|shot|photographed|captured|taken|filmed) {WEAK} " + LATERAL,
    CAMERA + " {WEAK} " + LATERAL,
    "facing {WEAK} (to the |towards the )?{LAT}( in (the )?{FRAME})?",
    # The camera off to a side, the degree after ("camera off to the left a bit").
    CAMERA + " (offset |off |shifted |moved )?(to (the|{P}) ){LAT}( hand)?( side)? {WEAK}(?= ([,.;!]|$))",
    # Moved a little round towards a side ("back of the teddy, drifting a little round to its left").
    "{MOVE} {WEAK} (a?round |over |across )?(to|towards) (the|{P}) {LAT}( hand)?{PART}",
    "{WEAK} (a?round|over|across) (to|towards) (the|{P}) {LAT}( hand)?{PART}",
    "({MOVE} )?(a?round|over|across) (to|towards) (the|{P}) {LAT}( hand)?( side)? {WEAK}(?= ([,.;!]|$|and |with |from |at ))",
]
# A slight side said off the back ("a touch left of dead behind"): the slight side of the back.
BACK_SLIGHT_VIEW = (
    SEEN + "(from )?{WEAK} ((to|towards|on) )?(the |{P} )?{LAT}( hand)?( side)? of "
    "((the|{P}) (back|rear)( of {obj})?|(dead|straight|directly|right) behind)"
)
# Off a side towards an end, short of the diagonal ("from its right side, a little towards the
# front": ``right-slight-front``).
SIDE_SLIGHT_VIEW_FRAMES = [
    # The articles may go unsaid, as non-native writers drop them ("from right, little bit to front").
    SEEN + "from ((the|{P}) )?{LAT}( hand)?( side| end)?( of {obj})?( ,)? (and |but )?{WEAK} (towards|to|toward) "
    "((the|{P}) )?{LON}( side| end)?",
    SEEN + "{WEAK} (towards|to|toward) (the|{P}) {LON}( side| end)? (from|of) (the|{P}) {LAT}( hand)?( side| end)?( of {obj})?",
]
# An explicit azimuth from the front towards a side ("45 degrees round to its right", "turned 30
# degrees to the left"): the side whose azimuth is nearest (:func:`_nearest_side`).
# The turn may be a fraction of one ("a quarter turn": vocabulary.words writes 90 degrees) and
# may name the front it starts from; a side said first and the angle after it count from the front
# towards that side ("from its right side, about 45 degrees off").
FROM_FRONT = "( ,)?( (starting |counting )?from (the|{P}) front( of {obj})?)?"
# The front an angle is turned away from, said between the angle and its side ("turned 30 degrees
# away from straight-on toward its left").
AWAY_FROM_FRONT = "( away)?( from ((the|{P}) front|(a |the )?(straight|head|dead|square|face|front) on|(the )?center))?( ,)?"
AZIMUTH_PHRASES = [
    SEEN + "(from )?{d}( turn| swing| rotation)? (a?round|over|off|across|towards|to)( to)? (the|{P}) {LAT}( hand)?( side)?"
    "( of {obj})?" + FROM_FRONT,
    "(turned|rotated|swung|orbited|moved|circled|walked|go|going) (a?round )?{d}"
    + AWAY_FROM_FRONT
    + " (to|towards) (the|{P}) {LAT}( hand)?( side)?"
    + FROM_FRONT,
    "{d} (to the )?{LAT} of (the )?(front|center|straight on|head on)",
    SEEN + "(from |at )?(a |an )?{d} angle (on|to|from|off|towards) (the|{P}) {LAT}( hand)?( side)?( of {obj})?",
    SEEN + "from (the|{P}) {LAT}( hand)?( side)?( of {obj})?( ,)? ({ABOUT} )?{d} (off|round|around|in|over)",
]

# An offset from a named view, as a family: a reference view, an amount and a direction, in any
# order ("from behind him, little bit more to right", "looking at the camera but swung a few
# degrees to its left", "45 deg off its nose towards its left", "from its left flank, a few degrees
# toward the front", "20 degrees towards the back from its right side"). The amount is a slight
# degree word or a small turn without a number ({HEDGE}: vocabulary.OFFSET_HEDGES; 10 to 40
# degrees off the reference, the "slight" sides) or an explicit angle (the side nearest it). A
# sideways offset said without its reference is a cue of its own that the reference said elsewhere
# completes (:func:`_combined_view`; none is the front); one towards an end names its side.
# {MOVED}: how the camera gets there ("swung", "nudged", "angled", "round", "over"), optional.
# A cheat is film language for a small move of the camera ("cheat it a little toward the front").
TURN_VERBS = (
    "({MOVE}|turn|rotate|angle|angled|angling|lean|leaning|leaned|leant|offset|pan|panned|panning|pivot|pivoted|pivoting"
    "|swivel|swivelled|swiveled|(cheat|cheated|cheating)( it)?)"
)
MOVED = "((" + TURN_VERBS + "|round|around|over|across|off) )?((a?round|over|across) )?"
# The amount with its verb before or after it ("swung a bit", "a bit rotated", "slightly off").
AMOUNT = "(" + TURN_VERBS + " " + MOVED + "{HEDGE}|" + MOVED + "{HEDGE}( " + TURN_VERBS + ")?)"
# ... or a small turn said as a noun ("with a slight turn to its left", "a little twist towards its right").
SMALL_TURN = "(a |an )(slight|small|little|tiny|wee|gentle|minor|subtle) (turn|twist|rotation|swing|swivel|pivot)"
TURNED_BY = "(" + TURN_VERBS + " " + MOVED + "{HEDGE}|{HEDGE} " + TURN_VERBS + "|" + SMALL_TURN + ")"
TOWARD = "(((a?round|over|across|off|off axis|off center|back) )?(to|towards|in the direction of)|(so as )?to (show|reveal))"
# Nearer one way without an amount said ("more toward the back", "a hair closer to the front").
NEARER = "(({HEDGE} )?(closer|nearer|more)( to| towards)?)"
# The amount and its direction, one way or the other.
OFFSET_TOWARD = "(" + AMOUNT + " " + TOWARD + "|" + NEARER + ")"
# A side favoured, the amount left to the verb ("favouring its left side", "cheated slightly right").
FAVOURING = "(favoring|favouring|favor|favour|favors|favours|favored|favoured|cheat|cheated|cheating|biased|bias)"
# Not a part of the frame ("closer to the left edge", "a bit to the left third").
NOT_FRAME_PART = "(?! (of|in|edge|edges|corner|third|half|part|border|margin|quarter)( |$))"
# The reference said after an amount, with "off" / "from" / "of" ("45 degrees off its nose", "just
# left of the front", "a bit to the left of head-on").
# The front as a part there ("its face", "the fridge doors", "the TV's screen").
REF_FRONT = (
    "(((the|{P}) (@\\d+ )?|@\\d+ )(front|face|nose|bow|snout|muzzle|grille|screen|doors)( of {obj})?|{FRONT_ON}"
    "|(head|dead|straight|square|face|nose) on|the camera line)"
)
REF_BACK = "((the|{P}) (back|rear|tail|stern)( of {obj})?|(dead|straight|directly|right|squarely) behind|behind( {obj})?|tail on)"
# A view just said as a clause, maybe with its object ("from behind him, ...", "from the front of
# it, ..."): what a sideways offset alone after it is taken from.
_VIEW_ENDS = ("behind", "front", "back", "rear", "view", "angle", "on", "lens", "camera", "profile", "side", "flank", "ahead")
_VIEW_OBJECTS = ("", " him", " her", " it", " them", " of it", " of him", " of her", " @\\d", " of @\\d")
AFTER_REF = "(?:" + "|".join(f"(?<={e}{o} , )" for e in _VIEW_ENDS for o in _VIEW_OBJECTS) + ")"
LAT_SIDE = "(the |(the )?{P} )?{LAT}( hand)?{PART}"
OFFSET_VIEW_FRAMES = [
    # The camera moved by a small amount ("swung a few degrees to its left", "a bit rotated over to the right").
    TURNED_BY + " " + TOWARD + " " + LAT_SIDE + "(?! of )",
    # A small turn said in degrees is no place in the frame ("a couple of degrees to the right").
    "{TURNHEDGE}( more)? " + TOWARD + " " + LAT_SIDE + "(?! of )",
    # Turned from the view said before it ("from behind of it but a bit to the left side").
    "(but|though|yet|only|then) " + OFFSET_TOWARD + " " + LAT_SIDE + NOT_FRAME_PART,
    # A side favoured ("from the front, but favouring its left side", "cheated slightly to the right").
    FAVOURING + " ({HEDGE} )?(" + TOWARD + " )?" + LAT_SIDE + NOT_FRAME_PART,
    # Right after a view clause ("from behind him, little bit more to right", "rear view, slightly
    # off to the right", "from behind, turn right a bit").
    AFTER_REF + OFFSET_TOWARD + " " + LAT_SIDE + "(?= ([,.;!]|$|and |with |so |but ))",
    AFTER_REF + TURN_VERBS + " (to )?(the |{P} )?{LAT}( hand)?( side)? {HEDGE}(?= ([,.;!]|$|and |with |so |but ))",
    # Off its front by that much ("a few degrees off its nose towards its left", "from just left of the front").
    AMOUNT + " (off|from) " + REF_FRONT + "( ,)? " + MOVED + TOWARD + " " + LAT_SIDE,
    "(from )?" + AMOUNT + " (" + TOWARD + " )?" + LAT_SIDE + " (of|from|off) " + REF_FRONT,
]
# The same off the back ("a smidge to the right of its tail", "from just right of behind").
OFFSET_BACK_VIEW_FRAMES = [
    AMOUNT + " (off|from) " + REF_BACK + "( ,)? " + MOVED + TOWARD + " " + LAT_SIDE,
    "(from )?" + AMOUNT + " (" + TOWARD + " )?" + LAT_SIDE + " (of|from|off) " + REF_BACK,
]
# Off a side towards an end ("from its left flank, a few degrees toward the front", "a tad towards
# the back from its right side", "slightly off its left side towards the rear").
# Without an article it is no diagonal's side ("rear-right corner" is no right side).
LAT_REF = "((the|{P}) |(?<!rear )(?<!back )(?<!front )(?<!end )){LAT}( hand)?{PART}( (view|angle|shot))?( of {obj})?"
# An end said as a direction, or an adverb of it ("towards the front", "a bit forward").
LON_SIDE = "((the|{P}) {LON}( side| end)?|{LONWARD})"
SIDE_OFFSET_FRAMES = [
    SEEN + "(from |off |at )?" + LAT_REF + "( ,)? (and |but |then |though |yet |although )?" + OFFSET_TOWARD + " " + LON_SIDE,
    SEEN
    + "(from |off |at )?"
    + LAT_REF
    + "( ,)? (and |but |then |though |yet |although )?"
    + AMOUNT
    + " {LONWARD}(?= ([,.;!]|$|and |with |so |but ))",
    SEEN + AMOUNT + " " + TOWARD + " " + LON_SIDE + "( ,)? (from|of|off) " + LAT_REF,
    SEEN + AMOUNT + " (off|from) " + LAT_REF + "( ,)? " + MOVED + TOWARD + " " + LON_SIDE,
]
# Degrees more past a side already said: "more", or "further" as one walks on ("from its right,
# then 30 degrees further toward its back").
FURTHER = "( more| further| farther)?"
# ... and by an explicit angle (the side nearest the side's azimuth moved that far).
SIDE_OFFSET_DEGREES_FRAMES = [
    SEEN
    + "(from |off |at )?"
    + LAT_REF
    + "( ,)? (and |but |then |though |yet |although )?"
    + MOVED
    + "(by )?{d}(?<= degrees)"
    + FURTHER
    + " "
    + TOWARD
    + " "
    + LON_SIDE,
    SEEN + MOVED + "{d}(?<= degrees) " + TOWARD + " " + LON_SIDE + "( ,)? (from|of|off) " + LAT_REF,
    SEEN + MOVED + "{d}(?<= degrees) (off|from) " + LAT_REF + "( ,)? " + MOVED + TOWARD + " " + LON_SIDE,
]
# An explicit angle sideways, from the front unless a back is said with it (:func:`_combined_view`):
# "swung 30 degrees to its left", "45 deg off its nose towards its left", "60 degrees round to its
# right from head-on", "20 degrees right of its nose".
TURNED_TOWARD = MOVED + TOWARD + " " + LAT_SIDE
TURN_FRAMES = [
    TURN_VERBS + " " + MOVED + "{d}" + FURTHER + " (" + TOWARD + " )?" + LAT_SIDE + "(?! of )",
    MOVED + "((at )?(an |a )?angle of )?{d}(?<= degrees)" + FURTHER + " " + TOWARD + " " + LAT_SIDE + "(?! of )",
    # The angle said after the move, hedged or not ("swung off to its right, maybe 25 degrees").
    TURN_VERBS + " " + MOVED + TOWARD + " " + LAT_SIDE + "( ,)? (by )?{d}(?<= degrees)(?= ([,.;!?]|$))",
    # ... or as an aside after a hedge ("turned a little, maybe 20 degrees, toward its own right").
    TURN_VERBS + " " + MOVED + "{HEDGE}( ,)? (say )?{d}(?<= degrees)( ,)? " + TOWARD + " " + LAT_SIDE + "(?! of )",
    # The turn's noun or its "round" may follow the angle ("a quarter turn round from its face
    # towards its left", "sixty degrees round from the fridge doors, towards the fridge's left").
    MOVED + "(a )?{d}(?<= degrees)( turn)?( (a?round|over|across))? (off|from) " + REF_FRONT + "( ,)? " + TURNED_TOWARD,
    "(from )?" + MOVED + "{d}(?<= degrees) (" + TOWARD + " )?" + LAT_SIDE + " (of|from|off) " + REF_FRONT,
]
# Off the back by an explicit angle ("30 degrees off its tail towards its right").
TURN_BACK_FRAMES = [
    MOVED + "{d}(?<= degrees) (off|from) " + REF_BACK + "( ,)? " + MOVED + TOWARD + " " + LAT_SIDE,
    "(from )?" + MOVED + "{d}(?<= degrees) (" + TOWARD + " )?" + LAT_SIDE + " (of|from|off) " + REF_BACK,
]

# A clock direction around the subject ("from 2 o'clock", "at the ten o'clock position"): the clock
# face seen from above with 12 at the subject's front, so 3 o'clock is its right (+90 degrees) and
# each hour 30 degrees; read as the side nearest that azimuth, like an explicit angle.
CLOCK_PHRASES = [
    SEEN + "((from|at) )?(the |{P} )?{d} o clock( (position|direction|angle|side|mark))?( of {obj})?",
]
# "One o'clock": "one" stays a word (vocabulary.words).
CLOCK_ONE_HOUR = CLOCK_PHRASES[0].replace("{d}", "one")
CLOCK_HOUR_DEG = 30.0
# The clock face said around the subject with its front at twelve ("as on a clock face with the
# screen at twelve", "the bear looking at 12", "imagine teddy is the centre of a clock", "picture
# a clock under the car with its bonnet at twelve"): CLOCK_PHRASES' convention said again, so
# understood, no constraint; a clock put otherwise ("its back at twelve") stays unread. Where a
# clock is said (RULE_CONTEXTS), an hour needs no "o'clock" ("stand at 7", "the view from one",
# "from half past ten", "a quarter to six"); "on its six" is behind it, as pilots say it.
_CLOCK_END = "(?= ([,.;:!?()]|$|and |with |as |for |on |in |of |please ))"
# An hour said on the dial the setup laid round the subject ("the camera at about four on the dial").
CLOCK_DIAL = "(at|to|from) (the )?({ABOUT} )?(?P<d>1[01]|[1-9]) on the (dial|clock|clock face|clockface)" + _CLOCK_END
_FRONT_AT_12 = "(" + "|".join(sorted({*FACING_PARTS["front"], *END_PARTS["front"]}, key=len, reverse=True)) + ")"
CLOCK_SETUP_PHRASES = [
    "((as |like )?(on|in) )?(a |the )?clock( face)?( (laid |lying |flat )?(on|under|around|round|below|beneath) (the |a )?"
    "([a-z]+|@\\d))?(?= ([,.;:!?()]|$|with |and ))",
    "(imagine|picture|pretend|think)( of)?( that)? ({obj}|he|she) ((is|s|sits|stands|stand|sit|as) )?(at |in )?(the )?"
    "(center|middle) of (a |the )?clock( face)?",
    "((with )?(the |{P} )" + _FRONT_AT_12 + " |({obj}|he|she) )?(is |are )?((looking|facing|pointing|pointed|aimed|turned"
    "|looks|faces|points)( (at|to|towards))?|at|to) (12|noon)" + _CLOCK_END,
    # Said as what the front is ("his face is twelve", "(the seat is 12 o'clock)").
    "(the |{P} )" + _FRONT_AT_12 + " (is|being|=) (12|noon)( o clock)?" + _CLOCK_END,
]
_HOUR = "(?P<d>1[01]|[1-9])"  # twelve is where the subject faces ("its handle at 12")
_AT_HOUR = "(((stand|standing|stood|shoot|shooting|go|walk|move|be|camera|the camera) )?(at|from|to) (the )?|the view from )"
CLOCK_BARE_HOURS = {  # hours past the hour said: its template
    0.0: _AT_HOUR + _HOUR + "( (position|mark))?" + _CLOCK_END,
    0.5: "(from |at |to )?(the )?half past " + _HOUR + _CLOCK_END,
    0.25: "(from |at |to )?(the )?(a )?quarter past " + _HOUR + _CLOCK_END,
    -0.25: "(from |at |to )?(the )?(a )?quarter to " + _HOUR + _CLOCK_END,
}
CLOCK_ONE = _AT_HOUR + "one" + _CLOCK_END  # "one" stays a word (vocabulary.words): one o'clock
# Words a row needs somewhere in the text besides its own, by template.
RULE_CONTEXTS = {t: (" clock ",) for t in (*CLOCK_BARE_HOURS.values(), CLOCK_ONE)}
SIX_OF = "(on|at|from|watching|watch|covering|cover|check|checking) ({P}|his|her|its|their) (?P<d>6)" + _CLOCK_END
# An azimuth said as such, signed ("an azimuth of 30 degrees", "at minus 45 degrees azimuth").
SIGNED_AZIMUTH_PHRASES = [
    "(at |from |with )?(an |a )?azimuth( angle)?( of| ,)? {sd}",
    "(at |from )?{sd}(?<= degrees) (of )?azimuth",
]
# Degrees off a side towards an end ("from its left, 15 degrees towards the back"): the side's
# azimuth moved that far, as the nearest side (:func:`_nearest_side`).
SIDE_DEGREES_PHRASES = [
    SEEN + "from (the|{P}) {LAT}( hand)?( side| end)?( of {obj})?( ,)? (by )?({ABOUT} )?{d}(?<= degrees) "
    "(towards|toward|to) (the|{P}) {LON}( side| end)?",
]

# View cues for one subject that together name one side ("a three-quarter view ... from its
# left" is the front-left); any other two different sides contradict each other.
VIEW_COMBINATIONS = {
    frozenset(pair): side
    for lat in ("left", "right")
    for pair, side in [
        (("three-quarter", lat), f"front-{lat}"),
        (("three-quarter", f"front-{lat}"), f"front-{lat}"),
        (("three-quarter", f"back-{lat}"), f"back-{lat}"),
        (("back-three-quarter", lat), f"back-{lat}"),
        (("back-three-quarter", f"back-{lat}"), f"back-{lat}"),
        (("front", lat), f"front-{lat}"),
        (("back", lat), f"back-{lat}"),
        (("front", f"front-{lat}"), f"front-{lat}"),
        (("back", f"back-{lat}"), f"back-{lat}"),
        ((lat, f"front-{lat}"), f"front-{lat}"),
        ((lat, f"back-{lat}"), f"back-{lat}"),
        (("side", lat), lat),
        (("front", f"front-slight-{lat}"), f"front-slight-{lat}"),
        (("back", f"front-slight-{lat}"), f"back-slight-{lat}"),
        (("back", f"back-slight-{lat}"), f"back-slight-{lat}"),
        ((lat, f"{lat}-slight-front"), f"{lat}-slight-front"),
        ((lat, f"{lat}-slight-back"), f"{lat}-slight-back"),
    ]
} | {
    frozenset(("three-quarter", "front")): "three-quarter",
    frozenset(("three-quarter", "back")): "back-three-quarter",
    frozenset(("three-quarter", "back-three-quarter")): "back-three-quarter",
    frozenset(("back-three-quarter", "back")): "back-three-quarter",
}
# An exact end ("dead on", "directly from the left") combines as its end does, and said again
# plainly ("from the front, dead on") stays exact.
VIEW_COMBINATIONS |= {
    frozenset(f"{v}-exact" if v == end else v for v in pair): side
    for pair, side in list(VIEW_COMBINATIONS.items())
    for end in EXACT_ENDS
    if end in pair
} | {frozenset((end, f"{end}-exact")): f"{end}-exact" for end in EXACT_ENDS}
# A side view said with an exact side keeps it exact ("pure left profile, perpendicular to its flank").
VIEW_COMBINATIONS |= {frozenset(("side", f"{lat}-exact")): f"{lat}-exact" for lat in ("left", "right")}
# Exactness said apart makes an end exact and leaves any other side as it is.
VIEW_COMBINATIONS |= {
    frozenset((EXACT_ONLY, side)): f"{side}-exact" if side in EXACT_ENDS else side for side in VIEW_SIDES if side != EXACT_ONLY
}

# Every object of the scene at once ("the whole group", "all of them"): each one not named
# otherwise joins as a secondary subject (it must be in the picture).
GROUP_PHRASES = [
    "(the )?(whole|entire) (group|lot|bunch|collection|arrangement|set ?up|ensemble|gang)( of (them|objects|things))?",
    "(all|each|every one|both) of them",
    "all (of )?(the )?(objects|things|items|pieces)",
    "everything( (in|on) the (scene|table|room|floor))?",
]

# Named elevations; the hints yield to any other elevation in the sentence.
ELEVATION_PHRASES = {
    "eye level": [
        "(at |from |on )?(the |{P} )?eye (level|height|line)( (shot|view|angle|camera))?",
        # Eye to eye with it ("teddy, eye to eye", "eye-to-eye with the bear").
        "(at |from )?eye to eye( with ({obj}|(the |{P} )?{ANCHOR_EYE}))?",
        # The camera set on the surface the subject stands on ("the camera resting on the table").
        "(the )?(camera|lens) (is )?(lying|resting|sitting|placed|set|put|standing)( down)? on the "
        "({SURFACE}|tabletop|table top)",
        "with the camera at {P} (height|level|eye level)",
        "(shot )?straight on at {P} height",
        "(at|from|on) (the )?(same height|same level|height|level) (as|of|with|like) ({obj}|(the |{P} )?{ANCHOR_EYE})",
        "(at|from) {P} (height|level)",
        "{LEVEL} {obj}",
        # As high as it or a part at its height ("camera as high as its head").
        "((the )?(camera|lens) )?(just )?as high as ({obj}|(the |{P} )?{ANCHOR_EYE})",
        # The subject at the lens's height ("the sofa level with the lens", "the ball at lens height").
        "(?<=@\\d )(is )?({LEVEL}|at) the (camera|lens)( (height|level))?",
        "(at|from) (the )?(camera|lens) (height|level)",
        # At its middle height ("from mid-height", "at half its height", "from halfway up it").
        "(at |from )?(its |the |{P} )?(mid|middle|half) (height|level)( of {obj})?",
        "(at |from )?half {P} height",
        "(from )?halfway up( {obj})?(?! the )",
        # "eye level with it", "eye-level with the seat".
        "(at |from )?(the )?eye (level|height|line) with ({obj}|(the |{P} )?{ANCHOR_EYE})",
        # The height of the eyes said the other way round ("at level of eyes", "on the height of the eyes").
        "(at |on |from )?(the )?(level|height|line) of (the |{P} )?eyes",
        # From its eyes ("not from up high, from his eyes"): at their height (parse20h).
        "(at|from) {P} eyes(?! (level|height|line|of) )",
        # At the height of a subject named ("ball and plant both in the frame, at ball height").
        "(at|from) (the )?{obj} (height|level)",
        # Down (or up) to a part's height ("crouched down to its roofline", "lowered to the bonnet").
        "((the )?(camera|lens) )?(crouched|crouching|crouch|squatting|squat|kneeling|kneel|down|lowered|dropped|brought|raised"
        "|lifted|held|set|come|coming|get|getting) (down |up )?to (the |{P} )?(own )?{ANCHOR_EYE}( (level|height|line))?",
        "(from |at )?(a )?(neutral|level|straight) (angle|height)",
        "(from |at |in )?(a |an )?(horizontal|flat|neutral|level|levelled|leveled|even) "
        "(camera angle|camera position|{EYENOUN}|camera|position)",
        # The height of the surface the subject rests on, or sits on: level with the subject.
        "(with the camera |camera )?(at|from) (the |a )?{SURFACE} (height|level)",
        # A height named by a body or a surface ("chest height", "at seat level", "lens at the
        # car's own height"), and a level camera said plainly ("dead level with it", "flat on").
        "((with )?(the )?(camera|lens) )?({ROUGHLY} )?((down |up |right |low )?(at|from|on) )?(the |a |{P} )?{ANCHOR_EYE}( 's)? "
        "(height|level|high|position|line)",
        # The height of a surface or part named ("from the height of the coffee table").
        "((put |with |set |hold |keep )?(the )?(camera|lens) )?({ROUGHLY} )?(at|from|on) ({ROUGHLY} )?(the |a )?"
        "(height|level) of "
        "(the |a |{P} )?"
        "({ANCHOR_EYE}|{SURFACE}|coffee table|side table)( of {obj})?",
        "((with )?(the )?(camera|lens) )?({ROUGHLY} )?(at|from|on) {P} (own )?(height|level)",
        "(at |from )?(its |their )?own (height|level)",
        "((the )?(camera|lens) (is )?(held |kept |set |placed |put )?)?({STRONG} )?{LEVEL} {obj}",
        "((the )?(camera|lens|shot|view) )?(held )?({STRONG} |flat )level(?= ([,.;!]|$))",
        # A view noun, then "level" ("viewpoint level"); not "camera level": that keeps the horizon level.
        "({EYENOUN}|lens) (level|flat)(?= ([,.;!]|$))",
        # Level with a part or a surface named by a height anchor ("level with the seat").
        "((the )?(camera|lens) )?({ROUGHLY} )?({STRONG} )?{LEVEL} (the |{P} )?{ANCHOR_EYE}( (height|level|line))?"
        "( of ({obj}|(the |{P} )?{ANCHOR_EYE}))?",
        # Level with an edge or the middle of such a part, or with where it starts ("lens level with
        # the top of the backrest", "level with where the leaves begin"): a part of the subject is at
        # its height, as the part itself is (parse20h).
        "((the )?(camera|lens) )?({ROUGHLY} )?({STRONG} )?{LEVEL} (the )?(top|top edge|upper edge|middle|center|mid point)"
        " of (the |{P} )?{ANCHOR_EYE}",
        "((the )?(camera|lens) )?({ROUGHLY} )?({STRONG} )?{LEVEL} (where|the point where|the spot where|the place where) "
        "(the |{P} )?{ANCHOR_EYE} (start|starts|begin|begins|end|ends|meet|meets|join|joins)",
        # The camera at the subject's middle ("camera roughly at its middle", "lens on its centre").
        "(the )?(camera|lens) (is |held |kept |set |placed |put )?({ROUGHLY} )?(at|on) ({P}|(the )?{ANCHOR_EYE} 's) "
        "(own )?{MIDDLE}",
        "flat on",
        # The camera brought to the subject's height ("camera lowered to the car's level").
        # Also oneself ("get down to the bear's level", "come down to its height"): parse18p6.
        "((the )?(camera|lens) )?(lowered|raised|brought|dropped|lifted|moved|set|held|put|{GET}|come|coming|came)"
        "( yourself| the camera| the lens)?( down| up)? to "
        "(the |a |{P} )?(own )?({ANCHOR_EYE} )?(level|height)( of {obj})?",
        # "Level" alone as a clause, of the camera ("bench from behind, level").
        "{CLAUSE}(nice and )?level(?= ([,.;!]|$))",
    ],
    "slightly above": [
        # Not "kind of overhead": a hedge on where the camera is, roughly overhead (bird's-eye).
        "(from |with the camera )?({WEAK}|just) (above|higher( up)?|(?<!kind of )(?<!sort of )overhead)( {obj}| than {obj})?",
        # A hedge before a place on top ("the camera is a bit on top of him", "slightly on top").
        "(from |with the camera )?({WEAK}|just) (on|over|above) (the )?top( of {obj})?",
        "(a |an )?({WEAK} |slight |gentle |mild |shallow )(down|high) (angle|tilt)",
        "(with )?(the )?(camera|lens) {AIM} (down {WEAK}|{WEAK} down)",
        "{WEAK} from above",
        # Said with "upper", as non-native writers say "from above" ("little bit from upper", "look
        # from a little bit upper").
        "((look|looks|looking) )?({WEAK} from (the )?upper|from {WEAK} upper)( side)?"
        "(?= ([,.;:!?]|$|and |with |but |to |at |on ))",
        "(looking|look|looks|{AIM}) {WEAK} down( (at|on|onto) {obj})?",
        # The camera said as "it" between ("angle it gently down", "tilt it a bit down"): parse20h.
        "{AIM} (it|the camera|the lens) ({WEAK} down|down {WEAK})( (at|on|onto) {obj})?",
        "(from )?(a )?slightly (high|higher|elevated|raised) (angle|position|viewpoint|vantage point|camera)",
        # A little elevation or height ("slight elevation", "a touch of height"), looking down gently.
        "(a |with )?(slight|gentle|mild|small|little) (elevation|height)",
        "{WEAK} of (elevation|height)",
        "{WEAK} (looking|look|looks|{AIM}) down( (at|on|onto) {obj})?",
        "{WEAK} (above|over) (the )?(level|horizontal|horizon)",
        "slightly elevated( (angle|view|position|viewpoint|camera))?",
        "(a )?(slight|gentle|mild|shallow) high angle( shot)?",
        "({WEAK} |just )?(above|higher than|over) (eye|{ANCHOR_EYE}) (level|height)",
        # Above the subject's own height or a part of it ("from just over its own height", "a
        # touch above its seat", "a little higher than its roof").
        "(from )?({WEAK} |just )?(above|over|higher than) {HEIGHT_OF} (level|height|line)",
        "(from )?({WEAK} |just )(above|over|higher than) {P} (own )?({ANCHOR_EYE}|top)(?! (level|height|line) )",
        # A part said with "the" ("from just over the lip", "a touch above the roofline"); not the top
        # of a table, what the subject stands on (the low angle's "lens just above the tabletop"): parse20h.
        "(from |taken from |shot from |(the )?(camera|lens) )?({WEAK} |just )(above|over|higher than) "
        "the (?!tabletop |table top ){PARTS}"
        "(?! (level|height|line|of) )",
        # Slightly higher than a part at the subject's height ("slightly higher than the seat").
        "({WEAK}|just) higher than (the |{P} )?{ANCHOR_EYE}( (level|height))?",
        # Degree words after or around a height ("a touch high", "looking down a bit").
        "{WEAK} (high|higher|up|raised|elevated|lifted)( up| angle)?(?! (in|on|at) )",
        # The degree said after ("elevated slightly", "raised a touch").
        # Said of the camera, or the camera up by a little ("camera raised slightly", "cam up a bit").
        "((with )?(the )?(camera|lens) (is |was )?)?(raised|elevated|lifted) {WEAK}(?= ([,.;!]|$|and |with |looking ))",
        "(the )?camera (is )?(up|higher) {WEAK}(?= ([,.;!]|$|and |with |looking ))",
        "(looking|look|looks|{AIM}) down {WEAK}( (at|on|onto) {obj})?",
        "(looking|look|looks|{AIM}) down( (at|on|onto) {obj})? {WEAK}",
        "{WEAK} (of )?a high angle",
        "(from )?{WEAK} (above|over|higher than) {obj}",
        # A few degrees said for the slight class ("a few degrees above", "a couple of degrees up",
        # the camera looking "a few degrees down": N degrees down is N above).
        "(from |with the camera |camera )?{FEW} (above|up|higher|over|high|overhead|down)"
        "( {obj}| than {obj}| (the )?(horizon|horizontal))?(?! (from|to|the|its|his|her|their|left|right) )",
        "(looking|look|looks|{AIM}) down {FEW}( (at|on|onto) {obj})?",
        # A few degrees over a part of it or its own height ("lens a few degrees above the roofline",
        # "a couple of degrees over the mug's rim").
        "((with )?(the )?(camera|lens) )?((at|from) )?{FEW} (above|over|higher than) (the |{P} )(own )?({ANCHOR_EYE}|top)"
        "( (level|height|line))?",
        "(looking|look|looks|{AIM}) {FEW} down( (at|on|onto) {obj})?",
        # A weak word before any high place ("bit from up top", "a touch from up high").
        "{WEAK} from (up top|up high|high up|higher up|on high|overhead|up above|high|higher)(?! (angle|up|above) )",
        # A shallow angle said with its direction ("from above at a shallow angle").
        "(from )?(above|over)( ,)? (at )?(a |an )?(shallow|slight|gentle|mild|small) angle",
        "(at |from )?(a |an )?(shallow|slight|gentle|mild|small) angle (from )?(above|over)",
    ],
    "high angle": [
        "(from |in |with )?(a |an )?high angle( (shot|view|position|camera))?",
        "(from |in |with )?(a |an )?{VERY} high angle( (shot|view|position|camera))?",
        "(a |an )?high (shot|view)",
        # Clipped and abbreviated (parse18p6): "hi angle", "hi-angle shot"; "HA" as a shot list's
        # clause of its own after another ("VASE / HA / MS"; not laughter: "ha ha, ...").
        "(from |in |with )?(a |an )?hi (angle|shot|view|perspective)( (shot|view|position|camera))?",
        "(?<!ha [,;:.!?] )(?<!la [,;:.!?] ){CLAUSE}ha(?= ([,.;:!]|$))",
        # A shot named by its direction ("a downward shot": "downward" reads as "down").
        # An article or a clause's start before it: "top down shot" is a plan view, not this.
        "({CLAUSE}|(?<![a-z])a |(?<![a-z])an )down (shot|angle|view|perspective|camera angle)( (of|on|onto) {obj})?",
        "with the camera (well|high|far) above {obj}",
        "(from )?(a |an )?(high|elevated|raised|lofty|towering)"
        " (vantage( point)?|viewpoint|position|perspective|perch|place|spot|point)",
        "(from |in |with )?(a |an )?(elevated|raised|lofty) (view|angle|shot|camera)",
        "(from )?(well|high|far) above( {obj})?",
        "(well|far) above eye (level|height)",
        "(from )?(well|far|way|much) (above|over|higher than) {HEIGHT_OF} (level|height|line)",
    ],
    "bird's-eye": [
        "(from |in |as )?(a |an )?birds?( 's)? eye( (view|shot|angle|perspective))?",
        "(from |in |as )?(a |an )?overhead( (shot|view|angle|perspective))?",
        "(from |in |as )?(a |an )?aerial( (shot|view|angle|perspective))?",
        # High up in the air (parse18p6: "a view from way up in the air").
        "(from )?({VERY} |high |far )?up (high )?in the (air|sky)",
        "((seen|shot|viewed) )?from ({VERY} |high )?overhead",
        # Roughly overhead ("from kinda overhead", "sort of overhead"): "kind of" hedges the place.
        "((seen|shot|viewed) )?(from )?(kind of|sort of|more or less|roughly|pretty much) overhead",
        "((seen|shot|viewed) )?from the top",
        # The camera up by the ceiling ("from the ceiling looking down", "from up near the ceiling").
        "(from |at )?(up )?(near |by |at |against |under |just under )?the ceiling",
        "((seen|shot|viewed|looking) )?(steeply|strongly|sharply) (from above|down( (at|on) {obj})?)",
        "(from |in |with )?(a )?steep high angle( (shot|view))?",
        "(look|looks|looking|{AIM}) (down (steeply|sharply)|(steeply|sharply) down)( (at|on|onto) {obj})?",
        "from (above|overhead)( ,)? (at )?(a )?(steep|sharp) angle",
        "(at |from )?(a )?(steep|sharp) angle (from )?(above|overhead)",
        "(from |in |with )?(a )?steep (overhead|downward|down|top)( (angle|shot|view))?",
        "(high|far|way|well|right) (up )?overhead",
        "(at |from )?(the )?ceiling (height|level)",
        # From the sky or the air, as a drone or a bird sees it.
        "(from|out of) (up in )?the (sky|air)",
    ],
    "top-down": [
        # Held exactly overhead, maybe said of the camera hanging there ("camera hanging dead
        # overhead", "perched bang over it"); a bare "hanging overhead" stays a high angle.
        "((hovering|hanging|perched|floating|suspended|mounted|poised|positioned|held) )?(from )?({NEARLY} )?"
        "(directly|straight|right|vertically|squarely|exactly|dead|bang|smack|plumb|precisely) (up )?(above|overhead|over)"
        "( {obj})?",
        "((seen|shot|viewed) )?(directly|straight|vertically|squarely) from above",
        # Vertically from the ceiling or from overhead ("shot vertically from the ceiling down",
        # "from the ceiling straight down").
        "((seen|shot|viewed|looking|taken) )?(directly|straight|vertically|squarely) (down )?from (the ceiling|overhead|up top)"
        "( (straight |vertically |directly )?down)?",
        "from the ceiling (straight|vertically|directly) down",
        # The camera exactly on top of it ("camera directly on top", "lens right on top of the mug").
        "(with )?(the )?(camera|lens|cam) (is |sits |sitting |held |placed |positioned |mounted )?"
        "(directly|straight|right|dead|squarely|exactly|bang|smack|plumb|precisely) on top( of {obj})?",
        "looking ({NEARLY} )?(straight|directly|vertically) down( (at|on) {obj})?",
        "{AIM}( the camera| the lens)? (straight|directly|vertically) down( (at|on|onto) {obj})?",
        "(from |in |as )?(a |an |the )?top down( (view|shot|angle|perspective))?",
        # A top-down view called flat, as a flat lay is ("a true top-down flat view"): not level.
        "(a |an |the )?top down flat (view|lay|shot|photo|picture|image)",
        "(shot |looking )?({NEARLY} )?straight down( (at|on) {obj})?",
        # A top view is a plan view, as in product and architectural photography.
        "(a )?(plan view|flat lay|top view)",
        # So is a film's top shot (the camera straight above the set), and a top angle with it.
        "(from |in |as )?(a |an |the )?top (shot|angle)",
        # As near to vertical as can be ("as close to vertical as you can", "near-vertical").
        "(as )?(near|close|nearly|almost|near) (to )?vertical(ly)?( as (possible|you can|it gets|can be|you can get))?",
        "(straight |perfectly |fully )?vertical(ly)? (down|overhead|above)",
        "(a |an )?(drone|overhead) (style )?top down",
        # Looking (or aiming) down straight, the insisting word before or after "down": "look
        # down straight on it", "peering right down onto the mug", "camera looks directly down at
        # him", "look down right on top of it"; "straight on" there is no front view.
        "((the )?(camera|lens|cam) )?{LOOK} ({NEARLY} )?{DOWNRIGHT} down({DOWNONTO})?",
        "((the )?(camera|lens|cam) )?{LOOK} down ({NEARLY} )?{DOWNRIGHT}{DOWNONTO}",
        "((the )?(camera|lens|cam) )?{LOOK} down ({NEARLY} )?(straight|directly|vertically)(?= ([,.;!]|$|and |from ))",
        # The nadir: the point straight below the camera.
        "(a |an |the )?nadir( (shot|view|angle|perspective))?",
        "(with )?(the )?(camera|lens) {AIM} (straight|directly|vertically) (down|at the (floor|ground|grass|table))",
        # The lens turned to the floor ("right above it, lens facing the floor").
        "(with )?(the )?(camera|lens) (facing|{AIM}) (straight |directly )?(down )?((at|towards|to) )?"
        "the (floor|ground|grass|lawn|table)",
        # ... the ground said to lie straight below ("lens aimed at the grass directly beneath"):
        # below the camera, not the camera below the subject.
        "(with )?(the )?(camera|lens) (facing|{AIM}) (straight |directly )?(down )?((at|towards|to) )?"
        "the (floor|ground|grass|lawn|table) ({STRONG}|right|just) (below|beneath|under|underneath)( (it|us|me|{obj}))?",
        # The camera or a drone's gimbal turned as far down as it goes ("gimbal straight down",
        # "camera tilted all the way down", "lens pointed completely downward", "aimed down vertically").
        "(the )?(camera|lens|gimbal)( (is|was))?( ({AIM}|facing|turned|looking))?( the (camera|lens))? ({NEARLY} )?{FULLY} down"
        "( (at|on|onto) {obj})?",
        "{AIM}( the camera| the lens)? {FULLY} down( (at|on|onto) {obj})?",
        # The subject right under the camera, said from the camera's side ("the tree directly beneath
        # us", "straight below the drone"): the camera straight above it.
        "({STRONG}|right|just) (below|beneath|under|underneath) (us|me|the (camera|lens|drone|gimbal))",
        # ... or said of the subject alone, ending the sentence ("lens ninety degrees down, the
        # tree right underneath"). "From right underneath" puts the camera below, and so may "the
        # mug right underneath, looking up": hence the sentence's end.
        "(?<!from ){obj} (is |sits |lies |stands )?({STRONG}|right|just) (below|beneath|under|underneath)(?= ([.;!]|$))",
        "(the )?(camera|lens|gimbal)( (is|was))?( ({AIM}|facing|turned|looking))? down (vertically|straight|fully)",
    ],
    "low angle": [
        "(from |in |with )?(a |an )?low angle( (shot|view|position|camera))?",
        "(from |in |with )?(a |an )?{VERY} low angle( (shot|view|position|camera))?",
        "(a |an )?low (shot|view)",
        "(from |in |with )?(a |an )?lo (angle|shot|view|perspective)( (shot|view|position|camera))?",
        "(?<!ha [,;:.!?] )(?<!la [,;:.!?] ){CLAUSE}la(?= ([,.;:!]|$))",
        # An article or a clause's start before it: "a close up shot" is a size, not this.
        "({CLAUSE}|(?<![a-z])a |(?<![a-z])an )up (shot|angle|view|perspective|camera angle)( (of|at|on) {obj})?",
        "with the camera (below|beneath|under|lower than) {obj}( ,? looking up)?",
        # The camera said below it ("camera beneath it", "lens under it looking up"): parse20h.
        "(the )?(camera|lens) (is |sits |held )?(below|beneath|under|underneath|lower than) {obj}( ,? looking up)?",
        "(from )?(a |an )?(low|lowered) (vantage( point)?|viewpoint|position|perspective|place|spot|point)",
        # The camera just off the ground ("from just above the ground", "an inch above the floor").
        "(from )?((just|right|only) |{WEAK} )?(above|over|off) the (ground|floor|grass|lawn)",
        # Just above the surface the subject stands on, said of the camera ("lens just above the tabletop").
        "(the )?(camera|lens) ((just|right|only) |{WEAK} )(above|over|off) the ({SURFACE}|tabletop|table top|ground|floor)",
        "(well|far) (below|under|beneath) eye (level|height)",
        "(from )?(well|far|way|much) (below|under|beneath|underneath|lower than) {HEIGHT_OF} (level|height|line)",
        "(from )?(well|far|way) (below|beneath|under)( {obj})?",
        "(a |an )?(heroic|hero) (angle|perspective)( shot)?",
    ],
    "slightly below": [
        "(from |with the camera )?({WEAK}|just) (below|beneath|under|underneath|lower)( {obj}| than {obj})?",
        "{WEAK} from (below|beneath)",
        "(looking|look|looks|{AIM}) {WEAK} up( (at|to|towards) {obj})?",
        "{AIM} (it|the camera|the lens) ({WEAK} up|up {WEAK})( (at|to|towards) {obj})?",
        "(from )?(a )?slightly (low|lower) (angle|position|viewpoint|vantage point|camera)",
        "{WEAK} (looking|look|looks|{AIM}) up( (at|to|towards) {obj})?",
        "{WEAK} (below|under|beneath) (the )?(level|horizontal|horizon)",
        "(a )?(slight|gentle|mild|shallow) low angle( shot)?",
        "(a |an )?({WEAK} |slight |gentle |mild |shallow )(up|low) (angle|tilt)",
        "(with )?(the )?(camera|lens) {AIM} (up {WEAK}|{WEAK} up)",
        "({WEAK} |just )?(below|under|beneath|lower than) (eye|{ANCHOR_EYE}) (level|height)",
        # Below the subject's own height or a part of it ("from just under its own height", "a
        # little below its seat", "a bit lower than its roof").
        "(from )?({WEAK} |just )?(below|under|beneath|underneath|lower than) {HEIGHT_OF} (level|height|line)",
        "(from )?({WEAK} |just )(below|under|beneath|underneath|lower than) {P} (own )?{ANCHOR_EYE}(?! (level|height|line) )",
        "(from |taken from |shot from |(the )?(camera|lens) )?({WEAK} |just )(below|under|beneath|underneath|lower than) "
        "the (?!tabletop |table top ){PARTS}(?! (level|height|line|of) )",
        "{WEAK} (low|lower)( down| angle)?(?! (in|on|at) )",
        "((with )?(the )?(camera|lens) (is |was )?)?(lowered|dropped) {WEAK}(?= ([,.;!]|$|and |with |looking ))",
        "(the )?camera (is )?(down|lower) {WEAK}(?= ([,.;!]|$|and |with |looking ))",
        "(looking|look|looks|{AIM}) up {WEAK}( (at|to|towards) {obj})?",
        "(looking|look|looks|{AIM}) up( (at|to|towards) {obj})? {WEAK}",
        "{WEAK} (of )?a low angle",
        "(from |with the camera |camera )?{FEW} (below|beneath|under|underneath|lower|low)"
        "( {obj}| than {obj}| (the )?(horizon|horizontal))?(?! (at|on|onto) )",
        "(looking|look|looks|{AIM}) up {FEW}( (at|to|towards) {obj})?",
        "((with )?(the )?(camera|lens) )?((at|from) )?{FEW} (below|beneath|under|underneath|lower than) (the |{P} )(own )?"
        "({ANCHOR_EYE}|top)( (level|height|line))?",
        "(looking|look|looks|{AIM}) {FEW} up( (at|to|towards) {obj})?",
        "{WEAK} from (down low|low down|lower down|down below)",
        "(from )?(below|beneath|under|underneath)( ,)? (at )?(a |an )?(shallow|slight|gentle|mild|small) angle",
        "(at |from )?(a |an )?(shallow|slight|gentle|mild|small) angle (from )?(below|beneath|under|underneath)",
    ],
    "worm's-eye": [
        "(from |in |as )?(a |an )?worms?( 's)? eye( (view|shot|angle|perspective))?",
        # Below the support itself ("put the camera underground", "from below ground level"), or
        # looking up through it ("through the grass", "through the wood").
        "(from )?((right|deep|just) )?(underground|below ground|beneath the ground|under the ground|in the ground)( level)?",
        "through (the |a )?({SURFACE}|{SUPPORT})( (top|surface))?",
        "((the |a )?(camera|lens) )?(buried|sunk|dug|set|placed|put|hidden) (down )?(in|into|under|beneath) (the |a )?{SUPPORT}",
        # A verb of burying, then the camera ("bury the camera in the lawn", "sink the lens into the sand").
        "(bury|buries|burying|buried|sink|sinks|sinking|sank|sunk|dig|digs|digging|dug|embed|embeds|embedding|embedded)"
        " (the |a |your |my )?(camera|lens)( (down|deep|right))? (in|into|under|beneath|below|underneath) (the |a )?{SUPPORT}"
        "( (right )?(below|beneath|under|underneath) {obj})?",
        # Burying says it alone ("bury the camera under the bench"): below the ground.
        "(bury|buries|burying|buried) (the |a |your |my )?(camera|lens)( (down|deep))?"
        "( (right )?(below|beneath|under|underneath) {obj})?",
        "(the |a )?(camera|lens) (is )?(buried|sunk|embedded|dug in|underground)"
        "(?= ([,.;!]|$|and |with |looking |aiming |pointing ))",
        "looking steeply up( at {obj})?",
        "from the ground( level)?( ,)? looking steeply up( at {obj})?",
        "(steeply|strongly|sharply) from (below|beneath)",
        "from (below|beneath|underneath)( ,)? (at )?(a )?(steep|sharp) angle",
        "(from |in |with )?(a )?(steep|sharp) (low|upward|up)( (angle|shot|view))?",
        "(look|looks|looking|{AIM}) (up (steeply|sharply)|(steeply|sharply) up)( (at|to|towards) {obj})?",
        # Below the floor the subject stands on ("from the cellar", "through a hole in the floor").
        "(from |in |down in )?(the |a )?(cellar|basement|crawl space|crawlspace)",
        "(up )?through (a |the )?(hole|gap|crack|opening|trapdoor|trap door|hatch) in (the |a )?{SUPPORT}",
        # From under what the subject stands on ("from underneath the table", "from beneath the
        # floor"): below the support, looking steeply up.
        "(from )?(underneath|beneath|below|under) (the |a )?{SURFACE}( (surface|top|level))?",
        "(from )?(underneath|beneath|below|under) (the |a )?{SUPPORT}( (surface|level))?",
    ],
}
# A person's place beside or before the subject ("as if sitting beside it", "as though you were
# standing in front of it", "from where a seated person's eyes would be"): the camera at their
# eyes, level with it; a hint, as a height said otherwise tells more.
AS_IF = (
    "(as if|as though|like|as)( (you|i|we|one|someone|somebody|a person|the viewer)"
    "( (were|was|are|is|am|m|re|s|had been|would be))?)?"
)
POSTURE = "(sitting|sat|seated|standing|stood)"
PERSON = "(person|viewer|visitor|guest|adult|man|woman|someone|somebody|observer|onlooker|spectator|customer)"
BESIDE_IT = (
    "(beside|next to|by|alongside|in front of|opposite|across from|facing|near|on|at|in) "
    "({obj}|(the |a |an )?({SURFACE}|chair|couch|bench|floor|ground|grass|lawn))"
)
ELEVATION_HINTS = {
    # The camera pointing level ("lens dead horizontal", "camera aimed horizontally"): a hint, as
    # a camera held horizontal may also mean a landscape frame; a horizontal frame or horizon is a
    # roll or an orientation, not a height.
    "eye level": [
        "(the )?(camera|lens|line of sight) (is |held |kept |stays |set )?({STRONG} |perfectly |nice and )?horizontal"
        "(?= ([,.;!]|$|and |with |at |on ))",
        "({STRONG}|perfectly) horizontal(?! (horizon|frame|framing|format|orientation|line|lines|image|picture|shot) )",
        # Parallel to what the subject stands on, or pointing neither up nor down ("lens parallel to
        # the floor", "not pointing up or down"): parse20h.
        "((the )?(camera|lens|line of sight) (is |held |kept |stays |set )?)?({STRONG} |perfectly )?parallel (to|with) (the )?"
        "(floor|ground|table|tabletop|desk|grass|lawn)",
        "((and |but )?not|neither) (pointing|pointed|tilted|tilting|angled|aimed|looking|facing) (up or down|down or up"
        "|up nor down|down nor up)",
        "{AIM}( the camera| the lens)? ({STRONG} |perfectly )?horizontal(ly)?",
        "(at|from) (the )?(height|level|eye level|eye height|eye line|head height) of (a |an |the )?"
        + PERSON
        + " "
        + POSTURE
        + "( "
        + BESIDE_IT
        + "){0,2}",
        AS_IF + " " + POSTURE + "( (down|up|there))?( " + BESIDE_IT + "){0,2}( would (see|view|have|look at) {obj})?",
        "(from |at )?(where |the height of )?(the |a |an |someone 's )?(eyes |eye line |head )?(of )?(a |an |the )?"
        + POSTURE
        + " "
        + PERSON
        + "( 's)? (eye level|eye height|eye line|eyeline|eyes|eye|head height|head)( (would be|would|are|is|were|sit|be))?",
    ],
    "high angle": [
        "(look|looks|looking) down( (at|on|onto) {obj})?",
        # Looking down on a part of it ("looking down on its crown", "looking down onto the lid").
        "(look|looks|looking) down (at|on|onto|into) (the |{P} )?{PARTS}",
        # The camera held up somewhere ("a drone hovering high", "perched up high", "mounted overhead").
        "(hovering|hanging|perched|floating|flying|mounted|suspended|poised|positioned|sitting|holding|staying|kept)"
        " (((high|well|far|way)( up)? )?(above|over)( {obj})?|high up|up high|way up|overhead|up above|high)(?! (in|on|at) )",
        "{GET} (up )?(high|higher)( up)?",
        "((shot|seen|shooting|taken|viewed|photographed) )?from (up )?(above|high)",
        # From over or from up, as other languages say "from above" ("von oben", "d'en haut"), the
        # clause ending there.
        "((shot|seen|shooting|taken|viewed|photographed) )?from (the )?(up|over|above|high)(?= ([,.;:!?]|$|and |with |but ))",
        # "From upper", a non-native "from above" ("von oben", "d'en haut"), the camera looking so too.
        "((shot|seen|shooting|taken|viewed|photographed|look|looks|looking) )?from (the )?(upper|more upper)( side)?"
        "(?= ([,.;:!?]|$|and |with |but |to |at |on |onto ))",
        "((shot|seen|shooting|taken|viewed|photographed) )?from high up",
        # "From the upside", a non-native "from above" (German "von oben", Dutch "van bovenaf").
        "((shot|seen|shooting|taken|viewed|photographed) )?from (the )?(upside|up side|topside)",
        "(from |at )?(a |an |the )?(higher|upper) (angle|position|viewpoint|vantage point|vantage)",
        # Said of a place up somewhere ("from higher up", "from on high", "from a height").
        "(from )?(higher up|on high|a height|up above)(?! (in|on|at|of) )",
        "{AIM}( the camera| the lens| it)? down( (at|on|onto|towards) {obj})?",
        # The camera said high, or a high camera ("camera high, looking at the mug", "a high camera").
        CAMERA + " (on |at )?(up )?(high|high up|up high)(?! (in|on|at) )(?= ([,.;!]|$|and |with |looking |near |above |over ))",
        "(a |an )?high (camera|lens)( (position|placement))?",
        ALONE.replace("{WORD}", "(high|high up|up high|way up)"),
        "(from )?(a |an )?high(?= (front|rear|back|side|three|profile|left|right) )",
        "(from )?(up high|high up|way above|up top)",
        "(from )?{VERY} (high up|up high|high|up)(?! (in|on|at) )",
        "((from |off )?(up )?(on|up|standing on|stood on|atop|at the top of|on top of|up on|halfway up) )?(a |the )?"
        "(step ?ladder|ladder|step stool|balcony|stairs|staircase)",
        "(from )?(up on|standing on|stood on|on top of) (a |the )?(chair|stool|table|box|crate|bench)",
        "((the )?(camera|lens) )?(held|kept|raised|lifted) (high|up high|high up|up)(?= ([,.;!]|$))",
        "(with )?(the )?(camera|lens) {AIM} (down|at the (floor|ground|grass))",
        # A camera or a drone's gimbal turned down ("gimbal facing down", "gimbal pointing down").
        "(the )?(camera|lens|gimbal) (is )?(facing|turned|{AIM}) down( (at|on|onto|towards) {obj})?",
        "((the )?(camera|lens) )?{AIM}( the camera| the lens)? (down )?{d} down",
        ALONE.replace("{WORD}", "(elevated|raised)"),
        "(shot|shoot|shoots|shooting|taken|filmed|framed|photographed) (high|high up|up high)(?! (in|on|at) )",
        # The camera put up on something tall ("camera high on a shelf", "lens up on the wardrobe").
        "(the )?(camera|lens) (placed |set |sitting |perched |put )?(high |high up |up high |up )on (top of )?(a |the )?"
        "(shelf|ledge|wardrobe|cupboard|cabinet|wall|mantelpiece|windowsill)",
        # An amount of height ("from a fair height", "at a decent elevation").
        "(from |at )?(a |quite a )?{AMOUNT} (height|elevation|altitude)",
        "(from )?(a |quite a )?({AMOUNT}|long) (way|bit|distance) (up|above)( {obj})?",
        # A place high above the scene ("from a first-floor window", "from upstairs", "off the rooftop").
        "((from|out of|at|on|up on|off|through) )?(a |an |the )?{HIGHPLACE}( {OPENING})?",
        # A height joined to a side ("from behind and above").
        "(?<= and )(from )?(above|overhead|up high|high up)(?= ([,.;!]|$))",
    ],
    "bird's-eye": [
        "((from|with|by|as|like) )?(a |the )?drone( 's)?( (shot|view|style|angle|camera|perspective|height))?"
        "( (hovering |high |right |straight )?(above|over) {obj})?",
    ],
    "low angle": [
        # From down or from under, as other languages say "from below" ("von unten"), the clause
        # ending there.
        "((shot|seen|shooting|taken|viewed|photographed) )?from (the )?(down|under|low)(?= ([,.;:!?]|$|and |with |but ))",
        "(look|looks|looking) up( (at|to|towards|into) {obj})?",
        "((shot|seen|shooting|taken|viewed|photographed) )?(up )?from (near |close to |down by |down on |low on )?(the |{P} )?"
        "(floor|ground|grass|lawn|roots|root)(?! (level|height) )( up(?= ([,.;!]|$)))?",
        "(from )?down (on|at) the (floor|ground|grass|lawn)",
        "{GET} (down )?(low|lower)( down)?",
        "((shot|seen|shooting|taken|viewed|photographed) )?(from|at) (the )?(ground|floor) (level|height)",
        "((shot|seen|shooting|taken|viewed|photographed) )?from (below|beneath|underneath)",
        "((shot|seen|shooting|taken|viewed|photographed) )?from (down )?(low|lower)( down)?",
        # A height before a view ("from a low front three-quarter", "a low side view").
        "(from )?(a |an )?low(?= (front|rear|back|side|three|profile|left|right) )",
        # A height alone as a clause ("the car from behind, low").
        ALONE.replace("{WORD}", "(low|low down|down low)"),
        "((the )?(camera|lens) )?(held|kept|lowered|dropped) (low|down low|low down|down)(?= ([,.;!]|$))",
        # A height named by the ground or a crouch ("knee height", "crouch down", "from the grass").
        "((with )?(the )?(camera|lens) )?((down |right |low )?(at|from) )?(the |a )?{ANCHOR_LOW} (height|level|high)",
        "(crouch|crouching|crouched|kneel|kneeling|knelt|squat|squatting)( down)?( low)?",
        "(from )?{VERY} (low|low down|down low)(?! (in|on|at) )",
        "(from |at )?(a )?lower (angle|position|viewpoint|vantage point|vantage)",
        "{AIM}( the camera| the lens| it)? up( (at|to|towards) {obj})?",
        # The camera said low, or a low camera ("CU on the bear, camera low", "a low camera near the floor").
        CAMERA + " (on |at )?(down )?(low|low down|down low)(?! (in|on|at) )(?= ([,.;!]|$|and |with |looking |near |by |under ))",
        "(a |an |the )?low (camera|lens)( (position|placement))?"
        "( (down )?(near|close to|by|low to|on|at|down on|down by) (the )?(ground|floor|grass|lawn))?",
        "(from )?(down low|low down|way down|down below)(?! (in|on|at) )",
        # A pitch said in degrees is a hint, as a pitch without them ("lens angled 15 degrees upward").
        "((the )?(camera|lens) )?{AIM}( the camera| the lens)? (up )?{d} up",
        # The camera itself down by the ground ("camera near the ground").
        CAMERA + " (right |low |flat )?(down )?(near|close to|by|low to|on|at|down on|down by) (the )?(ground|floor|grass|lawn)",
        # The camera resting on the floor ("camera lying on the rug"), shot low ("tail end, shot low").
        "(the )?(camera|lens) (is )?(lying|laid|resting|sitting|placed|set|put|flat|down)( down| flat)? on the "
        "(floor|ground|rug|carpet|grass|lawn|mat)",
        # The photographer lying down, said of oneself or as if ("lie flat on the grass", "as if you
        # were lying on the table", "lying on my belly"): the eye a little above what the subject
        # stands on, below the subject (parse20h). Said of a subject ("the bear lying on the rug") it
        # is where the subject rests (PLACE_PHRASES).
        "(" + AS_IF + " )?(you|i|we|one|someone|somebody|the photographer) (were |was |are |is |am |m |re |should be |must be )?"
        "(lying|laying|lie|lay)( down)?( flat)?( (on|in) {LIEON})?",
        "((?<=^ )|{CLAUSE}|(?<= and ))(lie|lay|get)( down)? (flat|prone|down|on (your|the) (belly|stomach|tummy|front|back))"
        "( (on|in) {LIEON})?",
        # The camera on what the subject stands on, pitched up at it ("cam resting on the tabletop
        # pitched up at it"): below the subject; without the pitch it is level with it (parse20h).
        "(the )?(camera|lens|cam) (is )?(lying|resting|sitting|placed|set|put|standing)( down| flat)? on the "
        "({SURFACE}|tabletop|table top|{SUPPORT})( ,)? (and )?((pitched|tilted|angled|aimed|pointing|pointed|looking|peering"
        "|{AIM}) )?up( (at|to|towards) {obj})?",
        "(shot|shoot|shoots|shooting|taken|filmed|framed|photographed) (low|low down|down low)(?! (in|on|at) )",
        "(?<= and )(from )?(below|beneath|down low|low down)(?= ([,.;!]|$))",
        # The camera at the subject's foot or under its crown ("right by the trunk", "at its foot",
        # "from the base of the stem", "under the canopy"); not a place of another object ("the
        # ball at the foot of the tree").
        "((right|close|just|up|down) )?(by|at|near|beside|next to|against|close to|from) (the |{P} )(foot|feet|base|trunk"
        "|roots|stem|legs)( of (it|them|(the |{P} )?(trunk|stem)))?(?! (of|level|height|line) )",
        "((right|close|just|standing|stood|down) )?(under|beneath|underneath|below) (the |{P} )(canopy|crown|branches|boughs"
        "|leaves|foliage|fronds|shade|lampshade)(?! (of|level|height|line) )",
        # Looking up at a part of it ("looking up at the shade", "looking up the trunk").
        "(look|looks|looking) up (at |to |towards |into |along )?(the |{P} )?{PARTS}",
    ],
}
# "<creature>'s-eye view" (vocabulary.EYE_VIEWS): the elevation class of whose eye it is; said
# without the eye it needs a view noun ("bird perspective", "an ant's view"), or says whose eyes
# see it ("as a frog would see it", "from the point of view of an ant").
for _elevation_class, _creatures in EYE_VIEWS.items():
    _creature = "(" + "|".join(sorted(_creatures, key=len, reverse=True)) + ")"
    ELEVATION_PHRASES[_elevation_class] += [
        # Said as roughly that ("almost worm's eye", "nearly a bird's-eye view"): the class's
        # own range allows for it. "Eye" may be written by ear as "I" before its noun ("a birds I
        # view", "worm I level": parse20h).
        "(from |in |as |through )?({NEARLY} |mostly |roughly |kind of |sort of )?(a |an |the )?"
        + _creature
        + "( 's)? (eyes?( ({EYENOUN}|level))?|i ({EYENOUN}|level))",
        "(from |in |as |through )?({NEARLY} |mostly |roughly |kind of |sort of )?(a |an |the )?" + _creature + "( 's)? {EYENOUN}",
        # As it sees things, said any way ("the way a bird sees it", "how birds see it", "as a bird
        # would look at it", "as seen by a frog"), or the creature alone ("from above, like a bird").
        "(as|like|the way|how|in the way) (a |an |the )?" + _creature + "s?"
        " (sees|would see|might see|see|views|would view|would look at|looks at|look at|would|does|do)"
        "( it| them| {obj}| things)?",
        "(as )?seen (by|through the eyes of) (a |an |the )?" + _creature + "s?",
        "(like|as) (a |an |the )?" + _creature + "s?(?= ([,.;!]|$|and |but ))",
        "(from |through )?(the )?({EYENOUN}|eyes) of (a |an )?" + _creature,
    ]

# The camera aimed straight at what the subject stands on ("camera pointing straight at the
# tabletop", "lens aimed squarely at the desk", "cam facing perpendicular to the floor"): looking
# straight down. Without "straight" only the floor-like surfaces already above say so.
# A lamp's shade as a height ("camera at the height of the shade"): the lamp's own height. Not a
# height anchor: "a shade higher" is a degree; and no "lamp" here, which would make it a word of
# the tables, so an unknown "ceiling lamp above the sofa" would no longer be a thing.
ELEVATION_PHRASES["eye level"].append("((the )?(camera|lens) )?(at|from) the (height|level) of (the|{P}) (lampshade|shade)")
ELEVATION_PHRASES["top-down"] += [
    "(with )?(the |your |my )?(camera|lens|cam|gimbal)( (is|was|should be))? ({AIM}|{LOOK}|facing|turned)"
    "(( {DOWNRIGHT}){1,2}| perpendicularly| perpendicular)( down)?( (at|towards|to|into|onto))? (the |a )?"
    "({SUPPORT}|table|desk|counter|countertop)( (top|surface))?",
    "(with )?(the |your |my )?(camera|lens|cam|gimbal)( (is|was|should be))? ({AIM}|facing|turned)( down)?"
    " ((at|towards|to|into|onto) )?(the |a )?({SUPPORT}|table|desk|counter|countertop)( (top|surface))?",
]

# Straight up from below, the mirror of top-down: the camera vertically under the subject, -90
# degrees (its explicit tolerance keeps -90 to -80, as top-down keeps 80 to 90). The held-out
# specs read it so ("looking straight up": -90, or a worm's-eye range holding it).
VERTICAL_UP_DEG = -90.0
VERTICAL_UP_PHRASES = [
    "looking ({NEARLY} )?(straight|directly|vertically) up( at {obj})?",
    # The camera pointed vertically up ("pointing the lens straight up").
    "{AIM}( the camera| the lens)? (straight|directly|vertically) up( (at|to|towards) {obj})?",
    "(with )?(the )?(camera|lens) {AIM} (straight|directly|vertically) up",
    # The zenith: the point straight above the camera.
    "(a |an |the )?zenith( (shot|view|angle|perspective))?",
    "from the ground( level)?( ,)? looking straight up( at {obj})?",
    "(from )?(directly|straight|right) (below|beneath|underneath|under)( {obj}| {P} {PARTS})?",
    "(looking )?(straight|directly|right) up (at|into|under) ({P} [a-z]+|{obj}|the (bottom|underside|base) of {obj})",
    "straight up at {obj}",
    # The camera turned as far up as it goes, maybe through what the subject stands on ("LENS
    # STRAIGHT UP THROUGH THE TOP", "camera tilted all the way up", "lens facing straight up").
    "(the )?(camera|lens|gimbal)( (is|was))?( ({AIM}|facing|turned|looking))?( the (camera|lens))? ({NEARLY} )?{FULLY} up"
    "( (at|to|towards) {obj})?{THROUGH}",
    "{AIM}( the camera| the lens| it)? {FULLY} up( (at|to|towards|into) ({obj}|(the |{P} ){PARTS}))?{THROUGH}",
    "(the )?(camera|lens|gimbal)( (is|was))?( ({AIM}|facing|turned|looking))? up (vertically|straight|fully){THROUGH}",
    # Pointed at the sky or the ceiling ("lens pointing skyward", "camera facing the ceiling"); a
    # camera "at the ceiling" is up there, looking down.
    "((the )?(camera|lens|gimbal) )?(({AIM}|facing|turned|looking|staring|gazing) )?(skyward|skywards|heavenward|heavenwards)",
    "((the )?(camera|lens|gimbal) )?({AIM}|facing|turned|looking|staring|gazing) ((at|to|towards|into) )?the "
    "(sky|heavens|zenith|ceiling)",
]

# A drone gimbal's pitch: the angle the camera looks down, written with either sign ("gimbal at 90",
# "gimbal -45", "gimbal pitched down about 50 degrees"); its magnitude is the elevation (an aircraft
# looks down on what it shoots). "Up" after it is no such pitch.
GIMBAL_PHRASES = [
    "(the )?(drone 's )?gimbal( ({AIM}|facing|turned|looking|set|at|to|of|is|:))*( down)? ({ABOUT} )?{sd}( down)?(?! up )",
]

# What follows degrees that belong to something else than the height word before them ("top down,
# 10 degrees to the left", "low angle, 10 degrees dutch clockwise").
NOT_A_HEIGHT_TAIL = (
    "(?! (above|below|up|down|high|higher|low|lower|overhead|off|round|around|to|clockwise|counterclockwise"
    "|dutch|roll|rolled|cant|canted|tilt|twist) )"
)
# Who looks, when the subject's angle is said from the camera ("the bench is 70 degrees below us").
OBSERVER = "(us|me|you|the camera|the lens|the cam|the drone)"
# Explicit elevations, by sign (+ above, - below); {sd} carries its own sign.
EXPLICIT_ELEVATION_PHRASES = {
    1.0: [
        # "around 30 degrees up" (not a pitch: "tilted 10 degrees up" is a low-angle hint).
        "(?<!tilted )(?<!tilt )(?<!tilting )(?<!pitched )(?<!angled )(?<!aimed )(?<!pointed )(?<!pointing )"
        "{d} (up|overhead)( (from|above|off) (the )?(ground|horizontal|horizon|level|{obj}))?",
        # The camera looking N degrees down is N degrees above (a pitch said with "tilted" or
        # "angled" stays a hint, as "up" does).
        "(?<!tilted )(?<!tilt )(?<!tilting )(?<!pitched )(?<!angled )(?<!aimed )(?<!pointed )(?<!pointing )"
        "((with )?(the )?(camera|lens) )?{d}(?<= degrees) down( (at|on|onto|towards) {obj})?"
        "(?! (from|to|the|its|his|her|their|left|right) )",
        "(from |at )?{d} above( {obj}|( the)? horizon|( the)? horizontal|( the)? ground|( the)? floor)?",
        # Pointing N degrees below the horizontal: looking down, so above (parse18p6).
        "((the )?(camera|lens|cam) )?((so )?(it |that it )?)?{AIM}( down)? {d}(?<= degrees) (below|under|beneath) (the )?"
        "(horizontal|horizon|level)",
        # The angle, then where from ("approx. 30 degrees from above", "25 degrees over it",
        # "10 degrees above its centre").
        "(from |at )?({ABOUT} )?{d}(?<= degrees) from (up )?(above|overhead|on high|up high|high up|up above|the top)",
        "(from |at )?({ABOUT} )?{d}(?<= degrees) (above|over|higher than)( {ELEVREF})?",
        "(from |at )?(a )?(height|elevation) of ({ABOUT} )?{d}(?<= degrees)( (up|above))?",
        # A bare number with its article and direction ("at a 45 from above", "a high 45").
        "(at |from )?(a |an )(high |steep )?{n}( degrees)?( angle)? (from )?(above|overhead)",
        "(a |an )high {n}(?= ([,.;!]|$))",
        # A steep angle given ("from a steep seventy degrees", "at a steep 60 degree angle"): steep is
        # said only of looking down (parse20h).
        "(at |from )?(a |an )?steep ({ABOUT} )?{d}(?<= degrees)( angle)?( (from )?(above|overhead))?",
        # The camera up by the angle, said plainly ("lens up around 35 degrees", "cam up 40 degrees"): no
        # verb of pointing before "up", so the camera's place, not its pitch (parse20h).
        "(the )?(camera|lens|cam) (is )?(up|high|high up|up high) ({ABOUT} )?{d}(?<= degrees)(?! (left|right|to|round|around) )",
        "(from |at )?(a |an )?{d} angle (from )?(above|overhead)",
        "with the camera {d} above {obj}",
        "looking down( at {obj})? from {d} above",
        # The angle's direction may follow it ("shoot down at it from about 40 degrees above it", "looked
        # down on from 60 degrees").
        "(looking|look|looks|looked|{AIM}) down( (at|on|onto)( {obj})?)? (at|from|by) ({ABOUT} )?(an angle of )?{d}"
        "( (above|over)( {ELEVREF})?)?",
        "(looking|look|looks|{AIM}) down( (at|on|onto) {obj})? ({ABOUT} )?{d}(?<= degrees)",
        "(at |from |with )?(an |a )?(camera )?(elevation|elevation angle) of {sd}",
        "(at |from |with )?(an |a )?{sd} (elevation|elevation angle)",
        "(at |from |with )?(an |a )?{d} (high angle|down angle)",
        # The camera raised by the angle ("elevate the lens twenty degrees", "raise the camera 30° up").
        "(elevate|elevated|elevating|raise|raised|raising|lift|lifted|lifting) (the )?(camera|lens|cam|view|viewpoint|angle)"
        "( by)? {d}(?<= degrees)( (up|higher|above))?",
        # Degrees and the way the camera points ("at a 45 degree angle looking down").
        "(at |from )?(a |an )?{d}(?<= degrees) angle( ,)? (looking|pointing|{AIM}) down( (at|on|onto) {obj})?",
        "(looking|look|looks|{AIM}) down( (at|on|onto) {obj})? (at|from) (a |an )?{d}(?<= degrees) angle",
        "elevated (by )?({ABOUT} )?{d}",
        # The camera raised by or to an angle ("camera raised 30 degrees", "lifted to about 35°").
        "((the )?(camera|lens) )?(elevated|raised|lifted|hoisted)( up)? (by |to )?({ABOUT} )?{d}(?<= degrees)"
        "( (above|over|off|from) (the )?(horizontal|horizon|ground|floor|level))?",
        # An angle said with the way it looks ("a 60 degree overhead angle", "a downward angle of
        # 30 degrees", "at an angle of 40 degrees from above", "angle: 40 deg down").
        "(at |from )?(a |an )?{d}(?<= degrees) (overhead|down|high|top|elevated|elevation|downwards?) angle",
        "(at |from )?(a |an )?(down|high|overhead|top|elevated|steep) angle (of )?({ABOUT} )?{d}(?<= degrees)",
        "(at |from )?(an |a )?angle of ({ABOUT} )?{d}(?<= degrees)( ,)? (from )?(above|overhead)",
        "(angle|elevation|height) : ({ABOUT} )?{d}(?<= degrees)( (up|down|above))?",
        # Degrees from the ground or the horizontal ("at 30 degrees from the ground").
        "(at |from )?({ABOUT} )?{d}(?<= degrees) (from|off) (the )?(ground|floor|horizontal|horizon)",
        # Degrees higher than the subject, or an elevation named then given ("elevation about 20 degrees").
        "((the )?camera )?{d}(?<= degrees) (higher|over) than {obj}",
        "((the )?camera )?(elevation|elevation angle)( of| at| ,| :)? ({ABOUT} )?{sd}",
        # "10 degrees high": the degrees said, so a height word is no size ("2 high").
        "{d}(?<= degrees) (high|higher|up high)(?! (in|on|at) )",
        "((seen|shot|viewed|photographed) )?from above( ,)? at (an angle of )?{d}",
        # An elevation named, then its degrees ("overhead view of the cushion, about 70 degrees").
        "{HIGHVIEW}( of {obj})?( ,)? ((at|from) )?({ABOUT} )?{d}(?<= degrees)" + NOT_A_HEIGHT_TAIL,
        # A bare number right after a height word, ending its clause ("overhead 90", "top down, 85").
        "{HIGHVIEW}( ,)? ((at|from|of) )?({ABOUT} )?{n}(?= ([,.;!]|$))",
        # The subject's angle from the camera ("hover so the bench is 70 degrees below us"): the
        # camera is that far above it.
        "{obj} (is |sits |lies |stands )?({ABOUT} )?{d}(?<= degrees) (below|under|beneath|underneath|down from) " + OBSERVER,
    ],
    -1.0: [
        "(from |at )?{d} below( {obj}|( the)? horizon|( the)? horizontal|( the)? ground|( the)? floor)?",
        # Pointing N degrees above the horizontal: looking up, so below (parse18p6).
        "((the )?(camera|lens|cam) )?((so )?(it |that it )?)?{AIM}( up)? {d}(?<= degrees) (above|over) (the )?"
        "(horizontal|horizon|level)",
        "(from |at )?({ABOUT} )?{d}(?<= degrees) from (down )?(below|beneath|underneath|down low|low down|down below)",
        "(from |at )?({ABOUT} )?{d}(?<= degrees) (below|under|beneath|underneath|lower than)( {ELEVREF})?",
        "(from |at )?{d}(?<= degrees) (under|beneath|underneath)( {obj})?",
        "(at |from )?(a |an )?{d}(?<= degrees) angle( ,)? (looking|pointing|{AIM}) up( (at|to|towards) {obj})?",
        "(looking|look|looks|{AIM}) up( (at|to|towards) {obj})? (at|from) (a |an )?{d}(?<= degrees) angle",
        "(from |at )?(a |an )?{d} angle (from )?below",
        "with the camera {d} below {obj}",
        "((the )?camera )?{d}(?<= degrees) lower than {obj}",
        "looking up( at {obj})? from {d} below",
        "(looking|look|looks|looked|{AIM}) up( (at|on|onto|to)( {obj})?)? (at|from|by) ({ABOUT} )?(an angle of )?{d}"
        "( (below|under|beneath|underneath)( {ELEVREF})?)?",
        "(looking|look|looks|{AIM}) up( (at|on|onto) {obj})? ({ABOUT} )?{d}(?<= degrees)",
        "(at |from |with )?(an |a )?{d} (low angle|up angle)",
        "((the )?(camera|lens) )?(lowered|dropped|sunk)( down)? (by |to )?({ABOUT} )?{d}(?<= degrees)"
        "( (below|under|beneath) (the )?(horizontal|horizon|level))?",
        "(at |from )?(a |an )?{d}(?<= degrees) (low|upwards?|up|worm 's eye) angle",
        "(at |from )?(a |an )?(up|low|upward) angle (of )?({ABOUT} )?{d}(?<= degrees)",
        "(at |from )?(an |a )?angle of ({ABOUT} )?{d}(?<= degrees)( ,)? (from )?(below|beneath|underneath)",
        "((seen|shot|viewed|photographed) )?from below( ,)? at (an angle of )?{d}",
        "{LOWVIEW}( of {obj})?( ,)? ((at|from) )?({ABOUT} )?{d}(?<= degrees)" + NOT_A_HEIGHT_TAIL,
        "{LOWVIEW}( ,)? ((at|from|of) )?({ABOUT} )?{n}(?= ([,.;!]|$))",
        "{obj} (is |sits |stands |towers )?({ABOUT} )?{d}(?<= degrees) (above|over|up from) " + OBSERVER,
    ],
}

# Degrees "of" or "in" elevation, as a surveyor says it ("viewed from forty degrees of elevation",
# "at -20 degrees in elevation", "twenty degrees of camera elevation"); its sign is the number's.
EXPLICIT_ELEVATION_PHRASES[1.0] += [
    "({SEEN_VERB} )?((at|from|with) )?(a |an )?{sd}(?<= degrees) (of|in) ((the )?camera )?(elevation angle|elevation)",
]

# A pitch in degrees, as a drone's or a gimbal's is given ("pitch 60 degrees down onto it", "at
# about 60 degrees pitch down", "camera pitched 45 degrees down"): the angle itself, which wins over
# the drone or the orbit said with it. Tilting or angling by degrees stays a hint (it may be counted
# from where the camera was).
PITCH = "(pitch|pitched|pitching)"
for _sign, _way in ((1.0, "down"), (-1.0, "up")):
    EXPLICIT_ELEVATION_PHRASES[_sign] += [
        "((the )?(camera|lens|gimbal|drone) )?"
        + PITCH
        + "( (the|its) (camera|lens|gimbal))? {d}(?<= degrees) "
        + _way
        + "( (at|on|onto|towards|to) {obj})?",
        "((the )?(camera|lens|gimbal|drone) )?" + PITCH + "( (the|its) (camera|lens|gimbal))? " + _way + " {d}(?<= degrees)"
        "( (at|on|onto|towards|to) {obj})?",
        "((at|with) )?(a )?{d}(?<= degrees)( of)? pitch " + _way + "( (at|on|onto|towards|to) {obj})?",
        "(a )?pitch (of )?{d}(?<= degrees) " + _way + "( (at|on|onto|towards|to) {obj})?",
    ]

# An angle said alone ("from way up, like 70 deg", "a fair height, about sixty degrees", "looking
# down on it from a drone, about 60 degrees"): an elevation only with a height said in the same
# sentence, nearer to it than any side or roll (:func:`_bare_angles` gives it that height's sign),
# else it stays not understood. Degrees that turn the camera round or about its axis are no height.
BARE_ANGLE_PHRASES = [
    "((at|from|by|of|like|say|to) )?({ABOUT} )?{d}(?<= degrees)( or so| or thereabouts)?"
    "(?! (round|around|off|to|towards|toward|left|right|clockwise|counterclockwise|from|of|turn|rotation|roll"
    "|tilt|cant|dutch|and|or|azimuth|up|down|above|below|high|higher|low|lower|overhead|under|beneath|underneath"
    "|elevation|angle|pitch) )",
    # A signed angle ("camera at minus fifteen degrees, i.e. beneath it looking up"): kept only where
    # the height said nearest is below the horizontal too (:func:`_bare_angles`; parse20h).
    "((at|from|of|to) )?({ABOUT} )?{negd}(?<= degrees)"
    "(?! (round|around|off|to|towards|toward|left|right|clockwise|counterclockwise|from|of|turn|rotation|roll"
    "|tilt|cant|dutch|and|or|azimuth|up|down|above|below|high|higher|low|lower|overhead|under|beneath|underneath"
    "|elevation|angle|pitch) )",
]
# Words before an angle that make it a turn, not a height ("swung 30 degrees", "rotate it 20 degrees").
TURN_WORDS = frozenset(
    {"turn", "turned", "turning", "rotate", "rotated", "rotating", "swing", "swung", "swinging", "spin", "spun"}
    | {"orbit", "orbited", "orbiting", "pan", "panned", "panning", "roll", "rolled", "rolling", "yaw", "yawed"}
    | {"it", "them", "round", "around"}
)

# Words that ask nothing of the camera beyond what a subject already asks (to be seen): where a
# subject rests ("the bear on the floor") and its being in the picture ("in the same shot").
PLACE_PHRASES = [
    "(?<=@\\d )((sitting|lying|standing|resting|placed|left|parked|sat) )?(on|upon|by|against) (the )?"
    "(floor|ground|grass|lawn|carpet|rug)(?! (level|height))",
]
# A subject asked only to be in the picture ("the bench in the frame too", "the cone should be in
# the picture too", "all in view"): understood, and such a subject takes no size, place or side
# said in a later clause of its own; those belong to the subject the picture is of ("cushion
# bottom left, bench in the frame too, wide": a wide cushion).
SEEN_PHRASES = [
    # Made to show up too ("make sure the teddy shows up too", "with the cone showing as well").
    "((make sure|so that|so) )?(shows|show|showing|turns|turn|turning|appears|appear) up( (in|within) (the )?{FRAME})?"
    "( too| as well| also)?(?= ([,.;!?]|$|and |with ))",
    "(is |are |be )?(showing|visible|seen|in view|in shot|in frame)( too| as well| also)(?= ([,.;!?]|$|and |with ))",
    "(all |both |each )?(visible |seen |showing )?(somewhere )?(in|within|inside) (the )?(same )?"
    "(shot|frame|picture|photo|image|pic|view)( too| as well| also)?(?= ([,.;!]|$|and |with ))",
]
# Words that label or wrap the request and ask nothing of the camera: a shot list's slate ("SC 12",
# "SHOT 6 -"), a screenplay's scene heading ("INT. LIVING ROOM - DAY"), courtesies ("if it isn't
# too much trouble"); the axis a roll turns about
# ("spun 15 degrees clockwise about the lens axis"): the roll itself is read apart.
NOTE_PHRASES = [
    # A hedge on an amount said before ("twenty-five degrees off its face, give or take a few").
    "give or take( (a (few|bit|little|touch)|some|a few degrees))?",
    # Its number may carry a letter ("Storyboard 7B", "shot 12 a,"), read apart by vocabulary.words.
    "((?<=^ )|{CLAUSE})(" + "|".join(SLATE_LABELS) + ") \\d+([a-z]| [a-z](?= ([,.;:!]|$)))?",
    # How many subjects the frame holds, each named anyway ("all three in frame", "a two-shot").
    "(all|both) (2|3|4|5)( of them)?( (in|within|inside) (the )?{FRAME})?",
    # A two-shot (three-shot) names how many subjects the frame holds, each named anyway.
    "(a |an )?(2|3) (shot|shots)",
    "((?<=^ )|{CLAUSE})(" + "|".join(SCENE_HEADINGS) + ")( \\.)?(( (int|ext))( \\.)?)?( [a-z]+){1,4}"
    "( , (" + "|".join(HEADING_TIMES) + "))?(?= ([,.;:!]|$))",
    "(" + "|".join(sorted(COURTESIES, key=len, reverse=True)) + ")",
    # The setting the picture is taken in ("of the lounge", "the garden:", "kitchen scene").
    # Not said as where the camera is ("from across the room": a distance, reported) nor before a
    # name it describes ("garden sofa").
    "(?<!across )(?<!around )(?<!through )((the|this|my|our|a|an|your) ((whole|entire) )?|(?<=^ )|{CLAUSE})"
    + "("
    + "|".join(sorted(SETTINGS, key=len, reverse=True))
    + ")"
    + "( (scene|shot|space|area|interior))?(?= ([,.;:!]|$|the |with |where |and ))",
    # Who asks for the picture, or whom it is for ("my grandson would like", "for the client").
    "((?<=^ )|{CLAUSE})((my|our|the|your|a|his|her) )?([a-z]+ )??("
    + "|".join(sorted(REQUESTERS, key=len, reverse=True))
    + ")( ("
    + "|".join(WANTING)
    + ")( (to have|to see|to get))?(?= )|(?= ([,.;:!]|$)))",
    "(for|from) (my|our|the|your|his|her) ([a-z]+ )??(" + "|".join(REQUESTERS) + ")(?= ([,.;:!]|$))",
    # Asking that something holds ("make sure the teddy shows up too"): what holds is read apart.
    "(make|making) sure( that)?",
    # The picture as the result ("in the final image the horizon slopes ..."): what it shows is read apart.
    "(in |on )?(the )?(final|finished|resulting|eventual|end) {FRAME}",
    # What the picture is for ("Shop product pic:", "Listing photo for the model car", "real-estate
    # shot:"): no constraint on the camera.
    "{PURPOSE}( {PURPOSE})? (shot|shots|photo|photos|pic|pics|picture|pictures|image|images|photograph|snap|snaps)"
    "(?= ([,.;:!]|$|for ))",
    "(about|around|round|on|along) (the |its |{P} )?(lens|optical|camera|camera 's|viewing|roll|shooting) axis",
    # The camera or lens named before the height or place the next words give ("lens a hair above its
    # head", "camera at the same height as the cushion"): the height is read from those words.
    CAMERA
    + "( (raised|lifted|lowered|dropped|held|hoisted|brought))?"
    + "(?= ({WEAK}|just|right|slightly|well|way|at|from|level|above|below|under|over|beneath|higher|lower|{AIM}|looking) )",
    # Placing the camera, said before what it should achieve ("position the camera so the tv faces it").
    "(position|move|put|place|set|bring|get) (the )?(camera|lens)( so( that)?)?(?= @| the | it )",
]
# Where the light comes from ("the light coming from the left", "sun from behind", "backlit from
# the right"): no view of the subject and no thing in the scene, but a wish the camera alone does
# not keep (the scene's light is baked in), so its words are reported as not understood.
LIGHT_PHRASES = [
    "((the|soft|hard|warm|cold|morning|evening|natural|window|key|main) )*(light|lighting|sun|sunlight|daylight|sunshine"
    "|shadows?|glow)( is| are)?( (coming|falling|shining|streaming|pouring|entering|spilling|hitting|lighting it))?( in)?"
    " from (the |{P} )?(left|right|above|below|behind|front|side|back|top|window|[a-z]+ side)( side)?",
    "((back|side|top|front|rim) ?lit|lit) from (the |{P} )?(left|right|above|below|behind|front|side|back|top)( side)?",
]
# Where in depth a subject stands ("the tree behind it", "the plant in the back too", "in the
# background"): it too is only asked to be seen as far as cues go, but the depth order is no
# constraint the camera keeps, so these words stay reported as not understood.
DEPTH_WORDS = frozenset({"behind", "beyond", "background", "back", "distance", "foreground"})

# The roll family as parts, in any order around a number and a direction: a verb or noun of
# turning about the lens axis, what is turned (the camera, or the picture, which turns the other
# way), where ("sideways", "about the lens axis"). "15 degrees of tilt clockwise", "20 degree
# clockwise camera rotation", "spin the camera 20 degrees clockwise on its axis".
ROLL_VERB_FORMS = (
    "(roll|rolled|rolling|tilt|tilted|tilting|cant|canted|rotate|rotated|rotating|turn|turned|twist|twisted|spin|spun"
    "|lean|leaned|leaning|bank|banked|dutch|dutched|skew|skewed|tip|tipped|cock|cocked|angle|angled|swing|swung)"
)
ROLL_NOUNS = "(roll|rolling|tilt|tilting|cant|canting|dutch|dutch angle|dutch tilt|rotation|lean|skew|slant|twist|spin|bank)"
ROLL_AXIS = (
    "(sideways|on its axis|on the lens axis|(about|around|round) (its|the) (own |lens |optical |viewing )?axis"
    "|(about|around|round) the lens)"
)
# The frame is the camera's rectangle: it turns with the camera ("frame rotated ten degrees
# clockwise"); the picture's content turns the other way.
# "Everything" is the whole frame the camera turns ("cant everything 20 degrees clockwise"; the
# rig is the camera: COMPOUNDS).
CAMERA_THING = "((the )?(whole |entire )?(camera|lens|cam|frame|framing)|everything)"
PICTURE_THING = "(the )?(whole |entire )?(picture|image|scene|photo|{HORIZON})"


# A roll's direction as a side: the camera's top going to that side ("rolled to the left",
# "a 10 degree right roll", "a leftward cant"): right is clockwise. "Of" after it makes a place
# ("to the left of the bear").
ROLL_SIDE = "((to |towards )?(the )?{side}( hand| side|wards?)?)(?! of )"
ROLL_SIDE_ADJECTIVE = "({side}( hand|wards?)?)"
ROLL_DIRECTION = "({dir}|" + ROLL_SIDE + ")"
# What a line does that is not level ("the horizon doesn't slope", "leaning neither way").
LEVEL_BREAKING = (
    "slope|sloping|slant|slanting|tilt|tilting|tilted|lean|leaning|leaned|leant|tip|tipping|tipped|dip|dipping"
    "|roll|rolling|rolled|cant|canting|canted|go crooked|run crooked|sit crooked"
)
# How a dutch angle goes to its side ("a dutch angle leaning left").
LEANING = "(leaning|leant|leaned|tilted|tilting|rolled|rolling|canted|canting|tipped|tipping|going|sloping)"
NOT_A_ROLL_SIDE = "(?! (of|side|third|half|edge|corner|part|profile|flank|view|angle)( |$))"
# Verbs that turn the camera about its lens axis only: said with a side they roll it. "Turn",
# "swing" and "angle" the camera to a side may aim it instead, and are a roll with a side only
# about the lens axis.
ROLL_SIDE_VERBS = "(roll|rolled|rolling|tilt|tilted|tilting|cant|canted|rotate|rotated|rotating|twist|twisted|spin|spun"
ROLL_SIDE_VERBS += "|lean|leaned|leaning|bank|banked|dutch|dutched|skew|skewed|tip|tipped|cock|cocked)"
# Giving the camera a roll ("give the camera 30 degrees clockwise", "apply a 15 degree tilt to the lens").
GIVE = (
    "(give|giving|gave|put|putting|apply|applying|applied|add|adding|added|dial in|dialling in|dialing in|set"
    "|hold|holding|keep|keeping)"
)


NEGATIVE_AGAIN = "( \\x28 counterclockwise \\x29)?"  # brackets as escapes: a bare "(" is a group
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

# Said between a roll's parts (parse18p6): a particle after its verb ("lean the camera over by
# 20 degrees"), a slight word or a comma before its degrees ("roll the camera to the left, 18
# degrees"; "tip it sideways a little, 10 degrees clockwise"), a size word before them ("a slight
# 8 degree cant ..."); the direction's own periphrases are in {dir}.
ROLL_OVER = "( over| round| across)?"
ROLL_PAUSE = "( {WEAK})?( ,)?"
ROLL_MILD = "(" + "|".join(DUTCH_SIZE_DEG) + ")"


def _roll_family(thing: str) -> list[str]:
    """Roll templates about ``thing`` (what turns): a verb or noun of turning, a number and a
    direction (clockwise, or a side) said once, in any order; a side needs the thing or the axis;
    also the thing given degrees or a share of a turn ("give the camera 30 degrees clockwise")."""
    verb = f"({thing} )?{ROLL_VERB_FORMS}"
    giving = f"({GIVE}( {thing}| it)? )?"  # "apply a 15 degree clockwise tilt (to the camera)"
    to_thing = f"( (to|on|for) {thing})?"
    return [
        f"{verb}( {thing}| it)?( {ROLL_AXIS})?( by| through)? {{d}}( {ROLL_AXIS})? {{dir}}( {ROLL_AXIS})?",
        f"{verb} ({thing}|it){ROLL_OVER}( {ROLL_AXIS})?{ROLL_PAUSE}( by| through)? {{d}}( {ROLL_AXIS})?( ,)? {{dir}}"
        f"( {ROLL_AXIS})?",
        f"{verb}( {thing}| it)?( {ROLL_AXIS})? {{dir}}( {ROLL_AXIS})?( by| through)? {{d}}( {ROLL_AXIS})?",
        f"{giving}(a |an )?{{d}}( of)? {{dir}}( {thing})? {ROLL_NOUNS}( {ROLL_AXIS})?{to_thing}",
        f"{giving}(a |an )?({ROLL_MILD} )?{{d}}( of)?( {thing})? {ROLL_NOUNS}( ,)? {ROLL_DIRECTION}( {ROLL_AXIS})?{to_thing}",
        f"{thing} at (a |an )?{{d}} (angle|slant|tilt) {{dir}}",
        # A side as the direction, with the thing turned or the lens axis said.
        f"{ROLL_SIDE_VERBS} {thing}( {ROLL_AXIS})?( by| through)? {{d}}( {ROLL_AXIS})? {ROLL_SIDE}( {ROLL_AXIS})?",
        f"{ROLL_SIDE_VERBS} {thing}( {ROLL_AXIS})? {ROLL_SIDE}( {ROLL_AXIS})?{ROLL_PAUSE}( by| through)? {{d}}( {ROLL_AXIS})?",
        f"{verb}( {thing}| it)?( by| through)? {{d}} {ROLL_SIDE} {ROLL_AXIS}",
        f"{verb}( {thing}| it)? {ROLL_AXIS}( by| through)? {{d}} {ROLL_SIDE}",
        f"{verb}( {thing}| it)? {ROLL_AXIS} {ROLL_SIDE}( by| through)? {{d}}",
        # A side said as the roll's adjective ("a 10 degree right roll", "a right-hand cant of 12").
        f"{giving}(a |an )?{{d}}( of)? {ROLL_SIDE_ADJECTIVE}( {thing})? {ROLL_NOUNS}( {ROLL_AXIS})?{to_thing}",
        f"{giving}(a |an )?{ROLL_SIDE_ADJECTIVE}( {thing})? {ROLL_NOUNS}( of)? {{d}}{to_thing}",
        # Given degrees or a share of a turn ("give the camera one twelfth of a turn clockwise").
        f"{GIVE} {thing} (a |an )?{{d}}( turn| of (a )?turn)?( {ROLL_AXIS})? {ROLL_DIRECTION}( {ROLL_AXIS})?",
        f"{GIVE} {thing} {ROLL_DIRECTION} (a |an )?{{d}}( turn| of (a )?turn)?",
        # A negative number about the lens axis is counter-clockwise, maybe said again in brackets
        # ("camera turned -15 degrees about its axis (counterclockwise)"); an unsigned one without
        # a direction says no way to turn.
        f"{verb}( {thing}| it)?( {ROLL_AXIS})?( by| through)? {{negd}} {ROLL_AXIS}{NEGATIVE_AGAIN}",
        f"{verb}( {thing}| it)? {ROLL_AXIS}( by| through)? {{negd}}{NEGATIVE_AGAIN}",
    ]


# Roll phrases, by how they relate to the camera's roll: +1 they describe the camera, -1 the
# picture (a horizon rotated clockwise means the camera rolled counter-clockwise), 0 a level camera.
ROLL_PHRASES = {
    1.0: [
        "(with )?(a |an )?{d}( {dir})? (dutch|canted)( (angle|tilt))?",
        "(with )?(a |an )?({dir} )?(dutch|canted)( (angle|tilt))?( of)? {d}( {dir})?( (frame|shot|view|composition))?",
        "(with )?(the )?camera (rolled|tilted|rotated|canted|turned|leaning) (by )?{d} {dir}",
        "(rolled|tilted|rotated|canted|turned) (by |through )?{d} {dir}",
        "(rolled|tilted|rotated|canted|turned) {dir} (by )?{d}",
        "((with )?(the )?camera )?(rolled|tilted|rotated|canted|leaning) (by )?({d} )?(to the )?{side}",
        "(with )?(the )?camera (rolled|rotated|canted) {dir}",
        "(with )?(a |an )?({mod} )?({dir} )?(dutch|canted) (angle|tilt)",
        "(at|on) (a |an )?({mod} )?(slant|tilt|cant|lean|skew)( (to|towards) the {side})?",
        # Turned about the lens's own axis ("the whole camera turned on its lens axis 25 degrees
        # clockwise"): a roll, whatever the verb of turning.
        "((the )?(whole )?(camera|lens|rig|frame|picture|image) )?(turned|turn|rotated|rotate|rolled|roll|spun|spin|twisted"
        "|twist) (on|about|around|round) (its|the) (own )?(lens |optical |viewing )?axis (by |through )?{d} {dir}",
        # Other verbs of rolling, with degrees and a direction or side ("banked 15 degrees left").
        "((with )?(the )?(camera|lens) )?{ROLLV}{ROLLED} (by |through )?{d} ({dir}|(to the |towards the )?{side})",
        "((with )?(the )?(camera|lens) )?{ROLLV}{ROLLED} ({dir}|(to the |towards the )?{side}) (by )?{d}",
        # A crooked frame said as an adjective ("frame a bit askew", "a wonky horizon"): a dutch angle.
        "((the )?(frame|shot|picture|image|horizon|camera) (is )?)?({WEAKROLL} |{mod} )?{ROLLADJ}( (frame|framing|horizon|shot))?"
        "( ,)?( {dir})?(?! (by|to|up|down) )",
        # Degrees off level ("15 degrees off level, clockwise").
        "(a |an )?{d} (off|out of) (level|true|plumb|horizontal)( ,)?( {dir})?",
        "(with )?(a |an )?{mod} (cant|tilt|lean|slant)(?= ([,.;!]|$))",
        # A direction or side without degrees ("a gentle clockwise tilt", "slight dutch to the left").
        "(with )?(a |an )?({mod} )?{dir} (tilt|roll|cant|rotation)",
        "(with )?(a |an )?({mod} )?" + ROLL_SIDE_ADJECTIVE + " (tilt|roll|cant|rotation)",
        # Degrees given to the camera, said after them ("apply 10 degrees anticlockwise to the camera").
        f"{GIVE} (a |an )?{{d}}( turn| of (a )?turn)? {ROLL_DIRECTION} (to|on) {CAMERA_THING}",
        "(with )?(a |an )?({mod} )?(dutch|canted)( (angle|tilt))? (to|towards) the {side}",
        # A dutch angle with degrees and a side, in either order, maybe leaning ("dutch angle 30
        # degrees to the left", "dutch tilt leaning right by 20 degrees"), in one clause: a side
        # after a comma, or before a part of the frame or of the subject, is a place or a view.
        "(with )?(a |an )?({mod} )?(dutch|canted)( (angle|tilt))?( of)? {d} (" + LEANING + " )?(to |towards )?(the )?{side}"
        "( hand)?" + NOT_A_ROLL_SIDE,
        "(with )?(a |an )?({mod} )?(dutch|canted)( (angle|tilt))? (" + LEANING + " )?(to |towards )?(the )?{side}"
        "( hand)? (by |of )?{d}",
        "(with )?(a |an )?({dir} )?(camera )?roll( of)? {sd}",
        "(camera )?roll angle( of| at)? {sd}( {dir})?",
        "(camera )?rolled (by )?{sd}",
        "(with )?(the )?camera 's {side} side (dipped|lowered|dipping|down)( by)?( {d})?",
        "(with )?(the )?{side} side (of the (camera|{FRAME}) )?(dipped|lowered|dipping|down)( by)?( {d})?",
        "dipping (to the )?{side}( by {d})?",
        # Number, direction and noun in any order ("8 degree counter-clockwise roll", "dutch angle
        # 10", "roll 5 degrees CCW").
        "(a |an )?{d} (of )?{dir} (roll|tilt|cant|rotation|dutch( angle| tilt)?|canted angle)",
        "(a |an )?{d} of (camera )?(roll|cant|rotation|dutch( angle| tilt)?)( {dir})?",
        "((the )?camera )?(rolled|tilted|rotated|canted|turned|spun|twisted|swivelled|swiveled) (by )?(a |an )?{d} turn {dir}",
        "(roll|rolled|rolling|cant|canted|tilt|tilted|tilting)( the camera| it)? (by )?{d} (to|towards) the {side}",
        "((the )?(camera|lens) )?(roll|rolled|rolling|cant|canted|tilt|tilted|tilting|rotate|rotated)"
        "( the camera| the lens| it)? (to the |towards the )?{side} (by )?{d}",
        # The camera itself turned to a side is a roll, not the subject's azimuth ("lens rotated ten degrees to the right").
        "(the )?(camera|lens) (rolled|rotated|tilted|turned|canted|twisted|spun) (by )?{d} (to|towards) the {side}",
        # Spun or twisted about the lens axis ("camera spun 15 degrees clockwise about the lens axis").
        "((the )?camera )?(spun|spin|spinning|twisted|twist|twisting|swivelled|swiveled|swivel|revolved|revolve|cocked|cock) "
        "((by )?{d} {dir}|{dir} (by )?{d})",
        "(roll|rolled|rolling|cant|canted) it (by )?{d} {dir}",
        "(a |an )?{d} (roll|tilt|cant) (to|towards) the {side}",
        "(camera )?(rolled|tilted|canted|rotated|turned) {WEAKROLL} ({dir}|to the {side})",
        "(a |an )?{dir} (roll|tilt|cant|rotation)( of)? {d}",
        "(roll|cant|rotate|rotated|rotating|turn|turned|tilt|tilted|tilting|twist|twisted)( the camera)? (by )?{d} {dir}",
        # Degrees and a direction alone as a clause ("Dutch angle on the car, 20 degrees CW").
        "{CLAUSE}(by )?{d} {dir}(?= ([,.;!]|$|and |with ))",
        "(roll|rolled|tilt|tilted|cant|canted)( the camera)? {dir} (by )?{d}",
        *_roll_family(CAMERA_THING),
        # Leaning or tipping to a side by a number ("lean the camera fifteen degrees to the left").
        "(lean|leaning|leaned|tip|tipping|tipped|bank|banking|banked)( the camera| the lens| it)? "
        "(by )?{d} (to|towards) the {side}",
        # A dutch angle as a verb ("dutched 15 degrees"): clockwise unless a direction is said.
        "dutched (by )?{d}( {dir})?",
        # Degrees said of the camera's roll ("10 degrees anticlockwise on the camera's roll").
        "{d} {dir} (on|of|in|to|for) (the )?((camera|lens|cam) 's )?(roll|rotation|cant|dutch)( axis)?",
    ],
    -1.0: [
        "(with )?(the )?(horizon|picture|image|scene) (tilted|rotated|slanted|sloping|turned|canted) (by )?{d} {dir}",
        "(with )?(the )?(horizon|picture|image|scene) (tilted|rotated|slanted|sloping|turned|canted) {dir}(( by)? {d})?",
        "(with )?(the )?(horizon|picture|image|scene) (tilted|rotated|slanted|sloping|turned|canted|leaning) "
        "({WEAKROLL} |(by )?{d} )?(down |downwards |downward )?(to the |towards the )?{side}( by {d})?",
        "(tilt|rotate|turn|cant|slant|twist|skew)( the)? (horizon|picture|image|scene|frame) (by )?{d} {dir}",
        "(a |an )?(tilted|rotated|slanted|canted|turned|sloping) (horizon|picture|image|frame) (of |by )?{d} {dir}",
        "(tilt|rotate|turn|cant|slant|twist|skew)( the)? (horizon|picture|image|scene|frame) {dir}( by {d})?",
        *_roll_family(PICTURE_THING),
    ],
    0.0: [
        "(keeping|keep|with|hold|holding) (the )?horizon ({HORIZON_LEVEL})",
        # A line that stands for the horizon kept, got or said to run level ("keep the table line
        # level", "the skyline must stay dead flat", "the edge of the desk running straight across
        # the photo"), or said not to slope ("the horizon mustn't tilt at all"): parse18p6.
        "((keeping|keep|with|hold|holding|get|getting|make|making|have|having) )?(the )?{HORIZON}{MUST}"
        "( (is|stays|stay|remains|remain|being|kept|runs|run|running|sits|sit|lies|lie|goes|go|reads|read))?"
        " ({STRONG} |perfectly |nice and |completely |totally )?{HORIZON_LEVEL}( across( (the|this) {FRAME})?)?",
        "(the )?{HORIZON} (doesn t|does not|don t|do not|must not|mustn t|should not|shouldn t|won t|will not|never"
        "|can t|cannot|may not) (" + LEVEL_BREAKING + ")( at all| whatsoever| either way| to either side| in the least)?",
        # Leaning neither way ("the camera upright, tilted to neither side").
        "(" + LEVEL_BREAKING + ") (neither way|to neither side|neither left nor right)",
        "(not|never) (" + LEVEL_BREAKING + ") (either way|to either side|at all|left or right|to the left or (to the )?right)",
        "(with )?(a |the )?({STRONG} |perfectly |nice and )?({HORIZON_LEVEL}) horizon",
        # Said as an absence ("no dutch", "not tilted"; "not tilted up" is a pitch).
        "(no|not|without|never) (any )?(dutch|cant|canted|tilted|rolled|tilt|roll|slant|slanting|sloping|leaning|tipping)"
        "( (angle|tilt))?"
        "( at all| whatsoever)?(?! (up|down) )",
        "(the )?horizon (is |stays |remains |being |kept )?({STRONG} |perfectly |nice and )?({HORIZON_LEVEL})",
        # The frame said level ("frame kept level", "the picture stays straight"): not a height.
        "(the )?(frame|picture|image|shot) (is |stays |remains |being |kept |held )({STRONG} |perfectly |nice and )?"
        "(level|straight|horizontal)(?! (with|to|as) )",
        "(with |and )?no (dutch |canted )?(angle|tilt|roll)( (on|in|to|of) the (horizon|frame|picture|image|camera|shot))?",
        "(keep|keeping|hold|holding) (it|things|everything|the shot|the frame|the picture)"
        " (nice and |perfectly |dead )?(level|straight)",
        "(with )?no camera roll",
        "without (any )?((dutch|canted) (angle|tilt)|roll|camera roll|tilt)",
        # Not level with something: that is a height ("camera held level with the chair").
        "((keep|keeping|hold|holding|with) )?(the )?camera (held )?(dead |perfectly |nice and )?level(?! (with|to) )",
        "(a )?level camera",
        # Said as an absence of any roll word ("no tilt at all", "no rolling", "not rotated") or
        # of a crooked frame ("horizon not crooked").
        f"(with )?(no|0) {ROLL_NOUNS}( at all| whatsoever)?",
        f"(not|never) {ROLL_VERB_FORMS}( {ROLL_AXIS})?( at all)?(?! (up|down|to|towards|by|{{dir}}) )",
        "((the )?(frame|shot|picture|image|horizon|camera) (is |being |stays )?)?(not|never) (at all )?{ROLLADJ}",
        # Square to the horizon ("the frame square to the horizon").
        "((the )?(frame|shot|picture|image|camera) )?(square|squared|parallel) (to|with) the horizon",
    ],
}

# The fewest letters of a table word read whole from two pieces ("a bove": :meth:`RuleParser._unslip`).
MIN_SPLIT_LETTERS = 5

# "Please" is dropped before the tables are read: said anywhere ("the mug really big please",
# "the bear please from behind") it parts no phrase from the clause end it asks for.
PLEASE = frozenset({"please"})
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
        "must",
        "will",
        "shall",
        # The subject said as a person ("he must fill the picture").
        "he",
        "she",
        "they",
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
        # Politeness and hedges carry no constraint either.
        "kindly",
        "maybe",
        "perhaps",
        "possibly",
        "hey",
        "hi",
        "hello",
        "thanks",
        "thank",
        "cheers",
        "ok",
        "okay",
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
# Parts of and positions on an object or the frame: a run of these is never a subject.
POSITION_WORDS = frozenset(
    {
        "far",
        "extreme",
        "outer",
        "front",
        "back",
        "rear",
        "side",
        "left",
        "right",
        "hand",
        "top",
        "bottom",
        "underside",
        "base",
        "center",
        "middle",
        "face",
        "profile",
        "edge",
        "corner",
        "half",
        "part",
        "upper",
        "lower",
        "behind",
    }
)
# Degree words ("a bit", "slightly") left over where no side or height follows them: reported,
# never a subject ("the bear a bit to the right" names no object "bit").
DEGREE_WORDS = frozenset(
    {
        "more",
        "less",
        "much",
        "slightly",
        "somewhat",
        "marginally",
        "bit",
        "little",
        "tad",
        "touch",
        "directly",
        "straight",
        "squarely",
        "fully",
        "strongly",
        "exactly",
        "dead",
        "completely",
        "perfectly",
        "purely",
        *(w for phrase in (*DEGREE_SCALE["slight"], *DEGREE_SCALE["exact"]) for w in phrase.split() if w != "a"),
    }
)
# Parts of an object ("so we see the backrest") and the scene around the objects ("a wide view of
# the room"): never a subject of their own; left unparsed and reported.
PART_WORDS = frozenset(
    {
        "backrest",
        "armrest",
        "arm",
        "arms",
        "leg",
        "legs",
        "seat",
        "lid",
        "handle",
        "screen",
        "door",
        "doors",
        "shade",
        "lampshade",
        "trunk",
        "branch",
        "branches",
        "leaf",
        "leaves",
        "wheel",
        "wheels",
        "head",
        "ear",
        "ears",
        "nose",
        "detail",
        "details",
        "texture",
        "surface",
        "shape",
        "outline",
        "silhouette",
        *(part for parts in SUBJECT_PARTS.values() for part in parts if " " not in part),
    }
)
# Small details any object may have, said to be seen ("so we see the seam down its back", "from
# the back, where the cables are", "the stitching on its paw"): a part of the subject, never an
# object of its own, nor a misspelt name ("cables" is no typo of "table").
DETAIL_PARTS = frozenset(
    f"{w}{s}"
    for w in (
        "seam",
        "stitch",
        "cable",
        "wire",
        "cord",
        "lead",
        "plug",
        "socket",
        "port",
        "label",
        "tag",
        "logo",
        "badge",
        "sticker",
        "zip",
        "zipper",
        "button",
        "screw",
        "bolt",
        "hinge",
        "switch",
        "knob",
        "dial",
        "vent",
        "strap",
        "buckle",
        "lace",
        "tassel",
        "crack",
        "scratch",
        "dent",
        "chip",
        "stain",
        "mark",
        "signature",
    )
    for s in ("", "s", "es")
    if not (s == "es" and not w.endswith(("ch", "sh", "x", "z", "s"))) and not (s == "s" and w.endswith(("ch", "sh")))
) | {"stitching", "stitches", "wiring", "paintwork", "brushwork", "grain", "glaze", "weave", "pattern", "print"}

SURROUNDINGS = frozenset(
    {
        "room",
        "space",
        "area",
        "place",
        "setting",
        "setup",
        "surroundings",
        "background",
        "foreground",
        "everything",
        "all",
        "floor",
        "ground",
        "wall",
        "walls",
        "ceiling",
        "sky",
        "lawn",
        "grass",
        "park",
        "garden",
        "tabletop",
        "layout",
        "arrangement",
        "interior",
    }
)
# Prepositions of place that are not stopwords: "the kitten beside the sofa" is about a kitten.
PLACE_PREPOSITIONS = frozenset(
    {"beside", "below", "above", "beneath", "underneath", "against", "alongside", "between", "among", "inside", "outside", "atop"}
)
# What relates a thing to a place: a preposition of place or a verb of resting ("the wristwatch
# lying by the mug", "skateboard under the bench", "a hammock strung from the tree"). A noun
# phrase opening the sentence and related so to a named object is the subject, the object a
# secondary one (:meth:`RuleParser._leftovers`).
RELATION_WORDS = PLACE_PREPOSITIONS | frozenset(
    {
        "by",
        "under",
        "near",
        "next",
        "upon",
        "lying",
        "lies",
        "laying",
        "sitting",
        "sits",
        "sat",
        "standing",
        "stands",
        "resting",
        "rests",
        "hanging",
        "hangs",
        "hung",
        "leaning",
        "leans",
        "perched",
        "parked",
        "propped",
        "strung",
        "tied",
        "hidden",
        "hiding",
        "tucked",
        "sleeping",
        "stacked",
        "balanced",
        "dropped",
        "curled",
        "sprawled",
        "draped",
        "lounging",
        "nestled",
        "wedged",
        "stuck",
        "posed",
        "displayed",
        "mounted",
        "attached",
        "piled",
        # States said between a thing and its place ("the cat asleep on the sofa").
        "asleep",
        "awake",
        "napping",
        "dozing",
        "seated",
        "crouched",
        "crouching",
        "kneeling",
        "floating",
        "waiting",
    }
)
# Prepositions that tie a thing to the object after them only in a noun phrase's place ("the book
# on top of | the bench"): too common after verbs ("focus on") to mark a subject without a
# determiner.
RELATION_OBJECT_WORDS = frozenset({"on", "in", "at", "top", "front", "inside", "across", "along", "against", "upon", "onto"})
# Words that place a thing, in a noun phrase's place or after it ("the light | falling on",
# "is | behind the sofa").
PLACE_WORDS = RELATION_WORDS | RELATION_OBJECT_WORDS | {"behind", "beyond"}
# Nouns of the picture itself, not of what is in it ("an interesting angle on the mug").
PICTURE_NOUNS = frozenset(
    {"angle", "angles", "perspective", "viewpoint", "vantage", "light", "lighting", "composition", "framing", "focus"}
    | {"exposure", "look", "style", "mood", "crop", "lens", "horizon", "distance", "shadow", "shadows", "reflection"}
    # What a picture brings out, never a thing in the scene ("a soft glow sitting on the vase", "the
    # emphasis placed on the ball", "my attention drawn to the bear").
    | {"glow", "emphasis", "attention", "interest", "highlight", "highlights", "atmosphere", "contrast", "silhouette"}
    | {"reflections", "bokeh", "blur", "sunlight", "daylight", "sunshine", "grain", "texture"}
    # The picture as made, and how it is held or feels ("look at the result", "a handheld, wonky
    # feel"): parse18p6.
    | {"result", "results", "print", "printout", "handheld", "feel", "vibe"}
)
# Nouns that name nothing in particular ("that thing", "a small object"): never a subject.
GENERIC_NOUNS = frozenset({"thing", "things", "stuff", "object", "objects", "item", "items", "something", "piece", "pair"}) | {
    w for speck in SPECK_WORDS for w in speck.split() if w not in ("on", "the")
}
# A frame turned or crooked ("a bit askew", "on a tilt"): a state of the picture, never a subject.
ROLL_STATE_WORDS = frozenset({w for phrase in (*ROLL_VERBS, *ROLL_ADJECTIVES) for w in phrase.split()}) | {
    "tilt",
    "cant",
    "slant",
    "lean",
    "skew",
    "kilter",
}
# Nouns of the vocabulary's tables (parts, supports, specks, kinds, slates): words the tables use
# that name things, so before a place relation they are a thing, not a verb ("plate next to the
# mug" is about a plate, where "focus on the mug" is a verb).
TABLE_NOUNS = frozenset(
    w
    for table in (*SUBJECT_PARTS.values(), SUPPORT_SURFACES, SPECK_WORDS, CLASS_NOUNS, SLATE_LABELS)
    for phrase in table
    for w in phrase.split()
) | {"mat", "ceiling", "canopy", "border", "headshot"}
MENTION_DETERMINERS = DETERMINERS - {"its", "their"}
# An article before a thing, as a one-word slice of the tokens ("a kazoo", "the teapot", "some books").
ARTICLE_WORDS = (["a"], ["an"], ["the"], ["some"])
# Words leading to a height named by a thing with a determiner ("at the | table height", "from the |
# seat level"): :func:`_height_anchor`.
HEIGHT_LEADS = frozenset(
    {"at", "from", "to", "around", "about", "near", "roughly", "approximately", "with", "own", "same", "just", "slightly"}
    | {"above", "below", "under", "over", "beneath", "underneath", "than", "its", "their", "his", "her", "'s", "down", "up"}
)
CONJUNCTIONS = frozenset({"and", "or", "plus"})
MAX_ATTRIBUTES = 3  # attribute words taken into a mention before its name ("the big fluffy brown bear")

SUBJECT_FIELDS = ("region", "shot", "view")

# --- compiling the tables -------------------------------------------------------------------------


# Words hedging a number said before it ("about thirty degrees", "roughly 20 degrees below"): the
# number read as said, wherever a template takes one ({d}, {sd}).
NUMBER_HEDGE = "(?:(?:about|around|roughly|approximately|approx|circa|some|maybe|perhaps|nearly|almost|close to) )?"


def _alternatives(options, opening: str = "(") -> str:
    """A regex group of ``options``, longest first so that a longer phrase wins over its prefix;
    ``opening`` is the group's opening ("(", "(?:" or a named group)."""
    return opening + "|".join(sorted(options, key=len, reverse=True)) + ")"


_MACROS = {
    # A height named by eye level, a height anchor or the subject's own ("its own", "the seat",
    # "its roof"), before "level" / "height" / "line"; expanded first, its macros after it.
    "{MIDDLE}": "(?:middle|center|midpoint|mid point|midsection|mid section|mid height|half height)",
    # What an angle is measured from ("25 degrees over it", "above the horizontal", "below its centre").
    "{ELEVREF}": "(?:{obj}|(?:the )?(?:horizontal|horizon|level|ground|floor|eye level|eye line)"
    "|(?:the |{P} )(?:own )?(?:{ANCHOR_EYE}|height|level)(?: of {obj})?)",
    # As far as it goes ("tilted fully down", "all the way up", "straight up").
    "{FULLY}": "(?:fully|all the way|completely|totally|straight|directly|vertically)",
    # Up through what the subject stands on ("LENS STRAIGHT UP THROUGH THE TOP").
    "{THROUGH}": "(?: through (?:the |a |{P} )?(?:{SURFACE}|{SUPPORT}|top|surface|glass|floor)(?: (?:top|surface))?)?",
    "{HEIGHT_OF}": "(?:(?:the |a |{P} )?(?:own )?(?:eye|{ANCHOR_EYE})|{P}(?: own)?)",
    "{FRAME}": FRAME,
    "{SEEN_VERB}": "(?:seen|viewed|shot|photographed|captured|taken|filmed)",
    # A number may be hedged before it ("about 30 degrees", "roughly 20"): the number it hedges.
    "{d}": NUMBER_HEDGE + r"(?P<d>\d+(?:\.\d+)?)(?: degrees)?",
    "{sd}": NUMBER_HEDGE + r"(?P<d>-?\d+(?:\.\d+)?)(?: degrees)?",
    "{negd}": NUMBER_HEDGE + r"(?P<d>-\d+(?:\.\d+)?)(?: degrees)?",
    # A bare number of at most two digits (no "degrees"), only where a height word leads it.
    "{n}": r"(?P<d>\d{1,2}(?:\.\d+)?)",
    # A direction of turning; said round about ("in the clockwise sense") it is read as itself by
    # the word pipeline (vocabulary._turn_directions), not here in every roll template.
    "{dir}": "(?P<dir>clockwise|counterclockwise)",
    "{side}": "(?P<side>left|right)",
    "{WEAK}": _alternatives(DEGREE_SCALE["slight"], "(?:"),
    "{STRONG}": _alternatives((*DEGREE_SCALE["exact"], "strongly"), "(?:"),
    # The same words where they make a view side exact (read back by _cue).
    "{EXACT}": _alternatives((*DEGREE_SCALE["exact"], "strongly"), "(?P<exact>"),
    # Said once or repeated ("really really tiny", "very, very small", "so so close").
    "{VERY}": _alternatives(DEGREE_SCALE["strong"], "(?:")
    + "(?:(?: ,)? "
    + _alternatives((*DEGREE_SCALE["strong"], "so"), "(?:")
    + ")*",
    # A small amount to turn by: a slight degree word or a small turn without a number, maybe
    # "more" ("a little bit more", "a few degrees").
    "{HEDGE}": _alternatives((*DEGREE_SCALE["slight"], *OFFSET_HEDGES), "(?:") + "(?: more)?",
    "{TURNHEDGE}": _alternatives([h for h in OFFSET_HEDGES if " " in h], "(?:"),
    # A part on one side of the subject ("the arm", "its end").
    "{SIDEPART}": _alternatives(SIDE_PARTS, "(?:"),
    "{PLENTY}": _alternatives(PLENTY_WORDS, "(?:"),
    # A level horizon, as a builder or a carpenter says it too ("horizon true", "spirit-level").
    "{HORIZON_LEVEL}": "(?:level|straight|flat|horizontal|true|plumb|even|neutral|spirit level|dead flat|dead level)",
    # A line standing for the horizon (vocabulary.HORIZON_LINES, a support's line or edge, the line
    # where one thing meets another), maybe placed behind the subject; and what it should do.
    "{HORIZON}": "(?:(?:"
    + "|".join(sorted(HORIZON_LINES, key=len, reverse=True))
    + "|(?:"
    + "|".join(HORIZON_SURFACES)
    + ") (?:line|edge)|(?:line|edge) of the (?:"
    + "|".join(HORIZON_SURFACES)
    + ")|line where (?:the )?[a-z]+ meets (?:the )?[a-z]+)(?: behind (?:it|him|her|them|@\\d+))?"
    + "(?: in the (?:background|distance|back))?)",
    "{MUST}": "(?: (?:should|must|has to|needs to|need to|ought to|will|shall|has got to|got to|is to))?"
    "(?: (?:appear|look|seem)(?: to)?)?(?: be)?",
    # A moderate grade of a size word ("fairly tight", "pretty small").
    "{FAIRLY}": "(?:fairly|pretty|quite|rather|reasonably|moderately)",
    # Pressed into the frame: the subject fills it ("crammed into the frame", "pack it into the shot").
    "{CRAM}": "(?:crammed|packed|squeezed|jammed|stuffed|wedged|squished|squashed|shoehorned)",
    "{CRAM_VERB}": "(?:cram|pack|squeeze|jam|stuff|wedge|squish|squash|shoehorn)",
    # Sizes "not too" may temper, either way: what is left is the middle size.
    "{NOT_TOO}": _alternatives(
        (
            "close",
            "tight",
            "big",
            "large",
            "near",
            "zoomed in",
            "zoomed",
            "cropped",
            "tightly cropped",
            "close up",
            "far",
            "far away",
            "far off",
            "wide",
            "small",
            "tiny",
            "distant",
            "zoomed out",
            "loose",
        ),
        "(?:",
    ),
    # Heights said otherwise (vocabulary): "even with", "a few degrees", "a first-floor window".
    "{LEVEL}": _alternatives(LEVEL_WITH, "(?:"),
    "{FEW}": _alternatives({" ".join(words(p)) for p in FEW_DEGREES}, "(?:"),
    "{HIGHPLACE}": _alternatives({" ".join(words(p)) for p in HIGH_PLACES}, "(?:"),
    "{OPENING}": _alternatives(HIGH_PLACE_OPENINGS, "(?:"),
    "{AMOUNT}": _alternatives(HEIGHT_AMOUNTS, "(?:"),
    "{EYENOUN}": _alternatives(EYE_VIEW_NOUNS, "(?:"),
    # A hedge on where the camera is ("lens roughly at its chin", "camera about level with it").
    "{ROUGHLY}": "(?:roughly|about|around|approximately|more or less|pretty much|somewhere around|near enough|just about)",
    "{ANCHOR_EYE}": _alternatives(HEIGHT_ANCHORS["eye level"], "(?:"),
    "{ANCHOR_LOW}": _alternatives(HEIGHT_ANCHORS["low angle"], "(?:"),
    "{mod}": "(?P<mod>" + "|".join(DUTCH_SIZE_DEG) + ")",
    "{WEAKROLL}": _alternatives(DEGREE_SCALE["slight"], "(?P<weak>"),
    # Moving the camera or oneself to a height ("get down low", "crouch lower").
    "{GET}": "(?:get|getting|go|going|crouch|crouching|kneel|kneeling|squat|squatting|climb|climbing|stand|standing|move|moving)",
    "{SHARE}": "(?P<share>" + "|".join(sorted(FRAME_FRACTIONS, key=len, reverse=True)) + r"|\d+(?:\.\d+)? percent)",
    # An end of a subject, from which to which all of it is seen ("head to toe", "roots up to
    # crown", "base through to the tip"), in the singular or the plural.
    "{END}": "(?:(?:base|bottom|top|floor|ground|foot|feet|toe|head|bulb|shade|tip|end|ear|arm|armrest|leg|wheel"
    "|bumper|nose|tail|front|back|rear|stern|bonnet|hood|boot|grille|paw|root|crown|canopy|treetop|peak|summit|apex"
    "|roof|lid|rim|lip|brim|spout|handle|edge|pot|leaves|branch|trunk|stem|stalk|pole|seat|backrest|side)(?:e?s)?)",
    "{END_TO}": "(?:(?:up|down|right|all the way|the whole way|through|over|across) )?(?:to|till|until|thru)",
    # A hedge before a number ("about 30 degrees", "maybe 40").
    "{ABOUT}": "(?:about|around|roughly|approximately|some|maybe|perhaps|circa|nearly|almost|close to|just under|just over"
    "|a good)",
    # A named elevation whose degrees may follow ("an overhead view ..., about 70 degrees").
    "{HIGHVIEW}": "(?:(?:from )?(?:high up|up high|way up|top down|straight down)"
    "|(?:from |in |as )?(?:a |an )?(?:overhead|high angle|elevated|aerial|birds?(?: 's)? eye|top)"
    "(?: (?:view|shot|angle|perspective))?|(?:from |in |as )?(?:a |an )?high (?:view|shot)|from above)",
    "{LOWVIEW}": "(?:(?:from )?(?:low down|down low)|(?:from |in |as )?(?:a |an )?(?:low angle|worms?(?: 's)? eye)"
    "(?: (?:view|shot|angle|perspective))?|from below)",
    # Pointing the camera ("shoot up at", "aimed down").
    "{AIM}": "(?:shoot|shoots|shooting|point|points|pointing|pointed|aim|aims|aiming|aimed|angle|angled|angling|tilt|tilted"
    "|tilting|pitch|pitched|pitching)",
    # Surfaces a subject rests or sits on: "at table height" is level with what stands on it.
    "{SURFACE}": "(?:table|tabletop|desk|counter|countertop|seat|bench|shelf|bed|sofa|couch|chair)",
    # What one lies on or in to shoot from low down ("lie flat on the grass", "on your belly").
    "{LIEON}": "(?:(?:the |a |your |my |his |her )?(?:table|tabletop|table top|desk|counter|floor|ground|grass|lawn|rug"
    "|carpet|mat|sand|belly|stomach|tummy|front|back))",
    # The whole subject said to fit ("so all of it fits", "the whole thing fits in the frame").
    "{FITS}": "(?: (?:fits|fit|fitting|goes|gets)(?: in(?: (?:the )?" + FRAME + ")?)?)?",
    "{PART}": "(?: " + _alternatives(SIDE_PARTS, "(?:") + ")?",
    # A part that one of its sides has ("the right armrest", "its left-hand doors").
    "{SIDED}": _alternatives(SIDED_PARTS, "(?:"),
    # Moving the camera round ("drifting a little round to its left").
    "{ROLLV}": _alternatives(ROLL_VERBS, "(?:"),
    # What a roll verb turns, said after it ("dutch it 25 degrees", "cant the frame 10 degrees left").
    "{ROLLED}": "(?: (?:it|them|the camera|the lens|the rig|the shot|the frame|the picture|the image|things))?",
    "{ROLLADJ}": _alternatives(ROLL_ADJECTIVES, "(?:"),
    "{MOVE}": "(?:drifting|drifted|drift|moving|moved|move|swinging|swung|swing|going|go|coming|come|edging|edged|edge"
    "|nudging|nudged|nudge|inching|inched|inch|shuffling|shuffled|shuffle"
    "|creeping|crept|shifting|shifted|sliding|slid|circling|circled|stepping|stepped|working|worked|orbiting|orbited"
    "|rotating|rotated|walking|walked|walk|turning|turned|sweeping|swept|wandering|easing|eased|ease)",
    # The front said as the camera's straight-on line ("a touch to his right of dead front").
    "{FRONT_ON}": "(?:(?:dead|straight|square|head|full) (?:front|on)|dead ahead|straight ahead|(?:the )?center)",
    # Close to: "almost straight up", "nearly vertically down".
    "{NEARLY}": "(?:almost|nearly|near|practically|virtually|pretty much|more or less)",
    "{CLASS}": _alternatives(CLASS_NOUNS, "(?:"),
    "{PURPOSE}": _alternatives(PURPOSES, "(?:"),
    "{SPECK}": _alternatives(SPECK_WORDS, "(?:"),
    "{SUPPORT}": _alternatives(SUPPORT_SURFACES, "(?:"),
    # A part of the subject ("its seat", "the shade", "the trunk").
    "{PARTS}": _alternatives(
        {p for parts in SUBJECT_PARTS.values() for p in parts}
        | (PART_WORDS - {"detail", "details", "texture", "surface", "shape", "outline", "silhouette"})
        | {"crown", "canopy", "underside", "belly"},
        "(?:",
    ),
    # Looking or aiming, and how straight down ("look down straight on it", "peering right down at").
    "{LOOK}": "(?:look|looks|looking|looked|peer|peers|peering|peered|gaze|gazes|gazing|gazed|stare|stares|staring"
    "|stared|glance|glances|glancing|shoot|shoots|shooting|point|points|pointing|pointed|aim|aims|aiming|aimed)",
    "{DOWNRIGHT}": "(?:straight|directly|vertically|right|squarely|dead|perpendicularly|plumb)",
    "{DOWNONTO}": " (?:on|at|onto|upon|into|over|to)(?: (?:the )?top of)?(?: {obj})?",
    # A clause's start: after a comma, a colon, a semicolon or a full stop ("bear. close.").
    "{CLAUSE}": "(?<=[,;:.!?(] )",
    # The whole picture a small element is part of ("a small element in the landscape").
    "{WHOLE}": "(?:(?:bigger|wider|larger|whole|overall|entire|big) )?(?:"
    + FRAME
    + "|scene|landscape|composition|view|background|setting|surroundings|scenery|room|interior|garden|park)",
    # Not before a number, which would make the words before it a height ("elevation 20 degrees").
    "{NOT_A_NUMBER}": "(?! (?:of |at |about |around |roughly |approximately |approx |some |~ )?-?\\d)",
    # "Own" after a possessive only insists ("from its own left", "the bear's own back").
    "{P}": r"(?P<ref>its|it 's|his|her|their|@\d+ 's)(?: own)?",
    # Not a subject whose possessive follows: "zoom in on the bear's face" closes in on the face.
    "{obj}": r"(?P<ref>it|him|her|them|@\d+(?! 's))",
}


@dataclass(frozen=True)
class _Rule:
    """One template: the field it sets and its value (for numbers: a sign multiplier); ``needs``:
    strings every match holds (:func:`_required`), and ``needs_any``: groups of strings of which
    every match holds one (:func:`_required_any`), so a text lacking one is not searched."""

    field: str
    value: object
    pattern: re.Pattern
    weak: bool = False
    needs: tuple[str, ...] = ()
    needs_any: tuple[tuple[str, ...], ...] = ()


def _pattern_tree(pattern: str):
    """The parse tree of a regular expression (``re``'s own parser), which :func:`_required` and
    :func:`_required_any` walk: parsed once per rule, as it is the slow part of building them."""
    return _re_parser.parse(pattern)


def _required(tree) -> tuple[str, ...]:
    """Literal strings of 3 characters or more that every match of the pattern whose parse
    ``tree`` (:func:`_pattern_tree`) is given contains: runs of
    literal characters outside optional parts, alternatives and lookarounds (a mandatory group or
    a repeat of one or more counts as its contents)."""
    out: list[str] = []

    def walk(items) -> None:
        run: list[str] = []
        for op, arg in items:
            if op is _re_nodes.LITERAL:
                run.append(chr(arg))
                continue
            out.append("".join(run))
            run = []
            if op is _re_nodes.SUBPATTERN:
                walk(arg[-1])
            elif op in (_re_nodes.MAX_REPEAT, _re_nodes.MIN_REPEAT) and arg[0] >= 1:
                walk(arg[2])
        out.append("".join(run))

    walk(tree)
    return tuple(dict.fromkeys(r for r in out if len(r) >= 3))


def _required_any(tree) -> tuple[tuple[str, ...], ...]:
    """Groups of literal strings (3 characters or more) of which every match of the pattern whose
    parse ``tree`` is given contains at least one: for each mandatory choice between alternatives ("(tight|close|big)"),
    one string each alternative must hold (its longest literal run, or the strings of its own
    first such group); a choice with an alternative holding none gives no group."""
    groups: list[tuple[str, ...]] = []

    def witnesses(items, mandatory: bool) -> list[str]:
        """Strings of which a match of ``items`` (a sequence) holds one; empty when unknown.
        ``mandatory``: every match of the whole pattern goes through ``items`` (not one
        alternative of several), so its choices are groups of the pattern."""
        found: list[tuple[str, ...]] = []
        run: list[str] = []
        for op, arg in items:
            if op is _re_nodes.LITERAL:
                run.append(chr(arg))
                continue
            if len(run) >= 3:
                found.append(("".join(run),))
            run = []
            if op is _re_nodes.SUBPATTERN:
                found += [tuple(w) for w in [witnesses(arg[-1], mandatory)] if w]
            elif op in (_re_nodes.MAX_REPEAT, _re_nodes.MIN_REPEAT) and arg[0] >= 1:
                found += [tuple(w) for w in [witnesses(arg[2], mandatory)] if w]
            elif op is _re_nodes.BRANCH:
                options = [witnesses(branch, False) for branch in arg[1]]
                if all(options):
                    group = tuple(dict.fromkeys(w for option in options for w in option))
                    found.append(group)
                    if mandatory:
                        groups.append(group)
        if len(run) >= 3:
            found.append(("".join(run),))
        # One string alone (the longest) says most; else the smallest group.
        singles = [f[0] for f in found if len(f) == 1]
        if singles:
            return [max(singles, key=len)]
        return list(min(found, key=len)) if found else []

    witnesses(tree, True)
    # A string holding another of its group adds nothing ("a little bit" holds "bit"): the
    # shortest ones are enough and quicker to look for.
    minimal = (tuple(w for w in g if not any(o != w and o in w for o in g)) for g in groups)
    return tuple(dict.fromkeys(g for g in minimal if len(g) > 1))


def _expand(template: str) -> str:
    """A template as the source of a regular expression matching whole words of normalised text."""
    t = re.sub(r"\((?!\?)", "(?:", template)
    for macro, regex in _MACROS.items():
        t = t.replace(macro, regex)
    # A macro may occur twice in a template: number its groups (read back by _groups).
    counter = itertools.count()
    t = re.sub(r"\(\?P<(\w+)>", lambda m: f"(?P<{m[1]}_{next(counter)}>", t)
    return f"(?<= )(?:{t})(?= )"


def _compiled(tree) -> re.Pattern:
    """The regular expression of a parse tree (:func:`_pattern_tree`), which ``re`` compiles
    without parsing the source again: parsing is most of a compile, and :func:`_required` needs the
    tree anyway, so the build parses each template once (the pattern keeps no source text)."""
    return _re_compiler.compile(tree)


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
    # First of the shot rows: an end-to-end idiom ("top to bottom") is read as this, not as medium.
    rows += [("shot", WHOLE_SPAN, t, False) for t in WHOLE_SPAN_PHRASES]
    for shot, terms in SHOT_TERMS.items():
        rows.append(("shot", shot, f"(a |an )?{_alternatives(terms)}( {SHOT_NOUN})?{link}", False))
    for shot, adjectives in SHOT_ADJECTIVES.items():
        rows.append(("shot", shot, f"(a |an )?{_alternatives(adjectives)} {SHOT_NOUN}{link}", False))
        # Its noun may belong to a view after it ("a wide establishing | shot from the front").
        rows.append(("shot", shot, f"(a |an )?{_alternatives(adjectives)}(?= {SHOT_NOUN} (from|at|in|with) )", False))
        if shot != "close-up":  # shot-list jargon drops the noun: "a medium wide of the sofa", "a wide of it"
            # Not "full": "full of" is what a thing holds ("the vase full of roses"), no full shot.
            jargon = [a for a in adjectives if a != "full"]
            rows.append(("shot", shot, f"(a |an )?{_alternatives(jargon)} of", False))
    rows += [("shot", shot, t, False) for shot, ts in SHOT_CLAUSES.items() for t in ts]
    rows += [("shot", "share", t, False) for t in SHARE_PHRASES]
    for region, areas in REGION_AREAS.items():
        # "The far left", "the very top": the same area, said to its edge.
        template = (
            f"{REGION_LEAD}{REGION_PREPOSITIONS} (the )?((far|extreme|very|outer) )?{_alternatives(areas)}"
            "( (of|in) (the )?{FRAME})?(?! of (?!" + EMPTY_FRAME_AFTER + "))(?! ground )"
        )
        rows.append(("region", region, template, False))
        template = f"{REGION_LEAD}{OCCUPYING} the {_alternatives(areas)}( (of|in) (the )?{{FRAME}})?(?! of )"
        rows.append(("region", region, template, False))
        # An area of the frame needs no preposition ("bottom right of the frame", "at bottom of picture").
        rows.append(("region", region, f"{REGION_LEAD}(the )?{_alternatives(areas)} (of|in) (the )?{{FRAME}}", False))
        # Right after its subject, an area that cannot be a view side ("bench left third, tree
        # right third", "cone lower left").
        named = [a for a in areas if (" " in a or region == "center") and a.split()[-1] not in ("side", "hand", "edge", "part")]
        # An area of the frame's, said with its possessive ("in the image's top-left").
        rows.append(("region", region, f"({REGION_PREPOSITIONS}|{OCCUPYING}) the {{FRAME}} 's {_alternatives(areas)}", False))
        if named:
            # After a verb of placing, a named area needs no preposition ("tucked bottom-left").
            template = f"{PLACING} (the )?{_alternatives(named)}( (of|in) (the )?{{FRAME}})?(?! of )"
            rows.append(("region", region, template, False))
            template = f"(?<=@\\d )(the )?{_alternatives(named)}( (of|in) (the )?{{FRAME}})?(?! of )"
            rows.append(("region", region, template, False))
            # ... or alone as a clause ("bench, left third, from low down"), also as a label
            # opening the sentence before its subject ("Left third: the mug", "Lower left - ball").
            rows.append(("region", region, f"((?<=^ )|{{CLAUSE}})(the )?{_alternatives(named)}(?= ([,.;:!?]|$))", False))
        if region in ("left", "right"):
            # A lone left or right straight after its subject, ending the clause, is where it
            # sits in the frame ("lamp left, bookcase right of frame"): a side would say "its".
            rows.append(("region", region, f"(?<=@\\d ){region}(?= ([,.;!]|$))", False))
            # So too pushed to its edge ("frame the fridge hard left", "the lamp placed far right").
            rows.append(("region", region, f"((?<=@\\d )|{PLACING} )(hard|far|extreme) {region}(?= ([,.;!]|$))", False))
    rows += [("region", region, t, False) for region, ts in REGION_PHRASES.items() for t in ts]
    for room, region in ROOM_SIDES.items():
        side = {"top": "(top|above)", "bottom": "(bottom|below)"}.get(room, room)
        rows += [
            ("region", region, t.replace("{SIDE}", side).replace("{BESIDE}", ROOM_BESIDE[room]), False) for t in ROOM_PHRASES
        ]
    for region, toward in (("left", "left"), ("right", "right"), ("top", "(above|top)"), ("bottom", "(below|bottom)")):
        rows += [("region", region, t.replace("{TOWARD}", toward), False) for t in OFF_CENTER]
    for view, sides in VIEW_SIDE_WORDS.items():
        rows += [("view", view, frame.replace("{SIDE}", _alternatives(sides)), False) for frame in VIEW_FRAMES]
        if view not in ("left", "right"):
            rows.append(("view", view, VIEW_CLAUSE.replace("{SIDE}", _alternatives(sides)), False))
        # A diagonal is no region: said as a place it is the camera's ("at the front right",
        # "along the left-rear diagonal").
        if "-" in view:
            rows.append(("view", view, "(at|on|to|along) (the|{P}) " + _alternatives(sides) + "( side| corner)?(?! of )", False))
            # Seen across that corner ("seen over its back-left corner", "looking across the sofa's
            # front-right corner").
            corner = (
                "(seen|viewed|looking|shot|photographed|taken|framed|angled)( in)? ((from )?(over|across|past|round|around|off)"
            )
            corner += "|from( (over|across|beyond|behind))?) (the|{P}) " + _alternatives(sides) + " (corner|edge|quarter|angle)"
            rows.append(("view", view, corner + "( of {obj})?", False))
            rows.append(("view", view, "(over|across) (the|{P}) " + _alternatives(sides) + " (corner|edge)( of {obj})?", False))
            # A corner turned to the camera, its end and its side said apart ("its rear corner on
            # the right nearest to us", "the front corner on the left facing the camera").
            lon, lat = view.split("-")
            lon_words = "(front|nose)" if lon == "front" else "(rear|back|tail)"
            rows.append(
                (
                    "view",
                    view,
                    "(the|{P}) " + lon_words + " corner (on|to|at) (the|{P}) " + lat + "( hand)?( side)?( ,)? "
                    "((is |being )?(nearest|closest|facing|pointing at|pointed at|turned to|turned towards)( to)?) " + VIEWER,
                    False,
                )
            )
            # A diagonal names a view wherever it stands as a noun phrase, a region never being one
            # ("I'm after a front-right 3/4", "go for rear left, medium", "do a front left on the
            # car"), unless a noun follows that it describes ("the front left leg").
            rows.append(("view", view, "((a|an|the|some|in|at|from) )?" + _alternatives(sides) + DIAGONAL_END, False))
        # A side's aspect or elevation, as anatomy, museums and architecture name a view ("rear
        # aspect", "left lateral aspect of the bear", "front elevation"); not "the side's
        # elevation" nor a height ("the front at eye-level elevation").
        aspect = "(the |{P} )?" + _alternatives(sides) + " (aspect|elevation)( of {obj})?(?! (of|angle) )"
        rows.append(("view", view, aspect, False))
        if view in NEGATED_ENDS:  # "anything but the front", "from any side except behind"
            rows.append(("view", NEGATED_ENDS[view], ALL_BUT.replace("{SIDE}", _alternatives(sides)), False))
        rows.append(("view", view, NOUN_BEFORE_SIDE.replace("{SIDE}", _alternatives(sides)), False))
        if view not in ("left", "right"):  # straight after its subject ("bear three quarter rear right", "chair front,")
            rows.append(("view", view, VIEW_AFTER_SUBJECT.replace("{SIDE}", _alternatives(sides)), False))
    rows += [("view", view, t, False) for view, ts in VIEW_PHRASES.items() for t in ts]
    rows += [("view", EXACT_ONLY, t, False) for t in EXACT_PHRASES]
    for lat, sign in (("left", -1.0), ("right", 1.0)):
        rows += [("view", ("turn", sign), t.replace("{LAT}", lat), False) for t in AZIMUTH_PHRASES + TURN_FRAMES]
        rows += [("view", ("azimuth", sign, 180.0, -1.0), t.replace("{LAT}", lat), False) for t in TURN_BACK_FRAMES]
        rows += [("view", f"front-slight-{lat}", t.replace("{LAT}", lat), False) for t in OFFSET_VIEW_FRAMES]
        rows += [("view", f"back-slight-{lat}", t.replace("{LAT}", lat), False) for t in OFFSET_BACK_VIEW_FRAMES]
        for lon, toward in (("front", -1.0), ("back", 1.0)):
            rows += [("view", f"{lat}-slight-{lon}", _lon_frame(t, lat, lon), False) for t in SIDE_OFFSET_FRAMES]
            rows += [
                ("view", ("azimuth", sign, 90.0, toward), _lon_frame(t, lat, lon), False) for t in SIDE_OFFSET_DEGREES_FRAMES
            ]
        # "90 degrees left" said alone: that far round to that side.
        rows.append(
            (
                "view",
                ("turn", sign),
                "(from |at )?{d}(?<= degrees) (round |off )?(to the |to )?" + lat + "(?= ([,.;!]|$))",
                False,
            )
        )
        for lon, toward in (("(front|face)", -1.0), ("(back|rear)", 1.0)):
            rows += [
                ("view", ("azimuth", sign, 90.0, toward), t.replace("{LAT}", lat).replace("{LON}", lon), False)
                for t in SIDE_DEGREES_PHRASES
            ]
        rows += [("view", f"front-slight-{lat}", t.replace("{LAT}", lat), False) for t in SLIGHT_VIEW_FRAMES]
        rows.append(("view", f"back-slight-{lat}", BACK_SLIGHT_VIEW.replace("{LAT}", lat), False))
        rows.append(("view", lat, PROFILE_CLAUSE.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_AFTER_SUBJECT.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_AFTER_VIEW_CLAUSE.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_ON.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_AFTER_HEIGHT.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_AFTER_VIEW.replace("{LAT}", lat), False))
        rows.append(("view", lat, SIDE_AFTER_SIDE_VIEW.replace("{LAT}", lat), False))
        for lon, lon_words in (("front", "(front|face)"), ("back", "(back|rear)")):
            rows += [
                ("view", f"{lat}-slight-{lon}", t.replace("{LAT}", lat).replace("{LON}", lon_words), False)
                for t in SIDE_SLIGHT_VIEW_FRAMES
            ]
        for lon, phrase in LONGITUDINAL.items():
            for degree, frame in COMBINED_VIEW_FRAMES:
                t = frame.replace("{LATERAL_OWN}", LATERAL_OWN).replace("{LATERAL}", LATERAL)
                t = t.replace("{LON}", phrase).replace("{LAT}", lat)
                rows.append(("view", f"{lon}-slight-{lat}" if degree else f"{lon}-{lat}", t, False))
    rows += [("view", ("azimuth", CLOCK_HOUR_DEG), t, False) for t in CLOCK_PHRASES + [SIX_OF, CLOCK_DIAL]]
    rows += [("view", ("azimuth", CLOCK_HOUR_DEG, half, 1.0), t, False) for half, t in CLOCK_BARE_HOURS.items()]
    rows += [("view", ("azimuth", CLOCK_HOUR_DEG, 1.0, 0.0), t, False) for t in (CLOCK_ONE, CLOCK_ONE_HOUR)]
    rows += [("note", None, t, False) for t in CLOCK_SETUP_PHRASES]
    rows += [("view", ("azimuth", 1.0), t, False) for t in SIGNED_AZIMUTH_PHRASES]
    rows += [("group", None, t, False) for t in GROUP_PHRASES]
    rows += [("elevation", e, t, False) for e, ts in ELEVATION_PHRASES.items() for t in ts]
    rows += [("elevation", e, t, True) for e, ts in ELEVATION_HINTS.items() for t in ts]
    rows += [("elevation_deg", sign, t, False) for sign, ts in EXPLICIT_ELEVATION_PHRASES.items() for t in ts]
    rows += [("elevation_deg", ("fixed", VERTICAL_UP_DEG), t, False) for t in VERTICAL_UP_PHRASES]
    rows += [("elevation_deg", ("magnitude", 1.0), t, False) for t in GIMBAL_PHRASES]
    rows += [("elevation_bare", None, t, True) for t in BARE_ANGLE_PHRASES]
    rows += [("place", None, t, False) for t in PLACE_PHRASES]
    rows += [("seen", None, t, False) for t in SEEN_PHRASES]
    rows += [("note", None, t, False) for t in NOTE_PHRASES]
    rows += [("light", None, t, False) for t in LIGHT_PHRASES]
    rows += [("correction", None, CORRECTION_PHRASE, False)]
    rows += [("roll_deg", sign, t, False) for sign, ts in ROLL_PHRASES.items() for t in ts]
    return rows + _family_rows(rows)


# --- families of phrasing1's misreadings (parse15), composed from the tables above ----------------
# A size pushed as far as it goes ("as big as it can possibly be", "as small as you can make it"),
# and a size said of the subject with a moderating word ("the mug rather small", "vase fairly big").
SIZE_EXTREME_FRAMES = [
    "(as )?{WORD} as (((it|you|we|one|they) )?((possibly|conceivably) )?(can|could|will|ll|would)"
    "( (possibly|reasonably|conceivably))?( (be|get( it)?|make it|go|manage( it)?|fit( it)?))?"
    "|possible|possibly can be|feasible)( in (the )?{FRAME})?",
    "{obj} {FAIRLY} {WORD}(?= ([,.;:!]|$|and |in |at |on |with |so |but ))",
]
# Room around the subject said to be seen ("plenty of tabletop visible round it", "lots of sky
# showing around it", "loads of floor in view about him").
ROOM_SEEN = (
    "(with )?{PLENTY} ([a-z]+ ){1,2}(visible|showing|in view|in shot|in frame|on show|to spare|left)"
    " (all )?(around|round|about) {obj}"
)

# The camera put where the subject's eyes are ("camera roughly where his eyes are", "lens just
# about where its face would be"): level with it.
EYE_PLACE = (
    "((the )?(camera|lens|cam) )?((({ABOUT}|just|right|roughly) )+)?((up|down|at|to) )?where {P}"
    " (eyes|nose|gaze|headlights|headlamps|{ANCHOR_EYE}) (are|is|would be|sit|sits|would sit)"
)

# A roll said with a particle after its verb ("the frame leaned over 15 degrees clockwise"), by
# what the picture's line does ("the horizon line running 10 degrees anticlockwise off level"), or
# as a noun before its degrees ("anticlockwise camera twist of thirty degrees", "a lens rotation of
# 20 degrees, counterclockwise"); {thing} the camera's or the picture's (:data:`CAMERA_THING`,
# :data:`PICTURE_THING`), which turns the other way.
ROLL_PARTICLE = "( over| round| around| across| off| away)?"
ROLL_LINE_VERBS = (
    "(running|runs|run|sitting|sits|lying|lies|slope|sloped|sloping|slopes|slant|slanted|slanting|slants|skewed|angled|set"
    "|going|dipping|dip|dips)"
)
OFF_LEVEL = "( (off|out of|from) (level|true|plumb|horizontal|the horizontal))?( (across|in) (the )?{FRAME})?"
# What the line is asked to do, maybe how it should look ("the horizon should slope 10 degrees
# anticlockwise", "have the skyline slope 8 degrees", "the horizon must spin 12 degrees clockwise",
# "should appear to tip").
ROLL_MODAL = (
    "( (should|must|will|shall|would|can|could|needs to|need to|has to|has got to|got to|ought to|is to|to))?"
    "( (appear|look|seem)( to)?)?( be)?"
)
# The line said to run or sit turned ("the floor line should run tilted 15 degrees ..."): parse18p6.
ROLL_LINE_TURNED = "( (tilted|tipped|sloped|slanted|canted|rotated|turned|skewed|angled))?"
ROLL_LINE = (
    "{thing}( line)?" + ROLL_MODAL + " (" + ROLL_VERB_FORMS + "|" + ROLL_LINE_VERBS + ")" + ROLL_LINE_TURNED + ROLL_PARTICLE
)
ROLL_FAMILY_FRAMES = [
    ROLL_LINE + "( by| through)? {d} {dir}" + OFF_LEVEL,
    ROLL_LINE + " {dir}( by| through)? {d}" + OFF_LEVEL,
    "(a |an )?{dir}{said} " + ROLL_NOUNS + "( of| by)? {d}",
    "(a |an )?{said_before}" + ROLL_NOUNS + " (of|by) {d}( ,)? {dir}",
]
# An upward angle with a word of its drama before it ("heroic upward angle", "a dramatic up shot of
# the tree", "an imposing low angle"): low.
DRAMATIC_UP = (
    "((a|an) )?(heroic|hero|dramatic|imposing|monumental|powerful|towering|epic|menacing|majestic)"
    " (up|low) (angle|shot|view|perspective|camera angle)( (of|at|on) {obj})?"
)
# The camera looking into the subject's eyes or face ("looking right into his button eyes"): its
# front, exactly when said so ("right" there is no side).
EYES_FRAME = (
    "(looking|look|looks|staring|stare|gazing|gaze|peering|peer)( {STRONGLY})? (into|at) (the |{P} )([a-z]+ )?(eyes|face)"
)
# A side said as "the <side> one" right after a view that lacks it ("back three-quarter, the
# right-hand one"): which side.
SIDE_ONE_AFTER_VIEW = (
    "(?:(?<=quarter , )|(?<=quarters , )|(?<=view , )|(?<=angle , )|(?<=diagonal , )|(?<=behind , )|(?<=rear , ))"
    "(the )?{LAT}( hand)?( side)? one(?= ([,.;!]|$))"
)
# Moved off a view just said towards a side, no amount said ("from the rear, edging out toward its
# right-hand end", "from behind, then ease over to its left"): that side, which the view said
# before it completes to their diagonal (VIEW_COMBINATIONS); with an amount it is the slight side
# (SLIGHT_VIEW_FRAMES, OFFSET_VIEW_FRAMES).
MOVED_TO_SIDE = (
    AFTER_REF + "((then|and|but|and then) )?{MOVE}( (out|off|over|a?round|across))? (to|towards) (the |{P} )?{LAT}( hand)?{PART}"
    "(?= ([,.;!?]|$|and |with |so |but ))"
)
# "At an angle" said with an end ("from behind at an angle", "the back, at an angle", "at an angle
# from the front"): that end's three-quarter, its side unsaid (VIEW_COMBINATIONS completes it with
# the end); alone it says no side and stays unread. A corner of that end left to the camera
# ("whichever rear corner you like", "either front corner") is the same three-quarter.
_END_WORDS = ("behind", "back", "rear", "front")
AT_AN_ANGLE = (
    "(?:"
    + "|".join(f"(?<={e}{o}{c} )" for e in _END_WORDS for o in ("", " it", " @\\d", " of it", " of @\\d") for c in ("", " ,"))
    + ")"
    "(at )?(an|a slight|a small) angle(?! of)|(at )?an angle(?= (from (the|{P}) (back|rear|front)|(from )?(behind|in front)))"
)
# The subject made to face the camera, said with a verb after it ("let the teddy face the camera",
# "have the mug face the lens"): its front.
MADE_TO_FACE = "(?<=@\\d )(face|faces) (towards |to )?" + VIEWER + "(?= ([,.;!?]|$|and |with |so |but |please ))"
# An end of it, or a part only at that end, as what is seen ("so that his face is what we see",
# "its tail lights are all we see"): that end.
END_SEEN = (
    "(the |{P} )?{LON}( side| end)? (is|are) (what|all|the (thing|part|bit)) (we|you|i|the camera|the viewer) (see|sees|get|gets)"
)
ANY_CORNER = "(whichever|whatever|either|any|one) (of (the|{P}) )?{END} corners?"
# Whose side is meant, said with the side: the subject's own, against the camera's ("on HIS left
# side, not yours", "its right, mind, not the camera's"), as it would see it itself ("the right side
# as the fridge itself would see it"), or of one sitting in it ("the left of whoever sits in it");
# also an end or side said on that side ("from the end on its left"). Each names that side.
_NOT_YOURS = "(not|and not|rather than) (yours|urs|your|ur|mine|ours|the (camera|viewer|lens|photographer) 's)( {LAT})?"
# An end and a side said together as what is seen ("the front and its left side both in view",
# "the doors plus its right side", "where the car's nose meets its right flank", "its right side
# and the back"): their diagonal. An end may be named by a part found at it (LON_WORDS, FACING_PARTS).
_AND = "(and|plus|&|as well as|together with|along with)"
_LAT_SIDE = "(the |{P} )?{LAT}( hand)?{PART}( of {obj})?(?! of )"
TWO_SIDES_PHRASES = [
    "(the |{P} |{CLAUSE})({LON})( side| end)?( of {obj})? " + _AND + " " + _LAT_SIDE,
    "(the |{P} )?{LAT}( hand)?{PART} " + _AND + " (the |{P} )({LON})( side| end)?(?! of )",
    "((the (corner|edge|point|spot) )?where )(the |{P} )({LON})( side| end)? (meets|joins|turns into) " + _LAT_SIDE,
]
OWN_SIDE_PHRASES = [
    "((on|at|to|from) )?{P} {LAT}( hand)?( side)?( ,)?( (mind|i mean|that is|remember))?( ,)? " + _NOT_YOURS,
    "(the |{P} )?{LAT}( hand)?( side)? (as|like) ({obj}|he|she)( (itself|himself|herself))?( (would|will|does))?"
    " (see|sees|know|knows|feel|feels|have|has) it",
    "(the |{P} )?{LAT}( hand)?( side)? of (whoever|whomever|anyone|anybody|someone|somebody|a person|the person|one)"
    "( who)? (sits|sitting|sat|seated|lies|lying|stands|standing) (in|on|at) (it|{obj})",
    "from (the|{P}) (end|side) (on|at|to) (the|{P}) {LAT}( hand)?( side)?( of {obj})?",
]
# Verbs of looking other than "look", for every height said with it ("peering up", "gazing
# upward along the pole", "staring down at it"): the height phrases of "look" said with them.
LOOK_VERBS = "(peering|peer|peers|gazing|gaze|gazes|staring|stare|stares|glancing|glance|glances|peeking|peeping)"
LOOK_WORD = re.compile(r"\blook(?:ing|s)?\b")


def _family_rows(tables: list[tuple[str, object, str, bool]]) -> list[tuple[str, object, str, bool]]:
    """Rows of the families above, each over every side, size or roll word of the tables; ``tables``:
    the tables' own rows, whose height phrases of "look" are said again with the other verbs of
    looking (:data:`LOOK_VERBS`)."""
    rows = []
    for shot in ("close-up", "wide"):
        said = _alternatives(w for w in SIZE_WORDS[shot] if " " not in w)
        rows += [("shot", shot, t.replace("{WORD}", said), False) for t in SIZE_EXTREME_FRAMES]
    rows.append(("shot", "wide", ROOM_SEEN, False))
    rows.append(("elevation", "eye level", EYE_PLACE, False))
    rows.append(("elevation", "low angle", DRAMATIC_UP, False))
    rows.append(("view", "front-exact", EYES_FRAME.replace("( {STRONGLY})?", " (right|straight|directly|dead|squarely)"), False))
    rows.append(("view", "front", EYES_FRAME.replace("( {STRONGLY})?", ""), False))
    rows += [("view", lat, SIDE_ONE_AFTER_VIEW.replace("{LAT}", lat), False) for lat in ("left", "right")]
    rows += [("view", lat, MOVED_TO_SIDE.replace("{LAT}", lat), False) for lat in ("left", "right")]
    rows.append(("view", "front", MADE_TO_FACE, False))
    rows += [("view", end, END_SEEN.replace("{LON}", LON_WORDS[end]), False) for end in ("front", "back")]
    rows.append(("view", "three-quarter", AT_AN_ANGLE, False))
    rows.append(("view", "back-three-quarter", ANY_CORNER.replace("{END}", "(rear|back)"), False))
    rows.append(("view", "three-quarter", ANY_CORNER.replace("{END}", "front"), False))
    rows += [("view", lat, t.replace("{LAT}", lat), False) for lat in ("left", "right") for t in OWN_SIDE_PHRASES]
    for lon in ("front", "back"):
        ends = LON_WORDS[lon][:-1] + "|" + "|".join(sorted(FACING_PARTS[lon], key=len, reverse=True)) + ")"
        rows += [
            ("view", f"{lon}-{lat}", t.replace("{LAT}", lat).replace("{LON}", ends), False)
            for lat in ("left", "right")
            for t in TWO_SIDES_PHRASES
        ]
    for sign, thing in ((1.0, CAMERA_THING), (-1.0, PICTURE_THING)):
        # The camera may go unsaid in a roll's noun ("a clockwise twist of 20 degrees"); the
        # picture, which turns the other way, must be said.
        after, before = (f"( {thing})?", f"({thing} )?") if sign > 0 else (f" {thing}", f"{thing} ")
        for frame in ROLL_FAMILY_FRAMES:
            t = frame.replace("{thing}", thing).replace("{said}", after).replace("{said_before}", before)
            rows.append(("roll_deg", sign, t, False))
    rows += [
        (field, value, LOOK_WORD.sub(LOOK_VERBS, t), weak)
        for field, value, t, weak in tables
        if field in ("elevation", "elevation_deg") and LOOK_WORD.search(t)
    ]
    return rows


# An end's words as a direction, and as an adverb ("towards the rear", "a bit forward").
# A part found only at that end names it too ("slightly toward its tail lights": vocabulary.END_PARTS).
LON_WORDS = {
    "front": _alternatives(("front", "face", "nose", "bow", *END_PARTS["front"])),
    "back": _alternatives(("back", "rear", "tail", "stern", *END_PARTS["back"])),
}
# Also the place itself ("from the right side, drifting a bit behind him", "a touch in front of
# it"); not before a named object, where it relates the two ("a bit behind the vase").
LONWARD_WORDS = {
    "front": "(forward|forwards|frontward|frontwards|in front( of (it|him|her|them))?)",
    "back": "(backward|backwards|rearward|rearwards|behind( (it|him|her|them))?)",
}


def _lon_frame(template: str, lat: str, lon: str) -> str:
    """A side-offset template for the side ``lat`` turned towards the end ``lon``."""
    return template.replace("{LAT}", lat).replace("{LONWARD}", LONWARD_WORDS[lon]).replace("{LON}", LON_WORDS[lon])


def _lexicon(rows) -> frozenset[str]:
    """Every word the tables use: such a word before a name is not an attribute of the subject."""
    text = " ".join(t for _, _, t, _ in rows) + " " + " ".join(_MACROS.values())
    # The words a direction of turning is said with, which the word pipeline reads (TURN_DIRECTION_*).
    said = {w for lead in TURN_DIRECTION_LEADS for w in lead if w.isalpha()} | TURN_DIRECTION_NOUNS
    return frozenset(re.findall(r"[a-z]+", re.sub(r"\{[^}]*\}|\(\?P<\w+>", " ", text))) | STOPWORDS | said


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
    ``determiner``: right after "the"/"a"... (a noun phrase); ``subject``: the noun phrase of
    unknown words the run opens the sentence with, when a place relation ties it to a named object
    ("wristwatch" of "wristwatch lying by the mug"), else None."""

    at: int
    text: str
    slot: bool
    determiner: bool
    subject: str | None = None


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
        self.rules = []
        for field, value, template, weak in rows:
            tree = _pattern_tree(_expand(template))
            # A row said only where a word is said too (an hour said bare, where a clock is).
            needs = _required(tree) + RULE_CONTEXTS.get(template, ())
            self.rules.append(_Rule(field, value, _compiled(tree), weak, needs, _required_any(tree)))
        # Details are words too: never a misspelt name ("cables" is no "table").
        self.lexicon = _lexicon(rows) | DETAIL_PARTS

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction:
        """``text`` as a :class:`ParsedInstruction` with subjects from ``vocabulary``;
        :class:`InputError` (one line) for an empty instruction, one without a subject, a subject
        not in the scene or an ambiguous one, and contradictory cues."""
        if not text or not text.strip():
            raise InputError(f"the instruction is empty; expected e.g. 'a close-up of the {_example(vocabulary)} on the left'")
        if not len(vocabulary):
            raise InputError("the scene names no objects (no semantic labels), so no subject can be matched")
        said = words(text)
        parsed = self._read(text, said, vocabulary)
        return self._skipping_a_word(parsed, said, vocabulary) if parsed.not_understood() else parsed

    def _skipping_a_word(self, parsed: ParsedInstruction, said: list[str], vocabulary: Vocabulary) -> ParsedInstruction:
        """``parsed`` read again with one word of a clause it did not understand left out, when
        that reads the rest of the clause: a word the tables use in an unusual place breaks a
        phrase they know ("seen from its left flank side": "from its left flank"), and so does one
        they do not know ("pointed straight glossy at the lens", "back xyz right diagonal"). The
        reading is kept only when it keeps every field of ``parsed`` and adds one, or, leaving out
        a word the tables do not know, reads more words and changes a value ("back" ->
        "back-right"); of several, the one gaining most (the earliest word on a tie). The word
        left out is reported in ``unparsed``.

        Only a word between two others is left out, and the rest of its clause and the words on
        both sides of it must be read once it is: the word broke a phrase ("Mug up front" is no
        front view: "mug" is a name; "the far side of the room" is no side view: "room" stays
        unread). Never a stopword, a negation, a number or a word of a scene name, nor a word of a
        noun phrase's own: the one after its determiner ("the middle ground" is not "the ground")
        or the noun an "of" follows ("the front left wheel of the car" is no front-left view):
        leaving those out changes what is asked ("off to his left" without "his" is a region)."""
        readings = _readings(parsed)
        runs = [set(words(run)) for run in parsed.not_understood()]
        names = vocabulary.name_words()
        best, best_gain = parsed, 0
        for i, word in enumerate(said[1:-1], start=1):
            neighbours = {said[i - 1], said[i + 1]}
            clause = next((run for run in runs if word in run), None)
            if clause is None or not _skippable(word, names) or neighbours & (names | PUNCTUATION):
                continue
            if said[i - 1] in DETERMINERS or said[i + 1] == "of":  # a noun phrase's own words
                continue
            try:
                again = self._read(parsed.text, said[:i] + said[i + 1 :], vocabulary)
            except InputError:
                continue
            # The word must have broken a phrase: its clause and the words beside it are read now.
            if (clause | neighbours) - {word} & {w for run in again.not_understood() for w in words(run)}:
                continue
            # A value changes only for an unknown word ("back xyz right diagonal"): one the
            # tables use may say something ("almost on the tabletop" is no eye level).
            read = _unread(parsed) - _unread(again) - 1 if word not in self.lexicon else 0
            gain = _extension(readings, _readings(again), read)
            if gain > best_gain:
                best, best_gain = replace(again, unparsed=[*again.unparsed, word]), gain
        return best

    def _read(self, text: str, said: list[str], vocabulary: Vocabulary) -> ParsedInstruction:
        """The reading of ``text`` from its normalised words ``said`` (see :meth:`parse`)."""
        tokens, slips = self._unslip(said, vocabulary)
        tokens = _unrepeated(_unfilled([t for t in tokens if t not in PLEASE]))
        tokens, mentions, corrected = self._spot(tokens, vocabulary)
        corrected = slips + corrected
        cues = _corrected(_unnegated(_bare_angles(self._cues(tokens), tokens), tokens), tokens)
        unparsed = []
        determined = [m.text.split()[0] in MENTION_DETERMINERS for m in mentions]
        # A thing placed at a named object, or a setting holding it, is what the sentence is about.
        placed = self._placed_thing(tokens, cues)
        if placed is not None:
            mentions.append(_Mention(placed[0], placed[1], vocabulary.match(placed[1])))
        setting = self._setting_holding(tokens)
        if setting is not None:  # a room or a garden is never one of the scene's objects ("garden" of "garden bench")
            raise InputError(f"subject {setting[1]!r} is not in this scene; known: {vocabulary.names}")
        for run in self._leftovers(tokens, cues, determined):
            # The sentence's subject: a scene object, or refused naming the closest; a part or a
            # position tied to the subject ("so we see the seam down its back") is neither.
            if run.subject is not None and not _never_a_name(run.subject):
                mentions.append(_Mention(run.at, run.subject, vocabulary.match(run.subject)))
            # In a subject's place a run names an object if it can; led by a determiner it must.
            elif (
                run.slot
                and not _never_a_name(run.text)
                and (run.determiner or vocabulary.candidates(run.text) or _before_relation(run.text) in KIN_NAMES)
            ):
                mentions.append(_Mention(run.at, run.text, vocabulary.match(_before_relation(run.text))))
            else:
                unparsed.append(run)
        for run in unparsed:  # a thing joined to a subject is one too ("harmonica?? next to the mug")
            thing = self._joined_thing(tokens, run) or self._placed_second(tokens, run)
            if thing is not None:
                mentions.append(_Mention(run.at, thing, vocabulary.match(thing)))
        if not mentions:  # the sentence names its subject somewhere: try what was not understood
            for run in unparsed:
                # A description is read too ("the thing with the books on it": parse19p7).
                if (not _never_a_name(run.text) or vocabulary.described(key(run.text))) and vocabulary.candidates(run.text):
                    mentions.append(_Mention(run.at, run.text, vocabulary.match(run.text)))
            unparsed = [run for run in unparsed if run.at not in {m.at for m in mentions}]
        unparsed_text = [run.text for run in unparsed] + [c.text for c in cues if c.field == "light"]
        group = any(c.field == "group" for c in cues)
        if not mentions and group:  # "a bird's eye of everything": the scene's objects, the first primary
            mentions = [_Mention(len(tokens), name, name) for name in vocabulary.names[:1]]
        if not mentions:
            hint = f" (not understood: {clip(repr(unparsed_text))})" if unparsed else ""
            raise InputError(f"no subject in {clip(text.strip())!r}{hint}; name one of the scene's objects: {vocabulary.names}")
        mentions.sort(key=lambda m: m.at)
        subjects = _attach(cues, mentions, tokens, vocabulary)
        if group:
            named = {s.name for s in subjects}
            subjects += [ParsedSubject(n, n, "secondary", vocabulary.symmetric(n)) for n in vocabulary.names if n not in named]
        elevation, elevation_deg = _elevation(cues)
        return ParsedInstruction(text, subjects, elevation, elevation_deg, _roll(cues), unparsed_text, corrected)

    def _unslip(self, tokens: list[str], vocabulary: Vocabulary) -> tuple[list[str], list[dict[str, str]]]:
        """``tokens`` with each mistyped table word read as it (:func:`~capframe.translate.vocabulary.slip_of`:
        "hight" -> "height"; :func:`_view_slip`: "from the font"), and those readings; a word the
        tables or the scene's names use is never one."""
        names = vocabulary.name_words()
        out, read = [], []
        for token in tokens:
            known = token in self.lexicon or token in STOPWORDS or singular(token) in names
            joined = out[-1] + token if out and not known and token.isalpha() and out[-1].isalpha() else ""
            if len(joined) >= MIN_SPLIT_LETTERS and joined in self.lexicon:
                # A table word split in two, its second piece no word the tables know ("slightly a
                # bove it", "be neath", "hori zontal"): read whole (parse20h).
                read.append({"said": f"{out[-1]} {token}", "read": joined})
                out[-1] = joined
                continue
            target = None if known else self._unknown_word(out, token, names, vocabulary)
            out.extend(target or (token,))
            if target:
                read.append({"said": token, "read": " ".join(target)})
        # A number word before a fraction mistyped was read as a digit ("three-qarter" -> "3
        # quarter"): "three quarter" as :func:`~capframe.translate.vocabulary.words` writes it.
        out = ["three" if t == "3" and out[k + 1 : k + 2] in (["quarter"], ["quarters"]) else t for k, t in enumerate(out)]
        return out, read

    def _unknown_word(self, before: list[str], token: str, names: set[str], vocabulary: Vocabulary) -> tuple[str, ...] | None:
        """How a word neither the tables nor the scene's names use is read, or None: with its
        held letters let go ("pleeease", "biiig": :func:`unstretched`), as the table word it
        mistypes, as the name words it writes short or runs together
        (:meth:`Vocabulary.expansion`: "tbl", "teddybear")."""
        if not token.isalpha():
            return None
        loose = unstretched(token, lambda w: w in self.lexicon or w in STOPWORDS or w in names)
        target = loose or slip_of(token) or _view_slip(before, token, names)
        return (target,) if target else vocabulary.expansion(token)

    def _spot(self, tokens: list[str], vocabulary: Vocabulary) -> tuple[list[str], list[_Mention], list[dict[str, str]]]:
        """Replace each subject mention by a placeholder ``@k``: the longest name or alias at each
        position, with the attribute words and determiner before it. A longer run of words that
        misspells one name or alias is read as it; each such reading is returned."""
        forms = {f for f in vocabulary.forms() if _spottable(f)}
        longest = max(map(len, forms), default=0)
        keys = [singular(t) for t in tokens]
        out: list[str] = []
        mentions: list[_Mention] = []
        corrected: list[dict[str, str]] = []
        i = 0
        while i < len(tokens):
            n = next((n for n in range(min(longest, len(tokens) - i), 0, -1) if tuple(keys[i : i + n]) in forms), 0)
            if n == 1 and _height_anchor(tokens, i):
                n = 0
            if (
                n
                and " ".join(tokens[i : i + n]) in OWN_PARTS
                and _owned(out, mentions, vocabulary.candidates(" ".join(tokens[i : i + n])))
            ):
                n = 0  # a part of what was named ("the tv, its screen to us"), not a name of its own
            read = tokens[i : i + n]
            misspelt = self._misspelt(tokens, keys, i, n, longest + 1, vocabulary)
            if misspelt is not None:
                n, read = misspelt
                corrected.append({"said": " ".join(tokens[i : i + n]), "read": " ".join(read)})
            if not n:
                out.append(tokens[i])
                i += 1
                continue
            before: list[str] = []
            while out and len(before) < MAX_ATTRIBUTES and self._attribute(out[-1]):
                before.insert(0, out.pop())
            if out and out[-1] in MENTION_DETERMINERS:
                before.insert(0, out.pop())
            name = vocabulary.match(" ".join(before + list(read)))
            mentions.append(_Mention(len(out), " ".join(before + tokens[i : i + n]), name, len(mentions)))
            out.append(f"@{len(mentions) - 1}")
            i += n
        return out, mentions, corrected

    def _misspelt(
        self, tokens: list[str], keys: list[str], i: int, shorter: int, longest: int, vocabulary: Vocabulary
    ) -> tuple[int, tuple[str, ...]] | None:
        """The longest run of more than ``shorter`` words from ``i`` that misspells one name or
        alias (:meth:`Vocabulary.correction`), as (its length, the words read), judged on its
        singular words and, when they differ, on the words as written ("vaes" is "vase" with two
        letters swapped, its crude singular "vae" is not); words the phrase tables use are never
        taken for a misspelling ("close" is not "closet"), unless the name has them as written
        ("floor lamb" is "floor lamp"), nor are attributes ("green bench" is no "garden bench"),
        nor a word of a name said as written ("little bear" is no "little car": "bear" names the
        teddy bear)."""
        named = vocabulary.name_words()
        for n in range(min(longest, len(keys) - i), shorter, -1):
            window = tuple(keys[i : i + n])
            if not all(w.isalpha() for w in window):
                continue
            for said in dict.fromkeys((window, tuple(tokens[i : i + n]))):
                form = vocabulary.correction(said)
                if (
                    form is not None
                    and _spottable(form)
                    and all(w in form or (w not in self.lexicon and w not in ATTRIBUTES and w not in named) for w in window)
                ):
                    return n, form
        return None

    def _attribute(self, token: str) -> bool:
        """Whether ``token`` may describe the subject named after it: a known attribute, a setting
        ("garden sofa", "kitchen table"), or a word the tables do not use ("fluffy")."""
        return token in ATTRIBUTES or token in SETTINGS or (token.isalpha() and token not in self.lexicon)

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
            if not all(need in text for need in rule.needs) or not all(
                any(need in text for need in group) for group in rule.needs_any
            ):
                continue
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

    def _leftovers(self, tokens: list[str], cues: list[_Cue], determined: list[bool]) -> list[_Run]:
        """Runs of words no phrase explains, less stopwords at their ends, each marked whether it
        stands in a subject's place (right after a head, right before a region, joined to a
        subject by "and"/"or", or opening the sentence as a noun phrase: "the kitten hiding behind
        the cushion" is about a kitten, not the cushion). ``determined[k]``: the spotted mention
        ``@k`` opens with a determiner."""
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
            before, after = ends.get(span[0]), starts.get(span[-1] + 1)
            # Words right before "shot of" / "view of" describe the picture, not a subject ("a
            # candid shot of the bear", "a dramatic worm's-eye view of the tree").
            of_picture = after is not None and (after.forward or tokens[after.end : after.end + 1] == ["of"])
            # Words ending on "of"/"at" right before a named object describe the picture of it ("frame
            # a dramatic look at the mug", "photograph a close study of the teddy"), not a subject.
            following = tokens[span[-1] + 1] if span[-1] + 1 < len(tokens) else ""
            of_named = tokens[span[-1]] in ("of", "at") and following.startswith("@")
            asked = self._asked_thing(tokens, span)
            slot = asked or (
                not (of_named or (after is not None and after.forward))
                and (
                    (before is not None and before.forward)
                    or (after is not None and after.field == "region")
                    or _coordinated(tokens, span)
                    or (_opening_noun_phrase(tokens, span, determined) and not of_picture)
                )
            )
            opening = (before is not None and before.forward) or _sentence_opening(tokens, span[0])
            subject = self._related_subject(tokens, span) if opening and not _topic_opening(tokens, span) else None
            for part in _position_split(tokens, span):
                run = [tokens[k] for k in part]
                lo, hi = 0, len(run)
                while lo < hi and run[lo] in STOPWORDS:
                    lo += 1
                while hi > lo and run[hi - 1] in STOPWORDS:
                    hi -= 1
                if lo < hi:
                    determiner = asked or (lo > 0 and run[lo - 1] in MENTION_DETERMINERS)
                    introduced = determiner and self._introduced(
                        run[: lo - 1], run[lo:hi], tokens[part[0] + hi : part[0] + hi + 1]
                    )
                    runs.append(
                        _Run(
                            part[0], " ".join(run[lo:hi]), slot or introduced, determiner, subject if part[0] == span[0] else None
                        )
                    )
        return runs

    def _introduced(self, before: list[str], thing: list[str], after: list[str]) -> bool:
        """Whether ``thing`` (after its article) is introduced by "there is" ("Next to the vase
        there's a sugar bowl, take it from the front"): a thing the sentence is about, in a
        subject's place, when its words are at most :data:`MAX_ATTRIBUTES`, its head no word of
        the tables and no amount ("there's a lot of room", "a bit of space" name nothing)."""
        return (
            before[-2:] in EXISTENTIALS
            and after != ["of"]
            and len(thing) <= MAX_ATTRIBUTES
            and all(w.isalpha() for w in thing)
            and thing[-1] not in self.lexicon
            and thing[-1] not in ATTRIBUTES
        )

    def _asked_thing(self, tokens: list[str], span: list[int]) -> bool:
        """Whether ``span`` is a thing named alone as the instruction's first sentence, which the
        next one opens by placing "it" at a named object ("Hourglass? It stands by the mug",
        "Candle. It's next to the vase"): the subject, named without an article, whatever it
        names. Words the tables use are never such a thing, and "it" said to be the named object
        is no place ("Sorry. It is the mug I want")."""
        end = span[-1] + 1
        if span[0] != 0 or tokens[end : end + 1] not in (["?"], ["."]) or tokens[end + 1 : end + 2] != ["it"]:
            return False
        placing = _up_to_subject(tokens[end + 2 :])
        if not any(t in RELATION_WORDS for t in placing) or len(placing) > MAX_ATTRIBUTES + 1:
            return False
        content = [tokens[k] for k in span if tokens[k] not in STOPWORDS]
        return 0 < len(content) <= MAX_ATTRIBUTES and all(w.isalpha() and w not in self.lexicon for w in content)

    def _joined_thing(self, tokens: list[str], run: _Run) -> str | None:
        """The thing a run not understood names when it is joined to a named subject, so a second
        subject (refused when the scene lacks it), else None: a noun of words the tables do not use,
        right before a relation to the subject ("harmonica?? next to the mug", "a kazoo beside it")
        or right after a joining word after it (:data:`JOINS_AFTER`: "mug and harmonica", "mug
        plus a kazoo", "bench with a bicycle, both visible"; after "with" only with an article:
        "the sofa with cushions" is the sofa), or there tied back to the subject ("plus the speaker
        beside it"; after "with" or a comma only when both are asked for)."""
        said = run.text.split()
        start = next((k for k in range(run.at, len(tokens)) if tokens[k : k + len(said)] == said), None)
        if start is None:
            return None
        # The joining word may open the run ("plus a kazoo"): the thing is what follows it.
        lead = next((j for j in JOINS_AFTER if said[: len(j)] == j), [])
        before = [t for t in tokens[:start] if t != ","] + said[: len(lead)]
        rest = said[len(lead) :] if lead else tokens[start - 1 : start] + said
        article = rest[:1] in ARTICLE_WORDS
        thing = said[len(lead) + article :] if lead else said
        if article and not lead:
            before = before[:-1]
        # A relation back to the subject may end the run ("plus the speaker beside it"): the thing
        # is what comes before it, and the rest of the clause follows it.
        relation = next((k for k in range(1, len(thing)) if thing[k] in RELATION_WORDS), len(thing))
        thing, tied = thing[:relation], thing[relation:]
        if not thing or len(thing) > MAX_ATTRIBUTES or _never_a_name(" ".join(thing)):
            return None
        head = thing[-1]
        if not head.isalpha() or head in self.lexicon or head in ATTRIBUTES:
            return None
        after = tied + tokens[start + len(said) :]
        # Before a relation only as the sentence's opening ("a kazoo beside the mug"), not a time or
        # a place said on the way ("taken at dusk with the bench ...").
        opening = all(t in STOPWORDS or t in PUNCTUATION for t in tokens[:start])
        while after and after[0] in PUNCTUATION:
            after = after[1:]
        joined_after = (
            not lead and opening and any(after[: len(j)] == j and _names_subject(after[len(j) :]) for j in JOINS_BEFORE)
        )
        # After a joining word only where the clause ends on it ("mug plus a kazoo, both in frame"),
        # not before what places it ("the bench with a sunset behind it").
        following = tokens[start + len(said) : start + len(said) + 1]
        ends = not tied and (not following or following[0] in PUNCTUATION or following[0] in THING_ENDS)
        # Or it is tied back to the subject ("the speaker beside it", "the bicycle leaning against
        # it"): after "and" or "plus" that is a second thing; after "with" only when both are asked
        # for ("the bench with the bicycle leaning against it, both in frame"; "the bench with a
        # sunset behind it" is the bench).
        clause = tied + list(itertools.takewhile(lambda t: t not in PUNCTUATION, tokens[start + len(said) :]))
        back = clause[-1:] in (["it"], ["them"]) and len(clause) <= MAX_ATTRIBUTES + 1
        both = any(t in BOTH_WORDS for t in tokens)
        # Set beside it after a comma, when both are asked for ("the mug, the teapot next to it,
        # both sharp").
        set_off = tokens[: start - 1] if article and not lead else tokens[:start]
        apposed = len(set_off) > 1 and set_off[-2].startswith("@") and set_off[-1] == "," and back and both and not ends
        joined_before = apposed or any(
            before[-len(j) :] == j
            and len(before) > len(j)
            and before[-len(j) - 1].startswith("@")
            and (article or j != ["with"])
            and (ends or (back and (j != ["with"] or both or tied[:1] in SIDE_BY)))
            for j in JOINS_AFTER
        )
        return " ".join(thing) if joined_after or joined_before else None

    def _placed_second(self, tokens: list[str], run: _Run) -> str | None:
        """The thing a run names when it is placed at the subject named right before it, or before
        one verb of placing, and both are asked for (:data:`BOTH_WORDS`: "the mug next to a laptop,
        both sharp", "the sofa under the painting, both in frame", "the car parked beside a kite,
        both visible"): a second subject, refused when the scene lacks it; without
        "both" it is a landmark, reported ("the mug next to a hairbrush"). Its words are at most
        :data:`MAX_ATTRIBUTES`, none a word of the tables; None otherwise."""
        if not any(t in BOTH_WORDS for t in tokens):
            return None
        said = run.text.split()
        start = next((k for k in range(run.at, len(tokens)) if tokens[k : k + len(said)] == said), None)
        if start is None:
            return None
        # The run may hold a verb of placing, the preposition and an article ("parked next to a
        # laptop"): the thing follows them.
        if len(said) > 1 and not _opening_preposition(said) and _placing(said[0]) and _opening_preposition(said[1:]):
            said, start = said[1:], start + 1
        opening = _opening_preposition(said)
        article = said[len(opening) : len(opening) + 1] in ARTICLE_WORDS
        skip = len(opening) + (article if opening else 0)
        said, start = said[skip:], start + skip
        # Back from the thing over an article and the place preposition to the named subject.
        k = start - (tokens[start - 1 : start] in ARTICLE_WORDS)
        relation = next((p for p in PLACED_PREPOSITIONS if k >= len(p) and tokens[k - len(p) : k] == list(p)), None)
        if relation is None:
            return None
        # The subject right before the relation, or before one verb of placing ("the car parked beside").
        k -= len(relation)
        k -= k >= 2 and _placing(tokens[k - 1]) and tokens[k - 2].startswith("@")
        if k < 1 or not tokens[k - 1].startswith("@"):
            return None
        end = start + len(said)
        if end < len(tokens) and tokens[end] not in PUNCTUATION and tokens[end] not in THING_ENDS:
            return None
        if len(said) > MAX_ATTRIBUTES or not all(w.isalpha() and w not in self.lexicon for w in said):
            return None
        return " ".join(said) if said and not _never_a_name(" ".join(said)) else None

    def _related_subject(self, tokens: list[str], span: list[int]) -> str | None:
        """The noun phrase ``span`` opens with when a place relation (:data:`RELATION_WORDS`) ties
        it to the named object right after the span ("sunglasses lying next to | the teddy"): words
        the tables do not use, attributes aside ("tall mirror"), or any words after a determiner
        ("a cat sat on the sofa": "cat" is also a table word, of "a cat's-eye view"); None
        otherwise. Such a phrase is the sentence's subject, whatever it names."""
        if span[-1] + 1 >= len(tokens) or not tokens[span[-1] + 1].startswith("@"):
            return None
        # The thing may follow a verb asking for it or putting it there ("could you find the
        # abacus by", "my grandson left his ukulele next to", "I put the abacus by"); "our
        # postman having his lunch on" is about the postman.
        first = next((k for k, at in enumerate(span) if tokens[at] not in STOPWORDS), 0)
        verb = next(
            (
                k
                for k, at in enumerate(span[:-1])
                if (tokens[at] in PUTTING_VERBS or (k == first and tokens[at] in PLACED_LEADS))
                and tokens[at + 1] in PUT_DETERMINERS
            ),
            None,
        )
        span = span if verb is None else span[verb + 1 :]
        lead = next((tokens[at] for at in span if tokens[at] in MENTION_DETERMINERS or tokens[at] not in STOPWORDS), "")
        determined = lead in MENTION_DETERMINERS  # "(of) the candle in front of": a noun phrase
        relation = RELATION_WORDS | RELATION_OBJECT_WORDS if determined else RELATION_WORDS
        start = next(k for k, at in enumerate(span) if tokens[at] == lead) if lead else 0
        # "to the left of" (or right) places it too, as "beside" does.
        beside = [k for k, at in enumerate(span) if tokens[at] in ("left", "right") and tokens[at + 1 : at + 2] == ["of"]]
        cut = next((k for k, at in enumerate(span) if k > start and (tokens[at] in relation or k in beside)), None)
        phrase = [tokens[at] for at in span[:cut]] if cut else []
        while phrase and phrase[0] in STOPWORDS:
            phrase.pop(0)
        while phrase and phrase[-1] in STOPWORDS:
            phrase.pop()
        phrase = _unplaced(phrase)  # "the light falling on the vase" is about light, no thing
        # What a possessor owns is the thing, judged without the possessor ("Grandma's rocking
        # horse", "Dad's slippers": a requester is a table word), which the name keeps unless it
        # is such a word ("Rubik's cube", "my dog's bowl").
        owner = next((k for k in range(len(phrase) - 1, -1, -1) if phrase[k] == "'s"), None)
        owned = phrase if owner is None else phrase[owner + 1 :]
        content = [w for w in owned if w not in STOPWORDS]
        if not content or all(w in ATTRIBUTES for w in content) or _never_a_name(" ".join(content)):
            return None
        if any(w in ("camera", "lens") for w in phrase):  # "a camera buried in the sand below the bench"
            return None
        # A possessive determines the phrase as an article does ("Grandpa's walking stick").
        if (
            owner is None
            and not determined
            and any(w in self.lexicon and w not in ATTRIBUTES and w not in TABLE_NOUNS for w in content)
        ):
            return None  # "focus on the mug": a verb of the tables, not a thing
        possessor = [w for w in phrase[: owner or 0] if w not in STOPWORDS]
        return " ".join(owned if any(w in self.lexicon for w in possessor) or _never_a_name(" ".join(possessor)) else phrase)

    def _placed_thing(self, tokens: list[str], cues: list[_Cue]) -> tuple[int, str] | None:
        """The thing placed at a named object, when the sentence is about it: ``(token, words)`` of
        "<noun phrase> <placing words> <place preposition> @k" (:data:`PLACED_PREPOSITIONS`), the
        placing words a verb of where it is (a participle, a relative clause: :func:`_placing`)
        with adverbs ("fountain splashing away somewhere behind the bench", "the fireplace that's
        behind our settee", "a close detail of the teaspoon resting in the mug"), the noun phrase in
        the subject's place (:func:`_subject_place`); else None. Its head names no view,
        position, size or state (:data:`RESERVED`, :func:`_never_a_name`), nor the camera or its
        move (:data:`CAMERA_HOLDERS`), and no phrase explains it. A known subject before a landmark
        ("the mug on the table") is no such phrase, nor is a simile ("like a toddler looking up at
        the teddy")."""
        covered = {k for c in cues for k in range(c.start, c.end)}
        for at, token in enumerate(tokens):
            if not token.startswith("@"):
                continue
            found = _placed_phrase(tokens[:at])
            if found is None:
                continue
            start, end = found
            thing = tokens[start:end]
            head = thing[-1]
            determined = start > 0 and tokens[start - 1] in MENTION_DETERMINERS
            if (
                head.isalpha()
                and head not in ATTRIBUTES
                and (end - 1) not in covered
                and head not in RESERVED
                and not any(w in CAMERA_HOLDERS for w in thing)
                and not _never_a_name(" ".join(thing))
                and _subject_place(tokens[: start - determined])
            ):
                return start, " ".join(thing)
        return None

    def _setting_holding(self, tokens: list[str]) -> tuple[int, str] | None:
        """The setting a picture is of when it holds the named object ("a picture of the kitchen
        with the plant in it", "the lounge, with the sofa inside it"): ``(token, words)`` of a
        :data:`HOLDING_SETTINGS` word after a determiner, "of" or the opening, then "with" (or
        "containing", "holding") the subject and "in it" / "inside" / "in there"; else None. A
        setting with the subject in a part of the frame ("a wide view of the room with the plant
        in the lower right") or said where the subject is ("the sofa in the living room") is the
        setting, understood, as before."""
        for at, token in enumerate(tokens):
            if not token.startswith("@") or at < 2 or tokens[at - 1] not in HOLDING_WORDS:
                continue
            clause = list(itertools.takewhile(lambda t: t not in PUNCTUATION, tokens[at + 1 :]))
            if tuple(clause) not in HELD_INSIDE:
                continue
            before = tokens[: at - 1]
            if before[-1:] == [","]:
                before = before[:-1]
            for n in (2, 1):
                said = " ".join(before[-n:])
                lead = before[-n - 1 : -n] if len(before) > n else []
                if len(before) >= n and said in HOLDING_SETTINGS and (not lead or lead[0] in MENTION_DETERMINERS | {"of"}):
                    return len(before) - n, said
        return None


# Words said twice for emphasis, maybe with a comma between ("really, really small", "tiny, tiny").
EMPHATIC_WORDS = frozenset(DEGREE_SCALE["strong"]) | {"so"} | {w for ws in SIZE_WORDS.values() for w in ws}


EXISTENTIALS = (["there", "'s"], ["there", "is"], ["there", "are"], ["there", "was"], ["there", "s"])


# Family said as names, without an article ("Photograph Grandma in the armchair"): a person, in a
# subject's place a subject (refused when the scene lacks it), as "my sister" is.
KIN_NAMES = frozenset(
    {"grandma", "grandpa", "gran", "granny", "nan", "nana", "mum", "mom", "mummy", "mommy", "dad", "daddy", "auntie"}
)


def _unfilled(tokens: list[str]) -> list[str]:
    """``tokens`` without a filler "like" before an emphatic or size word, as people talk ("the mug
    like super close", "like really low"): it would part that word from the subject or the verb
    before it. A "like" before anything else may compare ("shot like a portrait") and stays."""
    return [t for t, after in zip(tokens, [*tokens[1:], ""]) if t != "like" or after not in EMPHATIC_WORDS]


def _unrepeated(tokens: list[str]) -> list[str]:
    """``tokens`` with a word said again straight after itself (an emphatic word also after a
    comma) said once: emphasis by repetition grades as the word once ("tiny tiny", "really,
    really small", "so so close"). A comma between other words parts clauses ("zoomed in, in the
    middle")."""
    out: list[str] = []
    for token in tokens:
        if token.isalpha() and out[-1:] == [token]:
            continue
        if token in EMPHATIC_WORDS and out[-2:] == [token, ","]:
            out.pop()
            continue
        out.append(token)
    return out


def _before_relation(text: str) -> str:
    """A noun phrase's words before a place relation ("vase" of "vase on its left"), so a refusal
    names the thing; ``text`` whole when none follows its first word."""
    said = text.split()
    cut = next((k for k in range(1, len(said)) if said[k] in RELATION_WORDS or said[k] in RELATION_OBJECT_WORDS), len(said))
    return " ".join(said[:cut])


def _position_split(tokens: list[str], span: list[int]) -> list[list[int]]:
    """``span`` cut after a leading "<position words> of" ("the top of | the giraffe"), so what
    follows stands in the subject's place on its own; else ``span`` whole."""
    for k, at in enumerate(span):
        if tokens[at] == "of":
            head = [tokens[j] for j in span[:k] if tokens[j] not in STOPWORDS]
            if head and all(w in POSITION_WORDS for w in head):
                return [span[:k], span[k + 1 :]]
            break
    return [span]


def _height_anchor(tokens: list[str], i: int) -> bool:
    """Whether ``tokens[i]`` names a height rather than an object: a surface or body word
    before "height"/"level" after a word leading to a height ("at table height" in a scene with a
    coffee table called "table", "cam at middle-shelf height"); after a determiner only where a word
    leading to a height comes first ("at the seat level"): "the sofa level with the lens" names the
    sofa."""
    if not (tokens[i] in HEIGHT_ANCHORS["eye level"] and i + 1 < len(tokens) and tokens[i + 1] in ("height", "level")):
        return False
    if i > 0 and tokens[i - 1] in MENTION_DETERMINERS:
        return i > 1 and tokens[i - 2] in HEIGHT_LEADS
    return True


def _never_a_name(text: str) -> bool:
    """Whether ``text`` holds only position, degree, part, surroundings and generic words, with
    attributes ("back", "left side", "a bit", "the backrest", "the room", "that small thing"):
    never a subject; nor is filler alone ("a nice": :data:`~capframe.translate.vocabulary.FILLER_WORDS`).
    An attribute alone ("the red") is not such a run."""
    if all(w in FILLER_WORDS for w in text.split()):
        return True
    if any(NUMBER.fullmatch(w) or w == "degrees" for w in text.split()):  # "10 degrees roll" names no object
        return True
    content = [w for w in text.split() if w not in STOPWORDS and w not in ATTRIBUTES]
    # "End" too ("shoot it from that end": a side said again, never a thing); not a position word,
    # which would split "the far end of the table" where it is reported.
    never = POSITION_WORDS | DEGREE_WORDS | PART_WORDS | DETAIL_PARTS | SURROUNDINGS | GENERIC_NOUNS | ROLL_STATE_WORDS | {"end"}
    if bool(content) and all(w in never for w in content):
        return True
    # A detail of the subject, then where on it ("the seam down its back", "cables along the back").
    if content and content[0] in DETAIL_PARTS:
        return True
    # A noun phrase whose head is a word of the picture or a position ("the best side", "an
    # interesting angle", "the angle should be low", "the light from the left"): its head is the
    # last word before the first function word, preposition ("the fountain | behind the tree") or
    # verb of what it does ("the gardener | raking leaves", "the light | falling on").
    said = text.split()
    while said and said[0] in STOPWORDS:
        said.pop(0)
    ends = STOPWORDS | PLACE_WORDS
    phrase = list(itertools.takewhile(lambda w: w not in ends, said))
    phrase = _unplaced(phrase[:1] + list(itertools.takewhile(lambda w: not _placing(w), phrase[1:])))
    return bool(phrase) and phrase[-1] in never | PICTURE_NOUNS


def _opening_noun_phrase(tokens: list[str], span: list[int], determined: list[bool]) -> bool:
    """Whether the run opens the sentence with a determiner and names something other than
    photographic words ("the horizon level" is not a subject), and is not just words describing
    the subject named right after it ("the wide sofa"), nor the topic of a sentence that names
    what is wanted (:func:`_topic_opening`: "my preference is rear left for the bench")."""
    if span[0] != 0 or tokens[0] not in MENTION_DETERMINERS or _topic_opening(tokens, span):
        return False
    words_ = [tokens[k] for k in span[1:]]
    content = [w for w in words_ if w not in STOPWORDS]
    # Words between a determiner and the next subject may describe it; not when that subject
    # brings its own determiner ("the dog chasing the ball" is about a dog).
    following = tokens[span[-1] + 1] if span[-1] + 1 < len(tokens) else ""
    describes_next = following.startswith("@") and not determined[int(following[1:])]
    if describes_next and not any(w in STOPWORDS or w in POSITION_WORDS or w in PLACE_PREPOSITIONS for w in words_):
        return False
    return any(w not in RESERVED for w in content)


# Words that make an opening noun phrase the topic of what follows ("my wish would be the vase",
# "the brief says the armchair at eye level", "the plan: the bear, close-up").
TOPIC_LINKS = frozenset({"is", "are", "was", "be", "says", "said", "reads", "means"})


def _up_to_subject(tokens: list[str]) -> list[str]:
    """The first words of ``tokens`` up to a named subject (``@k``) or punctuation."""
    return list(itertools.takewhile(lambda t: not t.startswith("@") and t not in PUNCTUATION, tokens))


# Marks ending a sentence: what follows one opens a new sentence ("Not sure this is right... find
# the abacus by the mug").
SENTENCE_ENDS = frozenset(".!?;")

# Verbs of putting a thing somewhere, and the determiners opening the thing put ("my grandson left
# his ukulele next to the chair", "someone parked a bike by the bench").
PUTTING_VERBS = frozenset({"left", "put", "placed", "set", "dropped", "parked", "leaned", "leant", "hung", "stashed", "hid"})
PUT_DETERMINERS = MENTION_DETERMINERS | {"his", "her"}


def _sentence_opening(tokens: list[str], at: int) -> bool:
    """Whether ``tokens[at]`` opens a sentence: only function words and punctuation come between
    it and the instruction's start or the last sentence end (:data:`SENTENCE_ENDS`)."""
    start = max((k + 1 for k in range(at) if tokens[k] in SENTENCE_ENDS), default=0)
    return all(t in STOPWORDS or t in PUNCTUATION for t in tokens[start:at])


def _topic_opening(tokens: list[str], span: list[int]) -> bool:
    """Whether the run opening the sentence is a topic, not a thing: it goes on with a copula or
    a verb of saying (:data:`TOPIC_LINKS`), or a colon follows it, and then names what is wanted
    (a subject or a clause), never a place ("the lantern is next to the bench" is a lantern)."""
    words_ = [tokens[k] for k in span]
    rest = tokens[span[-1] + 1 :]
    colon = rest[:1] == [":"]
    linked = any(w in TOPIC_LINKS for w in words_[1:]) or colon
    # What it goes on to, up to the next subject or clause end ("is | behind the sofa", ": | it sits beside").
    onward = _up_to_subject(rest[colon:])
    return linked and not any(w in PLACE_WORDS for w in words_ + onward)


def _spottable(form: tuple[str, ...]) -> bool:
    """Whether a name or alias is spotted in running text: not one reserved photographic word."""
    return len(form) > 1 or form[0] not in RESERVED


def _owned(out: list[str], mentions: list[_Mention], names: list[str]) -> bool:
    """Whether a part word that names ``names`` follows a possessive ("its screen") or, after a
    comma, a mention of one of them ("bookcase, shelves to the camera"): a part, not a name."""
    if out[-1:] in (["its"], ["his"], ["her"], ["their"], ["'s"]):
        return True
    return out[-1:] == [","] and len(out) > 1 and out[-2].startswith("@") and mentions[int(out[-2][1:])].name in names


# Words joining a thing to a named subject after it ("harmonica next to the mug") and before it
# ("the mug and a harmonica", "the bench with a bicycle").
JOINS_BEFORE = tuple(
    w.split() for w in ("next to", "beside", "by", "near", "alongside", "together with", "along with", "with", "and", "plus")
)
# After a subject a place relation names a landmark, which stays reported ("the mug next to a
# hairbrush"); a joining word names a second subject.
JOINS_AFTER = tuple(w.split() for w in ("and", "plus", "with", "together with", "along with", "as well as"))


# Words after a joined thing that end its clause ("mug and a kazoo both in frame", "... too").
THING_ENDS = frozenset({"both", "too", "also", "as", "visible", "please", "in", "together", "showing"})
# Words that ask for two things at once ("both in frame", "the two together").
# Set at its side ("the cone, with the rubber duck beside it"): a thing to see with it, as "both"
# says; "the bench with a sunset behind it" is the bench.
SIDE_BY = (["beside"], ["next"], ["alongside"], ["by"])
BOTH_WORDS = frozenset({"both", "together"})  # "two" is read as "2": "the two together" has "together"


def _names_subject(tokens: list[str]) -> bool:
    """Whether ``tokens`` open with a named subject, maybe after a determiner ("the @0", "@1")."""
    rest = tokens[1:] if tokens[:1] and tokens[0] in MENTION_DETERMINERS else tokens
    return bool(rest) and rest[0].startswith("@")


def _coordinated(tokens: list[str], span: list[int]) -> bool:
    """Whether the run is joined to a subject by "and"/"or" ("the bear and the giraffe", "the bear,
    and the giraffe beside it")."""
    first, last = span[0], span[-1]
    before = next((tokens[k] for k in range(first - 1, -1, -1) if tokens[k] != ","), "")
    return (tokens[first] in CONJUNCTIONS and before.startswith("@")) or (
        tokens[last] in CONJUNCTIONS and last + 1 < len(tokens) and tokens[last + 1].startswith("@")
    )


# --- a thing placed at a named object (parse15) -----------------------------------------------------
# Place prepositions that end the words placing a thing at a named object, longest first ("the kite
# stuck up in the tree", "the radiator which is behind the armchair").
PLACED_PREPOSITIONS = tuple(
    w.split()
    for w in (
        "in front of", "on top of", "out of", "next to", "close to", "up against", "right by",
        "in", "on", "at", "by", "near", "under", "behind", "beyond", "beside", "below", "above", "over",
        "beneath", "underneath", "against", "alongside", "between", "among", "amid", "inside", "outside",
        "atop", "into", "onto", "upon", "across", "along", "around", "round", "within", "past", "from",
    )
)  # fmt: skip
# Pronouns opening a relative clause after a thing ("the rug that ...", "the toaster what ...").
RELATIVE_PRONOUNS = frozenset({"that", "which", "who", "whom", "what"})
# Places that relate a thing to a named object without a verb ("a snow globe behind the pillow",
# "swing set behind the tree"); not "on", "in", "at" and the like, which also say where a camera
# looks or what a shot is ("focus on the mug", "spotlight on the sofa", "tight in on the bear").
BARE_PLACED_PREPOSITIONS = frozenset(
    tuple(w.split())
    for w in ("behind", "beside", "next to", "in front of", "on top of", "atop", "underneath", "beneath", "alongside")
)
# Verbs of where the photographer goes or puts the camera, which open an instruction bare as a
# noun phrase would ("stand behind the sofa", "step beside the bench", "get in front of it").
STANDING_VERBS = frozenset(
    {"stand", "go", "get", "move", "step", "walk", "sit", "kneel", "crouch", "squat", "lie", "put", "place", "position"}
    | {"hold", "stay", "shoot", "come", "hover", "fly", "wait", "start", "circle", "set", "park", "plant", "climb"}
)
# Words opening a relative clause or a verb of being between a thing and its place ("the rug that's
# under the sofa", "the toaster what is beside the fridge", "the hamster who is hiding ...").
PLACED_RELATIVES = frozenset({"that", "which", "who", "what", "'s", "s", "is", "are", "was", "were", "being", "been"})
# Verb forms of where a thing is that are neither a participle in -ing/-ed nor a verb of resting
# (:data:`RELATION_WORDS`): "the kite stuck in the tree", "the cat that sleeps on the sofa"; not
# those that are nouns too ("the umbrella stand by ...", "the rest of ...").
PLACED_VERBS = frozenset(
    {"kept", "stuck", "laid", "lain", "stood", "hangs", "sleeps", "naps", "dozes", "hides", "waits", "peeks", "peeps"}
    | {"perches", "plays", "lives", "stays", "leant", "strewn", "thrown", "flung", "slung", "spread", "lit", "grown"}
    | {"cast", "drawn"}
)
# Adverbs said among the placing words ("splashing away somewhere behind", "curled up fast asleep
# on", "parked right behind", "napping quietly under").
PLACED_ADVERBS = frozenset(
    {"away", "somewhere", "just", "right", "directly", "out", "up", "down", "off", "there", "here", "still", "now"}
    | {"quietly", "peacefully", "happily", "slowly", "lazily", "comfortably", "fast", "sound", "soundly", "proudly"}
    | {"neatly", "safely", "casually", "open", "upright", "sideways", "alone", "all", "currently", "half", "partly"}
)
# Participles of aiming or holding a camera, never of where a thing is ("a drone hovering above the
# tree, looking down at the bench").
AIMING_VERBS = frozenset(
    {"looking", "facing", "pointing", "pointed", "aiming", "aimed", "shooting", "angled", "angling", "tilted", "tilting"}
    | {"turned", "turning", "raised", "lowered", "peering", "gazing", "staring", "zoomed", "zooming", "framed", "focused"}
    | {"focussed", "centered", "centred", "cropped", "positioned", "placed", "pushed", "nudged", "shifted"}
)
# Who holds or is the camera, or how it moves, never the subject ("the photographer crouching beside
# the bench", "orbit paused over the vase").
CAMERA_HOLDERS = frozenset(
    {"camera", "lens", "cam", "drone", "phone", "tripod", "gimbal", "photographer", "cameraman", "viewer", "observer"}
    | {"onlooker", "spectator", "orbit", "pan", "dolly", "crane", "jib", "track", "tracking", "sweep", "move", "rig"}
    | {"slider", "flyover", "flythrough", "path", "pass"}
)
# Words before a noun phrase that keep it in the subject's place: asking for it ("could you
# include the fireplace ..."), or a picture of it ("a close detail of the teaspoon ...").
PLACED_LEADS = frozenset({"include", "including", "feature", "featuring", "find", "spot", "catch", "grab"})
PLACED_PICTURES = frozenset(
    {"shot", "photo", "photograph", "picture", "pic", "image", "snap", "snapshot", "view", "closeup", "detail", "macro"}
    | {"study", "portrait", "crop", "capture", "still", "photos", "pictures", "pics", "shots", "images"}
)
# Words before "on" / "onto" that make the noun phrase after them what the shot is of ("zoom right
# in on", "tight on", "close up on", "a low angle onto").
SHOT_ONTO = frozenset({"in", "tight", "close", "up", "closeup", "angle", "focus", "focused", "zoom", "zoomed"})
# Words that make the noun phrase a comparison, not the subject ("like a toddler looking up at").
SIMILE_WORDS = frozenset({"like", "as", "if"})
# A setting holding the named object, then the subject (:meth:`RuleParser._setting_holding`): the
# setting words of the tables but those naming the picture itself ("scene", "setting").
HOLDING_SETTINGS = frozenset(SETTINGS) - {"scene", "setting", "interior", "outdoors"}
HOLDING_WORDS = frozenset({"with", "containing", "holding"})
HELD_INSIDE = frozenset(
    tuple(w.split()) for w in ("in it", "inside it", "inside", "in there", "within it", "in here", "inside of it")
)


def _opening_preposition(said: list[str]) -> tuple[str, ...] | list[str]:
    """The place preposition (:data:`PLACED_PREPOSITIONS`) ``said`` opens with, words following
    it; () otherwise."""
    return next((p for p in PLACED_PREPOSITIONS if said[: len(p)] == list(p) and len(said) > len(p)), ())


def _placing(word: str) -> bool:
    """Whether ``word`` is a verb of where a thing is: a verb of resting (:data:`RELATION_WORDS`,
    :data:`PLACED_VERBS`) or a participle in -ing / -ed ("splashing", "crawling", "dunked") but
    one of aiming a camera (:data:`AIMING_VERBS`: "looking", "pointed")."""
    if word in RELATION_WORDS or word in PLACED_VERBS:
        return True
    return (
        word.isalpha()
        and word not in AIMING_VERBS
        and ((len(word) > 4 and word.endswith("ing")) or (len(word) > 3 and word.endswith("ed")))
    )


def _placed_phrase(before: list[str]) -> tuple[int, int] | None:
    """Where the noun phrase lies in ``before`` (the words before a named object) when they end on
    "<noun phrase> <placing words> <place preposition>": ``(start, end)`` of its words (up to
    :data:`MAX_ATTRIBUTES`, after a determiner, "of", another function word or the opening), the
    placing words at most five, of them one a verb of being or of where it is
    (:data:`PLACED_RELATIVES`, :func:`_placing`), the others adverbs (:data:`PLACED_ADVERBS`);
    else None."""
    preposition = next((p for p in PLACED_PREPOSITIONS if before[-len(p) :] == list(p)), None)
    if preposition is None:
        return None
    end = len(before) - len(preposition)
    # A relative clause places it whatever its verb ("the cat who sleep on", "a candle that's been
    # lit beside"): from its pronoun on, at most five words.
    relative = next((k for k in range(end - 1, max(end - 6, 0) - 1, -1) if _relative(before, k, end)), None)
    if relative is not None and all(w.isalpha() or w == "'s" for w in before[relative:end]):
        end = relative - (relative > 0 and before[relative - 1] == ",")
        verb = True
    else:
        verb = False
    while end > 0 and len(before) - len(preposition) - end < 5:
        word = before[end - 1]
        if word in PLACED_RELATIVES or _placing(word):
            verb = True
        elif word not in PLACED_ADVERBS and not (word == "," and before[end] in PLACED_RELATIVES):
            break  # a comma may set off the relative clause ("the heater, which is next to")
        end -= 1
    bare = end == len(before) - len(preposition) and not verb and tuple(preposition) in BARE_PLACED_PREPOSITIONS
    if not verb and not bare:  # bare: "a snow globe behind the pillow", the noun phrase right before the place
        return None
    # A noun in -ing or -ed is the phrase's head when nothing else is ("the painting hanging above").
    if (end == 0 or not _noun_word(before[end - 1])) and before[end] not in PLACED_RELATIVES | PLACED_ADVERBS:
        if any(w in PLACED_RELATIVES or _placing(w) for w in before[end + 1 : len(before) - len(preposition)]):
            end += 1
    start = end
    while start > 0 and end - start < MAX_ATTRIBUTES and _noun_word(before[start - 1]):
        start -= 1
    if bare and start < end and (before[start] in STANDING_VERBS or (start > 0 and _placing(before[start - 1]))):
        # Where the photographer goes ("Stand in front of the bench, then ..."), or how a thing
        # placed is ("camera sitting low beside the bench": "low" is no thing).
        return None
    return (start, end) if start < end else None


def _relative(before: list[str], k: int, end: int) -> bool:
    """Whether ``before[k]`` opens a relative clause ending at ``end``: a relative pronoun, but not
    "that" pointing at a noun a placing word follows ("that bell sitting next to")."""
    if before[k] not in RELATIVE_PRONOUNS:
        return False
    pointing = before[k] == "that" and k + 1 < end and _noun_word(before[k + 1]) and not _placing(before[k + 1])
    return not (pointing and any(_placing(w) for w in before[k + 2 : end]))


def _noun_word(word: str) -> bool:
    """Whether ``word`` may belong to a noun phrase: a word, not a function word."""
    return word.isalpha() and word not in STOPWORDS and word not in MENTION_DETERMINERS


def _unplaced(phrase: list[str]) -> list[str]:
    """``phrase`` less the placing words it ends with ("granddaughter cuddling" -> "granddaughter",
    "light falling" -> "light"), its first word always kept."""
    while len(phrase) > 1 and (phrase[-1] in PLACED_RELATIVES | PLACED_ADVERBS or _placing(phrase[-1])):
        phrase = phrase[:-1]
    return phrase


def _subject_place(before: list[str]) -> bool:
    """Whether a noun phrase after ``before`` stands in the subject's place: it opens the
    sentence (after function words, punctuation and words asking for it, :data:`PLACED_LEADS`) or
    follows "<a picture noun> of" ("a close detail of", "a close up of"); never in a comparison
    (:data:`SIMILE_WORDS`)."""
    if any(w in SIMILE_WORDS for w in before[-3:]):
        return False
    if all(w in STOPWORDS or w in PUNCTUATION or w in PLACED_LEADS or NUMBER.fullmatch(w) for w in before):
        return True  # a count may open it ("two ducks swimming near the bench")
    if before[-1:] in (["on"], ["onto"]) and before[-2:-1] and before[-2] in SHOT_ONTO:
        return True  # what the shot closes in on ("zoom in tight on the soda can resting on the sofa")
    if before[-1:] != ["of"]:
        return False
    picture = before[-2:-1]
    return bool(picture) and (picture[0] in PLACED_PICTURES or before[-3:-1] == ["close", "up"])


# What a shot "with" another object in view says of it: that it is in the picture too, beside the
# subject said before ("in a wide shot with the sofa in view", "a medium shot with the lamp visible
# behind"): parse20s.
ALSO_IN_VIEW = re.compile(
    r" (the |a |an )?@\d+ (in (view|shot|frame|the (background|frame|shot|picture))|visible|showing|too|as well|behind)( |$)"
)


def _cue(rule: _Rule, m: re.Match, start: int, end: int) -> _Cue:
    groups = _groups(m)
    slot = groups.get("ref")
    ref = int(slot.split()[0][1:]) if slot and slot.startswith("@") else None
    value, weak = rule.value, rule.weak
    if rule.field == "elevation_deg":
        if isinstance(rule.value, tuple):  # ("fixed", degrees) or ("magnitude", sign): a sign of its own
            value = rule.value[1] if rule.value[0] == "fixed" else rule.value[1] * abs(float(groups["d"]))
        else:
            value = rule.value * float(groups["d"])
    elif rule.field == "elevation_bare":
        value = float(groups["d"])
    elif rule.field == "roll_deg":
        value, weak = _roll_value(rule.value, groups)
    elif rule.field == "shot" and rule.value == "share":
        value = _shot_of_share(groups["share"])
    elif rule.field == "view" and isinstance(rule.value, tuple) and rule.value[0] == "turn":
        # ("turn", sign): turned that far sideways from a reference said with it (_combined_view).
        value = ("turn", rule.value[1] * float(groups["d"]))
    elif rule.field == "view" and isinstance(rule.value, tuple):
        # ("azimuth", sign[, from, towards]): sign * (from + towards * degrees), from the front.
        _, sign, origin, toward = (*rule.value, 0.0, 1.0)[:4]
        value = _nearest_side(sign * (origin + toward * float(groups.get("d", 0.0))))
    elif rule.field == "view" and groups.get("exact") and value in EXACT_ENDS:
        value = f"{value}-exact"
    forward = rule.field == "head" or (rule.field == "shot" and re.search(f" {HEAD_LINK}$", m.group()) is not None)
    if forward and rule.field == "shot" and m.group().endswith(" with") and ALSO_IN_VIEW.match(m.string, m.end()):
        forward = False  # "a wide shot with the sofa in view": the sofa is beside the subject, not it
    return _Cue(rule.field, value, start, end, m.group(), ref, slot is not None and ref is None, weak, forward)


def _shot_of_share(said: str) -> str:
    """The shot size of a share of the frame ("a third", "70 percent"): the one whose range of
    :data:`~capframe.constraints.SHOT_SIZES` holds it, of two the one whose middle (within the
    frame: a close-up's range runs past 1) is nearer."""
    share = float(said.split()[0]) / 100.0 if said.endswith("percent") else FRAME_FRACTIONS[said]

    def off_middle(size: str) -> float:
        lo, hi = SHOT_SIZES[size]
        return abs((lo + min(hi, 1.0)) / 2 - share)

    return min((k for k, (lo, hi) in SHOT_SIZES.items() if lo <= share <= hi), key=off_middle, default="close-up")


def _nearest_side(azimuth: float) -> str:
    """The view side of one azimuth nearest ``azimuth`` degrees (0 front, > 0 the subject's right),
    of two at the same azimuth the narrower ("90 degrees round to its right" is "right-exact": an
    angle said is meant exactly)."""
    single = [(side, a[0]) for side, a in VIEW_SIDES.items() if len(a) == 1]
    nearest = min(single, key=lambda sa: arc_deg(sa[1], azimuth))[1]
    return min((side for side, a in single if a == nearest), key=view_tolerance_deg)


def _roll_value(multiplier: float, groups: dict) -> tuple[float, bool]:
    """Roll in degrees of a roll phrase, and whether its magnitude is a default (a weak cue)."""
    if multiplier == 0:
        return 0.0, False
    sign = -1.0 if groups.get("dir") == "counterclockwise" or groups.get("side") == "left" else 1.0
    if groups.get("d") is not None:
        return multiplier * sign * float(groups["d"]), False
    size = "slight" if groups.get("weak") else groups.get("mod") or ""  # "rolled a touch clockwise"
    return multiplier * sign * DUTCH_SIZE_DEG.get(size, DUTCH_DEFAULT_DEG), True


def _attach(cues: list[_Cue], mentions: list[_Mention], tokens: list[str], vocabulary: Vocabulary) -> list[ParsedSubject]:
    """Subjects in order of first mention, with the region/shot/view cues given to them."""
    subjects: dict[str, ParsedSubject] = {}
    for m in mentions:
        if m.name not in subjects:
            role = "secondary" if subjects else "primary"
            subjects[m.name] = ParsedSubject(m.text, m.name, role, vocabulary.symmetric(m.name))
    seen_only = _seen_only(cues, mentions, tokens) | _related_objects(cues, mentions, tokens)
    for cue in cues:
        if cue.field not in SUBJECT_FIELDS:
            continue
        names = _candidates(cue, [m for m in mentions if cue.ref is not None or m.at not in seen_only] or mentions)
        free = [n for n in names if getattr(subjects[n], cue.field) in (None, cue.value)]
        held = getattr(subjects[names[0]], cue.field)
        combined = {"view": _combined_view, "region": _combined_region, "shot": _combined_shot}.get(cue.field, lambda *_: None)(
            held, cue.value
        )
        # A second view cue completes the first one's side ("three-quarter" + "from its left"),
        # unless it leads straight into another subject ("from the front, the bear; from the
        # left, the chair"), which then takes it.
        if free and (free[0] == names[0] or combined is None or _leads_into(cue, free[0], mentions, tokens)):
            setattr(subjects[free[0]], cue.field, cue.value)
        elif combined is not None:
            setattr(subjects[names[0]], cue.field, combined)
        else:
            raise InputError(
                f"conflicting {cue.field} for {names[0]!r}: {_said_view(held)!r} and {_said_view(cue.value)!r} ({cue.text!r})"
            )
    for subject in subjects.values():
        subject.view = _said_view(subject.view)
        subject.shot = _said_shot(subject.shot)
    return list(subjects.values())


# View words a slip is read as where only a view word can stand (:func:`_view_slip`).
VIEW_SLIP_TARGETS = ("front", "back", "rear", "left", "right", "side", "profile", "behind")
VIEW_SLIP_LEADS = ("the", "its", "his", "her", "their")
# Rows of a QWERTY keyboard: a letter struck for its neighbour is a slip, any other letter may be
# another word ("from the bank" is no "back").
KEY_ROWS = ("qwertyuiop", "asdfghjkl", "zxcvbnm")
_KEY_AT = {c: (r, k) for r, row in enumerate(KEY_ROWS) for k, c in enumerate(row)}


def _neighbour_keys(a: str, b: str) -> bool:
    """Whether the letters ``a`` and ``b`` are neighbouring keys (same row or the row next to it)."""
    (ra, ka), (rb, kb) = _KEY_AT.get(a, (9, 0)), _KEY_AT.get(b, (-9, 0))
    return abs(ra - rb) <= 1 and abs(ka - kb) <= 1 and a != b


def _slipped(said: str, word: str) -> bool:
    """Whether ``said`` is ``word`` with one letter dropped, added or swapped with the next, or
    struck on a neighbouring key (:func:`_neighbour_keys`)."""
    if not one_edit(said, word):
        return False
    if len(said) != len(word):
        return True
    diff = [k for k in range(len(word)) if said[k] != word[k]]
    return len(diff) == 2 or _neighbour_keys(said[diff[0]], word[diff[0]])


def _view_slip(before: list[str], token: str, names: set[str]) -> str | None:
    """The view word ``token`` mistypes by one letter (:func:`_slipped`: "font", "lefy", "rigjt")
    where only a view word stands, right after "from the" / "from its" ("from the font"), or None:
    also when it is one letter from a word of the scene's names or from two view words."""
    if before[-2:-1] != ["from"] or before[-1:] not in ([w] for w in VIEW_SLIP_LEADS) or not token.isalpha():
        return None
    if any(one_edit(token, name) for name in names):
        return None
    targets = [w for w in VIEW_SLIP_TARGETS if _slipped(token, w)]
    return targets[0] if len(targets) == 1 else None


def _combined_view(held, said):
    """The one view side two view cues of a subject name together (:data:`VIEW_COMBINATIONS`), an
    explicit sideways turn ``("turn", degrees)`` taken from the end said with it (from the front,
    or from the back: "from behind, 30 degrees to its left" is -150), else None (a conflict)."""
    if isinstance(held, tuple) or isinstance(said, tuple):
        turn, reference = (held, said) if isinstance(held, tuple) else (said, held)
        if isinstance(reference, tuple):
            return None
        return _turned(reference, turn[1])
    return VIEW_COMBINATIONS.get(frozenset((held, said))) or _restated_view(held, said)


def _restated_view(held: str, said: str) -> str | None:
    """Of two sides naming one way round the subject, the narrower one when its azimuth lies inside
    the other's range: a side said again more precisely ("from behind, a bit to the left - over its
    left shoulder" is -160, within the back-left diagonal's -165 to -105); else None. Sides with
    two azimuths ("three-quarter") or none in common stay a conflict (VIEW_COMBINATIONS names the
    sides that combine into a third one)."""
    if held not in VIEW_SIDES or said not in VIEW_SIDES or len(VIEW_SIDES[held]) != 1 or len(VIEW_SIDES[said]) != 1:
        return None
    narrow, wide = sorted((held, said), key=view_tolerance_deg)
    if view_tolerance_deg(narrow) == view_tolerance_deg(wide):
        return None
    inside = arc_deg(VIEW_SIDES[narrow][0], VIEW_SIDES[wide][0]) < view_tolerance_deg(wide)
    return narrow if inside else None


# Shot cues that say all of the subject is in, not how big: they yield to a size word.
YIELDING_SHOTS = frozenset({WHOLE_SPAN, WHOLE})


def _combined_shot(held, said) -> str | None:
    """The size two shot cues of a subject say together: all of it in (:data:`YIELDING_SHOTS`:
    from end to end, the whole of it) with a size word is that size ("filling the frame, top to
    bottom" is a close-up, "the whole sofa, small in frame" wide), and with each other all of it;
    else None (a conflict)."""
    if held in YIELDING_SHOTS and said in YIELDING_SHOTS:
        return held
    if held in YIELDING_SHOTS or said in YIELDING_SHOTS:
        return said if held in YIELDING_SHOTS else held
    return None


def _said_shot(shot: str | None) -> str | None:
    """A subject's shot as the constraints name it: all of it in, said alone, is medium."""
    return "medium" if shot in YIELDING_SHOTS else shot


# A height and a side of the frame said apart are the corner between them ("at the bottom, on the
# left"; "in the corner at the top, to the right").
REGION_CORNERS = {
    f"{'upper' if height == 'top' else 'lower'} {lat}": frozenset((height, lat))
    for height in ("top", "bottom")
    for lat in ("left", "right")
}


def _combined_region(held, said) -> str | None:
    """The corner two region cues of a subject name together: a half of each axis ("at the
    bottom" + "on the left": "lower left"), or a corner and one of its own halves ("in the
    lower-left corner" + "at the bottom"); else None (a conflict)."""
    for corner, halves in REGION_CORNERS.items():
        if {held, said} <= halves | {corner} and {held, said} != {corner} and len({held, said}) == 2:
            return corner
    return _nested_region(held, said)


def _nested_region(held, said) -> str | None:
    """Of two region cues whose boxes nest, the inner one ("on the right third" + "negative space
    to the left", i.e. "right": the right third); else None (a conflict). Boxes are
    ``constraints.REGIONS`` (x0, y0, x1, y1) in frame fractions."""

    def inside(a: str, b: str) -> bool:
        (ax0, ay0, ax1, ay1), (bx0, by0, bx1, by1) = REGIONS[a], REGIONS[b]
        return bx0 <= ax0 and by0 <= ay0 and ax1 <= bx1 and ay1 <= by1

    if held not in REGIONS or said not in REGIONS:
        return None
    return said if inside(said, held) else held if inside(held, said) else None


def _turned(reference: str | None, degrees: float) -> str | None:
    """The side nearest ``degrees`` turned sideways (> 0 towards the subject's right) from the
    end ``reference`` (None or an exactness alone: the front); None for a reference that is no end."""
    if reference in (None, EXACT_ONLY, "front", "front-exact"):
        return _nearest_side(degrees)
    if reference in ("back", "back-exact"):
        return _nearest_side(math.copysign(180.0 - abs(degrees), degrees))
    return None


def _said_view(view):
    """A view cue as the side it names on its own: a turn from the front, an exactness alone the
    front exactly."""
    if isinstance(view, tuple):
        return _turned(None, view[1])
    return "front-exact" if view == EXACT_ONLY else view


def _seen_only(cues: list[_Cue], mentions: list[_Mention], tokens: list[str]) -> set[int]:
    """Token positions of the mentions asked only to be in the picture (:data:`SEEN_PHRASES`, a
    depth word, :data:`DEPTH_WORDS`, or a place relation to a pronoun, "the mug beside it", after
    them, stopwords between), but the first mention's."""
    starts = {c.start for c in cues if c.field == "seen"}
    covered = {k for c in cues for k in range(c.start, c.end)}  # "seen from behind" is a view, no depth
    out = set()
    for m in mentions[1:]:
        for k in range(m.at + 1, len(tokens)):
            # Placed at a pronoun, maybe through "to" or "of" ("beside it", "next to it", "in front of it").
            tied = tokens[k + 2 : k + 3] if tokens[k + 1 : k + 2] in (["to"], ["of"]) else tokens[k + 1 : k + 2]
            placed = tokens[k] in RELATION_WORDS | {"front"} and tied in (["it"], ["them"], ["him"], ["her"])
            if k in starts or placed or (tokens[k] in DEPTH_WORDS and k not in covered):
                out.add(m.at)
            if k in starts or tokens[k] not in STOPWORDS:
                break
    return out


def _related_objects(cues: list[_Cue], mentions: list[_Mention], tokens: list[str]) -> set[int]:
    """Token positions of the mentions that are the object of a place relation to the mention
    before them, in one clause ("the teddy on | the sofa", "the bear lying next to | the mug"):
    words between them only relation words (:data:`RELATION_WORDS`, :data:`RELATION_OBJECT_WORDS`)
    and stopwords, none a cue's. What the sentence asks later belongs to the first of them ("the
    teddy on the sofa, from the front" is the teddy's front)."""
    covered = {k for c in cues for k in range(c.start, c.end)}
    out = set()
    for before, m in zip(mentions, mentions[1:]):
        between = range(before.at + 1, m.at)
        related = any(tokens[k] in RELATION_WORDS or tokens[k] in RELATION_OBJECT_WORDS for k in between)
        if related and all(
            k not in covered and (tokens[k] in STOPWORDS or tokens[k] in RELATION_WORDS or tokens[k] in RELATION_OBJECT_WORDS)
            for k in between
        ):
            out.add(m.at)
    return out


def _leads_into(cue: _Cue, name: str, mentions: list[_Mention], tokens: list[str]) -> bool:
    """Whether the next word after ``cue``, punctuation aside, starts a mention of ``name``."""
    following = next((k for k in range(cue.end, len(tokens)) if tokens[k] not in PUNCTUATION), None)
    return any(m.at == following and m.name == name for m in mentions)


def _candidates(cue: _Cue, mentions: list[_Mention]) -> list[str]:
    """Names a subject cue may belong to, the preferred first (see the module docstring)."""
    if cue.ref is not None:
        return [next(m.name for m in mentions if m.placeholder == cue.ref)]
    before = [m.name for m in mentions if m.at < cue.start]
    after = [m.name for m in mentions if m.at >= cue.end]
    near = [before[-1]] if before else []
    far = [after[0]] if after else []
    return far + near if cue.forward and not cue.pronoun else near + far


# Cues that carry an angle of their own: a bare angle belongs to the nearest of them.
ANGLE_FIELDS = ("elevation", "elevation_deg", "view", "roll_deg")


def _bare_angles(cues: list[_Cue], tokens: list[str]) -> list[_Cue]:
    """``cues`` with each bare angle (:data:`BARE_ANGLE_PHRASES`) read as explicit degrees when
    the nearest cue carrying an angle (:data:`ANGLE_FIELDS`; of two as near, the one before) is a
    height above or below the horizontal, signed as it is ("from way up, like 70 deg": +70); a
    bare angle nearer a side or a roll, after a verb of turning (:data:`TURN_WORDS`) or with no
    height said is dropped, so its words are reported as not understood."""
    angled = [c for c in cues if c.field in ANGLE_FIELDS]
    out = []
    for cue in cues:
        if cue.field != "elevation_bare":
            out.append(cue)
            continue
        if cue.start and tokens[cue.start - 1] in TURN_WORDS or not angled:
            continue
        nearest = min(angled, key=lambda c: (c.start - cue.end if c.start >= cue.end else cue.start - c.end, c.start > cue.start))
        sign = _side_of(nearest) if nearest.field.startswith("elevation") else 0.0
        if cue.value == 0.0 and nearest.field.startswith("elevation"):  # no side to take: level
            sign = 1.0
        if cue.value < 0.0:  # signed already: kept only beside a height below ("minus 15, beneath it")
            sign = -1.0 if sign < 0.0 else 0.0
            cue = replace(cue, value=-cue.value)
        if sign and not _beyond_slight(nearest, sign * cue.value):
            out.append(replace(cue, field="elevation_deg", value=sign * cue.value, weak=False))
    return out


# Words that deny the view, height, size or place said right after them ("not from the side",
# "rather than from above", "instead of a close-up"); phrases with their own denial ("no dutch",
# "not too close") start with it and are kept.
# "Don't" is "don t" once its apostrophe splits it ("TV small, don't zoom in": no close-up).
NEGATIONS = tuple(
    w.split()
    for w in ("not", "no", "never", "nor", "rather than", "instead of", "as opposed to", "but not", "don t", "dont", "do not")
    # Everything but a view, or showing one refused ("anything but the front of the car", "don't
    # show me its back", "no shots of its back", "avoid the front"): one end so denied is every
    # other way round (:func:`_unnegated`), any other view asks nothing.
    + ("anything but", "anywhere but", "any side but", "don t show me", "don t show", "do not show", "no shots of")
    + ("no shot of", "avoid", "avoiding", "don t want", "do not want", "dont want")
    # ... with a verb of shooting and what is shot between ("don't shoot it from the front").
    + tuple(
        f"{neg} {verb}{what}"
        for neg in ("don t", "do not", "dont", "never")
        for verb in ("shoot", "take", "photograph", "film", "show", "frame", "capture", "snap")
        for what in ("", " it", " him", " her", " them")
    )
)
NEGATION_WORDS = frozenset(w for n in NEGATIONS for w in n)
NEGATED_FIELDS = frozenset({"view", "elevation", "elevation_deg", "shot", "region"})


def _unnegated(cues: list[_Cue], tokens: list[str]) -> list[_Cue]:
    """``cues`` with the ones a negation right before denies (:data:`NEGATIONS`) dropped, so their
    words are reported as not understood and no longer conflict with what is wanted ("the mug
    from the front, not from the side"); but for one end of the subject denied alone, which
    leaves every other way round it (:data:`~capframe.constraints.NEGATED_ENDS`: "anything but the
    front" is "not-front", and "not the front, its back" the back)."""
    negation = {}  # id of a denied cue -> the longest negation right before it
    for c in cues:
        said = [n for n in NEGATIONS if c.field in NEGATED_FIELDS and tokens[max(c.start - len(n), 0) : c.start] == n]
        if said:
            negation[id(c)] = max(said, key=len)
    ends = [c for c in cues if id(c) in negation and c.field == "view" and _denied_end(c.value) is not None]
    kept = {}
    if len(ends) == 1:
        # The negation is part of what is understood then ("not from behind" as a whole).
        end, denial = ends[0], negation[id(ends[0])]
        kept[id(end)] = replace(
            end,
            value=NEGATED_ENDS[_denied_end(end.value)],
            start=end.start - len(denial),
            text=f"{' '.join(denial)} {end.text}",
        )
    return [kept.get(id(c), c) for c in cues if id(c) not in negation or id(c) in kept]


def _denied_end(view: object) -> str | None:
    """The end of the subject a denied view side names ("front", "front-exact": "front"), else None."""
    end = view.removesuffix("-exact") if isinstance(view, str) else None
    return end if end in NEGATED_ENDS else None


# A correction set off as a clause of its own ("..., sorry, I mean ...", "... no, ...", ". Scratch
# that, ..."), one marker or several (:data:`~capframe.translate.vocabulary.CORRECTION_MARKERS`).
_MARKER = "(" + "|".join(CORRECTION_MARKERS) + ")"
CORRECTION_PHRASE = f"(?<=[,.;:!?] ){_MARKER}(( ,)? {_MARKER})*( ,)?"
# The kinds of value a correction replaces: a height said as a name or as degrees is one kind.
CORRECTED_KINDS = {
    "view": "view",
    "region": "region",
    "shot": "shot",
    "elevation": "elevation",
    "elevation_deg": "elevation",
    "roll_deg": "roll",
}


def _corrected(cues: list[_Cue], tokens: list[str]) -> list[_Cue]:
    """``cues`` with each value a speaker took back dropped: a correction (:data:`CORRECTION_PHRASE`:
    "the mug from its left, sorry, from its right", "centred. No, on the left third") replaces
    the nearest value of the same kind (:data:`CORRECTED_KINDS`) said before it with the first
    value said after it; "I mean" closing a clause ("front-right, uh, front-left I mean") replaces
    the value before the one it closes. No object may be named between the two ("the mug on the
    left, sorry, the vase on the right" places two things). A correction that replaces nothing is
    dropped, so its words are reported as not understood, as before; a value taken back and the
    correction itself ask nothing (they are understood)."""
    dropped: set[int] = set()
    markers: set[int] = set()
    valued = [(k, c) for k, c in enumerate(cues) if c.field in CORRECTED_KINDS]
    for m, marker in enumerate(cues):
        if marker.field != "correction":
            continue
        said = [w for w in marker.text.split() if w not in PUNCTUATION]
        set_off = marker.end >= len(tokens) or tokens[marker.end] in PUNCTUATION or marker.text.endswith(",")
        closing = " ".join(said) in RESTATING_AFTER and set_off
        before = [(k, c) for k, c in valued if c.end <= marker.start]
        if closing:  # the value it closes is the new one
            new = before[-1] if before and all(t in PUNCTUATION for t in tokens[before[-1][1].end : marker.start]) else None
            before = before[:-1]
        else:
            new = next(((k, c) for k, c in valued if c.start >= marker.end), None)
        if new is None:
            continue
        kind = CORRECTED_KINDS[new[1].field]
        old = next(((k, c) for k, c in reversed(before) if CORRECTED_KINDS[c.field] == kind), None)
        if old is None or any(t.startswith("@") for t in tokens[old[1].end : new[1].start]):
            continue
        dropped.add(old[0])
        markers.add(m)
    taken_back = markers | dropped
    kept = [(k, c) for k, c in enumerate(cues) if c.field != "correction" or k in markers]
    return [replace(c, field="note") if k in taken_back else c for k, c in kept]


# A slight height says a small angle: a bare angle farther than this past its range is another
# angle ("slightly above, 45 degrees" may turn the camera 45 degrees round): reported, not read.
SLIGHT_ELEVATIONS = frozenset({"slightly above", "slightly below"})


def _beyond_slight(cue: _Cue, degrees: float) -> bool:
    """Whether ``degrees`` lies more than the explicit tolerance past the range of a slight height
    ``cue`` (:data:`SLIGHT_ELEVATIONS`)."""
    if cue.field != "elevation" or cue.value not in SLIGHT_ELEVATIONS:
        return False
    lo, hi = ELEVATIONS[cue.value]
    return not lo - EXPLICIT_ELEVATION_TOLERANCE_DEG <= degrees <= hi + EXPLICIT_ELEVATION_TOLERANCE_DEG


def _side_of(cue: _Cue) -> float:
    """+1 for a height cue above the horizontal, -1 below, 0 for one that straddles it (eye level)."""
    if cue.field == "elevation_deg":
        return float((cue.value > 0.0) - (cue.value < 0.0))
    lo, hi = ELEVATIONS[cue.value]
    return 1.0 if lo >= 0.0 else -1.0 if hi <= 0.0 else 0.0


def _elevation(cues: list[_Cue]) -> tuple[str | None, float | None]:
    """The named elevation or explicit degrees asked (hints yield to any other elevation cue)."""
    found = [c for c in cues if c.field in ("elevation", "elevation_deg")]
    found = [c for c in found if not c.weak] or found
    # A look's direction alone ("looking down on it") yields to a hint naming a height on its side
    # ("from a drone", "from up a ladder"): the height says how far above.
    found = [
        c for c in found if not (_direction_only(c) and any(_side_of(o) == _side_of(c) and not _direction_only(o) for o in found))
    ]
    degrees = sorted({c.value for c in found if c.field == "elevation_deg"})
    if len(degrees) == 1:  # an angle and a height word on its side are one elevation: the angle says it
        found = [c for c in found if not _yields_to(c, degrees[0])]
    found = _beyond_broad(found)
    named = _narrowest({c.value for c in found if c.field == "elevation"})
    if len(degrees) > 1:
        raise InputError(f"conflicting elevations: {[c.text for c in found]}")
    if len(named) > 1:
        # Heights said together that overlap are one: where they overlap, as degrees at its middle
        # (an angle said too must lie there). Two that only touch pile one image on the other
        # ("from way up, like from a drone"): the one farther from the horizontal.
        meet, tol = _meeting(named), EXPLICIT_ELEVATION_TOLERANCE_DEG
        if meet is None or (degrees and not meet[0] - tol <= degrees[0] <= meet[1] + tol):
            raise InputError(f"conflicting elevations: {[c.text for c in found]}")
        if meet[0] < meet[1]:
            degrees, named = degrees or [(meet[0] + meet[1]) / 2.0], []
        else:
            named = [max(named, key=lambda e: abs(sum(ELEVATIONS[e])))]
    if degrees and not -90.0 <= degrees[0] <= 90.0:
        raise InputError(f"elevation {degrees[0]:g} degrees is out of range; expected -90 to 90")
    if named and degrees:
        lo, hi = ELEVATIONS[named[0]]
        if not lo <= degrees[0] <= hi:
            raise InputError(f"conflicting elevations: {named[0]!r} is {lo:g} to {hi:g} degrees, not {degrees[0]:g}")
        named = []
    return (named[0] if named else None), (degrees[0] if degrees else None)


# Words of a hint that says only which way the camera looks ("looking down at it", "aim the lens
# up"), before what it looks at (after one of :data:`LOOK_TARGETS`: "on its crown").
DIRECTION_WORDS = frozenset(
    {"look", "looks", "looking", "down", "up", "the", "camera", "lens", "it", "with"}
    | {"shoot", "shoots", "shooting", "point", "points", "pointing", "pointed", "aim", "aims", "aiming", "aimed"}
    | {"angle", "angled", "angling", "tilt", "tilted", "tilting", "pitch", "pitched"}
)
LOOK_TARGETS = frozenset({"at", "on", "onto", "to", "towards", "into"})


def _direction_only(cue: _Cue) -> bool:
    """Whether ``cue`` is a height hint made only of the way the camera looks (:data:`DIRECTION_WORDS`),
    whatever it looks at."""
    said = list(itertools.takewhile(lambda w: w not in LOOK_TARGETS, cue.text.split()))
    return cue.field == "elevation" and cue.weak and all(w in DIRECTION_WORDS for w in said)


# Named heights exact enough to contradict an angle on their own side ("directly above, 30 degrees up").
EXACT_ELEVATIONS = frozenset({"top-down"})


def _yields_to(cue: _Cue, degrees: float) -> bool:
    """Whether a named height gives way to an explicit angle: it lies wholly on the angle's side of
    the horizontal ("from way up, like 70 degrees": high angle and 70 are one elevation, 70) and
    is not exact (:data:`EXACT_ELEVATIONS`); eye level and the other side stay a conflict."""
    return cue.field == "elevation" and cue.value not in EXACT_ELEVATIONS and _side_of(cue) * degrees > 0.0


# The broad heights, said of any camera well above or below ("from high above", "low down").
BROAD_ELEVATIONS = frozenset({"high angle", "low angle"})


def _beyond_broad(found: list[_Cue]) -> list[_Cue]:
    """Height cues less a broad one (:data:`BROAD_ELEVATIONS`) said as a place, not named as an
    angle, when another named height lies wholly beyond its range on its side of the horizontal:
    "from high above the table, almost vertical" is the near-vertical view, which is seen from
    high above; "a high angle, straight down" stays a conflict, as does "slightly above, top-down";
    heights that overlap ("a low angle, worm's eye") meet in :func:`_elevation`."""

    def beyond(other: _Cue, broad: _Cue) -> bool:
        (lo, hi), (other_lo, other_hi) = ELEVATIONS[broad.value], ELEVATIONS[other.value]
        return other_lo > hi if lo >= 0.0 else other_hi < lo

    def said_broadly(cue: _Cue) -> bool:
        return cue.field == "elevation" and cue.value in BROAD_ELEVATIONS and "angle" not in cue.text.split()

    named = [c for c in found if c.field == "elevation" and c.value not in BROAD_ELEVATIONS]
    return [c for c in found if not (said_broadly(c) and any(beyond(o, c) for o in named))]


def _narrowest(named: set[str]) -> list[str]:
    """Named elevations less those holding another one's range: "from overhead, looking straight
    down" is top-down, which lies inside bird's-eye; ranges that only overlap stay (a conflict)."""

    def inside(a: str, b: str) -> bool:
        return ELEVATIONS[b][0] <= ELEVATIONS[a][0] and ELEVATIONS[a][1] <= ELEVATIONS[b][1]

    return sorted(e for e in named if not any(o != e and inside(o, e) for o in named))


def _meeting(named: list[str]) -> tuple[float, float] | None:
    """Where named heights whose ranges overlap or touch meet, ``(lo, hi)`` degrees, or None when two
    lie apart ("from below ... from above"). Said together they describe one camera: "a low angle,
    worm's eye" (-60 to -50), "slightly above, a high angle" (25 to 30); "from way up, like from a
    drone" (high angle and bird's-eye) only touch, at 60. Every overlap of the named ranges is at
    most 10 degrees wide, so :func:`_elevation` reads it as its middle, in degrees."""
    lo = max(ELEVATIONS[e][0] for e in named)
    hi = min(ELEVATIONS[e][1] for e in named)
    return (lo, hi) if lo <= hi else None


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


def _readings(parsed: ParsedInstruction) -> dict[str, object]:
    """What ``parsed`` asks of the camera, one entry per field: per subject (by its order) its
    name, role, view, shot and region; the elevation, its degrees and the roll."""
    out: dict[str, object] = {"elevation": parsed.elevation, "elevation_deg": parsed.elevation_deg, "roll_deg": parsed.roll_deg}
    for k, s in enumerate(parsed.subjects):
        out |= {f"{k}.name": s.name, f"{k}.role": s.role, f"{k}.view": s.view, f"{k}.shot": s.shot, f"{k}.region": s.region}
    return {key: value for key, value in out.items() if value is not None}


def _unread(parsed: ParsedInstruction) -> int:
    """How many words of ``parsed`` are not understood."""
    return sum(len([w for w in words(run) if w not in PUNCTUATION]) for run in parsed.not_understood())


def _extension(before: dict[str, object], after: dict[str, object], read: int) -> int:
    """How far ``after`` improves on ``before`` having read ``read`` more words: the fields it adds
    when it keeps every one of ``before``; when it keeps each field but changes a value (a view
    read in full, "back" -> "back-right"), only if it read more words; else 0."""
    if any(key not in after for key in before):
        return 0
    if any(after[key] != value for key, value in before.items()):
        return 1 + len(after) - len(before) if read > 0 else 0
    return len(after) - len(before)


def _skippable(word: str, names: frozenset[str]) -> bool:
    """Whether :meth:`RuleParser._skipping_a_word` may leave ``word`` out: no stopword, no
    negation, no number and no word of a scene name (``names``)."""
    return word not in STOPWORDS and word not in NEGATION_WORDS and word not in names and not NUMBER.fullmatch(word)


def _example(vocabulary: Vocabulary) -> str:
    return vocabulary.names[0] if len(vocabulary) else "teddy bear"


_DEFAULT: RuleParser | None = None


def shared_parser() -> RuleParser:
    """The process's one :class:`RuleParser`: its tables are compiled once (about half a second),
    not per instruction (it holds no state between parses)."""
    global _DEFAULT
    if _DEFAULT is None:
        _DEFAULT = RuleParser()
    return _DEFAULT


def parse_instruction(text: str, vocabulary: Vocabulary) -> ParsedInstruction:
    """Parse ``text`` with the :func:`shared_parser`."""
    return shared_parser().parse(text, vocabulary)
