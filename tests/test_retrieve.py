"""Retrieve (labels tier): view measurements, QE answers, ranking."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _synth_helpers import aim_camera, build_scene, obj

from capframe.retrieve.qe import (
    ADAPTIVE_CUT_POINTS,
    REGION_SCALE,
    VIEW_SCALE_DEG,
    GeometricQE,
    SubjectGeometry,
    questions_for,
    retrieve,
)
from capframe.retrieve.views import cached_view_measurements, load_view_measurements, measure_views, scene_fingerprint
from capframe.scene import load_scene_dir, write_cameras_json
from capframe.translate.instruction import ParsedInstruction, ParsedSubject


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("retrieve") / "scene"
    gt = build_scene(root)
    # Replace the orbit by views with known content: the bear centred from its front, the bear
    # on the right from its left side, the bear from behind, and one looking away from everything.
    bear = obj(gt, "teddy bear")
    cams = [
        aim_camera(gt, bear, azimuth=0, elevation=10, distance=6),
        aim_camera(gt, bear, azimuth=-90, elevation=10, distance=6, point=(0.8, 0.5)),
        aim_camera(gt, bear, azimuth=180, elevation=10, distance=6),
        aim_camera(gt, bear, azimuth=0, elevation=10, distance=6, point=(3.0, 0.5)),
    ]
    for k, c in enumerate(cams):
        c.name = f"v{k}"
    write_cameras_json(cams, root / "cameras.json")
    return root, gt


def _parsed(**cues) -> ParsedInstruction:
    return ParsedInstruction("a test", [ParsedSubject("the bear", "teddy bear", **cues)])


def test_measurements_see_what_the_cameras_were_built_to_see(scene_dir):
    root, _ = scene_dir
    m = measure_views(load_scene_dir(root))
    bear = m.object_index("teddy bear")
    assert m.visible_fraction.shape == (4, 4) and m.label_map.shape == (4, 120, 160)
    assert m.pixels[:3, bear].min() > 50 and m.pixels[3, bear] == 0  # the last view looks away
    assert m.centroid[0, bear] == pytest.approx([0.5, 0.5], abs=0.06)
    assert m.centroid[1, bear] == pytest.approx([0.8, 0.5], abs=0.06)
    assert np.isnan(m.centroid[3, bear]).all()
    # The label map marks the bear where its visible mask is, and depth is valid there.
    assert (m.label_map[0] == bear).sum() > 0.6 * m.pixels[0, bear]
    assert (m.depth[0][m.label_map[0] == bear] > 0).all()


def test_view_cache_is_reused_and_invalidated(scene_dir, tmp_path):
    root, _ = scene_dir
    scene = load_scene_dir(root)
    first = cached_view_measurements(scene, tmp_path)
    assert load_view_measurements(tmp_path / "label_views.npz", scene_fingerprint(scene, 160)) is not None
    np.testing.assert_array_equal(cached_view_measurements(scene, tmp_path).pixels, first.pixels)
    # Other cameras: the cached file is stale.
    moved = load_scene_dir(root)
    moved.cameras[0].T_cw = moved.cameras[1].T_cw.copy()
    assert scene_fingerprint(moved, 160) != scene_fingerprint(scene, 160)
    assert load_view_measurements(tmp_path / "label_views.npz", scene_fingerprint(moved, 160)) is None


def test_questions_cover_every_cue():
    parsed = ParsedInstruction(
        "t",
        [
            ParsedSubject("the bear", "teddy bear", region="right", shot="medium", view="left"),
            ParsedSubject("the vase", "vase", role="secondary", symmetric=True, view="front"),
        ],
        elevation="high angle",
        roll_deg=10.0,
    )
    kinds = [(q.kind, q.subject) for q in questions_for(parsed)]
    assert kinds == [
        ("visible", "teddy bear"),
        ("region", "teddy bear"),
        ("shot", "teddy bear"),
        ("view", "teddy bear"),
        ("visible", "vase"),
        ("elevation", "teddy bear"),
        ("roll", None),
        ("overall", None),
    ]


def _qe(root, gt):
    scene = load_scene_dir(root)
    geometry = {
        o.name: SubjectGeometry(np.asarray(g["center"]), None if g["front"] is None else np.asarray(g["front"]))
        for o, g in zip(scene.semantics, gt["objects"])
    }
    return GeometricQE(measure_views(scene), geometry, np.asarray(gt["up"]))


def test_answers_are_geometric(scene_dir):
    root, gt = scene_dir
    qe = _qe(root, gt)
    questions = questions_for(_parsed(region="right", view="left"))
    answers = qe.answer(questions, [0, 1, 2, 3])
    col = {q.kind: i for i, q in enumerate(questions)}
    assert answers[1, col["region"]] == pytest.approx(100.0)  # centred at x = 0.8
    # Centred at x = 0.5, outside "right" (x >= 0.55): the fall-off of the distance to the box.
    x = qe.views.centroid[0, qe.views.object_index("teddy bear"), 0]
    assert answers[0, col["region"]] == pytest.approx(100 * math.exp(-(((0.55 - x) / REGION_SCALE) ** 2)))
    assert answers[1, col["view"]] == pytest.approx(100.0)  # seen from its left
    # From behind: 90 deg off the left side, 60 beyond the tolerance.
    assert answers[2, col["view"]] == pytest.approx(100 * math.exp(-((60 / VIEW_SCALE_DEG) ** 2)), rel=0.1)
    assert answers[3, col["visible"]] == 0.0 and answers[3, col["overall"]] < 5.0
    assert ((answers >= 0) & (answers <= 100)).all()


def test_view_answers_read_each_sides_tolerance(scene_dir):
    """A slight side accepts 15 degrees, not 30: from the front (view 0) "slightly from the left"
    (-20) is 20 degrees off, 5 beyond; from the left (view 1) it is 70 off, 55 beyond."""
    root, gt = scene_dir
    qe = _qe(root, gt)
    questions = questions_for(_parsed(view="front-slight-left"))
    view = [q.kind for q in questions].index("view")
    answers = qe.answer(questions, [0, 1])[:, view]
    assert answers[0] == pytest.approx(100 * math.exp(-((5 / VIEW_SCALE_DEG) ** 2)), rel=0.05)
    assert answers[1] == pytest.approx(100 * math.exp(-((55 / VIEW_SCALE_DEG) ** 2)), rel=0.05)


def test_elevation_and_roll_answers(scene_dir):
    root, gt = scene_dir
    qe = _qe(root, gt)
    parsed = ParsedInstruction("t", [ParsedSubject("the bear", "teddy bear")], elevation_deg=10.0, roll_deg=20.0)
    questions = questions_for(parsed)
    answers = qe.answer(questions, [0])[0]
    by_kind = dict(zip([q.kind for q in questions], answers))
    assert by_kind["elevation"] == pytest.approx(100.0)  # built at +10 deg
    # Level training view, 20 deg asked: 15 deg beyond the tolerance, one fall-off scale.
    assert by_kind["roll"] == pytest.approx(100 * math.exp(-1.0), rel=0.05)


def test_retrieve_ranks_the_view_that_satisfies_the_instruction_first(scene_dir):
    root, gt = scene_dir
    qe = _qe(root, gt)
    retrieval = retrieve(_parsed(region="right", view="left"), qe_scorer(qe), qe, top_k=2)
    assert retrieval.top[0] == 1
    assert 3 not in retrieval.top
    report = retrieval.to_dict(["v0", "v1", "v2", "v3"])
    assert report["top"][0] == "v1" and report["views"][0]["view"] == "v1"
    assert len(report["views"][0]["answers"]) == len(report["questions"])


class _FixedScores:
    """Coarse scorer and evaluator with given per-view scores (one question)."""

    def __init__(self, scores):
        self.scores = np.asarray(scores, dtype=float)

    def coarse(self, parsed):
        return np.zeros(len(self.scores))

    def questions(self, parsed):
        return questions_for(parsed)[:1]

    def answer(self, questions, views):
        return self.scores[views][:, None]


@pytest.mark.parametrize(
    "scores, top",
    [
        ([20, 90, 60, 55, 10, 5], [1]),  # the best leads by 30 > ADAPTIVE_CUT_POINTS: keep it alone
        ([20, 90, 80, 40, 10, 5], [1, 2]),
        ([90, 89, 88, 87, 86, 85], [0, 1]),  # ties keep the training order
    ],
)
def test_adaptive_cut_keeps_one_dominant_view(scores, top):
    assert ADAPTIVE_CUT_POINTS == 25.0
    fixed = _FixedScores(scores)
    assert retrieve(_parsed(), fixed, fixed, top_k=2).top == top


def qe_scorer(qe: GeometricQE):
    """A coarse scorer over the same measurements (the labels tier's)."""
    from capframe.retrieve.qe import coarse_scores

    class Scorer:
        def coarse(self, parsed):
            return coarse_scores(qe.views, [s.name for s in parsed.subjects])

    return Scorer()
