"""``capframe ground``: an instruction in, a camera out (Retrieve -> Translate -> Refine).

Writes into the output folder, atomically as one folder (nothing is written on an input error):

* everything ``capframe refine`` writes (``result.json``, ``render.png``, ``camera.json``,
  ``trajectory.npz``, ``losses.csv``, ``path.png``), with ``result.json`` extended by the parsed
  instruction, the retrieval (questions and per-view answers), the chosen initial view, the
  per-clause report and the candidates;
* ``labels.json``: the pseudo labels Refine optimised towards;
* camera exports: ``camera_path.json`` (nerfstudio) and ``colmap_image.txt`` (one ``images.txt`` line);
* with several candidates, ``candidates/<rank>/`` with each one's ``camera.json`` and ``render.png``.

The per-clause report is measured with the method's own pseudo labels (its subject Gaussians,
centroids and fronts, the estimated world up) — what the method believes it achieved, not a
ground-truth verdict (``capframe check`` gives that on synthetic scenes).

Per-scene work (the label renders of the training views) is cached in ``cache_dir``.
"""

from __future__ import annotations

import dataclasses
import json
import random
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from .backends import check_perception, make_parser
from .errors import InputError
from .evaluate.check import CheckReport, ConstraintChecker, format_report
from .evaluate.ground_truth import GTObject
from .geometry import pose_deviation
from .handoff import Coarse, Retrieved, read_fronts, read_groundings, read_masks, write_fronts, write_groundings, write_masks
from .refine.optimize import RefineConfig, RefineResult, refine_pose
from .refine.run import scene_scale, write_camera_result, write_refine_outputs
from .render import render
from .render.image import save_png
from .retrieve.qe import coarse_keep, rank_kept
from .scene import Camera, SceneDir, colmap_image_line, load_scene_dir, write_camera_json, write_camera_path_json
from .scene._io import atomic_directory, write_json
from .translate.grounding import Grounding, SubjectMasks
from .translate.instruction import ParsedInstruction
from .translate.labels import PseudoLabels, labels_from_constraints, write_pseudo_labels
from .translate.vocabulary import Vocabulary

# Two refined poses closer than this are the same candidate.
DISTINCT_ROTATION_DEG = 5.0
DISTINCT_TRANSLATION = 0.05  # of the scene scale


@dataclass
class GroundOptions:
    """Options of :func:`ground`.

    Attributes:
        top_k: retrieved views kept as initialisations.
        seed: picks the first initial view among the top K (as the paper does).
        candidates: refine from this many retrieved views and rank the resulting poses.
        attempts: with one candidate, refine from up to this many retrieved views, stopping at the
            first whose pseudo-label clauses all hold (a start in a bad basin costs a retry, not
            the result; most instructions need one refinement).
        parser: instruction parser backend (``capframe.backends.PARSERS``).
        perception: perception backend (``capframe.backends.PERCEPTIONS``).
        cache_dir: per-scene cache (default ``$XDG_CACHE_HOME/capframe/<scene>``).
        gravity: a gravity file for scenes whose ``scene.json`` has no up.
        drop: ablation: remove the ``layout`` (regions, shot sizes) or ``orientation`` (view side,
            elevation, roll) pseudo labels; the instruction itself is unchanged.
        box_noise: perturb each layout box by this fraction of the frame, in a random direction.
        front_noise_deg: rotate each subject's front about the up by this angle, random sign.
        noise_seed: seed of both perturbations.
        refine: the optimiser's settings.
    """

    top_k: int = 2
    seed: int = 0
    candidates: int = 1
    attempts: int = 3
    parser: str = "rules"
    perception: str = "labels"
    cache_dir: str | Path | None = None
    gravity: str | Path | None = None
    drop: str | None = None
    box_noise: float = 0.0
    front_noise_deg: float = 0.0
    noise_seed: int = 0
    refine: RefineConfig = dataclasses.field(default_factory=RefineConfig)


