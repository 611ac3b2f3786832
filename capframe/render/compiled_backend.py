"""Compiled CPU rasteriser (numba): the torch backend's rules, one Gaussian or pixel at a time.

One autograd function, :class:`_Render`, runs every stage as a compiled kernel, from the
Gaussians' parameters to the image and back:

* **projection**: the torch backend's EWA projection and culling
  (:func:`~capframe.render.torch_backend.project_gaussians`), per Gaussian, in float64; each
  kept Gaussian gets one row of the compositing table (2D mean, half conic, log-opacity,
  cut-off threshold, composited values), in index order, and its box of candidate tiles;
* **tile binning**: in the torch backend's depth order (its own sort key; a stable radix sort),
  each Gaussian is listed in every ``tile_size`` square tile where some pixel centre lies
  inside its cut-off ellipse (its exact x-range over each tile row), then a stable counting
  sort by tile keeps each tile's list in depth order;
* **compositing**: per pixel, front to back over its tile's list, with the torch backend's rules
  (3-sigma ellipse and alpha >= 1/255, alpha clamped at 0.999, stop before the transmittance
  would fall to 1e-4). Each (tile, Gaussian) pair records which of the tile's pixels it was
  composited into (a bit mask), so
* **its backward** to the 2D means, conics, opacities and composited values visits only the
  composited (Gaussian, pixel) pairs, front to back, recomputing their alphas; pairs that
  composited nothing (past a tile's stop, or outside the cut-offs: about 40%) are skipped on
  their mask alone;
* **the projection's backward** to the means, covariance factors and pose, scattered straight
  into the inputs' rows.

Tiles are split into one group per thread, group ``k`` of ``n`` taking the tile rows ``k, k + n,
...``: neighbouring rows cost alike, so the groups stay balanced however early compositing stops
(a split by pair counts cannot know that). Groups run in parallel and the backward accumulates
each group's gradients in its own buffer, zeroed by its own thread and summed in a fixed order,
so results do not depend on scheduling (images do not depend on the thread count either;
gradients only up to rounding, through the number of groups). Compositing computes in
the render dtype (float32 vectorises twice as wide; float64 renders stay float64 throughout);
the projection and the pose gradient's sums are float64 whatever the render dtype.
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

from .torch_backend import ALPHA_MAX, ALPHA_MIN, EPS2D, SIGMA_MAX, TRANSMITTANCE_MIN

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
# Columns of the compositing table before the composited values: mean x, mean y, a/2, b, c/2,
# log(opacity), threshold (a pixel counts where log(opacity) - sigma >= threshold). The values
# that follow are the features, the camera z and 1 (whose composite is the alpha).
_COLUMNS = 7
# Bits per word of a pair's pixel mask: a 4x4 tile is one word, one vector of float32 lanes.
_MASK_BITS = 16
# Index of the lowest set bit of a 32-bit word by a de Bruijn multiply (numba has no public
# count-trailing-zeros): the isolated bit times this constant puts a unique 5-bit pattern on top.
_DE_BRUIJN = 0x077CB531
_DE_BRUIJN_BIT = np.array(
    [0, 1, 28, 2, 29, 14, 24, 3, 30, 22, 20, 15, 25, 17, 4, 8, 31, 27, 13, 23, 21, 19, 16, 7, 26, 12, 18, 6, 11, 5, 10, 9],
    dtype=np.int64,
)


@njit(cache=True, inline="always")
def _footprint(table, g):
    """Row ``g`` of the compositing table: mean x, mean y, a/2, b, c/2, log(opacity)."""
    return table[g, 0], table[g, 1], table[g, 2], table[g, 3], table[g, 4], table[g, 5]


@njit(cache=True, inline="always")
def _lowest_bit(bits):
    """Index of the lowest set bit of ``bits`` (nonzero, below ``2**32``; masks use 16)."""
    return _DE_BRUIJN_BIT[(((bits & -bits) * _DE_BRUIJN) & 0xFFFFFFFF) >> 27]


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


@njit(cache=True)
def _all_finite(L):
    for i in range(3):
        for j in range(3):
            if not math.isfinite(L[i, j]):
                return False
    return True


@njit(cache=True, parallel=True)
def _project(means, factors, opacities, R, t, K, width, height, near, far, eps2d, limit, out, flags):
    """Per Gaussian: ``out`` (N, 8) = ``[u, v, a, b, c, z, extent x, extent y]`` (float64);
    ``flags`` (N,): 1 kept, 2 non-finite covariance, 0 otherwise (behind, beyond or off-screen,
    degenerate). ``limit`` is the render dtype's largest value: what would overflow it counts as
    non-finite, as in the torch backend."""
    for n in prange(len(means)):
        flags[n] = 0
        L = factors[n]
        if not _all_finite(L):
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
        level = 2.0 * math.log(max(float(opacities[n]), ALPHA_MIN) / ALPHA_MIN)
        k = math.sqrt(min(max(level, 0.0), 2.0 * SIGMA_MAX))
        ex, ey = k * math.sqrt(c00), k * math.sqrt(c11)
        if det > 0 and ex > 0 and ey > 0 and u + ex > 0 and v + ey > 0 and u - ex < width and v - ey < height:
            flags[n] = 1
            out[n, 0], out[n, 1] = u, v
            out[n, 2], out[n, 3], out[n, 4] = c11 / det, -c01 / det, c00 / det
            out[n, 5], out[n, 6], out[n, 7] = z, ex, ey


def _sortable(key: np.ndarray) -> np.ndarray:
    """Unsigned integers (N,) ordered as the floats ``key`` (N,) (float32 or float64)."""
    bits = key.view(np.uint32 if key.itemsize == 4 else np.uint64)
    top = bits.dtype.type(1) << bits.dtype.type(8 * key.itemsize - 1)
    return np.where(bits & top, ~bits, bits | top)


@njit(cache=True)
def _depth_order(flags, keys):
    """The kept Gaussians (``flags == 1``): their indices ``kept`` (G,) in index order and
    ``order`` (G,), positions in ``kept`` sorted by ``keys`` (N,) (unsigned integers), ties in
    index order (a stable least-significant-byte-first radix sort)."""
    num = 0
    for n in range(len(flags)):
        num += flags[n] == 1
    kept, key = np.empty(num, np.int64), np.empty(num, keys.dtype)
    j = 0
    for n in range(len(flags)):
        if flags[n] == 1:
            kept[j], key[j] = n, keys[n]
            j += 1
    order, order_out, key_out = np.arange(num), np.empty(num, np.int64), np.empty_like(key)
    counts = np.empty(256, np.int64)
    byte_mask = keys.dtype.type(255)
    for byte in range(keys.itemsize):
        shift = keys.dtype.type(8 * byte)
        counts[:] = 0
        for j in range(num):
            counts[(key[j] >> shift) & byte_mask] += 1
        if counts.max() == num:  # all keys share this byte
            continue
        total = 0
        for b in range(256):
            counts[b], total = total, total + counts[b]
        for j in range(num):
            d = (key[j] >> shift) & byte_mask
            order_out[counts[d]], key_out[counts[d]] = order[j], key[j]
            counts[d] += 1
        order, order_out = order_out, order
        key, key_out = key_out, key
    return kept, order


@njit(cache=True, parallel=True)
def _visible_table(kept, geometry, opacities, features, tile_size, tiles_x, tiles_y, table, reach, boxes):
    """The compositing table's rows (G, 7 + D + 2) of the Gaussians ``kept`` (G,), in that
    (index) order, their cut-off ``reach`` on sigma (G,) and ``boxes`` (G, 5): the first and
    last tile column and row their footprint box spans and the number of tiles in it."""
    ft = table.dtype.type
    channels = features.shape[1]
    for i in prange(len(kept)):
        n = kept[i]
        table[i, 0], table[i, 1] = geometry[n, 0], geometry[n, 1]
        table[i, 2], table[i, 3], table[i, 4] = ft(0.5) * ft(geometry[n, 2]), geometry[n, 3], ft(0.5) * ft(geometry[n, 4])
        log_opacity = math.log(max(opacities[n], ft(1e-30)))
        # Cut-offs: sigma <= 4.5 (the 3-sigma ellipse) and alpha >= 1/255, as q >= threshold.
        table[i, 5], table[i, 6] = log_opacity, max(log_opacity - ft(SIGMA_MAX), ft(LOG_ALPHA_MIN))
        for ch in range(channels):
            table[i, _COLUMNS + ch] = features[n, ch]
        table[i, _COLUMNS + channels], table[i, _COLUMNS + channels + 1] = geometry[n, 5], 1.0
        reach[i] = min(float(log_opacity) - LOG_ALPHA_MIN, SIGMA_MAX) + _REACH_MARGIN
        u, v, ex, ey = float(table[i, 0]), float(table[i, 1]), geometry[n, 6], geometry[n, 7]
        boxes[i, 0] = max(int(math.floor((u - ex) / tile_size)), 0)
        boxes[i, 1] = min(int(math.floor((u + ex) / tile_size)), tiles_x - 1)
        boxes[i, 2] = max(int(math.floor((v - ey) / tile_size)), 0)
        boxes[i, 3] = min(int(math.floor((v + ey) / tile_size)), tiles_y - 1)
        boxes[i, 4] = max(boxes[i, 1] - boxes[i, 0] + 1, 0) * max(boxes[i, 3] - boxes[i, 2] + 1, 0)


@njit(cache=True, parallel=True)
def _list_tiles(table, reach, boxes, order, first, tile_size, tiles_x, pair_tile, listed):
    """Per Gaussian, the ``r``-th in depth ``order`` (G,) (table rows), the tiles where some
    pixel centre lies inside its cut-off ellipse ``sigma <= reach`` (reach holds a margin against
    rounding) into ``pair_tile`` from ``first[r]`` on (room for its whole box), their number into
    ``listed[r]``: the pairs come out in depth order, which the sort by tile keeps.

    Scanlines, as :func:`~capframe.render.torch_backend.intersect_tiles`: per tile row, the
    ellipse's exact x-range over the row's band of pixel centres gives the tiles, no test per
    tile. With ``D = ac - b^2`` the right edge at height ``dy`` is
    ``x = -b dy / a + sqrt(2 a reach - D dy^2) / a``, concave in ``dy``, so its maximum over the
    band is at the ellipse's rightmost point clamped to the band (the left edge likewise)."""
    for r in prange(len(order)):
        i = order[r]
        mx, my = float(table[i, 0]), float(table[i, 1])
        a, b, c = 2.0 * float(table[i, 2]), float(table[i, 3]), 2.0 * float(table[i, 4])
        det, two_k = a * c - b * b, 2.0 * reach[i]
        inv_a = 1.0 / a
        y_reach = math.sqrt(two_k * a / det)  # |dy| on the ellipse
        dy_right = -b * math.sqrt(two_k / (c * det))  # the rightmost point's; the leftmost is its mirror
        count = first[r]
        for ty in range(boxes[i, 2], boxes[i, 3] + 1):
            band = ty * tile_size + 0.5 - my
            lo, hi = max(band, -y_reach), min(band + tile_size - 1, y_reach)
            if lo > hi:
                continue
            dr, dl = min(max(dy_right, lo), hi), min(max(-dy_right, lo), hi)
            right = mx + (-b * dr + math.sqrt(max(two_k * a - det * dr * dr, 0.0))) * inv_a
            left = mx + (-b * dl - math.sqrt(max(two_k * a - det * dl * dl, 0.0))) * inv_a
            # Tile tx holds pixel centres [tx S + 0.5, tx S + S - 0.5].
            tx0 = max(int(math.ceil((left + 0.5 - tile_size) / tile_size)), boxes[i, 0])
            tx1 = min(int(math.floor((right - 0.5) / tile_size)), boxes[i, 1])
            for tx in range(tx0, tx1 + 1):
                pair_tile[count] = ty * tiles_x + tx
                count += 1
        listed[r] = count - first[r]


