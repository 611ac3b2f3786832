"""The MLLM instruction parser: the paper's subject, layout and orientation parsers, producing
the same :class:`~capframe.translate.instruction.ParsedInstruction` as the rule parser.

Three requests per instruction (prompts ``subjects``, ``layout``, ``orientation``): first the
subjects, each matched to one name of the scene's vocabulary (the main subject listed first);
then, for those subjects, their layout and the camera's angles (these two are sent together, each
answer keyed by subject name, so every subject is answered exactly once by construction). Every
answer has passed its JSON schema in the :class:`~.chat.ChatModel`; here it is also checked for
meaning, and a meaningless answer is a one-line :class:`~capframe.errors.ModelError` naming the
field: names outside the scene's list or the parsed subjects, a box not ordered or not inside
``[0, 1]``, a box not centred in the region the same answer names.

How numbers become the parsed instruction's cues (DESIGN §3 conventions):

* a box becomes :attr:`ParsedSubject.box` (the pseudo labels' mask box), beside the named region
  and shot size the checker reads;
* an azimuth offset becomes the view side nearest to it (:func:`view_side`); with
  ``either_side`` the nearest side that accepts its mirror as well ("side", "three-quarter");
* an elevation becomes ``elevation_deg`` when the instruction states the number, else the named
  elevation whose interval holds it with the nearest centre (:func:`named_elevation`);
* a roll is the roll, in degrees.

A mention the model leaves unmatched (``name`` null) is matched by the vocabulary's own rules,
whose error names the closest known objects, as the rule parser's does.
"""

from __future__ import annotations

import math

from ...constraints import ELEVATIONS, REGIONS, SHOT_SIZES, VIEW_SIDES
from ...errors import InputError, ModelError, clip
from ...measure import wrap_deg
from ...translate.instruction import ParsedInstruction, ParsedSubject, check_box
from ...translate.vocabulary import Vocabulary, key
from .chat import ChatModel
from .prompts import load

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


class MLLMParser:
    """:class:`~capframe.backends.InstructionParser` through a chat model.

    Args:
        chat: the model (an endpoint or local weights behind the response cache).
    """

    def __init__(self, chat: ChatModel):
        self.chat = chat
        self.prompts = {name: load(name) for name in ("subjects", "layout", "orientation")}

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction:
        """``text`` as a :class:`ParsedInstruction` with subjects from ``vocabulary``."""
        if not text or not text.strip():
            raise InputError("the instruction is empty; expected e.g. 'a close-up of the teddy bear on the left'")
        if not len(vocabulary):
            raise InputError("the scene names no objects (no semantic labels), so no subject can be matched")
        subjects = self._subjects(text, vocabulary)
        listing = "; ".join(f"{name} (said: {mention!r})" for mention, name, _ in subjects)
        fields = {"instruction": text.strip(), "subjects": listing, "regions": ", ".join(REGIONS), "shots": ", ".join(SHOT_SIZES)}
        names = [name for _, name, _ in subjects]
        layout, orientation = self.chat.complete_many(
            [
                self.prompts[p].request(fields, schema=self.prompts[p].keyed(("properties", "subjects"), names, "subject"))
                for p in ("layout", "orientation")
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
            if name not in vocabulary.candidates(mention)
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
        mention it leaves unmatched goes through :meth:`Vocabulary.match`, whose error names the
        closest objects. A subject named twice is one subject."""
        prompt = self.prompts["subjects"]
        objects = "; ".join(
            e.name + (f": {', '.join(e.aliases)}" if e.aliases else "") for e in sorted(vocabulary.entries, key=lambda e: e.name)
        )
        schema = prompt.narrowed(("properties", "subjects", "items", "properties", "name"), enum=[*vocabulary.names, None])
        schema["properties"]["subjects"]["maxItems"] = min(schema["properties"]["subjects"]["maxItems"], len(vocabulary))
        data = self.chat.complete(prompt.request({"instruction": text.strip(), "objects": objects}, schema=schema)).data
        found: dict[str, str] = {}
        for i, s in enumerate(data["subjects"]):
            name = s["name"]
            if name is None:
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
        """Per subject: (region, shot, box or None)."""
        out = {}
        for name, entry in self._answered_once("layout", data, names).items():
            box = entry["box"]
            if box is not None:
                try:
                    box = check_box(box, f"subjects.{name}.box")
                except InputError as err:
                    raise self._fail("layout", str(err)) from None
                region = entry["region"]
                cx, cy = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
                if region is not None:
                    x0, y0, x1, y1 = REGIONS[region]
                    if not (x0 <= cx <= x1 and y0 <= cy <= y1):
                        raise self._fail(
                            "layout", f"subjects.{name}.box is centred at ({cx:.2f}, {cy:.2f}), outside its region {region!r}"
                        )
            out[name] = (entry["region"], entry["shot"], box)
        return out

    def _orientation(self, data: dict, names: list[str]) -> dict[str, tuple[bool, str | None]]:
        """Per subject: (symmetric, view side or None)."""
        out = {}
        for name, entry in self._answered_once("orientation", data, names).items():
            azimuth = entry["azimuth_deg"]
            if azimuth is not None and not math.isfinite(azimuth):
                raise self._fail("orientation", f"{name}: azimuth_deg {azimuth!r} is not finite")
            out[name] = (entry["symmetric"], None if azimuth is None else view_side(azimuth, entry["either_side"]))
        return out
