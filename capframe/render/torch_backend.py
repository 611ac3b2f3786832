"""Pure-PyTorch Gaussian rasteriser: runs on any device, differentiable w.r.t. the pose.

It follows gsplat's "classic" rules so that both backends agree pixel for pixel:

* EWA projection with the perspective Jacobian clamped slightly outside the frustum, plus a
  ``0.3`` px^2 low-pass on the 2D covariance;
* a Gaussian contributes to a pixel when it lies inside its 3-sigma ellipse and its alpha
  ``min(0.999, opacity * exp(-sigma))`` is at least ``1/255``;
* front-to-back compositing that stops before a Gaussian would drive the transmittance below
  ``1e-4``.

One rule differs from gsplat's on purpose, the **3-sigma cut**: gsplat (1.5) skips a Gaussian at
a pixel only when its alpha is below ``1/255``, which for an opaque Gaussian reaches out to
``sqrt(2 ln 255) = 3.33`` sigma; here it also stops at the 3-sigma ellipse (``sigma <= 4.5``).
The ring between the two holds alphas of at most ``opacity * exp(-4.5) < 0.011`` per Gaussian
(where many tails overlap, alpha differs from gsplat's by up to about 0.1), and dropping it keeps
an opaque Gaussian's footprint, and so the (tile, Gaussian) pairs and the time, about 20% smaller,
for every opacity above ``exp(4.5) / 255 = 0.35``. The compiled backend applies the same rule.

Unlike a tile-sorted CUDA kernel, the per-pixel cut-off here is the ellipse itself, so the image
does not depend on the tile size. Work is organised in square pixel tiles: each (tile, Gaussian)
pair evaluates its ``tile_size^2`` pixels in one vectorised step, and the transmittance is a
segmented cumulative sum of ``log(1 - alpha)`` over the depth-sorted pairs of each tile. Tiles are
processed in chunks, and the compositing backward is analytic and recomputes its per-pixel state
from the per-slot inputs, so memory stays bounded at any resolution.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import torch
from torch import Tensor

from ..geometry.quaternion import quat_to_rotmat

ALPHA_MAX = 0.999
ALPHA_MIN = 1.0 / 255.0
TRANSMITTANCE_MIN = 1e-4
EPS2D = 0.3
SIGMA_MAX = 4.5  # 0.5 * 3^2: the 3-sigma ellipse


def covariance_factor(quats: Tensor, scales: Tensor) -> Tensor:
    """Factor ``L = R S`` of the world covariances ``Sigma = L L^T``: (N, 4) wxyz, (N, 3) -> (N, 3, 3)."""
    return quat_to_rotmat(quats) * scales[:, None, :]


def clamped_slopes(means_cam: Tensor, K: Tensor, width: int, height: int) -> tuple[Tensor, Tensor]:
    """``x/z`` and ``y/z`` (N,) of camera-frame points, clamped to 30% beyond the image borders,
    as gsplat evaluates the projection's Jacobian."""
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    x, y, z = means_cam.unbind(-1)
    margin_x, margin_y = 0.3 * 0.5 * width / fx, 0.3 * 0.5 * height / fy
    tx = torch.clamp(x / z, -(cx / fx + margin_x), (width - cx) / fx + margin_x)
    ty = torch.clamp(y / z, -(cy / fy + margin_y), (height - cy) / fy + margin_y)
    return tx, ty


def ewa_project(
    means_cam: Tensor, R: Tensor, factors: Tensor, K: Tensor, width: int, height: int, eps2d: float = EPS2D
) -> tuple[Tensor, Tensor]:
    """Perspective projection of 3D Gaussians (requires camera-frame ``z > 0``).

    The 2D covariance is ``(J R L)(J R L)^T`` plus the low-pass, with ``J`` the projection's
    Jacobian at the mean, evaluated with ``x/z`` and ``y/z`` clamped to 30% beyond the image
    borders as gsplat does, so Gaussians far outside the view do not blow up.

    Args:
        means_cam: (N, 3) camera-frame means.
        R: (3, 3) world-to-camera rotation.
        factors: (N, 3, 3) world covariance factors ``L``.
        K: (3, 3) intrinsics.
    Returns:
        means2d (N, 2) in pixels and the low-passed 2D covariances (N, 2, 2).
    """
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    x, y, z = means_cam.unbind(-1)
    tx, ty = clamped_slopes(means_cam, K, width, height)
    # Rows of J R: J = [[fx/z, 0, -fx tx/z], [0, fy/z, -fy ty/z]] with tx, ty the clamped x/z, y/z.
    JR = torch.stack([(fx / z)[:, None] * (R[0] - tx[:, None] * R[2]), (fy / z)[:, None] * (R[1] - ty[:, None] * R[2])], 1)
    M = JR @ factors  # (N, 2, 3)
    cov2d = M @ M.transpose(-1, -2) + eps2d * torch.eye(2, dtype=M.dtype, device=M.device)
    means2d = torch.stack([fx * x / z + cx, fy * y / z + cy], -1)
    return means2d, cov2d


