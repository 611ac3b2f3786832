"""Tiny random-weight models in the released layouts, built offline: the test fixtures' and
``capframe bench models``' stand-ins for real checkpoints. Each is written the way its real
counterpart is distributed (a ``save_pretrained`` folder; for Orient Anything a ``.pt`` state
dict with transformers-4 key names beside a DINOv2 config folder) and loads through the same
code. They are about the smallest that run every code path: hidden size 32, 2 layers, patches
of 8 (14 for DINOv2) pixels."""

from __future__ import annotations

import json
from pathlib import Path

import torch

from .image_text import FGCLIP_EXTRAS, FGCLIP_KEEP_POSITIONS, FGCLIP_LONG_TOKENS
from .weights import quiet_transformers

WIDTH = 32
PROJECTION = 16
TOWER = {"hidden_size": WIDTH, "intermediate_size": 64, "num_hidden_layers": 2, "num_attention_heads": 4}
IMAGENET_MEAN, IMAGENET_STD = [0.485, 0.456, 0.406], [0.229, 0.224, 0.225]


def _byte_vocab(specials: list[str], byte_tokens: bool) -> dict[str, int]:
    """Specials, then every byte: as ``<0xNN>`` fallback tokens (SentencePiece style) or as
    GPT-2 byte characters with and without CLIP's ``</w>`` word end. Words then tokenise to
    characters, so different texts get different ids."""
    from tokenizers.pre_tokenizers import ByteLevel

    vocab = {s: i for i, s in enumerate(specials)}
    if byte_tokens:
        pieces = [f"<0x{b:02X}>" for b in range(256)] + ["▁"] + [chr(c) for c in range(ord("a"), ord("z") + 1)]
    else:
        alphabet = sorted(ByteLevel.alphabet())
        pieces = alphabet + [ch + "</w>" for ch in alphabet]
    for piece in pieces:
        vocab.setdefault(piece, len(vocab))
    return vocab


def _clip_tokenizer():
    from transformers import CLIPTokenizer

    vocab = _byte_vocab(["<|startoftext|>", "<|endoftext|>"], byte_tokens=False)
    return CLIPTokenizer(vocab=vocab, merges=[]), vocab


# The special tokens' ids of the Gemma-style vocabulary below (SigLIP's defaults are CLIP's).
GEMMA_IDS = {"pad_token_id": 0, "eos_token_id": 1, "bos_token_id": 2}


def _gemma_tokenizer(cls):
    vocab = _byte_vocab(["<pad>", "<eos>", "<bos>", "<unk>", "<mask>"], byte_tokens=True)
    # SigLIP pools the last position of a right-padded sequence, as real checkpoints pad.
    return cls(vocab=vocab, merges=[], padding_side="right"), vocab


# What tiny_image_text builds: the backend names, and SigLIP 2's NaFlex variant of ``siglip``.
TINY_IMAGE_TEXT = {"clip": "clip", "siglip": "siglip", "siglip-naflex": "siglip", "fg-clip": "fg-clip", "fg-clip2": "fg-clip2"}


def tiny_image_text(directory: str | Path, kind: str, seed: int = 0) -> Path:
    """Write a tiny random-weight model of ``kind`` (a key of :data:`TINY_IMAGE_TEXT`) into
    ``directory``: config, weights, tokenizer and image processor. Returns the folder."""
    directory = Path(directory)
    torch.manual_seed(seed)
    model, tokenizer, processor = _tiny_parts(kind)
    with quiet_transformers():
        model.save_pretrained(directory)
        tokenizer.save_pretrained(directory)
        processor.save_pretrained(directory)
    if kind == "fg-clip":
        _add_weights(directory, _fgclip_extras(model))
    if kind == "fg-clip2":
        _add_weights(directory, _fgclip2_extras(model))
        _set_model_type(directory, "fgclip2")
    return directory


