"""Parametric objects made of 3D Gaussians: the synthetic scenes' object catalog.

Every object is built in its own local frame: up = +z, front = +x, base on z = 0, lengths in
metres at real-world size (the object's own left is +y, its right -y). Surfaces are sampled with
small flat Gaussians (tangent standard deviation about 0.8x the local sample spacing, thin along
the normal) so that neighbours overlap and surfaces render solid.

An asymmetric object has a canonical front that is plainly visible in renders (the teddy bear's
face, the armchair's and sofa's seat, the television's bright screen, the bookshelf's books, the
toy car's headlights, the refrigerator's doors and handles, the bench's seat); the Gaussians that
make it up are flagged in :attr:`ObjectGaussians.front_feature`.

Public entry points: :data:`CATALOG`, :func:`catalog_names`, :func:`lookup`,
:func:`resolve_names` and :func:`build_object`.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import torch

from ..errors import InputError
from ..geometry import rotmat_to_quat
from .captured import CONFIG as CAPTURED_CONFIG
from .captured import CapturedSource, captured_arrays, load_captured

# --- colours -------------------------------------------------------------------------------------

COLORS: dict[str, tuple[float, float, float]] = {
    "red": (0.78, 0.13, 0.12),
    "blue": (0.16, 0.32, 0.74),
    "navy": (0.12, 0.17, 0.38),
    "green": (0.20, 0.52, 0.24),
    "teal": (0.10, 0.50, 0.50),
    "yellow": (0.93, 0.79, 0.16),
    "mustard": (0.80, 0.60, 0.12),
    "orange": (0.93, 0.48, 0.12),
    "purple": (0.47, 0.24, 0.58),
    "pink": (0.93, 0.56, 0.66),
    "white": (0.90, 0.90, 0.88),
    "cream": (0.93, 0.87, 0.72),
    "beige": (0.80, 0.72, 0.58),
    "grey": (0.50, 0.50, 0.52),
    "silver": (0.74, 0.75, 0.77),
    "black": (0.14, 0.14, 0.15),
    "brown": (0.45, 0.28, 0.15),
    "tan": (0.76, 0.58, 0.38),
    "terracotta": (0.74, 0.37, 0.22),
}


def _rgb(name_or_rgb) -> np.ndarray:
    if isinstance(name_or_rgb, str):
        return np.array(COLORS[name_or_rgb], dtype=np.float64)
    return np.asarray(name_or_rgb, dtype=np.float64)


def shade(color, factor: float) -> np.ndarray:
    """``color`` scaled by ``factor`` (clipped to [0, 1])."""
    return np.clip(_rgb(color) * factor, 0.0, 1.0)


def mix(a, b, t: float) -> np.ndarray:
    return (1.0 - t) * _rgb(a) + t * _rgb(b)


# --- surface primitives ---------------------------------------------------------------------------

SIGMA_PER_SPACING = 0.8  # tangent standard deviation / sample spacing (neighbours overlap)
NORMAL_PER_SPACING = 0.12  # normal standard deviation / sample spacing (flat splats)
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def _perpendicular(n: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each row of ``n`` (deterministic)."""
    helper = np.where(np.abs(n[:, 2:3]) < 0.9, np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]]))
    return _unit(np.cross(helper, n))


def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rotation_from_z(direction) -> np.ndarray:
    """A rotation taking +z to ``direction``."""
    d = _unit(np.asarray(direction, dtype=np.float64)[None])[0]
    x = _perpendicular(d[None])[0]
    return np.stack([x, np.cross(d, x), d], axis=1)


@dataclass
class Samples:
    """Surface samples of one primitive: points (k, 3), first tangent t1, second tangent t2 and
    outward normal (k, 3 each; t1 and t2 need not be exactly perpendicular to the normal), and
    the sample spacing along t1 and t2 (k,)."""

    points: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    normal: np.ndarray
    s1: np.ndarray
    s2: np.ndarray

    def transformed(self, R: np.ndarray, c: np.ndarray) -> Samples:
        return Samples(self.points @ R.T + c, self.t1 @ R.T, self.t2 @ R.T, self.normal @ R.T, self.s1, self.s2)

    @staticmethod
    def concat(parts: list[Samples]) -> Samples:
        return Samples(*[np.concatenate([getattr(p, k) for p in parts]) for k in ("points", "t1", "t2", "normal", "s1", "s2")])


def _ring_samples(
    radii: np.ndarray, zs: np.ndarray, tangent_r: np.ndarray, tangent_z: np.ndarray, h: float, step: np.ndarray, phase: np.ndarray
) -> Samples:
    """Rings of a surface of revolution about +z: station i has radius radii[i], height zs[i], unit
    profile tangent (tangent_r[i], tangent_z[i]) and spacing step[i] along the profile. The normal
    is the profile tangent turned clockwise in the (r, z) plane: outward for a profile traced
    upwards on the outside, towards the axis for one traced downwards on the inside."""
    pts, t1s, t2s, ns, s1s, s2s = [], [], [], [], [], []
    for r, z, tr, tz, ds, ph in zip(radii, zs, tangent_r, tangent_z, step, phase):
        count = max(1, math.ceil(2.0 * math.pi * r / h)) if r > 1e-9 else 1
        phi = 2.0 * math.pi * (np.arange(count) + ph) / count
        c, s = np.cos(phi), np.sin(phi)
        pts.append(np.stack([r * c, r * s, np.full(count, z)], 1))
        t1s.append(np.stack([-s, c, np.zeros(count)], 1))
        t2s.append(np.stack([tr * c, tr * s, np.full(count, tz)], 1))
        ns.append(np.stack([tz * c, tz * s, np.full(count, -tr)], 1))
        arc = 2.0 * math.pi * r / count if r > 1e-9 else ds
        s1s.append(np.full(count, max(arc, 1e-6)))
        s2s.append(np.full(count, ds))
    return Samples(
        np.concatenate(pts),
        np.concatenate(t1s),
        np.concatenate(t2s),
        np.concatenate(ns),
        np.concatenate(s1s),
        np.concatenate(s2s),
    )


class Part:
    """One surface primitive, in the object's local frame after ``rot`` and ``center``."""

    area: float = 0.0

    def __init__(
        self,
        color,
        *,
        feature: bool = False,
        detail: float = 1.0,
        min_count: int = 0,
        rot=None,
        center=(0.0, 0.0, 0.0),
        opacity: float = 0.93,
        noise: float = 0.04,
        emissive: bool = False,
        texture: float = 0.22,
    ):
        self.color = color
        self.emissive = emissive
        self.texture = 0.0 if emissive else texture
        self.feature = feature
        self.detail = detail
        self.min_count = min_count if min_count else (40 if feature else 0)
        self.rot = np.eye(3) if rot is None else np.asarray(rot, dtype=np.float64)
        self.center = np.asarray(center, dtype=np.float64)
        self.opacity = opacity
        self.noise = noise

    def spacing(self, h: float) -> float:
        hp = h * self.detail
        if self.min_count and self.area > 0:
            hp = min(hp, math.sqrt(self.area / self.min_count))
        return hp

    def sample_local(self, h: float, rng: np.random.Generator) -> Samples:  # pragma: no cover
        raise NotImplementedError

    def sample(self, h: float, rng: np.random.Generator) -> Samples:
        return self.sample_local(self.spacing(h), rng).transformed(self.rot, self.center)


