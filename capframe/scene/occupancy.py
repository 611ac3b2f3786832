"""Free space of a scene: where a camera can physically be.

An :class:`Occupancy` is a voxel grid aligned with the world up, built once per scene from its
Gaussians (:func:`build_occupancy`, cached by :func:`cached_occupancy`):

* **occupied**: a voxel holding a solid Gaussian (opacity >= :data:`SOLID_OPACITY`) or one of the
  six points one standard deviation from its centre along its axes, so large flat Gaussians (walls,
  floors) leave no holes between their centres;
* **floor**: the lowest large horizontal layer of occupied voxels, when the scene has one (a room
  floor, the ground of an outdoor scene); everything below its top is solid ground. Its surface
  is also kept as a plane at the height of the floor's own Gaussians (:func:`_floor_height`):
  the clearance above the floor is measured to that plane, not to the top of its voxel layers,
  which may lie almost a voxel higher (more in a large outdoor scene, where a voxel is taller
  than a toy car: a camera at such an object's own height would count as underground);
* **ceiling**: where walls stand around the scene (a room: most horizontal directions from the
  middle of the footprint meet a column reaching the top of the occupied heights), a ceiling at
  the walls' top (:func:`_walls`; a room captured without one has one in reality, and a camera
  over a wall would leave the room), or -1 without walls;
* **surfaces**: an occupied voxel above the floor with a free voxel over it whose solid samples
  all lie within :data:`FLAT_VOXELS` of one height (a table top, a seat, the top of a box) is a
  flat upward surface: the clearance over it is the height above its highest sample
  (:meth:`Occupancy.clearance`), not the distance to the voxel's top, which may lie most of a
  voxel higher (a camera at a small object's own height on a table would count as inside the
  table top);
* **free**: empty voxels above the floor and below the ceiling that connect (6-neighbourhood) to
  a training camera, or to the top of the grid for a scene without cameras. The inside of a
  closed object or of a room's wall is not free, even where no Gaussian sits (Gaussians only
  cover surfaces), nor is the space behind a room's walls.

:meth:`Occupancy.clearance` is a signed distance in world units, trilinearly interpolated (and
differentiable with respect to the point): positive in free space (distance to the nearest voxel
that is not free), negative elsewhere (distance to the nearest free voxel). The zero level lies
half a voxel from the centres of the boundary voxels.

Around a small subject a query adds a finer grid (:meth:`Occupancy.around`): a voxel a third of a
teddy's height keeps a camera a voxel from the teddy and from its table top, more than a low close
view leaves between them. Inside it, a point is free when either grid frees it.
"""

from __future__ import annotations

import hashlib
import json
import math
import zipfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import torch
from torch import Tensor

from ..errors import InputError
from ._io import write_npz
from .model import Camera, GaussianScene

FORMAT = 7
VOXELS = 96  # cells along the longest side of the grid
SOLID_OPACITY = 0.5  # fainter Gaussians (haze, floaters) do not block a camera
PADDING = 0.15  # the grid extends this share of its size beyond the Gaussians and cameras
# A layer is a floor when it covers this share of the occupied footprint (seen from above).
FLOOR_COVERAGE = 0.3
# Walls enclose the scene when columns reaching WALL_HEIGHT of the occupied heights above the
# floor stand in this share of the horizontal directions from the middle of the footprint.
ENCLOSED_SHARE = 0.6
WALL_HEIGHT = 0.8
# An edge of the hull of the walls met runs along a wall when it is this many columns long or
# more (shorter ones cut a corner) and half of it or more lies within WALL_EDGE_COLUMNS of a wall
# met.
WALL_LENGTH_COLUMNS = 8.0
WALL_EDGE_COLUMNS = 2.0
# Columns beyond a wall lower than this share of the occupied heights above the floor (the
# floor's fringe, the foot of the wall, grass) do not hide the wall from a ray.
FRINGE_HEIGHT = 0.25
# A camera keeps this many voxels below the ceiling plane (the plane is known to about half a
# voxel); it is also the unit of Refine's free-space loss.
MARGIN_VOXELS = 0.5
# ... and this many from a surface the voxels hold (Occupancy.slack): one grid knows a surface to
# about half a voxel, and a second grid of the same scene (built under another estimate of the up
# or around other training cameras, as the ground-truth check's is) places it up to about a voxel
# away from the first (0.78 voxel on a tilted room whose two ups differ by 0.7 degrees).
SURFACE_MARGIN_VOXELS = 1.0
# ... and this many voxels above the floor plane or a flat surface, which their own Gaussians
# place (Occupancy.slack).
FLOOR_MARGIN_VOXELS = 0.25
# An occupied voxel under a free one is a flat surface when its solid samples' heights span at
# most this many voxels.
FLAT_VOXELS = 0.25
# The floor plane lies at this quantile of the heights of the solid samples in the floor's layers
# (grass and rugs lie above most of the floor's own samples; the bases of objects standing on it
# are left out with their columns, _floor_height).
FLOOR_QUANTILE = 0.9
# The ceiling plane lies at this quantile of the heights of the solid Gaussians' centres in the
# walls' two top layers (their 1-sigma points reach above the walls; a few floaters may too).
CEILING_QUANTILE = 0.98
# A subject spanning fewer than this many voxels (a teddy on a table in a room 45 units across)
# gets a finer grid around it (Occupancy.around): the scene grid's margins (a voxel from a
# surface) keep a camera farther from such a subject and its table top than the subject's own
# size, so a low close view is never free in it.
DETAIL_SUBJECT_VOXELS = 6.0
DETAIL_SUBJECT_CELLS = 16  # the finer grid's voxel: this fraction of the subject's longest extent
DETAIL_CELLS = 64  # cells along each side of the finer grid (four subject extents)
DETAIL_REACH_CELLS = 16  # its clearance is exact up to this many cells, and this many beyond
# Over this many cells inside its faces the finer grid's clearance blends into the scene grid's,
# so the clearance stays continuous (Refine follows its gradient).
DETAIL_BLEND_CELLS = 4.0
# Occupancy.seen_past_support: a subject's base is this quantile of its points' heights, and its
# footprint the points within BASE_BAND of its height range above the base. Solid geometry at one
# of SUPPORT_DEPTHS (shares of the reach) under a point supports it; the reach is SUPPORT_REACH of
# the subject's height, at most SUPPORT_REACH_VOXELS (a sofa on legs, whose base is its seat's
# underside, stands on nothing that near). The ring testing whether a subject stands on a support
# has SUPPORT_RING points SUPPORT_RING_VOXELS outside its footprint (its own voxels' clearance
# reaches about a voxel beyond its points).
BASE_QUANTILE = 0.02
BASE_BAND = 0.1
SUPPORT_DEPTHS = (0.1, 0.25, 0.5, 0.75, 1.0)
SUPPORT_REACH = 0.05
SUPPORT_REACH_VOXELS = 0.5
SUPPORT_RING = 16
SUPPORT_RING_VOXELS = 1.5


