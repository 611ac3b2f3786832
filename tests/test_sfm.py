"""Structure from motion (capframe.scene.sfm): Sim(3) fitting, camera alignment, `capframe colmap`."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from conftest import make_camera
from PIL import Image

from capframe.cli import main
from capframe.errors import InputError
from capframe.evaluate.ground_truth import ground_truth_cameras
from capframe.scene import load_scene_dir
from capframe.scene.colmap import read_colmap
from capframe.scene.sfm import align_cameras, colmap_command, reconstruct, umeyama_sim3
from capframe.synth.generator import generate_scene


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random proper rotation (3, 3)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q * np.linalg.det(q)  # det(-q) = -det(q) in 3D: this makes det +1


@pytest.mark.parametrize("scale", [1e-2, 1.0, 1e4])
@pytest.mark.parametrize("planar", [False, True])
def test_umeyama_recovers_a_similarity(scale, planar):
    rng = np.random.default_rng(7)
    src = rng.normal(size=(20, 3)) + 1e4  # far from the origin: centring must keep the precision
    if planar:  # camera centres of an orbit lie in a plane, where a reflection fits as well
        src[:, 2] = 1e4
    R, t = random_rotation(rng), rng.normal(size=3) * 1e4
    s_fit, R_fit, t_fit = umeyama_sim3(src, scale * src @ R.T + t)
    assert s_fit == pytest.approx(scale, rel=1e-9)
    np.testing.assert_allclose(R_fit, R, atol=1e-9)
    np.testing.assert_allclose(t_fit, t, rtol=0, atol=1e-9 * (np.abs(t).max() + scale * 2e4))


def test_umeyama_returns_a_rotation_for_mirrored_points():
    rng = np.random.default_rng(3)
    src = rng.normal(size=(10, 3))
    s, R, t = umeyama_sim3(src, src * [1.0, 1.0, -1.0])
    assert np.linalg.det(R) == pytest.approx(1.0)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert s > 0


@pytest.mark.parametrize(
    "src, message",
    [
        (np.zeros((2, 3)), "at least 3"),
        (np.outer(np.arange(5.0), [1.0, 2.0, 3.0]), "one line"),
        (np.ones((4, 3)), "coincide"),
    ],
)
def test_umeyama_rejects_degenerate_points(src, message):
    with pytest.raises(InputError, match=message):
        umeyama_sim3(src, src)


@pytest.mark.parametrize("scale", [1e-2, 1e4])
def test_align_cameras_keeps_projections(scale):
    rng = np.random.default_rng(1)
    camera = make_camera(eye=(0.3, -0.5, -4.0))
    points = rng.normal(size=(50, 3)) * 0.5  # around the origin, in front of the camera
    R, t = random_rotation(rng), rng.normal(size=3) * 1e4
    (moved,) = align_cameras([camera], scale, R, t)

    def pixels(cam, X):
        x = X @ cam.R.T + cam.t
        assert (x[:, 2] > 0).all()
        return (x @ cam.K.T)[:, :2] / x[:, 2:]

    np.testing.assert_allclose(pixels(moved, scale * points @ R.T + t), pixels(camera, points), atol=1e-6)
    np.testing.assert_allclose(moved.center, scale * R @ camera.center + t, rtol=1e-12)


# --- end to end -------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def unposed_scene(tmp_path_factory):
    """A small synthetic tabletop orbit without poses, scaled and tilted so that the alignment
    has a non-trivial similarity to find."""
    return generate_scene(
        tmp_path_factory.mktemp("sfm") / "scene",
        seed=5,
        preset="tabletop",
        capture="orbit",
        views=14,
        resolution=(240, 180),
        density=0.5,
        poses=False,
        scale=50.0,
        tilt_deg=25.0,
    )


@pytest.fixture(scope="module")
def recovered(unposed_scene, tmp_path_factory):
    """``capframe colmap``'s output for the unposed scene (COLMAP's world, no Gaussians)."""
    out = tmp_path_factory.mktemp("recovered") / "out"
    assert main(["colmap", str(unposed_scene), "-o", str(out)]) == 0
    return out


def test_colmap_writes_cameras_only(recovered, capsys):
    assert sorted(p.name for p in recovered.iterdir()) == ["cameras.json", "colmap.json", "images", "scene.json", "sparse"]
    scene = load_scene_dir(recovered)
    assert len(scene.cameras) == 14 and scene.gaussians is None
    assert not list(recovered.parent.glob(".*"))  # no work folder left beside the output
    assert "aligned_to_ground_truth" not in json.loads((recovered / "colmap.json").read_text())


def test_align_truth_maps_recovered_poses_into_the_synthetic_world(unposed_scene, recovered, tmp_path, capsys):
    out = tmp_path / "aligned"
    assert main(["align-truth", str(recovered), "--truth", str(unposed_scene), "-o", str(out)]) == 0
    assert "rotation error mean" in capsys.readouterr().out
    record = json.loads((out / "colmap.json").read_text())
    assert record["aligned_to_ground_truth"] and record["images_registered"] == record["images_total"] == 14
    assert record["rotation_error_deg"]["max"] < 2.0
    assert record["position_error_rel"]["max"] < 0.02
    scene = load_scene_dir(out)  # a complete posed scene: Gaussians, labels, cameras, images
    assert scene.gaussians is not None and scene.gaussians.labels is not None
    assert scene.metadata.up is None and not scene.metadata.aligned
    assert all(os.path.islink(c.image_path) for c in scene.cameras)
    truth = {c.name: c for c in ground_truth_cameras(unposed_scene)}
    assert sorted(truth) == [c.name for c in scene.cameras]
    # Intrinsics are recovered too (one shared focal length, principal point at the centre).
    np.testing.assert_allclose(scene.cameras[0].K, truth[scene.cameras[0].name].K, rtol=0.02)
    assert (out / "ground_truth.json").read_bytes() == (unposed_scene / "ground_truth.json").read_bytes()
    # The model is moved by the same similarity as cameras.json: their cameras agree.
    for from_model, listed in zip(read_colmap(out / "sparse" / "0"), scene.cameras, strict=True):
        np.testing.assert_allclose(from_model.T_cw, listed.T_cw, atol=1e-9)


def test_reconstruct_is_repeatable(unposed_scene, tmp_path):
    a = reconstruct(unposed_scene / "images", tmp_path / "a")
    b = reconstruct(unposed_scene / "images", tmp_path / "b")
    assert (tmp_path / "a" / "sparse" / "0" / "images.bin").is_file()
    for ca, cb in zip(a.cameras, b.cameras, strict=True):
        np.testing.assert_array_equal(ca.T_cw, cb.T_cw)


# --- bad inputs -------------------------------------------------------------------------------------


def test_colmap_rejects_a_scene_without_images(tmp_path):
    (tmp_path / "scene" / "images").mkdir(parents=True)
    with pytest.raises(InputError, match="no images"):
        colmap_command(tmp_path / "scene", tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_colmap_says_how_few_views_registered(tmp_path, capsys):
    (tmp_path / "scene" / "images").mkdir(parents=True)
    for i in range(4):  # flat images: no features, nothing registers
        Image.new("RGB", (64, 48), (40 * i, 90, 90)).save(tmp_path / "scene" / "images" / f"{i}.png")
    assert main(["colmap", str(tmp_path / "scene"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "only 0 of 4 images registered (need at least 3)" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_align_truth_needs_a_synthetic_scene(recovered, tmp_path, capsys):
    (tmp_path / "plain").mkdir()
    assert main(["align-truth", str(recovered), "--truth", str(tmp_path / "plain"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "only a synthetic scene has a ground truth" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_align_truth_needs_colmap_output(unposed_scene, tmp_path, capsys):
    assert main(["align-truth", str(unposed_scene), "--truth", str(unposed_scene), "-o", str(tmp_path / "out")]) == 2
    assert "expected the output directory of capframe colmap" in capsys.readouterr().err


def test_colmap_refuses_a_non_empty_output(unposed_scene, tmp_path):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "keep.txt").write_text("x")
    with pytest.raises(InputError, match="already exists"):
        colmap_command(unposed_scene, tmp_path / "out")
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["keep.txt"]