class Ellipsoid(Part):
    """Ellipsoid surface: a Fibonacci sphere mapped by diag(radii); each splat's tangent axes and
    sizes follow the map's Jacobian, so coverage stays even on elongated shapes."""

    def __init__(self, radii, color, **kw):
        super().__init__(color, **kw)
        self.radii = np.asarray(radii, dtype=np.float64)
        a, b, c = self.radii
        p = 1.6075  # Knud Thomsen's approximation of the ellipsoid area
        self.area = 4.0 * math.pi * (((a * b) ** p + (a * c) ** p + (b * c) ** p) / 3.0) ** (1.0 / p)

    def sample_local(self, h, rng):
        n = max(self.min_count, 8, math.ceil(self.area / h**2))
        i = np.arange(n) + 0.5
        z = 1.0 - 2.0 * i / n
        rho = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
        phi = math.pi * (3.0 - math.sqrt(5.0)) * i
        d = np.stack([rho * np.cos(phi), rho * np.sin(phi), z], 1)
        e1 = _perpendicular(d)
        e2 = np.cross(d, e1)
        J = np.stack([e1 * self.radii, e2 * self.radii], 2)  # (n, 3, 2): images of the sphere's tangents
        U, S, _ = np.linalg.svd(J, full_matrices=False)
        spacing = math.sqrt(4.0 * math.pi / n) * 1.07
        t1 = U[:, :, 0]
        normal = _unit(np.cross(J[:, :, 0], J[:, :, 1]))
        t2 = np.cross(normal, t1)
        return Samples(d * self.radii, t1, t2, normal, spacing * S[:, 0], spacing * S[:, 1])


class RoundedBox(Part):
    """Superellipsoid ``sum |x_i / r_i|^p = 1`` (a pillow-like rounded box for p ~ 4-8): a grid on
    the box of half-extents ``radii``, projected radially onto the surface."""

    def __init__(self, radii, color, power: float = 6.0, **kw):
        super().__init__(color, **kw)
        self.radii = np.asarray(radii, dtype=np.float64)
        self.power = power
        a, b, c = self.radii
        self.area = 8.0 * (a * b + a * c + b * c) * 0.9

    def _project(self, q):
        t = np.sum(np.abs(q / self.radii) ** self.power, axis=-1, keepdims=True) ** (-1.0 / self.power)
        return q * t

    def sample_local(self, h, rng):
        pts, t1s, t2s, ns, s1s, s2s = [], [], [], [], [], []
        for axis in range(3):
            u_axis, v_axis = [k for k in range(3) if k != axis]
            nu = max(2, math.ceil(2 * self.radii[u_axis] / h))
            nv = max(2, math.ceil(2 * self.radii[v_axis] / h))
            du, dv = 2 * self.radii[u_axis] / nu, 2 * self.radii[v_axis] / nv
            uu, vv = np.meshgrid(
                (np.arange(nu) + 0.5) * du - self.radii[u_axis], (np.arange(nv) + 0.5) * dv - self.radii[v_axis], indexing="ij"
            )
            for sign in (-1.0, 1.0):
                q = np.zeros((nu * nv, 3))
                q[:, u_axis], q[:, v_axis] = uu.ravel(), vv.ravel()
                q[:, axis] = sign * self.radii[axis]
                eu, ev = np.zeros(3), np.zeros(3)
                eu[u_axis], ev[v_axis] = 1e-4 * du, 1e-4 * dv
                p = self._project(q)
                ju = (self._project(q + eu) - self._project(q - eu)) / 2e-4  # per grid step
                jv = (self._project(q + ev) - self._project(q - ev)) / 2e-4
                grad = np.sign(p) * np.abs(p / self.radii) ** (self.power - 1) / self.radii
                normal = _unit(grad)
                t1 = _unit(ju - np.sum(ju * normal, 1, keepdims=True) * normal)
                t2 = np.cross(normal, t1)
                pts.append(p)
                t1s.append(t1)
                t2s.append(t2)
                ns.append(normal)
                s1s.append(np.maximum(np.linalg.norm(ju, axis=1), 1e-6))
                s2s.append(np.maximum(np.abs(np.sum(jv * t2, 1)), np.linalg.norm(jv, axis=1) * 0.5))
        return Samples(
            np.concatenate(pts),
            np.concatenate(t1s),
            np.concatenate(t2s),
            np.concatenate(ns),
            np.concatenate(s1s),
            np.concatenate(s2s),
        )


class Box(Part):
    """Axis-aligned (before ``rot``) box surface; ``faces`` picks which of "+x -x +y -y +z -z"."""

    _FACES = {"+x": (0, 1.0), "-x": (0, -1.0), "+y": (1, 1.0), "-y": (1, -1.0), "+z": (2, 1.0), "-z": (2, -1.0)}

    def __init__(self, half, color, faces: str = "+x -x +y -y +z -z", **kw):
        super().__init__(color, **kw)
        self.half = np.asarray(half, dtype=np.float64)
        self.faces = faces.split()
        self.area = sum(4 * np.prod([self.half[k] for k in range(3) if k != self._FACES[f][0]]) for f in self.faces)

    def sample_local(self, h, rng):
        pts, t1s, t2s, ns, s1s, s2s = [], [], [], [], [], []
        for face in self.faces:
            axis, sign = self._FACES[face]
            u_axis, v_axis = [k for k in range(3) if k != axis]
            nu = max(1, round(2 * self.half[u_axis] / h))
            nv = max(1, round(2 * self.half[v_axis] / h))
            du, dv = 2 * self.half[u_axis] / nu, 2 * self.half[v_axis] / nv
            uu, vv = np.meshgrid(
                (np.arange(nu) + 0.5) * du - self.half[u_axis], (np.arange(nv) + 0.5) * dv - self.half[v_axis], indexing="ij"
            )
            k = nu * nv
            p = np.zeros((k, 3))
            p[:, u_axis] = uu.ravel() + rng.uniform(-0.15, 0.15, k) * du
            p[:, v_axis] = vv.ravel() + rng.uniform(-0.15, 0.15, k) * dv
            p[:, axis] = sign * self.half[axis]
            t1, t2, normal = np.zeros((k, 3)), np.zeros((k, 3)), np.zeros((k, 3))
            t1[:, u_axis] = 1.0
            t2[:, v_axis] = 1.0
            normal[:, axis] = sign
            pts.append(p)
            t1s.append(t1)
            t2s.append(t2)
            ns.append(normal)
            s1s.append(np.full(k, du))
            s2s.append(np.full(k, dv))
        return Samples(
            np.concatenate(pts),
            np.concatenate(t1s),
            np.concatenate(t2s),
            np.concatenate(ns),
            np.concatenate(s1s),
            np.concatenate(s2s),
        )


