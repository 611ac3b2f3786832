"""Ground-truth checker: cameras built analytically to satisfy (or violate) each constraint kind."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from _synth_helpers import aim_camera, build_scene, obj, point_camera

from capframe import measure as check_module
from capframe.cli import main
from capframe.constraints import Constraints, SubjectConstraint
from capframe.errors import InputError
from capframe.evaluate import GroundTruthChecker, check_camera, check_command
from capframe.scene import write_camera_json
from capframe.synth.instructions import generate_instructions


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    root = tmp_path_factory.mktemp("scene")
    gt = build_scene(root)
    return root, gt, GroundTruthChecker(root, long_side=128)  # low resolution keeps the tests fast


def one(name="teddy bear", **kwargs) -> Constraints:
    elevation = {k: kwargs.pop(k) for k in ("elevation", "elevation_deg", "roll_deg") if k in kwargs}
    return Constraints(subjects=[SubjectConstraint(name, **kwargs)], **elevation)


def bear_camera(gt, **kwargs):
    kwargs.setdefault("azimuth", 0.0)
    kwargs.setdefault("elevation", 10.0)
    kwargs.setdefault("distance", 5.0)
    return aim_camera(gt, obj(gt, "teddy bear"), **kwargs)


def test_region_inside_and_outside_the_box(world):
    root, gt, checker = world
    cam = bear_camera(gt, point=(0.8, 0.5))
    right = checker.check(cam, one(region="right")).row("region")
    assert right.satisfied and right.error == 0.0
    assert right.measured[0] == pytest.approx(0.8, abs=0.03) and right.measured[1] == pytest.approx(0.5, abs=0.03)
    assert right.details["source"] == "visible mask"
    left = checker.check(cam, one(region="left")).row("region")
    assert not left.satisfied and left.error == pytest.approx(0.8 - 0.45, abs=0.03)
    corner = checker.check(bear_camera(gt, point=(0.25, 0.75)), one(region="lower left"))
    assert corner.all_satisfied


def test_region_falls_back_to_the_projected_centre_out_of_frame(world):
    root, gt, checker = world
    report = checker.check(bear_camera(gt, point=(1.35, 0.5)), one(region="right"))
    row = report.row("region")
    assert row.details["source"] == "projected centre" and row.measured[0] == pytest.approx(1.35, abs=1e-3)
    assert not row.satisfied and row.error == pytest.approx(0.35, abs=1e-3)
    assert not report.row("visibility").satisfied  # empty mask


def test_shot_sizes(world):
    root, gt, checker = world
    close, medium, wide = (bear_camera(gt, distance=d) for d in (1.8, 5.0, 12.0))
    assert checker.check(close, one(shot="close-up")).all_satisfied
    assert checker.check(medium, one(shot="medium")).all_satisfied
    assert checker.check(wide, one(shot="wide")).all_satisfied
    row = checker.check(wide, one(shot="close-up")).row("shot")
    assert not row.satisfied and row.measured < 0.3 and row.error == pytest.approx(0.55 - row.measured)
    row = checker.check(close, one(shot="wide")).row("shot")
    assert not row.satisfied and row.measured > 0.9


def test_view_sides_with_wrapping(world):
    root, gt, checker = world
    left = bear_camera(gt, azimuth=-90.0)
    row = checker.check(left, one(view="left")).row("view")
    assert row.satisfied and row.measured == pytest.approx(-90.0, abs=1e-6) and row.error == pytest.approx(0.0, abs=1e-6)
    row = checker.check(left, one(view="right")).row("view")
    assert not row.satisfied and row.error == pytest.approx(180.0, abs=1e-6)
    behind = checker.check(bear_camera(gt, azimuth=-165.0), one(view="back")).row("view")
    assert behind.satisfied and behind.error == pytest.approx(15.0, abs=1e-6)  # -165 is 15 deg from +180
    assert checker.check(bear_camera(gt, azimuth=40.0), one(view="three-quarter")).all_satisfied
    assert checker.check(bear_camera(gt, azimuth=-50.0), one(view="three-quarter")).all_satisfied
    row = checker.check(bear_camera(gt, azimuth=0.0), one(view="three-quarter")).row("view")
    assert not row.satisfied and row.error == pytest.approx(45.0, abs=1e-6)
    row = checker.check(bear_camera(gt, azimuth=130.0), one(view="back-left")).row("view")
    assert not row.satisfied and row.error == pytest.approx(95.0, abs=1e-6)  # -135 vs +130 wraps to 95


@pytest.mark.parametrize(
    "view, azimuth, satisfied, error",
    [
        # Slight sides: -20 / +20 (or -160 / +160 from behind) within 15 degrees.
        ("front-slight-left", -20.0, True, 0.0),
        ("front-slight-left", -33.0, True, 13.0),
        ("front-slight-left", 0.0, False, 20.0),  # the straight front is not "slightly from the left"
        ("front-slight-left", -45.0, False, 25.0),  # nor is the full front-left
        ("front-slight-right", 8.0, True, 12.0),
        ("back-slight-left", -170.0, True, 10.0),
        ("back-slight-left", 180.0, False, 20.0),
        ("back-slight-right", 150.0, True, 10.0),
        # Either profile, either rear diagonal: the nearer of -90 / +90 and -135 / +135, within 30.
        ("side", 100.0, True, 10.0),
        ("side", -75.0, True, 15.0),
        ("side", 0.0, False, 90.0),
        ("back-three-quarter", -120.0, True, 15.0),
        ("back-three-quarter", 180.0, False, 45.0),
    ],
)
def test_new_view_sides_by_hand(world, view, azimuth, satisfied, error):
    root, gt, checker = world
    row = checker.check(bear_camera(gt, azimuth=azimuth), one(view=view)).row("view")
    assert row.satisfied is satisfied and row.error == pytest.approx(error, abs=1e-6)
    assert row.target["tolerance_deg"] == (15.0 if "slight" in view else 30.0)


def test_view_of_a_symmetric_subject_is_not_applicable(world):
    root, gt, checker = world
    cam = aim_camera(gt, obj(gt, "vase"), azimuth=0.0, elevation=10.0, distance=5.0)
    report = checker.check(cam, one("vase", view="left"))
    assert report.row("view").satisfied is None and report.all_satisfied


def test_elevation_named_and_explicit(world):
    root, gt, checker = world
    cam = bear_camera(gt, elevation=20.0)
    row = checker.check(cam, one(elevation="slightly above")).row("elevation")
    assert row.satisfied and row.measured == pytest.approx(20.0, abs=1e-6)
    row = checker.check(cam, one(elevation="bird's-eye")).row("elevation")
    assert not row.satisfied and row.error == pytest.approx(40.0, abs=1e-6)
    assert checker.check(bear_camera(gt, elevation=35.0), one(elevation_deg=30.0)).all_satisfied
    row = checker.check(bear_camera(gt, elevation=45.0), one(elevation_deg=30.0)).row("elevation")
    assert not row.satisfied and row.error == pytest.approx(5.0, abs=1e-6)
    below = checker.check(bear_camera(gt, elevation=-12.0, distance=3.0), one(elevation="low angle"))
    assert below.all_satisfied


def test_top_down_and_slightly_below_by_hand(world):
    """top-down is 80..90 degrees (bird's-eye 60..90 would take 70), slightly below -30..-8."""
    root, gt, checker = world
    row = checker.check(bear_camera(gt, elevation=85.0, distance=4.0), one(elevation="top-down")).row("elevation")
    assert row.satisfied and row.measured == pytest.approx(85.0, abs=1e-6)
    row = checker.check(bear_camera(gt, elevation=70.0, distance=4.0), one(elevation="top-down")).row("elevation")
    assert not row.satisfied and row.error == pytest.approx(10.0, abs=1e-6)
    row = checker.check(bear_camera(gt, elevation=-10.0, distance=3.0), one(elevation="slightly below")).row("elevation")
    assert row.satisfied and row.error == 0.0
    row = checker.check(bear_camera(gt, elevation=-40.0, distance=3.0), one(elevation="slightly below")).row("elevation")
    assert not row.satisfied and row.error == pytest.approx(10.0, abs=1e-6)


def test_roll_sign_tolerance_and_undefined_overhead(world):
    root, gt, checker = world
    cam = bear_camera(gt, roll=15.0)
    row = checker.check(cam, one(roll_deg=15.0)).row("roll")
    assert row.satisfied and row.measured == pytest.approx(15.0, abs=1e-6)
    row = checker.check(cam, one(roll_deg=-15.0)).row("roll")
    assert not row.satisfied and row.error == pytest.approx(30.0, abs=1e-6)
    row = checker.check(bear_camera(gt, roll=7.0), one(roll_deg=0.0)).row("roll")
    assert not row.satisfied and row.error == pytest.approx(7.0, abs=1e-6)
    overhead = bear_camera(gt, elevation=89.0, distance=4.0)
    report = checker.check(overhead, one(roll_deg=20.0, elevation="bird's-eye"))
    assert report.row("roll").satisfied is None and report.all_satisfied


def test_visibility_occluded_subject(world):
    root, gt, checker = world
    bear, vase = obj(gt, "teddy bear"), obj(gt, "vase")
    B, V = np.array(bear["center"]), np.array(vase["center"])
    C = B + 3.0 * bear["radius"] * (B - V) / np.linalg.norm(B - V)  # the bear stands between camera and vase
    cam = point_camera(C, V, gt["up"])
    report = checker.check(cam, Constraints([SubjectConstraint("vase"), SubjectConstraint("teddy bear", role="secondary")]))
    hidden, blocker = report.row("visibility", "vase"), report.row("visibility", "teddy bear")
    assert not hidden.satisfied and hidden.measured < 0.2 and hidden.details["in_front"] and hidden.details["mask_pixels"] > 0
    assert blocker.satisfied and blocker.measured > 0.9
    assert not report.all_satisfied


def test_visibility_subject_cut_off_by_the_frame_edge(world):
    root, gt, checker = world
    # Centre just past the right edge: the in-frame part of the mask sits in the right region,
    # but most of the bear is outside the photo.
    report = checker.check(bear_camera(gt, point=(1.03, 0.5)), one(region="right"))
    vis = report.row("visibility")
    assert vis.details["mask_pixels"] > 0 and vis.details["in_frame_fraction"] < 0.5
    assert not vis.satisfied and "cut off" in vis.note
    whole = checker.check(bear_camera(gt, point=(0.8, 0.5)), one(region="right")).row("visibility")
    assert whole.satisfied and whole.details["in_frame_fraction"] > 0.95


def test_visibility_subject_behind_the_camera(world):
    root, gt, checker = world
    bear = obj(gt, "teddy bear")
    S = np.array(bear["center"])
    front_cam = bear_camera(gt)
    C = front_cam.center
    away = point_camera(C, C + (C - S), gt["up"])  # looks straight away from the bear
    report = checker.check(away, one(region="center"))
    vis, region = report.row("visibility"), report.row("region")
    assert not vis.satisfied and not vis.details["in_front"] and vis.details["mask_pixels"] == 0
    assert not region.satisfied and region.measured is None


def test_all_constraints_together_and_two_subjects(world):
    root, gt, checker = world
    cam = bear_camera(gt, azimuth=-80.0, elevation=18.0, distance=5.0, roll=-12.0, point=(0.75, 0.6))
    c = one(region="right", shot="medium", view="left", elevation="slightly above", roll_deg=-12.0)
    report = checker.check(cam, c)
    assert report.all_satisfied and len(report.rows) == 7, report.to_dict()  # six clauses and the clearance
    assert report.row("clearance").measured > 0
    # Two subjects: the bear on the left and the red armchair on the right from the bear's front-right side.
    for ins in generate_instructions(gt, 12, seed=3, scene="t"):
        if ins.kind == "two-subject":
            two = checker.check(ins.witness, ins.constraints)
            subjects = {r.subject for r in two.rows if r.constraint != "clearance"}
            assert two.all_satisfied and subjects == {s.name for s in ins.constraints.subjects}
            break
    else:
        pytest.fail("no two-subject instruction generated")


def test_generated_witness_cameras_satisfy_the_checker(world):
    root, gt, checker = world
    instructions = generate_instructions(gt, 12, seed=7, scene="t")
    assert {i.kind for i in instructions} == {"layout", "layout+view", "view+elevation", "elevation", "roll", "two-subject"}
    for ins in instructions:
        report = checker.check(ins.witness, ins.constraints)
        assert report.all_satisfied, (ins.text, report.to_dict())


def test_subject_names_colours_and_aliases(world):
    root, gt, checker = world
    cam = aim_camera(gt, obj(gt, "armchair", "red"), azimuth=0.0, elevation=10.0, distance=5.0)
    assert checker.check(cam, one("red armchair")).all_satisfied
    assert checker.check(cam, one("Red  Chair")).all_satisfied
    assert checker.check(bear_camera(gt), one("plush toy")).all_satisfied
    with pytest.raises(InputError, match="ambiguous.*blue armchair.*red armchair"):
        checker.check(cam, one("armchair"))
    with pytest.raises(InputError, match="'teddy bare' is not in this scene; closest: .*teddy bear"):
        checker.check(cam, one("teddy bare"))


def test_check_camera_and_command_outputs(world, tmp_path, capsys, monkeypatch):
    root, gt, checker = world
    monkeypatch.setattr(check_module, "CHECK_LONG_SIDE", 128)  # speed: the command renders at the default size
    cam = bear_camera(gt, azimuth=-90.0, point=(0.8, 0.5))
    c = one(region="right", view="left")
    assert check_camera(root, cam, c).all_satisfied
    constraints = {
        "s-000": {
            "scene": "s",
            "text": "The teddy bear on the right, seen from its left.",
            "paraphrases": ["A photo of the bear on the right, showing its left side."],
            "constraints": c.to_dict(),
        },
        "s-001": {"scene": "s", "text": "x", "paraphrases": [], "constraints": one(region="left").to_dict()},
    }
    (tmp_path / "constraints.json").write_text(json.dumps(constraints))
    write_camera_json(cam, tmp_path / "camera.json")
    result = json.loads((tmp_path / "camera.json").read_text())
    result["instruction_id"] = "s-000"
    (tmp_path / "result.json").write_text(json.dumps(result))

    report = check_command(root, tmp_path / "result.json", tmp_path / "constraints.json", as_json=True)
    printed = json.loads(capsys.readouterr().out)
    assert report.all_satisfied and printed["all_satisfied"] and printed["instruction_id"] == "s-000"
    assert {r["constraint"] for r in printed["rows"]} == {"visibility", "region", "view", "clearance"}
    assert printed["text"].startswith("The teddy bear")

    check_command(root, tmp_path / "camera.json", tmp_path / "constraints.json", instruction_id="s-001")
    table = capsys.readouterr().out
    assert "FAIL" in table and "all satisfied: no (2/3)" in table and "region" in table
    assert check_command(root, tmp_path / "camera.json", tmp_path / "constraints.json", instruction_id="s-000.p1").all_satisfied
    capsys.readouterr()

    args = [str(root), str(tmp_path / "camera.json"), "--constraints", str(tmp_path / "constraints.json")]
    assert main(["check", *args, "--id", "s-000", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["all_satisfied"]
    assert main(["check", *args, "--id", "s-0000"]) == 2
    err = capsys.readouterr().err
    assert "instruction id 's-0000' is not in this file; closest: ['s-000'" in err and err.count("\n") == 1
    assert main(["check", *args]) == 2  # two instructions and no id
    assert "pass --id" in capsys.readouterr().err


def test_missing_ground_truth_and_labels(world, tmp_path):
    root, gt, checker = world
    bare = tmp_path / "bare"
    shutil.copytree(root, bare)
    (bare / "ground_truth.json").unlink()
    with pytest.raises(InputError, match="ground_truth.json not found"):
        GroundTruthChecker(bare)
    unlabelled = tmp_path / "unlabelled"
    shutil.copytree(root, unlabelled)
    (unlabelled / "labels.npy").unlink()
    (unlabelled / "semantics.json").unlink()
    with pytest.raises(InputError, match="semantic sidecar"):
        GroundTruthChecker(unlabelled)


def test_a_camera_below_the_floor_fails_its_clearance_whatever_it_sees(world):
    """Looking up at the bear from under the floor: the floor is behind the camera's near plane,
    so the bear is visible, but the camera is inside geometry."""
    root, gt, checker = world
    below = bear_camera(gt, elevation=-60.0, distance=5.0)
    report = checker.check(below, one(elevation="worm's-eye"))
    row = report.row("clearance")
    assert not row.satisfied and row.measured < 0 and "inside geometry" in row.note
    assert not report.all_satisfied
    above = checker.check(bear_camera(gt, elevation=40.0, distance=5.0), one(elevation="high angle"))
    assert above.row("clearance").satisfied and above.all_satisfied
