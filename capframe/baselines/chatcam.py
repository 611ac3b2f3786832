"""ChatCam-style anchor optimiser (after Liu et al., 2024, "ChatCam: Empowering Camera Control
through Conversational AI"), reduced to the one pose the paper compares.

ChatCam's released anchor selector picks the training image whose CLIP embedding is closest to
the text's; its paper then refines the anchor pose with CLIP gradients through the renderer (the
loss, steps and render size of that refinement are not published). Here:

* the start is the training view whose photograph scores highest against the instruction with
  the differentiable scorer's own model (its non-differentiable score of the training pictures,
  :meth:`~capframe.backends.scorers.ModelDiffScorer.view_scores`), as ChatCam's selector;
* the loss is ``1 - score`` of the full-scene render (a cosine for CLIP / FG-CLIP, a sigmoid
  probability for SigLIP 2 / FG-CLIP 2: never negative, so Refine's relative stopping tests keep
  their meaning) plus Refine's upright term at zero roll with Refine's weight (an image-text score
  is nearly blind to roll, so without it the camera drifts off level);
* the pose is optimised as Refine optimises it (Adam on a left-multiplied se(3) increment about
  the subjects' centroid, Refine's learning rates, step budget and resolution), for the whole
  budget: an image-text score has no clause to settle on.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import torch
from torch import Tensor

from ..refine.losses import upright_loss
from ..refine.optimize import LossWeights, PoseDescent, RefineConfig, RefineResult
from ..render import prepare, render
from ..scene import Camera, GaussianScene

# image (H, W, 3) in [0, 1] -> differentiable scalar score
ImageScore = Callable[[Tensor], Tensor]


@dataclass
class ChatCamConfig:
    """Settings of :func:`chatcam_pose`: Refine's descent (its ``iterations``, ``long_side`` and
    learning rates; its plateau, yaw scan and clause settings are not used) and the weight of the
    upright term (Refine's by default)."""

    descent: RefineConfig = field(default_factory=RefineConfig)
    upright: float = LossWeights.upright


class _Objective:
    """``1 - score(render) + upright`` as a function of the pose (the interface of Refine's descent)."""

    def __init__(self, scene: GaussianScene, camera: Camera, score: ImageScore, pivot: Tensor, up: Tensor, upright: float, dtype):
        self.camera, self.score, self.upright, self.dtype = camera, score, upright, dtype
        self.scene = prepare(scene, dtype)  # pose-independent work once
        self.centroids = [pivot.double()]  # the descent's pivot
        self.up = up.double()

    def __call__(self, T_cw: Tensor) -> tuple[Tensor, dict[str, Tensor]]:
        rgb = render(self.scene, self.camera, T_cw=T_cw, dtype=self.dtype, backend="cpu").rgb
        terms = {"score": 1.0 - self.score(rgb.clamp(0.0, 1.0)).double(), "upright": upright_loss(T_cw, self.up)}
        total = terms["score"] + self.upright * terms["upright"]
        return total, {k: v.detach() for k, v in terms.items()}

    def clauses_hold(self, terms: dict[str, Tensor]) -> bool:
        return False  # no clauses: the baseline spends its budget


def chatcam_pose(
    scene: GaussianScene,
    camera: Camera,
    score: ImageScore,
    pivot: np.ndarray,
    up: np.ndarray,
    scale: float,
    config: ChatCamConfig | None = None,
    dtype: torch.dtype = torch.float32,
) -> RefineResult:
    """Optimise ``camera``'s pose for the image-text ``score`` of its render.

    Args:
        scene: the Gaussians.
        camera: the start (its image size and intrinsics are kept; rendered at the descent's
            ``long_side`` while optimising).
        score: differentiable score of an (H, W, 3) render in [0, 1], e.g.
            ``lambda image: diff_scorer.score(image, text)``.
        pivot: (3,) point the rotations orbit (the subjects' centroid).
        up: (3,) world up of the upright term.
        scale: the scene scale (translation steps are relative to it).

    Returns:
        The best pose found and the trace, terms ``score`` (``1 - score``) and ``upright``.
    """
    start = time.perf_counter()
    config = config or ChatCamConfig()
    # Refine's descent with the whole budget: no plateau stop, no yaw scan.
    descent = RefineConfig(**{**vars(config.descent), "patience": config.descent.iterations + 1, "yaw_scan": 1})
    objective = _Objective(
        scene,
        camera.with_long_side(descent.long_side),
        score,
        torch.as_tensor(pivot, dtype=torch.float64),
        torch.as_tensor(up, dtype=torch.float64),
        config.upright,
        dtype,
    )
    run = PoseDescent(objective, scale, descent)
    T = run.descend(torch.as_tensor(camera.T_cw, dtype=torch.float64), descent.iterations, scan=False)
    return run.result(T, start)
