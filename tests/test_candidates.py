"""The constraint-solving start (capframe.refine.candidates), free space in Refine, and the
feasibility verdict: closed-form cameras checked by the ground-truth checker in a tilted, scaled
world; a subject whose asked side faces a wall; a start inside a solid block."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
import torch
from _synth_helpers import build_scene
from conftest import make_camera

from capframe.constraints import (
    EXPLICIT_ELEVATION_TOLERANCE_DEG,
    MIN_VISIBLE_FRACTION,
    VIEW_SIDES,
    Constraints,
    SubjectConstraint,
    view_tolerance_deg,
)
from capframe.evaluate import GroundTruthChecker
from capframe.geometry import camera_roll
from capframe.measure import CheckReport, CheckRow
from capframe.pipeline.outputs import closest_answer, feasibility, report_order, shortfall, shows_subjects
from capframe.pipeline.stages import Refined
from capframe.refine.candidates import (
    MARGIN_SPREAD,
    OVER_ELEVATIONS_DEG,
    SIZE_SLACK,
    _above_floor,
    _floor_elevation,
    _floor_reach,
    _free_edge,
    _inner_aim_point,
    _margin_azimuths,
    _margin_elevations,
    _place,
    _Ray,
    _Seen,
    _size_miss,
    _sized_distance,
    aimed_pose,
    shot_distance,
    solve_candidates,
    view_centre,
)
from capframe.refine.optimize import RefineConfig, RefineResult, free_space_loss, refine_pose
from capframe.scene import GaussianScene, load_scene_dir
from capframe.scene.directory import SceneDir, SceneMeta, SemanticObject
from capframe.scene.occupancy import build_occupancy
from capframe.translate.labels import (
    SHOT_MARGIN,
    PseudoLabels,
    SubjectLabel,
    accepted_azimuth_tolerance_deg,
    labels_from_constraints,
    view_target,
)
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    root = tmp_path_factory.mktemp("candidates")
    gt = build_scene(root)
    scene = load_scene_dir(root)
    checker = GroundTruthChecker(root, long_side=128)
    return root, gt, scene, checker


def pseudo_labels(scene, gt, constraints: Constraints):
    """Oracle pseudo labels: each subject's labelled Gaussians, their mean, its true front."""
    subjects = {}
    labels = scene.gaussians.labels.numpy()
    for s in constraints.subjects:
        obj = next(o for o in gt["objects"] if o["name"] == s.name)
        index = np.flatnonzero(labels == obj["label"])
        centroid = scene.gaussians.means.detach().double().numpy()[index].mean(0)
        subjects[s.name] = (index, centroid, None if obj["front"] is None else np.asarray(obj["front"]))
    return labels_from_constraints(constraints, subjects, np.asarray(gt["up"]))


@pytest.mark.parametrize(
    "subject, elevation",
    [
        (SubjectConstraint("teddy bear", view="left", shot="close-up"), None),
        (SubjectConstraint("teddy bear", view="back-right", shot="medium", region="right"), "high angle"),
        (SubjectConstraint("teddy bear", view="front", shot="wide", region="lower left"), "eye level"),
        (SubjectConstraint("vase", shot="medium", region="upper left"), "slightly above"),
        # Below the subject: the ray at the asked distance meets the floor, so the camera slides
        # in along it until it is above the floor, and looks up.
        (SubjectConstraint("teddy bear", view="front"), "low angle"),
    ],
)
def test_the_first_closed_form_camera_satisfies_the_clauses_as_solved(world, subject, elevation):
    """No refinement: the closed form alone puts a single subject where asked (region, shot size,
    view side, elevation), checked by the ground-truth checker, clearance included."""
    root, gt, scene, checker = world
    constraints = Constraints(subjects=[subject], elevation=elevation)
    labels = pseudo_labels(scene, gt, constraints)
    occupancy = build_occupancy(scene.gaussians, labels.up, scene.cameras)
    solved = solve_candidates(scene.gaussians, labels, scene.cameras[0], occupancy)
    assert solved[0].status == "kept"
    report = checker.check(solved[0].camera, constraints)
    assert report.all_satisfied, [r.to_dict() for r in report.rows if r.satisfied is False]


def test_shot_distance_inverts_the_projected_size():
    camera = make_camera(width=200, height=100, focal=150.0)
    d = shot_distance(0.5, 0.4, camera)
    # A sphere of radius 0.5 at distance d: its silhouette's half-angle is asin(r / d).
    projected = 2 * 150.0 * math.tan(math.asin(0.5 / d)) / 100
    assert projected == pytest.approx(0.4, rel=1e-12)


def test_aimed_pose_images_the_target_at_the_point():
    camera = make_camera(width=160, height=120, focal=140.0)
    target = np.array([0.3, -0.2, 1.0])
    T = aimed_pose(np.array([4.0, 1.0, 2.0]), target, (0.2, 0.8), camera, np.array([0.0, 0.0, 1.0]), 0.0)
    p = T[:3, :3] @ target + T[:3, 3]
    u, v, _ = camera.K @ (p / p[2])
    assert p[2] > 0 and (u / 160, v / 120) == pytest.approx((0.2, 0.8), abs=1e-9)
    np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-12)


@pytest.mark.parametrize("elevation_deg", [0.0, 28.0, 45.0, -30.0])
@pytest.mark.parametrize("point", [(0.775, 0.5), (0.167, 0.5), (0.775, 0.2), (0.5, 0.8)])
@pytest.mark.parametrize("roll_deg", [0.0, 10.0, -25.0])
def test_aimed_pose_keeps_the_asked_roll_with_the_target_off_centre(elevation_deg, point, roll_deg):
    """The horizon's roll is the asked one wherever in the frame the target lands: turning a
    pitched camera about its own axes (the earlier aim) rolled a subject in the right third seen
    from 28 degrees above by 9.8 degrees."""
    camera = make_camera(width=320, height=240, focal=257.0)
    up, target = np.array([0.0, 0.0, 1.0]), np.array([0.3, -0.2, 1.0])
    e = math.radians(elevation_deg)
    centre = target + 5.0 * np.array([0.6 * math.cos(e), -0.8 * math.cos(e), math.sin(e)])
    T = aimed_pose(centre, target, point, camera, up, roll_deg)
    p = T[:3, :3] @ target + T[:3, 3]
    u, v, _ = camera.K @ (p / p[2])
    assert p[2] > 0 and (u / 320, v / 240) == pytest.approx(point, abs=1e-9)
    np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-12)
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)
    roll = math.degrees(float(camera_roll(torch.tensor(T), torch.tensor(up))))
    assert roll == pytest.approx(roll_deg, abs=1e-9)


