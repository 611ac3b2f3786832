"""The local Qwen-VL backend (:class:`capframe.backends.mllm.local.LocalChat`) on tiny random-weight
models built offline: every answer schema-valid under xgrammar, images counted into the prompt
as the model's processor would, batches equal to one-by-one answers, bad folders rejected."""

from __future__ import annotations

import json

import jsonschema
import numpy as np
import pytest
import torch

from capframe.backends.mllm.chat import ChatRequest
from capframe.backends.mllm.local import LocalChat
from capframe.backends.models import ModelSettings
from capframe.backends.tiny import tiny_qwen3_vl, tiny_qwen_vl
from capframe.errors import InputError, ModelError

# What the roles ask for, in small: a closed choice, bounded integers, a list of objects with
# required keys, and a parsed instruction (subjects with layout boxes, an orientation offset).
# Strings are bounded so that a random model's answers end within the token budget (a byte-level
# vocabulary: a token per character).
UNIT = {"type": "number", "minimum": 0, "maximum": 1}  # a normalised box coordinate
SCHEMAS = {
    "enum": {
        "type": "object",
        "properties": {"side": {"enum": ["left", "right", "none"]}},
        "required": ["side"],
        "additionalProperties": False,
    },
    "integers": {
        "type": "object",
        "properties": {
            "score": {"type": "integer", "minimum": 0, "maximum": 100},
            "rating": {"type": "integer", "minimum": 1, "maximum": 5},
        },
        "required": ["score", "rating"],
        "additionalProperties": False,
    },
    "questions": {
        "type": "object",
        "properties": {
            "questions": {
                "type": "array",
                "minItems": 1,
                "maxItems": 2,
                "items": {
                    "type": "object",
                    "properties": {"q": {"type": "string", "maxLength": 6}, "kind": {"enum": ["a", "b"]}},
                    "required": ["q", "kind"],
                    "additionalProperties": False,
                },
            }
        },
        "required": ["questions"],
        "additionalProperties": False,
    },
    "parsed": {
        "type": "object",
        "properties": {
            "subjects": {
                "type": "array",
                "minItems": 1,
                "maxItems": 1,
                "items": {
                    "type": "object",
                    "properties": {
                        "name": {"type": "string", "maxLength": 5},
                        "box": {"type": "array", "items": UNIT, "minItems": 4, "maxItems": 4},
                    },
                    "required": ["name", "box"],
                    "additionalProperties": False,
                },
            },
            "orientation": {
                "type": "object",
                "properties": {"azimuth": {"type": "integer", "minimum": -180, "maximum": 180}, "cue": {"type": "boolean"}},
                "required": ["azimuth", "cue"],
                "additionalProperties": False,
            },
        },
        "required": ["subjects", "orientation"],
        "additionalProperties": False,
    },
}
# Images are downscaled to a long side of 32 pixels: the tiny image processor (patch 16, merge 2)
# then makes one 32 x 32 tile of them, a single token; unscaled, these pictures would take 2.
IMAGE_SIDE = 32
PICTURES = (
    np.random.default_rng(0).integers(0, 256, (90, 120, 3), dtype=np.uint8),
    np.random.default_rng(1).integers(0, 256, (150, 110, 3), dtype=np.uint8),
)
TEXTS = ("the red chair on the left", "a dog seen from behind")


def _request(schema: str, images: int, text: str, max_tokens: int = 128) -> ChatRequest:
    return ChatRequest(
        system="You read photographic instructions.",
        user=text,
        schema=SCHEMAS[schema],
        schema_name=schema,
        prompt_version="test-1",
        images=PICTURES[:images],
        max_tokens=max_tokens,
    )


# Every schema with 0, 1 and 2 images, the texts alternating.
REQUESTS = [_request(name, images, TEXTS[(i + images) % 2]) for i, name in enumerate(SCHEMAS) for images in (0, 1, 2)]


@pytest.fixture(scope="module")
def weights(tmp_path_factory):
    return tiny_qwen3_vl(tmp_path_factory.mktemp("qwen3-vl"))


@pytest.fixture(scope="module")
def chat(weights):
    return LocalChat(ModelSettings(weights=str(weights), batch_size=4, image_side=IMAGE_SIDE, max_new_tokens=128))


