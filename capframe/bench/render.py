"""Renderer benchmark: forward + backward (w.r.t. the pose) time per iteration of the torch
reference and the compiled CPU backend side by side, with ns per Gaussian-pixel pair, their
parity, peak memory, and the pose-gradient error against central finite differences;
``capframe bench render-cuda`` times gsplat against the torch reference on a GPU.

A **Gaussian-pixel pair** is a (Gaussian, pixel) pair that is composited: the pixel centre lies
inside the Gaussian's cut-offs (3-sigma ellipse, alpha >= 1/255) and compositing has not stopped
there; the compiled backend counts them (``stats["composited"]``). The same count, for the same
scene and view, divides both backends' times. Tile pairs (``pairs``) are reported too; times are
of a :func:`~capframe.render.prepare`-d scene (its pose-independent work done once, as Refine
does), and the two backends alternate within each iteration so that load on the shared machine
affects both alike.

The scene imitates a trained 3DGS reconstruction seen from a training camera: Gaussians lie on
surfaces (a floor, boxes, spheres), flattened along the surface normal, sized to their
neighbour spacing, with mixed opacities, so several layers overlap on every pixel as in real
scenes.
"""

from __future__ import annotations

import math
import multiprocessing as mp
import os
import time

import numpy as np
import torch

from ..geometry import look_at, rotmat_to_quat, se3_exp
from ..render import prepare, render
from ..scene import Camera, GaussianScene
from ..scene._io import intrinsics
from .scale import PeakMemory


def surface_scene(n: int, seed: int = 0, dtype: torch.dtype = torch.float32) -> GaussianScene:
    """``n`` flat Gaussians on a floor (z = 0), three boxes and two spheres inside [-2, 2]^2."""
    g = torch.Generator().manual_seed(seed)
    parts = []
    # (sampler, area): every sampler returns points (k, 3) and unit normals (k, 3).

    def floor(k):
        p = torch.rand(k, 2, generator=g, dtype=torch.float64) * 4 - 2
        return torch.cat([p, torch.zeros(k, 1, dtype=torch.float64)], 1), torch.tensor([[0.0, 0, 1]], dtype=torch.float64).expand(
            k, 3
        )

    def sphere(centre, radius):
        def sample(k):
            d = torch.randn(k, 3, generator=g, dtype=torch.float64)
            d = d / d.norm(dim=1, keepdim=True)
            return torch.tensor(centre, dtype=torch.float64) + radius * d, d

        return sample, 4 * math.pi * radius**2

    def box(centre, half):
        c, h = torch.tensor(centre, dtype=torch.float64), torch.tensor(half, dtype=torch.float64)

        def sample(k):
            u = torch.rand(k, 3, generator=g, dtype=torch.float64) * 2 - 1
            axis = torch.randint(0, 3, (k,), generator=g)
            sign = torch.where(torch.rand(k, generator=g) < 0.5, -1.0, 1.0).to(torch.float64)
            u[torch.arange(k), axis] = sign
            normal = torch.zeros(k, 3, dtype=torch.float64)
            normal[torch.arange(k), axis] = sign
            return c + u * h, normal

        return sample, 8 * float(h[0] * h[1] + h[1] * h[2] + h[0] * h[2])

    surfaces = [
        (floor, 16.0),
        sphere((0.8, 0.6, 0.5), 0.5),
        sphere((-0.9, -0.7, 0.35), 0.35),
        box((-0.6, 0.8, 0.4), (0.4, 0.3, 0.4)),
        box((0.7, -0.8, 0.3), (0.3, 0.3, 0.3)),
        box((0.0, 0.0, 0.15), (0.25, 0.5, 0.15)),
    ]
    total_area = sum(a for _, a in surfaces)
    counts = [int(n * a / total_area) for _, a in surfaces]
    counts[0] += n - sum(counts)
    for (sample, area), k in zip(surfaces, counts):
        points, normals = sample(k)
        spacing = math.sqrt(area / max(k, 1))
        parts.append((points, normals, spacing))
    means = torch.cat([p for p, _, _ in parts])
    normals = torch.cat([nrm for _, nrm, _ in parts])
    spacing = torch.cat([torch.full((len(p),), s, dtype=torch.float64) for p, _, s in parts])
    # Rotation whose third column is the normal: the flat axis of the Gaussian.
    helper = torch.where(
        normals[:, :1].abs() < 0.9,
        torch.tensor([[1.0, 0, 0]], dtype=torch.float64),
        torch.tensor([[0.0, 1, 0]], dtype=torch.float64),
    )
    t1 = torch.linalg.cross(normals, helper)
    t1 = t1 / t1.norm(dim=1, keepdim=True)
    R = torch.stack([t1, torch.linalg.cross(normals, t1), normals], -1)
    jitter = torch.rand(len(means), 2, generator=g, dtype=torch.float64) * 0.8 + 0.6
    scales = torch.cat([spacing[:, None] * jitter, spacing[:, None] * 0.1], 1)
    opacities = torch.rand(len(means), generator=g, dtype=torch.float64) * 0.7 + 0.3
    colors = torch.rand(len(means), 3, generator=g, dtype=torch.float64)
    return GaussianScene.from_activated(means, rotmat_to_quat(R), scales, opacities, colors).to(dtype=dtype)


