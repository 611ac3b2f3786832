"""Benchmarks printed by ``capframe bench WHAT`` (and ``make bench``): a table by default, one
JSON object with ``--json``."""

from __future__ import annotations

import json


def run_bench(what: str, *, as_json: bool = False, models: str | None = None, segmenter: str = "detector") -> dict:
    """Run benchmark ``what`` and print its figures; ``segment`` reads ``models`` (the models
    config) for ``segmenter``, ``models`` also times the image encoders of ``models``."""
    if what == "render":
        from .render import bench_render

        figures = bench_render()
    elif what == "refine":
        from .refine import bench_refine

        figures = bench_refine()
    elif what == "ground":
        from .ground import bench_ground

        figures = bench_ground()
    elif what == "segment":
        from .segment import bench_segment

        figures = bench_segment(models, segmenter)
    elif what == "models":
        from .models import bench_models

        figures = bench_models(models)
    else:
        raise ValueError(f"unknown benchmark {what!r}")
    if as_json:
        print(json.dumps(figures))
    elif figures and all(isinstance(row, dict) for row in figures.values()):
        print_table(figures)
    else:
        width = max(map(len, figures))
        for key, value in figures.items():
            print(f"{key:<{width}}  {value:.4g}" if isinstance(value, float) else f"{key:<{width}}  {value}")
    return figures


def print_table(rows: dict[str, dict]) -> None:
    """One line per row, its figures in columns (numbers to 3 significant digits)."""
    columns = list(next(iter(rows.values())))
    cells = [
        [name] + [f"{row[c]:.3g}" if isinstance(row[c], float) else str(row[c]) for c in columns] for name, row in rows.items()
    ]
    header = ["", *columns]
    widths = [max(len(line[i]) for line in [header, *cells]) for i in range(len(header))]
    for line in [header, *cells]:
        print("  ".join(cell.ljust(w) if i == 0 else cell.rjust(w) for i, (cell, w) in enumerate(zip(line, widths))))
