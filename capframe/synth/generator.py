"""Synthetic 3DGS scenes with ground truth (``capframe synth``).

A scene is a few catalog objects (:mod:`capframe.synth.objects`) standing on a textured ground —
a table top, a room's floor with walls, or an outdoor lawn — and a set of training cameras
(orbit, forward-facing or walk-through), rendered with :func:`capframe.render.render`. The result
is a scene directory (docs/scene-directory.md) plus ``ground_truth.json`` for evaluation
(docs/synthetic-scenes.md).

Everything is built in metres in a z-up world with the objects around the origin, then the whole
world (Gaussians, cameras, up, fronts, centres) is rotated by the tilt rotation and multiplied by
``scale``. Same arguments, same bytes: all randomness comes from generators seeded with ``seed``
(one stream per concern, so that e.g. the number of views does not change the objects), JSON is
written with sorted keys and rounded floats, PNGs carry no metadata.
"""

from __future__ import annotations

import argparse
import dataclasses
import io
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pycolmap
import torch
from PIL import Image

from ..errors import InputError
from ..geometry import look_at, quat_multiply, rotmat_to_quat
from ..render import render
from ..scene import Camera, GaussianScene, write_cameras_json, write_colmap, write_ply
from ..scene._io import atomic_directory, atomic_write
from ..scene.directory import SceneMeta, SemanticObject, write_scene_meta, write_semantics
from .objects import (
    CATALOG,
    BuiltObject,
    ShapeBuilder,
    bake_lighting,
    build_object,
    catalog_names,
    lattice_hash,
    resolve_names,
)

PRESETS = ("tabletop", "room", "outdoor")
CAPTURES = ("orbit", "forward", "walkthrough")
DEFAULT_CAPTURE = {"tabletop": "orbit", "room": "forward", "outdoor": "orbit"}
GENERATOR_VERSION = 1
PIXELS_PER_SAMPLE = 2.8  # ground/wall sample spacing in the nearest training view, at density 1

# Objects drawn when none are given: (pool, (min, max) count), and per-preset size multipliers.
POOLS: dict[str, tuple[tuple[str, ...], tuple[int, int]]] = {
    "tabletop": (("mug", "teddy bear", "vase", "toy car", "ball", "cushion", "potted plant"), (2, 4)),
    "room": (
        ("armchair", "sofa", "coffee table", "floor lamp", "bookshelf", "television", "refrigerator", "potted plant"),
        (5, 6),
    ),
    "outdoor": (("bench", "tree", "traffic cone", "toy car", "ball", "teddy bear", "potted plant", "armchair"), (3, 5)),
}
SIZES: dict[str, dict[str, float]] = {
    "tabletop": {"ball": 0.6, "cushion": 0.75, "potted plant": 0.55},
    "room": {},
    "outdoor": {"toy car": 3.5, "ball": 2.5, "teddy bear": 4.0, "potted plant": 1.5},
}
BACKGROUNDS = {"tabletop": (0.86, 0.86, 0.84), "room": (0.80, 0.80, 0.82), "outdoor": (0.62, 0.76, 0.92)}

# Texture palettes: base colours (large blobs) and accents (small blobs) per surface.
_PALETTES = {
    "table": (
        [(0.62, 0.45, 0.30), (0.52, 0.36, 0.22), (0.70, 0.55, 0.38), (0.44, 0.29, 0.17)],
        [(0.30, 0.40, 0.55), (0.62, 0.30, 0.24), (0.85, 0.78, 0.55), (0.86, 0.84, 0.78)],
    ),
    "under": (
        [(0.45, 0.47, 0.50), (0.35, 0.37, 0.42), (0.55, 0.52, 0.48)],
        [(0.25, 0.30, 0.45), (0.65, 0.60, 0.50), (0.20, 0.20, 0.22)],
    ),
    "floor": (
        [(0.55, 0.40, 0.26), (0.46, 0.32, 0.20), (0.63, 0.48, 0.32)],
        [(0.32, 0.22, 0.14), (0.75, 0.62, 0.45), (0.42, 0.42, 0.48), (0.58, 0.34, 0.24)],
    ),
    "wall": (
        [(0.86, 0.83, 0.76), (0.78, 0.80, 0.82), (0.82, 0.77, 0.68)],
        [(0.60, 0.66, 0.74), (0.70, 0.74, 0.62), (0.78, 0.64, 0.58), (0.95, 0.93, 0.88)],
    ),
    "grass": (
        [(0.30, 0.48, 0.20), (0.20, 0.36, 0.12), (0.42, 0.54, 0.24)],
        [(0.66, 0.63, 0.56), (0.42, 0.33, 0.20), (0.72, 0.70, 0.64), (0.12, 0.22, 0.08), (0.58, 0.62, 0.30)],
    ),
    "bush": (
        [(0.18, 0.36, 0.14), (0.24, 0.44, 0.18), (0.30, 0.40, 0.16)],
        [(0.45, 0.55, 0.22), (0.10, 0.22, 0.08), (0.55, 0.45, 0.25)],
    ),
}


def _rng(seed: int, *keys: int) -> np.random.Generator:
    """An independent generator for one concern of one scene."""
    return np.random.default_rng(np.random.SeedSequence([seed, *keys]))


# --- Gaussian soup -------------------------------------------------------------------------------


@dataclass
class Soup:
    """A bag of Gaussians in float64 (world frame before tilt/scale), colours already lit."""

    means: np.ndarray
    quats: np.ndarray
    scales: np.ndarray
    opacities: np.ndarray
    rgb: np.ndarray

    @staticmethod
    def concat(parts: list[Soup]) -> Soup:
        return Soup(*[np.concatenate([getattr(p, f.name) for p in parts]) for f in dataclasses.fields(Soup)])

    def __len__(self) -> int:
        return len(self.means)


def _frames_to_quats(t1: np.ndarray, t2: np.ndarray, n: np.ndarray) -> np.ndarray:
    return rotmat_to_quat(torch.from_numpy(np.stack([t1, t2, n], axis=2))).numpy()


def _smoothstep(a: float, b: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - a) / (b - a), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _hash01(ix: np.ndarray, iy: np.ndarray, salt: int) -> np.ndarray:
    """Deterministic pseudo-random values in [0, 1) for 2D integer lattice points."""
    return lattice_hash(ix, iy, np.zeros_like(ix), salt)


