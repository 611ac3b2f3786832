"""The paper's Table 1, quantitative comparison of the methods: ``capframe quantitative``.

One row per method (in the order given): the ground-truth columns (instructions, the share fully
satisfied, the mean share of an instruction's constraints satisfied), then the columns of what was
measured, each only when its inputs exist:

* ``clip``, ``siglip``: the mean image-text metric of the method's frames (``capframe metrics``;
  CLIP cosine in [-1, 1], SigLIP 2 sigmoid probability in (0, 1));
* ``<judge>_as``, ``<judge>_wr`` per judge: its mean 1-5 alignment score of the method's frames
  and the share of instructions in which it picked the method's frame among every judged method
  (``capframe judge``);
* ``rating_mean``, ``rating_n``, ``preference_share``: the user study
  (``results/tables/userstudy.csv``, written by ``capframe userstudy import``).

An absent column is named in the Markdown with what adds it; a method a judge or the user study
did not see has an empty cell, never a made-up value.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..errors import InputError
from .judging import JUDGE_HINT, judge_models, read_judgements
from .metrics import METRIC_HINT, METRIC_NAMES, METRICS, read_metrics
from .tables import _write_tables, markdown_table

USERSTUDY_COLUMNS = ("method", "rating_mean", "rating_n", "preference_share")
USERSTUDY_HINT = "run `capframe userstudy import` to add them"


def read_userstudy(path: str | Path) -> pd.DataFrame:
    """The user study's per-method table (:data:`USERSTUDY_COLUMNS`, one row per method)."""
    frame = pd.read_csv(path)
    missing = [c for c in USERSTUDY_COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(f"lacks columns {missing}; expected {', '.join(USERSTUDY_COLUMNS)}", source=str(path))
    if frame["method"].duplicated().any():
        raise InputError(f"methods {sorted(frame['method'][frame['method'].duplicated()])} repeat", source=str(path))
    return frame[list(USERSTUDY_COLUMNS)]


def _ground_truth(tables: list[str | Path]) -> pd.DataFrame:
    """Per method (in order): instructions, full success and mean constraints satisfied from
    ``capframe aggregate``'s per-instruction CSVs."""
    rows = []
    for path in tables:
        frame = pd.read_csv(path)
        missing = [c for c in ("method", "all_satisfied", "constraints_satisfied") if c not in frame.columns]
        if missing:
            raise InputError(f"lacks columns {missing}; expected a table of capframe aggregate", source=str(path))
        for method, group in frame.groupby("method", sort=False):
            rows.append(
                {
                    "method": method,
                    "instructions": len(group),
                    "full_success": group["all_satisfied"].astype(float).mean(),
                    "constraints_satisfied": group["constraints_satisfied"].mean(),
                }
            )
    return pd.DataFrame(rows)


def quantitative_table(
    tables: list[str | Path], metrics: list[str | Path], judgements: list[str | Path], userstudy: str | Path | None
) -> tuple[pd.DataFrame, list[str]]:
    """Table 1 (module docstring) and the notes naming the columns that are absent."""
    out = _ground_truth(tables)
    notes = []
    scores = read_metrics(metrics)
    for column in METRICS:
        if column in scores.columns:
            out[column] = out["method"].map(scores.groupby("method")[column].mean())
        else:
            notes.append(f"{METRIC_NAMES[column]}: {METRIC_HINT[column]}")
    verdicts = read_judgements(judgements)
    if verdicts.empty:
        notes.append(f"judge AS and WR: {JUDGE_HINT}")
    for judge, rows in verdicts.groupby("judge", sort=True):
        per_method = rows.groupby("method")
        out[f"{judge}_as"] = out["method"].map(per_method["rating"].mean())
        out[f"{judge}_wr"] = out["method"].map(per_method["picked"].mean())
    if userstudy is not None:
        study = read_userstudy(userstudy)
        unknown = sorted(set(study["method"]) - set(out["method"]))
        if unknown:
            raise InputError(f"methods {unknown} are not in the table's methods {list(out['method'])}", source=str(userstudy))
        out = out.merge(study, on="method", how="left")
    else:
        notes.append(f"user-study rating and preference: {USERSTUDY_HINT}")
    return out, notes


HEADERS = {
    "method": "Method",
    "instructions": "Instructions",
    "full_success": "Full success",
    "constraints_satisfied": "Constraints satisfied",
    "clip": "CLIP",
    "siglip": "SigLIP 2",
    "rating_mean": "User rating",
    "rating_n": "Ratings",
    "preference_share": "User preference",
}


def quantitative_markdown(frame: pd.DataFrame, notes: list[str], models: dict[str, str]) -> str:
    """The table with readable headers (a judge's columns as ``<judge> AS``, ``<judge> WR``),
    shares as percentages, then the judges' models and the absent columns."""
    view = frame.rename(columns=lambda c: HEADERS.get(c) or c.replace("_as", " AS").replace("_wr", " WR"))
    formats = {"CLIP": ".3f", "SigLIP 2": ".3f", "User rating": ".2f", "Ratings": "d"}
    for column in view.columns:
        if column.endswith(" AS"):
            formats[column] = ".2f"
    for column in [c for c in view.columns if c.endswith(" WR")] + ["User preference"]:
        if column in view:
            view[column] = [None if pd.isna(v) else f"{100 * v:.1f}%" for v in view[column]]
    view = view.astype(object).where(view.notna(), None)
    lines = [markdown_table(view, formats)]
    lines += [f"\n{judge}: {model}" for judge, model in models.items()]
    if notes:
        lines.append("\nNot measured: " + "; ".join(notes) + ".")
    return "\n".join(lines)


def quantitative_command(
    tables: list[str], metrics: list[str], judgements: list[str], userstudy: str | None, output: str
) -> pd.DataFrame:
    """``capframe quantitative``: :func:`quantitative_table` to ``output`` (CSV) and ``<stem>.md``."""
    frame, notes = quantitative_table(tables, metrics, judgements, userstudy)
    _write_tables(output, frame, quantitative_markdown(frame, notes, judge_models(judgements)))
    return frame