def orbit_camera(width: int, height: int, azimuth_deg: float = 30.0) -> Camera:
    """A training-like view: 4.5 units out, 35 degrees up, 60 degree horizontal field of view."""
    az, el = math.radians(azimuth_deg), math.radians(35.0)
    eye = torch.tensor(
        [4.5 * math.cos(el) * math.cos(az), 4.5 * math.cos(el) * math.sin(az), 4.5 * math.sin(el)], dtype=torch.float64
    )
    T = look_at(eye, torch.tensor([0.0, 0.0, 0.3], dtype=torch.float64), torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64))
    focal = 0.5 * width / math.tan(math.radians(30.0))
    return Camera(T.numpy(), intrinsics(focal, focal, width / 2, height / 2), width, height, name="bench")


BACKENDS = ("torch", "compiled")


def _loss(out) -> torch.Tensor:
    return out.rgb.sum() + out.alpha.sum() + out.depth.mean()


def time_forward_backward(
    scene: GaussianScene, camera: Camera, iterations: int = 10, warmup: int = 2, backends=BACKENDS
) -> dict[str, tuple[float, dict]]:
    """Per backend: median seconds of one forward + backward w.r.t. the pose, and its stats.
    On a GPU scene the clock stops after the device has finished (CUDA runs asynchronously)."""
    prepared = prepare(scene)
    device = scene.means.device
    times: dict[str, list[float]] = {b: [] for b in backends}
    stats: dict[str, dict] = {}
    for i in range(warmup + iterations):
        for backend in backends:
            T = torch.as_tensor(camera.T_cw, device=device).clone().requires_grad_()
            start = time.perf_counter()
            out = render(prepared, camera, T_cw=T, backend=backend)
            _loss(out).backward()
            if device.type == "cuda":
                torch.cuda.synchronize(device)
            if i >= warmup:
                times[backend].append(time.perf_counter() - start)
            stats[backend] = out.stats
    return {b: (float(np.median(times[b])), stats[b]) for b in backends}


def _renders_and_pose_grads(scene: GaussianScene, camera: Camera, backends, dtype: torch.dtype) -> dict[str, tuple]:
    """Per backend: rgb (H, W, 3), alpha (H, W), depth (H, W) and the gradient (4, 4) of
    :func:`_loss` with respect to the pose, rendered on the scene's device."""
    results = {}
    prepared = prepare(scene, dtype)
    for backend in backends:
        T = torch.as_tensor(camera.T_cw, device=scene.means.device).clone().requires_grad_()
        out = render(prepared, camera, T_cw=T, backend=backend, dtype=dtype)
        _loss(out).backward()
        results[backend] = (out.rgb.detach(), out.alpha.detach(), out.depth.detach(), T.grad)
    return results


def parity(scene: GaussianScene, camera: Camera, dtype: torch.dtype) -> dict[str, float]:
    """Max abs differences compiled - torch of rgb, alpha, depth and the pose gradient (of
    :func:`_loss`), and the gradient's relative difference."""
    results = _renders_and_pose_grads(scene, camera, BACKENDS, dtype)
    diffs = [float((a - b).abs().max()) for a, b in zip(results["torch"], results["compiled"])]
    grad_rel = float((results["torch"][3] - results["compiled"][3]).norm() / results["torch"][3].norm())
    return {"rgb": diffs[0], "alpha": diffs[1], "depth": diffs[2], "pose_grad": diffs[3], "pose_grad_rel": grad_rel}


