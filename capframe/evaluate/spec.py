"""Hand-written instruction specs (the held-out set, issue #15) and how a camera is judged on them.

A spec is what an instruction means to a photographer, in the words of the constraint vocabulary
(:mod:`capframe.constraints`) plus two ranges the vocabulary has no name for:

* ``azimuth: [lo, hi]`` on a subject (degrees, DESIGN §3: 0 in front, +90 at its own right,
  ±180 behind): the arc from ``lo`` up to ``hi`` (``lo < hi``, at most 360 wide; ``[165, 195]`` is
  "directly from behind"), for degree words such as "slightly from its left" or "dead on";
* ``elevation_range: [lo, hi]`` (degrees, > 0 above) for elevations such as "slightly below".

One instruction of a spec file (YAML mapping)::

    id: ho-room-forward-03            unique in the set
    text: "show me the TV straight on, filling the frame"
    kind: size                        one of KINDS: the main difficulty
    feasible: true                    false: no free camera can satisfy it
    reason: occluded by wall          only when infeasible: one of REASONS
    subjects:                         primary first (role defaults: first primary, rest secondary)
      - {name: television, shot: close-up, azimuth: [-15, 15]}
    elevation: slightly above         or elevation_deg: 90, or elevation_range: [-30, -8] (one at most)
    roll_deg: 0                       optional
    absent: [piano]                   names the scene does not have (reason "unknown subject")
    note: free text                   optional

:func:`parse_spec` validates one entry (one-line :class:`InputError` naming the file, the
instruction and the field); :func:`judge` checks a camera against a spec with a
:class:`~capframe.measure.ConstraintChecker` (rows of the vocabulary, then ``azimuth`` and
``elevation`` rows for the ranges); :func:`clearance` says where a camera centre is physically
impossible in a synthetic scene (below the support, behind a wall, inside an object's box).
Evaluation only: the method never reads a spec.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import torch

from ..constraints import ELEVATIONS, REGIONS, SHOT_SIZES, VIEW_SIDES, Constraints, SubjectConstraint
from ..errors import InputError
from ..geometry import any_horizontal, view_angles
from ..measure import CheckReport, CheckRow, ConstraintChecker, interval_distance, wrap_deg
from ..scene import Camera
from .ground_truth import GroundTruth, GTObject

# The main difficulty of an instruction (what a failure on it is counted under).
KINDS = ("phrasing", "view", "height", "size", "framing", "typo", "roll", "subject")
# Why an infeasible instruction cannot be satisfied.
REASONS = ("unknown subject", "occluded by wall", "no free space", "below floor")

_TOP_KEYS = (
    "id",
    "text",
    "kind",
    "feasible",
    "reason",
    "subjects",
    "elevation",
    "elevation_deg",
    "elevation_range",
    "roll_deg",
    "absent",
    "note",
)
_SUBJECT_KEYS = ("name", "role", "region", "shot", "view", "azimuth")


@dataclass
class InstructionSpec:
    """One hand-written instruction and its machine-checkable meaning.

    Attributes:
        id: unique id; scene: the scene id it belongs to; text: the instruction as written.
        kind: one of :data:`KINDS`; feasible: whether some free camera satisfies it;
        reason: one of :data:`REASONS` when infeasible, else None.
        constraints: the vocabulary part (what :class:`~capframe.measure.ConstraintChecker` checks).
        azimuths: subject name -> ``(lo, hi)`` accepted azimuth arc in degrees.
        elevation_range: ``(lo, hi)`` accepted elevation in degrees around the primary, or None.
        absent: subject names the instruction uses that the scene does not have.
        note: a remark for the reader.
    """

    id: str
    scene: str
    text: str
    kind: str
    feasible: bool
    reason: str | None
    constraints: Constraints
    azimuths: dict[str, tuple[float, float]] = field(default_factory=dict)
    elevation_range: tuple[float, float] | None = None
    absent: tuple[str, ...] = ()
    note: str = ""

    @property
    def subject_names(self) -> list[str]:
        return [s.name for s in self.constraints.subjects]


def _fail(message: str, source: str, where: str) -> InputError:
    return InputError(f"{where}: {message}", source=source)


def _choice(entry: dict, key: str, options, source: str, where: str) -> str | None:
    value = entry.get(key)
    if value is not None and value not in options:
        raise _fail(f"{key!r} is {value!r}; expected one of {sorted(options)}", source, where)
    return value


def _number(value, key: str, source: str, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _fail(f"{key!r} is {value!r}; expected a number", source, where)
    return float(value)


def _range(value, key: str, bounds: tuple[float, float], max_width: float, source: str, where: str) -> tuple[float, float]:
    """A ``[lo, hi]`` pair of numbers inside ``bounds`` with ``0 < hi - lo <= max_width``."""
    if not isinstance(value, list) or len(value) != 2:
        raise _fail(f"{key!r} is {value!r}; expected [lo, hi] in degrees", source, where)
    lo, hi = (_number(v, key, source, where) for v in value)
    if not (bounds[0] <= lo < hi <= bounds[1]) or hi - lo > max_width:
        raise _fail(
            f"{key!r} is {value!r}; expected lo < hi within [{bounds[0]:g}, {bounds[1]:g}], at most {max_width:g} apart",
            source,
            where,
        )
    return lo, hi


def _subject(entry, index: int, source: str, where: str) -> tuple[SubjectConstraint, tuple[float, float] | None]:
    what = f"{where} subject {index}"
    if not isinstance(entry, dict):
        raise _fail(f"is {entry!r}; expected a mapping with 'name'", source, what)
    unknown = sorted(set(entry) - set(_SUBJECT_KEYS))
    if unknown or not isinstance(entry.get("name"), str) or not entry["name"].strip():
        raise _fail(f"needs a non-empty 'name'; unknown keys {unknown}; allowed {list(_SUBJECT_KEYS)}", source, what)
    what = f"{where} subject {entry['name']!r}"
    role = _choice(entry, "role", ("primary", "secondary"), source, what) or ("primary" if index == 0 else "secondary")
    region = _choice(entry, "region", REGIONS, source, what)
    shot = _choice(entry, "shot", SHOT_SIZES, source, what)
    view = _choice(entry, "view", VIEW_SIDES, source, what)
    azimuth = None
    if "azimuth" in entry:
        if view is not None:
            raise _fail("give either 'view' or 'azimuth', not both", source, what)
        azimuth = _range(entry["azimuth"], "azimuth", (-360.0, 360.0), 360.0, source, what)
    return SubjectConstraint(entry["name"], role, region, shot, view), azimuth


def parse_spec(entry, scene: str, source: str, index: int) -> InstructionSpec:
    """Validate one instruction entry of a spec file (module docstring); :class:`InputError`
    naming ``source``, the instruction and the field."""
    where = f"instruction {index}"
    if not isinstance(entry, dict):
        raise _fail(f"is {type(entry).__name__}; expected a mapping", source, where)
    if isinstance(entry.get("id"), str):
        where = f"instruction {index} ({entry['id']!r})"
    missing = [k for k in ("id", "text", "kind", "feasible") if k not in entry]
    unknown = sorted(set(entry) - set(_TOP_KEYS))
    if missing or unknown:
        raise _fail(f"missing keys {missing}, unknown keys {unknown}", source, where)
    for key in ("id", "text"):
        if not isinstance(entry[key], str) or not entry[key].strip():
            raise _fail(f"{key!r} is {entry[key]!r}; expected a non-empty string", source, where)
    kind = _choice(entry, "kind", KINDS, source, where)
    feasible = entry["feasible"]
    if not isinstance(feasible, bool):
        raise _fail(f"'feasible' is {feasible!r}; expected true or false", source, where)
    reason = _choice(entry, "reason", REASONS, source, where)
    if feasible == (reason is not None):
        raise _fail(f"'reason' is {reason!r}; an infeasible instruction needs one, a feasible one none", source, where)
    absent = entry.get("absent", [])
    if not isinstance(absent, list) or not all(isinstance(a, str) and a.strip() for a in absent):
        raise _fail(f"'absent' is {absent!r}; expected a list of names", source, where)
    if (reason == "unknown subject") != bool(absent):
        raise _fail(
            f"'absent' is {absent!r}; it names the missing subjects exactly when the reason is 'unknown subject'", source, where
        )
    subjects = entry.get("subjects", [])
    if not isinstance(subjects, list) or (not subjects and reason != "unknown subject"):
        raise _fail(f"'subjects' is {subjects!r}; expected a non-empty list", source, where)
    parsed = [_subject(s, i, source, where) for i, s in enumerate(subjects)]
    names = [s.name for s, _ in parsed]
    if len(set(names)) != len(names) or sum(s.role == "primary" for s, _ in parsed) > (1 if parsed else 0):
        raise _fail(f"subjects {names}: each named once, at most one primary", source, where)
    given = [k for k in ("elevation", "elevation_deg", "elevation_range") if entry.get(k) is not None]
    if len(given) > 1:
        raise _fail(f"give at most one of {given}", source, where)
    elevation = _choice(entry, "elevation", ELEVATIONS, source, where)
    elevation_deg = entry.get("elevation_deg")
    if elevation_deg is not None:
        elevation_deg = _number(elevation_deg, "elevation_deg", source, where)
        if abs(elevation_deg) > 90:
            raise _fail(f"'elevation_deg' is {elevation_deg:g}; expected a value in [-90, 90]", source, where)
    elevation_range = None
    if entry.get("elevation_range") is not None:
        elevation_range = _range(entry["elevation_range"], "elevation_range", (-90.0, 90.0), 180.0, source, where)
    roll = entry.get("roll_deg")
    roll = None if roll is None else _number(roll, "roll_deg", source, where)
    note = entry.get("note", "")
    if not isinstance(note, str):
        raise _fail(f"'note' is {note!r}; expected a string", source, where)
    constraints = Constraints([s for s, _ in parsed], elevation, elevation_deg, roll)
    azimuths = {s.name: a for s, a in parsed if a is not None}
    return InstructionSpec(
        entry["id"], scene, entry["text"], kind, feasible, reason, constraints, azimuths, elevation_range, tuple(absent), note
    )


# --- judging a camera -----------------------------------------------------------------------------


def _angles_deg(camera: Camera, obj, up: np.ndarray) -> tuple[float, float] | None:
    """Azimuth and elevation (degrees) of the camera centre around ``obj`` (its ``center`` and
    ``front``; any horizontal for a symmetric one); None at the object's centre."""
    centre = camera.center
    if np.linalg.norm(centre - obj.center) <= 1e-9 * max(obj.radius, 1e-300):
        return None
    front = obj.front if obj.front is not None else any_horizontal(up)
    t = lambda v: torch.tensor(np.asarray(v, dtype=np.float64))  # noqa: E731
    az, el = view_angles(t(centre), t(obj.center), t(front), t(up))
    return math.degrees(float(az)), math.degrees(float(el))


