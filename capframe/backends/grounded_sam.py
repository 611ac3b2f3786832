"""The ``grounded-sam`` segmenter: GroundingDINO boxes for the subject's name, SAM masks from them.

The paper's choices (its Grounded SAM step): the phrase is the subject's name, boxes scoring
below 0.3 are dropped, the best box per label is kept, SAM segments it with a single mask and
the largest outer contour is filled. Both models are transformers checkpoints in local
directories, named by the models config's ``grounding-dino`` and ``sam`` entries; on a CPU
without torchvision transformers uses their PIL image processors.
"""

from __future__ import annotations

import numpy as np
import torch

from ..retrieve.views import VIEWS_LONG_SIDE
from ..translate.instruction import ParsedSubject
from .masks import clip_box, subject_masks
from .models import ModelSettings
from .protocols import BackendContext, SubjectMasks
from .sam import ENTRY as SAM_ENTRY
from .sam import SamBoxes
from .views import view_image
from .weights import load_transformers

ENTRY = "grounding-dino"  # the models-config entry
BOX_THRESHOLD = 0.3  # the paper's box score threshold (the entry's ``threshold`` overrides it)


class GroundingDino:
    """Open-vocabulary boxes: the best-scoring box of a phrase in each image.

    Args:
        settings: the ``grounding-dino`` entry (``weights``: a transformers GroundingDINO
            directory; device, dtype, batch size, threshold).
    """

    def __init__(self, settings: ModelSettings):
        from transformers import GroundingDinoForObjectDetection

        self.model, self.processor = load_transformers(ENTRY, settings, "grounding-dino", GroundingDinoForObjectDetection)
        self.batch_size = settings.batch_size
        self.threshold = BOX_THRESHOLD if settings.threshold is None else settings.threshold

    def best_boxes(self, images: list[np.ndarray], phrase: str) -> list[np.ndarray | None]:
        """Per image (H, W, 3) uint8 RGB, the (4,) x0, y0, x1, y1 pixel box of ``phrase`` with the
        highest score at or above the threshold, or None."""
        text = phrase.lower().strip().rstrip(".") + "."  # GroundingDINO reads lower-case phrases ending with "."
        boxes: list[np.ndarray | None] = []
        for start in range(0, len(images), self.batch_size):
            batch = images[start : start + self.batch_size]
            inputs = self.processor(images=batch, text=[text] * len(batch), return_tensors="pt")
            inputs = {k: v.to(self.model.device) for k, v in inputs.items()}
            inputs["pixel_values"] = inputs["pixel_values"].to(self.model.dtype)
            with torch.no_grad():
                outputs = self.model(**inputs)
            results = self.processor.post_process_grounded_object_detection(
                outputs, inputs["input_ids"], threshold=self.threshold, target_sizes=[im.shape[:2] for im in batch]
            )
            for image, result in zip(batch, results):
                scores = result["scores"]
                best = result["boxes"][scores.argmax()].float().cpu().numpy() if len(scores) else None
                boxes.append(None if best is None else clip_box(best, *image.shape[:2]))
        return boxes


class GroundedSamSegmenter:
    """GroundingDINO + SAM masks of a subject in the views (the :class:`Segmenter` protocol).

    Args:
        context: the job's context; its models config needs ``grounding-dino`` and ``sam``.
    """

    def __init__(self, context: BackendContext):
        self.context = context
        detector, sam = context.models.settings(ENTRY), context.models.settings(SAM_ENTRY)  # both entries before any load
        self.detector = GroundingDino(detector)
        self.sam = SamBoxes(sam)

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks:
        """The subject's masks at the association's measurement resolution, in the views where
        GroundingDINO found it."""
        images = {v: view_image(self.context, v) for v in view_indices}
        boxes = self.detector.best_boxes([images[v] for v in view_indices], subject.name)
        found = {v: box[None] for v, box in zip(view_indices, boxes) if box is not None}
        masks = {v: m[0] for v, m in self.sam.masks(images, found).items()}
        size = self.context.scene.cameras[view_indices[0]].with_long_side(VIEWS_LONG_SIDE)
        return subject_masks(view_indices, masks, size.height, size.width)
