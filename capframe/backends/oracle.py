"""The oracle backends: perception from the scene's semantic labels (the embedded tier).

Every role but the parser has one here. They read the per-scene label renders of the training
views (:mod:`capframe.retrieve.views`, cached per scene), the per-Gaussian label ids and the
sidecar's annotated fronts; the state is built once per job and shared by the roles. The ``knn``
associator goes the model tier's way and reads no labels: a segmenter's 2D masks back-projected
with the views' rendered depth and matched to Gaussian means.

This is perception with perfect labels (DESIGN §4): results obtained with it measure the rest of
the method, and are reported as such.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..retrieve.qe import GeometricQE, SubjectGeometry, coarse_keep, coarse_scores, questions_for
from ..retrieve.views import VIEWS_LONG_SIDE, cached_view_measurements, measure_views
from ..scene import Camera
from ..translate.grounding import ground_by_labels, ground_by_masks
from ..translate.instruction import ParsedInstruction, ParsedSubject
from ..translate.labels import PseudoLabels
from .protocols import BackendContext, Grounding, Question, SubjectMasks
from .views import view_camera, view_depth


class SceneLabels:
    """The labelled scene as the oracle backends read it: the training views' label renders
    (``views``), each object's Gaussians, centroid and front (``by_label``) and QE's geometry."""

    def __init__(self, context: BackendContext):
        scene = context.scene
        if scene.semantics is None or scene.gaussians is None or scene.gaussians.labels is None:
            raise InputError(
                "has no semantic sidecar (semantics.json + labels.npy); the oracle backends read its labels",
                source=str(scene.root),
            )
        self.scene = scene
        self.up = context.up
        self.views = cached_view_measurements(scene, context.cache_dir)
        means = scene.gaussians.means.detach()
        self.by_label = {
            o.name: ground_by_labels(o.name, scene.gaussians.labels, means, scene.semantics) for o in scene.semantics
        }
        geometry = {name: SubjectGeometry(g.centroid, g.front) for name, g in self.by_label.items()}
        self.qe = GeometricQE(self.views, geometry, context.up)


def scene_labels(context: BackendContext) -> SceneLabels:
    """The context's :class:`SceneLabels`, built on first use."""
    return context.shared("oracle-labels", lambda: SceneLabels(context))


class OracleCoarse:
    """Coarse score: the subjects' visible, in-frame share per training view."""

    def __init__(self, context: BackendContext):
        self.labels = scene_labels(context)

    def coarse(self, parsed: ParsedInstruction) -> np.ndarray:
        return coarse_scores(self.labels.views, [s.name for s in parsed.subjects])

    def keep(self, scores: np.ndarray) -> list[int]:
        return coarse_keep(scores)


class OracleQE:
    """QE answered geometrically from the label renders (:class:`~capframe.retrieve.qe.GeometricQE`)."""

    def __init__(self, context: BackendContext):
        self.labels = scene_labels(context)

    def questions(self, parsed: ParsedInstruction) -> list[Question]:
        return self.labels.qe.questions(parsed)

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        return self.labels.qe.answer(questions, view_indices)


class OracleSegmenter:
    """The subject's label maps in the views that show it (all the views when none does)."""

    def __init__(self, context: BackendContext):
        self.labels = scene_labels(context)

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks:
        views = self.labels.views
        o = views.object_index(subject.name)
        shown = [v for v in view_indices if views.pixels[v, o] > 0] or list(view_indices)
        return SubjectMasks(shown, np.stack([views.label_map[v] == o for v in shown]))


class OracleAssociator:
    """The subject's Gaussians by label id."""

    needs_masks = False

    def __init__(self, context: BackendContext):
        self.labels = scene_labels(context)

    def associate(self, subject: ParsedSubject, masks: SubjectMasks | None) -> Grounding:
        return self.labels.by_label[subject.name]


class MaskAssociator:
    """The subject's Gaussians from its masks: each mask back-projected with its view's rendered
    depth, the nearest Gaussian means of those points (the paper's association step). It reads
    no labels: any segmenter's masks, at any resolution, on any scene."""

    needs_masks = True

    def __init__(self, context: BackendContext):
        self.context = context

    def associate(self, subject: ParsedSubject, masks: SubjectMasks | None) -> Grounding:
        if masks is None:
            raise InputError(f"--associator knn needs the segmenter's masks of {subject.name!r}; run capframe segment first")
        _, H, W = masks.masks.shape
        return ground_by_masks(
            subject.name,
            list(masks.masks),
            [view_depth(self.context, v, H, W) for v in masks.views],
            [view_camera(self.context, v, H, W) for v in masks.views],
            self.context.scene.gaussians.means.detach(),
        )


class OracleOrientation:
    """The front annotated in the semantic sidecar (None for a symmetric subject)."""

    needs_masks = False

    def __init__(self, context: BackendContext):
        self.labels = scene_labels(context)

    def front(self, subject: ParsedSubject, view_indices: list[int], masks: SubjectMasks | None) -> np.ndarray | None:
        return self.labels.by_label[subject.name].front


class OracleScorer:
    """Scores candidate cameras the way Retrieve scores a training view: the mean QE answer of the
    camera's label render (the paper ranks IVS/SVS candidates by FG-CLIP similarity instead)."""

    def __init__(self, context: BackendContext, long_side: int = VIEWS_LONG_SIDE):
        self.labels = scene_labels(context)
        self.long_side = long_side

    def scorer(self, parsed: ParsedInstruction, questions: list[Question], labels: PseudoLabels) -> QEScorer:
        """A :class:`QEScorer` of ``questions``; when none of them has a geometric answer (a
        model's questions may all be ``overall``), of the questions the oracle asks itself
        (:func:`~capframe.retrieve.qe.questions_for`)."""
        if all(q.kind == "overall" for q in questions):
            questions = questions_for(parsed)
        return QEScorer(self.labels.scene, questions, labels, self.long_side)


class QEScorer:
    """Mean QE answer (0-100) of each camera, from its label render.

    Args:
        scene: the scene (Gaussians with labels and a semantic sidecar).
        questions: the instruction's QE questions (those Retrieve asked).
        labels: the pseudo labels of Translate; their subject centroids and fronts are the
            subject geometry the view and elevation questions are answered with.
        long_side: measurement resolution (that of the training-view measurements).
    """

    def __init__(self, scene, questions: list[Question], labels: PseudoLabels, long_side: int = VIEWS_LONG_SIDE):
        self.scene, self.questions, self.long_side, self.up = scene, questions, long_side, labels.up
        self.geometry = {s.name: SubjectGeometry(s.centroid, s.front) for s in labels.subjects}

    def answers(self, cameras: list[Camera]) -> np.ndarray:
        """(N, Q) answers of the N cameras (all of one image size)."""
        views = measure_views(self.scene, self.long_side, cameras=cameras, objects=list(self.geometry))
        return GeometricQE(views, self.geometry, self.up).answer(self.questions, list(range(len(cameras))))

    def __call__(self, cameras: list[Camera]) -> np.ndarray:
        """(N,) scores."""
        return self.answers(cameras).mean(1)
