"""2D mask post-processing shared by the model segmenters (OpenCV).

- :func:`fill_largest_contour`: the paper's "polygon refinement" of a SAM mask: keep the largest
  outer contour and fill it (drops specks, closes holes).
- :func:`grabcut_box`: a mask from a detection box without SAM: OpenCV GrabCut seeded by the box
  and by a foreground prior from the rendered depth.
- :func:`subject_masks`: per-view masks resized to the association's measurement resolution and
  gathered into :class:`~capframe.backends.protocols.SubjectMasks`.
"""

from __future__ import annotations

import cv2
import numpy as np

from .protocols import SubjectMasks

GRABCUT_ITERATIONS = 5
# The depth prior: pixels of the box within this many subject half-sizes of the subject's depth
# are probable foreground, up to twice that probable background, farther (or nothing rendered)
# background. The half-size is the box's half-diagonal in pixels at the subject's depth.
DEPTH_FOREGROUND = 1.0
DEPTH_BACKGROUND = 2.0
CORE_FRACTION = 0.5  # the subject's depth is the median over this central share of the box (per axis)


def fill_largest_contour(mask: np.ndarray) -> np.ndarray:
    """(H, W) bool: the largest outer contour of ``mask`` (H, W) bool, filled; all False when
    the mask is empty."""
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    out = np.zeros(mask.shape, dtype=np.uint8)
    if contours:
        cv2.drawContours(out, [max(contours, key=cv2.contourArea)], -1, 1, thickness=cv2.FILLED)
    return out.astype(bool)


def resize_mask(mask: np.ndarray, height: int, width: int) -> np.ndarray:
    """(height, width) bool: ``mask`` (H, W) bool resized by area (a pixel is in when at least
    half of it was)."""
    if mask.shape == (height, width):
        return mask
    return cv2.resize(mask.astype(np.float32), (width, height), interpolation=cv2.INTER_AREA) >= 0.5


def clip_box(box: np.ndarray, height: int, width: int) -> np.ndarray:
    """(4,) ``box`` x0, y0, x1, y1 clipped to a ``width`` x ``height`` image (detectors' boxes
    may reach past the frame)."""
    return np.clip(np.asarray(box, dtype=np.float64), 0.0, [width, height, width, height])


def _box_pixels(box: np.ndarray, height: int, width: int) -> tuple[int, int, int, int]:
    """Integer pixel bounds ``(x0, y0, x1, y1)`` (end exclusive) of an ``(x0, y0, x1, y1)`` box,
    clipped to the image and at least one pixel wide."""
    x0, y0 = int(np.clip(np.floor(box[0]), 0, width - 1)), int(np.clip(np.floor(box[1]), 0, height - 1))
    x1, y1 = int(np.clip(np.ceil(box[2]), x0 + 1, width)), int(np.clip(np.ceil(box[3]), y0 + 1, height))
    return x0, y0, x1, y1


def depth_prior(depth: np.ndarray, box: np.ndarray, focal: float) -> np.ndarray:
    """(H, W) uint8 GrabCut labels from a box and the rendered depth.

    Outside the box: background. Inside: the subject's depth ``d`` is the median valid depth of the
    box's central part, its half-size ``r = half-diagonal(box) * d / focal`` in scene units; a
    pixel within ``DEPTH_FOREGROUND * r`` of ``d`` is probable foreground, within
    ``DEPTH_BACKGROUND * r`` probable background, else (a depth discontinuity: the wall behind,
    an occluder in front, or nothing rendered) background. Without valid depth in the core, the
    whole box is probable foreground (plain box-seeded GrabCut).

    Args:
        depth: (H, W) rendered depth, 0 where nothing is rendered.
        box: (4,) x0, y0, x1, y1 in pixels of this image.
        focal: focal length in pixels at this image size.
    """
    H, W = depth.shape
    labels = np.full((H, W), cv2.GC_BGD, dtype=np.uint8)
    x0, y0, x1, y1 = _box_pixels(box, H, W)
    inside = depth[y0:y1, x0:x1]
    mx, my = (x1 - x0) * (1 - CORE_FRACTION) / 2, (y1 - y0) * (1 - CORE_FRACTION) / 2
    core = depth[int(y0 + my) : max(int(y1 - my), int(y0 + my) + 1), int(x0 + mx) : max(int(x1 - mx), int(x0 + mx) + 1)]
    if not (core > 0).any():
        labels[y0:y1, x0:x1] = cv2.GC_PR_FGD
        return labels
    d = float(np.median(core[core > 0]))
    r = 0.5 * np.hypot(x1 - x0, y1 - y0) * d / focal
    off = np.abs(inside - d)
    labels[y0:y1, x0:x1] = np.where(
        inside <= 0,
        cv2.GC_BGD,
        np.where(off <= DEPTH_FOREGROUND * r, cv2.GC_PR_FGD, np.where(off <= DEPTH_BACKGROUND * r, cv2.GC_PR_BGD, cv2.GC_BGD)),
    )
    return labels


def grabcut_box(image: np.ndarray, depth: np.ndarray, box: np.ndarray, focal: float) -> np.ndarray:
    """(H, W) bool mask of the object in ``box``: GrabCut on the colours, seeded by
    :func:`depth_prior`. When the prior leaves no background or no foreground to learn colours
    from, the prior's foreground is the mask.

    Args:
        image: (H, W, 3) uint8 RGB.
        depth: (H, W) rendered depth at the same size, 0 where nothing is rendered.
        box: (4,) x0, y0, x1, y1 in pixels of this image.
        focal: focal length in pixels at this image size.
    """
    labels = depth_prior(depth, box, focal)
    foreground = (labels == cv2.GC_FGD) | (labels == cv2.GC_PR_FGD)
    if foreground.all() or not foreground.any():
        return foreground
    background_model, foreground_model = np.zeros((1, 65)), np.zeros((1, 65))
    bgr = np.ascontiguousarray(image[..., ::-1])
    cv2.grabCut(bgr, labels, None, background_model, foreground_model, GRABCUT_ITERATIONS, cv2.GC_INIT_WITH_MASK)
    return (labels == cv2.GC_FGD) | (labels == cv2.GC_PR_FGD)


def subject_masks(view_indices: list[int], masks: dict[int, np.ndarray], height: int, width: int) -> SubjectMasks:
    """The views in which a mask was found, each mask resized to ``height`` x ``width``; every
    view with an empty mask when none was (the association then reports the subject as not
    found).

    Args:
        view_indices: the views asked for, in order.
        masks: view -> (H_v, W_v) bool mask, for the views where the subject was found.
    """
    found = [v for v in view_indices if v in masks and masks[v].any()]
    if not found:
        return SubjectMasks(list(view_indices), np.zeros((len(view_indices), height, width), dtype=bool))
    return SubjectMasks(found, np.stack([resize_mask(masks[v], height, width) for v in found]))
