"""Refine losses on hand-checkable cases, and the pose gradient of the full objective."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

from capframe.constraints import ELEVATIONS
from capframe.geometry import look_at, se3_exp, view_direction
from capframe.refine.losses import (
    Box,
    Frame,
    aim_loss,
    bbox_extent,
    box_indicator,
    layout_terms,
    mask_extent,
    soft_centroid,
    upright_loss,
    view_loss,
)
from capframe.refine.optimize import LossWeights, RefineConfig, _Objective
from capframe.translate.labels import PseudoLabels, SubjectLabel, ViewTarget, layout_boxes, min_in_frame_share, view_target

f64 = torch.float64


def vec(*v):
    return torch.tensor(v, dtype=f64)


def rect_mask(height, width, x0, y0, x1, y1):
    mask = torch.zeros(height, width, dtype=f64)
    mask[y0:y1, x0:x1] = 1.0
    return mask


def test_box_exactly_containing_the_mask_gives_zero_layout_loss():
    mask = rect_mask(40, 80, 20, 10, 40, 30)
    box = Box(20 / 80, 10 / 40, 40 / 80, 30 / 40)
    terms = layout_terms(mask, box, box)
    assert float(terms["center"]) < 1e-6 and float(terms["inside"]) == 0.0 and float(terms["outside"]) == 0.0
    centroid, mass = soft_centroid(mask)
    assert torch.allclose(centroid, vec(30.0, 20.0)) and float(mass) == 400.0


def test_centre_distance_and_leakage_by_hand():
    mask = rect_mask(40, 80, 60, 10, 80, 30)  # centroid (70, 20): 30 px right of a box ending at x = 40
    box = Box(0.0, 0.0, 0.5, 1.0)
    terms = layout_terms(mask, box, box)
    assert math.isclose(float(terms["center"]), 30 / 80, rel_tol=1e-9)
    assert float(terms["outside"]) == 1.0 and float(terms["inside"]) == 1.0
    half = rect_mask(40, 80, 30, 10, 50, 30)  # half of it inside x < 40
    assert math.isclose(float(layout_terms(half, box, None)["outside"]), 0.5)


def test_rotated_box_indicator_turns_counter_clockwise_on_screen():
    # A thin horizontal box rotated by +90 degrees becomes vertical.
    flat = box_indicator(Box(0.1, 0.45, 0.9, 0.55), 100, 100)
    turned = box_indicator(Box(0.1, 0.45, 0.9, 0.55, 90.0), 100, 100)
    assert torch.equal(turned, flat.T)
    # At +30 degrees the right end rises (smaller y) as the scene under a positive roll does.
    tilted = box_indicator(Box(0.1, 0.48, 0.9, 0.52, 30.0), 100, 100)
    ys_right = tilted[:, 80].nonzero()[:, 0].float().mean()
    ys_left = tilted[:, 20].nonzero()[:, 0].float().mean()
    assert ys_right < 50 < ys_left


def test_mask_extent_of_an_ellipse_matches_its_bounding_box():
    ys, xs = torch.meshgrid(torch.arange(120, dtype=f64) + 0.5, torch.arange(160, dtype=f64) + 0.5, indexing="ij")
    mask = (((xs - 80) / 40) ** 2 + ((ys - 60) / 20) ** 2 <= 1).to(f64)  # 80 x 40 px ellipse
    centroid, mass = soft_centroid(mask)
    assert math.isclose(float(mask_extent(mask, centroid, mass)), 80 / 160, rel_tol=0.05)
    terms = layout_terms(mask, None, None, extent=(0.6, 0.9))
    assert math.isclose(float(terms["size"]), math.log(0.6 / bbox_extent(mask)), rel_tol=1e-9)


def lamp_mask(scale: torch.Tensor) -> torch.Tensor:
    """(120, 160) floor-lamp mask zoomed by ``scale`` about the frame centre: a heavy shade and foot
    joined by a thin pole, rows 32..88 at scale 1."""
    ys, xs = torch.meshgrid(torch.arange(120, dtype=f64) + 0.5, torch.arange(160, dtype=f64) + 0.5, indexing="ij")
    u, v = (xs - 80) / scale, (ys - 60) / scale
    shade = torch.sigmoid(4 * (8 - torch.maximum((u / 2).abs(), (v + 20).abs())))
    foot = torch.sigmoid(4 * (4 - torch.maximum((u / 3).abs(), (v - 24).abs())))
    pole = torch.sigmoid(4 * (0.8 - u.abs())) * torch.sigmoid(4 * (24 - v.abs()))
    return torch.maximum(torch.maximum(shade, foot), pole)


def test_size_term_reads_the_bounding_box_of_an_uneven_shape_with_the_smooth_gradient():
    """The lamp's 4-sigma span is far taller than its bounding box, so a moment-based size term
    would call a too-small lamp a close-up; the term must read the box the checker measures, and
    pull with the gradient of the smooth extent, itself checked against finite differences."""
    scale = torch.tensor(1.0, dtype=f64, requires_grad=True)
    mask = lamp_mask(scale)
    box = bbox_extent(mask)
    assert math.isclose(box, 56 / 120, abs_tol=2 / 120)
    assert float(mask_extent(mask.detach(), *soft_centroid(mask.detach()))) > 1.25 * box
    close_up = layout_boxes(None, "close-up")[2]
    size = layout_terms(mask, None, None, extent=close_up)["size"]
    assert math.isclose(float(size.detach()), math.log(close_up[0] / box), rel_tol=1e-9)

    def neg_log_smooth_extent(m):
        return -torch.log(mask_extent(m, *soft_centroid(m)))

    (grad,) = torch.autograd.grad(size, scale, retain_graph=True)
    (smooth_grad,) = torch.autograd.grad(neg_log_smooth_extent(mask), scale)
    assert float(grad) < 0 and math.isclose(float(grad), float(smooth_grad), rel_tol=1e-9)  # zooming in shrinks it
    with torch.no_grad():
        numeric = (neg_log_smooth_extent(lamp_mask(vec(1.0 + 1e-6))) - neg_log_smooth_extent(lamp_mask(vec(1.0 - 1e-6)))) / 2e-6
    assert math.isclose(float(smooth_grad), float(numeric), rel_tol=1e-4)


def test_framing_term_is_the_in_frame_shortfall_of_a_mask_cut_by_the_frame_edge():
    """A 20 x 20 px square on a canvas with a 10 px band around a 40 x 40 frame, shifted right by
    ``shift``: the share left in the frame is (20 - overhang) / 20, the overhang max(shift - 10, 0)."""
    frame = Frame(10.0, 10.0, 40, 40)
    for shift, share in ((0, 1.0), (15, 0.75), (20, 0.5)):
        mask = rect_mask(60, 60, 20 + shift, 20, 40 + shift, 40)
        framing = layout_terms(mask, None, None, frame=frame, min_in_frame=0.65)["framing"]
        assert math.isclose(float(framing), max(0.65 - share, 0.0), abs_tol=1e-12)
    assert min_in_frame_share(layout_boxes(None, "close-up")[2]) < min_in_frame_share(layout_boxes(None, "medium")[2])
    assert min_in_frame_share(None) == min_in_frame_share(layout_boxes(None, "wide")[2])


@pytest.mark.parametrize("pitch_deg", [0.0, 30.0, -60.0, 85.0])
def test_upright_ignores_pitch_and_penalises_roll(pitch_deg):
    up = vec(0, 0, 1)
    pitch = math.radians(pitch_deg)
    target = vec(math.cos(pitch), 0, -math.sin(pitch))  # looking down by pitch_deg
    level = look_at(vec(0, 0, 0), target, up)
    assert float(upright_loss(level, up)) < 1e-5
    rolled = look_at(vec(0, 0, 0), target, up, roll=math.radians(20))
    h = math.cos(pitch)
    assert math.isclose(float(upright_loss(rolled, up)), h * 2 * math.sin(math.radians(10)), rel_tol=1e-4)
    assert float(upright_loss(rolled, up, math.radians(20))) < 1e-5  # the asked roll is free
    upside_down = look_at(vec(0, 0, 0), target, up, roll=math.pi)
    assert float(upright_loss(upside_down, up)) > float(upright_loss(rolled, up))


def test_upright_is_finite_looking_straight_down():
    T = look_at(vec(0, 0, 5), vec(0, 0, 0), vec(0, 0, 1)).clone().requires_grad_()
    loss = upright_loss(T, vec(0, 0, 1))
    loss.backward()
    assert float(loss.detach()) < 1e-5 and torch.isfinite(T.grad).all()


def test_view_loss_is_zero_inside_the_accepted_set_and_positive_outside():
    subject, front, up = vec(0, 0, 0), vec(1, 0, 0), vec(0, 0, 1)

    def camera_at(az_deg, el_deg):
        eye = 4 * view_direction(
            torch.tensor(math.radians(az_deg), dtype=f64), torch.tensor(math.radians(el_deg), dtype=f64), front, up
        )
        return look_at(eye, subject, up)

    left = ((-90.0,), 18.0, (8.0, 26.0))
    assert float(view_loss(camera_at(-100, 15), subject, front, up, *left)) < 1e-5
    outside = float(view_loss(camera_at(-40, 15), subject, front, up, *left))
    # 32 degrees of azimuth to the arc end: chord 2 sin(16), weighted 0.99 at 15 degrees elevation.
    q_sq = math.cos(math.radians(15)) ** 2
    weight = q_sq / (q_sq + math.sin(math.radians(5)) ** 2)
    assert math.isclose(outside, weight * 2 * math.sin(math.radians(16)), rel_tol=1e-6)
    # 30 degrees of elevation above the range: the gap in sine space.
    above = float(view_loss(camera_at(-90, 56), subject, front, up, *left))
    assert math.isclose(above, math.sin(math.radians(56)) - math.sin(math.radians(26)), abs_tol=1e-5)  # + the 1e-6 floor
    elevation_only = float(view_loss(camera_at(0, 60), subject, None, up, (), 0.0, (8.0, 26.0)))
    assert math.isclose(elevation_only, math.sin(math.radians(60)) - math.sin(math.radians(26)), rel_tol=1e-9)
    # Straight above the subject: finite value and gradient.
    T = camera_at(0, 90).clone().requires_grad_()
    loss = view_loss(T, subject, front, up, (0.0,), 18.0, (-10.0, 10.0))
    loss.backward()
    # The azimuth part fades where azimuth is undefined; the elevation part pulls the camera down.
    assert math.isclose(float(loss.detach()), 1.0 - math.sin(math.radians(10)), abs_tol=1e-5)
    assert torch.isfinite(T.grad).all() and T.grad.abs().sum() > 0


def test_aim_loss_pulls_from_behind_the_camera():
    T = look_at(vec(0, 0, 0), vec(0, 0, 1), vec(0, -1, 0)).clone().requires_grad_()
    behind = vec(0, 0, -3)
    loss = aim_loss(T, behind, vec(0, 0, 1))
    loss.backward()
    assert math.isclose(float(loss.detach()), 2.0, rel_tol=1e-6) and torch.isfinite(T.grad).all()
    assert float(aim_loss(T.detach(), vec(0.0, 0.0, 5.0), vec(0, 0, 1))) < 1e-5


def test_wide_shot_size_term_has_no_lower_bound():
    """A wide shot's extent interval starts at 0 (log 0 must not be taken): a tiny mask costs
    nothing, one larger than the interval's top costs log(extent / hi) with a finite gradient."""
    _, _, extent = layout_boxes(None, "wide")
    assert extent[0] == 0.0
    ys, xs = torch.meshgrid(torch.arange(120, dtype=f64) + 0.5, torch.arange(160, dtype=f64) + 0.5, indexing="ij")
    for radius, expected_zero in ((4.0, True), (60.0, False)):
        scale = torch.tensor(radius, dtype=f64, requires_grad=True)
        mask = torch.sigmoid(scale - ((xs - 80) ** 2 + (ys - 60) ** 2).sqrt())
        size = layout_terms(mask, None, None, extent=extent)["size"]
        size.backward()
        assert torch.isfinite(size) and torch.isfinite(scale.grad)
        if expected_zero:
            assert float(size.detach()) == 0.0
        else:
            excess = math.log(bbox_extent(mask.detach()) / extent[1])
            assert excess > 0 and math.isclose(float(size.detach()), excess, rel_tol=1e-9) and float(scale.grad) > 0


