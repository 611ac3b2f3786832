"""The perception roles of the method (DESIGN §4) and the data they exchange.

Each learned component is one protocol. The pipeline (:mod:`capframe.pipeline`) only talks to
these; :mod:`capframe.backends.registry` names the implementations of each role. Views are
referred to by their index in the scene's training cameras.

==========  ===========================  ============================================
role        protocol                     embedded backends (offline, CPU)
==========  ===========================  ============================================
parser      :class:`InstructionParser`   ``rules`` (a photographic grammar); model
                                         tier: ``mllm`` (subject, layout and
                                         orientation parsers)
coarse      :class:`CoarseScorer`        ``oracle`` (subject visibility from labels);
                                         model tier: ``clip``, ``siglip``, ``fg-clip``,
                                         ``fg-clip2`` (image-text similarity)
qe          :class:`QuestionEvaluator`   ``oracle`` (answers from label renders);
                                         model tier: ``mllm`` (the model's questions,
                                         answers and adaptive cut)
segmenter   :class:`Segmenter`           ``oracle`` (label maps as 2D masks)
associator  :class:`Associator`          ``oracle`` (label ids), ``knn`` (masks
                                         back-projected, nearest Gaussian means)
orient      :class:`OrientationEstimator` ``oracle`` (annotated fronts); model tier:
                                         ``orient-anything`` (from the segmenter's masks)
scorer      :class:`ImageTextScorer`     ``oracle`` (QE answers of a label render); model
                                         tier: the image-text models of ``coarse``
diff-scorer :class:`DifferentiableScorer` model tier only: the image-text models
judge       :class:`Judge`               model tier only: ``mllm``, ``mllm-2`` (two
                                         judges, models config entries ``judge`` and
                                         ``judge-2``)
==========  ===========================  ============================================

Model-tier segmenters (user-supplied weights named in the models config): ``grounded-sam``
(GroundingDINO + SAM) and ``detector`` (a COCO detector on ONNX Runtime, masks by SAM or GrabCut).

"oracle" backends read the scene's semantic labels: perception with perfect labels, whose results
measure the rest of the method and are reported as such.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from .models import ModelsConfig

if TYPE_CHECKING:
    import torch

    from ..scene import Camera
    from ..translate.instruction import ParsedInstruction, ParsedSubject
    from ..translate.labels import PseudoLabels
    from ..translate.vocabulary import Vocabulary


@dataclass
class Question:
    """One Question-Evaluation question.

    Attributes:
        kind: visible | region | shot | view | elevation | roll | overall.
        text: the question as a person (or an MLLM) would read it.
        subject: the subject's scene name, or None for camera-wide questions.
        target: what is asked (a region name, a shot size, a view side, an angle interval...).
    """

    kind: str
    text: str
    subject: str | None = None
    target: dict = field(default_factory=dict)


@dataclass
class SubjectMasks:
    """A subject's 2D masks (a segmenter's output) in some views.

    Attributes:
        views: indices of the views (training cameras).
        masks: (len(views), H, W) boolean masks at the perception's measurement resolution.
    """

    views: list[int]
    masks: np.ndarray


@dataclass
class Grounding:
    """A subject found in the scene.

    Attributes:
        name: the subject's scene name.
        gaussians: (M,) indices of its Gaussians.
        centroid: (3,) mean of their means.
        front: (3,) unit front direction, or None (symmetric or unknown).
    """

    name: str
    gaussians: np.ndarray
    centroid: np.ndarray
    front: np.ndarray | None


@dataclass
class BackendContext:
    """What a backend may be built from.

    Attributes:
        scene: the loaded scene directory (:class:`~capframe.scene.SceneDir`).
        up: (3,) unit world up.
        cache_dir: the scene's cache folder (per-scene work such as view measurements).
        models: weights, endpoints and devices of the model backends.
    """

    scene: Any
    up: np.ndarray
    cache_dir: Path
    models: ModelsConfig = field(default_factory=ModelsConfig)
    _shared: dict = field(default_factory=dict, repr=False)

    def shared(self, key: str, make: Callable[[], Any]) -> Any:
        """``make()``, computed once per context: state several backends read (label renders)."""
        if key not in self._shared:
            self._shared[key] = make()
        return self._shared[key]

    def shared_with(self, prefix: str) -> list[Any]:
        """The shared values whose keys start with ``prefix``, in the order they were made
        (e.g. every chat model of the job, for its call counts)."""
        return [value for key, value in self._shared.items() if key.startswith(prefix)]


# Scores candidate cameras for one instruction: N cameras in, (N,) scores out (higher is better).
CameraScorer = Callable[[list["Camera"]], np.ndarray]


class InstructionParser(Protocol):
    """Text -> :class:`ParsedInstruction` (subjects matched to the scene's vocabulary)."""

    def parse(self, text: str, vocabulary: Vocabulary) -> ParsedInstruction: ...


class CoarseScorer(Protocol):
    """Cheap relevance of every training view to an instruction (a text-image similarity in the
    model tier)."""

    def coarse(self, parsed: ParsedInstruction) -> np.ndarray:
        """(V,) scores, higher is more relevant."""
        ...

    def keep(self, scores: np.ndarray) -> list[int]:
        """The views Question-Evaluation reads, best first: how many depends on how much the
        score can be trusted."""
        ...


class QuestionEvaluator(Protocol):
    """Question-Evaluation: the instruction's questions, answered 0-100 per view."""

    def questions(self, parsed: ParsedInstruction) -> list[Question]: ...

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        """(len(view_indices), len(questions)) answers in [0, 100]."""
        ...

    # Optional (:func:`capframe.retrieve.qe.rank_kept` uses them when present):
    # ``cut(scores, top_k) -> list[int]``, the retrieved views' positions among the kept ones
    # (a model's own adaptive cut), and ``record() -> dict``, what ``retrieval.json`` records of
    # the evaluator (model, prompt versions, reasons).


class Segmenter(Protocol):
    """A subject's 2D masks in the retrieved views."""

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks: ...


class Associator(Protocol):
    """A subject -> its Gaussians and centroid, from its masks when :attr:`needs_masks`."""

    needs_masks: bool

    def associate(self, subject: ParsedSubject, masks: SubjectMasks | None) -> Grounding: ...


class OrientationEstimator(Protocol):
    """A subject's front direction in world coordinates, or None when it has none; from the
    segmenter's masks of the subject in the retrieved views when :attr:`needs_masks`."""

    needs_masks: bool

    def front(self, subject: ParsedSubject, view_indices: list[int], masks: SubjectMasks | None) -> np.ndarray | None: ...


class ImageTextScorer(Protocol):
    """How well candidate cameras' renders match an instruction (the baselines' candidate ranking,
    FG-CLIP in the paper)."""

    def scorer(self, parsed: ParsedInstruction, questions: list[Question], labels: PseudoLabels) -> CameraScorer: ...


class DifferentiableScorer(Protocol):
    """An image-text score of a rendered image with gradients to the image (ChatCam-style)."""

    def score(self, image: torch.Tensor, text: str) -> torch.Tensor:
        """image (H, W, 3) in [0, 1] -> scalar score, differentiable."""
        ...

    def view_scores(self, text: str) -> np.ndarray:
        """(V,) scores of the scene's training pictures by the same model (no gradients)."""
        ...


class Judge(Protocol):
    """An MLLM judge: a 1-5 alignment score of an image with an instruction."""

    def rate(self, image: np.ndarray, text: str) -> float: ...
