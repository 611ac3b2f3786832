"""Geometric pseudo labels: what Refine optimises towards.

Per subject: its Gaussians and centroid, a layout target (where its mask should sit and how big
it should be) and, when the instruction names a view, the set of acceptable view angles. Angles
are degrees here (the labels are written to files); view angles and roll follow DESIGN §3.

Layout targets come in two boxes, both normalised ``[x0, y0, x1, y1]`` (origin top-left):

* ``region``: where the subject's centre must lie (``capframe.constraints.REGIONS``);
* ``box``: where its mask should stay: a square of the requested shot's extent centred on the
  region, or the region itself when no shot size is asked.

A requested shot size also gives ``extent``, the interval the subject's projected extent should
fall in. Every subject must also stay in the frame: :func:`min_in_frame_share` is the share of
its projection that must land inside it.

With a requested roll both are rotated about their centres, as the paper rotates its layout box:
the scene appears rotated counter-clockwise by the roll, and so does an upright subject.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constraints import (
    REGIONS,
    SHOT_SIZES,
    VIEW_SIDES,
    VIEW_TOLERANCE_DEG,
    Constraints,
    min_in_frame_fraction,
    view_tolerance_deg,
)
from ..errors import InputError, clip
from ..scene._io import MadeFrom, as_array, as_direction, as_float, read_stage_json, require_keys, write_json

# Target extent (fraction of the frame) of a subject's box for each shot size: inside the
# checker's accepted interval (capframe.constraints.SHOT_SIZES) with a margin on both sides.
SHOT_EXTENT = {"close-up": 0.75, "medium": 0.42, "wide": 0.18}
# Relative margin inside a shot size's accepted extent interval.
SHOT_MARGIN = 0.15
# The centroid is pulled into the region shrunk by this much, so it does not end on the border.
REGION_MARGIN = 0.04
# View targets aim this far inside the accepted tolerance for the same reason (at most half of a
# narrow tolerance, so a slight side keeps a band to aim at).
VIEW_MARGIN_DEG = 12.0
ELEVATION_MARGIN_DEG = 4.0
# Refine keeps this much more of a subject in the frame than the checker asks: its canvas sees
# only a band of a quarter frame around the photo, so it overestimates the in-frame share.
IN_FRAME_MARGIN = 0.05

assert all(SHOT_SIZES[k][0] < v < SHOT_SIZES[k][1] for k, v in SHOT_EXTENT.items())


@dataclass
class ViewTarget:
    """Acceptable camera positions around a subject.

    Attributes:
        azimuths_deg: acceptable azimuths (any one), or empty when only the elevation matters.
        azimuth_tolerance_deg: half-width accepted around each azimuth.
        elevation_range_deg: accepted ``[lo, hi]`` elevation, or None.
    """

    azimuths_deg: tuple[float, ...] = ()
    azimuth_tolerance_deg: float = VIEW_TOLERANCE_DEG - VIEW_MARGIN_DEG
    elevation_range_deg: tuple[float, float] | None = None


@dataclass
class SubjectLabel:
    """Pseudo labels of one subject.

    Attributes:
        name: the subject's scene name.
        gaussians: (M,) indices of its Gaussians in the scene.
        centroid: (3,) mean of those Gaussians.
        front: (3,) its front direction, or None for a symmetric subject.
        region: normalised box for its centre, or None.
        box: normalised box for its mask, or None.
        extent: ``(lo, hi)`` interval for its projected extent (a shot size), or None.
        view: acceptable view angles, or None.
    """

    name: str
    gaussians: np.ndarray
    centroid: np.ndarray
    front: np.ndarray | None = None
    region: tuple[float, float, float, float] | None = None
    box: tuple[float, float, float, float] | None = None
    extent: tuple[float, float] | None = None
    view: ViewTarget | None = None


@dataclass
class PseudoLabels:
    """Everything Refine needs from Translate.

    Attributes:
        subjects: the subjects, primary first.
        up: (3,) unit world up.
        roll_deg: requested roll (0 = level, the default when none is asked).
        box_angle_deg: rotation of the layout boxes about their centres (the requested roll).
    """

    subjects: list[SubjectLabel]
    up: np.ndarray
    roll_deg: float = 0.0
    box_angle_deg: float = 0.0


def _shrink(box: tuple[float, ...], margin: float) -> tuple[float, float, float, float]:
    x0, y0, x1, y1 = box
    mx, my = min(margin, (x1 - x0) / 4), min(margin, (y1 - y0) / 4)
    return (x0 + mx, y0 + my, x1 - mx, y1 - my)


def layout_boxes(
    region: str | None, shot: str | None, box: tuple[float, float, float, float] | None = None
) -> tuple[tuple | None, tuple | None, tuple | None]:
    """Centre region, mask box and extent interval for a subject's region and shot size, or for
    an explicit target ``box`` (a model parser's layout, normalised ``[x0, y0, x1, y1]``).

    The mask box is a square (in frame fractions) of the shot's extent centred on the region,
    shifted to stay inside the frame; without a shot size it is the region itself. The extent
    interval is the checker's, narrowed by ``SHOT_MARGIN`` (and capped at the frame for a
    close-up, whose accepted interval is open-ended). An explicit box is the mask box itself and,
    shrunk by ``REGION_MARGIN``, the centre's region (the paper keeps the mask's centroid inside
    its layout box); the extent still follows the shot size when one is named.
    """
    if box is not None:
        return _shrink(box, REGION_MARGIN), tuple(box), _extent(shot)
    region_box = _shrink(REGIONS[region], REGION_MARGIN) if region else None
    if shot is None:
        return region_box, (REGIONS[region] if region else None), None
    size = SHOT_EXTENT[shot]
    cx, cy = ((region_box[0] + region_box[2]) / 2, (region_box[1] + region_box[3]) / 2) if region_box else (0.5, 0.5)
    cx = min(max(cx, size / 2), 1 - size / 2)
    cy = min(max(cy, size / 2), 1 - size / 2)
    return region_box, (cx - size / 2, cy - size / 2, cx + size / 2, cy + size / 2), _extent(shot)


def _extent(shot: str | None) -> tuple[float, float] | None:
    """The extent interval Refine aims for with a shot size (see :func:`layout_boxes`)."""
    if shot is None:
        return None
    lo, hi = SHOT_SIZES[shot]
    return (lo * (1 + SHOT_MARGIN), min(hi * (1 - SHOT_MARGIN), 0.95))


def view_target(view: str | None, elevation_range: tuple[float, float] | None) -> ViewTarget | None:
    """Acceptable view angles for a named view side and an elevation interval (either optional)."""
    if view is None and elevation_range is None:
        return None
    elevation = None
    if elevation_range is not None:
        lo, hi = elevation_range
        m = min(ELEVATION_MARGIN_DEG, (hi - lo) / 4)
        elevation = (max(lo + m, -89.0), min(hi - m, 89.0))
    if view is None:
        return ViewTarget(elevation_range_deg=elevation)
    tolerance = view_tolerance_deg(view)
    return ViewTarget(VIEW_SIDES[view], tolerance - min(VIEW_MARGIN_DEG, tolerance / 2), elevation)


def accepted_azimuth_tolerance_deg(target: ViewTarget) -> float:
    """The half-width the checker accepts around each of ``target``'s azimuths: its own
    tolerance plus the margin :func:`view_target` took off (``T - min(m, T / 2)`` inverted)."""
    aimed = target.azimuth_tolerance_deg
    return aimed + min(VIEW_MARGIN_DEG, aimed)


def min_in_frame_share(extent: tuple[float, float] | None) -> float:
    """Share of a subject's projection Refine keeps inside the frame: the checker's visibility
    minimum for its shot size plus :data:`IN_FRAME_MARGIN`. A close-up, which may be cut off
    more, is recognised by its extent interval, the only one that starts at or above the
    checker's close-up minimum."""
    close_up = extent is not None and extent[0] >= SHOT_SIZES["close-up"][0]
    return min_in_frame_fraction("close-up" if close_up else None) + IN_FRAME_MARGIN