def _value_noise(uv: np.ndarray, cell: float, salt: int) -> np.ndarray:
    """Smooth random field in [0, 1] with features of about ``cell``: value noise (hashed lattice,
    smoothstep-faded bilinear interpolation), a pure function of the position and ``salt``."""
    g = uv / cell
    i = np.floor(g).astype(np.int64)
    f = g - i
    f = f * f * (3.0 - 2.0 * f)
    corner = lambda dx, dy: _hash01(i[:, 0] + dx, i[:, 1] + dy, salt)  # noqa: E731
    top = corner(0, 0) * (1 - f[:, 0]) + corner(1, 0) * f[:, 0]
    bottom = corner(0, 1) * (1 - f[:, 0]) + corner(1, 1) * f[:, 0]
    return top * (1 - f[:, 1]) + bottom * f[:, 1]


def blob_texture(uv: np.ndarray, cell: float, palette: str, salt: int) -> np.ndarray:
    """Multi-scale random colour blobs at surface coordinates ``uv`` (k, 2) in metres: large soft
    patches of the palette's base colours, then smaller, sharper accent spots down to about
    ``cell``. A pure function of the position and ``salt`` (so adjoining pieces of one surface
    match): dense, non-repeating detail for SIFT."""
    bases, accents = (np.asarray(p, dtype=np.float64) for p in _PALETTES[palette])
    pick = np.random.default_rng(np.random.SeedSequence([salt, 99]))
    col = np.broadcast_to(bases[int(pick.integers(len(bases)))], (len(uv), 3)).copy()
    octaves = [
        (7.0, bases, 0.45, 0.7),
        (3.0, bases, 0.5, 0.7),
        (1.6, accents, 0.66, 0.6),
        (1.0, accents, 0.68, 0.7),
        (0.6, bases, 0.6, 0.6),
    ]
    for k, (size, palette_k, threshold, amount) in enumerate(octaves):
        noise = _value_noise(uv, cell * size, salt * 16 + k)
        colour = palette_k[int(pick.integers(len(palette_k)))] * pick.uniform(0.85, 1.1)
        mask = _smoothstep(threshold, threshold + 0.08, noise) * amount
        col = col * (1 - mask[:, None]) + colour[None] * mask[:, None]
    if palette == "floor":  # wooden planks: rows along u with staggered joints, a tint per plank
        row = np.floor(uv[:, 1] / 0.16).astype(np.int64)
        plank = np.floor(uv[:, 0] / 1.1 + 0.37 * row).astype(np.int64)
        tint = 0.8 + 0.35 * _hash01(plank, row, salt + 5)
        seam = np.minimum(np.abs(uv[:, 1] / 0.16 - np.round(uv[:, 1] / 0.16)) * 0.16, 0.01) / 0.01
        col = col * (tint * (0.75 + 0.25 * seam))[:, None]
    return np.clip(col, 0.0, 1.0)


@dataclass
class Resolution:
    """Ground sampling that follows the cameras, as 3DGS densification does: a surface tile gets
    a sample spacing of about ``pixels`` pixels in the nearest training view that has it in front,
    quantised to ``s_min * 2^k`` and clamped to ``[s_min, s_max]``.

    Attributes:
        eyes, forwards: (m, 3) camera centres and unit viewing directions (pre-tilt metres).
        radians: angle of one sample at the target spacing (``pixels / focal``).
        s_min, s_max: spacing bounds in metres; tile: tile size in metres.
    """

    eyes: np.ndarray
    forwards: np.ndarray
    radians: float
    s_min: float
    s_max: float
    tile: float
    cos_view: float = 0.5  # cosine of the half field of view (diagonal) plus a margin

    def spacing(self, centres: np.ndarray, half_diag: float) -> np.ndarray:
        offset = centres[:, None, :] - self.eyes[None]  # (t, m, 3)
        dist = np.linalg.norm(offset, axis=2)
        in_view = np.einsum("tmk,mk->tm", offset, self.forwards) > self.cos_view * dist - half_diag
        dist = np.where(in_view, np.maximum(dist - half_diag, 0.0), np.inf).min(1)
        s = np.clip(dist * self.radians, self.s_min, self.s_max)
        return self.s_min * 2.0 ** np.round(np.log2(s / self.s_min))


def _plane(
    origin,
    u_axis,
    v_axis,
    u_range,
    v_range,
    spacing: float | Resolution,
    palette: str,
    cell: float,
    rng: np.random.Generator,
    keep=None,
    salt: int | None = None,
) -> Soup:
    """Flat Gaussians on a jittered grid over ``origin + u * u_axis + v * v_axis``, with a fixed
    ``spacing`` or one per tile from a :class:`Resolution`; ``keep(u, v)`` optionally filters
    samples. Colours from :func:`blob_texture` (a function of the surface position, so tiles of
    different spacing match), lit with the plane normal."""
    origin, u_axis, v_axis = (np.asarray(a, dtype=np.float64) for a in (origin, u_axis, v_axis))
    if isinstance(spacing, Resolution):
        tile = spacing.tile
        nt_u = max(1, math.ceil((u_range[1] - u_range[0]) / tile))
        nt_v = max(1, math.ceil((v_range[1] - v_range[0]) / tile))
        tu, tv = (u_range[1] - u_range[0]) / nt_u, (v_range[1] - v_range[0]) / nt_v
        cu, cv = np.meshgrid(u_range[0] + (np.arange(nt_u) + 0.5) * tu, v_range[0] + (np.arange(nt_v) + 0.5) * tv, indexing="ij")
        cu, cv = cu.ravel(), cv.ravel()
        centres = origin + cu[:, None] * u_axis + cv[:, None] * v_axis
        spacings = spacing.spacing(centres, 0.5 * math.hypot(tu, tv))
        tiles = [((a - tu / 2, a + tu / 2), (b - tv / 2, b + tv / 2), sp) for a, b, sp in zip(cu, cv, spacings)]
    else:
        tiles = [(u_range, v_range, spacing)]
    us, vs, dus, dvs = [], [], [], []
    for (u0, u1), (v0, v1), sp in tiles:
        nu, nv = max(1, math.ceil((u1 - u0) / sp - 1e-9)), max(1, math.ceil((v1 - v0) / sp - 1e-9))
        du, dv = (u1 - u0) / nu, (v1 - v0) / nv
        uu, vv = np.meshgrid(u0 + (np.arange(nu) + 0.5) * du, v0 + (np.arange(nv) + 0.5) * dv, indexing="ij")
        us.append(uu.ravel())
        vs.append(vv.ravel())
        dus.append(np.full(uu.size, du))
        dvs.append(np.full(uu.size, dv))
    du, dv = np.concatenate(dus), np.concatenate(dvs)
    uu = np.concatenate(us) + rng.uniform(-0.2, 0.2, len(du)) * du
    vv = np.concatenate(vs) + rng.uniform(-0.2, 0.2, len(dv)) * dv
    if keep is not None:
        mask = keep(uu, vv)
        uu, vv, du, dv = uu[mask], vv[mask], du[mask], dv[mask]
    k = len(uu)
    normal = np.cross(u_axis, v_axis)
    means = origin + uu[:, None] * u_axis + vv[:, None] * v_axis
    quats = _frames_to_quats(np.broadcast_to(u_axis, (k, 3)), np.broadcast_to(v_axis, (k, 3)), np.broadcast_to(normal, (k, 3)))
    scales = np.stack([0.7 * du, 0.7 * dv, 0.1 * np.minimum(du, dv)], 1)
    salt = int(rng.integers(2**31)) if salt is None else salt
    albedo = blob_texture(np.stack([uu, vv], 1), cell, palette, salt)
    albedo = np.clip(albedo * (1.0 + 0.05 * rng.standard_normal((k, 1))), 0.0, 1.0)
    rgb = bake_lighting(albedo, np.broadcast_to(normal, (k, 3)))
    return Soup(means, quats, scales, np.clip(0.95 + rng.uniform(-0.03, 0.03, k), 0, 1), rgb)


