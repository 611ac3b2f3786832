"""Model-tier segmenters: GroundingDINO + SAM (``grounded-sam``) and a closed-set ONNX detector
with SAM or GrabCut masks (``detector``), loaded from a models config and run through the
command line and the pipeline.

Tiny random-weight GroundingDINO and SAM checkpoints are built and saved by fixtures (no
download); a tiny ONNX detector with fixed detections is built with ``onnx.helper``. The real
COCO detector (``shared/models/centernet_coco.onnx``) segments a synthetic television and
teddy bear for the association-precision test.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import torch
import yaml
from _synth_helpers import build_scene

from capframe.backends import BackendContext, Backends, read_models_config
from capframe.backends.detector import COCO_CLASSES, OnnxDetector, coco_class, letterbox
from capframe.backends.masks import depth_prior, fill_largest_contour, grabcut_box, resize_mask
from capframe.backends.sam import SamBoxes, sam_input_boxes
from capframe.backends.tiny import tiny_sam
from capframe.cli import main
from capframe.errors import InputError
from capframe.scene import SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta
from capframe.translate.instruction import ParsedSubject

pytest.importorskip("transformers")
pytest.importorskip("onnxruntime")

CENTERNET = Path(__file__).resolve().parents[2] / "shared" / "models" / "centernet_coco.onnx"
WORDS = ["[PAD]", "[UNK]", "[CLS]", "[SEP]", "[MASK]", ".", "a", "the", "teddy", "bear", "armchair", "vase", "red", "blue"]


@pytest.fixture(autouse=True)
def _offline(monkeypatch, tmp_path_factory):
    """No network, and no Hugging Face cache outside the test's folders."""
    monkeypatch.setenv("HF_HUB_OFFLINE", "1")
    monkeypatch.setenv("HF_HOME", str(tmp_path_factory.getbasetemp() / "hf-home"))


def save_tiny_grounding_dino(path: Path) -> Path:
    """A random-weight GroundingDINO (Swin + BERT, about 180k parameters) with its processor."""
    from transformers import (
        BertConfig,
        BertTokenizer,
        GroundingDinoConfig,
        GroundingDinoForObjectDetection,
        GroundingDinoImageProcessorPil,
        GroundingDinoProcessor,
        SwinConfig,
    )

    torch.manual_seed(0)
    backbone = SwinConfig(embed_dim=8, depths=[1, 1, 1, 1], num_heads=[1, 1, 1, 1], window_size=4, out_indices=[2, 3, 4])
    text = BertConfig(hidden_size=32, num_hidden_layers=1, num_attention_heads=2, intermediate_size=37, vocab_size=len(WORDS))
    config = GroundingDinoConfig(
        backbone_config=backbone,
        text_config=text,
        d_model=32,
        encoder_layers=1,
        decoder_layers=2,  # one decoder layer trips transformers' tied-weights check
        encoder_ffn_dim=32,
        decoder_ffn_dim=32,
        encoder_attention_heads=2,
        decoder_attention_heads=2,
        num_queries=10,
        encoder_n_points=2,
        decoder_n_points=2,
        max_text_len=32,
    )
    GroundingDinoForObjectDetection(config).save_pretrained(path)
    image_processor = GroundingDinoImageProcessorPil(size={"shortest_edge": 64, "longest_edge": 96})
    tokenizer = BertTokenizer(vocab={w: i for i, w in enumerate(WORDS)})
    GroundingDinoProcessor(image_processor=image_processor, tokenizer=tokenizer).save_pretrained(path)
    return path


