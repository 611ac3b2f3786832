"""Witness cameras: a constructive proof that a constraint set can be satisfied in a scene.

The instruction generator only emits constraint sets for which :meth:`WitnessFinder.find` finds a
camera (and, when it can render the scene, one that also passes the ground-truth checker). It works
on geometric proxies from the ground truth, without rendering: every object is a bounding sphere
(``center``, ``radius``) whose image is a disc, plus its oriented box when the ground truth gives
one. A candidate camera is built analytically —

1. centre ``C = S + D * view_direction(azimuth, elevation)`` around the primary subject ``S``,
   with the azimuth from the asked view side (± up to 20°, inside the 30° tolerance), the
   elevation inside the asked range, and the distance ``D`` giving the asked shot size (or
   fitting both subjects of a two-subject layout);
2. orientation by ``look_at`` with the asked roll, the look-at target shifted (a few fixed-point
   steps) so that the primary lands on a point inside its region box —

and accepted when

* the camera is in free space: outside every object's bounding sphere (the primary's box, when
  given, so elongated subjects allow close-ups), above the support level (the highest bottom of
  the objects' spheres, a lower bound of the floor or table they stand on) by
  :data:`SUPPORT_MARGIN` primary radii or :data:`SUPPORT_MARGIN_SCALE` scene scales (splats seen
  at grazing angles from close by cover the view), inside the ``free_space`` ball (where the
  training cameras were) and inside the room's walls if the ground truth has a room;
* every subject is entirely in front of the camera and mostly in frame, and the centroid of its
  in-frame disc lies inside its region box (with :data:`REGION_MARGIN`);
* the primary's extent (in-frame disc, or its box's projected corners) is inside the asked shot
  range, above :data:`SHOT_LOW_FACTOR` times its lower end (proxies bound objects from outside);
* no object whose sphere reaches in front of a subject's centre covers more than
  :data:`MAX_OCCLUDED` of the subject's disc;
* roll, if asked, is measurable (not looking within 15° of straight up or down).

All lengths are relative to the objects' radii and the scene scale, so the result is invariant
to scaling, translating and tilting the scene.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from itertools import product

import numpy as np

from ..constraints import REGIONS, SHOT_SIZES, VIEW_SIDES, Constraints, view_tolerance_deg
from ..evaluate.ground_truth import Box, Room
from ..geometry import any_horizontal
from ..scene import Camera

MAX_OCCLUDED = 0.2  # largest share of a subject's disc a nearer object's disc may cover
REGION_MARGIN = 0.02  # the disc centroid must lie this far inside the region box
SHOT_MARGIN = 0.04  # the proxy extent must lie this far inside the shot range ...
SHOT_LOW_FACTOR = 1.3  # ... and above this multiple of its lower end (a proxy bounds the object from outside)
ROLL_MIN_TILT_DEG = 15.0  # roll is asked only when the camera is this far from looking straight up/down
SUPPORT_MARGIN = 0.4  # the camera stays this many primary radii above the support level ...
SUPPORT_MARGIN_SCALE = 0.02  # ... and at least this many scene scales (grass, rugs, thick ground)
ROOM_MARGIN = 0.5  # in a room, the camera stays this many primary radii inside the walls
FREE_RADIUS_SCALE = 1.0  # default free space: this many scene scales around the objects' centroid

# Candidate elevations (degrees) per named elevation, the preferred first.
_ELEVATION_CANDIDATES = {
    "eye level": (0.0, 6.0, -6.0),
    "slightly above": (18.0, 12.0, 25.0),
    "high angle": (40.0, 32.0, 50.0),
    "bird's-eye": (72.0, 66.0, 80.0),
    "low angle": (-15.0, -11.0, -22.0),
    "worm's-eye": (-65.0, -56.0, -75.0),
    "top-down": (86.0, 83.0, 89.0),
    "slightly below": (-15.0, -11.0, -22.0),
}
_FREE_ELEVATIONS = (12.0, 0.0, 25.0, 40.0)
# Candidate projected extents per shot size (fraction of the frame), the preferred first.
_SHOT_EXTENTS = {"close-up": (0.9, 0.8, 1.05), "medium": (0.45, 0.4, 0.52), "wide": (0.2, 0.15, 0.25)}
_FREE_EXTENTS = (0.4, 0.25, 0.55, 0.15)
_VIEW_OFFSETS = (0.0, 10.0, -10.0, 20.0, -20.0)


def default_intrinsics(width: int = 320, height: int = 240, hfov_deg: float = 60.0) -> tuple[np.ndarray, int, int]:
    """Pinhole intrinsics of the reference camera the witness uses when none is given."""
    f = 0.5 * width / math.tan(math.radians(hfov_deg) / 2)
    return np.array([[f, 0.0, width / 2], [0.0, f, height / 2], [0.0, 0.0, 1.0]]), width, height


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def look_at_np(eye: np.ndarray, target: np.ndarray, up: np.ndarray, roll: float = 0.0) -> np.ndarray:
    """NumPy twin of :func:`capframe.geometry.look_at` (same convention, ``roll`` in radians)."""
    forward = _unit(target - eye)
    right = np.cross(forward, up)
    if np.linalg.norm(right) < 1e-9:
        axis = np.zeros(3)
        axis[np.abs(forward).argmin()] = 1.0
        right = np.cross(forward, axis)
    right = _unit(right)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    right, down = c * right + s * down, -s * right + c * down
    T = np.eye(4)
    T[:3, :3] = np.stack([right, down, forward])
    T[:3, 3] = -T[:3, :3] @ eye
    return T


def view_direction_np(azimuth_deg: float, elevation_deg: float, front: np.ndarray, up: np.ndarray) -> np.ndarray:
    """NumPy twin of :func:`capframe.geometry.view_direction` (angles in degrees)."""
    f = _unit(front - (front @ up) * up)
    r = np.cross(f, up)
    a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
    return math.cos(e) * (math.cos(a) * f + math.sin(a) * r) + math.sin(e) * up


def region_target(region: str | None) -> tuple[float, float]:
    """The point (normalised) a subject is aimed at for a region: the box centre pulled 35% of
    the way towards the frame centre (the frame centre without a region)."""
    if region is None:
        return 0.5, 0.5
    x0, y0, x1, y1 = REGIONS[region]
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    return cx + 0.35 * (0.5 - cx), cy + 0.35 * (0.5 - cy)


def _circle_overlap(d: float, r1: float, r2: float) -> float:
    """Area of the intersection of two discs with radii r1, r2 whose centres are d apart."""
    if d >= r1 + r2:
        return 0.0
    if d <= abs(r1 - r2):
        return math.pi * min(r1, r2) ** 2
    a1 = r1 * r1 * math.acos(np.clip((d * d + r1 * r1 - r2 * r2) / (2 * d * r1), -1, 1))
    a2 = r2 * r2 * math.acos(np.clip((d * d + r2 * r2 - r1 * r1) / (2 * d * r2), -1, 1))
    k = 0.5 * math.sqrt(max((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2), 0.0))
    return a1 + a2 - k


_GRID = np.stack(np.meshgrid(np.linspace(-1, 1, 41), np.linspace(-1, 1, 41)), -1).reshape(-1, 2)
_GRID = _GRID[(_GRID**2).sum(1) <= 1.0]  # sample points of the unit disc


class WitnessFinder:
    """Searches witness cameras in one scene.

    Args:
        centers: (M, 3) object centres; radii: (M,) bounding radii; up: world up.
        scale: the scene scale ``s``.
        intrinsics: ``(K, width, height)`` of the reference camera (default: 320x240, 60° hfov).
        free_space: ``(center, radius)``, a ball the camera must stay in (where the training
            cameras were; default: ``FREE_RADIUS_SCALE * scale`` around the objects' centroid).
        room: the room the camera must stay inside (walls), if the scene has one.
        boxes: per object an oriented bounding box or None; where given, the shot size is measured
            on the box's projected corners and "inside the object" means inside the box (spheres
            overestimate the extent of elongated objects).
    """

    def __init__(
        self,
        centers: np.ndarray,
        radii: np.ndarray,
        up: np.ndarray,
        scale: float,
        intrinsics: tuple[np.ndarray, int, int] | None = None,
        free_space: tuple[np.ndarray, float] | None = None,
        room: Room | None = None,
        boxes: list[Box | None] | None = None,
    ):
        self.centers = np.asarray(centers, dtype=np.float64)
        self.radii = np.asarray(radii, dtype=np.float64)
        self.up = _unit(np.asarray(up, dtype=np.float64))
        self.K, self.width, self.height = intrinsics if intrinsics is not None else default_intrinsics()
        if free_space is None:
            free_space = (self.centers.mean(0), FREE_RADIUS_SCALE * scale)
        self.free_center, self.free_radius = np.asarray(free_space[0], dtype=np.float64), float(free_space[1])
        # Every object rests on a support and its bounding sphere reaches at least down to it, so the
        # highest sphere bottom bounds the support level from below (conservative with several supports).
        self.support = float(np.max(self.centers @ self.up - self.radii))
        self.scale = scale
        self.room = room
        self.boxes = list(boxes) if boxes is not None else [None] * len(self.centers)

    # -- candidate parameters ------------------------------------------------------------------

    def _distance_for_extent(self, radius: float, extent: float) -> float:
        fx, fy = self.K[0, 0], self.K[1, 1]
        tan_alpha = extent / max(2 * fx / self.width, 2 * fy / self.height)
        return radius / math.sin(math.atan(tan_alpha))

    def _elevations(self, c: Constraints) -> tuple[float, ...]:
        if c.elevation is not None:
            return _ELEVATION_CANDIDATES[c.elevation]
        if c.elevation_deg is not None:
            e = c.elevation_deg
            return tuple(float(np.clip(v, -89.0, 89.0)) for v in (e, e + 4.0, e - 4.0))
        return _FREE_ELEVATIONS

    # -- the search ----------------------------------------------------------------------------

    def find(self, constraints: Constraints, subjects: list[int], fronts: list[np.ndarray | None]) -> Camera | None:
        """The first camera of :meth:`candidates`, or None."""
        return next(self.candidates(constraints, subjects, fronts), None)

    def candidates(self, constraints: Constraints, subjects: list[int], fronts: list[np.ndarray | None]) -> Iterator[Camera]:
        """Cameras satisfying ``constraints`` on the proxies, the preferred first.

        ``subjects`` are the object indices of ``constraints.subjects`` (same order, primary
        first) and ``fronts`` their front directions (None for symmetric subjects).
        """
        sc = constraints.subjects
        p = subjects[0]
        S, r = self.centers[p], self.radii[p]
        front = fronts[0] if fronts[0] is not None else any_horizontal(self.up)
        if sc[0].view is not None:
            view = sc[0].view
            azimuths = [a + d for d in _VIEW_OFFSETS if abs(d) < view_tolerance_deg(view) for a in VIEW_SIDES[view]]
        elif len(subjects) > 1:
            azimuths = self._pair_azimuths(S, self.centers[subjects[1]], front)
        else:
            azimuths = [0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 120.0, -120.0, 150.0, -150.0, 180.0]
        extents = _SHOT_EXTENTS[sc[0].shot] if sc[0].shot is not None else _FREE_EXTENTS
        distances = [self._distance_for_extent(r, t) for t in extents]
        if self.boxes[p] is not None:  # a box images smaller than its sphere: try closer cameras too
            distances = [d * k for k in (1.0, 0.8, 0.62) for d in distances]
        if len(subjects) > 1:
            separation = np.linalg.norm(self.centers[subjects[1]] - S)
            d0 = separation * self.K[0, 0] / (0.4 * self.width)
            pair = [d0 * k for k in (1.0, 0.75, 1.35, 1.8)]
            distances = pair if sc[0].shot is None else distances + pair
        roll = math.radians(constraints.roll_deg or 0.0)
        for elevation, azimuth, distance in product(self._elevations(constraints), azimuths, distances):
            C = S + distance * view_direction_np(azimuth, elevation, front, self.up)
            if not self._free(C, p):
                continue
            T = self._aim(C, S, roll, region_target(sc[0].region))
            if T is not None and self._accept(T, constraints, subjects):
                yield Camera(T, self.K, self.width, self.height, name="witness")

    def _pair_azimuths(self, S1: np.ndarray, S2: np.ndarray, front: np.ndarray) -> list[float]:
        """Azimuths around S1, the most perpendicular to the line S1-S2 first."""
        delta = S2 - S1
        delta = delta - (delta @ self.up) * self.up
        candidates = [float(a) for a in np.arange(-180.0, 180.0, 15.0)]
        if np.linalg.norm(delta) < 1e-12:
            return candidates
        delta = _unit(delta)
        return sorted(candidates, key=lambda a: abs(view_direction_np(a, 0.0, front, self.up) @ delta))

    def _aim(self, C: np.ndarray, S: np.ndarray, roll: float, point: tuple[float, float]) -> np.ndarray | None:
        """Pose at ``C`` (with ``roll``) whose image of ``S`` falls on the normalised ``point``."""
        target = S.copy()
        fx, fy = self.K[0, 0], self.K[1, 1]
        for _ in range(12):
            T = look_at_np(C, target, self.up, roll)
            q = T[:3, :3] @ S + T[:3, 3]
            if q[2] <= 0:
                return None
            u = (fx * q[0] / q[2] + self.K[0, 2]) / self.width
            v = (fy * q[1] / q[2] + self.K[1, 2]) / self.height
            du, dv = point[0] - u, point[1] - v
            if abs(du) < 1e-4 and abs(dv) < 1e-4:
                return T
            distance = np.linalg.norm(target - C)
            target = target - (du * self.width / fx * T[0, :3] + dv * self.height / fy * T[1, :3]) * distance
        return T

    def _disc(self, T: np.ndarray, index: int) -> tuple[np.ndarray, float, float] | None:
        """Image disc (centre in pixels, radius in pixels) and depth of an object; None if behind."""
        q = T[:3, :3] @ self.centers[index] + T[:3, 3]
        dist = np.linalg.norm(q)
        r = self.radii[index]
        if q[2] <= 1e-9 or dist <= r:
            return None
        centre = np.array([self.K[0, 0] * q[0] / q[2] + self.K[0, 2], self.K[1, 1] * q[1] / q[2] + self.K[1, 2]])
        radius = 0.5 * (self.K[0, 0] + self.K[1, 1]) * math.tan(math.asin(r / dist))
        return centre, radius, float(dist)

    def _free(self, C: np.ndarray, primary: int) -> bool:
        """Whether a camera centre is in free space: outside every object's bounding sphere (the
        primary's oriented box instead, when given, so elongated subjects allow close-ups), above
        the support level (by the margins above), within ``free_radius`` and inside the room."""
        for j, box in enumerate(self.boxes):
            if j == primary and box is not None:
                inside = box.contains(C, 0.15 * self.radii[j])
            else:
                inside = np.linalg.norm(self.centers[j] - C) < 1.15 * self.radii[j]
            if inside:
                return False
        radius = self.radii[primary]
        if C @ self.up < self.support + max(SUPPORT_MARGIN * radius, SUPPORT_MARGIN_SCALE * self.scale):
            return False
        if self.room is not None and not self.room.contains(C, ROOM_MARGIN * radius):
            return False
        return bool(np.linalg.norm(C - self.free_center) <= self.free_radius)

    def _box_extent(self, T: np.ndarray, index: int) -> float | None:
        """Shot extent of an object's box: max(w / W, h / H) of its projected corners' bounding
        box clipped to the frame; None when a corner is not in front of the camera."""
        q = self.boxes[index].corners() @ T[:3, :3].T + T[:3, 3]
        if np.any(q[:, 2] <= 1e-3 * self.radii[index]):
            return None
        u = np.clip(self.K[0, 0] * q[:, 0] / q[:, 2] + self.K[0, 2], 0, self.width)
        v = np.clip(self.K[1, 1] * q[:, 1] / q[:, 2] + self.K[1, 2], 0, self.height)
        return max(np.ptp(u) / self.width, np.ptp(v) / self.height)

    def _accept(self, T: np.ndarray, c: Constraints, subjects: list[int]) -> bool:
        up = self.up
        if c.roll_deg is not None and abs(T[2, :3] @ up) > math.cos(math.radians(ROLL_MIN_TILT_DEG)):
            return False
        W, H = self.width, self.height
        for sc, index in zip(c.subjects, subjects):
            q = T[:3, :3] @ self.centers[index] + T[:3, 3]
            if q[2] < 1.05 * self.radii[index]:
                return False  # not entirely in front of the camera
            disc = self._disc(T, index)
            if disc is None:
                return False
            centre, radius, dist = disc
            points = centre + radius * _GRID
            inside = points[(points[:, 0] >= 0) & (points[:, 0] <= W) & (points[:, 1] >= 0) & (points[:, 1] <= H)]
            if len(inside) < 0.5 * len(_GRID) and (sc.shot != "close-up" or len(inside) < 0.25 * len(_GRID)):
                return False  # mostly out of frame
            if sc.region is not None:
                x0, y0, x1, y1 = REGIONS[sc.region]
                x, y = inside[:, 0].mean() / W, inside[:, 1].mean() / H
                m = REGION_MARGIN
                if not (x0 + m <= x <= x1 - m and y0 + m <= y <= y1 - m):
                    return False
            if sc.shot is not None:
                lo, hi = SHOT_SIZES[sc.shot]
                extent = (
                    self._box_extent(T, index)
                    if self.boxes[index] is not None
                    else (max(np.ptp(inside[:, 0]) / W, np.ptp(inside[:, 1]) / H))
                )
                if extent is None:
                    return False
                if not SHOT_LOW_FACTOR * lo + SHOT_MARGIN <= extent <= hi - SHOT_MARGIN:
                    return False
            for j in range(len(self.centers)):
                if j == index:
                    continue
                other = self._disc(T, j)
                if other is None or other[2] - self.radii[j] >= dist:
                    continue  # behind the camera, or entirely behind the subject's centre
                overlap = _circle_overlap(float(np.linalg.norm(other[0] - centre)), radius, other[1])
                if overlap > MAX_OCCLUDED * math.pi * radius * radius:
                    return False
        return True