def _foliage(centre: np.ndarray, salt: int):
    """Colour function for a bush: :func:`blob_texture` over (arc length around it, height)."""

    def colour(points, part):
        rel = points - centre
        uv = np.stack([np.arctan2(rel[:, 1], rel[:, 0]) * np.hypot(rel[:, 0], rel[:, 1]).mean(), points[:, 2]], 1)
        return blob_texture(uv, 0.22, "bush", salt)

    return colour


def _disk_keep(radius: float):
    return lambda u, v: np.hypot(u, v) <= radius


# --- stage: ground, walls, camera paths ----------------------------------------------------------


@dataclass
class Stage:
    """Where things go, in metres, z-up, before tilt and scale.

    Attributes:
        region: free-object region, ``("disk", r)`` or ``("rect", x0, x1, y0, y1)``.
        walls: room walls as (centre point of the wall (2,), inward normal (2,), half length) —
            empty outside rooms.
        bounds: room interior ``(x0, x1, y0, y1)`` or None.
        target: the point the cameras look at (3,).
        unit: a typical length of the stage (clearances are fractions of it).
    """

    preset: str
    capture: str
    region: tuple
    walls: list = field(default_factory=list)
    bounds: tuple | None = None
    target: np.ndarray = field(default_factory=lambda: np.zeros(3))
    unit: float = 1.0
    room: tuple[float, float, float] | None = None


def _make_stage(preset: str, capture: str, objects: list[BuiltObject], grow: float, rng) -> Stage:
    gap = {"tabletop": 0.04, "room": 0.2, "outdoor": 0.3}[preset]
    free = [o for o in objects if not (preset == "room" and o.spec.wall)]
    packed = math.sqrt(sum((o.footprint + gap) ** 2 for o in free)) * 1.2 * grow
    mean_height = float(np.mean([o.height for o in objects])) if objects else 0.3
    if preset == "tabletop":
        radius = max(0.3, packed)
        return Stage(preset, capture, ("disk", radius), target=np.array([0.0, 0.0, 0.35 * mean_height]), unit=radius)
    if preset == "outdoor":
        radius = max(2.0, packed)
        return Stage(preset, capture, ("disk", radius), target=np.array([0.0, 0.0, 0.35 * mean_height]), unit=radius)
    # room: interior [-lx/2, lx/2] x [-ly/2, ly/2], the back wall at +x; cameras stand on the -x side
    if capture == "forward":
        lx = max(4.6, 1.8 * packed + 2.1) + rng.uniform(0.0, 0.6)
        ly = max(4.0, 1.8 * packed + 1.0) + rng.uniform(0.0, 0.5)
    else:
        lx = max(4.6, 2.0 * (packed + 1.6)) + rng.uniform(0.0, 0.6)
        ly = max(4.2, 2.0 * (packed + 1.6)) + rng.uniform(0.0, 0.5)
    height = 2.6
    hx, hy = lx / 2, ly / 2
    walls = [
        (np.array([hx, 0.0]), np.array([-1.0, 0.0]), hy),
        (np.array([0.0, hy]), np.array([0.0, -1.0]), hx),
        (np.array([0.0, -hy]), np.array([0.0, 1.0]), hx),
    ]
    if capture == "forward":
        region = ("rect", -hx + 1.9, hx - 0.5, -hy + 0.5, hy - 0.5)
        target = np.array([0.55 + 0.1 * hx, 0.0, 0.5])
    else:  # cameras inside the room: a closed room, objects in the middle and along the walls
        walls.append((np.array([-hx, 0.0]), np.array([1.0, 0.0]), hy))
        region = ("disk", max(0.8, min(hx, hy) - 1.6))
        target = np.array([0.0, 0.0, 0.45])
    return Stage(preset, capture, region, walls=walls, bounds=(-hx, hx, -hy, hy), target=target, unit=1.0, room=(lx, ly, height))


def _focal(width: int, rng) -> tuple[float, float]:
    """Focal length (pixels) for a horizontal field of view of 55-65 degrees, and that FOV."""
    fov = rng.uniform(55.0, 65.0)
    return (width / 2.0) / math.tan(math.radians(fov) / 2.0), fov


def _fit_distance(radius: float, focal: float, width: int, height: int) -> float:
    """Distance at which a sphere of ``radius`` just fills the shorter image side."""
    half = math.atan(min(width, height) / 2.0 / focal)
    return radius / math.sin(half)


def _split(n: int, parts: int) -> list[int]:
    return [len(a) for a in np.array_split(np.arange(n), parts) if len(a)]


