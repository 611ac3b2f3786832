"""Scale: the occlusion phase's occluder cull, the synthetic scenes at capture statistics and
``capframe bench scale``'s arguments."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import torch
from conftest import make_camera

from capframe.errors import InputError
from capframe.geometry import camera_center, look_at
from capframe.refine.optimize import Occluders
from capframe.render import prepare, render
from capframe.scene import GaussianScene

f64 = torch.float64


def _cluttered_scene(seed: int = 0) -> tuple[GaussianScene, np.ndarray]:
    """A subject (a ball at the origin), a blob half in front of it seen from -z, and clutter all
    around: small and huge Gaussians, some near the camera and beside it. Returns the scene and
    the subject's indices."""
    g = torch.Generator().manual_seed(seed)
    subject = torch.randn(400, 3, generator=g, dtype=f64) * 0.15
    blocker = torch.randn(400, 3, generator=g, dtype=f64) * 0.12 + torch.tensor([0.15, 0.0, -1.2], dtype=f64)
    clutter = (torch.rand(6000, 3, generator=g, dtype=f64) * 2 - 1) * 12.0
    near_sight = (torch.rand(300, 3, generator=g, dtype=f64) * 2 - 1) * torch.tensor([1.0, 1.0, 2.5], dtype=f64)
    # A ring of small Gaussians over the subject's silhouette, midway to the camera at (0, 0, -4).
    angle = torch.rand(200, generator=g, dtype=f64) * 2 * math.pi
    rim = torch.stack([0.22 * angle.cos(), 0.22 * angle.sin(), torch.full_like(angle, -1.5)], 1)
    means = torch.cat([subject, blocker, clutter, near_sight - torch.tensor([0.0, 0.0, 1.0], dtype=f64), rim])
    n = len(means)
    scales = torch.exp(torch.randn(n, 3, generator=g, dtype=f64) * 0.5 - 3.5)
    scales[-len(rim) :] = 0.01
    scales[800::50] *= 30.0  # huge ones
    quats = torch.randn(n, 4, generator=g, dtype=f64)
    opacities = torch.rand(n, generator=g, dtype=f64) * 0.8 + 0.2
    opacities[-len(near_sight) - len(rim) : -len(rim)] = 0.05  # faint, so the subject shows through them
    colours = torch.rand(n, 3, generator=g, dtype=f64)
    return GaussianScene.from_activated(means, quats, scales, opacities, colours), np.arange(400)


def _pose(eye) -> torch.Tensor:
    t = lambda v: torch.tensor(v, dtype=f64)  # noqa: E731
    return look_at(t(eye), t((0.0, 0.0, 0.0)), t((0.0, -1.0, 0.0)))


def test_occluder_cull_keeps_every_gaussian_that_changes_the_subject_mask():
    """The subject channel and its pose gradient rendered from the culled set equal the whole
    scene's, at the culling centre and at centres inside the ball that reuses the cull."""
    scene, subject = _cluttered_scene()
    camera = make_camera(width=64, height=48, focal=60.0).padded(16, 12)
    labels = SimpleNamespace(subjects=[SimpleNamespace(gaussians=subject)])
    occluders = Occluders(scene, labels, camera, f64, extent=1.0)
    full = prepare(scene, f64)
    members = torch.zeros(len(scene), 1, dtype=f64)
    members[subject] = 1.0
    start = _pose((0.0, 0.0, -4.0))
    gaussians, membership = occluders.around(camera_center(start))
    assert len(gaussians) < 0.4 * len(scene)  # most of the clutter is culled
    culled_centre, reach = occluders.centre.clone(), occluders.reach
    for offset in ((0.0, 0.0, 0.0), (0.9, 0.0, 0.0), (0.0, -0.6, 0.6)):
        direction = torch.tensor(offset, dtype=f64)
        eye = camera_center(start) + (0.95 * reach * direction / direction.norm() if direction.norm() > 0 else 0.0)
        values = []
        for source, extra in ((full, members), occluders.around(eye)):
            T = _pose(tuple(eye.tolist())).clone().requires_grad_()
            out = render(source, camera, T_cw=T, extra=extra, colors=False, dtype=f64, backend="compiled")
            out.extra.sum().backward()
            values.append((out.extra[..., 0], T.grad))
        assert torch.equal(occluders.centre, culled_centre)  # inside the ball: the same cull
        assert float(values[0][0].detach().sum()) > 0.2
        assert torch.allclose(values[0][0], values[1][0], rtol=1e-9, atol=1e-12)
        assert torch.allclose(values[0][1], values[1][1], rtol=1e-8, atol=1e-10)
    # The blocker hides part of the subject: the cull kept it.
    alone = render(full, camera, T_cw=start, subset=torch.as_tensor(subject), colors=False, dtype=f64, backend="compiled")
    assert float(values[0][0].detach().sum()) < 0.9 * float(alone.alpha.sum())


