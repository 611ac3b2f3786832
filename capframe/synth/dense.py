"""Synthetic scenes at the scale of real captures: a generated scene refined to millions of
Gaussians with the statistics of captured 3DGS files (``capframe bench scale``).

A 3DGS trainer covers a surface with many small, overlapping, anisotropic Gaussians of mixed
opacity; our generator covers it with fewer, regular, nearly opaque disks. :func:`densify` turns
each generated Gaussian into ``k`` children drawn inside its ellipsoid (so labels, object ranges and
the ground truth carry over), with

* opacities drawn from the captured files' opacity distribution;
* log-scales that split the parent's footprint among its children (the geometric mean shrinks by
  ``sqrt(k)``) with the *shape* (the sorted log-scales about their mean) of a captured Gaussian;
* SH degree 3: DC from the parent's colour, bands 1-3 drawn with :data:`SH_BAND_STD`;
* floaters (small Gaussians anywhere in the scene's box) and huge faint Gaussians (a captured
  huge Gaussian's size ratio and opacity) at the captured files' shares, unlabelled.

:func:`capture_statistics` measures those distributions from the real files.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from ..geometry import quat_to_rotmat
from ..scene import GaussianScene, read_gaussians
from ..scene.model import SH_C0, opacity_logit
from ..scene.stats import floater_mask
from .generator import SynthScene

REAL = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "real" / "captured"
CAPTURED_FILES = (
    "plant/plant.splat",
    "academic_tarot_cards/academic_tarot_cards.splat",
    "playcanvas/guitar.compressed.ply",
    "playcanvas/biker.spz",
    "donut-inria/fused.ply",
)
# A Gaussian is "huge" when its largest standard deviation exceeds this multiple of the file's
# median largest one, "faint" below this opacity.
HUGE_RATIO = 10.0
FAINT_OPACITY = 0.2
# Standard deviation of the SH coefficients of bands 1, 2, 3 (every channel). None of the captured
# files stores SH above degree 0, so these are assumed, not measured: a band's spread a few times
# below the DC spread and falling with the degree, as in trained scenes' view-dependent colour.
SH_BAND_STD = (0.08, 0.05, 0.03)
SPREAD = 0.5  # children's offsets from the parent, in parent standard deviations


@dataclass
class CaptureStatistics:
    """Distributions pooled over captured 3DGS files (M Gaussians in all).

    Attributes:
        files: (name, Gaussian count, SH degree) of each file.
        opacities: (M,) activated opacities.
        shapes: (M, 3) sorted log-scales minus their mean: a Gaussian's anisotropy.
        floater_share: share of Gaussians outside each file's largest connected cluster
            (:func:`~capframe.scene.stats.floater_mask`).
        huge_share: share of huge faint Gaussians (:data:`HUGE_RATIO`, :data:`FAINT_OPACITY`).
        huge_log_ratio: (H,) log of their largest scale over the file's median largest scale.
        huge_opacities: (H,) their opacities.
    """

    files: list[tuple[str, int, int]]
    opacities: np.ndarray
    shapes: np.ndarray
    floater_share: float
    huge_share: float
    huge_log_ratio: np.ndarray
    huge_opacities: np.ndarray

    def summary(self) -> dict:
        """The figures ``capframe bench scale`` prints: opacity deciles and histogram, the
        anisotropy (median largest / smallest and middle / smallest scale ratio), the shares."""
        counts, _ = np.histogram(self.opacities, bins=10, range=(0.0, 1.0))
        return {
            "files": [f"{name} ({n}, SH {d})" for name, n, d in self.files],
            "gaussians": len(self.opacities),
            "opacity_deciles": np.quantile(self.opacities, np.linspace(0.1, 0.9, 9)).round(3).tolist(),
            "opacity_histogram_10_bins": (counts / counts.sum()).round(3).tolist(),
            "scale_ratio_max_min_median": float(np.exp(np.median(self.shapes[:, 2] - self.shapes[:, 0]))),
            "scale_ratio_mid_min_median": float(np.exp(np.median(self.shapes[:, 1] - self.shapes[:, 0]))),
            "floater_share": self.floater_share,
            "huge_faint_share": self.huge_share,
            "max_sh_degree": max(d for _, _, d in self.files),
            "sh_band_std_assumed": list(SH_BAND_STD),
        }


def capture_statistics(root: str | Path = REAL, files: tuple[str, ...] = CAPTURED_FILES) -> CaptureStatistics:
    """Measure :class:`CaptureStatistics` from ``files`` under ``root``; :class:`InputError`
    naming a missing file."""
    root = Path(root)
    opacities, shapes, ratios, huge_op, floaters, listed = [], [], [], [], 0, []
    for name in files:
        path = root / name
        if not path.is_file():
            raise InputError("captured 3DGS file not found (the real material lives in ../shared/data/real)", source=str(path))
        g = read_gaussians(path)
        op = g.opacities.double().numpy()
        log_scales = np.sort(g.log_scales.double().numpy(), axis=1)
        floaters += int((~floater_mask(g.means.numpy())).sum())
        log_ratio = log_scales[:, 2] - np.median(log_scales[:, 2])
        huge = (log_ratio > math.log(HUGE_RATIO)) & (op < FAINT_OPACITY)
        opacities.append(op)
        shapes.append(log_scales - log_scales.mean(1, keepdims=True))
        ratios.append(log_ratio[huge])
        huge_op.append(op[huge])
        listed.append((name, len(g), g.sh_degree))
    total = sum(n for _, n, _ in listed)
    return CaptureStatistics(
        listed,
        np.concatenate(opacities),
        np.concatenate(shapes),
        floaters / total,
        sum(len(r) for r in ratios) / total,
        np.concatenate(ratios),
        np.concatenate(huge_op),
    )


def _remap_ranges(value, k: int):
    """Every ``[start, end)`` Gaussian index range in ``value`` (a ground-truth field) times ``k``."""
    return [[a * k, b * k] for a, b in value]


def densify(scene: SynthScene, count: int, stats: CaptureStatistics, seed: int = 0) -> SynthScene:
    """``scene`` with about ``count`` Gaussians at the statistics of ``stats`` (module doc).

    Each generated Gaussian gets the same number ``k`` of children, stored next to each other, so
    an object's index range ``[a, b)`` becomes ``[k a, k b)``; floaters and huge faint Gaussians
    are appended with label -1. The ground truth's ranges and count follow; everything else
    (objects, cameras, up) is unchanged.
    """
    base = scene.gaussians
    n0 = len(base)
    extras = round(count * stats.floater_share), round(count * stats.huge_share)
    k = max(1, round((count - sum(extras)) / n0))
    rng = np.random.default_rng(seed)
    parent = np.repeat(np.arange(n0), k)
    n = len(parent)

    R = quat_to_rotmat(torch.nn.functional.normalize(base.quats.double(), dim=-1)).numpy()  # (n0, 3, 3)
    log_s = base.log_scales.double().numpy()
    offsets = rng.standard_normal((n, 3)) * SPREAD * np.exp(log_s)[parent]
    means = base.means.double().numpy()[parent] + np.einsum("nij,nj->ni", R[parent], offsets)
    # The children's size: the parent's geometric mean over sqrt(k) (its footprint split k ways);
    # their shape: a captured Gaussian's, its axes in the order of the parent's.
    size = log_s.mean(1)[parent] - 0.5 * math.log(k)
    shape = stats.shapes[rng.integers(0, len(stats.shapes), n)]
    order = np.argsort(np.argsort(log_s, axis=1), axis=1)[parent]  # rank of each parent axis
    child_log_s = size[:, None] + np.take_along_axis(shape, order, axis=1)
    opacities = stats.opacities[rng.integers(0, len(stats.opacities), n)]
    quats = base.quats.double().numpy()[parent]
    dc = base.sh[:, 0].double().numpy()[parent] + rng.normal(0.0, 0.02 / SH_C0, (n, 3))

    # Floaters and huge faint Gaussians, anywhere in the scene's box (1 % - 99 % of the means).
    lo, hi = np.quantile(means, [0.01, 0.99], axis=0)
    m = sum(extras)
    extra_means = lo + rng.random((m, 3)) * (hi - lo)
    extra_log_s = child_log_s[rng.integers(0, n, m)]
    extra_op = stats.opacities[rng.integers(0, len(stats.opacities), m)]
    if extras[1]:
        pick = rng.integers(0, len(stats.huge_log_ratio), extras[1])
        extra_log_s[extras[0] :] += stats.huge_log_ratio[pick, None]
        extra_op[extras[0] :] = stats.huge_opacities[pick]
    extra_quats = rng.standard_normal((m, 4))
    extra_dc = rng.normal(0.0, 1.0, (m, 3))

    total = n + m
    sh = np.zeros((total, 16, 3), dtype=np.float32)
    sh[:n, 0], sh[n:, 0] = dc, extra_dc
    for band, std in enumerate(SH_BAND_STD, start=1):
        sh[:, band**2 : (band + 1) ** 2] = rng.normal(0.0, std, (total, 2 * band + 1, 3))
    f32 = lambda a: torch.from_numpy(np.ascontiguousarray(a, dtype=np.float32))  # noqa: E731
    gaussians = GaussianScene(
        means=f32(np.concatenate([means, extra_means])),
        quats=f32(np.concatenate([quats, extra_quats])),
        log_scales=f32(np.concatenate([child_log_s, extra_log_s])),
        opacity_logits=opacity_logit(f32(np.concatenate([opacities, extra_op]))),
        sh=torch.from_numpy(sh),
        labels=torch.cat([base.labels[torch.from_numpy(parent)], torch.full((m,), -1, dtype=torch.int64)]),
    )
    truth = dict(scene.ground_truth, num_gaussians=total)
    truth["objects"] = [dict(o, gaussians=_remap_ranges([o["gaussians"]], k)[0]) for o in truth["objects"]]
    truth["front_feature"] = {key: _remap_ranges(ranges, k) for key, ranges in truth["front_feature"].items()}
    truth["densified"] = {"children": k, "floaters": extras[0], "huge_faint": extras[1], "seed": int(seed)}
    return dataclasses.replace(scene, gaussians=gaussians, ground_truth=truth)


__all__ = ["CaptureStatistics", "capture_statistics", "densify"]