def ball_before_wall(seed: int, spacing: float, wall_y: float, wall_height: float, scale: float, opacity: float) -> GaussianScene:
    """400 Gaussians on a ball of radius 0.3 about (0, 0, 0.4) (indices 0..399), a floor z = 0 and
    a wall at y = ``wall_y`` of height ``wall_height``, both over x, y in [-3, 3] sampled every
    ``spacing``; isotropic ``scale`` and ``opacity`` everywhere, random colours."""
    g = torch.Generator().manual_seed(seed)
    ball = torch.randn(400, 3, generator=g, dtype=torch.float64)
    ball = ball / ball.norm(dim=1, keepdim=True) * 0.3 + torch.tensor([0.0, 0.0, 0.4], dtype=torch.float64)
    s = torch.arange(-3.0, 3.0 + 1e-9, spacing, dtype=torch.float64)
    a, b = torch.meshgrid(s, s, indexing="ij")
    floor = torch.stack([a.reshape(-1), b.reshape(-1), torch.zeros(a.numel(), dtype=torch.float64)], 1)
    heights = (b.reshape(-1) + 3) / 6 * wall_height
    wall = torch.stack([a.reshape(-1), torch.full((a.numel(),), wall_y, dtype=torch.float64), heights], 1)
    means = torch.cat([ball, floor, wall])
    n = len(means)
    return GaussianScene.from_activated(
        means.float(),
        torch.tensor([1.0, 0, 0, 0]).expand(n, 4).clone(),
        torch.full((n, 3), scale),
        torch.full((n,), opacity),
        torch.rand(n, 3, generator=g),
    )


def walled_scene() -> tuple[GaussianScene, np.ndarray, np.ndarray]:
    """A ball (the subject, front -y) in front of a wall at y = 0.6 (x in [-3, 3], z in [0, 3]) on
    a floor; returns the Gaussians, the subject's indices and the up."""
    gaussians = ball_before_wall(seed=0, spacing=0.1, wall_y=0.6, wall_height=3.0, scale=0.06, opacity=0.9)
    return gaussians, np.arange(400), np.array([0.0, 0.0, 1.0])


def test_a_view_facing_a_wall_is_reported_infeasible():
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    subjects = {"ball": (index, centroid, np.array([0.0, -1.0, 0.0]))}
    cameras = [make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))]
    occupancy = build_occupancy(gaussians, up, cameras)
    behind = labels_from_constraints(Constraints(subjects=[SubjectConstraint("ball", view="back")]), subjects, up)
    solved = solve_candidates(gaussians, behind, cameras[0], occupancy)
    assert solved and all(c.status in ("occluded", "inside geometry") for c in solved)
    failing = CheckReport([CheckRow("view", "ball", False, 10.0, {}, 170.0)])
    verdict = feasibility(failing, solved)
    assert not verdict["feasible"] and verdict["failing"][0]["constraint"] == "view"
    assert verdict["reasons"] and all("occluded" in r or "free space" in r for r in verdict["reasons"])
    # The front is open: solved, and feasible even if a clause failed elsewhere.
    front = labels_from_constraints(Constraints(subjects=[SubjectConstraint("ball", view="front")]), subjects, up)
    solved = solve_candidates(gaussians, front, cameras[0], occupancy)
    assert solved[0].status == "kept" and feasibility(failing, solved)["feasible"]


def test_refine_leaves_a_start_inside_a_wall():
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(
        Constraints(subjects=[SubjectConstraint("ball", shot="medium")]), {"ball": (index, centroid, None)}, up
    )
    start = make_camera(eye=(0.0, 0.6, 0.8), target=(0.0, -3.0, 0.8), up=(0.0, 0.0, -1.0))  # in the wall, facing away
    occupancy = build_occupancy(gaussians, up, [make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))])
    assert float(occupancy.clearance(torch.as_tensor(start.center))) < 0
    result = refine_pose(gaussians, start, labels, 4.0, RefineConfig(iterations=400), occupancy=occupancy)
    end = -result.T_cw[:3, :3].T @ result.T_cw[:3, 3]
    assert float(occupancy.clearance(torch.as_tensor(end))) >= 0


def test_free_space_loss_gradient_matches_finite_differences():
    gaussians, _, up = walled_scene()
    occupancy = build_occupancy(gaussians, up, [make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))])
    T = torch.as_tensor(make_camera(eye=(0.4, 0.63, 1.1), target=(0.0, -3.0, 0.8), up=(0.0, 0.0, -1.0)).T_cw)
    t = T[:3, 3].clone().requires_grad_(True)

    def loss(translation):
        pose = torch.cat([torch.cat([T[:3, :3], translation[:, None]], 1), T[3:]])
        return free_space_loss(pose, occupancy)

    value = loss(t)
    assert value > 0
    value.backward()
    h = 1e-5
    numeric = [(loss(t.detach() + h * e) - loss(t.detach() - h * e)).item() / (2 * h) for e in torch.eye(3, dtype=torch.float64)]
    np.testing.assert_allclose(t.grad.numpy(), numeric, rtol=1e-4, atol=1e-6)


