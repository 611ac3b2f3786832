"""The embedded perception tier: oracle perception from the scene's semantic labels.

It implements :class:`~capframe.backends.CoarseScorer`, :class:`~capframe.backends.QuestionEvaluator`,
:class:`~capframe.backends.SubjectGrounder` and :class:`~capframe.backends.OrientationEstimator`
from the per-scene label-render measurements (:mod:`capframe.retrieve.views`), the per-Gaussian
labels and the sidecar's fronts. With ``masks=True`` grounding goes the model tier's way: the
label maps of the retrieved views act as a segmenter's 2D masks, back-projected with rendered depth
and matched to Gaussian means by KNN.

This is perception with perfect labels (DESIGN §4): results obtained with it measure the rest of
the method, and are reported as such.
"""

from __future__ import annotations

import numpy as np

from ..retrieve.qe import GeometricQE, Question, SubjectGeometry, coarse_scores
from ..retrieve.views import ViewMeasurements
from ..scene import SceneDir
from ..translate.grounding import Grounding, SubjectMasks, ground_by_labels, ground_by_masks
from ..translate.instruction import ParsedInstruction, ParsedSubject


class LabelPerception:
    """Coarse scoring, QE, grounding and orientation from labels.

    Args:
        scene: the loaded scene (Gaussians with labels, cameras, semantics).
        views: its view measurements.
        up: (3,) world up.
        masks: ground through back-projected label masks instead of the label ids.
    """

    def __init__(self, scene: SceneDir, views: ViewMeasurements, up: np.ndarray, masks: bool = False):
        self.scene = scene
        self.views = views
        self.masks = masks
        means = scene.gaussians.means.detach()
        self._by_label = {
            o.name: ground_by_labels(o.name, scene.gaussians.labels, means, scene.semantics) for o in scene.semantics
        }
        geometry = {name: SubjectGeometry(g.centroid, g.front) for name, g in self._by_label.items()}
        self._qe = GeometricQE(views, geometry, up)

    def coarse(self, parsed: ParsedInstruction) -> np.ndarray:
        return coarse_scores(self.views, [s.name for s in parsed.subjects])

    def questions(self, parsed: ParsedInstruction) -> list[Question]:
        return self._qe.questions(parsed)

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        return self._qe.answer(questions, view_indices)

    def front(self, subject: ParsedSubject, view_indices: list[int]) -> np.ndarray | None:
        return self._by_label[subject.name].front

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks | None:
        """With ``masks``: the subject's label maps in the views that show it (all the views when
        none does); else None."""
        if not self.masks:
            return None
        o = self.views.object_index(subject.name)
        views = [v for v in view_indices if self.views.pixels[v, o] > 0] or list(view_indices)
        return SubjectMasks(views, np.stack([self.views.label_map[v] == o for v in views]))

    def associate(self, subject: ParsedSubject, masks: SubjectMasks | None) -> Grounding:
        """The subject's Gaussians by label id, or by back-projecting ``masks`` with the views'
        rendered depth (the model tier's route)."""
        if masks is None:
            return self._by_label[subject.name]
        return ground_by_masks(
            subject.name,
            list(masks.masks),
            [self.views.depth[v] for v in masks.views],
            [self.views.cameras[v] for v in masks.views],
            self.scene.gaussians.means.detach(),
        )
