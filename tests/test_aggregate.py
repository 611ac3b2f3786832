"""Tables: per-method summaries, the comparison and its Pareto front."""

from __future__ import annotations

import numpy as np
import pandas as pd

from capframe.evaluate.aggregate import compare_command, instruction_rows, pareto_front, summary_table


def test_pareto_front_keeps_points_nothing_beats():
    seconds = np.array([1.0, 2.0, 3.0, 0.5, 10.0])
    success = np.array([0.5, 0.4, 0.9, 0.1, 0.9])
    # 2 s / 0.4 is beaten by 1 s / 0.5; 10 s / 0.9 by 3 s / 0.9.
    assert pareto_front(seconds, success).tolist() == [3, 0, 2]


def test_compare_ranks_methods_and_writes_the_plot(tmp_path):
    rows = [{"method": m, "instruction": f"i{k}", "all_satisfied": ok, "seconds": s, "iterations": 1, "region": ok}
            for m, oks, s in (("capframe", [True, True, False], 5.0), ("ivs", [True, False, False], 2.0))
            for k, ok in enumerate(oks)]  # fmt: skip
    for method in ("capframe", "ivs"):
        pd.DataFrame([r for r in rows if r["method"] == method]).to_csv(tmp_path / f"{method}.csv", index=False)
    summary = compare_command([str(tmp_path / "capframe.csv"), str(tmp_path / "ivs.csv")], str(tmp_path / "methods.csv"))
    assert summary["method"].tolist() == ["capframe", "ivs"]
    assert summary["full_success"].tolist() == [2 / 3, 1 / 3]
    assert (tmp_path / "methods.md").is_file() and (tmp_path / "methods_pareto.png").stat().st_size > 1000


def test_summary_reports_each_kinds_mean_error_over_the_instructions_that_have_it(tmp_path):
    """An instruction's error per kind is its worst row's (two subjects: 0 and 30 deg -> 30); the
    summary averages over the instructions with that kind (30 and 10 -> 20), not over all three."""
    import json

    def row(kind, ok, error):
        return {"constraint": kind, "subject": "s", "satisfied": ok, "error": error}

    reports = [[row("view", True, 0.0), row("view", False, 30.0), row("region", True, 0.0)],
               [row("view", True, 10.0), row("roll", None, None)],
               [row("region", False, 0.25)]]  # fmt: skip
    checks, results = [], []
    for k, rows in enumerate(reports):
        checks.append(tmp_path / f"i{k}.json")
        checks[-1].write_text(json.dumps({"instruction_id": f"i{k}", "all_satisfied": all(r["satisfied"] is not False for r in rows), "rows": rows}))
        results.append(tmp_path / f"r{k}.json")
        results[-1].write_text(json.dumps({"timings": {"total_s": 1.0 + k}, "iterations": 5}))
    frame = instruction_rows("capframe", checks, results)
    assert frame["view_error"].tolist()[:2] == [30.0, 10.0] and np.isnan(frame["view_error"][2])
    summary = summary_table(frame).iloc[0]
    assert summary["view_error_deg"] == 20.0 and summary["region_error_frame"] == 0.125
    assert summary["view_success"] == 0.5 and summary["full_success"] == 1 / 3 and "roll_error_deg" not in summary


def test_grid_puts_each_method_side_by_side(tmp_path):
    import json

    import pytest
    from PIL import Image

    from capframe.errors import InputError
    from capframe.evaluate.grid import TILE_WIDTH, grid_command

    for method, ok in (("capframe", True), ("ivs", False)):
        folder = tmp_path / method
        folder.mkdir()
        Image.new("RGB", (160, 120), "gray").save(folder / "render.png")
        rows = [{"constraint": "region", "subject": "mug", "satisfied": ok}, {"constraint": "roll", "subject": None, "satisfied": None}]
        (tmp_path / f"{method}.json").write_text(json.dumps({"all_satisfied": ok, "satisfied": int(ok), "applicable": 1, "rows": rows}))
    out = tmp_path / "grid.png"
    grid_command("the mug on the left", ["capframe", "ivs"], [str(tmp_path / "capframe"), str(tmp_path / "ivs")],
                 [str(tmp_path / "capframe.json"), str(tmp_path / "ivs.json")], str(out))  # fmt: skip
    image = Image.open(out)
    assert image.width > 2 * TILE_WIDTH and image.height > 240
    with pytest.raises(InputError, match="pair up"):
        grid_command("t", ["capframe"], [], [], str(out))