def labels_from_constraints(
    constraints: Constraints,
    subjects: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray | None]],
    up: np.ndarray,
    boxes: dict[str, tuple[float, float, float, float]] | None = None,
) -> PseudoLabels:
    """Pseudo labels for parsed constraints.

    Args:
        constraints: what the instruction asks.
        subjects: per subject name, its Gaussian indices (M,), centroid (3,) and front (3,) or None.
        up: (3,) world up.
        boxes: per subject name, an explicit layout box (a model parser's ``ParsedSubject.box``)
            that replaces the box of its region and shot size.
    """
    roll = constraints.roll_deg or 0.0
    elevation = constraints.elevation_range()
    labels = []
    for k, subject in enumerate(constraints.subjects):
        if subject.name not in subjects:
            raise InputError(f"subject {subject.name!r} has no Gaussians; known: {sorted(subjects)}")
        index, centroid, front = subjects[subject.name]
        region, box, extent = layout_boxes(subject.region, subject.shot, (boxes or {}).get(subject.name))
        # The elevation is measured around the primary subject (the first).
        view = view_target(subject.view if front is not None else None, elevation if k == 0 else None)
        labels.append(
            SubjectLabel(
                subject.name,
                np.asarray(index),
                np.asarray(centroid, dtype=np.float64),
                None if front is None else np.asarray(front, dtype=np.float64),
                region,
                box,
                extent,
                view,
            )
        )
    return PseudoLabels(labels, np.asarray(up, dtype=np.float64), roll_deg=roll, box_angle_deg=roll)


