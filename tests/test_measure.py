"""The measurement layer (capframe.measure): its distances on hand-checkable values, and one
measurement for every consumer (Question-Evaluation's per-view answers and the checker agree)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _synth_helpers import aim_camera, build_scene, obj

from capframe.constraints import Constraints, SubjectConstraint
from capframe.evaluate import GroundTruthChecker
from capframe.measure import box_distance, interval_distance, wrap_deg
from capframe.retrieve.views import measure_views
from capframe.scene import load_scene_dir


@pytest.mark.parametrize(
    "angle, wrapped",
    [(0.0, 0.0), (180.0, 180.0), (-180.0, 180.0), (190.0, -170.0), (-190.0, 170.0), (540.0, 180.0), (359.5, -0.5), (-720.0, 0.0)],
)
def test_wrap_deg_lands_in_the_half_open_interval(angle, wrapped):
    assert wrap_deg(angle) == pytest.approx(wrapped, abs=1e-12)
    assert -180.0 < wrap_deg(angle) <= 180.0


def test_wrap_deg_is_the_shortest_signed_difference():
    # 350 deg and 10 deg are 20 deg apart, whichever way round.
    assert wrap_deg(10.0 - 350.0) == pytest.approx(20.0)
    assert wrap_deg(350.0 - 10.0) == pytest.approx(-20.0)


@pytest.mark.parametrize(
    "value, lo, hi, distance", [(0.5, 0.0, 1.0, 0.0), (-0.25, 0.0, 1.0, 0.25), (3.0, 0.0, 1.0, 2.0), (2.0, 2.0, 2.0, 0.0)]
)
def test_interval_distance(value, lo, hi, distance):
    assert interval_distance(value, lo, hi) == distance


@pytest.mark.parametrize(
    "x, y, distance",
    [
        (0.5, 0.5, 0.0),  # inside
        (0.2, 0.2, 0.0),  # on the corner
        (0.5, 0.9, 0.1),  # below the bottom edge only
        (0.2 - 0.03, 0.8 + 0.04, 0.05),  # diagonal from the lower-left corner: a 3-4-5 triangle
    ],
)
def test_box_distance(x, y, distance):
    assert box_distance(x, y, (0.2, 0.2, 0.8, 0.8)) == pytest.approx(distance, abs=1e-12)


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    root = tmp_path_factory.mktemp("measure")
    return root, build_scene(root)


@pytest.mark.parametrize("azimuth, elevation, point", [(0.0, 10.0, (0.5, 0.5)), (60.0, 35.0, (0.3, 0.65))])
def test_question_evaluation_and_the_checker_measure_the_same(world, azimuth, elevation, point):
    """QE answers from per-view measurements; the checker measures a camera; both must read one
    measurement: the same region centroid and shot extent for the same camera and resolution."""
    root, gt = world
    camera = aim_camera(gt, obj(gt, "teddy bear"), azimuth=azimuth, elevation=elevation, distance=4.0, point=point)
    long_side = max(camera.width, camera.height)
    views = measure_views(load_scene_dir(root), long_side=long_side, cameras=[camera], objects=["teddy bear"])
    report = GroundTruthChecker(root, long_side=long_side).check(
        camera, Constraints(subjects=[SubjectConstraint("teddy bear", region="center", shot="medium")])
    )
    o = views.object_names.index("teddy bear")
    np.testing.assert_allclose(report.row("region").measured, views.centroid[0, o], atol=1e-9)
    assert report.row("shot").measured == pytest.approx(views.extent[0, o], abs=1e-9)
    # The centroid is where the camera was aimed (a ball's visible mask is nearly symmetric).
    assert math.dist(report.row("region").measured, point) < 0.03
