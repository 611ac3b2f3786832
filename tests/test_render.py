"""Renderer properties: analytic cases, gradients, invariances and degenerate inputs."""

from __future__ import annotations

import importlib.util
import math
import warnings

import numpy as np
import pytest
import torch
from conftest import make_camera, make_scene

from capframe.geometry import se3_exp
from capframe.render import render
from capframe.render.sh import sh_basis
from capframe.render.torch_backend import ALPHA_MAX, ALPHA_MIN, SIGMA_MAX, TRANSMITTANCE_MIN, composite_blocks
from capframe.scene import Camera, GaussianScene

f64 = torch.float64


def axis_camera(width=40, height=30, focal=50.0, cx=20.5, cy=15.5) -> Camera:
    """Camera at the origin looking along +z with the principal point on a pixel centre."""
    return Camera(np.eye(4), np.array([[focal, 0, cx], [0, focal, cy], [0, 0, 1.0]]), width, height)


def gaussians(means, scales, opacities, colors, dtype=f64) -> GaussianScene:
    n = len(means)
    quats = torch.tensor([[1.0, 0, 0, 0]] * n)
    t = lambda v: torch.as_tensor(v, dtype=torch.float64)  # noqa: E731
    return GaussianScene.from_activated(t(means), t(quats), t(scales), t(opacities), t(colors)).to(dtype=dtype)


def test_single_isotropic_gaussian_matches_analytic_image():
    z, s, o, color = 4.0, 0.05, 0.8, (0.9, 0.4, 0.1)
    cam = axis_camera()
    out = render(gaussians([[0, 0, z]], [[s, s, s]], [o], [color]), cam, backend="torch", dtype=f64)
    var = (cam.K[0, 0] * s / z) ** 2 + 0.3  # projected variance plus the 0.3 px^2 low-pass
    u, v = np.meshgrid(np.arange(cam.width) + 0.5, np.arange(cam.height) + 0.5)
    sigma = ((u - 20.5) ** 2 + (v - 15.5) ** 2) / (2 * var)
    alpha = np.minimum(0.999, o * np.exp(-sigma))
    alpha[(sigma > 4.5) | (alpha < 1 / 255)] = 0.0
    assert np.unravel_index(int(out.alpha.argmax()), out.alpha.shape) == (15, 20)
    np.testing.assert_allclose(out.alpha.numpy(), alpha, atol=1e-12)
    np.testing.assert_allclose(out.rgb.numpy(), alpha[..., None] * np.array(color), atol=1e-12)
    np.testing.assert_allclose(out.depth.numpy()[alpha > 0], z, atol=1e-12)
    assert (out.depth.numpy()[alpha == 0] == 0).all()


def test_front_to_back_order_and_background():
    # Far green Gaussian listed first: sorting by depth must still put red in front.
    scene = gaussians([[0, 0, 4.0], [0, 0, 2.0]], [[0.2] * 3, [0.1] * 3], [0.7, 0.6], [[0, 1, 0], [1, 0, 0]])
    out = render(scene, axis_camera(), backend="torch", dtype=f64, background=(0, 0, 1))
    a_near = 0.6  # exactly at the pixel centre sigma = 0
    a_far = 0.7
    t_far = (1 - a_near) * a_far
    rgb = out.rgb[15, 20]
    assert torch.allclose(rgb, torch.tensor([a_near, t_far, 1 - a_near - t_far], dtype=f64), atol=1e-12)
    assert math.isclose(float(out.alpha[15, 20]), a_near + t_far, rel_tol=1e-12)
    assert math.isclose(float(out.depth[15, 20]), (a_near * 2.0 + t_far * 4.0) / (a_near + t_far), rel_tol=1e-12)


