"""Compiled CPU rasteriser (numba): the torch backend's rules, one Gaussian or pixel at a time.

One autograd function, :class:`_Render`, runs every stage as a compiled kernel, from the
Gaussians' parameters to the image and back, in four parallel regions (each a fork and join of
the kernel threads, which costs more than the serial work between them at small sizes):

1. **projection** (:func:`_project`, per Gaussian): the torch backend's EWA projection and
   culling (:func:`~capframe.render.torch_backend.project_gaussians`) in float64; each kept
   Gaussian writes, at its place in the torch backend's depth order (its own sort key; a stable
   radix sort, :func:`_depth_order`, run before), its compositing-table row (2D mean, half
   conic, log-opacity, cut-off threshold, composited values), its cut-off ellipse for binning
   and its box of candidate tiles. Every later stage names a Gaussian by that place, so a
   tile's list (in depth order) reads the table forwards, not scattered over all of it.
2. **binning and compositing** (:func:`_rasterize`, per group of tile rows): each group lists
   its rows' (tile, Gaussian) pairs in depth order, where some pixel centre of the tile lies
   inside the Gaussian's cut-off ellipse (its exact x-range over each tile row), sorts them by
   tile (a stable counting sort keeps each tile's list in depth order) and composites per pixel,
   front to back, with the torch backend's rules (3-sigma ellipse and alpha >= 1/255, alpha
   clamped at 0.999, stop before the transmittance would fall to 1e-4). Each pair records which
   of the tile's pixels it was composited into (a bit mask) and their alphas, so
3. **its backward** (:func:`_composite_backward`) to the 2D means, conics, opacities and
   composited values visits only the composited (Gaussian, pixel) pairs, front to back, with
   the recorded alphas (no ``exp``); pairs that composited nothing (outside the cut-offs, or
   past the pixels' stop: about 40%) are skipped on their mask alone;
4. **the projection's backward** (:func:`_project_backward`) to the means, covariance factors
   and pose, scattered straight into the inputs' rows, skipping the Gaussians that composited
   nothing (hidden ones: about 30% of the kept ones in a dense view).

Tiles are split into one group per thread, group ``k`` of ``n`` taking the tile rows ``k, k + n,
...``: neighbouring rows cost alike, so the groups stay balanced however early compositing stops
(a split by pair counts cannot know that). Groups run in parallel and the backward accumulates
each group's gradients in its own buffer, zeroed by its own thread and summed in a fixed order,
so results do not depend on scheduling (images do not depend on the thread count either;
gradients only up to rounding, through the number of groups). Compositing computes in
the render dtype (float32 vectorises twice as wide; float64 renders stay float64 throughout);
the projection and the pose gradient's sums are float64 whatever the render dtype. A render
without gradients records neither masks nor alphas.
"""

from __future__ import annotations

import math
import os
import threading
import warnings

import numba
import numpy as np
import torch
from llvmlite import ir
from numba import njit, prange, types
from numba.core import cgutils
from numba.extending import intrinsic
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
# Gaussians per block of the projection backward's interleaved split over threads.
_BLOCK = 64
# How many Gaussians ahead the per-Gaussian kernels prefetch the rows they will visit in depth order,
# and how many pairs ahead compositing prefetches a tile's next table rows (far apart in the table).
_AHEAD = 8
_PAIRS_AHEAD = 4
# Bits per word of a pair's pixel mask: a 4x4 tile is one word, one vector of float32 lanes.
_MASK_BITS = 16
# Index of the lowest set bit of a 32-bit word by a de Bruijn multiply (numba has no public
# count-trailing-zeros): the isolated bit times this constant puts a unique 5-bit pattern on top.
_DE_BRUIJN = 0x077CB531
_DE_BRUIJN_BIT = np.array(
    [0, 1, 28, 2, 29, 14, 24, 3, 30, 22, 20, 15, 25, 17, 4, 8, 31, 27, 13, 23, 21, 19, 16, 7, 26, 12, 18, 6, 11, 5, 10, 9],
    dtype=np.int64,
)


def _prefetcher(write: bool):
    """An intrinsic ``prefetch(array, row)`` that asks the CPU to fetch the cache line holding
    row ``row`` of ``array`` (its first element), to be read or (``write``) written, while the
    work before the access goes on: rows visited in another order than their memory's (a
    permutation) are cache misses that the hardware cannot foresee."""

    @intrinsic
    def prefetch(typingctx, array, row):
        if not isinstance(array, types.Array) or not isinstance(row, types.Integer):
            return None

        def codegen(context, builder, signature, args):
            array_type = signature.args[0]
            data = context.make_array(array_type)(context, builder, args[0])
            index = context.cast(builder, args[1], signature.args[1], types.intp)
            inds = [index] + [ir.Constant(index.type, 0)] * (array_type.ndim - 1)
            shape, strides = cgutils.unpack_tuple(builder, data.shape), cgutils.unpack_tuple(builder, data.strides)
            pointer = cgutils.get_item_pointer2(context, builder, data.data, shape, strides, array_type.layout, inds)
            i32, byte_pointer = ir.IntType(32), ir.IntType(8).as_pointer()
            function = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), [byte_pointer, i32, i32, i32]), "llvm.prefetch.p0"
            )
            # Arguments: read (0) or write (1), keep in all cache levels (3), data cache (1).
            flags = [ir.Constant(i32, int(write)), ir.Constant(i32, 3), ir.Constant(i32, 1)]
            builder.call(function, [builder.bitcast(pointer, byte_pointer), *flags])
            return context.get_dummy_value()

        return types.void(array, row), codegen

    return prefetch