class Lathe(Part):
    """Surface of revolution about +z through the profile ``(z_k, r_k)``, optionally with flat caps
    at the first and/or last profile point."""

    def __init__(self, zs, rs, color, cap_start: bool = False, cap_end: bool = False, **kw):
        super().__init__(color, **kw)
        self.zs = np.asarray(zs, dtype=np.float64)
        self.rs = np.asarray(rs, dtype=np.float64)
        self.cap_start, self.cap_end = cap_start, cap_end
        seg = np.hypot(np.diff(self.zs), np.diff(self.rs))
        self.arclen = np.concatenate([[0.0], np.cumsum(seg)])
        area = float(np.sum(math.pi * (self.rs[:-1] + self.rs[1:]) * seg))
        if cap_start:
            area += math.pi * self.rs[0] ** 2
        if cap_end:
            area += math.pi * self.rs[-1] ** 2
        self.area = area

    def sample_local(self, h, rng):
        length = self.arclen[-1]
        count = max(1, math.ceil(length / h))
        ds = length / count
        s = (np.arange(count) + 0.5) * ds
        z = np.interp(s, self.arclen, self.zs)
        r = np.interp(s, self.arclen, self.rs)
        seg = np.clip(np.searchsorted(self.arclen, s) - 1, 0, len(self.zs) - 2)
        dz, dr = np.diff(self.zs)[seg], np.diff(self.rs)[seg]
        norm = np.maximum(np.hypot(dz, dr), 1e-12)
        phase = (np.arange(count) * _GOLDEN) % 1.0
        parts = [_ring_samples(r, z, dr / norm, dz / norm, h, np.full(count, ds), phase)]
        caps = ((self.cap_start, self.rs[0], self.zs[0], -1.0), (self.cap_end, self.rs[-1], self.zs[-1], 1.0))
        for flag, radius, height, facing in caps:
            if flag and radius > 0:
                parts.append(_disk_samples(radius, h, facing=facing).transformed(np.eye(3), np.array([0.0, 0.0, height])))
        return Samples.concat(parts)


def _disk_samples(radius: float, h: float, inner: float = 0.0, facing: float = 1.0) -> Samples:
    """Rings filling the annulus ``inner <= r <= radius`` in the plane z = 0, normal ``facing`` * z."""
    count = max(1, math.ceil((radius - inner) / h))
    dr = (radius - inner) / count
    r = inner + (np.arange(count) + 0.5) * dr
    return _ring_samples(
        r, np.zeros(count), np.full(count, -facing), np.zeros(count), h, np.full(count, dr), (np.arange(count) * _GOLDEN) % 1.0
    )


class Disk(Part):
    """Flat disk (or annulus) of ``radius`` in the local z = 0 plane (normal +z before ``rot``)."""

    def __init__(self, radius, color, inner: float = 0.0, **kw):
        super().__init__(color, **kw)
        self.radius, self.inner = float(radius), float(inner)
        self.area = math.pi * (self.radius**2 - self.inner**2)

    def sample_local(self, h, rng):
        return _disk_samples(self.radius, h, self.inner)


class Tube(Part):
    """Tube of ``radius`` along the polyline ``path`` (k, 3), frames by parallel transport."""

    def __init__(self, path, radius, color, **kw):
        super().__init__(color, **kw)
        self.path = np.asarray(path, dtype=np.float64)
        self.radius = float(radius)
        seg = np.linalg.norm(np.diff(self.path, axis=0), axis=1)
        self.arclen = np.concatenate([[0.0], np.cumsum(seg)])
        self.area = 2.0 * math.pi * self.radius * self.arclen[-1]

    def sample_local(self, h, rng):
        length = self.arclen[-1]
        count = max(2, math.ceil(length / h))
        ds = length / count
        s = (np.arange(count) + 0.5) * ds
        centers = np.stack([np.interp(s, self.arclen, self.path[:, k]) for k in range(3)], 1)
        seg = np.clip(np.searchsorted(self.arclen, s) - 1, 0, len(self.path) - 2)
        tangents = _unit(np.diff(self.path, axis=0)[seg])
        around = max(4, math.ceil(2.0 * math.pi * self.radius / h))
        normal = _perpendicular(tangents[:1])[0]
        pts, t1s, t2s, ns = [], [], [], []
        for k in range(count):
            T = tangents[k]
            normal = _unit((normal - (normal @ T) * T)[None])[0]
            binormal = np.cross(T, normal)
            phi = 2.0 * math.pi * (np.arange(around) + 0.5 * (k % 2)) / around
            radial = np.cos(phi)[:, None] * normal + np.sin(phi)[:, None] * binormal
            pts.append(centers[k] + self.radius * radial)
            t1s.append(np.cross(T, radial))
            t2s.append(np.broadcast_to(T, (around, 3)))
            ns.append(radial)
        n = count * around
        return Samples(
            np.concatenate(pts),
            np.concatenate(t1s),
            np.concatenate(t2s).copy(),
            np.concatenate(ns),
            np.full(n, 2.0 * math.pi * self.radius / around),
            np.full(n, ds),
        )


# --- building ------------------------------------------------------------------------------------


def lattice_hash(ix: np.ndarray, iy: np.ndarray, iz: np.ndarray, salt: int) -> np.ndarray:
    """Deterministic pseudo-random values in [0, 1) on an integer lattice (a 64-bit mix)."""
    with np.errstate(over="ignore"):
        h = ix.astype(np.uint64) * np.uint64(0x9E3779B97F4A7C15)
        h ^= iy.astype(np.uint64) * np.uint64(0xC2B2AE3D27D4EB4F)
        h ^= iz.astype(np.uint64) * np.uint64(0x165667B19E3779F9)
        h ^= np.uint64(salt & 0xFFFFFFFF) * np.uint64(0xD6E8FEB86659FD93)
        for shift, mult in ((31, 0xBF58476D1CE4E5B9), (29, 0x94D049BB133111EB)):
            h ^= h >> np.uint64(shift)
            h *= np.uint64(mult)
        h ^= h >> np.uint64(32)
    return (h >> np.uint64(11)).astype(np.float64) / float(2**53)


def material_noise(points: np.ndarray, cell: float, salt: int) -> np.ndarray:
    """3D value noise in [0, 1] with features of about ``cell``, plus a finer octave: the mottled
    surface texture of an object's material (what gives SIFT something to hold on)."""
    out = np.zeros(len(points))
    for octave, (size, weight) in enumerate(((1.0, 0.65), (0.45, 0.35))):
        g = points / (cell * size)
        i = np.floor(g).astype(np.int64)
        f = g - i
        f = f * f * (3.0 - 2.0 * f)
        value = np.zeros(len(points))
        for dx in (0, 1):
            for dy in (0, 1):
                for dz in (0, 1):
                    w = (f[:, 0] if dx else 1 - f[:, 0]) * (f[:, 1] if dy else 1 - f[:, 1]) * (f[:, 2] if dz else 1 - f[:, 2])
                    value += w * lattice_hash(i[:, 0] + dx, i[:, 1] + dy, i[:, 2] + dz, salt * 7 + octave)
        out += weight * value
    return out


@dataclass
class ObjectGaussians:
    """Gaussians of one object in its local frame (float64 numpy arrays).

    Attributes:
        means: (N, 3); quats: (N, 4) ``wxyz``; scales: (N, 3) positive standard deviations;
        opacities: (N,) in (0, 1); rgb: (N, 3) albedo in [0, 1] (unlit, see :func:`bake_lighting`);
        front_feature: (N,) bool, the Gaussians of the canonical front feature (all False for a
            symmetric object);
        normals: (N, 3) outward unit surface normals (the splats' thin axis);
        emissive: (N,) bool, light-emitting surfaces (screens, bulbs, headlights) that lighting
            leaves as they are.
    """

    means: np.ndarray
    quats: np.ndarray
    scales: np.ndarray
    opacities: np.ndarray
    rgb: np.ndarray
    front_feature: np.ndarray
    normals: np.ndarray
    emissive: np.ndarray

    def __len__(self) -> int:
        return len(self.means)

    def scaled(self, factor: float) -> ObjectGaussians:
        return dataclasses.replace(self, means=self.means * factor, scales=self.scales * factor)

    def lit(self, light=None) -> np.ndarray:
        """Colours with :func:`bake_lighting` applied in this frame."""
        return bake_lighting(self.rgb, self.normals, self.emissive, light)


