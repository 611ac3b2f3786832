"""The ChatCam-style baseline on a tiny random-weight CLIP: the pose gradient of its whole objective
against central differences, the optimiser raising the score, ``capframe baseline chatcam`` and
its one-line errors, and the workflow scheduling it only with a differentiable scorer configured."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import torch
from _synth_helpers import aim_camera, build_scene, obj
from test_workflow import _fake_generated_suite, _jobs, planned_outputs

from capframe.backends import BackendContext, read_models_config
from capframe.backends.scorers import ModelDiffScorer
from capframe.backends.tiny import tiny_image_text
from capframe.baselines.chatcam import ChatCamConfig, _Objective, chatcam_pose
from capframe.cli import main
from capframe.evaluate.check import read_result_camera
from capframe.geometry.lie import se3_exp
from capframe.refine.optimize import RefineConfig
from capframe.scene import SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta
from capframe.translate.instruction import ParsedInstruction

TEXT = "a photo of the teddy bear"


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    root = tmp_path_factory.mktemp("chatcam")
    gt = build_scene(root / "scene")
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene" / "scene.json")
    tiny_image_text(root / "clip", "clip")
    (root / "models.yaml").write_text("clip: {weights: clip}\n")
    return root, gt


def diff_scorer(root: Path, scene=None, double: bool = False) -> ModelDiffScorer:
    up = np.array([0.0, 0.0, 1.0]) if scene is None else np.asarray(scene.metadata.up)
    context = BackendContext(scene, up, root / "cache", read_models_config(root / "models.yaml"))
    scorer = ModelDiffScorer(context, "clip")
    if double:
        scorer.model.model.double()
    return scorer


def start(gt):
    bear = obj(gt, "teddy bear")
    return bear, aim_camera(gt, bear, azimuth=30, elevation=15, distance=6, point=(0.7, 0.4))


def test_pose_gradient_of_the_objective_matches_central_differences(setup):
    """d (1 - score(render) + upright) / d twist at a tilted start, float64 render and model: the
    whole chain pose -> Gaussians' projection -> rasteriser -> CLIP preprocessing and image tower
    -> cosine, plus the upright term. The rasteriser's cutoffs (alpha floor, transmittance stop)
    are small steps in the image: at this pose one lies within 1e-6 of the start along the pitch
    axis (a central difference there reads 0.45 against an exact 0.28), so the step is 1e-7, where
    truncation (eps^2) and rounding (1e-16 / eps) both stay below the tolerance."""
    root, gt = setup
    scene = load_scene_dir(root / "scene")
    scorer = diff_scorer(root, double=True)
    bear, camera = start(gt)
    camera = camera.with_long_side(40)
    T0 = torch.as_tensor(camera.T_cw, dtype=torch.float64)
    T0 = se3_exp(torch.tensor([0.0, 0.0, 0.2, 0.0, 0.0, 0.0], dtype=torch.float64)) @ T0  # rolled: upright acts
    up = torch.as_tensor(gt["up"], dtype=torch.float64)
    objective = _Objective(
        scene.gaussians, camera, lambda image: scorer.score(image, TEXT), torch.zeros(3), up, 2.0, torch.float64
    )

    def f(twist: torch.Tensor) -> torch.Tensor:
        return objective(se3_exp(twist) @ T0)[0]

    twist = torch.zeros(6, dtype=torch.float64, requires_grad=True)
    value = f(twist)
    (gradient,) = torch.autograd.grad(value, twist)
    assert objective(T0)[1]["upright"] > 0.1 and gradient[:3].abs().max() > 0 and gradient[3:].abs().max() > 0
    eps = 1e-7
    with torch.no_grad():
        for k in range(6):
            step = torch.zeros(6, dtype=torch.float64)
            step[k] = eps
            numeric = (f(step) - f(-step)) / (2 * eps)
            error = abs(float(gradient[k] - numeric))
            assert error <= 1e-5 * max(abs(float(numeric)), 1e-3), (k, float(gradient[k]), float(numeric))


def test_optimiser_raises_the_image_text_score(setup):
    """A few Adam steps at Refine's learning rates raise the score of the render (and the best
    pose returned is the one of the best recorded loss)."""
    root, gt = setup
    scene = load_scene_dir(root / "scene")
    scorer = diff_scorer(root)
    bear, camera = start(gt)
    centroid = scene.gaussians.means.detach().double()[scene.gaussians.labels == bear["label"]].mean(0).numpy()
    config = ChatCamConfig(RefineConfig(iterations=12, long_side=48))
    result = chatcam_pose(
        scene.gaussians, camera, lambda image: scorer.score(image, TEXT), centroid, np.asarray(gt["up"]), gt["scale"], config
    )
    assert result.iterations == 12 and result.stop_reason == "max_iterations" and len(result.losses) == 13
    score = 1.0 - result.history["score"]
    assert score.max() > score[0] + 1e-4, score
    best = int(np.argmin(result.losses))
    np.testing.assert_allclose(result.T_cw, result.trajectory[best])


def test_cli_writes_a_result_that_check_reads(setup, tmp_path, capsys):
    root, _ = setup
    out = tmp_path / "chatcam"
    args = ["baseline", "chatcam", str(root / "scene"), TEXT, "-o", str(out), "--diff-scorer", "clip"]
    args += ["--models", str(root / "models.yaml"), "--cache", str(tmp_path / "cache"), "--iterations", "3"]
    assert main([*args, "--long-side", "40", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    result = json.loads((out / "result.json").read_text())
    assert result["method"] == "chatcam" and printed["T_cw"] == result["T_cw"]
    assert (out / "render.png").is_file() and (out / "camera.json").is_file()
    search = result["search"]
    assert search["iterations"] == 3 and search["config"]["long_side"] == 40
    # the start is the training picture the model scores highest
    scene = load_scene_dir(root / "scene")
    anchors = diff_scorer(root, scene).view_scores(TEXT)
    assert search["init_view"] == scene.cameras[int(np.argmax(anchors))].name
    assert search["init_view_score"] == pytest.approx(float(anchors.max()), abs=1e-6)
    assert {"anchor_s", "optimise_s", "total_s"} <= set(result["timings"])
    camera, _ = read_result_camera(out / "result.json")
    np.testing.assert_allclose(camera.T_cw, result["T_cw"])
    constraints = tmp_path / "constraints.json"
    constraints.write_text(json.dumps(ParsedInstruction.from_dict(result["instruction"]).constraints().to_dict()))
    assert main(["check", str(root / "scene"), str(out / "result.json"), "--constraints", str(constraints), "--json"]) == 0
    assert "all_satisfied" in json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(
    "extra, message",
    [
        ([], "baseline 'chatcam' needs a differentiable image-text scorer: --diff-scorer clip|siglip|fg-clip|fg-clip2"),
        (["--diff-scorer", "oracle"], "--diff-scorer 'oracle' is unknown; available: clip, siglip, fg-clip, fg-clip2"),
        (["--diff-scorer", "clip"], "backend 'clip' needs an entry in the models config"),
    ],
)
def test_bad_input_is_one_line(setup, tmp_path, capsys, extra, message):
    root, _ = setup
    out = tmp_path / "out"
    assert main(["baseline", "chatcam", str(root / "scene"), TEXT, "-o", str(out), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("capframe: error:") and message in err, err
    assert not out.exists()


def test_workflow_schedules_chatcam_only_with_a_differentiable_scorer(tmp_path):
    """One baseline job per baseline and instruction (4 scenes, one instruction each); chatcam's
    command gets the scorer, the models config and Refine's step budget and resolution."""
    _fake_generated_suite(tmp_path)
    (tmp_path / "models.yaml").write_text("clip: {weights: clip}\n")
    without = planned_outputs(tmp_path, "--config", "models=models.yaml")
    assert "results/baselines/splatraj/" in without and "results/baselines/chatcam/" not in without
    assert _jobs(without)["baseline"] == 3 * 4
    diff = planned_outputs(tmp_path, "-p", "--config", "models=models.yaml", "backends={'diff-scorer': 'clip'}")
    assert "results/baselines/chatcam/tabletop-orbit/tabletop-orbit-000" in diff and _jobs(diff)["baseline"] == 4 * 4
    # checked and tabled like the other baselines
    assert "results/check/chatcam/tabletop-orbit/tabletop-orbit-000.json" in diff and "results/tables/chatcam.csv" in diff
    [command] = [line for line in diff.splitlines() if "capframe baseline chatcam results/scenes/tabletop-orbit" in line]
    assert "--diff-scorer clip" in command and "--models models.yaml" in command
    assert "--iterations 1500 --long-side 160" in command
