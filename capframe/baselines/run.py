"""``capframe baseline {ivs,svs,splatraj,chatcam}``: the method's Parse / Retrieve / Translate (as in
``capframe ground``), then a baseline's pose search instead of Refine.

Writes into the output folder, atomically as one folder (nothing is written on an input error):

* ``result.json``: ``T_cw``, ``K``, ``width``, ``height`` (readable by ``capframe check``), the
  method, the parsed instruction, the retrieved views, the search (candidate count and the best
  candidates for IVS/SVS; iterations and losses for SplaTraj and ChatCam), the chosen camera's
  ``score`` by the candidate scorer (for SplaTraj and ChatCam measured after the fact, for
  comparison only) and per-stage wall
  times with ``total_s``;
* ``render.png``: the chosen frame at full resolution;
* ``camera.json``: the chosen camera.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..backends import CameraScorer, DifferentiableScorer, Question, backend_names
from ..errors import InputError
from ..pipeline import GroundOptions, Job, StageClock, open_job, stages
from ..pipeline.outputs import write_camera_result
from ..refine.optimize import RefineResult
from ..render import render
from ..scene import Camera, SceneDir, scene_scale
from ..scene._io import atomic_directory
from ..translate.labels import PseudoLabels
from .candidates import ivs_candidates, svs_candidates
from .chatcam import ChatCamConfig, chatcam_pose
from .scoring import best_candidate
from .splatraj import SplaTrajConfig, splatraj_pose

METHODS = ("ivs", "svs", "splatraj", "chatcam")
MAX_VIEWS = 13  # L = min(13, N) retrieved views for IVS (paper supplement)
TOP_CANDIDATES = 5  # best IVS/SVS candidates listed in result.json
MIN_RADIUS = 1e-3  # of the scene scale: the SVS sphere of a point-like subject


@dataclass
class BaselineOptions:
    """Options of :func:`run_baseline`.

    Attributes:
        seed: seed of the SVS samples.
        max_views: IVS interpolates between ``L = min(max_views, N)`` retrieved views; SVS
            samples as many poses as IVS interpolates, ``3 L (L - 1) / 2`` (at least one).
        splatraj: settings of the SplaTraj-style optimiser.
        chatcam: settings of the ChatCam-style optimiser (Refine's step budget and resolution).
        stages: backends, cache and gravity of the shared stages (as ``capframe ground``).
    """

    seed: int = 0
    max_views: int = MAX_VIEWS
    splatraj: SplaTrajConfig = field(default_factory=SplaTrajConfig)
    chatcam: ChatCamConfig = field(default_factory=ChatCamConfig)
    stages: GroundOptions = field(default_factory=GroundOptions)


def search_ranking(coarse: list[float], ranked: list[int]) -> list[int]:
    """Every training view, best first: Retrieve's QE ranking of the views it kept (``ranked``),
    then the others by ``coarse`` score (the kept views are the coarse top M, so the top L of this
    ranking is the coarse top L whenever L >= M)."""
    return ranked + [int(v) for v in np.argsort(-np.asarray(coarse), kind="stable") if int(v) not in ranked]


@dataclass
class Search:
    """What a baseline's pose search reads: the scene, every training view best first (Retrieve's
    ranking), the pseudo labels, the candidate scorer, the options and the clock; the instruction
    and the differentiable scorer for ChatCam (None for the others)."""

    scene: SceneDir
    ranking: list[int]
    labels: PseudoLabels
    scorer: CameraScorer
    options: BaselineOptions
    clock: StageClock
    text: str
    diff: DifferentiableScorer | None = None

    def unpack(self) -> tuple[SceneDir, list[int], PseudoLabels, CameraScorer, BaselineOptions, StageClock]:
        return self.scene, self.ranking, self.labels, self.scorer, self.options, self.clock


def _select(candidates: list[Camera], scorer: CameraScorer, clock: StageClock) -> tuple[Camera, float, list[dict]]:
    """The best candidate, its score and the :data:`TOP_CANDIDATES` best with their scores."""
    best, scores = best_candidate(candidates, scorer)
    clock.done("score", f"best {candidates[best].name}: {scores[best]:.1f}")
    order = np.argsort(-scores, kind="stable")[:TOP_CANDIDATES]
    top = [{"name": candidates[i].name, "score": float(scores[i]), "T_cw": candidates[i].T_cw.tolist()} for i in order]
    return candidates[best], float(scores[best]), top


def _ivs(search: Search) -> tuple[Camera, float, dict]:
    scene, ranking, labels, scorer, options, clock = search.unpack()
    views = ranking[: min(options.max_views, len(scene.cameras))]
    candidates = ivs_candidates([scene.cameras[v] for v in views])
    clock.done("candidates", f"{len(candidates)} poses between the top {len(views)} views")
    camera, score, top = _select(candidates, scorer, clock)
    return camera, score, {"views": [scene.cameras[v].name for v in views], "candidates": len(candidates), "best": top}


def _svs(search: Search) -> tuple[Camera, float, dict]:
    scene, ranking, labels, scorer, options, clock = search.unpack()
    L = min(options.max_views, len(scene.cameras))
    means = scene.gaussians.means.detach().double().numpy()[np.concatenate([s.gaussians for s in labels.subjects])]
    centre = means.mean(0)
    radius = max(
        float(np.linalg.norm(means - centre, axis=1).max()), MIN_RADIUS * scene_scale(scene.cameras, scene.gaussians.means)
    )
    candidates = svs_candidates(centre, radius, labels.up, scene.cameras[0], max(1, 3 * L * (L - 1) // 2), options.seed)
    clock.done("candidates", f"{len(candidates)} poses around the subjects (radius {radius:.3g})")
    camera, score, top = _select(candidates, scorer, clock)
    return (
        camera,
        score,
        {"centre": centre.tolist(), "radius": radius, "candidates": len(candidates), "seed": options.seed, "best": top},
    )


def _splatraj(search: Search) -> tuple[Camera, float, dict]:
    scene, ranking, labels, scorer, options, clock = search.unpack()
    start = scene.cameras[ranking[0]]
    result = splatraj_pose(scene.gaussians, start, labels, scene_scale(scene.cameras, scene.gaussians.means), options.splatraj)
    clock.done(
        "optimise", f"from {start.name}: {result.iterations} iterations, loss {result.losses[0]:.3g} -> {result.losses.min():.3g}"
    )
    return _optimised(start, result, scorer, clock, {"init_view": start.name}, dataclasses.asdict(options.splatraj))


def _chatcam(search: Search) -> tuple[Camera, float, dict]:
    scene, _, labels, scorer, options, clock = search.unpack()
    anchors = search.diff.view_scores(search.text)
    start = scene.cameras[int(np.argmax(anchors))]
    clock.done("anchor", f"{start.name}: {anchors.max():.3g} (best of {len(anchors)} training pictures)")
    # The rotations orbit the subjects' centroid, as Refine's and SplaTraj's (the parametrisation only).
    pivot = scene.gaussians.means.detach().double()[np.concatenate([s.gaussians for s in labels.subjects])].mean(0)
    result = chatcam_pose(
        scene.gaussians,
        start,
        lambda image: search.diff.score(image, search.text),
        pivot.numpy(),
        labels.up,
        scene_scale(scene.cameras, scene.gaussians.means),
        options.chatcam,
    )
    clock.done("optimise", f"{result.iterations} iterations, 1 - score {result.losses[0]:.3g} -> {result.losses.min():.3g}")
    config = {
        "iterations": options.chatcam.descent.iterations,
        "long_side": options.chatcam.descent.long_side,
        "upright": options.chatcam.upright,
    }
    return _optimised(start, result, scorer, clock, {"init_view": start.name, "init_view_score": float(anchors.max())}, config)


def _optimised(
    start: Camera, result: RefineResult, scorer: CameraScorer, clock: StageClock, init: dict, config: dict
) -> tuple[Camera, float, dict]:
    """An optimiser baseline's answer: the camera at ``result``'s pose, its candidate score
    (reported, not used by the search) and the record of the run (``init``: its start)."""
    camera = start.with_pose(result.T_cw)
    score = float(scorer([camera])[0])
    clock.done("score", f"{score:.1f} (not used by the search)")
    record = init | {
        "iterations": result.iterations,
        "stop_reason": result.stop_reason,
        "loss_initial": float(result.losses[0]),
        "loss": float(result.losses.min()),
        "loss_terms": result.terms,
        "config": config,
    }
    return camera, score, record


SEARCHES = {"ivs": _ivs, "svs": _svs, "splatraj": _splatraj, "chatcam": _chatcam}


def _diff_scorer(job: Job) -> DifferentiableScorer:
    """The job's differentiable image-text scorer, loaded before any stage runs (so a missing one
    costs nothing); the embedded tier has none."""
    if "diff-scorer" not in job.backends.choices:
        raise InputError(
            f"baseline 'chatcam' needs a differentiable image-text scorer: --diff-scorer "
            f"{'|'.join(backend_names('diff-scorer'))} with its weights in --models (the embedded tier has none)"
        )
    return job.backends["diff-scorer"]


def run_baseline(
    method: str,
    scene_dir: str | Path,
    text: str,
    out_dir: str | Path,
    options: BaselineOptions | None = None,
    progress: bool = True,
) -> dict:
    """Find the camera for ``text`` with the baseline ``method`` and write it to ``out_dir``.

    Returns the content of ``result.json``.
    """
    if method not in SEARCHES:
        raise InputError(f"baseline {method!r} is unknown; available: {', '.join(METHODS)}")
    options = options or BaselineOptions()
    if options.max_views < 1:
        raise InputError(f"max_views {options.max_views}: must be at least 1")
    clock = StageClock(progress)
    job = open_job(scene_dir, options.stages)
    job.check_final_render()
    diff = _diff_scorer(job) if method == "chatcam" else None
    parsed = stages.parse(job, text, clock)
    coarse = stages.coarse(job, parsed, clock)
    retrieved = stages.qe(job, coarse, options.stages, clock)
    labels = stages.perceive(job, retrieved, options.stages, clock)
    questions = [Question(**q) for q in retrieved.retrieval["questions"]]
    scorer = job.backends["scorer"].scorer(parsed, questions, labels)
    ranking = search_ranking(list(coarse.coarse.values()), job.view_indices([v["view"] for v in retrieved.retrieval["views"]]))
    camera, score, search = SEARCHES[method](Search(job.scene, ranking, labels, scorer, options, clock, parsed.text, diff))
    image = render(job.scene.gaussians, camera).rgb
    clock.done("render", f"{camera.width}x{camera.height}")
    fields = {
        "method": method,
        "score": score,
        "search": search,
        "instruction": parsed.to_dict(),
        "retrieval": {"top": retrieved.top},
        "up": job.up.tolist(),
        "timings": clock.total(),
    }
    with atomic_directory(out_dir) as tmp:
        return write_camera_result(tmp, camera, image, fields)
