"""Scene directory contract: load_scene_dir and import_scene."""

from __future__ import annotations

import builtins
import io
import json
import os

import numpy as np
import pytest
import torch
from _scene_helpers import (
    centred,
    inria_cameras_entries,
    random_cameras,
    random_inria_columns,
    random_scene,
    touch_images,
    write_ply_by_hand,
)

from capframe.cli import main
from capframe.errors import InputError
from capframe.scene import (
    SceneMeta,
    SemanticObject,
    import_scene,
    load_scene_dir,
    read_cameras_json,
    read_colmap,
    read_ply,
    write_cameras_json,
    write_colmap,
    write_ply,
)
from capframe.scene.directory import write_scene_meta, write_semantics

OBJECTS = [
    SemanticObject(id=0, name="teddy bear", aliases=["bear"], symmetric=False, front=np.array([0.0, 2.0, 0.0])),
    SemanticObject(id=3, name="vase", symmetric=True),
]


def make_scene_dir(root, n=30):
    """A complete scene directory, including a ground_truth.json the loader must never read."""
    scene, cameras = random_scene(n=n, degree=1), random_cameras(4)
    write_ply(scene, root / "scene.ply")
    write_cameras_json(cameras, root / "cameras.json")
    touch_images(root / "images", cameras)
    write_scene_meta(SceneMeta(up=np.array([0.0, 0.0, 3.0]), aligned=True), root / "scene.json")
    labels = np.where(np.arange(n) % 3 == 0, 0, np.where(np.arange(n) % 3 == 1, 3, -1))
    write_semantics(OBJECTS, labels, root)
    (root / "ground_truth.json").write_text("{ this is not JSON and must not be read")
    return scene, cameras, labels


def test_load_full_scene_dir_never_opens_ground_truth(tmp_path, monkeypatch):
    scene, cameras, labels = make_scene_dir(tmp_path)
    opened = []

    def spy(real):
        def wrapper(file, *args, **kwargs):
            opened.append(os.fspath(file) if not isinstance(file, int) else file)
            return real(file, *args, **kwargs)

        return wrapper

    monkeypatch.setattr(builtins, "open", spy(builtins.open))
    monkeypatch.setattr(io, "open", spy(io.open))
    loaded = load_scene_dir(tmp_path)
    monkeypatch.undo()

    assert not [f for f in opened if str(f).endswith("ground_truth.json")]
    assert any(str(f).endswith("labels.npy") for f in opened)  # the spy does see the loader's reads
    assert torch.equal(loaded.gaussians.means, scene.means)
    assert loaded.gaussians.labels.dtype == torch.int64
    assert torch.equal(loaded.gaussians.labels, torch.from_numpy(labels))
    assert [c.name for c in loaded.cameras] == [c.name for c in cameras]
    assert loaded.cameras[0].image_path == str(tmp_path / "images" / "view_000.png")
    assert loaded.images_dir == tmp_path / "images"
    np.testing.assert_allclose(loaded.metadata.up, [0, 0, 1])
    assert loaded.metadata.aligned is True
    bear, vase = loaded.semantics
    assert (bear.name, bear.aliases, bear.symmetric) == ("teddy bear", ["bear"], False)
    np.testing.assert_allclose(bear.front, [0, 1, 0])
    assert vase.front is None and vase.symmetric


def test_labels_length_mismatch_names_labels_npy(tmp_path):
    make_scene_dir(tmp_path)
    np.save(tmp_path / "labels.npy", np.zeros(7, np.int32))
    with pytest.raises(InputError, match=r"labels\.npy: has 7 labels but scene\.ply has 30 Gaussians") as info:
        load_scene_dir(tmp_path)
    assert str(tmp_path / "labels.npy") in str(info.value)


def test_unknown_label_id_and_half_a_sidecar(tmp_path):
    make_scene_dir(tmp_path)
    np.save(tmp_path / "labels.npy", np.full(30, 5, np.int32))
    with pytest.raises(InputError, match=r"label ids \[5\] are not in semantics.json"):
        load_scene_dir(tmp_path)
    (tmp_path / "labels.npy").unlink()
    with pytest.raises(InputError, match="has semantics.json but no labels.npy"):
        load_scene_dir(tmp_path)


def test_cameras_only_loading_skips_the_ply(tmp_path):
    make_scene_dir(tmp_path)
    (tmp_path / "scene.ply").write_bytes(b"garbage")  # not read
    loaded = load_scene_dir(tmp_path, load_gaussians=False)
    assert loaded.gaussians is None and len(loaded.cameras) == 4


def test_camera_sources_in_order(tmp_path):
    cameras = random_cameras(3)
    write_ply(random_scene(n=5), tmp_path / "scene.ply")
    write_colmap(cameras, tmp_path / "sparse" / "0")
    loaded = load_scene_dir(tmp_path)
    assert [c.name for c in loaded.cameras] == [c.name for c in cameras]
    assert loaded.metadata.up is None and loaded.semantics is None
    write_cameras_json(cameras[:1], tmp_path / "cameras.json")  # cameras.json wins over sparse/0
    assert len(load_scene_dir(tmp_path).cameras) == 1