def arc_deviation(azimuth: float, lo: float, hi: float) -> float:
    """Angular distance (degrees) of ``azimuth`` outside the arc from ``lo`` up to ``hi``."""
    offset = (azimuth - lo) % 360.0
    if offset <= hi - lo:
        return 0.0
    return min(offset - (hi - lo), 360.0 - offset)


def _azimuth_row(name: str, arc: tuple[float, float], obj, camera: Camera, up: np.ndarray) -> CheckRow:
    target = {"azimuth_range_deg": list(arc)}
    if obj.front is None:
        return CheckRow("azimuth", name, None, None, target, None, "deg", "subject is symmetric: no azimuth")
    angles = _angles_deg(camera, obj, up)
    if angles is None:
        return CheckRow("azimuth", name, False, None, target, None, "deg", "camera at the subject centre")
    error = arc_deviation(angles[0], *arc)
    return CheckRow("azimuth", name, error == 0.0, wrap_deg(angles[0]), target, error, "deg")


def _elevation_row(name: str, rng: tuple[float, float], obj, camera: Camera, up: np.ndarray) -> CheckRow:
    target = {"range_deg": list(rng)}
    angles = _angles_deg(camera, obj, up)
    if angles is None:
        return CheckRow("elevation", name, False, None, target, None, "deg", "camera at the subject centre")
    error = interval_distance(angles[1], *rng)
    return CheckRow("elevation", name, error == 0.0, angles[1], target, error, "deg")