def test_layout_boxes_stay_in_frame_and_regions_shrink():
    region, box, extent = layout_boxes("right third", "medium")
    assert box[2] <= 1.0 and box[0] >= 0.0 and math.isclose(box[2] - box[0], 0.42)
    assert region[0] > 2 / 3 and region[2] < 1.0
    assert 0.25 < extent[0] < extent[1] < 0.6


def blob(n=400, seed=0):
    from capframe.scene import GaussianScene

    g = torch.Generator().manual_seed(seed)
    means = torch.randn(n, 3, generator=g, dtype=f64) * vec(0.3, 0.2, 0.4) + vec(0, 0, 0.4)
    return GaussianScene.from_activated(
        means,
        torch.randn(n, 4, generator=g, dtype=f64),
        torch.full((n, 3), 0.06, dtype=f64),
        torch.full((n,), 0.7, dtype=f64),
        torch.rand(n, 3, generator=g, dtype=f64),
    )


def test_view_targets_aim_inside_each_sides_tolerance():
    """The margin is 12 degrees, at most half the tolerance: 30 - 12 = 18 for a side, 15 - 7.5 for
    a slight side; an elevation range keeps min(4, width / 4) off each end, within +-89."""
    assert view_target("left", None) == ViewTarget((-90.0,), 18.0, None)
    assert view_target("front-slight-left", None) == ViewTarget((-20.0,), 7.5, None)
    assert view_target("side", ELEVATIONS["top-down"]) == ViewTarget((-90.0, 90.0), 18.0, (82.5, 87.5))
    assert view_target(None, ELEVATIONS["slightly below"]).elevation_range_deg == (-26.0, -12.0)


