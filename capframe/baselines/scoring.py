"""Scorers of the view-search baselines: candidate cameras in, one score per camera out.

The paper ranks IVS and SVS candidates by FG-CLIP text-image similarity (model tier). The
embedded tier scores a candidate the way Retrieve scores a training view: its label render is
measured (:func:`~capframe.retrieve.views.measure_views`) and the instruction's QE questions are
answered from the measurements (:class:`~capframe.retrieve.qe.GeometricQE`); the score is the mean
answer. Any callable ``list[Camera] -> (N,) scores`` can take its place.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..retrieve.qe import GeometricQE, Question, SubjectGeometry
from ..retrieve.views import VIEWS_LONG_SIDE, measure_views
from ..scene import Camera, SceneDir
from ..translate.labels import PseudoLabels

Scorer = Callable[[list[Camera]], np.ndarray]


class QEScorer:
    """Mean QE answer (0-100) of each camera, from its label render.

    Args:
        scene: the scene (Gaussians with labels and a semantic sidecar).
        questions: the instruction's QE questions (those Retrieve asked).
        labels: the pseudo labels of Translate; their subject centroids and fronts are the
            subject geometry the view and elevation questions are answered with.
        long_side: measurement resolution (that of the training-view measurements).
    """

    def __init__(self, scene: SceneDir, questions: list[Question], labels: PseudoLabels, long_side: int = VIEWS_LONG_SIDE):
        self.scene, self.questions, self.long_side, self.up = scene, questions, long_side, labels.up
        self.geometry = {s.name: SubjectGeometry(s.centroid, s.front) for s in labels.subjects}

    def answers(self, cameras: list[Camera]) -> np.ndarray:
        """(N, Q) answers of the N cameras (all of one image size)."""
        views = measure_views(self.scene, self.long_side, cameras=cameras, objects=list(self.geometry))
        return GeometricQE(views, self.geometry, self.up).answer(self.questions, list(range(len(cameras))))

    def __call__(self, cameras: list[Camera]) -> np.ndarray:
        """(N,) scores."""
        return self.answers(cameras).mean(1)


def best_candidate(cameras: list[Camera], scorer: Scorer) -> tuple[int, np.ndarray]:
    """Index of the best-scoring camera (the first of equals) and all (N,) scores."""
    scores = np.asarray(scorer(cameras), dtype=np.float64)
    return int(np.argmax(scores)), scores
