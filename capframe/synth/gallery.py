"""Picture sheets of the synthetic material, for people to look at (docs/objects.png,
docs/contact_sheet.png): every catalog object from the front, its right side and the back, and a
grid of training views of a few generated scenes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageDraw

from ..geometry import look_at, view_direction
from ..render import render
from ..scene import Camera, GaussianScene
from .objects import BuiltObject, ObjectGaussians, build_object, catalog_names

VIEWS = {"front": 0.0, "right side": 90.0, "back": 180.0}


def gaussians_to_scene(g: ObjectGaussians, extra_labels: np.ndarray | None = None) -> GaussianScene:
    """A float32 :class:`GaussianScene` of an object's Gaussians (colours as SH degree 0)."""
    t = lambda a: torch.from_numpy(np.ascontiguousarray(a)).to(torch.float32)  # noqa: E731
    labels = None if extra_labels is None else torch.from_numpy(extra_labels.astype(np.int64))
    return GaussianScene.from_activated(t(g.means), t(g.quats), t(g.scales), t(g.opacities), t(g.lit()), labels)


def object_camera(
    obj: BuiltObject, azimuth_deg: float, elevation_deg: float = 15.0, size=(160, 120), fov_deg: float = 40.0, fill: float = 0.8
) -> Camera:
    """A camera at the given view angles around an object in its local frame (front +x, up +z),
    far enough that its bounding sphere fills ``fill`` of the image height."""
    f64 = dict(dtype=torch.float64)
    up, front = torch.tensor([0.0, 0.0, 1.0], **f64), torch.tensor([1.0, 0.0, 0.0], **f64)
    direction = view_direction(
        torch.tensor(math.radians(azimuth_deg), **f64), torch.tensor(math.radians(elevation_deg), **f64), front, up
    )
    width, height = size
    focal = (height / 2) / math.tan(math.radians(fov_deg) / 2)
    distance = obj.radius / math.sin(math.atan(fill * height / 2 / focal))
    center = torch.from_numpy(obj.center)
    T = look_at(center + distance * direction, center, up)
    K = np.array([[focal, 0.0, width / 2], [0.0, focal, height / 2], [0.0, 0.0, 1.0]])
    return Camera(T.numpy(), K, width, height, name=f"az{azimuth_deg:+.0f}")


def _to_image(rgb: torch.Tensor) -> Image.Image:
    return Image.fromarray((rgb.clamp(0, 1).numpy() * 255.0 + 0.5).astype(np.uint8))


def _label(image: Image.Image, text: str) -> Image.Image:
    draw = ImageDraw.Draw(image)
    draw.rectangle([0, 0, image.width, 12], fill=(255, 255, 255))
    draw.text((3, 0), text, fill=(0, 0, 0))
    return image


def object_gallery(
    path: str | Path, names: list[str] | None = None, *, tile=(200, 150), seed: int = 0, density: float = 1.0, columns: int = 2
) -> Path:
    """Render every catalog object (or ``names``) from the front, its right side and the back and
    save a labelled grid PNG at ``path``."""
    names = names or catalog_names()
    tiles = []
    for i, name in enumerate(names):
        obj = build_object(name, seed=seed + i, density=density)
        scene = gaussians_to_scene(obj.gaussians)
        row = []
        for view, azimuth in VIEWS.items():
            with torch.no_grad():
                out = render(scene, object_camera(obj, azimuth, size=tile), background=(0.82, 0.84, 0.86))
            row.append(_label(_to_image(out.rgb), f"{obj.color} {name}: {view}"))
        tiles.append(row)
    return _save_grid(tiles, path, columns)


def _save_grid(rows: list[list[Image.Image]], path: str | Path, columns: int = 1) -> Path:
    """Lay out rows of equal-size tiles, ``columns`` rows side by side, and save as PNG."""
    tw, th = rows[0][0].size
    per = len(rows[0])
    blocks = math.ceil(len(rows) / columns)
    sheet = Image.new("RGB", (columns * per * tw + (columns - 1) * 6, blocks * th), (255, 255, 255))
    for k, row in enumerate(rows):
        bx, by = k // blocks, k % blocks
        for j, image in enumerate(row):
            sheet.paste(image, (bx * (per * tw + 6) + j * tw, by * th))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(path)
    return path


def contact_sheet(scene_dirs: list[str | Path], path: str | Path, *, per_scene: int = 6, tile=(200, 150)) -> Path:
    """A grid with ``per_scene`` evenly spaced training images of each scene directory."""
    rows = []
    for root in scene_dirs:
        images = sorted((Path(root) / "images").glob("*.png"))
        picks = [images[round(k * (len(images) - 1) / max(per_scene - 1, 1))] for k in range(min(per_scene, len(images)))]
        row = [_label(Image.open(p).convert("RGB").resize(tile, Image.BILINEAR), f"{Path(root).name}/{p.stem}") for p in picks]
        row += [Image.new("RGB", tile, (255, 255, 255))] * (per_scene - len(row))
        rows.append(row)
    return _save_grid(rows, path, 1)


__all__ = ["object_gallery", "contact_sheet", "object_camera", "gaussians_to_scene"]
