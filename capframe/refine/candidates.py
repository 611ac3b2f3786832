"""A constraint-solving start: cameras computed in closed form from the pseudo labels.

The pseudo labels nearly define the wanted camera. For the primary subject (centroid ``c``,
radius ``r``, front ``f``, world up ``u``):

* **distance** from the asked extent ``e`` (share of the frame): a sphere of radius ``r`` at
  distance ``d`` spans ``2 k r / sqrt(d^2 - r^2)`` of the frame with ``k = max(fx / W, fy / H)``,
  so ``d = sqrt((2 k r / e)^2 + r^2)``; without a shot size, the distance of the reference view;
* **position** on the subject's view sphere, ``C = o + d v(azimuth, elevation)`` around its
  view centre ``o`` (:func:`view_centre`: the centroid moved along ``u`` to the middle of the
  subject's height, as the angles are meant; :func:`~capframe.geometry.view_direction`), at
  angles spread over the accepted ranges, or around the subject and at the reference view's
  elevation when none is asked; only when none of these is kept, at elevations over an
  occluder (:data:`OVER_ELEVATIONS_DEG`) when no elevation is asked, then at azimuths between
  the aimed and the accepted tolerance of an asked side (:data:`MARGIN_SPREAD`: a side facing
  a wall a little way off is seen only obliquely);
* **orientation**: ``c`` imaged at the centre of its region (or layout box), the horizon at the
  asked roll (:func:`aimed_pose`).

Each candidate is then checked against the scene's free space (:mod:`capframe.scene.occupancy`)
and by a low-resolution render of the whole scene: along its ray, from where it meets the floor
plane when that is nearer than its distance, the centre slides towards the subject
(:data:`SLIDES`) until it is free (positions below the subject that look up at it through an
occupied voxel, its support, rendered last), and the subject is seen there as the checker asks
(:data:`~capframe.constraints.MIN_VISIBLE_FRACTION` of it unhidden by other objects, enough of it
inside the frame); so an asked elevation below the subject, whose ray meets the floor, puts the
camera low near the floor, looking up, and a view behind a couch against a wall uses the gap
between them if one is there. A ray with no free position is dropped as ``inside geometry``, one
whose free positions all show the subject hidden as ``occluded``, or cut off by the frame as ``too
close``. The render, not the voxels, judges occlusion: a voxel is coarse next to small subjects
(a table top a voxel thick, a subject a few voxels wide). The kept ones are ranked by how far the
other subjects' projected centroids land from their regions (the closed form places only the
primary), then by how central their angles are in the accepted ranges; without regions, a kept
camera that misses another subject is first turned where it stands to the middle of them all
(:func:`_group_aim`), which keeps its view angles. When none is kept and the
primary has a region, the grid is tried once more aimed at the region's point nearest the frame
centre (a large subject aimed at a corner's centre overflows the frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch

from ..constraints import MIN_VISIBLE_FRACTION
from ..geometry import look_at, view_angles, view_direction
from ..measure import interval_distance
from ..render import NEAR_FRACTION, scene_extent
from ..render.lod import SCENE_CELL, cached_hierarchy, ray_cosine, subject_owner
from ..render.masks import subject_masks
from ..scene._io import finite_or_null
from ..scene.model import Camera, GaussianScene
from ..scene.occupancy import Occupancy, solid_points
from ..translate.labels import (
    ELEVATION_MARGIN_DEG,
    SHOT_MARGIN,
    PseudoLabels,
    SubjectLabel,
    accepted_azimuth_tolerance_deg,
    min_in_frame_share,
)

# The candidate grid: azimuths at these shares of the accepted tolerance around each asked
# azimuth, elevations at these shares of the accepted interval (central first; the ends reach a
# gentle low angle over a table's edge, or a steep one near the floor).
AZIMUTH_SPREAD = (0.0, -0.6, 0.6)
# When no camera of that grid is kept (a side facing a wall a little way off, reachable only
# obliquely), azimuths at these shares of the margin between the aimed and the accepted tolerance,
# beyond the aimed one on both sides: Refine then only has to hold the camera there.
# The same shares of the margin between the aimed and the accepted elevation interval, beyond
# either end, are tried last: a low angle at a large subject that rests low is reachable only
# near the interval's upper end (the floor bounds the distance at a steeper one, and nearer the
# subject overflows the frame), a high angle under a ceiling only near its lower end.
MARGIN_SPREAD = (0.5, 0.85)
ELEVATION_SPREAD = (0.5, 0.2, 0.8, 0.05, 0.95)
# Without an asked view side: azimuths around the subject, from the reference view's side.
AROUND_DEG = (0.0, 45.0, -45.0, 90.0, -90.0, 135.0, -135.0, 180.0)
# Without an asked elevation, the reference view's, within these bounds (degrees).
NATURAL_ELEVATION_DEG = (5.0, 35.0)
# Without an asked elevation, when no camera of the grid is kept (another object stands between
# the subject and every asked side at that elevation), these higher ones look over it.
OVER_ELEVATIONS_DEG = (50.0, 65.0)
# A centre slides towards the subject by these shares of its distance until it is free and the
# subject seen; never nearer than NEAREST_RADII subject radii (the subject's own voxels keep the
# camera out of it; a tall thin subject seen from the floor needs a camera inside its radius).
SLIDES = (1.0, 0.85, 0.7, 0.55, 0.4, 0.3, 0.2, 0.12)
NEAREST_RADII = 0.4
# Long side (pixels) of the renders that judge occlusion and framing, and how many free
# positions along one ray are rendered at most (the nearest ones are seldom better).
CHECK_LONG_SIDE = 64
# A kept camera misses the asked size when its subject's extent (frame fraction, at the check
# render's resolution) lies more than this outside the extent the checker accepts: the free
# space stopped it short of the asked distance.
SIZE_SLACK = 0.02
SIGHT_LOD_PIXELS = 2.0  # cells of the scene's level-of-detail cut span at most this (pixels)
RENDERS_PER_RAY = 3
# Once this many check renders are spent and a camera is kept, the search for one as asked stops
# (a size the free space cannot give, a second subject no angle frames, are searched at a bounded
# cost; a solve whose first kept cameras are as asked spends a few). The margin elevations are
# tried at the grid's azimuths only, which bounds what they add when nothing is kept.
RENDER_BUDGET = 36
# Above the floor plane a camera keeps the occupancy's floor margin (a quarter voxel), but no
# more than this share of the primary subject's height: in a large outdoor scene a voxel is
# most of a small subject's height (a toy car on a lawn), so a low angle at it needs a camera
# lower than that margin; the plane is measured from the floor's own Gaussians, to well under
# a voxel, and a camera above it is not below the ground.
FLOOR_MARGIN_HEIGHTS = 0.1
# Solid points of the primary subject that find the surface it stands on (a table top bounds a low
# angle as the floor does: :func:`_floor_elevation`).
SUPPORT_POINTS = 128


@dataclass
class Candidate:
    """One closed-form camera and its verdict.

    Attributes:
        camera: the camera (the template's intrinsics and size).
        azimuth_deg: its azimuth around the primary subject (around the reference view's side
            when the subject has no front).
        elevation_deg: its elevation around the primary subject.
        distance: distance from the camera to the subject's view centre (world units).
        clearance: signed clearance of the camera centre (world units; < 0 inside geometry).
        visible: share of the subject unhidden by other objects there (0 when not rendered).
        in_frame: share of the subject's projection inside the frame (0 when not rendered).
        layout_error: summed distance (frame fractions) of the other subjects' projected
            centroids outside their regions (1 for one behind the camera).
        size_miss: how far (frame fractions) the subject's extent lies outside the asked one
            (:func:`_size_miss`; 0 without a shot size or when not rendered).
        others_unseen: how many other subjects are not seen as the checker asks (hidden, or
            too much of them outside the frame) there; 0 when not rendered.
        status: ``kept``, ``inside geometry`` (no free position along its ray), ``occluded``
            (hidden at every free one) or ``too close`` (cut off by the frame at every free one).
    """

    camera: Camera
    azimuth_deg: float
    elevation_deg: float
    distance: float
    clearance: float
    visible: float
    in_frame: float
    layout_error: float
    status: str
    size_miss: float = 0.0
    others_unseen: int = 0

    @property
    def as_asked(self) -> bool:
        """Kept, at the asked size and with every other subject seen: the closed form's answer."""
        return self.status == "kept" and self.size_miss == 0.0 and self.others_unseen == 0

    def to_dict(self) -> dict:
        """The candidate as ``result.json``'s ``solved`` lists it; a number that is not finite
        (a degenerate placement) is null, so the result is still written."""
        return finite_or_null(
            {
                "azimuth_deg": round(self.azimuth_deg, 3),
                "elevation_deg": round(self.elevation_deg, 3),
                "distance": self.distance,
                "clearance": self.clearance,
                "visible": round(self.visible, 4),
                "in_frame": round(self.in_frame, 4),
                "layout_error": round(self.layout_error, 4),
                "size_miss": round(self.size_miss, 4),
                "others_unseen": self.others_unseen,
                "status": self.status,
            }
        )


def subject_radius(gaussians: GaussianScene, subject: SubjectLabel) -> float:
    """90th percentile of the subject's Gaussians' distances to its centroid (> 0)."""
    means = gaussians.means.detach()[torch.as_tensor(subject.gaussians, dtype=torch.long)].double()
    radius = float((means - torch.as_tensor(subject.centroid)).norm(dim=-1).quantile(0.9)) if len(means) else 0.0
    return max(radius, 1e-9)


def view_centre(gaussians: GaussianScene, subject: SubjectLabel, up: np.ndarray) -> tuple[np.ndarray, float]:
    """The point a subject's view angles are measured around, (3,), and its height (world
    units): its centroid moved along the unit ``up`` to the middle of its Gaussians' height span,
    and that span. A tree's crown holds most of its Gaussians, which lifts the centroid well
    above the middle of the tree that "from 20 degrees below" (and the checker) measures from;
    the centroid stays the point the layout aims at (the mask's centre of mass)."""
    means = gaussians.means.detach()[torch.as_tensor(subject.gaussians, dtype=torch.long)].double().numpy()
    centroid = np.asarray(subject.centroid, dtype=np.float64)
    if not len(means):
        return centroid, 0.0
    heights = means @ up
    low, high = float(heights.min()), float(heights.max())
    return centroid + ((low + high) / 2 - float(centroid @ up)) * up, high - low


def subject_floor_margin(height: float) -> float | None:
    """The height above the floor a camera keeps for a subject ``height`` tall (world units):
    :data:`FLOOR_MARGIN_HEIGHTS` of it (:meth:`Occupancy.height_kept` caps it at the occupancy's
    own margin), or None for a subject without height (the occupancy's margin)."""
    return FLOOR_MARGIN_HEIGHTS * height if height > 0 else None


def shot_distance(radius: float, extent: float, camera: Camera) -> float:
    """Distance at which a sphere of ``radius`` spans ``extent`` of ``camera``'s frame (its
    larger share of width or height)."""
    k = max(camera.K[0, 0] / camera.width, camera.K[1, 1] / camera.height)
    return math.sqrt((2.0 * k * radius / extent) ** 2 + radius**2)


def aimed_pose(
    centre: np.ndarray, target: np.ndarray, point: tuple[float, float], camera: Camera, up: np.ndarray, roll_deg: float
):
    """(4, 4) pose at ``centre`` whose ray through the normalised ``point`` of ``camera``'s frame
    runs to ``target``, with roll ``roll_deg`` (:func:`~capframe.geometry.camera_roll`'s).

    Solved in closed form (:func:`_level_aim`): the yaw and pitch of a camera rolled by
    ``roll_deg`` whose ray through ``point`` has the elevation and heading of ``target - centre``.
    Turning a camera that looks at ``target`` about its own axes instead tilts the horizon once
    it is pitched (a subject in the right third seen from 45 degrees above comes out rolled 18
    degrees). Where no pitch reaches (a point far off-centre vertically while looking nearly
    straight up or down, where roll is undefined anyway), that turn is the answer."""
    f64 = dict(dtype=torch.float64)
    ray = np.linalg.solve(camera.K, [point[0] * camera.width, point[1] * camera.height, 1.0])
    ray /= np.linalg.norm(ray)
    centre = np.asarray(centre, dtype=np.float64)
    R = _level_aim(np.asarray(target, dtype=np.float64) - centre, ray, np.asarray(up, dtype=np.float64), math.radians(roll_deg))
    if R is None:
        eye, aim, vertical = (torch.tensor(v, **f64) for v in (centre, target, up))
        R = _turn_onto(ray) @ look_at(eye, aim, vertical, math.radians(roll_deg)).numpy()[:3, :3]
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = -R @ centre
    return T


def _level_aim(sight: np.ndarray, ray: np.ndarray, up: np.ndarray, roll: float) -> np.ndarray | None:
    """(3, 3) world-to-camera rotation whose camera-frame ``ray`` (3,, unit; x right, y down, z
    forward) points along the world direction ``sight`` (3,), rolled by ``roll`` radians; None
    when ``sight`` is vertical or no pitch within +-90 degrees reaches its elevation.

    With heading ``h`` (horizontal, unit) and pitch ``p``, an unrolled camera has forward
    ``F = cos p h + sin p u``, right ``h x u``, down ``F x right``; rolling it maps the ray to
    ``(x', y', z')`` in those axes (x' = x cos r - y sin r, y' = x sin r + y cos r). Its world
    elevation is ``z' sin p - y' cos p``, set to the sight's ``sin a``: ``p = b + asin(sin a /
    rho)`` with ``(y', z') = rho (sin b, cos b)``. Its horizontal part lies at ``g = atan2(x',
    y' sin p + z' cos p)`` from ``h`` towards the right, so ``h`` is the sight's heading turned
    back by ``g``."""
    u = up / np.linalg.norm(up)
    sight = sight / np.linalg.norm(sight)
    level = sight - (sight @ u) * u
    if np.linalg.norm(level) < 1e-9:
        return None
    level /= np.linalg.norm(level)
    x, y, z = ray
    x_, y_ = x * math.cos(roll) - y * math.sin(roll), x * math.sin(roll) + y * math.cos(roll)
    rho, b = math.hypot(y_, z), math.atan2(y_, z)
    if abs(float(sight @ u)) > rho:
        return None
    pitch = b + math.asin(float(sight @ u) / rho)
    if math.cos(pitch) <= 1e-9:
        return None
    g = math.atan2(x_, y_ * math.sin(pitch) + z * math.cos(pitch))
    heading = math.cos(g) * level - math.sin(g) * np.cross(level, u)
    forward = math.cos(pitch) * heading + math.sin(pitch) * u
    right = np.cross(heading, u)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    return np.stack([c * right + s * down, -s * right + c * down, forward])


def _turn_onto(ray: np.ndarray) -> np.ndarray:
    """(3, 3) smallest rotation of camera coordinates taking the optical axis onto ``ray`` (3,,
    unit): a target on the axis moves to the ray's pixel."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, ray)
    s, c = np.linalg.norm(axis), float(z @ ray)
    if s <= 1e-12:
        return np.eye(3)
    k = axis / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * K + (1 - c) * K @ K


def _aim_point(subject: SubjectLabel) -> tuple[float, float]:
    box = subject.region or subject.box
    return ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2) if box is not None else (0.5, 0.5)


def _inner_aim_point(subject: SubjectLabel) -> tuple[float, float] | None:
    """The point of the subject's region nearest the frame centre, or None without a region or
    when that is its centre: a large subject aimed at a corner region's centre overflows the frame
    (a tall lamp seen from above under a low ceiling), and the checker asks only that its centroid
    lie in the region."""
    if subject.region is None:
        return None
    x0, y0, x1, y1 = subject.region
    inner = (min(max(0.5, x0), x1), min(max(0.5, y0), y1))
    return None if np.allclose(inner, _aim_point(subject)) else inner


def _angles_to_try(subject: SubjectLabel, reference_elevation: float) -> tuple[list[float], list[float]]:
    """Azimuths (degrees, about the subject's front) and elevations to place candidates at."""
    view = subject.view
    if view is not None and view.azimuths_deg:
        azimuths = [a + share * view.azimuth_tolerance_deg for a in view.azimuths_deg for share in AZIMUTH_SPREAD]
    else:
        azimuths = list(AROUND_DEG)
    if view is not None and view.elevation_range_deg is not None:
        lo, hi = view.elevation_range_deg
        elevations = [lo + share * (hi - lo) for share in ELEVATION_SPREAD]
    else:
        elevations = [min(max(reference_elevation, NATURAL_ELEVATION_DEG[0]), NATURAL_ELEVATION_DEG[1])]
    return azimuths, elevations


def _margin_azimuths(subject: SubjectLabel) -> list[float]:
    """Azimuths (degrees) between the aimed and the accepted tolerance of an asked view side
    (:data:`MARGIN_SPREAD`), tried when the grid of :func:`_angles_to_try` keeps no camera."""
    view = subject.view
    if view is None or not view.azimuths_deg:
        return []
    aimed = view.azimuth_tolerance_deg
    margin = accepted_azimuth_tolerance_deg(view) - aimed
    return [a + sign * (aimed + share * margin) for share in MARGIN_SPREAD for a in view.azimuths_deg for sign in (-1.0, 1.0)]


def _margin_elevations(subject: SubjectLabel) -> list[float]:
    """Elevations (degrees) between the aimed and the accepted interval of an asked elevation,
    beyond both ends (:data:`MARGIN_SPREAD`), the upper end first; tried when no camera of the
    grid is as asked. The accepted interval inverts :func:`~capframe.translate.labels.view_target`'s
    margin ``min(M, width / 4)`` on each side: an aimed width ``w`` had ``M`` taken off each end
    when ``w >= 2 M``, else ``w / 2``."""
    view = subject.view
    if view is None or view.elevation_range_deg is None:
        return []
    lo, hi = view.elevation_range_deg
    margin = ELEVATION_MARGIN_DEG if hi - lo >= 2 * ELEVATION_MARGIN_DEG else (hi - lo) / 2
    ends = [(hi + share * margin, lo - share * margin) for share in MARGIN_SPREAD]
    return [min(max(e, -89.0), 89.0) for pair in ends for e in pair]


def _floor_elevation(
    occupancy: Occupancy, origin: np.ndarray, distance: float, floor_margin: float | None, support_top: float | None
) -> float | None:
    """The steepest elevation (degrees, < 0) at which a camera ``distance`` from the view centre
    ``origin`` (3,) stays its floor margin above the floor plane and above ``support_top``, the
    height of the surface the subject stands on (None: none): ``-asin(h / distance)`` for a
    centre ``h`` above the higher of the two and the margin; None without either or when no
    elevation reaches it. Under a table top the subject is seen only past the top's edge, if at
    all (:meth:`Occupancy.seen_past_support`)."""
    heights = [_height_over_floor(occupancy, origin, floor_margin)]
    if support_top is not None:
        heights.append(float(occupancy.rotation[2] @ origin) - support_top - occupancy.height_kept(floor_margin))
    height = min((h for h in heights if h is not None), default=None)
    if height is None or height <= 0.0 or height >= distance:
        return None
    return -math.degrees(math.asin(height / distance))


def _above_floor(grid: list[float], margin: list[float], bounds: list[float | None]) -> tuple[list[float], list[float]]:
    """The grid's and the margin's elevations (degrees) no steeper than the first of ``bounds``
    (:func:`_floor_elevation` at the asked distance, then at the nearest accepted one, over the
    subject's support, then over the floor alone) that
    leaves any: below it the ray at that distance meets the floor, and the camera slides in to
    be free, larger in the frame than asked, at every azimuth alike (a low angle at a tall tree
    in a medium shot is reachable only near the interval's upper end). Both lists unchanged when
    no bound leaves any (no elevation gives an accepted size; sliding in gives the nearest)."""
    for bound in bounds:
        if bound is None:
            return grid, margin
        kept = [e for e in grid if e >= bound], [e for e in margin if e >= bound]
        if kept[0] or kept[1]:
            return kept
    return grid, margin


def _horizontal(vector: np.ndarray, up: np.ndarray) -> np.ndarray:
    flat = vector - (vector @ up) * up
    norm = np.linalg.norm(flat)
    if norm < 1e-9:  # straight above or below: any horizontal direction
        flat = np.cross(up, np.eye(3)[int(np.argmin(np.abs(up)))])
        norm = np.linalg.norm(flat)
    return flat / norm


def solve_candidates(
    gaussians: GaussianScene, labels: PseudoLabels, reference: Camera, occupancy: Occupancy, keep: int = 3
) -> list[Candidate]:
    """Closed-form cameras for the primary subject of ``labels`` (see the module docstring), best
    first: up to ``keep`` kept ones, then the dropped ones with their reason.

    Args:
        gaussians: the scene.
        labels: the pseudo labels (primary subject first).
        reference: the best retrieved view: its intrinsics and size are the candidates', and it
            sets the distance without a shot size, the elevation without an asked one, and the
            azimuth origin of a subject without a front.
        occupancy: the scene's free space.
    """
    subject, up = labels.subjects[0], labels.up
    centroid = subject.centroid
    radius = subject_radius(gaussians, subject)
    # Angles and distances are measured around the view centre; the camera aims at the centroid.
    origin, height = view_centre(gaussians, subject, up)
    floor_margin = subject_floor_margin(height)
    to_reference = reference.center - origin
    front = subject.front if subject.front is not None else _horizontal(to_reference, up)
    f64 = dict(dtype=torch.float64)
    _, reference_elevation = view_angles(
        torch.tensor(reference.center, **f64), torch.tensor(origin, **f64), torch.tensor(front, **f64), torch.tensor(up, **f64)
    )
    if subject.extent is not None:
        distance = shot_distance(radius, (subject.box[2] - subject.box[0]), reference)
    else:
        distance = max(float(np.linalg.norm(to_reference)), shot_distance(radius, 0.9, reference))
    azimuths, elevations = _angles_to_try(subject, math.degrees(float(reference_elevation)))
    sight = _Sight(gaussians, labels, reference)
    subject_voxels = occupancy.voxelize(gaussians.subset(torch.as_tensor(subject.gaussians, dtype=torch.long)))
    point = _aim_point(subject)
    # The grid, then (only while no camera is as asked) elevations over an occluder when none is
    # asked (the asked azimuths stay central), then the azimuths in the margin of an asked side,
    # then the elevations in the margin of an asked interval.
    over = [] if subject.view is not None and subject.view.elevation_range_deg is not None else OVER_ELEVATIONS_DEG
    margin_azimuths = _margin_azimuths(subject)
    margin_elevations = _margin_elevations(subject)
    if subject.extent is not None:
        # At the asked distance, else at the nearest whose size the checker still accepts.
        nearest = distance * (subject.box[2] - subject.box[0]) / _accepted_extent(subject.extent)[1]
        # Above the surface the subject stands on, else above the floor only (past a table's edge).
        support_top = occupancy.support_top(solid_points(gaussians, torch.as_tensor(subject.gaussians), SUPPORT_POINTS))
        tops = [support_top, None] if support_top is not None else [None]
        bounds = [_floor_elevation(occupancy, origin, d, floor_margin, top) for top in tops for d in (distance, nearest)]
        elevations, margin_elevations = _above_floor(elevations, margin_elevations, bounds)
    inner = _inner_aim_point(subject)
    phases = [
        [(e, a, point) for e in elevations for a in azimuths],
        [(e, a, point) for e in over for a in azimuths],
        [(e, a, point) for e in elevations for a in margin_azimuths],
        [(e, a, point) for e in margin_elevations for a in azimuths],
        # Last, the grid aimed nearer the frame centre, inside the asked region.
        [(e, a, inner) for e in elevations for a in azimuths] if inner is not None else [],
    ]
    starts = np.cumsum([len(p) for p in phases])[:-1]
    out = []
    for rank, (elevation, azimuth, point) in enumerate(angle for phase in phases for angle in phase):
        if rank in starts and any(c.as_asked for c in out):
            break
        if sight.renders >= RENDER_BUDGET and any(c.status == "kept" for c in out):
            break
        direction = view_direction(
            torch.tensor(math.radians(azimuth), **f64),
            torch.tensor(math.radians(elevation), **f64),
            torch.tensor(front, **f64),
            torch.tensor(up, **f64),
        ).numpy()
        along = distance if subject.extent is not None else _spread_distance(labels, direction, distance, point, reference)
        ray = _Ray(origin, centroid, direction, floor_margin, subject_voxels, float(up @ origin) - height / 2)
        camera, clearance, seen, status = _place(occupancy, sight, ray, along, radius, labels, point, reference)
        if status == "kept" and seen.others_unseen and all(s.region is None for s in labels.subjects):
            camera, seen = _group_aim(camera, seen, labels, reference, sight)
        camera.name = f"solved-{rank}"
        distance_out = float(np.linalg.norm(camera.center - origin))
        layout = _layout_error(camera, labels.subjects[1:])
        miss = _size_miss(seen.extent, subject.extent) if seen.rendered else 0.0
        verdict = (seen.visible, seen.in_frame, layout, status, miss, seen.others_unseen)
        out.append(Candidate(camera, azimuth, elevation, distance_out, clearance, *verdict))
        # Alone in the frame the first ones as asked are the best (the grid is ordered); with
        # other subjects the ranking by layout needs them all.
        if len(labels.subjects) == 1 and sum(c.as_asked for c in out) >= keep:
            break
    # Every other subject seen, then the asked size (a camera that slid in to be free, or saw a
    # subject cut off, is kept only behind those that need no such compromise), then the layout;
    # a stable sort: the grid order (central angles first) breaks ties.
    kept = sorted(
        (c for c in out if c.status == "kept"), key=lambda c: (c.others_unseen, round(c.size_miss, 1), round(c.layout_error, 2))
    )
    return kept[:keep] + [c for c in out if c.status != "kept"]


@dataclass
class _Seen:
    """What a check render of :class:`_Sight` measured (all zero when not rendered)."""

    visible: float = 0.0
    in_frame: float = 0.0
    extent: float = 0.0
    others_unseen: int = 0
    rendered: bool = False


class _Sight:
    """How the primary subject is seen from a camera: low-resolution renders of the whole scene
    and of the subject alone (:func:`~capframe.render.masks.subject_masks`, as the checker
    measures visibility), through a level-of-detail cut of the scene
    (:func:`~capframe.render.lod.cached_hierarchy`, built once per query and shared with Refine's
    occlusion phase) whose merged cells span at most :data:`SIGHT_LOD_PIXELS` pixels."""

    def __init__(self, gaussians: GaussianScene, labels: PseudoLabels, reference: Camera):
        self.near = NEAR_FRACTION * scene_extent(gaussians.means.detach())
        owner = subject_owner(len(gaussians), [torch.as_tensor(s.gaussians, dtype=torch.long) for s in labels.subjects])
        self.hierarchy = cached_hierarchy(gaussians, None, owner, torch.float32, SCENE_CELL)
        self.min_in_frame = [min_in_frame_share(s.extent) for s in labels.subjects]
        self.long_side = CHECK_LONG_SIDE
        self.renders = 0

    def __call__(self, camera: Camera) -> _Seen:
        """The primary subject's visible and in-frame shares and extent seen by ``camera``, and
        how many other subjects it does not see as the checker asks."""
        self.renders += 1
        camera = camera.with_long_side(self.long_side)
        canvas = camera.padded(camera.width // 2, camera.height // 2)  # subject_masks' own-render canvas
        focal = float(max(camera.K[0, 0], camera.K[1, 1]))
        centre = torch.as_tensor(camera.center, dtype=torch.float64)
        cosine = ray_cosine(canvas.K, canvas.width, canvas.height)
        gaussians, owner, _ = self.hierarchy.cut(centre, focal, SIGHT_LOD_PIXELS, 0.0, cosine)
        members = owner[:, None] == torch.arange(len(self.min_in_frame))
        masks, _ = subject_masks(gaussians, camera, members, backend="cpu", near=self.near)
        unseen = sum(not self._sees(m.visible_fraction, m.in_frame, k) for k, m in enumerate(masks[1:], 1))
        return _Seen(masks[0].visible_fraction, masks[0].in_frame, masks[0].extent(), unseen, True)

    def _sees(self, visible: float, in_frame: float, k: int = 0) -> bool:
        return visible >= MIN_VISIBLE_FRACTION and in_frame >= self.min_in_frame[k]

    def sees(self, seen: _Seen) -> bool:
        """Whether the primary subject is seen as the checker asks."""
        return self._sees(seen.visible, seen.in_frame)


@dataclass
class _Ray:
    """Where :func:`_place` puts a camera: at ``origin + t direction`` (the view centre, (3,),
    and a unit (3,) direction), aimed at ``target`` (the centroid, (3,)), kept ``floor_margin``
    above the floor (None: the occupancy's own margin); ``subject_voxels`` ((X, Y, Z) bool, the
    subject's own) do not block its line of sight; ``base`` is the height (along the up) of the
    subject's lowest Gaussian."""

    origin: np.ndarray
    target: np.ndarray
    direction: np.ndarray
    floor_margin: float | None = None
    subject_voxels: np.ndarray | None = None
    base: float = -math.inf


def _place(
    occupancy: Occupancy,
    sight: _Sight,
    ray: _Ray,
    distance: float,
    radius: float,
    labels: PseudoLabels,
    point: tuple[float, float],
    reference: Camera,
) -> tuple[Camera, float, _Seen, str]:
    """The first camera along ``ray``, at the :data:`SLIDES` shares of ``distance``, that is free
    (it keeps the occupancy's margins, the ray's above the floor: :meth:`Occupancy.slack`) and sees the
    subject (of the first :data:`RENDERS_PER_RAY` free ones, those below the subject's base whose
    straight line to the centroid crosses an occupied voxel, the subject's aside, last: a low
    angle at an object on a table finds free space under the table far out, where the table top
    hides it, and above the table only near it; nearer is not better elsewhere, between a subject
    and a wall behind it say), moved once along the ray towards the
    asked size when its render shows the subject at a size the checker does not accept
    (:func:`_sized_distance`; outwards no farther than the free space's edge, when it slid in)
    and the camera there is free and sees it too; one that shows the subject unhidden but cut off
    by the frame, with a blocked share farther out, moved out to the free space's edge
    (:func:`_free_edge`: looking down over an occluder under a ceiling, the first free share may be
    too near to frame a large subject) when the subject is seen there; else the first free one
    (``occluded`` or ``too close``), else the farthest (``inside geometry``). Returns it, its clearance, what its check
    render saw and its status."""

    def at(along: float) -> tuple[Camera, float, bool]:
        centre = ray.origin + max(along, NEAREST_RADII * radius) * ray.direction
        camera = reference.with_pose(aimed_pose(centre, ray.target, point, reference, labels.up, labels.roll_deg))
        # Written so that a NaN is never free.
        free = float(occupancy.slack(torch.as_tensor(centre), ray.floor_margin)) >= 0
        return camera, float(occupancy.clearance(torch.as_tensor(centre))), free

    distance = min(distance, _floor_reach(occupancy, ray))
    outermost, blocked, free_ones = None, None, []
    for share in SLIDES:
        along = share * distance
        camera, clearance, free = at(along)
        outermost = outermost or (camera, clearance, _Seen(), "inside geometry")
        if not free:
            blocked = along
            continue
        under = float(occupancy.rotation[2] @ camera.center) < ray.base
        hidden = under and occupancy.segment_blocked(camera.center, ray.target, ray.subject_voxels) > 0
        free_ones.append((hidden, along, camera, clearance, blocked))
    first_free = None
    # A stable sort: the positions seen through the support last, each group in the slides' order.
    for _, along, camera, clearance, blocked in sorted(free_ones, key=lambda position: position[0])[:RENDERS_PER_RAY]:
        seen = sight(camera)
        if sight.sees(seen):
            sized = _sized_distance(along, seen.extent, labels.subjects[0].extent)
            if sized is not None and sized > along and blocked is not None:
                # Outwards only as far as the free space's edge before the blocked share.
                sized = min(sized, _free_edge(lambda d: at(d)[2], along, blocked))
            if sized is not None and (moved := at(sized))[2] and sight.sees(seen_there := sight(moved[0])):
                return moved[0], moved[1], seen_there, "kept"
            return camera, clearance, seen, "kept"
        if seen.visible >= MIN_VISIBLE_FRACTION and blocked is not None and blocked > along:
            # Cut off by the frame with free space farther out: as far out as it stays free.
            edge = at(_free_edge(lambda d: at(d)[2], along, blocked))
            if sight.sees(seen_there := sight(edge[0])):
                return edge[0], edge[1], seen_there, "kept"
        first_free = first_free or (camera, clearance, seen, "occluded" if seen.visible < MIN_VISIBLE_FRACTION else "too close")
    return first_free or outermost


def _group_aim(camera: Camera, seen: _Seen, labels: PseudoLabels, reference: Camera, sight: _Sight) -> tuple[Camera, _Seen]:
    """``camera`` turned where it stands to look at the middle of all the subjects (the mean of
    the unit directions to their centroids) when its check render there shows more of the other
    subjects and still the primary as the checker asks; else ``camera`` and what it ``seen``.
    Where it stands fixes every view angle, and without regions no subject has a place in the
    frame: a car seen from behind, high over a tree beyond it, shows the tree only looking
    between the two."""
    directions = [np.asarray(s.centroid, dtype=np.float64) - camera.center for s in labels.subjects]
    middle = np.mean([d / np.linalg.norm(d) for d in directions], axis=0)
    if np.linalg.norm(middle) < 1e-6:  # subjects on opposite sides: no middle to look at
        return camera, seen
    turned = reference.with_pose(
        aimed_pose(camera.center, camera.center + middle, (0.5, 0.5), reference, labels.up, labels.roll_deg)
    )
    seen_turned = sight(turned)
    if sight.sees(seen_turned) and seen_turned.others_unseen < seen.others_unseen:
        return turned, seen_turned
    return camera, seen


def _floor_reach(occupancy: Occupancy, ray: _Ray) -> float:
    """How far along ``ray`` from its origin a camera stays its margin above the floor plane (inf
    when the ray does not descend to it): the slides of :func:`_place` start there, so that a low
    angle, whose ray meets the ground soon, samples the stretch above it (a distance of 74 at a
    car on a lawn put its last two slides at 15 and 9, and the free stretch at -9 degrees lay
    between 10 and 14.5). Not the ceiling plane: it is inferred from the walls' top, and the
    first slide at its margin would put the camera against it."""
    rise = float(occupancy.rotation[2] @ ray.direction)
    above = _height_over_floor(occupancy, ray.origin, ray.floor_margin)
    return above / -rise if rise < 0 and above is not None and above > 0 else math.inf


def _height_over_floor(occupancy: Occupancy, point: np.ndarray, floor_margin: float | None) -> float | None:
    """How high the world ``point`` (3,) stands above the floor plane less the height a camera
    keeps over it (:meth:`Occupancy.height_kept` of ``floor_margin``); None without a floor."""
    if not math.isfinite(occupancy.floor_height):
        return None
    return float(occupancy.rotation[2] @ point) - occupancy.floor_height - occupancy.height_kept(floor_margin)


def _accepted_extent(asked: tuple[float, float]) -> tuple[float, float]:
    """The extent interval the checker accepts for Refine's ``asked`` one (the
    :data:`~capframe.translate.labels.SHOT_MARGIN` it took off put back)."""
    return asked[0] / (1 + SHOT_MARGIN), asked[1] / (1 - SHOT_MARGIN)


def _size_miss(extent: float, asked: tuple[float, float] | None) -> float:
    """How far (frame fractions, beyond :data:`SIZE_SLACK`) ``extent`` lies outside the interval
    the checker accepts for the asked one (:func:`_accepted_extent`); 0 without one."""
    if asked is None:
        return 0.0
    return max(interval_distance(extent, *_accepted_extent(asked)) - SIZE_SLACK, 0.0)


def _free_edge(free, inner: float, outer: float, steps: int = 6) -> float:
    """The farthest distance found free by bisecting between ``inner`` (free) and ``outer`` (not
    free) in ``steps`` halvings; ``free(distance)`` tells whether the camera there is free."""
    for _ in range(steps):
        middle = (inner + outer) / 2
        inner, outer = (middle, outer) if free(middle) else (inner, middle)
    return inner


def _sized_distance(distance: float, extent: float, asked: tuple[float, float] | None) -> float | None:
    """The distance at which a subject seen at ``extent`` of the frame from ``distance`` spans
    the asked interval, a tenth of its width inside the nearer end (a projected size scales as
    one over the distance); None when the checker accepts ``extent`` already (Refine's size term
    finishes the work from there), or nothing was asked or seen. The closed form's distance
    assumes a sphere of the subject's radius, which a long or flat subject seen end-on or
    edge-on is not."""
    if asked is None or extent <= 0.0 or _size_miss(extent, asked) == 0.0:
        return None
    lo, hi = asked
    target = hi - 0.1 * (hi - lo) if extent > hi else lo + 0.1 * (hi - lo)
    return distance * extent / target


def _spread_distance(
    labels: PseudoLabels, direction: np.ndarray, distance: float, point: tuple[float, float], reference: Camera
) -> float:
    """The distance along ``direction`` at which the second subject's projected offset from the
    primary matches the offset of their regions' centres horizontally (offsets of points at a
    similar depth scale as one over the distance); ``distance`` when there is no second subject
    with a region, or it lands on the wrong side (the ranking then demotes the candidate)."""
    if len(labels.subjects) < 2 or labels.subjects[1].region is None:
        return distance
    primary, second = labels.subjects[0], labels.subjects[1]
    camera = reference.with_pose(
        aimed_pose(primary.centroid + distance * direction, primary.centroid, point, reference, labels.up, labels.roll_deg)
    )
    p = camera.T_cw[:3, :3] @ second.centroid + camera.T_cw[:3, 3]
    if p[2] <= 0:
        return distance
    offset = (camera.K[0] @ (p / p[2])) / camera.width - point[0]
    wanted = (second.region[0] + second.region[2]) / 2 - point[0]
    if offset * wanted <= 0 or abs(offset) < 0.02:
        return distance
    return distance * min(max(offset / wanted, 0.25), 4.0)


def _layout_error(camera: Camera, others: list[SubjectLabel]) -> float:
    """Summed distance (frame fractions) of the projected centroids of ``others`` outside their
    regions; 1 for each one behind the camera."""
    from ..measure import box_distance

    error = 0.0
    for subject in others:
        box = subject.region or subject.box
        if box is None:
            continue
        p = camera.T_cw[:3, :3] @ subject.centroid + camera.T_cw[:3, 3]
        if p[2] <= 0:
            error += 1.0
            continue
        u, v, _ = camera.K @ (p / p[2])
        error += box_distance(u / camera.width, v / camera.height, box)
    return error
