"""The image-text model backends of three roles (``clip``, ``siglip``, ``fg-clip``, ``fg-clip2``):

- ``coarse``: every training view scored against the instruction; the top ``max(1, |views| // 8)``
  go on to Question-Evaluation (the paper's FG-CLIP pre-filter);
- ``scorer``: candidate cameras of the IVS/SVS baselines rendered and scored against the
  instruction;
- ``diff-scorer``: the score of a rendered image tensor, differentiable w.r.t. its pixels (the
  ChatCam-style baseline).

Scores follow the model's convention (:meth:`ImageTextModel.score`: a cosine for CLIP and
FG-CLIP, a sigmoid probability for SigLIP 2 and FG-CLIP 2). A model serving several roles is
loaded once per job. The training views' embeddings are computed once per scene and model and
kept in the per-scene cache, keyed by the model's identity and the views' pictures, so every
instruction on the scene reuses them.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import torch

from ..scene import Camera
from ..scene._io import atomic_write
from .image_text import ImageTextModel
from .protocols import BackendContext, CameraScorer, Question
from .view_images import render_image, training_picture, views_fingerprint

if TYPE_CHECKING:
    from ..translate.instruction import ParsedInstruction
    from ..translate.labels import PseudoLabels


def image_text_model(context: BackendContext, backend: str) -> ImageTextModel:
    """The job's ``backend`` model, loaded on first use from the models config."""
    return context.shared(f"model:{backend}", lambda: ImageTextModel(backend, context.models.settings(backend)))


def view_embeddings(model: ImageTextModel, context: BackendContext) -> np.ndarray:
    """(V, D) normalised embeddings of the scene's training views, from
    ``<cache>/embeddings/<backend>-<key>.npy`` or computed and written there (atomically).

    The key combines the model's identity (weights, ONNX file, dtype) with the views' pictures
    (:func:`~capframe.backends.view_images.views_fingerprint`). Pictures are read in batches, so
    memory holds one batch of photographs at a time.
    """
    scene = context.scene
    path = Path(context.cache_dir) / "embeddings" / f"{model.backend}-{model.identity}-{views_fingerprint(scene)}.npy"
    if path.is_file():
        cached = np.load(path)
        if cached.shape == (len(scene.cameras), model.feature_size):
            return cached
    chunks = []
    for start in range(0, len(scene.cameras), model.batch_size):
        cameras = scene.cameras[start : start + model.batch_size]
        chunks.append(model.embed_images([training_picture(scene, c) for c in cameras]))
    embeddings = np.concatenate(chunks) if chunks else np.zeros((0, model.feature_size), np.float32)
    buffer = io.BytesIO()
    np.save(buffer, embeddings)
    atomic_write(path, buffer.getvalue())
    return embeddings


def keep_for_qe(scores: np.ndarray) -> list[int]:
    """The paper's pre-filter: the top ``max(1, |views| // 8)`` views by score, best first."""
    return [int(v) for v in np.argsort(-scores, kind="stable")[: max(1, len(scores) // 8)]]


class ModelCoarse:
    """Coarse retrieval: the image-text score of every training view with the instruction."""

    def __init__(self, context: BackendContext, backend: str):
        self.context = context
        self.model = image_text_model(context, backend)

    def coarse(self, parsed: ParsedInstruction) -> np.ndarray:
        """(V,) scores of the training views (the model's convention)."""
        views = torch.from_numpy(view_embeddings(self.model, self.context)).to(self.model.device)
        return self.model.score(views, self.model.embed_texts([parsed.text]))[:, 0].cpu().numpy().astype(np.float64)

    def keep(self, scores: np.ndarray) -> list[int]:
        return keep_for_qe(scores)


class ModelScorer:
    """Candidate cameras ranked by the image-text score of their renders with the instruction
    (the paper's IVS/SVS ranking)."""

    def __init__(self, context: BackendContext, backend: str):
        self.scene = context.scene
        self.model = image_text_model(context, backend)

    def scorer(self, parsed: ParsedInstruction, questions: list[Question], labels: PseudoLabels) -> CameraScorer:
        text = self.model.embed_texts([parsed.text])

        def score(cameras: list[Camera]) -> np.ndarray:
            """(N,) scores of the cameras' full-scene renders."""
            images = self.model.embed_images([render_image(self.scene, c) for c in cameras])
            return self.model.score(torch.from_numpy(images).to(text.device), text)[:, 0].cpu().numpy().astype(np.float64)

        return score


class ModelDiffScorer:
    """The image-text score of a rendered image, differentiable w.r.t. its pixels: the model's
    preprocessing on tensors (:mod:`.tensor_images`), its image tower and the instruction's
    embedding (computed once per text)."""

    def __init__(self, context: BackendContext, backend: str):
        self.context = context
        self.model = image_text_model(context, backend)
        self._texts: dict[str, torch.Tensor] = {}

    def _text(self, text: str) -> torch.Tensor:
        if text not in self._texts:
            self._texts[text] = self.model.embed_texts([text])
        return self._texts[text]

    def view_scores(self, text: str) -> np.ndarray:
        """(V,) scores of the scene's training pictures with ``text`` by the same model, without
        gradients (their embeddings from the per-scene cache): the ChatCam-style start."""
        views = torch.from_numpy(view_embeddings(self.model, self.context)).to(self.model.device)
        return self.model.score(views, self._text(text))[:, 0].cpu().numpy().astype(np.float64)

    def score(self, image: torch.Tensor, text: str) -> torch.Tensor:
        """image (H, W, 3) in [0, 1] -> scalar score (the model's convention), with gradients
        to the image."""
        embedding = self.model.differentiable_embeddings(image.permute(2, 0, 1)[None])
        return self.model.score(embedding, self._text(text))[0, 0]
