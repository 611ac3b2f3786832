"""Orient Anything (V1) as the orientation estimator: DINOv2 + an MLP head read a subject's crop
and classify its azimuth, polar angle, in-plane rotation and a confidence; each retrieved view's
estimate is turned into a world front through that view's camera, and the confident ones are
averaged on the circle.

Checkpoints are the released ``.pt`` state dicts (keys ``dinov2.*`` with transformers-4 names,
``down_sampler.net{1,2}.{0,1}.*``) beside a DINOv2 config folder. Two output layouts were
released, told apart by the head's width:

======  =========================================  ============================
width   bins                                       rotation
======  =========================================  ============================
722     360 azimuth, 180 polar, 180 rotation, 2    ``argmax - 90`` (Dec. 2024)
902     360 azimuth, 180 polar, 360 rotation, 2    ``argmax - 180`` (Oct. 2025)
======  =========================================  ============================

Azimuth is ``argmax`` in [0, 360), polar ``argmax - 90`` in [-90, 90), confidence the first of
the two softmaxed confidence logits. The conversion to a world front is derived in
docs/models.md ("Orient Anything: from an image estimate to a world front").
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import torch
from torch import nn

from ..errors import InputError
from ..scene import Camera
from .models import ModelSettings
from .protocols import BackendContext, SubjectMasks
from .views import view_image
from .weights import quiet_transformers, torch_device_dtype

if TYPE_CHECKING:
    from ..translate.instruction import ParsedSubject

BACKEND = "orient-anything"


@dataclass(frozen=True)
class Layout:
    """An output layout: the rotation bins and the angle of bin 0."""

    rotation_bins: int
    rotation_offset: int

    @property
    def width(self) -> int:
        return 360 + 180 + self.rotation_bins + 2


LAYOUTS = {layout.width: layout for layout in (Layout(180, 90), Layout(360, 180))}

# transformers 5 renamed DINOv2's attention weights (its conversion_mapping.py); a raw state dict
# keeps the old names.
V5_RENAMES = (
    ("attention.attention.query", "attention.q_proj"),
    ("attention.attention.key", "attention.k_proj"),
    ("attention.attention.value", "attention.v_proj"),
    ("attention.output.dense", "attention.o_proj"),
)

# A subject fills this share of its square crop (Orient Anything's resize_foreground ratio).
FILL = 0.85
# Above this elevation the camera looks down (or up) the subject's up axis: azimuth is undefined.
MAX_ELEVATION_DEG = 80.0


@dataclass(frozen=True)
class OrientEstimate:
    """One crop's estimate, in Orient Anything's convention (degrees).

    Attributes:
        azimuth: [0, 360): 0 when the subject faces the camera, 90 when its front points to the
            image's left (the camera then sees the subject's left side).
        polar: [-90, 90): > 0 when the camera looks down on the subject.
        rotation: in-plane rotation of the subject in the image.
        confidence: [0, 1]: how sure the model is that the subject has a front.
    """

    azimuth: float
    polar: float
    rotation: float
    confidence: float


def decode(logits: torch.Tensor) -> list[OrientEstimate]:
    """(B, 722 | 902) head outputs -> B estimates (argmax of each angle's bins)."""
    layout = LAYOUTS[logits.shape[-1]]
    logits = logits.float()
    azimuth = logits[:, :360].argmax(-1)
    polar = logits[:, 360:540].argmax(-1) - 90
    rotation = logits[:, 540 : 540 + layout.rotation_bins].argmax(-1) - layout.rotation_offset
    confidence = torch.softmax(logits[:, -2:], dim=-1)[:, 0]
    return [
        OrientEstimate(float(a), float(p), float(r), float(c))
        for a, p, r, c in zip(azimuth.tolist(), polar.tolist(), rotation.tolist(), confidence.tolist())
    ]


class OrientHead(nn.Module):
    """The released head: Linear-BatchNorm-ReLU, Linear-BatchNorm (width -> outputs)."""

    def __init__(self, width: int, outputs: int):
        super().__init__()
        self.net1 = nn.Sequential(nn.Linear(width, outputs), nn.BatchNorm1d(outputs), nn.ReLU())
        self.net2 = nn.Sequential(nn.Linear(outputs, outputs), nn.BatchNorm1d(outputs))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.net2(self.net1(x))


class OrientAnythingNet(nn.Module):
    """DINOv2 + head, named as the checkpoint names them: pixel values (B, 3, H, W) -> (B, width)
    logits from the CLS token of DINOv2's last (normalised) hidden state."""

    def __init__(self, config, outputs: int):
        super().__init__()
        from transformers import Dinov2Model

        self.dinov2 = Dinov2Model(config)
        self.down_sampler = OrientHead(config.hidden_size, outputs)

    def forward(self, pixel_values: torch.Tensor) -> torch.Tensor:
        return self.down_sampler(self.dinov2(pixel_values=pixel_values).last_hidden_state[:, 0])


def v5_keys(state: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """A released state dict with transformers 5's DINOv2 attention names."""
    out = {}
    for key, value in state.items():
        for old, new in V5_RENAMES:
            key = key.replace(old, new)
        out[key] = value
    return out


def _files(settings: ModelSettings) -> tuple[Path, Path]:
    """(checkpoint, DINOv2 config folder) of the entry, both checked."""
    where = f"models config entry {BACKEND!r}"
    if settings.weights is None or settings.config is None:
        raise InputError(f"{where}: give weights (the .pt checkpoint) and config (the DINOv2 folder)")
    weights, config = Path(settings.weights), Path(settings.config)
    if not weights.is_file():
        raise InputError(f"{where}: checkpoint not found", source=str(weights))
    for name in ("config.json", "preprocessor_config.json"):
        if not (config / name).is_file():
            raise InputError(f"{where}: no {name} in the DINOv2 config folder", source=str(config))
    return weights, config


def load_net(weights: Path, config_dir: Path) -> OrientAnythingNet:
    """The checkpoint at ``weights`` in a DINOv2 built from ``config_dir``; one-line errors for a
    file that is not an Orient Anything checkpoint, an unknown output layout and a config that
    does not fit the weights."""
    from transformers import Dinov2Config

    source = str(weights)
    try:
        state = torch.load(weights, map_location="cpu", weights_only=True)
    except Exception as err:  # pickle and zip errors of a file that is not a state dict
        raise InputError(f"is not a PyTorch state dict ({str(err).splitlines()[0]})", source=source) from None
    head = "down_sampler.net2.0.weight"
    if not isinstance(state, dict) or head not in state:
        raise InputError(f"wrong checkpoint layout: no {head}; not an Orient Anything checkpoint", source=source)
    width = state[head].shape[0]
    if width not in LAYOUTS:
        raise InputError(
            f"wrong checkpoint layout: {width} outputs; Orient Anything releases have {sorted(LAYOUTS)}", source=source
        )
    state = v5_keys(state)
    with quiet_transformers(), torch.device("meta"):
        # On the meta device: no random initialisation of weights that are replaced right away.
        net = OrientAnythingNet(Dinov2Config.from_pretrained(config_dir, local_files_only=True), width)
    expected = net.state_dict()
    missing, unexpected = sorted(set(expected) - set(state)), sorted(set(state) - set(expected))
    if missing or unexpected:
        example = f"missing {missing[0]}" if missing else f"unexpected {unexpected[0]}"
        raise InputError(
            f"wrong checkpoint layout: {len(missing)} weights missing, {len(unexpected)} unexpected ({example})", source=source
        )
    for key, value in expected.items():
        if value.shape != state[key].shape:
            raise InputError(
                f"config.json and the weights disagree: {key} is {tuple(state[key].shape)} in the weights, "
                f"{tuple(value.shape)} by {config_dir / 'config.json'}",
                source=source,
            )
    net.load_state_dict(state, assign=True)
    return net.eval().requires_grad_(False)


class OrientAnything:
    """The model of the models config's ``orient-anything`` entry, loaded once per job: crops in,
    estimates out. With an ONNX file configured the crops run on onnxruntime and the PyTorch
    weights are not loaded (the layout is read from the file's output width).
    """

    def __init__(self, settings: ModelSettings):
        from transformers.models.bit.image_processing_pil_bit import BitImageProcessorPil

        weights, config_dir = _files(settings)
        with quiet_transformers():
            self.processor = BitImageProcessorPil.from_pretrained(config_dir, local_files_only=True)
        self.batch_size = settings.batch_size
        self.net, self.onnx = None, None
        if settings.onnx:
            from .onnx import OnnxEncoder

            self.onnx = OnnxEncoder(settings.onnx, ["pixel_values"], settings.threads)
            width = self.onnx.session.get_outputs()[0].shape[-1]
            if width not in LAYOUTS:
                raise InputError(
                    f"outputs {width} values; Orient Anything's layouts have {sorted(LAYOUTS)}", source=settings.onnx
                )
        else:
            self.device, dtype = torch_device_dtype(BACKEND, settings)
            self.net = load_net(weights, config_dir).to(self.device, dtype)

    def logits(self, pixel_values: torch.Tensor) -> torch.Tensor:
        """(B, 3, H, W) processor output -> (B, width) logits (PyTorch)."""
        return self.net(pixel_values.to(self.device, next(self.net.parameters()).dtype))

    def pixel_values(self, images: list[np.ndarray]) -> torch.Tensor:
        """(B, 3, H, W) processor output of (H, W, 3) uint8 images."""
        from PIL import Image

        return self.processor(images=[Image.fromarray(i) for i in images], return_tensors="pt")["pixel_values"]

    def estimate(self, crops: list[np.ndarray]) -> list[OrientEstimate]:
        """One estimate per crop ((H, W, 3) uint8, the subject on white)."""
        out: list[OrientEstimate] = []
        for start in range(0, len(crops), self.batch_size):
            pixels = self.pixel_values(crops[start : start + self.batch_size])
            if self.onnx is not None:
                logits = torch.from_numpy(self.onnx({"pixel_values": pixels}))
            else:
                with torch.no_grad():
                    logits = self.logits(pixels)
            out += decode(logits)
        return out


def _resized_mask(mask: np.ndarray, width: int, height: int) -> np.ndarray:
    """(H, W) bool mask at another size, nearest neighbour (masks come at the perception's
    measurement resolution, pictures at the camera's)."""
    from PIL import Image

    if mask.shape == (height, width):
        return mask
    return np.asarray(Image.fromarray(mask.astype(np.uint8) * 255).resize((width, height), Image.NEAREST)) > 0


def subject_crop(image: np.ndarray, mask: np.ndarray) -> np.ndarray | None:
    """The subject alone, as Orient Anything reads it: the pixels outside ``mask`` white, cut to
    the mask's box, centred on a white square in which it fills :data:`FILL` of the side.

    Args:
        image: (H, W, 3) uint8.
        mask: (H, W) bool, at the image's size.

    Returns:
        (S, S, 3) uint8, or None for an empty mask.
    """
    rows, cols = np.nonzero(mask)
    if len(rows) == 0:
        return None
    y0, y1, x0, x1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    subject = np.where(mask[y0:y1, x0:x1, None], image[y0:y1, x0:x1], np.uint8(255))
    side = max(1, math.ceil(max(y1 - y0, x1 - x0) / FILL))
    canvas = np.full((side, side, 3), 255, dtype=np.uint8)
    top, left = (side - (y1 - y0)) // 2, (side - (x1 - x0)) // 2
    canvas[top : top + y1 - y0, left : left + x1 - x0] = subject
    return canvas


def subject_direction(camera: Camera, mask: np.ndarray) -> np.ndarray | None:
    """(3,) unit world direction from the subject to the camera: minus the ray through the mask's
    centroid (pixel centres at integer + 0.5), or None for an empty mask.

    Args:
        camera: the view's camera at the mask's image size.
        mask: (H, W) bool.
    """
    rows, cols = np.nonzero(mask)
    if len(rows) == 0:
        return None
    pixel = np.array([cols.mean() + 0.5, rows.mean() + 0.5, 1.0])
    ray = camera.R.T @ np.linalg.solve(camera.K, pixel)
    return -ray / np.linalg.norm(ray)


def world_front(azimuth_deg: float, to_camera: np.ndarray, up: np.ndarray) -> np.ndarray | None:
    """The subject's world front from Orient Anything's azimuth in one view (docs/models.md).

    The camera sits at the design's view azimuth ``phi = -azimuth`` around the subject (the
    model's azimuth grows as the camera moves to the subject's left), so the front is the
    camera's horizontal direction ``h`` turned by ``phi`` about the up:
    ``f = cos(phi) h + sin(phi) (u x h)``.

    Args:
        azimuth_deg: the model's azimuth.
        to_camera: (3,) unit direction from the subject to the camera.
        up: (3,) unit world up.

    Returns:
        (3,) unit front perpendicular to ``up``, or None when the camera is within
        ``90 - MAX_ELEVATION_DEG`` degrees of the up axis (the azimuth means nothing there).
    """
    along = float(to_camera @ up)
    if abs(along) > math.sin(math.radians(MAX_ELEVATION_DEG)):
        return None
    h = to_camera - along * up
    h = h / np.linalg.norm(h)
    phi = -math.radians(azimuth_deg)
    front = math.cos(phi) * h + math.sin(phi) * np.cross(up, h)
    return front / np.linalg.norm(front)


def circular_mean(fronts: list[np.ndarray], weights: list[float]) -> np.ndarray | None:
    """The weighted circular mean of unit fronts (all perpendicular to the up): their weighted
    sum, normalised; None when they cancel out (opposite estimates of equal weight)."""
    if not fronts:
        return None
    total = np.sum([w * f for f, w in zip(fronts, weights)], axis=0)
    norm = float(np.linalg.norm(total))
    return total / norm if norm > 1e-6 * sum(weights) else None


@dataclass
class ViewFront:
    """One retrieved view's reading: the estimate, and the world front it gives (None when the
    view was gated out: low confidence or a camera straight above/below)."""

    view: int
    estimate: OrientEstimate
    front: np.ndarray | None


class OrientAnythingOrientation:
    """The ``orient-anything`` backend: a subject's front from its masks in the retrieved views.

    Per view: the subject cropped from the view's picture with its mask, Orient Anything's
    estimate, gated by ``min_confidence`` (models config), turned into a world front through the
    view's camera; the fronts' circular mean weighted by confidence. None when no view passes.
    """

    needs_masks = True

    def __init__(self, context: BackendContext):
        settings = context.models.settings(BACKEND)
        self.model = context.shared(f"model:{BACKEND}", lambda: OrientAnything(settings))
        self.min_confidence = settings.min_confidence
        self.context, self.scene, self.up = context, context.scene, np.asarray(context.up, dtype=np.float64)

    def view_fronts(self, masks: SubjectMasks) -> list[ViewFront]:
        """Each masked view's estimate and world front (empty masks are skipped). The view's
        picture is the job's (:func:`~capframe.backends.views.view_image`, read once for every
        backend); mask and camera are brought to its size."""
        views, crops, directions = [], [], []
        for view, mask in zip(masks.views, masks.masks):
            image = view_image(self.context, view)
            height, width = image.shape[:2]
            full = _resized_mask(mask, width, height)
            crop = subject_crop(image, full)
            if crop is not None:
                views.append(view)
                crops.append(crop)
                directions.append(subject_direction(self.scene.cameras[view].resized(width, height), full))
        out = []
        for view, estimate, direction in zip(views, self.model.estimate(crops), directions):
            confident = estimate.confidence >= self.min_confidence
            out.append(ViewFront(view, estimate, world_front(estimate.azimuth, direction, self.up) if confident else None))
        return out

    def front(self, subject: ParsedSubject, view_indices: list[int], masks: SubjectMasks | None) -> np.ndarray | None:
        if masks is None:
            raise InputError(f"--orient {BACKEND} needs the segmenter's masks of {subject.name!r}")
        readings = [r for r in self.view_fronts(masks) if r.front is not None]
        return circular_mean([r.front for r in readings], [r.estimate.confidence for r in readings])
