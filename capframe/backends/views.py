"""What model backends see of a training view: its image and its rendered depth.

The image is the view's training photograph when the scene has it (as the paper segments the
training images), else a render of the scene from the view. Depth is always rendered (the
alpha-normalised camera z of :func:`capframe.render.render`, 0 where nothing is rendered): mask
back-projection and the GrabCut depth prior need it aligned with the Gaussians. Both are computed
once per job and view (``BackendContext.shared``) and shared by every backend that asks.
"""

from __future__ import annotations

import numpy as np
import torch

from ..render import PreparedGaussians, prepare, render
from ..render.image import read_rgb
from ..scene import Camera
from .protocols import BackendContext


def _prepared(context: BackendContext) -> PreparedGaussians:
    """The scene's Gaussians prepared for rendering, once per job."""
    return context.shared("prepared-gaussians", lambda: prepare(context.scene.gaussians))


def view_image(context: BackendContext, view: int) -> np.ndarray:
    """(H, W, 3) uint8 RGB image of training view ``view``: its photograph, or a render at the
    camera's size when the scene has none."""

    def make() -> np.ndarray:
        camera = context.scene.cameras[view]
        if camera.image_path is not None:
            return read_rgb(camera.image_path, "training image")
        with torch.no_grad():
            rgb = render(_prepared(context), camera).rgb
        return (rgb.clamp(0.0, 1.0).cpu().numpy() * 255.0 + 0.5).astype(np.uint8)

    return context.shared(f"view-image:{view}", make)


def view_camera(context: BackendContext, view: int, height: int, width: int) -> Camera:
    """Training view ``view`` resized to ``width`` x ``height`` pixels."""
    return context.scene.cameras[view].resized(width, height)


def view_depth(context: BackendContext, view: int, height: int, width: int) -> np.ndarray:
    """(height, width) float32 rendered depth of training view ``view`` at that size (0 where
    nothing is rendered)."""

    def make() -> np.ndarray:
        camera = view_camera(context, view, height, width)
        with torch.no_grad():
            depth = render(_prepared(context), camera, colors=False).depth
        return depth.cpu().numpy().astype(np.float32)

    return context.shared(f"view-depth:{view}:{height}x{width}", make)
