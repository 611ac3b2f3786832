"""Pictures for the image-text backends: every training view streamed once per scene (its
photograph at the camera's size, its render when the scene has none), with a fingerprint for
the embedding cache, and renders of candidate cameras.

The segmenters and Orient Anything read a few retrieved views per job through
:mod:`capframe.backends.views`, which keeps each picture for the job; the coarse scorer reads
every training view, so it streams them instead of keeping hundreds of photographs in memory.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import torch

from ..render import render
from ..scene import Camera, SceneDir


def image_file(scene: SceneDir, camera: Camera) -> Path | None:
    """The training image of ``camera``, or None when the scene has none."""
    if not camera.image_path:
        return None
    path = Path(camera.image_path)
    path = path if path.is_absolute() else scene.root / path
    return path if path.is_file() else None


def render_image(scene: SceneDir, camera: Camera) -> np.ndarray:
    """(H, W, 3) uint8 render of ``camera`` at its image size (black background)."""
    with torch.no_grad():
        rgb = render(scene.gaussians, camera).rgb
    return (rgb.clamp(0.0, 1.0).cpu().numpy() * 255.0 + 0.5).astype(np.uint8)


def training_picture(scene: SceneDir, camera: Camera) -> np.ndarray:
    """(H, W, 3) uint8 picture of a training view at the camera's image size: its photograph
    (resized when stored at another size), else its render."""
    from PIL import Image

    path = image_file(scene, camera)
    if path is None:
        return render_image(scene, camera)
    with Image.open(path) as image:
        image = image.convert("RGB")
        if image.size != (camera.width, camera.height):
            image = image.resize((camera.width, camera.height), Image.BICUBIC)
        return np.asarray(image)


def views_fingerprint(scene: SceneDir) -> str:
    """Changes when any training view's picture would: its photograph's size and time, or for a
    rendered view the PLY, the pose, the intrinsics and the image size."""
    h = hashlib.sha256()
    ply = scene.root / "scene.ply"
    for camera in scene.cameras:
        h.update(camera.name.encode())
        path = image_file(scene, camera)
        source = path if path is not None else ply
        stat = source.stat()
        h.update(f"{source}:{stat.st_size}:{stat.st_mtime_ns}:{camera.width}x{camera.height}".encode())
        if path is None:
            h.update(np.ascontiguousarray(camera.T_cw).tobytes() + np.ascontiguousarray(camera.K).tobytes())
    return h.hexdigest()[:16]
