"""``capframe models export``: a model backend's image encoder as an ONNX file, checked against
PyTorch on images of several aspect ratios before it is reported.

SAM's image encoder is its vision encoder with the neck: padded pixel values -> the image
embeddings its mask decoder reads (``SamModel`` needs nothing else from the image; SAM-HQ's
intermediate embeddings do not arise, its checkpoints are not ``sam`` ones)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from .image_text import FAMILIES, ImageTextModel
from .models import ModelSettings, read_models_config
from .onnx import OnnxEncoder, export, parity
from .orient_anything import BACKEND as ORIENT_ANYTHING
from .orient_anything import OrientAnything
from .sam import ENTRY as SAM
from .sam import SamBoxes

EXPORTABLE = (*FAMILIES, ORIENT_ANYTHING, SAM)
# Picture sizes (width, height) the parity check runs on: landscape, portrait, square.
CHECK_SIZES = ((64, 48), (40, 72), (56, 56))


def check_images(seed: int = 0) -> list[np.ndarray]:
    """Random (H, W, 3) uint8 pictures of :data:`CHECK_SIZES`."""
    rng = np.random.default_rng(seed)
    return [rng.integers(0, 256, (h, w, 3), dtype=np.uint8) for w, h in CHECK_SIZES]


def encoder_inputs(backend: str, model, images: list[np.ndarray]) -> list[dict[str, torch.Tensor]]:
    """The image encoder's inputs of (H, W, 3) uint8 ``images``, per batch, as ``model`` (the
    backend's PyTorch model) prepares them."""
    if backend == ORIENT_ANYTHING:
        return [{"pixel_values": model.pixel_values(images)}]
    if backend == SAM:
        return [{"pixel_values": model.processor(images=images, return_tensors="pt")["pixel_values"]}]
    return [batch for _, batch in model.model_inputs(images)]


def encoder_of(backend: str, settings: ModelSettings):
    """(model, its weights module, its encoder function, input names, per-batch inputs of the
    check images) of ``backend`` loaded in float32 on the CPU with PyTorch (what is exported)."""
    settings = dataclasses.replace(settings, onnx=None, device="cpu", dtype="float32")
    if backend == ORIENT_ANYTHING:
        model = OrientAnything(settings)
        module, forward, names = model.net, model.net.forward, ["pixel_values"]
    elif backend == SAM:
        model = SamBoxes(settings)
        module, forward, names = model.model, model.model.get_image_embeddings, ["pixel_values"]
    else:
        model = ImageTextModel(backend, settings)
        module, forward, names = model.model, model.image_features, list(model.inputs)
    return model, module, forward, names, encoder_inputs(backend, model, check_images())


def example_inputs(model, names: list[str], batch: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """The first image of ``batch``, for the export to trace; NaFlex patches padded to the
    model's longest sequence (the exported length)."""
    example = {name: batch[name][:1] for name in names}
    longest = model.longest_sequence() if isinstance(model, ImageTextModel) else None
    if longest is not None:
        missing = longest - example["pixel_values"].shape[1]
        example["pixel_values"] = torch.nn.functional.pad(example["pixel_values"], (0, 0, 0, missing))
        example["pixel_attention_mask"] = torch.nn.functional.pad(example["pixel_attention_mask"], (0, missing))
    return example


def export_backend(backend: str, settings: ModelSettings, output: str | Path, threads: int | None = None) -> float:
    """Write ``backend``'s image encoder to ``output`` and return the largest difference between
    onnxruntime's and PyTorch's outputs on the check images."""
    model, module, forward, names, batches = encoder_of(backend, settings)
    export(module, forward, example_inputs(model, names, batches[0]), output)
    encoder = OnnxEncoder(output, names, threads)
    return max(parity(encoder, forward, batch) for batch in batches)


def export_command(backend: str, models: str | Path | None, output: str | Path) -> None:
    """``capframe models export BACKEND --models FILE -o OUT.onnx``."""
    if backend not in EXPORTABLE:
        raise InputError(f"backend {backend!r} has no image encoder to export; exportable: {', '.join(EXPORTABLE)}")
    settings = read_models_config(models).settings(backend)
    difference = export_backend(backend, settings, output, settings.threads)
    print(f"{output}: {backend} image encoder, max |onnxruntime - PyTorch| = {difference:.2e} on {len(CHECK_SIZES)} images")