def judge(checker: ConstraintChecker, camera: Camera, spec: InstructionSpec) -> CheckReport:
    """The check of ``camera`` against ``spec``: the vocabulary rows of ``checker`` (visibility,
    region, shot, view, elevation, roll), then an ``azimuth`` row per subject with an azimuth
    range and an ``elevation`` row for an elevation range (around the primary subject). A spec
    that names only subjects the scene lacks (``absent``, no known subject) has nothing to see:
    one unsatisfied ``subject`` row says so, whatever the camera."""
    if not spec.constraints.subjects:
        row = CheckRow("subject", None, False, None, {"absent": list(spec.absent)}, None, note="the scene lacks the subject")
        return CheckReport([row], spec.id, spec.text)
    report = checker.check(camera, spec.constraints)
    up = checker.up
    for name, arc in spec.azimuths.items():
        report.rows.append(_azimuth_row(name, arc, checker.resolve(name), camera, up))
    if spec.elevation_range is not None:
        primary = next(s.name for s in spec.constraints.subjects if s.role == "primary")
        report.rows.append(_elevation_row(primary, spec.elevation_range, checker.resolve(primary), camera, up))
    report.instruction_id, report.text = spec.id, spec.text
    return report


# --- where a camera cannot be ---------------------------------------------------------------------


