"""Real spherical harmonics up to degree 3, in the basis and sign convention of the Inria 3DGS
code (and gsplat), so colours of scenes trained there evaluate identically."""

from __future__ import annotations

import torch
from torch import Tensor

C0 = 0.28209479177387814
C1 = 0.4886025119029199
C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
C3 = (
    -0.5900435899266435,
    2.890611442640554,
    -0.4570457994644658,
    0.3731763325901154,
    -0.4570457994644658,
    1.445305721320277,
    -0.5900435899266435,
)


def sh_basis(dirs: Tensor, degree: int) -> Tensor:
    """SH basis functions at unit directions: (N, 3) -> (N, (degree+1)^2)."""
    x, y, z = dirs.unbind(-1)
    basis = [torch.full_like(x, C0)]
    if degree >= 1:
        basis += [-C1 * y, C1 * z, -C1 * x]
    if degree >= 2:
        xx, yy, zz = x * x, y * y, z * z
        basis += [
            C2[0] * x * y,
            C2[1] * y * z,
            C2[2] * (2 * zz - xx - yy),
            C2[3] * x * z,
            C2[4] * (xx - yy),
        ]
    if degree >= 3:
        basis += [
            C3[0] * y * (3 * xx - yy),
            C3[1] * x * y * z,
            C3[2] * y * (4 * zz - xx - yy),
            C3[3] * z * (2 * zz - 3 * xx - 3 * yy),
            C3[4] * x * (4 * zz - xx - yy),
            C3[5] * z * (xx - yy),
            C3[6] * x * (xx - 3 * yy),
        ]
    return torch.stack(basis, -1)


def eval_sh_colors(sh: Tensor, dirs: Tensor, degree: int | None = None) -> Tensor:
    """RGB of Gaussians seen along ``dirs`` (camera centre to mean, any length).

    Args:
        sh: (N, K, 3) coefficients.
        dirs: (N, 3) viewing directions.
        degree: evaluate up to this degree (default: all stored).
    Returns:
        (N, 3) colours ``max(SH + 0.5, 0)``.
    """
    stored = int(round(sh.shape[1] ** 0.5)) - 1
    degree = stored if degree is None else min(degree, stored)
    if degree == 0:  # view-independent: skip the direction normalisation entirely
        return (C0 * sh[:, 0] + 0.5).clamp_min(0.0)
    d = dirs / dirs.norm(dim=-1, keepdim=True).clamp_min(torch.finfo(dirs.dtype).tiny)
    k = (degree + 1) ** 2
    rgb = (sh_basis(d, degree)[:, :, None] * sh[:, :k]).sum(1)
    return (rgb + 0.5).clamp_min(0.0)
