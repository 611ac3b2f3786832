"""Captured 3DGS objects as catalog entries (``config/captured.yaml``).

A captured object is a real 3DGS file (``../shared/data/real``, read at synth time and never
copied into the repository) brought into the catalog's local frame (up = +z, front = +x, base on
z = 0, metres), in four steps:

1. **clean**: keep the largest connected cluster of Gaussians (:func:`capframe.scene.stats.floater_mask`);
2. **thin**: keep the ``target * density`` Gaussians of largest ``opacity * s1 * s2`` (the two
   largest standard deviations: the splat's footprint), which carry nearly all of the rendered
   colour; the faint, tiny remainder costs render time and shows little;
3. **upright**: turn the file's up axis onto +z, then its front azimuth onto +x;
4. **scale**: to the annotated real height or width of the kept means (between their 0.5 %
   and 99.5 % quantiles per axis, :func:`robust_box`), so the size holds at any density.

Colours are the SH DC term (synthetic scenes are SH degree 0); the capture's lighting is already
in them. Run ``python -m capframe.synth.captured --views DIR`` to render every entry from four
sides (how the up axes and fronts in the file were checked).
"""

from __future__ import annotations

import argparse
import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
import yaml

from ..errors import InputError
from ..geometry import quat_multiply, quat_to_rotmat, rotmat_to_quat
from ..scene import read_gaussians
from ..scene.model import SH_C0
from ..scene.stats import floater_mask

REPO_ROOT = Path(__file__).resolve().parents[2]
CONFIG = REPO_ROOT / "config" / "captured.yaml"
_AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1), "-z": (0, 0, -1)}
BOX_QUANTILE = 0.005  # the size is measured between these quantiles of the means
_FIELDS = ("name", "aliases", "file", "up", "front_deg", "size_m", "measure", "color", "target", "credits")


@dataclass(frozen=True)
class CapturedSource:
    """One entry of ``config/captured.yaml`` (fields documented at the top of that file);
    ``path`` is the resolved file."""

    name: str
    aliases: tuple[str, ...]
    path: Path
    up: str
    front_deg: float | None
    size_m: float
    measure: str
    color: str
    target: int
    credits: str


def _entry(raw: object, where: str, root: Path) -> CapturedSource:
    if not isinstance(raw, dict) or set(raw) != set(_FIELDS):
        fields = sorted(raw) if isinstance(raw, dict) else type(raw).__name__
        raise InputError(f"{where}: fields {fields}; expected exactly {', '.join(_FIELDS)}")
    if raw["up"] not in _AXES:
        raise InputError(f"{where}.up: {raw['up']!r}; expected one of {', '.join(_AXES)}")
    if raw["measure"] not in ("height", "width"):
        raise InputError(f"{where}.measure: {raw['measure']!r}; expected height or width")
    size, target = raw["size_m"], raw["target"]
    if not (isinstance(size, (int, float)) and size > 0) or not (isinstance(target, int) and target > 0):
        raise InputError(f"{where}: size_m {size!r}, target {target!r}; expected positive numbers")
    front = raw["front_deg"]
    return CapturedSource(
        name=str(raw["name"]),
        aliases=tuple(str(a) for a in raw["aliases"]),
        path=root / str(raw["file"]),
        up=raw["up"],
        front_deg=None if front is None else float(front),
        size_m=float(size),
        measure=raw["measure"],
        color=str(raw["color"]),
        target=target,
        credits=str(raw["credits"]),
    )