def _camera_path(stage: Stage, n: int, focal: float, size: tuple[int, int], rng) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Training cameras as (eye, target, roll in radians), pre-tilt metres."""
    width, height = size
    c = stage.target
    jitter_roll = lambda: math.radians(float(np.clip(rng.normal(0.0, 0.8), -2.0, 2.0)))  # noqa: E731
    out = []
    if stage.preset == "room":
        lx, ly, _ = stage.room
        hx, hy = lx / 2, ly / 2
    if stage.capture == "orbit":
        rings = 1 if n < 30 else 2 if n < 90 else 3  # neighbours within ~15 degrees for SIFT
        if stage.preset == "room":
            rho = min(hx, hy) - 0.7
            specs = [(rho, h) for h in np.linspace(1.25, 1.85, rings)]
        else:
            radius = stage.region[1] + 0.1 * stage.unit
            dist = _fit_distance(radius, focal, width, height)
            elevations = (18.0, 55.0) if stage.preset == "tabletop" else (12.0, 38.0)
            specs = []
            for e in np.linspace(*elevations, rings + 2)[1:-1] if rings > 1 else [sum(elevations) / 2]:
                e = math.radians(e)
                specs.append((dist * math.cos(e), c[2] + dist * math.sin(e)))
        for (rho, z), m in zip(specs, _split(n, len(specs))):
            phase = rng.uniform(0, 2 * math.pi)
            for j in range(m):
                az = phase + 2 * math.pi * (j + rng.uniform(-0.25, 0.25)) / m
                r = rho * (1 + rng.uniform(-0.05, 0.05))
                eye = np.array([c[0] + r * math.cos(az), c[1] + r * math.sin(az), z * (1 + rng.uniform(-0.04, 0.04))])
                target = c + rng.normal(0.0, 0.03 * np.linalg.norm(eye - c), 3)
                out.append((eye, target, jitter_roll()))
        return out
    if stage.capture == "forward":
        if stage.preset == "room":
            base_x, width_m, heights = -hx + 0.35, min(1.6, ly * 0.4), (1.3, 1.75)
        else:
            radius = stage.region[1] + 0.1 * stage.unit
            dist = _fit_distance(radius, focal, width, height) * 1.1
            lift = dist * math.sin(math.radians(20.0 if stage.preset == "tabletop" else 10.0))
            base_x, width_m, heights = -dist, 0.5 * dist, (c[2] + 0.8 * lift, c[2] + 1.3 * lift)
        rows = 1 if n < 6 else 2 if n < 20 else 3
        for k, m in enumerate(_split(n, rows)):
            z = heights[0] + (heights[1] - heights[0]) * (k / max(rows - 1, 1))
            for j in range(m):
                y = width_m * ((j + 0.5) / m - 0.5 + rng.uniform(-0.15, 0.15) / m)
                x = base_x + rng.uniform(-0.05, 0.05) * width_m
                eye = np.array([x, y, z + rng.uniform(-0.03, 0.03) * width_m])
                target = c + rng.normal(0.0, 0.03 * np.linalg.norm(eye - c), 3)
                out.append((eye, target, jitter_roll()))
        return out
    # walk-through: along part of an ellipse around the target, looking inwards and ahead
    if stage.preset == "room":
        a, b, z0 = hx - 0.75, hy - 0.75, 1.55
    else:
        radius = stage.region[1] + 0.1 * stage.unit
        dist = _fit_distance(radius, focal, width, height) * 0.85
        a = b = dist
        z0 = c[2] + dist * math.sin(math.radians(25.0 if stage.preset == "tabletop" else 8.0))
    span = math.radians(rng.uniform(200.0, 250.0))
    start = math.pi - span / 2 + rng.uniform(-0.3, 0.3)
    wobble = rng.uniform(0, 2 * math.pi)
    for k in range(n):
        t = start + span * (k / max(n - 1, 1))
        w = 1.0 + 0.08 * math.sin(2.3 * t + wobble)
        eye = np.array([c[0] + a * w * math.cos(t), c[1] + b * w * math.sin(t), z0 * (1 + 0.02 * math.sin(5 * t))])
        inward = c[:2] - eye[:2]
        dist_in = np.linalg.norm(inward)
        ahead = np.array([-a * math.sin(t), b * math.cos(t)])
        look = 0.72 * inward / dist_in + 0.28 * ahead / np.linalg.norm(ahead)
        look = look / np.linalg.norm(look)
        target = np.array([eye[0] + look[0] * dist_in, eye[1] + look[1] * dist_in, c[2]])
        target += rng.normal(0.0, 0.02 * dist_in, 3)
        out.append((eye, target, jitter_roll()))
    return out


# --- placement -----------------------------------------------------------------------------------


@dataclass
class Placed:
    """An object instance placed in the pre-tilt world: ``position`` of its base origin (x, y),
    ``yaw`` of its front (+x) about z."""

    obj: BuiltObject
    position: np.ndarray
    yaw: float
    rect_lo: np.ndarray  # local footprint rectangle (x, y)
    rect_hi: np.ndarray

    def corners(self, margin: float = 0.0) -> np.ndarray:
        lo, hi = self.rect_lo - margin, self.rect_hi + margin
        local = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return local @ np.array([[c, s], [-s, c]]) + self.position

    def distance_to(self, points: np.ndarray) -> np.ndarray:
        """Horizontal distance from points (k, 2) to the footprint rectangle (0 inside)."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        local = (points - self.position) @ np.array([[c, -s], [s, c]])
        centre, half = (self.rect_lo + self.rect_hi) / 2, (self.rect_hi - self.rect_lo) / 2
        return np.linalg.norm(np.maximum(np.abs(local - centre) - half, 0.0), axis=1)