def conic_of(cov2d: Tensor) -> Tensor:
    """Inverse 2D covariance as ``(a, b, c)`` with ``sigma = a dx^2/2 + b dx dy + c dy^2/2``:
    (N, 2, 2) -> (N, 3). The caller guarantees a positive determinant."""
    a, b, c = cov2d[:, 0, 0], cov2d[:, 0, 1], cov2d[:, 1, 1]
    det = a * c - b * b
    return torch.stack([c / det, -b / det, a / det], -1)


def pixel_extent(cov2d: Tensor, opacities: Tensor) -> Tensor:
    """Half-widths (N, 2) in pixels of the axis-aligned box around the region a Gaussian can
    touch: its 3-sigma ellipse, shrunk to where ``opacity * exp(-sigma) >= 1/255``."""
    level = 2.0 * torch.log(opacities.clamp_min(ALPHA_MIN) / ALPHA_MIN)  # (k sigma)^2 of the alpha floor
    k = torch.sqrt(level.clamp(0.0, 2.0 * SIGMA_MAX))
    return k[:, None] * torch.sqrt(torch.stack([cov2d[:, 0, 0], cov2d[:, 1, 1]], -1))


def may_touch_frame(means_cam: Tensor, factors: Tensor, K: Tensor, width: int, height: int, eps2d: float = EPS2D) -> Tensor:
    """(N,) False only for Gaussians (camera-frame ``z > 0``) whose footprint box
    (:func:`pixel_extent` of :func:`ewa_project`) certainly misses the frame; cheap, no matrix products.

    Bound: a row of ``J R`` is ``(f / z) (R_i - t R_2)``, of norm ``(f / z) sqrt(1 + t^2)`` with
    the same clamped ``t`` as the projection, and ``|row L| <= |row| |L|_F``, so the 2D variance
    is at most ``(f / z)^2 (1 + t^2) |L|_F^2 + eps2d``; the extent uses the largest cut-off,
    3 sigma. The 1% and 1 px slack absorb rounding.
    """
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    x, y, z = means_cam.unbind(-1)
    spread2 = (factors * factors).sum((1, 2))  # |L|_F^2: the sum of the squared scales
    tx, ty = clamped_slopes(means_cam, K, width, height)
    k = math.sqrt(2.0 * SIGMA_MAX) * 1.01
    reach_x = k * torch.sqrt((fx / z) ** 2 * (1 + tx * tx) * spread2 + eps2d) + 1.0
    reach_y = k * torch.sqrt((fy / z) ** 2 * (1 + ty * ty) * spread2 + eps2d) + 1.0
    u, v = fx * x / z + cx, fy * y / z + cy
    return (u + reach_x > 0) & (u - reach_x < width) & (v + reach_y > 0) & (v - reach_y < height)


@dataclass
class Projection:
    """Depth-sorted visible Gaussians of one view.

    Attributes:
        index: (G,) indices into the input Gaussians, nearest first.
        means2d: (G, 2) pixel coordinates.
        conics: (G, 3) inverse 2D covariances ``(a, b, c)``.
        depths: (G,) camera-frame z.
        extents: (G, 2) pixel half-widths of the touched region (no gradient).
    """

    index: Tensor
    means2d: Tensor
    conics: Tensor
    depths: Tensor
    extents: Tensor