def _tiny_parts(kind: str):
    """(model, tokenizer, image processor) of a tiny ``kind``."""
    import transformers as tf

    if kind in ("clip", "fg-clip"):
        from transformers.models.clip.image_processing_pil_clip import CLIPImageProcessorPil

        tokenizer, vocab = _clip_tokenizer()
        end, start = vocab["<|endoftext|>"], vocab["<|startoftext|>"]
        text = TOWER | {"vocab_size": len(vocab), "eos_token_id": end, "bos_token_id": start, "pad_token_id": end}
        config = tf.CLIPConfig(
            text_config=text, vision_config=TOWER | {"image_size": 32, "patch_size": 8}, projection_dim=PROJECTION
        )
        model = tf.CLIPModel(config)
        processor = CLIPImageProcessorPil(size={"shortest_edge": 32}, crop_size={"height": 32, "width": 32})
    elif kind == "siglip":
        from transformers.models.siglip.image_processing_pil_siglip import SiglipImageProcessorPil

        tokenizer, vocab = _gemma_tokenizer(tf.GemmaTokenizer)
        config = tf.SiglipConfig(
            text_config=TOWER | GEMMA_IDS | {"vocab_size": len(vocab), "max_position_embeddings": 64},
            vision_config=TOWER | {"image_size": 32, "patch_size": 8},
        )
        model = tf.SiglipModel(config)
        processor = SiglipImageProcessorPil(size={"height": 32, "width": 32})
    elif kind in ("siglip-naflex", "fg-clip2"):
        from transformers.models.siglip2.image_processing_pil_siglip2 import Siglip2ImageProcessorPil

        tokenizer, vocab = _gemma_tokenizer(tf.Siglip2Tokenizer)
        config = tf.Siglip2Config(
            text_config=TOWER | GEMMA_IDS | {"vocab_size": len(vocab), "max_position_embeddings": 64},
            vision_config=TOWER | {"patch_size": 8, "num_patches": 16},
        )
        model = tf.Siglip2Model(config)
        processor = Siglip2ImageProcessorPil(patch_size=8, max_num_patches=16)
    else:
        raise ValueError(f"no tiny model {kind!r}; expected one of {list(TINY_IMAGE_TEXT)}")
    return model, tokenizer, processor


def _fgclip_extras(model) -> dict[str, torch.Tensor]:
    """FG-CLIP v1's 5 extra weights: the 77 CLIP positions stretched to 248 as FG-CLIP built its
    long table (the first 20 kept, each later interval split in four), used for both the
    original and the stretched table; the long projection starts as the short one."""
    table = model.text_model.embeddings.position_embedding.weight.detach()
    keep = FGCLIP_KEEP_POSITIONS
    source = torch.arange(FGCLIP_LONG_TOKENS, dtype=torch.float64)
    source[keep:] = keep + (source[keep:] - keep) / 4
    low = source.floor().long().clamp(max=len(table) - 2)
    frac = (source - low).float()[:, None]  # > 1 past the last row: extrapolates its slope
    stretched = table[low] * (1 - frac) + table[low + 1] * frac
    scale = model.logit_scale.detach().clone()
    return dict(
        zip(
            FGCLIP_EXTRAS,
            (stretched, stretched.clone(), model.text_projection.weight.detach().clone(), scale, scale.clone()),
        )
    )


def _fgclip2_extras(model) -> dict[str, torch.Tensor]:
    """Some of FG-CLIP 2's extra heads (the loader must accept and leave them out)."""
    hidden = model.config.text_config.hidden_size
    return {
        "longtext_head.weight": torch.randn(hidden, hidden),
        "longtext_head.bias": torch.zeros(hidden),
        "boxtext_head.weight": torch.randn(hidden, hidden),
        "dense_feature_head.probe": torch.randn(1, 1, hidden),
        "text_model.embeddings.position_embedding_res.weight": torch.randn(196, hidden),
    }


