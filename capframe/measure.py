"""One measurement layer: how well a camera satisfies an instruction's constraints, given each
subject's Gaussians, centre and front. Used by the method's own per-clause report (from its pseudo
labels), by Question-Evaluation's geometric answers and by the ground-truth checker
(:mod:`capframe.evaluate.check`, from the ground truth): one measurement, different sources.

==========  ===========================================================  ======================
constraint  measured                                                     satisfied when
==========  ===========================================================  ======================
visibility  share of the subject's own-render alpha that survives in      centre in front, mask
            the full render (membership composited as an extra channel),  non-empty, shares >= MIN
            and share of its projection inside the frame (not cut off);
            from a camera lower than the subject's base, at most the
            share of its points seen past the surface it stands on
            (Occupancy.seen_past_support), when an occupancy is given
region      centroid of the subject's visible (alpha-weighted) mask in     inside REGIONS[region]
            normalised image coordinates (projected centre if empty)
shot        max(bbox w / W, bbox h / H) of the own-render mask alpha>0.5  inside SHOT_SIZES[shot]
view        azimuth of the camera centre around the subject (DESIGN §3)   within view_tolerance_deg
                                                                          of one VIEW_SIDES entry
elevation   asin(p . up) around the primary subject's centre              in elevation_range()
roll        geometry.camera_roll                                          within ROLL_TOLERANCE_DEG
clearance   signed distance of the camera centre to geometry (walls,      >= 0 (not inside)
            floor, objects): scene.occupancy, when one is given, with
            its finer grid around a small primary subject
==========  ===========================================================  ======================

``error`` is the distance outside the accepted set for region (normalised units), shot and
elevation (0 when satisfied), and the angular deviation from the nearest asked angle for view and
roll (degrees). Roll is not applicable (``satisfied = None``) when the camera looks within 10° of
straight up or down; a view side asked of a symmetric subject is not applicable either. Masks are
rendered at a modest resolution (long side :data:`CHECK_LONG_SIDE`); angles do not depend on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import torch

from .constraints import (
    MIN_VISIBLE_FRACTION,
    REGIONS,
    ROLL_TOLERANCE_DEG,
    SHOT_SIZES,
    VIEW_SIDES,
    Constraints,
    min_in_frame_fraction,
    view_tolerance_deg,
)
from .errors import InputError, clip
from .geometry import any_horizontal, camera_roll, view_angles
from .render import NEAR_FRACTION, resolve_backend, scene_extent
from .render.masks import SubjectMask, subject_masks
from .scene import Camera, GaussianScene
from .scene.occupancy import Occupancy, solid_points


@dataclass
class Subject:
    """A subject as the measurements see it.

    Attributes:
        id: key of its membership mask (:class:`ConstraintChecker` ``members``).
        name: its scene name.
        center: (3,) its centre (view angles are measured around it).
        radius: its size (scene units): a camera closer than 1e-9 of it to the centre has no angles.
        front: (3,) unit front, or None for a symmetric subject.
    """

    id: int
    name: str
    center: np.ndarray
    radius: float
    front: np.ndarray | None


CHECK_LONG_SIDE = 256  # masks are rendered with this many pixels on the longer side
SIGHT_POINTS = 128  # points of a subject whose line of sight past its support is followed
ROLL_UNDEFINED_DEG = 10.0  # roll is not measured within this angle of looking straight up/down


def wrap_deg(angle: float) -> float:
    """An angle difference wrapped to (-180, 180]."""
    wrapped = math.fmod(angle + 180.0, 360.0)
    wrapped = wrapped + 360.0 if wrapped <= 0 else wrapped
    return wrapped - 180.0


@dataclass
class CheckRow:
    """The check of one constraint.

    Attributes:
        constraint: ``visibility``, ``region``, ``shot``, ``view``, ``elevation`` or ``roll``.
        subject: the subject's name (None for camera-wide constraints: roll).
        satisfied: True/False, or None when the constraint is not applicable to this camera/subject.
        measured: the measured value (a number, ``[x, y]`` for region), None if undefined.
        target: what was asked (JSON-able description).
        error: see the module docstring; None when undefined.
        unit: unit of ``measured`` and ``error``.
        note: a short human remark (why not applicable, fallbacks).
        details: further measurements (JSON-able).
    """

    constraint: str
    subject: str | None
    satisfied: bool | None
    measured: float | list[float] | None
    target: dict
    error: float | None
    unit: str = ""
    note: str = ""
    details: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "constraint": self.constraint,
            "subject": self.subject,
            "satisfied": self.satisfied,
            "measured": self.measured,
            "target": self.target,
            "error": self.error,
            "unit": self.unit,
            "note": self.note,
            "details": self.details,
        }


@dataclass
class CheckReport:
    """All rows of one check; ``all_satisfied`` ignores rows that are not applicable."""

    rows: list[CheckRow]
    instruction_id: str | None = None
    text: str | None = None

    @property
    def all_satisfied(self) -> bool:
        return all(r.satisfied for r in self.rows if r.satisfied is not None)

    def row(self, constraint: str, subject: str | None = None) -> CheckRow:
        """The row of ``constraint`` (for ``subject`` if given); KeyError if there is none."""
        for r in self.rows:
            if r.constraint == constraint and (subject is None or r.subject == subject):
                return r
        raise KeyError(f"no {constraint!r} row" + (f" for {subject!r}" if subject else ""))

    def to_dict(self) -> dict:
        applicable = [r for r in self.rows if r.satisfied is not None]
        return {
            "instruction_id": self.instruction_id,
            "text": self.text,
            "all_satisfied": self.all_satisfied,
            "satisfied": sum(bool(r.satisfied) for r in applicable),
            "applicable": len(applicable),
            "rows": [r.to_dict() for r in self.rows],
        }


def _finite(value: float) -> float | None:
    return float(value) if value is not None and math.isfinite(value) else None


def interval_distance(value: float, lo: float, hi: float) -> float:
    """Distance of ``value`` outside ``[lo, hi]`` (0 inside)."""
    return max(lo - value, value - hi, 0.0)


def box_distance(x: float, y: float, box: tuple[float, float, float, float]) -> float:
    """Distance of the point ``(x, y)`` outside ``box`` = ``[x0, y0, x1, y1]`` (0 inside)."""
    x0, y0, x1, y1 = box
    return math.hypot(max(x0 - x, 0.0, x - x1), max(y0 - y, 0.0, y - y1))


class ConstraintChecker:
    """Checks cameras against constraints, given each subject's Gaussians, centre and front.

    The ground-truth check (:class:`GroundTruthChecker`) and the method's own per-clause report
    (``capframe ground``, from its pseudo labels) are this one measurement with different sources.

    Args:
        gaussians: the whole scene (on the device to render on).
        objects: per subject name, its centre, radius and front (``Subject``).
        members: per object id (``Subject.id``), (N,) boolean mask of its Gaussians.
        up: (3,) unit world up.
        long_side: render size of the masks (longer side, pixels; default :data:`CHECK_LONG_SIDE`).
        backend: render backend (``auto``: gsplat on CUDA, else the CPU default, the compiled one).
        occupancy: the scene's free space; with it every check has a ``clearance`` row.
    """

    def __init__(
        self,
        gaussians: GaussianScene,
        objects: dict[str, Subject],
        members: dict[int, torch.Tensor],
        up: np.ndarray,
        *,
        long_side: int | None = None,
        backend: str = "auto",
        occupancy: Occupancy | None = None,
    ):
        self.backend = resolve_backend(backend)
        self.occupancy = occupancy
        device = "cuda" if self.backend == "gsplat" else "cpu"
        self.gaussians = gaussians.to(device=device)
        self.objects = objects
        self.members = {key: m.to(device) for key, m in members.items()}
        self.up = np.asarray(up, dtype=np.float64)
        self.long_side = long_side or CHECK_LONG_SIDE
        self.near = NEAR_FRACTION * scene_extent(self.gaussians.means.detach())
        self._around: dict[int, Occupancy] = {}
        self._points: dict[int, np.ndarray] = {}

    def resolve(self, name: str) -> Subject:
        """The object a constraint's subject name refers to."""
        if name not in self.objects:
            raise InputError(f"subject {name!r} is unknown here; known: {sorted(self.objects)}")
        return self.objects[name]

    def check(self, camera: Camera, constraints: Constraints) -> CheckReport:
        """Check ``camera`` against ``constraints``; see the module docstring for the measures."""
        if not constraints.subjects:
            raise InputError("the constraints name no subject; nothing to check")
        subjects = [(s, self.resolve(s.name)) for s in constraints.subjects]
        primary = next((obj for s, obj in subjects if s.role == "primary"), subjects[0][1])
        T = camera.T_cw
        centre = camera.center
        up = self.up

        masks = self._masks(camera, [obj for _, obj in subjects])
        rows: list[CheckRow] = []
        for (sc, obj), mask in zip(subjects, masks):
            z = float(T[2, :3] @ obj.center + T[2, 3])
            past_support = None
            if self.occupancy is not None:
                past_support = self.occupancy.seen_past_support(self._solid_points(obj), centre)
            rows.append(self._visibility(sc.name, mask, z, min_in_frame_fraction(sc.shot), past_support))
            if sc.region is not None:
                rows.append(self._region(sc.name, sc.region, mask, camera, obj, z))
            if sc.shot is not None:
                rows.append(self._shot(sc.name, sc.shot, mask))
            if sc.view is not None:
                rows.append(self._view(sc.name, sc.view, centre, obj, up))
        elevation_range = constraints.elevation_range()
        if elevation_range is not None:
            name = next((s.name for s, obj in subjects if obj is primary), subjects[0][0].name)
            rows.append(self._elevation(name, constraints, elevation_range, centre, primary, up))
        if constraints.roll_deg is not None:
            rows.append(self._roll(constraints.roll_deg, T, up))
        if self.occupancy is not None:
            rows.append(self._clearance(centre, primary))
        return CheckReport(rows)

    # --- measurements -------------------------------------------------------------------------

    def _masks(self, camera: Camera, objects: list[Subject]) -> list[SubjectMask]:
        """Per subject: its visible and own masks at the check resolution (see :func:`subject_masks`)."""
        member = torch.stack([self.members[obj.id] for obj in objects], 1)
        masks, _ = subject_masks(
            self.gaussians, camera.with_long_side(self.long_side), member, backend=self.backend, near=self.near
        )
        return masks

    def _solid_points(self, obj: Subject) -> np.ndarray:
        """(P, 3) float64 centres of up to :data:`SIGHT_POINTS` of the subject's solid Gaussians
        (evenly spread over their order; all of its Gaussians when none is solid), one array per
        subject."""
        if obj.id not in self._points:
            self._points[obj.id] = solid_points(self.gaussians, self.members[obj.id], SIGHT_POINTS)
        return self._points[obj.id]

    def _visibility(self, name: str, mask: SubjectMask, z: float, min_in_frame: float, past_support: float | None) -> CheckRow:
        fraction, in_frame, pixels = mask.visible_fraction, mask.in_frame, mask.pixels
        through_support = past_support is not None and past_support < fraction
        if through_support:
            fraction = past_support
        in_front = z > 0
        ok = in_front and pixels > 0 and fraction >= MIN_VISIBLE_FRACTION and in_frame >= min_in_frame
        notes = []
        if not in_front:
            notes.append("subject centre is behind the camera")
        if pixels == 0:
            notes.append("subject mask is empty (out of frame)")
        elif fraction < MIN_VISIBLE_FRACTION:
            notes.append(
                "subject is mostly seen through the surface it stands on" if through_support else "subject is mostly occluded"
            )
        if pixels > 0 and in_frame < min_in_frame:
            notes.append("subject is mostly cut off by the frame edge")
        return CheckRow(
            "visibility",
            name,
            ok,
            fraction,
            {"min_visible_fraction": MIN_VISIBLE_FRACTION, "min_in_frame_fraction": min_in_frame},
            max(MIN_VISIBLE_FRACTION - fraction, min_in_frame - in_frame, 0.0),
            "fraction",
            "; ".join(notes),
            {"in_front": in_front, "mask_pixels": pixels, "in_frame_fraction": in_frame, "seen_past_support": past_support},
        )

    def _region(self, name: str, region: str, mask: SubjectMask, camera: Camera, obj: Subject, z: float) -> CheckRow:
        box = REGIONS[region]
        target = {"region": region, "box": list(box)}
        note = ""
        if (centroid := mask.centroid()) is not None:
            x, y = centroid
            source = "visible mask"
        elif z > 0:
            p = camera.K @ (camera.T_cw[:3, :3] @ obj.center + camera.T_cw[:3, 3])
            x, y = p[0] / p[2] / camera.width, p[1] / p[2] / camera.height
            source = "projected centre"
            note = "mask empty: projected centre used"
        else:
            return CheckRow(
                "region",
                name,
                False,
                None,
                target,
                None,
                "normalised",
                "subject behind the camera: no image position",
                {"source": None},
            )
        error = box_distance(x, y, box)
        return CheckRow("region", name, error == 0.0, [x, y], target, error, "normalised", note, {"source": source})

    def _shot(self, name: str, shot: str, mask: SubjectMask) -> CheckRow:
        lo, hi = SHOT_SIZES[shot]
        target = {"shot": shot, "range": [lo, hi]}
        if mask.pixels == 0:
            return CheckRow(
                "shot", name, False, 0.0, target, interval_distance(0.0, lo, hi), "frame fraction", "subject mask is empty"
            )
        width, height = mask.bbox_size()
        extent = max(width, height)
        error = interval_distance(extent, lo, hi)
        return CheckRow(
            "shot", name, error == 0.0, extent, target, error, "frame fraction", "", {"bbox_width": width, "bbox_height": height}
        )

    def _view(self, name: str, view: str, centre: np.ndarray, obj: Subject, up: np.ndarray) -> CheckRow:
        target = {"view": view, "azimuths_deg": list(VIEW_SIDES[view]), "tolerance_deg": view_tolerance_deg(view)}
        if obj.front is None:
            return CheckRow("view", name, None, None, target, None, "deg", "subject is symmetric: no view side")
        angles = self._angles(centre, obj, up)
        if angles is None:
            return CheckRow("view", name, False, None, target, None, "deg", "camera at the subject centre")
        azimuth = angles[0]
        deviation = min(abs(wrap_deg(azimuth - a)) for a in VIEW_SIDES[view])
        return CheckRow("view", name, deviation <= view_tolerance_deg(view), azimuth, target, deviation, "deg")

    def _elevation(
        self, name: str, constraints: Constraints, rng: tuple[float, float], centre: np.ndarray, obj: Subject, up: np.ndarray
    ) -> CheckRow:
        target = {"range_deg": list(rng)}
        if constraints.elevation is not None:
            target["elevation"] = constraints.elevation
        else:
            target["elevation_deg"] = constraints.elevation_deg
        angles = self._angles(centre, obj, up)
        if angles is None:
            return CheckRow("elevation", name, False, None, target, None, "deg", "camera at the subject centre")
        error = interval_distance(angles[1], *rng)
        return CheckRow("elevation", name, error == 0.0, angles[1], target, error, "deg")

    def _clearance(self, centre: np.ndarray, primary: Subject) -> CheckRow:
        clearance = float(self._space_around(primary).clearance(torch.as_tensor(centre, dtype=torch.float64)))
        note = "" if clearance >= 0 else "camera inside geometry (an object, a wall or below the floor)"
        return CheckRow(
            "clearance", None, clearance >= 0, clearance, {"clearance": ">= 0"}, max(-clearance, 0.0), "scene units", note
        )

    def _space_around(self, primary: Subject) -> Occupancy:
        """The free space with a finer grid around ``primary`` where it is small for the scene's
        grid (:meth:`~capframe.scene.occupancy.Occupancy.around`; one per subject): half a voxel
        of a large outdoor grid from a toy car is open air, not inside the car. An occupancy that
        has its finer grid already (the method's own) is kept."""
        if self.occupancy.detail is not None:
            return self.occupancy
        if primary.id not in self._around:
            members = self.members[primary.id].nonzero()[:, 0].cpu()
            self._around[primary.id] = self.occupancy.around(self.gaussians, members)
        return self._around[primary.id]

    def _roll(self, roll_deg: float, T: np.ndarray, up: np.ndarray) -> CheckRow:
        target = {"roll_deg": roll_deg, "tolerance_deg": ROLL_TOLERANCE_DEG}
        forward_up = float(T[2, :3] @ up)
        if abs(forward_up) > math.cos(math.radians(ROLL_UNDEFINED_DEG)):
            return CheckRow(
                "roll",
                None,
                None,
                None,
                target,
                None,
                "deg",
                f"camera looks within {ROLL_UNDEFINED_DEG:g} deg of straight up/down: roll undefined",
            )
        roll = math.degrees(float(camera_roll(torch.as_tensor(T), torch.as_tensor(up))))
        deviation = abs(wrap_deg(roll - roll_deg))
        return CheckRow("roll", None, deviation <= ROLL_TOLERANCE_DEG, roll, target, deviation, "deg")

    def _angles(self, centre: np.ndarray, obj: Subject, up: np.ndarray) -> tuple[float, float] | None:
        """Azimuth and elevation (degrees) of the camera centre around ``obj``; None if coincident."""
        if np.linalg.norm(centre - obj.center) <= 1e-9 * max(obj.radius, 1e-300):
            return None
        f64 = dict(dtype=torch.float64)
        front = obj.front if obj.front is not None else any_horizontal(up)
        az, el = view_angles(
            torch.tensor(centre, **f64), torch.tensor(obj.center, **f64), torch.tensor(front, **f64), torch.tensor(up, **f64)
        )
        return math.degrees(float(az)), math.degrees(float(el))