@njit(cache=True)
def _sort_by_tile(pair_tile, first, listed, order, num_tiles):
    """Stable counting sort by tile of the listed (tile, Gaussian) pairs, in depth ``order``
    (G,) (:func:`_list_tiles`): each tile's list stays in depth order. Returns tile_start
    (tiles + 1,) offsets into tile_gaussian (pairs,), the table rows."""
    tile_start = np.zeros(num_tiles + 1, np.int64)
    for i in range(len(listed)):
        for k in range(first[i], first[i] + listed[i]):
            tile_start[pair_tile[k] + 1] += 1
    for t in range(num_tiles):
        tile_start[t + 1] += tile_start[t]
    cursor = tile_start[:num_tiles].copy()
    tile_gaussian = np.empty(tile_start[num_tiles], np.int32)
    for r in range(len(listed)):
        for k in range(first[r], first[r] + listed[r]):
            t = pair_tile[k]
            tile_gaussian[cursor[t]] = order[r]
            cursor[t] += 1
    return tile_start, tile_gaussian


@njit(cache=True, inline="always")
def _group_tiles(group, groups, tiles_x, tiles_y):
    """Tiles of group ``group`` of ``groups``: the tile rows ``group, group + groups, ...``."""
    return [ty * tiles_x + tx for ty in range(group, tiles_y, groups) for tx in range(tiles_x)]


