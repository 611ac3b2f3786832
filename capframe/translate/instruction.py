"""The parsed instruction: what every instruction parser returns (the rule grammar here, an MLLM
with JSON-schema output in the model tier).

Subjects carry the categorical cues of :mod:`capframe.constraints` (region, shot size, view side)
and the instruction carries the camera's elevation and roll. The numeric targets Refine needs
(layout boxes, view offsets) follow from these and are written beside them by :meth:`to_dict`, so a
reader of ``result.json`` sees both what was understood and what it became.
"""

from __future__ import annotations

import dataclasses
from dataclasses import asdict, dataclass, field

from ..constraints import ELEVATIONS, REGIONS, SHOT_SIZES, VIEW_SIDES, Constraints, SubjectConstraint
from ..errors import InputError, clip
from .labels import layout_boxes
from .vocabulary import FILLER_WORDS, PUNCTUATION, words


@dataclass
class ParsedSubject:
    """One subject of an instruction.

    Attributes:
        mention: the words that named it ("the red chair").
        name: the scene-vocabulary name it was matched to ("armchair").
        role: "primary" (the first mentioned) or "secondary".
        symmetric: whether it has no canonical front (view sides do not apply to it).
        region: key of :data:`~capframe.constraints.REGIONS`, or None.
        shot: key of :data:`~capframe.constraints.SHOT_SIZES`, or None.
        view: key of :data:`~capframe.constraints.VIEW_SIDES`, or None.
        box: an explicit layout box ``(x0, y0, x1, y1)`` in ``[0, 1]`` (origin top-left) where
            its mask should sit, or None. A model parser's layout (the paper's layout pseudo
            label); it replaces the box of ``region`` and ``shot`` in the pseudo labels, while the
            checker keeps reading the named cues, which the parser sets to the closest ones.
    """

    mention: str
    name: str
    role: str = "primary"
    symmetric: bool = False
    region: str | None = None
    shot: str | None = None
    view: str | None = None
    box: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        # Validation is shared with the constraint vocabulary, so an MLLM's invalid key is named.
        SubjectConstraint(self.name, self.role, self.region, self.shot, self.view)
        if self.box is not None:
            self.box = check_box(self.box, f"subject {self.name!r} box")

    @property
    def needs_front(self) -> bool:
        """Whether orientation is estimated for it: asymmetric, with a view cue."""
        return self.view is not None and not self.symmetric


def check_box(box, what: str) -> tuple[float, float, float, float]:
    """``box`` as four floats ``x0 < x1``, ``y0 < y1`` inside ``[0, 1]``; :class:`InputError`
    naming ``what`` otherwise."""
    try:
        values = tuple(float(v) for v in box)
    except (TypeError, ValueError):
        values = ()
    if len(values) != 4 or not all(0.0 <= v <= 1.0 for v in values) or not (values[0] < values[2] and values[1] < values[3]):
        raise InputError(f"{what} is {clip(repr(box))}; expected [x0, y0, x1, y1] in [0, 1] with x0 < x1 and y0 < y1")
    return values