@dataclass
class _Footing:
    """Where a subject stands (:meth:`Occupancy._footing`): the height of its base's plane, the
    middle (3,) and radius of its footprint on it, the reach probed under it, and the height of
    the top of the surface under it (all world units, heights along the up axis)."""

    base: float
    middle: np.ndarray
    radius: float
    reach: float
    top: float


@dataclass
class Occupancy:
    """A scene's voxel grid. X x Y x Z voxels; the grid frame's third axis is the world up.

    Attributes:
        rotation: (3, 3) world -> grid frame rotation (rows: two horizontal axes, then up).
        origin: (3,) grid-frame coordinates of the corner of voxel (0, 0, 0).
        voxel: edge length of a voxel (world units).
        occupied: (X, Y, Z) bool, a solid Gaussian there.
        free: (X, Y, Z) bool, where a camera can be.
        floor_top: index of the floor's highest layer, or -1 without a floor.
        ceiling: index of the lowest layer above the free space (the walls' top), or -1 without
            walls.
        sdf: (X, Y, Z) float32 signed clearance at the voxel centres (world units; see the module),
            with the floor's layers free below free columns (the floor plane bounds it instead).
        floor_height: grid-frame height (along the up) of the floor plane, or NaN without a floor.
        ceiling_height: grid-frame height of the ceiling plane (the walls' top), or NaN without
            walls or when a training camera stands over them (the ceiling layer bounds it then).
        surface_layer: (X, Y) int16, the layer of the flat upward surface in each column, or -1.
        surface_height: (X, Y) float32, its grid-frame height (the highest of its samples; 0
            where there is none).
        detail: a finer grid around one small subject (:meth:`around`; never cached): inside
            it a point is free when either grid frees it.
    """

    rotation: np.ndarray
    origin: np.ndarray
    voxel: float
    occupied: np.ndarray
    free: np.ndarray
    floor_top: int
    sdf: np.ndarray
    ceiling: int = -1
    floor_height: float = math.nan
    ceiling_height: float = math.nan
    surface_layer: np.ndarray | None = None
    surface_height: np.ndarray | None = None
    detail: Occupancy | None = None

    @property
    def margin(self) -> float:
        """The depth a camera keeps below the ceiling plane, and the unit of Refine's free-space
        loss (world units): :data:`MARGIN_VOXELS` voxels."""
        return MARGIN_VOXELS * self.voxel

    def grid_coordinates(self, points: Tensor) -> Tensor:
        """(..., 3) world points -> (..., 3) continuous voxel coordinates (voxel centres at integers)."""
        rotation = torch.as_tensor(self.rotation, dtype=points.dtype)
        origin = torch.as_tensor(self.origin, dtype=points.dtype)
        return (points @ rotation.T - origin) / self.voxel - 0.5

    def clearance(self, points: Tensor | np.ndarray) -> Tensor:
        """Signed clearance (world units) of (..., 3) points: trilinear in the voxel values,
        differentiable. Beyond the grid it grows with the distance outside it, with the sign of
        the nearest border voxel (the grid's padding is free except below the floor), except in a
        room, where it falls with that distance (the grid holds the room and every training
        camera with a padding: beyond it, past an open side, stands the room's fourth wall); never more
        than the height above the floor plane or a flat surface in the point's column (within a
        voxel of the surface's; negative under it), nor than the depth below the ceiling plane.
        Inside :attr:`detail` the voxel clearance is the larger of its grid's and this grid's."""
        voxels, floor, ceiling = self._terms(points, kept=False)
        return torch.minimum(torch.minimum(voxels, floor), ceiling)

    @property
    def floor_margin(self) -> float:
        """The height a camera keeps above the floor plane or a flat surface (world units):
        :data:`FLOOR_MARGIN_VOXELS` voxels."""
        return FLOOR_MARGIN_VOXELS * self.voxel

    def height_kept(self, floor_margin: float | None = None) -> float:
        """The height a camera keeps above the floor plane or a flat surface (world units):
        ``floor_margin`` when given, but never more than :attr:`floor_margin`."""
        return self.floor_margin if floor_margin is None else min(floor_margin, self.floor_margin)

    def slack(self, points: Tensor | np.ndarray, floor_margin: float | None = None) -> Tensor:
        """How far (world units) (..., 3) points are from breaking the clearance a camera keeps
        (< 0: too near a surface), differentiable: the voxel clearance less
        :data:`SURFACE_MARGIN_VOXELS` voxels (inside :attr:`detail`, the larger of its grid's and
        this grid's, each less its own voxels), the height above the floor plane or a flat surface
        less :meth:`height_kept` of ``floor_margin`` (the plane is measured from the floor's own
        Gaussians, not known to half a voxel only: a camera at a small object's own height, or low
        under it, stands within half a voxel of the floor), the depth below the ceiling plane less
        the margin (the walls' top is known as the floor is, but it is inferred: a room captured
        without a ceiling has one)."""
        voxels, floor, ceiling = self._terms(points)
        floor = floor - self.height_kept(floor_margin)
        return torch.minimum(torch.minimum(voxels, floor), ceiling - self.margin)

    def _terms(self, points: Tensor | np.ndarray, kept: bool = True) -> tuple[Tensor, Tensor, Tensor]:
        """(voxel clearance, less the margin a camera keeps from the voxels' surfaces when
        ``kept``; height above the floor plane or the flat surface under the point; depth below
        the ceiling plane) of (..., 3) points; +inf where there is none. Inside :attr:`detail`,
        free in either grid is free: the finer grid frees what lies near a small subject, the
        scene grid keeps what its flat surfaces free (the finer grid knows a table top only to a
        cell)."""
        points = torch.as_tensor(points)
        dtype = points.dtype if points.is_floating_point() else torch.float64
        points = points.to(dtype)
        voxels = self._voxel_clearance(points) - SURFACE_MARGIN_VOXELS * self.voxel * kept
        if self.detail is not None:
            finer = self.detail._voxel_clearance(points) - SURFACE_MARGIN_VOXELS * self.detail.voxel * kept
            voxels = voxels + self.detail._inner_weight(points) * torch.relu(finer - voxels)
        height = points @ torch.as_tensor(self.rotation[2], dtype=dtype)
        unbounded = torch.full_like(voxels, math.inf)
        floor = height - self.floor_height if math.isfinite(self.floor_height) else unbounded
        if self.surface_layer is not None:
            g = self.grid_coordinates(points)
            cell = g.detach().round().long()
            shape = torch.tensor(self.sdf.shape)
            column = ((cell[..., :2] >= 0) & (cell[..., :2] < shape[:2])).all(-1)
            i, j = (cell[..., a].clamp(0, self.sdf.shape[a] - 1) for a in range(2))
            layer = torch.as_tensor(self.surface_layer, dtype=torch.long)[i, j]
            # Its voxel, the one over it and the one under it: the slab under a surface stays
            # solid for a voxel (it was taken out of the voxel values).
            above = column & (layer >= 0) & (cell[..., 2] >= layer - 1) & (cell[..., 2] <= layer + 1)
            surface = height - torch.as_tensor(self.surface_height, dtype=dtype)[i, j]
            floor = torch.where(above, torch.minimum(floor, surface), floor)
        ceiling = self.ceiling_height - height if math.isfinite(self.ceiling_height) else unbounded
        return voxels, floor, ceiling

    def _voxel_clearance(self, points: Tensor) -> Tensor:
        """The voxel values' clearance of (..., 3) float points, extended beyond the grid
        (:meth:`clearance`)."""
        g = self.grid_coordinates(points)
        shape = torch.tensor(self.sdf.shape, dtype=g.dtype)
        inside = torch.minimum(torch.maximum(g, torch.zeros_like(g)), shape - 1)
        outside = (g - inside).norm(dim=-1) * self.voxel
        value = _trilinear(torch.as_tensor(self.sdf, dtype=g.dtype), inside)
        value = value + torch.where(value >= 0, outside, -outside)
        if self.ceiling >= 0:  # a room: beyond the grid (past its open side) is outside the room
            value = torch.where(outside > 0, value.clamp_max(0.0) - outside, value)
        return value

    def _inner_weight(self, points: Tensor) -> Tensor:
        """(...,) weight of this grid's clearance at (..., 3) points: 1 deeper inside than a cell
        and :data:`DETAIL_BLEND_CELLS` more, falling linearly to 0 a cell inside its faces."""
        g = self.grid_coordinates(points)
        shape = torch.tensor(self.sdf.shape, dtype=g.dtype)
        depth = torch.minimum(g + 0.5, shape - 0.5 - g).min(-1).values
        return ((depth - 1.0) / DETAIL_BLEND_CELLS).clamp(0.0, 1.0)

    def around(self, gaussians: GaussianScene, members: Tensor | np.ndarray) -> Occupancy:
        """This occupancy with a finer grid (:attr:`detail`) around the Gaussians ``members``
        ((M,) long indices: a subject) when they span fewer than :data:`DETAIL_SUBJECT_VOXELS`
        voxels; itself otherwise, or when the finer grid finds no free space."""
        gaussians = gaussians.to(device="cpu")
        rotation = torch.as_tensor(self.rotation)
        means = gaussians.means.detach()[torch.as_tensor(members, dtype=torch.long)].double() @ rotation.T
        if len(means) == 0:
            return self
        lo, hi = (means.quantile(q, dim=0).numpy() for q in (0.02, 0.98))
        extent = float((hi - lo).max())
        if extent >= DETAIL_SUBJECT_VOXELS * self.voxel:
            return self
        detail = _detail_grid(self, gaussians, (lo + hi) / 2, extent / DETAIL_SUBJECT_CELLS)
        return self if detail is None else replace(self, detail=detail)

    def segment_blocked(self, start: np.ndarray, end: np.ndarray, ignore: np.ndarray | None = None, samples: int = 64) -> float:
        """Share of ``samples`` points on the segment ``start`` -> ``end`` (world, (3,) each) that
        fall in occupied voxels, not counting those where ``ignore`` ((X, Y, Z) bool) is set, nor
        those above the height of a flat surface in its voxel (the clearance's rule: a camera low
        over a table top stands in the top's voxel, and so does its line of sight)."""
        t = np.linspace(0.0, 1.0, samples)[:, None]
        points = torch.as_tensor(start + t * (end - start), dtype=torch.float64)
        index = self.grid_coordinates(points).round().long().numpy()
        valid = ((index >= 0) & (index < np.array(self.occupied.shape))).all(1)
        i, j, k = index[valid].T
        hit = self.occupied[i, j, k]
        if ignore is not None:
            hit &= ~ignore[i, j, k]
        if self.surface_layer is not None:
            heights = points[valid].numpy() @ self.rotation[2]
            hit &= ~((self.surface_layer[i, j] == k) & (heights > self.surface_height[i, j]))
        return float(hit.sum()) / samples

    def support_depth(self, points: np.ndarray, reach: float) -> np.ndarray:
        """(P,) the depth (world units) of the solid geometry right under each of the (P, 3) world
        points: the first of :data:`SUPPORT_DEPTHS` shares of ``reach`` below it where the
        clearance is negative, +inf where there is none. Probed, not read from the voxels, so a
        table top a few hundredths thick in a coarse grid counts."""
        depths = np.asarray(SUPPORT_DEPTHS) * reach
        probes = points[:, None, :] - depths[None, :, None] * self.rotation[2]
        solid = (self.clearance(torch.as_tensor(probes, dtype=torch.float64)) < 0).numpy()
        return np.where(solid.any(1), depths[solid.argmax(1)], np.inf)

    def support_top(self, points: np.ndarray) -> float | None:
        """The height (along the up axis, world units) of the top of the surface a subject's (P, 3)
        points stand on, or None when they stand on nothing wider than themselves (see
        :meth:`_footing`)."""
        footing = self._footing(points)
        return None if footing is None else footing.top

    def seen_past_support(self, points: np.ndarray, centre: np.ndarray) -> float | None:
        """Share of a subject's (P, 3) points that a camera at ``centre``, lower than the top of
        the surface the subject stands on, sees past that surface; None when the camera is not
        lower, or the subject stands on nothing wider than itself (:meth:`_footing`).

        A camera under a table top sees the object on it only through the top. The renders say
        otherwise: the object's base and the top lie in one plane, their Gaussians interleave in
        the depth order, and about half the base's alpha survives the composite. So the sight is
        settled geometrically: each point's line of sight crosses the plane of the base once, and
        the point is hidden where that crossing lies over the support (:meth:`support_depth`) or
        inside the base's own footprint, which the support carries. Only a camera lower than the
        support's top looks through it: one crouching between the floor and a bookcase's raised
        base sees the bookcase over the floor."""
        up, height = self.rotation[2], float(centre @ self.rotation[2])
        heights = points @ up
        if len(points) == 0 or height >= np.quantile(heights, BASE_QUANTILE):  # not lower than the base: no probing
            return None
        footing = self._footing(points)
        if footing is None or height >= footing.top:
            return None
        share = np.minimum((footing.base - height) / np.maximum(heights - height, 1e-12), 1.0)
        crossings = centre + share[:, None] * (points - centre)
        offset = crossings - footing.middle
        inside = np.linalg.norm(offset - (offset @ up)[:, None] * up, axis=1) <= footing.radius
        return float(1.0 - (inside | np.isfinite(self.support_depth(crossings, footing.reach))).mean())

    def _footing(self, points: np.ndarray) -> _Footing | None:
        """Where a subject's (P, 3) points stand: the plane of its base (its lowest
        :data:`BASE_QUANTILE` of heights), the footprint's middle and radius, and the top of the
        surface under it; None without points or when that surface is no wider than the subject.
        The subject stands on a support when the ring of :data:`SUPPORT_RING` points
        :data:`SUPPORT_RING_VOXELS` voxels outside its footprint mostly has one under it, within
        the reach of :meth:`support_depth`; the ring keeps clear of the subject's own voxels, so a
        subject hanging free stands on nothing."""
        if len(points) == 0:
            return None
        up = self.rotation[2]
        heights = points @ up
        base = float(np.quantile(heights, BASE_QUANTILE))
        lowest = points[heights <= base + BASE_BAND * (heights.max() - base)]
        middle = lowest.mean(0)
        middle = middle + (base - float(middle @ up)) * up
        flat = lowest - middle - ((lowest - middle) @ up)[:, None] * up
        radius = float(np.linalg.norm(flat, axis=1).max())
        angles = np.linspace(0.0, 2.0 * math.pi, SUPPORT_RING, endpoint=False)
        ring = middle + (radius + SUPPORT_RING_VOXELS * self.voxel) * (
            np.cos(angles)[:, None] * self.rotation[0] + np.sin(angles)[:, None] * self.rotation[1]
        )
        reach = min(SUPPORT_REACH * float(heights.max() - base), SUPPORT_REACH_VOXELS * self.voxel)
        ring_depths = self.support_depth(ring, reach)
        supported = np.isfinite(ring_depths)
        if supported.mean() < 0.5:
            return None
        return _Footing(base, middle, radius, reach, base - float(np.median(ring_depths[supported])))

    def voxelize(self, gaussians: GaussianScene) -> np.ndarray:
        """(X, Y, Z) bool: the voxels the solid Gaussians of ``gaussians`` occupy (e.g. one subject's)."""
        return _occupied(self, _solid_samples(gaussians) @ torch.as_tensor(self.rotation).T)


