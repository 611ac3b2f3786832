"""Robust statistics of captured Gaussians: where the object is, and which Gaussians float away.

Captured 3DGS scenes carry *floaters*: small clouds of Gaussians far from the subject, left by
the optimiser where the training views disagreed. A mean or a bounding box is dragged by them;
medians are not. :func:`floater_mask` keeps the largest spatially connected cluster of Gaussians
(occupied voxels joined through their 26 neighbours), which drops both far floaters and detached
specks near the subject, whatever the subject's shape (an elongated guitar has no useful radius).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def robust_centre(means: np.ndarray) -> np.ndarray:
    """Coordinate-wise median of the (N, 3) means: (3,)."""
    return np.median(np.asarray(means, dtype=np.float64), axis=0)


def robust_radius(means: np.ndarray, quantile: float = 0.5) -> float:
    """The ``quantile`` of the distances from the (N, 3) means to their coordinate-wise median.

    The median (0.5) ignores any fraction of floaters below one half, however far they are."""
    means = np.asarray(means, dtype=np.float64)
    if len(means) == 0:
        raise InputError("no Gaussians to measure; expected at least one")
    return float(np.quantile(np.linalg.norm(means - robust_centre(means), axis=1), quantile))


def _components(cells: np.ndarray) -> np.ndarray:
    """Connected components of occupied voxels (M, 3) int64 under 26-connectivity: (M,) ids."""
    index = {tuple(c): i for i, c in enumerate(cells.tolist())}
    offsets = [(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1) if (dx, dy, dz) != (0, 0, 0)]
    component = np.full(len(cells), -1, dtype=np.int64)
    for start in range(len(cells)):
        if component[start] >= 0:
            continue
        component[start] = start
        stack = [start]
        while stack:
            x, y, z = cells[stack.pop()].tolist()
            for dx, dy, dz in offsets:
                j = index.get((x + dx, y + dy, z + dz))
                if j is not None and component[j] < 0:
                    component[j] = start
                    stack.append(j)
    return component


def floater_mask(means: np.ndarray, cells_per_radius: float = 12.0) -> np.ndarray:
    """Gaussians of the largest connected cluster: (N,) bool, True = keep.

    The means are binned into cubic voxels of side ``robust_radius(means) / cells_per_radius``
    (the median distance to the median, so floaters do not set the grid); voxels touching through
    a face, an edge or a corner are connected, and the component holding the most Gaussians is
    kept. A gap wider than about two voxels (1/6 of the median radius by default) separates a
    floater from the subject.

    Args:
        means: (N, 3) Gaussian centres.
        cells_per_radius: voxels per median radius; larger cuts closer floaters and, when too
            large, thin parts of the subject.
    """
    means = np.asarray(means, dtype=np.float64)
    if len(means) == 0:
        return np.zeros(0, dtype=bool)
    cell = robust_radius(means) / cells_per_radius
    if not cell > 0:
        return np.ones(len(means), dtype=bool)
    keys = np.floor((means - robust_centre(means)) / cell).astype(np.int64)
    cells, inverse = np.unique(keys, axis=0, return_inverse=True)
    component = _components(cells)
    sizes = np.bincount(component[inverse.reshape(-1)], minlength=len(cells))
    return component[inverse.reshape(-1)] == int(np.argmax(sizes))


__all__ = ["robust_centre", "robust_radius", "floater_mask"]