def _add_weights(directory: Path, extra: dict[str, torch.Tensor]) -> None:
    """Add tensors to the folder's ``model.safetensors``."""
    from safetensors.torch import load_file, save_file

    path = directory / "model.safetensors"
    save_file(load_file(path) | {k: v.contiguous() for k, v in extra.items()}, path, metadata={"format": "pt"})


def _set_model_type(directory: Path, model_type: str) -> None:
    path = directory / "config.json"
    path.write_text(json.dumps(json.loads(path.read_text()) | {"model_type": model_type}, indent=2))


# transformers 4 names of DINOv2's attention weights, as the released Orient Anything .pt files have them.
V4_NAMES = {
    "attention.q_proj": "attention.attention.query",
    "attention.k_proj": "attention.attention.key",
    "attention.v_proj": "attention.attention.value",
    "attention.o_proj": "attention.output.dense",
}


def tiny_orient_anything(directory: str | Path, outputs: int = 902, seed: int = 0) -> tuple[Path, Path]:
    """A tiny Orient Anything: a DINOv2 config folder (hidden 32, 2 layers, 56 px, patch 14, with
    its Bit image processor) and a ``.pt`` state dict with ``outputs`` (722 or 902) head
    outputs, random BatchNorm statistics and transformers-4 key names. Returns (weights, config)."""
    from transformers import Dinov2Config
    from transformers.models.bit.image_processing_pil_bit import BitImageProcessorPil

    from .orient_anything import OrientAnythingNet

    directory = Path(directory)
    config_dir = directory / "dinov2"
    torch.manual_seed(seed)
    config = Dinov2Config(hidden_size=WIDTH, num_hidden_layers=2, num_attention_heads=4, image_size=56, patch_size=14)
    processor = BitImageProcessorPil(
        size={"shortest_edge": 64}, crop_size={"height": 56, "width": 56}, image_mean=IMAGENET_MEAN, image_std=IMAGENET_STD
    )
    with quiet_transformers():
        config.save_pretrained(config_dir)
        processor.save_pretrained(config_dir)
    net = OrientAnythingNet(config, outputs)
    for norm in (net.down_sampler.net1[1], net.down_sampler.net2[1]):
        norm.running_mean.normal_()
        norm.running_var.uniform_(0.5, 2.0)
    state = {}
    for key, value in net.state_dict().items():
        for new, old in V4_NAMES.items():
            key = key.replace(new, old)
        state[key] = value
    weights = directory / "dino_weight.pt"
    torch.save(state, weights)
    return weights, config_dir


# Qwen-VL's chat specials, in the order the real vocabulary has them after its text tokens.
QWEN_SPECIALS = [
    "<|endoftext|>",
    "<|im_start|>",
    "<|im_end|>",
    "<|vision_start|>",
    "<|vision_end|>",
    "<|image_pad|>",
    "<|video_pad|>",
]
# Qwen-VL's chat layout (system, then user turns whose images come as
# <|vision_start|><|image_pad|><|vision_end|> before or between the text parts): our own template,
# which also reads OpenAI-style ``image_url`` parts, as ``transformers serve`` passes them on.
QWEN_CHAT_TEMPLATE = (
    "{% for message in messages %}<|im_start|>{{ message['role'] }}\n"
    "{% if message['content'] is string %}{{ message['content'] }}"
    "{% else %}{% for part in message['content'] %}"
    "{% if part['type'] in ('image', 'image_url') %}<|vision_start|><|image_pad|><|vision_end|>"
    "{% elif part['type'] == 'text' %}{{ part['text'] }}{% endif %}"
    "{% endfor %}{% endif %}<|im_end|>\n{% endfor %}"
    "{% if add_generation_prompt %}<|im_start|>assistant\n{% endif %}"
)
# What tiny_qwen_vl builds: kind -> the vision tower's patch size (pixels).
TINY_QWEN_VL = {"qwen3-vl": 16, "qwen2.5-vl": 14}


