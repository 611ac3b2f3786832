"""A spatial index for the frame cull of large scenes: Gaussians grouped into chunks, each with a
bounding sphere of its means and the largest spread of its members, so a view rejects whole chunks
before testing Gaussians (:func:`capframe.render.frame_index`).

Chunks are the cells of a uniform grid (about :data:`CHUNK` Gaussians per cell on average), split
further by spread class (``floor(log2)`` of ``|L|_F`` over the median, so the few huge Gaussians of
a capture share chunks among themselves instead of widening every chunk) and into runs of at most
:data:`CHUNK` members.

The chunk test is conservative, so the cull through the index keeps exactly the Gaussians the
brute-force cull keeps. The per-Gaussian test (:func:`~capframe.render.torch_backend.may_touch_frame`)
keeps a Gaussian at depth ``z`` and pixel ``u = f x / z + c`` only if ``u + r > 0`` with the reach
``r = k sqrt((f / z)^2 (1 + t^2) s^2 + eps) + 1 <= k sqrt(1 + t_max^2) f s / z + k sqrt(eps) + 1``
(``s = |L|_F``, ``t`` clamped to ``|t| <= t_max``); times ``z > 0`` that is a linear inequality in
the mean, ``f x + (c + k sqrt(eps) + 1) z + k sqrt(1 + t_max^2) f s > 0``, which holds for some
point of a chunk's sphere only if it holds at the sphere's centre moved by the radius along the
inequality's normal. The same holds for the other three borders and for the depth bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
from torch import Tensor

from .torch_backend import EPS2D, SIGMA_MAX

CHUNK = 4096  # Gaussians per chunk at most (and per grid cell on average)
SLACK = 1.01  # relative slack on the chunk bounds: absorbs float64 rounding


@dataclass
class ChunkIndex:
    """Chunks of a scene's Gaussians.

    Attributes:
        order: (N,) the Gaussians' indices, chunk by chunk.
        starts: (C + 1,) each chunk's first position in ``order`` (and the end).
        centres: (C, 3) float64 centres of the chunks' bounding spheres of means.
        radii: (C,) float64 radii of those spheres.
        spreads: (C,) float64 the largest ``|L|_F`` (root of the summed variances) in each chunk.
    """

    order: Tensor
    starts: Tensor
    centres: Tensor
    radii: Tensor
    spreads: Tensor

    def __len__(self) -> int:
        return len(self.radii)

    @classmethod
    def build(cls, means: Tensor, spreads: Tensor, chunk: int = CHUNK) -> ChunkIndex:
        """Index of Gaussians with means (N, 3) and spreads ``|L|_F`` (N,) (module doc)."""
        means = means.detach().to(torch.float64)
        spreads = spreads.detach().to(torch.float64)
        n = len(means)
        lo, hi = means.min(0).values, means.max(0).values
        cells = max(1, n // chunk)
        side = max(float((hi - lo).prod().clamp_min(1e-300) ** (1.0 / 3.0)) / cells ** (1.0 / 3.0), 1e-300)
        side = max(side, float((hi - lo).max()) / 2**16)  # at most 2^16 cells per axis
        key = ((means - lo) / side).floor().long().clamp(0, 2**16 - 1)
        scale_class = torch.log2(spreads / spreads.median().clamp_min(1e-300)).floor().clamp(0, 62).long()
        packed = (((scale_class << 16 | key[:, 0]) << 16 | key[:, 1]) << 16) | key[:, 2]
        packed, order = torch.sort(packed, stable=True)
        # Chunk boundaries: where the key changes, and every `chunk` members within a run.
        device = means.device
        change = torch.ones(n, dtype=torch.bool, device=device)
        change[1:] = packed[1:] != packed[:-1]
        position = torch.arange(n, device=device)
        run_start = torch.cummax(torch.where(change, position, torch.zeros_like(position)), 0).values
        boundary = change | ((position - run_start) % chunk == 0)
        starts = torch.cat([boundary.nonzero()[:, 0], position.new_tensor([n])])
        owner = torch.cumsum(boundary.long(), 0) - 1  # chunk of each position
        count = len(starts) - 1
        m = means[order]
        low = m.new_full((count, 3), math.inf).scatter_reduce(0, owner[:, None].expand(-1, 3), m, "amin")
        high = m.new_full((count, 3), -math.inf).scatter_reduce(0, owner[:, None].expand(-1, 3), m, "amax")
        centres = (low + high) / 2
        radii = m.new_zeros(count).scatter_reduce(0, owner, (m - centres[owner]).norm(dim=1), "amax")
        widest = m.new_zeros(count).scatter_reduce(0, owner, spreads[order], "amax")
        return cls(order, starts, centres, radii, widest)

    def candidates(self, pose: Tensor, K: Tensor, width: int, height: int, near: float, far: float) -> Tensor:
        """Indices (M,) of the Gaussians in the chunks that may touch the frame of a camera at
        ``pose`` (4, 4) with intrinsics ``K`` (3, 3) (module doc), in chunk order."""
        pose, K = pose.detach().to(torch.float64), K.detach().to(torch.float64)
        R, t = pose[:3, :3], pose[:3, 3]
        local = self.centres @ R.T + t  # camera-frame chunk centres
        r = self.radii * SLACK
        x, y, z = local.unbind(1)
        keep = (z + r > near * (1.0 - 1e-3)) & (z - r < far * (1.0 + 1e-3))
        k = math.sqrt(2.0 * SIGMA_MAX) * 1.01
        pad = k * math.sqrt(EPS2D) + 1.0
        for axis, size, coord in ((0, width, x), (1, height, y)):
            f, c = float(K[axis, axis]), float(K[axis, 2])
            t_max = (max(c, size - c) + 0.15 * size) / f  # clamped_slopes: 30% of the size beyond
            reach = k * math.sqrt(1.0 + t_max**2) * f * self.spreads * SLACK
            # u + reach > 0 and u - reach < size, times z, at the sphere's most favourable point.
            low_side = f * coord + (c + pad) * z + r * math.hypot(f, c + pad) + reach
            high_side = -f * coord + (size - c + pad) * z + r * math.hypot(f, size - c + pad) + reach
            keep &= (low_side > 0) & (high_side > 0)
        chosen = keep.nonzero()[:, 0]
        if len(chosen) == 0:
            return self.order[:0]
        lengths = self.starts[chosen + 1] - self.starts[chosen]
        first = torch.repeat_interleave(self.starts[chosen], lengths)
        run_start = torch.repeat_interleave(torch.cumsum(lengths, 0) - lengths, lengths)
        offset = torch.arange(int(lengths.sum()), device=lengths.device) - run_start
        return self.order[first + offset]


__all__ = ["CHUNK", "ChunkIndex"]
