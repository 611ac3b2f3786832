"""Image-text scorers (CLIP, SigLIP 2 fixed-resolution and NaFlex, FG-CLIP, FG-CLIP 2) on tiny
random-weight models built offline: loading through the models config and its one-line errors,
the score conventions against transformers' own forward passes, FG-CLIP's long-caption path,
the tensor preprocessing against the image processors, the differentiable score's gradient
against finite differences, the per-scene view-embedding cache, and the coarse / scorer roles in
`capframe ground` and `capframe baseline`."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import torch
from _model_helpers import KINDS, pictures, write_tiny_models
from _synth_helpers import build_scene
from PIL import Image

from capframe.backends import BackendContext, read_models_config
from capframe.backends.image_text import FGCLIP_EXTRAS, FGCLIP_KEEP_POSITIONS, ImageTextModel
from capframe.backends.scorers import ModelCoarse, ModelDiffScorer, keep_for_qe, view_embeddings
from capframe.backends.tiny import TINY_IMAGE_TEXT
from capframe.cli import main
from capframe.errors import InputError
from capframe.scene import SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta


@pytest.fixture(scope="module")
def configs(tmp_path_factory) -> dict[str, Path]:
    return write_tiny_models(tmp_path_factory.mktemp("models"))


def load(configs, kind: str) -> ImageTextModel:
    backend = TINY_IMAGE_TEXT[kind]
    return ImageTextModel(backend, read_models_config(configs[kind]).settings(backend))


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("scorers") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


@pytest.mark.parametrize("kind", KINDS)
def test_scores_follow_the_model_convention_and_match_transformers_forward(configs, kind):
    """Embeddings are unit vectors; the score is the cosine (CLIP family) or SigLIP's sigmoid
    probability, equal to what the native model's own forward pass computes."""
    model = load(configs, kind)
    images = pictures((40, 32), (32, 48), (64, 64))
    texts = ["the teddy bear on the left", "a red armchair, seen from above"]
    image_emb, text_emb = torch.from_numpy(model.embed_images(images)), model.embed_texts(texts)
    assert image_emb.shape == (3, model.feature_size) and text_emb.shape == (2, model.feature_size)
    assert torch.allclose(image_emb.norm(dim=-1), torch.ones(3)) and torch.allclose(text_emb.norm(dim=-1), torch.ones(2))
    scores = model.score(image_emb, text_emb)
    texts_in = [t.lower() for t in texts] if kind == "fg-clip2" else texts
    ids = model.tokenizer(texts_in, padding="max_length", max_length=model.text_tokens, return_tensors="pt")["input_ids"]
    for row, image in enumerate(images):
        [(_, batch)] = model.model_inputs([image])
        with torch.no_grad():
            out = model.model(input_ids=ids, **batch)
        if model.sigmoid:
            assert ((scores > 0) & (scores < 1)).all()
            assert torch.allclose(scores[row], torch.sigmoid(out.logits_per_image[0]), atol=1e-5)
        else:
            cosine = out.logits_per_image[0] / model.model.logit_scale.exp()
            assert torch.allclose(scores[row], cosine, atol=1e-5)


def test_fgclip_long_captions_compose_the_two_position_tables(configs):
    model = load(configs, "fg-clip")
    weights = load_extras(configs)
    res, ori = weights[FGCLIP_EXTRAS[0]], weights[FGCLIP_EXTRAS[1]]
    keep = FGCLIP_KEEP_POSITIONS
    assert torch.equal(model.long.positions[:keep], ori[:keep]) and torch.equal(model.long.positions[keep:], res[keep:])
    assert torch.equal(model.long.projection, weights["text_filip_projection.weight"])
    # With CLIP's own table in the first 77 rows and the short projection, the long path is the
    # short one: the padding after the end token cannot reach it under the causal mask.
    model.long.positions[:77] = model.model.text_model.embeddings.position_embedding.weight
    model.long.projection.copy_(model.model.text_projection.weight)
    short = model.embed_texts(["a close-up of the vase"])
    ids = model.tokenizer(["a close-up of the vase"], padding="max_length", max_length=248, return_tensors="pt")["input_ids"]
    with torch.no_grad():
        assert torch.allclose(torch.nn.functional.normalize(model.long(ids), dim=-1), short, atol=1e-5)
    # A caption beyond 77 tokens takes the long path (truncated at 248), not a 77-token cut.
    long_text = "the teddy bear " * 12
    assert len(model.tokenizer(long_text)["input_ids"]) > 77
    ids = model.tokenizer([long_text], padding="max_length", max_length=248, truncation=True, return_tensors="pt")["input_ids"]
    with torch.no_grad():
        expected = torch.nn.functional.normalize(model.long(ids), dim=-1)
    assert torch.allclose(model.embed_texts([long_text]), expected, atol=1e-6)


def load_extras(configs) -> dict[str, torch.Tensor]:
    from safetensors.torch import load_file

    return load_file(configs["fg-clip"].parent / "fg-clip" / "model.safetensors")


