"""The photographic constraint vocabulary shared by the instruction generator, the parser, the
pseudo labels and the ground-truth checker, so all of them mean the same thing by "on the left"
or "seen from its right".

Angles are in degrees here (they appear in files); view angles follow DESIGN §3: azimuth 0 is in
front of the subject, +90 at its own right; elevation > 0 is above, looking down; roll > 0 dips
the camera's right side.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

from .errors import InputError

# Where a subject's centre must lie, as normalised [x0, y0, x1, y1] boxes (origin top-left).
REGIONS: dict[str, tuple[float, float, float, float]] = {
    "left": (0.0, 0.0, 0.45, 1.0),
    "right": (0.55, 0.0, 1.0, 1.0),
    "center": (0.3, 0.3, 0.7, 0.7),
    "top": (0.0, 0.0, 1.0, 0.45),
    "bottom": (0.0, 0.55, 1.0, 1.0),
    "left third": (0.0, 0.0, 1 / 3, 1.0),
    "center third": (1 / 3, 0.0, 2 / 3, 1.0),
    "right third": (2 / 3, 0.0, 1.0, 1.0),
    "upper left": (0.0, 0.0, 0.45, 0.45),
    "upper right": (0.55, 0.0, 1.0, 0.45),
    "lower left": (0.0, 0.55, 0.45, 1.0),
    "lower right": (0.55, 0.55, 1.0, 1.0),
}

# Shot size: the subject's projected extent, max(bbox width / W, bbox height / H), in [lo, hi].
SHOT_SIZES: dict[str, tuple[float, float]] = {
    "close-up": (0.55, 10.0),  # fills most of the frame; partly cut off is fine
    "medium": (0.25, 0.6),
    "wide": (0.0, 0.3),
}

# View side: acceptable azimuths of the camera around the subject (any one of them), each within
# view_tolerance_deg(side). "side", "three-quarter" and "back-three-quarter" leave the side open.
VIEW_SIDES: dict[str, tuple[float, ...]] = {
    "front": (0.0,),
    "back": (180.0,),
    "left": (-90.0,),
    "right": (90.0,),
    "front-left": (-45.0,),
    "front-right": (45.0,),
    "back-left": (-135.0,),
    "back-right": (135.0,),
    "three-quarter": (-45.0, 45.0),
    "back-three-quarter": (-135.0, 135.0),
    "side": (-90.0, 90.0),
    # "slightly from the left": off the front (or back) towards a side, short of the diagonal.
    "front-slight-left": (-20.0,),
    "front-slight-right": (20.0,),
    "back-slight-left": (-160.0,),
    "back-slight-right": (160.0,),
    # "from its right side, a little towards the front": off a side towards the front (back), as far
    # from that side as the slight sides above are from the front.
    "left-slight-front": (-70.0,),
    "left-slight-back": (-110.0,),
    "right-slight-front": (70.0,),
    "right-slight-back": (110.0,),
    # "dead on", "directly from the left", "tail on": one end exactly, at half the tolerance.
    "front-exact": (0.0,),
    "back-exact": (180.0,),
    "left-exact": (-90.0,),
    "right-exact": (90.0,),
    # "anything but the front", "not from behind": every azimuth outside that end's tolerance,
    # centred on the opposite end.
    "not-front": (180.0,),
    "not-back": (0.0,),
    "not-left": (90.0,),
    "not-right": (-90.0,),
}
VIEW_TOLERANCE_DEG = 30.0
# The slight sides lie between two sides 45 degrees apart: a narrower tolerance keeps them from
# accepting the straight front (back) or the full diagonal (-20 +- 15 is -35 to -5).
VIEW_TOLERANCES_DEG: dict[str, float] = {
    "front-slight-left": 15.0,
    "front-slight-right": 15.0,
    "back-slight-left": 15.0,
    "back-slight-right": 15.0,
    "left-slight-front": 15.0,
    "left-slight-back": 15.0,
    "right-slight-front": 15.0,
    "right-slight-back": 15.0,
    "front-exact": 15.0,
    "back-exact": 15.0,
    "left-exact": 15.0,
    "right-exact": 15.0,
}
# The side a negated end leaves ("anything but the front" is "not-front"): every azimuth outside
# the end's tolerance.
NEGATED_ENDS = {end: f"not-{end}" for end in ("front", "back", "left", "right")}
VIEW_TOLERANCES_DEG |= {side: 180.0 - VIEW_TOLERANCE_DEG for side in NEGATED_ENDS.values()}
# The ends a degree word may make exact: "<end>-exact" is that end within the narrower tolerance.
EXACT_ENDS = ("front", "back", "left", "right")

# Elevation of the camera above the subject's horizon, [lo, hi] degrees.
ELEVATIONS: dict[str, tuple[float, float]] = {
    "eye level": (-12.0, 12.0),
    "slightly above": (8.0, 30.0),
    "high angle": (25.0, 60.0),
    "bird's-eye": (60.0, 90.0),
    "low angle": (-60.0, -8.0),
    "worm's-eye": (-90.0, -50.0),
    "top-down": (80.0, 90.0),  # straight down: within 10 degrees of vertical
    "slightly below": (-30.0, -8.0),
}
EXPLICIT_ELEVATION_TOLERANCE_DEG = 10.0
ROLL_TOLERANCE_DEG = 5.0
MIN_VISIBLE_FRACTION = 0.5  # share of the subject's pixels not hidden by other objects
# Share of the subject's projection inside the frame (the rest is cut off by the frame edge);
# a close-up may cut off more.
MIN_IN_FRAME_FRACTION = 0.6
CLOSE_UP_MIN_IN_FRAME_FRACTION = 0.35


def min_in_frame_fraction(shot: str | None) -> float:
    """Share of a subject's projection that must lie inside the frame for a shot size (or None)."""
    return CLOSE_UP_MIN_IN_FRAME_FRACTION if shot == "close-up" else MIN_IN_FRAME_FRACTION