LIGHT_DIRECTION = (0.35, 0.25, 0.9)  # towards the key light: high, front-left of +x


def bake_lighting(rgb: np.ndarray, normals: np.ndarray, emissive: np.ndarray | None = None, light=None) -> np.ndarray:
    """Lambertian shading baked into colours (SH degree 0 has no view dependence, so shading
    is what shows shape): ``albedo * (ambient + sky + key * max(0, n . l))``; emissive rows keep
    their colour. ``light`` points towards the light (default :data:`LIGHT_DIRECTION`, z up)."""
    l = _unit(np.asarray(LIGHT_DIRECTION if light is None else light, dtype=np.float64)[None])[0]  # noqa: E741
    key = np.clip(normals @ l, 0.0, None)
    sky = 0.5 * (1.0 + normals[:, 2])
    factor = 0.42 + 0.18 * sky + 0.55 * key
    out = np.clip(rgb * factor[:, None], 0.0, 1.0)
    if emissive is not None:
        out[emissive] = rgb[emissive]
    return out


class ShapeBuilder:
    """Collects primitives, then samples them all with one spacing chosen so the object gets about
    ``target`` Gaussians (a primitive's ``detail`` scales its spacing; ``min_count`` guarantees
    small features enough samples)."""

    def __init__(self, texture_cell: float | None = None):
        self.parts: list[Part] = []
        self.texture_cell = texture_cell  # feature size of the material texture (default 2.5 spacings)

    def add(self, part: Part) -> Part:
        self.parts.append(part)
        return part

    def ellipsoid(self, center, radii, color, **kw):
        return self.add(Ellipsoid(radii, color, center=center, **kw))

    def sphere(self, center, radius, color, **kw):
        return self.add(Ellipsoid((radius, radius, radius), color, center=center, **kw))

    def rounded_box(self, center, half, color, power: float = 6.0, **kw):
        return self.add(RoundedBox(half, color, power=power, center=center, **kw))

    def box(self, center, half, color, **kw):
        return self.add(Box(half, color, center=center, **kw))

    def lathe(self, zs, rs, color, **kw):
        return self.add(Lathe(zs, rs, color, **kw))

    def cylinder(self, base, radius, height, color, axis=(0.0, 0.0, 1.0), caps: bool = True, **kw):
        R = rotation_from_z(axis)
        return self.add(Lathe([0.0, height], [radius, radius], color, cap_start=caps, cap_end=caps, rot=R, center=base, **kw))

    def disk(self, center, radius, color, normal=(0.0, 0.0, 1.0), **kw):
        return self.add(Disk(radius, color, rot=rotation_from_z(normal), center=center, **kw))

    def tube(self, path, radius, color, **kw):
        return self.add(Tube(path, radius, color, **kw))

    def build(self, target: int, rng: np.random.Generator) -> ObjectGaussians:
        total = sum(p.area / p.detail**2 for p in self.parts)
        h = math.sqrt(total / max(target, 1))
        salt = int(rng.integers(2**31))
        if self.texture_cell is None:
            self.texture_cell = 2.5 * h
        chunks = []
        for part in self.parts:
            samples = part.sample(h, rng)
            k = len(samples.points)
            if callable(part.color):
                base = np.asarray(part.color(samples.points, part), dtype=np.float64).reshape(k, 3)
            else:
                base = np.broadcast_to(_rgb(part.color), (k, 3))
            grain = part.noise * rng.standard_normal((k, 1))
            if part.texture > 0:
                grain = grain + part.texture * (material_noise(samples.points, self.texture_cell, salt) - 0.5)[:, None]
            rgb = np.clip(base * (1.0 + grain), 0.0, 1.0)
            normal = _unit(samples.normal)
            t1 = _unit(samples.t1 - np.sum(samples.t1 * normal, 1, keepdims=True) * normal)
            t2 = np.cross(normal, t1)
            R = np.stack([t1, t2, normal], axis=2)
            s1, s2 = samples.s1 * SIGMA_PER_SPACING, samples.s2 * SIGMA_PER_SPACING
            sn = np.maximum(NORMAL_PER_SPACING * np.minimum(samples.s1, samples.s2), 1e-5)
            scales = np.stack([s1, s2, sn], 1)
            opac = np.clip(part.opacity + rng.uniform(-0.04, 0.04, k), 0.05, 0.995)
            chunks.append((samples.points, R, scales, opac, rgb, np.full(k, part.feature), normal, np.full(k, part.emissive)))
        means = np.concatenate([c[0] for c in chunks])
        R = np.concatenate([c[1] for c in chunks])
        quats = rotmat_to_quat(torch.from_numpy(R)).numpy()
        return ObjectGaussians(
            means=means,
            quats=quats,
            scales=np.concatenate([c[2] for c in chunks]),
            opacities=np.concatenate([c[3] for c in chunks]),
            rgb=np.concatenate([c[4] for c in chunks]),
            front_feature=np.concatenate([c[5] for c in chunks]).astype(bool),
            normals=np.concatenate([c[6] for c in chunks]),
            emissive=np.concatenate([c[7] for c in chunks]).astype(bool),
        )


# --- the catalog ---------------------------------------------------------------------------------

Design = Callable[[ShapeBuilder, np.ndarray, np.random.Generator], None]


@dataclass(frozen=True)
class ObjectSpec:
    """A catalog entry.

    Attributes:
        name: canonical name; aliases: other names it answers to.
        symmetric: True when the object has no canonical front.
        colors: colour names an instance may take (the instance's colour becomes an attribute).
        target: number of Gaussians at density 1.
        design: fills a :class:`ShapeBuilder` given the instance's base colour and an RNG
            (None for a captured object).
        wall: prefers to stand with its back against a wall (rooms).
        front_description: what marks the front (docs and error messages).
        captured: the real 3DGS file a captured object is read from (``config/captured.yaml``);
            None for a parametric object.
    """

    name: str
    aliases: tuple[str, ...]
    symmetric: bool
    colors: tuple[str, ...]
    target: int
    design: Design | None = field(repr=False)
    wall: bool = False
    front_description: str = ""
    captured: CapturedSource | None = None


