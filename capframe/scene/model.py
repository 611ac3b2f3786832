"""In-memory scene model: Gaussians and cameras.

``GaussianScene`` keeps the parameters the way 3DGS trainers store them (log-scales, opacity
logits, SH coefficients), so an Inria PLY reads and writes back bit for bit; the activated values
the renderer needs (positive scales, opacities in (0, 1)) are properties. ``Camera`` keeps its pose
and intrinsics in float64 (DESIGN §3); rendering casts to float32.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import torch
from torch import Tensor

from ..errors import InputError


def sh_degree_of(num_coeffs: int) -> int:
    """SH degree from the number of coefficients per channel, (degree + 1)^2."""
    degree = int(round(num_coeffs**0.5)) - 1
    if (degree + 1) ** 2 != num_coeffs or not 0 <= degree <= 3:
        raise InputError(f"{num_coeffs} SH coefficients per channel; expected 1, 4, 9 or 16 (degree 0-3)")
    return degree


@dataclass
class GaussianScene:
    """A set of N 3D Gaussians.

    Attributes:
        means: (N, 3) centres in world units.
        quats: (N, 4) rotations, ``wxyz``, normalised at render time.
        log_scales: (N, 3) natural-log standard deviations along the rotated axes.
        opacity_logits: (N,) logits of the opacities.
        sh: (N, (d+1)^2, 3) spherical-harmonics coefficients, degree d in 0..3; ``sh[:, 0]`` is DC.
        labels: optional (N,) int64 semantic label ids (-1 = unlabelled).
    """

    means: Tensor
    quats: Tensor
    log_scales: Tensor
    opacity_logits: Tensor
    sh: Tensor
    labels: Tensor | None = None

    def __post_init__(self) -> None:
        n = self.means.shape[0]
        expected = {
            "means": (n, 3),
            "quats": (n, 4),
            "log_scales": (n, 3),
            "opacity_logits": (n,),
        }
        for name, shape in expected.items():
            if tuple(getattr(self, name).shape) != shape:
                raise InputError(f"GaussianScene.{name} has shape {tuple(getattr(self, name).shape)}, expected {shape}")
        if self.sh.ndim != 3 or self.sh.shape[0] != n or self.sh.shape[2] != 3:
            raise InputError(f"GaussianScene.sh has shape {tuple(self.sh.shape)}, expected ({n}, (d+1)^2, 3)")
        sh_degree_of(self.sh.shape[1])
        if self.labels is not None and tuple(self.labels.shape) != (n,):
            raise InputError(f"GaussianScene.labels has shape {tuple(self.labels.shape)}, expected ({n},)")

    @classmethod
    def from_activated(
        cls,
        means: Tensor,
        quats: Tensor,
        scales: Tensor,
        opacities: Tensor,
        colors_or_sh: Tensor,
        labels: Tensor | None = None,
    ) -> GaussianScene:
        """Build from activated values: positive scales (N, 3), opacities in (0, 1) (N,), and
        either RGB colours in [0, 1] (N, 3) or SH coefficients (N, K, 3).

        Opacities are clipped to ``[1e-6, 1 - 1e-6]`` so their logits stay finite (:func:`opacity_logit`).
        """
        if colors_or_sh.ndim == 2:
            sh = rgb_to_sh_dc(colors_or_sh)[:, None, :]
        else:
            sh = colors_or_sh
        return cls(
            means=means,
            quats=quats,
            log_scales=torch.log(scales),
            opacity_logits=opacity_logit(opacities),
            sh=sh,
            labels=labels,
        )

    def __len__(self) -> int:
        return self.means.shape[0]

    @property
    def scales(self) -> Tensor:
        """(N, 3) positive standard deviations."""
        return torch.exp(self.log_scales)

    @property
    def opacities(self) -> Tensor:
        """(N,) opacities in (0, 1)."""
        return torch.sigmoid(self.opacity_logits)

    @property
    def sh_degree(self) -> int:
        return sh_degree_of(self.sh.shape[1])

    def _map(self, fn) -> GaussianScene:
        values = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        return GaussianScene(**{k: (fn(k, v) if v is not None else None) for k, v in values.items()})

    def to(self, device: torch.device | str | None = None, dtype: torch.dtype | None = None) -> GaussianScene:
        """Move to a device and/or cast the floating-point fields (labels stay int64)."""
        return self._map(lambda k, v: v.to(device=device) if k == "labels" else v.to(device=device, dtype=dtype))

    def subset(self, index: Tensor) -> GaussianScene:
        """The Gaussians selected by a boolean mask (N,) or an index tensor (M,)."""
        return self._map(lambda k, v: v[index])

    def check_finite(self, source: str | None = None) -> None:
        """Raise :class:`InputError` naming the first field with a non-finite value."""
        for name in ("means", "quats", "log_scales", "opacity_logits", "sh"):
            value = getattr(self, name)
            bad = ~torch.isfinite(value)
            if bad.any():
                row = int(bad.reshape(value.shape[0], -1).any(1).nonzero()[0])
                raise InputError(
                    f"{int(bad.reshape(value.shape[0], -1).any(1).sum())} Gaussians have non-finite "
                    f"'{name}' (first: Gaussian {row}); expected finite values",
                    source=source,
                )
        zero_quat = self.quats.norm(dim=-1) == 0
        if zero_quat.any():
            raise InputError(
                f"{int(zero_quat.sum())} Gaussians have an all-zero quaternion (first: Gaussian "
                f"{int(zero_quat.nonzero()[0])}); expected a rotation",
                source=source,
            )


SH_C0 = 0.28209479177387814  # Y_0^0 = 1 / (2 sqrt(pi))


def opacity_logit(opacities: Tensor, eps: float = 1e-6) -> Tensor:
    """Logits of opacities (any shape), clipped to ``[eps, 1 - eps]`` first so they stay finite
    (quantised formats store fully transparent and fully opaque splats as 0 and 1)."""
    p = opacities.clamp(eps, 1.0 - eps)
    return torch.log(p) - torch.log1p(-p)


def rgb_to_sh_dc(rgb: Tensor) -> Tensor:
    """DC SH coefficient that evaluates to ``rgb`` (Inria convention: colour = SH + 0.5)."""
    return (rgb - 0.5) / SH_C0


@dataclass
class Camera:
    """A pinhole camera.

    Attributes:
        T_cw: (4, 4) float64 world-to-camera pose, OpenCV axes.
        K: (3, 3) float64 intrinsics in pixels (pixel centres at integer + 0.5).
        width, height: image size in pixels.
        name: identifier, usually the training image's file name stem.
        image_path: path of the training image, if any.
    """

    T_cw: np.ndarray
    K: np.ndarray
    width: int
    height: int
    name: str = ""
    image_path: str | None = field(default=None)

    def __post_init__(self) -> None:
        self.T_cw = np.asarray(self.T_cw, dtype=np.float64)
        self.K = np.asarray(self.K, dtype=np.float64)
        self.width, self.height = int(self.width), int(self.height)
        self.validate()

    def validate(self, source: str | None = None) -> None:
        """Raise :class:`InputError` unless the pose is a finite rigid transform and K is a valid
        pinhole matrix for a positive image size."""
        where = source or (f"camera '{self.name}'" if self.name else "camera")
        if self.T_cw.shape != (4, 4) or self.K.shape != (3, 3):
            raise InputError(f"T_cw has shape {self.T_cw.shape} and K {self.K.shape}; expected (4, 4) and (3, 3)", source=where)
        for name, value in (("T_cw", self.T_cw), ("K", self.K)):
            if not np.isfinite(value).all():
                raise InputError(f"{name} has non-finite values {value.tolist()}; expected finite numbers", source=where)
        R = self.T_cw[:3, :3]
        if np.abs(R @ R.T - np.eye(3)).max() > 1e-5 or np.linalg.det(R) < 0:
            raise InputError("rotation part of T_cw is not a proper rotation (R R^T != I or det < 0)", source=where)
        if not np.allclose(self.T_cw[3], [0, 0, 0, 1]):
            raise InputError(f"last row of T_cw is {self.T_cw[3].tolist()}, expected [0, 0, 0, 1]", source=where)
        if self.K[0, 0] <= 0 or self.K[1, 1] <= 0:
            raise InputError(f"focal lengths fx={self.K[0, 0]}, fy={self.K[1, 1]}; expected positive", source=where)
        if self.width <= 0 or self.height <= 0:
            raise InputError(f"image size {self.width}x{self.height}; expected positive", source=where)

    @property
    def R(self) -> np.ndarray:
        return self.T_cw[:3, :3]

    @property
    def t(self) -> np.ndarray:
        return self.T_cw[:3, 3]

    @property
    def center(self) -> np.ndarray:
        """Camera centre in world coordinates, ``-R^T t``."""
        return -self.R.T @ self.t

    @property
    def T_wc(self) -> np.ndarray:
        """Camera-to-world pose (OpenCV axes)."""
        T = np.eye(4)
        T[:3, :3] = self.R.T
        T[:3, 3] = self.center
        return T

    def resized(self, width: int, height: int) -> Camera:
        """The same camera at another image size (intrinsics scaled per axis)."""
        K = self.K.copy()
        K[0] *= width / self.width
        K[1] *= height / self.height
        return dataclasses.replace(self, K=K, width=width, height=height)

    def with_long_side(self, long_side: int) -> Camera:
        """The same camera resized so that its longer side is ``long_side`` pixels."""
        s = long_side / max(self.width, self.height)
        return self.resized(max(1, round(self.width * s)), max(1, round(self.height * s)))

    def padded(self, pad_x: int, pad_y: int) -> Camera:
        """The same camera on a canvas with a border of ``pad_x`` and ``pad_y`` pixels on each
        side: the principal point moves with the frame, so the canvas's centre crop is exactly
        this camera's image."""
        K = self.K.copy()
        K[0, 2] += pad_x
        K[1, 2] += pad_y
        return dataclasses.replace(self, K=K, width=self.width + 2 * pad_x, height=self.height + 2 * pad_y)

    def with_pose(self, T_cw: np.ndarray) -> Camera:
        return dataclasses.replace(self, T_cw=np.asarray(T_cw, dtype=np.float64))


def scene_extent(means: Tensor) -> float:
    """Robust size of a point set: median distance to the coordinate-wise median (> 0)."""
    if len(means) == 0:
        return 1.0
    centre = means.median(0).values
    extent = float((means - centre).norm(dim=-1).median())
    return extent if extent > 0 else 1.0


def scene_scale(cameras: list[Camera], means: Tensor) -> float:
    """Scene scale ``s`` (DESIGN §3): the median distance from the training cameras to the scene
    centre (the median of the Gaussian means); the Gaussians' own extent without cameras."""
    if not cameras:
        return scene_extent(means.detach())
    centre = means.detach().median(0).values.double().numpy()
    return float(np.median([np.linalg.norm(c.center - centre) for c in cameras]))