def test_bad_scene_json_and_empty_folder(tmp_path):
    with pytest.raises(InputError, match="not a scene directory"):
        load_scene_dir(tmp_path)
    make_scene_dir(tmp_path)
    (tmp_path / "scene.json").write_text(json.dumps({"format": 2}))
    with pytest.raises(InputError, match="scene.json: 'format' is 2"):
        load_scene_dir(tmp_path)


def make_inria_output(root, dataset):
    """A reference-trainer output folder: two iterations, cameras.json, cfg_args -> dataset."""
    for iteration, seed in ((7000, 1), (30000, 2)):
        folder = root / "point_cloud" / f"iteration_{iteration}"
        folder.mkdir(parents=True)
        write_ply_by_hand(folder / "point_cloud.ply", random_inria_columns(25, 3, seed=seed))
    cameras = random_cameras(3)
    (root / "cameras.json").write_text(json.dumps(inria_cameras_entries(cameras)))
    touch_images(dataset / "images", cameras, suffix=".JPG")
    (root / "cfg_args").write_text(
        f"Namespace(data_device='cuda', eval=False, images='images', model_path='{root}', resolution=-1, "
        f"sh_degree=3, source_path='{dataset}', white_background=False)"
    )
    return cameras


def test_import_inria_output(tmp_path):
    cameras = make_inria_output(tmp_path / "output", tmp_path / "dataset")
    dst = import_scene(tmp_path / "output", tmp_path / "scene")
    # The PLY is validated and rewritten; an Inria file comes out byte for byte the same.
    latest = tmp_path / "output" / "point_cloud" / "iteration_30000" / "point_cloud.ply"
    assert (dst / "scene.ply").read_bytes() == latest.read_bytes()
    assert json.loads((dst / "scene.json").read_text()) == {"format": 1, "up": None, "aligned": False}
    link = dst / "images" / "view_001.JPG"
    assert link.is_symlink() and link.resolve() == (tmp_path / "dataset" / "images" / "view_001.JPG").resolve()
    loaded = load_scene_dir(dst)
    for a, b in zip(loaded.cameras, centred(cameras)):
        np.testing.assert_allclose(a.T_cw, b.T_cw, atol=1e-9)
        np.testing.assert_allclose(a.K, b.K, atol=1e-12)
    assert loaded.cameras[1].image_path == str(link)
    assert len(loaded.gaussians) == 25


def test_import_colmap_dataset_with_and_without_ply(tmp_path):
    src = tmp_path / "colmap"
    cameras = random_cameras(4, seed=9)
    touch_images(src / "images", cameras)
    write_colmap(cameras, src / "sparse" / "0")
    write_ply(random_scene(n=12, degree=0), tmp_path / "trained.ply")

    dst = import_scene(src, tmp_path / "with_ply", copy_images=True, ply=tmp_path / "trained.ply")
    copied = dst / "images" / "view_002.png"
    assert copied.is_file() and not copied.is_symlink() and copied.read_bytes() == b"image view_002"
    assert (dst / "sparse" / "0" / "images.bin").is_file()
    assert torch.equal(read_ply(dst / "scene.ply").sh, read_ply(tmp_path / "trained.ply").sh)
    for a, b in zip(read_cameras_json(dst / "cameras.json"), read_colmap(src / "sparse" / "0")):
        np.testing.assert_allclose(a.T_cw, b.T_cw, atol=1e-12)
        np.testing.assert_allclose(a.K, b.K, atol=0)

    cameras_only = import_scene(src, tmp_path / "cameras_only")
    assert not (cameras_only / "scene.ply").exists()
    loaded = load_scene_dir(cameras_only)
    assert loaded.gaussians is None and len(loaded.cameras) == 4


def test_import_errors(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="matches no importable layout; looked for an Inria 3DGS output"):
        import_scene(tmp_path / "empty", tmp_path / "dst")
    assert not (tmp_path / "dst").exists()
    src = tmp_path / "colmap"
    cameras = random_cameras(2)
    touch_images(src / "images", cameras[:1])  # the second camera's image is missing
    write_colmap(cameras, src / "sparse" / "0")
    with pytest.raises(InputError, match=r"no image found for cameras \['view_001'\]"):
        import_scene(src, tmp_path / "dst")
    assert not (tmp_path / "dst").exists() and not list(tmp_path.glob(".dst.*"))  # nothing half-written
    touch_images(src / "images", cameras)
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "file").write_text("x")
    with pytest.raises(InputError, match="already exists and is not an empty folder"):
        import_scene(src, tmp_path / "taken")


def test_cli_import(tmp_path, capsys):
    make_inria_output(tmp_path / "output", tmp_path / "dataset")
    assert main(["import", str(tmp_path / "output"), str(tmp_path / "scene")]) == 0
    assert (tmp_path / "scene" / "cameras.json").is_file()
    assert main(["import", str(tmp_path / "nowhere"), str(tmp_path / "x")]) == 2
    assert "nowhere: source folder or file not found" in capsys.readouterr().err