class StageClock:
    """One line per stage on stderr with its wall time."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.start = self.last = time.perf_counter()
        self.timings: dict[str, float] = {}

    def done(self, stage: str, message: str = "") -> None:
        now = time.perf_counter()
        self.timings[f"{stage}_s"] = now - self.last
        if self.enabled:
            print(f"[{now - self.start:6.1f} s] {stage:<9} {message}", file=sys.stderr, flush=True)
        self.last = now


def default_cache_dir(scene_dir: Path) -> Path:
    import hashlib
    import os

    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "capframe"
    key = hashlib.sha256(str(scene_dir.resolve()).encode()).hexdigest()[:10]
    return base / f"{scene_dir.name}-{key}"


def load_scene(scene_dir: Path, options: GroundOptions) -> tuple[SceneDir, np.ndarray]:
    """The scene and its world up, checked for what grounding needs; :class:`InputError` otherwise."""
    from .geometry.gravity import world_up

    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None:
        raise InputError("has no scene.ply; ground renders the scene", source=str(scene_dir))
    if not scene.cameras:
        raise InputError("has no training cameras; recover them first with `capframe colmap`", source=str(scene_dir))
    if options.perception.startswith("label") and scene.semantics is None:
        raise InputError(
            f"has no semantic sidecar (semantics.json + labels.npy); --perception {options.perception} needs one",
            source=str(scene_dir),
        )
    return scene, world_up(scene_dir, options.gravity)


def make_perception(scene: SceneDir, up: np.ndarray, options: GroundOptions):
    """The perception backend of ``options`` for ``scene`` (its per-scene cache warmed)."""
    from .backends.labels import LabelPerception
    from .retrieve.views import cached_view_measurements

    cache = Path(options.cache_dir) if options.cache_dir else default_cache_dir(scene.root)
    views = cached_view_measurements(scene, cache)
    return LabelPerception(scene, views, up, masks=options.perception == "label-masks")


def segment(parsed: ParsedInstruction, perception, view_indices: list[int]) -> dict[str, SubjectMasks]:
    """Segmentation: each subject's 2D masks in the retrieved views; empty for a perception that
    associates without masks."""
    masks = {s.name: perception.segment(s, view_indices) for s in parsed.subjects}
    return {name: m for name, m in masks.items() if m is not None}


def associate(parsed: ParsedInstruction, perception, masks: dict[str, SubjectMasks]) -> dict[str, Grounding]:
    """Association: each subject's Gaussians and centroid (from its masks when it has some)."""
    return {s.name: perception.associate(s, masks.get(s.name)) for s in parsed.subjects}


def orient(parsed: ParsedInstruction, perception, view_indices: list[int]) -> dict[str, np.ndarray | None]:
    """Orientation: the front of each subject that needs one (:attr:`ParsedSubject.needs_front`)."""
    return {s.name: perception.front(s, view_indices) for s in parsed.subjects if s.needs_front}


def pseudo_labels(
    parsed: ParsedInstruction, groundings: dict[str, Grounding], fronts: dict[str, np.ndarray | None], up: np.ndarray
) -> PseudoLabels:
    """The pseudo labels of ``parsed`` from its subjects' groundings and fronts (a front is used
    only where :attr:`ParsedSubject.needs_front` asks for one)."""
    missing = [s.name for s in parsed.subjects if s.name not in groundings or (s.needs_front and s.name not in fronts)]
    if missing:
        raise InputError(
            f"subjects {missing} lack a grounding or a front; run capframe associate / capframe orient for this instruction"
        )
    subjects = {
        s.name: (groundings[s.name].gaussians, groundings[s.name].centroid, fronts.get(s.name) if s.needs_front else None)
        for s in parsed.subjects
    }
    return labels_from_constraints(parsed.constraints(), subjects, up)


def translate(parsed: ParsedInstruction, perception, view_indices: list[int], up: np.ndarray) -> PseudoLabels:
    """Pseudo labels of ``parsed``: each subject segmented in the retrieved views and associated
    with its Gaussians, its front from the orientation backend (asked only where needed)."""
    groundings = associate(parsed, perception, segment(parsed, perception, view_indices))
    return pseudo_labels(parsed, groundings, orient(parsed, perception, view_indices), up)