def _shifted(box: tuple | None, dx: float, dy: float) -> tuple | None:
    return None if box is None else (box[0] + dx, box[1] + dy, box[2] + dx, box[3] + dy)


def perturbed(labels: PseudoLabels, box_noise: float, front_noise_deg: float, seed: int) -> PseudoLabels:
    """Pseudo labels with moderate noise (the sensitivity study): each box and region shifted by
    ``box_noise`` (frame fraction) in a random direction, each front turned about the up by
    ``front_noise_deg`` with a random sign; ``seed`` draws both."""
    from ..geometry import so3_exp

    rng = np.random.default_rng(seed)
    subjects = []
    for s in labels.subjects:
        angle = rng.uniform(0, 2 * np.pi)
        dx, dy = box_noise * np.cos(angle), box_noise * np.sin(angle)
        front = s.front
        if front is not None and front_noise_deg:
            import torch

            turn = np.radians(front_noise_deg) * rng.choice([-1.0, 1.0])
            R = so3_exp(torch.as_tensor(labels.up * turn, dtype=torch.float64)).numpy()
            front = R @ front
        subjects.append(dataclasses.replace(s, region=_shifted(s.region, dx, dy), box=_shifted(s.box, dx, dy), front=front))
    return dataclasses.replace(labels, subjects=subjects)


def _to_json(labels: PseudoLabels) -> dict:
    def subject(s: SubjectLabel) -> dict:
        view = (
            None
            if s.view is None
            else {
                "azimuths_deg": list(s.view.azimuths_deg),
                "azimuth_tolerance_deg": s.view.azimuth_tolerance_deg,
                "elevation_range_deg": None if s.view.elevation_range_deg is None else list(s.view.elevation_range_deg),
            }
        )
        return {
            "name": s.name,
            "gaussians": s.gaussians.tolist(),
            "centroid": s.centroid.tolist(),
            "front": None if s.front is None else s.front.tolist(),
            "region": None if s.region is None else list(s.region),
            "box": None if s.box is None else list(s.box),
            "extent": None if s.extent is None else list(s.extent),
            "view": view,
        }

    return {
        "format": 1,
        "up": labels.up.tolist(),
        "roll_deg": labels.roll_deg,
        "box_angle_deg": labels.box_angle_deg,
        "subjects": [subject(s) for s in labels.subjects],
    }