@njit(cache=True)
def _tile_pixels(tx, ty, tile_size, width, height, px, py):
    """Pixel centres of tile ``(tx, ty)`` (clipped to the image) into ``px, py``, row-major;
    their count."""
    count = 0
    for y in range(ty * tile_size, min(ty * tile_size + tile_size, height)):
        for x in range(tx * tile_size, min(tx * tile_size + tile_size, width)):
            px[count], py[count] = x + 0.5, y + 0.5
            count += 1
    return count


@njit(cache=True, parallel=True)
def _composite(table, tile_start, tile_gaussian, groups, tile_size, tiles_x, out, masks):
    """Composite the table's values into ``out`` (H, W, C) (zeros on entry) and mark in
    ``masks`` (pairs, words) (zeros on entry) the pixels each pair was composited into; returns
    the number of composited (Gaussian, pixel) pairs.

    At each pixel, Gaussian ``g`` counts where ``q = log(opacity) - sigma >= threshold`` (the
    cut-offs), with ``alpha = min(0.999, exp(q))``; compositing stops before ``T`` would fall
    to 1e-4. A tile's pixels advance together through its list, each with its own state; the
    cut-off test is one vectorised pass per pair, then only the passing pixels are visited.
    ``masks`` (pairs, words): bit ``j`` of word ``w`` of a pair is the tile's pixel ``32 w + j``.
    Group ``k`` of ``groups`` (one per thread) takes the tile rows ``k, k + groups, ...``:
    neighbouring rows cost alike, so the groups stay balanced whatever stops compositing early."""
    height, width, channels = out.shape
    tiles_y = -(-height // tile_size)
    ft = table.dtype.type
    alpha_max, t_min, one = ft(ALPHA_MAX), ft(TRANSMITTANCE_MIN), ft(1.0)
    pixels, words = tile_size * tile_size, masks.shape[1]
    composited = np.zeros(groups, np.int64)
    for group in prange(groups):
        acc = np.empty((pixels, channels), table.dtype)
        live, values = np.empty(words, np.int64), np.empty(channels, table.dtype)
        px, py = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
        q, T = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
        count_pairs = 0  # a local count: neighbouring groups' counters would share a cache line
        for tile in _group_tiles(group, groups, tiles_x, tiles_y):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            count = _tile_pixels(tile % tiles_x, tile // tiles_x, tile_size, width, height, px, py)
            acc[:count] = 0.0
            T[:count] = 1.0
            for word in range(words):  # bit j of word w: pixel 32 w + j is still compositing
                live[word] = (np.int64(1) << min(_MASK_BITS, max(count - word * _MASK_BITS, 0))) - 1
            remaining = count
            for pair in range(start, end):
                g = tile_gaussian[pair]
                mx, my, half_a, b, half_c, log_opacity = _footprint(table, g)
                threshold = table[g, 6]
                for ch in range(channels):
                    values[ch] = table[g, _COLUMNS + ch]
                for p in range(count):  # branch-free, vectorised: most pixels fail the cut-offs
                    dx, dy = px[p] - mx, py[p] - my
                    q[p] = log_opacity - (half_a * dx * dx + b * dx * dy + half_c * dy * dy)
                for word in range(words):
                    first = word * _MASK_BITS
                    bits = 0
                    for j in range(min(_MASK_BITS, count - first)):
                        bits |= np.int64(q[first + j] >= threshold) << j
                    bits &= live[word]
                    done = 0
                    while bits != 0:  # the pixels inside the cut-offs, not stopped
                        j = _lowest_bit(bits)
                        bits &= bits - 1
                        p = first + j
                        alpha = min(alpha_max, math.exp(q[p]))
                        next_T = T[p] * (one - alpha)
                        if next_T <= t_min:
                            live[word] &= ~(np.int64(1) << j)
                            remaining -= 1
                            continue
                        w = alpha * T[p]
                        for ch in range(channels):
                            acc[p, ch] += w * values[ch]
                        T[p] = next_T
                        done |= np.int64(1) << j
                        count_pairs += 1
                    masks[pair, word] = done
                if remaining == 0:
                    break
            for p in range(count):
                y, x = int(py[p]), int(px[p])
                for ch in range(channels):
                    out[y, x, ch] = acc[p, ch]
        composited[group] = count_pairs
    return composited.sum()


@njit(cache=True, parallel=True)
def _composite_backward(table, tile_start, tile_gaussian, groups, tile_size, tiles_x, out, grad_out, masks, grads):
    """Gradients of ``sum(grad_out * out)``: per group, (groups, G, 5 + C) to the table's
    ``[mean x, mean y, a, b, c, log(opacity)]`` and values but the last (the constant 1).

    Per pixel, with ``c_i = v_i . grad``, ``w_i = alpha_i T_i`` and the output's total
    ``C = sum_i w_i c_i``: ``d/d alpha_i = T_i c_i - (C - sum_{k<=i} w_k c_k) / (1 - alpha_i)``,
    and ``d alpha_i / d q_i = alpha_i`` where alpha is not clamped, with ``q = log(opacity) - sigma``.
    Only the pairs' masked pixels are visited, front to back, so ``T_i`` is rebuilt exactly.
    Groups as in :func:`_composite`; each zeroes and fills its own slice of ``grads``.
    """
    height, width, channels = out.shape
    tiles_y = -(-height // tile_size)
    ft = table.dtype.type
    alpha_max, one = ft(ALPHA_MAX), ft(1.0)
    pixels = tile_size * tile_size
    words = masks.shape[1]
    for group in prange(groups):
        pixel_grad = np.empty((pixels, channels), table.dtype)
        g_values = np.empty(channels, table.dtype)
        px, py = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
        T, total, done = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
        row = grads[group]
        row[:] = 0.0
        for tile in _group_tiles(group, groups, tiles_x, tiles_y):
            start, end = tile_start[tile], tile_start[tile + 1]
            if start == end:
                continue
            count = _tile_pixels(tile % tiles_x, tile // tiles_x, tile_size, width, height, px, py)
            for p in range(count):
                y, x = int(py[p]), int(px[p])
                total[p] = 0.0
                for ch in range(channels):
                    pixel_grad[p, ch] = grad_out[y, x, ch]
                    total[p] += pixel_grad[p, ch] * out[y, x, ch]
            T[:count] = 1.0
            done[:count] = 0.0
            for pair in range(start, end):
                drawn = 0
                for word in range(words):
                    drawn |= masks[pair, word]
                if drawn == 0:  # most pairs: past the tile's stop or outside the cut-offs
                    continue
                g = tile_gaussian[pair]
                mx, my, half_a, b, half_c, log_opacity = _footprint(table, g)
                g_mx, g_my, g_a, g_b, g_c, g_q = ft(0.0), ft(0.0), ft(0.0), ft(0.0), ft(0.0), ft(0.0)
                g_values[:] = 0.0
                for word in range(words):
                    bits = np.int64(masks[pair, word])
                    while bits != 0:
                        p = word * _MASK_BITS + _lowest_bit(bits)
                        bits &= bits - 1
                        dx, dy = px[p] - mx, py[p] - my
                        alpha = min(alpha_max, math.exp(log_opacity - (half_a * dx * dx + b * dx * dy + half_c * dy * dy)))
                        w = alpha * T[p]
                        contrib = ft(0.0)
                        for ch in range(channels):
                            contrib += pixel_grad[p, ch] * table[g, _COLUMNS + ch]
                            g_values[ch] += w * pixel_grad[p, ch]
                        done[p] += w * contrib
                        if alpha < alpha_max:
                            grad_q = alpha * (T[p] * contrib - (total[p] - done[p]) / (one - alpha))
                            # sigma = a dx^2/2 + b dx dy + c dy^2/2 with dx = x - mean x; q = log(o) - sigma.
                            g_mx += grad_q * (ft(2.0) * half_a * dx + b * dy)
                            g_my += grad_q * (b * dx + ft(2.0) * half_c * dy)
                            g_a -= grad_q * ft(0.5) * dx * dx
                            g_b -= grad_q * dx * dy
                            g_c -= grad_q * ft(0.5) * dy * dy
                            g_q += grad_q
                        T[p] *= one - alpha
                row[g, 0] += g_mx
                row[g, 1] += g_my
                row[g, 2] += g_a
                row[g, 3] += g_b
                row[g, 4] += g_c
                row[g, 5] += g_q
                for ch in range(channels - 1):
                    row[g, 6 + ch] += g_values[ch]


@njit(cache=True, parallel=True)
def _project_backward(
    means,
    factors,
    opacities,
    R,
    t,
    K,
    width,
    height,
    eps2d,
    kept,
    grads,
    chunks,
    grad_means,
    grad_factors,
    grad_opacities,
    grad_features,
    grad_pose,
):
    """Backward of the projection and the table for the ``kept`` Gaussians (G,) (the table's
    rows), given the groups' ``grads`` (groups, G, 6 + D + 1) to the table
    (:func:`_composite_backward`): into
    the Gaussians' rows of (N, 3) the means, (N, 3, 3) the factors (skipped when
    ``grad_factors`` is empty), (N,) the opacities, (N, D) the features, and per chunk of
    ``kept`` (chunks, 12) to ``[R (row-major), t]``."""
    fx, fy = K[0, 0], K[1, 1]
    channels = grad_features.shape[1]
    for chunk in prange(len(chunks) - 1):
        gj = np.empty((2, 3))  # gradient to the rows of J R
        grad = np.empty(7)  # [u, v, a, b, c, log(opacity), z]
        for i in range(chunks[chunk], chunks[chunk + 1]):
            n = kept[i]
            grad[:] = 0.0
            for group in range(len(grads)):
                for col in range(6):
                    grad[col] += grads[group, i, col]
                grad[6] += grads[group, i, 6 + channels]
                for ch in range(channels):
                    grad_features[n, ch] += grads[group, i, 6 + ch]
            grad_opacities[n] = grad[5] / max(float(opacities[n]), 1e-30)  # d log(o) / d o
            m, L = means[n], factors[n]
            x, y, z = _camera_point(R, t, m)
            j0, j1, tx, ty, free_x, free_y = _jacobian_rows(R, K, x, y, z, width, height)
            m0, m1 = _row_times(j0, L), _row_times(j1, L)
            c00, c01, c11 = _dot(m0, m0) + eps2d, _dot(m0, m1), _dot(m1, m1) + eps2d
            det = c00 * c11 - c01 * c01
            q00, q01, q11 = c11 / det, -c01 / det, c00 / det
            # Conic = cov^-1, so d cov = -Q G Q with G the conic gradient as a symmetric matrix.
            g00, g01, g11 = grad[2], 0.5 * grad[3], grad[4]
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
                for r in range(3):
                    if len(grad_factors):
                        grad_factors[n, r, col] = j0[r] * gm0 + j1[r] * gm1
                    gj[0, r] += L[r, col] * gm0
                    gj[1, r] += L[r, col] * gm1
            # Rows j0 = (fx/z)(R0 - tx R2), j1 = (fy/z)(R1 - ty R2).
            ax, ay = fx / z, fy / z
            g_tx, g_ty = 0.0, 0.0
            gj0, gj1 = gj[0], gj[1]
            g_z = grad[6] - (_dot(j0, gj0) + _dot(j1, gj1)) / z
            for col in range(3):
                grad_pose[chunk, col] += ax * gj0[col]
                grad_pose[chunk, 3 + col] += ay * gj1[col]
                grad_pose[chunk, 6 + col] -= ax * tx * gj0[col] + ay * ty * gj1[col]
                g_tx -= ax * R[2, col] * gj0[col]
                g_ty -= ay * R[2, col] * gj1[col]
            # u = fx x/z + cx, v = fy y/z + cy; tx = x/z and ty = y/z where not clamped.
            g_x = grad[0] * ax + (g_tx / z if free_x else 0.0)
            g_y = grad[1] * ay + (g_ty / z if free_y else 0.0)
            g_z -= (g_x * x + g_y * y) / z
            # p = R m + t.
            g_p = (g_x, g_y, g_z)
            for r in range(3):
                grad_means[n, r] = R[0, r] * g_x + R[1, r] * g_y + R[2, r] * g_z
                for col in range(3):
                    grad_pose[chunk, 3 * r + col] += g_p[r] * m[col]
                grad_pose[chunk, 9 + r] += g_p[r]


def _threads() -> int:
    """Kernel threads: torch's intra-op count, so one setting governs both."""
    threads = max(1, min(torch.get_num_threads(), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(threads)
    return threads


def _numpy(x: Tensor) -> np.ndarray:
    """The values of ``x``, in its dtype, without a copy where it is contiguous."""
    return x.detach().contiguous().numpy()


def _float64(x: Tensor) -> np.ndarray:
    return x.detach().to(torch.float64).contiguous().numpy()


class _Render(torch.autograd.Function):
    """Projection, binning and compositing with their analytic backward: differentiable to the
    means, the factors, the opacities, the features and the pose. Returns the (H, W, D + 2)
    composite of ``[features, camera z, 1]``."""

    @staticmethod
    def forward(ctx, means, factors, opacities, features, T_cw, K, sort_key, width, height, near, far, tile_size, stats):
        m, L, o, f = _numpy(means), _numpy(factors), _numpy(opacities), _numpy(features)
        R, t, k = _float64(T_cw[:3, :3]), _float64(T_cw[:3, 3]), _float64(K)
        tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
        geometry = np.empty((len(m), 8))
        flags = np.empty(len(m), np.int8)
        limit = float(torch.finfo(means.dtype).max)
        threads = _threads()
        with _LAUNCH:
            _project(m, L, o, R, t, k, width, height, near, far, EPS2D, limit, geometry, flags)
            # The sort key is the torch backend's own (render dtype), so both order ties alike.
            kept, order = _depth_order(flags, _sortable(sort_key))
            table = np.empty((len(kept), _COLUMNS + f.shape[1] + 2), m.dtype)
            reach, boxes = np.empty(len(kept)), np.empty((len(kept), 5), np.int64)
            _visible_table(kept, geometry, o, f, tile_size, tiles_x, tiles_y, table, reach, boxes)
            first = np.zeros(len(kept) + 1, np.int64)
            np.cumsum(boxes[order, 4], out=first[1:])
            pair_tile, listed = np.empty(first[-1], np.int32), np.empty(len(kept), np.int64)
            _list_tiles(table, reach, boxes, order, first, tile_size, tiles_x, pair_tile, listed)
            tile_start, tile_gaussian = _sort_by_tile(pair_tile, first, listed, order, tiles_x * tiles_y)
            out = np.zeros((height, width, table.shape[1] - _COLUMNS), m.dtype)
            masks = np.zeros((len(tile_gaussian), -(-tile_size * tile_size // _MASK_BITS)), np.uint16)
            composited = _composite(table, tile_start, tile_gaussian, threads, tile_size, tiles_x, out, masks)
        skipped = int((flags == 2).sum())
        if skipped:
            warnings.warn(f"{skipped} Gaussians with non-finite covariance (huge or NaN scales) were skipped", stacklevel=4)
        stats.update(visible=len(kept), pairs=len(tile_gaussian), composited=int(composited))
        ctx.arrays = (m, L, o, R, t, k, width, height, kept, table, tile_start, tile_gaussian, threads, tile_size, masks)
        ctx.num_features = f.shape[1]
        image = torch.from_numpy(out)
        ctx.save_for_backward(image)  # the backward reads it: in-place edits must raise
        return image

    @staticmethod
    def backward(ctx, grad_image):
        (image,) = ctx.saved_tensors
        m, L, o, R, t, k, width, height, kept, table, tile_start, tile_gaussian, groups, tile_size, masks = ctx.arrays
        ctx.arrays = None
        dtype, num, tiles_x = m.dtype, len(m), -(-width // tile_size)
        grads = np.empty((groups, len(kept), table.shape[1] - 2), dtype)
        chunks = np.linspace(0, len(kept), _threads() + 1).astype(np.int64)
        grad_means, grad_opacities = np.zeros((num, 3), dtype), np.zeros(num, dtype)
        grad_factors = np.zeros((num if ctx.needs_input_grad[1] else 0, 3, 3), dtype)
        grad_features = np.zeros((num, ctx.num_features), dtype)
        grad_pose = np.zeros((len(chunks) - 1, 12))
        with _LAUNCH:
            _composite_backward(
                table, tile_start, tile_gaussian, groups, tile_size, tiles_x, image.numpy(), _numpy(grad_image), masks, grads
            )
            _project_backward(
                m, L, o, R, t, k, width, height, EPS2D, kept, grads, chunks,
                grad_means, grad_factors, grad_opacities, grad_features, grad_pose,
            )  # fmt: skip
        pose = torch.zeros(4, 4, dtype=grad_image.dtype)
        total = torch.from_numpy(grad_pose.sum(0)).to(grad_image.dtype)
        pose[:3, :3], pose[:3, 3] = total[:9].view(3, 3), total[9:]
        factors = torch.from_numpy(grad_factors) if ctx.needs_input_grad[1] else None
        return (
            torch.from_numpy(grad_means),
            factors,
            torch.from_numpy(grad_opacities),
            torch.from_numpy(grad_features),
            pose,
            *[None] * 8,
        )


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
        sort_key = (means @ T_cw[2, :3] + T_cw[2, 3]).numpy()  # as project_gaussians sorts
    stats: dict = {}
    image = _Render.apply(means, factors, opacities, features, T_cw, K, sort_key, width, height, near, far, tile_size, stats)
    return image[..., :-2], image[..., -1], image[..., -2], stats