def load_captured(path: str | Path = CONFIG) -> list[CapturedSource]:
    """The entries of a captured-objects file (default ``config/captured.yaml``); its ``root`` is
    relative to the repository root. :class:`InputError` naming the file and field when malformed."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as err:
        raise InputError(f"cannot read the captured objects: {err}", source=str(path)) from None
    if not isinstance(data, dict) or not isinstance(data.get("objects"), list) or "root" not in data:
        raise InputError("expected a mapping with 'root' and a list 'objects'", source=str(path))
    root = (REPO_ROOT / str(data["root"])).resolve()
    return [_entry(raw, f"{path}: objects[{i}]", root) for i, raw in enumerate(data["objects"])]


def upright_rotation(up: str, front_deg: float | None) -> np.ndarray:
    """(3, 3) rotation taking the file axis ``up`` to +z, then the front azimuth to +x."""
    u = np.asarray(_AXES[up], dtype=np.float64)
    # A proper rotation taking u to z: the axis u x z by the angle between them (a half turn
    # about x when u = -z).
    axis = np.cross(u, [0.0, 0.0, 1.0])
    if np.linalg.norm(axis) < 1e-9:
        R_up = np.eye(3) if u[2] > 0 else np.diag([1.0, -1.0, -1.0])
    else:
        k = axis / np.linalg.norm(axis)
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R_up = np.eye(3) + K + K @ K  # sin = 1, 1 - cos = 1: a quarter turn
    a = -math.radians(front_deg or 0.0)
    R_yaw = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])
    return R_yaw @ R_up


@functools.lru_cache(maxsize=8)
def _decoded(path: Path):
    """The file's Gaussians, cleaned: (means, quats, scales, opacities, rgb) float64 numpy, and
    the fraction of Gaussians the floater rule removed."""
    if not path.is_file():
        raise InputError(
            "captured object file not found; the captured catalog objects read ../shared/data/real (see config/captured.yaml)",
            source=str(path),
        )
    g = read_gaussians(path)
    means = g.means.double().numpy()
    keep = floater_mask(means)
    rgb = np.clip(0.5 + SH_C0 * g.sh[:, 0].double().numpy(), 0.0, 1.0)
    arrays = (means, g.quats.double().numpy(), g.scales.double().numpy(), g.opacities.double().numpy(), rgb)
    return tuple(a[keep] for a in arrays), float(1.0 - keep.mean())


def captured_arrays(source: CapturedSource, density: float = 1.0) -> dict[str, np.ndarray]:
    """The captured object in the catalog frame (up +z, front +x, base on z = 0, metres).

    Returns float64 arrays ``means`` (K, 3), ``quats`` (K, 4) wxyz, ``scales`` (K, 3),
    ``opacities`` (K,), ``rgb`` (K, 3) and ``normals`` (K, 3) (each splat's thinnest axis), with
    K = min(N, round(target * density)) of the N cleaned Gaussians.
    """
    (means, quats, scales, opacities, rgb), _ = _decoded(source.path)
    keep = min(len(means), max(1, round(source.target * density)))
    area = opacities * np.prod(np.sort(scales, axis=1)[:, 1:], axis=1)
    pick = np.sort(np.argsort(-area, kind="stable")[:keep])  # a ranking no turn or scale changes
    R = upright_rotation(source.up, source.front_deg)
    means = means[pick] @ R.T
    lo, hi = robust_box(means)
    extent = hi[2] - lo[2] if source.measure == "height" else float(np.max(hi[:2] - lo[:2]))
    factor = source.size_m / extent
    q = quat_multiply(rotmat_to_quat(torch.from_numpy(R)).expand(keep, 4), torch.from_numpy(quats[pick])).numpy()
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    rot = quat_to_rotmat(torch.from_numpy(q)).numpy()
    normals = rot[np.arange(keep), :, np.argmin(scales[pick], axis=1)]
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, 0.0])
    return {
        "means": (means - centre) * factor,
        "quats": q,
        "scales": scales[pick] * factor,
        "opacities": opacities[pick],
        "rgb": rgb[pick],
        "normals": normals,
    }


def robust_box(means: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Corners (3,), (3,) of the box between the 0.5 % and 99.5 % quantiles of the (N, 3) means
    per axis: the object's size, unmoved by the faint outermost splats that thinning drops."""
    return np.quantile(means, BOX_QUANTILE, axis=0), np.quantile(means, 1.0 - BOX_QUANTILE, axis=0)


def floater_fraction(source: CapturedSource) -> float:
    """Fraction of the file's Gaussians the floater rule removes."""
    return _decoded(source.path)[1]


def _render_views(out_dir: Path) -> None:
    """Render every captured entry from azimuths 0, 90, 180, 270 (15 degrees up) to ``out_dir``."""
    from PIL import Image

    from ..geometry import look_at
    from ..render import render
    from ..scene import Camera, GaussianScene

    out_dir.mkdir(parents=True, exist_ok=True)
    for source in load_captured():
        a = captured_arrays(source)
        f32 = lambda v: torch.from_numpy(np.ascontiguousarray(v, dtype=np.float32))  # noqa: E731
        scene = GaussianScene.from_activated(*(f32(a[k]) for k in ("means", "quats", "scales", "opacities", "rgb")))
        centre = (a["means"].min(0) + a["means"].max(0)) / 2
        radius = float(np.linalg.norm(a["means"].max(0) - a["means"].min(0))) / 2
        tiles = []
        for azimuth in (0.0, 90.0, 180.0, 270.0):
            az, el = math.radians(azimuth), math.radians(15.0)
            eye = centre + 2.6 * radius * np.array([math.cos(az) * math.cos(el), math.sin(az) * math.cos(el), math.sin(el)])
            T = look_at(torch.from_numpy(eye), torch.from_numpy(centre), torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64))
            cam = Camera(T.numpy(), np.array([[200.0, 0, 100], [0, 200.0, 100], [0, 0, 1]]), 200, 200)
            with torch.no_grad():
                rgb = render(scene, cam, background=(1.0, 1.0, 1.0)).rgb.clamp(0, 1).numpy()
            tiles.append((rgb * 255 + 0.5).astype(np.uint8))
        Image.fromarray(np.concatenate(tiles, axis=1)).save(out_dir / f"{source.name.replace(' ', '_')}.png")
        print(f"{source.name}: {len(a['means'])} Gaussians kept, floaters removed {floater_fraction(source):.4%}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="Render the captured catalog objects from 4 sides (azimuth 0, 90, 180, 270).")
    parser.add_argument("--views", type=Path, required=True, help="output folder for the PNGs")
    _render_views(parser.parse_args().views)
