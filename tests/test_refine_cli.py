"""capframe refine from files to files: outputs, their fields, and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_refine import FRONT, UP, blob, camera_looking, subjects_of

from capframe.cli import main
from capframe.constraints import Constraints, SubjectConstraint
from capframe.scene import read_cameras_json, write_cameras_json, write_ply
from capframe.translate.labels import labels_from_constraints, read_pseudo_labels, write_pseudo_labels


@pytest.fixture
def scene_dir(tmp_path):
    root = tmp_path / "scene"
    scene = blob()
    write_ply(scene, root / "scene.ply")
    views = [
        camera_looking((2.5 * np.cos(a), 2.5 * np.sin(a), 0.8), (0, 0, 0.4)) for a in np.linspace(0, 2 * np.pi, 6, endpoint=False)
    ]
    for k, view in enumerate(views):
        view.name = f"view_{k}"
    write_cameras_json(views, root / "cameras.json")
    c = Constraints([SubjectConstraint("blob", region="right", view="left")], elevation="slightly above")
    labels = labels_from_constraints(c, subjects_of(scene, {"blob": slice(None)}, {"blob": FRONT}), UP)
    write_pseudo_labels(labels, tmp_path / "labels.json")
    return root


def test_refine_writes_its_outputs(scene_dir, tmp_path):
    labels = tmp_path / "labels.json"
    assert read_pseudo_labels(labels).subjects[0].view.azimuths_deg == (-90.0,)
    out = tmp_path / "out"
    assert main(["refine", str(scene_dir), "--labels", str(labels), "--init", "view_1", "-o", str(out), "--long-side", "64"]) == 0
    result = json.loads((out / "result.json").read_text())
    assert np.asarray(result["T_cw"]).shape == (4, 4) and np.asarray(result["K"]).shape == (3, 3)
    assert (result["width"], result["height"]) == (64, 48)
    assert result["stop_reason"] in ("satisfied", "plateau", "converged", "max_iterations")
    assert set(result["timings"]) >= {"refine_s", "final_render_s", "total_s"}
    trajectory = np.load(out / "trajectory.npz")
    poses = trajectory["poses"]
    assert (
        poses.shape[1:] == (4, 4)
        and result["iterations"] + 1 <= len(poses) <= result["iterations"] + 2
        and np.isfinite(poses).all()
    )
    # The start is the asked view orbited about the world up through the subject (the yaw scan):
    # the subject keeps its place in the camera frame and the camera stays level.
    init, centroid = read_cameras_json(scene_dir / "cameras.json")[1].T_cw, read_pseudo_labels(labels).subjects[0].centroid
    assert np.allclose(poses[0][:3, :3] @ centroid + poses[0][:3, 3], init[:3, :3] @ centroid + init[:3, 3])
    assert abs(poses[0][0, :3] @ UP) < 1e-9
    assert any(np.allclose(pose, result["T_cw"]) for pose in poses)  # returns the best pose visited
    lines = (out / "losses.csv").read_text().splitlines()
    assert lines[0].startswith("iteration,loss") and len(lines) == len(poses) + 1
    for name in ("render.png", "camera.json", "path.png"):
        assert (out / name).stat().st_size > 0


def test_refine_bad_input_is_one_line_and_writes_nothing(scene_dir, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["refine", str(scene_dir), "--labels", str(tmp_path / "labels.json"), "--init", "view_9", "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "view_9" in err and "view_" in err.split("closest")[1]
    assert not out.exists()
    (tmp_path / "broken.json").write_text("{}")
    code = main(["refine", str(scene_dir), "--labels", str(tmp_path / "broken.json"), "--init", "view_1", "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "broken.json" in err and not out.exists()