def save_onnx_detector(path: Path, detections: np.ndarray, input_shape=(1, 3, 64, 64), width: int = 6) -> Path:
    """An ONNX "detector" whose ``detections`` output is the constant ``detections`` (N, width),
    with one image input of ``input_shape`` and a second, unused output (as CenterNet has)."""
    import onnx
    from onnx import TensorProto, helper, numpy_helper

    table = numpy_helper.from_array(detections[None].astype(np.float32), "table")
    nodes = [
        helper.make_node("Constant", [], ["detections"], value=table),
        helper.make_node("ReduceMean", ["images"], ["heat"], keepdims=1),
    ]
    graph = helper.make_graph(
        nodes,
        "fake_detector",
        [helper.make_tensor_value_info("images", TensorProto.FLOAT, list(input_shape))],
        [
            helper.make_tensor_value_info("heat", TensorProto.FLOAT, [1] * len(input_shape)),
            helper.make_tensor_value_info("detections", TensorProto.FLOAT, [1, len(detections), width]),
        ],
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
    model.ir_version = 8
    onnx.save(model, path)
    return path


@pytest.fixture(scope="module")
def weights(tmp_path_factory):
    root = tmp_path_factory.mktemp("weights")
    return {
        "grounding-dino": save_tiny_grounding_dino(root / "grounding-dino"),
        "sam": tiny_sam(root / "sam", whole_image=True),
        "sam-random": tiny_sam(root / "sam-random"),
    }


def write_models(path: Path, entries: dict) -> Path:
    path.write_text(
        yaml.safe_dump({name: {k: str(v) if isinstance(v, Path) else v for k, v in e.items()} for name, e in entries.items()})
    )
    return path


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("segmenters") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


@pytest.fixture(scope="module")
def retrieval(scene_dir, tmp_path_factory):
    """retrieval.json of an instruction on the teddy bear (oracle Retrieve)."""
    out = tmp_path_factory.mktemp("retrieve") / "retrieval.json"
    cache = out.parent / "cache"
    assert main(["retrieve", str(scene_dir), "the teddy bear on the right", "-o", str(out), "--cache", str(cache)]) == 0
    return out


# --- COCO names, letterbox, mask post-processing ------------------------------------------------------


def test_subject_names_map_to_coco_classes_and_an_unknown_one_names_the_closest():
    assert len(COCO_CLASSES) == 80 and COCO_CLASSES[62] == "tv" and COCO_CLASSES[77] == "teddy bear"
    for name in ("television", "tv", "TV", " Television  Set "):
        assert COCO_CLASSES[coco_class(name)] == "tv"
    assert COCO_CLASSES[coco_class("sofa")] == "couch"
    assert COCO_CLASSES[coco_class("mug")] == "cup"
    assert COCO_CLASSES[coco_class("teddy-bear")] == "teddy bear"
    with pytest.raises(InputError, match="subject 'floor lamp' is not a COCO class; the closest are ") as err:
        coco_class("floor lamp")
    assert "\n" not in str(err.value)


def test_letterbox_centres_the_image_and_its_mapping_inverts():
    image = np.zeros((120, 160, 3), dtype=np.uint8)
    image[30:90, 40:120] = 255  # a white box at x 40..120, y 30..90
    canvas, scale, (ox, oy) = letterbox(image, 64)
    assert canvas.shape == (64, 64, 3) and canvas.dtype == np.float32
    assert scale == pytest.approx(0.4) and (ox, oy) == (0.0, 8.0)
    ys, xs = np.nonzero(canvas[..., 0] > 127)
    assert (xs.min() - ox) / scale == pytest.approx(40, abs=3) and (ys.max() + 1 - oy) / scale == pytest.approx(90, abs=3)
    assert canvas[:8].max() == 0 and canvas[56:].max() == 0  # black bars above and below


def test_largest_contour_is_kept_and_filled():
    mask = np.zeros((40, 40), dtype=bool)
    mask[5:30, 5:30] = True
    mask[12:18, 12:18] = False  # a hole
    mask[34:37, 34:37] = True  # a speck
    filled = fill_largest_contour(mask)
    assert filled[5:30, 5:30].all() and not filled[34:37, 34:37].any()
    assert not fill_largest_contour(np.zeros((8, 8), dtype=bool)).any()
    assert resize_mask(filled, 20, 20).sum() == pytest.approx(filled.sum() / 4, rel=0.1)


def test_grabcut_separates_an_object_from_background_by_depth_and_colour():
    """A red disc at depth 2 standing on a grey floor that recedes from depth 1.5 to 6 and a
    far wall: the box is loose, the floor around the disc is at the disc's depth."""
    H, W = 96, 128
    yy, xx = np.mgrid[0:H, 0:W]
    depth = np.where(yy > 40, 1.5 + (H - yy) * 0.08, 8.0).astype(np.float32)
    disc = (xx - 64) ** 2 + (yy - 50) ** 2 < 15**2
    depth[disc] = 2.0
    depth[:6] = 0.0  # nothing rendered at the top
    rng = np.random.default_rng(0)
    image = np.clip(rng.normal(120, 10, (H, W, 3)), 0, 255).astype(np.uint8)
    image[disc] = (200, 30, 30)
    box = np.array([40.0, 28.0, 90.0, 75.0])
    labels = depth_prior(depth, box, focal=100.0)
    assert (labels[:, :40] == 0).all()  # cv2.GC_BGD outside the box
    mask = grabcut_box(image, depth, box, focal=100.0)
    iou = (mask & disc).sum() / (mask | disc).sum()
    assert iou > 0.9


def test_sam_boxes_map_to_its_input_frame_as_the_processor_maps_them(weights):
    from transformers import AutoProcessor

    processor = AutoProcessor.from_pretrained(weights["sam-random"], local_files_only=True)
    image = np.zeros((120, 160, 3), dtype=np.uint8)
    boxes = np.array([[10.0, 20.0, 90.0, 100.0], [0.0, 0.0, 160.0, 120.0]])
    inputs = processor(images=image, input_boxes=[boxes.tolist()], return_tensors="pt")
    ours = sam_input_boxes(boxes, inputs["original_sizes"][0].tolist(), inputs["reshaped_input_sizes"][0].tolist())
    assert torch.allclose(ours.float(), inputs["input_boxes"][0].float())


def test_sam_masks_are_image_sized_and_embeddings_are_computed_once_per_view(weights):
    sam = SamBoxes(_settings(weights["sam-random"]))
    images = {3: np.full((120, 160, 3), 90, dtype=np.uint8), 5: np.full((60, 80, 3), 200, dtype=np.uint8)}
    masks = sam.masks(images, {3: np.array([[10.0, 10.0, 100.0, 80.0]]), 5: np.array([[0.0, 0.0, 40.0, 30.0], [5, 5, 70, 50]])})
    assert masks[3].shape == (1, 120, 160) and masks[5].shape == (2, 60, 80) and masks[3].dtype == bool
    embedding = sam._embeddings[3][0]
    sam.masks(images, {3: np.array([[0.0, 0.0, 50.0, 50.0]])})
    assert sam._embeddings[3][0] is embedding


def _settings(weights_dir: Path, **extra):
    from capframe.backends import ModelSettings

    return ModelSettings(weights=str(weights_dir), **extra)


# --- the ONNX detector ---------------------------------------------------------------------------------


def test_onnx_detector_reads_nchw_letterboxes_and_maps_boxes_back(tmp_path):
    # 64 x 64 input; a 160 x 120 image becomes 64 x 48 at y offset 8 (scale 0.4).
    table = np.array(
        [
            [16.0, 20.0, 48.0, 44.0, 0.9, 77.0],  # teddy bear -> image box 40, 30, 120, 90
            [0.0, 8.0, 8.0, 16.0, 0.5, 77.0],  # a weaker teddy bear
            [0.0, 8.0, 8.0, 16.0, 0.95, 62.0],  # a tv
            [0.0, 8.0, 8.0, 16.0, 0.1, 77.0],  # below the threshold
        ]
    )
    path = save_onnx_detector(tmp_path / "det.onnx", table)
    detector = OnnxDetector(_settings(path, threads=1))
    assert (detector.layout, detector.size) == ("NCHW", 64)
    image = np.zeros((120, 160, 3), dtype=np.uint8)
    found = detector.detect(image)
    assert found[:, 4].tolist() == pytest.approx([0.95, 0.9, 0.5])
    assert detector.best_box(image, 77) == pytest.approx([40.0, 30.0, 120.0, 90.0])
    assert detector.best_box(image, 0) is None
    strict = OnnxDetector(_settings(path, threshold=0.92))
    assert strict.best_box(image, 77) is None


@pytest.mark.parametrize(
    ("input_shape", "width", "message"),
    [
        ((1, 64, 64), 6, r"input is \[\('images', \[1, 64, 64\]\)\]; expected one image"),
        ((1, 4, 64, 64), 6, "expected one image"),
        ((1, 3, 64, 32), 6, "expected one image"),
        ((1, 64, 64, 3), 5, r"has no \[1, N, 6\] output"),
    ],
)
def test_onnx_detector_rejects_a_wrong_layout_in_one_line(tmp_path, input_shape, width, message):
    path = save_onnx_detector(tmp_path / "det.onnx", np.zeros((2, width)), input_shape=input_shape, width=width)
    with pytest.raises(InputError, match=message) as err:
        OnnxDetector(_settings(path))
    assert str(path) in str(err.value) and "\n" not in str(err.value)


def test_detector_segmenter_masks_by_grabcut_and_associates_the_right_gaussians(scene_dir, tmp_path):
    """A fixed box around the teddy bear in one view (from its label render), GrabCut with the
    rendered depth, then the knn associator: the Gaussians found are the bear's."""
    scene = load_scene_dir(scene_dir)
    context = BackendContext(scene, np.asarray(scene.metadata.up), tmp_path / "cache")
    labels_map = Backends({}, context)["segmenter"].segment(ParsedSubject("teddy bear", "teddy bear"), [0]).masks[0]
    ys, xs = np.nonzero(labels_map)
    H, W = labels_map.shape  # the measurement resolution; the detector sees the full 160 x 120 render
    s = scene.cameras[0].width / W
    box = np.array([xs.min() - 3, ys.min() - 3, xs.max() + 4, ys.max() + 4]) * s  # a loose box
    size = 64
    scale = size / max(scene.cameras[0].width, scene.cameras[0].height)
    oy = (size - round(scene.cameras[0].height * scale)) // 2
    table = np.array([[*(box * scale + [0, oy, 0, oy]), 0.8, 77.0]])
    models = write_models(tmp_path / "models.yaml", {"detector": {"weights": save_onnx_detector(tmp_path / "d.onnx", table)}})
    context = BackendContext(scene, np.asarray(scene.metadata.up), tmp_path / "cache", read_models_config(models))
    backends = Backends({"segmenter": "detector", "associator": "knn"}, context)
    subject = ParsedSubject("teddy bear", "teddy bear")
    masks = backends["segmenter"].segment(subject, [0, 1])
    assert masks.masks.shape[1:] == (H, W) and masks.masks.any()
    found = backends["associator"].associate(subject, masks).gaussians
    bear = scene.gaussians.labels.numpy() == 0
    assert bear[found].mean() >= 0.9 and bear[found].sum() >= 0.2 * bear.sum()


def test_detector_segmenter_masks_by_sam_when_the_models_config_has_it(scene_dir, weights, tmp_path):
    table = np.array([[10.0, 20.0, 40.0, 44.0, 0.8, 77.0]])
    detector = save_onnx_detector(tmp_path / "d.onnx", table)
    models = write_models(tmp_path / "models.yaml", {"detector": {"weights": detector}, "sam": {"weights": weights["sam"]}})
    scene = load_scene_dir(scene_dir)
    context = BackendContext(scene, np.asarray(scene.metadata.up), tmp_path / "cache", read_models_config(models))
    segmenter = Backends({"segmenter": "detector"}, context)["segmenter"]
    assert segmenter.sam is not None
    masks = segmenter.segment(ParsedSubject("teddy bear", "teddy bear"), [0, 1])
    assert masks.views == [0, 1] and masks.masks.shape == (2, 120, 160) and masks.masks.all()  # the whole-image SAM


# --- grounded-sam through the models config, the CLI and the pipeline ------------------------------------


def test_grounded_sam_segments_and_associates_through_the_command_line(scene_dir, retrieval, weights, tmp_path):
    models = write_models(
        tmp_path / "models.yaml",
        {
            "grounding-dino": {"weights": weights["grounding-dino"], "threshold": 0.01, "batch_size": 2},
            "sam": {"weights": weights["sam"]},
        },
    )
    common = ["--segmenter", "grounded-sam", "--models", str(models), "--cache", str(tmp_path / "cache")]
    masks = tmp_path / "masks.npz"
    assert main(["segment", str(scene_dir), "--retrieval", str(retrieval), "-o", str(masks), *common]) == 0
    with np.load(masks) as data:
        assert data["subjects"].tolist() == ["teddy bear"]
        assert data["masks_0"].shape[1:] == (120, 160) and data["masks_0"].all()  # the whole-image SAM
        assert set(data["views_0"].tolist()) <= set(json.loads(retrieval.read_text())["top"])
    subjects = tmp_path / "subjects.json"
    args = ["associate", str(scene_dir), "--retrieval", str(retrieval), "--masks", str(masks), "-o", str(subjects)]
    assert main([*args, "--associator", "knn", *common]) == 0
    assert len(json.loads(subjects.read_text())["subjects"]["teddy bear"]["gaussians"]) > 0


def test_ground_runs_with_grounded_sam_and_oracle_roles_mixed(scene_dir, weights, tmp_path):
    models = write_models(
        tmp_path / "models.yaml",
        {"grounding-dino": {"weights": weights["grounding-dino"], "threshold": 0.01}, "sam": {"weights": weights["sam"]}},
    )
    out = tmp_path / "out"
    args = ["ground", str(scene_dir), "the teddy bear on the right", "-o", str(out), "--segmenter", "grounded-sam"]
    args += ["--associator", "knn", "--models", str(models), "--cache", str(tmp_path / "cache"), "--iterations", "60", "--json"]
    assert main(args) == 0
    result = json.loads((out / "result.json").read_text())
    assert result["options"]["backends"]["segmenter"] == "grounded-sam" and "segment_s" in result["timings"]


def test_a_backend_is_built_once_per_job(scene_dir, weights, tmp_path):
    models = write_models(
        tmp_path / "models.yaml", {"grounding-dino": {"weights": weights["grounding-dino"]}, "sam": {"weights": weights["sam"]}}
    )
    context = BackendContext(load_scene_dir(scene_dir), np.array([0.0, 0.0, 1.0]), tmp_path / "cache", read_models_config(models))
    backends = Backends({"segmenter": "grounded-sam"}, context)
    assert backends["segmenter"] is backends["segmenter"]


# --- loaders: one-line errors naming the file -----------------------------------------------------------


def _corrupt(src: Path, dst: Path, edit) -> Path:
    shutil.copytree(src, dst)
    edit(dst)
    return dst


def _drop_a_tensor(root: Path) -> None:
    from safetensors.torch import load_file, save_file

    tensors = load_file(root / "model.safetensors")
    del tensors[sorted(tensors)[0]]
    save_file(tensors, root / "model.safetensors", metadata={"format": "pt"})


def _widen_the_encoder(root: Path) -> None:
    config = json.loads((root / "config.json").read_text())
    config["vision_config"]["hidden_size"] = 48
    (root / "config.json").write_text(json.dumps(config))


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("missing", "weights .*missing is not a directory"),
        ("no config", "has no config.json; expected a transformers sam checkpoint"),
        ("wrong model", "is a 'grounding-dino' checkpoint; models config entry 'sam' needs a 'sam' one"),
        ("no weights file", "has no weights file; expected one of model.safetensors"),
        ("missing tensor", "the weights lack or misshape 1 of the model's tensors"),
        ("shape mismatch", "cannot be loaded as SamModel: the weights' shapes disagree with config.json"),
        ("no processor", "has no readable processor files"),
    ],
)
def test_sam_loader_rejects_bad_weights_in_one_line(weights, tmp_path, case, message):
    sam = weights["sam-random"]
    directory = {
        "missing": lambda: tmp_path / "missing",
        "no config": lambda: _corrupt(sam, tmp_path / "c", lambda d: (d / "config.json").unlink()),
        "wrong model": lambda: weights["grounding-dino"],
        "no weights file": lambda: _corrupt(sam, tmp_path / "w", lambda d: (d / "model.safetensors").unlink()),
        "missing tensor": lambda: _corrupt(sam, tmp_path / "t", _drop_a_tensor),
        "shape mismatch": lambda: _corrupt(sam, tmp_path / "s", _widen_the_encoder),
        "no processor": lambda: _corrupt(sam, tmp_path / "p", lambda d: (d / "processor_config.json").unlink()),
    }[case]()
    with pytest.raises(InputError, match=message) as err:
        SamBoxes(_settings(directory))
    assert "\n" not in str(err.value)
    assert str(directory) in str(err.value)


