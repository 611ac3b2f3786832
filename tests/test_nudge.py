"""The nudge after Refine (capframe.refine.nudge): a camera that misses an asked angle by a few
degrees moves on the subject's view sphere into the accepted interval, the subject keeping its
pixel; and the answer takes it when the method's own report then holds."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import torch
from conftest import make_camera
from test_candidates import walled_scene

from capframe.constraints import Constraints, SubjectConstraint
from capframe.geometry import camera_roll, view_angles
from capframe.measure import CheckReport, CheckRow
from capframe.pipeline.outputs import closest_answer
from capframe.pipeline.stages import Refined
from capframe.refine.nudge import NUDGE_MARGIN_DEG, angle_misses, orbited
from capframe.refine.optimize import RefineResult
from capframe.scene.directory import SceneDir, SceneMeta, SemanticObject
from capframe.scene.occupancy import build_occupancy
from capframe.translate.labels import labels_from_constraints
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import Vocabulary

F64 = dict(dtype=torch.float64)


def angles(camera, pivot, front, up) -> tuple[float, float]:
    az, el = view_angles(
        torch.tensor(camera.center, **F64), torch.tensor(pivot, **F64), torch.tensor(front, **F64), torch.tensor(up, **F64)
    )
    return math.degrees(float(az)), math.degrees(float(el))


def pixel(camera, point) -> np.ndarray:
    x = camera.R @ point + camera.t
    return (camera.K @ (x / x[2]))[:2]


def roll(camera, up) -> float:
    return math.degrees(float(camera_roll(torch.tensor(camera.T_cw, **F64), torch.tensor(up, **F64))))


@pytest.mark.parametrize("turn", [(0.0, -3.0), (12.0, 0.0), (-7.0, 5.0)])
@pytest.mark.parametrize("share", [1.0, 0.55])
def test_orbited_turns_the_centre_by_the_asked_angles_and_keeps_the_aim_pixel_and_roll(turn, share):
    """Azimuth (about the subject's own front, +90 its right) and elevation of the camera centre
    about the pivot change by exactly the turn, the distance by ``share``; the aimed point keeps
    its pixel; the horizon keeps its roll when the point is at the image centre."""
    up = np.array([0.0, 0.0, 1.0])
    front = np.array([0.3, -1.0, 0.0])
    pivot = np.array([0.2, 0.1, 0.5])
    camera = make_camera(eye=(1.5, -3.0, 1.2), target=tuple(pivot), up=tuple(up), width=64, height=48)
    moved = orbited(camera, pivot, pivot, front, up, turn, share)
    before, after = angles(camera, pivot, front, up), angles(moved, pivot, front, up)
    assert after[0] - before[0] == pytest.approx(turn[0], abs=1e-9)
    assert after[1] - before[1] == pytest.approx(turn[1], abs=1e-9)
    assert np.linalg.norm(moved.center - pivot) == pytest.approx(share * np.linalg.norm(camera.center - pivot), rel=1e-12)
    np.testing.assert_allclose(pixel(moved, pivot), pixel(camera, pivot), atol=1e-9)
    assert roll(moved, up) == pytest.approx(roll(camera, up), abs=1e-9)


def test_orbited_keeps_an_off_centre_aim_at_its_pixel():
    """A subject in the lower left of the frame stays there: the turn is about the pivot (the
    subject's view centre), the aim its centroid."""
    up = np.array([0.0, 0.0, 1.0])
    pivot, aim = np.array([0.0, 0.0, 0.5]), np.array([0.0, 0.0, 0.7])
    camera = make_camera(eye=(0.5, -4.0, 0.8), target=(0.9, 0.3, 1.3), up=tuple(up))
    moved = orbited(camera, pivot, aim, None, up, (0.0, -4.0))
    np.testing.assert_allclose(pixel(moved, aim), pixel(camera, aim), atol=1e-9)
    assert angles(moved, pivot, [1.0, 0.0, 0.0], up)[1] == pytest.approx(angles(camera, pivot, [1.0, 0.0, 0.0], up)[1] - 4.0)


def test_orbited_refuses_an_aim_behind_the_camera_and_a_pole():
    up = np.array([0.0, 0.0, 1.0])
    camera = make_camera(eye=(0.0, -4.0, 1.0), target=(0.0, 0.0, 1.0), up=tuple(up))
    assert orbited(camera, np.zeros(3), np.array([0.0, -6.0, 1.0]), None, up, (0.0, 5.0)) is None
    assert orbited(camera, np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0]), None, up, (0.0, 89.5)) is None


