"""Photographic instructions with machine-checkable constraints for synthetic scenes.

The generator is part of the benchmark, not of the method: it reads the scene's
``ground_truth.json`` (object names, colours, centres, radii, fronts, world up) and, deterministically
for a seed, draws constraint sets (:class:`~capframe.constraints.Constraints`), keeps only those a
witness camera satisfies (:mod:`capframe.synth.witness`; verified with the ground-truth checker on
the rendered scene by :func:`write_instructions`), and phrases each one several ways.

Kinds (cycled in a seeded order over a scene's ``count``; a kind a scene cannot support falls back:
``layout+view`` -> ``layout``, ``view+elevation`` -> ``elevation`` without an asymmetric object,
``two-subject`` -> ``layout`` with a single object):

================  ==========================================================================
kind              constraints
================  ==========================================================================
layout            region; shot (60%); a level horizon, roll 0 (15%)
layout+view       region + view side (asymmetric subject); shot (60%)
view+elevation    view side + elevation (named 60%, explicit degrees 40%); shot (60%); region (30%)
elevation         elevation (named or explicit); shot (70%); region (40%)
roll              dutch angle ±10..30° ; region (60%); shot (50%); elevation (30%); view (30%)
two-subject       primary + secondary in opposite regions (left/right, thirds, diagonal corners);
                  primary's view side (40%, if asymmetric); elevation (40%); wide shot (25%)
================  ==========================================================================

Judgement rules (:func:`incompatibility`): view sides only for asymmetric subjects; a close-up
only with no region or a half-frame/centre region (never a corner or third) and never in a
two-subject layout; no wide shot from a high, bird's-eye, low or worm's-eye angle; an elevation
range starting at 55° or more (bird's-eye) only with left/right/centre or no region; no roll when
the elevation range reaches beyond ±75° (roll is undefined looking straight down or up); only the
primary of a two-subject layout carries a view side or shot size; worm's-eye is never generated
(the ground truth has no floor), nor are the parser's finer entries (top-down, slightly below, the
slight, side and back-three-quarter view sides: the grammar lists phrases for them, the sampling
tables leave them out). Then the witness search must succeed.

Grammar (see :func:`grammar_markdown`, rendered into docs/instruction-grammar.md). A sentence is

    HEAD [REGION] {, CLAUSE} .

* single subject: HEAD is a shot head (``a close-up of X``) when a shot is asked (70%), else a plain
  head (``a photo of X``, ``frame X``, ``X`` ...); REGION follows the subject directly
  (``... X on the left of the frame``); CLAUSEs are the view, elevation and roll phrases and, with a
  plain head, the trailing shot phrase, in a shuffled order.
* two subjects: HEAD is ``X1 R1 and X2 R2`` in one of a few frames (``a photo with {A} and {B}``, or
  ``a wide shot with {A} and {B}`` for a wide shot); the primary is always mentioned first.

The original text names subjects by their reference names; paraphrases may use unique aliases
("the bear", "the red chair") and are chosen from a pool of renderings, greedily the one whose
words differ most from the texts already chosen. All choices come from one ``random.Random(seed)``.

Placeholders: ``{X}`` the subject ("the teddy bear", "the red armchair" when names repeat, an
alias such as "the bear" in paraphrases), ``{P}`` a possessive ("its" or "the teddy bear's"),
``{obj}`` an object pronoun ("it"), ``{d}`` a whole number of degrees. In a two-subject sentence,
view phrases starting with "with"/"from" use the subject's name for ``{P}``/``{obj}``; the others
are prefixed with the subject (``the teddy bear seen from its left``); elevation phrases name the
primary. Roll sign (DESIGN §3): clockwise as seen by the photographer (the camera's right side dips)
is positive.

Files (:func:`write_instructions`): ``instructions.tsv`` with columns ``id, scene, text,
paraphrase_of, kind`` (each original, followed by its paraphrases with ids ``<id>.p<k>`` and
``paraphrase_of = <id>``), and ``constraints.json`` keyed by original id:
``{"<id>": {"scene", "text", "kind", "paraphrases": [texts], "constraints": Constraints.to_dict()}}``.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constraints import ELEVATIONS, REGIONS, Constraints, SubjectConstraint
from ..errors import InputError
from ..evaluate.check import GroundTruthChecker
from ..evaluate.ground_truth import GroundTruth, GTObject, parse_ground_truth, read_ground_truth
from ..scene import Camera
from ..scene._io import atomic_write, write_json
from .witness import WitnessFinder

KINDS = ("layout", "layout+view", "view+elevation", "elevation", "roll", "two-subject")
PARAPHRASES = 3  # paraphrases per instruction (besides the original text)
VERIFY_CANDIDATES = 3  # proxy witnesses tried against the exact verifier per constraint set

# --- phrase tables (the grammar) --------------------------------------------------------------

SHOT_HEADS = {
    "close-up": ["a close-up of {X}", "a tight shot of {X}", "a close shot of {X}", "a close-up photo of {X}"],
    "medium": ["a medium shot of {X}", "a mid shot of {X}", "a medium-distance photo of {X}", "a mid-range shot of {X}"],
    "wide": ["a wide shot of {X}", "a long shot of {X}", "a distant shot of {X}", "a wide view of {X}"],
}
PLAIN_HEADS = ["a photo of {X}", "a shot of {X}", "frame {X}", "capture {X}", "photograph {X}", "a picture of {X}", "{X}"]
SHOT_CLAUSES = {
    "close-up": ["filling the frame", "filling most of the frame", "shot up close", "framed tightly"],
    "medium": [
        "as a medium shot",
        "at medium size in the frame",
        "framed at mid distance",
        "taking up a moderate part of the frame",
    ],
    "wide": ["small in the frame", "from far away", "as a wide shot", "with plenty of space around {obj}"],
}
REGION_PHRASES = {
    "left": [
        "on the left",
        "on the left of the frame",
        "on the left side of the frame",
        "in the left half of the frame",
        "at the left of the picture",
    ],
    "right": [
        "on the right",
        "on the right of the frame",
        "on the right side of the frame",
        "in the right half of the frame",
        "at the right of the picture",
    ],
    "center": [
        "in the centre of the frame",
        "in the center of the frame",
        "centred in the frame",
        "in the middle of the frame",
        "centered in the picture",
    ],
    "top": ["at the top of the frame", "in the upper half of the frame", "near the top of the picture", "high in the frame"],
    "bottom": [
        "at the bottom of the frame",
        "in the lower half of the frame",
        "near the bottom of the picture",
        "low in the frame",
    ],
    "left third": [
        "in the left third of the frame",
        "within the left third of the picture",
        "in the leftmost third of the frame",
    ],
    "center third": [
        "in the middle third of the frame",
        "in the central third of the frame",
        "within the centre third of the picture",
    ],
    "right third": [
        "in the right third of the frame",
        "within the right third of the picture",
        "in the rightmost third of the frame",
    ],
    "upper left": [
        "in the upper-left corner of the frame",
        "in the top-left corner",
        "at the top left of the frame",
        "in the upper left of the picture",
    ],
    "upper right": [
        "in the upper-right corner of the frame",
        "in the top-right corner",
        "at the top right of the frame",
        "in the upper right of the picture",
    ],
    "lower left": [
        "in the lower-left corner of the frame",
        "in the bottom-left corner",
        "at the bottom left of the frame",
        "in the lower left of the picture",
    ],
    "lower right": [
        "in the lower-right corner of the frame",
        "in the bottom-right corner",
        "at the bottom right of the frame",
        "in the lower right of the picture",
    ],
}
VIEW_PHRASES = {
    "front": [
        "seen from the front",
        "seen from {P} front",
        "showing {P} front",
        "facing the camera",
        "in front view",
        "with the camera in front of {obj}",
    ],
    "back": [
        "seen from behind",
        "seen from {P} back",
        "showing {P} back",
        "facing away from the camera",
        "in rear view",
        "with the camera behind {obj}",
    ],
    "left": [
        "seen from {P} left",
        "showing {P} left side",
        "in left profile",
        "with the camera at {P} left",
        "from {P} left side",
        "with {P} left side towards the camera",
    ],
    "right": [
        "seen from {P} right",
        "showing {P} right side",
        "in right profile",
        "with the camera at {P} right",
        "from {P} right side",
        "with {P} right side towards the camera",
    ],
    "front-left": [
        "seen from {P} front left",
        "showing {P} front and left side",
        "in a front-left three-quarter view",
        "with the camera at {P} front left",
        "from {P} front-left",
    ],
    "front-right": [
        "seen from {P} front right",
        "showing {P} front and right side",
        "in a front-right three-quarter view",
        "with the camera at {P} front right",
        "from {P} front-right",
    ],
    "back-left": [
        "seen from {P} back left",
        "showing {P} back and left side",
        "seen from behind on {P} left",
        "with the camera at {P} back left",
        "from {P} rear left",
    ],
    "back-right": [
        "seen from {P} back right",
        "showing {P} back and right side",
        "seen from behind on {P} right",
        "with the camera at {P} back right",
        "from {P} rear right",
    ],
    "three-quarter": [
        "in three-quarter view",
        "at a three-quarter angle",
        "seen at three-quarters",
        "in a three-quarter front view",
    ],
    # Never generated (_VIEWS): the parser's wider vocabulary, listed so the grammar covers it.
    "back-three-quarter": ["in a rear three-quarter view", "at a back three-quarter angle", "seen at three-quarters from behind"],
    "side": ["seen from the side", "in profile", "in a side view", "showing {P} side"],
    "front-slight-left": ["seen slightly from {P} left", "from a bit to {P} left", "with the camera slightly to {P} left"],
    "front-slight-right": ["seen slightly from {P} right", "from a bit to {P} right", "with the camera slightly to {P} right"],
    "back-slight-left": ["seen from behind and slightly to {P} left", "from behind, a little to {P} left"],
    "back-slight-right": ["seen from behind and slightly to {P} right", "from behind, a little to {P} right"],
    "left-slight-front": ["seen from {P} left, slightly towards the front", "from {P} left side, a bit to the front"],
    "left-slight-back": ["seen from {P} left, slightly towards the back", "from {P} left side, a bit to the rear"],
    "right-slight-front": ["seen from {P} right, slightly towards the front", "from {P} right side, a bit to the front"],
    "right-slight-back": ["seen from {P} right, slightly towards the back", "from {P} right side, a bit to the rear"],
    "front-exact": ["seen from directly in front", "head-on", "dead on"],
    "back-exact": ["seen from directly behind", "tail-on"],
    "left-exact": ["seen directly from {P} left", "exactly from {P} left side"],
    "right-exact": ["seen directly from {P} right", "exactly from {P} right side"],
    "not-front": ["from anywhere but {P} front", "not from the front"],
    "not-back": ["from anywhere but behind", "not from behind"],
    "not-left": ["from anywhere but {P} left", "not from {P} left side"],
    "not-right": ["from anywhere but {P} right", "not from {P} right side"],
}
ELEVATION_PHRASES = {
    "eye level": ["at eye level", "from eye level", "with the camera at {P} height", "shot straight on at {P} height"],
    "slightly above": [
        "from slightly above",
        "looking a little down at {obj}",
        "with the camera slightly above {obj}",
        "from a little above",
    ],
    "high angle": ["from a high angle", "looking down at {obj}", "in a high-angle shot", "with the camera well above {obj}"],
    "bird's-eye": [
        "from a bird's-eye view",
        "seen from overhead",
        "looking steeply down at {obj}",
        "in an overhead shot",
        "as a bird's-eye shot",
    ],
    "low angle": ["from a low angle", "looking up at {obj}", "in a low-angle shot", "with the camera below {obj}, looking up"],
    "worm's-eye": ["from a worm's-eye view", "looking steeply up at {obj}", "from the ground looking steeply up"],
    "top-down": ["from directly above", "looking straight down at {obj}", "as a top-down view", "from straight above"],
    "slightly below": [
        "from slightly below",
        "looking a little up at {obj}",
        "with the camera slightly below {obj}",
        "from a little below",
    ],
}
EXPLICIT_ELEVATION_PHRASES = {
    "above": [
        "from {d} degrees above",
        "with the camera {d} degrees above {obj}",
        "looking down at {obj} from {d}° above",
        "at an elevation of {d} degrees",
    ],
    "below": [
        "from {d} degrees below",
        "with the camera {d} degrees below {obj}",
        "looking up at {obj} from {d}° below",
        "at an elevation of -{d} degrees",
    ],
}
ROLL_PHRASES = {
    "clockwise": [
        "with a {d}-degree clockwise dutch angle",
        "with the camera rolled {d} degrees clockwise",
        "camera tilted {d}° clockwise",
        "with a dutch tilt of {d} degrees clockwise",
        "with the camera's right side dipped {d} degrees",
    ],
    "counter-clockwise": [
        "with a {d}-degree counter-clockwise dutch angle",
        "with the camera rolled {d} degrees counter-clockwise",
        "camera tilted {d}° anticlockwise",
        "with a dutch tilt of {d} degrees counterclockwise",
        "with the camera's left side dipped {d} degrees",
    ],
    "level": ["keeping the horizon level", "with no dutch angle", "with a straight horizon", "with the horizon straight"],
}
TWO_SUBJECT_HEADS = ["{A} and {B}", "a photo with {A} and {B}", "frame {A} and {B}", "a shot of {A} and {B}", "{A}, {B}"]
TWO_SUBJECT_WIDE_HEADS = ["a wide shot with {A} and {B}", "a wide view with {A} and {B}"]

# --- sampling tables --------------------------------------------------------------------------

_REGION_WEIGHTS = {
    "left": 3,
    "right": 3,
    "center": 3,
    "top": 1,
    "bottom": 1,
    "left third": 1,
    "center third": 0.5,
    "right third": 1,
    "upper left": 0.7,
    "upper right": 0.7,
    "lower left": 0.7,
    "lower right": 0.7,
}
_CLOSE_UP_REGIONS = ("left", "right", "center", "top", "bottom")
_BIRDS_EYE_REGIONS = ("left", "right", "center")
# Worm's-eye, top-down and slightly below are never generated, nor are the view sides after three-quarter.
_NAMED_ELEVATIONS = ("eye level", "slightly above", "high angle", "bird's-eye", "low angle")
_EXPLICIT_ABOVE = (15, 20, 30, 40, 45)
_EXPLICIT_BELOW = (10, 15)
_ROLL_DEGREES = (10, 15, 20, 25, 30)
_VIEWS = ("front", "back", "left", "right", "front-left", "front-right", "back-left", "back-right", "three-quarter")
_PAIR_REGIONS = [
    (("left", "right"), 4),
    (("right", "left"), 4),
    (("left third", "right third"), 1),
    (("right third", "left third"), 1),
    (("upper left", "lower right"), 0.5),
    (("lower left", "upper right"), 0.5),
]
_MAX_ATTEMPTS = 60


@dataclass
class Instruction:
    """One generated instruction.

    Attributes:
        id: ``<scene>-<nnn>``; paraphrase k has id ``<id>.p<k>`` (k from 1).
        scene: the scene's name.
        text: the original phrasing.
        paraphrases: other phrasings of the same constraints.
        constraints: what a result must satisfy.
        kind: the generator kind (see the module docstring).
        witness: a camera that satisfies the constraints on the ground truth's proxies, and passes
            the verifier when one was given (the generator's evidence of satisfiability; not
            written to files), or None.
    """

    id: str
    scene: str
    text: str
    paraphrases: list[str]
    constraints: Constraints
    kind: str
    witness: Camera | None = None

    def paraphrase_ids(self) -> list[str]:
        return [f"{self.id}.p{k + 1}" for k in range(len(self.paraphrases))]


def _weighted(rng: random.Random, table: dict | list) -> object:
    items = list(table.items()) if isinstance(table, dict) else table
    return rng.choices([k for k, _ in items], weights=[w for _, w in items])[0]


# --- judgement rules --------------------------------------------------------------------------


def incompatibility(constraints: Constraints, symmetric: dict[str, bool]) -> str | None:
    """Why a constraint set should not be generated (None if it may be): the judgement rules of the
    module docstring. ``symmetric`` maps subject names to whether the subject has no front."""
    c = constraints
    rng = c.elevation_range()
    extreme_up = rng is not None and rng[0] >= 55.0
    looks_up = rng is not None and rng[1] <= 0.0
    two = len(c.subjects) > 1
    for s in c.subjects:
        if s.view is not None and symmetric.get(s.name, True):
            return f"view side asked of the symmetric {s.name}"
        if s.shot == "close-up" and (two or s.region not in (None, *_CLOSE_UP_REGIONS)):
            return "a close-up only with no region or a half-frame/centre region, and of a single subject"
        if s.shot == "wide" and (
            c.elevation in ("high angle", "bird's-eye", "low angle", "worm's-eye") or looks_up or extreme_up
        ):
            return "no wide shot from a steep or low angle"
        if extreme_up and s.region not in (None, *_BIRDS_EYE_REGIONS):
            return "from overhead only left/right/centre regions"
    if c.elevation == "worm's-eye":
        return "worm's-eye is not generated"
    if c.roll_deg is not None and rng is not None and max(abs(rng[0]), abs(rng[1])) > 75.0:
        return "no roll when the camera may look straight up or down (roll undefined)"
    if two and any(s.view is not None or s.shot is not None for s in c.subjects[1:]):
        return "only the primary subject carries a view side or a shot size"
    return None


# --- sampling ---------------------------------------------------------------------------------


def _region(rng: random.Random) -> str:
    return _weighted(rng, _REGION_WEIGHTS)


def _shot(rng: random.Random) -> str:
    return _weighted(rng, {"close-up": 1, "medium": 1.2, "wide": 0.8})


def _elevation(rng: random.Random, c: Constraints, explicit_share: float = 0.4) -> None:
    if rng.random() < explicit_share:
        if rng.random() < 0.8:
            c.elevation_deg = float(rng.choice(_EXPLICIT_ABOVE))
        else:
            c.elevation_deg = -float(rng.choice(_EXPLICIT_BELOW))
    else:
        c.elevation = _weighted(
            rng, {"eye level": 1, "slightly above": 1.3, "high angle": 1, "bird's-eye": 0.7, "low angle": 0.8}
        )


def _sample(kind: str, rng: random.Random, subjects: list[str], asymmetric: bool) -> Constraints:
    """One random constraint set of ``kind`` for the named subjects (not yet judged); view sides
    are drawn only when the primary is ``asymmetric``."""
    s = SubjectConstraint(subjects[0])
    c = Constraints(subjects=[s])
    if kind == "layout":
        s.region = _region(rng)
        s.shot = _shot(rng) if rng.random() < 0.6 else None
        c.roll_deg = 0.0 if rng.random() < 0.15 else None
    elif kind == "layout+view":
        s.region, s.view = _region(rng), rng.choice(_VIEWS)
        s.shot = _shot(rng) if rng.random() < 0.6 else None
    elif kind == "view+elevation":
        s.view = rng.choice(_VIEWS)
        _elevation(rng, c)
        s.shot = _shot(rng) if rng.random() < 0.6 else None
        s.region = _region(rng) if rng.random() < 0.3 else None
    elif kind == "elevation":
        _elevation(rng, c)
        s.shot = _shot(rng) if rng.random() < 0.7 else None
        s.region = _region(rng) if rng.random() < 0.4 else None
    elif kind == "roll":
        c.roll_deg = float(rng.choice(_ROLL_DEGREES)) * rng.choice((1.0, -1.0))
        s.region = _region(rng) if rng.random() < 0.6 else None
        s.shot = _shot(rng) if rng.random() < 0.5 else None
        if rng.random() < 0.3:
            c.elevation = rng.choice(("eye level", "slightly above", "high angle", "low angle"))
        s.view = rng.choice(_VIEWS) if asymmetric and rng.random() < 0.3 else None
    elif kind == "two-subject":
        (r1, r2) = _weighted(rng, _PAIR_REGIONS)
        s.region = r1
        c.subjects.append(SubjectConstraint(subjects[1], role="secondary", region=r2))
        s.view = rng.choice(_VIEWS) if asymmetric and rng.random() < 0.4 else None
        if rng.random() < 0.4:
            if rng.random() < 0.3:
                c.elevation_deg = float(rng.choice((15, 20, 30)))
            else:
                c.elevation = rng.choice(("eye level", "slightly above", "high angle"))
        s.shot = "wide" if rng.random() < 0.25 else None
    else:
        raise ValueError(f"unknown kind {kind!r}")
    return c


# --- phrasing ---------------------------------------------------------------------------------


def _fill(template: str, **values: str) -> str:
    return template.format(**values)


def _absolute(template: str) -> bool:
    """View phrases that stand on their own in a two-subject sentence (they name the subject)."""
    return template.startswith(("with ", "from "))


def _possessive(noun_phrase: str) -> str:
    return noun_phrase + ("'" if noun_phrase.endswith("s") else "'s")


def render_text(rng: random.Random, c: Constraints, references: dict[str, list[str]], use_aliases: bool) -> str:
    """One phrasing of ``c``. ``references`` maps each subject name to the nouns that may name it
    (its reference name first, then unique aliases); aliases are used only with ``use_aliases``."""

    def noun(name: str) -> str:
        options = references[name]
        return "the " + (rng.choice(options) if use_aliases and len(options) > 1 and rng.random() < 0.6 else options[0])

    s = c.subjects[0]
    X = noun(s.name)
    two = len(c.subjects) > 1
    clauses: list[str] = []
    if two:
        s2 = c.subjects[1]
        A = f"{X} {rng.choice(REGION_PHRASES[s.region])}"
        B = f"{noun(s2.name)} {rng.choice(REGION_PHRASES[s2.region])}"
        head = _fill(rng.choice(TWO_SUBJECT_WIDE_HEADS if s.shot == "wide" else TWO_SUBJECT_HEADS), A=A, B=B)
        named = dict(P=_possessive(X), obj=X)
        if s.view is not None:
            t = rng.choice(VIEW_PHRASES[s.view])
            clauses.append(_fill(t, **named) if _absolute(t) else f"{X} " + _fill(t, P="its", obj="it"))
        pronouns = named
    else:
        pronouns = dict(P="its" if rng.random() < 0.7 else _possessive(X), obj="it")
        if s.shot is not None and rng.random() < 0.7:
            head = _fill(rng.choice(SHOT_HEADS[s.shot]), X=X)
        else:
            head = _fill(rng.choice(PLAIN_HEADS), X=X)
            if s.shot is not None:
                clauses.append(_fill(rng.choice(SHOT_CLAUSES[s.shot]), obj="it"))
        if s.region is not None:
            head += " " + rng.choice(REGION_PHRASES[s.region])
        if s.view is not None:
            clauses.append(_fill(rng.choice(VIEW_PHRASES[s.view]), **pronouns))
    if c.elevation is not None:
        clauses.append(_fill(rng.choice(ELEVATION_PHRASES[c.elevation]), **pronouns))
    elif c.elevation_deg is not None:
        d = abs(c.elevation_deg)
        side = "above" if c.elevation_deg >= 0 else "below"
        clauses.append(_fill(rng.choice(EXPLICIT_ELEVATION_PHRASES[side]), d=f"{d:g}", **pronouns))
    if c.roll_deg is not None:
        direction = "level" if c.roll_deg == 0 else ("clockwise" if c.roll_deg > 0 else "counter-clockwise")
        clauses.append(_fill(rng.choice(ROLL_PHRASES[direction]), d=f"{abs(c.roll_deg):g}"))
    rng.shuffle(clauses)
    text = head + "".join(", " + clause for clause in clauses) + "."
    return text[0].upper() + text[1:]


def _words(text: str) -> set[str]:
    return set(text.lower().rstrip(".").replace(",", " ").split())


def _phrasings(rng: random.Random, c: Constraints, references: dict[str, list[str]], count: int) -> list[str]:
    """``count`` distinct phrasings: the first with reference names only, then, from a pool of
    candidates, greedily the one whose words differ most (Jaccard) from those already chosen."""
    texts = [render_text(rng, c, references, use_aliases=False)]
    pool: list[str] = []
    for _ in range(40):
        text = render_text(rng, c, references, use_aliases=True)
        if text not in texts and text not in pool:
            pool.append(text)
        if len(pool) >= 4 * count:
            break
    while len(texts) < count and pool:

        def distance(t: str) -> float:
            w = _words(t)
            return min(1.0 - len(w & _words(o)) / len(w | _words(o)) for o in texts)

        best = max(pool, key=distance)  # first maximum: deterministic
        texts.append(best)
        pool.remove(best)
    return texts


# --- the generator ----------------------------------------------------------------------------


def _kind_schedule(rng: random.Random, count: int, gt: GroundTruth) -> list[str]:
    has_front = any(o.front is not None for o in gt.objects)
    order = list(KINDS)
    rng.shuffle(order)
    kinds = []
    for i in range(count):
        kind = order[i % len(order)]
        if kind in ("layout+view",) and not has_front:
            kind = "layout"
        if kind == "view+elevation" and not has_front:
            kind = "elevation"
        if kind == "two-subject" and len(gt.objects) < 2:
            kind = "layout"
        kinds.append(kind)
    return kinds


def _witness(finder: WitnessFinder, c: Constraints, subjects: list[int], fronts: list, verify) -> Camera | None:
    """The first proxy witness that ``verify`` accepts (the first one without ``verify``)."""
    for k, camera in enumerate(finder.candidates(c, subjects, fronts)):
        if verify is None or verify(camera, c):
            return camera
        if k + 1 >= VERIFY_CANDIDATES:
            break
    return None


def generate_instructions(
    ground_truth: dict | GroundTruth,
    count: int,
    seed: int,
    *,
    scene: str = "scene",
    cameras: list[Camera] | None = None,
    paraphrases: int = PARAPHRASES,
    verify: Callable[[Camera, Constraints], bool] | None = None,
) -> list[Instruction]:
    """Generate ``count`` instructions for a scene from its ground truth, deterministically for ``seed``.

    Args:
        ground_truth: the parsed ``ground_truth.json`` (dict) or a :class:`GroundTruth`.
        count: number of instructions (originals; each also gets ``paraphrases`` paraphrases).
        seed: random seed; the same inputs and seed give the same output.
        scene: scene name, the prefix of the ids.
        cameras: the scene's training cameras, if known: the first one's intrinsics are the witness
            search's reference camera (default 320x240, 60° horizontal field of view), and the
            witness stays inside the ball around their mean centre that holds them all and every
            object (default: the ball of radius ``scale`` around the objects' centroid).
        paraphrases: paraphrases per instruction.
        verify: optional exact test of a witness camera (e.g. the ground-truth checker on the
            rendered scene); proxy witnesses that fail it are skipped (up to
            :data:`VERIFY_CANDIDATES` per constraint set, then the set is dropped).
    """
    gt = ground_truth if isinstance(ground_truth, GroundTruth) else parse_ground_truth(ground_truth)
    if count < 1:
        raise InputError(f"count is {count}; expected at least 1 instruction")
    rng = random.Random(seed)
    objects = gt.objects
    names = {id(o): gt.reference_name(o) for o in objects}
    if len(set(n.lower() for n in names.values())) != len(objects):
        raise InputError("objects share a name and a colour, so instructions cannot tell them apart", source="ground_truth.json")
    index = {names[id(o)]: i for i, o in enumerate(objects)}
    symmetric = {names[id(o)]: o.front is None for o in objects}
    references = {names[id(o)]: [names[id(o)], *gt.unique_aliases(o)] for o in objects}
    centers, radii = np.stack([o.center for o in objects]), np.array([o.radius for o in objects])
    intrinsics, free_space = None, None
    if cameras:
        intrinsics = (cameras[0].K, cameras[0].width, cameras[0].height)
        positions = np.stack([c.center for c in cameras])
        middle = positions.mean(0)
        reach = max(np.linalg.norm(positions - middle, axis=1).max(), (np.linalg.norm(centers - middle, axis=1) + radii).max())
        free_space = (middle, float(reach))
    finder = WitnessFinder(centers, radii, gt.up, gt.scale, intrinsics, free_space, gt.room, [o.box for o in objects])

    pool = list(objects)
    rng.shuffle(pool)
    asymmetric = [o for o in pool if o.front is not None]
    kinds = _kind_schedule(rng, count, gt)
    instructions = []
    seen: set[str] = set()
    for i, kind in enumerate(kinds):
        found = None
        for attempt in range(_MAX_ATTEMPTS):
            if attempt == _MAX_ATTEMPTS // 2:
                kind = "layout"  # the scheduled kind found nothing feasible: fall back to the simplest
            choices = asymmetric if kind in ("layout+view", "view+elevation") else pool
            primary: GTObject = choices[(i + attempt) % len(choices)]
            subjects = [names[id(primary)]]
            if kind == "two-subject":
                others = [o for o in pool if o is not primary]
                subjects.append(names[id(rng.choice(others))])
            c = _sample(kind, rng, subjects, primary.front is not None)
            key = repr(c.to_dict())
            if key in seen or incompatibility(c, symmetric) is not None:
                continue
            fronts = [objects[index[n]].front for n in subjects]
            witness = _witness(finder, c, [index[n] for n in subjects], fronts, verify)
            if witness is not None:
                found = (c, witness)
                break
        if found is None:  # nothing new was feasible: a centred subject (witness None if even that fails)
            subject = pool[i % len(pool)]
            c = Constraints(subjects=[SubjectConstraint(names[id(subject)], region="center")])
            found = (c, _witness(finder, c, [index[names[id(subject)]]], [subject.front], verify))
        c, witness = found
        seen.add(repr(c.to_dict()))
        texts = _phrasings(rng, c, references, 1 + paraphrases)
        instructions.append(Instruction(f"{scene}-{i:03d}", scene, texts[0], texts[1:], c, kind, witness))
    return instructions


def _tsv_field(text: str) -> str:
    if any(ch in text for ch in "\t\n\r"):
        raise ValueError(f"text {text!r} holds a tab or line break")
    return text


def write_instructions(scene_dir: str | Path, out_dir: str | Path, count: int = 3, seed: int = 0) -> list[Instruction]:
    """``capframe instructions``: generate ``count`` instructions for the synthetic scene in
    ``scene_dir`` and write ``out_dir/instructions.tsv`` and ``out_dir/constraints.json``
    (formats in the module docstring). The scene's training cameras, if any, give the witness
    search its reference intrinsics and free space (see :func:`generate_instructions`); when the
    scene has Gaussians and labels, every witness is verified with the ground-truth checker
    (:class:`~capframe.evaluate.check.GroundTruthChecker`), so each written constraint set has a
    camera that provably satisfies it."""
    from ..scene import load_scene_dir

    scene_dir = Path(scene_dir)
    gt = read_ground_truth(scene_dir)
    name = scene_dir.resolve().name
    cameras = load_scene_dir(scene_dir, load_gaussians=False).cameras if _has_scene(scene_dir) else []
    verify = None
    if all((scene_dir / f).is_file() for f in ("scene.ply", "semantics.json", "labels.npy")):
        checker = GroundTruthChecker(scene_dir)
        verify = lambda camera, c: checker.check(camera, c).all_satisfied  # noqa: E731
    instructions = generate_instructions(gt, count, seed, scene=name, cameras=cameras or None, verify=verify)
    rows = ["id\tscene\ttext\tparaphrase_of\tkind"]
    for ins in instructions:
        rows.append("\t".join([ins.id, ins.scene, _tsv_field(ins.text), "", ins.kind]))
        for pid, text in zip(ins.paraphrase_ids(), ins.paraphrases):
            rows.append("\t".join([pid, ins.scene, _tsv_field(text), ins.id, ins.kind]))
    out_dir = Path(out_dir)
    atomic_write(out_dir / "instructions.tsv", "\n".join(rows) + "\n")
    write_json(
        out_dir / "constraints.json",
        {
            ins.id: {
                "scene": ins.scene,
                "text": ins.text,
                "kind": ins.kind,
                "paraphrases": ins.paraphrases,
                "constraints": ins.constraints.to_dict(),
            }
            for ins in instructions
        },
    )
    return instructions


def _has_scene(scene_dir: Path) -> bool:
    return any((scene_dir / f).exists() for f in ("scene.ply", "cameras.json", "sparse", "transforms.json"))


# --- documentation ----------------------------------------------------------------------------


def grammar_markdown() -> str:
    """The phrase tables as Markdown (docs/instruction-grammar.md is this text)."""
    out = [
        "# Instruction grammar",
        "",
        "Generated by `capframe.synth.instructions.grammar_markdown()` from the generator's phrase tables;",
        "a test keeps this file in sync. How sentences are assembled, the kinds and the judgement rules",
        "are described in the module docstring of `capframe/synth/instructions.py`.",
        "",
        "A sentence is `HEAD [REGION] {, CLAUSE} .` (first letter capitalised). Placeholders: `{X}` the",
        "subject (`the teddy bear`; `the red armchair` when two objects share a name; an alias such as",
        "`the bear` in paraphrases), `{P}` a possessive (`its` or `the teddy bear's`), `{obj}` an object",
        "pronoun (`it`; the subject's name in two-subject sentences), `{d}` whole degrees,",
        "`{A}`/`{B}` a subject followed by its region phrase. Two-subject view phrases that do not start",
        "with `with`/`from` are prefixed with the subject (`the teddy bear seen from its left`).",
        "Roll: clockwise as seen by the photographer (right side dips) is positive (DESIGN §3).",
        "Worm's-eye phrases are listed for parsers but never generated (the ground truth has no floor).",
        "",
    ]

    def table(title: str, key_name: str, mapping: dict) -> None:
        out.extend([f"## {title}", "", f"| {key_name} | phrases |", "|---|---|"])
        for key, phrases in mapping.items():
            out.append(f"| {key} | " + " · ".join(f"`{p}`" for p in phrases) + " |")
        out.append("")

    table("Shot heads (`HEAD` with a shot size)", "shot", SHOT_HEADS)
    out.extend(["## Plain heads", "", " · ".join(f"`{p}`" for p in PLAIN_HEADS), ""])
    table("Trailing shot clauses (after a plain head)", "shot", SHOT_CLAUSES)
    table("Regions (`REGION`, right after the subject)", "region", REGION_PHRASES)
    table("View sides (asymmetric subjects only)", "view", VIEW_PHRASES)
    table("Named elevations", "elevation", ELEVATION_PHRASES)
    table("Explicit elevations (`elevation_deg` = +d above, -d below)", "side", EXPLICIT_ELEVATION_PHRASES)
    table("Roll (`roll_deg` = +d clockwise, -d counter-clockwise, 0 level)", "direction", ROLL_PHRASES)
    out.extend(
        [
            "## Two-subject heads",
            "",
            " · ".join(f"`{p}`" for p in TWO_SUBJECT_HEADS),
            "",
            "With a wide shot of the primary: " + " · ".join(f"`{p}`" for p in TWO_SUBJECT_WIDE_HEADS),
            "",
        ]
    )
    assert set(REGION_PHRASES) == set(REGIONS) and set(ELEVATION_PHRASES) == set(ELEVATIONS)
    return "\n".join(out)
