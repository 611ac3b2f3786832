"""Segment benchmark: ``capframe ground`` end to end with a model segmenter and the ``knn``
associator (every other role oracle), on the default suite's instructions whose subjects the
segmenter can name (for the closed-set ``detector``: every subject maps to a COCO class).

Scenes are prepared and caches warmed as in :mod:`capframe.bench.ground`. An instruction whose
subject the segmenter finds in none of the retrieved views ends with an input error: it counts
as a failure, its reason printed. Printed: full success (every constraint satisfied) over the
instructions run, the instructions grounded (a camera came out), the share of constraints
satisfied over those, the precision of the subjects' associated Gaussians against the scene's
labels (evaluation only), the median and maximum seconds per grounded instruction and the
benchmark's wall time (scene preparation and cache warm-up included).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from ..backends import check_choice
from ..errors import InputError
from ..pipeline import GroundOptions
from ..scene import load_scene_dir
from ..scene._io import read_json
from .ground import ground_and_check, prepared_cases
from .refine import DEFAULT_SUITE, suite_cases


def can_name(segmenter: str, subjects: list[str]) -> bool:
    """Whether ``segmenter`` can segment every subject: a closed-set detector only COCO classes."""
    if segmenter != "detector":
        return True
    from ..backends.detector import coco_class

    try:
        for name in subjects:
            coco_class(name)
    except InputError:
        return False
    return True


def association_precision(ground_dir: Path, labels_json: Path) -> list[float]:
    """Per subject of a result's ``labels.json``, the share of its Gaussians whose scene label is
    the subject's."""
    scene = load_scene_dir(ground_dir)
    ids = {o.name: o.id for o in scene.semantics}
    labels = scene.gaussians.labels.numpy()
    return [float((labels[s["gaussians"]] == ids[s["name"]]).mean()) for s in read_json(labels_json)["subjects"]]


def bench_segment(
    models: str | Path, segmenter: str = "detector", suite: str | Path = DEFAULT_SUITE, root: str | Path = "results/bench/suite"
) -> dict:
    """Run the benchmark with ``segmenter`` built from the ``models`` config (scenes, instructions
    and caches under ``root``, shared with the other benchmarks)."""
    check_choice("segmenter", segmenter)
    started = time.perf_counter()
    root = Path(root)
    rows, precision = [], []
    nameable, skipped = [], []
    for case in suite_cases(suite, root):
        if can_name(segmenter, [s.name for s in case[2].subjects]):
            nameable.append(case)
        else:
            skipped.append(case[1])
    for key, constraints, text, ground_dir, gravity, checker in prepared_cases(nameable, root):
        options = GroundOptions(
            cache_dir=root / "cache" / ground_dir.name,
            gravity=gravity,
            backends={"segmenter": segmenter, "associator": "knn"},
            models=models,
        )
        out = root / f"ground-{segmenter}" / key
        try:
            ok, satisfied, applicable, seconds = ground_and_check(ground_dir, text, out, options, checker, constraints)
        except InputError as err:
            rows.append((key, False, 0, 0, float("nan"), False))
            print(f"{key}: FAIL ({err})  {text}", file=sys.stderr, flush=True)
            continue
        precision += association_precision(ground_dir, out / "labels.json")
        rows.append((key, ok, satisfied, applicable, seconds, True))
        print(
            f"{key}: {'ok  ' if ok else 'FAIL'} {satisfied}/{applicable} constraints, {seconds:.1f} s, "
            f"association precision {', '.join(f'{p:.2f}' for p in precision[-len(constraints.subjects) :])}  {text}",
            file=sys.stderr,
            flush=True,
        )
    if not rows:
        raise InputError(f"--segmenter {segmenter}: no instruction of the suite has subjects it can name")
    times = np.array([r[4] for r in rows if r[5]])
    successes = sum(r[1] for r in rows)
    return {
        "segmenter": segmenter,
        "instructions": len(rows),
        "skipped": ", ".join(skipped) or "none",
        "full_success": f"{successes}/{len(rows)}",
        "full_success_rate": successes / len(rows),
        "grounded_instructions": f"{sum(r[5] for r in rows)}/{len(rows)}",
        "constraint_success_rate_grounded": float(sum(r[2] for r in rows) / max(1, sum(r[3] for r in rows))),
        "mean_association_precision": float(np.mean(precision)) if precision else float("nan"),
        "median_ground_s": float(np.median(times)) if len(times) else float("nan"),
        "max_ground_s": float(times.max()) if len(times) else float("nan"),
        "wall_s": time.perf_counter() - started,
    }