def elevation_row(measured, lo, hi, subject="pot"):
    from capframe.measure import interval_distance

    error = interval_distance(measured, lo, hi)
    return CheckRow("elevation", subject, error == 0.0, measured, {"range_deg": [lo, hi]}, error, "deg")


def view_row(measured, azimuths, tolerance=30.0, subject="pot"):
    from capframe.measure import wrap_deg

    deviation = min(abs(wrap_deg(measured - a)) for a in azimuths)
    target = {"view": "x", "azimuths_deg": azimuths, "tolerance_deg": tolerance}
    return CheckRow("view", subject, deviation <= tolerance, measured, target, deviation, "deg")


def visible(subject="pot", ok=True):
    return CheckRow("visibility", subject, ok, 0.9 if ok else 0.1, {}, 0.0 if ok else 0.4, "fraction")


def test_angle_misses_on_hand_checked_rows():
    """An elevation of -6.8 asked in [-30, -8] turns -3.2 (to 2 degrees inside); a view 35
    degrees off its left (tolerance 30) turns 7 degrees towards it; both wrap across the back."""
    assert angle_misses(CheckReport([visible(), elevation_row(-6.8, -30.0, -8.0)]), "pot") == pytest.approx((0.0, -3.2))
    assert angle_misses(CheckReport([elevation_row(63.0, 25.0, 60.0)]), "pot") == pytest.approx((0.0, -5.0))
    assert angle_misses(CheckReport([elevation_row(-1.0, 0.0, 4.0)]), "pot") == pytest.approx((0.0, 2.0))  # a quarter width
    assert angle_misses(CheckReport([view_row(-55.0, [-90.0])]), "pot") == pytest.approx((-7.0, 0.0))
    assert angle_misses(CheckReport([view_row(145.0, [180.0, -180.0])]), "pot") == pytest.approx((7.0, 0.0))
    assert angle_misses(CheckReport([view_row(-145.0, [180.0])]), "pot") == pytest.approx((-7.0, 0.0))
    both = angle_misses(CheckReport([view_row(-55.0, [-90.0]), elevation_row(-6.8, -30.0, -8.0)]), "pot")
    assert both == pytest.approx((-7.0, -3.2))
    assert NUDGE_MARGIN_DEG == 2.0


def test_angle_misses_leaves_other_failures_and_large_misses():
    """No turn when nothing angular fails, when another clause fails, when the failing angle is
    another subject's, or when the miss is not a settling error."""
    assert angle_misses(CheckReport([visible(), elevation_row(-9.0, -30.0, -8.0)]), "pot") is None
    assert angle_misses(CheckReport([visible(ok=False), elevation_row(-6.8, -30.0, -8.0)]), "pot") is None
    assert angle_misses(CheckReport([view_row(-55.0, [-90.0], subject="tree")]), "pot") is None
    assert angle_misses(CheckReport([elevation_row(10.0, 25.0, 60.0)]), "pot") is None


def test_a_camera_just_below_an_asked_height_is_nudged_into_it_and_answered():
    """A ball before a wall, asked from slightly above ([8, 30] degrees): Refine ended at about 5
    degrees with the ball shown; the answer is that camera turned 5 degrees up about the ball,
    in free space, every clause of its own report holding; without the nudge it failed."""
    gaussians, index, up = walled_scene()
    centroid = gaussians.means[:400].double().mean(0).numpy()
    labels = labels_from_constraints(
        Constraints(subjects=[SubjectConstraint("ball", shot="medium")], elevation="slightly above"),
        {"ball": (index, centroid, None)},
        up,
    )
    low = make_camera(eye=(0.0, -4.0, 0.7), target=(0.0, 0.0, 0.4), up=(0.0, 0.0, 1.0))
    occupancy = build_occupancy(gaussians, up, [low])
    scene = SceneDir(Path("."), gaussians, [low], None, SceneMeta(up), None)
    vocabulary = Vocabulary.from_semantics([SemanticObject(0, "ball", [], True)])
    parsed = parse_instruction("the ball, medium shot, from slightly above", vocabulary)
    result = RefineResult(low.T_cw, 1, "plateau", {}, low.T_cw[None], np.array([0.1]), {}, 0.0)
    answer, reports = closest_answer(scene, labels, parsed, Refined([(low, result)]), occupancy)
    assert answer.runs[0][1].stop_reason == "nudged" and reports[0].all_satisfied
    elevation = reports[0].row("elevation").measured
    assert 8.0 < elevation < 8.0 + NUDGE_MARGIN_DEG + 1e-6
    assert answer.runs[0][1].nudge_deg[1] > 0
    assert not reports[1].all_satisfied and reports[1].row("elevation").satisfied is False
