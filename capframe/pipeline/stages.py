"""The method, one function per stage: parse, coarse, qe (Retrieve); segment, associate, orient,
translate (Translate); refine (Refine). ``capframe ground`` chains them in one process
(:func:`capframe.pipeline.ground`); the workflow runs each as its own ``capframe`` verb with files in between
(:mod:`capframe.handoff`); the baselines share parse to translate. Their options are one
:class:`GroundOptions`.

Every stage reads its perception from one :class:`~capframe.backends.Backends` (built once per
job); none reads the ground truth.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import os
import random
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from ..backends import BackendContext, Backends, Grounding, SubjectMasks, read_models_config
from ..backends.registry import ROLES, resolve_choices
from ..errors import InputError, clip
from ..geometry import camera_center, pose_deviation
from ..geometry.gravity import world_up
from ..handoff import Coarse, Retrieved
from ..measure import CheckReport, ConstraintChecker, Subject
from ..refine.candidates import Candidate, solve_candidates, view_centre
from ..refine.optimize import RefineConfig, RefineResult, refine_pose
from ..render import check_render_memory
from ..retrieve.qe import rank_kept
from ..scene import Camera, SceneDir, load_scene_dir, scene_scale
from ..scene.occupancy import Occupancy, cached_occupancy
from ..translate.instruction import ParsedInstruction
from ..translate.labels import PseudoLabels, labels_from_constraints, perturbed
from ..translate.vocabulary import Vocabulary

DROPPABLE = ("layout", "orientation")


@dataclass
class GroundOptions:
    """Options of :func:`capframe.pipeline.ground` and of its stages.

    Attributes:
        top_k: retrieved views kept as initialisations.
        seed: picks the first initial view among the top K (as the paper does).
        candidates: refine from this many retrieved views and rank the resulting poses.
        attempts: with one candidate, refine from up to this many retrieved views, stopping at the
            first whose pseudo-label clauses all hold (a start in a bad basin costs a retry, not
            the result; most instructions need one refinement).
        backends: role -> backend name (:data:`capframe.backends.ROLES`); unnamed roles take
            their default.
        models: the models config file (weights, endpoints) of model backends.
        cache_dir: per-scene cache (default ``$XDG_CACHE_HOME/capframe/<scene>``).
        gravity: a gravity file for scenes whose ``scene.json`` has no up.
        drop: ablation: remove the ``layout`` (regions, shot sizes) or ``orientation`` (view side,
            elevation, roll) pseudo labels; the instruction itself is unchanged.
        box_noise: perturb each layout box by this fraction of the frame, in a random direction.
        front_noise_deg: rotate each subject's front about the up by this angle, random sign.
        noise_seed: seed of both perturbations.
        solve: Refine also starts from up to this many cameras solved in closed form from the
            pseudo labels (:mod:`capframe.refine.candidates`), alternating with the retrieved
            views, the solved first; 0 starts from the retrieved views only (the paper).
        free_space: keep cameras out of geometry with the scene's occupancy
            (:mod:`capframe.scene.occupancy`); also needed by ``solve``.
        refine: the optimiser's settings.
    """

    top_k: int = 2
    seed: int = 0
    candidates: int = 1
    attempts: int = 3
    backends: dict[str, str] = dataclasses.field(default_factory=dict)
    models: str | Path | None = None
    cache_dir: str | Path | None = None
    gravity: str | Path | None = None
    drop: str | None = None
    box_noise: float = 0.0
    front_noise_deg: float = 0.0
    noise_seed: int = 0
    solve: int = 3
    free_space: bool = True
    refine: RefineConfig = dataclasses.field(default_factory=RefineConfig)

    def check(self) -> None:
        """:class:`InputError` for an unknown backend, ablation or a count below 1."""
        self.backends = resolve_choices(self.backends)
        if self.drop not in (None, *DROPPABLE):
            raise InputError(f"--drop {self.drop!r}; expected one of {list(DROPPABLE)}")
        if min(self.top_k, self.candidates, self.attempts) < 1:
            raise InputError(
                f"--topk {self.top_k}, --candidates {self.candidates}, --attempts {self.attempts}: each must be at least 1"
            )
        if self.solve < 0:
            raise InputError(f"--solve {self.solve}; expected 0 (retrieved views only) or more")
        if self.solve and not self.free_space:
            raise InputError("--solve needs the free space (drop --no-free-space, or pass --solve 0)")

    def record(self) -> dict:
        """The options that chose the camera, as ``result.json`` records them."""
        return {
            "top_k": self.top_k,
            "seed": self.seed,
            "candidates": self.candidates,
            "attempts": self.attempts,
            "solve": self.solve,
            "free_space": self.free_space,
            "backends": resolve_choices(self.backends),
        }


def cache_dir(scene: SceneDir, options: GroundOptions) -> Path:
    """The per-scene cache: ``options.cache_dir`` or :func:`default_cache_dir`."""
    return Path(options.cache_dir) if options.cache_dir else default_cache_dir(scene.root)


def default_cache_dir(scene_dir: Path) -> Path:
    """``$XDG_CACHE_HOME/capframe/<scene name>-<hash of its path>``."""
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "capframe"
    # The path's bytes as the file system has them: a name that is not UTF-8 has no str.encode().
    key = hashlib.sha256(os.fsencode(scene_dir.resolve())).hexdigest()[:10]
    return base / f"{scene_dir.name}-{key}"


class StageClock:
    """Each stage's wall time; with ``enabled``, one line per stage on stderr. ``counters`` are
    what the stages' models cost so far (the MLLM response cache's counters), reported with the
    timings."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.start = self.last = time.perf_counter()
        self.timings: dict[str, float] = {}
        self.counters: dict[str, float] = {}

    def done(self, stage: str, message: str = "") -> None:
        now = time.perf_counter()
        self.timings[f"{stage}_s"] = now - self.last
        if self.enabled:
            print(f"[{now - self.start:6.1f} s] {stage:<9} {clip(message)}", file=sys.stderr, flush=True)
        self.last = now

    def total(self) -> dict[str, float]:
        """The stage timings, ``total_s`` (the wall time since the clock started) and the counters."""
        return dict(self.timings, total_s=time.perf_counter() - self.start) | self.counters


