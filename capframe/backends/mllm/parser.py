"""The MLLM instruction parser: the paper's subject, layout and orientation parsers, producing
the same :class:`~capframe.translate.instruction.ParsedInstruction` as the rule parser.

Three requests per instruction (prompts ``subjects``, ``layout``, ``orientation``): first the
subjects, each matched to one name of the scene's vocabulary (the main subject listed first);
then, for those subjects, their layout and the camera's angles (these two are sent together, each
answer keyed by subject name, so every subject is answered exactly once by construction).

The schemas say everything the pipeline requires of an answer, so that a constrained decoder
(xgrammar locally; a server's structured output) can only produce one the pipeline takes, and the
validation in the :class:`~.chat.ChatModel` refuses, and feeds back, any other:

* a subject's name is one of the scene's names or :data:`UNKNOWN` (an enum, which is part of the
  request and so of the cache key); a scene without names (an open vocabulary, grounded by name)
  gets a short free string instead;
* a layout box is its centre and size, the centre bounded to the region the same answer names
  (one schema branch per region, :func:`layout_entry`) and at least half the smallest box from
  the frame's edge; :func:`frame_box` shrinks it about its centre to fit the frame;
* angles are bounded (azimuth -180 to 180, elevation and roll -90 to 90) and null is "no cue".

An answer that is not a schema-valid one (a model that does not validate) is still refused here
in one line (:class:`~capframe.errors.ModelError`) where it would mislead: names outside the
scene's list or the parsed subjects.

How numbers become the parsed instruction's cues (DESIGN §3 conventions):

* a box becomes :attr:`ParsedSubject.box` (the pseudo labels' mask box), beside the named region
  and shot size the checker reads;
* an azimuth offset becomes the view side nearest to it (:func:`view_side`); with
  ``either_side`` the nearest side that accepts its mirror as well ("side", "three-quarter");
* an elevation becomes ``elevation_deg`` when the instruction states the number, else the named
  elevation whose interval holds it with the nearest centre (:func:`named_elevation`);
* a roll is the roll, in degrees.

A mention the model leaves unmatched (``name`` :data:`UNKNOWN`) is matched by the vocabulary's
own rules, whose error names the closest known objects, as the rule parser's does.
"""

from __future__ import annotations

import copy

from ...constraints import ELEVATIONS, REGIONS, SHOT_SIZES, VIEW_SIDES
from ...errors import InputError, ModelError, clip
from ...measure import wrap_deg
from ...translate.instruction import ParsedInstruction, ParsedSubject
from ...translate.vocabulary import Vocabulary, key
from .chat import ChatModel
from .prompts import load

# The subject parser's name for a subject that is none of the scene's objects.
UNKNOWN = "unknown"

# Views whose accepted azimuths are their own mirror images: the answers for "either side".
_MIRRORED = {k: v for k, v in VIEW_SIDES.items() if {round(wrap_deg(-a), 6) for a in v} == {round(wrap_deg(a), 6) for a in v}}
_SINGLE = {k: v for k, v in VIEW_SIDES.items() if len(v) == 1}


def view_side(azimuth_deg: float, either_side: bool = False) -> str:
    """The :data:`~capframe.constraints.VIEW_SIDES` key nearest to an azimuth (0 front, +90 the
    subject's right); with ``either_side`` among the sides that accept the mirror as well."""
    table = _MIRRORED if either_side else _SINGLE
    return min(table, key=lambda k: min(abs(wrap_deg(azimuth_deg - a)) for a in table[k]))


def named_elevation(elevation_deg: float) -> str:
    """The :data:`~capframe.constraints.ELEVATIONS` key whose interval holds ``elevation_deg``
    with the nearest centre (the intervals cover -90 to 90)."""
    holding = [k for k, (lo, hi) in ELEVATIONS.items() if lo <= elevation_deg <= hi]
    return min(holding, key=lambda k: abs(sum(ELEVATIONS[k]) / 2 - elevation_deg))


