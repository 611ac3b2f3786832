"""One rendering entry point, :func:`render`, over three backends.

``torch`` is the pure-PyTorch reference (CPU or any device); ``compiled`` the numba CPU kernel
with the same rules (:mod:`.compiled_backend`); ``gsplat`` uses the CUDA kernels. ``cpu`` names
the CPU default, ``compiled`` unless the environment variable ``CAPFRAME_CPU_RENDERER`` says
``torch``: everything that renders on the CPU with gradients (Refine, the baselines) asks for it.
``auto`` picks gsplat when CUDA and gsplat are available, else the CPU default.

Precision: poses are float64. Before anything is cast to the render dtype, the world is shifted
so that the camera centre is the origin (in float64), which keeps far-from-origin scenes (offsets
of 1e4 units and more) as accurate as scenes at the origin.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
from dataclasses import dataclass, field

import torch
from torch import Tensor

from ..errors import InputError
from ..geometry.camera import camera_center
from ..scene.model import Camera, GaussianScene, scene_extent
from .chunks import ChunkIndex
from .sh import eval_sh_colors

DEPTH_ALPHA_MIN = 1e-4  # below this accumulated alpha the normalised depth is undefined
NEAR_FRACTION = 1e-4  # default near plane as a fraction of the scene extent (scale invariant)
# Scenes of at least this many Gaussians are culled to the frame before the colours are evaluated
# and the backend runs (:func:`frame_index`): a captured scene of millions seen from inside holds
# most of them outside any one view. Below, the backend's own culling costs less than the pass.
PRECULL_MIN = 1 << 17
CULL_CHUNK = 1 << 20  # Gaussians per chunk of that pass: bounds its float64 temporaries


@dataclass
class RenderOutput:
    """Images of one view. ``H x W`` is the camera's image size.

    Attributes:
        rgb: (H, W, 3) colour over the background, or None when rendered without colours.
        alpha: (H, W) accumulated opacity.
        depth: (H, W) alpha-normalised camera z; 0 where ``alpha <= DEPTH_ALPHA_MIN``.
        extra: (H, W, C) composited extra per-Gaussian channels (not normalised), or None.
        stats: counts reported by the backend.
    """

    rgb: Tensor | None
    alpha: Tensor
    depth: Tensor
    extra: Tensor | None = None
    stats: dict = field(default_factory=dict)

    @property
    def depth_valid(self) -> Tensor:
        """(H, W) bool: where ``depth`` is defined."""
        return self.alpha > DEPTH_ALPHA_MIN


# Peak bytes a render holds per pixel and composited channel, in units of the render dtype: the
# tile buffer twice while a chunk is added to it, its untiled copy, and the image's conversions
# to 8 bits. Refine's low-resolution renders are far below any limit; full-resolution frames of
# 100000-pixel-wide cameras are what this guards against.
RENDER_COPIES = 4
# Renders estimated below this are not checked: asking for the free memory synchronises a CUDA
# device, and Refine renders thousands of small frames.
UNCHECKED_RENDER_BYTES = 1 << 30


def render_bytes(width: int, height: int, channels: int = 3, dtype: torch.dtype = torch.float32) -> int:
    """Estimated peak memory of a ``width`` x ``height`` render of ``channels`` composited
    channels (colour 3, plus extra channels), alpha and depth included."""
    itemsize = torch.empty((), dtype=dtype).element_size()
    return width * height * (channels + 2) * itemsize * RENDER_COPIES


def available_memory(device: torch.device) -> int:
    """Bytes that can still be allocated on ``device`` (free GPU memory; available RAM)."""
    if device.type == "cuda":
        return torch.cuda.mem_get_info(device)[0]
    import psutil

    return psutil.virtual_memory().available


def check_render_memory(
    cameras: Camera | list[Camera],
    channels: int = 3,
    device: torch.device | str = "cpu",
    dtype: torch.dtype = torch.float32,
    source: str | None = None,
) -> None:
    """:class:`InputError` (naming ``source``, the file the cameras come from) when the largest
    of ``cameras`` cannot be rendered in the memory left on ``device``: checked by every
    :func:`render`, and by commands before any work for the frames they render at the end."""
    camera = max([cameras] if isinstance(cameras, Camera) else cameras, key=lambda c: c.width * c.height)
    need = render_bytes(camera.width, camera.height, channels, dtype)
    if need <= UNCHECKED_RENDER_BYTES:
        return
    have = available_memory(torch.device(device))
    if need > have:
        raise InputError(
            f"camera {camera.name!r} is {camera.width}x{camera.height}: rendering it needs about {need / 2**30:.1f} GiB, "
            f"{have / 2**30:.1f} GiB is available; expected a smaller image (e.g. --long-side)",
            source=source,
        )


BACKENDS = ("torch", "compiled", "gsplat")
CPU_RENDERER_VARIABLE = "CAPFRAME_CPU_RENDERER"


def resolve_backend(backend: str) -> str:
    """``auto`` -> ``gsplat`` with CUDA and gsplat installed, else ``cpu``; ``cpu`` -> the value of
    ``CAPFRAME_CPU_RENDERER`` (``compiled`` or ``torch``; default ``compiled``)."""
    if backend == "auto":
        has_gsplat = importlib.util.find_spec("gsplat") is not None
        return "gsplat" if torch.cuda.is_available() and has_gsplat else resolve_backend("cpu")
    if backend == "cpu":
        backend = os.environ.get(CPU_RENDERER_VARIABLE, "compiled")
        if backend not in ("compiled", "torch"):
            raise InputError(f"{CPU_RENDERER_VARIABLE}={backend!r}; expected 'compiled' or 'torch'")
        return backend
    if backend not in BACKENDS:
        raise ValueError(f"unknown render backend {backend!r}; expected 'auto', 'cpu', 'torch', 'compiled' or 'gsplat'")
    return backend


@dataclass
class PreparedGaussians:
    """The pose-independent inputs of a render, computed once by :func:`prepare` for scenes that
    are rendered many times (Refine renders the same subjects at every step).

    Attributes:
        means: (N, 3) float64 (the recentring on the camera is done in float64).
        factors: (N, 3, 3) covariance factors ``L = R S`` (``Sigma = L L^T``), render dtype.
        opacities: (N,) render dtype.
        sh: (N, K, 3) render dtype.
        extent: the scene extent the default near plane is relative to.
        index: the spatial index of the frame cull (:class:`~capframe.render.chunks.ChunkIndex`;
            scenes of :data:`PRECULL_MIN` Gaussians or more), or None.
    """

    means: Tensor
    factors: Tensor
    opacities: Tensor
    sh: Tensor
    extent: float
    index: ChunkIndex | None = None

    def __len__(self) -> int:
        return len(self.means)

    def spreads(self) -> Tensor:
        """(N,) float64 ``|L|_F``, the root of each Gaussian's summed variances (no gradient)."""
        return self.factors.detach().to(torch.float64).square().sum((1, 2)).sqrt()

    def subset(self, index: Tensor) -> PreparedGaussians:
        """The Gaussians ``index`` (without a spatial index)."""
        return PreparedGaussians(self.means[index], self.factors[index], self.opacities[index], self.sh[index], self.extent)