def test_transmittance_cutoff_stops_before_one_in_ten_thousand():
    # Alpha clamps at 0.999: after one Gaussian T = 1e-3, a second would leave 1e-6 < 1e-4, so it is skipped.
    scene = gaussians(
        [[0, 0, 2.0], [0, 0, 3.0], [0, 0, 4.0]], [[0.3] * 3] * 3, [1.0, 1.0, 1.0], [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    )
    out = render(scene, axis_camera(), backend="torch", dtype=f64)
    assert torch.allclose(out.rgb[15, 20], torch.tensor([0.999, 0, 0], dtype=f64), atol=1e-12)


def test_extra_channel_of_ones_equals_alpha(scene, camera):
    out = render(scene, camera, backend="torch", extra=torch.ones(len(scene), 2))
    assert torch.allclose(out.extra, out.alpha[..., None].expand(-1, -1, 2), atol=1e-6)


def _pose_loss(scene, camera, T, weights, backend="torch"):
    out = render(scene, camera, T_cw=T, backend=backend, dtype=f64)
    return (out.rgb * weights[0]).sum() + (out.alpha * weights[1]).sum() + (out.depth * weights[2]).sum()


@pytest.mark.parametrize("backend", ["torch", "compiled"])
@pytest.mark.parametrize("tau_scale", [0.0, 0.05])
def test_pose_gradient_matches_central_differences(tau_scale, backend):
    scene = make_scene(150, seed=3, sh_degree=2, dtype=f64)
    camera = make_camera(width=40, height=30)
    g = torch.Generator().manual_seed(1)
    weights = (
        torch.rand(30, 40, 3, generator=g, dtype=f64),
        torch.rand(30, 40, generator=g, dtype=f64),
        torch.rand(30, 40, generator=g, dtype=f64),
    )
    tau0 = torch.randn(6, generator=g, dtype=f64) * tau_scale
    T0 = torch.as_tensor(camera.T_cw)

    tau = tau0.clone().requires_grad_()
    _pose_loss(scene, camera, se3_exp(tau) @ T0, weights, backend).backward()
    assert torch.isfinite(tau.grad).all()

    h = 1e-6
    numeric = torch.zeros(6, dtype=f64)
    for i in range(6):
        e = torch.zeros(6, dtype=f64)
        e[i] = h
        with torch.no_grad():
            numeric[i] = (
                _pose_loss(scene, camera, se3_exp(tau0 + e) @ T0, weights, backend)
                - _pose_loss(scene, camera, se3_exp(tau0 - e) @ T0, weights, backend)
            ) / (2 * h)
    assert float((tau.grad - numeric).norm() / numeric.norm()) < 1e-3


def reference_composite(attributes, slot_index, block_x, block_y, block_first, tile_size):
    """Compositing written from first principles (explicit sigma, log-space transmittance that
    carries over the earlier blocks of the same tile), differentiated by autograd."""
    slots = attributes[slot_index]
    mean, conic, opacity, values = slots[..., :2], slots[..., 2:5], slots[..., 5], slots[..., 6:]
    ys, xs = torch.meshgrid(torch.arange(tile_size, dtype=f64), torch.arange(tile_size, dtype=f64), indexing="ij")
    log_keep, out = {}, []
    for k in range(len(slot_index)):
        dx = (block_x[k] * tile_size + xs + 0.5).flatten()[None] - mean[k, :, :1]
        dy = (block_y[k] * tile_size + ys + 0.5).flatten()[None] - mean[k, :, 1:]
        a, b, c = conic[k, :, :1], conic[k, :, 1:2], conic[k, :, 2:]
        sigma = 0.5 * a * dx**2 + b * dx * dy + 0.5 * c * dy**2
        g = opacity[k, :, None] * torch.exp(-sigma)
        alpha = torch.where((sigma <= SIGMA_MAX) & (g >= ALPHA_MIN), g.clamp_max(ALPHA_MAX), torch.zeros_like(g))
        log_keep[k] = torch.log1p(-alpha)
        carried = sum(
            (log_keep[j].sum(0) for j in range(k) if block_first[j] == block_first[k]), torch.zeros(tile_size**2, dtype=f64)
        )
        log_after = carried + torch.cumsum(log_keep[k], 0)
        weights = torch.where(
            log_after > math.log(TRANSMITTANCE_MIN), alpha * torch.exp(log_after - log_keep[k]), torch.zeros_like(alpha)
        )
        out.append(weights.T @ torch.cat([values[k], torch.ones_like(values[k, :, :1])], -1))
    return torch.stack(out)


def test_analytic_compositing_backward_matches_autograd():
    g = torch.Generator().manual_seed(0)
    G, nb, B, S = 9, 4, 6, 4
    means2d = torch.rand(G, 2, generator=g, dtype=f64) * 8
    L = torch.randn(G, 2, 2, generator=g, dtype=f64) * 0.4
    cov = L @ L.transpose(-1, -2) + 1.2 * torch.eye(2, dtype=f64)
    det = cov[:, 0, 0] * cov[:, 1, 1] - cov[:, 0, 1] ** 2
    conics = torch.stack([cov[:, 1, 1] / det, -cov[:, 0, 1] / det, cov[:, 0, 0] / det], -1)
    opacities = torch.rand(G, 1, generator=g, dtype=f64) * 0.9 + 0.05
    values = torch.randn(G, 3, generator=g, dtype=f64)
    attributes = torch.cat([means2d, conics, opacities, values], -1)
    attributes[-1] = 0.0  # the padding row
    attributes.requires_grad_()
    # Gaussians appear in several slots (several tiles); the last row pads partly filled blocks.
    slot_index = torch.randint(0, G - 1, (nb, B), generator=g)
    slot_index[1, 4:] = G - 1
    # Blocks 0-1 form one tile (a carry crosses the block boundary), 2 and 3 are tiles of their own.
    block_x, block_y, block_first = torch.tensor([0, 0, 1, 1]), torch.tensor([0, 0, 0, 1]), torch.tensor([0, 0, 2, 3])
    args = (slot_index, block_x, block_y, block_first, S)
    assert torch.autograd.gradcheck(lambda a: composite_blocks(a, *args), (attributes,))
    analytic = composite_blocks(attributes, *args)
    reference = reference_composite(attributes, *args)
    assert torch.allclose(analytic, reference, atol=1e-14)
    (grad_analytic,) = torch.autograd.grad(
        (analytic * torch.arange(analytic.numel(), dtype=f64).view_as(analytic)).sum(), attributes
    )
    (grad_reference,) = torch.autograd.grad(
        (reference * torch.arange(reference.numel(), dtype=f64).view_as(reference)).sum(), attributes
    )
    assert torch.allclose(grad_analytic, grad_reference, rtol=1e-9, atol=1e-9)


def test_tile_size_and_chunking_do_not_change_the_image_or_gradient(scene, camera):
    results = []
    for options in (
        {"tile_size": 4},
        {"tile_size": 8, "block": 8},
        {"tile_size": 16},
        {"tile_size": 4, "max_chunk_elements": 2048},
    ):
        T = torch.as_tensor(camera.T_cw).clone().requires_grad_()
        out = render(scene, camera, T_cw=T, backend="torch", dtype=f64, **options)
        (out.rgb.sum() + out.depth.sum()).backward()
        results.append((out.rgb, out.depth, T.grad))
        if "max_chunk_elements" in options:
            assert out.stats["chunks"] > 1
    for rgb, depth, grad in results[1:]:
        assert torch.allclose(rgb, results[0][0], atol=1e-12)
        assert torch.allclose(depth, results[0][1], atol=1e-10)
        assert torch.allclose(grad, results[0][2], rtol=1e-9, atol=1e-9)


def test_scale_and_offset_invariance():
    scene = make_scene(300, seed=5, sh_degree=1)
    camera = make_camera()
    k, offset = 100.0, torch.tensor([1e4, -1e4, 1e4])
    moved = GaussianScene(scene.means * k + offset, scene.quats, scene.log_scales + math.log(k), scene.opacity_logits, scene.sh)
    R = camera.R
    centre = camera.center * k + offset.double().numpy()
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, -R @ centre
    a = render(scene, camera, backend="torch")
    b = render(moved, camera.with_pose(T), backend="torch")
    assert float(a.alpha.max()) > 0.5
    assert float((a.rgb - b.rgb).abs().max()) < 2e-4
    assert float((a.alpha - b.alpha).abs().max()) < 2e-4
    valid = a.depth_valid & b.depth_valid
    assert torch.allclose(b.depth[valid], a.depth[valid] * k, rtol=1e-4)


def test_behind_camera_near_plane_and_inside_cloud_give_finite_values_and_gradients():
    scene = make_scene(400, seed=7, spread=2.0, scale=(0.05, 0.4))  # the camera sits inside the cloud
    camera = make_camera(eye=(0.0, 0.0, 0.0), target=(0.0, 0.0, 1.0))
    tau = torch.zeros(6, dtype=f64, requires_grad=True)
    out = render(scene, camera, T_cw=se3_exp(tau) @ torch.as_tensor(camera.T_cw), backend="torch")
    assert out.stats["visible"] < len(scene)  # some are behind the camera
    (out.rgb.sum() + out.alpha.sum() + out.depth.sum()).backward()
    for image in (out.rgb, out.alpha, out.depth):
        assert torch.isfinite(image).all()
    assert torch.isfinite(tau.grad).all() and tau.grad.abs().sum() > 0


def test_degenerate_gaussians_are_handled(camera):
    scene = make_scene(50, seed=2)
    n = len(scene)
    log_scales = scene.log_scales.clone()
    log_scales[0] = -float("inf")  # zero scale: a point, blurred by the 0.3 px low-pass
    log_scales[1] = 80.0  # exp(80) overflows float32: its covariance is not finite
    logits = scene.opacity_logits.clone()
    logits[2], logits[3] = float("inf"), -float("inf")  # saturated opacities
    weird = GaussianScene(scene.means, scene.quats, log_scales, logits, scene.sh)
    T = torch.as_tensor(camera.T_cw).clone().requires_grad_()
    with pytest.warns(UserWarning, match="non-finite covariance"):
        out = render(weird, camera, T_cw=T, backend="torch")
    (out.rgb.sum() + out.depth.sum()).backward()
    assert torch.isfinite(out.rgb).all() and torch.isfinite(out.depth).all() and torch.isfinite(T.grad).all()
    assert out.stats["visible"] <= n - 1


def test_sh_basis_is_orthonormal():
    # Fibonacci sphere: a near-uniform quadrature, independent of the basis constants.
    n = 200_000
    i = torch.arange(n, dtype=f64) + 0.5
    z = 1 - 2 * i / n
    phi = math.pi * (1 + 5**0.5) * i
    r = torch.sqrt(1 - z * z)
    dirs = torch.stack([r * torch.cos(phi), r * torch.sin(phi), z], -1)
    Y = sh_basis(dirs, 3)
    gram = Y.T @ Y * (4 * math.pi / n)
    assert torch.allclose(gram, torch.eye(16, dtype=f64), atol=1e-4)


def _gsplat_torch_impl():
    spec = importlib.util.find_spec("gsplat")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("gsplat is not installed")
    path = f"{spec.submodule_search_locations[0]}/cuda/_torch_impl.py"
    # Load the pure-PyTorch reference file alone: importing the gsplat package is not needed.
    module_spec = importlib.util.spec_from_file_location("gsplat_torch_reference", path)
    module = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(module)
    return module


def test_projection_matches_gsplat_reference_implementation():
    from capframe.render.torch_backend import covariance_factor, project_gaussians

    ref = _gsplat_torch_impl()
    scene = make_scene(500, seed=11, spread=1.5, dtype=f64)
    camera = make_camera(eye=(0.5, -1.0, -3.0), width=80, height=60)
    T, K = torch.as_tensor(camera.T_cw), torch.as_tensor(camera.K)
    factors = covariance_factor(scene.quats, scene.scales)
    covs = factors @ factors.transpose(-1, -2)
    proj = project_gaussians(scene.means, factors, scene.opacities, T, K, 80, 60, 0.01, 1e10)
    radii, means2d, depths, conics, _ = ref._fully_fused_projection(scene.means, covs, T[None], K[None], 80, 60)
    idx = proj.index
    assert (radii[0, idx] > 0).all(1).all()
    assert torch.allclose(proj.means2d, means2d[0, idx], atol=1e-10)
    assert torch.allclose(proj.depths, depths[0, idx], atol=1e-12)
    assert torch.allclose(proj.conics, conics[0, idx], rtol=1e-9, atol=1e-12)


def test_frustum_precull_never_drops_a_gaussian_the_projection_keeps():
    """may_touch_frame is a bound on the exact footprint test (EWA covariance, opacity cut-off,
    on-screen box); Gaussians around and beside the frustum, thin, huge and near the camera."""
    from capframe.render.torch_backend import covariance_factor, ewa_project, may_touch_frame, pixel_extent

    g = torch.Generator().manual_seed(3)
    n = 20000
    means = torch.randn(n, 3, generator=g, dtype=f64) * torch.tensor([4.0, 3.0, 2.0], dtype=f64) + torch.tensor(
        [0, 0, 2.5], dtype=f64
    )
    means[:, 2] = means[:, 2].abs() + 0.05  # in front of the camera, some very near
    scales = torch.exp(torch.randn(n, 3, generator=g, dtype=f64) * 1.5 - 2.0)  # anisotropic, up to metres
    quats = torch.randn(n, 4, generator=g, dtype=f64)
    factors = covariance_factor(quats / quats.norm(dim=1, keepdim=True), scales)
    opacities = torch.rand(n, generator=g, dtype=f64)
    R = torch.eye(3, dtype=f64)  # axis_camera's pose
    K = torch.as_tensor(axis_camera(64, 48, 60.0, 32.0, 24.0).K, dtype=f64)
    means_cam = means
    means2d, cov2d = ewa_project(means_cam, R, factors, K, 64, 48)
    ext = pixel_extent(cov2d, opacities)
    exact = (means2d + ext > 0).all(1) & (means2d[:, 0] - ext[:, 0] < 64) & (means2d[:, 1] - ext[:, 1] < 48)
    bound = may_touch_frame(means_cam, factors, K, 64, 48)
    assert bool(bound[exact].all())
    assert 0.1 < exact.float().mean() < 0.9 and float(bound.float().mean()) < 0.95  # the test exercises both sides


@pytest.mark.cuda
@pytest.mark.skipif(not torch.cuda.is_available() or importlib.util.find_spec("gsplat") is None, reason="needs CUDA and gsplat")
def test_gsplat_and_torch_backends_agree():
    """gsplat's CUDA rasteriser ("classic") against the torch reference, whose rules the compiled
    backend shares. Images agree up to one documented rule (capframe.render.torch_backend): we
    also cut each Gaussian at its 3-sigma ellipse, where gsplat skips it only when its alpha is
    below 1/255 (out to 3.33 sigma); hence a mean tolerance, not a pixel-exact one."""
    scene = make_scene(5000, seed=4, sh_degree=3).to("cuda")
    camera = make_camera(width=160, height=120, focal=150.0)
    outs, grads = {}, {}
    for backend in ("torch", "gsplat"):
        T = torch.as_tensor(camera.T_cw, device="cuda").clone().requires_grad_()
        out = render(scene, camera, T_cw=T, backend=backend)
        (out.rgb.sum() + out.alpha.sum() + 0.1 * out.depth.sum()).backward()
        outs[backend], grads[backend] = out, T.grad.flatten()
    for name in ("rgb", "alpha"):
        diff = (getattr(outs["torch"], name) - getattr(outs["gsplat"], name)).abs().mean()
        assert float(diff) < 1e-3, name
    # Depth as composited (alpha times the normalised depth), relative to the scene's depth: the
    # normalised depth of a pixel covered only by the ring's faint tails is that of whichever
    # tail is there, so it differs by the whole depth range where one backend has no alpha.
    torch_out, gsplat_out = outs["torch"], outs["gsplat"]
    diff = (torch_out.depth * torch_out.alpha - gsplat_out.depth * gsplat_out.alpha).abs().mean()
    assert float(diff / torch_out.depth[torch_out.depth_valid].mean()) < 1e-3
    cosine = torch.nn.functional.cosine_similarity(grads["torch"], grads["gsplat"], dim=0)
    assert float(cosine) > 0.99


@pytest.mark.cuda
@pytest.mark.skipif(not torch.cuda.is_available() or importlib.util.find_spec("gsplat") is None, reason="needs CUDA and gsplat")
def test_gsplat_matches_torch_without_the_three_sigma_cut(monkeypatch):
    """With the 3-sigma cut moved out to the alpha floor of the most opaque Gaussian (so that only
    the 1/255 floor cuts, gsplat's rule), the torch reference and gsplat agree to float32
    rounding: the rule is the only difference between them."""
    import capframe.render.torch_backend as torch_backend

    monkeypatch.setattr(torch_backend, "SIGMA_MAX", math.log(ALPHA_MAX / ALPHA_MIN))
    scene = make_scene(5000, seed=4, sh_degree=3).to("cuda")
    camera = make_camera(width=160, height=120, focal=150.0)
    ours, theirs = (render(scene, camera, backend=backend) for backend in ("torch", "gsplat"))
    for name in ("rgb", "alpha"):
        diff = (getattr(ours, name) - getattr(theirs, name)).abs()
        assert float(diff.mean()) < 1e-6 and float(diff.max()) < 1e-3, name
    assert float((ours.depth - theirs.depth).abs().mean()) < 1e-5


@pytest.mark.cuda
@pytest.mark.skipif(not torch.cuda.is_available(), reason="needs CUDA")
def test_culled_render_on_cuda_matches_cpu():
    """A scene large enough for the frame cull's spatial index (PRECULL_MIN) renders on the GPU
    as on the CPU: the index is built and queried on the scene's own device."""
    from capframe.render import PRECULL_MIN

    scene = make_scene(PRECULL_MIN + 1000, seed=5, spread=3.0, scale=(0.005, 0.02))
    camera = make_camera(eye=(0.5, -0.5, -2.0), width=64, height=48)
    outs = {device: render(scene.to(device), camera, backend="torch") for device in ("cpu", "cuda")}
    for name in ("rgb", "alpha", "depth"):
        assert torch.allclose(getattr(outs["cuda"], name).cpu(), getattr(outs["cpu"], name), atol=1e-5), name
    assert outs["cpu"].stats["visible"] < len(scene)  # some lie behind the camera or off the frame: culled


def stiff_scene(seed: int) -> GaussianScene:
    """Random Gaussians with the cases a renderer gets wrong: needle-thin and flat covariances,
    opacities within 1e-6 of 0 and 1, Gaussians behind the camera and straddling the near plane,
    and tiny and huge scales. The camera is :func:`make_camera`'s (at z = -4 looking at the origin)."""
    g = torch.Generator().manual_seed(seed)
    n = 600
    means = (torch.rand(n, 3, generator=g, dtype=f64) * 2 - 1) * torch.tensor([1.5, 1.5, 3.5], dtype=f64)
    means[:20, 2] = -4.0 + torch.rand(20, generator=g, dtype=f64) * 2e-3 - 1e-3  # around the camera's plane
    scales = torch.exp(torch.randn(n, 3, generator=g, dtype=f64) * 0.8 - 3.5)
    scales[20:60, :2] = 1e-7  # needles: the 0.3 px low-pass is all their 2D spread
    scales[60:100, 0] = 1e-6  # flat sheets, some seen edge-on
    scales[100:110] = 3.0  # huge: cover the view
    scales[110:130] = 1e-9  # points
    quats = torch.randn(n, 4, generator=g, dtype=f64)
    opacities = torch.rand(n, generator=g, dtype=f64) * 0.9 + 0.05
    opacities[130:180] = 1.0 - 1e-7
    opacities[180:230] = 1.0 / 255.0 + torch.rand(50, generator=g, dtype=f64) * 1e-3
    opacities[230:240] = 1e-6
    sh = torch.randn(n, 4, 3, generator=g, dtype=f64) * 0.5
    return GaussianScene.from_activated(means, quats, scales, opacities.clamp(1e-12, 1 - 1e-12), sh)


def _render_with_gradients(scene, camera, backend, dtype=f64, **options):
    """Images, pose gradient and the scene parameters' gradients of a weighted loss."""
    params = [p.detach().clone().requires_grad_() for p in (scene.means, scene.log_scales, scene.opacity_logits, scene.sh)]
    leaf = GaussianScene(params[0], scene.quats, params[1], params[2], params[3])
    T = torch.as_tensor(camera.T_cw).clone().requires_grad_()
    g = torch.Generator().manual_seed(0)
    out = render(leaf, camera, T_cw=T, backend=backend, dtype=dtype, **options)
    weights = torch.rand(*out.rgb.shape, generator=g, dtype=f64).to(dtype)
    ((out.rgb * weights).sum() + out.alpha.sum() + 0.3 * out.depth.sum()).backward()
    return out, T.grad, [p.grad for p in params]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_compiled_backend_matches_torch_on_stiff_scenes(seed):
    """Images, alphas, depths and the gradients (pose, means, scales, opacities, SH) agree with the
    PyTorch reference within 1e-5 (float64)."""
    scene = stiff_scene(seed)
    camera = make_camera(width=72, height=56)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the 1e-9 scales may warn about nothing here; both paths alike
        ref, ref_pose, ref_params = _render_with_gradients(scene, camera, "torch")
        out, pose, params = _render_with_gradients(scene, camera, "compiled")
    assert 0 < out.stats["visible"] < len(scene) - 20 and float(out.alpha.detach().max()) > 0.99
    for name in ("rgb", "alpha", "depth"):
        assert float((getattr(out, name) - getattr(ref, name)).abs().max().detach()) <= 1e-5, name
    assert float((pose - ref_pose).abs().max()) <= 1e-5 * max(1.0, float(ref_pose.abs().max()))
    for got, want in zip(params, ref_params):
        assert float((got - want).abs().max()) <= 1e-5 * max(1.0, float(want.abs().max()))


@pytest.mark.parametrize(("colors", "extras"), [(False, 1), (False, 0), (True, 2)])
def test_compiled_backend_matches_torch_at_every_channel_count(colors, extras):
    """The compiled kernels have copies for some channel counts (colour: 5 with camera z and
    alpha; one mask: 3) and a general one: masks only (3), no values at all (2) and colour with
    two masks (7) agree with the reference within 1e-5 (float64), images and the gradients to
    the pose and the extra channels."""
    scene = stiff_scene(4)
    camera = make_camera(width=72, height=56)
    g = torch.Generator().manual_seed(1)
    extra_values = torch.rand(len(scene), extras, generator=g, dtype=f64) if extras else None
    results = {}
    for backend in ("torch", "compiled"):
        T = torch.as_tensor(camera.T_cw).clone().requires_grad_()
        extra = extra_values.clone().requires_grad_() if extras else None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the stiff scene's 1e-9 scales, in both paths alike
            out = render(scene, camera, T_cw=T, extra=extra, colors=colors, backend=backend, dtype=f64)
        loss = out.alpha.sum() + 0.3 * out.depth.sum()
        loss = loss + (out.rgb.square().sum() if colors else 0.0) + (out.extra.square().sum() if extras else 0.0)
        loss.backward()
        results[backend] = (out, T.grad, extra.grad if extras else None)
    (ref, ref_pose, ref_extra), (out, pose, extra_grad) = results["torch"], results["compiled"]
    assert float(out.alpha.detach().max()) > 0.99
    names = ("alpha", "depth") + (("rgb",) if colors else ()) + (("extra",) if extras else ())
    for name in names:
        assert float((getattr(out, name) - getattr(ref, name)).abs().max().detach()) <= 1e-5, name
    assert float((pose - ref_pose).abs().max()) <= 1e-5 * max(1.0, float(ref_pose.abs().max()))
    if extras:
        assert float((extra_grad - ref_extra).abs().max()) <= 1e-5 * max(1.0, float(ref_extra.abs().max()))


def test_compiled_backend_image_does_not_depend_on_tile_size():
    scene = stiff_scene(3)
    camera = make_camera(width=50, height=38)
    outs = [_render_with_gradients(scene, camera, "compiled", tile_size=s) for s in (4, 8, 16)]
    for out, pose, _ in outs[1:]:
        assert torch.allclose(out.rgb, outs[0][0].rgb, atol=1e-12, rtol=0)
        assert torch.allclose(pose, outs[0][1], rtol=1e-10, atol=1e-10)


def test_compiled_backward_matches_central_differences():
    """Directional derivatives of a weighted loss along random directions of the pose, the means,
    the log-scales, the opacity logits and the SH coefficients."""
    scene = make_scene(150, seed=8, sh_degree=1, dtype=f64)
    camera = make_camera(width=40, height=30)
    g = torch.Generator().manual_seed(2)
    weights = torch.rand(30, 40, 3, generator=g, dtype=f64)
    T0 = torch.as_tensor(camera.T_cw)

    def loss(tau, means, log_scales, logits, sh):
        out = render(
            GaussianScene(means, scene.quats, log_scales, logits, sh),
            camera,
            T_cw=se3_exp(tau) @ T0,
            backend="compiled",
            dtype=f64,
        )
        return (out.rgb * weights).sum() + out.alpha.sum() + out.depth.sum()

    x0 = [torch.zeros(6, dtype=f64), scene.means, scene.log_scales, scene.opacity_logits, scene.sh]
    x = [v.detach().clone().requires_grad_() for v in x0]
    loss(*x).backward()
    for k, v in enumerate(x0):
        d = torch.randn(v.shape, generator=g, dtype=f64)
        analytic = float((x[k].grad * d).sum())
        h = 1e-7
        with torch.no_grad():
            plus = [u + h * d if j == k else u for j, u in enumerate(x0)]
            minus = [u - h * d if j == k else u for j, u in enumerate(x0)]
            numeric = float((loss(*plus) - loss(*minus)) / (2 * h))
        assert abs(analytic - numeric) <= 1e-4 * max(1.0, abs(numeric)), (k, analytic, numeric)


def test_compiled_backend_does_not_depend_on_the_thread_count():
    """Tiles are split into one group per thread: the image must be bitwise the same whatever the
    split, and the gradients (summed per group, then over groups) the same up to rounding."""
    scene = stiff_scene(4)
    camera = make_camera(width=64, height=48)
    threads = torch.get_num_threads()
    results = []
    try:
        for count in (1, 2):
            torch.set_num_threads(count)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                results.append(_render_with_gradients(scene, camera, "compiled", dtype=torch.float32))
    finally:
        torch.set_num_threads(threads)
    _assert_same_renders(results, rtol=1e-4)


def _assert_same_renders(results, rtol):
    """Every ``(output, pose gradient, parameter gradients)`` of ``results`` has the first one's
    images bit for bit and statistics, and its gradients up to ``rtol`` of their largest entry."""
    (out, pose, params), rest = results[0], results[1:]
    for other, other_pose, other_params in rest:
        for name in ("rgb", "alpha", "depth"):
            assert torch.equal(getattr(other, name), getattr(out, name)), name
        assert other.stats == out.stats
        assert torch.allclose(other_pose, pose, rtol=rtol, atol=rtol * float(pose.abs().max()))
        for got, want in zip(other_params, params):
            assert torch.allclose(got, want, rtol=rtol, atol=rtol * float(want.abs().max()))


def test_compiled_backend_does_not_depend_on_the_number_of_tile_row_groups(monkeypatch):
    """Groups of tile rows (``k, k + n, ...``) list, sort and composite their own pairs, and each
    has its own stretch of the pair and alpha buffers: with more groups than threads or than
    tile rows, the image is bitwise the same and the gradients the same up to rounding."""
    import capframe.render.compiled_backend as compiled

    scene = stiff_scene(6)
    camera = make_camera(width=44, height=20)  # 5 rows of 4-pixel tiles
    results = []
    for groups in (1, 2, 3, 7):
        monkeypatch.setattr(compiled, "_threads", lambda groups=groups: groups)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            results.append(_render_with_gradients(scene, camera, "compiled"))
    assert results[0][0].stats["composited"] > 0
    _assert_same_renders(results, rtol=1e-10)


def test_compiled_backend_renders_the_same_without_gradients():
    """A render without gradients records no pixel masks or alphas for a backward: its images
    and counts are bitwise those of the same render with gradients, at every tile size."""
    scene = stiff_scene(5)
    camera = make_camera(width=50, height=38)
    for tile_size in (4, 8):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            recorded, _, _ = _render_with_gradients(scene, camera, "compiled", dtype=torch.float32, tile_size=tile_size)
            with torch.no_grad():
                plain = render(scene, camera, backend="compiled", dtype=torch.float32, tile_size=tile_size)
        for name in ("rgb", "alpha", "depth"):
            assert torch.equal(getattr(plain, name), getattr(recorded, name).detach()), name
        assert plain.stats == recorded.stats and recorded.stats["composited"] > 0


def test_compiled_backend_renders_empty_views_and_keeps_gradients_of_unseen_gaussians_zero():
    """No Gaussian in view (all behind the camera) gives an empty image and zero gradients; the
    backward scatters into the visible Gaussians' rows only."""
    scene = make_scene(40, seed=6, dtype=f64)
    camera = make_camera(width=32, height=24)
    behind = GaussianScene(scene.means - torch.tensor([0.0, 0.0, 10.0], dtype=f64), scene.quats, scene.log_scales,
                           scene.opacity_logits, scene.sh)  # fmt: skip
    for s, visible in ((behind, False), (scene, True)):
        out, pose, params = _render_with_gradients(s, camera, "compiled")
        assert (out.stats["visible"] > 0) == visible
        if not visible:
            assert float(out.alpha.detach().abs().max()) == 0.0 and float(pose.abs().max()) == 0.0
            assert all(float(p.abs().max()) == 0.0 for p in params)
    # A Gaussian the renderer culls gets no gradient, one it composites does.
    far = scene.means.detach().clone()
    far[0] = torch.tensor([0.0, 0.0, -20.0], dtype=f64)  # behind the camera (at z = -4)
    moved = GaussianScene(far.requires_grad_(), scene.quats, scene.log_scales, scene.opacity_logits, scene.sh)
    out = render(moved, camera, backend="compiled", dtype=f64)
    (out.rgb.sum() + out.alpha.sum()).backward()
    assert float(moved.means.grad[0].abs().max()) == 0.0 and float(moved.means.grad[1:].abs().max()) > 0.0


@pytest.mark.parametrize("dtype", [torch.float32, f64])
def test_compiled_backend_orders_equal_depths_as_the_reference(dtype):
    """Gaussians at exactly the same depth, overlapping, of different colours: the composite
    depends on their order, which both backends take from the same key with ties in index
    order (the compiled backend's radix sort must be stable), at depths of several magnitudes."""
    means = [[0.0, 0.0, 4.0], [0.02, 0.0, 4.0], [0.0, 0.02, 4.0], [0.01, 0.01, 0.5], [0.0, 0.0, 0.5], [0, 0, 300.0]]
    colors = [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1], [1, 0, 1]]
    scales = [[0.2] * 3, [0.2] * 3, [0.2] * 3, [0.03] * 3, [0.03] * 3, [20.0] * 3]
    scene = gaussians(means, scales, [0.6, 0.7, 0.8, 0.5, 0.9, 0.7], colors, dtype=dtype)
    outs = [render(scene, axis_camera(), backend=b, dtype=dtype) for b in ("torch", "compiled")]
    assert float(outs[0].alpha.max()) > 0.9
    for name in ("rgb", "alpha", "depth"):
        scale = float(getattr(outs[0], name).abs().max())  # depths up to 300: float32 rounds at 3e-5
        assert float((getattr(outs[0], name) - getattr(outs[1], name)).abs().max()) <= 1e-6 * max(1.0, scale), name
    reordered = gaussians(means[::-1], scales[::-1], [0.6, 0.7, 0.8, 0.5, 0.9, 0.7][::-1], colors[::-1], dtype=dtype)
    flipped = render(reordered, axis_camera(), backend="compiled", dtype=dtype)
    assert float((flipped.rgb - outs[1].rgb).abs().max()) > 0.01  # the test sees the order


