"""Image-text models loaded from local weights into transformers' native classes: embed images,
embed texts, score; and a differentiable score of a rendered image tensor.

==========  ======================================  =========================================
backend     weights (a ``save_pretrained`` folder)  score of an image and a text
==========  ======================================  =========================================
clip        CLIP (``CLIPModel``; ViT-H/14 for the   cosine of the L2-normalised embeddings,
            benchmark's metric)                     in [-1, 1]
siglip      SigLIP 2 fixed resolution               sigmoid probability
            (``SiglipModel``) or NaFlex             ``sigmoid(cos * exp(logit_scale) +
            (``Siglip2Model``), by ``model_type``   logit_bias)``, in (0, 1)
fg-clip     FG-CLIP v1 into ``CLIPModel``: exactly  cosine, as CLIP (the paper ranks views by
            5 weights beyond it, its long-caption   ``exp(logit_scale) * cos``, the same order)
            path (248 tokens)
fg-clip2    FG-CLIP 2 into ``Siglip2Model`` (its    sigmoid probability, as SigLIP
            short-caption path); its extra heads
            are checked and left out
==========  ======================================  =========================================

No remote code runs (FG-CLIP's own code does not import under transformers 5 and needs
torchvision): the native classes compute FG-CLIP's short path exactly, and the long-caption path
is written here from the released model's definition. Images go through the model's own (PIL)
image processor, or through onnxruntime when the models config names an exported encoder; the
differentiable path repeats the processor's steps on tensors (:mod:`.tensor_images`).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F

from ..errors import InputError
from .models import ModelSettings
from .tensor_images import TensorPreprocess
from .weights import WEIGHT_FILES, quiet_transformers, torch_device_dtype


@dataclass(frozen=True)
class Family:
    """How a backend's weights load and score.

    Attributes:
        model_types: ``model_type`` values of ``config.json`` the backend loads.
        sigmoid: SigLIP's score (a sigmoid probability) instead of the cosine.
        extras: checkpoint weights beyond the native class, required exactly (FG-CLIP).
        extra_prefixes: prefixes of checkpoint weights beyond the native class that are allowed
            and left out (FG-CLIP 2's long, box and dense heads).
        lowercase: captions are lower-cased (FG-CLIP 2 was trained so).
    """

    model_types: tuple[str, ...]
    sigmoid: bool
    extras: tuple[str, ...] = ()
    extra_prefixes: tuple[str, ...] = ()
    lowercase: bool = False


# FG-CLIP v1: the long-caption position tables (248 rows), its projection and two unused scales.
FGCLIP_EXTRAS = (
    "text_model.embeddings.position_embedding_res.weight",
    "text_model.embeddings.position_embedding_ori.weight",
    "text_filip_projection.weight",
    "logit_scale_finegraind",
    "logit_scale_hardneg",
)

FAMILIES = {
    "clip": Family(("clip",), sigmoid=False),
    "siglip": Family(("siglip", "siglip2"), sigmoid=True),
    "fg-clip": Family(("clip",), sigmoid=False, extras=FGCLIP_EXTRAS),
    "fg-clip2": Family(
        ("fgclip2", "siglip2"),
        sigmoid=True,
        extra_prefixes=(
            "longtext_head.",
            "boxtext_head.",
            "dense_feature_head.",
            "text_model.embeddings.position_embedding_res.",
            "text_model.embeddings.position_embedding_ori.",
        ),
        lowercase=True,
    ),
}

# FG-CLIP's long path: positions below this read the original table, the rest the stretched one.
FGCLIP_KEEP_POSITIONS = 20
FGCLIP_LONG_TOKENS = 248

NAFLEX_INPUTS = ("pixel_values", "pixel_attention_mask", "spatial_shapes")
# FG-CLIP 2's patch budget of an image with more than this many patches (else 128), from its README.
FGCLIP2_BUDGETS = ((784, 1024), (576, 784), (256, 576), (128, 256))


def _native(model_type: str):
    """(config class, model class, PIL image processor class) of a ``model_type``."""
    import transformers as tf
    from transformers.models.clip.image_processing_pil_clip import CLIPImageProcessorPil
    from transformers.models.siglip.image_processing_pil_siglip import SiglipImageProcessorPil
    from transformers.models.siglip2.image_processing_pil_siglip2 import Siglip2ImageProcessorPil

    if model_type == "clip":
        return tf.CLIPConfig, tf.CLIPModel, CLIPImageProcessorPil
    if model_type == "siglip":
        return tf.SiglipConfig, tf.SiglipModel, SiglipImageProcessorPil
    return tf.Siglip2Config, tf.Siglip2Model, Siglip2ImageProcessorPil


def model_directory(backend: str, settings: ModelSettings) -> Path:
    """The weights folder of ``backend``: it must hold ``config.json`` and a weights file."""
    if settings.weights is None:
        raise InputError(f"models config entry {backend!r}: the {backend} backend needs weights (a local model folder)")
    path = Path(settings.weights)
    if not path.is_dir():
        raise InputError(f"models config entry {backend!r}: weights folder not found", source=str(path))
    if not (path / "config.json").is_file():
        raise InputError(f"models config entry {backend!r}: no config.json in the weights folder", source=str(path))
    if not any((path / name).is_file() for name in WEIGHT_FILES):
        raise InputError(f"models config entry {backend!r}: no weights file ({', '.join(WEIGHT_FILES)})", source=str(path))
    return path


def fingerprint(*paths: Path | None, extra: str = "") -> str:
    """A short key that changes when any of the files (or the files of a folder) change: their
    names, sizes and modification times (hashing gigabytes of weights per job would cost more
    than the cache saves)."""
    h = hashlib.sha256(extra.encode())
    for path in paths:
        if path is None:
            continue
        files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
        for f in files:
            stat = f.stat()
            h.update(f"{f.resolve()}:{stat.st_size}:{stat.st_mtime_ns}".encode())
    return h.hexdigest()[:16]


def _check_loading(backend: str, family: Family, info: dict, source: str) -> None:
    """One-line errors for a checkpoint that does not fit the configured class: missing or
    reshaped weights (config.json and the weights disagree) and weights of another layout."""
    if info["mismatched_keys"]:
        key, stored, expected = sorted(info["mismatched_keys"])[0]
        raise InputError(
            f"config.json and the weights disagree: {key} is {tuple(stored)} in the weights, {tuple(expected)} by config.json",
            source=source,
        )
    if info["missing_keys"]:
        missing = sorted(info["missing_keys"])
        raise InputError(
            f"wrong checkpoint layout for {backend}: {len(missing)} weights missing, e.g. {missing[0]}", source=source
        )
    unexpected = {k for k in info["unexpected_keys"] if not k.endswith("position_ids")}
    allowed = {k for k in unexpected if k in family.extras or k.startswith(family.extra_prefixes)}
    if unexpected - allowed:
        other = sorted(unexpected - allowed)
        raise InputError(
            f"wrong checkpoint layout for {backend}: {len(other)} weights it does not have, e.g. {other[0]}", source=source
        )
    if family.extras and set(family.extras) - unexpected:
        absent = sorted(set(family.extras) - unexpected)
        raise InputError(
            f"wrong checkpoint layout for {backend}: no {absent[0]} (an FG-CLIP checkpoint has {len(family.extras)} weights "
            "beyond CLIP; a plain CLIP checkpoint is the clip backend's)",
            source=source,
        )


def read_tensors(directory: Path, names: Sequence[str]) -> dict[str, torch.Tensor]:
    """The named tensors of the checkpoint in ``directory`` (single or sharded, safetensors or
    PyTorch pickles, as transformers looks for them), reading only the files that hold them."""
    from safetensors import safe_open

    index = next((directory / n for n in WEIGHT_FILES if n.endswith(".index.json") and (directory / n).is_file()), None)
    if index is not None:
        weight_map = json.loads(index.read_text())["weight_map"]
        files = sorted({weight_map[n] for n in names if n in weight_map})
    else:
        files = [next(n for n in WEIGHT_FILES if (directory / n).is_file())]
    found: dict[str, torch.Tensor] = {}
    for name in files:
        if name.endswith(".safetensors"):
            with safe_open(directory / name, framework="pt") as f:
                found |= {k: f.get_tensor(k) for k in names if k in f.keys()}
        else:
            state = torch.load(directory / name, map_location="cpu", weights_only=True, mmap=True)
            found |= {k: state[k] for k in names if k in state}
    return found


class ImageTextModel:
    """One image-text model of the models config, loaded once per job.

    Args:
        backend: ``clip``, ``siglip``, ``fg-clip`` or ``fg-clip2`` (:data:`FAMILIES`).
        settings: its models-config entry (weights folder, device, dtype, batch size, and an
            optional ONNX image encoder with its thread count).

    Attributes:
        identity: changes whenever the embeddings would (weights, ONNX file, dtype): the key of
            cached view embeddings.
        sigmoid: the score is SigLIP's sigmoid probability (else CLIP's cosine).
    """

    def __init__(self, backend: str, settings: ModelSettings):
        import transformers as tf

        self.backend = backend
        self.family = FAMILIES[backend]
        self.sigmoid = self.family.sigmoid
        directory = model_directory(backend, settings)
        source = str(directory)
        raw = json.loads((directory / "config.json").read_text())
        self.model_type = raw.get("model_type")
        if self.model_type not in self.family.model_types:
            raise InputError(
                f"config.json is a {self.model_type!r} model; the {backend} backend loads {list(self.family.model_types)}",
                source=source,
            )
        config_class, model_class, processor_class = _native(self.model_type)
        self.device, dtype = torch_device_dtype(backend, settings)
        with quiet_transformers():
            config = config_class(**_portable(raw))
            try:
                model, info = model_class.from_pretrained(
                    directory,
                    config=config,
                    local_files_only=True,
                    output_loading_info=True,
                    ignore_mismatched_sizes=True,
                    dtype=dtype,
                )
                self.tokenizer = tf.AutoTokenizer.from_pretrained(directory, local_files_only=True)
                self.processor = processor_class.from_pretrained(directory, local_files_only=True)
            except (OSError, ValueError) as err:
                raise InputError(f"cannot load the {backend} model ({str(err).splitlines()[0]})", source=source) from None
        _check_loading(backend, self.family, info, source)
        self.model = model.to(self.device).eval().requires_grad_(False)
        self.naflex = self.model_type in ("siglip2", "fgclip2")
        self.inputs = NAFLEX_INPUTS if self.naflex else ("pixel_values",)
        self.text_tokens = config.text_config.max_position_embeddings
        self.batch_size = settings.batch_size
        self.preprocess = TensorPreprocess.of(self.processor)
        self.long = self._long_caption_path(directory) if self.family.extras else None
        self.onnx = None
        if settings.onnx:
            from .onnx import OnnxEncoder

            self.onnx = OnnxEncoder(settings.onnx, self.inputs, settings.threads, self.feature_size)
        self.identity = fingerprint(
            directory, Path(settings.onnx) if settings.onnx else None, extra=f"{backend}:{settings.dtype}"
        )

    @property
    def feature_size(self) -> int:
        """D, the size of an embedding."""
        return self.model.config.projection_dim if self.model_type == "clip" else self.model.config.text_config.hidden_size

    # --- texts --------------------------------------------------------------------------------

    def embed_texts(self, texts: Sequence[str]) -> torch.Tensor:
        """(T, D) L2-normalised float32 embeddings of ``texts`` on the model's device. FG-CLIP
        reads a text longer than CLIP's 77 tokens with its long-caption path (248 tokens)."""
        texts = [t.lower() for t in texts] if self.family.lowercase else list(texts)
        out = torch.empty(len(texts), self.feature_size, device=self.device)
        if self.long is not None:
            long = [len(ids) > self.text_tokens for ids in self.tokenizer(texts, verbose=False)["input_ids"]]
        else:
            long = [False] * len(texts)
        for is_long in (False, True):
            rows = [i for i, flag in enumerate(long) if flag == is_long]
            if not rows:
                continue
            length = FGCLIP_LONG_TOKENS if is_long else self.text_tokens
            ids = self.tokenizer(
                [texts[i] for i in rows], padding="max_length", max_length=length, truncation=True, return_tensors="pt"
            )["input_ids"].to(self.device)
            with torch.no_grad():
                # No attention mask: CLIP pools the first end token under a causal mask and
                # SigLIP pools the last position, both as trained, so padding needs none.
                features = self.long(ids) if is_long else self.model.get_text_features(input_ids=ids).pooler_output
            out[rows] = F.normalize(features.float(), dim=-1)
        return out

    def _long_caption_path(self, directory: Path) -> FGCLIPLongText:
        tensors = read_tensors(directory, FGCLIP_EXTRAS[:3])
        return FGCLIPLongText(self.model, *[tensors[k].to(self.device, self.model.dtype) for k in FGCLIP_EXTRAS[:3]])

    # --- images -------------------------------------------------------------------------------

    def image_features(self, *inputs: torch.Tensor) -> torch.Tensor:
        """(B, D) unnormalised image embeddings of model inputs (named as :attr:`inputs`): the
        function the ONNX export writes."""
        return self.model.get_image_features(**dict(zip(self.inputs, inputs))).pooler_output

    def max_patches(self, width: int, height: int) -> int | None:
        """NaFlex: the patch budget of an image. FG-CLIP 2 picks it from the image's own patch
        count (its README's rule), SigLIP 2 uses its processor's."""
        if not self.naflex:
            return None
        if self.backend != "fg-clip2":
            return self.processor.max_num_patches
        p = self.processor.patch_size
        count = (width // p) * (height // p)
        return next((budget for above, budget in FGCLIP2_BUDGETS if count > above), 128)

    def longest_sequence(self) -> int | None:
        """NaFlex: the largest patch budget :meth:`max_patches` gives (an ONNX export's length)."""
        if not self.naflex:
            return None
        return FGCLIP2_BUDGETS[0][1] if self.backend == "fg-clip2" else self.processor.max_num_patches

    def model_inputs(self, images: Sequence[np.ndarray]) -> list[tuple[list[int], dict[str, torch.Tensor]]]:
        """The processor's inputs of ``images`` ((H, W, 3) uint8 each), in batches of at most
        ``batch_size`` images sharing a patch budget: (image indices, inputs) per batch."""
        from PIL import Image

        groups: dict[int | None, list[int]] = {}
        for i, image in enumerate(images):
            groups.setdefault(self.max_patches(image.shape[1], image.shape[0]), []).append(i)
        batches = []
        for budget, members in groups.items():
            for start in range(0, len(members), self.batch_size):
                rows = members[start : start + self.batch_size]
                extra = {"max_num_patches": budget} if budget is not None else {}
                batch = self.processor(images=[Image.fromarray(images[i]) for i in rows], return_tensors="pt", **extra)
                batches.append((rows, {name: batch[name] for name in self.inputs}))
        return batches

    def embed_images(self, images: Sequence[np.ndarray]) -> np.ndarray:
        """(N, D) L2-normalised float32 embeddings of ``images`` ((H, W, 3) uint8 each), by
        onnxruntime when an ONNX encoder is configured."""
        out = np.empty((len(images), self.feature_size), dtype=np.float32)
        for rows, batch in self.model_inputs(images):
            if self.onnx is not None:
                features = torch.from_numpy(self.onnx(batch))
            else:
                with torch.no_grad():
                    features = self.image_features(*[batch[n].to(self.device) for n in self.inputs]).float().cpu()
            out[rows] = F.normalize(features, dim=-1).numpy()
        return out

    def differentiable_embeddings(self, images: torch.Tensor) -> torch.Tensor:
        """(B, D) L2-normalised embeddings of rendered images, differentiable w.r.t. the pixels.

        Args:
            images: (B, 3, H, W) in [0, 1] (any dtype; cast to the model's).
        """
        dtype = self.model.dtype
        budget = self.max_patches(images.shape[-1], images.shape[-2])
        inputs = self.preprocess(images.to(self.device, dtype), max_patches=budget)
        return F.normalize(self.image_features(*[inputs[n] for n in self.inputs]), dim=-1)

    # --- scores -------------------------------------------------------------------------------

    def score(self, image_embeddings: torch.Tensor, text_embeddings: torch.Tensor) -> torch.Tensor:
        """(N, T) scores of N images against T texts from their normalised embeddings: the cosine
        (CLIP, FG-CLIP; in [-1, 1]) or SigLIP's sigmoid probability
        ``sigmoid(cos * exp(logit_scale) + logit_bias)`` (SigLIP 2, FG-CLIP 2; in (0, 1))."""
        cos = image_embeddings @ text_embeddings.to(image_embeddings).T
        if not self.sigmoid:
            return cos
        scale = self.model.logit_scale.to(cos).exp()
        return torch.sigmoid(cos * scale + self.model.logit_bias.to(cos))


def _portable(raw: dict) -> dict:
    """``config.json`` as keyword arguments of a native config class: without the fields that
    name another class (FG-CLIP 2 calls itself ``fgclip2``, with remote-code entries)."""
    drop = ("model_type", "architectures", "auto_map", "transformers_version")
    out = {k: v for k, v in raw.items() if k not in drop}
    for sub in ("text_config", "vision_config"):
        if isinstance(out.get(sub), dict):
            out[sub] = {k: v for k, v in out[sub].items() if k not in drop}
    return out


class FGCLIPLongText(torch.nn.Module):
    """FG-CLIP's long-caption text path on a native ``CLIPModel``: up to 248 tokens.

    Position ``i`` adds row ``i`` of the original table (``position_embedding_ori``) for the
    first 20 positions and of the stretched one (``position_embedding_res``) after; the causal
    text transformer and its final norm are CLIP's own; the first end token's state is
    projected by ``text_filip_projection`` (not ``text_projection``).

    Args:
        model: the loaded ``CLIPModel`` (its text transformer is shared, not copied).
        res, ori: (248, W) position tables; projection: (D, W) weight of the long projection.
    """

    def __init__(self, model, res: torch.Tensor, ori: torch.Tensor, projection: torch.Tensor):
        super().__init__()
        self.text = model.text_model
        keep = torch.arange(len(res), device=res.device)[:, None] < FGCLIP_KEEP_POSITIONS
        self.register_buffer("positions", torch.where(keep, ori, res))
        self.register_buffer("projection", projection)
        self.eos = model.config.text_config.eos_token_id

    def forward(self, ids: torch.Tensor) -> torch.Tensor:
        """ids (T, L <= 248) -> (T, D) unnormalised text embeddings."""
        length = ids.shape[1]
        hidden = self.text.embeddings.token_embedding(ids) + self.positions[:length]
        # Additive causal mask: works with every attention implementation transformers picks.
        blocked = torch.ones(length, length, dtype=torch.bool, device=ids.device).triu(1)
        mask = torch.zeros(length, length, dtype=hidden.dtype, device=ids.device).masked_fill(
            blocked, torch.finfo(hidden.dtype).min
        )
        hidden = self.text.encoder(inputs_embeds=hidden, attention_mask=mask[None, None]).last_hidden_state
        hidden = self.text.final_layer_norm(hidden)
        pooled = hidden[torch.arange(len(ids), device=ids.device), (ids == self.eos).int().argmax(-1)]
        return pooled @ self.projection.T
