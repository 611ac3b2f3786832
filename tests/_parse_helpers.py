"""The scenes the parser's family tests (tests/test_parse16.py ... test_parse18*.py, test_parse_skip.py)
read their own wordings against: a vocabulary of catalog names, none symmetric, and its parse."""

from __future__ import annotations

from collections.abc import Callable

from capframe.scene.directory import SemanticObject
from capframe.translate.instruction import ParsedInstruction
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary


def scene_of(names: list[str]) -> Vocabulary:
    """The vocabulary of a scene holding ``names`` (one object each, none symmetric)."""
    return Vocabulary.from_semantics([SemanticObject(k, n, [], False) for k, n in enumerate(names)])


def parser_of(scene: Vocabulary) -> Callable[[str], ParsedInstruction]:
    """``parse(text)`` against ``scene``."""
    return lambda text: parse_instruction(text, scene)