# Two refined poses closer than this are the same candidate.
DISTINCT_ROTATION_DEG = 5.0
DISTINCT_TRANSLATION = 0.05  # of the scene scale


@dataclass
class Job:
    """What every stage of one job reads: the scene, its world up and the job's backends."""

    scene: SceneDir
    up: np.ndarray
    backends: Backends

    def view_indices(self, names: list[str], source: str | None = None) -> list[int]:
        return view_indices(self.scene, names, source)

    @property
    def view_names(self) -> list[str]:
        return [c.name for c in self.scene.cameras]

    def check_final_render(self) -> None:
        """:class:`InputError` before any work when the result's full-resolution frame, rendered
        at the size of the training view Refine starts from, cannot fit in memory."""
        check_render_memory(self.scene.cameras, device=self.scene.gaussians.means.device, source=str(self.scene.root))

    def check_subjects(self, parsed: ParsedInstruction, source: str | None) -> None:
        """:class:`InputError` naming ``source`` (the stage file ``parsed`` was read from) when a
        subject is not an object of a scene with semantics: the parser matches names to that
        vocabulary (DESIGN §3: subjects are matched by name), so another name was not parsed here."""
        if self.scene.semantics is None:
            return
        known = [o.name for o in self.scene.semantics]
        for i, subject in enumerate(parsed.subjects):
            if subject.name not in known:
                raise InputError(
                    f"instruction.subjects[{i}].name is {clip(subject.name)!r}; expected an object of {self.scene.root}: {known}",
                    source=source or str(self.scene.root),
                )


def view_indices(scene: SceneDir, names: list[str], source: str | None = None) -> list[int]:
    """Indices of the named training views; :class:`InputError` naming any that is not one (and
    ``source``, the file the names were read from)."""
    index = {c.name: i for i, c in enumerate(scene.cameras)}
    missing = [n for n in names if n not in index]
    if missing:
        raise InputError(f"views {clip(repr(missing))} are not training views of {scene.root}", source=source or str(scene.root))
    return [index[n] for n in names]


def open_job(scene_dir: str | Path, options: GroundOptions) -> Job:
    """The scene at ``scene_dir`` checked for what the method needs (Gaussians, training cameras,
    a world up), with the backends of ``options``; :class:`InputError` otherwise."""
    options.check()
    scene_dir = Path(scene_dir)
    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None:
        raise InputError("has no scene.ply; the method renders the scene", source=str(scene_dir))
    if not scene.cameras:
        raise InputError("has no training cameras; recover them first with `capframe colmap`", source=str(scene_dir))
    oracles = [ROLES[role].option for role, name in options.backends.items() if name == "oracle"]
    if oracles and scene.semantics is None:
        raise InputError(
            f"has no semantic sidecar (semantics.json + labels.npy); {', '.join(o + ' oracle' for o in oracles)} read it",
            source=str(scene_dir),
        )
    up = world_up(scene_dir, options.gravity)
    context = BackendContext(scene, up, cache_dir(scene, options), read_models_config(options.models))
    return Job(scene, up, Backends(options.backends, context))


