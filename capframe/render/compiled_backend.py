"""Compiled CPU rasteriser (numba): the torch backend's rules, one Gaussian or pixel at a time.

Every stage is a compiled kernel with its analytic backward:

* **projection**: the torch backend's EWA projection and culling
  (:func:`~capframe.render.torch_backend.project_gaussians`), per Gaussian, with its backward to
  the means, the covariance factors and the pose; the depth sort uses the torch backend's key;
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
import os
import threading
import warnings

import numba
import numpy as np
import torch
from numba import njit, prange
from torch import Tensor

from .torch_backend import ALPHA_MAX, ALPHA_MIN, EPS2D, SIGMA_MAX, TRANSMITTANCE_MIN, _GatherRows

# numba's OpenMP layer leaves its threads spinning after each kernel, where they take the cores
# from torch's own threads (a render alternates between the two): 3-6x slower end to end on two
# cores. The workqueue layer's threads sleep. An explicit NUMBA_THREADING_LAYER still wins.
if "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = "workqueue"

# The workqueue layer aborts the process when two threads launch kernels at once: they take turns.
_LAUNCH = threading.Lock()

LOG_ALPHA_MIN = math.log(ALPHA_MIN)
# Binning margin on the cut-off exponent: a tile is listed when sigma <= reach + this somewhere on
# its pixel-centre rectangle, so rounding never drops a pixel the per-pixel test keeps.
_REACH_MARGIN = 1e-4


@njit(cache=True)
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
    candidates = 0
    for g in range(num):
        boxes[g, 0] = max(int(math.floor((means2d[g, 0] - extents[g, 0]) / tile_size)), 0)
        boxes[g, 1] = min(int(math.floor((means2d[g, 0] + extents[g, 0]) / tile_size)), tiles_x - 1)
        boxes[g, 2] = max(int(math.floor((means2d[g, 1] - extents[g, 1]) / tile_size)), 0)
        boxes[g, 3] = min(int(math.floor((means2d[g, 1] + extents[g, 1]) / tile_size)), tiles_y - 1)
        candidates += max(boxes[g, 1] - boxes[g, 0] + 1, 0) * max(boxes[g, 3] - boxes[g, 2] + 1, 0)
    # (tile, Gaussian) pairs in Gaussian order, then a stable counting sort by tile: each tile's
    # list stays in depth order.
    pair_tile = np.empty(candidates, np.int64)
    pair_gaussian = np.empty(candidates, np.int64)
    counts = np.zeros(num_tiles, np.int64)
    pairs = 0
    for g in range(num):
        for ty in range(boxes[g, 2], boxes[g, 3] + 1):
            for tx in range(boxes[g, 0], boxes[g, 1] + 1):
                if _touches(means2d, conics, reach, g, tx, ty, tile_size):
                    t = ty * tiles_x + tx
                    pair_tile[pairs], pair_gaussian[pairs] = t, g
                    counts[t] += 1
                    pairs += 1
    tile_start = np.zeros(num_tiles + 1, np.int64)
    tile_start[1:] = np.cumsum(counts)
    cursor = tile_start[:num_tiles].copy()
    tile_gaussian = np.empty(pairs, np.int64)
    for k in range(pairs):
        t = pair_tile[k]
        tile_gaussian[cursor[t]] = pair_gaussian[k]
        cursor[t] += 1
    return tile_start, tile_gaussian


# Columns of a tile's gathered Gaussians: mean x, mean y, a/2, b, c/2, log(opacity), threshold, values.
_COLUMNS = 7


@njit(cache=True)
def _gather(local, means2d, conics, log_opacity, threshold, values, tile_gaussian, start, end):
    """Copy the Gaussians of one tile's list into consecutive rows of ``local`` (n, 7 + D): the
    pixel loops then read memory in order."""
    for k in range(end - start):
        g = tile_gaussian[start + k]
        local[k, 0], local[k, 1] = means2d[g, 0], means2d[g, 1]
        local[k, 2], local[k, 3], local[k, 4] = 0.5 * conics[g, 0], conics[g, 1], 0.5 * conics[g, 2]
        local[k, 5], local[k, 6] = log_opacity[g], threshold[g]
        for ch in range(values.shape[1]):
            local[k, _COLUMNS + ch] = values[g, ch]


@njit(cache=True)
def _tile_pixels(tile, tiles_x, tile_size, width, height, px, py):
    """Pixel centres of one tile (clipped to the image) into ``px, py``, row-major; their count."""
    ty, tx = tile // tiles_x, tile % tiles_x
    count = 0
    for y in range(ty * tile_size, min(ty * tile_size + tile_size, height)):
        for x in range(tx * tile_size, min(tx * tile_size + tile_size, width)):
            px[count], py[count] = x + 0.5, y + 0.5
            count += 1
    return count


@njit(cache=True)
def _exponents(local, k, px, py, count, q):
    """``q = log(opacity) - sigma`` of listed Gaussian ``k`` at the tile's ``count`` pixels: one
    branch-free loop (vectorised), since most pixels of a tile fail the cut-offs."""
    mx, my, half_a, b, half_c, log_opacity = local[k, 0], local[k, 1], local[k, 2], local[k, 3], local[k, 4], local[k, 5]
    for p in range(count):
        dx, dy = px[p] - mx, py[p] - my
        q[p] = log_opacity - (half_a * dx * dx + b * dx * dy + half_c * dy * dy)


@njit(cache=True, parallel=True)
def _forward(means2d, conics, log_opacity, threshold, values, tile_start, tile_gaussian, group_start, tile_size, tiles_x, out):
    """Composite ``values`` (G, D) into ``out`` (H, W, D) (zeros on entry); returns the number of
    composited (Gaussian, pixel) pairs.

    At each pixel, Gaussian ``k`` counts where ``q = log(opacity) - sigma >= threshold`` (the
    cut-offs), with ``alpha = min(0.999, exp(q))``; compositing stops before ``T`` would fall
    to 1e-4. A tile's pixels advance together through its list, each with its own state."""
    height, width, channels = out.shape
    longest = np.max(tile_start[1:] - tile_start[:-1]) if len(tile_start) > 1 else 0
    composited = np.zeros(len(group_start) - 1, np.int64)
    pixels = tile_size * tile_size
    for group in prange(len(group_start) - 1):
        local = np.empty((longest, _COLUMNS + channels))
        acc = np.empty((pixels, channels))
        px, py, q, T = np.empty(pixels), np.empty(pixels), np.empty(pixels), np.empty(pixels)
        alive = np.empty(pixels, np.bool_)
        for tile in range(group_start[group], group_start[group + 1]):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            _gather(local, means2d, conics, log_opacity, threshold, values, tile_gaussian, start, end)
            count = _tile_pixels(tile, tiles_x, tile_size, width, height, px, py)
            acc[:count] = 0.0
            T[:count] = 1.0
            alive[:count] = True
            remaining = count
            for k in range(end - start):
                _exponents(local, k, px, py, count, q)
                threshold_k = local[k, 6]
                for p in range(count):
                    if q[p] < threshold_k or not alive[p]:
                        continue
                    alpha = min(ALPHA_MAX, math.exp(q[p]))
                    next_T = T[p] * (1.0 - alpha)
                    if next_T <= TRANSMITTANCE_MIN:
                        alive[p] = False
                        remaining -= 1
                        continue
                    w = alpha * T[p]
                    for ch in range(channels):
                        acc[p, ch] += w * local[k, _COLUMNS + ch]
                    T[p] = next_T
                    composited[group] += 1
                if remaining == 0:
                    break
            for p in range(count):
                y, x = int(py[p]), int(px[p])
                for ch in range(channels):
                    out[y, x, ch] = acc[p, ch]
    return composited.sum()


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
    The forward's per-pixel state is recomputed in the same order; each tile sums its pixels'
    gradients per listed Gaussian first, then adds them to the group's.
    """
    height, width, channels = out.shape
    longest = np.max(tile_start[1:] - tile_start[:-1]) if len(tile_start) > 1 else 0
    pixels = tile_size * tile_size
    for group in prange(len(group_start) - 1):
        local = np.empty((longest, _COLUMNS + channels))
        grads = np.empty((longest, 6 + channels))  # per listed Gaussian: mean x, y, a, b, c, log(opacity), values
        pixel_grad = np.empty((pixels, channels))
        px, py, q, T = np.empty(pixels), np.empty(pixels), np.empty(pixels), np.empty(pixels)
        total, done = np.empty(pixels), np.empty(pixels)
        alive = np.empty(pixels, np.bool_)
        for tile in range(group_start[group], group_start[group + 1]):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            n = end - start
            _gather(local, means2d, conics, log_opacity, threshold, values, tile_gaussian, start, end)
            grads[:n] = 0.0
            count = _tile_pixels(tile, tiles_x, tile_size, width, height, px, py)
            for p in range(count):
                y, x = int(py[p]), int(px[p])
                total[p] = 0.0
                for ch in range(channels):
                    pixel_grad[p, ch] = grad_out[y, x, ch]
                    total[p] += pixel_grad[p, ch] * out[y, x, ch]
            T[:count] = 1.0
            done[:count] = 0.0
            alive[:count] = True
            remaining = count
            for k in range(n):
                _exponents(local, k, px, py, count, q)
                threshold_k = local[k, 6]
                for p in range(count):
                    if q[p] < threshold_k or not alive[p]:
                        continue
                    alpha = min(ALPHA_MAX, math.exp(q[p]))
                    next_T = T[p] * (1.0 - alpha)
                    if next_T <= TRANSMITTANCE_MIN:
                        alive[p] = False
                        remaining -= 1
                        continue
                    w = alpha * T[p]
                    contrib = 0.0
                    for ch in range(channels):
                        contrib += pixel_grad[p, ch] * local[k, _COLUMNS + ch]
                        grads[k, 6 + ch] += w * pixel_grad[p, ch]
                    done[p] += w * contrib
                    if alpha < ALPHA_MAX:
                        grad_q = alpha * (T[p] * contrib - (total[p] - done[p]) / (1.0 - alpha))
                        # sigma = a dx^2/2 + b dx dy + c dy^2/2 with dx = x - mean x; q = log(o) - sigma.
                        dx, dy = px[p] - local[k, 0], py[p] - local[k, 1]
                        half_a, b, half_c = local[k, 2], local[k, 3], local[k, 4]
                        grads[k, 0] += grad_q * (2.0 * half_a * dx + b * dy)
                        grads[k, 1] += grad_q * (b * dx + 2.0 * half_c * dy)
                        grads[k, 2] -= grad_q * 0.5 * dx * dx
                        grads[k, 3] -= grad_q * dx * dy
                        grads[k, 4] -= grad_q * 0.5 * dy * dy
                        grads[k, 5] += grad_q
                    T[p] = next_T
                if remaining == 0:
                    break
            for k in range(n):
                g = tile_gaussian[start + k]
                for j in range(5):
                    grad_geometry[group, g, j] += grads[k, j]
                grad_geometry[group, g, 5] += grads[k, 5] * math.exp(-log_opacity[g])  # d log(o) / d o
                for ch in range(channels):
                    grad_values[group, g, ch] += grads[k, 6 + ch]


@njit(cache=True)
def _jacobian_rows(R, K, x, y, z, width, height):
    """Rows ``j0, j1`` (3-tuples) of ``J R`` at the camera point ``(x, y, z)`` with the clamped
    slopes ``tx, ty`` and whether each was left unclamped (see
    :func:`~capframe.render.torch_backend.ewa_project`)."""
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    margin_x, margin_y = 0.3 * 0.5 * width / fx, 0.3 * 0.5 * height / fy
    sx, sy = x / z, y / z
    lo_x, hi_x = -(cx / fx + margin_x), (width - cx) / fx + margin_x
    lo_y, hi_y = -(cy / fy + margin_y), (height - cy) / fy + margin_y
    tx, ty = min(max(sx, lo_x), hi_x), min(max(sy, lo_y), hi_y)
    ax, ay = fx / z, fy / z
    j0 = (ax * (R[0, 0] - tx * R[2, 0]), ax * (R[0, 1] - tx * R[2, 1]), ax * (R[0, 2] - tx * R[2, 2]))
    j1 = (ay * (R[1, 0] - ty * R[2, 0]), ay * (R[1, 1] - ty * R[2, 1]), ay * (R[1, 2] - ty * R[2, 2]))
    return j0, j1, tx, ty, lo_x <= sx <= hi_x, lo_y <= sy <= hi_y


@njit(cache=True)
def _row_times(j, L):
    """Row vector ``j`` (3-tuple) times the 3x3 matrix ``L``, as a 3-tuple."""
    return (
        j[0] * L[0, 0] + j[1] * L[1, 0] + j[2] * L[2, 0],
        j[0] * L[0, 1] + j[1] * L[1, 1] + j[2] * L[2, 1],
        j[0] * L[0, 2] + j[1] * L[1, 2] + j[2] * L[2, 2],
    )


@njit(cache=True)
def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


@njit(cache=True)
def _camera_point(R, t, m):
    return (
        R[0, 0] * m[0] + R[0, 1] * m[1] + R[0, 2] * m[2] + t[0],
        R[1, 0] * m[0] + R[1, 1] * m[1] + R[1, 2] * m[2] + t[1],
        R[2, 0] * m[0] + R[2, 1] * m[1] + R[2, 2] * m[2] + t[2],
    )


@njit(cache=True, parallel=True)
def _project(means, factors, opacities, R, t, K, width, height, near, far, eps2d, limit, out, flags):
    """Per Gaussian: ``out`` (N, 8) = ``[u, v, a, b, c, z, extent x, extent y]``; ``flags`` (N,):
    1 kept, 2 non-finite covariance, 0 otherwise (behind, beyond or off-screen, degenerate).
    ``limit`` is the render dtype's largest value: what would overflow it counts as non-finite,
    as in the torch backend."""
    for n in prange(len(means)):
        flags[n] = 0
        L = factors[n]
        if not np.isfinite(L).all():
            flags[n] = 2
            continue
        x, y, z = _camera_point(R, t, means[n])
        if not (near < z < far):
            continue
        j0, j1, _, _, _, _ = _jacobian_rows(R, K, x, y, z, width, height)
        m0, m1 = _row_times(j0, L), _row_times(j1, L)
        u, v = K[0, 0] * x / z + K[0, 2], K[1, 1] * y / z + K[1, 2]
        c00, c01, c11 = _dot(m0, m0) + eps2d, _dot(m0, m1), _dot(m1, m1) + eps2d
        if not (abs(c00) <= limit and abs(c01) <= limit and abs(c11) <= limit and abs(u) <= limit and abs(v) <= limit):
            flags[n] = 2
            continue
        det = c00 * c11 - c01 * c01
        level = 2.0 * math.log(max(opacities[n], ALPHA_MIN) / ALPHA_MIN)
        k = math.sqrt(min(max(level, 0.0), 2.0 * SIGMA_MAX))
        ex, ey = k * math.sqrt(c00), k * math.sqrt(c11)
        if det > 0 and ex > 0 and ey > 0 and u + ex > 0 and v + ey > 0 and u - ex < width and v - ey < height:
            flags[n] = 1
            out[n, 0], out[n, 1] = u, v
            out[n, 2], out[n, 3], out[n, 4] = c11 / det, -c01 / det, c00 / det
            out[n, 5], out[n, 6], out[n, 7] = z, ex, ey


@njit(cache=True, parallel=True)
def _project_backward(means, factors, R, t, K, width, height, eps2d, index, grad, chunks, grad_means, grad_factors, grad_pose):
    """Backward of :func:`_project` for the kept Gaussians ``index`` (G,), given ``grad`` (G, 6)
    to ``[u, v, a, b, c, z]``: (G, 3) to the means, (G, 3, 3) to the factors (skipped when
    ``grad_factors`` is empty), and per chunk of
    ``index`` (chunks, 12) to ``[R (row-major), t]``."""
    fx, fy = K[0, 0], K[1, 1]
    for chunk in prange(len(chunks) - 1):
        gj = np.empty((2, 3))  # gradient to the rows of J R
        for i in range(chunks[chunk], chunks[chunk + 1]):
            n = index[i]
            m, L = means[n], factors[n]
            x, y, z = _camera_point(R, t, m)
            j0, j1, tx, ty, free_x, free_y = _jacobian_rows(R, K, x, y, z, width, height)
            m0, m1 = _row_times(j0, L), _row_times(j1, L)
            c00, c01, c11 = _dot(m0, m0) + eps2d, _dot(m0, m1), _dot(m1, m1) + eps2d
            det = c00 * c11 - c01 * c01
            q00, q01, q11 = c11 / det, -c01 / det, c00 / det
            # Conic = cov^-1, so d cov = -Q G Q with G the conic gradient as a symmetric matrix.
            g00, g01, g11 = grad[i, 2], 0.5 * grad[i, 3], grad[i, 4]
            h00, h01 = g00 * q00 + g01 * q01, g00 * q01 + g01 * q11  # H = G Q
            h10, h11 = g01 * q00 + g11 * q01, g01 * q01 + g11 * q11
            s00 = -(q00 * h00 + q01 * h10)
            s01 = -(q00 * h01 + q01 * h11)
            s11 = -(q01 * h01 + q11 * h11)
            # cov = M M^T + eps I with M = (J R) L: dM = 2 S M, dL = (J R)^T dM, d(J R) = dM L^T.
            gj[:] = 0.0
            for col in range(3):
                gm0 = 2.0 * (s00 * m0[col] + s01 * m1[col])
                gm1 = 2.0 * (s01 * m0[col] + s11 * m1[col])
                for row in range(3):
                    if len(grad_factors):
                        grad_factors[i, row, col] = j0[row] * gm0 + j1[row] * gm1
                    gj[0, row] += L[row, col] * gm0
                    gj[1, row] += L[row, col] * gm1
            # Rows j0 = (fx/z)(R0 - tx R2), j1 = (fy/z)(R1 - ty R2).
            ax, ay = fx / z, fy / z
            g_tx, g_ty = 0.0, 0.0
            gj0, gj1 = gj[0], gj[1]
            g_z = grad[i, 5] - (_dot(j0, gj0) + _dot(j1, gj1)) / z
            for col in range(3):
                grad_pose[chunk, col] += ax * gj0[col]
                grad_pose[chunk, 3 + col] += ay * gj1[col]
                grad_pose[chunk, 6 + col] -= ax * tx * gj0[col] + ay * ty * gj1[col]
                g_tx -= ax * R[2, col] * gj0[col]
                g_ty -= ay * R[2, col] * gj1[col]
            # u = fx x/z + cx, v = fy y/z + cy; tx = x/z and ty = y/z where not clamped.
            g_u, g_v = grad[i, 0] * ax + (g_tx / z if free_x else 0.0), grad[i, 1] * ay + (g_ty / z if free_y else 0.0)
            g_x, g_y = g_u, g_v
            g_z -= (g_u * x + g_v * y) / z
            # p = R m + t.
            g_p = (g_x, g_y, g_z)
            for row in range(3):
                grad_means[i, row] = R[0, row] * g_x + R[1, row] * g_y + R[2, row] * g_z
                for col in range(3):
                    grad_pose[chunk, 3 * row + col] += g_p[row] * m[col]
                grad_pose[chunk, 9 + row] += g_p[row]


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


def _numpy(x: Tensor) -> np.ndarray:
    """The values of ``x``, in its dtype: the kernels compute in float64 whatever they read."""
    return x.detach().contiguous().numpy()


def _float64(x: Tensor) -> np.ndarray:
    return x.detach().to(torch.float64).contiguous().numpy()


class _Project(torch.autograd.Function):
    """Compiled :func:`~capframe.render.torch_backend.project_gaussians`: differentiable to the
    means, the factors and the pose; returns the kept Gaussians' ``index``, means2d, conics and
    depths (nearest first) and their extents (no gradient)."""

    @staticmethod
    def forward(ctx, means, factors, opacities, T_cw, K, width, height, near, far, sort_key):
        m, L, R, t, k = _numpy(means), _numpy(factors), _float64(T_cw[:3, :3]), _float64(T_cw[:3, 3]), _float64(K)
        out = np.empty((len(m), 8))
        flags = np.empty(len(m), np.int8)
        limit = float(torch.finfo(means.dtype).max)
        with _LAUNCH:
            _project(m, L, _float64(opacities), R, t, k, width, height, near, far, EPS2D, limit, out, flags)
        skipped = int((flags == 2).sum())
        if skipped:
            warnings.warn(f"{skipped} Gaussians with non-finite covariance (huge or NaN scales) were skipped", stacklevel=4)
        kept = np.flatnonzero(flags == 1)
        # The sort key is the torch backend's own (render dtype), so both order ties alike.
        index = kept[np.argsort(sort_key[kept], kind="stable")]
        ctx.arrays = (m, L, R, t, k, width, height, index)
        ctx.num = len(m)
        kept_out = out[index]
        means2d, conics, depths, extents = (
            torch.from_numpy(np.ascontiguousarray(kept_out[:, cols])).to(means.dtype)
            for cols in (slice(0, 2), slice(2, 5), 5, slice(6, 8))
        )
        index = torch.from_numpy(index)
        ctx.mark_non_differentiable(index, extents)
        return index, means2d, conics, depths, extents

    @staticmethod
    def backward(ctx, _, grad_means2d, grad_conics, grad_depths, __):
        m, L, R, t, k, width, height, index = ctx.arrays
        ctx.arrays = None
        grad = np.concatenate([_float64(grad_means2d), _float64(grad_conics), _float64(grad_depths)[:, None]], 1)
        chunks = np.linspace(0, len(index), _threads() + 1).astype(np.int64)
        grad_means = np.zeros((len(index), 3))
        with_factors = ctx.needs_input_grad[1]
        grad_factors = np.zeros((len(index) if with_factors else 0, 3, 3))
        grad_pose = np.zeros((len(chunks) - 1, 12))
        with _LAUNCH:
            _project_backward(m, L, R, t, k, width, height, EPS2D, index, grad, chunks, grad_means, grad_factors, grad_pose)
        dtype, rows = grad_means2d.dtype, torch.from_numpy(index)
        means = torch.zeros(ctx.num, 3, dtype=dtype).index_add_(0, rows, torch.from_numpy(grad_means).to(dtype))
        factors = None
        if with_factors:
            factors = torch.zeros(ctx.num, 3, 3, dtype=dtype).index_add_(0, rows, torch.from_numpy(grad_factors).to(dtype))
        pose = torch.zeros(4, 4, dtype=dtype)
        total = torch.from_numpy(grad_pose.sum(0)).to(dtype)
        pose[:3, :3], pose[:3, 3] = total[:9].view(3, 3), total[9:]
        return means, factors, None, pose, None, None, None, None, None, None


class _Rasterize(torch.autograd.Function):
    """Tile-binned compositing of depth-sorted Gaussians with its analytic backward."""

    @staticmethod
    def forward(ctx, means2d, conics, opacities, values, extents, width, height, tile_size, stats):
        dtype = values.dtype
        m, cn, v, o = _numpy(means2d), _numpy(conics), _numpy(values), _float64(opacities)
        log_opacity = np.log(np.maximum(o, 1e-30))
        # Cut-offs: sigma <= 4.5 (the 3-sigma ellipse) and alpha >= 1/255, as q >= threshold.
        threshold = np.maximum(log_opacity - SIGMA_MAX, LOG_ALPHA_MIN)
        reach = np.minimum(log_opacity - LOG_ALPHA_MIN, SIGMA_MAX)
        tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
        tile_start, tile_gaussian = _bin_tiles(m, cn, reach, _numpy(extents), tile_size, tiles_x, tiles_y)
        groups = _balanced_groups(tile_start, _threads())
        out = np.zeros((height, width, v.shape[1]))
        state = (m, cn, log_opacity, threshold, v, tile_start, tile_gaussian, groups, tile_size, tiles_x)
        with _LAUNCH:
            stats["composited"] = int(_forward(*state, out))
        ctx.state, ctx.out = state, out
        stats["pairs"] = len(tile_gaussian)
        return torch.from_numpy(out).to(dtype)

    @staticmethod
    def backward(ctx, grad_out):
        state, out = ctx.state, ctx.out
        groups, num = len(state[7]) - 1, len(state[0])
        grad_geometry = np.zeros((groups, num, 6))
        grad_values = np.zeros((groups, num, out.shape[2]))
        with _LAUNCH:
            _backward(*state, out, _numpy(grad_out), grad_geometry, grad_values)
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
    tile_size: int = 4,
) -> tuple[Tensor, Tensor, Tensor, dict]:
    """Same contract as :func:`capframe.render.torch_backend.rasterize_torch` (CPU tensors only).

    Args:
        tile_size: binning tile edge in pixels; the image does not depend on it.
    Returns:
        features (H, W, D), alpha (H, W), accumulated camera-z (H, W), stats (visible Gaussians,
        tile pairs at ``tile_size``, composited (Gaussian, pixel) pairs).
    """
    if means.device.type != "cpu":
        raise ValueError(f"the compiled render backend runs on the CPU; got tensors on {means.device}")
    with torch.no_grad():
        sort_key = (means @ T_cw[2, :3] + T_cw[2, 3]).double().numpy()  # as project_gaussians sorts
    index, means2d, conics, depths, extents = _Project.apply(
        means, factors, opacities.detach(), T_cw, K, width, height, near, far, sort_key
    )
    # The alpha is composited as a channel of ones, after the depth.
    values = torch.cat([_GatherRows.apply(features, index), depths[:, None], torch.ones_like(depths)[:, None]], -1)
    stats = {"visible": len(index)}
    image = _Rasterize.apply(
        means2d, conics, _GatherRows.apply(opacities, index), values, extents, width, height, tile_size, stats
    )
    return image[..., :-2], image[..., -1], image[..., -2], stats
