"""Subject -> Gaussian subset, and the subject's orientation.

Two routes, as in DESIGN §4:

* labels: the scene's per-Gaussian label ids (semantic sidecar) give the subset directly;
* masks: 2D masks of the subject in the retrieved views (from a segmenter; label renders stand in
  for one in the embedded tier) are back-projected with the alpha-normalised rendered depth, and
  the Gaussians whose means are the nearest neighbours of those points form the subset (the
  paper's Translate step, what the model tier uses).

The centroid is the mean of the subset's means. Orientation comes from the sidecar's annotated
front; a subject without one is treated as symmetric (layout only).
"""

from __future__ import annotations

import numpy as np
import torch

from ..backends.protocols import Grounding
from ..errors import InputError
from ..scene import Camera, SemanticObject

KNN_NEIGHBOURS = 4  # Gaussians taken per back-projected point
# A neighbour counts only within this many median nearest-neighbour spacings of the Gaussian
# means: points back-projected onto the background past the subject's silhouette find no member.
KNN_RADIUS_SPACINGS = 3.0
_CHUNK = 2048  # back-projected points per distance block (bounds memory at N * 2048 floats)


def ground_by_labels(name: str, labels: torch.Tensor, means: torch.Tensor, objects: list[SemanticObject]) -> Grounding:
    """The subject's Gaussians from the per-Gaussian label ids; front from the sidecar."""
    obj = next((o for o in objects if o.name == name), None)
    if obj is None:
        raise InputError(f"subject {name!r} is not in the semantic sidecar; known: {sorted(o.name for o in objects)}")
    index = torch.nonzero(labels == obj.id)[:, 0].numpy()
    if index.size == 0:
        raise InputError(f"subject {name!r} (label {obj.id}) has no Gaussians in labels.npy")
    centroid = means[index].double().mean(0).numpy()
    front = None if obj.symmetric or obj.front is None else np.asarray(obj.front, dtype=np.float64)
    return Grounding(name, index, centroid, front)


def back_project(mask: np.ndarray, depth: np.ndarray, camera: Camera) -> np.ndarray:
    """World points (P, 3) of the mask's pixels with valid depth.

    Args:
        mask: (H, W) boolean subject mask.
        depth: (H, W) rendered camera-z, 0 where invalid.
        camera: the view at the mask's resolution (pixel centres at integer + 0.5).
    """
    v, u = np.nonzero(mask & (depth > 0))
    z = depth[v, u].astype(np.float64)
    pixels = np.stack([u + 0.5, v + 0.5, np.ones_like(z)], 1)
    rays = pixels @ np.linalg.inv(camera.K).T  # camera-frame directions with z = 1
    points_cam = rays * z[:, None]
    return (points_cam - camera.t) @ camera.R  # R^T (x - t), row-wise


def median_spacing(means: torch.Tensor, sample: int = 2048, seed: int = 0) -> float:
    """Median distance from a Gaussian mean to its nearest other mean (on a random sample)."""
    g = torch.Generator().manual_seed(seed)
    pick = torch.randperm(len(means), generator=g)[:sample]
    d = torch.cdist(means[pick].double(), means.double())
    d[torch.arange(len(pick)), pick] = float("inf")
    return float(d.min(1).values.median())


def knn_members(points: np.ndarray, means: torch.Tensor, k: int = KNN_NEIGHBOURS, radius: float | None = None) -> np.ndarray:
    """Indices of the Gaussians that are among the ``k`` nearest means of some point, within
    ``radius`` (default :data:`KNN_RADIUS_SPACINGS` median spacings).

    Args:
        points: (P, 3) back-projected world points.
        means: (N, 3) Gaussian means.
    """
    if len(points) == 0:
        return np.zeros(0, dtype=np.int64)
    means64 = means.detach().double()
    if radius is None:
        radius = KNN_RADIUS_SPACINGS * median_spacing(means64)
    hit = torch.zeros(len(means64), dtype=torch.bool)
    pts = torch.as_tensor(points, dtype=torch.float64)
    for start in range(0, len(pts), _CHUNK):
        d, idx = torch.cdist(pts[start : start + _CHUNK], means64).topk(min(k, len(means64)), largest=False)
        hit[idx[d <= radius]] = True
    return torch.nonzero(hit)[:, 0].numpy()


def ground_by_masks(
    name: str,
    masks: list[np.ndarray],
    depths: list[np.ndarray],
    cameras: list[Camera],
    means: torch.Tensor,
    front: np.ndarray | None = None,
) -> Grounding:
    """The subject's Gaussians from its 2D masks in some views: back-projection + KNN.

    Args:
        masks: per view (H, W) boolean mask of the subject.
        depths: per view (H, W) rendered depth at the same resolution.
        cameras: the views at that resolution.
        means: (N, 3) Gaussian means.
        front: the subject's front if an orientation estimate exists.
    """
    points = [back_project(m, d, c) for m, d, c in zip(masks, depths, cameras)]
    cloud = np.concatenate(points) if points else np.zeros((0, 3))
    if len(cloud) == 0:
        raise InputError(f"subject {name!r}: its masks are empty in every retrieved view; cannot locate it in 3D")
    index = knn_members(cloud, means)
    if index.size == 0:
        raise InputError(f"subject {name!r}: no Gaussian lies near its back-projected mask")
    centroid = means[index].double().mean(0).numpy()
    return Grounding(name, index, centroid, front)
