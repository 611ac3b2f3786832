"""Perception backends behind small protocols (DESIGN §4).

Each learned component of the method is one protocol; the pipeline (``capframe ground``) only
talks to these. The embedded tier (offline, CPU) implements them with a rule grammar and the
scene's semantic labels (:mod:`capframe.backends.labels`); the model tier (MLLM, FG-CLIP,
GroundingDINO + SAM, Orient Anything) implements the same protocols with user-supplied weights.

Views are referred to by their index in the scene's training cameras.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ..errors import InputError
from ..retrieve.qe import Question
from ..translate.grounding import Grounding, SubjectMasks
from ..translate.instruction import ParsedInstruction, ParsedSubject
from ..translate.vocabulary import Vocabulary


class InstructionParser(Protocol):
    """Text -> :class:`ParsedInstruction` (subjects matched to the scene's vocabulary)."""

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction: ...


class CoarseScorer(Protocol):
    """Cheap relevance of every training view to an instruction (a text-image similarity in the
    model tier)."""

    def coarse(self, parsed: ParsedInstruction) -> np.ndarray:
        """(V,) scores, higher is more relevant."""
        ...


class QuestionEvaluator(Protocol):
    """Question-Evaluation: the instruction's questions, answered 0-100 per view."""

    def questions(self, parsed: ParsedInstruction) -> list[Question]: ...

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        """(len(view_indices), len(questions)) answers in [0, 100]."""
        ...


class SubjectGrounder(Protocol):
    """A subject -> its Gaussians and centroid, in two steps: 2D masks in the retrieved views
    (segmentation), lifted to the Gaussians (association)."""

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks | None:
        """The subject's masks in those views, or None for a grounder that associates without
        masks (the embedded tier's label ids)."""
        ...

    def associate(self, subject: ParsedSubject, masks: SubjectMasks | None) -> Grounding: ...


class OrientationEstimator(Protocol):
    """A subject's front direction in world coordinates, or None when it has none."""

    def front(self, subject: ParsedSubject, view_indices: list[int]) -> np.ndarray | None: ...


PARSERS = ("rules",)
PERCEPTIONS = ("labels", "label-masks")


def make_parser(name: str) -> InstructionParser:
    """The instruction parser called ``name`` (see :data:`PARSERS`)."""
    if name == "rules":
        from ..translate.parse import RuleParser

        return RuleParser()
    raise InputError(f"--parser {name!r} is unknown; available: {list(PARSERS)}")


def check_perception(name: str) -> None:
    if name not in PERCEPTIONS:
        raise InputError(f"--perception {name!r} is unknown; available: {list(PERCEPTIONS)}")