def test_detector_loader_rejects_a_missing_or_unreadable_file(tmp_path):
    with pytest.raises(InputError, match="weights .*nothing.onnx is not a file"):
        OnnxDetector(_settings(tmp_path / "nothing.onnx"))
    bad = tmp_path / "bad.onnx"
    bad.write_text("not a model")
    with pytest.raises(InputError, match="onnxruntime cannot load it") as err:
        OnnxDetector(_settings(bad))
    assert str(bad) in str(err.value) and "\n" not in str(err.value)


def test_a_segmenter_without_its_models_config_entry_is_one_line(scene_dir, retrieval, weights, tmp_path, capsys):
    models = write_models(tmp_path / "models.yaml", {"grounding-dino": {"weights": weights["grounding-dino"]}})
    args = [
        "segment",
        str(scene_dir),
        "--retrieval",
        str(retrieval),
        "-o",
        str(tmp_path / "m.npz"),
        "--segmenter",
        "grounded-sam",
    ]
    assert main([*args, "--models", str(models), "--cache", str(tmp_path / "cache")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("capframe: error: backend 'sam' needs an entry in the models config") and "\n" not in err
    assert not (tmp_path / "m.npz").exists()


def test_models_config_checks_threshold_and_threads_and_resolves_relative_weights(tmp_path):
    path = tmp_path / "models.yaml"
    for text, message in (
        ("detector: {weights: d.onnx, threshold: 1.5}\n", r"threshold 1.5 must lie in \(0, 1\)"),
        ("detector: {weights: d.onnx, threads: 0}\n", "threads 0 must be at least 1"),
        ("detector: {weights: d.onnx, threads: two}\n", "threads = 'two' is not a int"),
    ):
        path.write_text(text)
        with pytest.raises(InputError, match=message):
            read_models_config(path)
    path.write_text("detector: {weights: d.onnx, threshold: 0.25, threads: 1}\nsam: {weights: /models/sam}\n")
    config = read_models_config(path)
    settings = config.settings("detector")
    assert (settings.threshold, settings.threads) == (0.25, 1)
    assert settings.weights == str(tmp_path / "d.onnx")  # relative to the config file
    assert config.settings("sam").weights == "/models/sam"


# --- real weights: the COCO CenterNet on a synthetic television and teddy bear -------------------------------


@pytest.fixture(scope="module")
def tv_and_bear(tmp_path_factory):
    """A tabletop scene with a television and a teddy bear (and a mug), 480 x 360 renders."""
    from capframe.synth.generator import generate_scene

    root = tmp_path_factory.mktemp("tv-bear") / "scene"
    generate_scene(root, seed=1, objects=["television", "teddy bear", "mug"], preset="tabletop", views=16, resolution=(480, 360))
    return root


@pytest.mark.skipif(not CENTERNET.is_file(), reason="needs shared/models/centernet_coco.onnx")
def test_real_coco_detector_with_grabcut_associates_the_right_object(tv_and_bear, tmp_path):
    """Views 1 and 2 show the screen and the bear large and unoccluded (CenterNet is weak on
    small blurry renders: shared/models/README.md). Precision of the associated Gaussians
    against labels.npy >= 0.8 for both subjects."""
    cache = ["--cache", str(tmp_path / "cache")]
    retrieval = tmp_path / "retrieval.json"
    text = "the television on the left of the frame and the teddy bear on the right of the frame"
    assert main(["retrieve", str(tv_and_bear), text, "-o", str(retrieval), *cache]) == 0
    data = json.loads(retrieval.read_text())
    data["top"] = ["frame_0001", "frame_0002"]
    retrieval.write_text(json.dumps(data))
    models = write_models(tmp_path / "models.yaml", {"detector": {"weights": CENTERNET, "threads": 1}})
    masks, subjects = tmp_path / "masks.npz", tmp_path / "subjects.json"
    common = ["--retrieval", str(retrieval), "--segmenter", "detector", "--models", str(models), *cache]
    assert main(["segment", str(tv_and_bear), "-o", str(masks), *common]) == 0
    assert main(["associate", str(tv_and_bear), "--masks", str(masks), "--associator", "knn", "-o", str(subjects), *common]) == 0
    labels = np.load(tv_and_bear / "labels.npy")
    ids = {o["name"]: o["id"] for o in json.loads((tv_and_bear / "semantics.json").read_text())["objects"]}
    groundings = json.loads(subjects.read_text())["subjects"]
    for name in ("television", "teddy bear"):
        found = np.asarray(groundings[name]["gaussians"])
        precision = float((labels[found] == ids[name]).mean())
        assert precision >= 0.8, (name, precision)
        assert (labels[found] == ids[name]).sum() >= 0.1 * (labels == ids[name]).sum(), name


def test_bench_segment_runs_only_what_the_segmenter_can_name_and_needs_a_models_config(capsys):
    from capframe.bench.segment import can_name

    assert can_name("detector", ["television", "mug"]) and not can_name("detector", ["traffic cone", "ball"])
    assert can_name("grounded-sam", ["traffic cone"])
    assert main(["bench", "segment"]) == 2
    assert "capframe bench segment needs --models" in capsys.readouterr().err