def test_accepted_tolerance_inverts_the_aimed_one_for_every_side():
    """The margin azimuths reach into the checker's tolerance, never beyond it."""
    for view in VIEW_SIDES:
        target = view_target(view, None)
        assert accepted_azimuth_tolerance_deg(target) == pytest.approx(view_tolerance_deg(view))
    right = SubjectLabel("tv", np.arange(3), np.zeros(3), np.array([0.0, -1.0, 0.0]), view=view_target("right", None))
    # aimed 90 +- 18, accepted 90 +- 30: at 0.5 and 0.85 of the 12 deg between them.
    assert sorted(_margin_azimuths(right)) == pytest.approx([61.8, 66.0, 114.0, 118.2])


def test_a_view_hidden_by_a_low_wall_is_solved_from_over_it():
    """A ball behind a low wall (in front of it): no camera at the reference view's elevation
    sees it, so without an asked elevation the closed form looks over the wall, at the asked
    azimuth (not at the edge of the accepted range, where Refine would stop)."""
    gaussians = ball_before_wall(seed=1, spacing=0.05, wall_y=-1.0, wall_height=1.0, scale=0.04, opacity=0.95)
    up = np.array([0.0, 0.0, 1.0])
    centroid = gaussians.means[:400].double().mean(0).numpy()
    subjects = {"ball": (np.arange(400), centroid, np.array([0.0, -1.0, 0.0]))}
    reference = make_camera(eye=(0.0, -4.0, 0.6), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [reference])
    front = labels_from_constraints(Constraints(subjects=[SubjectConstraint("ball", view="front")]), subjects, up)
    solved = solve_candidates(gaussians, front, reference, occupancy)
    kept = [c for c in solved if c.status == "kept"]
    assert kept and kept[0].azimuth_deg == 0.0 and kept[0].elevation_deg == OVER_ELEVATIONS_DEG[0]
    assert all(c.status == "occluded" for c in solved if c.elevation_deg < OVER_ELEVATIONS_DEG[0])


def test_report_order_puts_a_free_camera_that_shows_the_subject_first():
    """When the first pose fails a clause: free space first, then the subject shown, then the
    fewest failing clauses, Refine's order breaking ties; a first pose that satisfies every
    clause keeps the order."""

    def report(*failing: str) -> CheckReport:
        names = ("visibility", "elevation", "view", "clearance")
        return CheckReport([CheckRow(c, "ball", c not in failing, 0.0, {}, 0.0) for c in names])

    hidden, low, wrong_side_low, inside = (
        report("visibility"),
        report("elevation"),
        report("elevation", "view"),
        report("clearance"),
    )
    assert report_order([hidden, wrong_side_low, inside, low]) == [3, 1, 0, 2]
    assert report_order([report(), hidden, low]) == [0, 1, 2]


