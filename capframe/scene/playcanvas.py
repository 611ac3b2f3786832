"""PlayCanvas compressed PLY (``*.compressed.ply``, written by SuperSplat, splat-transform and gsplat).

A binary PLY with three elements (layout as read by PlayCanvas's engine and ``splat-transform``):

- ``chunk``, one row per 256 consecutive splats: float32 ``min_x min_y min_z max_x max_y max_z``,
  ``min_scale_* max_scale_*`` (log-scales) and optionally ``min_r min_g min_b max_r max_g max_b``.
- ``vertex``: four uint32 words per splat, each field an unsigned fraction ``v / (2^bits - 1)``
  interpolated between its chunk's min and max:

  - ``packed_position``: x in bits 21-31 (11 bits), y in bits 11-20 (10), z in bits 0-10 (11);
  - ``packed_scale``: the same 11/10/11 layout, in log-scale space;
  - ``packed_color``: r, g, b, opacity, 8 bits each from the high byte down; colour in the
    chunk's colour range (or 0..1 without one), opacity as is (not a logit);
  - ``packed_rotation``: smallest three: bits 30-31 hold the index of the largest component of
    the ``rot_0..rot_3`` (wxyz) quaternion, the other three, in index order, sit in bits 20-29,
    10-19 and 0-9 as ``(v / 1023 - 0.5) * sqrt(2)``; the largest is ``sqrt(1 - sum of squares)``.

- optional ``sh``: uint8 ``f_rest_0..f_rest_{M-1}`` (channel-major, as in the Inria PLY), each
  ``(t - 0.5) * 8`` with ``t = (v + 0.5) / 256`` (0 and 255 map to t = 0 and 1 exactly).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from .model import GaussianScene, opacity_logit, rgb_to_sh_dc
from .ply import read_binary_elements

CHUNK_SIZE = 256
_PACKED = ("packed_position", "packed_rotation", "packed_scale", "packed_color")
_CHUNK = tuple(f"{m}_{a}" for m in ("min", "max") for a in "xyz") + tuple(f"{m}_scale_{a}" for m in ("min", "max") for a in "xyz")
_CHUNK_COLOR = tuple(f"{m}_{c}" for m in ("min", "max") for c in "rgb")
# For each index of the largest component, the indices of the three stored ones, in bit order.
_OTHERS = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])


def _unorm(packed: np.ndarray, shift: int, bits: int) -> np.ndarray:
    """The ``bits``-bit field at ``shift`` of (N,) uint32 words as a float32 fraction in [0, 1]."""
    mask = (1 << bits) - 1
    return ((packed >> shift) & mask).astype(np.float32) / mask


def _unpack_111011(packed: np.ndarray) -> np.ndarray:
    """(N,) uint32 -> (N, 3) fractions: 11 bits x, 10 bits y, 11 bits z from the high bit down."""
    return np.stack([_unorm(packed, 21, 11), _unorm(packed, 11, 10), _unorm(packed, 0, 11)], axis=1)


def unpack_rotation(packed: np.ndarray) -> np.ndarray:
    """(N,) uint32 smallest-three words -> (N, 4) float32 unit quaternions in ``rot_0..3`` (wxyz) order."""
    n = len(packed)
    largest = (packed >> 30).astype(np.intp)
    small = (np.stack([_unorm(packed, s, 10) for s in (20, 10, 0)], axis=1) - 0.5) * np.float32(np.sqrt(2.0))
    quats = np.empty((n, 4), dtype=np.float32)
    np.put_along_axis(quats, _OTHERS[largest], small, axis=1)
    np.put_along_axis(quats, largest[:, None], np.sqrt(np.maximum(0.0, 1.0 - (small**2).sum(1, keepdims=True))), axis=1)
    # Quantisation can push the stored three past unit length; renormalise.
    return quats / np.linalg.norm(quats, axis=1, keepdims=True)


def _lerp(chunk: np.ndarray, lo: tuple[str, ...], hi: tuple[str, ...], index: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Per splat ``min + t (max - min)`` with min/max the chunk columns ``lo``/``hi``: t (N, 3) -> (N, 3)."""
    low = np.stack([chunk[name] for name in lo], axis=1)[index]
    high = np.stack([chunk[name] for name in hi], axis=1)[index]
    return low + t * (high - low)


