"""A camera that misses an asked angle by a few degrees, moved on its subject's view sphere into
the accepted interval.

Refine's view and elevation terms are hinges that its layout terms pull against, so a run can
settle a degree or two outside an asked interval (a low angle at a pot plant with a tree behind
it: the camera stops where looking up costs the tree's place in the frame). The checker reads
the angles of the camera centre around the subject's view centre, so the miss is closed in closed
form: the centre moves by the missing angle plus a margin on the sphere about that point, and the
camera turns so the subject's centroid keeps its pixel and the horizon keeps its roll; where
that centre is inside geometry (under the floor), it comes nearer along the same direction. Whether
the other clauses still hold is the caller's to check (the method's own report).

:class:`ViewSphere` reads where a camera is on that sphere and places one at a pose; the last
search (:mod:`capframe.refine.search`) draws its cameras on it too.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import torch

from ..geometry import any_horizontal, camera_roll, subject_frame
from ..measure import CheckReport, wrap_deg
from ..scene import Camera
from .candidates import aimed_pose

NUDGE_MARGIN_DEG = 2.0  # past the interval's edge, at most a quarter of its width
NUDGE_MAX_DEG = 8.0  # a larger miss is not a settling error: Refine went elsewhere
# Shares of the distance tried, nearest last, until the moved camera is in free space: an angle
# below a subject on the ground is reached under the floor from afar but above it from nearer.
DISTANCE_SHARES = (1.0, 0.85, 0.7, 0.55, 0.4)


def angle_misses(report: CheckReport, primary: str) -> tuple[float, float] | None:
    """The turn (azimuth, elevation) in degrees that brings ``report``'s failing ``view`` and
    ``elevation`` rows of the subject ``primary`` inside their intervals with
    :data:`NUDGE_MARGIN_DEG`; None when no such row fails, when any other clause fails (another
    subject's view among them), or when a miss exceeds :data:`NUDGE_MAX_DEG`.

    An azimuth turn is towards the nearest accepted side (a view row lists the side's azimuths
    and their tolerance); an elevation turn towards the nearest end of the range.
    """
    azimuth = elevation = 0.0
    for row in report.rows:
        if row.satisfied is not False:
            continue
        if row.constraint not in ("view", "elevation") or row.subject != primary or row.measured is None:
            return None
        if row.constraint == "view":
            # A view row's error is the deviation from the side's centre, not from its tolerance.
            tolerance = row.target["tolerance_deg"]
            offset = min((wrap_deg(a - row.measured) for a in row.target["azimuths_deg"]), key=abs)
            miss = abs(offset) - tolerance
            azimuth = offset - math.copysign(tolerance - min(NUDGE_MARGIN_DEG, tolerance / 2), offset)
        else:
            lo, hi = row.target["range_deg"]
            miss = lo - row.measured if row.measured < lo else row.measured - hi
            margin = min(NUDGE_MARGIN_DEG, (hi - lo) / 4)
            elevation = (lo + margin if row.measured < lo else hi - margin) - row.measured
        if miss > NUDGE_MAX_DEG:
            return None
    return (azimuth, elevation) if (azimuth or elevation) else None


@dataclass
class SpherePose:
    """A camera on a subject's view sphere: azimuth and elevation of its centre about the pivot
    (degrees, DESIGN §3), its distance, the normalised point its aim images at and its roll
    (degrees)."""

    azimuth: float
    elevation: float
    distance: float
    point: tuple[float, float]
    roll: float


class ViewSphere:
    """The sphere of cameras about ``pivot`` (3,) (a subject's view centre) that look at ``aim``
    (3,) (its centroid): azimuth about ``front`` (3,, None: any horizontal), elevation from the
    world ``up`` (3,)."""

    def __init__(self, pivot: np.ndarray, aim: np.ndarray, front: np.ndarray | None, up: np.ndarray):
        f64 = dict(dtype=torch.float64)
        self.pivot, self.aim, self.up = pivot, aim, up
        self.f, self.u, self.r = (
            v.numpy()
            for v in subject_frame(
                torch.tensor(front if front is not None else any_horizontal(up), **f64), torch.tensor(up, **f64)
            )
        )

    def pose(self, camera: Camera) -> SpherePose | None:
        """Where ``camera`` is on the sphere; None at the pivot or with the aim behind it."""
        offset = camera.center - self.pivot
        distance = float(np.linalg.norm(offset))
        x_cam = camera.R @ self.aim + camera.t
        if distance <= 0.0 or x_cam[2] <= 0.0:
            return None
        pixel = camera.K @ (x_cam / x_cam[2])
        f64 = dict(dtype=torch.float64)
        return SpherePose(
            math.degrees(math.atan2(float(offset @ self.r), float(offset @ self.f))),
            math.degrees(math.asin(max(-1.0, min(1.0, float(offset @ self.u) / distance)))),
            distance,
            (float(pixel[0]) / camera.width, float(pixel[1]) / camera.height),
            math.degrees(float(camera_roll(torch.tensor(camera.T_cw, **f64), torch.tensor(self.up, **f64)))),
        )

    def direction(self, azimuth_deg: float, elevation_deg: float) -> np.ndarray:
        """(3,) unit direction from the pivot at those angles."""
        a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
        return math.cos(e) * (math.cos(a) * self.f + math.sin(a) * self.r) + math.sin(e) * self.u

    def camera(self, camera: Camera, pose: SpherePose) -> Camera:
        """``camera`` (its intrinsics) placed at ``pose``, imaging the aim at its point with its roll."""
        centre = self.pivot + pose.distance * self.direction(pose.azimuth, pose.elevation)
        return camera.with_pose(aimed_pose(centre, self.aim, pose.point, camera, self.up, pose.roll))


def orbited(
    camera: Camera,
    pivot: np.ndarray,
    aim: np.ndarray,
    front: np.ndarray | None,
    up: np.ndarray,
    turn_deg: tuple[float, float],
    distance_scale: float = 1.0,
) -> Camera | None:
    """``camera`` moved on the sphere about ``pivot`` (3,) by ``turn_deg`` (azimuth about the
    subject's ``front``, elevation; degrees, DESIGN §3) and ``distance_scale`` times as far from
    it, turned so ``aim`` (3,) keeps its pixel and the camera its roll. None when ``aim`` is behind
    the camera or the new elevation would pass a pole (the sphere has no azimuth there)."""
    sphere = ViewSphere(pivot, aim, front, up)
    pose = sphere.pose(camera)
    if pose is None or abs(pose.elevation + turn_deg[1]) >= 89.0:
        return None
    moved = dataclasses.replace(
        pose,
        azimuth=pose.azimuth + turn_deg[0],
        elevation=pose.elevation + turn_deg[1],
        distance=distance_scale * pose.distance,
    )
    return sphere.camera(camera, moved)
