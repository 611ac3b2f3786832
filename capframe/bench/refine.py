"""Refine benchmark: the optimiser alone, on the synthetic default suite.

Pseudo labels come from the ground truth (oracle), so only the optimiser is measured. Each
instruction starts from a training view in which the primary subject is visible, drawn with a
fixed seed (not the best view). The checker judges the final camera. Printed: the share of
constraints satisfied and the median refinement time at the default resolution, then a sweep
of optimisation resolutions and iteration budgets (error against wall time) with the deviation
of each low-resolution pose from the full-resolution one. The sweep is written to
``<out>/sweep.csv`` and ``<out>/error_vs_time.png``.
"""

from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path

import numpy as np

from ..constraints import Constraints
from ..evaluate.check import GroundTruthChecker
from ..evaluate.ground_truth import read_ground_truth
from ..evaluate.oracle import initial_view, oracle_labels
from ..geometry import pose_deviation
from ..refine import RefineConfig, refine_pose
from ..scene import load_scene_dir, scene_scale
from ..scene._io import read_json

DEFAULT_SUITE = Path(__file__).resolve().parents[2] / "config" / "suites" / "default.yaml"


def suite_cases(suite: str | Path, root: Path) -> list[tuple[Path, str, Constraints]]:
    """(scene_dir, instruction id, constraints) of every instruction of ``suite``, generating the
    scenes and instructions under ``root`` when they are not there yet."""
    from ..synth.generator import generate_scene
    from ..synth.instructions import write_instructions
    from ..synth.suite import load_suite

    _, scenes = load_suite(suite)
    cases = []
    for entry in scenes:
        scene_dir = root / "scenes" / entry.id
        if not scene_dir.is_dir():
            generate_scene(scene_dir, **entry.generate_kwargs())
        sheet = root / "instructions" / entry.id
        if not (sheet / "constraints.json").is_file():
            write_instructions(scene_dir, sheet, count=entry.instructions, seed=entry.seed)
        for key, item in read_json(sheet / "constraints.json").items():
            cases.append((scene_dir, key, Constraints.from_dict(item["constraints"])))
    return cases


def bench_refine(
    suite: str | Path = DEFAULT_SUITE,
    root: str | Path = "results/bench/suite",
    sweep: bool = True,
    out: str | Path = "results/bench/refine",
) -> dict:
    """Run the benchmark on ``suite``; scenes and instructions are generated under ``root`` (shared
    with the other benchmarks), the sweep is written under ``out``."""
    root, out = Path(root), Path(out)
    cases = suite_cases(suite, root)
    default = RefineConfig()
    settings = [("default", default)]
    if sweep:
        settings += [(f"res{r}", dataclasses.replace(default, long_side=r)) for r in (80, 320)]
        settings += [(f"iters{n}", dataclasses.replace(default, iterations=n)) for n in (50, 150)]
    rows, loaded = [], {}
    for scene_dir, key, constraints in cases:
        if scene_dir not in loaded:
            scene = load_scene_dir(scene_dir)
            # The scale capframe refine (and the workflow) use: the method does not know gt.scale.
            loaded[scene_dir] = (
                scene.gaussians,
                read_ground_truth(scene_dir),
                GroundTruthChecker(scene_dir),
                scene_scale(scene.cameras, scene.gaussians.means),
            )
        gaussians, gt, checker, scale = loaded[scene_dir]
        labels = oracle_labels(gaussians, gt, constraints)
        camera = initial_view(scene_dir, gt, constraints, key)
        full_res_pose = None
        for name, config in settings:
            result = refine_pose(gaussians, camera, labels, scale, config)
            report = checker.check(camera.with_pose(result.T_cw), constraints)
            judged = [r for r in report.rows if r.satisfied is not None]
            if name == "res320":
                full_res_pose = result.T_cw
            rows.append(
                {
                    "setting": name,
                    "long_side": config.long_side,
                    "iterations_budget": config.iterations,
                    "scene": scene_dir.name,
                    "instruction": key,
                    "seconds": result.seconds,
                    "iterations": result.iterations,
                    "stop_reason": result.stop_reason,
                    "constraints": len(judged),
                    "satisfied": sum(r.satisfied for r in judged),
                    "all_satisfied": report.all_satisfied,
                    "T_cw": result.T_cw,
                    "scale": scale,
                }
            )
        if full_res_pose is not None:
            for row in rows[-len(settings) :]:
                row["dR_deg"], row["dt_rel"] = pose_deviation(row["T_cw"], full_res_pose, row["scale"])
    return _summarise(rows, out, sweep)


def _summarise(rows: list[dict], out: Path, sweep: bool) -> dict:
    by_setting: dict[str, list[dict]] = {}
    for row in rows:
        by_setting.setdefault(row["setting"], []).append(row)
    figures = {}
    summary = []
    for name, group in by_setting.items():
        total = sum(r["constraints"] for r in group)
        entry = {
            "setting": name,
            "long_side": group[0]["long_side"],
            "iterations_budget": group[0]["iterations_budget"],
            "constraint_success_rate": sum(r["satisfied"] for r in group) / max(total, 1),
            "full_success_rate": float(np.mean([r["all_satisfied"] for r in group])),
            "median_s": float(np.median([r["seconds"] for r in group])),
            "mean_s": float(np.mean([r["seconds"] for r in group])),
            "mean_iterations": float(np.mean([r["iterations"] for r in group])),
        }
        if "dR_deg" in group[0]:
            entry["mean_dR_deg"] = float(np.mean([r["dR_deg"] for r in group]))
            entry["mean_dt_rel"] = float(np.mean([r["dt_rel"] for r in group]))
        summary.append(entry)
    default = next(s for s in summary if s["setting"] == "default")
    figures["instructions"] = len(by_setting["default"])
    figures["constraint_success_rate"] = default["constraint_success_rate"]
    figures["full_success_rate"] = default["full_success_rate"]
    figures["median_refine_s"] = default["median_s"]
    figures["mean_iterations"] = default["mean_iterations"]
    if sweep:
        for s in summary:
            if s["setting"] != "default":
                figures[f"{s['setting']}_constraint_success_rate"] = s["constraint_success_rate"]
                figures[f"{s['setting']}_median_s"] = s["median_s"]
        figures["default_vs_full_res_dR_deg"] = default.get("mean_dR_deg", math.nan)
        figures["default_vs_full_res_dt_rel"] = default.get("mean_dt_rel", math.nan)
        figures["res80_vs_full_res_dR_deg"] = next(s for s in summary if s["setting"] == "res80").get("mean_dR_deg", math.nan)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "sweep.csv", "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=[k for k in rows[0] if k != "T_cw"], extrasaction="ignore")
            writer.writeheader()
            writer.writerows(rows)
        _plot(summary, out / "error_vs_time.png")
        figures["sweep_csv"] = str(out / "sweep.csv")
    return figures


def _plot(summary: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4), dpi=120)
    for s in summary:
        ax.scatter(s["mean_s"], 1.0 - s["constraint_success_rate"], s=30)
        ax.annotate(
            s["setting"], (s["mean_s"], 1.0 - s["constraint_success_rate"]), textcoords="offset points", xytext=(4, 4), fontsize=8
        )
    ax.set_xlabel("mean refinement time per instruction (s)")
    ax.set_ylabel("constraints not satisfied (share)")
    ax.set_title("Refine with oracle pseudo labels: error against run time")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
