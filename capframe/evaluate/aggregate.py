"""Aggregation of per-instruction results into tables: ``capframe aggregate``."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np
import pandas as pd

from ..scene._io import atomic_write, read_json


def instruction_rows(method: str, checks: list[Path], results: list[Path]) -> pd.DataFrame:
    """One row per instruction: overall verdict, verdict per constraint kind, run time.

    ``checks`` and ``results`` pair up: a check report (``capframe check -o``) and the method's
    ``result.json`` (for its wall time and iterations).
    """
    rows = []
    for check_path, result_path in zip(checks, results):
        report = read_json(check_path)
        result = read_json(result_path)
        row = {"method": method, "instruction": report.get("instruction_id") or Path(check_path).stem,
               "all_satisfied": bool(report["all_satisfied"]), "seconds": result.get("timings", {}).get("refine_s", np.nan),
               "iterations": result.get("iterations", np.nan)}
        kinds = defaultdict(list)
        for r in report["rows"]:
            if r["satisfied"] is not None:
                kinds[r["constraint"]].append(bool(r["satisfied"]))
        row.update({kind: all(v) for kind, v in kinds.items()})
        rows.append(row)
    return pd.DataFrame(rows)


def summary_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per method: full success rate, success rate per constraint kind, median and mean seconds."""
    kinds = [c for c in ("visibility", "region", "shot", "view", "elevation", "roll") if c in frame]
    out = frame.groupby("method").agg(instructions=("instruction", "count"), full_success=("all_satisfied", "mean"),
                                      median_s=("seconds", "median"), mean_s=("seconds", "mean"))
    for kind in kinds:
        out[f"{kind}_success"] = frame.groupby("method")[kind].apply(lambda s: s.dropna().astype(float).mean())
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
