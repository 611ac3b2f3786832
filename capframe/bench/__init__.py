"""Benchmarks printed by ``capframe bench WHAT`` (and ``make bench``): a table by default, one
JSON object with ``--json``. ``--suite`` picks the suite of ``refine`` and ``ground`` (a name in
``config/suites`` or a path; default: the default suite); ``colmap`` takes ``--photos``,
``--reference`` and ``--points`` (default: the real capture in ``../shared/data/real``); ``scale``
takes ``--sizes`` (counts of Gaussians, e.g. ``0.3M,1M,3M``);
``ground`` on a suite whose instructions are committed (hand-written specs: the held-out sets) is
:mod:`capframe.bench.heldout`; ``ground --parse-only`` parses a suite's instructions without
placing any camera (:mod:`capframe.bench.parse_only`). The benchmarks that run the method write under ``results/bench``
(checked before any work, as every verb's outputs are); figures not measured are null in the JSON."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..scene._io import OUTPUTS, finite_or_null, json_text

SUITES = Path(__file__).resolve().parents[2] / "config" / "suites"
# Where refine, ground and segment write their scenes, runs and tables (relative to the working folder).
RESULTS = Path("results/bench")


def resolve_suite(suite: str | Path | None) -> Path:
    """The suite file named ``suite``: ``config/suites/<name>.yaml``, or a path; the default
    suite for None. :class:`InputError` naming the known suites otherwise."""
    if suite is None:
        return SUITES / "default.yaml"
    path = Path(suite)
    if path.is_file():
        return path
    named = SUITES / f"{suite}.yaml"
    if named.is_file():
        return named
    known = sorted(p.stem for p in SUITES.glob("*.yaml"))
    raise InputError(f"--suite {str(suite)!r} is neither a file nor a suite name; known: {known}")


def run_bench(
    what: str,
    *,
    as_json: bool = False,
    suite: str | Path | None = None,
    models: str | None = None,
    segmenter: str = "detector",
    benchmarks: str | None = None,
    photos: str | None = None,
    reference: str | None = None,
    points: str | None = None,
    sizes: str | None = None,
    parse_only: bool = False,
    blind: bool = False,
) -> dict:
    """Run benchmark ``what`` and print its figures; ``suite`` is refine's and ground's,
    ``segment`` reads ``models`` (the models config) for ``segmenter``, ``models`` also times the
    image encoders of ``models``, ``startup`` reads a workflow run's ``benchmarks`` folder;
    ``colmap`` runs on ``photos`` against ``reference`` and ``points``; ``scale`` on ``sizes``;
    ``parse_only`` turns ``ground`` into the parse-only check; ``blind`` keeps a held-out suite's
    words out of ``ground``'s progress lines."""
    if suite is not None and what not in ("refine", "ground"):
        raise InputError("--suite applies to bench refine and bench ground only")
    path = resolve_suite(suite)
    if (photos, reference, points) != (None, None, None) and what != "colmap":
        raise InputError("--photos, --reference and --points apply to bench colmap only")
    if sizes is not None and what != "scale":
        raise InputError("--sizes applies to bench scale only")
    if parse_only and what != "ground":
        raise InputError("--parse-only applies to bench ground only")
    if blind and (what != "ground" or parse_only):
        raise InputError("--blind applies to bench ground on a held-out suite only (not with --parse-only)")
    if what in ("refine", "ground", "segment", "colmap", "scale"):
        OUTPUTS["into"].check(RESULTS)
    if what == "render":
        from .render import bench_render

        figures = bench_render()
    elif what == "render-cuda":
        from ..render import resolve_backend

        if resolve_backend("auto") != "gsplat":  # "auto" is gsplat exactly when CUDA and gsplat are there
            raise InputError("bench render-cuda needs a CUDA device and gsplat (pip install -e .[cuda])")
        from .render import bench_render_cuda

        figures = bench_render_cuda()
    elif what == "refine":
        from ..synth.heldout import has_committed_instructions
        from .refine import bench_refine

        if has_committed_instructions(path):
            raise InputError(
                f"bench refine needs generated instructions (oracle labels); {path.name} commits its own", source=str(path)
            )
        figures = bench_refine(path)
    elif what == "ground" and parse_only:
        from .parse_only import bench_parse_only

        figures = bench_parse_only(path)
    elif what == "ground":
        from ..synth.heldout import has_committed_instructions

        if has_committed_instructions(path):
            from .heldout import bench_heldout

            figures = bench_heldout(path, blind=blind)
        elif blind:
            raise InputError(f"--blind applies to a suite with committed instructions (a held-out set); {path.name} has none")
        else:
            from .ground import bench_ground

            figures = bench_ground(path)
    elif what == "segment":
        from .segment import bench_segment

        figures = bench_segment(models, segmenter)
    elif what == "mllm":
        from .mllm import bench_mllm

        figures = bench_mllm()
    elif what == "startup":
        from .startup import bench_startup

        figures = bench_startup(benchmarks)
    elif what == "colmap":
        from .colmap import bench_colmap

        figures = bench_colmap(photos, reference, points, RESULTS / "colmap")
    elif what == "scale":
        from .scale import bench_scale

        figures = bench_scale(sizes, RESULTS / "scale")
    elif what == "models":
        from .models import bench_models

        figures = bench_models(models)
    else:
        raise ValueError(f"unknown benchmark {what!r}")
    if as_json:
        print(json_text(finite_or_null(figures), "the figures", indent=None))
    elif "sizes" in figures:
        from .scale import format_scale

        print(format_scale(figures))
    elif "median_parse_ms" in figures:
        from .parse_only import format_parse_summary

        print(format_parse_summary(figures))
    elif "per_kind" in figures:
        from .heldout import format_summary

        print(format_summary(figures))
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
