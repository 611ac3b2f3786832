"""Ground-truth alignment of recovered cameras (synthetic scenes, evaluation only): ``capframe
colmap --align-ground-truth`` hands :func:`align_to_ground_truth` to the COLMAP stage, which
otherwise never sees the ground truth."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..scene import Camera
from ..scene.sfm import MIN_REGISTERED, align_cameras, pose_errors, umeyama_sim3
from .ground_truth import read_ground_truth
from .oracle import ground_truth_cameras

# What a synthetic scene carries besides its photos; linked into the aligned scene.
ALIGNED_SCENE_FILES = ("scene.ply", "semantics.json", "labels.npy", "ground_truth.json")


def align_to_ground_truth(cameras: list[Camera], scene_dir: str | Path) -> tuple[list[Camera], tuple, dict]:
    """Map recovered cameras into a synthetic scene's ground-truth world (evaluation only).

    The similarity is :func:`umeyama_sim3` from the recovered camera centres to the true centres
    of the same-named views in ``scene_dir/ground_truth.json``. Returns the aligned cameras,
    ``(s, R, t)``, and the record for ``colmap.json``: the alignment and :func:`pose_errors`
    against the truth, positions relative to the ground truth's scene scale.
    """
    source = str(Path(scene_dir) / "ground_truth.json")
    scale = read_ground_truth(scene_dir).scale
    truth = {c.name: c for c in ground_truth_cameras(scene_dir)}
    matched = [c for c in cameras if c.name in truth]
    if len(matched) < MIN_REGISTERED:
        raise InputError(
            f"only {len(matched)} registered views have a ground-truth camera (need at least "
            f"{MIN_REGISTERED}); the names must match the images'",
            source=source,
        )
    s, R, t = umeyama_sim3(np.array([c.center for c in matched]), np.array([truth[c.name].center for c in matched]))
    aligned = align_cameras(cameras, s, R, t)
    errors = pose_errors([c for c in aligned if c.name in truth], list(truth.values()), scale)
    record = {
        "alignment": {"scale": s, "R": R.tolist(), "t": t.tolist(), "views": len(matched)},
        "ground_truth_scale": scale,
        **errors,
    }
    return aligned, (s, R, t), record


# --- the `capframe colmap` verb ---------------------------------------------------------------------
