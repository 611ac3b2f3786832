"""Ground benchmark: ``capframe ground`` end to end on the synthetic default suite.

Each scene is prepared once as the workflow would (COLMAP for a scene without poses, mapped into
the ground-truth world for evaluation; a gravity file for a scene that is not aligned) and its
per-scene cache (label renders of the training views) is warmed before timing. Then every
instruction text goes through Retrieve -> Translate -> Refine with the embedded defaults and the
ground-truth checker judges the camera. Printed: the full-success rate (every constraint of the
instruction satisfied), the share of constraints satisfied, and the median and maximum wall time
per instruction with warm caches.
"""

from __future__ import annotations

import contextlib
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from ..evaluate.check import GroundTruthChecker, read_result_camera
from ..pipeline import GroundOptions, ground
from ..scene import load_scene_dir
from ..scene._io import read_json
from .refine import DEFAULT_SUITE, suite_cases


def prepare_scene(scene_dir: Path, root: Path) -> tuple[Path, Path | None]:
    """The scene directory to ground in and its gravity file (None when scene.json has an up):
    COLMAP poses when the scene has none, a gravity estimate when it is not aligned."""
    scene = load_scene_dir(scene_dir, load_gaussians=False)
    with contextlib.redirect_stdout(sys.stderr):  # their one-line summaries; stdout may carry --json
        return _prepare(scene_dir, scene, root)


def _prepare(scene_dir: Path, scene, root: Path) -> tuple[Path, Path | None]:
    from ..evaluate.alignment import align_truth_command
    from ..geometry.gravity import gravity_command
    from ..scene.sfm import colmap_command

    if not scene.cameras:
        posed = root / "posed" / scene_dir.name
        if not posed.is_dir():
            recovered = root / "sfm" / scene_dir.name
            if not recovered.is_dir():
                colmap_command(scene_dir, recovered)
            align_truth_command(recovered, scene_dir, posed)
        scene_dir, scene = posed, load_scene_dir(posed, load_gaussians=False)
    if scene.metadata.up is not None:
        return scene_dir, None
    gravity = root / "gravity" / f"{scene_dir.name}.json"
    if not gravity.is_file():
        gravity_command(scene_dir, gravity)
    return scene_dir, gravity


def ground_and_check(
    ground_dir: Path, text: str, out: Path, options: GroundOptions, checker: GroundTruthChecker, constraints
) -> tuple[bool, int, int, float]:
    """``ground`` one instruction with warm caches, timed, and its camera checked.

    Returns:
        (every constraint satisfied, constraints satisfied, constraints applicable, seconds).
    """
    shutil.rmtree(out, ignore_errors=True)
    if not (Path(options.cache_dir) / "label_views.npz").is_file():  # warm the cache, untimed
        ground(ground_dir, text, out, options, progress=False)
        shutil.rmtree(out)
    start = time.perf_counter()
    ground(ground_dir, text, out, options, progress=False)
    seconds = time.perf_counter() - start
    camera, _ = read_result_camera(out / "result.json")
    report = checker.check(camera, constraints)
    applicable = [r for r in report.rows if r.satisfied is not None]
    return report.all_satisfied, sum(bool(r.satisfied) for r in applicable), len(applicable), seconds


def prepared_cases(cases: list[tuple[Path, str, object]], root: Path):
    """Each of ``cases`` (:func:`suite_cases`' scene, id, constraints) with its text and its scene
    prepared as the workflow would (:func:`prepare_scene`, once per scene), its checker built once:
    yields ``(key, constraints, text, ground_dir, gravity, checker)``."""
    prepared, checkers = {}, {}
    for scene_dir, key, constraints in cases:
        if scene_dir not in prepared:
            prepared[scene_dir] = prepare_scene(scene_dir, root)
        ground_dir, gravity = prepared[scene_dir]
        if ground_dir not in checkers:
            checkers[ground_dir] = GroundTruthChecker(ground_dir)
        text = read_json(root / "instructions" / scene_dir.name / "constraints.json")[key]["text"]
        yield key, constraints, text, ground_dir, gravity, checkers[ground_dir]


def bench_ground(suite: str | Path = DEFAULT_SUITE, root: str | Path = "results/bench/suite") -> dict:
    root = Path(root)
    rows = []
    for key, constraints, text, ground_dir, gravity, checker in prepared_cases(suite_cases(suite, root), root):
        options = GroundOptions(cache_dir=root / "cache" / ground_dir.name, gravity=gravity)
        rows.append((key, *ground_and_check(ground_dir, text, root / "ground" / key, options, checker, constraints)))
        print(
            f"{key}: {'ok  ' if rows[-1][1] else 'FAIL'} {rows[-1][2]}/{rows[-1][3]} constraints, {rows[-1][4]:.1f} s  {text}",
            file=sys.stderr,
            flush=True,
        )
    times = np.array([r[4] for r in rows])
    return {
        "instructions": len(rows),
        "full_success_rate": float(np.mean([r[1] for r in rows])),
        "constraint_success_rate": float(sum(r[2] for r in rows) / max(1, sum(r[3] for r in rows))),
        "median_ground_s": float(np.median(times)),
        "max_ground_s": float(times.max()),
    }
