"""Compiled CPU rasteriser (numba): the torch backend's rules, one pixel at a time.

The projection (EWA, culling, depth sort) is the torch backend's own
:func:`~capframe.render.torch_backend.project_gaussians`, so the pose gradient flows through the
same differentiable code. What is compiled is the part whose cost grows with the pixels:

* **tile binning**: each depth-sorted Gaussian is listed in every ``tile_size`` square tile where
  some pixel centre lies inside its cut-off ellipse (exact ellipse-rectangle test), in depth
  order;
* **compositing**: per pixel, front to back over its tile's list, with the torch backend's rules
  (3-sigma ellipse and alpha >= 1/255, alpha clamped at 0.999, stop before the transmittance
  would fall to 1e-4);
* **its backward** to the 2D means, conics, opacities and composited values, recomputing the
  forward's per-pixel state front to back (no per-pixel state is stored).

Tiles are split into one contiguous group per thread, balanced by their pair counts; groups run
in parallel and the backward accumulates each group's gradients in its own buffer, summed in a
fixed order, so results do not depend on scheduling. Arithmetic inside the kernels is float64
whatever the render dtype.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import torch
from numba import njit, prange
from torch import Tensor

from .torch_backend import ALPHA_MAX, ALPHA_MIN, SIGMA_MAX, TRANSMITTANCE_MIN, project_gaussians

LOG_ALPHA_MIN = math.log(ALPHA_MIN)
# Binning margin on the cut-off exponent: a tile is listed when sigma <= reach + this somewhere on
# its pixel-centre rectangle, so rounding never drops a pixel the per-pixel test keeps.
_REACH_MARGIN = 1e-4


@njit(cache=True, inline="always")
def _edge_min(a, b, c, fixed, lo, hi, fixed_is_y):
    """Minimum of ``sigma = a dx^2/2 + b dx dy + c dy^2/2`` along a rectangle edge: one offset
    fixed, the other in ``[lo, hi]``."""
    if fixed_is_y:
        t = min(max(-b * fixed / a, lo), hi)
        return 0.5 * a * t * t + b * t * fixed + 0.5 * c * fixed * fixed
    t = min(max(-b * fixed / c, lo), hi)
    return 0.5 * a * fixed * fixed + b * fixed * t + 0.5 * c * t * t


@njit(cache=True)
def _tile_min_sigma(a, b, c, x0, x1, y0, y1):
    """Minimum of sigma over the offset rectangle ``[x0, x1] x [y0, y1]`` (offsets from the mean):
    zero when it holds the mean, else the least of its four edges (sigma is convex)."""
    if x0 <= 0.0 <= x1 and y0 <= 0.0 <= y1:
        return 0.0
    m = min(_edge_min(a, b, c, y0, x0, x1, True), _edge_min(a, b, c, y1, x0, x1, True))
    return min(m, min(_edge_min(a, b, c, x0, y0, y1, False), _edge_min(a, b, c, x1, y0, y1, False)))


@njit(cache=True)
def _touches(means2d, conics, reach, g, tx, ty, tile_size):
    """Whether some pixel centre of tile ``(tx, ty)`` lies inside Gaussian ``g``'s cut-off
    ellipse ``sigma <= reach`` (with a margin against rounding)."""
    x0 = tx * tile_size + 0.5 - means2d[g, 0]
    y0 = ty * tile_size + 0.5 - means2d[g, 1]
    sigma = _tile_min_sigma(conics[g, 0], conics[g, 1], conics[g, 2], x0, x0 + tile_size - 1, y0, y0 + tile_size - 1)
    return sigma <= reach[g] + _REACH_MARGIN


@njit(cache=True)
def _bin_tiles(means2d, conics, reach, extents, tile_size, tiles_x, tiles_y):
    """Depth-ordered Gaussian lists of every tile.

    Args:
        means2d (G, 2), conics (G, 3), reach (G,) cut-off on sigma, extents (G, 2) pixel
            half-widths of the footprint box; Gaussians nearest first.
    Returns:
        tile_start (tiles + 1,) offsets into tile_gaussian (pairs,).
    """
    num_tiles, num = tiles_x * tiles_y, len(means2d)
    boxes = np.empty((num, 4), np.int64)
    counts = np.zeros(num_tiles + 1, np.int64)
    for g in range(num):
        boxes[g, 0] = max(int(math.floor((means2d[g, 0] - extents[g, 0]) / tile_size)), 0)
        boxes[g, 1] = min(int(math.floor((means2d[g, 0] + extents[g, 0]) / tile_size)), tiles_x - 1)
        boxes[g, 2] = max(int(math.floor((means2d[g, 1] - extents[g, 1]) / tile_size)), 0)
        boxes[g, 3] = min(int(math.floor((means2d[g, 1] + extents[g, 1]) / tile_size)), tiles_y - 1)
        for ty in range(boxes[g, 2], boxes[g, 3] + 1):
            for tx in range(boxes[g, 0], boxes[g, 1] + 1):
                if _touches(means2d, conics, reach, g, tx, ty, tile_size):
                    counts[ty * tiles_x + tx] += 1
    tile_start = np.zeros(num_tiles + 1, np.int64)
    tile_start[1:] = np.cumsum(counts[:num_tiles])
    cursor = tile_start[:num_tiles].copy()
    tile_gaussian = np.empty(tile_start[num_tiles], np.int64)
    # Gaussians in depth order, so each tile's list is too.
    for g in range(num):
        for ty in range(boxes[g, 2], boxes[g, 3] + 1):
            for tx in range(boxes[g, 0], boxes[g, 1] + 1):
                if _touches(means2d, conics, reach, g, tx, ty, tile_size):
                    t = ty * tiles_x + tx
                    tile_gaussian[cursor[t]] = g
                    cursor[t] += 1
    return tile_start, tile_gaussian


@njit(cache=True, inline="always")
def _alpha(means2d, conics, log_opacity, threshold, g, px, py):
    """``(alpha, dx, dy)`` of Gaussian ``g`` at pixel centre ``(px, py)``; alpha is 0 outside the
    cut-offs (``q = log(opacity) - sigma < threshold``), else ``min(0.999, exp(q))``."""
    dx, dy = px - means2d[g, 0], py - means2d[g, 1]
    q = log_opacity[g] - (0.5 * conics[g, 0] * dx * dx + conics[g, 1] * dx * dy + 0.5 * conics[g, 2] * dy * dy)
    if q < threshold[g]:
        return 0.0, dx, dy
    return min(ALPHA_MAX, math.exp(q)), dx, dy


@njit(cache=True, parallel=True)
def _forward(means2d, conics, log_opacity, threshold, values, tile_start, tile_gaussian, group_start, tile_size, tiles_x, out):
    """Composite ``values`` (G, D) into ``out`` (H, W, D) (zeros on entry)."""
    height, width, channels = out.shape
    acc = np.empty((len(group_start) - 1, channels))
    for group in prange(len(group_start) - 1):
        for tile in range(group_start[group], group_start[group + 1]):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            ty, tx = tile // tiles_x, tile % tiles_x
            for y in range(ty * tile_size, min(ty * tile_size + tile_size, height)):
                for x in range(tx * tile_size, min(tx * tile_size + tile_size, width)):
                    acc[group, :] = 0.0
                    T = 1.0
                    for k in range(start, end):
                        g = tile_gaussian[k]
                        alpha, _, _ = _alpha(means2d, conics, log_opacity, threshold, g, x + 0.5, y + 0.5)
                        if alpha == 0.0:
                            continue
                        next_T = T * (1.0 - alpha)
                        if next_T <= TRANSMITTANCE_MIN:
                            break
                        w = alpha * T
                        for ch in range(channels):
                            acc[group, ch] += w * values[g, ch]
                        T = next_T
                    for ch in range(channels):
                        out[y, x, ch] = acc[group, ch]


@njit(cache=True, parallel=True)
def _backward(
    means2d,
    conics,
    log_opacity,
    threshold,
    values,
    tile_start,
    tile_gaussian,
    group_start,
    tile_size,
    tiles_x,
    out,
    grad_out,
    grad_geometry,
    grad_values,
):
    """Gradients of ``sum(grad_out * out)``: per group, (groups, G, 6) to
    ``[mean x, mean y, a, b, c, opacity]`` and (groups, G, D) to the values.

    Per pixel, with ``c_i = v_i . grad``, ``w_i = alpha_i T_i`` and the output's total
    ``C = sum_i w_i c_i``: ``d/d alpha_i = T_i c_i - (C - sum_{k<=i} w_k c_k) / (1 - alpha_i)``,
    and ``d alpha_i / d q_i = alpha_i`` where alpha is not clamped, with ``q = log(opacity) - sigma``.
    """
    height, width, channels = out.shape
    for group in prange(len(group_start) - 1):
        for tile in range(group_start[group], group_start[group + 1]):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            ty, tx = tile // tiles_x, tile % tiles_x
            for y in range(ty * tile_size, min(ty * tile_size + tile_size, height)):
                for x in range(tx * tile_size, min(tx * tile_size + tile_size, width)):
                    total = 0.0
                    for ch in range(channels):
                        total += grad_out[y, x, ch] * out[y, x, ch]
                    T, done = 1.0, 0.0
                    for k in range(start, end):
                        g = tile_gaussian[k]
                        alpha, dx, dy = _alpha(means2d, conics, log_opacity, threshold, g, x + 0.5, y + 0.5)
                        if alpha == 0.0:
                            continue
                        next_T = T * (1.0 - alpha)
                        if next_T <= TRANSMITTANCE_MIN:
                            break
                        w = alpha * T
                        contrib = 0.0
                        for ch in range(channels):
                            contrib += grad_out[y, x, ch] * values[g, ch]
                            grad_values[group, g, ch] += w * grad_out[y, x, ch]
                        done += w * contrib
                        if alpha < ALPHA_MAX:
                            grad_q = alpha * (T * contrib - (total - done) / (1.0 - alpha))
                            a, b, c = conics[g, 0], conics[g, 1], conics[g, 2]
                            # sigma = a dx^2/2 + b dx dy + c dy^2/2 with dx = x - mean x; q = log(o) - sigma.
                            grad_geometry[group, g, 0] += grad_q * (a * dx + b * dy)
                            grad_geometry[group, g, 1] += grad_q * (b * dx + c * dy)
                            grad_geometry[group, g, 2] -= grad_q * 0.5 * dx * dx
                            grad_geometry[group, g, 3] -= grad_q * dx * dy
                            grad_geometry[group, g, 4] -= grad_q * 0.5 * dy * dy
                            grad_geometry[group, g, 5] += grad_q * math.exp(-log_opacity[g])
                        T = next_T


def _balanced_groups(tile_start: np.ndarray, groups: int) -> np.ndarray:
    """(groups + 1,) tile offsets splitting the tiles into contiguous runs of about equal pair
    counts (plus one per tile, for tiles' fixed cost)."""
    work = tile_start + np.arange(len(tile_start))
    cuts = np.searchsorted(work, np.linspace(0, work[-1], groups + 1)[1:-1])
    return np.concatenate([[0], cuts, [len(tile_start) - 1]]).astype(np.int64)


def _threads() -> int:
    """Kernel threads: torch's intra-op count, so one setting governs both."""
    threads = max(1, min(torch.get_num_threads(), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(threads)
    return threads


class _Rasterize(torch.autograd.Function):
    """Tile-binned compositing of depth-sorted Gaussians with its analytic backward."""

    @staticmethod
    def forward(ctx, means2d, conics, opacities, values, extents, width, height, tile_size, stats):
        dtype = values.dtype
        m = means2d.detach().double().contiguous().numpy()
        cn = conics.detach().double().contiguous().numpy()
        o = opacities.detach().double().numpy()
        v = values.detach().double().contiguous().numpy()
        log_opacity = np.log(np.maximum(o, 1e-30))
        # Cut-offs: sigma <= 4.5 (the 3-sigma ellipse) and alpha >= 1/255, as q >= threshold.
        threshold = np.maximum(log_opacity - SIGMA_MAX, LOG_ALPHA_MIN)
        reach = np.minimum(log_opacity - LOG_ALPHA_MIN, SIGMA_MAX)
        tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
        tile_start, tile_gaussian = _bin_tiles(
            m, cn, reach, extents.detach().double().contiguous().numpy(), tile_size, tiles_x, tiles_y
        )
        groups = _balanced_groups(tile_start, _threads())
        out = np.zeros((height, width, v.shape[1]))
        state = (m, cn, log_opacity, threshold, v, tile_start, tile_gaussian, groups, tile_size, tiles_x)
        _forward(*state, out)
        ctx.state, ctx.out = state, out
        stats["pairs"] = len(tile_gaussian)
        return torch.from_numpy(out).to(dtype)

    @staticmethod
    def backward(ctx, grad_out):
        state, out = ctx.state, ctx.out
        groups, num = len(state[7]) - 1, len(state[0])
        grad_geometry = np.zeros((groups, num, 6))
        grad_values = np.zeros((groups, num, out.shape[2]))
        _backward(*state, out, grad_out.detach().double().contiguous().numpy(), grad_geometry, grad_values)
        ctx.state = ctx.out = None
        geometry = torch.from_numpy(grad_geometry.sum(0)).to(grad_out.dtype)
        values = torch.from_numpy(grad_values.sum(0)).to(grad_out.dtype)
        return geometry[:, :2], geometry[:, 2:5], geometry[:, 5], values, None, None, None, None, None


def rasterize_compiled(
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
    tile_size: int = 8,
) -> tuple[Tensor, Tensor, Tensor, dict]:
    """Same contract as :func:`capframe.render.torch_backend.rasterize_torch` (CPU tensors only).

    Args:
        tile_size: binning tile edge in pixels; the image does not depend on it.
    Returns:
        features (H, W, D), alpha (H, W), accumulated camera-z (H, W), stats (visible Gaussians,
        tile pairs at ``tile_size``).
    """
    if means.device.type != "cpu":
        raise ValueError(f"the compiled render backend runs on the CPU; got tensors on {means.device}")
    proj = project_gaussians(means, factors, opacities.detach(), T_cw, K, width, height, near, far)
    # The alpha is composited as a channel of ones, after the depth.
    values = torch.cat([features[proj.index], proj.depths[:, None], torch.ones_like(proj.depths)[:, None]], -1)
    stats = {"visible": len(proj.index)}
    image = _Rasterize.apply(
        proj.means2d, proj.conics, opacities[proj.index], values, proj.extents, width, height, tile_size, stats
    )
    return image[..., :-2], image[..., -1], image[..., -2], stats
