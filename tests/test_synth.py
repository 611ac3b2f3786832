"""Synthetic scenes: determinism, non-intersecting layouts, visible fronts, tilt, scale, errors."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import pytest
import torch

from capframe.errors import InputError
from capframe.geometry import camera_roll, look_at, view_direction
from capframe.render import render
from capframe.scene import Camera, load_scene_dir, read_colmap
from capframe.synth.gallery import gaussians_to_scene, object_camera
from capframe.synth.generator import build_scene, generate_scene, parse_resolution, synth_command
from capframe.synth.objects import CATALOG, build_object, catalog_names, lookup

F64 = dict(dtype=torch.float64)


def _files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


SMALL = dict(preset="tabletop", views=3, resolution=(64, 48), density=0.25)


def test_same_seed_gives_identical_files(tmp_path):
    a = generate_scene(tmp_path / "a", seed=11, **SMALL)
    b = generate_scene(tmp_path / "b", seed=11, **SMALL)
    files_a, files_b = _files(a), _files(b)
    expected = {
        "scene.ply",
        "cameras.json",
        "scene.json",
        "semantics.json",
        "labels.npy",
        "ground_truth.json",
        "sparse/0/cameras.bin",
        "sparse/0/images.bin",
        "sparse/0/points3D.bin",
    }
    assert expected <= set(files_a)
    assert sum(name.startswith("images/") and name.endswith(".png") for name in files_a) == 3
    assert files_a.keys() == files_b.keys()
    assert [k for k in files_a if files_a[k] != files_b[k]] == []
    c = generate_scene(tmp_path / "c", seed=12, **SMALL)
    assert _files(c)["scene.ply"] != files_a["scene.ply"]
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())  # no temporary folders left


def test_scene_directory_follows_the_contract(tmp_path):
    root = generate_scene(tmp_path / "s", seed=3, **SMALL)
    scene = load_scene_dir(root)
    gt = json.loads((root / "ground_truth.json").read_text())
    assert len(scene.cameras) == 3 and all(c.image_path for c in scene.cameras)
    assert scene.metadata.aligned and np.allclose(scene.metadata.up, [0, 0, 1])
    labels = scene.gaussians.labels.numpy()
    assert len(labels) == gt["num_gaussians"] == len(scene.gaussians)
    for obj, sem in zip(gt["objects"], scene.semantics):
        assert {"id", "name", "aliases", "color", "center", "radius", "front", "label"} <= set(obj)
        assert sem.name == obj["name"] and sem.id == obj["id"] == obj["label"]
        start, end = obj["gaussians"]
        assert (labels[start:end] == obj["id"]).all() and (labels == obj["id"]).sum() == end - start
        assert (obj["front"] is None) == CATALOG[obj["name"]].symmetric
    assert (labels == -1).sum() > 0
    colmap = read_colmap(root / "sparse" / "0")
    for a, b in zip(colmap, scene.cameras):
        assert a.name == b.name and np.allclose(a.T_cw, b.T_cw, atol=1e-9) and np.allclose(a.K, b.K)
    distances = [np.linalg.norm(c.center - np.asarray(gt["center"])) for c in scene.cameras]
    assert gt["scale"] == pytest.approx(float(np.median(distances)), rel=1e-6)


def test_unposed_scene_has_images_but_no_cameras(tmp_path):
    root = generate_scene(tmp_path / "s", seed=3, poses=False, **SMALL)
    assert not (root / "cameras.json").exists() and not (root / "sparse").exists()
    assert len(list((root / "images").glob("*.png"))) == 3
    meta = json.loads((root / "scene.json").read_text())
    assert meta["up"] is None and meta["aligned"] is False
    assert len(json.loads((root / "ground_truth.json").read_text())["cameras"]) == 3


def test_scene_without_images_is_the_same_scene_minus_its_photos(tmp_path):
    full = _files(generate_scene(tmp_path / "a", seed=3, **SMALL))
    root = generate_scene(tmp_path / "b", seed=3, images=False, **SMALL)
    bare = _files(root)
    assert not (root / "images").exists() and not any(name.startswith("images/") for name in bare)
    for name in ("scene.ply", "labels.npy", "semantics.json", "ground_truth.json", "scene.json"):
        assert bare[name] == full[name], name
    with_images, without = load_scene_dir(tmp_path / "a").cameras, load_scene_dir(root).cameras
    assert all(c.image_path is None for c in without)
    for a, b in zip(with_images, without):
        assert a.name == b.name and np.array_equal(a.T_cw, b.T_cw) and np.array_equal(a.K, b.K)
    with pytest.raises(InputError, match="without poses needs its images"):
        generate_scene(tmp_path / "c", seed=3, images=False, poses=False, **SMALL)


def _box_contains(box: dict, points: np.ndarray, shrink: float = 0.0) -> np.ndarray:
    local = (points - np.asarray(box["center"])) @ np.asarray(box["axes"]).T
    return (np.abs(local) <= np.asarray(box["half_extents"]) - shrink).all(1)


@pytest.mark.parametrize(
    "preset,capture,seed", [("tabletop", None, 5), ("room", "forward", 6), ("room", "orbit", 7), ("outdoor", "walkthrough", 8)]
)
def test_objects_do_not_intersect(preset, capture, seed):
    scene = build_scene(seed=seed, preset=preset, capture=capture, views=8, density=0.2, tilt_deg=20.0)
    gt = scene.ground_truth
    means = scene.gaussians.means.double().numpy()
    labels = scene.gaussians.labels.numpy()
    assert len(gt["objects"]) >= 2
    up = np.asarray(gt["up"])
    for a in gt["objects"]:
        inside_own = _box_contains(a["box"], means[labels == a["id"]])
        assert inside_own.mean() > 0.99
        for b in gt["objects"]:
            if a is not b:
                assert not _box_contains(b["box"], means[labels == a["id"]]).any(), (a["name"], b["name"])
        # every object stands on the ground: its lowest Gaussians are at the base height
        heights = (means[labels == a["id"]] - np.asarray(a["base"])) @ up
        assert abs(heights.min()) < 0.05 * a["height"]
    for cam in scene.cameras:  # no camera inside an object
        for obj in gt["objects"]:
            assert not _box_contains(obj["box"], cam.center[None]).any()


def _front_share(scene, feature: torch.Tensor, camera: Camera, subset=None) -> float:
    out = render(scene, camera, extra=feature[:, None], subset=subset, backend="torch")
    return float(out.extra.sum() / out.alpha.sum().clamp_min(1e-9))


@pytest.mark.parametrize("name", sorted(n for n, s in CATALOG.items() if not s.symmetric))
def test_front_feature_faces_the_view_angle_convention(name):
    """A camera at azimuth 0 (DESIGN §3, view_direction) sees the front feature; one behind does not."""
    obj = build_object(name, seed=2, density=0.4)
    scene = gaussians_to_scene(obj.gaussians)
    feature = torch.from_numpy(obj.gaussians.front_feature.astype(np.float32))
    assert feature.sum() > 0
    front = _front_share(scene, feature, object_camera(obj, 0.0, 15.0, size=(64, 48)))
    back = _front_share(scene, feature, object_camera(obj, 180.0, 15.0, size=(64, 48)))
    assert front > 0.2 and back < 0.3 * front, (front, back)


def test_symmetric_objects_have_no_front_feature():
    for name, spec in CATALOG.items():
        if spec.symmetric:
            assert not build_object(name, seed=0, density=0.2).gaussians.front_feature.any(), name


def test_tilted_scene_fronts_up_and_upright_views():
    tilt = 33.0
    scene = build_scene(
        seed=21,
        preset="room",
        objects=["television", "armchair", "toy car", "vase"],
        views=6,
        density=0.3,
        tilt_deg=tilt,
        resolution=(64, 48),
    )
    gt = scene.ground_truth
    up = np.asarray(gt["up"])
    assert math.degrees(math.acos(np.clip(up[2], -1, 1))) == pytest.approx(tilt, abs=1e-6)
    assert np.abs(up).max() < 0.99  # not an axis
    assert np.allclose(up, np.asarray(gt["world_rotation"]) @ [0, 0, 1])
    assert scene.meta.up is None and not scene.meta.aligned
    up_t = torch.from_numpy(up)
    for cam in scene.cameras:
        T = torch.from_numpy(cam.T_cw)
        assert abs(math.degrees(float(camera_roll(T, up_t)))) < 3.0
        assert float(T[1, :3] @ up_t) < -0.5  # image "down" points against up: an upright photo
    # In the rendered training view, the floor fills the bottom of the frame, not the top.
    cam = scene.cameras[0]
    floor = (scene.gaussians.labels == -1) & (torch.abs(scene.gaussians.means.double() @ up_t) < 1e-3)
    mask = render(scene.gaussians, cam, extra=floor.float()[:, None], backend="torch").extra[..., 0]
    assert mask[:12].mean() < 0.1 and mask[-16:].mean() > 0.3
    # Fronts are world directions perpendicular to up, and the view-angle convention holds in the world.
    features = torch.zeros(len(scene.gaussians))
    for ranges in gt["front_feature"].values():
        for a, b in ranges:
            features[a:b] = 1.0
    for obj in gt["objects"]:
        if obj["front"] is None:
            continue
        front = np.asarray(obj["front"])
        assert abs(front @ up) < 1e-9 and np.linalg.norm(front) == pytest.approx(1.0)
        centre = torch.tensor(obj["center"], **F64)
        subset = scene.gaussians.labels == obj["id"]
        shares = []
        for azimuth in (0.0, 180.0):
            d = view_direction(
                torch.tensor(math.radians(azimuth), **F64), torch.tensor(math.radians(15.0), **F64), torch.from_numpy(front), up_t
            )
            T = look_at(centre + 3.0 * obj["radius"] * d, centre, up_t)
            camera = Camera(T.numpy(), np.array([[60.0, 0, 32], [0, 60.0, 24], [0, 0, 1]]), 64, 48)
            shares.append(_front_share(scene.gaussians, features, camera, subset))
        assert shares[0] > 0.2 and shares[1] < 0.3 * shares[0], (obj["name"], shares)


def test_scale_multiplies_lengths_exactly():
    kw = dict(seed=9, preset="outdoor", views=5, density=0.2, tilt_deg=12.0)
    a, b = build_scene(scale=1.0, **kw), build_scene(scale=7.5, **kw)
    ga, gb = a.gaussians, b.gaussians
    assert torch.allclose(gb.means.double(), 7.5 * ga.means.double(), rtol=1e-6, atol=1e-5)
    assert torch.allclose(gb.scales.double(), 7.5 * ga.scales.double(), rtol=1e-5)
    assert torch.equal(ga.quats, gb.quats) and torch.equal(ga.sh, gb.sh) and torch.equal(ga.labels, gb.labels)
    for ca, cb in zip(a.cameras, b.cameras):
        assert np.allclose(cb.center, 7.5 * ca.center, rtol=1e-12) and np.allclose(ca.R, cb.R, atol=1e-12)
    ta, tb = a.ground_truth, b.ground_truth
    assert tb["scale"] == pytest.approx(7.5 * ta["scale"], rel=1e-9)
    assert np.allclose(ta["up"], tb["up"])
    for oa, ob in zip(ta["objects"], tb["objects"]):
        assert np.allclose(ob["center"], 7.5 * np.asarray(oa["center"]), rtol=1e-9)
        assert ob["radius"] == pytest.approx(7.5 * oa["radius"], rel=1e-9)
        assert (oa["front"] is None and ob["front"] is None) or np.allclose(ob["front"], oa["front"])


def test_a_tabletop_records_its_table_top_and_the_floor_under_it():
    """The ground truth's ``table`` (evaluation only) is where the generator put the top and the
    floor, in a tilted, scaled world: every unlabelled Gaussian at the top's height lies over the
    top's box, and those lowest lie at the floor height; other presets record no table."""
    from capframe.evaluate.ground_truth import parse_ground_truth

    scene = build_scene(seed=4, preset="tabletop", views=4, density=0.2, tilt_deg=15.0, scale=3.0)
    truth = parse_ground_truth(json.loads(json.dumps(scene.ground_truth, default=lambda a: np.asarray(a).tolist())))
    table = truth.table
    means = scene.gaussians.means.double().numpy()[scene.gaussians.labels.numpy() < 0]
    heights = means @ truth.up
    on_top = means[np.abs(heights - table.top_height) < 1e-4]
    assert table.top_height == pytest.approx(0.0, abs=1e-9) and len(on_top) > 100
    assert all(table.over(p) for p in on_top)
    local = (on_top - table.box.center) @ table.box.axes[:2].T
    np.testing.assert_allclose(np.abs(local).max(0), table.box.half_extents[:2], rtol=0.05)
    assert heights.min() == pytest.approx(table.floor_height, abs=1e-4)
    assert build_scene(seed=4, preset="outdoor", views=4, density=0.2).ground_truth.get("table") is None


