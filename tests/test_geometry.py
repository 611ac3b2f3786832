"""Lie-group maps and the camera conventions of DESIGN §3 on hand-checkable cases."""

from __future__ import annotations

import math

import pytest
import torch

from capframe.geometry import (
    camera_axes,
    camera_center,
    camera_roll,
    look_at,
    project,
    quat_multiply,
    quat_to_rotmat,
    rotmat_to_quat,
    se3_exp,
    se3_log,
    so3_exp,
    so3_log,
    view_angles,
    view_direction,
    world_to_camera,
)

f64 = dict(dtype=torch.float64)


def vec(*v):
    return torch.tensor(v, **f64)


def test_so3_exp_log_roundtrip_including_zero_and_pi():
    omegas = torch.cat(
        [
            torch.randn(50, 3, **f64, generator=torch.Generator().manual_seed(0)),
            torch.zeros(1, 3, **f64),
            vec(math.pi - 1e-9, 0, 0)[None],
            vec(1e-9, -2e-9, 0)[None],
        ]
    )
    omegas = omegas[omegas.norm(dim=-1) < math.pi]  # log returns the angle in [0, pi]
    R = so3_exp(omegas)
    assert torch.allclose(R @ R.transpose(-1, -2), torch.eye(3, **f64).expand_as(R), atol=1e-12)
    assert torch.allclose(so3_log(R), omegas, atol=1e-7)
    near_pi = so3_exp(vec(0, math.pi - 1e-7, 0))
    assert torch.allclose(so3_exp(so3_log(near_pi)), near_pi, atol=1e-9)


def test_so3_exp_matches_axis_angle_by_hand():
    R = so3_exp(vec(0, 0, math.pi / 2))  # 90 degrees about z: x -> y
    assert torch.allclose(R @ vec(1, 0, 0), vec(0, 1, 0), atol=1e-15)


def test_se3_exp_log_roundtrip_and_small_angle_branch_continuity():
    tau = torch.randn(100, 6, **f64, generator=torch.Generator().manual_seed(0))
    tau[:, :3] *= 3.0 / tau[:, :3].norm(dim=-1, keepdim=True).clamp_min(3.0)  # angles below pi
    assert torch.allclose(se3_log(se3_exp(tau)), tau, atol=1e-9)
    # Taylor and closed-form branches agree across the switch point (theta^2 = 1e-3 in float64).
    for theta in (math.sqrt(1e-3) * (1 - 1e-9), math.sqrt(1e-3) * (1 + 1e-9)):
        t = vec(theta, 0, 0, 0.3, -0.2, 0.1)
        exact_R = vec(1, 0, 0, 0, math.cos(theta), -math.sin(theta), 0, math.sin(theta), math.cos(theta)).reshape(3, 3)
        assert torch.allclose(se3_exp(t)[:3, :3], exact_R, atol=1e-15)


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_exp_gradients_finite_at_zero(dtype):
    tau = torch.zeros(6, dtype=dtype, requires_grad=True)
    (se3_exp(tau) * torch.arange(16, dtype=dtype).reshape(4, 4)).sum().backward()
    assert torch.isfinite(tau.grad).all()
    # d exp(tau)/d tau at 0 is the generator: rotation about x moves y into z.
    tau = torch.zeros(6, **f64, requires_grad=True)
    se3_exp(tau)[2, 1].backward()
    assert torch.allclose(tau.grad, vec(1, 0, 0, 0, 0, 0))


def test_quaternion_roundtrip_and_product():
    g = torch.Generator().manual_seed(0)
    q = torch.randn(20, 4, **f64, generator=g)
    q = q / q.norm(dim=-1, keepdim=True)
    R = quat_to_rotmat(q)
    assert torch.allclose(quat_to_rotmat(rotmat_to_quat(R)), R, atol=1e-12)
    q2 = torch.randn(20, 4, **f64, generator=g)
    assert torch.allclose(quat_to_rotmat(quat_multiply(q, q2)), R @ quat_to_rotmat(q2), atol=1e-12)


def test_look_at_axes_follow_opencv():
    eye, target, up = vec(0, 0, 0), vec(1, 0, 0), vec(0, 0, 1)  # looking along +x, z up
    T = look_at(eye, target, up)
    right, down, forward = camera_axes(T)
    assert torch.allclose(forward, vec(1, 0, 0))
    assert torch.allclose(right, vec(0, -1, 0))  # with z up and x forward, the right is -y
    assert torch.allclose(down, vec(0, 0, -1))
    assert torch.allclose(camera_center(look_at(vec(3, 4, 5), target, up)), vec(3, 4, 5))