def view_tolerance_deg(view: str) -> float:
    """Half-width in degrees accepted around each azimuth of the view side ``view``."""
    return VIEW_TOLERANCES_DEG.get(view, VIEW_TOLERANCE_DEG)


def arc_deg(a: float, b: float) -> float:
    """The angle between the azimuths ``a`` and ``b`` degrees, in [0, 180]."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


def view_within(narrow: str, wide: str) -> bool:
    """Whether every azimuth the view side ``narrow`` accepts is one ``wide`` accepts too
    ("front-exact" within "front", not "front-slight-left": -35 lies outside +-30)."""
    tn, tw = view_tolerance_deg(narrow), view_tolerance_deg(wide)
    return all(any(arc_deg(a, b) + tn <= tw + 1e-9 for b in VIEW_SIDES[wide]) for a in VIEW_SIDES[narrow])


def _check_name(value: str | None, table: dict, field_name: str) -> None:
    if value is not None and value not in table:
        raise InputError(f"{field_name} {value!r} is unknown; expected one of {sorted(table)}")


@dataclass
class SubjectConstraint:
    """What the instruction asks of one subject.

    Attributes:
        name: scene vocabulary name (matched by name, never by position).
        role: "primary" or "secondary".
        region: key of :data:`REGIONS` or None.
        shot: key of :data:`SHOT_SIZES` or None.
        view: key of :data:`VIEW_SIDES` or None (asymmetric subjects only).
    """

    name: str
    role: str = "primary"
    region: str | None = None
    shot: str | None = None
    view: str | None = None

    def __post_init__(self) -> None:
        _check_name(self.region, REGIONS, "region")
        _check_name(self.shot, SHOT_SIZES, "shot")
        _check_name(self.view, VIEW_SIDES, "view")
        if self.role not in ("primary", "secondary"):
            raise InputError(f"role {self.role!r} is unknown; expected 'primary' or 'secondary'")


@dataclass
class Constraints:
    """The machine-checkable content of one instruction.

    Attributes:
        subjects: one entry per subject, the primary first.
        elevation: key of :data:`ELEVATIONS`, or None.
        elevation_deg: an explicit elevation ("from 30 degrees above"), or None.
        roll_deg: requested roll (a dutch angle, > 0 clockwise), 0 for "level", or None.
    """

    subjects: list[SubjectConstraint] = field(default_factory=list)
    elevation: str | None = None
    elevation_deg: float | None = None
    roll_deg: float | None = None

    def __post_init__(self) -> None:
        _check_name(self.elevation, ELEVATIONS, "elevation")
        if self.elevation is not None and self.elevation_deg is not None:
            raise InputError("give either a named elevation or elevation_deg, not both")

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> Constraints:
        try:
            subjects = [SubjectConstraint(**s) for s in data.get("subjects", [])]
            return cls(
                subjects=subjects,
                elevation=data.get("elevation"),
                elevation_deg=data.get("elevation_deg"),
                roll_deg=data.get("roll_deg"),
            )
        except TypeError as err:  # unknown or missing keys
            raise InputError(f"malformed constraints {data!r}: {err}") from None

    def elevation_range(self) -> tuple[float, float] | None:
        """Accepted elevation interval in degrees, if any."""
        if self.elevation is not None:
            return ELEVATIONS[self.elevation]
        if self.elevation_deg is not None:
            e, tol = self.elevation_deg, EXPLICIT_ELEVATION_TOLERANCE_DEG
            return (max(-90.0, e - tol), min(90.0, e + tol))
        return None