def _format_target(row: CheckRow) -> str:
    t = row.target
    if row.constraint == "visibility":
        return f">= {t['min_visible_fraction']:.2f} visible"
    if row.constraint == "region":
        return f"{t['region']} [{', '.join(f'{v:.2f}' for v in t['box'])}]"
    if row.constraint == "shot":
        return f"{t['shot']} [{t['range'][0]:.2f}, {t['range'][1]:.2f}]"
    if row.constraint == "view":
        return f"{t['view']} ({'/'.join(f'{a:+.0f}' for a in t['azimuths_deg'])} ±{t['tolerance_deg']:.0f}°)"
    if row.constraint == "elevation":
        name = t.get("elevation") or f"{t['elevation_deg']:+.0f}°"
        return f"{name} [{t['range_deg'][0]:+.0f}°, {t['range_deg'][1]:+.0f}°]"
    if row.constraint == "clearance":
        return ">= 0 (outside geometry)"
    return f"{t['roll_deg']:+.0f}° ±{t['tolerance_deg']:.0f}°"


def _format_measured(row: CheckRow) -> str:
    m = row.measured
    if m is None:
        return "-"
    if row.constraint == "region":
        return f"({m[0]:.2f}, {m[1]:.2f})"
    if row.unit == "deg":
        return f"{m:+.1f}°"
    return f"{m:.2f}"


