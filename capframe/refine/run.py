"""One refinement from files to files: ``capframe refine``.

Reads a scene directory, pseudo labels and an initial camera; writes into the output folder
(atomically, as one folder):

* ``result.json``: final ``T_cw`` (4x4), ``K``, width, height, iterations, stop reason, loss terms
  at the final pose, per-stage wall times and the device;
* ``render.png``: the final frame at full resolution;
* ``camera.json``: the final camera (capframe format);
* ``trajectory.npz``: pose per iteration (``poses``), total loss (``loss``) and each loss term;
* ``losses.csv``: the loss curves;
* ``path.png``: top view of the camera path (along the world up) with the subjects.
"""

from __future__ import annotations

import dataclasses
import platform
import time
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageDraw

from ..errors import InputError
from ..render import render, scene_extent
from ..render.image import save_png
from ..scene import Camera, load_scene_dir, read_camera_json, write_camera_json
from ..scene._io import atomic_directory, write_json
from ..translate.labels import PseudoLabels, read_pseudo_labels
from .optimize import RefineConfig, RefineResult, refine_pose


def scene_scale(cameras: list[Camera], means: torch.Tensor) -> float:
    """Scene scale ``s`` (DESIGN §3): the median distance from the training cameras to the scene
    centre (the median of the Gaussian means); the Gaussians' own extent without cameras."""
    if not cameras:
        return scene_extent(means.detach())
    centre = means.detach().median(0).values.double().numpy()
    return float(np.median([np.linalg.norm(c.center - centre) for c in cameras]))


def initial_camera(scene_cameras: list[Camera], init: str) -> Camera:
    """A camera.json path or the name of a training view."""
    if Path(init).is_file():
        return read_camera_json(init)
    for camera in scene_cameras:
        if camera.name == init:
            return camera
    import difflib

    close = difflib.get_close_matches(init, [c.name for c in scene_cameras], n=3)
    raise InputError(f"--init {init!r} is neither a camera.json nor a training view; closest views: {close}")


def refine_to_dir(
    scene_dir: str | Path, labels_path: str | Path, init: str, out_dir: str | Path, config: RefineConfig | None = None
) -> RefineResult:
    config = config or RefineConfig()
    t0 = time.perf_counter()
    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None:
        raise InputError("scene has no scene.ply to refine against", source=str(scene_dir))
    labels = read_pseudo_labels(labels_path)
    camera = initial_camera(scene.cameras, init)
    scale = scene_scale(scene.cameras, scene.gaussians.means)
    t_load = time.perf_counter()
    result = refine_pose(scene.gaussians, camera, labels, scale, config)
    final = camera.with_pose(result.T_cw)
    t_render = time.perf_counter()
    image = render(scene.gaussians, final, backend="auto").rgb
    timings = {"load_s": t_load - t0, "refine_s": result.seconds, "final_render_s": time.perf_counter() - t_render}
    timings["total_s"] = time.perf_counter() - t0
    with atomic_directory(out_dir) as tmp:
        write_refine_outputs(tmp, final, result, labels, config, timings, image)
    return result


def write_camera_result(out: Path, camera: Camera, image: torch.Tensor, fields: dict) -> dict:
    """The files of every method's result folder, what ``capframe check`` and the image grid read:
    ``result.json`` (the camera's ``T_cw``, ``K``, ``width``, ``height``, then ``fields``),
    ``camera.json`` and ``render.png`` (``image``: (H, W, 3) in [0, 1]). Returns ``result.json``'s
    content."""
    summary = {"T_cw": camera.T_cw.tolist(), "K": camera.K.tolist(), "width": camera.width, "height": camera.height, **fields}
    write_json(out / "result.json", summary)
    write_camera_json(camera, out / "camera.json")
    save_png(image, out / "render.png")
    return summary