def support_level(truth: GroundTruth) -> float:
    """Height (along the up) of the surface the objects stand on: the lowest bottom of their
    oriented boxes (of their bounding spheres where a box is missing)."""
    up = truth.up
    bottoms = []
    for o in truth.objects:
        if o.box is not None:
            bottoms.append(float(o.box.center @ up - np.abs(o.box.axes @ up) @ o.box.half_extents))
        else:
            bottoms.append(float(o.center @ up - o.radius))
    return min(bottoms)


def below_support(truth: GroundTruth, centre: np.ndarray) -> bool:
    """Whether a camera centre lies below the surface the objects stand on: under the table top
    (within its extent) or under the floor it stands on, when the ground truth records the table
    (a camera beside a table, lower than its top, stands in the room); else below
    :func:`support_level` anywhere (the floor or ground, or a table top taken as an unbounded
    plane, which counts a camera beside the table as below it)."""
    height = float(centre @ truth.up)
    if truth.table is not None:
        table = truth.table
        return height < table.floor_height or (height < table.top_height and table.over(centre))
    return height < support_level(truth)


def clearance(
    truth: GroundTruth, walls: list[str], centre: np.ndarray, enclosed: Callable[[GTObject, np.ndarray], bool] | None = None
) -> list[str]:
    """Why a camera centre is physically impossible in a synthetic scene (empty when it is not):
    ``below the support`` (:func:`below_support`), ``behind the <±x|±y> wall`` (``walls`` lists
    the room's walls, ground_truth.json ``room.walls``), ``above the walls`` (a synthetic room has
    no ceiling, a real one has), ``inside <object>`` (inside its oriented box and, when
    ``enclosed`` is given, enclosed by its surface: ``enclosed(object, centre)``; a box is a
    loose bound of a tree, whose crown leaves open air below and around it, or of a sofa's seat)."""
    out = []
    if below_support(truth, centre):
        out.append("below the support")
    if truth.room is not None:
        local = truth.room.rotation.T @ centre
        half = truth.room.size / 2
        for wall in walls:
            axis, sign = "xy".index(wall[1]), 1.0 if wall[0] == "+" else -1.0
            if sign * local[axis] > half[axis]:
                out.append(f"behind the {wall} wall")
        if local[2] > truth.room.size[2]:
            out.append("above the walls (a real room's ceiling)")
    for o in truth.objects:
        if o.box is not None and o.box.contains(centre) and (enclosed is None or enclosed(o, centre)):
            out.append(f"inside {truth.reference_name(o)}")
    return out


__all__ = [
    "KINDS",
    "REASONS",
    "InstructionSpec",
    "arc_deviation",
    "below_support",
    "clearance",
    "judge",
    "parse_spec",
    "support_level",
]