def _rectangles_overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test for two convex quadrilaterals (4, 2)."""
    for poly in (a, b):
        for k in range(4):
            edge = poly[(k + 1) % 4] - poly[k]
            axis = np.array([-edge[1], edge[0]])
            pa, pb = a @ axis, b @ axis
            if pa.max() <= pb.min() or pb.max() <= pa.min():
                return False
    return True


def _place(objects: list[BuiltObject], stage: Stage, cameras: list, rng) -> list[Placed] | None:
    """Rejection-sample positions and yaws: no two footprints overlap (with a gap), every object
    stays inside the stage and clear of the camera positions; wall objects stand with their back
    to a wall, facing into the room; asymmetric objects face mostly towards open space."""
    gap = {"tabletop": 0.03, "room": 0.2, "outdoor": 0.5}[stage.preset]
    cam_clear = {"tabletop": 0.1, "room": 0.8, "outdoor": 1.2}[stage.preset]
    cam_xy = np.array([e[:2] for e, _, _ in cameras])
    cam_centre = cam_xy.mean(0)
    order = sorted(range(len(objects)), key=lambda i: (not (objects[i].spec.wall and stage.walls), -objects[i].footprint))
    placed: dict[int, Placed] = {}
    for i in order:
        obj = objects[i]
        lo, hi = obj.lo[:2], obj.hi[:2]
        for _ in range(500):
            if obj.spec.wall and stage.walls:
                # forward captures look at the back wall (+x): prefer it, and use only the back half
                # of the side walls, where a wall object still faces the cameras' side of the room
                w = int(rng.integers(len(stage.walls) + (2 if stage.capture == "forward" else 0)))
                point, normal, half_len = stage.walls[w if w < len(stage.walls) else 0]
                along = np.array([-normal[1], normal[0]])
                half_w = max(-lo[1], hi[1])
                if half_len - half_w - 0.2 <= 0:
                    continue
                offset = rng.uniform(-(half_len - half_w - 0.2), half_len - half_w - 0.2)
                yaw = math.atan2(normal[1], normal[0]) + math.radians(rng.uniform(-3.0, 3.0))
                position = point + along * offset + normal * (-lo[0] + 0.06)
                if stage.capture == "forward" and normal[0] == 0 and position[0] < 0:
                    continue
            else:
                if stage.region[0] == "disk":
                    r = stage.region[1] * math.sqrt(rng.random())
                    a = rng.uniform(0, 2 * math.pi)
                    position = np.array([r * math.cos(a), r * math.sin(a)])
                else:
                    _, x0, x1, y0, y1 = stage.region
                    position = np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)])
                if obj.spec.symmetric or stage.capture == "orbit":
                    yaw = rng.uniform(-math.pi, math.pi)
                else:  # face the cameras (open space), give or take 60 degrees
                    towards = (cam_centre - position) if stage.capture == "forward" else -position
                    if np.linalg.norm(towards) < 1e-6:
                        towards = np.array([1.0, 0.0])
                    yaw = math.atan2(towards[1], towards[0]) + math.radians(rng.uniform(-60.0, 60.0))
            candidate = Placed(obj, position, yaw, lo, hi)
            corners = candidate.corners()
            if stage.region[0] == "disk" and not (obj.spec.wall and stage.walls):
                if np.linalg.norm(corners, axis=1).max() > stage.region[1] + 0.5 * stage.unit:
                    continue
            if stage.bounds is not None:
                x0, x1, y0, y1 = stage.bounds
                m = 0.02
                if (
                    corners[:, 0].min() < x0 + m
                    or corners[:, 0].max() > x1 - m
                    or corners[:, 1].min() < y0 + m
                    or corners[:, 1].max() > y1 - m
                ):
                    continue
            if stage.preset == "tabletop" and np.abs(corners).max() > stage.region[1] + 0.5 * stage.unit:
                continue
            if candidate.distance_to(cam_xy).min() < cam_clear:
                continue
            padded = candidate.corners(gap / 2)
            if any(_rectangles_overlap(padded, p.corners(gap / 2)) for p in placed.values()):
                continue
            placed[i] = candidate
            break
        else:
            return None
    return [placed[i] for i in range(len(objects))]


# --- environment ---------------------------------------------------------------------------------


TABLE_THICKNESS = 0.04  # the table top's edge strip (tabletop preset)
TABLE_HEIGHT = 0.74  # the floor under the table lies this far below its top


def table_half_size(stage: Stage) -> tuple[float, float]:
    """Half the size (x, y) of a tabletop stage's table top, centred on the origin at height 0."""
    r = stage.region[1]
    return max(0.75, r + 0.55), max(0.6, r + 0.4)


def _environment(stage: Stage, cameras: list, focal: float, size: tuple[int, int], density: float, rng) -> Soup:
    """Ground, table, walls and backdrop Gaussians (unlabelled), textured and lit. Surfaces are
    sampled by :class:`Resolution`: about :data:`PIXELS_PER_SAMPLE` px per sample in the nearest
    training view (divided by sqrt(density)), so detail follows the cameras and the image
    resolution."""
    k = 1.0 / math.sqrt(density)
    width, height = size
    eyes = np.array([e for e, _, _ in cameras])
    forwards = np.array([(t - e) / np.linalg.norm(t - e) for e, t, _ in cameras])

    half_diagonal = math.atan(math.hypot(width, height) / 2.0 / focal)
    cos_view = math.cos(min(half_diagonal + math.radians(8.0), math.pi / 2))

    def resolution(cell: float, s_max: float, s_min: float | None = None) -> Resolution:
        s_min = (cell / 3.0 if s_min is None else s_min) * k
        return Resolution(eyes, forwards, PIXELS_PER_SAMPLE * k / focal, s_min, max(s_max * k, s_min), 16 * s_min, cos_view)

    parts = []
    if stage.preset == "tabletop":
        hx, hy = table_half_size(stage)
        cell = 0.035
        parts.append(_plane((0, 0, 0), (1, 0, 0), (0, 1, 0), (-hx, hx), (-hy, hy), resolution(cell, 0.03), "table", cell, rng))
        thick = TABLE_THICKNESS
        for sign in (-1.0, 1.0):  # table edges
            parts.append(
                _plane(
                    (sign * hx, 0, -thick / 2),
                    (0, sign, 0),
                    (0, 0, 1),
                    (-hy, hy),
                    (-thick / 2, thick / 2),
                    0.015 * k,
                    "table",
                    cell,
                    rng,
                )
            )
            parts.append(
                _plane(
                    (0, sign * hy, -thick / 2),
                    (-sign, 0, 0),
                    (0, 0, 1),
                    (-hx, hx),
                    (-thick / 2, thick / 2),
                    0.015 * k,
                    "table",
                    cell,
                    rng,
                )
            )
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                for ax, ay in ((1, 0), (0, 1), (-1, 0), (0, -1)):
                    origin = (sx * (hx - 0.08) + 0.03 * ax, sy * (hy - 0.08) + 0.03 * ay, -0.39)
                    parts.append(
                        _plane(origin, (-ay, ax, 0), (0, 0, 1), (-0.03, 0.03), (-0.35, 0.35), 0.03 * k, "under", 0.1, rng)
                    )
        parts.append(
            _plane(
                (0, 0, -TABLE_HEIGHT),
                (1, 0, 0),
                (0, 1, 0),
                (-5.0, 5.0),
                (-5.0, 5.0),
                resolution(0.12, 0.4, 0.06),
                "under",
                0.12,
                rng,
                keep=_disk_keep(5.0),
            )
        )
    elif stage.preset == "outdoor":
        reach = float(np.max(np.linalg.norm(eyes[:, :2], axis=1)))
        radius = max(14.0, 1.6 * reach)
        cell = 0.18
        parts.append(
            _plane(
                (0, 0, 0),
                (1, 0, 0),
                (0, 1, 0),
                (-radius, radius),
                (-radius, radius),
                resolution(cell, 0.5),
                "grass",
                cell,
                rng,
                keep=_disk_keep(radius),
            )
        )
        bushes = ShapeBuilder()
        count = 22
        for j in range(count):
            a = 2 * math.pi * (j + rng.uniform(-0.3, 0.3)) / count
            d = radius * rng.uniform(0.78, 0.9)
            size = rng.uniform(1.2, 2.6)
            centre = np.array([d * math.cos(a), d * math.sin(a), 0.6 * size])
            bushes.ellipsoid(
                centre, (size, size * rng.uniform(0.8, 1.4), size), _foliage(centre, int(rng.integers(2**31))), noise=0.1
            )
        g = bushes.build(round(6000 * density), rng)
        parts.append(Soup(g.means, g.quats, g.scales, g.opacities, g.lit()))
    else:
        lx, ly, height = stage.room
        hx, hy = lx / 2, ly / 2
        cell = 0.09
        res = resolution(cell, 0.12)
        floor_x0 = -hx - (1.0 if stage.capture == "forward" else 0.0)
        parts.append(_plane((0, 0, 0), (1, 0, 0), (0, 1, 0), (floor_x0, hx), (-hy, hy), res, "floor", cell, rng))
        for point, normal, half_len in stage.walls:
            along = np.array([-normal[1], normal[0], 0.0])
            parts.append(
                _plane((point[0], point[1], 0.0), along, (0, 0, 1), (-half_len, half_len), (0.0, height), res, "wall", cell, rng)
            )
            base = np.array([point[0] + 0.012 * normal[0], point[1] + 0.012 * normal[1], 0.0])  # skirting board
            board = _plane(base, along, (0, 0, 1), (-half_len, half_len), (0.0, 0.09), 0.03 * k, "wall", cell, rng)
            board.rgb[:] = bake_lighting(np.full((len(board), 3), 0.93), np.broadcast_to(np.r_[normal, 0.0], (len(board), 3)))
            parts.append(board)
    return Soup.concat(parts)


