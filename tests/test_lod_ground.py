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
    root = tmp_path_factory.mktemp("lod-ground") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


def test_ground_through_the_cut_matches_full_detail(scene_dir, tmp_path):
    """Cells of up to 8 px (four times the default: this small scene's Gaussians are large, and
    at 8 px the cut merges about half of a subject's from a training view) against every Gaussian: the same per-clause verdicts (own report and ground truth) and
    a camera within 5 degrees and 5% of its distance to the subject."""
    results, truths = {}, {}
    for pixels in (0.0, 8.0):
        out = tmp_path / f"out-{pixels}"
        options = GroundOptions(cache_dir=tmp_path / "cache", candidates=1, refine=RefineConfig(iterations=300, lod_pixels=pixels))
        results[pixels] = ground(scene_dir, INSTRUCTION, out, options, progress=False)
        camera, _ = read_result_camera(out / "result.json")
        constraints = ParsedInstruction.from_dict(results[pixels]["instruction"]).constraints()
        truths[pixels] = GroundTruthChecker(scene_dir).check(camera, constraints).to_dict()
    verdicts = lambda report: [(r["constraint"], r["subject"], r["satisfied"]) for r in report["rows"]]  # noqa: E731
    assert verdicts(results[8.0]["report"]) == verdicts(results[0.0]["report"])
    assert verdicts(truths[8.0]) == verdicts(truths[0.0])
    assert truths[0.0]["all_satisfied"]
    T0, T1 = (np.asarray(results[p]["T_cw"]) for p in (0.0, 8.0))
    angle = np.degrees(np.arccos(np.clip((np.trace(T0[:3, :3].T @ T1[:3, :3]) - 1) / 2, -1, 1)))
    print(f"rotation {angle:.3f} deg", end=" ")
    assert angle <= 5.0
    c0, c1 = -T0[:3, :3].T @ T0[:3, 3], -T1[:3, :3].T @ T1[:3, 3]
    centroid = read_pseudo_labels(tmp_path / "out-0.0" / "labels.json").subjects[0].centroid
    shift = np.linalg.norm(c1 - c0) / np.linalg.norm(c0 - centroid)
    print(f"centre {shift:.4f} of the distance")
    assert shift <= 0.05