def _teddy_bear(b: ShapeBuilder, fur: np.ndarray, rng) -> None:
    light = mix(fur, "cream", 0.6)
    dark = (0.05, 0.04, 0.04)
    b.ellipsoid((0.0, 0.0, 0.115), (0.075, 0.088, 0.105), fur)  # body
    b.ellipsoid((0.035, 0.0, 0.105), (0.05, 0.06, 0.075), light, feature=True)  # belly
    b.sphere((0.005, 0.0, 0.255), 0.075, fur)  # head
    for side in (-1.0, 1.0):
        b.ellipsoid((-0.005, side * 0.058, 0.318), (0.018, 0.026, 0.026), fur)  # ears
        b.ellipsoid((0.008, side * 0.058, 0.318), (0.008, 0.017, 0.017), light)
        b.ellipsoid((0.03, side * 0.088, 0.14), (0.03, 0.028, 0.06), fur, rot=rotation_x(side * 0.35))  # arms
        b.ellipsoid((0.07, side * 0.052, 0.038), (0.078, 0.036, 0.036), fur)  # legs
        b.disk((0.146, side * 0.052, 0.04), 0.026, light, normal=(1.0, 0.0, 0.0), feature=True)  # foot pads
        eye_dir = np.array([math.cos(0.3) * math.cos(0.42), side * math.cos(0.3) * math.sin(0.42), math.sin(0.3)])
        b.sphere(np.array([0.005, 0.0, 0.255]) + 0.071 * eye_dir, 0.0115, dark, feature=True, noise=0.0)
    b.ellipsoid((0.066, 0.0, 0.236), (0.034, 0.04, 0.029), light, feature=True)  # snout
    b.ellipsoid((0.099, 0.0, 0.248), (0.011, 0.018, 0.012), dark, feature=True, noise=0.0)  # nose


def _seat_furniture(b: ShapeBuilder, fabric: np.ndarray, rng, width: float, seats: int) -> None:
    """Armchair (seats = 1) or sofa: backrest at -x, arms at +-y, seat cushions open to +x."""
    depth, half_w = 0.86, width / 2.0
    cushion = shade(fabric, 1.18)
    dark = shade(fabric, 0.75)
    wood = (0.22, 0.14, 0.08)
    b.rounded_box((0.0, 0.0, 0.22), (depth / 2, half_w - 0.02, 0.13), dark, power=8)  # base
    b.rounded_box((-depth / 2 + 0.1, 0.0, 0.53), (0.1, half_w, 0.33), fabric, power=8)  # backrest
    for side in (-1.0, 1.0):
        b.rounded_box((0.0, side * (half_w - 0.065), 0.34), (depth / 2, 0.065, 0.23), fabric, power=8)
        for x in (-depth / 2 + 0.05, depth / 2 - 0.05):
            b.cylinder((x, side * (half_w - 0.05), 0.0), 0.022, 0.1, wood)
    inner = half_w - 0.13
    w = 2 * inner / seats
    for k in range(seats):
        y = -inner + (k + 0.5) * w
        b.rounded_box((0.06, y, 0.405), (0.32, w / 2 - 0.01, 0.055), cushion, power=6, feature=True)
        b.rounded_box(
            (-depth / 2 + 0.24, y, 0.62), (0.05, w / 2 - 0.015, 0.19), cushion, power=6, feature=True, rot=rotation_y(-0.18)
        )


def _armchair(b, fabric, rng):
    _seat_furniture(b, fabric, rng, width=0.86, seats=1)


def _sofa(b, fabric, rng):
    seats = int(rng.integers(2, 4))
    _seat_furniture(b, fabric, rng, width=0.75 + 0.6 * seats, seats=seats)


def _wood_grain(base):
    base = _rgb(base)

    def color(p, part):
        stripes = 0.5 + 0.5 * np.sin(p[:, 1] * 90.0 + 3.0 * np.sin(p[:, 0] * 7.0))
        return base[None] * (0.88 + 0.18 * stripes[:, None])

    return color


def _coffee_table(b, wood, rng):
    length, width, height = 1.0 + 0.2 * rng.random(), 0.55 + 0.1 * rng.random(), 0.44
    b.box((0.0, 0.0, height - 0.025), (length / 2, width / 2, 0.025), _wood_grain(wood))
    b.box((0.0, 0.0, 0.12), (length / 2 - 0.06, width / 2 - 0.06, 0.012), _wood_grain(shade(wood, 0.9)))
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            b.box(
                (sx * (length / 2 - 0.05), sy * (width / 2 - 0.05), (height - 0.05) / 2),
                (0.025, 0.025, (height - 0.05) / 2),
                shade(wood, 0.8),
                faces="+x -x +y -y",
            )


def _floor_lamp(b, shade_color, rng):
    metal = (0.15, 0.15, 0.16)
    b.lathe([0.0, 0.0, 0.03, 0.03], [0.0, 0.16, 0.16, 0.0], metal)  # base
    b.tube([(0.0, 0.0, 0.03), (0.0, 0.0, 1.33)], 0.014, metal)
    b.lathe([1.3, 1.62], [0.24, 0.15], shade_color, opacity=0.96)  # shade
    b.sphere((0.0, 0.0, 1.38), 0.05, (1.0, 0.96, 0.8), noise=0.0, emissive=True)
    b.lathe([1.3, 1.3], [0.24, 0.2], shade(shade_color, 0.7))  # rim below the shade


def _ball(b, color, rng):
    axis = _unit(rng.standard_normal(3)[None])[0]
    x_axis = _perpendicular(axis[None])[0]
    other = ("white",) if not np.allclose(color, COLORS["white"]) else ("blue",)
    second = _rgb(other[0])
    third = _rgb("yellow") if not np.allclose(color, COLORS["yellow"]) else _rgb("red")

    def beach(p, part):
        q = p - np.array([0.0, 0.0, 0.11])
        u = q @ x_axis
        v = q @ np.cross(axis, x_axis)
        seg = np.floor((np.arctan2(v, u) + math.pi) / (2 * math.pi) * 6).astype(int) % 6
        palette = np.stack([_rgb(color), second, third, _rgb(color), second, third])
        out = palette[seg]
        cap = np.abs(q @ axis) > 0.095
        out[cap] = second
        return out

    b.sphere((0.0, 0.0, 0.11), 0.11, beach)


def _television(b, frame, rng):
    width, height, bottom = 1.1, 0.64, 0.46
    zc = bottom + height / 2
    b.box((0.0, 0.0, zc), (0.03, width / 2, height / 2), frame, faces="-x +y -y +z -z")
    border = 0.03
    for y, half_y, z, half_z in (
        (0.0, width / 2, zc + height / 2 - border / 2, border / 2),
        (0.0, width / 2, zc - height / 2 + border / 2, border / 2),
        (width / 2 - border / 2, border / 2, zc, height / 2 - border),
        (-width / 2 + border / 2, border / 2, zc, height / 2 - border),
    ):  # bezel
        b.box((0.03, y, z), (0.0005, half_y, half_z), frame, faces="+x", min_count=20)
    b.box((-0.07, 0.0, zc - 0.03), (0.045, width * 0.3, height * 0.3), shade(frame, 0.85), faces="-x +y -y +z -z")
    b.box((-0.02, 0.0, bottom / 2 + 0.02), (0.025, 0.05, bottom / 2), shade(frame, 0.9))  # neck
    b.box((0.0, 0.0, 0.015), (0.17, 0.3, 0.015), shade(frame, 0.9))  # foot
    sw, sh = width / 2 - 0.032, height / 2 - 0.032

    def picture(p, part):
        u = (p[:, 1] + sw) / (2 * sw)  # 0 on the screen's right edge (-y), 1 on its left
        v = (p[:, 2] - (zc - sh)) / (2 * sh)  # 0 at the bottom
        sky = np.stack([0.1 + 0.35 * (1 - v), 0.45 + 0.35 * (1 - v), np.full_like(v, 1.0)], 1)
        hills = v < 0.38 + 0.08 * np.sin(u * 9.0)
        out = np.where(hills[:, None], np.array([[0.2, 0.8, 0.15]]), sky)
        sun = (u - 0.72) ** 2 + ((v - 0.7) * 0.58) ** 2 < 0.012
        out[sun] = (1.0, 0.95, 0.35)
        house = (np.abs(u - 0.3) < 0.07) & (v > 0.25) & (v < 0.45)
        out[house] = (1.0, 0.35, 0.3)
        return out

    b.box((0.03, 0.0, zc), (0.0005, sw, sh), picture, faces="+x", feature=True, detail=0.7, noise=0.01, emissive=True)