def _qwen_tokenizer():
    """A byte-level Qwen2 tokenizer (a token per byte, no merges) with Qwen's chat specials and
    :data:`QWEN_CHAT_TEMPLATE`, and the specials' ids."""
    from tokenizers.pre_tokenizers import ByteLevel
    from transformers import Qwen2Tokenizer

    vocab = {piece: i for i, piece in enumerate(sorted(ByteLevel.alphabet()))}
    tokenizer = Qwen2Tokenizer(vocab=vocab, merges=[], unk_token=None, pad_token="<|endoftext|>", eos_token="<|im_end|>")
    tokenizer.add_special_tokens({"additional_special_tokens": QWEN_SPECIALS})
    tokenizer.chat_template = QWEN_CHAT_TEMPLATE
    return tokenizer, {name: tokenizer.convert_tokens_to_ids(name) for name in QWEN_SPECIALS}


def _qwen_text(tokenizer, ids: dict[str, int]) -> dict:
    """The tiny language model's config fields (hidden 32, 2 layers, 2 key-value heads of 8)."""
    return TOWER | {
        "vocab_size": len(tokenizer),
        "num_key_value_heads": 2,
        "head_dim": 8,
        "max_position_embeddings": 2048,
        "pad_token_id": ids["<|endoftext|>"],
        "eos_token_id": ids["<|im_end|>"],
        "bos_token_id": None,
    }


def tiny_qwen_vl(directory: str | Path, kind: str = "qwen3-vl", seed: int = 0) -> Path:
    """Write a tiny random-weight Qwen3-VL or Qwen2.5-VL (``kind``, a key of
    :data:`TINY_QWEN_VL`) into ``directory``: config, weights, a byte-level tokenizer with
    Qwen's chat specials and template, and the image processor (images are resized to 2 x 2 up to
    4 x 4 patches: 1 to 4 tokens after the 2 x 2 merge). About 150k parameters. Returns the folder."""
    import transformers as tf
    from transformers.models.qwen2_vl.image_processing_pil_qwen2_vl import Qwen2VLImageProcessorPil

    if kind not in TINY_QWEN_VL:
        raise ValueError(f"no tiny Qwen-VL {kind!r}; expected one of {list(TINY_QWEN_VL)}")
    directory = Path(directory)
    torch.manual_seed(seed)
    tokenizer, ids = _qwen_tokenizer()
    patch = TINY_QWEN_VL[kind]
    text = _qwen_text(tokenizer, ids)
    vision = {"depth": 2, "hidden_size": WIDTH, "intermediate_size": 64, "num_heads": 4, "patch_size": patch}
    vision |= {"out_hidden_size": WIDTH, "spatial_merge_size": 2}
    tokens = {
        "image_token_id": ids["<|image_pad|>"],
        "video_token_id": ids["<|video_pad|>"],
        "vision_start_token_id": ids["<|vision_start|>"],
        "vision_end_token_id": ids["<|vision_end|>"],
    }
    if kind == "qwen3-vl":
        text["rope_parameters"] = {"rope_type": "default", "mrope_section": [2, 1, 1], "mrope_interleaved": True}
        vision |= {"num_position_embeddings": 64, "deepstack_visual_indexes": [1]}
        config = tf.Qwen3VLConfig(text_config=text, vision_config=vision, **tokens)
        model_class = tf.Qwen3VLForConditionalGeneration
    else:
        text["rope_parameters"] = {"rope_type": "default", "mrope_section": [2, 1, 1]}
        vision |= {"window_size": 4 * patch, "fullatt_block_indexes": [1]}
        config = tf.Qwen2_5_VLConfig(text_config=text, vision_config=vision, **tokens)
        model_class = tf.Qwen2_5_VLForConditionalGeneration
    model = model_class(config)
    model.generation_config.eos_token_id = ids["<|im_end|>"]
    model.generation_config.pad_token_id = ids["<|endoftext|>"]
    side = 4 * patch
    processor = Qwen2VLImageProcessorPil(patch_size=patch, merge_size=2, min_pixels=(2 * patch) ** 2, max_pixels=side * side)
    with quiet_transformers():
        model.save_pretrained(directory)
        tokenizer.save_pretrained(directory)
        processor.save_pretrained(directory)
    return directory