def _peak_memory_child(n: int, width: int, height: int, backend: str, queue) -> None:
    scene = surface_scene(n)
    camera = orbit_camera(width, height)
    loaded = PeakMemory.high_water_gb()
    seconds, stats = time_forward_backward(scene, camera, iterations=3, warmup=1, backends=(backend,))[backend]
    peak = PeakMemory.high_water_gb()
    queue.put((seconds, stats, peak * 1e3, (peak - loaded) * 1e3))


def peak_memory(n: int, width: int, height: int, backend: str) -> tuple[float, dict, float, float]:
    """Run one size with one backend in a fresh process: (seconds, stats, peak resident MB, its
    growth over the loaded scene MB). The peak is the child's ``VmHWM``, its own address space's:
    ``ru_maxrss`` would not do, since Linux carries the peak of the process that forked the child
    across its exec, so every child reported the parent's peak."""
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_peak_memory_child, args=(n, width, height, backend, queue))
    proc.start()
    result = queue.get()
    proc.join()
    return result


def pose_gradient_error(backend: str, seed: int = 0) -> float:
    """Relative error ||g - g_fd|| / ||g_fd|| of the pose gradient at a random small twist,
    float64, central differences. The step is 1e-8: in a dense scene a larger step lets some of
    the ~1e5 pair-pixels cross the 1/255 alpha floor or the depth-validity threshold, and each
    crossing is a jump that swamps the difference quotient."""
    scene = surface_scene(3000, seed=seed, dtype=torch.float64)
    camera = orbit_camera(64, 48)
    g = torch.Generator().manual_seed(seed)
    weights = torch.rand(48, 64, 3, generator=g, dtype=torch.float64)
    T0 = torch.as_tensor(camera.T_cw)

    def loss(tau):
        out = render(scene, camera, T_cw=se3_exp(tau) @ T0, backend=backend, dtype=torch.float64)
        return (out.rgb * weights).sum() + out.alpha.sum() + out.depth.sum()

    tau0 = torch.randn(6, generator=g, dtype=torch.float64) * 0.01
    tau = tau0.clone().requires_grad_()
    loss(tau).backward()
    numeric = torch.zeros(6, dtype=torch.float64)
    with torch.no_grad():
        for i in range(6):
            e = torch.zeros(6, dtype=torch.float64)
            e[i] = 1e-8
            numeric[i] = (loss(tau0 + e) - loss(tau0 - e)) / 2e-8
    return float((tau.grad - numeric).norm() / numeric.norm())


def _side_by_side(figures: dict, label: str, timed: dict[str, tuple[float, dict]]) -> None:
    """Seconds and ns per Gaussian-pixel pair of both backends, and the speed-up."""
    pairs = timed["compiled"][1]["composited"]
    figures[f"gaussian_pixel_pairs_{label}"] = pairs
    figures[f"tile_pairs_{label}"] = timed["torch"][1]["pairs"]
    for backend, (seconds, _) in timed.items():
        figures[f"{backend}_{label}_s"] = seconds
        figures[f"{backend}_{label}_ns_per_pair"] = seconds / pairs * 1e9
    figures[f"speedup_{label}"] = timed["torch"][0] / timed["compiled"][0]


def bench_render() -> dict:
    """The figures of ``capframe bench render``: per size, both backends' seconds and ns per
    Gaussian-pixel pair and their ratio, parity at 50k, per-backend peak memory (fresh
    processes), pose-gradient errors; with the thread count, the OpenMP wait policy and the
    machine's load (1-minute average) before and after, since the timings depend on both."""
    figures: dict = {
        "threads": torch.get_num_threads(),
        "openmp_wait_policy": os.environ.get("OMP_WAIT_POLICY", "unset"),
        "load_before": os.getloadavg()[0],
    }
    for n, (w, h) in ((5_000, (160, 120)), (50_000, (160, 120)), (300_000, (640, 480))):
        scene, camera = surface_scene(n), orbit_camera(w, h)
        label = f"{n // 1000}k_{w}x{h}"
        _side_by_side(figures, label, time_forward_backward(scene, camera, iterations=10 if n <= 50_000 else 3, warmup=1))
        if n == 50_000:
            for name, value in parity(scene, camera, torch.float32).items():
                figures[f"parity_f32_{label}_{name}"] = value
            for name, value in parity(surface_scene(n, dtype=torch.float64), camera, torch.float64).items():
                figures[f"parity_f64_{label}_{name}"] = value
    for backend in BACKENDS:
        seconds, stats, peak, growth = peak_memory(100_000, 640, 480, backend)
        figures[f"{backend}_100k_640x480_s"] = seconds
        figures[f"{backend}_peak_mem_100k_640x480_mb"] = peak
        figures[f"{backend}_render_mem_growth_100k_640x480_mb"] = growth
        figures[f"{backend}_pose_grad_rel_err"] = pose_gradient_error(backend)
    figures["load_after"] = os.getloadavg()[0]
    return figures