@pytest.mark.parametrize("scan_turned", [False, True])
def test_when_every_refined_pose_hides_the_subject_its_start_is_the_answer(scan_turned):
    """A ball before a wall: Refine ended behind the wall (free space, the ball hidden by the
    wall) from a start in front that shows it; the start, unrefined, is returned first and its
    report says the ball is seen; the refined pose follows. When Refine's yaw scan turned the
    start behind the wall before its first step (so the trajectory starts there), the answer is
    still the start camera itself, with the loss measured at it before the scan: reporting on one
    pose while writing another claimed a hidden subject as seen."""
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(
        Constraints(subjects=[SubjectConstraint("ball", shot="medium")]), {"ball": (index, centroid, None)}, up
    )
    front = make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    behind = make_camera(eye=(0.0, 4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [front])
    assert float(occupancy.clearance(torch.as_tensor(behind.center))) > 0
    first = behind if scan_turned else front
    at_start = {"start_loss": 0.9, "start_terms": {"size": 0.45}} if scan_turned else {}
    result = RefineResult(
        behind.T_cw,
        1,
        "max_iterations",
        {},
        np.stack([first.T_cw, behind.T_cw]),
        np.array([1.0, 0.1]),
        {"size": np.array([0.7, 0.0])},
        0.0,
        **at_start,
    )
    scene = SceneDir(Path("."), gaussians, [front], None, SceneMeta(up), None)
    parsed = parse_instruction("the ball, medium shot", Vocabulary.from_semantics([SemanticObject(0, "ball", [], True)]))
    answer, reports = closest_answer(scene, labels, parsed, Refined([(front, result)]), occupancy)
    assert [(r.iterations, r.stop_reason) for _, r in answer.runs] == [(0, "unrefined"), (1, "max_iterations")]
    np.testing.assert_array_equal(answer.cameras[0].T_cw, front.T_cw)
    np.testing.assert_array_equal(answer.runs[0][1].trajectory, front.T_cw[None])
    loss, terms = (0.9, {"size": 0.45}) if scan_turned else (1.0, {"size": 0.7})
    assert answer.runs[0][1].terms == terms and list(answer.runs[0][1].losses) == [loss]
    assert shows_subjects(reports[0]) and not shows_subjects(reports[1])


def test_refine_records_the_loss_at_the_given_pose_before_its_yaw_scan():
    """``start_loss`` is the objective at the camera Refine was given, though the yaw scan turned
    it (a start whose loss is lower elsewhere on the orbit): a run without the scan, which starts
    at the given pose, measures the same loss there."""
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(
        Constraints(subjects=[SubjectConstraint("ball", shot="medium")]), {"ball": (index, centroid, None)}, up
    )
    side = make_camera(eye=(3.0, -1.0, 1.0), target=(0.5, 0.5, 0.4), up=(0.0, 0.0, -1.0))
    scanned = refine_pose(gaussians, side, labels, 4.0, RefineConfig(iterations=0, occlusion_iterations=0))
    still = refine_pose(gaussians, side, labels, 4.0, RefineConfig(iterations=0, occlusion_iterations=0, yaw_scan=1))
    assert not np.allclose(scanned.trajectory[0], side.T_cw)
    np.testing.assert_array_equal(still.trajectory[0], side.T_cw)
    assert still.start_loss is None
    assert scanned.start_loss == pytest.approx(float(still.losses[0]), rel=1e-9)
    assert scanned.start_terms == pytest.approx(still.terms, rel=1e-9)


def test_a_start_that_satisfies_every_clause_outranks_a_refined_pose_that_fails_one():
    """Refine traded the asked high angle for the layout (the ball seen from 37 degrees up at the
    start, 8 degrees at the end, both showing it): the start, unrefined, satisfies every clause
    by the method's own report and is returned first; a refined pose that satisfies every clause
    keeps the first place (no start joins it)."""
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(
        Constraints(subjects=[SubjectConstraint("ball")], elevation="high angle"), {"ball": (index, centroid, None)}, up
    )
    high = make_camera(eye=(0.0, -3.0, 2.7), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    level = make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [level])
    scene = SceneDir(Path("."), gaussians, [level], None, SceneMeta(up), None)
    parsed = parse_instruction("the ball from a high angle", Vocabulary.from_semantics([SemanticObject(0, "ball", [], True)]))

    def run(start, end) -> RefineResult:
        trajectory = np.stack([start.T_cw, end.T_cw])
        return RefineResult(end.T_cw, 1, "plateau", {}, trajectory, np.array([1.0, 0.1]), {"size": np.array([0.7, 0.0])}, 0.0)

    answer, reports = closest_answer(scene, labels, parsed, Refined([(high, run(high, level))]), occupancy)
    assert [r.stop_reason for _, r in answer.runs] == ["unrefined", "plateau"]
    np.testing.assert_array_equal(answer.cameras[0].T_cw, high.T_cw)
    assert reports[0].all_satisfied and not reports[1].all_satisfied
    assert all(r.satisfied for r in reports[1].rows if r.constraint != "elevation")
    answer, reports = closest_answer(scene, labels, parsed, Refined([(level, run(level, high))]), occupancy)
    assert [r.stop_reason for _, r in answer.runs] == ["plateau"] and reports[0].all_satisfied


def test_a_camera_drawn_inside_the_accepted_intervals_answers_when_no_run_does():
    """Refine's run and its start both fail (the ball too big from too near, seen level): the
    search draws inside the asked intervals and returns, first, a free camera whose own report
    satisfies every clause (a small ball from a high angle), the same on every call; with no
    draw in free space (an occupancy with none) the runs stand as they were."""
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    constraints = Constraints(subjects=[SubjectConstraint("ball", shot="wide")], elevation="high angle")
    labels = labels_from_constraints(constraints, {"ball": (index, centroid, None)}, up)
    near = make_camera(eye=(0.0, -1.2, 0.5), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0), width=96, height=72)
    occupancy = build_occupancy(gaussians, up, [near])
    scene = SceneDir(Path("."), gaussians, [near], None, SceneMeta(up), None)
    parsed = parse_instruction(
        "the ball small in frame from a high angle", Vocabulary.from_semantics([SemanticObject(0, "ball", [], True)])
    )
    run = RefineResult(near.T_cw, 0, "plateau", {}, near.T_cw[None], np.array([1.0]), {}, 0.0)

    answer, reports = closest_answer(scene, labels, parsed, Refined([(near, run)]), occupancy)
    assert not reports[-1].all_satisfied
    assert answer.runs[0][1].stop_reason == "searched" and reports[0].all_satisfied
    searched = answer.cameras[0]
    assert float(occupancy.clearance(torch.as_tensor(searched.center))) > 0
    assert np.linalg.norm(searched.center - centroid) > np.linalg.norm(near.center - centroid)
    again, _ = closest_answer(scene, labels, parsed, Refined([(near, run)]), occupancy)
    np.testing.assert_array_equal(again.cameras[0].T_cw, searched.T_cw)

    blocked = dataclasses.replace(occupancy, sdf=np.full_like(occupancy.sdf, -1.0))
    answer, reports = closest_answer(scene, labels, parsed, Refined([(near, run)]), blocked)
    assert "searched" not in [r.stop_reason for _, r in answer.runs] and not reports[0].all_satisfied


def solve_two_balls(offset: tuple[float, float, float]):
    """The closed-form cameras (up to 8 kept) for the ball of :func:`ball_before_wall` with a
    second ball ``offset`` from it (secondary), seen by a reference 4 in front of it along -y.
    Returns the candidates, the Gaussian means (N, 3), the two balls' indices, the labels and the
    scene."""
    gaussians = ball_before_wall(seed=2, spacing=0.1, wall_y=3.0, wall_height=0.2, scale=0.04, opacity=0.95)
    second = gaussians.means[:400] + torch.tensor(offset, dtype=gaussians.means.dtype)
    n = len(gaussians) + 400
    gaussians = GaussianScene.from_activated(
        torch.cat([gaussians.means, second]),
        torch.tensor([1.0, 0, 0, 0]).expand(n, 4).clone(),
        torch.full((n, 3), 0.04),
        torch.full((n,), 0.95),
        torch.rand(n, 3, generator=torch.Generator().manual_seed(3)),
    )
    up = np.array([0.0, 0.0, 1.0])
    means = gaussians.means.double().numpy()
    first, other = np.arange(400), np.arange(n - 400, n)
    subjects = {"ball": (first, means[first].mean(0), None), "bear": (other, means[other].mean(0), None)}
    reference = make_camera(eye=(0.0, -4.0, 0.4), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [reference])
    constraints = Constraints(subjects=[SubjectConstraint("ball"), SubjectConstraint("bear", role="secondary")])
    labels = labels_from_constraints(constraints, subjects, up)
    return solve_candidates(gaussians, labels, reference, occupancy, keep=8), means, (first, other), labels, gaussians


