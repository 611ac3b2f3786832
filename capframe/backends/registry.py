"""One name for every role and backend: the CLI's options, the workflow config's schema and the
workflow's stage selection all read :data:`ROLES` (a test checks the schema agrees).

A backend is built once per job from a :class:`BackendContext` (the scene, its world up, the
per-scene cache and the models config) and reused for every call in that job
(:class:`Backends`). Every role is chosen on its own; any mix of backends is valid.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import InputError
from .protocols import BackendContext

Factory = Callable[[BackendContext], Any]


def _rules(context: BackendContext):
    from ..translate.parse import shared_parser

    return shared_parser()


def _oracle(kind: str) -> Factory:
    def build(context: BackendContext):
        from . import oracle

        return getattr(oracle, kind)(context)

    build.__name__ = f"oracle_{kind}"
    return build


def _grounded_sam(context: BackendContext):
    from .grounded_sam import GroundedSamSegmenter

    return GroundedSamSegmenter(context)


def _detector(context: BackendContext):
    from .detector import DetectorSegmenter

    return DetectorSegmenter(context)


# Image-text models (capframe.backends.image_text): each serves the coarse, scorer and diff-scorer roles.
IMAGE_TEXT = ("clip", "siglip", "fg-clip", "fg-clip2")


def _image_text(kind: str) -> dict[str, Factory]:
    """The image-text model backends of one role (``scorers.kind(context, name)``), imported only
    when built: the model libraries stay off the embedded tier's path."""

    def factory(name: str) -> Factory:
        def build(context: BackendContext):
            from . import scorers

            return getattr(scorers, kind)(context, name)

        build.__name__ = f"{kind}_{name}"
        return build

    return {name: factory(name) for name in IMAGE_TEXT}


def _orient_anything(context: BackendContext):
    from .orient_anything import OrientAnythingOrientation

    return OrientAnythingOrientation(context)


def _chat(context: BackendContext, entry: str):
    """The chat model of the models config's ``entry`` (built once per job and shared by the
    roles that read it: the parser and QE both read ``mllm``)."""
    from .mllm.factory import chat_model

    return chat_model(context, entry)


def _mllm_parser(context: BackendContext):
    from .mllm.parser import MLLMParser

    return MLLMParser(_chat(context, "mllm"))


def _mllm_qe(context: BackendContext):
    from .mllm.qe import MLLMQE

    return MLLMQE(_chat(context, "mllm"), context)


def _mllm_judge(entry: str) -> Factory:
    """A judge reading the models config's ``entry``: two entries, two independent judges."""

    def build(context: BackendContext):
        from .mllm.judge import MLLMJudge

        return MLLMJudge(_chat(context, entry))

    build.__name__ = f"mllm_judge_{entry}"
    return build


@dataclass(frozen=True)
class Role:
    """A perception role: its option, what it does, its backends (name -> factory) and default."""

    option: str
    help: str
    backends: dict[str, Factory]
    default: str | None


ROLES: dict[str, Role] = {
    "parser": Role("--parser", "instruction parser", {"rules": _rules, "mllm": _mllm_parser}, "rules"),
    "coarse": Role("--coarse-scorer", "coarse scorer of the training views", {"oracle": _oracle("OracleCoarse")}, "oracle"),
    "qe": Role("--qe", "Question-Evaluation of the kept views", {"oracle": _oracle("OracleQE"), "mllm": _mllm_qe}, "oracle"),
    "segmenter": Role(
        "--segmenter",
        "subject segmenter (2D masks)",
        {"oracle": _oracle("OracleSegmenter"), "grounded-sam": _grounded_sam, "detector": _detector},
        "oracle",
    ),
    "associator": Role(
        "--associator",
        "subject -> Gaussians (knn: from the segmenter's masks)",
        {"oracle": _oracle("OracleAssociator"), "knn": _oracle("MaskAssociator")},
        "oracle",
    ),
    "orient": Role("--orient", "subject orientation estimator", {"oracle": _oracle("OracleOrientation")}, "oracle"),
    "scorer": Role(
        "--scorer", "image-text scorer of candidate cameras (baselines)", {"oracle": _oracle("OracleScorer")}, "oracle"
    ),
    "diff-scorer": Role("--diff-scorer", "differentiable image-text scorer (ChatCam-style)", {}, None),
    # Two judges (the paper's two): models config entries "judge" and "judge-2".
    "judge": Role("--judge", "MLLM judge (benchmark)", {"mllm": _mllm_judge("judge"), "mllm-2": _mllm_judge("judge-2")}, None),
}

# Model-tier backends, appended to their roles.
ROLES["coarse"].backends.update(_image_text("ModelCoarse"))
ROLES["scorer"].backends.update(_image_text("ModelScorer"))
ROLES["diff-scorer"].backends.update(_image_text("ModelDiffScorer"))
ROLES["orient"].backends["orient-anything"] = _orient_anything

# Associators that read the segmenter's masks (the workflow runs segmentation only for these).
MASK_ASSOCIATORS = ("knn",)
# Orientation estimators that read the segmenter's masks (the workflow passes them the masks).
MASK_ORIENTERS = ("orient-anything",)


def backend_names(role: str) -> list[str]:
    """The backends of ``role``, in registry order."""
    return list(ROLES[role].backends)


def check_choice(role: str, name: str) -> None:
    """:class:`InputError` naming the available backends when ``name`` is not one of ``role``."""
    if role not in ROLES:
        raise InputError(f"role {role!r} is unknown; roles: {', '.join(ROLES)}")
    if name not in ROLES[role].backends:
        available = ", ".join(backend_names(role)) or "none yet (the model tier adds them)"
        raise InputError(f"{ROLES[role].option} {name!r} is unknown; available: {available}")


def resolve_choices(choices: dict[str, str | None] | None = None) -> dict[str, str]:
    """Every role with a backend: the defaults updated by ``choices`` (None keeps the default),
    each checked. Roles without any backend are left out unless chosen."""
    chosen = {role: r.default for role, r in ROLES.items() if r.default is not None}
    chosen |= {role: name for role, name in (choices or {}).items() if name is not None}
    for role, name in chosen.items():
        check_choice(role, name)
    return chosen


class Backends:
    """The backends of one job: each built on first use from ``context``, then reused.

    Args:
        choices: role -> backend name (see :func:`resolve_choices`).
        context: what the backends are built from.
    """

    def __init__(self, choices: dict[str, str], context: BackendContext):
        self.choices = resolve_choices(choices)
        self.context = context
        self._built: dict[str, Any] = {}

    def __getitem__(self, role: str) -> Any:
        if role not in self._built:
            if role not in self.choices:
                raise InputError(f"no backend chosen for the {ROLES[role].help} ({ROLES[role].option})")
            self._built[role] = ROLES[role].backends[self.choices[role]](self.context)
        return self._built[role]
