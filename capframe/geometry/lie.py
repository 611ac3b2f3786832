"""SO(3) and SE(3) exponential and logarithm maps.

Tangent vectors are ordered rotation first, as in the paper: ``tau = (omega, v)`` with ``omega``
the rotation vector (radians) and ``v`` the translational part. All functions are batched over
leading dimensions, differentiable, and finite (value and gradient) at zero, where small-angle
Taylor branches take over. ``torch.where`` only ever sees safe inputs in both branches.
"""

from __future__ import annotations

import torch
from torch import Tensor

# Below these squared angles the closed forms lose digits to cancellation; the Taylor series,
# truncated after the theta^6 term, is exact to the dtype's precision there.
_SMALL_ANGLE_SQ = {torch.float64: 1e-3, torch.float32: 1e-1, torch.float16: 1e-1, torch.bfloat16: 1e-1}


def hat(w: Tensor) -> Tensor:
    """Skew-symmetric matrix of ``w``: (..., 3) -> (..., 3, 3), with ``hat(w) @ x == w x x``."""
    zero = torch.zeros_like(w[..., 0])
    wx, wy, wz = w.unbind(-1)
    return torch.stack(
        [
            torch.stack([zero, -wz, wy], -1),
            torch.stack([wz, zero, -wx], -1),
            torch.stack([-wy, wx, zero], -1),
        ],
        -2,
    )


def _exp_coefficients(theta_sq: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """A = sin(t)/t, B = (1 - cos t)/t^2, C = (t - sin t)/t^3 for t = sqrt(theta_sq)."""
    small = theta_sq < _SMALL_ANGLE_SQ.get(theta_sq.dtype, 1e-1)
    t2 = torch.where(small, torch.ones_like(theta_sq), theta_sq)  # safe for sqrt / division
    t = t2.sqrt()
    a_exact = torch.sin(t) / t
    half_sinc = torch.sin(0.5 * t) / (0.5 * t)
    b_exact = 0.5 * half_sinc * half_sinc  # 2 sin^2(t/2) / t^2, free of the 1 - cos cancellation
    c_exact = (1.0 - a_exact) / t2
    s = theta_sq
    a_taylor = 1.0 - s / 6.0 + s * s / 120.0 - s * s * s / 5040.0
    b_taylor = 0.5 - s / 24.0 + s * s / 720.0 - s * s * s / 40320.0
    c_taylor = 1.0 / 6.0 - s / 120.0 + s * s / 5040.0 - s * s * s / 362880.0
    return (
        torch.where(small, a_taylor, a_exact),
        torch.where(small, b_taylor, b_exact),
        torch.where(small, c_taylor, c_exact),
    )


def so3_exp(omega: Tensor) -> Tensor:
    """Rotation matrix of a rotation vector (Rodrigues): (..., 3) -> (..., 3, 3)."""
    a, b, _ = _exp_coefficients((omega * omega).sum(-1))
    W = hat(omega)
    eye = torch.eye(3, dtype=omega.dtype, device=omega.device).expand_as(W)
    return eye + a[..., None, None] * W + b[..., None, None] * (W @ W)


def se3_exp(tau: Tensor) -> Tensor:
    """Homogeneous transform of a twist ``tau = (omega, v)``: (..., 6) -> (..., 4, 4)."""
    omega, v = tau[..., :3], tau[..., 3:]
    a, b, c = _exp_coefficients((omega * omega).sum(-1))
    W = hat(omega)
    W2 = W @ W
    eye = torch.eye(3, dtype=tau.dtype, device=tau.device).expand_as(W)
    R = eye + a[..., None, None] * W + b[..., None, None] * W2
    V = eye + b[..., None, None] * W + c[..., None, None] * W2
    t = (V @ v[..., None])[..., 0]
    T = torch.zeros(*tau.shape[:-1], 4, 4, dtype=tau.dtype, device=tau.device)
    T[..., :3, :3] = R
    T[..., :3, 3] = t
    T[..., 3, 3] = 1.0
    return T


def so3_log(R: Tensor) -> Tensor:
    """Rotation vector of a rotation matrix: (..., 3, 3) -> (..., 3), angle in [0, pi].

    Stable at both ends: near 0 it uses ``theta / sin(theta)`` through ``atan2``, near ``pi`` the
    axis comes from the symmetric part ``(R + R^T)/2 - cos(theta) I = (1 - cos theta) a a^T``.
    """
    v = 0.5 * torch.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1
    )  # sin(theta) * axis
    sin_t = v.norm(dim=-1)
    cos_t = 0.5 * (R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0)
    theta = torch.atan2(sin_t, cos_t)
    # Regular branch: theta / sin(theta) * v, with the theta -> 0 limit 1 + theta^2/6.
    small = theta * theta < 1e-6
    sin_safe = torch.where(small, torch.ones_like(sin_t), sin_t)
    scale = torch.where(small, 1.0 + theta * theta / 6.0, theta / sin_safe)
    regular = scale[..., None] * v
    # Near-pi branch: axis from the largest diagonal of the symmetric part, sign from v.
    eye = torch.eye(3, dtype=R.dtype, device=R.device)
    S = 0.5 * (R + R.transpose(-1, -2)) - cos_t[..., None, None] * eye
    col = S.diagonal(dim1=-2, dim2=-1).argmax(-1)
    axis = torch.take_along_dim(S, col[..., None, None].expand(*S.shape[:-2], 3, 1), dim=-1)[..., 0]
    axis = axis / axis.norm(dim=-1, keepdim=True).clamp_min(torch.finfo(R.dtype).tiny)
    sign = torch.where((axis * v).sum(-1) < 0, -1.0, 1.0).to(R.dtype)
    near_pi = cos_t < -0.99
    return torch.where(near_pi[..., None], (sign * theta)[..., None] * axis, regular)


def se3_log(T: Tensor) -> Tensor:
    """Twist ``(omega, v)`` of a homogeneous transform: (..., 4, 4) -> (..., 6)."""
    omega = so3_log(T[..., :3, :3])
    _, b, c = _exp_coefficients((omega * omega).sum(-1))
    W = hat(omega)
    eye = torch.eye(3, dtype=T.dtype, device=T.device).expand_as(W)
    V = eye + b[..., None, None] * W + c[..., None, None] * (W @ W)
    v = torch.linalg.solve(V, T[..., :3, 3:4])[..., 0]
    return torch.cat([omega, v], -1)


def left_update(tau: Tensor, T: Tensor) -> Tensor:
    """Pose update by left composition, ``T <- exp(tau) @ T``: (..., 6), (..., 4, 4) -> (..., 4, 4)."""
    return se3_exp(tau) @ T


def rotation_angle_deg(R_a: Tensor, R_b: Tensor) -> Tensor:
    """Geodesic angle between two rotations in degrees: (..., 3, 3) x2 -> (...)."""
    return torch.rad2deg(so3_log(R_a.transpose(-1, -2) @ R_b).norm(dim=-1))