def test_kept_cameras_that_see_every_subject_rank_first():
    """A second ball straight behind the first as the reference view sees them: the closed-form
    camera on the reference's side (the first of the grid) sees the primary but not the other,
    hidden behind it; cameras 45 degrees round see both and rank first."""
    solved, *_ = solve_two_balls((0.0, 2.5, 0.0))
    kept = [c for c in solved if c.status == "kept"]
    assert kept[0].others_unseen == 0 and abs(kept[0].azimuth_deg) == 45.0
    assert next(c for c in kept if c.azimuth_deg == 0.0).others_unseen == 1
    assert [c.others_unseen for c in kept] == sorted(c.others_unseen for c in kept)


def test_a_kept_camera_turns_to_the_middle_of_the_subjects_to_see_them_all():
    """A second ball 2.6 to the side of the first, as far as the reference view stands from it:
    from the reference's side (the first of the grid) looking at the primary, the second lies 33
    degrees off the axis, out of the 28-degree half frame; turned where it stands to the middle
    of the two, the camera sees both (the primary left of the centre, the second right of it),
    and its view angles stay."""
    solved, means, balls, labels, gaussians = solve_two_balls((2.6, 0.0, 0.0))
    front = next(c for c in solved if c.status == "kept" and c.azimuth_deg == 0.0)
    assert front.others_unseen == 0
    T, K = front.camera.T_cw, front.camera.K
    u = [float(K[0] @ (p / p[2])) for p in (T[:3, :3] @ means[k].mean(0) + T[:3, 3] for k in balls)]
    assert u[0] < front.camera.width / 2 < u[1]
    origin, _ = view_centre(gaussians, labels.subjects[0], np.array([0.0, 0.0, 1.0]))
    direction = (front.camera.center - origin) / np.linalg.norm(front.camera.center - origin)
    assert direction @ np.array([0.0, -1.0, 0.0]) > 0.99  # still on the reference's side


def test_margin_elevations_reach_into_the_accepted_interval_never_beyond():
    """The margin elevations invert view_target's margin for wide and narrow intervals: each lies
    between the aimed and the accepted end, at MARGIN_SPREAD of the margin, upper end first."""
    for lo, hi in [(-60.0, -8.0), (8.0, 30.0), (-12.0, 12.0), (80.0, 90.0), (-90.0, -80.0), (25.0, 31.0)]:
        target = view_target(None, (lo, hi))
        label = SubjectLabel("vase", np.arange(3), np.zeros(3), None, view=target)
        aimed = target.elevation_range_deg
        margins = _margin_elevations(label)
        assert len(margins) == 2 * len(MARGIN_SPREAD) and margins[0] > aimed[1]
        for e in margins:
            assert lo <= e <= hi and not aimed[0] <= e <= aimed[1]
    low = SubjectLabel("sofa", np.arange(3), np.zeros(3), None, view=view_target(None, (-60.0, -8.0)))
    # aimed -56 .. -12, accepted -60 .. -8: at 0.5 and 0.85 of the 4 degrees beyond each end.
    assert _margin_elevations(low) == pytest.approx([-10.0, -58.0, -8.6, -59.4])


def test_free_edge_and_sized_distance():
    """The free edge is found by bisection to within (outer - inner) / 2^steps; the sized distance
    scales the distance by the measured over the wanted extent, a tenth inside the nearer end."""
    assert _free_edge(lambda d: d <= 3.3, 2.0, 4.0, steps=10) == pytest.approx(3.3, abs=2.0 / 2**10)
    assert _free_edge(lambda d: False, 2.0, 4.0) == 2.0
    assert _sized_distance(10.0, 0.8, (0.3, 0.5)) == pytest.approx(10.0 * 0.8 / 0.48)
    assert _sized_distance(10.0, 0.1, (0.3, 0.5)) == pytest.approx(10.0 * 0.1 / 0.32)
    assert _sized_distance(10.0, 0.4, (0.3, 0.5)) is None and _sized_distance(10.0, 0.4, None) is None
    assert _sized_distance(10.0, 0.55, (0.3, 0.5)) is None  # the checker accepts it: Refine's to finish
    # The checker's interval, not Refine's narrower one: inside it nothing is missed.
    medium = (0.25 * (1 + SHOT_MARGIN), 0.6 * (1 - SHOT_MARGIN))
    assert _size_miss(0.58, medium) == 0.0 and _size_miss(0.7, medium) == pytest.approx(0.1 - SIZE_SLACK)
    assert _size_miss(0.9, None) == 0.0


def test_report_order_returns_the_camera_nearest_to_a_clause_it_cannot_meet():
    """Poses failing the same clauses: the one nearest to meeting them comes first (a view 20
    degrees off before one 100 degrees off; an angle weighs its error over 90 degrees against a
    frame fraction), whatever Refine's order."""

    def report(view_error: float, shot_error: float = 0.0) -> CheckReport:
        rows = [CheckRow("visibility", "sofa", True, 1.0, {}, 0.0), CheckRow("view", "sofa", False, 0.0, {}, view_error, "deg")]
        rows.append(CheckRow("shot", "sofa", shot_error == 0.0, 0.5, {}, shot_error, "frame fraction"))
        return CheckReport(rows)

    assert report_order([report(100.0), report(20.0), report(60.0)]) == [1, 2, 0]
    assert report_order([report(30.0, 0.5), report(50.0)]) == [1, 0]  # fewer failing clauses first
    assert report_order([report(60.0), report(40.0, 0.0)]) == [1, 0]
    assert shortfall(report(45.0, 0.2)) == pytest.approx(0.7)