def subject_name_schema(vocabulary: Vocabulary) -> dict:
    """The JSON schema of a subject's ``name``: one of the scene's names or :data:`UNKNOWN`, or
    for a scene that names no objects (an open vocabulary) the prompt file's short free string."""
    if not len(vocabulary):
        return copy.deepcopy(load("subjects").schema["properties"]["subjects"]["items"]["properties"]["name"])
    return {"enum": [*vocabulary.names, *([] if UNKNOWN in vocabulary else [UNKNOWN])]}


def layout_entry(subject: dict) -> dict:
    """The layout prompt's per-subject schema ``subject`` as one branch per region (and one for
    none): the region's value fixed and the box's centre bounded to the region, so that a box
    centred outside the region it is said to be in cannot be decoded."""
    branches = []
    for region in [*REGIONS, None]:
        branch = copy.deepcopy(subject)
        branch["properties"]["region"] = {"type": "null"} if region is None else {"const": region}
        box = next(b for b in branch["properties"]["box"]["anyOf"] if b.get("type") == "object")["properties"]
        x0, y0, x1, y1 = (0.0, 0.0, 1.0, 1.0) if region is None else REGIONS[region]
        for axis, lo, hi in (("center_x", x0, x1), ("center_y", y0, y1)):
            box[axis]["minimum"] = max(box[axis]["minimum"], lo)
            box[axis]["maximum"] = min(box[axis]["maximum"], hi)
        branches.append(branch)
    return {"anyOf": branches}


def frame_box(center_x: float, center_y: float, width: float, height: float) -> tuple[float, float, float, float]:
    """The box ``(x0, y0, x1, y1)`` of a layout answer's centre and size, shrunk about its centre
    where it reaches past the frame ``[0, 1]`` (so its centre, the region's cue, is kept)."""
    half_x = min(width / 2, center_x, 1 - center_x)
    half_y = min(height / 2, center_y, 1 - center_y)
    return (
        max(0.0, center_x - half_x),
        max(0.0, center_y - half_y),
        min(1.0, center_x + half_x),
        min(1.0, center_y + half_y),
    )


