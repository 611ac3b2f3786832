"""Oracle pseudo labels from a synthetic scene's ground truth.

They measure Refine alone (``capframe bench refine`` and the workflow's oracle variant): the
subjects' Gaussians from the labels, their fronts and the world up from ``ground_truth.json``.
This is evaluation machinery; the method itself never reads the ground truth.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..constraints import Constraints
from ..errors import InputError
from ..scene import Camera, GaussianScene
from ..translate.labels import PseudoLabels, labels_from_constraints
from .ground_truth import GroundTruth, ground_truth_cameras


def oracle_labels(gaussians: GaussianScene, ground_truth: GroundTruth, constraints: Constraints) -> PseudoLabels:
    """Pseudo labels of ``constraints`` with every subject resolved through the ground truth."""
    if gaussians.labels is None:
        raise ValueError("oracle labels need per-Gaussian labels")
    labels = gaussians.labels.numpy()
    means = gaussians.means.detach().double().numpy()
    subjects = {}
    for subject in constraints.subjects:
        obj = ground_truth.resolve(subject.name)
        index = np.flatnonzero(labels == obj.label)
        subjects[subject.name] = (index, means[index].mean(0), obj.front)
    return labels_from_constraints(constraints, subjects, ground_truth.up)


def visible_views(cameras: list[Camera], point: np.ndarray) -> list[Camera]:
    """Cameras that image ``point`` in front of them and inside their frame."""
    out = []
    for camera in cameras:
        q = camera.R @ point + camera.t
        if q[2] <= 0:
            continue
        u, v = (camera.K @ (q / q[2]))[:2]
        if 0 <= u < camera.width and 0 <= v < camera.height:
            out.append(camera)
    return out


def initial_view(scene_dir: str | Path, ground_truth: GroundTruth, constraints: Constraints, instruction_id: str) -> Camera:
    """A training view that shows the primary subject, drawn with a seed derived from the
    instruction id: a fixed, not the best, starting point for Refine."""
    import zlib

    primary = ground_truth.resolve(constraints.subjects[0].name)
    cameras = ground_truth_cameras(scene_dir)
    if not cameras:
        raise InputError("ground_truth.json lists no training cameras", source=str(Path(scene_dir) / "ground_truth.json"))
    return start_view(cameras, primary.center, zlib.crc32(instruction_id.encode()))


def start_view(cameras: list[Camera], point: np.ndarray, seed: int) -> Camera:
    """One of the cameras that image ``point`` in frame, drawn with ``seed``; when none does (a
    subject outside every training frame), the camera whose optical axis is closest to it."""
    views = visible_views(cameras, point)
    if not views:
        return min(cameras, key=lambda c: _angle_off_axis(c, point))
    return views[int(np.random.default_rng(seed).integers(len(views)))]


def _angle_off_axis(camera: Camera, point: np.ndarray) -> float:
    """Angle (radians) between the camera's optical axis and the ray to ``point``."""
    q = camera.R @ point + camera.t
    return float(np.arccos(np.clip(q[2] / max(np.linalg.norm(q), 1e-300), -1.0, 1.0)))


def oracle_command(scene_dir: str | Path, constraints_path: str | Path, instruction_id: str, out_dir: str | Path) -> None:
    """Write ``labels.json`` (oracle pseudo labels) and ``init.json`` (:func:`initial_view`) for
    one instruction."""
    from ..evaluate.check import load_constraints
    from ..scene import load_scene_dir, write_camera_json
    from ..translate.labels import write_pseudo_labels
    from .ground_truth import read_ground_truth

    _, _, constraints = load_constraints(constraints_path, instruction_id)
    scene = load_scene_dir(scene_dir)
    gt = read_ground_truth(scene_dir)
    out = Path(out_dir)
    write_pseudo_labels(oracle_labels(scene.gaussians, gt, constraints), out / "labels.json")
    write_camera_json(initial_view(scene_dir, gt, constraints, instruction_id), out / "init.json")
