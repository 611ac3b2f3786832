"""Candidate poses of the view-search baselines (paper supplement, "Details of IVS and SVS").

* IVS interpolates between the top retrieved training views: for every pair, three poses at
  ``t = 1/4, 1/2, 3/4``, rotations by SLERP and camera centres linearly;
* SVS samples camera centres on a sphere around the subjects' mean centre, each looking at it,
  level: directions uniform over the sphere with elevations in ``[-70, 90]`` degrees about the
  world up, distances uniform in ``[1.1 d, 1.6 d]`` where ``d`` is the distance from which the
  subjects' bounding sphere just fits in the view.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import torch
from torch import Tensor

from ..geometry import camera_center, look_at, so3_exp, so3_log
from ..scene import Camera

IVS_FRACTIONS = (0.25, 0.5, 0.75)
SVS_ELEVATION_DEG = (-70.0, 90.0)  # no views from below the scene
SVS_DISTANCE = (1.1, 1.6)  # (alpha, beta): camera distances in units of the fitting distance d


def interpolate_pose(T_a: Tensor, T_b: Tensor, t: Tensor) -> Tensor:
    """Poses between two world-to-camera poses: (4, 4), (4, 4), (F,) -> (F, 4, 4).

    The rotation follows the geodesic ``R_a (R_a^T R_b)^t`` (quaternion SLERP along the shorter
    arc) and the camera centre the straight line between the two centres, so ``t = 0`` gives
    ``T_a`` and ``t = 1`` gives ``T_b``. Interpolating centres rather than the translations
    ``t = -R C`` keeps the path a straight line in the world whatever the rotations.
    """
    R_a, R_b = T_a[:3, :3], T_b[:3, :3]
    R = R_a @ so3_exp(t[:, None] * so3_log(R_a.T @ R_b))
    C = (1.0 - t[:, None]) * camera_center(T_a) + t[:, None] * camera_center(T_b)
    T = torch.zeros(len(t), 4, 4, dtype=T_a.dtype)
    T[:, :3, :3] = R
    T[:, :3, 3] = -(R @ C[..., None])[..., 0]
    T[:, 3, 3] = 1.0
    return T


def ivs_candidates(cameras: list[Camera], fractions: tuple[float, ...] = IVS_FRACTIONS) -> list[Camera]:
    """IVS candidates: the ``L`` given views (best first), then for every pair ``i < j`` one pose
    per fraction between them; ``L + len(fractions) L (L - 1) / 2`` cameras.

    An interpolated camera keeps the intrinsics and image size of the better-ranked view ``i``.
    """
    t = torch.tensor(fractions, dtype=torch.float64)
    out = list(cameras)
    for a, b in itertools.combinations(cameras, 2):
        poses = interpolate_pose(torch.from_numpy(a.T_cw), torch.from_numpy(b.T_cw), t)
        out += [
            dataclasses.replace(a, T_cw=T.numpy(), name=f"{a.name}~{b.name}@{f:g}", image_path=None)
            for T, f in zip(poses, fractions)
        ]
    return out


def fit_distance(radius: float, camera: Camera) -> float:
    """Distance from which a sphere of ``radius`` just fits in ``camera``'s view: its angular
    radius equals the narrowest half field of view (principal point to the nearest image edge)."""
    (fx, _, cx), (_, fy, cy) = camera.K[0], camera.K[1]
    half = min(math.atan(cx / fx), math.atan((camera.width - cx) / fx), math.atan(cy / fy), math.atan((camera.height - cy) / fy))
    return radius / math.sin(half)


def sphere_directions(
    up: np.ndarray, count: int, rng: np.random.Generator, elevation_deg: tuple[float, float] = SVS_ELEVATION_DEG
) -> np.ndarray:
    """(count, 3) unit directions uniform over the part of the sphere whose elevation about
    ``up`` lies in ``elevation_deg``: uniform directions, those outside the band rejected."""
    lo, hi = (math.sin(math.radians(e)) for e in elevation_deg)
    kept = np.zeros((0, 3))
    while len(kept) < count:
        d = rng.standard_normal((2 * count, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        kept = np.concatenate([kept, d[(d @ up >= lo) & (d @ up <= hi)]])
    return kept[:count]


def svs_candidates(
    centre: np.ndarray,
    radius: float,
    up: np.ndarray,
    camera: Camera,
    count: int,
    seed: int = 0,
    elevation_deg: tuple[float, float] = SVS_ELEVATION_DEG,
    distance: tuple[float, float] = SVS_DISTANCE,
) -> list[Camera]:
    """SVS candidates: ``count`` level cameras looking at ``centre`` (3,) from directions of
    :func:`sphere_directions` at distances uniform in ``distance`` times :func:`fit_distance`
    of ``radius``, with ``camera``'s intrinsics and image size. Deterministic for a seed."""
    rng = np.random.default_rng(seed)
    up = np.asarray(up, dtype=np.float64) / np.linalg.norm(up)
    directions = sphere_directions(up, count, rng, elevation_deg)
    distances = rng.uniform(*distance, count) * fit_distance(radius, camera)
    target, world_up = torch.as_tensor(centre, dtype=torch.float64), torch.from_numpy(up)
    eyes = torch.from_numpy(np.asarray(centre) + distances[:, None] * directions)
    return [
        dataclasses.replace(camera, T_cw=look_at(eye, target, world_up).numpy(), name=f"svs{k}", image_path=None)
        for k, eye in enumerate(eyes)
    ]
