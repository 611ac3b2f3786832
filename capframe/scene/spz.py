"""Niantic ``.spz`` files (versions 2-4; layout as documented and read by Niantic's ``spz`` library).

Version 4: a 32-byte little-endian header ``magic 0x5053474e ("NGSP"), version, numPoints (uint32),
shDegree, fractionalBits, flags, numStreams (uint8), tocByteOffset (uint32), 12 reserved bytes``;
optional extension records up to ``tocByteOffset``; a table of contents of ``numStreams`` pairs
``(compressed size, uncompressed size)`` as uint64; then one zstd stream per attribute.
Versions 2-3: the whole file is gzip; inside, a 16-byte header (the same first 16 bytes, with the
last one reserved) followed by the attributes back to back. The attributes, in this order:

- positions: 3 x 24-bit two's-complement fixed point per splat, ``v / 2^fractionalBits``;
- alphas: uint8 opacity ``v / 255`` (not a logit);
- colours: uint8 SH DC coefficient ``(v / 255 - 0.5) / 0.15``;
- scales: uint8 log-scale ``v / 16 - 10``;
- rotations, ``xyzw`` quaternion: version 2 three bytes ``x y z`` as ``v / 127.5 - 1`` with
  ``w = sqrt(1 - |xyz|^2)``; versions 3+ four bytes, a little-endian uint32 "smallest three": bits
  30-31 the index of the largest component, then for the other components from the highest index
  down, 10 bits each from bit 0 up: 9 bits magnitude ``m / 511 * sqrt(1/2)`` and a sign bit;
- SH: ``(d+1)^2 - 1`` coefficients per splat (degree d up to 4), coefficient-major with the colour
  channel fastest, each uint8 ``(v - 128) / 128``.

Axes: Niantic's documentation says spz stores RUB axes (x right, y up, z back, as OpenGL) by
default, while 3DGS PLY files keep the RDF axes of their COLMAP world (y down, z forward). By default
the reader turns RUB into RDF (a half turn about x: y and z negated, the quaternion and the SH
coefficients transformed to match), so an spz and a PLY of the same capture share one world, as
the biker pair in the real test data does. ``to_rdf=False`` keeps the file's axes (for files
written with ``UNSPECIFIED`` axes from a PLY). Degree-4 SH is cut to degree 3 (the highest this
project renders), which keeps every band it can use.
"""

from __future__ import annotations

import gzip
import struct
import zlib
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from .model import GaussianScene, opacity_logit

MAGIC = 0x5053474E
_COLOR_SCALE = 0.15
_MAX_DEGREE = 3
# Signs of the real SH basis functions of bands 1-3 (3DGS order) under (x, y, z) -> (x, -y, -z):
# band 1 y, z, x; band 2 xy, yz, 3z^2-1, xz, x^2-y^2; band 3 y(3x^2-y^2), xyz, y(5z^2-1), z(5z^2-3),
# x(5z^2-1), z(x^2-y^2), x(x^2-3y^2).
_HALF_TURN_X_SH = np.array([-1, -1, 1, -1, 1, 1, -1, 1, -1, 1, -1, -1, 1, -1, 1], dtype=np.float32)


def _decompress_zstd(data: bytes, size: int) -> bytes:
    """One zstd frame -> ``size`` bytes (zstandard is imported here: only version 4 needs it)."""
    import zstandard

    return zstandard.ZstdDecompressor().decompress(data, max_output_size=size)


def _streams_v4(data: bytes, header: tuple, sizes: list[int], source: str) -> list[bytes]:
    """The version-4 attribute streams, decompressed and checked against the expected ``sizes``."""
    num_streams, toc_offset = header[6], header[7]
    if num_streams != len(sizes) or toc_offset < 32 or toc_offset + 16 * num_streams > len(data):
        raise InputError(
            f"header declares {num_streams} streams with a table at byte {toc_offset}; expected {len(sizes)} "
            f"streams in a file of {len(data)} bytes",
            source=source,
        )
    toc = np.frombuffer(data, dtype="<u8", count=2 * num_streams, offset=toc_offset).reshape(-1, 2)
    streams, start = [], toc_offset + 16 * num_streams
    for (packed, unpacked), size in zip(toc.tolist(), sizes):
        if unpacked != size or start + packed > len(data):
            raise InputError(f"truncated or inconsistent stream table ({unpacked} bytes, expected {size})", source=source)
        try:
            streams.append(_decompress_zstd(data[start : start + packed], size))
        except Exception as err:  # zstandard raises its own error type for corrupt frames
            raise InputError(f"corrupt zstd stream ({err})", source=source) from None
        if len(streams[-1]) != size:
            raise InputError(f"a zstd stream holds {len(streams[-1])} bytes, expected {size}", source=source)
        start += packed
    return streams


def _streams_legacy(body: bytes, sizes: list[int], source: str) -> list[bytes]:
    """The attributes of a gunzipped version 2-3 body (after its 16-byte header), back to back."""
    if len(body) < sum(sizes):
        raise InputError(f"truncated data: {len(body)} bytes of attributes, expected {sum(sizes)}", source=source)
    offsets = np.cumsum([0, *sizes])
    return [body[a:b] for a, b in zip(offsets[:-1], offsets[1:])]