_prefetch_read, _prefetch_write = _prefetcher(False), _prefetcher(True)


@njit(cache=True, inline="always")
def _footprint(table, g):
    """Row ``g`` of the compositing table: mean x, mean y, a/2, b, c/2, log(opacity)."""
    return table[g, 0], table[g, 1], table[g, 2], table[g, 3], table[g, 4], table[g, 5]


@njit(cache=True, inline="always")
def _lowest_bit(bits):
    """Index of the lowest set bit of ``bits`` (nonzero, below ``2**32``; masks use 16)."""
    return _DE_BRUIJN_BIT[(((bits & -bits) * _DE_BRUIJN) & 0xFFFFFFFF) >> 27]


@njit(cache=True)
def _slope_bounds(K, width, height):
    """The bounds ``lo_x, hi_x, lo_y, hi_y`` the slopes ``x/z, y/z`` are clamped to (the frame
    and a 30% margin, see :func:`~capframe.render.torch_backend.clamped_slopes`): the same for
    every Gaussian, so computed once per render rather than with six divisions per Gaussian."""
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    margin_x, margin_y = 0.3 * 0.5 * width / fx, 0.3 * 0.5 * height / fy
    return -(cx / fx + margin_x), (width - cx) / fx + margin_x, -(cy / fy + margin_y), (height - cy) / fy + margin_y