def test_an_overhang_leaves_only_the_margin_of_an_asked_elevation():
    """A ball under a slab (z = 0.9, y from -2 to 0.5, x from -3 to 3) that overhangs its front:
    "slightly above" (8 to 30 degrees, aimed 12 to 26) sees it only below about 11 degrees, so
    every camera of the grid is occluded and the closed form keeps one at an elevation in the
    margin between the aimed and the accepted interval, in front as asked."""
    g = ball_before_wall(seed=4, spacing=0.05, wall_y=3.0, wall_height=0.2, scale=0.04, opacity=0.95)
    a, b = torch.meshgrid(torch.arange(-3.0, 3.0 + 1e-9, 0.05), torch.arange(-2.0, 0.5 + 1e-9, 0.05), indexing="ij")
    slab = torch.stack([a.reshape(-1), b.reshape(-1), torch.full((a.numel(),), 0.9)], 1)
    n = len(g) + len(slab)
    gaussians = GaussianScene.from_activated(
        torch.cat([g.means, slab.float()]),
        torch.tensor([1.0, 0, 0, 0]).expand(n, 4).clone(),
        torch.full((n, 3), 0.04),
        torch.full((n,), 0.95),
        torch.rand(n, 3, generator=torch.Generator().manual_seed(5)),
    )
    up = np.array([0.0, 0.0, 1.0])
    subjects = {"ball": (np.arange(400), gaussians.means[:400].double().mean(0).numpy(), np.array([0.0, -1.0, 0.0]))}
    reference = make_camera(eye=(0.0, -4.0, 0.5), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [reference])
    constraints = Constraints(subjects=[SubjectConstraint("ball", view="front")], elevation="slightly above")
    labels = labels_from_constraints(constraints, subjects, up)
    low, high = labels.subjects[0].view.elevation_range_deg
    solved = solve_candidates(gaussians, labels, reference, occupancy)
    assert all(c.status == "occluded" for c in solved if low <= c.elevation_deg <= high)
    best = solved[0]
    assert best.status == "kept" and best.azimuth_deg == 0.0 and 8.0 <= best.elevation_deg < low
    assert best.visible >= MIN_VISIBLE_FRACTION


def tree_on_lawn() -> tuple[GaussianScene, np.ndarray, np.ndarray]:
    """A "tree" (indices 0..399): a trunk of 40 Gaussians on the line x = y = 0 from z = 0 to 2
    and a crown of 358 on the sphere of radius 1 about (0, 0, 3), with its lowest and highest
    points (0, 0, 0) and (0, 0, 4) among them, on a floor z = 0 over x, y in [-8, 8]. Most
    Gaussians are in the crown, so the centroid stands near z = 2.7, well above the middle of
    the tree's height (z = 2). Returns the Gaussians, the tree's indices and the up."""
    g = torch.Generator().manual_seed(7)
    trunk = torch.stack([torch.zeros(40), torch.zeros(40), torch.linspace(0.0, 2.0, 40)], 1).double()
    crown = torch.randn(358, 3, generator=g, dtype=torch.float64)
    crown = crown / crown.norm(dim=1, keepdim=True) + torch.tensor([0.0, 0.0, 3.0], dtype=torch.float64)
    crown = crown.clamp(min=torch.tensor([-9.0, -9.0, 2.0], dtype=torch.float64))  # the crown sits on the trunk
    ends = torch.tensor([[0.0, 0.0, 0.0], [0.0, 0.0, 4.0]], dtype=torch.float64)
    s = torch.arange(-8.0, 8.0 + 1e-9, 0.25, dtype=torch.float64)
    a, b = torch.meshgrid(s, s, indexing="ij")
    floor = torch.stack([a.reshape(-1), b.reshape(-1), torch.zeros(a.numel(), dtype=torch.float64)], 1)
    means = torch.cat([trunk, crown, ends, floor])
    n = len(means)
    gaussians = GaussianScene.from_activated(
        means.float(),
        torch.tensor([1.0, 0, 0, 0]).expand(n, 4).clone(),
        torch.full((n, 3), 0.08),
        torch.full((n,), 0.95),
        torch.rand(n, 3, generator=g),
    )
    return gaussians, np.arange(400), np.array([0.0, 0.0, 1.0])


def test_view_centre_is_the_middle_of_the_subjects_height_under_its_centroid():
    """The tree's view centre: its centroid's horizontal position at half its height (z = 2,
    the middle of 0 and 4), and the height 4; the centroid stands far higher (the crown)."""
    gaussians, index, up = tree_on_lawn()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(Constraints(subjects=[SubjectConstraint("tree")]), {"tree": (index, centroid, None)}, up)
    centre, height = view_centre(gaussians, labels.subjects[0], up)
    assert centroid[2] > 2.5
    np.testing.assert_allclose(centre, [centroid[0], centroid[1], 2.0], atol=1e-6)
    assert height == pytest.approx(4.0, abs=1e-6)


def test_an_explicit_low_angle_at_a_tree_is_solved_around_the_middle_of_its_height():
    """ "From 20 degrees below" a tree whose crown lifts the centroid: the closed form's cameras
    lie at the elevations they report around the middle of the tree's height (where the checker
    and the photographer measure), not around the centroid, and the first kept one within the
    accepted +-10 degrees of -20 there."""
    gaussians, index, up = tree_on_lawn()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    constraints = Constraints(subjects=[SubjectConstraint("tree", shot="medium")], elevation_deg=-20.0)
    labels = labels_from_constraints(constraints, {"tree": (index, centroid, None)}, up)
    reference = make_camera(eye=(0.0, -12.0, 2.0), target=(0.0, 0.0, 2.0), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [reference])
    solved = solve_candidates(gaussians, labels, reference, occupancy)
    middle = np.array([centroid[0], centroid[1], 2.0])
    for c in solved:
        offset = c.camera.center - middle
        elevation = math.degrees(math.asin(offset @ up / np.linalg.norm(offset)))
        assert elevation == pytest.approx(c.elevation_deg, abs=1e-6)
        assert np.linalg.norm(offset) == pytest.approx(c.distance, rel=1e-9)
    kept = solved[0]
    assert kept.status == "kept"
    assert abs(kept.elevation_deg + 20.0) <= EXPLICIT_ELEVATION_TOLERANCE_DEG
    assert float(occupancy.clearance(torch.as_tensor(kept.camera.center))) >= 0.0