def own_report(scene: SceneDir, labels: PseudoLabels, parsed: ParsedInstruction, camera: Camera) -> CheckReport:
    """The per-clause report of ``camera``, measured with the method's own pseudo labels."""
    objects, members = {}, {}
    means = scene.gaussians.means.detach().double().numpy()
    for k, s in enumerate(labels.subjects):
        radius = float(np.sqrt(((means[s.gaussians] - s.centroid) ** 2).sum(1).mean()))
        objects[s.name] = GTObject(k, s.name, s.centroid, radius, -1, s.front)
        member = torch.zeros(len(means), dtype=torch.bool)
        member[torch.as_tensor(s.gaussians)] = True
        members[k] = member
    checker = ConstraintChecker(scene.gaussians, objects, members, labels.up)
    report = checker.check(camera, parsed.constraints())
    report.text = parsed.text
    return report


def _same_pose(a: np.ndarray, b: np.ndarray, scale: float) -> bool:
    angle, distance = pose_deviation(a, b, scale)
    return angle < DISTINCT_ROTATION_DEG and distance < DISTINCT_TRANSLATION


def _check_options(options: GroundOptions) -> None:
    check_perception(options.perception)
    if options.drop not in (None, "layout", "orientation"):
        raise InputError(f"--drop {options.drop!r}; expected 'layout' or 'orientation'")
    if min(options.top_k, options.candidates, options.attempts) < 1:
        raise InputError(
            f"--topk {options.top_k}, --candidates {options.candidates}, --attempts {options.attempts}: each must be at least 1"
        )


def parse_stage(scene: SceneDir, text: str, options: GroundOptions, clock: StageClock) -> ParsedInstruction:
    """``text`` parsed against the scene's vocabulary (before any expensive work, so bad input
    fails fast)."""
    parsed = make_parser(options.parser).parse(text, Vocabulary.from_semantics(scene.semantics or []))
    clock.done(
        "parse",
        ", ".join(f"{s.name} ({s.role})" for s in parsed.subjects)
        + (f"; not understood: {parsed.unparsed}" if parsed.unparsed else ""),
    )
    return parsed


def coarse_stage(scene: SceneDir, up: np.ndarray, parsed: ParsedInstruction, perception, clock: StageClock) -> Coarse:
    """Coarse retrieval: every training view scored, the top M kept for QE."""
    names = [c.name for c in scene.cameras]
    scores = np.asarray(perception.coarse(parsed), dtype=np.float64)
    kept = coarse_keep(scores)
    clock.done("coarse", f"{len(kept)} of {len(names)} views kept")
    return Coarse(parsed, dict(zip(names, scores.tolist())), [names[v] for v in kept], up)


def qe_stage(scene: SceneDir, coarse: Coarse, perception, options: GroundOptions, clock: StageClock) -> Retrieved:
    """QE scoring of the kept views; the top K are retrieved, and Refine's starts drawn (seeded)."""
    names = [c.name for c in scene.cameras]
    if sorted(coarse.coarse) != sorted(names):
        raise InputError(
            "the coarse scores are not of this scene's training views; rerun capframe coarse", source=str(scene.root)
        )
    scores = np.array([coarse.coarse[n] for n in names])
    retrieval = rank_kept(coarse.parsed, perception, scores, _view_indices(scene, coarse.kept), options.top_k)
    first = random.Random(options.seed).choice(retrieval.top)
    starts = [first] + [v for v in retrieval.ranked() if v != first]
    clock.done("retrieve", "top: " + ", ".join(names[v] for v in retrieval.top))
    return Retrieved(
        coarse.parsed, retrieval.to_dict(names), [names[v] for v in retrieval.top], [names[v] for v in starts], coarse.up
    )