def tiny_qwen3_vl(directory: str | Path, seed: int = 0) -> Path:
    """A tiny random-weight Qwen3-VL in ``directory`` (:func:`tiny_qwen_vl`). Returns the folder."""
    return tiny_qwen_vl(directory, "qwen3-vl", seed)


def tiny_qwen3(directory: str | Path, seed: int = 0) -> Path:
    """A tiny random-weight text-only Qwen3 with the tiny Qwen-VL's tokenizer, in ``directory``:
    what ``transformers serve`` can serve without torchvision (it loads a Qwen-VL folder through
    ``AutoProcessor``, whose video processor needs torchvision). Returns the folder."""
    import transformers as tf

    directory = Path(directory)
    torch.manual_seed(seed)
    tokenizer, ids = _qwen_tokenizer()
    model = tf.Qwen3ForCausalLM(tf.Qwen3Config(**_qwen_text(tokenizer, ids)))
    model.generation_config.eos_token_id = ids["<|im_end|>"]
    model.generation_config.pad_token_id = ids["<|endoftext|>"]
    with quiet_transformers():
        model.save_pretrained(directory)
        tokenizer.save_pretrained(directory)
    return directory


def tiny_sam(directory: str | Path, whole_image: bool = False, seed: int = 0) -> Path:
    """A tiny SAM (about 57k parameters: vision hidden 32, 2 layers, 64 px, patch 16; prompt
    encoder and mask decoder hidden 16) with its processor (long side 64, masks 16 px), in a
    ``save_pretrained`` folder. With ``whole_image`` its mask decoder's last layers are set so
    that every pixel's logit is positive: its masks are then the whole image whatever the random
    weights draw, so end-to-end tests do not depend on luck. Returns the folder."""
    from transformers import SamConfig, SamImageProcessorPil, SamModel, SamProcessor
    from transformers.models.sam.configuration_sam import SamMaskDecoderConfig, SamPromptEncoderConfig, SamVisionConfig

    torch.manual_seed(seed)
    vision = SamVisionConfig(
        hidden_size=WIDTH,
        num_hidden_layers=2,
        num_attention_heads=2,
        image_size=64,
        patch_size=16,
        window_size=2,
        global_attn_indexes=[1],
        output_channels=16,
        mlp_dim=64,
        num_pos_feats=8,  # 2 * 8 = the prompt encoder's width
        initializer_range=0.02,  # SAM's default, 1e-10, makes the image embeddings vanish
    )
    prompt = SamPromptEncoderConfig(hidden_size=16, image_size=64, patch_size=16, mask_input_channels=4)
    decoder = SamMaskDecoderConfig(hidden_size=16, num_attention_heads=2, mlp_dim=32, iou_head_hidden_dim=16)
    model = SamModel(SamConfig(vision_config=vision, prompt_encoder_config=prompt, mask_decoder_config=decoder))
    with torch.no_grad():  # initialised to zeros: random, so that the export carries them
        for name, parameter in model.vision_encoder.named_parameters():
            if name == "pos_embed" or "rel_pos" in name:
                parameter.normal_(std=0.02)
    if whole_image:
        with torch.no_grad():
            model.mask_decoder.upscale_conv2.weight.zero_()
            model.mask_decoder.upscale_conv2.bias.fill_(1.0)
            for mlp in model.mask_decoder.output_hypernetworks_mlps:
                mlp.proj_out.weight.zero_()
                mlp.proj_out.bias.fill_(1.0)
    image_processor = SamImageProcessorPil(
        size={"longest_edge": 64},
        pad_size={"height": 64, "width": 64},
        mask_size={"longest_edge": 16},
        mask_pad_size={"height": 16, "width": 16},
    )
    with quiet_transformers():
        model.save_pretrained(directory)
        SamProcessor(image_processor=image_processor).save_pretrained(directory)
    return Path(directory)
