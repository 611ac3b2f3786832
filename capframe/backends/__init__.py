"""Perception backends behind small protocols (DESIGN §4): the roles and the data they exchange
(:mod:`~capframe.backends.protocols`), one registry naming every role's backends
(:mod:`~capframe.backends.registry`), the models config (:mod:`~capframe.backends.models`) and the
oracle tier (:mod:`~capframe.backends.oracle`, imported only when an oracle backend is built)."""

from .models import ModelsConfig, ModelSettings, read_models_config
from .protocols import (
    Associator,
    CameraScorer,
    CoarseScorer,
    DifferentiableScorer,
    Grounding,
    ImageTextScorer,
    InstructionParser,
    Judge,
    OrientationEstimator,
    Question,
    QuestionEvaluator,
    Segmenter,
    SubjectMasks,
)
from .registry import MASK_ASSOCIATORS, ROLES, BackendContext, Backends, backend_names, check_choice, resolve_choices

__all__ = [
    "Associator",
    "BackendContext",
    "Backends",
    "CameraScorer",
    "CoarseScorer",
    "DifferentiableScorer",
    "Grounding",
    "ImageTextScorer",
    "InstructionParser",
    "Judge",
    "MASK_ASSOCIATORS",
    "ModelSettings",
    "ModelsConfig",
    "OrientationEstimator",
    "Question",
    "QuestionEvaluator",
    "ROLES",
    "Segmenter",
    "SubjectMasks",
    "backend_names",
    "check_choice",
    "read_models_config",
    "resolve_choices",
]