def solid_points(gaussians: GaussianScene, members: Tensor, count: int) -> np.ndarray:
    """(P, 3) float64 centres of up to ``count`` of the solid Gaussians (opacity >=
    :data:`SOLID_OPACITY`) among ``members`` (a (N,) bool mask or indices), evenly spread over
    their order; of all the members when none is solid."""
    member = torch.zeros(len(gaussians), dtype=torch.bool)
    member[torch.as_tensor(members).cpu()] = True
    solid = member & (torch.sigmoid(gaussians.opacity_logits.detach().cpu()) >= SOLID_OPACITY)
    means = gaussians.means.detach().cpu()[solid if solid.any() else member].double().numpy()
    return means[np.linspace(0, len(means) - 1, min(len(means), count)).astype(int)]


def _trilinear(values: Tensor, coords: Tensor) -> Tensor:
    """``values`` (X, Y, Z) interpolated at (..., 3) voxel coordinates inside the grid."""
    upper = torch.tensor(values.shape, dtype=torch.long) - 1
    low = coords.detach().floor().long()
    low = torch.minimum(low, (upper - 1).clamp_min(0))
    frac = coords - low.to(coords.dtype)
    out = torch.zeros(coords.shape[:-1], dtype=values.dtype)
    for corner in range(8):
        offset = torch.tensor([(corner >> a) & 1 for a in range(3)])
        index = torch.minimum(low + offset, upper)
        weight = torch.ones_like(out)
        for a in range(3):
            weight = weight * (frac[..., a] if offset[a] else 1.0 - frac[..., a])
        out = out + weight * values[index[..., 0], index[..., 1], index[..., 2]]
    return out


