"""Tables: per-instruction rows, per-method summaries, the comparison, the image grid."""

from __future__ import annotations

import numpy as np
import pandas as pd

from capframe.evaluate.aggregate import compare_command, instruction_rows, summary_table


def test_compare_ranks_methods(tmp_path):
    rows = [
        {"method": m, "instruction": f"i{k}", "all_satisfied": ok, "seconds": s, "iterations": 1, "region": ok}
        for m, oks, s in (("ivs", [True, False, False], 2.0), ("capframe", [True, True, False], 5.0))
        for k, ok in enumerate(oks)
    ]
    for method in ("capframe", "ivs"):
        pd.DataFrame([r for r in rows if r["method"] == method]).to_csv(tmp_path / f"{method}.csv", index=False)
    summary = compare_command([str(tmp_path / "ivs.csv"), str(tmp_path / "capframe.csv")], str(tmp_path / "methods.csv"))
    assert summary["method"].tolist() == ["capframe", "ivs"]
    assert summary["full_success"].tolist() == [2 / 3, 1 / 3]
    assert pd.read_csv(tmp_path / "methods.csv")["method"].tolist() == ["capframe", "ivs"] and (tmp_path / "methods.md").is_file()


def test_summary_reports_each_kinds_mean_error_over_the_instructions_that_have_it(tmp_path):
    """An instruction's error per kind is its worst row's (two subjects: 0 and 30 deg -> 30); the
    summary averages over the instructions with that kind (30 and 10 -> 20), not over all three."""
    import json

    def row(kind, ok, error):
        return {"constraint": kind, "subject": "s", "satisfied": ok, "error": error}

    reports = [
        [row("view", True, 0.0), row("view", False, 30.0), row("region", True, 0.0)],
        [row("view", True, 10.0), row("roll", None, None)],
        [row("region", False, 0.25)],
    ]
    checks, results = [], []
    for k, rows in enumerate(reports):
        checks.append(tmp_path / "scene-a" / f"i{k}.json")  # checks are laid out <method>/<scene>/<id>.json
        checks[-1].parent.mkdir(exist_ok=True)
        applicable = [r["satisfied"] for r in rows if r["satisfied"] is not None]
        checks[-1].write_text(
            json.dumps(
                {
                    "instruction_id": f"i{k}",
                    "all_satisfied": all(applicable),
                    "rows": rows,
                    "satisfied": sum(applicable),
                    "applicable": len(applicable),
                }
            )
        )
        results.append(tmp_path / f"r{k}.json")
        results[-1].write_text(json.dumps({"timings": {"total_s": 1.0 + k}, "iterations": 5}))
    frame = instruction_rows("capframe", checks, results)
    assert frame["scene"].tolist() == ["scene-a"] * 3
    assert frame["constraints_satisfied"].tolist() == [2 / 3, 1.0, 0.0]
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
        rows = [
            {"constraint": "region", "subject": "mug", "satisfied": ok},
            {"constraint": "roll", "subject": None, "satisfied": None},
        ]
        (tmp_path / f"{method}.json").write_text(
            json.dumps({"all_satisfied": ok, "satisfied": int(ok), "applicable": 1, "rows": rows})
        )
    out = tmp_path / "grid.png"
    grid_command(
        "the mug on the left",
        ["capframe", "ivs"],
        [str(tmp_path / "capframe"), str(tmp_path / "ivs")],
        [str(tmp_path / "capframe.json"), str(tmp_path / "ivs.json")],
        str(out),
    )
    image = Image.open(out)
    assert image.width > 2 * TILE_WIDTH and image.height > 240
    with pytest.raises(InputError, match="pair up"):
        grid_command("t", ["capframe"], [], [], str(out))