def one_line_error(configs, backend: str, weights: Path, match: str) -> None:
    config = weights.parent / f"{weights.name}-{backend}.yaml"
    config.write_text(f"{backend}: {{weights: {weights}}}\n")
    with pytest.raises(InputError, match=match) as err:
        ImageTextModel(backend, read_models_config(config).settings(backend))
    assert "\n" not in str(err.value)


def test_loaders_reject_missing_files_wrong_layouts_and_mismatched_configs(configs, tmp_path):
    root = configs["clip"].parent
    one_line_error(configs, "clip", tmp_path / "absent", "weights folder not found")
    (tmp_path / "empty").mkdir()
    shutil.copy(root / "clip" / "config.json", tmp_path / "empty")
    one_line_error(configs, "clip", tmp_path / "empty", "no weights file")
    one_line_error(configs, "clip", root / "siglip", "config.json is a 'siglip' model; the clip backend loads \\['clip'\\]")
    one_line_error(configs, "fg-clip", root / "clip", "wrong checkpoint layout for fg-clip: no logit_scale_finegraind")
    one_line_error(configs, "clip", root / "fg-clip", "wrong checkpoint layout for clip: 5 weights it does not have")
    one_line_error(configs, "siglip", root / "fg-clip2", "config.json is a 'fgclip2' model; the siglip backend loads")
    mismatched = tmp_path / "mismatched"
    shutil.copytree(root / "clip", mismatched)
    config = json.loads((mismatched / "config.json").read_text())
    (mismatched / "config.json").write_text(json.dumps(config | {"projection_dim": 8}))
    one_line_error(configs, "clip", mismatched, "config.json and the weights disagree: .*projection.weight is \\(16, 32\\)")
    with pytest.raises(InputError, match="backend 'siglip' needs an entry in the models config"):
        read_models_config(configs["clip"]).settings("siglip")


@pytest.mark.parametrize("kind", ["clip", "siglip", "siglip-naflex"])
def test_tensor_preprocessing_is_the_image_processor_on_tensors(configs, kind):
    """Exactly the processor's input when no resize is needed; close to it after a 4x
    downscale (PIL rounds its resized image to 8 bits, the tensor path does not)."""
    model = load(configs, kind)
    for (width, height), tolerance in (((40, 32) if kind == "clip" else (32, 32), 1e-6), ((160, 128), 0.03)):
        [image] = pictures((width, height), seed=width)
        [(_, expected)] = model.model_inputs([image])
        tensor = torch.from_numpy(image).permute(2, 0, 1)[None].double() / 255
        got = model.preprocess(tensor, max_patches=model.max_patches(width, height))
        assert set(got) == set(model.inputs)
        for name in model.inputs:
            assert got[name].shape == expected[name].shape, name
        if kind == "siglip-naflex":
            assert torch.equal(got["spatial_shapes"], expected["spatial_shapes"])
            assert torch.equal(got["pixel_attention_mask"], expected["pixel_attention_mask"].long())
        difference = (got["pixel_values"] - expected["pixel_values"].double()).abs().mean()
        assert difference < tolerance, (width, float(difference))


@pytest.mark.parametrize("kind", ["clip", "siglip-naflex"])
def test_differentiable_score_gradient_matches_central_differences(configs, kind):
    """d score / d pixels of a rendered image (float64), along a random direction. The central
    difference's truncation error falls as eps^2 (1.9e-5 relative at eps 1e-3 for CLIP,
    1.9e-7 at 1e-4): at 1e-6 what is left is rounding."""
    backend = TINY_IMAGE_TEXT[kind]
    context = BackendContext(None, np.array([0.0, 0.0, 1.0]), Path("unused"), read_models_config(configs[kind]))
    scorer = ModelDiffScorer(context, backend)
    scorer.model.model.double()
    g = torch.Generator().manual_seed(0)
    image = (0.2 + 0.6 * torch.rand(40, 56, 3, generator=g, dtype=torch.float64)).requires_grad_(True)
    text = "a close-up of the teddy bear"
    score = scorer.score(image, text)
    (gradient,) = torch.autograd.grad(score, image)
    direction = torch.randn(image.shape, generator=g, dtype=torch.float64)
    eps = 1e-6
    with torch.no_grad():
        numeric = (scorer.score(image + eps * direction, text) - scorer.score(image - eps * direction, text)) / (2 * eps)
    analytic = (gradient * direction).sum()
    assert abs(float(analytic - numeric)) <= 1e-8 * abs(float(numeric)), (float(analytic), float(numeric))


def test_view_embeddings_are_computed_once_per_scene_and_model(configs, scene_dir, tmp_path, monkeypatch):
    scene = load_scene_dir(scene_dir)
    calls = []
    real = ImageTextModel.embed_images
    monkeypatch.setattr(ImageTextModel, "embed_images", lambda self, images: calls.append(len(images)) or real(self, images))

    def embeddings(kind):
        context = BackendContext(scene, np.asarray(scene.metadata.up), tmp_path / "cache", read_models_config(configs[kind]))
        return view_embeddings(load(configs, kind), context)

    first = embeddings("clip")
    assert first.shape == (len(scene.cameras), 16) and sum(calls) == len(scene.cameras)
    assert np.array_equal(embeddings("clip"), first) and sum(calls) == len(scene.cameras)  # read back
    embeddings("siglip")  # another model: its own entry
    assert sum(calls) == 2 * len(scene.cameras)
    assert len(list((tmp_path / "cache" / "embeddings").iterdir())) == 2