def up_frame(up: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose third row is the unit ``up`` and first two rows are horizontal."""
    up = np.asarray(up, dtype=np.float64)
    up = up / np.linalg.norm(up)
    helper = np.eye(3)[int(np.argmin(np.abs(up)))]
    x = np.cross(helper, up)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(up, x), up])


def _solid_samples(gaussians: GaussianScene) -> Tensor:
    """(7 S, 3) float64 world points: the centre of each solid Gaussian (the first S rows) and the
    six points one standard deviation from it along its axes (S solid Gaussians)."""
    from ..geometry.quaternion import quat_to_rotmat

    solid = torch.sigmoid(gaussians.opacity_logits.detach()) >= SOLID_OPACITY
    means = gaussians.means.detach()[solid].double()
    axes = quat_to_rotmat(gaussians.quats.detach()[solid].double())  # (S, 3, 3), columns are the axes
    sigma = gaussians.log_scales.detach()[solid].double().exp()  # (S, 3)
    offsets = axes * sigma[:, None, :]  # (S, 3, 3): column a is sigma_a times axis a
    points = [means] + [means + sign * offsets[:, :, a] for a in range(3) for sign in (1.0, -1.0)]
    return torch.cat(points)


def _occupied(grid: Occupancy, points: Tensor) -> np.ndarray:
    """(X, Y, Z) bool: the voxels of ``grid`` holding any of the (P, 3) grid-frame ``points``."""
    return _voxels_holding(points, grid.origin, grid.voxel, grid.occupied.shape)


def _voxel_index(points: Tensor, origin: np.ndarray, voxel: float, shape: tuple[int, ...]) -> tuple[Tensor, Tensor]:
    """The (P, 3) long index of the voxel (side ``voxel``, from ``origin`` (3,)) holding each of
    the (P, 3) ``points``, and the (P,) bool mask of those inside a grid of ``shape``."""
    index = ((points - torch.as_tensor(origin)) / voxel).floor().long()
    return index, ((index >= 0) & (index < torch.tensor(shape))).all(1)


def _voxels_holding(points: Tensor, origin: np.ndarray, voxel: float, shape: tuple[int, int, int]) -> np.ndarray:
    """(X, Y, Z) bool, ``shape``: the voxels of side ``voxel`` from ``origin`` (3,) holding any of
    the (P, 3) ``points``; points outside the grid are left out."""
    index, inside = _voxel_index(points, origin, voxel, shape)
    out = np.zeros(shape, dtype=bool)
    out[tuple(index[inside].T.numpy())] = True
    return out


def _floor_top(occupied: np.ndarray) -> int:
    """Index of the top layer of the floor: the fullest layer in the lower half of the occupied
    heights, if it covers :data:`FLOOR_COVERAGE` of the footprint, and the layers just above it
    that are at least half as full (a floor a few voxels thick); -1 when there is none."""
    per_layer = occupied.sum((0, 1))
    footprint = occupied.any(2).sum()
    heights = np.flatnonzero(per_layer)
    if footprint == 0:
        return -1
    lower = heights[heights <= (heights[0] + heights[-1]) / 2]
    floor = int(lower[np.argmax(per_layer[lower])])
    if per_layer[floor] < FLOOR_COVERAGE * footprint:
        return -1
    top = floor
    while top + 1 < len(per_layer) and per_layer[top + 1] >= 0.5 * per_layer[floor]:
        top += 1
    return top


def _floor_height(points: Tensor, grid: Occupancy) -> float:
    """Grid-frame height of the floor plane: the :data:`FLOOR_QUANTILE` of the heights of the
    (P, 3) grid-frame solid ``points`` inside the floor's layers (``grid.floor_top`` >= 0), in the
    columns whose voxel over the floor's top layer is free (all columns when none is). The bases
    of objects standing on the floor share its layers in their own columns (their walls, and
    inside them, which is not free, their bottoms): in a large outdoor
    scene (a voxel 3.8 high, a bench 6.5) they were a sixth of the layers' samples and lifted
    the plane 1.3 above the ground, a third of the way up a bench one asked to see from below."""
    floor = int(np.argmax(grid.occupied.sum((0, 1))[: grid.floor_top + 1]))
    heights = points[:, 2]
    low = grid.origin[2] + floor * grid.voxel
    high = grid.origin[2] + (grid.floor_top + 1) * grid.voxel
    layers = (heights >= low) & (heights < high)
    if grid.floor_top + 1 < grid.occupied.shape[2]:
        index, in_grid = _voxel_index(points, grid.origin, grid.voxel, grid.occupied.shape)
        open_above = torch.as_tensor(grid.free[:, :, grid.floor_top + 1])
        column = index[:, :2].clamp(min=0)
        column = torch.minimum(column, torch.tensor(grid.occupied.shape[:2]) - 1)
        own = layers & in_grid & open_above[column[:, 0], column[:, 1]]
        layers = own if own.any() else layers
    inside = heights[layers]
    return float(inside.quantile(FLOOR_QUANTILE)) if len(inside) else high


def _flat_surfaces(points: Tensor, grid: Occupancy) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The flat upward surfaces above the floor (module docstring) from the (P, 3) grid-frame
    solid ``points``: (X, Y) int16 layer (-1 where none), (X, Y) float32 height of the highest
    sample there, and the (X, Y, Z) bool surface voxels. A column keeps its highest surface."""
    shape = grid.occupied.shape
    over = np.zeros(shape, dtype=bool)
    over[:, :, :-1] = grid.free[:, :, 1:]
    candidate = grid.occupied & over
    candidate[:, :, : grid.floor_top + 1] = False
    index, inside = _voxel_index(points, grid.origin, grid.voxel, shape)
    index, heights = index[inside].numpy(), points[inside, 2].numpy()
    keep = candidate[index[:, 0], index[:, 1], index[:, 2]]
    flat_index = np.ravel_multi_index(tuple(index[keep].T), shape)
    high = np.full(math.prod(shape), -np.inf)
    low = np.full(math.prod(shape), np.inf)
    np.maximum.at(high, flat_index, heights[keep])
    np.minimum.at(low, flat_index, heights[keep])
    flat = (candidate.reshape(-1) & (high - low <= FLAT_VOXELS * grid.voxel)).reshape(shape)
    layer = np.where(flat.any(2), shape[2] - 1 - np.argmax(flat[:, :, ::-1], axis=2), -1).astype(np.int16)
    i, j = np.nonzero(layer >= 0)
    height = np.zeros(shape[:2], dtype=np.float32)
    height[i, j] = high.reshape(shape)[i, j, layer[i, j]]
    return layer, height, flat


def _ceiling_height(means: Tensor, grid: Occupancy) -> float:
    """Grid-frame height of the ceiling plane: the :data:`CEILING_QUANTILE` of the heights of the
    (S, 3) grid-frame solid Gaussian centres in the two layers below ``grid.ceiling`` (the walls'
    top layers; centres, not 1-sigma points, which reach above the walls), or the bottom of the
    ceiling layer when none lies there."""
    heights = means[:, 2]
    high = grid.origin[2] + grid.ceiling * grid.voxel
    inside = heights[(heights >= high - 2 * grid.voxel) & (heights < high)]
    return float(inside.quantile(CEILING_QUANTILE)) if len(inside) else high


def _walls(occupied: np.ndarray, floor_top: int, directions: int = 720) -> tuple[int, np.ndarray | None]:
    """The layer just above the top of a scene's walls and the (X, Y) columns inside them, or
    (-1, None) when no walls enclose the scene.

    From the middle of the occupied footprint, a horizontal ray in each of ``directions``
    directions crosses the columns holding occupied voxels above the floor; it meets a wall when
    the outermost of them that rises above the fringe (:data:`FRINGE_HEIGHT`) is tall (it
    reaches :data:`WALL_HEIGHT` of the occupied heights above the floor) and lower columns lie
    between it and the middle. The scene is enclosed when
    :data:`ENCLOSED_SHARE` of the rays meet a wall: three walls around a room are, a box or a
    tree standing alone, or a table on a lawn, are not. Inside are the columns a ray crosses
    before its wall (all of them on an open side), and on the room's side of every wall
    (:func:`_wall_sides`: past an open side, only between the walls' planes); the ceiling is the
    layer above the median top of the walls met."""
    above = occupied[:, :, floor_top + 1 :]
    columns = above.any(2)
    if not columns.any():
        return -1, None
    heights = np.flatnonzero(above.any((0, 1)))
    top = np.where(columns, above.shape[2] - 1 - np.argmax(above[:, :, ::-1], axis=2), -1)  # (X, Y) highest layer
    tall = top >= heights[0] + WALL_HEIGHT * (heights[-1] - heights[0])
    # A floor that reaches past the walls carries a low fringe there, a voxel or two high: it
    # is outside the room, not the room's outermost structure.
    standing = top >= heights[0] + FRINGE_HEIGHT * (heights[-1] - heights[0])
    xs, ys = np.nonzero(columns)
    middle = np.array([(xs.min() + xs.max()) / 2, (ys.min() + ys.max()) / 2])
    reach = np.arange(0.0, float(np.hypot(*columns.shape)), 0.5)
    inside = np.zeros(columns.shape, dtype=bool)
    tops, hits = [], []
    for angle in np.linspace(0.0, 2.0 * np.pi, directions, endpoint=False):
        cells = np.round(middle + reach[:, None] * [np.cos(angle), np.sin(angle)]).astype(int)
        cells = cells[((cells >= 0) & (cells < columns.shape)).all(1)]
        occupied_at = np.flatnonzero(standing[cells[:, 0], cells[:, 1]])
        along = tall[cells[:, 0], cells[:, 1]]
        end = len(cells)
        # The outermost structure is tall, with lower columns between it and the middle: a wall.
        if len(occupied_at) and along[occupied_at[-1]] and not along[: np.flatnonzero(along).max()].all():
            tops.append(top[tuple(cells[occupied_at[-1]])])
            hits.append(cells[occupied_at[-1]])
            end = occupied_at[-1] + 1
        inside[cells[:end, 0], cells[:end, 1]] = True
    if len(tops) < ENCLOSED_SHARE * directions:
        return -1, None
    return floor_top + 1 + int(np.median(tops)) + 1, inside & _wall_sides(columns.shape, np.array(hits, dtype=np.float64))


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """The (K, 2) vertices, counter-clockwise, of the convex hull of (N, 2) points (monotone
    chain; collinear points dropped)."""
    ordered = sorted(set(map(tuple, points)))
    if len(ordered) < 3:
        return np.array(ordered, dtype=np.float64).reshape(-1, 2)

    def chain(sequence):
        out: list[tuple[float, float]] = []
        for p in sequence:
            while len(out) >= 2 and _turn(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(chain(ordered) + chain(ordered[::-1]), dtype=np.float64)


def _turn(o, a, b) -> float:
    """The z of (a - o) x (b - o) for 2-D points: > 0 when o, a, b turn counter-clockwise."""
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _wall_sides(shape: tuple[int, int], hits: np.ndarray) -> np.ndarray:
    """(X, Y) columns on the room's side of every wall: the half-planes of the edges of the convex
    hull of the (N, 2) wall columns the rays met that run along walls (:data:`WALL_LENGTH_COLUMNS`
    long or more, half of them or more within :data:`WALL_EDGE_COLUMNS` of a wall met). An edge
    across an open side is not a wall: the walls beside the opening go on past what the capture
    saw, as a room's walls do, so the space beyond it lies between their planes (a camera may back
    out of a stage set, not round behind a side wall)."""
    hull = _convex_hull(hits)
    gx, gy = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    sides = np.ones(shape, dtype=bool)
    for a, b in zip(hull, np.roll(hull, -1, axis=0)):
        length = np.linalg.norm(b - a)
        if length < WALL_LENGTH_COLUMNS:
            continue  # a corner's chamfer: its plane would cut across the space past an opening
        along = a + np.linspace(0.0, 1.0, max(int(length), 2))[:, None] * (b - a)
        near = np.linalg.norm(along[:, None] - hits[None], axis=2).min(1) <= WALL_EDGE_COLUMNS
        if near.mean() < 0.5:
            continue  # an open side
        # Counter-clockwise, the room lies on the edge's left; inside the inner edge of the
        # wall's outermost column (half a column in from its centre).
        sides &= _turn(a, b, (gx, gy)) >= 0.5 * length
    return sides


def dilate(mask: np.ndarray) -> np.ndarray:
    """(X, Y, Z) bool ``mask`` grown by one voxel towards its 6 neighbours (nothing wraps around
    the grid's faces)."""
    grown = mask.copy()
    for axis in range(3):
        for shift in (1, -1):
            source = [slice(None)] * 3
            target = [slice(None)] * 3
            source[axis] = slice(None, -1) if shift == 1 else slice(1, None)
            target[axis] = slice(1, None) if shift == 1 else slice(None, -1)
            grown[tuple(target)] |= mask[tuple(source)]
    return grown


def _flood(empty: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """(X, Y, Z) bool: the voxels of ``empty`` connected to ``seeds`` through 6-neighbours."""
    reached = seeds & empty
    while True:
        grown = dilate(reached) & empty
        if grown.sum() == reached.sum():
            return reached
        reached = grown


def _distance_to(mask: np.ndarray, chunk: int = 4096) -> np.ndarray:
    """(X, Y, Z) float32 Euclidean distance (voxels) from every voxel centre to the nearest voxel
    of ``mask``; exact, by three separable passes of ``min_j f(j) + (i - j)^2`` along lines."""
    big = float(sum(s * s for s in mask.shape)) * 4.0
    field = torch.where(torch.as_tensor(mask), 0.0, big)
    for axis in range(3):
        moved = field.movedim(axis, -1)
        lines = moved.reshape(-1, moved.shape[-1])
        n = lines.shape[-1]
        steps = torch.arange(n, dtype=torch.float32)
        square = (steps[:, None] - steps[None, :]) ** 2  # (i, j)
        out = torch.empty_like(lines)
        for start in range(0, len(lines), chunk):
            out[start : start + chunk] = (lines[start : start + chunk, None, :] + square).min(-1).values
        field = out.reshape(moved.shape).movedim(-1, axis)
    return field.clamp_max(big).sqrt().numpy()


def _on_surface(grid: Occupancy, points: Tensor) -> np.ndarray:
    """(P,) bool: which (P, 3) grid-frame ``points`` lie in a voxel of ``grid`` holding a flat
    upward surface (:func:`_flat_surfaces`)."""
    if grid.surface_layer is None:
        return np.zeros(len(points), dtype=bool)
    index, inside = _voxel_index(points, grid.origin, grid.voxel, grid.occupied.shape)
    i, j, k = index[inside].T.numpy()
    out = np.zeros(len(points), dtype=bool)
    out[inside.numpy()] = grid.surface_layer[i, j] == k
    return out


def _distance_within(mask: np.ndarray, reach: int) -> np.ndarray:
    """(X, Y, Z) float32 Euclidean distance (voxels) from every voxel centre to the nearest voxel
    of ``mask``, exact up to ``reach`` voxels and ``reach`` beyond: :func:`_distance_to`'s three
    separable passes, each a minimum over the ``reach`` voxels either side (every axis offset
    of a nearest voxel within ``reach`` is within it), in O(reach) shifts of the whole grid."""
    field = torch.where(torch.as_tensor(mask), 0.0, float(3 * (reach + 1) ** 2))
    for axis in range(3):
        n = field.shape[axis]
        out = field.clone()
        for step in range(1, min(reach, n - 1) + 1):
            lower, upper = out.narrow(axis, 0, n - step), out.narrow(axis, step, n - step)
            lower.copy_(torch.minimum(lower, field.narrow(axis, step, n - step) + step * step))
            upper.copy_(torch.minimum(upper, field.narrow(axis, 0, n - step) + step * step))
        field = out
    return field.sqrt().clamp_max(reach).numpy()


def build_occupancy(gaussians: GaussianScene, up: np.ndarray, cameras: list[Camera] = ()) -> Occupancy:
    """The occupancy of a scene (see the module docstring) in a grid of :data:`VOXELS` cells
    along its longest side, around the solid Gaussians and the training camera centres."""
    rotation = up_frame(up)
    samples = _solid_samples(gaussians)
    if len(samples) == 0:
        raise InputError(f"no Gaussian has an opacity of {SOLID_OPACITY} or more: nothing to build free space from")
    points = samples @ torch.as_tensor(rotation).T
    centres = np.array([c.center for c in cameras]).reshape(-1, 3) @ rotation.T
    # Robust bounds: stray far Gaussians (background shells, floaters) do not set the grid size.
    lo = np.minimum(np.quantile(points.numpy(), 0.005, axis=0), centres.min(0, initial=np.inf))
    hi = np.maximum(np.quantile(points.numpy(), 0.995, axis=0), centres.max(0, initial=-np.inf))
    size = float((hi - lo).max())
    voxel = size * (1 + 2 * PADDING) / VOXELS
    lo, hi = lo - PADDING * size, hi + PADDING * size
    shape = tuple(int(math.ceil(s)) for s in (hi - lo) / voxel)
    grid = Occupancy(rotation, lo, voxel, np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool), -1, np.zeros(shape))
    grid.occupied = _occupied(grid, points)
    grid.floor_top = _floor_top(grid.occupied)
    empty = ~grid.occupied
    empty[:, :, : grid.floor_top + 1] = False
    seeds = np.zeros(shape, dtype=bool)
    if len(cameras):
        index = np.floor((centres - lo) / voxel).astype(int)
        index = index[((index >= 0) & (index < np.array(shape))).all(1)]
        seeds[tuple(index.T)] = True
    if grid.floor_top >= 0:
        grid.ceiling, inside = _walls(grid.occupied, grid.floor_top)
    if grid.ceiling >= 0:  # a room: no camera over or behind its walls (nor below a training camera)
        walls_top = grid.ceiling
        grid.ceiling = max(grid.ceiling, int(np.flatnonzero(seeds.any((0, 1))).max(initial=-1)) + 1)
        if grid.ceiling == walls_top:
            grid.ceiling_height = _ceiling_height(points[: len(points) // 7], grid)
        empty[:, :, grid.ceiling :] = False
        empty &= inside[:, :, None] | seeds.any(2, keepdims=True)
    if not (seeds & empty).any():  # no camera in free space: the sky is outside everything
        seeds[:, :, -1] = True
    grid.free = _flood(empty, seeds)
    room = grid.free
    if grid.floor_top >= 0:
        # The floor plane bounds the clearance from below (Occupancy.clearance), so the floor's
        # layers count as free under a free column, except voxels holding a solid sample more
        # than the margin above the plane: an object standing on the floor lower than a voxel
        # (a toy car in a large outdoor scene) is still an obstacle.
        grid.floor_height = _floor_height(points, grid)
        raised = _occupied(grid, points[points[:, 2] > grid.floor_height + grid.margin])
        room = grid.free.copy()
        layers = slice(0, grid.floor_top + 1)
        room[:, :, layers] |= grid.free[:, :, grid.floor_top + 1 : grid.floor_top + 2] & ~raised[:, :, layers]
    # Flat upward surfaces count as free, their height bounding the clearance in their column
    # (Occupancy._terms), as the floor's layers do.
    grid.surface_layer, grid.surface_height, flat = _flat_surfaces(points, grid)
    room = room | flat
    if grid.free.any():
        outside = _distance_to(~room) - 0.5
        inside = _distance_to(room) - 0.5
        grid.sdf = (np.where(room, outside, -inside) * voxel).astype(np.float32)
    else:
        grid.sdf = np.full(shape, -voxel, dtype=np.float32)
    return grid


def _detail_grid(grid: Occupancy, gaussians: GaussianScene, centre: np.ndarray, voxel: float) -> Occupancy | None:
    """A grid of :data:`DETAIL_CELLS` cells a side, of side ``voxel``, centred on the grid-frame
    point ``centre`` (3,), finer than ``grid``. Its voxels hold the solid samples, grown by a cell
    (samples a fine voxel apart leave gaps a flood would pass through, into a closed object or
    behind a wall), but not those of ``grid``'s flat surfaces: their height bounds the clearance,
    as in ``grid`` (grown by a cell, a table top would keep a camera three cells over it). Free
    are the empty cells connected to ``grid``'s free space, within a voxel of the space ``grid``
    counts clear (its free space with the floor's layers and the flat surfaces). None when no
    cell is free."""
    shape = (DETAIL_CELLS,) * 3
    origin = centre - DETAIL_CELLS / 2 * voxel
    rotation = torch.as_tensor(grid.rotation)
    # The Gaussians whose 1-sigma points can reach the grid.
    means = gaussians.means.detach().double() @ rotation.T
    reach = gaussians.log_scales.detach().double().exp().max(1).values
    near = ((means - torch.as_tensor(centre)).abs().max(1).values <= DETAIL_CELLS / 2 * voxel + reach).nonzero()[:, 0]
    points = _solid_samples(gaussians.subset(near)) @ rotation.T
    detail = Occupancy(grid.rotation, origin, voxel, np.zeros(shape, bool), np.zeros(shape, bool), -1, np.zeros(shape))
    detail.occupied = dilate(_occupied(detail, points[~_on_surface(grid, points)]))
    cells = torch.as_tensor(origin + (np.indices(shape).reshape(3, -1).T + 0.5) * voxel)
    index, inside = _voxel_index(cells, grid.origin, grid.voxel, grid.sdf.shape)
    i, j, k = index.clamp_min(0).minimum(torch.tensor(grid.sdf.shape) - 1).T.numpy()
    inside = inside.numpy()
    # Beyond the scene grid: free unless the scene is a room (past its open side stands a wall).
    clear = np.where(inside, dilate(grid.sdf > 0)[i, j, k], grid.ceiling < 0).reshape(shape)
    seeds = np.where(inside, grid.free[i, j, k], grid.ceiling < 0).reshape(shape)
    empty = ~detail.occupied & clear
    detail.free = _flood(empty, seeds & empty)
    if not detail.free.any():
        return None
    outside = _distance_within(~detail.free, DETAIL_REACH_CELLS) - 0.5
    within = _distance_within(detail.free, DETAIL_REACH_CELLS) - 0.5
    detail.sdf = (np.where(detail.free, outside, -within) * voxel).astype(np.float32)
    return detail


def enclosed(gaussians: GaussianScene, point: np.ndarray, cells: int = 32) -> bool:
    """Whether the world ``point`` (3,) lies inside the closed surface of ``gaussians`` (one
    object's): in a voxel holding one of their solid samples (:func:`_solid_samples`), or in an
    empty voxel that no 6-connected path of empty voxels joins to the outside of their bounding
    box. The grid spans the box (axis-aligned in the world) with ``cells`` voxels along its longest
    side and one empty voxel around it, fine enough that a surface sampled every few percent of
    the object's size is closed, coarse enough that its 1-sigma points leave no holes in it."""
    samples = _solid_samples(gaussians)
    if len(samples) == 0:
        return False
    lo, hi = samples.min(0).values.numpy(), samples.max(0).values.numpy()
    voxel = float((hi - lo).max()) / cells
    if not voxel > 0 or ((point < lo) | (point > hi)).any():
        return False
    origin = lo - voxel
    shape = tuple(int(math.ceil(s)) + 2 for s in (hi - lo) / voxel)
    solid = _voxels_holding(samples, origin, voxel, shape)
    border = np.zeros(shape, dtype=bool)
    border[[0, -1], :, :] = border[:, [0, -1], :] = border[:, :, [0, -1]] = True
    outside = _flood(~solid, border)
    i, j, k = np.floor((point - origin) / voxel).astype(int)
    return not outside[i, j, k]


# --- cache ----------------------------------------------------------------------------------------


def gaussians_fingerprint(gaussians: GaussianScene) -> str:
    """The Gaussians an occupancy is built from (``gaussians`` in the file, checked by
    :func:`load_occupancy` against the scene it is read for). The cameras and the up are left
    out: the workflow builds one occupancy per scene (from COLMAP's cameras and the estimated up
    for a scene without poses) and Refine on oracle labels reads it too, with the true ones."""
    h = hashlib.sha256()
    for tensor in (gaussians.means, gaussians.log_scales, gaussians.quats, gaussians.opacity_logits):
        h.update(tensor.detach().cpu().contiguous().numpy().tobytes())
    return h.hexdigest()[:16]


def occupancy_fingerprint(gaussians: GaussianScene, up: np.ndarray, cameras: list[Camera]) -> str:
    """Changes whenever the occupancy would: the solid Gaussians, the up, the camera centres."""
    # Every constant the stored grid depends on (the margins apply when it is read, not stored).
    constants = (
        FORMAT,
        VOXELS,
        SOLID_OPACITY,
        PADDING,
        FLOOR_COVERAGE,
        ENCLOSED_SHARE,
        WALL_HEIGHT,
        WALL_LENGTH_COLUMNS,
        WALL_EDGE_COLUMNS,
        FRINGE_HEIGHT,
        FLOOR_QUANTILE,
        FLAT_VOXELS,
        CEILING_QUANTILE,
    )
    h = hashlib.sha256(":".join(map(str, constants)).encode())
    h.update(gaussians_fingerprint(gaussians).encode())
    h.update(np.asarray(up, dtype=np.float64).tobytes())
    for c in cameras:
        h.update(np.ascontiguousarray(c.center).tobytes())
    return h.hexdigest()[:16]


def save_occupancy(grid: Occupancy, path: str | Path, fingerprint: str, gaussians: str | None = None) -> None:
    """Write ``grid`` as one ``.npz``, atomically; ``gaussians`` is the
    :func:`gaussians_fingerprint` of the Gaussians it was built from."""
    meta = {
        "format": FORMAT,
        "fingerprint": fingerprint,
        "voxel": grid.voxel,
        "floor_top": grid.floor_top,
        "ceiling": grid.ceiling,
        "floor_height": None if math.isnan(grid.floor_height) else grid.floor_height,
        "ceiling_height": None if math.isnan(grid.ceiling_height) else grid.ceiling_height,
    }
    if gaussians is not None:
        meta["gaussians"] = gaussians
    arrays = dict(rotation=grid.rotation, origin=grid.origin, occupied=grid.occupied, free=grid.free, sdf=grid.sdf)
    if grid.surface_layer is not None:
        arrays |= dict(surface_layer=grid.surface_layer, surface_height=grid.surface_height)
    write_npz(path, meta, **arrays)


def load_occupancy(path: str | Path, fingerprint: str | None = None, gaussians: str | None = None) -> Occupancy | None:
    """The occupancy in ``path``; None when absent or stale (another format or ``fingerprint``;
    None accepts any). :class:`InputError` naming the file when it is a folder, is not an
    occupancy (unreadable, fields missing, shapes that do not match, a rotation that is not one,
    a voxel that is not a positive size, any NaN or infinite number), or was built from other
    Gaussians than ``gaussians`` (a :func:`gaussians_fingerprint`; a file that records none is
    not checked)."""
    path = Path(path)
    source = str(path)
    if path.is_dir():
        raise InputError("is a folder; expected an occupancy .npz (capframe occupancy)", source=source)
    if not path.is_file():
        return None
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            if not isinstance(meta, dict):
                raise ValueError(f"meta is {type(meta).__name__}, expected a JSON object")
            if meta.get("format") != FORMAT or fingerprint not in (None, meta.get("fingerprint")):
                return None
            arrays = {k: data[k] for k in ("rotation", "origin", "occupied", "free", "sdf")}
            arrays |= {k: data[k] for k in ("surface_layer", "surface_height") if k in data}
            voxel, floor_top, ceiling = float(meta["voxel"]), meta["floor_top"], meta["ceiling"]
            floor_height = math.nan if meta["floor_height"] is None else float(meta["floor_height"])
            ceiling_height = math.nan if meta["ceiling_height"] is None else float(meta["ceiling_height"])
    except (OSError, EOFError, ValueError, TypeError, KeyError, zipfile.BadZipFile) as err:
        raise InputError(f"is not an occupancy file ({err}); rebuild it with capframe occupancy", source=source) from None
    problem = _occupancy_problem(arrays, voxel, floor_top, ceiling)
    if problem is not None:
        raise InputError(f"{problem}; rebuild it with capframe occupancy", source=source)
    if gaussians is not None and meta.get("gaussians", gaussians) != gaussians:
        raise InputError(
            f"was built from another scene (Gaussians {meta['gaussians']}, expected {gaussians}); "
            "rebuild it with capframe occupancy",
            source=source,
        )
    if (floor_top >= 0) != math.isfinite(floor_height):
        raise InputError(
            f"floor_height is {floor_height} with floor_top {floor_top}; expected a finite height exactly when there is a "
            "floor; rebuild it with capframe occupancy",
            source=source,
        )
    if ceiling < 0 and math.isfinite(ceiling_height):
        raise InputError(
            f"ceiling_height is {ceiling_height} without a ceiling (ceiling -1); rebuild it with capframe occupancy",
            source=source,
        )
    return Occupancy(
        voxel=voxel, floor_top=floor_top, ceiling=ceiling, floor_height=floor_height, ceiling_height=ceiling_height, **arrays
    )


def _occupancy_problem(arrays: dict[str, np.ndarray], voxel: float, floor_top, ceiling) -> str | None:
    """What makes the fields of an occupancy file unusable, or None."""
    rotation, origin, sdf = arrays["rotation"], arrays["origin"], arrays["sdf"]
    if not (math.isfinite(voxel) and voxel > 0):
        return f"voxel is {voxel}; expected a positive size"
    if rotation.shape != (3, 3) or origin.shape != (3,) or sdf.ndim != 3:
        shapes = f"{rotation.shape}, {origin.shape}, {sdf.shape}"
        return f"rotation, origin and sdf have shapes {shapes}; expected (3, 3), (3,), (X, Y, Z)"
    for name in ("occupied", "free"):
        if arrays[name].dtype != bool or arrays[name].shape != sdf.shape:
            return f"{name} is {arrays[name].dtype} of shape {arrays[name].shape}; expected bool of the sdf's {sdf.shape}"
    for name in ("rotation", "origin", "sdf"):
        if arrays[name].dtype.kind != "f":
            return f"{name} is {arrays[name].dtype}; expected floating-point numbers"
        if not np.isfinite(arrays[name]).all():
            return f"{name} holds NaN or infinite numbers; expected finite numbers"
    if np.abs(rotation @ rotation.T - np.eye(3)).max() > 1e-6:
        return "rotation is not a rotation matrix"
    if ("surface_layer" in arrays) != ("surface_height" in arrays):
        return "holds one of surface_layer and surface_height; expected both or neither"
    if "surface_layer" in arrays:
        layer, height = arrays["surface_layer"], arrays["surface_height"]
        if layer.shape != sdf.shape[:2] or height.shape != sdf.shape[:2] or layer.dtype.kind != "i":
            shapes = f"{layer.shape}, {height.shape}"
            return f"surface_layer / surface_height have shapes {shapes}; expected integers and floats of {sdf.shape[:2]}"
        if (
            height.dtype.kind != "f"
            or not np.isfinite(height).all()
            or layer.min(initial=-1) < -1
            or layer.max(initial=-1) >= sdf.shape[2]
        ):
            return "surface_layer / surface_height hold layers outside the grid or numbers that are not finite"
    for name, layer in (("floor_top", floor_top), ("ceiling", ceiling)):
        if isinstance(layer, bool) or not isinstance(layer, int) or not -1 <= layer <= sdf.shape[2]:
            return f"{name} is {layer!r}; expected a layer index of the grid or -1"
    return None


def cached_occupancy(gaussians: GaussianScene, up: np.ndarray, cameras: list[Camera], cache_dir: str | Path) -> Occupancy:
    """The scene's occupancy from ``cache_dir/occupancy.npz``, built and written when absent or stale."""
    fingerprint = occupancy_fingerprint(gaussians, up, cameras)
    path = Path(cache_dir) / "occupancy.npz"
    grid = load_occupancy(path, fingerprint)
    if grid is None:
        grid = build_occupancy(gaussians, up, cameras)
        save_occupancy(grid, path, fingerprint, gaussians_fingerprint(gaussians))
    return grid
