"""Image encoders on ONNX Runtime: the export of every backend's encoder matches PyTorch to 1e-4
on pictures of several aspect ratios, the backends run onnxruntime (without busy-waiting, with
the configured threads) when the models config names an ONNX file, a file that does not fit the
model is a one-line error, and `capframe models export` / `capframe bench models` run."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from _model_helpers import KINDS, pictures, write_tiny_models

from capframe.backends import read_models_config
from capframe.backends.export import export_backend
from capframe.backends.image_text import ImageTextModel
from capframe.backends.onnx import OnnxEncoder
from capframe.backends.orient_anything import OrientAnything
from capframe.backends.sam import SamBoxes
from capframe.backends.tiny import TINY_IMAGE_TEXT, tiny_sam
from capframe.cli import main
from capframe.errors import InputError

PARITY = 1e-4


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    return write_tiny_models(tmp_path_factory.mktemp("models"))


def entry(configs, name: str):
    """(backend, settings) of a tiny model's config (``oa722``/``oa902``: Orient Anything)."""
    backend = "orient-anything" if name.startswith("oa") else TINY_IMAGE_TEXT[name]
    return backend, read_models_config(configs[name]).settings(backend)


@pytest.fixture(scope="module")
def exported(configs, tmp_path_factory):
    """name -> (ONNX file, largest difference from PyTorch on the check pictures)."""
    folder = tmp_path_factory.mktemp("onnx")
    out = {}
    for name in [*KINDS, "oa722", "oa902"]:
        backend, settings = entry(configs, name)
        out[name] = (folder / f"{name}.onnx", export_backend(backend, settings, folder / f"{name}.onnx"))
    return out


@pytest.mark.parametrize("name", [*KINDS, "oa722", "oa902"])
def test_export_matches_pytorch(exported, name):
    path, difference = exported[name]
    assert path.is_file() and difference <= PARITY, difference


@pytest.mark.parametrize("kind", ["clip", "siglip-naflex", "fg-clip2"])
def test_image_text_backend_runs_onnxruntime_when_configured(configs, exported, kind, monkeypatch):
    """Same embeddings as PyTorch, with PyTorch's image tower out of the way; NaFlex batches of
    other aspect ratios and (FG-CLIP 2) shorter patch budgets than the export's are padded."""
    backend, settings = entry(configs, kind)
    images = pictures((64, 48), (40, 72), (160, 120), seed=3)
    reference = ImageTextModel(backend, settings).embed_images(images)
    model = ImageTextModel(backend, dataclasses.replace(settings, onnx=str(exported[kind][0]), threads=2))
    assert model.onnx is not None and model.identity != ImageTextModel(backend, settings).identity

    def no_pytorch(*_):
        raise AssertionError("PyTorch image tower used")

    monkeypatch.setattr(model, "image_features", no_pytorch)
    assert np.abs(model.embed_images(images) - reference).max() <= PARITY


def test_orient_anything_runs_onnxruntime_without_loading_pytorch_weights(configs, exported):
    backend, settings = entry(configs, "oa722")
    crops = pictures((30, 30), (48, 40), seed=5)
    reference = OrientAnything(settings).estimate(crops)
    model = OrientAnything(dataclasses.replace(settings, onnx=str(exported["oa722"][0])))
    assert model.net is None
    for got, expected in zip(model.estimate(crops), reference):
        assert (got.azimuth, got.polar, got.rotation) == (expected.azimuth, expected.polar, expected.rotation)
        assert abs(got.confidence - expected.confidence) <= PARITY


# --- SAM: the image encoder on onnxruntime, the prompt encoder and mask decoder on PyTorch --------


@pytest.fixture(scope="module")
def sam(tmp_path_factory):
    """(models config naming a tiny random-weight SAM, its exported image encoder, the export's
    largest difference from PyTorch)."""
    root = tmp_path_factory.mktemp("sam")
    tiny_sam(root / "sam")
    config = root / "models.yaml"
    config.write_text("sam: {weights: sam, batch_size: 2}\n")
    onnx = root / "sam.onnx"
    return config, onnx, export_backend("sam", read_models_config(config).settings("sam"), onnx)


def test_sam_export_matches_pytorch(sam):
    _, onnx, difference = sam
    assert onnx.is_file() and difference <= PARITY, difference


def test_sam_backend_runs_onnxruntime_when_configured(sam, monkeypatch):
    """Same image embeddings as PyTorch (<= 1e-4) and the same masks from the same boxes, with
    PyTorch's vision encoder never called (and its weights freed)."""
    from transformers.models.sam.modeling_sam import SamVisionEncoder

    config, onnx, _ = sam
    settings = read_models_config(config).settings("sam")
    images = dict(enumerate(pictures((64, 48), (40, 72), (160, 120), seed=7)))
    boxes = {0: np.array([[4.0, 4.0, 50.0, 40.0], [20, 10, 60, 45]]), 1: np.array([[0.0, 8.0, 39.0, 60.0]])}
    boxes[2] = np.array([[30.0, 20.0, 150.0, 110.0]])
    pytorch = SamBoxes(settings)
    reference = pytorch.masks(images, boxes)

    def no_pytorch(*_, **__):
        raise AssertionError("PyTorch vision encoder used")

    monkeypatch.setattr(SamVisionEncoder, "forward", no_pytorch)
    model = SamBoxes(dataclasses.replace(settings, onnx=str(onnx), threads=2))
    assert model.onnx is not None and model.model.vision_encoder is None
    masks = model.masks(images, boxes)
    for key in boxes:
        difference = (model._embeddings[key][0] - pytorch._embeddings[key][0]).abs().max().item()
        assert difference <= PARITY, difference
        assert masks[key].shape == reference[key].shape == (len(boxes[key]), *images[key].shape[:2])
        assert (masks[key] == reference[key]).all(), (masks[key] != reference[key]).sum()
    # The masks are not all empty or all full: they depend on the embeddings.
    assert 0 < sum(m.sum() for m in reference.values()) < sum(m.size for m in reference.values())


