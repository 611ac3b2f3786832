"""Scale benchmark: the method on scenes of 0.3 to 3 million Gaussians at real-capture statistics.

The statistics of the captured 3DGS files in ``../shared/data/real`` (opacities, anisotropic
scales, floaters, huge faint Gaussians; :func:`capframe.synth.dense.capture_statistics`) are
measured and printed once. One synthetic room (the ``room`` preset, seed :data:`SEED`) is
generated with its instructions (written on the room as generated, verified by the ground-truth
checker), then refined to each size (:func:`capframe.synth.dense.densify`, SH degree 3) and
written as a scene directory; both are kept under ``results/bench/scale`` for later runs.

Each size is measured in a fresh process (so no size inherits another's memory), with the
embedded roles (oracle perception) as ``capframe ground`` runs them, phase by phase:

* ``load``: the scene directory read and the job opened (:func:`capframe.pipeline.stages.open_job`);
* ``views``: the per-scene cache built from empty: the training views' label renders and the
  occupancy grid;
* per query (:data:`QUERIES` instructions): ``retrieve`` (parse, coarse, QE), ``translate``,
  ``refine`` (free space, closed-form starts, the optimiser), ``result`` (the own-label report and
  the frame at the training views' size) and ``ground`` their sum, with the seconds of the
  ``occlusion`` phase inside Refine (the visibility check, and the occluded steps when needed);
* ``occlusion_forced``: one refinement from the first query's camera whose occlusion phase
  always runs (``min_visible`` above 1), the phase's own seconds and its steps;
* ``render_1000``: the ground camera's frame at 1000 px on the long side, colours included;
* ``ivs``: the IVS baseline's candidate search on the first query's pseudo labels.

Memory is the process's peak resident set within each phase (``VmHWM`` after resetting it through
``/proc/self/clear_refs``), so it includes what earlier phases still hold: the scene above all.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing as mp
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..scene._io import read_json

SIZES = "0.3M,1M,3M"
SEED = 3  # the room: six objects, furniture of several sizes
QUERIES = 2
VIEWS = 24
PHASES = ("load", "views", "retrieve", "translate", "refine", "result", "ground", "render_1000", "ivs")


def parse_sizes(text: str) -> list[int]:
    """``"0.3M,1M,250k"`` -> [300000, 1000000, 250000]; :class:`InputError` otherwise."""
    sizes = []
    for item in text.split(","):
        item = item.strip()
        unit = {"k": 1e3, "m": 1e6}.get(item[-1:].lower(), 1.0)
        try:
            value = float(item[:-1] if unit != 1.0 else item) * unit
        except ValueError:
            value = float("nan")
        if not (value >= 1000 and value <= 2e7):
            raise InputError(f"--sizes item {item!r}; expected a count of Gaussians from 1k to 20M, e.g. 0.3M or 250k")
        sizes.append(int(round(value)))
    return sizes


def size_label(count: int) -> str:
    return f"{count / 1e6:g}M" if count >= 100_000 else f"{count / 1e3:g}k"


class PeakMemory:
    """Peak resident memory of this process per phase: ``VmHWM`` reset through
    ``/proc/self/clear_refs`` (Linux) at each phase's start."""

    def __init__(self, label: str = ""):
        self.label = label  # progress lines on stderr name the phase after it
        self.peaks: dict[str, float] = {}
        self.seconds: dict[str, float] = {}
        self.cpu: dict[str, float] = {}  # process CPU seconds (all threads): what a busy machine's wall time hides

    @staticmethod
    def _reset() -> None:
        with contextlib.suppress(OSError):
            Path("/proc/self/clear_refs").write_text("5")

    @staticmethod
    def high_water_gb() -> float:
        """The resident peak since the last reset, in GB (1e9 bytes); NaN off Linux."""
        with contextlib.suppress(OSError):
            for line in Path("/proc/self/status").read_text().splitlines():
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024 / 1e9
        return float("nan")

    @contextlib.contextmanager
    def phase(self, name: str):
        self._reset()
        start, cpu = time.perf_counter(), time.process_time()
        yield
        seconds, cpu, peak = time.perf_counter() - start, time.process_time() - cpu, self.high_water_gb()
        self.seconds[name] = self.seconds.get(name, 0.0) + seconds
        self.cpu[name] = self.cpu.get(name, 0.0) + cpu
        self.peaks[name] = max(self.peaks.get(name, 0.0), peak)
        print(f"  {name}{self.label}: {seconds:.1f} s (CPU {cpu:.1f} s), peak {peak:.2f} GB", file=sys.stderr, flush=True)