@pytest.fixture(scope="module")
def one_by_one(chat):
    return [chat.complete(request) for request in REQUESTS]


def test_every_answer_is_schema_valid(chat, one_by_one, weights):
    for request, reply in zip(REQUESTS, one_by_one):
        assert reply.data == json.loads(reply.text)
        jsonschema.validate(reply.data, request.schema)
        assert reply.model == str(weights.resolve()) and reply.attempts >= 1 and reply.seconds > 0
    # A random model answers differently to different prompts and images: the batch comparison
    # below can tell rows apart.
    assert len({reply.text for reply in one_by_one}) >= 6


def test_token_counts(chat, one_by_one):
    """The answer's tokens (a token per byte here, plus the turn's end) and the prompt's: each
    image adds <|vision_start|>, one image token and <|vision_end|>."""
    for reply in one_by_one:
        if reply.attempts == 1:
            assert reply.completion_tokens == len(reply.text.encode()) + 1
    prompts = {(r.schema_name, len(r.images), r.user): reply.prompt_tokens for r, reply in zip(REQUESTS, one_by_one)}
    for (schema, images, text), tokens in prompts.items():
        if images and (schema, 0, text) in prompts:
            assert tokens - prompts[schema, 0, text] == 3 * images
    text = chat.tokenizer.apply_chat_template(
        [{"role": "system", "content": REQUESTS[0].system}, {"role": "user", "content": REQUESTS[0].user}],
        tokenize=False,
        add_generation_prompt=True,
    )
    assert one_by_one[0].prompt_tokens == len(chat.tokenizer(text).input_ids)


def test_batches_equal_one_by_one(chat, one_by_one):
    """Greedy decoding: batches of 4 mixing schemas, image counts and prompt lengths (left
    padding, a grammar per row) give each request the answer it gets alone."""
    batched = chat.complete_many(REQUESTS)
    assert [r.text for r in batched] == [r.text for r in one_by_one]
    assert [(r.prompt_tokens, r.completion_tokens, r.attempts) for r in batched] == [
        (r.prompt_tokens, r.completion_tokens, r.attempts) for r in one_by_one
    ]


def test_a_budget_too_small_fails_after_the_retries(weights):
    """No answer to the parsed-instruction schema fits in 8 tokens: each attempt is cut off,
    and after 1 + retries attempts the error names the entry and the weights folder."""
    chat = LocalChat(ModelSettings(weights=str(weights), retries=1, max_new_tokens=8), "parser")
    with pytest.raises(ModelError) as caught:
        chat.complete(_request("parsed", 1, TEXTS[0]))
    message = str(caught.value)
    assert "\n" not in message and f"'parser' (local weights {weights.resolve()})" in message
    assert "not JSON" in message and "after 2 attempts; 16 tokens" in message


def test_image_placeholder_in_text_rejected(chat):
    with pytest.raises(InputError, match="image placeholder"):
        chat.complete(_request("enum", 1, "look at <|image_pad|> here"))


def test_qwen2_5_vl(tmp_path):
    folder = tiny_qwen_vl(tmp_path / "qwen2.5-vl", "qwen2.5-vl")
    chat = LocalChat(ModelSettings(weights=str(folder), image_side=IMAGE_SIDE))
    assert type(chat.model).__name__ == "Qwen2_5_VLForConditionalGeneration"
    for images in (0, 2):
        reply = chat.complete(_request("integers", images, TEXTS[0]))
        jsonschema.validate(reply.data, SCHEMAS["integers"])


def test_bad_weights_folder_rejected(tmp_path, weights):
    def error(**settings) -> str:
        with pytest.raises(InputError) as caught:
            LocalChat(ModelSettings(**settings))
        assert "\n" not in str(caught.value)
        return str(caught.value)

    assert "needs weights" in error(endpoint="http://localhost:1/v1")
    assert f"{tmp_path / 'absent'} is not a directory" in error(weights=str(tmp_path / "absent"))
    assert "has no config.json; expected a Qwen3-VL or Qwen2.5-VL checkpoint" in error(weights=str(tmp_path))
    clip = tmp_path / "clip"
    clip.mkdir()
    (clip / "config.json").write_text('{"model_type": "clip"}')
    assert f"{clip / 'config.json'}: is a 'clip' checkpoint" in error(weights=str(clip))
    (clip / "config.json").write_text('{"model_type": "qwen3_vl"}')
    assert f"{clip}: has no weights file" in error(weights=str(clip))
    if not torch.cuda.is_available():
        assert "torch sees no CUDA device" in error(weights=str(weights), device="cuda")


