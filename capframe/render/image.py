"""Reading and writing images."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from ..errors import InputError
from ..scene._io import atomic_write


def read_rgb(path: str | Path, what: str) -> np.ndarray:
    """(H, W, 3) uint8 RGB of the image file at ``path``; :class:`InputError` naming it and
    ``what`` it was expected to be otherwise."""
    from PIL import UnidentifiedImageError

    try:
        with Image.open(path) as image:
            return np.asarray(image.convert("RGB"))
    except (OSError, UnidentifiedImageError) as err:
        raise InputError(f"cannot read the {what} ({err})", source=str(path)) from None


def to_uint8(image: torch.Tensor) -> np.ndarray:
    """(H, W, C) float image in [0, 1] -> (H, W, C) uint8, rounded to nearest."""
    return (image.detach().clamp(0.0, 1.0) * 255.0 + 0.5).to(torch.uint8).cpu().numpy()


def save_png(image: torch.Tensor, path: str | Path) -> None:
    """Write an (H, W, 3) float image in [0, 1] (or (H, W) grey) as a PNG, atomically.

    The PNG carries no timestamp, so the same image always gives the same bytes."""
    save_image(image, path, "PNG")


def save_image(image: torch.Tensor, path: str | Path, format: str | None = None) -> None:
    """Write an (H, W, 3) float image in [0, 1] (or (H, W) grey) atomically, as ``format``
    (``PNG`` or ``JPEG``; default: JPEG for a ``.jpg``/``.jpeg`` path, else PNG)."""
    if format is None:
        format = "JPEG" if Path(path).suffix.lower() in (".jpg", ".jpeg") else "PNG"
    buffer = io.BytesIO()
    rgb = to_uint8(image if image.dim() == 3 else image[..., None].expand(-1, -1, 3))
    Image.fromarray(rgb).save(buffer, format=format, **({"quality": 95} if format == "JPEG" else {}))
    atomic_write(path, buffer.getvalue())