def _unpack_smallest_three(words: np.ndarray) -> np.ndarray:
    """(N,) uint32 -> (N, 4) float32 ``xyzw`` quaternions (versions 3+)."""
    n = len(words)
    largest = (words >> 30).astype(np.intp)
    quats = np.zeros((n, 4), dtype=np.float32)
    rows = np.arange(n)
    # Slot k (bits 10k..10k+9) holds the k-th component counted down from index 3, skipping the largest.
    slot = np.zeros(n, dtype=np.uint32)
    for i in (3, 2, 1, 0):
        field = (words >> (10 * slot)) & 0x3FF
        value = (field & 0x1FF).astype(np.float32) / 511.0 * np.float32(np.sqrt(0.5))
        value = np.where(field & 0x200, -value, value)
        stored = largest != i
        quats[rows[stored], i] = value[stored]
        slot += stored
    quats[rows, largest] = np.sqrt(np.maximum(0.0, 1.0 - (quats**2).sum(1)))
    return quats


def _unpack_first_three(bytes3: np.ndarray) -> np.ndarray:
    """(N, 3) uint8 -> (N, 4) float32 ``xyzw`` quaternions (version 2)."""
    xyz = bytes3.astype(np.float32) / 127.5 - 1.0
    return np.concatenate([xyz, np.sqrt(np.maximum(0.0, 1.0 - (xyz**2).sum(1, keepdims=True)))], axis=1)


def _fixed24(raw: np.ndarray, fractional_bits: int) -> np.ndarray:
    """(N, 9) uint8 -> (N, 3) float32 positions from little-endian 24-bit two's complement."""
    b = raw.reshape(-1, 3, 3).astype(np.int32)
    v = b[..., 0] | (b[..., 1] << 8) | (b[..., 2] << 16)
    v = np.where(v & 0x800000, v - (1 << 24), v)
    return (v.astype(np.float64) / (1 << fractional_bits)).astype(np.float32)


def _half_turn_x(means: np.ndarray, quats: np.ndarray, rest: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotate Gaussians by a half turn about x (RUB <-> RDF): means (N, 3), wxyz quats (N, 4),
    SH rest (N, K-1, 3) -> the same shapes. For R = diag(1, -1, -1) the rotation R Q R^T has
    quaternion (w, x, -y, -z)."""
    flip = np.array([1, -1, -1], dtype=np.float32)
    signs = _HALF_TURN_X_SH[: rest.shape[1], None]
    return means * flip, quats * np.concatenate([[1], flip]).astype(np.float32), rest * signs


def read_spz(path: str | Path, to_rdf: bool = True) -> GaussianScene:
    """Read a Niantic ``.spz`` file (versions 2, 3 or 4) into a float32 :class:`GaussianScene`,
    turned from spz's RUB axes to RDF unless ``to_rdf`` is false (see the module doc).

    Raises :class:`InputError` naming the file for a missing file, a bad magic number, an
    unsupported version or SH degree, no splats, truncated or corrupt data and non-finite values.
    """
    path, source = Path(path), str(path)
    if not path.is_file():
        raise InputError("file not found", source=source)
    data = path.read_bytes()
    if data[:2] == b"\x1f\x8b":  # versions 1-3 gzip the whole file
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError, zlib.error) as err:
            raise InputError(f"corrupt or truncated gzip data ({err})", source=source) from None
    if len(data) < 16 or struct.unpack_from("<I", data)[0] != MAGIC:
        raise InputError("not an .spz file (no 'NGSP' magic number)", source=source)
    version = struct.unpack_from("<I", data, 4)[0]
    if version not in (2, 3, 4):
        raise InputError(f"spz version {version}; this reader supports versions 2, 3 and 4", source=source)
    if version == 4 and len(data) < 32:
        raise InputError("truncated header (version 4 has 32 bytes)", source=source)
    header = struct.unpack_from("<IIIBBBBI" if version == 4 else "<IIIBBBB", data)
    n, degree, fractional_bits = header[2], header[3], header[4]
    if n == 0:
        raise InputError("holds no Gaussians (numPoints 0); expected at least one", source=source)
    if degree > 4:
        raise InputError(f"SH degree {degree}; expected 0-4", source=source)
    k = (degree + 1) ** 2 - 1  # SH coefficients per channel beyond DC
    sizes = [9 * n, n, 3 * n, 3 * n, (4 if version >= 3 else 3) * n] + ([3 * k * n] if k else [])
    if version == 4:
        streams = _streams_v4(data, header, sizes, source)
    else:
        streams = _streams_legacy(data[16:], sizes, source)
    raw = [np.frombuffer(s, dtype=np.uint8) for s in streams]
    if version >= 3:
        xyzw = _unpack_smallest_three(raw[4].view("<u4").astype(np.uint32))
    else:
        xyzw = _unpack_first_three(raw[4].reshape(n, 3))
    quats = xyzw[:, [3, 0, 1, 2]]
    dc = (raw[2].reshape(n, 1, 3).astype(np.float32) / 255.0 - 0.5) / _COLOR_SCALE
    rest = (raw[5].reshape(n, k, 3).astype(np.float32) - 128.0) / 128.0 if k else np.zeros((n, 0, 3), np.float32)
    rest = rest[:, : (_MAX_DEGREE + 1) ** 2 - 1]
    means, quats = _fixed24(raw[0], fractional_bits), quats / np.linalg.norm(quats, axis=1, keepdims=True)
    if to_rdf:
        means, quats, rest = _half_turn_x(means, quats, rest)
    scene = GaussianScene(
        means=torch.from_numpy(means),
        quats=torch.from_numpy(quats),
        log_scales=torch.from_numpy(raw[3].reshape(n, 3).astype(np.float32) / 16.0 - 10.0),
        opacity_logits=opacity_logit(torch.from_numpy(raw[1].astype(np.float32) / 255.0)),
        sh=torch.from_numpy(np.concatenate([dc, rest], axis=1)),
    )
    scene.check_finite(source=source)
    return scene