def test_greedy_whatever_the_checkpoints_generation_config(chat, one_by_one):
    """A checkpoint's sampling settings and repetition penalty (Qwen2.5-VL ships 1.05) leave
    the answers greedy: the same as with the tiny model's plain generation_config."""
    saved = chat.model.generation_config
    chat.model.generation_config = saved.__class__.from_dict(
        saved.to_dict() | {"do_sample": True, "temperature": 0.7, "top_k": 20, "repetition_penalty": 5.0}
    )
    try:
        assert [chat.complete(r).text for r in REQUESTS[6:9]] == [r.text for r in one_by_one[6:9]]
    finally:
        chat.model.generation_config = saved


def test_through_the_factory_and_the_cache(weights, tmp_path, one_by_one):
    """A models-config entry with weights builds a LocalChat behind the response cache: the
    first ask runs the model, the second is answered from the cache, and a job whose every ask
    is cached never loads the weights."""
    from capframe.backends.mllm.factory import build_chat

    settings = ModelSettings(weights=str(weights), image_side=IMAGE_SIDE, max_new_tokens=128)
    chat = build_chat(settings, "mllm", tmp_path / "cache")
    assert chat.identity == str(weights.resolve())
    first, again = chat.complete(REQUESTS[4]), chat.complete(REQUESTS[4])
    assert first.text == again.text == one_by_one[4].text and not first.cached and again.cached
    assert chat.stats()["mllm_cache_hits"] == 1
    # A later job over the same cache answers without loading the weights at all.
    rerun = build_chat(settings, "mllm", tmp_path / "cache")
    assert rerun.complete(REQUESTS[4]).text == first.text and rerun.inner.loaded is None
    rerun.complete(REQUESTS[3])
    assert rerun.inner.loaded is not None  # the first miss loads them


def test_the_parser_under_xgrammar_answers_only_the_scene_s_objects_and_cues_the_pipeline_takes(weights):
    """The subject, layout and orientation parsers on the tiny random model: its subject names can
    only come from the scene's enum and its layout and angles only from bounds the pipeline takes,
    so every instruction parses (into a random subject of the scene with random cues)."""
    from capframe.backends.mllm.parser import MLLMParser
    from capframe.scene import SemanticObject
    from capframe.translate.vocabulary import Vocabulary

    class Recording:
        def __init__(self, inner):
            self.inner, self.identity, self.replies = inner, inner.identity, []

        def complete(self, request):
            return self.complete_many([request])[0]

        def complete_many(self, requests):
            replies = self.inner.complete_many(requests)
            self.replies += [(r.prompt_version, reply.data) for r, reply in zip(requests, replies)]
            return replies

    chat = Recording(LocalChat(ModelSettings(weights=str(weights), max_new_tokens=1024)))
    scene = Vocabulary.from_semantics(
        [SemanticObject(i, n, [], n == "mug") for i, n in enumerate(("teddy bear", "mug", "toy car"))]
    )
    for text in ("A close-up of the teddy bear on the left, seen from its right", "the toy car from behind, wide shot"):
        parsed = MLLMParser(chat).parse(text, scene)
        assert parsed.subjects and {s.name for s in parsed.subjects} <= set(scene.names)
        assert all(s.box is None or (0 <= s.box[0] < s.box[2] <= 1 and 0 <= s.box[1] < s.box[3] <= 1) for s in parsed.subjects)
    said = [s["name"] for version, data in chat.replies if version.startswith("subjects-") for s in data["subjects"]]
    assert said and set(said) <= set(scene.names)
    assert [v.split("-v")[0] for v, _ in chat.replies] == ["subjects", "layout", "orientation"] * 2