def test_coarse_keeps_an_eighth_of_the_views_as_the_paper(configs, scene_dir, tmp_path):
    assert keep_for_qe(np.array([0.1, 0.5, 0.3])) == [1]
    assert keep_for_qe(np.arange(17.0)) == [16, 15]
    scene = load_scene_dir(scene_dir)
    context = BackendContext(scene, np.asarray(scene.metadata.up), tmp_path / "cache", read_models_config(configs["fg-clip"]))
    coarse = ModelCoarse(context, "fg-clip")
    from capframe.translate.instruction import ParsedInstruction

    scores = coarse.coarse(ParsedInstruction("the vase"))
    assert scores.shape == (len(scene.cameras),) and np.all(np.abs(scores) <= 1)


def test_ground_runs_with_model_and_oracle_roles(configs, scene_dir, tmp_path):
    """FG-CLIP coarse retrieval and Orient Anything orientation (tiny random weights) with the
    oracle segmenter, the knn associator and oracle QE, through the command line."""
    root = configs["clip"].parent
    models = tmp_path / "models.yaml"
    models.write_text(
        f"fg-clip: {{weights: {root / 'fg-clip'}}}\n"
        f"orient-anything: {{weights: {root / 'oa902' / 'dino_weight.pt'}, config: {root / 'oa902' / 'dinov2'}}}\n"
    )
    out = tmp_path / "out"
    args = ["ground", str(scene_dir), "the teddy bear on the right, seen from its front", "-o", str(out)]
    args += ["--coarse-scorer", "fg-clip", "--segmenter", "oracle", "--associator", "knn", "--orient", "orient-anything"]
    args += ["--models", str(models), "--cache", str(tmp_path / "cache"), "--iterations", "150", "--json"]
    assert main(args) == 0
    result = json.loads((out / "result.json").read_text())
    backends = result["options"]["backends"]
    assert backends["coarse"] == "fg-clip" and backends["orient"] == "orient-anything" and backends["qe"] == "oracle"
    assert {"segment_s", "orient_s"} <= set(result["timings"]) and np.isfinite(np.asarray(result["T_cw"])).all()
    assert len(result["retrieval"]["views"]) == 1  # max(1, 6 // 8) views go on to QE


def test_baseline_ranks_candidates_with_a_model_scorer(configs, scene_dir, tmp_path):
    out = tmp_path / "ivs"
    args = ["baseline", "ivs", str(scene_dir), "the teddy bear on the right", "-o", str(out), "--scorer", "siglip"]
    args += ["--models", str(configs["siglip"]), "--cache", str(tmp_path / "cache"), "--json"]
    assert main(args) == 0
    result = json.loads((out / "result.json").read_text())
    assert 0 < result["score"] < 1  # SigLIP's sigmoid probability
    assert all(0 < c["score"] < 1 for c in result["search"]["best"])


def test_tensor_resizing_follows_pil_closer_than_kornia():
    """Why the differentiable path resizes with interpolate(antialias=True), not kornia: against
    CLIP's PIL processor (640x480 -> shorter side 224, bicubic, centre crop), on a smooth picture
    with a sharp edge, kornia's Gaussian antialiasing is several times further off."""
    import kornia
    from transformers.models.clip.image_processing_pil_clip import CLIPImageProcessorPil

    from capframe.backends.tensor_images import TensorPreprocess

    processor = CLIPImageProcessorPil()
    base = np.random.default_rng(0).integers(0, 256, (30, 40, 3), dtype=np.uint8)
    image = np.array(Image.fromarray(base).resize((640, 480), Image.BICUBIC))
    image[100:300, 200:210] = 255
    expected = processor(images=[Image.fromarray(image)], return_tensors="pt")["pixel_values"].double()
    x = torch.from_numpy(image).permute(2, 0, 1)[None].double() / 255
    ours = TensorPreprocess.of(processor)(x)["pixel_values"]
    resized = kornia.geometry.transform.resize(x, 224, interpolation="bicubic", side="short", antialias=True)
    top, left = (resized.shape[-2] - 224) // 2, (resized.shape[-1] - 224) // 2
    mean = torch.tensor(processor.image_mean, dtype=x.dtype)[:, None, None]
    std = torch.tensor(processor.image_std, dtype=x.dtype)[:, None, None]
    theirs = (resized[..., top : top + 224, left : left + 224] - mean) / std
    ours_error, kornia_error = (ours - expected).abs().max(), (theirs - expected).abs().max()
    assert ours_error < 0.1 and kornia_error > 4 * ours_error, (float(ours_error), float(kornia_error))