def retrieve_stage(
    scene: SceneDir, up: np.ndarray, parsed: ParsedInstruction, perception, options: GroundOptions, clock: StageClock
) -> Retrieved:
    """Retrieve: rank the training views for ``parsed`` (coarse, then QE)."""
    return qe_stage(scene, coarse_stage(scene, up, parsed, perception, clock), perception, options, clock)


def _view_indices(scene: SceneDir, names: list[str]) -> list[int]:
    index = {c.name: i for i, c in enumerate(scene.cameras)}
    missing = [n for n in names if n not in index]
    if missing:
        raise InputError(f"retrieved views {missing} are not training views of this scene", source=str(scene.root))
    return [index[n] for n in names]


def ablated(parsed: ParsedInstruction, drop: str | None) -> ParsedInstruction:
    """``parsed`` without its layout or orientation cues (the sensitivity study's label removal)."""
    if drop is None:
        return parsed
    if drop == "layout":
        subjects = [dataclasses.replace(s, region=None, shot=None) for s in parsed.subjects]
        return dataclasses.replace(parsed, subjects=subjects)
    subjects = [dataclasses.replace(s, view=None) for s in parsed.subjects]
    return dataclasses.replace(parsed, subjects=subjects, elevation=None, elevation_deg=None, roll_deg=None)


def _shifted(box: tuple | None, dx: float, dy: float) -> tuple | None:
    return None if box is None else (box[0] + dx, box[1] + dy, box[2] + dx, box[3] + dy)


def perturbed(labels: PseudoLabels, box_noise: float, front_noise_deg: float, seed: int) -> PseudoLabels:
    """Pseudo labels with moderate noise: each box and region shifted by ``box_noise`` (frame
    fraction) in a random direction, each front turned about the up by ``front_noise_deg``."""
    rng = np.random.default_rng(seed)
    subjects = []
    for s in labels.subjects:
        angle = rng.uniform(0, 2 * np.pi)
        dx, dy = box_noise * np.cos(angle), box_noise * np.sin(angle)
        front = s.front
        if front is not None and front_noise_deg:
            from .geometry import so3_exp

            turn = np.radians(front_noise_deg) * rng.choice([-1.0, 1.0])
            R = so3_exp(torch.as_tensor(labels.up * turn, dtype=torch.float64)).numpy()
            front = R @ front
        subjects.append(dataclasses.replace(s, region=_shifted(s.region, dx, dy), box=_shifted(s.box, dx, dy), front=front))
    return dataclasses.replace(labels, subjects=subjects)


def labels_stage(
    retrieved: Retrieved,
    groundings: dict[str, Grounding],
    fronts: dict[str, np.ndarray | None],
    options: GroundOptions,
    clock: StageClock,
) -> PseudoLabels:
    """The pseudo labels from the subjects' groundings and fronts (ablated and perturbed as
    ``options`` ask)."""
    labels = pseudo_labels(ablated(retrieved.parsed, options.drop), groundings, fronts, retrieved.up)
    if options.box_noise or options.front_noise_deg:
        labels = perturbed(labels, options.box_noise, options.front_noise_deg, options.noise_seed)
    clock.done("translate", ", ".join(f"{s.name}: {len(s.gaussians)} Gaussians" for s in labels.subjects))
    return labels


def translate_stage(
    scene: SceneDir, retrieved: Retrieved, perception, clock: StageClock, options: GroundOptions | None = None
) -> PseudoLabels:
    """Translate: segmentation, association and orientation in the retrieved views, then the
    pseudo labels."""
    options = options or GroundOptions()
    parsed = ablated(retrieved.parsed, options.drop)
    views = _view_indices(scene, retrieved.top)
    groundings = associate(parsed, perception, segment(parsed, perception, views))
    return labels_stage(retrieved, groundings, orient(parsed, perception, views), options, clock)


