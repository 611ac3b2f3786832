"""antimatter15 ``.splat`` files (the WebGL viewer's format; also written by gsplat and SuperSplat).

No header: N records of 32 bytes, little-endian::

    0..11   x y z           float32 position
    12..23  sx sy sz        float32 *linear* standard deviations
    24..27  r g b a         uint8 colour and opacity, value / 255
    28..31  qw qx qy qz     uint8 quaternion components, (value - 128) / 128

Only the SH DC term survives (degree 0). The writers quantise the normalised quaternion as
``q * 128 + 128`` clipped to 0..255, so decoding gives a near-unit quaternion that is normalised again.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from .model import GaussianScene, opacity_logit, rgb_to_sh_dc

RECORD_BYTES = 32
_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0], dtype=np.float32)


def decode_splat(records: np.ndarray) -> GaussianScene:
    """Decode (N, 32) uint8 records into a float32 :class:`GaussianScene` (degree 0)."""
    floats = np.ascontiguousarray(records[:, :24]).view("<f4").astype(np.float32)  # (N, 6): position, scale
    rgba = records[:, 24:28].astype(np.float32) / 255.0
    quats = (records[:, 28:32].astype(np.float32) - 128.0) / 128.0
    norm = np.linalg.norm(quats, axis=1, keepdims=True)
    # All four bytes at 128 is no rotation at all; the identity keeps such a splat renderable.
    quats = np.where(norm > 0, quats / np.where(norm > 0, norm, 1.0), _IDENTITY)
    with np.errstate(divide="ignore", invalid="ignore"):  # scale <= 0 gives -inf or NaN: check_finite reports it
        log_scales = np.log(floats[:, 3:6])
    rgba = torch.from_numpy(rgba)
    return GaussianScene(
        means=torch.from_numpy(np.ascontiguousarray(floats[:, :3])),
        quats=torch.from_numpy(quats),
        log_scales=torch.from_numpy(log_scales),
        opacity_logits=opacity_logit(rgba[:, 3]),
        sh=rgb_to_sh_dc(rgba[:, None, :3]),
    )


def read_splat(path: str | Path) -> GaussianScene:
    """Read an antimatter15 ``.splat`` file into a float32 :class:`GaussianScene` (SH degree 0).

    Raises :class:`InputError` naming the file when it is missing or empty, when its size is not a
    multiple of 32 bytes (truncated, or not a ``.splat``), and for non-finite values or
    non-positive scales.
    """
    path, source = Path(path), str(path)
    if not path.is_file():
        raise InputError("file not found", source=source)
    data = np.fromfile(path, dtype=np.uint8)
    if len(data) == 0:
        raise InputError("holds no Gaussians (empty file)", source=source)
    if len(data) % RECORD_BYTES:
        raise InputError(
            f"size {len(data)} bytes is not a multiple of {RECORD_BYTES}; truncated, or not an antimatter15 .splat file",
            source=source,
        )
    scene = decode_splat(data.reshape(-1, RECORD_BYTES))
    scene.check_finite(source=source)
    return scene
