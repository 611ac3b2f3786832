"""The questionnaire's key (``key.json``): which method each image of each group shows.

Format 1::

    {"format": 1, "questionnaire": "<16 hex digits>", "nonce": "<32 hex digits>", "seed": 0,
     "methods": ["capframe", "oracle", ...],
     "groups": [{"group": 1, "scene": "...", "instruction": "<id>", "text": "...",
                 "methods": {"A": "oracle", "B": "capframe", "C": "ivs"},
                 "images": {"A": "img/<hash>.png", ...},
                 "sources": {"A": "results/refine/oracle/<scene>/<id>/render.png", ...}}, ...]}

``questionnaire`` is the hash of everything else (:func:`questionnaire_id`); the page and every
answer row carry it. ``nonce`` is random per questionnaire: it makes the id and the image names
(hashes of the nonce, the group and the label) impossible to work back to a method.
"""

from __future__ import annotations

import hashlib
import json
import string
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..scene._io import read_json, require_keys, write_json

# The answer file's columns, in order: one row per participant, group and image; ``best`` is 1 on
# the image picked as the best of its group, else 0. The page's script writes the same header.
ANSWER_COLUMNS = ("questionnaire", "participant", "group", "image", "rating", "best")
RATINGS = (1, 2, 3, 4, 5)
LABELS = string.ascii_uppercase


@dataclass(frozen=True)
class Group:
    """One instruction of the questionnaire and the renders it shows.

    Attributes:
        number: position in the page, from 1.
        scene: the scene (``results/instructions/<scene>/``).
        instruction: the instruction's id in that scene's ``constraints.json``.
        text: the instruction as the participant reads it.
        methods: label (``A``, ``B``, ...) -> method, in the page's order.
        images: label -> the image's path inside the site folder.
        sources: label -> the render it was copied from.
    """

    number: int
    scene: str
    instruction: str
    text: str
    methods: dict[str, str]
    images: dict[str, str]
    sources: dict[str, str]

    def to_dict(self) -> dict:
        return {
            "group": self.number,
            "scene": self.scene,
            "instruction": self.instruction,
            "text": self.text,
            "methods": dict(self.methods),
            "images": dict(self.images),
            "sources": dict(self.sources),
        }


@dataclass(frozen=True)
class Key:
    """Everything that ties the page to the methods (never shipped with the page)."""

    questionnaire: str
    nonce: str
    seed: int
    methods: tuple[str, ...]
    groups: tuple[Group, ...]

    def content(self) -> dict:
        """The key as JSON, less its id: what :func:`questionnaire_id` hashes."""
        return {
            "format": 1,
            "nonce": self.nonce,
            "seed": self.seed,
            "methods": list(self.methods),
            "groups": [g.to_dict() for g in self.groups],
        }

    def write(self, path: str | Path) -> None:
        content = self.content()
        write_json(path, {"format": 1, "questionnaire": self.questionnaire, **content})

    def group(self, number: int) -> Group | None:
        return next((g for g in self.groups if g.number == number), None)


def questionnaire_id(content: dict) -> str:
    """16 hex digits of the SHA-256 of ``content`` (a key's JSON without its id) in canonical
    form (sorted keys, no spaces): equal for equal keys, whatever the file's layout."""
    canonical = json.dumps(content, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()[:16]


def read_key(path: str | Path) -> Key:
    """The key at ``path``, checked: format 1, groups with unique numbers and labels, methods of
    the key's list, and an id that still matches the content (else the key was edited after the
    questionnaire was made, and answers would be counted against the wrong methods)."""
    source = str(path)
    data = read_json(path)
    require_keys(data, ("format", "questionnaire", "nonce", "seed", "methods", "groups"), "the key", source)
    if data["format"] != 1:
        raise InputError(f"format is {data['format']!r}; expected 1 (a key.json of capframe userstudy make)", source=source)
    methods = _strings(data["methods"], "methods", source)
    if not isinstance(data["groups"], list) or not data["groups"]:
        raise InputError(f"groups is {data['groups']!r}; expected a non-empty list", source=source)
    groups = tuple(_group(entry, f"groups[{i}]", set(methods), source) for i, entry in enumerate(data["groups"]))
    numbers = [g.number for g in groups]
    if len(set(numbers)) != len(numbers):
        raise InputError(f"group numbers {numbers} repeat; expected each group once", source=source)
    key = Key(str(data["questionnaire"]), str(data["nonce"]), _integer(data["seed"], "seed", source), tuple(methods), groups)
    actual = questionnaire_id(key.content())
    if actual != key.questionnaire:
        raise InputError(
            f"questionnaire is {key.questionnaire!r} but the key's content hashes to {actual!r}: the key was edited after "
            "the questionnaire was made; use the key.json written with it",
            source=source,
        )
    return key


def _group(entry: Any, where: str, methods: set[str], source: str) -> Group:
    require_keys(entry, ("group", "scene", "instruction", "text", "methods", "images", "sources"), where, source)
    shown = _mapping(entry["methods"], f"{where}.methods", source)
    labels = list(shown)
    if labels != list(LABELS[: len(labels)]) or len(labels) < 2:
        raise InputError(f"{where}.methods has labels {labels}; expected A, B, ... in order (two at least)", source=source)
    unknown = sorted(set(shown.values()) - methods)
    if unknown:
        raise InputError(f"{where}.methods shows {unknown}, not in the key's methods {sorted(methods)}", source=source)
    images = _mapping(entry["images"], f"{where}.images", source)
    sources = _mapping(entry["sources"], f"{where}.sources", source)
    for name, mapping in (("images", images), ("sources", sources)):
        if list(mapping) != labels:
            raise InputError(f"{where}.{name} has labels {list(mapping)}; expected {labels}", source=source)
    return Group(
        number=_integer(entry["group"], f"{where}.group", source),
        scene=str(entry["scene"]),
        instruction=str(entry["instruction"]),
        text=str(entry["text"]),
        methods=shown,
        images=images,
        sources=sources,
    )


def _integer(value: Any, what: str, source: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{what} is {value!r}; expected a whole number", source=source)
    return value


def _strings(value: Any, what: str, source: str) -> list[str]:
    if not isinstance(value, list) or not value or not all(isinstance(v, str) and v for v in value):
        raise InputError(f"{what} is {value!r}; expected a non-empty list of names", source=source)
    return value


def _mapping(value: Any, what: str, source: str) -> dict[str, str]:
    if not isinstance(value, dict) or not all(isinstance(v, str) for v in value.values()):
        raise InputError(f"{what} is {value!r}; expected label -> name", source=source)
    return value