def refine_stage(
    scene: SceneDir, labels: PseudoLabels, retrieved: Retrieved, out_dir: str | Path, options: GroundOptions, clock: StageClock
) -> dict:
    """Refine from the retrieved starts (see :class:`GroundOptions` ``attempts``/``candidates``),
    report on the best pose with the pseudo labels and write the outputs. Returns ``result.json``."""
    scale = scene_scale(scene.cameras, scene.gaussians.means)
    starts = _view_indices(scene, retrieved.starts[: max(options.candidates, options.attempts)])
    names = [c.name for c in scene.cameras]
    runs: list[tuple[int, RefineResult]] = []
    for v in starts:
        result = refine_pose(scene.gaussians, scene.cameras[v], labels, scale, options.refine)
        runs.append((v, result))
        clock.done(
            "refine", f"from {names[v]}: {result.iterations} iterations, loss {result.losses.min():.4g} ({result.stop_reason})"
        )
        if options.candidates == 1 and result.stop_reason == "satisfied":
            break
    # A run whose clauses all held beats a lower loss that left one failing.
    runs.sort(key=lambda run: (run[1].stop_reason != "satisfied", float(run[1].losses.min())))
    distinct: list[tuple[int, RefineResult]] = []
    for run in runs:
        if not any(_same_pose(run[1].T_cw, kept[1].T_cw, scale) for kept in distinct):
            distinct.append(run)

    cameras = [scene.cameras[v].with_pose(r.T_cw) for v, r in distinct]
    reports = [own_report(scene, labels, retrieved.parsed, c) for c in cameras]
    images = [render(scene.gaussians, c).rgb for c in cameras[: 1 if len(cameras) == 1 else None]]
    clock.done("report", "own labels: " + ("all clauses hold" if reports[0].all_satisfied else "some clauses fail"))
    timings = dict(clock.timings, total_s=time.perf_counter() - clock.start)
    extra = {
        "instruction": retrieved.parsed.to_dict(),
        "retrieval": retrieved.retrieval,
        "init_view": names[distinct[0][0]],
        "report": reports[0].to_dict(),
        "candidates": [
            {
                "rank": k,
                "init_view": names[v],
                "loss": float(r.losses.min()),
                "T_cw": r.T_cw.tolist(),
                "own_all_satisfied": rep.all_satisfied,
            }
            for k, ((v, r), rep) in enumerate(zip(distinct, reports))
        ],
        "options": {
            "top_k": options.top_k,
            "seed": options.seed,
            "candidates": options.candidates,
            "attempts": options.attempts,
            "parser": options.parser,
            "perception": options.perception,
        },
        "up": retrieved.up.tolist(),
    }
    with atomic_directory(out_dir) as tmp:
        write_refine_outputs(tmp, cameras[0], distinct[0][1], labels, options.refine, timings, images[0], extra)
        write_pseudo_labels(labels, tmp / "labels.json")
        write_camera_path_json([cameras[0]], tmp / "camera_path.json")
        (tmp / "colmap_image.txt").write_text(colmap_image_line(cameras[0], 1) + "\n")
        if len(cameras) > 1:
            for k, (camera, image) in enumerate(zip(cameras, images)):
                write_camera_json(camera, tmp / "candidates" / str(k) / "camera.json")
                save_png(image, tmp / "candidates" / str(k) / "render.png")
    if clock.enabled:
        print(format_report(reports[0]), file=sys.stderr)
    return json.loads((Path(out_dir) / "result.json").read_text())


def ground(
    scene_dir: str | Path, text: str, out_dir: str | Path, options: GroundOptions | None = None, progress: bool = True
) -> dict:
    """Find the camera for ``text`` in the scene at ``scene_dir`` and write it to ``out_dir``
    (the three stages in one process). Returns the content of ``result.json``."""
    options = options or GroundOptions()
    _check_options(options)
    clock = StageClock(progress)
    scene, up = load_scene(Path(scene_dir), options)
    parsed = parse_stage(scene, text, options, clock)
    perception = make_perception(scene, up, options)
    clock.done("views", f"{len(scene.cameras)} training views measured (cached per scene)")
    retrieved = retrieve_stage(scene, up, parsed, perception, options, clock)
    labels = translate_stage(scene, retrieved, perception, clock, options)
    return refine_stage(scene, labels, retrieved, out_dir, options, clock)


