"""Subject masks of a view and what they measure: how much of each subject is visible, where it sits
in the frame and how large it is.

The same measurements serve the method (Question-Evaluation answers, the per-clause report of
``capframe ground``) and the evaluation (the ground-truth checker); they differ only in where the
subjects' Gaussians come from.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch
from torch import Tensor

from ..scene import Camera, GaussianScene
from . import PreparedGaussians, RenderOutput, prepare, render

MASK_THRESHOLD = 0.5  # own-render alpha above this is the subject's mask (extent, pixel count)
EMPTY_WEIGHT = 1e-3  # below this total alpha (in pixels) a mask counts as empty


def bbox_fractions(alpha: Tensor) -> tuple[float, float]:
    """Width and height of the bounding box of ``alpha > MASK_THRESHOLD`` as fractions of the
    image ((0, 0) if empty). (H, W) -> (width, height)."""
    mask = alpha > MASK_THRESHOLD
    if not mask.any():
        return 0.0, 0.0
    H, W = mask.shape
    rows, cols = mask.any(1).nonzero()[:, 0], mask.any(0).nonzero()[:, 0]
    return float(cols.max() - cols.min() + 1) / W, float(rows.max() - rows.min() + 1) / H


@dataclass
class SubjectMask:
    """One subject in one view.

    Attributes:
        visible: (H, W) the subject's share of the full render's alpha (other objects occlude it).
        own: (H, W) alpha of the subject rendered alone, cropped to the frame.
        in_frame: share of the subject's own alpha (rendered on a wide canvas) inside the frame.
    """

    visible: Tensor
    own: Tensor
    in_frame: float

    @property
    def pixels(self) -> int:
        """Pixels of the own mask inside the frame."""
        return int((self.own > MASK_THRESHOLD).sum())

    @property
    def visible_fraction(self) -> float:
        """Share of the subject's in-frame alpha not hidden by other objects (0 when empty)."""
        own = float(self.own.sum())
        return min(1.0, float(self.visible.sum()) / own) if own > EMPTY_WEIGHT else 0.0

    def centroid(self) -> tuple[float, float] | None:
        """Alpha-weighted centre of the visible mask in normalised coordinates (origin top-left),
        or None when nothing is visible."""
        weight = float(self.visible.sum())
        if weight <= EMPTY_WEIGHT:
            return None
        H, W = self.visible.shape
        v = self.visible.to(torch.float64)
        ys = (torch.arange(H, dtype=torch.float64) + 0.5) / H
        xs = (torch.arange(W, dtype=torch.float64) + 0.5) / W
        return float((v.sum(0) * xs).sum()) / weight, float((v.sum(1) * ys).sum()) / weight

    def bbox_size(self) -> tuple[float, float]:
        """Width and height of the own mask's bounding box as frame fractions ((0, 0) if empty)."""
        return bbox_fractions(self.own)

    def extent(self) -> float:
        """The subject's projected size: max(bbox width / W, bbox height / H) of the own mask."""
        return max(self.bbox_size())


def subject_masks(
    gaussians: GaussianScene | PreparedGaussians,
    camera: Camera,
    members: Tensor,
    *,
    backend: str = "auto",
    near: float | None = None,
) -> tuple[list[SubjectMask], RenderOutput]:
    """Masks of several subjects in one view, without gradients.

    Args:
        gaussians: the whole scene (on the device to render on); :func:`~capframe.render.prepare`
            it once to measure many views.
        camera: the view, at the resolution to measure at.
        members: (N, S) boolean, column s marks subject s's Gaussians.
        near: near plane (default: the renderer's).
    Returns:
        one :class:`SubjectMask` per subject, and the full render (alpha, depth; ``extra`` holds
        the S visible masks).

    Each subject alone is rendered on a canvas with a guard band of half the frame on each side,
    whose centre crop is exactly the frame, so the share cut off by the frame edge is measured.
    """
    W, H = camera.width, camera.height
    gx, gy = W // 2, H // 2
    canvas = camera.padded(gx, gy)
    options = dict(backend=backend, near=near)
    with torch.no_grad():
        if not isinstance(gaussians, PreparedGaussians):  # once for the 1 + S renders below
            gaussians = prepare(gaussians)
        full = render(gaussians, camera, extra=members.to(gaussians.means.dtype), colors=False, **options)
        masks = []
        for s in range(members.shape[1]):
            if members[:, s].any():
                own_canvas = render(gaussians, canvas, subset=members[:, s], colors=False, **options).alpha.cpu()
            else:
                own_canvas = torch.zeros(canvas.height, canvas.width)
            own = own_canvas[gy : gy + H, gx : gx + W]
            total = float(own_canvas.sum())
            in_frame = float(own.sum()) / total if total > EMPTY_WEIGHT else 0.0
            masks.append(SubjectMask(full.extra[..., s].clamp(0.0, 1.0).cpu(), own, in_frame))
    return masks, full
