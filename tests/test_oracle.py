"""The oracle's starting view: a seeded training view that shows the subject, or the nearest to it."""

from __future__ import annotations

import numpy as np
import torch

from capframe.evaluate.oracle import start_view
from capframe.geometry import look_at
from capframe.scene import Camera

K = np.array([[50.0, 0, 32], [0, 50.0, 24], [0, 0, 1]])
UP = torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64)


def _camera(eye, target, name) -> Camera:
    return Camera(
        look_at(torch.tensor(eye, dtype=torch.float64), torch.tensor(target, dtype=torch.float64), UP).numpy(),
        K,
        64,
        48,
        name=name,
    )


def test_start_view_is_a_seeded_view_that_shows_the_point():
    cameras = [_camera([5, 0, 0], [0, 0, 0], "a"), _camera([0, 5, 0], [0, 0, 0], "b"), _camera([5, 0, 0], [10, 0, 0], "away")]
    picks = {start_view(cameras, np.zeros(3), seed).name for seed in range(20)}
    assert picks == {"a", "b"}
    assert start_view(cameras, np.zeros(3), 7).name == start_view(cameras, np.zeros(3), 7).name


def test_start_view_falls_back_to_the_camera_facing_the_point_most_directly():
    # the point is outside every frame: 60 deg off the first camera's axis, 120 deg off the second's
    point = np.array([0.0, 0.0, 0.0])
    cameras = [
        _camera([5, 0, 0], [5 - np.cos(np.radians(60)), np.sin(np.radians(60)), 0], "sideways"),
        _camera([5, 0, 0], [6, 0, 0], "behind"),
    ]
    assert start_view(cameras, point, 0).name == "sideways"