def _stage_inputs(args, options: GroundOptions) -> tuple[SceneDir, np.ndarray, object]:
    _check_options(options)
    scene, up = load_scene(Path(args.scene), options)
    return scene, up, make_perception(scene, up, options)


def retrieve_command(args) -> None:
    """``capframe retrieve``: parse and rank the training views (coarse + QE), write ``retrieval.json``."""
    options = GroundOptions(
        top_k=args.topk,
        seed=args.seed,
        parser=args.parser,
        perception=args.perception,
        cache_dir=args.cache,
        gravity=args.gravity,
    )
    clock = StageClock(True)
    scene, up, perception = _stage_inputs(args, options)
    parsed = parse_stage(scene, args.instruction, options, clock)
    write_json(args.output, retrieve_stage(scene, up, parsed, perception, options, clock).to_dict())


def coarse_command(args) -> None:
    """``capframe coarse``: parse the instruction and score every training view, ``coarse.json``."""
    options = GroundOptions(parser=args.parser, perception=args.perception, cache_dir=args.cache, gravity=args.gravity)
    clock = StageClock(True)
    scene, up, perception = _stage_inputs(args, options)
    coarse_stage(scene, up, parse_stage(scene, args.instruction, options, clock), perception, clock).write(args.output)


def qe_command(args) -> None:
    """``capframe qe``: QE scoring of the coarse stage's views, ``retrieval.json``."""
    options = GroundOptions(
        top_k=args.topk, seed=args.seed, perception=args.perception, cache_dir=args.cache, gravity=args.gravity
    )
    coarse = Coarse.read(args.coarse)
    scene, _, perception = _stage_inputs(args, options)
    write_json(args.output, qe_stage(scene, coarse, perception, options, StageClock(True)).to_dict())


def _translate_step(args) -> tuple[StageClock, Retrieved, SceneDir, object, list[int]]:
    """What each Translate step reads: its clock, the retrieval, the scene, the perception and
    the retrieved views' indices."""
    options = GroundOptions(perception=args.perception, cache_dir=args.cache, gravity=args.gravity)
    clock = StageClock(True)
    retrieved = Retrieved.read(args.retrieval)
    scene, _, perception = _stage_inputs(args, options)
    return clock, retrieved, scene, perception, _view_indices(scene, retrieved.top)


def segment_command(args) -> None:
    """``capframe segment``: the subjects' 2D masks in the retrieved views, ``masks.npz``."""
    clock, retrieved, scene, perception, views = _translate_step(args)
    masks = segment(retrieved.parsed, perception, views)
    if not masks:
        raise InputError(f"--perception {args.perception} associates without masks; segmentation has nothing to do")
    write_masks(masks, [c.name for c in scene.cameras], args.output)
    clock.done("segment", ", ".join(f"{name}: {len(m.views)} views" for name, m in masks.items()))


def associate_command(args) -> None:
    """``capframe associate``: each subject's Gaussians (from ``--masks`` when given), ``subjects.json``."""
    clock, retrieved, scene, perception, views = _translate_step(args)
    masks = (
        read_masks(args.masks, [c.name for c in scene.cameras]) if args.masks else segment(retrieved.parsed, perception, views)
    )
    groundings = associate(retrieved.parsed, perception, masks)
    write_groundings(groundings, args.output)
    clock.done("associate", ", ".join(f"{name}: {len(g.gaussians)} Gaussians" for name, g in groundings.items()))


def orient_command(args) -> None:
    """``capframe orient``: the fronts of the subjects that need one, ``fronts.json``."""
    clock, retrieved, _, perception, views = _translate_step(args)
    fronts = orient(retrieved.parsed, perception, views)
    write_fronts(fronts, args.output)
    clock.done("orient", ", ".join(fronts) or "no subject needs a front")


