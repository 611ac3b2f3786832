"""SAM: masks from boxes (transformers ``SamModel`` + ``SamProcessor``, from a local directory).

One mask per box, ``multimask_output=False`` (the box is the whole prompt, as in Grounded SAM),
then the largest outer contour filled (:func:`~capframe.backends.masks.fill_largest_contour`).
The image encoder is the expensive part: its embedding of each view is computed once per job and
reused for every subject segmented in that view. With an ONNX file in the entry's ``onnx`` field
(``capframe models export sam``) the embeddings come from onnxruntime and the PyTorch vision
encoder (nearly all of SAM's weights) is dropped; the prompt encoder and mask decoder stay on
PyTorch (they are cheap per box).
"""

from __future__ import annotations

import numpy as np
import torch

from ..errors import InputError
from .masks import fill_largest_contour
from .models import ModelSettings
from .weights import load_transformers

ENTRY = "sam"  # the models-config entry


def sam_input_boxes(boxes: np.ndarray, original_size: list[int], reshaped_size: list[int]) -> torch.Tensor:
    """(B, 4) float64 boxes in SAM's resized input frame (long side 1024), mapped from ``boxes``
    (B, 4) x0, y0, x1, y1 in pixels of an image of ``original_size`` (h, w) resized to
    ``reshaped_size`` (h, w), as ``SamProcessor`` maps them (scaled per axis)."""
    (old_h, old_w), (new_h, new_w) = original_size, reshaped_size
    scale = np.array([new_w / old_w, new_h / old_h, new_w / old_w, new_h / old_h])
    return torch.as_tensor(np.asarray(boxes, dtype=np.float64) * scale)


def sam_onnx_encoder(path: str, config, threads: int | None = None):
    """The :class:`~capframe.backends.onnx.OnnxEncoder` of SAM's exported image encoder at
    ``path``, checked against the model's ``config`` (a ``SamConfig``): one ``pixel_values``
    input, (B, C, h, w) embeddings of the decoder's width and grid. :class:`InputError` naming
    the entry when the file is missing, unreadable or another model's."""
    from .onnx import OnnxEncoder

    try:
        encoder = OnnxEncoder(path, ["pixel_values"], threads)
    except InputError as err:
        raise InputError(f"models config entry {ENTRY!r}: onnx {err}") from None
    grid = config.prompt_encoder_config.image_embedding_size
    expected = [config.vision_config.output_channels, grid, grid]
    shape = encoder.session.get_outputs()[0].shape
    if len(shape) != 4 or list(shape[1:]) != expected:
        raise InputError(
            f"models config entry {ENTRY!r}: onnx {path} outputs {shape}; this SAM's image embeddings are {['batch', *expected]}"
        )
    return encoder


class SamBoxes:
    """SAM prompted with boxes, built from the models config's ``sam`` entry.

    Args:
        settings: the entry (``weights``: a transformers SAM directory; device, dtype; ``onnx``:
            its exported image encoder, run with ``threads`` intra-op threads).
    """

    def __init__(self, settings: ModelSettings):
        from transformers import SamModel

        self.model, self.processor = load_transformers(ENTRY, settings, "sam", SamModel)
        self.batch_size = settings.batch_size
        self.onnx = None
        if settings.onnx:
            self.onnx = sam_onnx_encoder(settings.onnx, self.model.config, settings.threads)
            self.model.vision_encoder = None  # its weights are the encoder's: freed
        self._embeddings: dict[object, tuple[torch.Tensor, torch.Tensor, torch.Tensor]] = {}

    def image_embeddings(self, pixel_values: torch.Tensor) -> torch.Tensor:
        """(B, C, h, w) image embeddings (vision encoder and neck) of (B, 3, S, S) padded pixel
        values, on the model's device and dtype: onnxruntime's when an ONNX file is configured."""
        if self.onnx is not None:
            embeddings = torch.from_numpy(self.onnx({"pixel_values": pixel_values}))
            return embeddings.to(self.model.device, self.model.dtype)
        with torch.no_grad():
            return self.model.get_image_embeddings(pixel_values.to(self.model.device, self.model.dtype))

    def _embed(self, images: dict[object, np.ndarray]) -> None:
        """Image embeddings (with the sizes post-processing needs) of the ``images`` (key ->
        (H, W, 3) uint8 RGB) not embedded yet, ``batch_size`` images per encoder pass."""
        todo = [key for key in images if key not in self._embeddings]
        for start in range(0, len(todo), self.batch_size):
            keys = todo[start : start + self.batch_size]
            inputs = self.processor(images=[images[k] for k in keys], return_tensors="pt")
            embeddings = self.image_embeddings(inputs["pixel_values"])
            for i, key in enumerate(keys):
                self._embeddings[key] = (
                    embeddings[i : i + 1],
                    inputs["original_sizes"][i : i + 1],
                    inputs["reshaped_input_sizes"][i : i + 1],
                )

    def masks(self, images: dict[object, np.ndarray], boxes: dict[object, np.ndarray]) -> dict[object, np.ndarray]:
        """Masks of boxes in images.

        Args:
            images: key (a view index) -> (H, W, 3) uint8 RGB image.
            boxes: key -> (B, 4) boxes x0, y0, x1, y1 in pixels of that image.
        Returns:
            key -> (B, H, W) bool masks, each the largest contour of SAM's mask, filled.
        """
        self._embed({key: images[key] for key in boxes})
        out = {}
        for key, box in boxes.items():
            embedding, original_size, reshaped_size = self._embeddings[key]
            scaled = sam_input_boxes(box, original_size[0].tolist(), reshaped_size[0].tolist())
            with torch.no_grad():
                pred = self.model(
                    image_embeddings=embedding,
                    input_boxes=scaled[None].to(self.model.device, self.model.dtype),
                    multimask_output=False,
                ).pred_masks
            masks = self.processor.image_processor.post_process_masks(pred.float().cpu(), original_size, reshaped_size)[0]
            out[key] = np.stack([fill_largest_contour(m[0].numpy()) for m in masks])  # masks: (B, 1, H, W)
        return out
