"""A :class:`~capframe.backends.mllm.chat.ChatModel` over local Qwen3-VL / Qwen2.5-VL weights
through transformers, each answer constrained to its request's JSON schema by xgrammar.

No torchvision is needed: ``AutoProcessor`` of these models builds a video processor that
requires it, so the tokenizer and the image processor are loaded on their own, the chat template
is rendered to text, and each image's ``<|image_pad|>`` is expanded to the image's token count,
``prod(image_grid_thw) / merge_size**2``, as the model's own processor would.

Decoding is greedy. At every step xgrammar masks the tokens that would leave the schema's
grammar, so an answer that ends is JSON of the schema's shape; one cut off by the token budget is
not, nor one that breaks a keyword xgrammar does not enforce. Every answer is therefore validated
(:func:`~capframe.backends.mllm.chat.validate_reply`), and an invalid one asked again with the
fault fed back as a new user turn (the prompt changes, so the greedy answer does too), up to
``retries`` times; then a :class:`~capframe.errors.ModelError` names the entry and weights folder.

:meth:`LocalChat.complete_many` runs up to ``batch_size`` requests per ``generate()`` call, left
padded, each row under its own schema's grammar: xgrammar's transformers logits processor takes
one compiled grammar per row and keeps one matcher per row.

xgrammar 0.2.8's JSON string rule admits raw control characters (all but CR and LF), which JSON
forbids inside strings and compact JSON never needs outside them: tokens holding a byte below
0x20 are masked as well, so that such an answer is not generated in the first place.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import InputError, ModelError
from ..models import ModelSettings
from ..weights import WEIGHT_FILES, load_pretrained, quiet_transformers, torch_device_dtype
from .chat import FEEDBACK, ChatReply, ChatRequest, validate_reply
from .images import downscale

# config.json model_type -> the transformers class that generates with it.
MODEL_CLASSES = {
    "qwen3_vl": "Qwen3VLForConditionalGeneration",
    "qwen3_vl_moe": "Qwen3VLMoeForConditionalGeneration",
    "qwen2_5_vl": "Qwen2_5_VLForConditionalGeneration",
}
# The token that ends an assistant turn in Qwen's chat format; the grammar's and generate()'s stop.
TURN_END = "<|im_end|>"


@dataclass
class _Row:
    """One request in flight: its chat so far, its images and what its attempts cost."""

    request: ChatRequest
    messages: list[dict]
    images: list
    cap: int
    attempts: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    text: str = ""
    fault: str = ""
    data: dict | None = None


class LocalChat:
    """The chat contract over the Qwen-VL weights folder of a models-config entry.

    Attributes:
        identity: the weights folder (absolute).
        settings: the entry (``weights``, ``device``, ``dtype``, ``batch_size``, ``image_side``,
            ``retries``, ``max_new_tokens``).
        model, tokenizer, image_processor: the loaded parts (the tokenizer pads on the left).
    """

    def __init__(self, settings: ModelSettings, entry_name: str = "mllm"):
        self.settings = settings
        self.entry = entry_name
        self.root = qwen_folder(settings.weights, entry_name)
        self.identity = str(self.root)
        self.device, dtype = torch_device_dtype(entry_name, settings)
        self.tokenizer, self.image_processor, self.model = _load(self.root, dtype)
        self.model.to(self.device).eval()
        self.image_pad = self.tokenizer.convert_ids_to_tokens(self.model.config.image_token_id)
        self.merge = int(self.image_processor.merge_size)
        turn_end = self.tokenizer.convert_tokens_to_ids(TURN_END)
        if not isinstance(turn_end, int) or turn_end == self.tokenizer.unk_token_id:
            raise InputError(f"the tokenizer has no {TURN_END} token; expected Qwen's chat vocabulary", source=str(self.root))
        self.stops = [turn_end]
        self.pad = self.tokenizer.pad_token_id if self.tokenizer.pad_token_id is not None else turn_end
        import xgrammar as xgr

        vocab = self.model.config.get_text_config().vocab_size  # the logits' width, may exceed the tokenizer's
        info = xgr.TokenizerInfo.from_huggingface(self.tokenizer, vocab_size=vocab, stop_token_ids=self.stops)
        # The compiler keeps every grammar it compiled, keyed by the schema text: each schema is compiled once.
        self._compiler = xgr.GrammarCompiler(info)
        control = [i for i, piece in enumerate(info.decoded_vocab) if any(byte < 0x20 for byte in piece)]
        self._mask_control = _MaskTokens(control)

    # --- the contract ------------------------------------------------------------------------

    def complete(self, request: ChatRequest) -> ChatReply:
        """One validated answer to ``request``."""
        return self.complete_many([request])[0]

    def complete_many(self, requests: list[ChatRequest]) -> list[ChatReply]:
        """The replies to ``requests``, in order, ``batch_size`` requests per ``generate()`` call.
        Greedy decoding makes each answer the one :meth:`complete` gives alone."""
        size = self.settings.batch_size
        return [reply for start in range(0, len(requests), size) for reply in self._batch(requests[start : start + size])]

    # --- one batch ---------------------------------------------------------------------------

    def _batch(self, requests: list[ChatRequest]) -> list[ChatReply]:
        """Up to ``1 + retries`` generate() calls: the first over all requests, each further one
        over those whose answer failed validation, their fault fed back. The batch's wall time is
        shared equally among its replies (so that summed seconds are the time spent)."""
        start = time.perf_counter()
        rows = [self._row(request) for request in requests]
        pending = rows
        for attempt in range(1, self.settings.retries + 2):
            for row, (text, prompt_tokens, completion_tokens) in zip(pending, self._generate(pending)):
                row.attempts, row.text = attempt, text
                row.prompt_tokens += prompt_tokens
                row.completion_tokens += completion_tokens
                try:
                    row.data = validate_reply(text, row.request.schema)
                except ValueError as invalid:
                    row.fault = str(invalid)
                    row.messages += [
                        {"role": "assistant", "content": text},
                        {"role": "user", "content": FEEDBACK.format(error=invalid)},
                    ]
            pending = [row for row in rows if row.data is None]
            if not pending:
                break
        if pending:
            row = pending[0]
            raise ModelError(
                f"MLLM entry {self.entry!r} (local weights {self.root}): invalid answer: {row.fault} "
                f"(after {row.attempts} attempts; {row.completion_tokens} tokens)"
            )
        seconds = (time.perf_counter() - start) / len(rows)
        return [
            ChatReply(
                data=row.data,
                text=row.text,
                model=self.identity,
                prompt_tokens=row.prompt_tokens,
                completion_tokens=row.completion_tokens,
                seconds=seconds,
                attempts=row.attempts,
            )
            for row in rows
        ]

    def _row(self, request: ChatRequest) -> _Row:
        """The request's first chat (system, then the user turn: its images, then its text), its
        images downscaled to ``image_side`` and its token budget."""
        from PIL import Image

        images = []
        for image in request.images:
            if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
                raise ValueError(f"an image for the model must be (H, W, 3) uint8 RGB, got {image.shape} {image.dtype}")
            images.append(Image.fromarray(downscale(image, self.settings.image_side)))
        if images:
            user = {"role": "user", "content": [{"type": "image"}] * len(images) + [{"type": "text", "text": request.user}]}
        else:
            user = {"role": "user", "content": request.user}
        messages = [{"role": "system", "content": request.system}, user]
        return _Row(request, messages, images, min(request.max_tokens, self.settings.max_new_tokens))

    def _generate(self, rows: list[_Row]) -> list[tuple[str, int, int]]:
        """One greedy, grammar-constrained ``generate()`` over ``rows``: per row the answer text
        (up to its stop token, or its first ``cap`` tokens) and its (prompt, completion) tokens.

        The batch runs for the largest budget; a row's answer is cut to its own budget, which
        leaves it as it would be alone (a row's greedy tokens do not depend on the others)."""
        import torch
        import xgrammar as xgr
        from transformers import GenerationConfig, LogitsProcessorList

        texts = [self._chat_text(row) for row in rows]
        pictures = [image for row in rows for image in row.images]
        vision = {}
        if pictures:
            processed = self.image_processor(images=pictures, return_tensors="pt")
            grid = processed["image_grid_thw"]
            texts = self._expand_images(texts, (grid.prod(-1) // self.merge**2).tolist())
            vision = {"pixel_values": processed["pixel_values"].to(self.device, self.model.dtype), "image_grid_thw": grid}
        encoded = self.tokenizer(texts, return_tensors="pt", padding=True, add_special_tokens=False)
        inputs = {key: value.to(self.device) for key, value in (dict(encoded) | vision).items()}
        grammars = [self._compiler.compile_json_schema(json.dumps(row.request.schema), any_whitespace=False) for row in rows]
        # Fields left unset here are filled from the checkpoint's generation_config, whose sampling
        # settings do_sample=False overrides; its repetition penalty (1.05 in Qwen2.5-VL's) is reset.
        config = GenerationConfig(
            max_new_tokens=max(row.cap for row in rows),
            do_sample=False,
            repetition_penalty=1.0,
            eos_token_id=self.stops,
            pad_token_id=self.pad,
        )
        # A fresh processor per call: it keeps each row's grammar state (xgrammar: single use).
        processors = LogitsProcessorList([self._mask_control, xgr.contrib.hf.LogitsProcessor(grammars)])
        try:
            with torch.inference_mode(), quiet_transformers():
                output = self.model.generate(**inputs, generation_config=config, logits_processor=processors)
        except RuntimeError as err:  # out of memory, a device fault
            raise ModelError(
                f"MLLM entry {self.entry!r} (local weights {self.root}): generation failed: {str(err).splitlines()[0]}"
            ) from None
        answers = []
        prompt_tokens = encoded["attention_mask"].sum(-1).tolist()
        for row, tokens, used in zip(rows, output[:, encoded["input_ids"].shape[1] :].tolist(), prompt_tokens):
            tokens = tokens[: row.cap]
            end = next((i for i, token in enumerate(tokens) if token in self.stops), None)
            answer = tokens if end is None else tokens[:end]
            answers.append((self.tokenizer.decode(answer), used, len(tokens) if end is None else end + 1))
        return answers

    def _chat_text(self, row: _Row) -> str:
        """The row's chat rendered by the model's template, ending in the assistant's turn."""
        text = self.tokenizer.apply_chat_template(row.messages, tokenize=False, add_generation_prompt=True)
        if text.count(self.image_pad) != len(row.images):
            raise InputError(
                f"a {row.request.schema_name!r} request's text holds the model's image placeholder {self.image_pad}; "
                f"images go in the request's images ({len(row.images)} here)"
            )
        return text

    def _expand_images(self, texts: list[str], counts: list[int]) -> list[str]:
        """``texts`` with their images' placeholders, in order across the texts, repeated to the
        images' token counts."""
        counts = iter(counts)
        expanded = []
        for text in texts:
            pieces = text.split(self.image_pad)
            expanded.append(pieces[0] + "".join(self.image_pad * next(counts) + piece for piece in pieces[1:]))
        return expanded


class _MaskTokens:
    """A logits processor that rules out the tokens ``ids`` at every step."""

    def __init__(self, ids: list[int]):
        self.ids = ids

    def __call__(self, input_ids, scores):
        """``scores`` (batch, vocab) with the columns ``ids`` set to -inf, in place."""
        scores[:, self.ids] = float("-inf")
        return scores


def qwen_folder(weights: str | None, entry: str) -> Path:
    """The entry's weights folder, checked for a Qwen-VL ``config.json`` and a weights file."""
    if weights is None:
        raise InputError(f"models config entry {entry!r} needs weights (a local Qwen3-VL or Qwen2.5-VL folder) or an endpoint")
    root = Path(weights).expanduser().resolve()
    if not root.is_dir():
        raise InputError(f"models config entry {entry!r}: weights {root} is not a directory (a Qwen-VL checkpoint folder)")
    config = root / "config.json"
    try:
        found = json.loads(config.read_text()).get("model_type")
    except OSError:
        expected = f"expected a Qwen3-VL or Qwen2.5-VL checkpoint ({entry!r})"
        raise InputError(f"has no config.json; {expected}", source=str(root)) from None
    except (json.JSONDecodeError, AttributeError):
        raise InputError(f"is not a JSON object of model settings ({entry!r})", source=str(config)) from None
    if found not in MODEL_CLASSES:
        raise InputError(
            f"is a {found!r} checkpoint; models config entry {entry!r} needs one of {sorted(MODEL_CLASSES)} (Qwen-VL)",
            source=str(config),
        )
    if not any((root / name).is_file() for name in WEIGHT_FILES):
        raise InputError(f"has no weights file; expected one of {', '.join(WEIGHT_FILES)} ({entry!r})", source=str(root))
    return root


def _load(root: Path, dtype):
    """(tokenizer padding on the left, image processor, model) of a checked Qwen-VL folder."""
    import transformers
    from transformers import AutoImageProcessor, AutoTokenizer

    model_type = json.loads((root / "config.json").read_text())["model_type"]
    with quiet_transformers():
        try:
            tokenizer = AutoTokenizer.from_pretrained(root, local_files_only=True, padding_side="left")
            image_processor = AutoImageProcessor.from_pretrained(root, local_files_only=True)
        except (OSError, ValueError, TypeError, KeyError) as err:
            message = str(err).splitlines()[0] if str(err) else type(err).__name__
            raise InputError(f"has no readable tokenizer or image processor files: {message}", source=str(root)) from None
        model = load_pretrained(getattr(transformers, MODEL_CLASSES[model_type]), root, dtype)
    if tokenizer.chat_template is None:
        tokenizer.chat_template = _legacy_chat_template(root)
    return tokenizer, image_processor, model


def _legacy_chat_template(root: Path) -> str:
    """The chat template of a folder that keeps it only in the processor's ``chat_template.json``
    (as some Qwen-VL releases do), which the tokenizer does not read."""
    try:
        return json.loads((root / "chat_template.json").read_text())["chat_template"]
    except (OSError, json.JSONDecodeError, KeyError, TypeError):
        raise InputError(
            "has no chat template; expected chat_template.jinja, tokenizer_config.json's chat_template or chat_template.json",
            source=str(root),
        ) from None