def write_pseudo_labels(labels: PseudoLabels, path: str | Path, made_from: MadeFrom | None = None) -> None:
    """``labels.json``; ``made_from`` (the stage files read) is recorded as its ``inputs``."""
    write_json(path, _to_json(labels) | {"inputs": {} if made_from is None else made_from.record()})


def _numbers(value, what: str, source: str, size: int | None = None) -> tuple | None:
    """None for null, else a JSON list of ``size`` (any number when None) finite numbers."""
    if value is None:
        return None
    if not isinstance(value, list):
        raise InputError(f"{what} is {clip(repr(value))}; expected a list of numbers or null", source=source)
    return tuple(as_array(value, (len(value) if size is None else size,), what, source).tolist())


def _box(value, what: str, source: str) -> tuple | None:
    """None for null, else a frame box ``[x0, y0, x1, y1]`` of finite numbers with some area."""
    box = _numbers(value, what, source, 4)
    if box is not None and not (box[0] < box[2] and box[1] < box[3]):
        raise InputError(f"{what} is {list(box)}; expected [x0, y0, x1, y1] with x0 < x1 and y0 < y1", source=source)
    return box


def read_pseudo_labels(path: str | Path, made_from: MadeFrom | None = None) -> PseudoLabels:
    """Pseudo labels written by :func:`write_pseudo_labels`, checked field by field (finite
    numbers, a world up, unit fronts with a horizontal direction, boxes with an area, a shot's
    extent with its box, at least one subject with Gaussians)."""
    source = str(path)
    data = read_stage_json(path, "labels", "capframe translate", ("subjects", "up", "roll_deg", "box_angle_deg"), made_from)
    if not isinstance(data["subjects"], list) or not data["subjects"]:
        raise InputError(f"subjects is {clip(repr(data['subjects']))}; expected at least one subject", source=source)
    up = as_direction(data["up"], "up", source)
    subjects = []
    for i, s in enumerate(data["subjects"]):
        what = f"subjects[{i}]"
        require_keys(s, ("name", "gaussians", "centroid", "front", "region", "box", "extent", "view"), what, source)
        try:
            index = np.asarray(s["gaussians"], dtype=np.int64)
        except (TypeError, ValueError):
            index = np.zeros((0,), dtype=np.int64)
        if not isinstance(s["name"], str) or index.ndim != 1 or index.size == 0 or index.min() < 0:
            raise InputError(f"{what}: expected a name and a non-empty list of Gaussian indices", source=source)
        v = s["view"]
        if v is not None:
            require_keys(v, ("azimuths_deg", "azimuth_tolerance_deg", "elevation_range_deg"), f"{what}.view", source)
            v = ViewTarget(
                _numbers(v["azimuths_deg"], f"{what}.view.azimuths_deg", source) or (),
                as_float(v["azimuth_tolerance_deg"], f"{what}.view.azimuth_tolerance_deg", source),
                _numbers(v["elevation_range_deg"], f"{what}.view.elevation_range_deg", source, 2),
            )
        front = None if s["front"] is None else as_direction(s["front"], f"{what}.front", source)
        # Azimuths are measured about the up from the front's horizontal part (subject_frame).
        if front is not None and np.linalg.norm(front - (front @ up) * up) < 1e-6:
            raise InputError(
                f"{what}.front is {front.tolist()}, along the up; expected a front with a horizontal part", source=source
            )
        box = _box(s["box"], f"{what}.box", source)
        extent = _numbers(s["extent"], f"{what}.extent", source, 2)
        if extent is not None and box is None:
            raise InputError(
                f"{what}.extent is {list(extent)} with box null; expected the shot's box with its extent", source=source
            )
        subjects.append(
            SubjectLabel(
                s["name"],
                index,
                as_array(s["centroid"], (3,), f"{what}.centroid", source),
                front,
                _box(s["region"], f"{what}.region", source),
                box,
                extent,
                v,
            )
        )
    return PseudoLabels(
        subjects,
        up,
        as_float(data["roll_deg"], "roll_deg", source),
        as_float(data["box_angle_deg"], "box_angle_deg", source),
    )