def _potted_plant(b, pot, rng):
    b.lathe([0.0, 0.0, 0.24, 0.24, 0.27, 0.27, 0.2], [0.0, 0.1, 0.13, 0.145, 0.145, 0.125, 0.12], pot)
    b.disk((0.0, 0.0, 0.215), 0.122, (0.22, 0.15, 0.1))  # soil
    leaves = int(rng.integers(12, 18))
    for k in range(leaves):
        az = 2 * math.pi * (k * _GOLDEN) + rng.uniform(-0.2, 0.2)
        el = rng.uniform(0.35, 1.25)
        length = rng.uniform(0.2, 0.32)
        base_z = 0.22 + rng.uniform(0.0, 0.18)
        d = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
        green = np.array([0.16, 0.45 + rng.uniform(-0.08, 0.1), 0.16 + rng.uniform(0.0, 0.08)])
        R = rotation_z(az) @ rotation_y(-el)  # leaf x-axis along d
        b.ellipsoid(
            np.array([0.0, 0.0, base_z]) + d * length * 0.55, (length / 2, length * 0.16, 0.006), green, rot=R, detail=0.8
        )
    b.tube([(0.0, 0.0, 0.2), (0.0, 0.0, 0.42)], 0.01, (0.2, 0.35, 0.15))


def _mug(b, color, rng):
    r_out, r_in, height = 0.042, 0.037, 0.096
    b.lathe([0.0, 0.0, height, height, 0.008], [0.0, r_out, r_out, r_in, r_in], color)
    b.disk((0.0, 0.0, 0.008), r_in, shade(color, 0.6))
    t = np.linspace(0.0, math.pi, 14)
    path = np.stack([np.zeros_like(t), r_out - 0.003 + 0.03 * np.sin(t), 0.049 + 0.028 * np.cos(t)], 1)
    b.tube(path, 0.0065, color)


def _toy_car(b, paint, rng):
    glass = (0.55, 0.75, 0.9)
    black = (0.06, 0.06, 0.07)
    b.rounded_box((0.0, 0.0, 0.058), (0.13, 0.062, 0.03), paint, power=8)  # body
    b.rounded_box((-0.025, 0.0, 0.104), (0.06, 0.054, 0.026), paint, power=8)  # cabin
    b.box((0.032, 0.0, 0.106), (0.004, 0.045, 0.016), glass, faces="+x", feature=True, rot=rotation_y(0.5))
    b.box((-0.082, 0.0, 0.106), (0.003, 0.045, 0.016), glass, faces="-x", rot=rotation_y(-0.5))
    for side in (-1.0, 1.0):
        b.box((-0.025, side * 0.0545, 0.106), (0.04, 0.001, 0.014), glass, faces="+y" if side > 0 else "-y")
        for x in (-0.08, 0.08):
            b.cylinder((x, side * 0.055, 0.03), 0.03, 0.022, black, axis=(0.0, side, 0.0))
            b.disk((x, side * 0.0775, 0.03), 0.016, (0.75, 0.75, 0.78), normal=(0.0, side, 0.0), noise=0.0)
        b.ellipsoid((0.128, side * 0.038, 0.064), (0.008, 0.014, 0.011), (1.0, 0.97, 0.7), feature=True, noise=0.0, emissive=True)
        b.ellipsoid((-0.129, side * 0.04, 0.066), (0.006, 0.014, 0.008), (0.95, 0.08, 0.06), noise=0.0, emissive=True)
    b.box((0.131, 0.0, 0.05), (0.002, 0.022, 0.012), (0.15, 0.15, 0.17), faces="+x", feature=True)  # grille
    b.box((0.131, 0.0, 0.033), (0.003, 0.06, 0.006), (0.8, 0.8, 0.82), faces="+x +z", feature=True)  # bumper


_BOOK_COLORS = (
    (0.75, 0.15, 0.12),
    (0.12, 0.3, 0.65),
    (0.15, 0.5, 0.25),
    (0.9, 0.75, 0.2),
    (0.92, 0.9, 0.85),
    (0.45, 0.2, 0.5),
    (0.9, 0.45, 0.15),
    (0.1, 0.1, 0.1),
    (0.2, 0.6, 0.7),
)


def _bookshelf(b, wood, rng):
    width, depth, height, t = 0.9, 0.32, 1.8, 0.02
    hd, hw = depth / 2, width / 2
    for side in (-1.0, 1.0):
        b.box((0.0, side * (hw - t / 2), height / 2), (hd, t / 2, height / 2), wood)
    b.box((-hd + 0.005, 0.0, height / 2), (0.005, hw - t, height / 2), shade(wood, 0.85), faces="+x -x")
    levels = 5
    gap = (height - t) / levels
    for k in range(levels + 1):
        b.box((0.0, 0.0, k * gap + t / 2), (hd, hw - t, t / 2), shade(wood, 1.05), faces="+x +z -z")
    for k in range(levels):
        y = -hw + t + 0.01
        while True:
            bw = rng.uniform(0.025, 0.05)
            if y + bw > hw - t - 0.005:
                break
            if rng.random() < 0.06:  # an occasional gap
                y += bw
                continue
            bh = gap * rng.uniform(0.62, 0.86)
            bd = rng.uniform(0.19, 0.25)
            color = np.array(_BOOK_COLORS[int(rng.integers(len(_BOOK_COLORS)))]) * rng.uniform(0.8, 1.1)
            b.box(
                (hd - 0.04 - bd / 2, y + bw / 2, k * gap + t + bh / 2),
                (bd / 2, bw / 2 - 0.001, bh / 2),
                np.clip(color, 0, 1),
                faces="+x +z +y -y",
                feature=True,
                detail=0.6,
                min_count=1,
            )
            y += bw


def _refrigerator(b, color, rng):
    width, depth, height = 0.7, 0.68, 1.78
    hw, hd = width / 2, depth / 2
    steel = (0.55, 0.56, 0.58)

    def coils(p, part):
        lines = np.floor(p[:, 2] / 0.05) % 2 == 0
        return np.where(lines[:, None], np.array([[0.12, 0.12, 0.12]]), np.array([[0.3, 0.3, 0.3]]))

    b.box((0.0, 0.0, height / 2), (hd, hw, height / 2), color, faces="+y -y +z")
    b.box((-hd, 0.0, height / 2 + 0.05), (0.001, hw - 0.03, height / 2 - 0.1), coils, faces="-x")
    b.box((-hd + 0.002, 0.0, height / 2), (0.001, hw, height / 2), shade(color, 0.8), faces="-x", detail=2.0)
    b.box((hd, 0.0, height / 2), (0.001, hw, height / 2), (0.12, 0.12, 0.13), faces="+x", detail=1.5)  # seams
    split = 1.15
    door = shade(color, 1.04)
    b.box(
        (hd + 0.02, 0.0, (split + height) / 2 + 0.005),
        (0.02, hw - 0.006, (height - split) / 2 - 0.012),
        door,
        faces="+x +y -y +z -z",
        feature=True,
    )
    b.box((hd + 0.02, 0.0, split / 2 + 0.02), (0.02, hw - 0.006, split / 2 - 0.028), door, faces="+x +y -y +z -z", feature=True)
    y = hw - 0.07
    for z0, z1 in ((split + 0.08, split + 0.4), (split - 0.45, split - 0.06)):
        b.tube(
            [(hd + 0.04, y, z0), (hd + 0.085, y, z0 + 0.02), (hd + 0.085, y, z1 - 0.02), (hd + 0.04, y, z1)],
            0.013,
            steel,
            feature=True,
        )
    b.box((hd + 0.041, -hw + 0.12, height - 0.12), (0.001, 0.06, 0.02), (0.2, 0.2, 0.22), faces="+x", feature=True)


