"""Images for a chat request: downscaled to a long side, encoded as PNG or JPEG, hashed for the
response cache. Shared by the endpoint client (data URLs, raw base64) and its benchmark."""

from __future__ import annotations

import base64
import hashlib
import io

import numpy as np
from PIL import Image

# Images with more pixels than this go as JPEG (quality 90): a photograph compresses ~5x better
# than PNG, and a model sees no difference at that quality; smaller ones stay lossless.
JPEG_ABOVE_PIXELS = 512 * 512
JPEG_QUALITY = 90


def downscale(image: np.ndarray, long_side: int) -> np.ndarray:
    """``image`` (H, W, 3) uint8 resized so that ``max(H, W) <= long_side`` (aspect kept, each
    side at least 1 pixel; PIL's antialiased bicubic filter), or itself when already small enough."""
    height, width = image.shape[:2]
    if max(height, width) <= long_side:
        return image
    scale = long_side / max(height, width)
    size = (max(1, round(width * scale)), max(1, round(height * scale)))
    return np.asarray(Image.fromarray(image).resize(size, Image.Resampling.BICUBIC))


def encode(image: np.ndarray, long_side: int) -> tuple[str, str]:
    """``image`` (H, W, 3) uint8 RGB downscaled to ``long_side`` (:func:`downscale`), as
    (MIME type, base64 text): PNG, or JPEG above :data:`JPEG_ABOVE_PIXELS`."""
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"an image to send must be (H, W, 3) uint8 RGB, got {image.shape} {image.dtype}")
    small = downscale(image, long_side)
    buffer = io.BytesIO()
    if small.shape[0] * small.shape[1] > JPEG_ABOVE_PIXELS:
        Image.fromarray(small).save(buffer, format="JPEG", quality=JPEG_QUALITY)
        mime = "image/jpeg"
    else:
        # compress_level 1: a few times faster than the default 6 for a few percent more bytes
        Image.fromarray(small).save(buffer, format="PNG", compress_level=1)
        mime = "image/png"
    return mime, base64.b64encode(buffer.getvalue()).decode("ascii")


def data_url(image: np.ndarray, long_side: int) -> str:
    """``image`` as a ``data:image/...;base64,...`` URL (OpenAI's ``image_url`` content part)."""
    mime, text = encode(image, long_side)
    return f"data:{mime};base64,{text}"


def image_hash(image: np.ndarray) -> str:
    """SHA-256 of an image's shape, dtype and pixels (the response cache's key of an image)."""
    digest = hashlib.sha256(f"{image.shape} {image.dtype}".encode())
    digest.update(memoryview(np.ascontiguousarray(image)).cast("B"))
    return digest.hexdigest()