@njit(cache=True)
def _jacobian_rows(R, K, bounds, x, y, z):
    """Rows ``j0, j1`` (3-tuples) of ``J R`` at the camera point ``(x, y, z)`` with the slopes
    ``tx, ty`` clamped to ``bounds`` (:func:`_slope_bounds`) and whether each was left unclamped
    (see :func:`~capframe.render.torch_backend.ewa_project`)."""
    fx, fy = K[0, 0], K[1, 1]
    lo_x, hi_x, lo_y, hi_y = bounds
    sx, sy = x / z, y / z
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
def _project(
    means,
    factors,
    opacities,
    features,
    R,
    t,
    K,
    width,
    height,
    near,
    far,
    eps2d,
    limit,
    tile_size,
    rank,
    table,
    ellipses,
    boxes,
    flags,
    room,
):
    """Per Gaussian ``n`` of the (N,) inputs: the projection and culling, and for the kept ones
    (``flags[n] == 1``) everything binning and compositing read:

    * ``table`` (N, 7 + D + 2), render dtype: in row ``rank[n]`` (its place in depth order,
      :func:`_depth_order`), the compositing table's row (see ``_COLUMNS``);
    * ``ellipses`` (N, 8) float64: in row ``rank[n]``, the cut-off ellipse for binning, of the
      table's rounded values: mean x, mean y, b, 2 reach a, det = ac - b^2, 1/a, its reach in y,
      the y of its rightmost point (reach: the cut-off on sigma, with a margin against rounding);
    * ``boxes`` (N, 4) int32: in row ``rank[n]``, first and last tile column and row of its
      footprint box; an empty box (no rows) where the Gaussian is not kept.

    Binning visits the Gaussians in depth order, once per group of tile rows: rows in index order
    would make each visit a cache miss beyond some ten thousand Gaussians (twice the listing's
    time at 50k); these scattered writes cost the projection less (at 50k, single-threaded, 0.8
    ms against 2.7 ms saved), and it runs on every thread. The same holds for the table: a
    tile's Gaussians, read in depth order, lie in a band of rows that neighbouring tiles share.
    The rows a Gaussian ``_AHEAD`` places on will write are prefetched: without, each scattered
    write waits on memory (at 300k Gaussians, 640x480, 2 threads: 28 ms against 9 ms).

    ``room`` (numba's threads, groups + 8), zeros on entry: per kernel thread (its
    ``numba.get_thread_id()``), the room each group of tile
    rows (:func:`_group_tiles`, ``groups`` of them) needs for its (tile, Gaussian) pairs, the
    tiles of the boxes in its rows (rows 64 bytes apart: no cache line shared between threads).

    ``flags`` (N,): 1 kept, 2 non-finite covariance, 0 otherwise (behind, beyond or off-screen,
    degenerate). ``limit`` is the render dtype's largest value: what would overflow it counts as
    non-finite, as in the torch backend. Table rows of Gaussians not kept are left unwritten."""
    ft = table.dtype.type
    tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
    channels = features.shape[1]
    groups = room.shape[1] - 8
    bounds = _slope_bounds(K, width, height)
    num = len(means)
    for n in prange(num):
        if n + _AHEAD < num:  # the rows this Gaussian's successor will write
            ahead = rank[n + _AHEAD]
            _prefetch_write(table, ahead)
            _prefetch_write(ellipses, ahead)
            _prefetch_write(boxes, ahead)
        flags[n] = 0
        r = rank[n]
        boxes[r, 2], boxes[r, 3] = 0, -1  # no rows: skipped by binning unless kept below
        L = factors[n]
        if not _all_finite(L):
            flags[n] = 2
            continue
        x, y, z = _camera_point(R, t, means[n])
        if not (near < z < far):
            continue
        j0, j1, _, _, _, _ = _jacobian_rows(R, K, bounds, x, y, z)
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
        if not (det > 0 and ex > 0 and ey > 0 and u + ex > 0 and v + ey > 0 and u - ex < width and v - ey < height):
            continue
        flags[n] = 1
        row = table[r]
        row[0], row[1] = u, v
        row[2], row[3], row[4] = ft(0.5) * ft(c11 / det), -c01 / det, ft(0.5) * ft(c00 / det)
        log_opacity = math.log(max(opacities[n], ft(1e-30)))
        # Cut-offs: sigma <= 4.5 (the 3-sigma ellipse) and alpha >= 1/255, as q >= threshold.
        row[5], row[6] = log_opacity, max(log_opacity - ft(SIGMA_MAX), ft(LOG_ALPHA_MIN))
        for ch in range(channels):
            row[_COLUMNS + ch] = features[n, ch]
        row[_COLUMNS + channels], row[_COLUMNS + channels + 1] = z, 1.0
        # Binning works on the table's rounded values, which the per-pixel test uses.
        mx, my = float(row[0]), float(row[1])
        a, b, c = 2.0 * float(row[2]), float(row[3]), 2.0 * float(row[4])
        two_k = 2.0 * (min(float(log_opacity) - LOG_ALPHA_MIN, SIGMA_MAX) + _REACH_MARGIN)
        conic_det = a * c - b * b
        ellipses[r, 0], ellipses[r, 1], ellipses[r, 2], ellipses[r, 3] = mx, my, b, two_k * a
        ellipses[r, 4], ellipses[r, 5] = conic_det, 1.0 / a
        ellipses[r, 6] = math.sqrt(two_k * a / conic_det)  # |dy| on the ellipse
        ellipses[r, 7] = -b * math.sqrt(two_k / (c * conic_det))  # the rightmost point's; the leftmost's is its mirror
        boxes[r, 0] = max(int(math.floor((mx - ex) / tile_size)), 0)
        boxes[r, 1] = min(int(math.floor((mx + ex) / tile_size)), tiles_x - 1)
        boxes[r, 2] = max(int(math.floor((my - ey) / tile_size)), 0)
        boxes[r, 3] = min(int(math.floor((my + ey) / tile_size)), tiles_y - 1)
        columns, rows = boxes[r, 1] - boxes[r, 0] + 1, room[numba.get_thread_id()]
        for group in range(groups):
            first, stop, step = _rows_of_group(boxes[r, 2], boxes[r, 3], group, groups)
            rows[group] += columns * max(-(-(stop - first) // step), 0)


@njit(cache=True, inline="always")
def _rows_of_group(ty0, ty1, group, groups):
    """The tile rows ``ty0 .. ty1`` that group ``group`` of ``groups`` owns
    (``ty = group mod groups``), as ``range`` arguments."""
    return ty0 + (group - ty0) % groups, ty1 + 1, groups


@njit(cache=True)
def _depth_order(keys):
    """``rank`` (N,): each Gaussian's place in the order of ``keys`` (N,) (floats' bits, as
    unsigned integers of their size; ordered as the floats), ties in index order (a stable
    least-significant-byte-first radix sort). Sorted before the projection, culled ones included,
    so that it can write its rows in this order; among the kept ones the order is the same as
    sorting them alone."""
    num = len(keys)
    order, order_out = np.arange(num), np.empty(num, np.int64)
    key, key_out = np.empty_like(keys), np.empty_like(keys)
    top = keys.dtype.type(1) << keys.dtype.type(8 * keys.itemsize - 1)  # the sign bit
    for j in range(num):  # ordered as unsigned integers: negatives' bits flipped, positives' sign bit set
        key[j] = ~keys[j] if keys[j] & top else keys[j] | top
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
    rank = np.empty(num, np.int64)
    for r in range(num):
        rank[order[r]] = r
    return rank


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


@njit(cache=True)
def _list_pairs(ellipses, boxes, group, groups, tile_size, tiles_x, pair_tile, pair_gaussian, start):
    """The (tile, Gaussian) pairs of group ``group``'s tile rows, in depth order, from ``start``
    on into ``pair_tile`` and ``pair_gaussian`` (a Gaussian named by its place in depth order,
    its row of ``ellipses``, ``boxes`` and the table: :func:`_project`); returns where they end.
    A Gaussian is listed in a tile where some pixel centre lies inside its cut-off ellipse.

    Scanlines, as :func:`~capframe.render.torch_backend.intersect_tiles`: per tile row, the
    ellipse's exact x-range over the row's band of pixel centres gives the tiles, no test per
    tile. With ``D = ac - b^2`` the right edge at height ``dy`` is
    ``x = -b dy / a + sqrt(2 a reach - D dy^2) / a``, concave in ``dy``, so its maximum over the
    band is at the ellipse's rightmost point clamped to the band (the left edge likewise)."""
    count = start
    for r in range(len(boxes)):
        first, stop, step = _rows_of_group(boxes[r, 2], boxes[r, 3], group, groups)
        if first >= stop:
            continue
        mx, my, b, two_ka = ellipses[r, 0], ellipses[r, 1], ellipses[r, 2], ellipses[r, 3]
        det, inv_a, y_reach, dy_right = ellipses[r, 4], ellipses[r, 5], ellipses[r, 6], ellipses[r, 7]
        for ty in range(first, stop, step):
            band = ty * tile_size + 0.5 - my
            lo, hi = max(band, -y_reach), min(band + tile_size - 1, y_reach)
            if lo > hi:
                continue
            dr, dl = min(max(dy_right, lo), hi), min(max(-dy_right, lo), hi)
            right = mx + (-b * dr + math.sqrt(max(two_ka - det * dr * dr, 0.0))) * inv_a
            left = mx + (-b * dl - math.sqrt(max(two_ka - det * dl * dl, 0.0))) * inv_a
            # Tile tx holds pixel centres [tx S + 0.5, tx S + S - 0.5].
            tx0 = max(int(math.ceil((left + 0.5 - tile_size) / tile_size)), boxes[r, 0])
            tx1 = min(int(math.floor((right - 0.5) / tile_size)), boxes[r, 1])
            for tx in range(tx0, tx1 + 1):
                pair_tile[count], pair_gaussian[count] = ty * tiles_x + tx, r
                count += 1
    return count


@njit(cache=True)
def _sort_by_tile(pair_tile, pair_gaussian, start, end, tiles, tile_range, tile_gaussian):
    """Stable counting sort by tile of the pairs ``start .. end`` of ``pair_tile`` and
    ``pair_gaussian``, all in ``tiles`` (a list), into the same places of ``tile_gaussian``:
    tile ``t``'s Gaussians, in depth order, are ``tile_gaussian[tile_range[t, 0]:tile_range[t, 1]]``."""
    for t in tiles:
        tile_range[t, 0] = 0
    for k in range(start, end):
        tile_range[pair_tile[k], 0] += 1
    cursor = start
    for t in tiles:
        cursor, tile_range[t, 0] = cursor + tile_range[t, 0], cursor
        tile_range[t, 1] = tile_range[t, 0]
    for k in range(start, end):
        t = pair_tile[k]
        tile_gaussian[tile_range[t, 1]] = pair_gaussian[k]
        tile_range[t, 1] += 1


@njit(cache=True, inline="always")
def _composite(table, tile_gaussian, tile_range, tiles, tile_size, out, masks, alphas, alpha_start, stream, words, channels):
    """Composite the table's values into ``out`` over ``tiles`` (a list), their
    Gaussians ``tile_gaussian[tile_range[t, 0]:tile_range[t, 1]]`` in depth order; returns the
    number of composited (Gaussian, pixel) pairs. ``out``: the composite of ``[features, camera
    z, 1]`` (C = D + 2 channels) as three images, (H, W, D), (H, W) and (H, W), so that each is
    contiguous. ``masks``, ``alphas`` and ``alpha_start`` (when
    ``masks`` is not empty) and ``tile_range[t, 2]`` as in :func:`_rasterize`, the alphas from
    ``stream`` on.

    At each pixel, Gaussian ``g`` counts where ``q = log(opacity) - sigma >= threshold`` (the
    cut-offs), with ``alpha = min(0.999, exp(q))``; compositing stops before ``T`` would fall
    to 1e-4. A tile's pixels advance together through its list, each with its own state; the
    cut-off test is one vectorised pass per pair, then only the passing pixels are visited.
    ``words``: mask words per pair (the tile's pixels, padded to whole words of 16), ``channels``:
    C; constants where the caller can make them so (:func:`_rasterize`)."""
    out_features, out_depth, out_alpha = out
    height, width = out_alpha.shape
    tiles_x = -(-width // tile_size)
    ft = table.dtype.type
    alpha_max, t_min, one = ft(ALPHA_MAX), ft(TRANSMITTANCE_MIN), ft(1.0)
    pixels = words * _MASK_BITS  # padded to whole words; the padding never composites (not live)
    record = len(masks) > 0
    acc = np.empty((pixels, channels), table.dtype)
    live, values = np.empty(words, np.int64), np.empty(channels, table.dtype)
    px, py = np.zeros(pixels, table.dtype), np.zeros(pixels, table.dtype)
    q, T = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
    count_pairs = 0
    for tile in tiles:
        start, stop = tile_range[tile, 0], tile_range[tile, 1]
        tile_range[tile, 2] = start
        alpha_start[tile] = stream
        if start == stop:
            continue
        visited = stop
        count = _tile_pixels(tile % tiles_x, tile // tiles_x, tile_size, width, height, px, py)
        acc[:count] = 0.0
        T[:count] = 1.0
        for word in range(words):  # bit j of word w: pixel 16 w + j is still compositing
            live[word] = (np.int64(1) << min(_MASK_BITS, max(count - word * _MASK_BITS, 0))) - 1
        remaining = count
        for pair in range(start, stop):
            if pair + _PAIRS_AHEAD < stop:
                _prefetch_read(table, tile_gaussian[pair + _PAIRS_AHEAD])
            g = tile_gaussian[pair]
            mx, my, half_a, b, half_c, log_opacity = _footprint(table, g)
            threshold = table[g, 6]
            for ch in range(channels):
                values[ch] = table[g, _COLUMNS + ch]
            for word in range(words):
                first = word * _MASK_BITS
                bits = 0
                for j in range(_MASK_BITS):  # branch-free, vectorised: most pixels fail the cut-offs
                    dx, dy = px[first + j] - mx, py[first + j] - my
                    q[first + j] = log_opacity - (half_a * dx * dx + b * dx * dy + half_c * dy * dy)
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
                    if record:
                        alphas[stream] = alpha
                        stream += 1
                if record:
                    masks[pair, word] = done
            if remaining == 0:
                visited = pair + 1
                break
        tile_range[tile, 2] = visited
        for p in range(count):
            y, x = int(py[p]), int(px[p])
            for ch in range(channels - 2):
                out_features[y, x, ch] = acc[p, ch]
            out_depth[y, x], out_alpha[y, x] = acc[p, channels - 2], acc[p, channels - 1]
    return count_pairs


@njit(cache=True, parallel=True)
def _rasterize(
    table, ellipses, boxes, groups, tile_size, bases, pair_tile, pair_gaussian, tile_gaussian, tile_range, out, masks,
    alphas, alpha_start, counts,
):  # fmt: skip
    """Bin and composite: group ``k`` of ``groups`` (one per thread) takes the tile rows ``k, k +
    groups, ...`` (neighbouring rows cost alike, so the groups stay balanced whatever stops
    compositing early), lists their pairs (:func:`_list_pairs`) from ``bases[k]`` on, sorts them
    by tile (:func:`_sort_by_tile`) and composites them (:func:`_composite`) into ``out``
    (three images as there, zeros on entry). ``counts`` (groups, 2): the group's listed and composited pairs.

    For the backward (skipped where ``masks`` is empty): ``tile_range[t, 2]`` ends the pairs
    tile ``t`` visited; ``masks`` (pairs, words) marks the pixels each visited pair was
    composited into (bit ``j`` of word ``w``: the tile's pixel ``16 w + j``) and ``alphas``
    holds their alphas, in compositing order, tile ``t``'s from ``alpha_start[t]`` on (group
    ``k``'s from ``tile_size^2 bases[k]``)."""
    height, width = out[2].shape  # the alpha image's
    tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
    words, channels = -(-tile_size * tile_size // _MASK_BITS), table.shape[1] - _COLUMNS
    for group in prange(groups):
        tiles = _group_tiles(group, groups, tiles_x, tiles_y)
        end = _list_pairs(ellipses, boxes, group, groups, tile_size, tiles_x, pair_tile, pair_gaussian, bases[group])
        _sort_by_tile(pair_tile, pair_gaussian, bases[group], end, tiles, tile_range, tile_gaussian)
        stream = tile_size * tile_size * bases[group]
        # Constants the compiler unrolls and vectorises for (compositing and its backward take a
        # quarter less time at 50k): one mask word (4x4 tiles) with a colour (3 values, camera z,
        # 1) or one extra channel (a subject's mask); other sizes and counts take the general copy.
        if words == 1 and channels == 5:
            count_pairs = _composite(
                table, tile_gaussian, tile_range, tiles, tile_size, out, masks, alphas, alpha_start, stream, 1, 5
            )
        elif words == 1 and channels == 3:
            count_pairs = _composite(
                table, tile_gaussian, tile_range, tiles, tile_size, out, masks, alphas, alpha_start, stream, 1, 3
            )
        else:
            count_pairs = _composite(
                table, tile_gaussian, tile_range, tiles, tile_size, out, masks, alphas, alpha_start, stream, words, channels
            )
        counts[group, 0], counts[group, 1] = end - bases[group], count_pairs


@njit(cache=True, inline="always")
def _tiles_backward(
    table, tile_range, tile_gaussian, tiles, tile_size, out, grad_out, masks, alphas, alpha_start, row, words, channels
):
    """:func:`_composite_backward` of the pairs of ``tiles`` (a list) into ``row`` (N, 5 + C),
    ``words`` and ``channels`` as in :func:`_composite`."""
    (out_features, out_depth, out_alpha), (grad_features, grad_depth, grad_alpha) = out, grad_out
    height, width = out_alpha.shape
    tiles_x = -(-width // tile_size)
    ft = table.dtype.type
    alpha_max, one = ft(ALPHA_MAX), ft(1.0)
    pixels = words * _MASK_BITS
    pixel_grad = np.empty((pixels, channels), table.dtype)
    g_values = np.empty(channels, table.dtype)
    px, py = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
    T, total, done = np.empty(pixels, table.dtype), np.empty(pixels, table.dtype), np.empty(pixels, table.dtype)
    for tile in tiles:
        start, end = tile_range[tile, 0], tile_range[tile, 2]
        if start == end:
            continue
        stream = alpha_start[tile]
        count = _tile_pixels(tile % tiles_x, tile // tiles_x, tile_size, width, height, px, py)
        for p in range(count):
            y, x = int(py[p]), int(px[p])
            for ch in range(channels - 2):
                pixel_grad[p, ch] = grad_features[y, x, ch]
            pixel_grad[p, channels - 2], pixel_grad[p, channels - 1] = grad_depth[y, x], grad_alpha[y, x]
            total[p] = 0.0
            for ch in range(channels - 2):
                total[p] += pixel_grad[p, ch] * out_features[y, x, ch]
            total[p] += pixel_grad[p, channels - 2] * out_depth[y, x]
            total[p] += pixel_grad[p, channels - 1] * out_alpha[y, x]
        T[:count] = 1.0
        done[:count] = 0.0
        for pair in range(start, end):
            if pair + _PAIRS_AHEAD < end:
                _prefetch_read(table, tile_gaussian[pair + _PAIRS_AHEAD])
            drawn = 0
            for word in range(words):
                drawn |= masks[pair, word]
            if drawn == 0:  # past the tile's stop at these pixels, or outside the cut-offs
                continue
            g = tile_gaussian[pair]
            mx, my, half_a, b, half_c, _ = _footprint(table, g)
            g_mx, g_my, g_a, g_b, g_c, g_q = ft(0.0), ft(0.0), ft(0.0), ft(0.0), ft(0.0), ft(0.0)
            g_values[:] = 0.0
            for word in range(words):
                bits = np.int64(masks[pair, word])
                while bits != 0:
                    p = word * _MASK_BITS + _lowest_bit(bits)
                    bits &= bits - 1
                    alpha = alphas[stream]
                    stream += 1
                    w = alpha * T[p]
                    contrib = ft(0.0)
                    for ch in range(channels):
                        contrib += pixel_grad[p, ch] * table[g, _COLUMNS + ch]
                        g_values[ch] += w * pixel_grad[p, ch]
                    done[p] += w * contrib
                    if alpha < alpha_max:
                        grad_q = alpha * (T[p] * contrib - (total[p] - done[p]) / (one - alpha))
                        # sigma = a dx^2/2 + b dx dy + c dy^2/2 with dx = x - mean x; q = log(o) - sigma.
                        dx, dy = px[p] - mx, py[p] - my
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
def _composite_backward(table, tile_range, tile_gaussian, groups, tile_size, out, grad_out, masks, alphas, alpha_start, grads):
    """Gradients of ``sum(grad_out * out)`` (both three images as in :func:`_composite`): per
    group, (groups, N, 5 + C) to the table's
    ``[mean x, mean y, a, b, c, log(opacity)]`` and values but the last (the constant 1), in the
    table's rows (each group zeroes its own).

    Per pixel, with ``c_i = v_i . grad``, ``w_i = alpha_i T_i`` and the output's total
    ``C = sum_i w_i c_i``: ``d/d alpha_i = T_i c_i - (C - sum_{k<=i} w_k c_k) / (1 - alpha_i)``,
    and ``d alpha_i / d q_i = alpha_i`` where alpha is not clamped, with ``q = log(opacity) - sigma``.
    Only the pairs' masked pixels are visited, front to back, with the forward's alphas, so
    ``T_i`` is rebuilt exactly. Tiles, groups, masks and alphas as in :func:`_rasterize`.
    """
    height, width = out[2].shape  # the alpha image's
    tiles_x, tiles_y = -(-width // tile_size), -(-height // tile_size)
    words, channels = masks.shape[1], table.shape[1] - _COLUMNS
    for group in prange(groups):
        row = grads[group]
        row[:] = 0.0  # all of it, in memory order: the kept Gaussians' rows lie scattered over it
        tiles = _group_tiles(group, groups, tiles_x, tiles_y)
        if words == 1 and channels == 5:
            _tiles_backward(
                table, tile_range, tile_gaussian, tiles, tile_size, out, grad_out, masks, alphas, alpha_start, row, 1, 5
            )
        elif words == 1 and channels == 3:
            _tiles_backward(
                table, tile_range, tile_gaussian, tiles, tile_size, out, grad_out, masks, alphas, alpha_start, row, 1, 3
            )
        else:
            _tiles_backward(
                table,
                tile_range,
                tile_gaussian,
                tiles,
                tile_size,
                out,
                grad_out,
                masks,
                alphas,
                alpha_start,
                row,
                words,
                channels,
            )


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
    rank,
    grads,
    chunks,
    grad_means,
    grad_factors,
    grad_opacities,
    grad_features,
    grad_pose,
):
    """Backward of the projection and the table for the ``kept`` Gaussians (G,), given the
    groups' ``grads`` (groups, N, 6 + D + 1) to their table rows, Gaussian ``n``'s in row
    ``rank[n]`` (:func:`_composite_backward`; Gaussians that composited nothing are skipped): into
    the Gaussians' rows of (N, 3) the means, (N, 3, 3) the factors, (N,) the opacities, (N, D)
    the features (each skipped when empty: no gradient asked for), and per chunk of ``kept``
    (chunks, 15) to ``[R (row-major), t]`` and the sum of the means' gradients (float64 sums of
    the render dtype's values, as if stored). Chunk ``k`` of ``chunks`` takes the blocks
    ``k, k + chunks, ...`` of ``_BLOCK`` Gaussians of ``kept``: hidden Gaussians (skipped) cluster
    in index ranges (the far side of an object), so halves of ``kept`` would not cost alike, and
    whole blocks keep threads off each other's cache lines. The ``grads`` rows, in depth order,
    are prefetched ``_AHEAD`` Gaussians on."""
    fx, fy = K[0, 0], K[1, 1]
    bounds = _slope_bounds(K, width, height)
    channels = grad_features.shape[1]
    mean_type = grad_means.dtype.type
    num = len(kept)
    for chunk in prange(chunks):
        gj = np.empty((2, 3))  # gradient to the rows of J R
        grad = np.empty(7)  # [u, v, a, b, c, log(opacity), z]
        # The chunk's own sum: neighbouring rows of grad_pose share a cache line, which two threads
        # adding per Gaussian would pass back and forth.
        pose = np.zeros(15)
        for block in range(chunk * _BLOCK, num, chunks * _BLOCK):
            for i in range(block, min(block + _BLOCK, num)):
                if i + _AHEAD < num:
                    for group in range(len(grads)):
                        _prefetch_read(grads[group], rank[kept[i + _AHEAD]])
                n = kept[i]
                r = rank[n]
                grad[:] = 0.0
                for group in range(len(grads)):
                    for col in range(6):
                        grad[col] += grads[group, r, col]
                    grad[6] += grads[group, r, 6 + channels]
                    if len(grad_features):
                        for ch in range(channels):
                            grad_features[n, ch] += grads[group, r, 6 + ch]
                # Composited nothing (hidden, or past every tile's stop), or a zero gradient: nothing to add.
                if grad[0] == 0.0 and grad[1] == 0.0 and grad[2] == 0.0 and grad[3] == 0.0 and grad[4] == 0.0:
                    if grad[5] == 0.0 and grad[6] == 0.0:
                        continue
                if len(grad_opacities):
                    grad_opacities[n] = grad[5] / max(float(opacities[n]), 1e-30)  # d log(o) / d o
                m, L = means[n], factors[n]
                x, y, z = _camera_point(R, t, m)
                j0, j1, tx, ty, free_x, free_y = _jacobian_rows(R, K, bounds, x, y, z)
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
                    pose[col] += ax * gj0[col]
                    pose[3 + col] += ay * gj1[col]
                    pose[6 + col] -= ax * tx * gj0[col] + ay * ty * gj1[col]
                    g_tx -= ax * R[2, col] * gj0[col]
                    g_ty -= ay * R[2, col] * gj1[col]
                # u = fx x/z + cx, v = fy y/z + cy; tx = x/z and ty = y/z where not clamped.
                g_x = grad[0] * ax + (g_tx / z if free_x else 0.0)
                g_y = grad[1] * ay + (g_ty / z if free_y else 0.0)
                g_z -= (g_x * x + g_y * y) / z
                # p = R m + t.
                g_p = (g_x, g_y, g_z)
                for r in range(3):
                    g_mean = mean_type(R[0, r] * g_x + R[1, r] * g_y + R[2, r] * g_z)
                    if len(grad_means):
                        grad_means[n, r] = g_mean
                    pose[12 + r] += g_mean  # as stored, in float64
                    for col in range(3):
                        pose[3 * r + col] += g_p[r] * m[col]
                    pose[9 + r] += g_p[r]

        grad_pose[chunk] = pose


def _threads() -> int:
    """Kernel threads: torch's intra-op count, so one setting governs both."""
    threads = max(1, min(torch.get_num_threads(), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(threads)
    return threads


def _aligned(shape: tuple[int, ...], dtype) -> np.ndarray:
    """An uninitialised array whose data starts on a 64-byte cache line: rows of 16, 32 or 64
    bytes, written at random places, then touch one line each, not two."""
    size = int(np.prod(shape)) * np.dtype(dtype).itemsize
    raw = np.empty(size + 64, np.uint8)
    start = -raw.ctypes.data % 64
    return raw[start : start + size].view(dtype).reshape(shape)


def _numpy(x: Tensor) -> np.ndarray:
    """The values of ``x``, in its dtype, without a copy where it is contiguous."""
    return x.detach().contiguous().numpy()


def _float64(x: Tensor) -> np.ndarray:
    return x.detach().to(torch.float64).contiguous().numpy()


class _Render(torch.autograd.Function):
    """Projection, binning and compositing with their analytic backward: differentiable to the
    means, the factors, the opacities, the features and the pose. Returns the composite of
    ``[features, camera z, 1]`` as three contiguous images: features (H, W, D), alpha (H, W) and
    the alpha-weighted camera z (H, W) (slices of one image would make every later operation on
    them, and their gradients, strided)."""

    @staticmethod
    def forward(
        ctx, means, factors, opacities, features, T_cw, K, world, centre, sort_key, width, height, near, far, tile_size, record,
        stats,
    ):  # fmt: skip
        m, L, o, f = _numpy(means), _numpy(factors), _numpy(opacities), _numpy(features)
        R, t, k = _float64(T_cw[:3, :3]), _float64(T_cw[:3, 3]), _float64(K)
        num, tiles = len(m), -(-width // tile_size) * -(-height // tile_size)
        table = np.empty((num, _COLUMNS + f.shape[1] + 2), m.dtype)
        ellipses, boxes, flags = _aligned((num, 8), np.float64), _aligned((num, 4), np.int32), np.empty(num, np.int8)
        limit = float(torch.finfo(means.dtype).max)
        threads = _threads()
        with _LAUNCH:
            # The sort key is the torch backend's own (render dtype), so both order ties alike.
            rank = _depth_order(sort_key.view(np.uint32 if sort_key.itemsize == 4 else np.uint64))
            room = np.zeros((numba.get_num_threads(), threads + 8), np.int64)  # per kernel thread, per group
            _project(
                m, L, o, f, R, t, k, width, height, near, far, EPS2D, limit, tile_size, rank, table, ellipses, boxes, flags, room
            )  # fmt: skip
            kept, room = np.flatnonzero(flags == 1), room[:, :threads].sum(0)
            bases = np.zeros(threads, np.int64)
            np.cumsum(room[:-1], out=bases[1:])
            pair_tile, pair_gaussian, tile_gaussian = (np.empty(room.sum(), np.int32) for _ in range(3))
            tile_range, alpha_start = np.empty((tiles, 3), np.int64), np.empty(tiles, np.int64)
            out = (
                np.zeros((height, width, f.shape[1]), m.dtype),
                np.zeros((height, width), m.dtype),
                np.zeros((height, width), m.dtype),
            )
            masks = np.empty((room.sum() if record else 0, -(-tile_size * tile_size // _MASK_BITS)), np.uint16)
            alphas = np.empty(room.sum() * tile_size * tile_size if record else 0, m.dtype)
            counts = np.empty((threads, 2), np.int64)
            _rasterize(
                table, ellipses, boxes, threads, tile_size, bases, pair_tile, pair_gaussian, tile_gaussian, tile_range,
                out, masks, alphas, alpha_start, counts,
            )  # fmt: skip
        skipped = int((flags == 2).sum())
        if skipped:
            warnings.warn(f"{skipped} Gaussians with non-finite covariance (huge or NaN scales) were skipped", stacklevel=4)
        stats.update(visible=len(kept), pairs=int(counts[:, 0].sum()), composited=int(counts[:, 1].sum()))
        ctx.arrays = (m, L, o, R, t, k, width, height, kept, table, tile_range, tile_gaussian, threads, tile_size, masks, alphas)
        ctx.arrays += (alpha_start, rank)
        ctx.num_features, ctx.recentred = f.shape[1], world is not None
        features, depth, alpha = (torch.from_numpy(a) for a in out)
        ctx.save_for_backward(features, depth, alpha)  # the backward reads them: in-place edits must raise
        return features, alpha, depth

    @staticmethod
    def backward(ctx, grad_features, grad_alpha, grad_depth):
        out = tuple(x.numpy() for x in ctx.saved_tensors)
        grad_out = (_numpy(grad_features), _numpy(grad_depth), _numpy(grad_alpha))
        (
            m,
            L,
            o,
            R,
            t,
            k,
            width,
            height,
            kept,
            table,
            tile_range,
            tile_gaussian,
            groups,
            tile_size,
            masks,
            alphas,
            alpha_start,
            rank,
        ) = ctx.arrays
        ctx.arrays = None
        dtype, num = m.dtype, len(m)
        grads = np.empty((groups, num, table.shape[1] - 2), dtype)
        chunks = _threads()
        # Gradients nobody asked for (a fixed scene's means, opacities, factors, colours) are not computed.
        needs_means = ctx.needs_input_grad[0] or ctx.needs_input_grad[6]
        grad_means = np.zeros((num if needs_means else 0, 3), dtype)
        grad_factors = np.zeros((num if ctx.needs_input_grad[1] else 0, 3, 3), dtype)
        grad_opacities = np.zeros(num if ctx.needs_input_grad[2] else 0, dtype)
        grad_features = np.zeros((num if ctx.needs_input_grad[3] else 0, ctx.num_features), dtype)
        grad_pose = np.zeros((chunks, 15))
        with _LAUNCH:
            _composite_backward(
                table, tile_range, tile_gaussian, groups, tile_size, out, grad_out, masks, alphas, alpha_start, grads,
            )  # fmt: skip
            _project_backward(
                m, L, o, R, t, k, width, height, EPS2D, kept, rank, grads, chunks,
                grad_means, grad_factors, grad_opacities, grad_features, grad_pose,
            )  # fmt: skip
        pose = torch.zeros(4, 4, dtype=grad_alpha.dtype)
        sums = torch.from_numpy(grad_pose.sum(0))
        total = sums[:12].to(pose.dtype)
        pose[:3, :3], pose[:3, 3] = total[:9].view(3, 3), total[9:]
        factors, opacities, features = (
            torch.from_numpy(grad) if needed else None
            for grad, needed in zip((grad_factors, grad_opacities, grad_features), ctx.needs_input_grad[1:4])
        )
        means = torch.from_numpy(grad_means) if needs_means else None
        if not ctx.recentred:
            return (means, factors, opacities, features, pose, None, None, None, *[None] * 8)
        # means = world - centre, rounded: the world means' gradient is the means' (in float64),
        # the centre's minus their sum.
        world = means.to(torch.float64) if ctx.needs_input_grad[6] else None
        return (None, factors, opacities, features, pose, None, world, -sums[12:], *[None] * 8)


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
    origin: tuple[Tensor, Tensor] | None = None,
) -> tuple[Tensor, Tensor, Tensor, dict]:
    """Same contract as :func:`capframe.render.torch_backend.rasterize_torch` (CPU tensors only).

    Args:
        tile_size: binning tile edge in pixels; the image does not depend on it.
        origin: optional world means (N, 3) and camera centre (3,) (float64) of which ``means``
            are ``world - centre`` in the render dtype, computed without gradient: gradients go
            to these two instead (the centre's summed in the kernel), so the caller's recentring
            costs autograd nothing per Gaussian.
    Returns:
        features (H, W, D), alpha (H, W), accumulated camera-z (H, W), stats (visible Gaussians,
        tile pairs at ``tile_size``, composited (Gaussian, pixel) pairs).
    """
    if means.device.type != "cpu":
        raise ValueError(f"the compiled render backend runs on the CPU; got tensors on {means.device}")
    with torch.no_grad():
        sort_key = (means @ T_cw[2, :3] + T_cw[2, 3]).numpy()  # as project_gaussians sorts
    stats: dict = {}
    # Without a backward to come, the forward records nothing for it.
    world, centre = (None, None) if origin is None else origin
    inputs = (means, factors, opacities, features, T_cw, world, centre)
    record = torch.is_grad_enabled() and any(x is not None and x.requires_grad for x in inputs)
    image, alpha, depth_sum = _Render.apply(
        means, factors, opacities, features, T_cw, K, world, centre, sort_key, width, height, near, far, tile_size, record, stats
    )
    return image, alpha, depth_sum, stats