def test_compiled_lowest_set_bit_on_every_position_and_mixed_words():
    """The de Bruijn count of trailing zeros that walks a pair's pixel mask: a wrong table entry
    would composite the wrong pixel."""
    from capframe.render.compiled_backend import _lowest_bit

    rng = np.random.default_rng(0)
    words = [1 << k for k in range(32)] + [int(w) | 1 << 31 for w in rng.integers(1, 2**31, 200)]
    for word in words:
        assert _lowest_bit(np.int64(word)) == (word & -word).bit_length() - 1, hex(word)


@pytest.mark.parametrize("backend", ["torch", "compiled"])
def test_precull_in_chunks_gives_the_same_image_and_pose_gradient(backend, monkeypatch):
    """Culling to the frame before the backend (in chunks of 97 Gaussians) changes nothing: the
    colours (SH degree 3), an extra channel, depth and the pose gradient are those of the render
    without it, on a scene whose Gaussians mostly lie outside the frame or behind the camera."""
    import capframe.render as render_module
    from capframe.render import frame_index, prepare

    monkeypatch.setattr(render_module, "CULL_CHUNK", 97)
    scene = make_scene(3000, seed=4, spread=6.0, scale=(0.02, 0.2), sh_degree=3, dtype=f64)
    camera = make_camera(eye=(0.0, -0.5, -2.0))
    extra = (torch.arange(len(scene)) % 3 == 0).to(f64)[:, None]
    results = []
    for precull in (False, True):
        T = torch.as_tensor(camera.T_cw).clone().requires_grad_()
        out = render(scene, camera, T_cw=T, extra=extra, backend=backend, dtype=f64, precull=precull)
        (out.rgb.sum() + out.extra.sum() + out.depth.sum()).backward()
        results.append((out.rgb, out.extra, out.depth, out.alpha, T.grad))
    for a, b in zip(*results):
        assert torch.allclose(a, b, rtol=1e-9, atol=1e-10)
    kept = frame_index(prepare(scene, f64), torch.as_tensor(camera.T_cw), torch.as_tensor(camera.K), 64, 48, 1e-4, math.inf, 97)
    assert 0 < len(kept) < 0.6 * len(scene)  # the cull did drop a good part of the scene