def project_gaussians(
    means: Tensor,
    factors: Tensor,
    opacities: Tensor,
    T_cw: Tensor,
    K: Tensor,
    width: int,
    height: int,
    near: float,
    far: float,
) -> Projection:
    """Cull and project Gaussians; differentiable w.r.t. ``T_cw``, the means and the factors.

    The differentiable projection runs on the Gaussians in front of the camera with finite
    factors; the rest of the culling (degenerate 2D covariance, footprint off-screen) selects
    from its output. That is safe only while every value is finite: an Inf from a culled
    Gaussian would turn into a NaN pose gradient (``0 * inf``) through the shared ops. So when a
    huge Gaussian overflows, the projection is redone without it.
    """
    R, t = T_cw[:3, :3], T_cw[:3, 3]
    with torch.no_grad():
        z = means @ R[2] + t[2]
        finite_3d = torch.isfinite(factors).flatten(1).all(1)
        front = ((z > near) & (z < far) & finite_3d).nonzero()[:, 0]
        # The projection is most of the per-Gaussian cost: skip those that provably miss the frame.
        front = front[may_touch_frame(means[front] @ R.T + t, factors[front], K, width, height)]
    skipped = len(finite_3d) - int(finite_3d.sum())
    means_cam = means[front] @ R.T + t
    means2d, cov2d = ewa_project(means_cam, R, factors[front], K, width, height)
    finite = (torch.isfinite(cov2d).flatten(1).all(1) & torch.isfinite(means2d).all(1)).detach()
    if not finite.all():
        skipped += len(finite) - int(finite.sum())
        front = front[finite]
        means_cam = means[front] @ R.T + t
        means2d, cov2d = ewa_project(means_cam, R, factors[front], K, width, height)
    if skipped:
        warnings.warn(f"{skipped} Gaussians with non-finite covariance (huge or NaN scales) were skipped", stacklevel=3)
    with torch.no_grad():
        m, c = means2d.detach(), cov2d.detach()
        det = c[:, 0, 0] * c[:, 1, 1] - c[:, 0, 1] ** 2
        extents = pixel_extent(c, opacities[front])
        on_screen = (m + extents > 0).all(1) & (m[:, 0] - extents[:, 0] < width) & (m[:, 1] - extents[:, 1] < height)
        ok = ((det > 0) & (extents > 0).all(1) & on_screen).nonzero()[:, 0]
        sel = ok[torch.argsort(z[front][ok], stable=True)]
    return Projection(front[sel], means2d[sel], conic_of(cov2d[sel]), means_cam[sel, 2], extents[sel])


@dataclass
class TileBlocks:
    """(tile, Gaussian) intersections laid out in fixed-size blocks.

    Each tile's depth-sorted pairs fill ``ceil(n / B)`` consecutive blocks of ``B`` slots; unused
    slots point at a dummy Gaussian (index ``G``) with zero opacity. This dense layout lets the
    transmittance scan run along a tensor dimension and the final reduction be a batched matmul,
    with at most ``B - 1`` wasted slots per tile.

    Attributes:
        gaussian: (num_blocks, B) index into the projection's Gaussians, ``G`` for padding.
        block_tile: (num_blocks,) flat tile id ``ty * tiles_x + tx`` of each block.
        block_first: (num_blocks,) index of the first block of the same tile.
        tile_block_start: (tiles + 1,) offsets of each tile's blocks.
        pairs: number of real (tile, Gaussian) pairs.
    """

    gaussian: Tensor
    block_tile: Tensor
    block_first: Tensor
    tile_block_start: Tensor
    pairs: int


def _row_spans(means2d: Tensor, conics: Tensor, reach: Tensor, band_lo: Tensor, band_hi: Tensor) -> tuple[Tensor, Tensor]:
    """x-range ``[lo, hi]`` of the ellipses ``sigma <= reach`` over horizontal bands of pixel
    centres ``band_lo <= y <= band_hi``: all (R,) per (Gaussian, row) entry; ``lo > hi`` when
    the ellipse misses the band.

    With ``D = ac - b^2``, the ellipse's right edge at height ``dy`` is
    ``x = -b dy / a + sqrt(2 a reach - D dy^2) / a``: concave in ``dy``, so its maximum over the
    band is at the ellipse's rightmost point clamped to the band (and symmetrically on the left).
    """
    mx, my = means2d.unbind(-1)
    a, b, c = conics.unbind(-1)
    det = a * c - b * b
    two_k = 2.0 * reach
    y_reach = torch.sqrt(two_k * a / det)  # |dy| on the ellipse (Sigma_yy = a / D)
    lo = torch.maximum(band_lo - my, -y_reach)
    hi = torch.minimum(band_hi - my, y_reach)
    dy_rightmost = -b * torch.sqrt(two_k / (c * det))  # Sigma_xy sqrt(2 reach / Sigma_xx); leftmost is its mirror

    def half_width(dy):
        return torch.sqrt((two_k * a - det * dy * dy).clamp_min(0.0)) / a

    dy_right, dy_left = dy_rightmost.clamp(lo, hi), (-dy_rightmost).clamp(lo, hi)
    right = mx - b * dy_right / a + half_width(dy_right)
    left = mx - b * dy_left / a - half_width(dy_left)
    empty = lo > hi
    return torch.where(empty, torch.ones_like(left), left), torch.where(empty, torch.zeros_like(right), right)


