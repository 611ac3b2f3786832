"""Baselines: IVS and SVS candidates and selection, the SplaTraj-style optimiser, ``capframe baseline``."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import torch
from _synth_helpers import aim_camera, build_scene, obj

from capframe.baselines import SplaTrajConfig, interpolate_pose, ivs_candidates, splatraj_pose, svs_candidates
from capframe.baselines.candidates import SVS_DISTANCE, fit_distance
from capframe.baselines.scoring import best_candidate
from capframe.cli import main
from capframe.evaluate.check import read_result_camera
from capframe.geometry import camera_roll, quat_to_rotmat, rotation_angle_deg, rotmat_to_quat, so3_exp
from capframe.refine.losses import soft_centroid
from capframe.render import render
from capframe.scene import Camera, SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta
from capframe.translate.labels import PseudoLabels, SubjectLabel

INSTRUCTION = "a medium shot of the teddy bear on the right of the frame, seen from its front, from slightly above"
f64 = dict(dtype=torch.float64)


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("baselines") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root, gt


def _pose(rotation: list[float], centre: list[float]) -> torch.Tensor:
    T = torch.eye(4, **f64)
    T[:3, :3] = so3_exp(torch.tensor(rotation, **f64))
    T[:3, 3] = -T[:3, :3] @ torch.tensor(centre, **f64)
    return T


def _slerp(q0: torch.Tensor, q1: torch.Tensor, t: float) -> torch.Tensor:
    """Textbook quaternion SLERP along the shorter arc."""
    if q0 @ q1 < 0:
        q1 = -q1
    angle = torch.arccos((q0 @ q1).clamp(-1.0, 1.0))
    return (torch.sin((1 - t) * angle) * q0 + torch.sin(t * angle) * q1) / torch.sin(angle)


def test_interpolation_hits_the_endpoints_and_the_slerp_midpoint():
    T_a, T_b = _pose([0.3, -1.2, 0.4], [1.0, 2.0, -3.0]), _pose([-2.0, 0.5, 1.1], [4.0, -1.0, 0.5])
    T = interpolate_pose(T_a, T_b, torch.tensor([0.0, 0.5, 1.0], **f64))
    torch.testing.assert_close(T[0], T_a, atol=1e-12, rtol=0)
    torch.testing.assert_close(T[2], T_b, atol=1e-12, rtol=0)
    mid = T[1, :3, :3]
    expected = quat_to_rotmat(_slerp(rotmat_to_quat(T_a[:3, :3]), rotmat_to_quat(T_b[:3, :3]), 0.5))
    torch.testing.assert_close(mid, expected, atol=1e-12, rtol=0)
    half = rotation_angle_deg(T_a[:3, :3], T_b[:3, :3]) / 2
    torch.testing.assert_close(rotation_angle_deg(T_a[:3, :3], mid), half)
    torch.testing.assert_close(rotation_angle_deg(mid, T_b[:3, :3]), half)
    # The camera centre moves on the segment between the two centres.
    torch.testing.assert_close(-mid.T @ T[1, :3, 3], torch.tensor([2.5, 0.5, -1.25], **f64), atol=1e-12, rtol=0)


def test_interpolated_rotations_are_orthonormal_even_near_a_half_turn():
    T_a, T_b = _pose([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]), _pose([0.0, math.pi - 1e-7, 0.0], [1.0, 1.0, 1.0])
    R = interpolate_pose(T_a, T_b, torch.linspace(0, 1, 9, **f64))[:, :3, :3]
    torch.testing.assert_close(R @ R.transpose(-1, -2), torch.eye(3, **f64).expand(9, 3, 3), atol=1e-12, rtol=0)
    torch.testing.assert_close(torch.linalg.det(R), torch.ones(9, **f64))
    torch.testing.assert_close(R[-1], T_b[:3, :3], atol=1e-9, rtol=0)


def test_ivs_has_the_views_plus_three_poses_per_pair_and_picks_the_best(scene_dir):
    cameras = load_scene_dir(scene_dir[0]).cameras
    L = len(cameras)
    candidates = ivs_candidates(cameras)
    assert len(candidates) == L + 3 * L * (L - 1) // 2
    assert [c.name for c in candidates[:L]] == [c.name for c in cameras]
    assert candidates[L].name == f"{cameras[0].name}~{cameras[1].name}@0.25"
    np.testing.assert_allclose(candidates[L + 1].center, (cameras[0].center + cameras[1].center) / 2, atol=1e-12)
    # The selection is the scorer's argmax (the first of equals).
    target = candidates[17].center
    best, scores = best_candidate(candidates, lambda cams: np.array([-np.linalg.norm(c.center - target) for c in cams]))
    assert best == 17 and scores.shape == (len(candidates),)
    assert best_candidate(candidates, lambda cams: np.ones(len(cams)))[0] == 0


def test_svs_samples_lie_in_the_paper_ranges_and_look_at_the_centre():
    up = np.array([0.3, -0.2, 0.9])
    up /= np.linalg.norm(up)
    centre, radius = np.array([5.0, -3.0, 10.0]), 0.7
    camera = Camera(np.eye(4), np.array([[140.0, 0, 80], [0, 140.0, 60], [0, 0, 1]]), 160, 120)
    cameras = svs_candidates(centre, radius, up, camera, 300, seed=3)
    d = fit_distance(radius, camera)
    assert math.degrees(math.asin(radius / d)) == pytest.approx(math.degrees(math.atan(60 / 140)))  # fits the narrower side
    offsets = np.stack([c.center for c in cameras]) - centre
    distance = np.linalg.norm(offsets, axis=1)
    assert distance.min() >= SVS_DISTANCE[0] * d - 1e-9 and distance.max() <= SVS_DISTANCE[1] * d + 1e-9
    elevation = np.degrees(np.arcsin(offsets @ up / distance))
    assert elevation.min() >= -70.0 and elevation.max() <= 90.0 and elevation.min() < -50.0 and elevation.max() > 70.0
    for c in cameras:
        forward = c.R[2]
        np.testing.assert_allclose(forward, (centre - c.center) / np.linalg.norm(centre - c.center), atol=1e-9)
        if abs(forward @ up) < 0.99:
            assert abs(float(camera_roll(torch.from_numpy(c.T_cw), torch.from_numpy(up)))) < 1e-9
        np.testing.assert_array_equal(c.K, camera.K)
    again = svs_candidates(centre, radius, up, camera, 300, seed=3)
    assert all(np.array_equal(a.T_cw, b.T_cw) for a, b in zip(cameras, again))
    assert not np.array_equal(svs_candidates(centre, radius, up, camera, 300, seed=4)[0].T_cw, cameras[0].T_cw)


def test_splatraj_reduces_its_loss_and_centres_the_subject(scene_dir):
    root, gt = scene_dir
    scene = load_scene_dir(root)
    bear = obj(gt, "teddy bear")
    members = scene.gaussians.labels == bear["label"]
    index = torch.nonzero(members)[:, 0].numpy()
    centroid = scene.gaussians.means[index].double().mean(0).numpy()
    labels = PseudoLabels([SubjectLabel("teddy bear", index, centroid)], np.asarray(gt["up"]))
    start = aim_camera(gt, bear, azimuth=30, elevation=15, distance=6, point=(0.8, 0.3))

    def offset(camera: Camera) -> float:
        mask = render(scene.gaussians, camera, subset=members, colors=False, backend="torch").alpha
        xy, _ = soft_centroid(mask)
        return math.hypot(float(xy[0]) / camera.width - 0.5, float(xy[1]) / camera.height - 0.5)

    result = splatraj_pose(scene.gaussians, start, labels, gt["scale"], SplaTrajConfig(iterations=120))
    assert result.iterations <= 120 and np.isfinite(result.losses).all()
    assert result.losses.min() < 0.5 * result.losses[0]
    assert offset(start.with_pose(result.T_cw)) < 0.3 * offset(start)
    assert set(result.terms) == {"center", "area", "upright"}


@pytest.mark.parametrize("method", ["ivs", "svs", "splatraj"])
def test_cli_writes_a_result_that_check_reads(scene_dir, tmp_path, method, capsys):
    root, _ = scene_dir
    out = tmp_path / method
    assert main(["baseline", method, str(root), INSTRUCTION, "-o", str(out), "--cache", str(tmp_path / "cache"), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    result = json.loads((out / "result.json").read_text())
    assert result["method"] == method and printed["T_cw"] == result["T_cw"]
    assert (out / "render.png").is_file() and (out / "camera.json").is_file()
    assert 0.0 <= result["score"] <= 100.0 and result["timings"]["total_s"] > 0
    assert result["search"]["candidates" if method != "splatraj" else "iterations"] > 0
    camera, _ = read_result_camera(out / "result.json")
    np.testing.assert_allclose(camera.T_cw, result["T_cw"])
    from capframe.translate.instruction import ParsedInstruction

    constraints = tmp_path / "constraints.json"
    constraints.write_text(json.dumps(ParsedInstruction.from_dict(result["instruction"]).constraints().to_dict()))
    assert main(["check", str(root), str(out / "result.json"), "--constraints", str(constraints), "--json"]) == 0
    assert "all_satisfied" in json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(
    "argv, message",
    [
        (
            ["baseline", "orbit", "{scene}", INSTRUCTION, "-o", "{out}"],
            "baseline 'orbit' is unknown; available: ivs, svs, splatraj, chatcam",
        ),
        (["baseline", "ivs", "{missing}", INSTRUCTION, "-o", "{out}"], "missing"),
    ],
)
def test_bad_input_is_one_line(scene_dir, tmp_path, capsys, argv, message):
    paths = {"scene": str(scene_dir[0]), "out": str(tmp_path / "out"), "missing": str(tmp_path / "missing")}
    assert main([a.format(**paths) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("capframe: error:") and message in err
    assert not (tmp_path / "out").exists()
