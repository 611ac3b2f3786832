"""A last search for a camera that satisfies every clause, drawn inside the accepted intervals.

Refine and the closed form aim at the middle of each asked interval. Where free space, occluders
and the frame pull against each other, the cameras that satisfy every clause may lie away from
that middle: a low angle at a car on a table is seen only from just under the table top's plane,
past its edge, where the medium shot needs the far end of the accepted distances; a wide shot in
a room fits only from where the room is deepest. When no refined, nudged or unrefined pose
satisfies every clause by the method's own report, cameras are drawn around the primary
subject's view centre, every other one local to the answer (what it holds kept nearly as it is,
what it fails moved just inside the accepted interval's nearer end, where the camera moves least)
and the others anywhere inside the intervals the report's rows accept:

* azimuth within the asked side's tolerance (:data:`INNER_SHARE` of it), elevation inside the
  asked range (an unasked angle near the answer's own, :data:`UNASKED_TURN_DEG`);
* distance scaled from the answer's so its measured extent lands inside the asked shot's range
  (the extent of a subject at distance ``d`` goes as ``1 / d``), else near the answer's;
* the subject's centroid imaged inside its asked region, else where the answer images it;
* the asked roll, else the answer's (:func:`~capframe.refine.candidates.aimed_pose` keeps it).

A draw whose centre is not in free space comes nearer along its direction until it is
(:data:`~capframe.refine.nudge.DISTANCE_SHARES`), else is dropped; the others are reported, up to
:data:`SEARCH_REPORTS` reports, and the first that satisfies every clause is the answer. Draws
are seeded: a query gives the same camera on every run.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
import torch

from ..measure import CheckReport, CheckRow, wrap_deg
from ..scene import Camera
from ..scene.occupancy import Occupancy
from .nudge import DISTANCE_SHARES, SpherePose, ViewSphere

SEARCH_REPORTS = 24  # own reports at most: a render each
SEARCH_DRAWS = 400  # draws at most, most of them rejected by free space alone
INNER_SHARE = 0.8  # the share of an interval's half-width drawn from: its edges are measured noisily
UNASKED_TURN_DEG = 30.0  # an unasked angle stays within this of the answer's own
UNASKED_SCALE = 0.2  # an unasked distance within exp(+-this) of the answer's
# A local draw (every other one) keeps what the answer holds within these: degrees, a share of
# the distance or extent, a share of the frame.
LOCAL_TURN_DEG = 4.0
LOCAL_SCALE = 0.05
LOCAL_SHIFT = 0.05
ELEVATION_LIMIT_DEG = 85.0  # the sphere has no azimuth at the poles
# An extent outside the asked shot's range is drawn between these shares of the nearer end (its
# reciprocals below a lower end): near the end, where the camera moves least.
NEAR_END_SHARES = (0.7, 0.95)
LOCAL_END_SHARES = (0.9, 0.98)  # ... and for a local draw, nearer still


def search_cameras(
    camera: Camera,
    report: CheckReport,
    primary: str,
    sphere: ViewSphere,
    measure: Callable[[Camera], CheckReport],
    occupancy: Occupancy | None = None,
    seed: int = 0,
) -> tuple[Camera, CheckReport] | None:
    """The first drawn camera whose ``measure`` (the own report) satisfies every clause, with
    that report; None when no draw does within the budget.

    Args:
        camera: the answer so far; what no clause asks is drawn near its own.
        report: its own report, whose rows of ``primary`` give the accepted intervals.
        primary: the primary subject's name.
        sphere: its view sphere (about its view centre, aimed at its centroid), where the
            cameras are drawn.
        measure: the own report of a camera.
        occupancy: the scene's free space; without it every draw is reported.
        seed: seeds the draws.
    """
    own = sphere.pose(camera)
    if own is None:
        return None
    rows = {row.constraint: row for row in report.rows if row.subject in (primary, None)}
    shares = DISTANCE_SHARES if occupancy is not None else (1.0,)

    def free(distance: float, direction: np.ndarray) -> bool:
        return occupancy is None or float(occupancy.clearance(torch.as_tensor(sphere.pivot + distance * direction))) > 0

    rng = np.random.default_rng(seed)
    reports = 0
    for draw in range(SEARCH_DRAWS):
        pose = _draw(own, rows, rng, local=draw % 2 == 0)
        direction = sphere.direction(pose.azimuth, pose.elevation)
        # Nearer along the same direction until free: a low angle is reached above the ground
        # only near the subject.
        reach = next((share * pose.distance for share in shares if free(share * pose.distance, direction)), None)
        if reach is None:
            continue
        drawn = sphere.camera(camera, dataclasses.replace(pose, distance=reach))
        drawn.name = f"{camera.name}-searched"
        measured = measure(drawn)
        if measured.all_satisfied:
            return drawn, measured
        reports += 1
        if reports >= SEARCH_REPORTS:
            break
    return None


def _draw(own: SpherePose, rows: dict[str, CheckRow], rng: np.random.Generator, local: bool) -> SpherePose:
    """One draw. ``local``: what a row asks and ``own`` holds stays near ``own`` (within
    :data:`LOCAL_TURN_DEG`, :data:`LOCAL_SCALE`, :data:`LOCAL_SHIFT`), what it fails is drawn
    just inside the accepted interval's nearer end; else each asked quantity anywhere inside its
    interval. What no row asks stays near ``own`` (:data:`UNASKED_TURN_DEG`, :data:`UNASKED_SCALE`)."""
    view, elevation, shot, region, roll = (rows.get(k) for k in ("view", "elevation", "shot", "region", "roll"))
    turn = LOCAL_TURN_DEG if local else UNASKED_TURN_DEG
    if view is not None:
        sides, tolerance = view.target["azimuths_deg"], view.target["tolerance_deg"]
        side = min(sides, key=lambda a: abs(wrap_deg(own.azimuth - a))) if local else float(rng.choice(sides))
        interval = _kept(view, side - tolerance, side + tolerance, local)
        azimuth = _near(side + wrap_deg(own.azimuth - side), *interval, turn, rng) if local else rng.uniform(*interval)
    else:
        azimuth = own.azimuth + rng.uniform(-turn, turn)
    if elevation is not None:
        interval = _kept(elevation, *elevation.target["range_deg"], local)
        pitch = _near(own.elevation, *interval, turn, rng) if local else rng.uniform(*interval)
    else:
        pitch = own.elevation + rng.uniform(-turn, turn)
    pitch = float(np.clip(pitch, -ELEVATION_LIMIT_DEG, ELEVATION_LIMIT_DEG))
    if shot is not None and shot.measured:
        # The extent goes as 1 / distance: the distance of an extent drawn inside the range.
        measured, (low, high) = float(shot.measured), shot.target["range"]
        if local:
            extent = _near(measured, *_nearest_part(measured, low, high, LOCAL_END_SHARES), LOCAL_SCALE * measured, rng)
        else:
            extent = rng.uniform(*_nearest_part(measured, low, high, NEAR_END_SHARES))
        distance = own.distance * measured / max(extent, 1e-3)
    else:
        scale = LOCAL_SCALE if local else UNASKED_SCALE
        distance = own.distance * math.exp(rng.uniform(-scale, scale))
    if region is not None:
        x0, y0, x1, y1 = region.target["box"]
        (xa, xb), (ya, yb) = _kept(region, x0, x1, local), _kept(region, y0, y1, local)
        if local:
            point = (_near(own.point[0], xa, xb, LOCAL_SHIFT, rng), _near(own.point[1], ya, yb, LOCAL_SHIFT, rng))
        else:
            point = (rng.uniform(xa, xb), rng.uniform(ya, yb))
    else:
        point = own.point
    turned = roll.target["roll_deg"] if roll is not None else own.roll
    return SpherePose(azimuth, pitch, distance, point, turned)


def _near(value: float, low: float, high: float, half_width: float, rng: np.random.Generator) -> float:
    """A draw within ``half_width`` of ``value`` clipped to ``[low, high]``; from ``value``
    outside the interval, within ``half_width`` inside its nearer end."""
    anchor = min(max(value, low), high)
    return rng.uniform(max(low, anchor - half_width), min(high, anchor + half_width))


def _kept(row: CheckRow, low: float, high: float, local: bool) -> tuple[float, float]:
    """Where a local draw of a quantity ``row`` measures may go: anywhere in ``[low, high]``
    when ``row`` holds (it stays near the answer's), else its middle :data:`INNER_SHARE` (the
    measured edge is noisy); a draw across the intervals always keeps to that middle."""
    return (low, high) if local and row.satisfied else _inner(low, high)


def _nearest_part(measured: float, low: float, high: float, shares: tuple[float, float]) -> tuple[float, float]:
    """The part of the accepted range ``[low, high]`` to draw an extent from: between ``shares``
    of the end nearer ``measured`` (their reciprocals at a lower end) when it lies outside,
    where the camera moves least; else its middle :data:`INNER_SHARE`."""
    if measured > high:
        return max(low, shares[0] * high), shares[1] * high
    if measured < low:
        return low / shares[1], min(high, low / shares[0])
    return _inner(low, high)


def _inner(low: float, high: float) -> tuple[float, float]:
    """The middle :data:`INNER_SHARE` of the interval ``[low, high]``."""
    middle, half = (low + high) / 2, INNER_SHARE * (high - low) / 2
    return middle - half, middle + half