def gsplat_parity(scene: GaussianScene, camera: Camera) -> dict[str, float]:
    """gsplat against the torch reference on the GPU, float32: mean and max abs differences of
    rgb, alpha and depth, and the pose gradients' cosine and relative difference (of
    :func:`_loss`). A mean, since one rule differs on purpose (the 3-sigma cut,
    :mod:`capframe.render.torch_backend`), which moves a few edge pixels by up to 1/255."""
    results = _renders_and_pose_grads(scene, camera, ("torch", "gsplat"), torch.float32)
    figures = {}
    for name, a, b in zip(("rgb", "alpha", "depth"), results["torch"], results["gsplat"]):
        figures[f"{name}_mean_abs"] = float((a - b).abs().mean())
        figures[f"{name}_max_abs"] = float((a - b).abs().max())
    g_torch, g_gsplat = results["torch"][3].flatten(), results["gsplat"][3].flatten()
    figures["pose_grad_cosine"] = float(torch.nn.functional.cosine_similarity(g_torch, g_gsplat, dim=0))
    figures["pose_grad_rel"] = float((g_torch - g_gsplat).norm() / g_torch.norm())
    return figures


CUDA_SIZES = ((50_000, (160, 120)), (300_000, (640, 480)), (1_000_000, (1280, 720)))


def bench_render_cuda() -> dict:
    """The figures of ``capframe bench render-cuda`` (CUDA and gsplat): per size, the seconds of
    one forward + backward to the pose of gsplat and of the torch reference on the GPU, and of
    the compiled CPU backend in the same run (all CPU threads), each with ns per Gaussian-pixel
    pair (counted by the compiled backend); gsplat's speed-up over both; parity at 50k.
    A size or backend that fails records its error instead of stopping the others."""
    device = torch.device("cuda")
    figures: dict = {"gpu": torch.cuda.get_device_name(device), "cpu_threads": torch.get_num_threads()}
    for n, (w, h) in CUDA_SIZES:
        scene, camera = surface_scene(n), orbit_camera(w, h)
        label = f"{n // 1000}k_{w}x{h}"
        on_gpu = scene.to(device)
        for backend, on, iterations in (("compiled", scene, 3), ("torch", on_gpu, 10), ("gsplat", on_gpu, 10)):
            key = f"{backend}_{on.means.device.type}_{label}"
            try:
                seconds, stats = time_forward_backward(on, camera, iterations=iterations, warmup=2, backends=(backend,))[backend]
            except Exception as error:  # a failing size is a figure: the others still run
                figures[f"{key}_error"] = f"{type(error).__name__}: {error}"
                continue
            figures[f"{key}_s"] = seconds
            if backend == "compiled":
                figures[f"gaussian_pixel_pairs_{label}"] = stats["composited"]
        pairs, gsplat_s = figures.get(f"gaussian_pixel_pairs_{label}"), figures.get(f"gsplat_cuda_{label}_s")
        for key in (f"torch_cuda_{label}", f"gsplat_cuda_{label}", f"compiled_cpu_{label}"):
            if pairs and f"{key}_s" in figures:
                figures[f"{key}_ns_per_pair"] = figures[f"{key}_s"] / pairs * 1e9
            if gsplat_s and f"{key}_s" in figures and key != f"gsplat_cuda_{label}":
                figures[f"gsplat_speedup_over_{key}"] = figures[f"{key}_s"] / gsplat_s
        if n == 50_000:
            try:
                for name, value in gsplat_parity(on_gpu, camera).items():
                    figures[f"parity_gsplat_torch_{label}_{name}"] = value
            except Exception as error:
                figures[f"parity_gsplat_torch_{label}_error"] = f"{type(error).__name__}: {error}"
    figures["peak_gpu_mem_mb"] = torch.cuda.max_memory_allocated(device) / 1e6
    return figures