def prepare(scene: GaussianScene, dtype: torch.dtype = torch.float32, extent: float | None = None) -> PreparedGaussians:
    """Pose-independent render inputs of ``scene``; ``extent`` defaults to its own extent.

    Gradients to the scene's parameters flow through the result, but it is meant for a scene
    that stays fixed while it is rendered (a prepared scene does not see later edits).
    """
    from .torch_backend import covariance_factor

    return PreparedGaussians(
        means=scene.means.to(torch.float64),
        factors=covariance_factor(scene.quats.to(dtype), scene.scales.to(dtype)),
        opacities=scene.opacities.to(dtype),
        sh=scene.sh.to(dtype),
        extent=scene_extent(scene.means.detach()) if extent is None else extent,
        index=chunk_index(scene) if len(scene) >= PRECULL_MIN else None,
    )


def indexed(gaussians: PreparedGaussians) -> PreparedGaussians:
    """``gaussians`` with a spatial index for the frame cull when it holds :data:`PRECULL_MIN`
    or more (a set rendered many times, such as the occlusion phase's occluders)."""
    if len(gaussians) < PRECULL_MIN or gaussians.index is not None:
        return gaussians
    with torch.no_grad():
        return dataclasses.replace(gaussians, index=ChunkIndex.build(gaussians.means, gaussians.spreads()))