def model_calls(job: Job, clock: StageClock) -> str:
    """The job's MLLM requests so far (every chat model's cache counters, summed), kept in
    ``clock.counters`` for the timings and returned for a stage's progress line: how many were
    answered from the response cache and how many asked a model; empty when no chat model was
    built."""
    stats = [chat.stats() for chat in job.backends.context.shared_with("mllm-chat:") if hasattr(chat, "stats")]
    if not stats:
        return ""
    clock.counters = {key: sum(s[key] for s in stats) for key in stats[0]}
    hits, misses = clock.counters["mllm_cache_hits"], clock.counters["mllm_cache_misses"]
    seconds = clock.counters["mllm_model_seconds"]
    return f"; mllm: {hits + misses} requests, {hits} from the cache, {misses} asked ({seconds:.1f} s)"


def parse(job: Job, text: str, clock: StageClock) -> ParsedInstruction:
    """``text`` parsed against the scene's vocabulary (before any expensive work, so bad input
    fails fast)."""
    parsed = job.backends["parser"].parse(text, Vocabulary.from_semantics(job.scene.semantics or []))
    clock.done(
        "parse",
        ", ".join(f"{s.name} ({s.role})" for s in parsed.subjects)
        + (f"; not understood: {parsed.unparsed}" if parsed.unparsed else "")
        + "".join(f"; read {c['said']!r} as {c['read']!r}" for c in parsed.corrected)
        + model_calls(job, clock),
    )
    return parsed


def coarse(job: Job, parsed: ParsedInstruction, clock: StageClock, source: str | None = None) -> Coarse:
    """Coarse retrieval: every training view scored, the top M kept for QE (M as the coarse
    scorer says: :meth:`~capframe.backends.CoarseScorer.keep`; ``source``: the file ``parsed``
    was read from, named by errors)."""
    names = job.view_names
    job.check_subjects(parsed, source)
    scorer = job.backends["coarse"]
    scores = np.asarray(scorer.coarse(parsed), dtype=np.float64)
    kept = scorer.keep(scores)
    clock.done("coarse", f"{len(kept)} of {len(names)} views kept")
    return Coarse(parsed, dict(zip(names, scores.tolist())), [names[v] for v in kept], job.up)


def qe(job: Job, coarse: Coarse, options: GroundOptions, clock: StageClock) -> Retrieved:
    """QE scoring of the kept views; the top K are retrieved, and Refine's starts drawn (seeded)."""
    names = job.view_names
    if sorted(coarse.coarse) != sorted(names):
        raise InputError(
            f"coarse scores views that are not the training views of {job.scene.root}; rerun capframe coarse",
            source=coarse.source or str(job.scene.root),
        )
    job.check_subjects(coarse.parsed, coarse.source)
    scores = np.array([coarse.coarse[n] for n in names])
    kept = job.view_indices(coarse.kept, coarse.source)
    retrieval = rank_kept(coarse.parsed, job.backends["qe"], scores, kept, options.top_k)
    first = random.Random(options.seed).choice(retrieval.top)
    starts = [first] + [v for v in retrieval.ranked() if v != first]
    clock.done("retrieve", "top: " + ", ".join(names[v] for v in retrieval.top) + model_calls(job, clock))
    return Retrieved(
        coarse.parsed, retrieval.to_dict(names), [names[v] for v in retrieval.top], [names[v] for v in starts], coarse.up
    )


def segment(job: Job, retrieved: Retrieved, clock: StageClock) -> dict[str, SubjectMasks]:
    """Segmentation: each subject's 2D masks in the retrieved views."""
    job.check_subjects(retrieved.parsed, retrieved.source)
    views = job.view_indices(retrieved.top, retrieved.source)
    masks = {s.name: job.backends["segmenter"].segment(s, views) for s in retrieved.parsed.subjects}
    clock.done("segment", ", ".join(f"{name}: {len(m.views)} views" for name, m in masks.items()))
    return masks