def test_projection_by_hand():
    T = torch.eye(4, **f64)
    K = vec(100, 0, 80, 0, 100, 60, 0, 0, 1).reshape(3, 3)
    uv = project(world_to_camera(vec(1.0, 0.5, 10.0)[None], T), K)
    assert torch.allclose(uv, vec(90.0, 65.0)[None])


def test_roll_sign_convention():
    up = vec(0, 0, 1)
    level = look_at(vec(-5, 0, 0), vec(0, 0, 0), up)
    assert abs(float(camera_roll(level, up))) < 1e-12
    rolled = look_at(vec(-5, 0, 0), vec(0, 0, 0), up, roll=math.radians(20))
    right, _, _ = camera_axes(rolled)
    assert float(right @ up) < 0  # positive roll dips the camera's right side
    assert math.isclose(math.degrees(float(camera_roll(rolled, up))), 20.0, abs_tol=1e-9)
    # The world appears rotated counter-clockwise: the horizon rises on the right of the frame.
    K = vec(100, 0, 50, 0, 100, 50, 0, 0, 1).reshape(3, 3)
    horizon = torch.stack([vec(0, -1, 0), vec(0, 1, 0)])  # right and left of the target (camera right is -y)
    level_uv = project(world_to_camera(horizon, level), K)
    rolled_uv = project(world_to_camera(horizon, rolled), K)
    assert torch.allclose(level_uv[:, 1], vec(50, 50))
    assert rolled_uv[0, 1] < 50 < rolled_uv[1, 1]  # right point up (smaller v), left point down


def test_view_angles_by_hand():
    subject, front, up = vec(1, 2, 3), vec(1, 0, 0), vec(0, 0, 1)  # subject faces +x; its right is -y
    az, el = view_angles(subject + vec(2, 0, 0), subject, front, up)
    assert abs(float(az)) < 1e-12 and abs(float(el)) < 1e-12  # in front
    az, _ = view_angles(subject + vec(0, -2, 0), subject, front, up)
    assert math.isclose(float(az), math.pi / 2)  # at its right
    az, _ = view_angles(subject + vec(-2, 0, 0), subject, front, up)
    assert math.isclose(abs(float(az)), math.pi)  # behind
    _, el = view_angles(subject + vec(1, 0, 1), subject, front, up)
    assert math.isclose(float(el), math.pi / 4)  # above, looking down
    # The front is projected perpendicular to up before use.
    az2, _ = view_angles(subject + vec(2, 0, 0), subject, vec(1, 0, 0.7), up)
    assert abs(float(az2)) < 1e-12


def test_view_direction_inverts_view_angles():
    front, up = vec(0.3, 0.9, 0.1), vec(0.1, -0.2, 1.0)
    up = up / up.norm()
    for az, el in [(0.0, 0.0), (1.2, 0.4), (-2.5, -0.7), (3.0, 1.2)]:
        d = view_direction(torch.tensor(az, **f64), torch.tensor(el, **f64), front, up)
        a2, e2 = view_angles(d * 3.0, torch.zeros(3, **f64), front, up)
        assert math.isclose(float(a2), az, abs_tol=1e-12) and math.isclose(float(e2), el, abs_tol=1e-12)


def test_look_at_straight_down_is_finite():
    T = look_at(vec(0, 0, 5), vec(0, 0, 0), vec(0, 0, 1))
    assert torch.isfinite(T).all()
    R = T[:3, :3]
    assert torch.allclose(R @ R.T, torch.eye(3, **f64), atol=1e-12)
    assert torch.allclose(camera_axes(T)[2], vec(0, 0, -1))


def test_padded_camera_centre_crop_is_the_original_image():
    import numpy as np
    from conftest import make_camera, make_scene

    from capframe.render import render

    scene, camera = make_scene(200, seed=9), make_camera(width=40, height=30)
    canvas = camera.padded(10, 6)
    assert (canvas.width, canvas.height) == (60, 42)
    full, crop = render(scene, canvas, backend="torch").rgb, render(scene, camera, backend="torch").rgb
    assert np.allclose(full[6:36, 10:50].numpy(), crop.numpy(), atol=1e-6)


def test_pose_deviation_on_a_hand_checked_pair():
    import numpy as np

    from capframe.geometry import pose_deviation

    a = np.eye(4)
    b = np.eye(4)
    b[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]  # 90 deg about z; centre stays at the origin
    b[:3, 3] = b[:3, :3] @ -np.array([2.0, 0.0, 0.0])  # centre at (2, 0, 0)
    dR, dt = pose_deviation(a, b, scale=4.0)
    assert abs(dR - 90.0) < 1e-9 and abs(dt - 0.5) < 1e-12