@dataclass
class ParsedInstruction:
    """An instruction turned into structure.

    Attributes:
        text: the instruction as given.
        subjects: the subjects, primary first.
        elevation: key of :data:`~capframe.constraints.ELEVATIONS`, or None.
        elevation_deg: an explicit elevation in degrees (> 0 above), or None.
        roll_deg: requested roll in degrees (> 0 clockwise as the photographer sees it, 0 level), or None.
        unparsed: fragments of the text the parser did not understand, in order.
        corrected: names read through a misspelling, ``{"said": "teddy baer", "read": "teddy bear"}``
            each (normalised words), in order.
        parser: which parser produced it, when a model did (its identity and prompt versions);
            not part of what was understood, so two parsers' readings compare equal without it.
    """

    text: str
    subjects: list[ParsedSubject] = field(default_factory=list)
    elevation: str | None = None
    elevation_deg: float | None = None
    roll_deg: float | None = None
    unparsed: list[str] = field(default_factory=list)
    corrected: list[dict[str, str]] = field(default_factory=list)
    parser: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        self.constraints()  # validates the named cues and the elevation pair

    def not_understood(self) -> list[str]:
        """The ``unparsed`` fragments that may ask something of the camera: those holding a word
        that is not filler (:data:`~capframe.translate.vocabulary.FILLER_WORDS`, e.g. "please",
        "nice", "photo of"). Non-empty means the instruction is only partly understood: every
        clause parsed may hold while a wish in these words is ignored."""
        return [run for run in self.unparsed if any(w not in FILLER_WORDS for w in words(run) if w not in PUNCTUATION)]

    @property
    def understood(self) -> str:
        """``"fully"`` or ``"partly"`` (:meth:`not_understood` is not empty)."""
        return "partly" if self.not_understood() else "fully"

    def constraints(self) -> Constraints:
        """The machine-checkable constraints. A view side asked of a symmetric subject is dropped:
        it has no front to be seen from."""
        subjects = [SubjectConstraint(s.name, s.role, s.region, s.shot, None if s.symmetric else s.view) for s in self.subjects]
        return Constraints(subjects, self.elevation, self.elevation_deg, self.roll_deg)

    def without(self, cues: str | None) -> ParsedInstruction:
        """The instruction without its ``layout`` (regions, shot sizes) or ``orientation`` (view
        sides, elevation, roll) cues, the sensitivity study's label removal; itself for None."""
        if cues is None:
            return self
        if cues == "layout":
            subjects = [dataclasses.replace(s, region=None, shot=None, box=None) for s in self.subjects]
            return dataclasses.replace(self, subjects=subjects)
        if cues == "orientation":
            subjects = [dataclasses.replace(s, view=None) for s in self.subjects]
            return dataclasses.replace(self, subjects=subjects, elevation=None, elevation_deg=None, roll_deg=None)
        raise InputError(f"cannot drop {cues!r} cues; expected 'layout' or 'orientation'")

    def to_dict(self) -> dict:
        """JSON-ready form: the fields of :data:`JSON_SCHEMA` plus, per subject, the derived layout
        targets (``layout``) and view offsets (``view_offsets_deg``), and whether it was
        ``understood`` fully or partly (with the ``not_understood`` fragments)."""
        data = asdict(self)
        if not self.parser:
            del data["parser"]
        for subject, out in zip(self.subjects, data["subjects"]):
            out["box"] = _listed(subject.box)
            region, box, extent = layout_boxes(subject.region, subject.shot, subject.box)
            out["layout"] = {"region": _listed(region), "box": _listed(box), "extent": _listed(extent)}
            out["view_offsets_deg"] = {
                "azimuth": list(VIEW_SIDES[subject.view]) if subject.view and not subject.symmetric else None
            }
        data["elevation_range_deg"] = _listed(self.constraints().elevation_range())
        data["understood"] = self.understood
        data["not_understood"] = self.not_understood()
        return data

    @classmethod
    def from_dict(cls, data: dict, source: str | None = None) -> ParsedInstruction:
        """Inverse of :meth:`to_dict` (derived fields are ignored); :class:`InputError` for bad input."""
        try:
            subjects = [ParsedSubject(**{k: s[k] for k in _SUBJECT_KEYS if k in s}) for s in data["subjects"]]
            return cls(
                str(data["text"]),
                subjects,
                data.get("elevation"),
                data.get("elevation_deg"),
                data.get("roll_deg"),
                list(data.get("unparsed", [])),
                [{"said": str(c["said"]), "read": str(c["read"])} for c in data.get("corrected", [])],
                dict(data.get("parser") or {}),
            )
        except (KeyError, TypeError) as err:
            raise InputError(
                f"malformed parsed instruction ({err!r}); expected the fields of JSON_SCHEMA", source=source
            ) from None


_SUBJECT_KEYS = ("mention", "name", "role", "symmetric", "region", "shot", "view", "box")


def _listed(value) -> list | None:
    return None if value is None else [float(v) for v in value]


def _nullable_enum(keys) -> dict:
    return {"enum": [*sorted(keys), None]}


# What a parser backend must produce (the MLLM backend passes it as the response's JSON schema).
JSON_SCHEMA: dict = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "ParsedInstruction",
    "type": "object",
    "required": ["text", "subjects"],
    "properties": {
        "text": {"type": "string"},
        "subjects": {
            "type": "array",
            "minItems": 1,
            "items": {
                "type": "object",
                "required": ["mention", "name", "role"],
                "properties": {
                    "mention": {"type": "string", "description": "the words naming the subject"},
                    "name": {"type": "string", "description": "a name from the scene vocabulary"},
                    "role": {"enum": ["primary", "secondary"]},
                    "symmetric": {"type": "boolean", "description": "no canonical front"},
                    "region": _nullable_enum(REGIONS),
                    "shot": _nullable_enum(SHOT_SIZES),
                    "view": _nullable_enum(VIEW_SIDES),
                    "box": {
                        "type": ["array", "null"],
                        "description": "explicit layout box [x0, y0, x1, y1], normalised, origin top-left",
                        "items": {"type": "number", "minimum": 0, "maximum": 1},
                        "minItems": 4,
                        "maxItems": 4,
                    },
                },
                "additionalProperties": True,
            },
        },
        "elevation": _nullable_enum(ELEVATIONS),
        "elevation_deg": {"type": ["number", "null"], "minimum": -90, "maximum": 90},
        "roll_deg": {"type": ["number", "null"], "minimum": -90, "maximum": 90},
        "unparsed": {"type": "array", "items": {"type": "string"}},
        "parser": {"type": "object", "description": "the model parser's identity and prompt versions"},
        "corrected": {
            "type": "array",
            "description": "names read through a misspelling",
            "items": {
                "type": "object",
                "required": ["said", "read"],
                "properties": {"said": {"type": "string"}, "read": {"type": "string"}},
                "additionalProperties": False,
            },
        },
    },
    "additionalProperties": True,
}
