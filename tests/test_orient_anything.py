"""Orient Anything: both released checkpoint layouts (722 and 902 outputs) loaded from tiny
random-weight `.pt` files with transformers-4 key names, decoding, one-line loader errors, and
the conversion of an image estimate into a world front, checked on cameras and synthetic
renders whose true front is known."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import torch
from _model_helpers import write_tiny_models
from _synth_helpers import aim_camera, build_scene, obj

from capframe.backends import BackendContext, Backends, read_models_config
from capframe.backends.orient_anything import (
    LAYOUTS,
    OrientAnything,
    OrientAnythingOrientation,
    OrientEstimate,
    circular_mean,
    decode,
    subject_crop,
    subject_direction,
    world_front,
)
from capframe.backends.tiny import V4_NAMES
from capframe.cli import main
from capframe.errors import InputError
from capframe.geometry import view_angles
from capframe.scene import SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta
from capframe.translate.instruction import ParsedSubject


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    return write_tiny_models(tmp_path_factory.mktemp("models"))


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    root = tmp_path_factory.mktemp("orient") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root, gt


def settings(configs, width: int):
    return read_models_config(configs[f"oa{width}"]).settings("orient-anything")


@pytest.mark.parametrize("width", [722, 902])
def test_both_layouts_load_with_their_transformers4_keys_renamed(configs, width):
    s = settings(configs, width)
    saved = torch.load(s.weights, weights_only=True)
    assert any(old in key for key in saved for old in V4_NAMES.values())  # the released naming
    model = OrientAnything(s)
    loaded = model.net.state_dict()
    for key, value in saved.items():
        for new, old in V4_NAMES.items():
            key = key.replace(old, new)
        assert torch.equal(loaded[key], value), key
    crops = [np.full((30, 20, 3), 200, dtype=np.uint8), np.zeros((40, 40, 3), dtype=np.uint8)]
    assert model.logits(model.pixel_values(crops)).shape == (2, width)
    for estimate in model.estimate(crops):
        assert 0 <= estimate.azimuth < 360 and -90 <= estimate.polar < 90 and 0 <= estimate.confidence <= 1


@pytest.mark.parametrize("width,rotation", [(722, -85.0), (902, -175.0)])
def test_decode_reads_each_layouts_bins(width, rotation):
    logits = torch.zeros(1, width)
    logits[0, 37] = logits[0, 360 + 100] = logits[0, 540 + 5] = 1.0
    logits[0, -2:] = torch.tensor([2.0, 0.0])
    [estimate] = decode(logits)
    assert (estimate.azimuth, estimate.polar, estimate.rotation) == (37.0, 10.0, rotation)
    assert estimate.confidence == pytest.approx(math.exp(2) / (math.exp(2) + 1))
    assert sorted(LAYOUTS) == [722, 902]


def rejected(s, match: str) -> None:
    with pytest.raises(InputError, match=match) as err:
        OrientAnything(s)
    assert "\n" not in str(err.value)


def test_loader_rejects_missing_files_wrong_layouts_and_mismatched_configs(configs, tmp_path):
    import dataclasses
    import shutil

    s = settings(configs, 902)
    rejected(dataclasses.replace(s, weights=str(tmp_path / "absent.pt")), "checkpoint not found")
    rejected(dataclasses.replace(s, config=str(tmp_path)), "no config.json in the DINOv2 config folder")
    rejected(dataclasses.replace(s, config=None), "give weights .* and config")
    (tmp_path / "text.pt").write_text("not a checkpoint")
    rejected(dataclasses.replace(s, weights=str(tmp_path / "text.pt")), "is not a PyTorch state dict")
    state = torch.load(s.weights, weights_only=True)

    def variant(name: str, change) -> str:
        path = tmp_path / name
        torch.save(change(dict(state)), path)
        return str(path)

    clip_like = variant("clip.pt", lambda st: {"text_projection.weight": torch.zeros(2, 2)})
    rejected(dataclasses.replace(s, weights=clip_like), "wrong checkpoint layout: no down_sampler.net2.0.weight")
    wide = variant("wide.pt", lambda st: st | {"down_sampler.net2.0.weight": torch.zeros(800, 902)})
    rejected(dataclasses.replace(s, weights=wide), "wrong checkpoint layout: 800 outputs; .* have \\[722, 902\\]")
    short = variant("short.pt", lambda st: {k: v for k, v in st.items() if "layer.1." not in k})
    rejected(dataclasses.replace(s, weights=short), "wrong checkpoint layout: [0-9]+ weights missing, 0 unexpected")
    bigger = tmp_path / "dinov2"
    shutil.copytree(s.config, bigger)
    config = json.loads((bigger / "config.json").read_text())
    (bigger / "config.json").write_text(json.dumps(config | {"hidden_size": 64}))
    rejected(
        dataclasses.replace(s, config=str(bigger)), "config.json and the weights disagree: .* is \\(1, 1, 32\\) in the weights"
    )


def mask_around(camera, point: np.ndarray, radius: int = 4) -> np.ndarray:
    """A disc mask centred on the pixel that images ``point``."""
    q = camera.R @ point + camera.t
    u, v = (camera.K @ (q / q[2]))[:2]
    rows, cols = np.mgrid[: camera.height, : camera.width]
    return (cols - math.floor(u)) ** 2 + (rows - math.floor(v)) ** 2 <= radius**2


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return math.degrees(math.acos(float(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1))))


def test_world_front_from_an_image_estimate_on_known_cameras(scene):
    """A camera at design azimuth phi around a subject with a known front sees it as Orient
    Anything's azimuth -phi; converting that estimate back through the camera (rolled, the
    subject off-centre, the world tilted) recovers the front."""
    _, gt = scene
    bear, up = obj(gt, "teddy bear"), np.asarray(gt["up"])
    front = np.asarray(bear["front"])
    for azimuth in (-150.0, -90.0, -30.0, 0.0, 45.0, 120.0, 180.0):
        for elevation in (-20.0, 0.0, 35.0, 70.0):
            for roll, point in ((0.0, (0.5, 0.5)), (25.0, (0.25, 0.7))):
                camera = aim_camera(gt, bear, azimuth=azimuth, elevation=elevation, distance=4.0, roll=roll, point=point)
                said = (-azimuth) % 360.0  # what the model reports for this view
                exact = (camera.center - np.asarray(bear["center"])) / np.linalg.norm(camera.center - bear["center"])
                assert angle_deg(world_front(said, exact, up), front) < 1e-6
                # The mask's centroid is the centre's pixel to half a pixel per axis (0.29 degrees of
                # ray at f = 140 px), which turns the horizontal direction up to 1 / cos(elevation) as much.
                direction = subject_direction(camera, mask_around(camera, np.asarray(bear["center"])))
                tolerance = 0.3 / math.cos(math.radians(elevation))
                assert angle_deg(world_front(said, direction, up), front) < tolerance, (azimuth, elevation, roll)
                logits = torch.zeros(1, 902)
                logits[0, round(said) % 360] = 1.0
                [estimate] = decode(logits)
                assert angle_deg(world_front(estimate.azimuth, direction, up), front) < 0.5 + tolerance
    overhead = aim_camera(gt, bear, azimuth=0.0, elevation=85.0, distance=4.0)
    assert world_front(0.0, subject_direction(overhead, mask_around(overhead, np.asarray(bear["center"]))), up) is None


def test_circular_mean_weights_fronts_and_gives_up_on_contradictions():
    up = np.array([0.0, 0.0, 1.0])
    turn = lambda deg: np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg)), 0.0])  # noqa: E731
    assert angle_deg(circular_mean([turn(10), turn(-10)], [0.7, 0.7]), turn(0)) < 1e-9
    assert angle_deg(circular_mean([turn(170), turn(-170)], [1.0, 1.0]), turn(180)) < 1e-9  # across the wrap
    assert angle_deg(circular_mean([turn(0), turn(90)], [3.0, 1.0]), turn(math.degrees(math.atan2(1, 3)))) < 1e-9
    assert circular_mean([turn(0), turn(180)], [1.0, 1.0]) is None and circular_mean([], []) is None
    assert abs(circular_mean([turn(30)], [0.9]) @ up) < 1e-12


def test_subject_crop_centres_the_subject_on_white():
    image = np.zeros((20, 30, 3), dtype=np.uint8)
    mask = np.zeros((20, 30), dtype=bool)
    mask[5:9, 10:20] = True
    crop = subject_crop(image, mask)
    assert crop.shape == (12, 12, 3)  # ceil(10 / 0.85)
    assert (crop[:4] == 255).all() and (crop[4:8, 1:11] == 0).all() and (crop[8:] == 255).all()
    assert subject_crop(image, np.zeros_like(mask)) is None


def test_backend_recovers_the_front_from_synthetic_renders(configs, scene, monkeypatch):
    """The backend on the oracle segmenter's masks of renders of a synthetic scene: the model
    replaced by what a perfect Orient Anything says in each view (the azimuth of that view's
    camera around the subject); one view disagrees with low confidence and is gated out."""
    root, gt = scene
    scene_dir = load_scene_dir(root)
    up = np.asarray(gt["up"])
    bear = obj(gt, "teddy bear")
    front, centre = np.asarray(bear["front"]), np.asarray(bear["center"])
    context = BackendContext(scene_dir, up, root / ".cache", read_models_config(configs["oa902"]))
    backends = Backends({"orient": "orient-anything"}, context)
    estimator = backends["orient"]
    assert isinstance(estimator, OrientAnythingOrientation) and estimator.needs_masks
    subject = ParsedSubject("the teddy bear", "teddy bear", "primary", symmetric=False, view="front")
    views = list(range(len(scene_dir.cameras)))
    masks = backends["segmenter"].segment(subject, views)
    said = []
    for k, v in enumerate(masks.views):
        C = scene_dir.cameras[v].center
        azimuth, _ = view_angles(torch.tensor(C), torch.tensor(centre), torch.tensor(front), torch.tensor(up))
        wrong = k == 0
        said.append(OrientEstimate((-math.degrees(float(azimuth)) + (90 if wrong else 0)) % 360, 0.0, 0.0, 0.3 if wrong else 0.9))

    def perfect(crops):
        assert len(crops) == len(said) and all(c.shape[0] == c.shape[1] and (c[0, 0] == 255).all() for c in crops)
        return said

    monkeypatch.setattr(estimator.model, "estimate", perfect)
    readings = estimator.view_fronts(masks)
    assert [r.front is None for r in readings] == [True] + [False] * (len(said) - 1)
    assert angle_deg(estimator.front(subject, views, masks), front) < 2.0
    with pytest.raises(InputError, match="needs the segmenter's masks of 'teddy bear'"):
        estimator.front(subject, views, None)


def test_orient_verb_segments_for_an_estimator_that_reads_masks(configs, scene, tmp_path):
    root, _ = scene
    common = ["--models", str(configs["oa722"]), "--cache", str(tmp_path / "cache")]
    text = "the teddy bear seen from its left"
    assert main(["retrieve", str(root), text, "-o", str(tmp_path / "retrieval.json"), *common]) == 0
    args = ["orient", str(root), "--retrieval", str(tmp_path / "retrieval.json"), "--orient", "orient-anything"]
    assert main([*args, "-o", str(tmp_path / "fronts.json"), *common]) == 0
    fronts = json.loads((tmp_path / "fronts.json").read_text())["fronts"]
    assert list(fronts) == ["teddy bear"]
    assert (
        main(["segment", str(root), "--retrieval", str(tmp_path / "retrieval.json"), "-o", str(tmp_path / "m.npz"), *common]) == 0
    )
    assert main([*args, "--masks", str(tmp_path / "m.npz"), "-o", str(tmp_path / "fronts2.json"), *common]) == 0
    # The same fronts; fronts2.json also records the masks it was made from (stage files' inputs, #21).
    segmented, given = (json.loads((tmp_path / name).read_text()) for name in ("fronts.json", "fronts2.json"))
    assert given["fronts"] == segmented["fronts"]
    assert set(segmented["inputs"]) == {"retrieval"} and set(given["inputs"]) == {"retrieval", "masks"}