def _synth_args(tmp_path, **overrides) -> argparse.Namespace:
    """`capframe synth` arguments as the command line parses them, with ``overrides``."""
    from capframe.cli import build_parser

    args = build_parser().parse_args(
        [
            "synth",
            str(tmp_path / "s"),
            "--seed",
            "0",
            "--preset",
            "tabletop",
            "--views",
            "3",
            "--resolution",
            "64x48",
            "--density",
            "0.2",
        ]
    )
    for key, value in overrides.items():
        setattr(args, key, value)
    return args


def test_unknown_object_names_list_the_catalog(tmp_path):
    with pytest.raises(InputError) as err:
        synth_command(_synth_args(tmp_path, objects="mug, tedy bear"))
    message = str(err.value)
    assert "'tedy bear'" in message and "did you mean 'teddy bear'" in message
    assert all(name in message for name in catalog_names())
    assert not (tmp_path / "s").exists()
    with pytest.raises(InputError, match="listed twice"):
        synth_command(_synth_args(tmp_path, objects="mug,cup"))


def test_synth_command_and_aliases(tmp_path, capsys):
    synth_command(_synth_args(tmp_path, objects="Teddy, coffee mug", resolution="48x32", no_poses=True))
    gt = json.loads((tmp_path / "s" / "ground_truth.json").read_text())
    assert [o["name"] for o in gt["objects"]] == ["teddy bear", "mug"]
    assert gt["cameras"][0]["width"] == 48 and "teddy bear" in capsys.readouterr().out
    assert lookup("fridge").name == "refrigerator" and lookup("TV").name == "television"