class MLLMParser:
    """:class:`~capframe.backends.InstructionParser` through a chat model.

    Args:
        chat: the model (an endpoint or local weights behind the response cache).
    """

    def __init__(self, chat: ChatModel):
        self.chat = chat
        self.prompts = {name: load(name) for name in ("subjects", "layout", "orientation")}
        self._layout_entry = layout_entry(self.prompts["layout"].schema["$defs"]["subject"])

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction:
        """``text`` as a :class:`ParsedInstruction` with subjects from ``vocabulary`` (any the
        model names when the vocabulary is empty: an open-vocabulary scene)."""
        if not text or not text.strip():
            raise InputError("the instruction is empty; expected e.g. 'a close-up of the teddy bear on the left'")
        subjects = self._subjects(text, vocabulary)
        listing = "; ".join(f"{name} (said: {mention!r})" for mention, name, _ in subjects)
        fields = {"instruction": text.strip(), "subjects": listing, "regions": ", ".join(REGIONS), "shots": ", ".join(SHOT_SIZES)}
        names = [name for _, name, _ in subjects]
        entries = {"layout": self._layout_entry, "orientation": None}
        layout, orientation = self.chat.complete_many(
            [
                self.prompts[p].request(fields, schema=self.prompts[p].keyed(("properties", "subjects"), names, "subject", value))
                for p, value in entries.items()
            ]
        )
        boxes = self._layout(layout.data, names)
        sides = self._orientation(orientation.data, names)
        parsed_subjects = [
            ParsedSubject(mention, name, role, sides[name][0], *boxes[name][:2], sides[name][1], boxes[name][2])
            for mention, name, role in subjects
        ]
        camera = orientation.data
        elevation, elevation_deg = None, camera["elevation_deg"]
        if elevation_deg is not None and not camera["elevation_explicit"]:
            elevation, elevation_deg = named_elevation(elevation_deg), None
        corrected = [
            {"said": " ".join(key(mention)), "read": name}
            for mention, name, _ in subjects
            if len(vocabulary) and name not in vocabulary.candidates(mention)
        ]
        return ParsedInstruction(
            text,
            parsed_subjects,
            elevation,
            elevation_deg,
            camera["roll_deg"],
            [],
            corrected,
            parser={"backend": "mllm", "model": self.chat.identity, "prompts": [p.version for p in self.prompts.values()]},
        )

    def _fail(self, prompt: str, message: str) -> ModelError:
        return ModelError(f"{self.chat.identity}: the {prompt} answer ({self.prompts[prompt].version}) is invalid: {message}")

    def _subjects(self, text: str, vocabulary: Vocabulary) -> list[tuple[str, str, str]]:
        """(mention, scene name, role) of each subject, the primary (listed first) first. The
        model picks names from the scene's list (with aliases, so a synonym can be read); a
        mention it leaves unmatched (:data:`UNKNOWN`) goes through :meth:`Vocabulary.match`,
        whose error names the closest objects. With an empty vocabulary the model's own name is
        the subject's (lower case, single spaces). A subject named twice is one subject."""
        prompt = self.prompts["subjects"]
        objects = "; ".join(
            e.name + (f": {', '.join(e.aliases)}" if e.aliases else "") for e in sorted(vocabulary.entries, key=lambda e: e.name)
        )
        schema = copy.deepcopy(prompt.schema)
        listed = schema["properties"]["subjects"]
        listed["items"]["properties"]["name"] = subject_name_schema(vocabulary)
        if len(vocabulary):
            listed["maxItems"] = min(listed["maxItems"], len(vocabulary))
        fields = {"instruction": text.strip(), "objects": objects or "none listed (name each subject yourself)"}
        data = self.chat.complete(prompt.request(fields, schema=schema)).data
        found: dict[str, str] = {}
        for i, s in enumerate(data["subjects"]):
            name = s["name"]
            if not len(vocabulary):
                name = " ".join(name.lower().split())
                if not name:
                    raise self._fail("subjects", f"subjects[{i}].name is blank; expected the object's name")
            elif name == UNKNOWN and UNKNOWN not in vocabulary:
                name = vocabulary.match(s["mention"])
            elif name not in vocabulary:
                raise self._fail(
                    "subjects", f"subjects[{i}].name {clip(repr(name))} is not a scene object; expected one of {vocabulary.names}"
                )
            found.setdefault(name, s["mention"])
        return [(mention, name, "secondary" if k else "primary") for k, (name, mention) in enumerate(found.items())]

    def _answered_once(self, prompt: str, data: dict, names: list[str]) -> dict[str, dict]:
        """The answer's entries by subject name: exactly the parsed subjects."""
        entries = data["subjects"]
        unknown = [n for n in entries if n not in names]
        if unknown:
            raise self._fail(prompt, f"subjects.{unknown[0]} is not a parsed subject; expected {names}")
        missing = [n for n in names if n not in entries]
        if missing:
            raise self._fail(prompt, f"subjects has no entry for {missing}")
        return {n: entries[n] for n in names}

    def _layout(self, data: dict, names: list[str]) -> dict[str, tuple]:
        """Per subject: (region, shot, box ``(x0, y0, x1, y1)`` or None)."""
        out = {}
        for name, entry in self._answered_once("layout", data, names).items():
            box = entry["box"]
            out[name] = (entry["region"], entry["shot"], None if box is None else frame_box(**box))
        return out

    def _orientation(self, data: dict, names: list[str]) -> dict[str, tuple[bool, str | None]]:
        """Per subject: (symmetric, view side or None)."""
        out = {}
        for name, entry in self._answered_once("orientation", data, names).items():
            azimuth = entry["azimuth_deg"]
            out[name] = (entry["symmetric"], None if azimuth is None else view_side(azimuth, entry["either_side"]))
        return out