def prepare_scenes(sizes: list[int], root: Path) -> tuple[dict, list[str], dict[int, Path]]:
    """The capture statistics' summary, the instruction texts and each size's scene directory
    (generated when absent; the room and its instructions once)."""
    from ..synth.dense import capture_statistics, densify
    from ..synth.generator import build_scene, write_scene
    from ..synth.instructions import write_instructions

    stats = capture_statistics()
    room = None
    base = root / "room"
    if not base.is_dir():
        room = build_scene(seed=SEED, preset="room", views=VIEWS)
        write_scene(room, base, None)
    sheet = root / "instructions"
    if not (sheet / "constraints.json").is_file():
        with contextlib.redirect_stdout(sys.stderr):
            write_instructions(base, sheet, count=QUERIES, seed=SEED)
    texts = [item["text"] for item in read_json(sheet / "constraints.json").values()][:QUERIES]
    scenes = {}
    for count in sizes:
        scenes[count] = root / f"scene-{size_label(count)}"
        if not scenes[count].is_dir():
            room = room or build_scene(seed=SEED, preset="room", views=VIEWS)
            start = time.perf_counter()
            write_scene(densify(room, count, stats, seed=SEED), scenes[count], None)
            print(f"{scenes[count]}: generated in {time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
    return stats.summary(), texts, scenes


def measure_size(scene_dir: Path, texts: list[str], work: Path) -> dict:
    """Every phase of the module doc on one scene, in this process: seconds and peak GB."""
    import torch

    from .._malloc import keep_freed_memory
    from ..backends import Question
    from ..backends.oracle import scene_labels
    from ..baselines.run import BaselineOptions, Search, _ivs, search_ranking
    from ..pipeline import GroundOptions, stages
    from ..pipeline.outputs import write_ground_result
    from ..refine.optimize import refine_pose
    from ..render import render
    from ..scene import scene_scale
    from ..scene.occupancy import cached_occupancy

    keep_freed_memory()  # as the capframe command runs
    meter = PeakMemory()
    cache = work / "cache"
    shutil.rmtree(work, ignore_errors=True)
    options = GroundOptions(cache_dir=cache)
    with meter.phase("load"):
        job = stages.open_job(scene_dir, options)
    scene = job.scene
    with meter.phase("views"):
        scene_labels(job.backends.context)  # the label renders of the training views
        cached_occupancy(scene.gaussians, job.up, scene.cameras, cache)
    rows, first = [], None
    for q, text in enumerate(texts):
        clock = stages.StageClock(False)
        per = PeakMemory(f" (query {q + 1})")
        with per.phase("retrieve"):
            parsed = stages.parse(job, text, clock)
            coarse = stages.coarse(job, parsed, clock)
            retrieved = stages.qe(job, coarse, options, clock)
        with per.phase("translate"):
            labels = stages.perceive(job, retrieved, options, clock)
        with per.phase("refine"):
            occupancy = stages.free_space(scene, job.up, options, clock, labels)
            starts = [scene.cameras[v] for v in job.view_indices(retrieved.starts)]
            refined = stages.refine(scene, labels, starts, options, clock, occupancy)
        with per.phase("result"):
            result = write_ground_result(work / f"ground-{q}", scene, labels, retrieved, refined, options, clock, occupancy)
        per.seconds["ground"] = sum(per.seconds[p] for p in ("retrieve", "translate", "refine", "result"))
        per.cpu["ground"] = sum(per.cpu[p] for p in ("retrieve", "translate", "refine", "result"))
        per.peaks["ground"] = max(per.peaks[p] for p in ("retrieve", "translate", "refine", "result"))
        occlusion = sum(r.occlusion_seconds for _, r in refined.runs)
        rows.append((per, occlusion, result["report"]["all_satisfied"]))
        print(f"  {text!r}: ground {per.seconds['ground']:.1f} s (occlusion {occlusion:.1f} s)", file=sys.stderr, flush=True)
        if first is None:
            first = (text, coarse, retrieved, labels, refined)
    text, coarse, retrieved, labels, refined = first
    start_camera, _ = refined.runs[0]
    forced = dataclasses.replace(options.refine, min_visible=1.01)
    with meter.phase("occlusion_forced"):
        occluded = refine_pose(scene.gaussians, start_camera, labels, scene_scale(scene.cameras, scene.gaussians.means), forced)
    occluded_steps = occluded.iterations - int(np.isnan(occluded.history["occlusion"]).sum()) + 1
    camera = refined.cameras[0].with_long_side(1000)
    with meter.phase("render_1000"), torch.no_grad():
        render(scene.gaussians, camera, background=(1.0, 1.0, 1.0))
    with meter.phase("ivs"):
        clock = stages.StageClock(False)
        scorer = job.backends["scorer"].scorer(
            retrieved.parsed, [Question(**q) for q in retrieved.retrieval["questions"]], labels
        )
        ranked = job.view_indices([v["view"] for v in retrieved.retrieval["views"]])
        ranking = search_ranking([coarse.coarse[name] for name in job.view_names], ranked)
        _ivs(Search(scene, ranking, labels, scorer, BaselineOptions(stages=options), clock, text, None))
    figures = {"gaussians": len(scene.gaussians)}
    for name in ("load", "views"):
        figures[f"{name}_s"], figures[f"{name}_gb"] = meter.seconds[name], meter.peaks[name]
        figures[f"{name}_cpu"] = meter.cpu[name]
    for name in ("retrieve", "translate", "refine", "result", "ground"):
        figures[f"{name}_s"] = float(np.mean([r[0].seconds[name] for r in rows]))
        figures[f"{name}_cpu"] = float(np.mean([r[0].cpu[name] for r in rows]))
        figures[f"{name}_gb"] = float(max(r[0].peaks[name] for r in rows))
    figures["ground_max_s"] = float(max(r[0].seconds["ground"] for r in rows))
    figures["ground_max_cpu"] = float(max(r[0].cpu["ground"] for r in rows))
    figures["occlusion_s"] = float(np.mean([r[1] for r in rows]))
    figures["own_labels_hold"] = sum(bool(r[2]) for r in rows)
    figures["occlusion_forced_s"] = occluded.occlusion_seconds
    figures["occlusion_forced_steps"] = occluded_steps
    figures["occlusion_forced_gb"] = meter.peaks["occlusion_forced"]
    figures["occlusion_forced_cpu"] = meter.cpu["occlusion_forced"]
    for name in ("render_1000", "ivs"):
        figures[f"{name}_s"], figures[f"{name}_gb"] = meter.seconds[name], meter.peaks[name]
        figures[f"{name}_cpu"] = meter.cpu[name]
    figures["peak_gb"] = max([*meter.peaks.values(), *(max(r[0].peaks.values()) for r in rows)])
    return figures


def _child(scene_dir: Path, texts: list[str], work: Path, queue) -> None:
    with contextlib.redirect_stdout(sys.stderr):
        queue.put(measure_size(scene_dir, texts, work))


def bench_scale(sizes: str | None = None, root: str | Path = "results/bench/scale") -> dict:
    """Measure every size of ``sizes`` (:func:`parse_sizes`; default :data:`SIZES`); returns
    ``{"capture": statistics summary, "queries": texts, "sizes": {label: figures}}``."""
    counts = parse_sizes(sizes or SIZES)
    root = Path(root)
    with contextlib.redirect_stdout(sys.stderr):
        capture, texts, scenes = prepare_scenes(counts, root)
    print(format_capture(capture), file=sys.stderr, flush=True)
    rows = {}
    ctx = mp.get_context("spawn")
    for count in counts:
        print(f"{size_label(count)}: measuring {scenes[count]}", file=sys.stderr, flush=True)
        queue = ctx.Queue()
        proc = ctx.Process(target=_child, args=(scenes[count], texts, root / "work", queue))
        proc.start()
        proc.join()
        if proc.exitcode != 0:
            raise RuntimeError(f"bench scale at {size_label(count)} failed in its process (exit code {proc.exitcode})")
        rows[size_label(count)] = queue.get()
    return {"capture": capture, "queries": texts, "sizes": rows}


def format_capture(capture: dict) -> str:
    """The capture statistics as a few lines."""
    lines = ["capture statistics (" + ", ".join(capture["files"]) + "):"]
    lines.append(f"  opacity deciles {capture['opacity_deciles']}")
    lines.append(f"  opacity histogram (10 bins over [0, 1]) {capture['opacity_histogram_10_bins']}")
    lines.append(
        f"  median scale ratio largest/smallest {capture['scale_ratio_max_min_median']:.3g}, "
        f"middle/smallest {capture['scale_ratio_mid_min_median']:.3g}"
    )
    lines.append(f"  floaters {capture['floater_share']:.2e}, huge faint {capture['huge_faint_share']:.2e} of the Gaussians")
    lines.append(
        f"  SH degree in the files: {capture['max_sh_degree']}; "
        f"bands 1-3 drawn with std {capture['sh_band_std_assumed']} (assumed)"
    )
    return "\n".join(lines)


def format_scale(figures: dict) -> str:
    """One row per phase, one column per size: wall seconds, process CPU seconds and peak GB."""
    sizes = figures["sizes"]
    labels = list(sizes)
    header = ["phase", *[f"{label} {unit}" for unit in ("s", "CPU s", "GB") for label in labels]]
    lines = [header]
    names = ["load", "views", "retrieve", "translate", "refine", "occlusion", "result", "ground", "ground_max"]
    names += ["occlusion_forced", "render_1000", "ivs", "peak"]
    for name in names:
        cells = [sizes[label].get(f"{name}_{unit}") for unit in ("s", "cpu", "gb") for label in labels]
        lines.append([name, *("" if v is None else f"{v:.3g}" for v in cells)])
    lines.append(["gaussians", *(str(sizes[label]["gaussians"]) for label in labels), *([""] * 2 * len(labels))])
    widths = [max(len(line[i]) for line in lines) for i in range(len(header))]
    text = "\n".join(
        "  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(line, widths))) for line in lines
    )
    return format_capture(figures["capture"]) + "\n" + text
