"""Scorers of the view-search baselines: candidate cameras in, one score per camera out.

The scorer comes from the image-text scorer role (:class:`~capframe.backends.ImageTextScorer`):
FG-CLIP similarity in the paper, the mean QE answer of a label render with the oracle backend
(:class:`~capframe.backends.oracle.QEScorer`). Any callable ``list[Camera] -> (N,) scores`` can take
its place.
"""

from __future__ import annotations

import numpy as np

from ..backends.protocols import CameraScorer
from ..scene import Camera


def best_candidate(cameras: list[Camera], scorer: CameraScorer) -> tuple[int, np.ndarray]:
    """Index of the best-scoring camera (the first of equals) and all (N,) scores."""
    scores = np.asarray(scorer(cameras), dtype=np.float64)
    return int(np.argmax(scores)), scores