def _cushion(b, color, rng):
    stripe = shade(color, 1.3)
    base = _rgb(color)

    def stripes(p, part):
        s = np.floor((p[:, 0] + p[:, 1]) / 0.05) % 2 == 0
        return np.where(s[:, None], base[None], stripe[None])

    b.rounded_box((0.0, 0.0, 0.065), (0.2, 0.2, 0.065), stripes, power=4)
    for z in (0.0, 0.13):
        b.sphere((0.0, 0.0, z), 0.012, shade(color, 0.6), noise=0.0)


def _vase(b, color, rng):
    z = np.linspace(0.0, 0.3, 24)
    r = 0.045 + 0.045 * np.sin(np.clip(z / 0.22, 0, 1) * math.pi) ** 1.2 - 0.01 * (z > 0.22) * (z - 0.22) / 0.08
    r = np.maximum(r, 0.034) + np.where(z > 0.27, (z - 0.27) * 0.5, 0.0)
    band = _rgb("white") if not np.allclose(color, COLORS["white"]) else _rgb("blue")
    base = _rgb(color)

    def banded(p, part):
        in_band = np.abs(p[:, 2] - 0.11) < 0.018
        return np.where(in_band[:, None], band[None], base[None])

    b.lathe(np.concatenate([[0.0], z]), np.concatenate([[0.0], r]), banded)
    b.lathe([0.3, 0.24], [r[-1] - 0.004, 0.03], shade(color, 0.35))  # inside of the neck


def _bench(b, wood, rng):
    length, metal = 1.5, (0.12, 0.12, 0.13)
    for k in range(3):
        b.box((0.16 - k * 0.11, 0.0, 0.44), (0.05, length / 2, 0.015), _wood_grain(wood), feature=True)
    for k in range(3):
        b.box((-0.22, 0.0, 0.58 + k * 0.12), (0.012, length / 2, 0.05), _wood_grain(shade(wood, 0.95)), rot=rotation_y(-0.12))
    for y in (-length / 2 + 0.08, length / 2 - 0.08):
        b.box((0.12, y, 0.22), (0.025, 0.02, 0.22), metal, faces="+x -x +y -y")
        b.box((-0.2, y, 0.45), (0.025, 0.02, 0.45), metal, faces="+x -x +y -y")
        b.box((-0.03, y, 0.62), (0.2, 0.02, 0.015), metal)  # armrest


def _tree(b, leaves, rng):
    bark = (0.35, 0.24, 0.15)
    height = rng.uniform(3.0, 4.0)
    b.lathe([0.0, height * 0.6], [0.16, 0.1], bark, detail=0.8)
    crown = height * 0.7
    for k in range(7):
        az = 2 * math.pi * k / 7 + rng.uniform(-0.3, 0.3)
        off = rng.uniform(0.3, 0.7)
        c = (off * math.cos(az), off * math.sin(az), crown + rng.uniform(-0.3, 0.5))
        r = rng.uniform(0.6, 0.9)
        b.ellipsoid(c, (r, r, r * 0.85), shade(leaves, rng.uniform(0.85, 1.15)), noise=0.12)
    b.ellipsoid((0.0, 0.0, crown + 0.5), (0.8, 0.8, 0.8), leaves, noise=0.12)


def _traffic_cone(b, color, rng):
    base = _rgb(color)

    def bands(p, part):
        white = (np.abs(p[:, 2] - 0.35) < 0.04) | (np.abs(p[:, 2] - 0.5) < 0.03)
        return np.where(white[:, None], np.array([[0.95, 0.95, 0.95]]), base[None])

    b.box((0.0, 0.0, 0.015), (0.19, 0.19, 0.015), shade(color, 0.6))
    b.lathe([0.03, 0.7, 0.7], [0.15, 0.025, 0.0], bands)


CATALOG: dict[str, ObjectSpec] = {
    spec.name: spec
    for spec in (
        ObjectSpec(
            "teddy bear",
            ("teddy", "stuffed bear", "bear", "plush bear", "stuffed animal"),
            False,
            ("brown", "tan", "cream", "pink", "grey", "white"),
            3000,
            _teddy_bear,
            front_description="face with eyes and snout",
        ),
        ObjectSpec(
            "armchair",
            ("chair", "easy chair", "lounge chair"),
            False,
            ("red", "blue", "green", "grey", "brown", "mustard", "teal", "navy"),
            3000,
            _armchair,
            front_description="seat opening with cushions",
        ),
        ObjectSpec(
            "sofa",
            ("couch", "settee"),
            False,
            ("red", "blue", "green", "grey", "brown", "mustard", "teal", "navy", "beige"),
            4000,
            _sofa,
            front_description="seat opening with cushions",
        ),
        ObjectSpec("coffee table", ("table", "low table"), True, ("brown", "tan", "white", "grey"), 2000, _coffee_table),
        ObjectSpec(
            "floor lamp", ("lamp", "standing lamp"), True, ("white", "cream", "red", "blue", "green", "black"), 1800, _floor_lamp
        ),
        ObjectSpec("ball", ("beach ball", "toy ball"), True, ("red", "blue", "green", "yellow", "orange", "purple"), 1500, _ball),
        ObjectSpec(
            "television",
            ("tv", "television set", "tv set", "screen"),
            False,
            ("black", "grey", "white"),
            3000,
            _television,
            wall=True,
            front_description="bright screen",
        ),
        ObjectSpec(
            "potted plant",
            ("plant", "houseplant", "pot plant"),
            True,
            ("terracotta", "white", "blue", "grey", "black"),
            3000,
            _potted_plant,
        ),
        ObjectSpec("mug", ("cup", "coffee mug", "coffee cup"), True, ("white", "red", "blue", "yellow", "green"), 1500, _mug),
        ObjectSpec(
            "toy car",
            ("car", "model car", "toy vehicle"),
            False,
            ("blue", "yellow", "green", "orange", "white", "purple"),
            2500,
            _toy_car,
            front_description="headlights and windscreen (red tail lights at the back)",
        ),
        ObjectSpec(
            "bookshelf",
            ("bookcase", "shelf", "book shelf"),
            False,
            ("brown", "tan", "white", "grey"),
            8000,
            _bookshelf,
            wall=True,
            front_description="shelf openings with coloured books",
        ),
        ObjectSpec(
            "refrigerator",
            ("fridge", "icebox"),
            False,
            ("white", "silver", "cream", "red"),
            3500,
            _refrigerator,
            wall=True,
            front_description="doors with handles",
        ),
        ObjectSpec(
            "cushion",
            ("pillow", "throw pillow"),
            True,
            ("red", "blue", "green", "yellow", "orange", "purple", "pink", "teal"),
            1500,
            _cushion,
        ),
        ObjectSpec("vase", ("flower vase",), True, ("blue", "white", "red", "green", "black", "terracotta"), 1500, _vase),
        ObjectSpec(
            "bench",
            ("park bench", "garden bench"),
            False,
            ("brown", "tan", "green"),
            3000,
            _bench,
            front_description="seat slats (backrest at the back)",
        ),
        ObjectSpec("tree", ("small tree",), True, ("green",), 4000, _tree),
        ObjectSpec("traffic cone", ("cone", "safety cone"), True, ("orange", "yellow"), 1500, _traffic_cone),
    )
}
PARAMETRIC = tuple(sorted(CATALOG))