def format_report(report: CheckReport) -> str:
    """A readable table of the report."""
    header = ("constraint", "subject", "target", "measured", "error", "result")
    lines = []
    for r in report.rows:
        result = "n/a" if r.satisfied is None else ("ok" if r.satisfied else "FAIL")
        error = "-" if r.error is None else (f"{r.error:.1f}°" if r.unit == "deg" else f"{r.error:.3f}")
        lines.append(
            (
                r.constraint,
                r.subject or "-",
                _format_target(r),
                _format_measured(r),
                error,
                result + (f"  ({r.note})" if r.note else ""),
            )
        )
    widths = [max(len(row[i]) for row in [header, *lines]) for i in range(len(header) - 1)]
    fmt = lambda row: "  ".join(c.ljust(w) for c, w in zip(row[:-1], widths)) + "  " + row[-1]  # noqa: E731
    out = []
    if report.instruction_id or report.text:
        out.append(f"instruction {report.instruction_id or '-'}: {clip(report.text or '')}".rstrip())
    out += [fmt(header), *(fmt(row) for row in lines)]
    applicable = [r for r in report.rows if r.satisfied is not None]
    ok = sum(bool(r.satisfied) for r in applicable)
    out.append(f"all satisfied: {'yes' if report.all_satisfied else 'no'} ({ok}/{len(applicable)})")
    return "\n".join(out)