def test_full_objective_pose_gradient_matches_finite_differences():
    """Every term but ``size``, whose value is the pixel bounding box (locally constant) and whose
    gradient is the smooth extent's by design; the test above checks that gradient."""
    from capframe.scene import Camera

    scene = blob()
    T0 = look_at(vec(2.5, 1.2, 1.0), vec(0, 0, 0.4), vec(0, 0, 1))
    camera = Camera(T0.numpy(), np.array([[60.0, 0, 32], [0, 60, 24], [0, 0, 1]]), 64, 48)
    subject = SubjectLabel(
        "blob",
        np.arange(len(scene)),
        scene.means.mean(0).numpy(),
        np.array([1.0, 0, 0]),
        region=(0.6, 0.1, 0.95, 0.9),
        box=(0.55, 0.2, 1.0, 0.8),
        extent=(0.5, 0.8),
        view=ViewTarget((-90.0,), 18.0, (8.0, 26.0)),
    )
    labels = PseudoLabels([subject], np.array([0.0, 0, 1]), roll_deg=10.0, box_angle_deg=10.0)
    objective = _Objective(scene, camera, labels, RefineConfig(weights=LossWeights(size=0.0)), f64)
    tau0 = torch.tensor([0.02, -0.03, 0.01, 0.05, -0.02, 0.03], dtype=f64)
    tau = tau0.clone().requires_grad_()
    loss, _ = objective(se3_exp(tau) @ T0)
    loss.backward()
    numeric = torch.zeros(6, dtype=f64)
    with torch.no_grad():
        for i in range(6):
            e = torch.zeros(6, dtype=f64)
            e[i] = 1e-7
            numeric[i] = (objective(se3_exp(tau0 + e) @ T0)[0] - objective(se3_exp(tau0 - e) @ T0)[0]) / 2e-7
    assert float((tau.grad - numeric).norm() / numeric.norm()) < 1e-3


def test_clearance_pushes_out_of_the_subject_and_vanishes_outside():
    from capframe.refine.losses import clearance_loss

    centre = vec(0, 0, 0)
    eye = vec(0.3, 0, 0).requires_grad_()
    loss = clearance_loss(look_at(eye, eye + vec(1, 0, 0), vec(0, 0, 1)), centre, 1.0)
    loss.backward()
    assert math.isclose(float(loss.detach()), 0.7, rel_tol=1e-9)
    assert torch.allclose(eye.grad, vec(-1.0, 0, 0))  # descent moves the camera straight out
    outside = look_at(vec(1.5, 0, 0), vec(0, 0, 0), vec(0, 0, 1))
    assert float(clearance_loss(outside, centre, 1.0)) == 0.0