def translate_command(args) -> None:
    """``capframe translate``: pseudo labels from ``retrieval.json``, written as ``labels.json``;
    from the association and orientation stages' files when given, else computed here."""
    options = GroundOptions(
        perception=args.perception,
        cache_dir=args.cache,
        gravity=args.gravity,
        drop=args.drop,
        box_noise=args.box_noise,
        front_noise_deg=args.front_noise,
        noise_seed=args.noise_seed,
    )
    retrieved = Retrieved.read(args.retrieval)
    clock = StageClock(True)
    if args.subjects:
        _check_options(options)
        scene = load_scene_dir(args.scene)
        if scene.gaussians is None:
            raise InputError("has no scene.ply; the subjects' Gaussian indices refer to it", source=str(args.scene))
        groundings = read_groundings(args.subjects, len(scene.gaussians))
        fronts = read_fronts(args.fronts) if args.fronts else {}
        labels = labels_stage(retrieved, groundings, fronts, options, clock)
    else:
        scene, _, perception = _stage_inputs(args, options)
        labels = translate_stage(scene, retrieved, perception, clock, options)
    write_pseudo_labels(labels, args.output)


def refine_retrieved(
    scene_dir: str | Path, labels_path: str | Path, retrieval_path: str | Path, out_dir: str | Path, options: GroundOptions
) -> dict:
    """``capframe refine --init retrieval.json``: Refine as ``capframe ground`` does, from files."""
    _check_options(options)
    from .translate.labels import read_pseudo_labels

    clock = StageClock(True)
    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None or not scene.cameras:
        raise InputError("needs scene.ply and training cameras to refine from retrieved views", source=str(scene_dir))
    return refine_stage(scene, read_pseudo_labels(labels_path), Retrieved.read(retrieval_path), out_dir, options, clock)


def retrieved_view(scene_dir: str | Path, retrieval_path: str | Path, out_dir: str | Path) -> dict:
    """Retrieve's answer on its own: the training view Refine starts from (``starts[0]`` of a
    ``retrieval.json``), written like a method's result (``result.json``, ``camera.json``,
    ``render.png``) so the benchmark checks the pose before refinement beside the pose after it.

    ``result.json`` has no ``timings``: the view was chosen by the coarse and QE jobs, whose
    benchmark files carry the cost (``capframe runtime``). Returns its content.
    """
    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None or not scene.cameras:
        raise InputError("needs scene.ply and training cameras to render a retrieved view", source=str(scene_dir))
    retrieved = Retrieved.read(retrieval_path)
    if not retrieved.starts:
        raise InputError("'starts' is empty; expected the retrieved views, best first", source=str(retrieval_path))
    camera = scene.cameras[_view_indices(scene, retrieved.starts[:1])[0]]
    image = render(scene.gaussians, camera).rgb
    with atomic_directory(out_dir) as tmp:
        summary = write_camera_result(
            tmp, camera, image, {"method": "retrieve", "init_view": camera.name, "instruction": retrieved.parsed.to_dict()}
        )
    return summary


def retrieved_view_command(args) -> None:
    """The ``capframe retrieved-view`` verb."""
    summary = retrieved_view(args.scene, args.retrieval, args.output)
    print(f"{args.output}: retrieved view {summary['init_view']}")


def ground_command(args) -> None:
    """The ``capframe ground`` verb."""
    options = GroundOptions(
        top_k=args.topk,
        seed=args.seed,
        candidates=args.candidates,
        attempts=args.attempts,
        parser=args.parser,
        perception=args.perception,
        cache_dir=args.cache,
        gravity=args.gravity,
        refine=RefineConfig(iterations=args.iterations, long_side=args.long_side),
    )
    result = ground(args.scene, args.instruction, args.output, options, progress=not args.json)
    if args.json:
        keys = ("T_cw", "K", "width", "height", "init_view", "timings", "report", "instruction")
        print(json.dumps({k: result[k] for k in keys}))
    else:
        print(f"{args.output}: camera from {result['init_view']}, {result['timings']['total_s']:.1f} s")