# --- the scene -----------------------------------------------------------------------------------


def tilt_rotation(seed: int, tilt_deg: float) -> np.ndarray:
    """The world rotation of a tilted scene: a random heading about z, then ``tilt_deg`` about a
    horizontal axis drawn from the seed (so world up ends up ``tilt_deg`` from +z, on no axis).
    The identity for ``tilt_deg == 0``."""
    if tilt_deg == 0:
        return np.eye(3)
    rng = _rng(seed, 7)
    heading = rng.uniform(-math.pi, math.pi)
    beta = rng.uniform(-math.pi, math.pi)
    axis = np.array([math.cos(beta), math.sin(beta), 0.0])
    angle = math.radians(tilt_deg)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R_tilt = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * (K @ K)
    c, s = math.cos(heading), math.sin(heading)
    return R_tilt @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass
class SynthScene:
    """A generated scene in memory (world frame: tilted and scaled).

    Attributes:
        gaussians: float32 Gaussians with ``labels`` (object id, -1 background).
        cameras: training cameras (names ``frame_0000``...).
        semantics: the semantic sidecar objects.
        ground_truth: the ``ground_truth.json`` content.
        background: render background colour.
        meta: ``scene.json`` content.
    """

    gaussians: GaussianScene
    cameras: list[Camera]
    semantics: list[SemanticObject]
    ground_truth: dict
    background: tuple[float, float, float]
    meta: SceneMeta
    poses: bool = True