def associate(job: Job, retrieved: Retrieved, masks: dict[str, SubjectMasks], clock: StageClock) -> dict[str, Grounding]:
    """Association: each subject's Gaussians and centroid (from its masks when the associator
    reads masks)."""
    job.check_subjects(retrieved.parsed, retrieved.source)
    associator = job.backends["associator"]
    groundings = {s.name: associator.associate(s, masks.get(s.name)) for s in retrieved.parsed.subjects}
    clock.done("associate", ", ".join(f"{name}: {len(g.gaussians)} Gaussians" for name, g in groundings.items()))
    return groundings


def orient(
    job: Job, retrieved: Retrieved, clock: StageClock, masks: dict[str, SubjectMasks] | None = None
) -> dict[str, np.ndarray | None]:
    """Orientation: the front of each subject that needs one (:attr:`ParsedSubject.needs_front`).
    An estimator that reads masks gets ``masks``, or the segmenter's, computed here."""
    job.check_subjects(retrieved.parsed, retrieved.source)
    views = job.view_indices(retrieved.top, retrieved.source)
    subjects = [s for s in retrieved.parsed.subjects if s.needs_front]
    estimator = job.backends["orient"] if subjects else None
    if estimator is not None and estimator.needs_masks and masks is None:
        masks = segment(job, retrieved, clock)
    fronts = {s.name: estimator.front(s, views, (masks or {}).get(s.name)) for s in subjects}
    clock.done("orient", ", ".join(fronts) or "no subject needs a front")
    return fronts


def translate(
    retrieved: Retrieved,
    groundings: dict[str, Grounding],
    fronts: dict[str, np.ndarray | None],
    options: GroundOptions,
    clock: StageClock,
) -> PseudoLabels:
    """The pseudo labels from the subjects' groundings and fronts (a front is used only where
    :attr:`ParsedSubject.needs_front` asks for one), ablated and perturbed as ``options`` ask."""
    parsed = retrieved.parsed.without(options.drop)
    missing = [s.name for s in parsed.subjects if s.name not in groundings or (s.needs_front and s.name not in fronts)]
    if missing:
        raise InputError(
            f"subjects {missing} lack a grounding or a front; run capframe associate / capframe orient for this instruction"
        )
    subjects = {
        s.name: (groundings[s.name].gaussians, groundings[s.name].centroid, fronts.get(s.name) if s.needs_front else None)
        for s in parsed.subjects
    }
    boxes = {s.name: s.box for s in parsed.subjects if s.box is not None}
    labels = labels_from_constraints(parsed.constraints(), subjects, retrieved.up, boxes)
    if options.box_noise or options.front_noise_deg:
        labels = perturbed(labels, options.box_noise, options.front_noise_deg, options.noise_seed)
    clock.done("translate", ", ".join(f"{s.name}: {len(s.gaussians)} Gaussians" for s in labels.subjects))
    return labels


def perceive(job: Job, retrieved: Retrieved, options: GroundOptions, clock: StageClock) -> PseudoLabels:
    """Translate in one call: segment (only for an associator or an orientation estimator that
    reads masks), associate and orient, on the instruction as ablated; then the pseudo labels."""
    ablated = Retrieved(
        retrieved.parsed.without(options.drop),
        retrieved.retrieval,
        retrieved.top,
        retrieved.starts,
        retrieved.up,
        retrieved.source,
    )
    needs_front = any(s.needs_front for s in ablated.parsed.subjects)
    reads_masks = job.backends["associator"].needs_masks or (needs_front and job.backends["orient"].needs_masks)
    masks = segment(job, ablated, clock) if reads_masks else None
    groundings = associate(job, ablated, masks or {}, clock)
    return translate(retrieved, groundings, orient(job, ablated, clock, masks), options, clock)


@dataclass
class Refined:
    """Refine's distinct poses, best first: each start camera with its :class:`RefineResult`,
    and the closed-form starts that were considered (kept or dropped, with why)."""

    runs: list[tuple[Camera, RefineResult]]
    solved: list[Candidate] = dataclasses.field(default_factory=list)

    @property
    def cameras(self) -> list[Camera]:
        return [start.with_pose(result.T_cw) for start, result in self.runs]


def _same_pose(a: np.ndarray, b: np.ndarray, scale: float) -> bool:
    angle, distance = pose_deviation(a, b, scale)
    return angle < DISTINCT_ROTATION_DEG and distance < DISTINCT_TRANSLATION


def free_space(
    scene: SceneDir, up: np.ndarray, options: GroundOptions, clock: StageClock, labels: PseudoLabels | None = None
) -> Occupancy | None:
    """The scene's occupancy from the per-scene cache (built once), with a finer grid around the
    primary subject of ``labels`` when it is small for the scene's grid (:meth:`Occupancy.around`);
    None without ``free_space``."""
    if not options.free_space:
        return None
    occupancy = cached_occupancy(scene.gaussians, up, scene.cameras, cache_dir(scene, options))
    clock.done("space", f"{int(occupancy.free.sum())} free voxels of {occupancy.voxel:.3g}")
    return subject_space(occupancy, scene, labels, clock)


