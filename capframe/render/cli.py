"""``capframe render``: one view of a scene from a camera file."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..scene import load_scene_dir, read_camera_json, read_ply
from . import check_render_memory, render
from .image import save_image


def render_command(scene: str, camera_path: str, output: str, *, backend: str = "auto", long_side: int | None = None) -> None:
    """Render ``scene`` (a scene directory or a 3DGS PLY file) from ``camera_path`` (camera.json)
    to the image ``output`` (JPEG for ``.jpg``/``.jpeg``, else PNG); the background is black."""
    camera = read_camera_json(camera_path)
    if long_side is not None:
        camera = camera.with_long_side(long_side)
    check_render_memory(camera, source=camera_path)
    source = Path(scene)
    if source.is_dir():
        gaussians = load_scene_dir(source).gaussians
        if gaussians is None:
            raise InputError("scene directory has no scene.ply to render", source=str(source))
    elif source.suffix.lower() == ".ply":
        gaussians = read_ply(source)
    else:
        raise InputError("expected a scene directory or a .ply file", source=str(source))
    out = render(gaussians, camera, backend=backend)
    save_image(out.rgb, output)