def test_a_camera_keeps_the_smaller_of_the_floor_margins():
    """A camera three quarters of the occupancy's floor margin above the floor plane (far from
    the tree) breaks that margin, but keeps a margin half as high (a small subject's): the
    slack is then the height above the plane less the smaller margin, and the free-space loss
    zero; a margin larger than the occupancy's is never taken."""
    gaussians, _, up = tree_on_lawn()
    occupancy = build_occupancy(gaussians, up, [make_camera(eye=(0.0, -12.0, 2.0), target=(0.0, 0.0, 2.0))])
    margin = occupancy.floor_margin
    point = torch.tensor([5.0, -5.0, occupancy.floor_height + 0.75 * margin], dtype=torch.float64)
    assert float(occupancy.slack(point)) == pytest.approx(-0.25 * margin, abs=1e-6)
    assert float(occupancy.slack(point, 0.5 * margin)) == pytest.approx(0.25 * margin, abs=1e-6)
    assert float(occupancy.slack(point, 10.0 * margin)) == pytest.approx(-0.25 * margin, abs=1e-6)
    T = torch.eye(4, dtype=torch.float64)
    T[:3, 3] = -point
    assert float(free_space_loss(T, occupancy, 0.5 * margin)) == 0.0
    assert float(free_space_loss(T, occupancy)) > 0.0


def test_the_floor_bounds_a_low_angle_at_the_asked_distance():
    """The steepest elevation at which a camera at distance d from the tree's view centre (z = 2)
    keeps its margin above the floor plane is -asin((2 - floor - margin) / d); the grid keeps the
    elevations no steeper than it, or all when none would be left."""
    gaussians, index, up = tree_on_lawn()
    occupancy = build_occupancy(gaussians, up, [make_camera(eye=(0.0, -12.0, 2.0), target=(0.0, 0.0, 2.0))])
    origin = np.array([0.0, 0.0, 2.0])
    height = 2.0 - occupancy.floor_height - 0.5 * occupancy.floor_margin
    bound = _floor_elevation(occupancy, origin, 8.0, 0.5 * occupancy.floor_margin, None)
    assert bound == pytest.approx(-math.degrees(math.asin(height / 8.0)), abs=1e-9)
    assert _floor_elevation(occupancy, origin, 1.0, None, None) is None  # the floor is beyond reach
    assert _above_floor([-20.0, -12.0, -5.0], [-3.0, -40.0], [-13.0]) == ([-12.0, -5.0], [-3.0])
    assert _above_floor([-20.0, -30.0], [-40.0], [-13.0]) == ([-20.0, -30.0], [-40.0])
    assert _above_floor([-20.0, -30.0], [-8.0, -40.0], [-7.0, -13.0]) == ([], [-8.0])  # the nearer distance's
    assert _above_floor([-20.0], [-40.0], [None]) == ([-20.0], [-40.0])


def test_floor_reach_stops_a_ray_at_the_floor_less_its_margin():
    gaussians, _, up = walled_scene()
    occupancy = build_occupancy(gaussians, up, [make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0))])
    origin = np.array([0.0, -1.0, 0.4])
    for elevation in (-10.0, -45.0, -90.0):
        e = math.radians(elevation)
        direction = np.array([0.0, -math.cos(e), math.sin(e)])
        reach = _floor_reach(occupancy, _Ray(origin, origin, direction))
        end = origin + reach * direction
        assert end[2] - occupancy.floor_height == pytest.approx(occupancy.height_kept(None), abs=1e-12)
    # Level or rising: unbounded.
    for direction in ([0.0, -1.0, 0.0], [0.0, -0.6, 0.8]):
        assert _floor_reach(occupancy, _Ray(origin, origin, np.array(direction))) == math.inf


def kept_low_angles(gaussians: GaussianScene, reference) -> tuple[list, object]:
    """The kept closed-form cameras for a low angle at the ball (indices 0..399, front -y) of a
    scene whose up is +z, and the occupancy built around ``reference``."""
    up = np.array([0.0, 0.0, 1.0])
    centroid = gaussians.means[:400].double().mean(0).numpy()
    subjects = {"ball": (np.arange(400), centroid, np.array([0.0, -1.0, 0.0]))}
    occupancy = build_occupancy(gaussians, up, [reference])
    low = labels_from_constraints(Constraints(subjects=[SubjectConstraint("ball")], elevation="low angle"), subjects, up)
    return [c for c in solve_candidates(gaussians, low, reference, occupancy) if c.status == "kept"], occupancy


def test_a_low_angle_from_a_far_reference_view_finds_the_stretch_above_the_floor():
    """The reference view is 40 units out: its distance scales the slides, which all fell under
    the floor at a low angle before they started where the ray meets the floor plane."""
    gaussians = ball_before_wall(seed=2, spacing=0.1, wall_y=2.9, wall_height=0.2, scale=0.06, opacity=0.9)
    kept, occupancy = kept_low_angles(gaussians, make_camera(eye=(0.0, -40.0, 2.0), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, -1.0)))
    assert kept and all(c.elevation_deg < 0 for c in kept)
    assert float(occupancy.clearance(torch.as_tensor(kept[0].camera.center))) >= 0


def test_a_table_top_bounds_a_low_angle_as_the_floor_does():
    """Over a support higher than the floor the steepest elevation keeping the camera above it is
    -asin((z - top - margin) / d) for a view centre at height z; the lower floor gives way to it."""
    gaussians = ball_on_table(seed=3)
    occupancy = build_occupancy(
        gaussians, np.array([0.0, 0.0, 1.0]), [make_camera(eye=(0.0, -12.0, 3.0), target=(0.0, 0.0, 1.3))]
    )
    origin = np.array([0.0, 0.0, 1.3])
    kept = occupancy.height_kept(None)
    bound = _floor_elevation(occupancy, origin, 2.0, None, 1.0)
    assert bound == pytest.approx(-math.degrees(math.asin((0.3 - kept) / 2.0)), abs=1e-9)
    assert _floor_elevation(occupancy, origin, 2.0, None, None) < bound  # the floor alone allows steeper
    assert _floor_elevation(occupancy, origin, 0.2, None, 1.0) is None  # the top is beyond reach