def _ranges(mask: np.ndarray, offset: int) -> list[list[int]]:
    """[start, end) index ranges of the True runs of ``mask``, shifted by ``offset``."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    edges = np.flatnonzero(np.diff(padded))
    return [[int(a) + offset, int(b) + offset] for a, b in zip(edges[::2], edges[1::2])]


def _check_args(preset, capture, views, scale, tilt_deg, resolution, density, seed) -> tuple[str, tuple[int, int]]:
    if preset not in PRESETS:
        raise InputError(f"preset {preset!r} is unknown; expected one of {', '.join(PRESETS)}")
    capture = capture or DEFAULT_CAPTURE[preset]
    if capture not in CAPTURES:
        raise InputError(f"capture {capture!r} is unknown; expected one of {', '.join(CAPTURES)}")
    if isinstance(views, bool) or not isinstance(views, (int, np.integer)) or views < 1:
        raise InputError(f"views {views!r}; expected a whole number >= 1")
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
        raise InputError(f"scale {scale!r}; expected a positive number")
    if not (isinstance(tilt_deg, (int, float)) and math.isfinite(tilt_deg) and abs(tilt_deg) <= 90):
        raise InputError(f"tilt {tilt_deg!r}; expected degrees in [-90, 90]")
    if not (isinstance(density, (int, float)) and math.isfinite(density) and 0 < density <= 100):
        raise InputError(f"density {density!r}; expected a positive number (at most 100)")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed {seed!r}; expected a whole number >= 0")
    try:
        width, height = (int(v) for v in resolution)
    except (TypeError, ValueError):
        raise InputError(f"resolution {resolution!r}; expected (width, height)") from None
    if not (8 <= width <= 8192 and 8 <= height <= 8192):
        raise InputError(f"resolution {width}x{height}; expected 8 to 8192 pixels per side")
    return capture, (width, height)


def build_scene(
    *,
    seed: int,
    objects: list[str] | None = None,
    preset: str = "tabletop",
    capture: str | None = None,
    views: int = 24,
    scale: float = 1.0,
    tilt_deg: float = 0.0,
    poses: bool = True,
    resolution: tuple[int, int] = (320, 240),
    density: float = 1.0,
) -> SynthScene:
    """Build a synthetic scene in memory (no rendering, no files); arguments as :func:`generate_scene`."""
    capture, (width, height) = _check_args(preset, capture, views, scale, tilt_deg, resolution, density, seed)
    if objects is None:
        pool, (lo, hi) = POOLS[preset]
        pick = _rng(seed, 1)
        count = int(pick.integers(lo, hi + 1))
        specs = [CATALOG[pool[int(j)]] for j in pick.choice(len(pool), size=count, replace=False)]
    else:
        if len(objects) == 0:
            raise InputError("no objects given; name at least one, or leave --objects out for the preset's choice")
        specs = resolve_names(list(objects))
    names = catalog_names()
    built = [
        build_object(
            spec.name, rng=_rng(seed, 2, names.index(spec.name)), density=density, size=SIZES[preset].get(spec.name, 1.0)
        )
        for spec in specs
    ]
    focal, fov = _focal(width, _rng(seed, 3))
    for attempt in range(8):
        grow = 1.2**attempt
        layout_rng = _rng(seed, 4, attempt)
        stage = _make_stage(preset, capture, built, grow, layout_rng)
        cameras = _camera_path(stage, views, focal, (width, height), _rng(seed, 5, attempt))
        placed = _place(built, stage, cameras, layout_rng)
        if placed is not None:
            break
    else:
        raise InputError(
            f"could not place {len(built)} objects ({', '.join(o.name for o in built)}) in a "
            f"{preset} scene without overlaps; try fewer or smaller objects"
        )
    env = _environment(stage, cameras, focal, (width, height), density, _rng(seed, 6))

    # Objects in the pre-tilt world, lit there.
    soups, labels, gt_objects, front_ranges = [], [], [], {}
    offset = 0
    R_world = tilt_rotation(seed, tilt_deg)
    S = float(scale)
    up = R_world @ np.array([0.0, 0.0, 1.0])
    for oid, p in enumerate(placed):
        g = p.obj.gaussians
        c, s = math.cos(p.yaw), math.sin(p.yaw)
        Rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        t = np.array([p.position[0], p.position[1], 0.0])
        q_yaw = rotmat_to_quat(torch.from_numpy(Rz)).expand(len(g), 4)
        quats = quat_multiply(q_yaw, torch.from_numpy(g.quats)).numpy()
        normals = g.normals @ Rz.T
        soups.append(Soup(g.means @ Rz.T + t, quats, g.scales, g.opacities, bake_lighting(g.rgb, normals, g.emissive)))
        labels.append(np.full(len(g), oid, dtype=np.int32))
        front = None if p.obj.spec.symmetric else (R_world @ Rz[:, 0])
        center = S * (R_world @ (Rz @ p.obj.center + t))
        lo, hi = p.obj.lo, p.obj.hi
        gt_objects.append(
            {
                "id": oid,
                "label": oid,
                "name": p.obj.name,
                "aliases": list(p.obj.spec.aliases),
                "color": p.obj.color,
                "symmetric": p.obj.spec.symmetric,
                "center": center,
                "radius": S * p.obj.radius,
                "front": front,
                "up": up,
                "base": S * (R_world @ t),
                "height": S * p.obj.height,
                "size": p.obj.size,
                "yaw_deg": math.degrees(p.yaw),
                "box": {
                    "center": S * (R_world @ (Rz @ ((lo + hi) / 2) + t)),
                    "axes": (R_world @ Rz).T,  # rows: the object's front (+x), left (+y), up (+z) in the world
                    "half_extents": S * (hi - lo) / 2,
                },
                "gaussians": [offset, offset + len(g)],
            }
        )
        front_ranges[str(oid)] = _ranges(g.front_feature, offset)
        offset += len(g)
    soups.append(env)
    labels.append(np.full(len(env), -1, dtype=np.int32))
    soup = Soup.concat(soups)
    label_array = np.concatenate(labels)

    # World transform: rotate (tilt), then scale every length.
    q_world = rotmat_to_quat(torch.from_numpy(R_world))
    means = S * (soup.means @ R_world.T)
    quats = quat_multiply(q_world.expand(len(soup), 4), torch.from_numpy(soup.quats)).numpy()
    f32 = lambda a: torch.from_numpy(np.ascontiguousarray(a, dtype=np.float32))  # noqa: E731
    gaussians = GaussianScene.from_activated(
        f32(means),
        f32(quats),
        f32(S * soup.scales),
        f32(soup.opacities),
        f32(soup.rgb),
        labels=torch.from_numpy(label_array.astype(np.int64)),
    )

    K = np.array([[focal, 0.0, width / 2.0], [0.0, focal, height / 2.0], [0.0, 0.0, 1.0]])
    z_up = torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64)
    cams = []
    for i, (eye, target, roll) in enumerate(cameras):
        T = look_at(torch.from_numpy(eye), torch.from_numpy(target), z_up, roll).numpy()
        R_cw = T[:3, :3] @ R_world.T
        centre = S * (R_world @ eye)
        T_w = np.eye(4)
        T_w[:3, :3] = R_cw
        T_w[:3, 3] = -R_cw @ centre
        cams.append(Camera(T_w, K, width, height, name=f"frame_{i:04d}", image_path=f"images/frame_{i:04d}.png"))

    scene_center = np.mean([o["center"] for o in gt_objects], axis=0)
    distances = [float(np.linalg.norm(cam.center - scene_center)) for cam in cams]
    semantics = [
        SemanticObject(
            o["id"],
            o["name"],
            list(o["aliases"]) + [f"{o['color']} {o['name']}"],
            o["symmetric"],
            None if o["front"] is None else np.asarray(o["front"]),
        )
        for o in gt_objects
    ]
    for o in gt_objects:
        o["aliases"] = list(o["aliases"]) + [f"{o['color']} {o['name']}"]
    ground_truth = {
        "format": 1,
        "generator": {
            "version": GENERATOR_VERSION,
            "seed": int(seed),
            "preset": preset,
            "capture": capture,
            "views": int(views),
            "scale": S,
            "tilt_deg": float(tilt_deg),
            "poses": bool(poses),
            "resolution": [width, height],
            "density": float(density),
        },
        "up": up,
        "scale": float(np.median(distances)),
        "center": scene_center,
        "world_rotation": R_world,
        "length_unit": S,
        "fov_x_deg": fov,
        "background": list(BACKGROUNDS[preset]),
        "num_gaussians": len(gaussians),
        "objects": gt_objects,
        "front_feature": front_ranges,
        "room": None
        if stage.room is None
        else {
            "size": S * np.array(stage.room),  # interior [-sx/2, sx/2] x [-sy/2, sy/2] x [0, sz] before world_rotation
            "walls": [("+" if n[0] + n[1] < 0 else "-") + ("x" if n[0] != 0 else "y") for _, n, _ in stage.walls],
        },
        "cameras": [{"name": c.name, "T_cw": c.T_cw, "K": c.K, "width": c.width, "height": c.height} for c in cams],
    }
    if preset == "tabletop":  # the top the objects stand on, and the floor under it (evaluation only)
        hx, hy = table_half_size(stage)
        ground_truth["table"] = {
            "box": {
                "center": S * (R_world @ np.array([0.0, 0.0, -TABLE_THICKNESS / 2])),
                "axes": R_world.T,
                "half_extents": S * np.array([hx, hy, TABLE_THICKNESS / 2]),
            },
            "floor_height": -S * TABLE_HEIGHT,
        }
    aligned = poses and tilt_deg == 0
    meta = SceneMeta(up=up if aligned else None, aligned=aligned)
    return SynthScene(gaussians, cams, semantics, ground_truth, BACKGROUNDS[preset], meta, poses)


# --- writing -------------------------------------------------------------------------------------


def _plain(value):
    """JSON-ready copy: numpy to lists, floats rounded to 10 significant digits (stable text)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(f"{float(value):.10g}")
        return 0.0 if v == 0 else v
    return value


def json_text(value) -> str:
    """Deterministic JSON text: sorted keys, two-space indent, rounded floats."""
    return json.dumps(_plain(value), sort_keys=True, indent=2) + "\n"