def test_sam_onnx_files_that_do_not_fit_are_one_line_errors_naming_the_entry(sam, exported, tmp_path):
    config, _, _ = sam
    settings = read_models_config(config).settings("sam")
    (tmp_path / "garbage.onnx").write_bytes(b"not a model")
    cases = [
        (tmp_path / "absent.onnx", "ONNX file not found"),
        (tmp_path / "garbage.onnx", "onnxruntime cannot load it"),
        (exported["clip"][0], "outputs \\['batch', 16\\]; this SAM's image embeddings are \\['batch', 16, 4, 4\\]"),
    ]
    for onnx, match in cases:
        with pytest.raises(InputError, match=f"^models config entry 'sam': onnx .*{match}") as err:
            SamBoxes(dataclasses.replace(settings, onnx=str(onnx)))
        assert "\n" not in str(err.value) and str(onnx) in str(err.value)


def test_models_export_command_writes_sam_image_encoder(sam, tmp_path, capsys):
    config, _, _ = sam
    out = tmp_path / "sam.onnx"
    assert main(["models", "export", "sam", "--models", str(config), "-o", str(out)]) == 0
    line = capsys.readouterr().out
    assert out.is_file() and "sam image encoder" in line
    assert float(line.split("= ")[1].split()[0]) <= PARITY


def test_sessions_never_spin_and_use_the_configured_threads(exported):
    encoder = OnnxEncoder(exported["clip"][0], ["pixel_values"], threads=2)
    options = encoder.session.get_session_options()
    assert options.intra_op_num_threads == 2 and options.inter_op_num_threads == 1
    assert options.get_session_config_entry("session.intra_op.allow_spinning") == "0"
    assert options.get_session_config_entry("session.inter_op.allow_spinning") == "0"


def test_onnx_files_that_do_not_fit_are_one_line_errors(configs, exported, tmp_path):
    cases = [
        ("clip", str(tmp_path / "absent.onnx"), "ONNX file not found"),
        ("siglip", str(exported["clip"][0]), "outputs 16 features; the model's image encoder outputs 32"),
        ("clip", str(exported["siglip-naflex"][0]), "takes inputs \\['pixel_values', 'pixel_attention_mask'"),
    ]
    (tmp_path / "garbage.onnx").write_bytes(b"not a model")
    cases.append(("clip", str(tmp_path / "garbage.onnx"), "onnxruntime cannot load it"))
    for kind, onnx, match in cases:
        backend, settings = entry(configs, kind)
        with pytest.raises(InputError, match=match) as err:
            ImageTextModel(backend, dataclasses.replace(settings, onnx=onnx))
        assert "\n" not in str(err.value)
    backend, settings = entry(configs, "oa902")
    with pytest.raises(InputError, match="outputs 16 values; Orient Anything's layouts have \\[722, 902\\]"):
        OrientAnything(dataclasses.replace(settings, onnx=str(exported["clip"][0])))


def test_models_export_command(configs, tmp_path, capsys):
    out = tmp_path / "fg-clip.onnx"
    assert main(["models", "export", "fg-clip", "--models", str(configs["fg-clip"]), "-o", str(out)]) == 0
    line = capsys.readouterr().out
    assert out.is_file() and "max |onnxruntime - PyTorch|" in line
    assert float(line.split("= ")[1].split()[0]) <= PARITY
    assert main(["models", "export", "oracle", "--models", str(configs["fg-clip"]), "-o", str(tmp_path / "x.onnx")]) == 2
    exportable = "clip, siglip, fg-clip, fg-clip2, orient-anything, sam"
    assert f"has no image encoder to export; exportable: {exportable}" in capsys.readouterr().err


def test_bench_models_prints_both_runtimes_for_every_tiny_model(capsys):
    assert main(["bench", "models", "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert set(figures) == {f"{kind} (tiny)" for kind in [*KINDS, "orient-anything", "sam"]}
    for row in figures.values():
        assert row["PyTorch s/image"] > 0 and row["onnxruntime s/image"] > 0 and row["max |difference|"] <= PARITY


def test_weights_over_the_limit_go_to_one_external_data_file(configs, exported, tmp_path):
    """A model over protobuf's 2 GiB (SAM ViT-H's encoder) cannot be one file: past the limit the
    weights go to ``<name>.data`` beside the graph. Forced here with a limit of 0 bytes: same
    features as the single-file export, the graph file itself holds no weights."""
    from capframe.backends import export as exports
    from capframe.backends.onnx import export

    backend, settings = entry(configs, "clip")
    model, module, forward, names, batches = exports.encoder_of(backend, settings)
    path = tmp_path / "split.onnx"
    export(module, forward, exports.example_inputs(model, names, batches[0]), path, external_data_bytes=0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["split.onnx", "split.onnx.data"]
    single, _ = exported["clip"]
    assert path.stat().st_size < (tmp_path / "split.onnx.data").stat().st_size
    for batch in batches:
        feed = {name: batch[name] for name in names}
        split, whole = OnnxEncoder(path, names)(feed), OnnxEncoder(single, names)(feed)
        assert np.array_equal(split, whole)