def test_occluder_cull_moves_with_the_camera():
    scene, subject = _cluttered_scene(1)
    camera = make_camera(width=64, height=48, focal=60.0)
    occluders = Occluders(scene, SimpleNamespace(subjects=[SimpleNamespace(gaussians=subject)]), camera, f64, extent=1.0)
    occluders.around(camera_center(_pose((0.0, 0.0, -4.0))))
    first = occluders.centre.clone()
    side = _pose((4.0, 0.0, 0.0))
    gaussians, membership = occluders.around(camera_center(side))
    assert not torch.equal(occluders.centre, first)
    members = torch.zeros(len(scene), 1, dtype=f64)
    members[subject] = 1.0
    whole = render(prepare(scene, f64), camera, T_cw=side, extra=members, colors=False, dtype=f64, backend="compiled")
    culled = render(gaussians, camera, T_cw=side, extra=membership, colors=False, dtype=f64, backend="compiled")
    assert torch.allclose(whole.extra, culled.extra, rtol=1e-9, atol=1e-12)


def test_densify_keeps_labels_ranges_and_draws_capture_statistics():
    """Children follow their parent's label and object range; counts, SH degree and the drawn
    opacities are those asked for; floaters and huge faint Gaussians are unlabelled."""
    from capframe.synth.dense import CaptureStatistics, densify
    from capframe.synth.generator import build_scene

    room = build_scene(seed=1, objects=["mug", "ball"], views=4, density=0.3)
    rng = np.random.default_rng(0)
    stats = CaptureStatistics(
        [("a", 1000, 0)],
        opacities=np.full(1000, 0.25),
        shapes=np.tile([-1.0, 0.0, 1.0], (1000, 1)),
        floater_share=0.01,
        huge_share=0.02,
        huge_log_ratio=rng.uniform(2.5, 3.0, 20),
        huge_opacities=np.full(20, 0.05),
    )
    n0 = len(room.gaussians)
    dense = densify(room, 10 * n0, stats, seed=2)
    k = dense.ground_truth["densified"]["children"]
    extras = dense.ground_truth["densified"]["floaters"] + dense.ground_truth["densified"]["huge_faint"]
    assert len(dense.gaussians) == k * n0 + extras == dense.ground_truth["num_gaussians"]
    assert abs(len(dense.gaussians) - 10 * n0) <= n0
    assert dense.gaussians.sh_degree == 3
    labels = dense.gaussians.labels
    assert torch.equal(labels[: k * n0], room.gaussians.labels.repeat_interleave(k))
    assert bool((labels[k * n0 :] == -1).all())
    for before, after in zip(room.ground_truth["objects"], dense.ground_truth["objects"]):
        a, b = after["gaussians"]
        assert [a, b] == [k * before["gaussians"][0], k * before["gaussians"][1]]
        assert bool((labels[a:b] == after["label"]).all())
    opacities = dense.gaussians.opacities[: k * n0]
    assert torch.allclose(opacities, torch.full_like(opacities, 0.25), atol=1e-5)
    log_s = torch.sort(dense.gaussians.log_scales[: k * n0], dim=1).values
    assert torch.allclose(log_s[:, 2] - log_s[:, 0], torch.full((k * n0,), 2.0), atol=1e-4)  # the captured shape


@pytest.mark.parametrize("bad", ["", "0.3X", "12", "nanM", "30M"])
def test_bench_scale_sizes_reject_bad_counts(bad):
    from capframe.bench.scale import parse_sizes

    with pytest.raises(InputError, match="--sizes"):
        parse_sizes(bad)


def test_bench_scale_sizes():
    from capframe.bench.scale import parse_sizes, size_label

    assert parse_sizes("0.3M, 1M,250k") == [300_000, 1_000_000, 250_000]
    assert [size_label(n) for n in (300_000, 3_000_000, 50_000)] == ["0.3M", "3M", "50k"]


def test_bench_render_peak_memory_is_the_child_process_own():
    """capframe bench render measures each backend's peak in a fresh process: the peak must be
    that process's own (VmHWM), not the parent's carried across fork and exec, as ru_maxrss is
    on Linux; a parent holding 800 MB more must not show in the child's figure."""
    import numpy as np
    import pytest

    from capframe.bench.render import peak_memory
    from capframe.bench.scale import PeakMemory

    if PeakMemory.high_water_gb() != PeakMemory.high_water_gb():  # NaN: no /proc/self/status
        pytest.skip("needs Linux's /proc")
    ballast = np.ones(100_000_000)  # 800 MB, resident
    parent = PeakMemory.high_water_gb() * 1e3
    seconds, stats, peak, growth = peak_memory(2000, 48, 32, "compiled")
    assert seconds > 0 and stats["composited"] > 0
    assert 0 < growth < peak < parent - 600, (peak, parent)
    del ballast
