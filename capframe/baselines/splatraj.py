"""SplaTraj-style single-pose optimiser (after Liu et al., 2024, "SplaTraj: Camera Trajectory
Generation with Semantic Gaussian Splatting"), reduced to the one pose the paper compares.

SplaTraj renders the queried object's mask and moves the camera for three image costs: the mask
centred in the image, the mask covering a desired share of the image, and an upright camera.
Nothing of the instruction's composition or viewpoint enters (no region, shot size, view side,
elevation or requested roll): that is what makes it a baseline. Here:

* the target is the union of the instruction's subjects (their Gaussians from Translate);
* ``center``: distance of the mask's soft centroid to the image centre, in units of the image's
  long side. While the mask is (nearly) empty it has no gradient, so it blends into the chord
  between the direction to the subjects' centroid and the optical axis, standing in for
  SplaTraj's decay prior (which pulls the camera towards a target it does not see yet);
* ``area``: ``|mask mass / image area - ratio|``. SplaTraj leaves the desired ratio to the user;
  :data:`AREA_RATIO` (a quarter of the frame) shows a subject prominently and whole;
* ``upright``: Refine's upright loss at zero roll (it penalises roll, never pitch).

The pose is optimised as Refine optimises it (Adam on a left-multiplied se(3) increment about the
subjects' centroid, the same learning rates, the mask rendered from the subjects' Gaussians only at
a low resolution), for a fixed number of iterations with no stop on success.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

from ..refine.losses import aim_loss, soft_centroid, target_ray, upright_loss
from ..refine.optimize import PoseDescent, RefineConfig, RefineResult
from ..render import prepare, render, scene_extent
from ..scene import Camera, GaussianScene
from ..translate.labels import PseudoLabels

AREA_RATIO = 0.25


@dataclass
class SplaTrajConfig:
    """Settings of :func:`splatraj_pose`.

    Attributes:
        iterations: Adam steps.
        area_ratio: desired share of the image covered by the subjects' mask.
        center, area, upright: weights of the loss terms.
        lr_rotation, lr_translation, long_side, mask_floor_px, threads: as in
            :class:`~capframe.refine.optimize.RefineConfig`.
    """

    iterations: int = 400
    area_ratio: float = AREA_RATIO
    center: float = 1.0
    area: float = 1.0
    upright: float = 1.0
    lr_rotation: float = 0.007
    lr_translation: float = 0.005
    long_side: int = 160
    mask_floor_px: float = 4.0
    threads: int = 1


class _Objective:
    """The SplaTraj loss as a function of the pose (the interface Refine's descent drives)."""

    def __init__(self, scene: GaussianScene, camera: Camera, labels: PseudoLabels, config: SplaTrajConfig, dtype: torch.dtype):
        self.camera, self.config, self.dtype = camera, config, dtype
        index = torch.as_tensor(np.concatenate([s.gaussians for s in labels.subjects]), dtype=torch.long)
        # Pose-independent work once; the near plane stays relative to the whole scene.
        self.subjects = prepare(scene.subset(index), dtype, extent=scene_extent(scene.means.detach()))
        self.centroids = [scene.means.detach()[index].double().mean(0)]  # the descent's pivot
        self.up = torch.as_tensor(labels.up, dtype=torch.float64)
        self.axis = target_ray((0.5, 0.5), torch.as_tensor(camera.K), camera.width, camera.height)
        self.image_centre = torch.tensor([camera.width / 2, camera.height / 2], dtype=torch.float64)

    def __call__(self, T_cw: Tensor) -> tuple[Tensor, dict[str, Tensor]]:
        cfg, w, h = self.config, self.camera.width, self.camera.height
        mask = render(self.subjects, self.camera, T_cw=T_cw, colors=False, dtype=self.dtype, backend="cpu").alpha.double()
        centroid, mass = soft_centroid(mask)
        offset = centroid - self.image_centre
        gate = (mass / cfg.mask_floor_px).clamp(0.0, 1.0)
        terms = {
            "center": gate * torch.sqrt(offset @ offset + 1e-12) / max(w, h)
            + (1.0 - gate) * aim_loss(T_cw, self.centroids[0], self.axis),
            "area": torch.sqrt((mass / (w * h) - cfg.area_ratio) ** 2 + 1e-12),
            "upright": upright_loss(T_cw, self.up),
        }
        total = cfg.center * terms["center"] + cfg.area * terms["area"] + cfg.upright * terms["upright"]
        return total, {k: v.detach() for k, v in terms.items()}

    def clauses_hold(self, terms: dict[str, Tensor]) -> bool:
        return False  # SplaTraj has no clauses to settle on: it runs its iterations


def splatraj_pose(
    scene: GaussianScene,
    camera: Camera,
    labels: PseudoLabels,
    scale: float,
    config: SplaTrajConfig | None = None,
    dtype: torch.dtype = torch.float32,
) -> RefineResult:
    """Optimise ``camera``'s pose for the SplaTraj loss of the subjects of ``labels``.

    Args:
        scene: the Gaussians.
        camera: the initial camera (its image size and intrinsics are kept).
        labels: pseudo labels from Translate (only the subjects' Gaussians and the up are used).
        scale: the scene scale (translation steps are relative to it).
    """
    start = time.perf_counter()
    config = config or SplaTrajConfig()
    # Refine's descent without its extras: no yaw scan, no plateau stop (patience beyond the run).
    descent = RefineConfig(
        iterations=config.iterations,
        lr_rotation=config.lr_rotation,
        lr_translation=config.lr_translation,
        patience=config.iterations + 1,
        yaw_scan=1,
    )
    threads = torch.get_num_threads()
    torch.set_num_threads(config.threads)
    try:
        run = PoseDescent(_Objective(scene, camera.with_long_side(config.long_side), labels, config, dtype), scale, descent)
        T = run.descend(torch.as_tensor(camera.T_cw, dtype=torch.float64), config.iterations, scan=False)
    finally:
        torch.set_num_threads(threads)
    return run.result(T, start)
