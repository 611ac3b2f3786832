"""``capframe ground`` through the level-of-detail cut against full detail: the same verdicts of
the method's own report and of the ground-truth checker, and a pose within a stated tolerance."""

from __future__ import annotations

import numpy as np
import pytest
from _synth_helpers import build_scene

from capframe.evaluate.check import GroundTruthChecker, read_result_camera
from capframe.pipeline import GroundOptions, ground
from capframe.refine.optimize import RefineConfig
from capframe.scene import SceneMeta
from capframe.scene.directory import write_scene_meta
from capframe.translate.instruction import ParsedInstruction
from capframe.translate.labels import read_pseudo_labels

INSTRUCTION = "a medium shot of the teddy bear on the right of the frame, seen from its front, from slightly above"


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    """Objects of 2000 overlapping Gaussians each: dense enough that cells of a few pixels merge."""
    root = tmp_path_factory.mktemp("lod-ground") / "scene"
    gt = build_scene(root, per_object=2000)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


def _ground(scene_dir, out, pixels: float) -> tuple[dict, dict]:
    options = GroundOptions(cache_dir=out.parent / "cache", candidates=1, refine=RefineConfig(iterations=300, lod_pixels=pixels))
    result = ground(scene_dir, INSTRUCTION, out, options, progress=False)
    camera, _ = read_result_camera(out / "result.json")
    constraints = ParsedInstruction.from_dict(result["instruction"]).constraints()
    return result, GroundTruthChecker(scene_dir).check(camera, constraints).to_dict()


def _verdicts(report: dict) -> list[tuple]:
    return [(row["constraint"], row["subject"], row["satisfied"]) for row in report["rows"]]


@pytest.mark.parametrize("pixels", [4.0, 8.0])
def test_ground_through_the_cut_matches_full_detail(scene_dir, tmp_path, pixels):
    """Cells of up to 4 and 8 px (2x and 4x the default; at the default's 2 px this scene's cut
    keeps every Gaussian and the result is identical) against every Gaussian: the same
    per-clause verdicts, own report and ground truth (all satisfied), and a camera within 10
    degrees and 15% of its distance to the subject (measured 4.1 / 4.7 degrees, 0.24 / 0.28
    units at a distance of 3.57 from the view centre, 7 / 8%). Refine stops at the first pose
    that satisfies every clause, so two valid runs differ by about that much, and so does their
    loss at the stop: it is within a quarter of full detail's (measured 12% above and 17% below,
    since Refine measures view angles around the middle of the subject's height; before, full
    detail stopped at 4-5 times the cut's loss)."""
    full, full_truth = _ground(scene_dir, tmp_path / "full", 0.0)
    lod, lod_truth = _ground(scene_dir, tmp_path / "lod", pixels)
    assert _verdicts(lod["report"]) == _verdicts(full["report"])
    assert _verdicts(lod_truth) == _verdicts(full_truth)
    assert full_truth["all_satisfied"] and lod_truth["all_satisfied"]
    T0, T1 = np.asarray(full["T_cw"]), np.asarray(lod["T_cw"])
    angle = np.degrees(np.arccos(np.clip((np.trace(T0[:3, :3].T @ T1[:3, :3]) - 1) / 2, -1, 1)))
    c0, c1 = -T0[:3, :3].T @ T0[:3, 3], -T1[:3, :3].T @ T1[:3, 3]
    centroid = read_pseudo_labels(tmp_path / "full" / "labels.json").subjects[0].centroid
    distance = np.linalg.norm(c0 - centroid)
    print(f"{pixels} px: rotation {angle:.2f} deg, centre {np.linalg.norm(c1 - c0):.3f} of distance {distance:.2f}")
    assert angle <= 10.0
    assert np.linalg.norm(c1 - c0) <= 0.15 * distance
    assert abs(lod["loss"] - full["loss"]) <= 0.25 * full["loss"]