def render_views(scene: SynthScene, backend: str = "auto") -> list[np.ndarray]:
    """Render every training camera: (H, W, 3) uint8 images over the scene's background.

    CPU rendering runs on one thread: the images are then bit-identical whatever the number of
    cores, and it is faster on a busy machine (parallel jobs oversubscribe the cores otherwise).
    Generate several scenes in parallel to use more cores."""
    images = []
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        with torch.no_grad():
            for cam in scene.cameras:
                out = render(scene.gaussians, cam, background=scene.background, backend=backend)
                images.append((out.rgb.clamp(0.0, 1.0).cpu().numpy() * 255.0 + 0.5).astype(np.uint8))
    finally:
        torch.set_num_threads(threads)
    return images


def png_bytes(image: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG", compress_level=6)
    return buffer.getvalue()


def _write_colmap_with_points(cameras: list[Camera], scene: GaussianScene, sparse_dir: Path, seed: int) -> None:
    """COLMAP model of the training cameras, with points3D (no tracks) from a subsample of the
    Gaussian means coloured by their DC colour, as a 3DGS trainer would initialise from."""
    write_colmap(cameras, sparse_dir)
    reconstruction = pycolmap.Reconstruction()
    reconstruction.read_binary(str(sparse_dir))
    n = len(scene)
    pick = np.sort(_rng(seed, 8).choice(n, size=min(n, 20000), replace=False))
    xyz = scene.means[pick].double().numpy()
    rgb = np.clip((scene.sh[pick, 0].numpy() * 0.28209479177387814 + 0.5) * 255.0 + 0.5, 0, 255).astype(np.uint8)
    for p, c in zip(xyz, rgb):
        reconstruction.add_point3D(p.reshape(3, 1), pycolmap.Track(), c.reshape(3, 1))
    reconstruction.write_binary(str(sparse_dir))


def write_scene(scene: SynthScene, out_dir: str | Path, images: list[np.ndarray] | None) -> Path:
    """Write ``scene`` and its rendered ``images`` (None: no images/ folder, cameras without
    image paths) as a scene directory, atomically."""
    out_dir = Path(out_dir)
    if images is None and not scene.poses:
        raise InputError("a scene without poses needs its images (COLMAP recovers the poses from them)")
    with atomic_directory(out_dir) as tmp:
        write_ply(scene.gaussians, tmp / "scene.ply")
        for cam, image in zip(scene.cameras, images or []):
            atomic_write(tmp / "images" / f"{cam.name}.png", png_bytes(image))
        if scene.poses:
            cams = [
                dataclasses.replace(c, image_path=None if images is None else str(tmp / "images" / f"{c.name}.png"))
                for c in scene.cameras
            ]
            write_cameras_json(cams, tmp / "cameras.json")
            _write_colmap_with_points(cams, scene.gaussians, tmp / "sparse" / "0", scene.ground_truth["generator"]["seed"])
        write_scene_meta(scene.meta, tmp / "scene.json")
        write_semantics(scene.semantics, scene.gaussians.labels.numpy(), tmp)
        atomic_write(tmp / "ground_truth.json", json_text(scene.ground_truth))
    return out_dir


def generate_scene(
    out_dir: str | Path,
    *,
    seed: int,
    objects: list[str] | None = None,
    preset: str = "tabletop",
    capture: str | None = None,
    views: int = 24,
    scale: float = 1.0,
    tilt_deg: float = 0.0,
    poses: bool = True,
    resolution: tuple[int, int] = (320, 240),
    density: float = 1.0,
    images: bool = True,
    backend: str = "auto",
) -> Path:
    """Generate a synthetic scene directory at ``out_dir`` (which must not hold files) and return it.

    Args:
        seed: everything random derives from it; the same arguments give byte-identical files.
        objects: catalog names or aliases (default: 2-6 drawn from the preset's pool).
        preset: "tabletop", "room" or "outdoor" — the ground and the usual objects.
        capture: "orbit", "forward" or "walkthrough" (default per preset: orbit, forward, orbit).
        views: number of training cameras.
        scale: multiplies every length (Gaussian means and scales, camera centres).
        tilt_deg: rotate the whole world so that up is ``tilt_deg`` off +z, about an axis drawn
            from the seed (``scene.json`` then has ``up = null``).
        poses: write ``cameras.json`` and ``sparse/0``; without, only images (poses for COLMAP to find).
        resolution: training image size (width, height).
        density: multiplies the number of Gaussians.
        images: render the training images. Without, the scene has cameras but no photos: enough
            for every stage of the embedded tier except COLMAP and gravity's vanishing points,
            and most of the generation time saved (needs ``poses``).
    """
    if not images and not poses:
        raise InputError("a scene without poses needs its images (COLMAP recovers the poses from them)")
    scene = build_scene(
        seed=seed,
        objects=objects,
        preset=preset,
        capture=capture,
        views=views,
        scale=scale,
        tilt_deg=tilt_deg,
        poses=poses,
        resolution=resolution,
        density=density,
    )
    return write_scene(scene, out_dir, render_views(scene, backend=backend) if images else None)


def parse_resolution(text: str) -> tuple[int, int]:
    """``"WxH"`` -> (W, H); :class:`InputError` otherwise."""
    parts = str(text).lower().replace("×", "x").split("x")
    try:
        width, height = (int(p) for p in parts)
    except ValueError:
        raise InputError(f"resolution {text!r}; expected WIDTHxHEIGHT, e.g. 320x240") from None
    if width <= 0 or height <= 0:
        raise InputError(f"resolution {text!r}; expected positive sizes")
    return width, height


def synth_command(args: argparse.Namespace) -> None:
    """The ``capframe synth`` verb."""
    names = None
    if args.objects is not None:
        names = [n.strip() for n in args.objects.split(",") if n.strip()]
    start = time.perf_counter()
    path = generate_scene(
        args.out_dir,
        seed=args.seed,
        objects=names,
        preset=args.preset,
        capture=args.capture,
        views=args.views,
        scale=args.scale,
        tilt_deg=args.tilt,
        poses=not args.no_poses,
        resolution=parse_resolution(args.resolution),
        density=args.density,
        images=not args.no_images,
    )
    gt = json.loads((Path(path) / "ground_truth.json").read_text())
    objects = ", ".join(f"{o['color']} {o['name']}" for o in gt["objects"])
    print(
        f"{path}: {gt['num_gaussians']} Gaussians, {args.views} views, objects: {objects} ({time.perf_counter() - start:.1f} s)"
    )


__all__ = [
    "generate_scene",
    "build_scene",
    "write_scene",
    "render_views",
    "synth_command",
    "parse_resolution",
    "tilt_rotation",
    "blob_texture",
    "json_text",
    "SynthScene",
    "PRESETS",
    "CAPTURES",
    "POOLS",
]
