"""Robustness to the statistics of captured Gaussians (issue 19, item 4): opacities near 0 and 1,
scales from 1e-5 to 1e2 of the scene scale, SH degree 3 and floaters far outside the scene. The
scene-scale estimates and the floater rule ignore the floaters; the renderer, the checker's
measurements and Refine stay finite."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from capframe.constraints import Constraints, SubjectConstraint
from capframe.geometry import look_at
from capframe.measure import ConstraintChecker, Subject
from capframe.refine import RefineConfig, refine_pose
from capframe.render import render
from capframe.scene import Camera, GaussianScene, scene_extent, scene_scale
from capframe.scene.stats import floater_mask, robust_centre, robust_radius
from capframe.translate.labels import labels_from_constraints

f64 = torch.float64
UP = np.array([0.0, 0.0, 1.0])
SUBJECT = 4000  # Gaussians of the subject: a 0.5 x 0.3 x 0.8 ellipsoid shell at (0, 0, 0.4)


def captured_like(floaters: float = 0.01, seed: int = 0, wild: bool = True) -> tuple[GaussianScene, int]:
    """A subject plus ``floaters`` (a fraction of its count) Gaussians 20-200 scene radii away, in
    clumps, as a capture leaves them. ``wild``: captured statistics on the subject too: half the
    opacities within 1e-3 of 0 or 1, scales log-uniform over 1e-5...1e2 of the subject's size
    (the large ones faint, as in trained scenes), SH degree 3 with random higher bands.

    Returns the float32 scene (subject first) and the subject's Gaussian count."""
    g = np.random.default_rng(seed)
    d = g.normal(size=(SUBJECT, 3))
    subject = d / np.linalg.norm(d, axis=1, keepdims=True) * [0.5, 0.3, 0.8] + [0.0, 0.0, 0.4]
    k = int(round(floaters * SUBJECT))
    clumps = g.normal(size=(max(1, k // 20), 3))
    clumps = clumps / np.linalg.norm(clumps, axis=1, keepdims=True) * g.uniform(20.0, 200.0, (len(clumps), 1))
    far = clumps[g.integers(len(clumps), size=k)] + g.normal(scale=0.05, size=(k, 3))
    giants = g.normal(scale=1.0, size=(40 if wild else 0, 3))
    means = np.concatenate([subject, far, giants])
    n = len(means)
    opacity = g.uniform(0.3, 0.95, n)
    scales = np.full((n, 3), 0.04) * g.uniform(0.5, 1.5, (n, 3))
    sh = np.zeros((n, 16, 3))
    sh[:, 0] = g.uniform(-1.5, 1.5, (n, 3))
    if wild:
        extreme = g.random(n) < 0.5
        opacity[extreme] = np.where(g.random(extreme.sum()) < 0.5, 1e-3, 1.0 - 1e-3)
        scales = 10.0 ** g.normal(-1.7, 0.4, (n, 1)) * np.where(g.random((n, 3)) < 0.2, 1e-3, 1.0)
        scales[g.permutation(n - len(giants))[: n // 100]] = 1e-5
        scales[n - len(giants) :] = 1e2
        opacity[n - len(giants) :] = 0.01
        sh[:, 1:] = g.normal(scale=0.3, size=(n, 15, 3))
    scene = GaussianScene.from_activated(
        torch.from_numpy(means),
        torch.from_numpy(g.normal(size=(n, 4))),
        torch.from_numpy(scales),
        torch.from_numpy(opacity),
        torch.from_numpy(sh),
    ).to(dtype=torch.float32)
    return scene, SUBJECT


def camera(eye=(2.4, 1.2, 1.0), target=(0.0, 0.0, 0.4), size=(64, 48)) -> Camera:
    T = look_at(torch.tensor(eye, dtype=f64), torch.tensor(target, dtype=f64), torch.from_numpy(UP))
    w, h = size
    return Camera(T.numpy(), np.array([[0.9 * w, 0, w / 2], [0, 0.9 * w, h / 2], [0, 0, 1]]), w, h)


@pytest.mark.parametrize("fraction", [0.01, 0.05])
def test_scale_estimates_ignore_far_floaters(fraction):
    clean, _ = captured_like(floaters=0.0, wild=False)
    dirty, _ = captured_like(floaters=fraction, wild=False)
    cams = [camera(eye=(2.5 * np.cos(a), 2.5 * np.sin(a), 1.0)) for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)]
    assert scene_extent(dirty.means) == pytest.approx(scene_extent(clean.means), rel=0.03 + fraction)
    assert scene_scale(cams, dirty.means) == pytest.approx(scene_scale(cams, clean.means), rel=0.02)
    assert robust_radius(dirty.means.numpy()) == pytest.approx(robust_radius(clean.means.numpy()), rel=0.03 + fraction)
    assert np.abs(robust_centre(dirty.means.numpy()) - robust_centre(clean.means.numpy())).max() < 0.02
    # A mean-based estimate is what these guard against: the floaters move it by metres.
    assert np.abs(dirty.means.double().mean(0).numpy() - clean.means.double().mean(0).numpy()).max() > 0.1


def test_floater_mask_keeps_the_subject_and_drops_far_and_detached_clumps():
    scene, n = captured_like(floaters=0.02, wild=False)
    means = scene.means.double().numpy()
    speck = np.array([[0.0, 0.0, 2.2]]) + np.random.default_rng(1).normal(scale=0.01, size=(30, 3))  # 1 m above the top
    keep = floater_mask(np.concatenate([means, speck]))
    assert keep[:n].mean() > 0.995
    assert not keep[n:].any()


def test_floater_mask_on_nothing_and_on_one_point():
    assert floater_mask(np.zeros((0, 3))).shape == (0,)
    assert floater_mask(np.ones((1, 3))).tolist() == [True]


def test_render_stays_finite_with_captured_statistics():
    scene, n = captured_like()
    assert scene.sh_degree == 3 and torch.isfinite(scene.log_scales).all()
    out = render(scene, camera(), background=(1.0, 1.0, 1.0), backend="torch")
    assert torch.isfinite(out.rgb).all() and torch.isfinite(out.alpha).all() and torch.isfinite(out.depth).all()
    assert float(out.alpha.min()) >= 0.0 and float(out.alpha.max()) <= 1.0 + 1e-5
    # The subject is still seen through the faint giants: its own render covers the middle.
    own = render(scene.subset(torch.arange(n)), camera(), backend="torch")
    assert float(own.alpha[18:30, 26:38].mean()) > 0.5


def test_checker_measures_a_captured_scene():
    scene, n = captured_like()
    centre = scene.means[:n].double().mean(0).numpy()
    subjects = {"statue": Subject(0, "statue", centre, 0.8, np.array([1.0, 0.0, 0.0]))}
    checker = ConstraintChecker(scene, subjects, {0: torch.arange(len(scene)) < n}, UP, backend="torch")
    report = checker.check(camera(), Constraints([SubjectConstraint("statue", region="center", shot="medium")]))
    for row in report.rows:
        assert row.measured is None or np.isfinite(np.asarray(row.measured, dtype=float)).all(), row
    assert report.row("visibility", "statue").satisfied


def test_refine_loss_and_pose_stay_finite_with_captured_statistics():
    scene, n = captured_like()
    centre = scene.means[:n].double().mean(0).numpy()
    constraints = Constraints([SubjectConstraint("statue", region="right", view="left")])
    labels = labels_from_constraints(constraints, {"statue": (np.arange(n), centre, np.array([1.0, 0.0, 0.0]))}, UP)
    result = refine_pose(scene, camera(), labels, 3.0, RefineConfig(iterations=120, long_side=48))
    assert np.isfinite(result.losses).all() and np.isfinite(result.trajectory).all()
    assert all(np.isfinite(v) for v in result.terms.values())
    assert result.losses.min() < result.losses[0]  # the gradient was finite and useful: the loss went down
