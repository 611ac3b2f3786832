"""The package's layers: evaluation is a leaf the method never imports, and no import cycle."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "capframe"
# Benchmark machinery may read the ground truth; the method, the scene, the renderer and the
# backends may not. synth generates the ground truth and checks its instructions against it.
MAY_IMPORT_EVALUATION = ("capframe.evaluate", "capframe.bench", "capframe.synth", "capframe.cli")


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every capframe module ``path`` imports, at any depth of its code (function-level imports
    included), relative imports resolved."""
    module = _module_name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("capframe")}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            if base.startswith("capframe"):
                out.add(base)
                out |= {f"{base}.{a.name}" for a in node.names}
    return out


def _graph() -> dict[str, set[str]]:
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {name: {m for m in _imports(path) if m in modules and m != name} for name, path in modules.items()}


def test_no_module_of_the_method_imports_evaluation():
    offenders = {
        name: sorted(m for m in deps if m == "capframe.evaluate" or m.startswith("capframe.evaluate."))
        for name, deps in _graph().items()
        if not name.startswith(MAY_IMPORT_EVALUATION)
    }
    assert {k: v for k, v in offenders.items() if v} == {}


def test_the_import_graph_has_no_cycle():
    """Module-level or not, no module imports itself through others (a package importing its own
    submodules is not a cycle)."""
    graph = _graph()
    edges = {a: {b for b in deps if not a.startswith(b + ".") and not b.startswith(a + ".")} for a, deps in graph.items()}
    state: dict[str, int] = {}
    cycles = []

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(edges[node]):
            if state.get(nxt) == 1:
                cycles.append(path[path.index(nxt) :] + [nxt] if nxt in path else [node, nxt])
            elif nxt not in state:
                visit(nxt, [*path, nxt])
        state[node] = 2

    for start in sorted(edges):
        if start not in state:
            visit(start, [start])
    assert cycles == []


def test_the_walker_sees_function_level_and_relative_imports(tmp_path):
    """The checks above would pass vacuously if imports were missed: the old ground.py imported
    evaluation inside a function, relatively."""
    graph = _graph()
    assert "capframe.measure" in graph["capframe.pipeline.stages"]
    assert "capframe.evaluate.alignment" in graph["capframe.cli"]  # imported inside _cmd_colmap
