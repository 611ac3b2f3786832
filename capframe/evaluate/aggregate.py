"""Aggregation of per-instruction results into tables: ``capframe aggregate`` and ``capframe compare``."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np
import pandas as pd

from ..scene._io import atomic_write, read_json

# Constraint kinds in table order, and the unit of each kind's checker error: the deviation from
# the target for view and roll, the distance to the accepted interval (0 inside) for the others;
# clearance (every camera has it) is the depth inside geometry.
KIND_UNITS = {
    "visibility": "fraction",
    "region": "frame",
    "shot": "frame",
    "view": "deg",
    "elevation": "deg",
    "roll": "deg",
    "clearance": "scene",
}


def instruction_rows(method: str, checks: list[Path], results: list[Path]) -> pd.DataFrame:
    """One row per instruction: its scene, overall verdict, share of its applicable constraints
    satisfied, verdict and worst checker error per constraint kind (``<kind>_error``, in
    :data:`KIND_UNITS`), run time.

    ``checks`` and ``results`` pair up: a check report (``capframe check -o``, laid out as
    ``<method>/<scene>/<id>.json``: the scene is its folder's name) and the method's
    ``result.json`` (for its wall time and iterations).
    """
    rows = []
    for check_path, result_path in zip(checks, results):
        report = read_json(check_path)
        result = read_json(result_path)
        applicable = report.get("applicable") or 0
        row = {
            "method": method,
            "scene": Path(check_path).parent.name,
            "instruction": report.get("instruction_id") or Path(check_path).stem,
            "all_satisfied": bool(report["all_satisfied"]),
            "constraints_satisfied": report["satisfied"] / applicable if applicable else np.nan,
            "seconds": result.get("timings", {}).get("total_s", np.nan),
            "iterations": result.get("iterations", np.nan),
        }
        kinds, errors = defaultdict(list), defaultdict(list)
        for r in report["rows"]:
            if r["satisfied"] is not None:
                kinds[r["constraint"]].append(bool(r["satisfied"]))
            if r.get("error") is not None:
                errors[r["constraint"]].append(float(r["error"]))
        row.update({kind: all(v) for kind, v in kinds.items()})
        row.update({f"{kind}_error": max(v) for kind, v in errors.items()})
        rows.append(row)
    return pd.DataFrame(rows)


def summary_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per method: full success rate, median and mean seconds, then per constraint kind its
    success rate and mean checker error (``<kind>_error_<unit>``, see :data:`KIND_UNITS`) over the
    instructions that have it."""
    out = frame.groupby("method").agg(
        instructions=("instruction", "count"),
        full_success=("all_satisfied", "mean"),
        median_s=("seconds", "median"),
        mean_s=("seconds", "mean"),
    )
    by_method = frame.groupby("method")
    for kind in KIND_UNITS:
        if kind in frame:
            out[f"{kind}_success"] = by_method[kind].apply(lambda s: s.dropna().astype(float).mean())
    for kind, unit in KIND_UNITS.items():
        if f"{kind}_error" in frame:
            out[f"{kind}_error_{unit}"] = by_method[f"{kind}_error"].mean()
    return out.reset_index()


def aggregate_command(method: str, checks: list[str], results: list[str], output: str) -> None:
    """Write the per-instruction table to ``output`` (CSV) and its summary beside it
    (``<output stem>_summary.csv`` and ``.md``), and print the summary."""
    if len(checks) != len(results):
        raise ValueError(f"{len(checks)} check reports but {len(results)} results; they must pair up")
    frame = instruction_rows(method, [Path(c) for c in checks], [Path(r) for r in results])
    summary = summary_table(frame)
    out = Path(output)
    atomic_write(out, frame.to_csv(index=False))
    atomic_write(out.with_name(out.stem + "_summary.csv"), summary.to_csv(index=False))
    markdown = summary.to_string(index=False, float_format=lambda v: f"{v:.3f}")
    atomic_write(out.with_name(out.stem + "_summary.md"), markdown + "\n")
    print(markdown)


def compare_command(tables: list[str], output: str) -> pd.DataFrame:
    """Summaries of several methods side by side, best full-success rate first (``output`` CSV,
    ``.md`` beside it), printed. Their error against end-to-end run time is ``capframe
    runtime``'s (``--methods-table``): each method's own timer here leaves out shared stages."""
    frame = pd.concat([pd.read_csv(t) for t in tables], ignore_index=True)
    summary = summary_table(frame).sort_values("full_success", ascending=False)
    out = Path(output)
    atomic_write(out, summary.to_csv(index=False))
    markdown = summary.to_string(index=False, float_format=lambda v: f"{v:.3f}")
    atomic_write(out.with_suffix(".md"), markdown + "\n")
    print(markdown)
    return summary
