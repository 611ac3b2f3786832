"""Benchmarks printed by ``capframe bench WHAT`` (and ``make bench``): a table by default, one
JSON object with ``--json``."""

from __future__ import annotations

import json


def run_bench(what: str, *, as_json: bool = False, models: str | None = None, segmenter: str = "detector") -> dict:
    """Run benchmark ``what`` and print its figures; ``segment`` reads ``models`` (the models
    config) for ``segmenter``."""
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
    else:
        raise ValueError(f"unknown benchmark {what!r}")
    if as_json:
        print(json.dumps(figures))
    else:
        width = max(map(len, figures))
        for key, value in figures.items():
            print(f"{key:<{width}}  {value:.4g}" if isinstance(value, float) else f"{key:<{width}}  {value}")
    return figures
