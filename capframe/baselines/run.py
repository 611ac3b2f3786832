"""``capframe baseline {ivs,svs,splatraj}``: the method's Parse / Retrieve / Translate (as in
``capframe ground``), then a baseline's pose search instead of Refine.

Writes into the output folder, atomically as one folder (nothing is written on an input error):

* ``result.json``: ``T_cw``, ``K``, ``width``, ``height`` (readable by ``capframe check``), the
  method, the parsed instruction, the retrieved views, the search (candidate count and the best
  candidates for IVS/SVS; iterations and losses for SplaTraj), the chosen camera's ``score`` by the
  candidate scorer (for SplaTraj measured after the fact, for comparison only) and per-stage wall
  times with ``total_s``;
* ``render.png``: the chosen frame at full resolution;
* ``camera.json``: the chosen camera.
"""

from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..backends import check_perception
from ..errors import InputError
from ..ground import GroundOptions, StageClock, load_scene, make_perception, parse_stage, translate
from ..refine.run import scene_scale, write_camera_result
from ..render import render
from ..retrieve.qe import Retrieval, retrieve
from ..scene import Camera, SceneDir
from ..scene._io import atomic_directory
from ..translate.labels import PseudoLabels
from .candidates import ivs_candidates, svs_candidates
from .scoring import QEScorer, Scorer, best_candidate
from .splatraj import SplaTrajConfig, splatraj_pose

METHODS = ("ivs", "svs", "splatraj")
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
        stages: parser, perception, cache and gravity of the shared stages (as ``capframe ground``).
    """

    seed: int = 0
    max_views: int = MAX_VIEWS
    splatraj: SplaTrajConfig = field(default_factory=SplaTrajConfig)
    stages: GroundOptions = field(default_factory=GroundOptions)


def search_ranking(retrieval: Retrieval) -> list[int]:
    """Every training view, best first: Retrieve's QE ranking of the views it kept, then the
    others by coarse score (the kept views are the coarse top M, so the top L of this ranking
    is the coarse top L whenever L >= M)."""
    ranked = retrieval.ranked()
    return ranked + [int(v) for v in np.argsort(-retrieval.coarse, kind="stable") if int(v) not in ranked]


def _select(candidates: list[Camera], scorer: Scorer, clock: StageClock) -> tuple[Camera, float, list[dict]]:
    """The best candidate, its score and the :data:`TOP_CANDIDATES` best with their scores."""
    best, scores = best_candidate(candidates, scorer)
    clock.done("score", f"best {candidates[best].name}: {scores[best]:.1f}")
    order = np.argsort(-scores, kind="stable")[:TOP_CANDIDATES]
    top = [{"name": candidates[i].name, "score": float(scores[i]), "T_cw": candidates[i].T_cw.tolist()} for i in order]
    return candidates[best], float(scores[best]), top


def _ivs(
    scene: SceneDir, retrieval: Retrieval, labels: PseudoLabels, scorer: Scorer, options: BaselineOptions, clock: StageClock
) -> tuple[Camera, float, dict]:
    views = search_ranking(retrieval)[: min(options.max_views, len(scene.cameras))]
    candidates = ivs_candidates([scene.cameras[v] for v in views])
    clock.done("candidates", f"{len(candidates)} poses between the top {len(views)} views")
    camera, score, top = _select(candidates, scorer, clock)
    return camera, score, {"views": [scene.cameras[v].name for v in views], "candidates": len(candidates), "best": top}


def _svs(
    scene: SceneDir, retrieval: Retrieval, labels: PseudoLabels, scorer: Scorer, options: BaselineOptions, clock: StageClock
) -> tuple[Camera, float, dict]:
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


def _splatraj(
    scene: SceneDir, retrieval: Retrieval, labels: PseudoLabels, scorer: Scorer, options: BaselineOptions, clock: StageClock
) -> tuple[Camera, float, dict]:
    start = scene.cameras[retrieval.top[0]]
    result = splatraj_pose(scene.gaussians, start, labels, scene_scale(scene.cameras, scene.gaussians.means), options.splatraj)
    camera = start.with_pose(result.T_cw)
    clock.done(
        "optimise", f"from {start.name}: {result.iterations} iterations, loss {result.losses[0]:.3g} -> {result.losses.min():.3g}"
    )
    score = float(scorer([camera])[0])
    clock.done("score", f"{score:.1f} (not used by the search)")
    return (
        camera,
        score,
        {
            "init_view": start.name,
            "iterations": result.iterations,
            "stop_reason": result.stop_reason,
            "loss_initial": float(result.losses[0]),
            "loss": float(result.losses.min()),
            "loss_terms": result.terms,
            "config": dataclasses.asdict(options.splatraj),
        },
    )


SEARCHES = {"ivs": _ivs, "svs": _svs, "splatraj": _splatraj}


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
    check_perception(options.stages.perception)
    if options.max_views < 1:
        raise InputError(f"max_views {options.max_views}: must be at least 1")
    clock = StageClock(progress)
    scene, up = load_scene(Path(scene_dir), options.stages)
    parsed = parse_stage(scene, text, options.stages, clock)
    perception = make_perception(scene, up, options.stages)
    clock.done("views", f"{len(scene.cameras)} training views measured (cached per scene)")
    retrieval = retrieve(parsed, perception, perception, options.stages.top_k)
    clock.done("retrieve", "top: " + ", ".join(scene.cameras[v].name for v in retrieval.top))
    labels = translate(parsed, perception, retrieval.top, up)
    clock.done("translate", ", ".join(f"{s.name}: {len(s.gaussians)} Gaussians" for s in labels.subjects))
    # The embedded tier's scorer; the model tier's (FG-CLIP on the colour render) takes its place.
    scorer = QEScorer(scene, retrieval.questions, labels)
    camera, score, search = SEARCHES[method](scene, retrieval, labels, scorer, options, clock)
    image = render(scene.gaussians, camera).rgb
    clock.done("render", f"{camera.width}x{camera.height}")
    fields = {
        "method": method,
        "score": score,
        "search": search,
        "instruction": parsed.to_dict(),
        "retrieval": {"top": [scene.cameras[v].name for v in retrieval.top]},
        "up": up.tolist(),
        "timings": dict(clock.timings, total_s=time.perf_counter() - clock.start),
    }
    with atomic_directory(out_dir) as tmp:
        summary = write_camera_result(tmp, camera, image, fields)
    return summary


def baseline_command(args) -> None:
    """The ``capframe baseline`` verb."""
    options = BaselineOptions(seed=args.seed, stages=GroundOptions(cache_dir=args.cache, gravity=args.gravity))
    result = run_baseline(args.method, args.scene, args.instruction, args.output, options, progress=not args.json)
    if args.json:
        keys = ("T_cw", "K", "width", "height", "method", "score", "timings")
        print(json.dumps({k: result[k] for k in keys}))
    else:
        print(f"{args.output}: {args.method} camera, score {result['score']:.1f}, {result['timings']['total_s']:.1f} s")
