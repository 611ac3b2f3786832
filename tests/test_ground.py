"""``capframe ground`` end to end on a tiny scene, its outputs, and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
from _synth_helpers import build_scene

from capframe.cli import main
from capframe.evaluate.check import GroundTruthChecker, read_result_camera
from capframe.pipeline import GroundOptions, ground
from capframe.pipeline.stages import own_checker, own_report
from capframe.refine.optimize import RefineConfig
from capframe.scene import SceneMeta, load_scene_dir, read_camera_json
from capframe.scene.directory import write_scene_meta
from capframe.translate.labels import read_pseudo_labels

INSTRUCTION = "a medium shot of the teddy bear on the right of the frame, seen from its front, from slightly above"


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("ground") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


@pytest.fixture(scope="module")
def grounded(scene_dir, tmp_path_factory):
    out = tmp_path_factory.mktemp("out") / "bear"
    options = GroundOptions(cache_dir=out.parent / "cache", candidates=2, refine=RefineConfig(iterations=300))
    return out, ground(scene_dir, INSTRUCTION, out, options, progress=False)


def test_ground_writes_a_camera_that_satisfies_the_instruction(scene_dir, grounded):
    out, result = grounded
    for name in (
        "result.json",
        "render.png",
        "camera.json",
        "camera_path.json",
        "colmap_image.txt",
        "labels.json",
        "trajectory.npz",
        "candidates/0/camera.json",
    ):
        assert (out / name).is_file(), name
    camera, _ = read_result_camera(out / "result.json")
    np.testing.assert_allclose(read_camera_json(out / "camera.json").T_cw, camera.T_cw)
    parsed = result["instruction"]
    assert [(s["name"], s["region"], s["shot"], s["view"]) for s in parsed["subjects"]] == [
        ("teddy bear", "right", "medium", "front")
    ]
    assert parsed["elevation"] == "slightly above"
    # The ground-truth checker agrees with the method's own report on this scene.
    from capframe.translate.instruction import ParsedInstruction

    report = GroundTruthChecker(scene_dir).check(camera, ParsedInstruction.from_dict(parsed).constraints())
    assert report.all_satisfied, report.to_dict()
    assert result["report"]["all_satisfied"]


def test_result_explains_the_retrieval(grounded):
    _, result = grounded
    retrieval = result["retrieval"]
    kinds = [q["kind"] for q in retrieval["questions"]]
    assert kinds == ["visible", "region", "shot", "view", "elevation", "overall"]
    scores = [v["score"] for v in retrieval["views"]]
    assert scores == sorted(scores, reverse=True)
    assert retrieval["top"][0] == retrieval["views"][0]["view"]
    assert all(np.isclose(v["score"], np.mean(v["answers"])) for v in retrieval["views"])
    losses = [c["loss"] for c in result["candidates"]]
    assert losses == sorted(losses)


def test_own_report_matches_ground_truth_checker_with_label_subjects(scene_dir, grounded):
    """With labels-tier pseudo labels, the own report measures the same things as the checker: the
    visible share and region centroid agree closely (centroids differ only by mean-vs-centre)."""
    out, result = grounded
    scene = load_scene_dir(scene_dir)
    labels = read_pseudo_labels(out / "labels.json")
    from capframe.translate.instruction import ParsedInstruction

    parsed = ParsedInstruction.from_dict(result["instruction"])
    camera, _ = read_result_camera(out / "result.json")
    own = own_report(own_checker(scene, labels), parsed, camera)
    truth = GroundTruthChecker(scene_dir).check(camera, parsed.constraints())
    for a, b in zip(own.rows, truth.rows):
        assert (a.constraint, a.subject) == (b.constraint, b.subject)
        if a.constraint in ("visibility", "shot"):
            assert a.measured == pytest.approx(b.measured, abs=1e-6)
        elif a.constraint == "region":
            assert a.measured == pytest.approx(b.measured, abs=1e-6)
        else:  # angles around the Gaussians' mean instead of the ground-truth centre
            assert a.measured == pytest.approx(b.measured, abs=3.0)


def test_mask_associator_grounds_the_same_subject(scene_dir, tmp_path):
    backends = {"segmenter": "oracle", "associator": "knn"}
    options = GroundOptions(cache_dir=tmp_path / "cache", backends=backends, refine=RefineConfig(iterations=100))
    result = ground(scene_dir, "the vase in the centre of the frame", tmp_path / "out", options, progress=False)
    labels = read_pseudo_labels(tmp_path / "out" / "labels.json")
    scene = load_scene_dir(scene_dir)
    vase = next(o for o in scene.semantics if o.name == "vase")
    assert (scene.gaussians.labels[labels.subjects[0].gaussians] == vase.id).float().mean() > 0.9
    assert result["options"]["backends"]["associator"] == "knn" and result["options"]["backends"]["parser"] == "rules"


@pytest.mark.parametrize(
    "instruction, message",
    [
        ("", "empty"),
        ("   ", "empty"),
        ("a photo from slightly above", "no subject"),
        ("a close-up of the giraffe on the left", "giraffe"),
    ],
)
def test_bad_instructions_fail_with_one_line_and_write_nothing(scene_dir, tmp_path, capsys, instruction, message):
    out = tmp_path / "out"
    code = main(["ground", str(scene_dir), instruction, "-o", str(out), "--cache", str(tmp_path / "cache")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and message in err, err
    assert not out.exists()


def test_unknown_subject_names_the_closest_known(scene_dir, tmp_path, capsys):
    assert main(["ground", str(scene_dir), "the tetti bar on the left", "-o", str(tmp_path / "o")]) == 2
    assert "teddy bear" in capsys.readouterr().err


def test_scene_without_sidecar_is_rejected_by_the_oracle_backends(scene_dir, tmp_path, capsys):
    import shutil

    bare = tmp_path / "bare"
    shutil.copytree(scene_dir, bare)
    (bare / "semantics.json").unlink()
    (bare / "labels.npy").unlink()
    assert main(["ground", str(bare), "the teddy bear on the left", "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "semantic sidecar" in err and "--coarse-scorer oracle" in err
    assert not (tmp_path / "o").exists()


def test_scene_without_up_asks_for_gravity(scene_dir, tmp_path, capsys):
    import shutil

    tilted = tmp_path / "tilted"
    shutil.copytree(scene_dir, tilted)
    write_scene_meta(SceneMeta(up=None, aligned=False), tilted / "scene.json")
    assert main(["ground", str(tilted), "the teddy bear on the left", "-o", str(tmp_path / "o")]) == 2
    assert "capframe gravity" in capsys.readouterr().err


def test_json_output_is_one_object(scene_dir, tmp_path, capsys):
    code = main(
        [
            "ground",
            str(scene_dir),
            "the vase on the left",
            "-o",
            str(tmp_path / "o"),
            "--json",
            "--iterations",
            "50",
            "--cache",
            str(tmp_path / "cache"),
        ]
    )
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert {"T_cw", "report", "instruction", "timings"} <= set(data)


def test_stage_verbs_reproduce_ground(scene_dir, tmp_path):
    """retrieve -> translate -> refine --init retrieval.json, one process each, gives the camera
    ground gives in one process (what the workflow's per-stage rules rely on)."""
    text, cache = "the vase on the right, from a high angle", str(tmp_path / "cache")
    assert (
        main(["ground", str(scene_dir), text, "-o", str(tmp_path / "g"), "--cache", cache, "--iterations", "200", "--json"]) == 0
    )
    assert main(["retrieve", str(scene_dir), text, "-o", str(tmp_path / "r.json"), "--cache", cache]) == 0
    assert (
        main(
            [
                "translate",
                str(scene_dir),
                "--retrieval",
                str(tmp_path / "r.json"),
                "-o",
                str(tmp_path / "l.json"),
                "--cache",
                cache,
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "refine",
                str(scene_dir),
                "--labels",
                str(tmp_path / "l.json"),
                "--init",
                str(tmp_path / "r.json"),
                "-o",
                str(tmp_path / "s"),
                "--iterations",
                "200",
            ]
        )
        == 0
    )
    staged = json.loads((tmp_path / "s" / "result.json").read_text())
    grounded = json.loads((tmp_path / "g" / "result.json").read_text())
    np.testing.assert_allclose(staged["T_cw"], grounded["T_cw"], atol=1e-9)
    assert staged["retrieval"] == grounded["retrieval"] and staged["report"]["rows"] == grounded["report"]["rows"]


@pytest.mark.parametrize("associator", ["oracle", "knn"])
def test_fine_stage_verbs_reproduce_retrieve_and_translate(scene_dir, tmp_path, associator):
    """parse -> coarse -> qe -> [segment] -> associate -> orient -> translate, one process each
    (the workflow's rules), write the same retrieval.json and labels.json as retrieve and translate."""
    text = "the teddy bear on the right, seen from its front"
    common = ["--cache", str(tmp_path / "cache"), "--associator", associator]
    scene, out = str(scene_dir), lambda name: str(tmp_path / name)
    assert main(["retrieve", scene, text, "-o", out("r.json"), *common]) == 0
    assert main(["translate", scene, "--retrieval", out("r.json"), "-o", out("l.json"), *common]) == 0
    assert main(["parse", scene, text, "-o", out("p.json"), *common]) == 0
    assert json.loads((tmp_path / "p.json").read_text())["needs"] == {"orientation": True}
    assert main(["coarse", scene, "--parsed", out("p.json"), "-o", out("c.json"), *common]) == 0
    assert main(["qe", scene, "--coarse", out("c.json"), "-o", out("q.json"), *common]) == 0
    assert without_inputs(tmp_path / "q.json") == without_inputs(tmp_path / "r.json")
    masks = []
    if associator == "knn":
        assert main(["segment", scene, "--retrieval", out("q.json"), "-o", out("m.npz"), *common]) == 0
        masks = ["--masks", out("m.npz")]
    assert main(["associate", scene, "--retrieval", out("q.json"), "-o", out("a.json"), *masks, *common]) == 0
    assert main(["orient", scene, "--retrieval", out("q.json"), "-o", out("f.json"), *common]) == 0
    assert list(json.loads((tmp_path / "f.json").read_text())["fronts"]) == ["teddy bear"]
    assert (
        main(
            [
                "translate",
                scene,
                "--retrieval",
                out("q.json"),
                "--subjects",
                out("a.json"),
                "--fronts",
                out("f.json"),
                "-o",
                out("staged.json"),
            ]
        )
        == 0
    )
    assert without_inputs(tmp_path / "staged.json") == without_inputs(tmp_path / "l.json")


def without_inputs(path) -> dict:
    """A stage file's content but the record of the files it was made from (a verb that read none,
    like retrieve, records none)."""
    data = json.loads(path.read_text())
    del data["inputs"]
    return data


def test_fine_stages_reject_missing_or_foreign_inputs(scene_dir, tmp_path, capsys):
    text = "the teddy bear seen from its left"
    cache = ["--cache", str(tmp_path / "cache")]
    assert main(["retrieve", str(scene_dir), text, "-o", str(tmp_path / "r.json"), *cache]) == 0
    assert (
        main(["associate", str(scene_dir), "--retrieval", str(tmp_path / "r.json"), "-o", str(tmp_path / "a.json"), *cache]) == 0
    )
    # the instruction needs the bear's front: translate without the orientation stage's file fails clearly
    code = main(
        [
            "translate",
            str(scene_dir),
            "--retrieval",
            str(tmp_path / "r.json"),
            "--subjects",
            str(tmp_path / "a.json"),
            "-o",
            str(tmp_path / "l.json"),
        ]
    )
    assert code == 2 and "capframe orient" in capsys.readouterr().err and not (tmp_path / "l.json").exists()
    # an unknown backend for any role is one line naming the available ones, and nothing is written
    segment = ["segment", str(scene_dir), "--retrieval", str(tmp_path / "r.json"), "-o", str(tmp_path / "m.npz"), *cache]
    for option, available in (
        ("--segmenter", "oracle, grounded-sam, detector"),
        ("--associator", "oracle, knn"),
        ("--parser", "rules"),
    ):
        assert main([*segment, option, "sam"]) == 2 and not (tmp_path / "m.npz").exists()
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"{option} 'sam' is unknown; available: {available}" in err
    # a retrieval file where a coarse file is expected names the file
    assert main(["qe", str(scene_dir), "--coarse", str(tmp_path / "r.json"), "-o", str(tmp_path / "q.json"), *cache]) == 2
    err = capsys.readouterr().err
    assert "r.json" in err and "not a coarse file" in err


def test_retrieved_view_is_the_first_start_unrefined(scene_dir, tmp_path, capsys):
    """``capframe retrieved-view`` writes the training camera Refine starts from (``starts[0]``),
    unchanged and readable by the checker; a start that is not a training view is named and
    nothing is written."""
    text, cache = "the vase on the right, from a high angle", ["--cache", str(tmp_path / "cache")]
    assert main(["retrieve", str(scene_dir), text, "-o", str(tmp_path / "r.json"), *cache]) == 0
    assert main(["retrieved-view", str(scene_dir), "--retrieval", str(tmp_path / "r.json"), "-o", str(tmp_path / "v")]) == 0
    retrieval = json.loads((tmp_path / "r.json").read_text())
    camera, _ = read_result_camera(tmp_path / "v" / "result.json")
    training = {c.name: c for c in load_scene_dir(scene_dir).cameras}[retrieval["starts"][0]]
    np.testing.assert_array_equal(camera.T_cw, training.T_cw)
    np.testing.assert_array_equal(camera.K, training.K)
    assert (camera.width, camera.height) == (training.width, training.height)
    assert json.loads((tmp_path / "v" / "result.json").read_text())["init_view"] == training.name
    assert (tmp_path / "v" / "render.png").stat().st_size > 0

    retrieval["starts"][0] = "frame_9999"
    (tmp_path / "bad.json").write_text(json.dumps(retrieval))
    code = main(["retrieved-view", str(scene_dir), "--retrieval", str(tmp_path / "bad.json"), "-o", str(tmp_path / "w")])
    assert code == 2 and "frame_9999" in capsys.readouterr().err and not (tmp_path / "w").exists()