def intersect_tiles(
    means2d: Tensor, conics: Tensor, opacities: Tensor, extents: Tensor, tile_size: int, tiles_x: int, tiles_y: int, block: int
) -> TileBlocks:
    """Tile blocks of the (tile, Gaussian) pairs where some pixel centre of the tile passes the
    Gaussian's cut-offs, for depth-sorted Gaussians.

    Scanline generation: for each Gaussian and each tile row its footprint box spans, the exact
    x-range of its cut-off ellipse over the row's pixel centres gives the tiles, so no pair is
    generated that touches no pixel (about a quarter of the footprint box's tiles).
    """
    with torch.no_grad():
        device = means2d.device
        num_gaussians, num_tiles = len(means2d), tiles_x * tiles_y
        y0 = torch.floor((means2d[:, 1] - extents[:, 1]) / tile_size).long().clamp(0, tiles_y)
        y1 = (torch.floor((means2d[:, 1] + extents[:, 1]) / tile_size).long() + 1).clamp(0, tiles_y)
        rows = (y1 - y0).clamp_min(0)
        row_gaussian = torch.repeat_interleave(torch.arange(num_gaussians, device=device), rows)
        row_first = torch.cumsum(rows, 0) - rows
        ty = y0[row_gaussian] + torch.arange(len(row_gaussian), device=device) - row_first[row_gaussian]
        # The cut-off is sigma <= min(4.5, log(255 opacity)), with a margin against rounding.
        reach = torch.log(opacities.clamp_min(ALPHA_MIN) / ALPHA_MIN).clamp_max(SIGMA_MAX) + 1e-4
        band_lo = (ty * tile_size).to(means2d.dtype) + 0.5
        left, right = _row_spans(
            means2d[row_gaussian], conics[row_gaussian], reach[row_gaussian], band_lo, band_lo + tile_size - 1
        )
        # Tile tx holds pixel centres [tx S + 0.5, tx S + S - 0.5].
        tx0 = torch.ceil((left + 0.5 - tile_size) / tile_size).long().clamp(0, tiles_x)
        tx1 = torch.floor((right - 0.5) / tile_size).long().clamp(-1, tiles_x - 1)
        counts = (tx1 - tx0 + 1).clamp_min(0)
        pair_row = torch.repeat_interleave(torch.arange(len(counts), device=device), counts)
        pair_first = torch.cumsum(counts, 0) - counts
        gaussian = row_gaussian[pair_row]
        tile = ty[pair_row] * tiles_x + tx0[pair_row] + torch.arange(len(pair_row), device=device) - pair_first[pair_row]
        # Gaussians are already in depth order, so a stable sort by tile keeps depth order per tile.
        tile, order = torch.sort(tile, stable=True)
        gaussian = gaussian[order]

        per_tile = torch.bincount(tile, minlength=num_tiles)
        pair_start = torch.cumsum(per_tile, 0) - per_tile
        blocks_per_tile = -(-per_tile // block)
        tile_block_start = torch.zeros(num_tiles + 1, dtype=torch.long, device=device)
        tile_block_start[1:] = torch.cumsum(blocks_per_tile, 0)
        num_blocks = int(tile_block_start[-1])
        rank = torch.arange(len(tile), device=device) - pair_start[tile]
        slots = torch.full((num_blocks * block,), num_gaussians, dtype=torch.long, device=device)
        slots[tile_block_start[tile] * block + rank] = gaussian
        block_tile = torch.repeat_interleave(torch.arange(num_tiles, device=device), blocks_per_tile)
    return TileBlocks(slots.view(num_blocks, block), block_tile, tile_block_start[block_tile], tile_block_start, len(tile))


# Forward passes whose per-pixel state holds at most this many slot-pixels keep it for the
# backward; larger ones recompute it there, so memory stays bounded.
KEEP_STATE_MAX = 1 << 23
# Block transmittances below this are treated as zero (compositing stopped long before).
_LOG_T_FLOOR = -80.0


@dataclass
class _BlockState:
    """Per slot-pixel quantities of a compositing pass, shapes (nb, B, S*S)."""

    weights: Tensor  # alpha * T, zero once compositing has stopped (T < 1e-4)
    odds: Tensor  # alpha / (1 - alpha)
    live: Tensor  # 1 where alpha = opacity * exp(-sigma) (inside the cut-offs, not clamped), else 0


def _segment_exclusive(block_sum: Tensor, block_first: Tensor) -> Tensor:
    """Sum over the earlier blocks of the same tile: (nb, P) -> (nb, P). float64 inside: it is a
    difference of running sums over all blocks of the chunk."""
    wide = block_sum.double()
    exclusive = torch.cumsum(wide, 0) - wide
    return (exclusive - exclusive[block_first]).to(block_sum.dtype)


def _offset_basis(tile_size: int, dtype: torch.dtype, device) -> Tensor:
    """Monomials ``[1, ox, oy, ox^2, ox oy, oy^2]`` of each pixel's offset from the tile centre:
    (6, S*S), pixels row-major."""
    o = torch.arange(tile_size, dtype=dtype, device=device) + 0.5 - 0.5 * tile_size
    oy, ox = torch.meshgrid(o, o, indexing="ij")
    ox, oy = ox.flatten(), oy.flatten()
    return torch.stack([torch.ones_like(ox), ox, oy, ox * ox, ox * oy, oy * oy])


def _block_state(exponent_coefs: Tensor, threshold: Tensor, block_first: Tensor, tile_size: int) -> _BlockState:
    """Weights of all slots over their tile's pixels. Runs outside autograd (inside
    :class:`_CompositeBlocks`), so it works in place; masks are kept as 0/1 floats because CPU
    kernels write and multiply those much faster than bool tensors.

    Args:
        exponent_coefs: (nb, B, 6) coefficients of ``q = log(opacity) - sigma`` in the offset basis.
        threshold: (nb, B, 1) the pixel counts where ``q >= threshold``.
    """
    nb, B, _ = exponent_coefs.shape
    basis = _offset_basis(tile_size, exponent_coefs.dtype, exponent_coefs.device)
    q = (exponent_coefs.reshape(-1, 6) @ basis).view(nb, B, -1)
    inside = q.clone().ge_(threshold)
    alpha = q.exp_().clamp_max_(ALPHA_MAX).mul_(inside)
    live = alpha.clone().lt_(ALPHA_MAX).mul_(inside)  # not clamped: d alpha / d q = alpha
    keep = 1.0 - alpha  # >= 1 - ALPHA_MAX, so dividing by it is safe
    # Transmittance after each slot: product within the block times the earlier blocks' product.
    after = torch.cumprod(keep, 1)
    log_block = torch.log(after[:, -1].clamp_min(math.exp(_LOG_T_FLOOR)))
    after.mul_(torch.exp(_segment_exclusive(log_block, block_first))[:, None, :])
    before = after / keep
    # gsplat stops before a Gaussian would leave T below 1e-4; T is monotone, so all later ones stop too.
    weights = before.mul_(alpha).mul_(after.gt_(TRANSMITTANCE_MIN))
    return _BlockState(weights, alpha.div_(keep), live)


def _with_alpha_channel(values: Tensor) -> Tensor:
    return torch.cat([values, torch.ones_like(values[..., :1])], -1)


class _CompositeBlocks(torch.autograd.Function):
    """Front-to-back compositing with an analytic backward. Small passes keep their per-pixel
    state for the backward; large ones keep only the per-slot inputs and recompute it."""

    @staticmethod
    def forward(ctx, exponent_coefs, threshold, values, block_first, tile_size):
        state = _block_state(exponent_coefs, threshold, block_first, tile_size)
        ctx.save_for_backward(exponent_coefs, threshold, values, block_first)
        ctx.tile_size = tile_size
        ctx.state = state if state.weights.numel() <= KEEP_STATE_MAX else None
        return state.weights.transpose(1, 2) @ _with_alpha_channel(values)

    @staticmethod
    def backward(ctx, grad_out):
        exponent_coefs, threshold, values, block_first = ctx.saved_tensors
        st = ctx.state or _block_state(exponent_coefs, threshold, block_first, ctx.tile_size)
        ctx.state = None
        grad_values = (st.weights @ grad_out)[..., :-1]
        # d out / d alpha_i = T_i v_i - (sum_{k>i} w_k v_k) / (1 - alpha_i), contracted with
        # grad_out; times alpha_i (= d alpha_i / d q_i where live) that is
        # w_i c_i - after_i * alpha_i / (1 - alpha_i).
        contrib = _with_alpha_channel(values) @ grad_out.transpose(1, 2)  # (nb, B, P): c_i = v_i . g
        weighted = contrib.mul_(st.weights)
        inclusive = torch.cumsum(weighted, 1)
        earlier = _segment_exclusive(inclusive[:, -1], block_first)
        tile_total = torch.zeros_like(inclusive[:, -1]).index_add(0, block_first, inclusive[:, -1])[block_first]
        after = inclusive.neg_().add_((tile_total - earlier)[:, None, :])  # sum over later slots
        grad_q = weighted.sub_(after.mul_(st.odds)).mul_(st.live)
        basis = _offset_basis(ctx.tile_size, grad_q.dtype, grad_q.device)
        grad_coefs = (grad_q.reshape(-1, grad_q.shape[-1]) @ basis.T).view_as(exponent_coefs)
        return grad_coefs, None, grad_values, None, None


class _GatherRows(torch.autograd.Function):
    """``source[index]`` whose backward scatters with ``index_add_`` (faster on CPU than the
    accumulating ``index_put_`` autograd uses for advanced indexing)."""

    @staticmethod
    def forward(ctx, source, index):
        ctx.save_for_backward(index)
        ctx.rows = source.shape[0]
        return source[index]

    @staticmethod
    def backward(ctx, grad):
        (index,) = ctx.saved_tensors
        out = grad.new_zeros(ctx.rows, *grad.shape[index.dim() :])
        return out.index_add_(0, index.flatten(), grad.flatten(0, index.dim() - 1)), None


def _slot_exponents(
    attributes: Tensor, slot_index: Tensor, block_x: Tensor, block_y: Tensor, tile_size: int
) -> tuple[Tensor, Tensor, Tensor]:
    """Per-slot coefficients of ``q = log(opacity) - sigma`` in the pixel-offset basis.

    With the offset ``(ox, oy)`` of a pixel from its tile centre and ``(ex, ey)`` the tile centre
    minus the mean, ``sigma = a (ex+ox)^2/2 + b (ex+ox)(ey+oy) + c (ey+oy)^2/2`` is a quadratic in
    ``(ox, oy)``, so the whole (slots, S*S) exponent is one matrix product with a fixed basis.

    Returns:
        coefficients (nb, B, 6), the cut-off threshold on q (nb, B, 1) and values (nb, B, D).
    """
    slots = _GatherRows.apply(attributes, slot_index)
    mx, my, a, b, c, opacity = slots[..., :6].unbind(-1)
    half = 0.5 * tile_size
    ex = (block_x * tile_size + half).to(slots.dtype)[:, None] - mx
    ey = (block_y * tile_size + half).to(slots.dtype)[:, None] - my
    log_opacity = torch.log(opacity.clamp_min(1e-30))
    sigma_centre = 0.5 * a * ex * ex + b * ex * ey + 0.5 * c * ey * ey
    coefs = torch.stack([log_opacity - sigma_centre, -(a * ex + b * ey), -(b * ex + c * ey), -0.5 * a, -b, -0.5 * c], -1)
    # A pixel counts inside the 3-sigma ellipse where opacity * exp(-sigma) >= 1/255:
    # q >= log(opacity) - 4.5 and q >= log(1/255).
    threshold = (log_opacity.detach() - SIGMA_MAX).clamp_min(math.log(ALPHA_MIN))[..., None]
    return coefs, threshold, slots[..., 6:]


def composite_blocks(
    attributes: Tensor, slot_index: Tensor, block_x: Tensor, block_y: Tensor, block_first: Tensor, tile_size: int
) -> Tensor:
    """Front-to-back compositing of depth-sorted pair blocks.

    Args:
        attributes: (G, 6 + D) per-Gaussian rows ``[mean2d (2), conic (3), opacity, values (D)]``;
            the row used by padding slots must have zero opacity.
        slot_index: (nb, B) row of ``attributes`` in each slot.
        block_x, block_y: (nb,) tile coordinates of each block.
        block_first: (nb,) index (within these blocks) of the first block of the same tile.
    Returns:
        (nb, tile_size^2, D + 1): each block's weighted sum of ``values`` per pixel and, last,
        its share of the alpha; summing the blocks of a tile gives the tile's image.
    """
    coefs, threshold, values = _slot_exponents(attributes, slot_index, block_x, block_y, tile_size)
    return _CompositeBlocks.apply(coefs, threshold, values, block_first, tile_size)


def rasterize_torch(
    means: Tensor,
    factors: Tensor,
    opacities: Tensor,
    features: Tensor,
    T_cw: Tensor,
    K: Tensor,
    width: int,
    height: int,
    *,
    near: float = 0.01,
    far: float = 1e10,
    tile_size: int = 4,
    block: int = 32,
    max_chunk_elements: int = 1 << 24,
) -> tuple[Tensor, Tensor, Tensor, dict]:
    """Render per-Gaussian features into an image.

    Args:
        means, factors, opacities: (N, 3) means, (N, 3, 3) covariance factors ``L``
            (``Sigma = L L^T``) and (N,) opacities.
        features: (N, D) values to composite (colours and any extra channels).
        T_cw: (4, 4) world-to-camera pose, OpenCV axes; K: (3, 3) intrinsics.
        tile_size: pixel tile edge; block: pair slots per block.
        max_chunk_elements: slot-pixels per chunk; bounds memory, larger is faster.
    Returns:
        features (H, W, D), alpha (H, W), accumulated camera-z ``sum_i w_i z_i`` (H, W), and
        stats (visible Gaussians, tile pairs, chunks).
    """
    proj = project_gaussians(means, factors, opacities.detach(), T_cw, K, width, height, near, far)
    tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
    blocks = intersect_tiles(
        proj.means2d.detach(),
        proj.conics.detach(),
        opacities[proj.index].detach(),
        proj.extents,
        tile_size,
        tiles_x,
        tiles_y,
        block,
    )

    # One row per visible Gaussian plus a zero-opacity row for empty slots.
    attributes = torch.cat(
        [proj.means2d, proj.conics, opacities[proj.index, None], features[proj.index], proj.depths[:, None]], -1
    )
    attributes = torch.cat([attributes, attributes.new_zeros(1, attributes.shape[1])], 0)

    pixels = tile_size * tile_size
    start = blocks.tile_block_start
    chunks = _chunk_tiles(start, max(1, max_chunk_elements // (pixels * block)))
    image_tiles = attributes.new_zeros(tiles_x * tiles_y, pixels, attributes.shape[1] - 6 + 1)
    for t0, t1 in chunks:
        b0, b1 = int(start[t0]), int(start[t1])
        if b1 == b0:
            continue
        tile = blocks.block_tile[b0:b1]
        out = composite_blocks(
            attributes, blocks.gaussian[b0:b1], tile % tiles_x, tile // tiles_x, blocks.block_first[b0:b1] - b0, tile_size
        )
        image_tiles = image_tiles.index_add(0, tile, out)
    image = (
        image_tiles.reshape(tiles_y, tiles_x, tile_size, tile_size, -1)
        .permute(0, 2, 1, 3, 4)
        .reshape(tiles_y * tile_size, tiles_x * tile_size, -1)[:height, :width]
    )
    stats = {"visible": len(proj.index), "pairs": blocks.pairs, "slots": blocks.gaussian.numel(), "chunks": len(chunks)}
    return image[..., :-2], image[..., -1], image[..., -2], stats


def _chunk_tiles(tile_start: Tensor, max_items: int) -> list[tuple[int, int]]:
    """Split tiles into consecutive ranges holding at most ``max_items`` items (blocks) according
    to the offsets ``tile_start``; a single tile with more items forms its own range."""
    num_tiles = len(tile_start) - 1
    total = int(tile_start[-1])
    if total == 0:
        return [(0, num_tiles)]
    chunks, t0 = [], 0
    while t0 < num_tiles:
        limit = int(tile_start[t0]) + max_items
        t1 = int(torch.searchsorted(tile_start, torch.tensor(limit, device=tile_start.device), right=True)) - 1
        t1 = min(max(t1, t0 + 1), num_tiles)
        chunks.append((t0, t1))
        t0 = t1
    return chunks
