"""Pinhole cameras in the project's convention (DESIGN §3).

``T_cw`` maps world to camera coordinates with OpenCV axes (x right, y down, z forward);
the camera centre is ``C = -R^T t``. ``K`` is in pixels with pixel centres at integer + 0.5,
so pixel ``(i, j)`` covers ``[i, i+1) x [j, j+1)`` in continuous image coordinates.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import Tensor


def any_horizontal(up: np.ndarray) -> np.ndarray:
    """A deterministic unit vector perpendicular to ``up``: (3,) -> (3,). It stands in for the
    front of a symmetric subject, whose elevation is defined but whose azimuth is not."""
    axis = np.zeros(3)
    axis[np.abs(up).argmin()] = 1.0
    v = axis - (axis @ up) * up
    return v / np.linalg.norm(v)


def camera_center(T_cw: Tensor) -> Tensor:
    """Camera centre in world coordinates: (..., 4, 4) -> (..., 3)."""
    R, t = T_cw[..., :3, :3], T_cw[..., :3, 3]
    return -(R.transpose(-1, -2) @ t[..., None])[..., 0]


def camera_axes(T_cw: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """World-frame right, down and forward axes of the camera, each (..., 3)."""
    R = T_cw[..., :3, :3]
    return R[..., 0, :], R[..., 1, :], R[..., 2, :]


def world_to_camera(points: Tensor, T_cw: Tensor) -> Tensor:
    """Transform world points into the camera frame: (N, 3), (4, 4) -> (N, 3)."""
    return points @ T_cw[:3, :3].transpose(0, 1) + T_cw[:3, 3]


def project(points_cam: Tensor, K: Tensor) -> Tensor:
    """Pinhole projection of camera-frame points to continuous pixel coordinates: (N, 3) -> (N, 2).

    The caller guarantees ``z > 0`` (cull first); nothing here guards the division.
    """
    uv = points_cam[:, :2] / points_cam[:, 2:3]
    return uv * torch.stack([K[0, 0], K[1, 1]]) + torch.stack([K[0, 2], K[1, 2]])


def look_at(eye: Tensor, target: Tensor, up: Tensor, roll: float | Tensor = 0.0) -> Tensor:
    """World-to-camera pose looking from ``eye`` at ``target``: (3,), (3,), (3,) -> (4, 4).

    The camera y-axis points along ``-up`` projected onto the image plane (an upright photo),
    then the camera is rolled by ``roll`` radians about its forward axis; ``roll > 0`` dips the
    camera's right side (DESIGN §3). When the view direction is parallel to ``up`` the upright
    frame is undefined; the right axis is then taken perpendicular to the world axis least
    aligned with the view direction, which keeps the result deterministic.
    """
    forward = target - eye
    forward = forward / forward.norm()
    up = up / up.norm()
    right = torch.linalg.cross(forward, up)
    if right.norm() < 1e-9:
        axis = torch.zeros_like(forward)
        axis[forward.abs().argmin()] = 1.0
        right = torch.linalg.cross(forward, axis)
    right = right / right.norm()
    down = torch.linalg.cross(forward, right)
    roll = torch.as_tensor(roll, dtype=eye.dtype, device=eye.device)
    c, s = torch.cos(roll), torch.sin(roll)
    right, down = c * right + s * down, -s * right + c * down
    R = torch.stack([right, down, forward], 0)
    T = torch.eye(4, dtype=eye.dtype, device=eye.device)
    T[:3, :3] = R
    T[:3, 3] = -R @ eye
    return T


def camera_roll(T_cw: Tensor, up: Tensor) -> Tensor:
    """Roll angle in radians (DESIGN §3): 0 when the camera x-axis is perpendicular to ``up``,
    positive when the camera's right side dips (``x_cam . up < 0``). (..., 4, 4), (3,) -> (...).

    Ill-conditioned when the camera looks straight up or down (``|forward . up| -> 1``); callers
    that measure roll must skip it there.
    """
    right, down, _ = camera_axes(T_cw)
    return torch.atan2(-(right * up).sum(-1), -(down * up).sum(-1))


def subject_frame(front: Tensor, up: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Orthonormal subject frame ``(f, u, r)``: front projected perpendicular to up, up, and the
    subject's own right-hand side ``r = f x u``. (3,), (3,) -> three (3,) tensors."""
    u = up / up.norm()
    f = front - (front @ u) * u
    f = f / f.norm()
    return f, u, torch.linalg.cross(f, u)


def view_angles(center: Tensor, subject: Tensor, front: Tensor, up: Tensor) -> tuple[Tensor, Tensor]:
    """Azimuth and elevation (radians) of camera centre(s) around a subject (DESIGN §3).

    ``center`` is (..., 3). With ``p = (C - S) / |C - S|``: elevation ``asin(p . u)`` (> 0 above,
    looking down), azimuth ``atan2(p . r, p . f)`` (0 in front, +pi/2 at the subject's right).
    """
    f, u, r = subject_frame(front, up)
    p = center - subject
    p = p / p.norm(dim=-1, keepdim=True)
    elevation = torch.asin((p @ u).clamp(-1.0, 1.0))
    azimuth = torch.atan2(p @ r, p @ f)
    return azimuth, elevation


def view_direction(azimuth: Tensor, elevation: Tensor, front: Tensor, up: Tensor) -> Tensor:
    """Unit vector from the subject towards a camera at the given view angles: () -> (3,).

    The inverse of :func:`view_angles`: yaw about the world up first, then pitch (DESIGN §5).
    """
    f, u, r = subject_frame(front, up)
    horizontal = torch.cos(azimuth) * f + torch.sin(azimuth) * r
    return torch.cos(elevation) * horizontal + torch.sin(elevation) * u


def pose_deviation(T_a, T_b, scale: float = 1.0) -> tuple[float, float]:
    """Rotation angle (degrees) and camera-centre distance (in units of ``scale``) between two
    poses: (4, 4) arrays or tensors -> two floats."""
    from .lie import rotation_angle_deg

    T_a, T_b = (torch.as_tensor(np.asarray(T), dtype=torch.float64) for T in (T_a, T_b))
    dR = float(rotation_angle_deg(T_a[:3, :3], T_b[:3, :3]))
    return dR, float((camera_center(T_a) - camera_center(T_b)).norm()) / scale