def test_a_medium_low_angle_at_a_ball_on_a_table_keeps_near_its_size_above_the_top():
    """A medium shot at a low angle of the ball on the table: bounded by the top, the grid starts at
    the shallow end of the interval, whose ray stays over the top, instead of sliding in from the
    steeper ones until the ball overflows the asked size."""
    gaussians = ball_on_table(seed=3)
    up = np.array([0.0, 0.0, 1.0])
    centroid = gaussians.means[:400].double().mean(0).numpy()
    subjects = {"ball": (np.arange(400), centroid, np.array([0.0, -1.0, 0.0]))}
    reference = make_camera(eye=(0.0, -12.0, 3.0), target=(0.0, 0.0, 1.3), up=(0.0, 0.0, -1.0))
    occupancy = build_occupancy(gaussians, up, [reference])
    asked = Constraints(subjects=[SubjectConstraint("ball", shot="medium")], elevation="low angle")
    labels = labels_from_constraints(asked, subjects, up)
    kept = [c for c in solve_candidates(gaussians, labels, reference, occupancy) if c.status == "kept"]
    assert kept and kept[0].camera.center[2] > 1.0 and -60.0 <= kept[0].elevation_deg <= -8.0
    assert kept[0].size_miss < 0.2


def test_the_inner_aim_point_is_the_region_point_nearest_the_frame_centre():
    def subject(region):
        return SubjectLabel("lamp", np.arange(3), np.zeros(3), region=region)

    assert _inner_aim_point(subject((0.04, 0.04, 0.41, 0.41))) == (0.41, 0.41)
    assert _inner_aim_point(subject((0.59, 0.04, 0.96, 0.96))) == (0.59, 0.5)
    assert _inner_aim_point(subject((0.3, 0.3, 0.7, 0.7))) is None  # its centre already
    assert _inner_aim_point(subject(None)) is None


def ball_on_table(seed: int) -> GaussianScene:
    """The ball of :func:`ball_before_wall` (indices 0..399) lifted onto a table top at z = 1
    (x, y in [-2, 2]) over a floor z = 0 (x, y in [-6, 6]), both of flat Gaussians."""
    g = torch.Generator().manual_seed(seed)
    ball = torch.randn(400, 3, generator=g, dtype=torch.float64)
    ball = ball / ball.norm(dim=1, keepdim=True) * 0.3 + torch.tensor([0.0, 0.0, 1.3], dtype=torch.float64)

    def sheet(half: float, z: float) -> torch.Tensor:
        s = torch.arange(-half, half + 1e-9, 0.1, dtype=torch.float64)
        a, b = torch.meshgrid(s, s, indexing="ij")
        return torch.stack([a.reshape(-1), b.reshape(-1), torch.full((a.numel(),), z, dtype=torch.float64)], 1)

    means = torch.cat([ball, sheet(2.0, 1.0), sheet(6.0, 0.0)])
    n = len(means)
    scales = torch.tensor([0.06, 0.06, 0.005]).repeat(n, 1)
    scales[:400] = 0.06
    return GaussianScene.from_activated(
        means.float(),
        torch.tensor([1.0, 0, 0, 0]).expand(n, 4).clone(),
        scales,
        torch.full((n,), 0.9),
        torch.rand(n, 3, generator=g),
    )


def test_a_low_angle_at_a_ball_on_a_table_is_solved_above_the_table_not_under_it():
    """Far out along a low ray the free space lies under the table top, which hides the ball: the
    positions below the ball that look at it through the table are rendered last, so the near
    ones above the table are reached."""
    reference = make_camera(eye=(0.0, -12.0, 3.0), target=(0.0, 0.0, 1.3), up=(0.0, 0.0, -1.0))
    kept, _ = kept_low_angles(ball_on_table(seed=3), reference)
    assert kept and kept[0].camera.center[2] > 1.0


class _Ceiling:
    """Free space below a ceiling: a camera is free within ``reach`` of the origin (no floor)."""

    rotation = np.eye(3)
    floor_height = -math.inf

    def __init__(self, reach: float):
        self.reach = reach

    def slack(self, centre, floor_margin=None):
        return torch.as_tensor(self.reach - float(np.linalg.norm(np.asarray(centre))))

    def clearance(self, centre):
        return self.slack(centre)

    def segment_blocked(self, *_):
        return 0


class _FitsFrom:
    """A subject wholly unhidden that fits the frame from ``fit`` out (cut off nearer)."""

    def __init__(self, fit: float):
        self.fit = fit

    def __call__(self, camera) -> _Seen:
        return _Seen(1.0, min(1.0, float(np.linalg.norm(camera.center)) / self.fit), 0.2, 0, True)

    def sees(self, seen: _Seen) -> bool:
        return seen.visible >= MIN_VISIBLE_FRACTION and seen.in_frame >= 1.0


def test_a_subject_cut_off_at_the_first_free_slide_is_placed_at_the_free_edge():
    """Looking down over an occluder under a ceiling: the slides from 10 out are free only from 3
    in, where the subject is cut off by the frame; the camera moves out to where the free space
    ends (3.2), where it fits (from 3.1), rather than being reported too close."""
    up = np.array([0.0, 0.0, 1.0])
    direction = np.array([0.0, -math.cos(math.radians(50.0)), math.sin(math.radians(50.0))])
    ray = _Ray(origin=np.zeros(3), target=np.zeros(3), direction=direction)
    subject = SubjectLabel("ball", np.arange(1), np.zeros(3), None)
    labels = PseudoLabels([subject], up)
    reference = make_camera(eye=(0.0, -10.0, 0.0), up=(0.0, 0.0, -1.0))
    camera, clearance, seen, status = _place(_Ceiling(3.2), _FitsFrom(3.1), ray, 10.0, 1.0, labels, (0.5, 0.5), reference)
    assert status == "kept" and seen.in_frame == 1.0
    assert 3.1 <= np.linalg.norm(camera.center) <= 3.2 and clearance >= 0
