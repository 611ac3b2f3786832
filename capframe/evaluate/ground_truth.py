"""A synthetic scene's ``ground_truth.json`` (evaluation only; no stage of the method reads it).

::

    {"up": [x, y, z], "scale": s,
     "objects": [{"id": 0, "name": "teddy bear", "aliases": ["bear"], "color": "brown",
                  "center": [x, y, z], "radius": r, "front": [x, y, z] | null, "label": 0,
                  "box": {"center": [...], "axes": [[...], [...], [...]], "half_extents": [...]}   (optional)
                 }, ...],
     "room": {"size": [sx, sy, sz]} | null, "world_rotation": [[...], [...], [...]],   (optional)
     "table": {"box": {"center": [...], "axes": [...], "half_extents": [...]},
               "floor_height": h} | null}                                              (optional)

``label`` is the object's id in ``labels.npy``; ``front`` is null for symmetric objects; the
optional oriented ``box`` (rows of ``axes`` are unit directions) and ``room`` refine the
instruction generator's feasibility checks. The optional ``table`` is the table top the objects
of a tabletop scene stand on (its slab as a box whose third axis is the up) and the height (along
the up) of the floor under it. Subjects are referred to by name; when two objects
share a name they are told apart by colour ("the red armchair"), see
:meth:`GroundTruth.reference_name`.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..scene import Camera
from ..scene._io import as_array, as_float, read_json, require_keys

GROUND_TRUTH_FILE = "ground_truth.json"


@dataclass
class Box:
    """An optional oriented bounding box: ``center`` (3,), ``axes`` (3, 3) whose rows are unit
    world directions, ``half_extents`` (3,) along them."""

    center: np.ndarray
    axes: np.ndarray
    half_extents: np.ndarray

    def corners(self) -> np.ndarray:
        """The 8 corners, (8, 3)."""
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
        return self.center + (signs * self.half_extents) @ self.axes

    def contains(self, point: np.ndarray, margin: float = 0.0) -> bool:
        """Whether ``point`` lies inside the box grown by ``margin``."""
        return bool(np.all(np.abs(self.axes @ (point - self.center)) <= self.half_extents + margin))


@dataclass(eq=False)
class GTObject:
    """One object of the ground truth (lengths in scene units, directions unit vectors)."""

    id: int
    name: str
    center: np.ndarray
    radius: float
    label: int
    front: np.ndarray | None = None
    color: str | None = None
    aliases: list[str] = field(default_factory=list)
    box: Box | None = None

    @property
    def symmetric(self) -> bool:
        return self.front is None


@dataclass
class Room:
    """An optional room (synthetic ``room`` preset): the interior is the box ``[-sx/2, sx/2] x
    [-sy/2, sy/2] x [0, sz]`` in the frame whose axes are the columns of ``rotation`` (world =
    ``rotation @ local``), ``size = (sx, sy, sz)`` in scene units."""

    rotation: np.ndarray
    size: np.ndarray

    def contains(self, point: np.ndarray, margin: float = 0.0) -> bool:
        """Whether a world point lies inside the room, at least ``margin`` from walls, floor and top."""
        p = self.rotation.T @ point
        half = self.size / 2
        inside_walls = abs(p[0]) <= half[0] - margin and abs(p[1]) <= half[1] - margin
        return bool(inside_walls and margin <= p[2] <= self.size[2] - margin)


@dataclass
class Table:
    """An optional table top (synthetic ``tabletop`` preset): its slab ``box`` (rows of its axes:
    the top's two horizontal directions, then the up) and the ``floor_height`` (along the up) of
    the floor it stands on."""

    box: Box
    floor_height: float

    @property
    def top_height(self) -> float:
        """Height (along the up) of the top's upper surface."""
        return float(self.box.center @ self.box.axes[2] + self.box.half_extents[2])

    def over(self, point: np.ndarray) -> bool:
        """Whether ``point`` lies within the top's horizontal extent (above or below it)."""
        local = self.box.axes[:2] @ (point - self.box.center)
        return bool(np.all(np.abs(local) <= self.box.half_extents[:2]))


@dataclass
class GroundTruth:
    """Parsed ``ground_truth.json``."""

    up: np.ndarray
    scale: float
    objects: list[GTObject]
    room: Room | None = None
    table: Table | None = None

    def _name_counts(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for o in self.objects:
            counts[o.name.lower()] = counts.get(o.name.lower(), 0) + 1
        return counts

    def reference_name(self, obj: GTObject) -> str:
        """The name instructions use for ``obj``: its name, or ``"<color> <name>"`` when another
        object shares the name (``None`` colours fall back to the name)."""
        if self._name_counts()[obj.name.lower()] > 1 and obj.color:
            return f"{obj.color} {obj.name}"
        return obj.name

    def unique_aliases(self, obj: GTObject) -> list[str]:
        """Aliases of ``obj`` (colour-prefixed like its reference name) that resolve to it alone."""
        prefix = f"{obj.color} " if self.reference_name(obj) != obj.name else ""
        out = []
        for alias in obj.aliases:
            text = alias if alias.lower().startswith(prefix.lower()) else prefix + alias
            found = self._matches(text)
            fresh = text.lower() not in (obj.name.lower(), self.reference_name(obj).lower()) and text not in out
            if fresh and len(found) == 1 and found[0] is obj:
                out.append(text)
        return out

    def _candidates(self, obj: GTObject) -> set[str]:
        names = {obj.name, *obj.aliases}
        out = {n.lower() for n in names}
        if obj.color:
            out |= {f"{obj.color} {n}".lower() for n in names}
        return out

    def _matches(self, name: str) -> list[GTObject]:
        key = " ".join(name.lower().split())
        exact = [o for o in self.objects if o.name.lower() == key]
        if len(exact) == 1:
            return exact
        coloured = [o for o in self.objects if o.color and f"{o.color} {o.name}".lower() == key]
        if coloured:
            return coloured
        if exact:
            return exact
        return [o for o in self.objects if key in self._candidates(o)]

    def resolve(self, name: str, source: str | None = None) -> GTObject:
        """The object a subject name refers to: its unique name, ``"<color> <name>"``, or a unique
        alias (case-insensitive). :class:`InputError` naming the closest names otherwise."""
        found = self._matches(name)
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            options = sorted(self.reference_name(o) for o in found)
            raise InputError(f"subject {name!r} is ambiguous in this scene; say which: {options}", source=source)
        vocabulary = sorted({self.reference_name(o) for o in self.objects} | {a for o in self.objects for a in o.aliases})
        close = difflib.get_close_matches(name.lower(), [v.lower() for v in vocabulary], n=3, cutoff=0.4)
        close = [v for v in vocabulary if v.lower() in close] or vocabulary[:5]
        raise InputError(f"subject {name!r} is not in this scene; closest: {close}", source=source)


def parse_ground_truth(data: object, source: str | None = None) -> GroundTruth:
    """Validate and parse the JSON value of a ``ground_truth.json``."""
    source = source or GROUND_TRUTH_FILE
    require_keys(data, ("up", "objects"), "ground truth", source)
    up = as_array(data["up"], (3,), "'up'", source)
    if not np.isfinite(up).all() or np.linalg.norm(up) == 0:
        raise InputError(f"'up' is {up.tolist()}; expected a finite non-zero direction", source=source)
    scale = as_float(data.get("scale", 1.0), "'scale'", source)
    if not np.isfinite(scale) or scale <= 0:
        raise InputError(f"'scale' is {scale!r}; expected a positive number", source=source)
    if not isinstance(data["objects"], list) or not data["objects"]:
        raise InputError("'objects' must be a non-empty list", source=source)
    objects = []
    for i, entry in enumerate(data["objects"]):
        require_keys(entry, ("name", "center", "radius"), f"object {i}", source)
        name = entry["name"]
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"object {i}: 'name' is {name!r}; expected a non-empty string", source=source)
        what = f"object {i} ('{name}')"
        oid = entry.get("id", i)
        label = entry.get("label", oid)
        for key, value in (("id", oid), ("label", label)):
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise InputError(f"{what}: {key!r} is {value!r}; expected an integer >= 0", source=source)
        center = as_array(entry["center"], (3,), f"{what} 'center'", source)
        radius = as_float(entry["radius"], f"{what} 'radius'", source)
        if not np.isfinite(center).all() or not np.isfinite(radius) or radius <= 0:
            raise InputError(f"{what}: expected a finite 'center' and a positive 'radius'", source=source)
        front = entry.get("front")
        if front is not None:
            front = as_array(front, (3,), f"{what} 'front'", source)
            horizontal = front - (front @ up) * up / (up @ up)
            if not np.isfinite(front).all() or np.linalg.norm(horizontal) < 1e-9 * max(np.linalg.norm(front), 1e-300):
                raise InputError(
                    f"{what}: 'front' {front.tolist()} has no horizontal part; expected a facing direction", source=source
                )
            front = front / np.linalg.norm(front)
        aliases = entry.get("aliases", [])
        if not isinstance(aliases, list) or not all(isinstance(a, str) for a in aliases):
            raise InputError(f"{what}: 'aliases' is {aliases!r}; expected a list of strings", source=source)
        color = entry.get("color")
        if color is not None and not isinstance(color, str):
            raise InputError(f"{what}: 'color' is {color!r}; expected a string", source=source)
        box = _parse_box(entry.get("box"), what, source)
        objects.append(GTObject(oid, name, center, radius, label, front, color or None, list(aliases), box))
    ids = [o.id for o in objects]
    if len(set(ids)) != len(ids):
        raise InputError(f"duplicate object ids {sorted({i for i in ids if ids.count(i) > 1})}", source=source)
    up = up / np.linalg.norm(up)
    return GroundTruth(up=up, scale=scale, objects=objects, room=_parse_room(data, source), table=_parse_table(data, up, source))


def _parse_box(box: object, what: str, source: str) -> Box | None:
    """The optional ``box`` of an object: ``{"center", "axes" (rows), "half_extents"}``."""
    if box is None:
        return None
    require_keys(box, ("center", "axes", "half_extents"), f"{what} 'box'", source)
    center = as_array(box["center"], (3,), f"{what} 'box' 'center'", source)
    axes = as_array(box["axes"], (3, 3), f"{what} 'box' 'axes'", source)
    half = as_array(box["half_extents"], (3,), f"{what} 'box' 'half_extents'", source)
    if not (np.isfinite(center).all() and np.isfinite(half).all() and (half >= 0).all()):
        raise InputError(f"{what}: 'box' needs a finite centre and non-negative half extents", source=source)
    if not np.isfinite(axes).all() or np.abs(axes @ axes.T - np.eye(3)).max() > 1e-6:
        raise InputError(f"{what}: 'box' 'axes' are not orthonormal rows", source=source)
    return Box(center, axes, half)


def _parse_room(data: dict, source: str) -> Room | None:
    """The optional ``room`` (``{"size": [sx, sy, sz]}``) with ``world_rotation`` (3x3, world =
    R @ local, identity if absent); None when the scene has no room."""
    room = data.get("room")
    if room is None:
        return None
    require_keys(room, ("size",), "'room'", source)
    size = as_array(room["size"], (3,), "'room' 'size'", source)
    rotation = as_array(data.get("world_rotation", np.eye(3).tolist()), (3, 3), "'world_rotation'", source)
    if not np.isfinite(size).all() or (size <= 0).any():
        raise InputError(f"'room' 'size' is {size.tolist()}; expected three positive lengths", source=source)
    if np.abs(rotation @ rotation.T - np.eye(3)).max() > 1e-6:
        raise InputError("'world_rotation' is not a rotation matrix", source=source)
    return Room(rotation, size)


def _parse_table(data: dict, up: np.ndarray, source: str) -> Table | None:
    """The optional ``table`` (``{"box": {...}, "floor_height": h}``); the box's third axis must be
    the up and the floor below the top."""
    table = data.get("table")
    if table is None:
        return None
    require_keys(table, ("box", "floor_height"), "'table'", source)
    box = _parse_box(table["box"], "'table'", source)
    if box is None:
        raise InputError("'table' 'box' is null; expected the top's box", source=source)
    floor = as_float(table["floor_height"], "'table' 'floor_height'", source)
    if float(box.axes[2] @ up) < 1 - 1e-6:
        third = box.axes[2].tolist()
        raise InputError(f"'table' 'box' 'axes' third row is {third}; expected the up {up.tolist()}", source=source)
    result = Table(box, floor)
    if not (np.isfinite(floor) and floor < result.top_height):
        raise InputError(f"'table' 'floor_height' is {floor!r}; expected a finite height below the top", source=source)
    return result


def read_ground_truth(scene_dir: str | Path) -> GroundTruth:
    """Read ``<scene_dir>/ground_truth.json``; :class:`InputError` if it is missing or malformed."""
    path = Path(scene_dir) / GROUND_TRUTH_FILE
    if not path.is_file():
        raise InputError(
            f"{GROUND_TRUTH_FILE} not found; checks and instructions need a synthetic scene's ground truth", source=str(scene_dir)
        )
    return parse_ground_truth(read_json(path), str(path))


def ground_truth_cameras(scene_dir: str | Path) -> list[Camera]:
    """The training cameras recorded in ``ground_truth.json`` (also for scenes written without poses)."""
    data = read_json(Path(scene_dir) / GROUND_TRUTH_FILE)
    return [
        Camera(np.asarray(c["T_cw"]), np.asarray(c["K"]), c["width"], c["height"], name=c["name"])
        for c in data.get("cameras", [])
    ]