def _captured_spec(source: CapturedSource) -> ObjectSpec:
    front = "" if source.front_deg is None else f"annotated in config/captured.yaml ({source.front_deg:g} degrees)"
    return ObjectSpec(
        source.name,
        source.aliases,
        source.front_deg is None,
        (source.color,),
        source.target,
        None,
        front_description=front,
        captured=source,
    )


# Captured objects join when the repository's config/captured.yaml is there (an installed
# package without the repository has the parametric catalog only); their files are read at synth time.
if CAPTURED_CONFIG.is_file():
    for _source in load_captured(CAPTURED_CONFIG):
        if _source.name in CATALOG:
            raise InputError(f"{CAPTURED_CONFIG}: captured object {_source.name!r} has a parametric object's name")
        CATALOG[_source.name] = _captured_spec(_source)


def catalog_names() -> list[str]:
    """Canonical names of the catalog: the parametric ones sorted, then the captured ones
    sorted. The generator keys each object's random stream by this index, so adding captured
    objects leaves the parametric objects (and the scenes made of them) unchanged."""
    return list(PARAMETRIC) + sorted(set(CATALOG) - set(PARAMETRIC))


def _normalise(name: str) -> str:
    return " ".join(name.strip().lower().replace("_", " ").replace("-", " ").split())


def lookup(name: str) -> ObjectSpec | None:
    """The catalog entry called ``name`` or one of its aliases (case and spacing ignored)."""
    key = _normalise(name)
    for spec in CATALOG.values():
        if key == spec.name or key in spec.aliases:
            return spec
    return None


def resolve_names(names: list[str]) -> list[ObjectSpec]:
    """Catalog entries for ``names``; :class:`InputError` listing the catalog (with a "did you
    mean" suggestion) for an unknown name, and for the same object named twice."""
    specs = []
    for name in names:
        spec = lookup(name)
        if spec is None:
            vocabulary = sorted({n for s in CATALOG.values() for n in (s.name, *s.aliases)})
            close = difflib.get_close_matches(_normalise(name), vocabulary, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise InputError(f"unknown object {name!r}{hint} The catalog has: {', '.join(catalog_names())}")
        if spec in specs:
            raise InputError(
                f"object {spec.name!r} is listed twice; scene objects are matched by name, so each catalog object may appear once"
            )
        specs.append(spec)
    return specs


@dataclass
class BuiltObject:
    """One object instance in its local frame (front +x, up +z, base on z = 0).

    Attributes:
        spec: the catalog entry; color: the instance's colour name; size: the size multiplier.
        gaussians: its Gaussians (local frame, metres x size); the lowest mean is at z = 0.
        lo, hi: corners of its local bounding box (means +- 1.5 standard deviations).
        height: top of the bounding box above the base; footprint: radius of the smallest circle
            about the local origin that holds the box's footprint; center: the box centre;
            radius: bounding-sphere radius about ``center``.
    """

    spec: ObjectSpec
    color: str
    size: float
    gaussians: ObjectGaussians
    lo: np.ndarray
    hi: np.ndarray
    height: float
    footprint: float
    center: np.ndarray
    radius: float

    @property
    def name(self) -> str:
        return self.spec.name


def _captured_gaussians(spec: ObjectSpec, density: float) -> ObjectGaussians:
    """A captured object's Gaussians (:func:`capframe.synth.captured.captured_arrays`). Its
    colours are the capture's, lighting included: every Gaussian is marked emissive so that
    :func:`bake_lighting` leaves it. The front feature is its front half: the Gaussians in front
    of the median along +x (what a camera at azimuth 0 sees, and one behind it does not)."""
    a = captured_arrays(spec.captured, density)
    x = a["means"][:, 0]
    front = np.zeros(len(x), dtype=bool) if spec.symmetric else x > np.median(x)
    return ObjectGaussians(
        means=a["means"],
        quats=a["quats"],
        scales=a["scales"],
        opacities=a["opacities"],
        rgb=a["rgb"],
        front_feature=front,
        normals=a["normals"],
        emissive=np.ones(len(x), dtype=bool),
    )


def build_object(
    name: str,
    *,
    rng: np.random.Generator | None = None,
    seed: int = 0,
    density: float = 1.0,
    color: str | None = None,
    size: float = 1.0,
) -> BuiltObject:
    """Build one instance of the catalog object ``name`` (or alias).

    Args:
        rng: random generator (default: one seeded with ``seed``); it picks the colour when
            ``color`` is None and the instance's variations (leaves, books, sofa seats).
        density: multiplies the number of Gaussians (about ``spec.target * density``).
        color: a colour name from :data:`COLORS` (default: one of the object's colours at random).
        size: multiplies every length.
    """
    spec = resolve_names([name])[0]
    rng = np.random.default_rng(seed) if rng is None else rng
    if color is None:
        color = spec.colors[int(rng.integers(len(spec.colors)))]
    elif color not in COLORS:
        raise InputError(f"unknown colour {color!r}; expected one of {', '.join(sorted(COLORS))}")
    if not (density > 0 and math.isfinite(density)):
        raise InputError(f"density {density!r}; expected a positive number")
    if spec.captured is not None:
        gaussians = _captured_gaussians(spec, density)
    else:
        builder = ShapeBuilder()
        spec.design(builder, _rgb(color), rng)
        gaussians = builder.build(max(1, round(spec.target * density)), rng)
    if size != 1.0:
        gaussians = gaussians.scaled(size)
    gaussians.means[:, 2] -= gaussians.means[:, 2].min()  # stand on z = 0
    means = gaussians.means
    extent = 1.5 * gaussians.scales.max(1)
    lo, hi = (means - extent[:, None]).min(0), (means + extent[:, None]).max(0)
    center = (lo + hi) / 2.0
    corners = np.array([[x, y] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])])
    return BuiltObject(
        spec=spec,
        color=color,
        size=size,
        gaussians=gaussians,
        lo=lo,
        hi=hi,
        height=float(hi[2]),
        footprint=float(np.linalg.norm(corners, axis=1).max()),
        center=center,
        radius=float(np.max(np.linalg.norm(means - center, axis=1) + extent)),
    )


__all__ = [
    "CATALOG",
    "PARAMETRIC",
    "COLORS",
    "LIGHT_DIRECTION",
    "ObjectSpec",
    "ObjectGaussians",
    "BuiltObject",
    "ShapeBuilder",
    "build_object",
    "catalog_names",
    "lookup",
    "resolve_names",
    "bake_lighting",
    "material_noise",
    "lattice_hash",
]
