"""A model's image preprocessing on tensors, differentiable: what its (PIL) image processor does
to a picture, done to a rendered image so that gradients reach the pixels.

The transformers image processors work on PIL images and NumPy arrays; a render that must pass
gradients to the camera pose cannot go through them. :class:`TensorPreprocess` reads the
processor's settings and repeats its steps with torch operations:

- ``crop`` (CLIP, FG-CLIP, DINOv2): resize the shorter side, centre crop, normalise;
- ``squash`` (SigLIP fixed resolution): resize to the model's square, normalise;
- ``patches`` (SigLIP 2 NaFlex, FG-CLIP 2): resize to the largest patch grid that fits the patch
  budget keeping the aspect ratio, normalise, cut into flattened patches, pad the sequence.

Resizing uses ``torch.nn.functional.interpolate`` with ``antialias=True``, whose downscaling
filter is PIL's (triangle/cubic kernels widened by the scale factor); kornia's ``resize`` blurs
with a Gaussian before sampling instead, which departed 9x further from CLIP's PIL processor
at an edge (docs/models.md, tests/test_scorers.py), so kornia is not used here.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch
import torch.nn.functional as F

from ..errors import InputError

# PIL resampling filter ids (PIL.Image.Resampling) -> interpolate modes with the same kernel.
RESAMPLE_MODES = {0: "nearest-exact", 2: "bilinear", 3: "bicubic"}


@dataclass(frozen=True)
class TensorPreprocess:
    """A model's image preprocessing, read from its image processor.

    Attributes:
        mode: ``crop``, ``squash`` or ``patches`` (see the module docstring).
        size: ``crop``: the shorter side after resizing; ``squash``: (height, width).
        crop: ``crop``: (height, width) of the centre crop, or None without one.
        resample: interpolate mode of the processor's resampling filter.
        scale: factor from [0, 1] pixel values to the processor's rescaled values (1 for the usual
            ``rescale_factor`` 1/255; 255 when the processor does not rescale).
        mean, std: (3,) normalisation.
        patch_size, max_patches: ``patches``: the patch side and the padded sequence length.
    """

    mode: str
    size: int | tuple[int, int] | None
    crop: tuple[int, int] | None
    resample: str
    scale: float
    mean: tuple[float, float, float]
    std: tuple[float, float, float]
    patch_size: int = 0
    max_patches: int = 0

    @classmethod
    def of(cls, processor) -> TensorPreprocess:
        """The preprocessing of a transformers image processor (CLIP, SigLIP, SigLIP 2, Bit)."""
        resample = RESAMPLE_MODES.get(int(processor.resample))
        if resample is None:
            raise InputError(
                f"image processor resampling {processor.resample!r}: the differentiable path reproduces "
                "nearest, bilinear and bicubic only"
            )
        scale = 255.0 * float(processor.rescale_factor) if processor.do_rescale else 255.0
        common = {
            "resample": resample,
            "scale": scale,
            "mean": tuple(processor.image_mean),
            "std": tuple(processor.image_std),
        }
        if getattr(processor, "max_num_patches", None):
            return cls("patches", None, None, patch_size=processor.patch_size, max_patches=processor.max_num_patches, **common)
        size = processor.size
        crop = (processor.crop_size["height"], processor.crop_size["width"]) if processor.do_center_crop else None
        if "shortest_edge" in size:
            resized = (int(size["shortest_edge"]),) * 2
            out = cls("crop", resized[0], crop, **common)
        else:
            resized = (int(size["height"]), int(size["width"]))
            out = cls("squash", resized, crop, **common)
        if crop is not None and (crop[0] > resized[0] or crop[1] > resized[1]):
            # The processors would pad such an image; no model we load is configured so.
            raise InputError(f"image processor crops {crop} from an image resized to {size}: it would pad")
        return out

    def __call__(self, images: torch.Tensor, max_patches: int | None = None) -> dict[str, torch.Tensor]:
        """The model inputs of ``images``.

        Args:
            images: (B, 3, H, W) pixel values in [0, 1], all of one size.
            max_patches: ``patches``: the sequence length (default :attr:`max_patches`).

        Returns:
            ``pixel_values`` (B, 3, h, w), or for ``patches`` ``pixel_values`` (B, P, p*p*3),
            ``pixel_attention_mask`` (B, P) and ``spatial_shapes`` (B, 2).
        """
        x = images * self.scale
        if self.mode == "patches":
            return self._patches(x, max_patches or self.max_patches)
        if self.mode == "crop":
            x = _resize(x, _shorter_side_size(x.shape[-2], x.shape[-1], self.size), self.resample, self.scale)
        else:
            x = _resize(x, self.size, self.resample, self.scale)
        if self.crop is not None:
            x = _center_crop(x, self.crop)
        return {"pixel_values": self._normalise(x)}

    def _normalise(self, x: torch.Tensor) -> torch.Tensor:
        mean = torch.tensor(self.mean, dtype=x.dtype, device=x.device)[:, None, None]
        std = torch.tensor(self.std, dtype=x.dtype, device=x.device)[:, None, None]
        return (x - mean) / std

    def _patches(self, x: torch.Tensor, max_patches: int) -> dict[str, torch.Tensor]:
        """NaFlex input: the patch grid the processor picks for this aspect ratio (its own
        search, so both paths agree), patches flattened as (row, column, channel)."""
        from transformers.models.siglip2.image_processing_pil_siglip2 import get_image_size_for_max_num_patches

        p = self.patch_size
        height, width = get_image_size_for_max_num_patches(x.shape[-2], x.shape[-1], p, max_patches)
        x = self._normalise(_resize(x, (height, width), self.resample, self.scale))
        b, c, gh, gw = x.shape[0], x.shape[1], height // p, width // p
        patches = x.reshape(b, c, gh, p, gw, p).permute(0, 2, 4, 3, 5, 1).reshape(b, gh * gw, p * p * c)
        padded = F.pad(patches, (0, 0, 0, max_patches - gh * gw))
        mask = torch.zeros(b, max_patches, dtype=torch.long, device=x.device)
        mask[:, : gh * gw] = 1
        shapes = torch.tensor([[gh, gw]] * b, dtype=torch.long, device=x.device)
        return {"pixel_values": padded, "pixel_attention_mask": mask, "spatial_shapes": shapes}


def _shorter_side_size(height: int, width: int, shorter: int) -> tuple[int, int]:
    """(h, w) with the shorter side ``shorter`` and the aspect ratio kept, the longer side
    truncated as transformers' ``get_resize_output_image_size`` does."""
    if height <= width:
        return shorter, int(shorter * width / height)
    return int(shorter * height / width), shorter


def _resize(x: torch.Tensor, size: tuple[int, int], mode: str, top: float) -> torch.Tensor:
    """(B, C, H, W) -> (B, C, *size), PIL-like: antialiased when shrinking, values kept in
    [0, top] (a bicubic kernel overshoots at edges; PIL's 8-bit result cannot); the identity at
    the same size (PIL copies the image then)."""
    if tuple(x.shape[-2:]) == tuple(size):
        return x
    if mode == "nearest-exact":
        return F.interpolate(x, size=size, mode=mode)
    return F.interpolate(x, size=size, mode=mode, align_corners=False, antialias=True).clamp(0.0, top)


def _center_crop(x: torch.Tensor, size: tuple[int, int]) -> torch.Tensor:
    """Centre crop with transformers' offsets ((H - h) // 2); :meth:`TensorPreprocess.of` made
    sure the image is at least the crop's size."""
    h, w = size
    top, left = (x.shape[-2] - h) // 2, (x.shape[-1] - w) // 2
    return x[..., top : top + h, left : left + w]
