"""Shared fixtures: small random scenes and cameras built in memory."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from capframe.geometry import look_at
from capframe.scene import Camera, GaussianScene


def make_scene(
    n: int = 200,
    *,
    seed: int = 0,
    spread: float = 1.0,
    scale: tuple[float, float] = (0.02, 0.08),
    sh_degree: int = 0,
    dtype=torch.float32,
) -> GaussianScene:
    """Random Gaussians in a cube of half-size ``spread`` around the origin."""
    g = torch.Generator().manual_seed(seed)
    means = (torch.rand(n, 3, generator=g) * 2 - 1) * spread
    quats = torch.randn(n, 4, generator=g)
    scales = torch.rand(n, 3, generator=g) * (scale[1] - scale[0]) + scale[0]
    opacities = torch.rand(n, generator=g) * 0.8 + 0.1
    sh = torch.randn(n, (sh_degree + 1) ** 2, 3, generator=g) * 0.5
    scene = GaussianScene.from_activated(means, quats, scales * spread, opacities, sh)
    return scene.to(dtype=dtype)


def make_camera(
    eye=(0.0, -0.5, -4.0),
    target=(0.0, 0.0, 0.0),
    up=(0.0, -1.0, 0.0),
    *,
    width: int = 64,
    height: int = 48,
    focal: float = 60.0,
    roll: float = 0.0,
) -> Camera:
    t = lambda v: torch.tensor(v, dtype=torch.float64)  # noqa: E731
    T = look_at(t(eye), t(target), t(up), roll)
    K = np.array([[focal, 0.0, width / 2], [0.0, focal, height / 2], [0.0, 0.0, 1.0]])
    return Camera(T.numpy(), K, width, height, name="test")


@pytest.fixture(autouse=True, scope="session")
def one_thread():
    """Test renders are small: threads gain little there, and on a busy 2-core machine intra-op
    threads oversubscribe the cores and slow every test by an order of magnitude."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


@pytest.fixture
def scene() -> GaussianScene:
    return make_scene()


@pytest.fixture
def camera() -> Camera:
    return make_camera()