def subject_space(occupancy: Occupancy, scene: SceneDir, labels: PseudoLabels | None, clock: StageClock) -> Occupancy:
    """``occupancy`` with a finer grid around the primary subject of ``labels`` where it needs one."""
    if labels is None or not labels.subjects:
        return occupancy
    occupancy = occupancy.around(scene.gaussians, labels.subjects[0].gaussians)
    if occupancy.detail is not None:
        clock.done("detail", f"{int(occupancy.detail.free.sum())} free cells of {occupancy.detail.voxel:.3g}")
    return occupancy


def refine(
    scene: SceneDir,
    labels: PseudoLabels,
    starts: list[Camera],
    options: GroundOptions,
    clock: StageClock,
    occupancy: Occupancy | None = None,
    solve: bool = True,
) -> Refined:
    """Refine from the closed-form starts (with ``solve``, ``options.solve`` of them, which need
    ``occupancy``) alternating with ``starts``: up to ``attempts`` of them, stopping at the first
    whose pseudo-label clauses all hold, or the first ``candidates`` when ranking several. Runs
    whose clauses all held rank first, then by loss, a camera inside geometry last; poses within
    :data:`DISTINCT_ROTATION_DEG` / :data:`DISTINCT_TRANSLATION` of a better one are dropped."""
    scale = scene_scale(scene.cameras, scene.gaussians.means)
    solved = []
    if solve and options.solve and occupancy is not None and starts:
        solved = solve_candidates(scene.gaussians, labels, starts[0], occupancy, keep=options.solve)
        kept = [c.camera for c in solved if c.status == "kept"]
        clock.done("solve", f"{len(kept)} of {len(solved)} closed-form cameras free and unoccluded")
        starts = [camera for pair in itertools.zip_longest(kept, starts) for camera in pair if camera is not None]
    runs: list[tuple[Camera, RefineResult]] = []
    for start in starts[: max(options.candidates, options.attempts)]:
        result = refine_pose(scene.gaussians, start, labels, scale, options.refine, occupancy=occupancy)
        runs.append((start, result))
        clock.done(
            "refine", f"from {start.name}: {result.iterations} iterations, loss {result.losses.min():.4g} ({result.stop_reason})"
        )
        if options.candidates == 1 and result.stop_reason == "satisfied":
            break

    def inside(result: RefineResult) -> bool:
        return occupancy is not None and float(occupancy.clearance(camera_center(torch.as_tensor(result.T_cw)))) < 0

    runs.sort(key=lambda run: (inside(run[1]), run[1].stop_reason != "satisfied", float(run[1].losses.min())))
    distinct: list[tuple[Camera, RefineResult]] = []
    for run in runs:
        if not any(_same_pose(run[1].T_cw, kept[1].T_cw, scale) for kept in distinct):
            distinct.append(run)
    return Refined(distinct, solved)


def own_checker(scene: SceneDir, labels: PseudoLabels, occupancy: Occupancy | None = None) -> ConstraintChecker:
    """The checker of the method's own pseudo labels (what it believes it achieved, not a
    ground-truth verdict), with a clearance row when ``occupancy`` is given: built once for all
    the cameras of one instruction."""
    objects, members = {}, {}
    means = scene.gaussians.means.detach().double().numpy()
    for k, s in enumerate(labels.subjects):
        radius = float(np.sqrt(((means[s.gaussians] - s.centroid) ** 2).sum(1).mean()))
        # View angles around the view centre, as Refine and the closed form aim them.
        centre, _ = view_centre(scene.gaussians, s, np.asarray(labels.up, dtype=np.float64))
        objects[s.name] = Subject(k, s.name, centre, radius, s.front)
        member = torch.zeros(len(means), dtype=torch.bool)
        member[torch.as_tensor(s.gaussians)] = True
        members[k] = member
    return ConstraintChecker(scene.gaussians, objects, members, labels.up, occupancy=occupancy)


def own_report(checker: ConstraintChecker, parsed: ParsedInstruction, camera: Camera) -> CheckReport:
    """The per-clause report of ``camera`` by the method's own ``checker`` (:func:`own_checker`)."""
    report = checker.check(camera, parsed.constraints())
    report.text = parsed.text
    return report