def chunk_index(scene: GaussianScene) -> ChunkIndex:
    """The spatial index of ``scene``'s frame cull, built on first use and kept on the scene
    object (a scene is not edited in place; :meth:`GaussianScene.subset` makes a new one)."""
    index = getattr(scene, "_chunk_index", None)
    if index is None:
        with torch.no_grad():
            index = ChunkIndex.build(scene.means, scene.scales.norm(dim=1))
        scene._chunk_index = index
    return index


def frame_index(
    gaussians: PreparedGaussians,
    pose: Tensor,
    K: Tensor,
    width: int,
    height: int,
    near: float,
    far: float,
    chunk: int = CULL_CHUNK,
) -> Tensor:
    """Indices (M,) of the Gaussians that may touch the frame of a camera at ``pose`` (4, 4)
    with intrinsics ``K`` (3, 3): the others are ones every backend culls (mean outside
    ``(near, far)`` or footprint box certainly off the frame,
    :func:`~capframe.render.torch_backend.may_touch_frame`). A 1e-3 relative slack on the depth
    bounds absorbs the render dtype's rounding. Computed ``chunk`` Gaussians at a time, in float64,
    without gradient; with a spatial index (:attr:`PreparedGaussians.index`) only the Gaussians of
    the chunks that may touch the frame are tested, with the same result."""
    from .torch_backend import may_touch_frame

    with torch.no_grad():
        pose = pose.detach().to(torch.float64)
        R, centre, K = pose[:3, :3], camera_center(pose), K.to(torch.float64)
        if gaussians.index is not None:
            pool = torch.sort(gaussians.index.candidates(pose, K, width, height, near, far)).values
        else:
            pool = None
        kept = []
        for start in range(0, len(gaussians) if pool is None else len(pool), chunk):
            rows = slice(start, start + chunk) if pool is None else pool[start : start + chunk]
            local = (gaussians.means[rows].detach() - centre) @ R.T
            z = local[:, 2]
            front = ((z > near * (1.0 - 1e-3)) & (z < far * (1.0 + 1e-3))).nonzero()[:, 0]
            factors = gaussians.factors[rows][front].detach().to(torch.float64)
            front = front[may_touch_frame(local[front], factors, K, width, height)]
            kept.append(start + front if pool is None else rows[front])
        return torch.cat(kept) if kept else torch.zeros(0, dtype=torch.long, device=pose.device)


