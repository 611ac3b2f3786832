"""Retrieve: coarse scoring of the training views, then Question-Evaluation (QE), keep the top K.

QE turns the parsed instruction into explicit questions (is the subject visible? in the asked
region? at the asked size? seen from the asked side? from the asked height? overall?) and answers
each 0-100 per view; a view's score is the mean of its answers. The embedded tier answers from the
label-render measurements (:mod:`capframe.retrieve.views`) and geometry (camera pose, subject
centroid and front, world up); the model tier will ask an MLLM the same questions.

Answers are smooth in the distance to the asked set, so the ranking still prefers the nearest
miss when no view satisfies a question exactly.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
import torch

from ..backends.protocols import Question
from ..constraints import (
    MIN_IN_FRAME_FRACTION,
    REGIONS,
    ROLL_TOLERANCE_DEG,
    SHOT_SIZES,
    VIEW_SIDES,
    min_in_frame_fraction,
    view_tolerance_deg,
)
from ..errors import InputError
from ..geometry import any_horizontal, camera_roll, view_angles
from ..measure import box_distance, interval_distance, wrap_deg
from ..translate.instruction import ParsedInstruction
from .views import ViewMeasurements

# Fall-off scales of the answers outside the asked set: an answer is 100 * exp(-(d / scale)^2).
REGION_SCALE = 0.12  # normalised image units
SHOT_SCALE = 0.15  # frame fraction
VIEW_SCALE_DEG = 45.0
ELEVATION_SCALE_DEG = 20.0
ROLL_SCALE_DEG = 15.0
# Keep the second best view only if its score is within this many points of the best: one view
# that clearly dominates is a better start than a weak runner-up.
ADAPTIVE_CUT_POINTS = 25.0
MIN_COARSE_KEEP = 6


@dataclass
class SubjectGeometry:
    """What QE needs to know of a subject in 3D: its centroid (3,) and front (3,) or None."""

    centroid: np.ndarray
    front: np.ndarray | None


def questions_for(parsed: ParsedInstruction) -> list[Question]:
    """The questions an instruction decomposes into, in a fixed order."""
    out = []
    for s in parsed.subjects:
        out.append(Question("visible", f"Is the {s.mention} visible and not cut off?", s.name, {"shot": s.shot}))
        if s.region:
            out.append(Question("region", f"Is the {s.mention} in the {s.region} of the frame?", s.name, {"region": s.region}))
        if s.shot:
            out.append(Question("shot", f"Is the {s.mention} framed as a {s.shot} shot?", s.name, {"shot": s.shot}))
        if s.view and not s.symmetric:
            out.append(Question("view", f"Is the {s.mention} seen from its {s.view}?", s.name, {"view": s.view}))
    elevation = parsed.constraints().elevation_range()
    if elevation is not None:
        primary = parsed.subjects[0]
        asked = parsed.elevation or f"{parsed.elevation_deg:+g} degrees"
        out.append(
            Question(
                "elevation",
                f"Is the camera at {asked} relative to the {primary.mention}?",
                primary.name,
                {"range_deg": list(elevation)},
            )
        )
    if parsed.roll_deg is not None:
        out.append(Question("roll", f"Is the camera rolled {parsed.roll_deg:+g} degrees?", None, {"roll_deg": parsed.roll_deg}))
    out.append(Question("overall", f"Does the view match: {parsed.text!r}?"))
    return out


def _falloff(distance: float, scale: float) -> float:
    return 100.0 * math.exp(-((distance / scale) ** 2))


class GeometricQE:
    """Answers QE questions from label-render measurements and scene geometry (embedded tier).

    Args:
        views: the scene's :class:`ViewMeasurements`.
        geometry: per subject name, its :class:`SubjectGeometry`.
        up: (3,) world up.
    """

    def __init__(self, views: ViewMeasurements, geometry: dict[str, SubjectGeometry], up: np.ndarray):
        self.views = views
        self.geometry = geometry
        self.up = np.asarray(up, dtype=np.float64)

    questions = staticmethod(questions_for)

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        """(len(view_indices), len(questions)) answers in [0, 100]; ``overall`` is the geometric
        mean of the view's other answers (one failed aspect makes the whole view a poor match), so
        it needs at least one other question."""
        if questions and all(q.kind == "overall" for q in questions):
            raise InputError("overall questions alone have no geometric answer; ask at least one other (visible, region, ...)")
        out = np.zeros((len(view_indices), len(questions)))
        for row, v in enumerate(view_indices):
            for col, q in enumerate(questions):
                if q.kind != "overall":
                    out[row, col] = getattr(self, "_" + q.kind)(v, q)
            others = [c for c, q in enumerate(questions) if q.kind != "overall"]
            overall = [c for c, q in enumerate(questions) if q.kind == "overall"]
            if overall:
                logs = np.log(np.maximum(out[row, others], 1.0) / 100.0)
                out[row, overall] = 100.0 * math.exp(float(logs.mean()))
        return out

    def _o(self, q: Question) -> int:
        return self.views.object_index(q.subject)

    def _visible(self, v: int, q: Question) -> float:
        o = self._o(q)
        if self.views.pixels[v, o] == 0:
            return 0.0
        min_in_frame = min_in_frame_fraction(q.target.get("shot"))
        return 100.0 * self.views.visible_fraction[v, o] * min(1.0, self.views.in_frame[v, o] / min_in_frame)

    def _region(self, v: int, q: Question) -> float:
        x, y = self.views.centroid[v, self._o(q)]
        if math.isnan(x):
            return 0.0
        return _falloff(box_distance(x, y, REGIONS[q.target["region"]]), REGION_SCALE)

    def _shot(self, v: int, q: Question) -> float:
        o = self._o(q)
        if self.views.pixels[v, o] == 0:
            return 0.0
        return _falloff(interval_distance(self.views.extent[v, o], *SHOT_SIZES[q.target["shot"]]), SHOT_SCALE)

    def _angles(self, v: int, name: str) -> tuple[float, float]:
        g = self.geometry[name]
        front = g.front if g.front is not None else any_horizontal(self.up)
        f64 = dict(dtype=torch.float64)
        az, el = view_angles(
            torch.tensor(self.views.cameras[v].center, **f64),
            torch.tensor(g.centroid, **f64),
            torch.tensor(front, **f64),
            torch.tensor(self.up, **f64),
        )
        return math.degrees(float(az)), math.degrees(float(el))

    def _view(self, v: int, q: Question) -> float:
        azimuth, _ = self._angles(v, q.subject)
        deviation = min(abs(wrap_deg(azimuth - a)) for a in VIEW_SIDES[q.target["view"]])
        return _falloff(max(0.0, deviation - view_tolerance_deg(q.target["view"])), VIEW_SCALE_DEG)

    def _elevation(self, v: int, q: Question) -> float:
        _, elevation = self._angles(v, q.subject)
        return _falloff(interval_distance(elevation, *q.target["range_deg"]), ELEVATION_SCALE_DEG)

    def _roll(self, v: int, q: Question) -> float:
        T = torch.as_tensor(self.views.cameras[v].T_cw)
        roll = math.degrees(float(camera_roll(T, torch.as_tensor(self.up))))
        excess = max(0.0, abs(wrap_deg(roll - q.target["roll_deg"])) - ROLL_TOLERANCE_DEG)
        return _falloff(excess, ROLL_SCALE_DEG)


def coarse_scores(views: ViewMeasurements, subjects: list[str]) -> np.ndarray:
    """(V,) cheap relevance of every view: the mean visible, in-frame share of the subjects, with
    their projected size as a small tie-breaker (a text-image similarity prefers views where the
    subject is prominent)."""
    o = [views.object_index(s) for s in subjects]
    shown = views.visible_fraction[:, o] * np.minimum(1.0, views.in_frame[:, o] / MIN_IN_FRAME_FRACTION)
    shown = np.where(views.pixels[:, o] > 0, shown, 0.0)
    return shown.mean(1) + 0.05 * np.minimum(views.extent[:, o], 1.0).mean(1)


@dataclass
class Retrieval:
    """The outcome of Retrieve.

    Attributes:
        coarse: (V,) coarse score of every training view.
        kept: indices of the top-M views by coarse score (best first).
        questions: the QE questions.
        answers: (M, Q) answers of the kept views, rows in ``kept`` order.
        scores: (M,) mean answer per kept view.
        top: indices (into the training views) of the retrieved views, best first.
        evaluator: what a model evaluator records of itself (model, prompt versions, and
            ``reasons``: per kept view, in ``kept`` order, a reason per answer); empty otherwise.
    """

    coarse: np.ndarray
    kept: list[int]
    questions: list[Question]
    answers: np.ndarray
    scores: np.ndarray
    top: list[int]
    evaluator: dict = field(default_factory=dict)

    def ranked(self) -> list[int]:
        """All kept views by QE score, best first (``top`` is a prefix of it)."""
        return [self.kept[i] for i in np.argsort(-self.scores, kind="stable")]

    def to_dict(self, view_names: list[str]) -> dict:
        ranked = np.argsort(-self.scores, kind="stable")
        reasons = self.evaluator.get("reasons")
        out = {
            "questions": [asdict(q) for q in self.questions],
            "views": [
                {
                    "view": view_names[self.kept[i]],
                    "coarse": float(self.coarse[self.kept[i]]),
                    "score": float(self.scores[i]),
                    "answers": [float(a) for a in self.answers[i]],
                    "retrieved": self.kept[i] in self.top,
                }
                | ({"reasons": list(reasons[i])} if reasons else {})
                for i in ranked
            ],
            "top": [view_names[v] for v in self.top],
        }
        if self.evaluator:
            out["evaluator"] = {k: v for k, v in self.evaluator.items() if k != "reasons"}
        return out


def coarse_keep(coarse: np.ndarray) -> list[int]:
    """Indices of the top M views by coarse score, best first: M = |views| / 8, at least
    :data:`MIN_COARSE_KEEP` (all views when there are fewer)."""
    m = min(len(coarse), max(MIN_COARSE_KEEP, math.ceil(len(coarse) / 8)))
    return [int(v) for v in np.argsort(-coarse, kind="stable")[:m]]


def rank_kept(parsed: ParsedInstruction, evaluator, coarse: np.ndarray, kept: list[int], top_k: int = 2) -> Retrieval:
    """Answer the QE questions on the ``kept`` views and keep the top ``top_k`` by mean answer
    (cut to one when the best leads the second by more than :data:`ADAPTIVE_CUT_POINTS`), or as
    the evaluator's own ``cut`` says when it has one (the MLLM's adaptive cut).

    Args:
        evaluator: a :class:`~capframe.backends.QuestionEvaluator`.
        coarse: (V,) coarse score of every training view.
        kept: the views to question (:func:`coarse_keep`).
    """
    questions = evaluator.questions(parsed)
    answers = evaluator.answer(questions, kept)
    scores = answers.mean(1)
    # A model evaluator brings its own cut (the paper's adaptive one on the model's scale) and a
    # record of what answered (model, prompt versions, reasons).
    cut = getattr(evaluator, "cut", None)
    if cut is not None:
        top = [kept[i] for i in cut(scores, top_k)]
    else:
        order = np.argsort(-scores, kind="stable")
        top = [kept[order[0]]]
        for i in order[1:top_k]:
            if scores[order[0]] - scores[i] > ADAPTIVE_CUT_POINTS:
                break
            top.append(kept[i])
    record = evaluator.record() if hasattr(evaluator, "record") else {}
    return Retrieval(coarse, kept, questions, answers, scores, top, record)


def retrieve(parsed: ParsedInstruction, scorer, evaluator, top_k: int = 2) -> Retrieval:
    """Rank the training views for ``parsed``: coarse scores (``scorer``, a
    :class:`~capframe.backends.CoarseScorer`), then QE on the views they keep (:func:`rank_kept`)."""
    coarse = scorer.coarse(parsed)
    return rank_kept(parsed, evaluator, coarse, coarse_keep(coarse), top_k)
