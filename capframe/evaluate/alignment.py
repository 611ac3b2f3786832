"""Ground-truth alignment of recovered cameras (synthetic scenes, evaluation only).

``capframe colmap`` leaves the cameras in COLMAP's arbitrary world and never sees the ground
truth; ``capframe align-truth`` (:func:`align_truth_command`) maps its output into a synthetic
scene's world and adds that scene's Gaussians, so the method can run on recovered poses and the
pose errors can be reported.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pycolmap

from ..errors import InputError
from ..scene import Camera
from ..scene._io import atomic_directory, read_json, write_json
from ..scene.colmap import read_colmap
from ..scene.sfm import MIN_REGISTERED, align_cameras, pose_errors, umeyama_sim3, write_posed_scene
from .ground_truth import ground_truth_cameras, read_ground_truth

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


def align_truth_command(recovered_dir: str | Path, truth_dir: str | Path, out_dir: str | Path) -> dict:
    """``capframe align-truth``: ``capframe colmap``'s output mapped into the ground-truth world.

    Reads ``recovered_dir`` (``sparse/0``, ``images/``, ``colmap.json``), aligns its cameras and
    model with :func:`align_to_ground_truth` against ``truth_dir`` (a synthetic scene), and writes
    ``out_dir`` as a complete posed scene: the aligned ``cameras.json``, ``sparse/0`` and
    ``images/``, the ground truth's :data:`ALIGNED_SCENE_FILES` hard-linked (or copied), and
    ``colmap.json``: the recovered record plus the alignment and pose errors. ``out_dir`` is written
    whole or not at all. Prints the pose errors and returns the record.
    """
    recovered_dir, truth_dir, out_dir = Path(recovered_dir), Path(truth_dir), Path(out_dir)
    missing = [name for name in ALIGNED_SCENE_FILES if not (truth_dir / name).is_file()]
    if missing:
        raise InputError(f"no {', '.join(missing)}: only a synthetic scene has a ground truth to align to", source=str(truth_dir))
    record_file = recovered_dir / "colmap.json"
    if not record_file.is_file():
        raise InputError("no colmap.json: expected the output directory of capframe colmap", source=str(recovered_dir))
    record = read_json(record_file)
    sparse_dir = recovered_dir / "sparse" / "0"
    cameras = read_colmap(sparse_dir, recovered_dir / "images")
    reconstruction = pycolmap.Reconstruction()
    reconstruction.read_binary(str(sparse_dir))
    aligned, (s, R, t), alignment = align_to_ground_truth(cameras, truth_dir)
    reconstruction.transform(pycolmap.Sim3d(s, pycolmap.Rotation3d(R), t))
    record = {**record, "aligned_to_ground_truth": True, **alignment}
    with atomic_directory(out_dir) as tmp:
        write_posed_scene(tmp, aligned, reconstruction, str(recovered_dir))
        for name in ALIGNED_SCENE_FILES:
            _link_or_copy(truth_dir / name, tmp / name)
        write_json(tmp / "colmap.json", record)
    rot, pos = record["rotation_error_deg"], record["position_error_rel"]
    print(
        f"{out_dir}: aligned to the ground truth of {truth_dir}: rotation error mean {rot['mean']:.3f} deg, "
        f"max {rot['max']:.3f} deg; position error mean {100 * pos['mean']:.3f} %, max {100 * pos['max']:.3f} % "
        "of the scene scale"
    )
    return record


def _link_or_copy(src: Path, dst: Path) -> None:
    """Hard-link ``src`` to ``dst`` (no copy of a large PLY), copying across file systems."""
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)