def render(
    scene: GaussianScene | PreparedGaussians,
    camera: Camera,
    *,
    T_cw: Tensor | None = None,
    subset: Tensor | None = None,
    extra: Tensor | None = None,
    backend: str = "auto",
    background: Tensor | tuple[float, float, float] | None = None,
    sh_degree: int | None = None,
    colors: bool = True,
    near: float | None = None,
    far: float = float("inf"),
    dtype: torch.dtype = torch.float32,
    precull: bool | None = None,
    **backend_options,
) -> RenderOutput:
    """Render ``scene`` from ``camera``.

    Args:
        scene: the Gaussians (on the device to render on), or a :func:`prepare`-d scene.
        camera: intrinsics, image size and, unless ``T_cw`` is given, the pose.
        T_cw: optional (4, 4) pose tensor overriding ``camera.T_cw``; gradients flow to it.
        subset: optional boolean mask (N,) or indices (M,) of the Gaussians to render.
        extra: optional (N, C) per-Gaussian channels composited alongside the colour
            (e.g. a 0/1 membership gives a soft subject mask).
        background: RGB added where the view is not fully covered (default black).
        sh_degree: evaluate SH up to this degree (default: all stored).
        colors: False skips the colour (``rgb`` is None): masks and depth only, faster.
        near: near plane in scene units; default ``1e-4`` of the scene extent.
        dtype: render precision (float64 for gradient checks).
        backend: ``auto``, ``cpu``, ``torch``, ``compiled`` or ``gsplat`` (:func:`resolve_backend`).
        precull: cull to the frame (:func:`frame_index`) before evaluating colours and calling the
            backend; the image and gradients are the same either way. Default: for scenes of
            at least :data:`PRECULL_MIN` Gaussians.
        backend_options: passed to the backend (torch: ``tile_size``, ``max_chunk_elements``;
            compiled: ``tile_size``).
    Returns:
        :class:`RenderOutput`.
    """
    name = resolve_backend(backend)
    device = scene.means.device
    check_render_memory(camera, (3 if colors else 0) + (0 if extra is None else extra.shape[1]), device, dtype)
    gaussians = scene if isinstance(scene, PreparedGaussians) else prepare(scene, dtype)
    if near is None:
        near = NEAR_FRACTION * gaussians.extent
    if not colors:  # no SH coefficients to copy along with a subset
        gaussians = dataclasses.replace(gaussians, sh=gaussians.sh[:, :0])
    if subset is not None:
        gaussians = gaussians.subset(subset)
        extra = extra[subset] if extra is not None else None
    pose = torch.as_tensor(camera.T_cw, device=device) if T_cw is None else T_cw
    pose = pose.to(device=device, dtype=torch.float64)
    K = torch.as_tensor(camera.K, dtype=dtype, device=device)
    if precull or (precull is None and len(gaussians) >= PRECULL_MIN):
        index = frame_index(gaussians, pose, K, camera.width, camera.height, near, far, CULL_CHUNK)
        gaussians = gaussians.subset(index)
        extra = extra[index] if extra is not None else None
    centre = camera_center(pose)
    means_local = (gaussians.means - centre).to(dtype)  # camera centre at the origin
    view = torch.zeros(4, 4, dtype=dtype, device=device)
    view[:3, :3] = pose[:3, :3].to(dtype)
    view[3, 3] = 1.0

    parts = [eval_sh_colors(gaussians.sh, means_local, sh_degree)] if colors else []
    if extra is not None:
        parts.append(extra.to(dtype))
    if len(parts) == 1:  # one part is passed as it is, without a copy
        features = parts[0]
    elif parts:
        features = torch.cat(parts, -1)
    else:
        features = means_local.new_zeros(len(means_local), 0)
    args = (means_local, gaussians.factors, gaussians.opacities, features, view, K)
    if name == "gsplat":
        from .gsplat_backend import rasterize_gsplat

        image, alpha, depth_sum, stats = rasterize_gsplat(
            *args, camera.width, camera.height, near=near, far=far, **backend_options
        )
    elif name == "compiled":
        from .compiled_backend import rasterize_compiled

        # The kernel takes the recentring's gradient itself (one sum, not three autograd passes over N).
        image, alpha, depth_sum, stats = rasterize_compiled(
            means_local.detach(), *args[1:], camera.width, camera.height, near=near, far=far,
            origin=(gaussians.means, centre), **backend_options,
        )  # fmt: skip
    else:
        from .torch_backend import rasterize_torch

        image, alpha, depth_sum, stats = rasterize_torch(
            *args, camera.width, camera.height, near=near, far=far, **backend_options
        )

    channels = 3 if colors else 0
    # Without extra channels the image is the colour (a slice would cost its backward an image-sized copy).
    rgb = (image if extra is None else image[..., :3]) if colors else None
    if background is not None and rgb is not None:
        bg = torch.as_tensor(background, dtype=dtype, device=device)
        rgb = rgb + (1.0 - alpha)[..., None] * bg
    valid = alpha > DEPTH_ALPHA_MIN
    depth = torch.where(valid, depth_sum / alpha.clamp_min(DEPTH_ALPHA_MIN), torch.zeros_like(alpha))
    stats["backend"] = name
    return RenderOutput(
        rgb=rgb, alpha=alpha, depth=depth, extra=image[..., channels:] if extra is not None else None, stats=stats
    )


__all__ = [
    "BACKENDS",
    "PreparedGaussians",
    "RenderOutput",
    "check_render_memory",
    "frame_index",
    "indexed",
    "prepare",
    "render",
    "resolve_backend",
    "scene_extent",
]
