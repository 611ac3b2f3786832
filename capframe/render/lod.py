"""Level of detail for low-resolution renders: Gaussians merged per octree cell by moment matching,
and the cut of that hierarchy whose cells project below a pixel.

At Refine's 160 px a subject of 300k Gaussians covers a few thousand pixels: most Gaussians are far
below a pixel, so a render of merged Gaussians gives the same masks for a fraction of the work.

Merge (moment matching, per cell and owner; cells never mix owners, so subject masks stay exact
memberships). Each Gaussian ``i`` carries a *mass* ``w_i = o_i A(Sigma_i)``: its opacity times its
splat area ``A`` (:func:`splat_area`, the mean of the pairwise products of its standard
deviations, proportional to its view-averaged integrated alpha). A cell's Gaussian has

* mass ``w = sum w_i`` (kept exactly, also across levels: a parent merges its children's masses);
* mean ``mu = sum w_i mu_i / w``;
* covariance ``Sigma = sum w_i (Sigma_i + (mu_i - mu)(mu_i - mu)^T) / w`` (first and second
  moments of the mixture, so merging the merged children equals merging the originals);
* SH DC ``sum w_i c_i / w`` (bands above 0 are dropped: the cut is for masks and depth);
* opacity ``min(w / A(Sigma), MAX_OPACITY)``: the cell's integrated alpha, saturated where the
  Gaussians overlap more than an opaque one could cover.

Cells are aligned on one octree: level ``l`` has cells of side ``cell * 2^l`` and each cell's parent
is the cell of its integer coordinates halved. :meth:`GaussianHierarchy.cut` picks, for a camera
centre and focal length, the coarsest cell along each branch whose diagonal projects below
``pixels`` at its nearest possible depth, and the original Gaussians where no cell does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
from torch import Tensor

from ..scene.model import GaussianScene, scene_extent
from . import PreparedGaussians, indexed
from .torch_backend import covariance_factor

MAX_OPACITY = 0.99  # a merged Gaussian's opacity cap (the renderer clamps alpha at 0.999)
KEY_BITS = 18  # bits per cell coordinate in a packed cell key; the owner takes the bits above
MAX_LEVELS = 16
# Finest cells of a whole scene's hierarchy (occluders, visibility checks), in median |L|_F:
# coarser than a subject's (seen up close), so building it over millions of Gaussians stays cheap.
SCENE_CELL = 2.0
MIN_SHRINK = 0.9  # a level is kept only when it holds at most this share of the level below


def splat_area(variances: Tensor) -> Tensor:
    """Splat area ``(s1 s2 + s2 s3 + s1 s3) / 3`` from the covariance eigenvalues ``s_k^2``:
    (..., 3) -> (...)."""
    s = variances.clamp_min(0.0).sqrt()
    return (s[..., 0] * s[..., 1] + s[..., 1] * s[..., 2] + s[..., 0] * s[..., 2]) / 3.0


def moment_match(
    means: Tensor, covariances: Tensor, masses: Tensor, dc: Tensor, group: Tensor, groups: int
) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """Merge Gaussians per group by moment matching (module doc), float64.

    Args:
        means: (N, 3); covariances: (N, 3, 3); masses: (N,) positive; dc: (N, 3) SH DC.
        group: (N,) group index in ``[0, groups)`` of each Gaussian.
    Returns:
        means (G, 3), covariances (G, 3, 3), masses (G,), dc (G, 3) of the groups.
    """
    mass = torch.zeros(groups, dtype=means.dtype).index_add_(0, group, masses)
    share = masses / mass.clamp_min(1e-300)[group]  # each Gaussian's weight within its group
    mean = torch.zeros(groups, 3, dtype=means.dtype).index_add_(0, group, share[:, None] * means)
    # Offsets from the merged mean (not raw second moments): exact far from the origin too.
    offset = means - mean[group]
    spread = covariances + offset[:, :, None] * offset[:, None, :]
    covariance = torch.zeros(groups, 3, 3, dtype=means.dtype).index_add_(0, group, share[:, None, None] * spread)
    colour = torch.zeros(groups, 3, dtype=means.dtype).index_add_(0, group, share[:, None] * dc)
    return mean, covariance, mass, colour


@dataclass
class Level:
    """The merged Gaussians of one octree level.

    Attributes:
        means: (M, 3) float64; covariances: (M, 3, 3) float64; masses: (M,) float64;
        dc: (M, 3) float64 SH DC.
        owner: (M,) int64 owner of the cell (its Gaussians' common owner).
        keys: (M, 3) int64 integer cell coordinates at this level.
        side: the cells' side length.
        children: (N_below,) index of each Gaussian (or cell) of the level below into this one.
    """

    means: Tensor
    covariances: Tensor
    masses: Tensor
    dc: Tensor
    owner: Tensor
    keys: Tensor
    side: float
    children: Tensor

    def __len__(self) -> int:
        return len(self.means)


def _pack(owner: Tensor, keys: Tensor) -> Tensor:
    """One int64 per (owner, cell): owner + 1 above three :data:`KEY_BITS`-bit coordinates."""
    packed = owner + 1
    for axis in range(3):
        packed = (packed << KEY_BITS) | keys[:, axis]
    return packed


def _merge_level(means, covariances, masses, dc, owner, keys, side) -> Level:
    """Merge the Gaussians of one level whose (owner, ``keys``) agree into the next level."""
    unique, group = torch.unique(_pack(owner, keys), return_inverse=True)
    mean, cov, mass, colour = moment_match(means, covariances, masses, dc, group, len(unique))
    first = torch.zeros(len(unique), dtype=torch.long).scatter_(0, group, torch.arange(len(group)))
    return Level(mean, cov, mass, colour, owner[first], keys[first], side, group)


def level_gaussians(level: Level, dtype: torch.dtype, extent: float) -> PreparedGaussians:
    """The render inputs of a level: covariance factors from its eigen-decomposition
    ``Sigma = V diag(s^2) V^T -> L = V diag(s)``, opacity ``min(w / A, MAX_OPACITY)``."""
    variances, vectors = torch.linalg.eigh(level.covariances)
    variances = variances.clamp_min(1e-12 * level.side**2)  # a flat cell of coplanar disks
    opacity = (level.masses / splat_area(variances)).clamp(max=MAX_OPACITY)
    return PreparedGaussians(
        means=level.means,
        factors=(vectors * variances.sqrt()[:, None, :]).to(dtype),
        opacities=opacity.to(dtype),
        sh=level.dc[:, None, :].to(dtype),
        extent=extent,
    )


class GaussianHierarchy:
    """An octree of merged Gaussians over ``scene`` (module doc), built once.

    Args:
        scene: the Gaussians.
        owner: (N,) int64 owner of each Gaussian (e.g. its subject, -1 for none); cells never mix owners.
        cell: side of the finest cells; default half the median of the Gaussians' ``|L|_F``
            (the root of their summed variances), at least the extent over ``2^KEY_BITS``.
        dtype: render dtype of :meth:`cut`'s output.
        extent: the extent the default near plane is relative to (default ``scene``'s).
    """

    def __init__(
        self,
        scene: GaussianScene,
        owner: Tensor,
        cell: float | None = None,
        dtype: torch.dtype = torch.float32,
        extent: float | None = None,
    ):
        if len(scene) == 0:
            raise ValueError("GaussianHierarchy needs at least one Gaussian")
        if int(owner.max()) + 2 >= 1 << (63 - 3 * KEY_BITS):
            raise ValueError(f"owner ids up to {int(owner.max())}; expected below {(1 << (63 - 3 * KEY_BITS)) - 2}")
        self.extent = scene_extent(scene.means.detach()) if extent is None else extent
        self.dtype = dtype
        self.owner = owner
        with torch.no_grad():
            means = scene.means.detach().to(torch.float64)
            scales = scene.scales.detach().to(torch.float64)
            factors = covariance_factor(scene.quats.detach().to(torch.float64), scales)
            covariances = factors @ factors.transpose(1, 2)
            self.full = PreparedGaussians(
                means, factors.to(dtype), scene.opacities.detach().to(dtype), scene.sh.detach().to(dtype), self.extent
            )
            masses = scene.opacities.detach().to(torch.float64) * splat_area(scales**2)
            dc = scene.sh[:, 0].detach().to(torch.float64)
            lo = means.min(0).values
            span = float((means.max(0).values - lo).max())
            side = float(0.5 * scales.norm(dim=1).median()) if cell is None else float(cell)
            side = max(side, span / (1 << KEY_BITS) * 1.001, 1e-300)
            self.levels: list[Level] = []
            keys = ((means - lo) / side).floor().long()
            roots = len(torch.unique(owner))
            while len(self.levels) < MAX_LEVELS:
                level = _merge_level(means, covariances, masses, dc, owner, keys, side)
                # A level that merges little is not kept (it would cost as much as the one below):
                # the cells double until they merge enough, or until one cell per owner is left.
                if len(level) <= MIN_SHRINK * len(means) or len(level) == roots:
                    self.levels.append(level)
                    means, covariances, masses, dc, owner = level.means, level.covariances, level.masses, level.dc, level.owner
                    keys = level.keys
                    if len(level) == roots:
                        break
                keys, side = keys // 2, 2.0 * side
            self.prepared = [level_gaussians(level, dtype, self.extent) for level in self.levels]

    def __len__(self) -> int:
        return len(self.full)

    def select(
        self, centre: Tensor, focal: float, pixels: float = 1.0, slack: float = 0.0, cos_half_angle: float = 1.0
    ) -> list[Tensor]:
        """The cut for any camera centre within ``slack`` of ``centre`` (3,), as indices: one
        tensor per level (finest first) of the cells taken, then one of the originals taken.

        A cell is usable when its side spans at most ``pixels`` pixels of focal length ``focal``
        at its nearest possible depth, ``(|mu - centre| - slack - sqrt(3) side) cos_half_angle``
        (``cos_half_angle``: cosine of the largest angle between a pixel's ray and the optical
        axis). Along each branch the coarsest usable cell is taken, the original Gaussians where
        none is: every original is drawn exactly once, itself or inside one cell.
        """
        centre = centre.detach().to(torch.float64)
        taken: list[Tensor] = []
        covered = None  # per cell of the current level: an ancestor is already in the cut
        for level in reversed(self.levels):
            depth = ((level.means - centre).norm(dim=1) - slack - math.sqrt(3.0) * level.side) * cos_half_angle
            take = level.side * focal <= pixels * depth
            if covered is not None:
                take &= ~covered
                covered = covered | take
            else:
                covered = take
            taken.append(take.nonzero()[:, 0])
            covered = covered[level.children]  # for each member of the level below
        taken.reverse()
        taken.append((~covered).nonzero()[:, 0])
        return taken

    def cut(
        self, centre: Tensor, focal: float, pixels: float = 1.0, slack: float = 0.0, cos_half_angle: float = 1.0
    ) -> tuple[PreparedGaussians, Tensor, Tensor]:
        """The Gaussians of :meth:`select`'s cut (same arguments), ready to render.

        Returns:
            the prepared Gaussians (SH DC only), their owners (M,), and the level of each (M,)
            (-1: an original).
        """
        taken = self.select(centre, focal, pixels, slack, cos_half_angle)
        sources = [*self.prepared, self.full]
        owners = [*(level.owner for level in self.levels), self.owner]
        parts = [source.subset(index) for source, index in zip(sources, taken)]
        tags = [torch.full((len(index),), k if k < len(self.levels) else -1, dtype=torch.long) for k, index in enumerate(taken)]
        gaussians = PreparedGaussians(
            means=torch.cat([p.means for p in parts]),
            factors=torch.cat([p.factors for p in parts]),
            opacities=torch.cat([p.opacities for p in parts]),
            sh=torch.cat([p.sh[:, :1] for p in parts]),
            extent=self.extent,
        )
        return gaussians, torch.cat([o[i] for o, i in zip(owners, taken)]), torch.cat(tags)


def ray_cosine(K, width: int, height: int) -> float:
    """Cosine of the largest angle between a pixel's ray and the optical axis of a
    ``width`` x ``height`` camera with intrinsics ``K`` (3, 3): a point seen at distance ``d``
    lies at depth at least ``d`` times it."""
    tx = max(float(K[0, 2]), width - float(K[0, 2])) / float(K[0, 0])
    ty = max(float(K[1, 2]), height - float(K[1, 2])) / float(K[1, 1])
    return 1.0 / math.sqrt(1.0 + tx * tx + ty * ty)


class LodView:
    """A hierarchy's cut for a moving camera (Refine's steps): cut again only when the camera
    centre leaves a ball around the last cut's centre. The ball's radius is the cut's ``slack``:
    a tenth of the camera's distance to the Gaussians' bounding sphere (a tenth of its radius
    inside it), so a cut stays within ``pixels`` wherever the camera is in the ball.

    Args:
        hierarchy: the Gaussians (:class:`GaussianHierarchy`).
        channels: columns of the one-hot membership of the owners (owners in ``[0, channels)``).
        camera: the canvas rendered (its intrinsics and size bound the projected cell size).
        pixels: see :meth:`GaussianHierarchy.cut`; 0 always renders every Gaussian.
    """

    def __init__(self, hierarchy: GaussianHierarchy, channels: int, camera, pixels: float):
        self.hierarchy, self.channels, self.pixels = hierarchy, channels, pixels
        self.extent = hierarchy.extent
        self.focal = float(max(camera.K[0, 0], camera.K[1, 1]))
        self.cosine = ray_cosine(camera.K, camera.width, camera.height)
        means = hierarchy.full.means
        self.bound_centre = (means.min(0).values + means.max(0).values) / 2
        self.radius = float((means - self.bound_centre).norm(dim=1).max())
        self.centre: Tensor | None = None
        self.levels: Tensor | None = None  # level of each Gaussian of the cut (-1: original)
        if pixels <= 0:
            self._store(hierarchy.full, hierarchy.owner, torch.full((len(hierarchy),), -1, dtype=torch.long))

    def _store(self, gaussians: PreparedGaussians, owner: Tensor, levels: Tensor) -> None:
        self.gaussians, self.levels = indexed(gaussians), levels
        self.membership = torch.nn.functional.one_hot(owner, self.channels).to(gaussians.opacities.dtype)

    def around(self, centre: Tensor) -> tuple[PreparedGaussians, Tensor]:
        """The Gaussians to render from ``centre`` (3,) and their (M, channels) membership."""
        if self.pixels <= 0:
            return self.gaussians, self.membership
        centre = centre.detach().to(torch.float64)
        if self.centre is None or float((centre - self.centre).norm()) > self.slack:
            distance = float((centre - self.bound_centre).norm())
            self.slack = 0.1 * max(distance - self.radius, self.radius)
            self.centre = centre
            self._store(*self.hierarchy.cut(centre, self.focal, self.pixels, self.slack, self.cosine))
        return self.gaussians, self.membership


_CACHE: dict = {}  # the hierarchies built by cached_hierarchy, by key (the last CACHED of them)
CACHED = 2  # a query's subjects and its whole scene


def cached_hierarchy(
    scene: GaussianScene, index: Tensor | None, owner: Tensor, dtype: torch.dtype, cell_factor: float = 0.5
) -> GaussianHierarchy:
    """The hierarchy of ``scene``'s Gaussians ``index`` (M,) (None: all) owned by ``owner`` (M,),
    with finest cells of ``cell_factor`` times their median ``|L|_F`` and the whole scene's
    extent. Built once per query: one query refines the same subjects from several starts and
    checks several closed-form cameras."""
    key = (
        id(scene),
        scene.means.data_ptr(),
        len(scene),
        None if index is None else index.numpy().tobytes(),
        owner.numpy().tobytes(),
        dtype,
        cell_factor,
    )
    if key not in _CACHE:
        while len(_CACHE) >= CACHED:
            _CACHE.pop(next(iter(_CACHE)))
        part = scene if index is None else scene.subset(index)
        with torch.no_grad():
            cell = cell_factor * float(part.scales.norm(dim=1).median())
        _CACHE[key] = GaussianHierarchy(part, owner, cell=cell, dtype=dtype, extent=scene_extent(scene.means.detach()))
    return _CACHE[key]


def subject_owner(count: int, subjects: list[Tensor]) -> Tensor:
    """(count,) int64: ``k`` for the Gaussians of ``subjects[k]`` (index tensors), -1 elsewhere."""
    owner = torch.full((count,), -1, dtype=torch.long)
    for k, index in enumerate(subjects):
        owner[index] = k
    return owner


__all__ = [
    "GaussianHierarchy",
    "Level",
    "LodView",
    "MAX_OPACITY",
    "SCENE_CELL",
    "level_gaussians",
    "moment_match",
    "ray_cosine",
    "cached_hierarchy",
    "splat_area",
    "subject_owner",
]
