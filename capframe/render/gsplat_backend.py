"""gsplat backend (CUDA). ``gsplat`` is imported inside the function only, so the CPU path never
touches it and never triggers its JIT build."""

from __future__ import annotations

from torch import Tensor


def rasterize_gsplat(
    means: Tensor,
    factors: Tensor,
    opacities: Tensor,
    features: Tensor,
    T_cw: Tensor,
    K: Tensor,
    width: int,
    height: int,
    *,
    near: float = 0.01,
    far: float = 1e10,
) -> tuple[Tensor, Tensor, Tensor, dict]:
    """Same contract as :func:`capframe.render.torch_backend.rasterize_torch`, via
    ``gsplat.rasterization`` ("classic" mode, 0.3 px low-pass). The pose gradient flows through
    ``viewmats``."""
    from gsplat import rasterization

    colors, alphas, meta = rasterization(
        means,
        None,
        None,
        opacities,
        features,
        T_cw[None],
        K[None],
        width,
        height,
        near_plane=near,
        far_plane=far,
        eps2d=0.3,
        packed=False,
        rasterize_mode="classic",
        render_mode="RGB+D",
        covars=factors @ factors.transpose(-1, -2),
    )
    image = colors[0]
    return image[..., :-1], alphas[0, ..., 0], image[..., -1], {"visible": int((meta["radii"] > 0).any(-1).sum())}