@pytest.mark.parametrize("text", ["320", "320x", "ax240", "0x10", "320x240x3"])
def test_bad_resolution(text):
    with pytest.raises(InputError, match="resolution"):
        parse_resolution(text)


@pytest.mark.parametrize(
    "bad",
    [
        dict(views=0),
        dict(scale=-1.0),
        dict(scale=float("nan")),
        dict(preset="moon"),
        dict(capture="drone"),
        dict(density=0.0),
        dict(seed=-3),
        dict(tilt_deg=120.0),
    ],
)
def test_bad_arguments(bad):
    kwargs = dict(seed=0, preset="tabletop", views=2) | bad
    with pytest.raises(InputError):
        build_scene(**kwargs)


SUITES = Path(__file__).resolve().parents[1] / "config" / "suites"


def test_suites_are_valid_and_shaped_like_the_benchmark():
    from capframe.synth.suite import load_suite

    name, default = load_suite(SUITES / "default.yaml")
    assert name == "default" and len(default) == 4 and sum(s.instructions for s in default) == 12
    assert all(s.resolution == (320, 240) and s.views <= 24 for s in default)
    name, full = load_suite(SUITES / "full.yaml")
    assert name == "full" and len(full) == 38 and sum(s.instructions for s in full) == 135
    groups = {g: sum(s.group == g for s in full) for g in {s.group for s in full}}
    assert groups == {"mipnerf360": 5, "deepblending": 13, "tanks": 4, "lerf": 4, "dl3dv": 12}
    assert min(s.views for s in full) == 12 and max(s.views for s in full) == 411
    assert all(s.instructions in (3, 4) for s in full)
    assert any(not s.poses for s in full) and any(s.tilt != 0 for s in full)
    assert {s.preset for s in full} == {"tabletop", "room", "outdoor"} and {s.capture for s in full} == {
        "orbit",
        "forward",
        "walkthrough",
    }
    assert len({s.resolution for s in full}) > 5
    assert len({s.id for s in full}) == 38 and len({s.seed for s in full}) == 38


def test_suite_errors_name_the_scene(tmp_path):
    from capframe.synth.suite import load_suite

    bad = tmp_path / "bad.yaml"
    bad.write_text(
        "suite: x\nscenes:\n  - {id: a, group: g, seed: 1, preset: room, capture: orbit, objects: [sofa, chiar],\n"
        "     views: 3, scale: 1, tilt: 0, poses: true, resolution: 64x48, density: 1, instructions: 3}\n"
    )
    with pytest.raises(InputError, match=r"scene 0 \('a'\).*did you mean 'chair'"):
        load_suite(bad)
    bad.write_text("suite: x\nscenes:\n  - {id: a, group: g, seed: 1, preset: room, capture: orbit, views: 3}\n")
    with pytest.raises(InputError, match="missing keys"):
        load_suite(bad)