def _check_layout(elements: dict[str, np.ndarray], source: str) -> None:
    """Raise :class:`InputError` unless the elements have the compressed layout (see the module doc)."""
    vertex, chunk = elements.get("vertex"), elements.get("chunk")
    if vertex is None or chunk is None:
        raise InputError(f"has elements {list(elements)}; a compressed PLY has 'chunk' and 'vertex'", source=source)
    missing = [p for p in _PACKED if p not in vertex.dtype.names or vertex.dtype[p].kind != "u"]
    missing += [p for p in _CHUNK if p not in chunk.dtype.names]
    if missing:
        raise InputError(f"missing or mistyped compressed-PLY properties {', '.join(missing)}", source=source)
    if len(vertex) == 0:
        raise InputError("holds no Gaussians ('element vertex 0'); expected at least one", source=source)
    if len(chunk) != -(-len(vertex) // CHUNK_SIZE):
        raise InputError(
            f"{len(chunk)} chunks for {len(vertex)} splats; expected one chunk per {CHUNK_SIZE} splats", source=source
        )
    sh = elements.get("sh")
    if sh is not None and (len(sh) != len(vertex) or len(sh.dtype.names or ()) not in (0, 9, 24, 45)):
        raise InputError(
            f"'sh' element has {len(sh)} rows of {len(sh.dtype.names or ())} values; expected {len(vertex)} rows "
            "of 9, 24 or 45 f_rest values",
            source=source,
        )


def _decode_sh_rest(sh: np.ndarray, n: int) -> np.ndarray:
    """The ``sh`` element's uint8 f_rest columns (channel-major) -> (N, K-1, 3) float32 coefficients."""
    m = len(sh.dtype.names or ())
    if m == 0:
        return np.zeros((n, 0, 3), dtype=np.float32)
    raw = np.stack([sh[f"f_rest_{i}"] for i in range(m)], axis=1).astype(np.float32)
    t = np.where(raw == 0, 0.0, np.where(raw == 255, 1.0, (raw + 0.5) / 256.0)).astype(np.float32)
    return ((t - 0.5) * 8.0).reshape(n, 3, m // 3).transpose(0, 2, 1)


def read_compressed_ply(path: str | Path) -> GaussianScene:
    """Read a PlayCanvas compressed PLY into a float32 :class:`GaussianScene`.

    Raises :class:`InputError` naming the file for a missing file, a layout that is not the
    compressed one, no splats, truncated data and non-finite values.
    """
    path, source = Path(path), str(path)
    if not path.is_file():
        raise InputError("file not found", source=source)
    elements = read_binary_elements(path)
    _check_layout(elements, source)
    chunk, vertex = elements["chunk"], elements["vertex"]
    n = len(vertex)
    index = np.arange(n) // CHUNK_SIZE
    words = {p: vertex[p].astype(np.uint32) for p in _PACKED}
    means = _lerp(chunk, _CHUNK[:3], _CHUNK[3:6], index, _unpack_111011(words["packed_position"]))
    log_scales = _lerp(chunk, _CHUNK[6:9], _CHUNK[9:12], index, _unpack_111011(words["packed_scale"]))
    rgba = np.stack([_unorm(words["packed_color"], s, 8) for s in (24, 16, 8, 0)], axis=1)
    rgb = rgba[:, :3]
    if all(c in chunk.dtype.names for c in _CHUNK_COLOR):
        rgb = _lerp(chunk, _CHUNK_COLOR[:3], _CHUNK_COLOR[3:], index, rgb)
    dc = rgb_to_sh_dc(torch.from_numpy(rgb.astype(np.float32)))[:, None, :]
    rest = torch.from_numpy(_decode_sh_rest(elements["sh"], n)) if "sh" in elements else dc[:, :0]
    scene = GaussianScene(
        means=torch.from_numpy(means.astype(np.float32)),
        quats=torch.from_numpy(unpack_rotation(words["packed_rotation"])),
        log_scales=torch.from_numpy(log_scales.astype(np.float32)),
        opacity_logits=opacity_logit(torch.from_numpy(rgba[:, 3].copy())),
        sh=torch.cat([dc, rest], dim=1),
    )
    scene.check_finite(source=source)
    return scene