def write_refine_outputs(
    out: Path,
    camera: Camera,
    result: RefineResult,
    labels: PseudoLabels,
    config: RefineConfig,
    timings: dict,
    image: torch.Tensor,
    extra: dict | None = None,
) -> None:
    """Write the files listed in the module docstring into ``out``; ``extra`` adds fields to
    ``result.json``."""
    fields = {
        "iterations": result.iterations,
        "stop_reason": result.stop_reason,
        "loss_terms": result.terms,
        "loss": float(result.losses.min()),
        "timings": timings,
        "device": platform.processor() or platform.machine(),
        "threads": config.threads,
        "config": dataclasses.asdict(config),
        "subjects": [s.name for s in labels.subjects],
        **(extra or {}),
    }
    write_camera_result(out, camera, image, fields)
    np.savez_compressed(out / "trajectory.npz", poses=result.trajectory, loss=result.losses, **result.history)
    names = list(result.history)
    rows = ["iteration,loss," + ",".join(names)]
    rows += [
        f"{i},{result.losses[i]:.6g}," + ",".join(f"{result.history[n][i]:.6g}" for n in names) for i in range(len(result.losses))
    ]
    (out / "losses.csv").write_text("\n".join(rows) + "\n")
    path_plot(result.trajectory, labels).save(out / "path.png")


def path_plot(trajectory: np.ndarray, labels: PseudoLabels, size: int = 480) -> Image.Image:
    """Top view along the world up: the camera path (grey), start (blue) and end (red) frustums,
    and the subjects' centroids (green)."""
    up = labels.up / np.linalg.norm(labels.up)
    a = np.cross(up, [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(up, a)
    centres = -np.einsum("nji,nj->ni", trajectory[:, :3, :3], trajectory[:, :3, 3])
    forwards = trajectory[:, 2, :3]
    subjects = np.stack([s.centroid for s in labels.subjects])
    points = np.concatenate([centres, subjects])
    xy = np.stack([points @ a, points @ b], 1)
    lo, hi = xy.min(0), xy.max(0)
    span = max(float((hi - lo).max()), 1e-9) * 1.3
    mid = (lo + hi) / 2

    def to_px(p):
        q = (np.array([p @ a, p @ b]) - mid) / span * (size - 20) + size / 2
        return float(q[0]), float(size - q[1])

    img = Image.new("RGB", (size, size), "white")
    draw = ImageDraw.Draw(img)
    draw.line([to_px(c) for c in centres], fill=(150, 150, 150), width=2)
    for k, colour in ((0, (40, 90, 220)), (len(centres) - 1, (220, 40, 40))):
        tip = centres[k] + forwards[k] * span * 0.08
        draw.line([to_px(centres[k]), to_px(tip)], fill=colour, width=3)
        x, y = to_px(centres[k])
        draw.ellipse([x - 4, y - 4, x + 4, y + 4], fill=colour)
    for s in subjects:
        x, y = to_px(s)
        draw.ellipse([x - 6, y - 6, x + 6, y + 6], fill=(40, 170, 60))
    return img


def _is_retrieval_file(init: str) -> bool:
    import json

    if not init.endswith(".json") or not Path(init).is_file():
        return False
    try:
        return "starts" in json.loads(Path(init).read_text())
    except ValueError:
        return False


def refine_command(args) -> None:
    config = RefineConfig(iterations=args.iterations, long_side=args.long_side)
    if args.weights:
        weights = dataclasses.asdict(config.weights)
        for item in args.weights.split(","):
            key, _, value = item.partition("=")
            if key not in weights:
                raise InputError(f"--weights: unknown term {key!r}; expected one of {sorted(weights)}")
            weights[key] = float(value)
        config = dataclasses.replace(config, weights=type(config.weights)(**weights))
    if _is_retrieval_file(args.init):
        from ..ground import GroundOptions, refine_retrieved

        options = GroundOptions(candidates=args.candidates, attempts=args.attempts, refine=config)
        refine_retrieved(args.scene, args.labels, args.init, args.output, options)
    else:
        refine_to_dir(args.scene, args.labels, args.init, args.output, config)
