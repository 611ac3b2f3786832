"""The benchmark's further tables: ``capframe sensitivity``, ``capframe groups``, ``capframe scene-table``,
``capframe runtime``.

Each verb writes a CSV and a Markdown table beside it (same stem, ``.md``), atomically, and prints
the Markdown.

* **Sensitivity** (the paper's Table "sensitivity"): each variant of the method against the
  unperturbed output, over the instructions both have a result for. ``ΔR`` is the geodesic angle
  between the two camera rotations (degrees), ``Δt`` the distance between the two camera centres
  divided by the scene scale (``ground_truth.json`` ``scale``), both averaged over the instructions;
  beside them the variant's full-success rate and its change against the reference's on the same
  instructions (ground-truth checks in place of the paper's CLIP/SigLIP deltas).
* **Groups** (the paper's Table "refine", Retrieve against Refine per dataset): per method and
  dataset group the full-success rate and the mean share of constraints satisfied, ground-truth
  checks in place of the paper's SigLIP 2 scores. Method ``retrieve`` is the retrieved view Refine
  starts from, unrefined.
* **Scenes**: per scene its views and Gaussians, whether COLMAP and gravity ran, COLMAP's
  registration and pose errors (``colmap.json``), the gravity error against the true up.
* **Runtime** (the paper's Table "time"): per scene the seconds of every stage summed over its
  jobs, from Snakemake's ``benchmark:`` files; per method the median seconds per instruction,
  end to end; with the methods table, every method's success and mean view error against those
  seconds, Pareto fronts marked (the error-against-run-time plot).
"""

from __future__ import annotations

import difflib
import io
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..scene._io import IMAGE_SUFFIXES, atomic_write, read_json
from ..scene.ply import _parse_header
from .ground_truth import read_ground_truth
from .metrics import METRIC_HINT, METRIC_NAMES, METRICS, parse_pair, read_metrics

DEFAULT_METHOD = "capframe"

# --- shared helpers --------------------------------------------------------------------------------


def rotation_delta_deg(R_a: np.ndarray, R_b: np.ndarray) -> float:
    """Geodesic angle between two rotations in degrees, accurate near 0 and 180 degrees
    (``atan2`` of the sine and cosine parts of ``R_a R_bᵀ``, not ``acos`` of the trace)."""
    D = np.asarray(R_a, dtype=np.float64) @ np.asarray(R_b, dtype=np.float64).T
    sine = 0.5 * np.linalg.norm([D[2, 1] - D[1, 2], D[0, 2] - D[2, 0], D[1, 0] - D[0, 1]])
    cosine = 0.5 * (np.trace(D) - 1.0)
    return math.degrees(math.atan2(sine, cosine))


def vector_angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two directions in degrees (``atan2(|a×b|, a·b)``: exact near 0 and 180)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b)))


def markdown_table(frame: pd.DataFrame, formats: dict[str, str] | None = None) -> str:
    """A GitHub pipe table of ``frame``: numbers with ``formats[column]`` (a format spec, default
    ``.3f`` for floats), NaN and None as an empty cell."""
    formats = formats or {}

    def cell(column: str, value) -> str:
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return ""
        if isinstance(value, (bool, np.bool_)):
            return "yes" if value else "no"
        if isinstance(value, (float, np.floating)):
            return format(float(value), formats.get(column, ".3f"))
        if isinstance(value, (int, np.integer)) and column in formats:
            return format(int(value), formats[column])
        return str(value).replace("|", "\\|")

    columns = [str(c) for c in frame.columns]
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for row in frame.itertuples(index=False):
        lines.append("| " + " | ".join(cell(c, v) for c, v in zip(columns, row)) + " |")
    return "\n".join(lines)


def _write_tables(output: str | Path, frame: pd.DataFrame, markdown: str) -> None:
    """``frame`` as CSV to ``output`` and ``markdown`` to ``<output stem>.md``, atomically; print it."""
    out = Path(output)
    atomic_write(out, frame.to_csv(index=False))
    atomic_write(out.with_suffix(".md"), markdown + "\n")
    print(markdown)


def _visible_dirs(root: Path) -> list[Path]:
    """Sub-folders of ``root`` by name, skipping hidden ones (atomic writes' temporary folders)."""
    return sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith("."))


# --- sensitivity -----------------------------------------------------------------------------------

# Variant name (without the "capframe-" prefix) -> (group, perturbation), in the paper's order.
# Top-K variants "top<K>" are recognised by pattern; any other name goes to the group "Other".
SENSITIVITY_GROUPS = ("Input text", "Top-K images", "Pseudo labels", "Refine", "Other")
_KNOWN_VARIANTS = {
    "paraphrase": ("Input text", "Paraphrased text"),
    "no-layout": ("Pseudo labels", "Layout label removal"),
    "no-orientation": ("Pseudo labels", "Orientation label removal"),
    "noise": ("Pseudo labels", "Moderate noise"),
}


def variant_label(name: str) -> tuple[str, str]:
    """(group, perturbation) of a variant for the sensitivity table."""
    key = name.removeprefix(DEFAULT_METHOD + "-")
    if key in _KNOWN_VARIANTS:
        return _KNOWN_VARIANTS[key]
    if key.startswith("top") and key[3:].isdigit():
        return "Top-K images", f"Top-{int(key[3:])} images"
    return "Other", key


def parse_variant_spec(spec: str) -> tuple[str, Path]:
    """``NAME=DIR`` as (name, folder); :class:`InputError` naming the spec otherwise."""
    name, folder = parse_pair(spec, "variant", "NAME=DIR", "top3=results/refine/capframe-top3")
    return name, Path(folder)


def result_folders(root: str | Path, what: str) -> dict[tuple[str, str], Path]:
    """``{(scene, instruction id): root/<scene>/<id>/result.json}`` of a method's result folders;
    :class:`InputError` naming ``root`` when it is missing."""
    root = Path(root)
    if not root.is_dir():
        raise InputError(
            f"{what} folder not found; expected <scene>/<id>/result.json folders (e.g. results/refine/capframe)", source=str(root)
        )
    found = {}
    for scene in _visible_dirs(root):
        for instruction in _visible_dirs(scene):
            if (instruction / "result.json").is_file():
                found[(scene.name, instruction.name)] = instruction / "result.json"
    return found


def _success(checks_root: Path, method: str, scene: str, instruction: str) -> bool | None:
    """``all_satisfied`` of ``<checks_root>/<method>/<scene>/<id>.json``, None when absent."""
    path = checks_root / method / scene / f"{instruction}.json"
    if not path.is_file():
        return None
    report = read_json(path)
    if not isinstance(report, dict) or "all_satisfied" not in report:
        raise InputError("not a check report: it lacks 'all_satisfied'", source=str(path))
    return bool(report["all_satisfied"])


def sensitivity_table(
    reference: str | Path,
    variants: list[tuple[str, Path]],
    checks_root: str | Path,
    scenes_root: str | Path,
    metrics: pd.DataFrame | None = None,
) -> pd.DataFrame:
    """One row per variant (grouped as in the paper): mean ΔR (deg) and Δt (/ scene scale) against
    the reference over the instructions both have results for, and the full-success rates.

    ``reference`` and each variant folder hold ``<scene>/<id>/result.json``; a folder's name is its
    method name in ``checks_root`` (``<checks_root>/<method>/<scene>/<id>.json``). The success
    rates are taken over the compared instructions that have a check report for both methods
    (``checked``); ``full_success_change`` is the variant's rate minus the reference's there.
    With ``metrics`` (``capframe metrics`` rows, methods named as the folders), ``delta_<metric>``
    is the mean of the variant's score minus the reference's over the compared instructions both
    have a score for (the paper's ΔCLIP and ΔSigLIP 2).
    """
    from .check import read_result_camera

    reference = Path(reference)
    checks_root, scenes_root = Path(checks_root), Path(scenes_root)
    ref_results = result_folders(reference, "reference")
    if not ref_results:
        raise InputError("no <scene>/<id>/result.json folders in the reference", source=str(reference))
    scales: dict[str, float] = {}
    cameras: dict[Path, object] = {}

    def camera(path: Path):
        if path not in cameras:
            cameras[path] = read_result_camera(path)[0]
        return cameras[path]

    columns = [c for c in METRICS if metrics is not None and c in metrics.columns]
    scores = {c: metrics.set_index(["method", "scene", "instruction"])[c].dropna().to_dict() for c in columns}
    rows = []
    for order, (name, folder) in enumerate(variants):
        var_results = result_folders(folder, f"variant {name!r}")
        common = sorted(set(ref_results) & set(var_results))
        d_rot, d_pos, ref_ok, var_ok = [], [], [], []
        for scene, instruction in common:
            if scene not in scales:
                scales[scene] = read_ground_truth(scenes_root / scene).scale
            a, b = camera(ref_results[(scene, instruction)]), camera(var_results[(scene, instruction)])
            d_rot.append(rotation_delta_deg(a.T_cw[:3, :3], b.T_cw[:3, :3]))
            d_pos.append(float(np.linalg.norm(a.center - b.center)) / scales[scene])
            ok_ref = _success(checks_root, reference.name, scene, instruction)
            ok_var = _success(checks_root, folder.name, scene, instruction)
            if ok_ref is not None and ok_var is not None:
                ref_ok.append(ok_ref)
                var_ok.append(ok_var)
        group, perturbation = variant_label(name)
        var_rate = float(np.mean(var_ok)) if var_ok else math.nan
        ref_rate = float(np.mean(ref_ok)) if ref_ok else math.nan
        rows.append(
            {
                "group": group,
                "perturbation": perturbation,
                "variant": name,
                "instructions": len(common),
                "only_reference": len(set(ref_results) - set(var_results)),
                "only_variant": len(set(var_results) - set(ref_results)),
                "delta_R_deg": float(np.mean(d_rot)) if d_rot else math.nan,
                "delta_t_rel": float(np.mean(d_pos)) if d_pos else math.nan,
                "checked": len(var_ok),
                "full_success": var_rate,
                "reference_success": ref_rate,
                "full_success_change": var_rate - ref_rate,
                "_order": order,
            }
        )
        for column, score in scores.items():
            deltas = [
                score[(folder.name, *key)] - score[(reference.name, *key)]
                for key in common
                if (folder.name, *key) in score and (reference.name, *key) in score
            ]
            rows[-1][f"delta_{column}"] = float(np.mean(deltas)) if deltas else math.nan
    frame = pd.DataFrame(rows)
    frame["_group"] = frame["group"].map(SENSITIVITY_GROUPS.index)
    return frame.sort_values(["_group", "_order"], kind="stable").drop(columns=["_group", "_order"]).reset_index(drop=True)


def sensitivity_markdown(frame: pd.DataFrame) -> str:
    """The paper's layout: Type, Perturbation, ΔR, Δt, then the success rates; a group's name only
    on its first row."""
    view = pd.DataFrame(
        {
            "Type": [g if i == 0 or g != frame["group"].iloc[i - 1] else "" for i, g in enumerate(frame["group"])],
            "Perturbation": frame["perturbation"],
            "Instructions": frame["instructions"],
            "ΔR (deg)": frame["delta_R_deg"],
            "Δt (/ scale)": frame["delta_t_rel"],
            "Full success": frame["full_success"],
            "Δ full success": frame["full_success_change"],
        }
    )
    formats = {"ΔR (deg)": ".2f", "Δt (/ scale)": ".3f", "Full success": ".3f", "Δ full success": "+.3f"}
    notes = []
    for column in METRICS:
        if f"delta_{column}" in frame.columns:
            view[f"Δ{METRIC_NAMES[column]}"] = frame[f"delta_{column}"]
            formats[f"Δ{METRIC_NAMES[column]}"] = "+.3f"
        else:
            notes.append(f"Δ{METRIC_NAMES[column]}: not measured ({METRIC_HINT[column]}).")
    return "\n\n".join([markdown_table(view, formats), *notes])


def sensitivity_command(
    reference: str, variants: list[str], checks_root: str, scenes_root: str, output: str, metrics: list[str] = ()
) -> pd.DataFrame:
    """``capframe sensitivity``: :func:`sensitivity_table` for ``NAME=DIR`` variant specs (and
    ``capframe metrics`` CSVs), written to ``output`` (CSV) and ``<stem>.md``, and printed."""
    specs = [parse_variant_spec(v) for v in variants]
    names = [n for n, _ in specs]
    if len(set(names)) != len(names):
        raise InputError(f"variant names {names} repeat; give each variant its own NAME")
    frame = sensitivity_table(reference, specs, checks_root, scenes_root, read_metrics(list(metrics)) if metrics else None)
    _write_tables(output, frame, sensitivity_markdown(frame))
    return frame


# --- dataset groups -------------------------------------------------------------------------------

ALL_GROUPS = "all"


def parse_group_spec(spec: str) -> tuple[str, str]:
    """``SCENE=GROUP`` as (scene, group); :class:`InputError` naming the spec otherwise."""
    return parse_pair(spec, "group", "SCENE=GROUP", "m360-garden=mipnerf360")


def group_table(tables: list[str | Path], groups: dict[str, str], metrics: pd.DataFrame | None = None) -> pd.DataFrame:
    """Per method (in the order of ``tables``) and dataset group, then over every group
    (``group = ALL_GROUPS``): instructions, full-success rate, the mean share of each
    instruction's constraints satisfied and, with ``metrics`` (``capframe metrics`` rows), the
    mean of each metric column it has (``siglip``: the paper's table; ``clip``).

    ``tables`` are per-instruction CSVs of ``capframe aggregate`` (with ``scene``,
    ``all_satisfied`` and ``constraints_satisfied`` columns); ``groups`` maps every scene in them
    to its group, whose order of first appearance orders the groups.
    """
    frames = []
    for path in tables:
        frame = pd.read_csv(path)
        missing = [c for c in ("method", "scene", "all_satisfied", "constraints_satisfied") if c not in frame.columns]
        if missing:
            raise InputError(f"lacks columns {missing}; expected a table of capframe aggregate (rerun it)", source=str(path))
        unknown = sorted(set(frame["scene"].astype(str)) - set(groups))
        if unknown:
            close = difflib.get_close_matches(unknown[0], list(groups), n=3) or sorted(groups)[:3]
            raise InputError(
                f"scenes {unknown} have no --group; closest known scenes to {unknown[0]!r}: {close}", source=str(path)
            )
        frames.append(frame.assign(group=frame["scene"].astype(str).map(groups)))
    if not frames:
        raise InputError("no tables given; expected capframe aggregate's per-instruction CSVs")
    frame = pd.concat(frames, ignore_index=True)
    columns = [c for c in METRICS if metrics is not None and c in metrics.columns]
    if columns:
        keys = ["method", "scene", "instruction"]
        frame["instruction"] = frame["instruction"].astype(str)
        frame = frame.merge(metrics[keys + columns], on=keys, how="left")
    frame = pd.concat([frame, frame.assign(group=ALL_GROUPS)], ignore_index=True)
    methods = list(dict.fromkeys(frame["method"]))
    order = list(dict.fromkeys(groups.values())) + [ALL_GROUPS]
    out = (
        frame.groupby(["method", "group"], sort=False)
        .agg(
            instructions=("all_satisfied", "size"),
            fully_satisfied=("all_satisfied", "sum"),
            full_success=("all_satisfied", "mean"),
            constraints_satisfied=("constraints_satisfied", "mean"),
            **{column: (column, "mean") for column in columns},
        )
        .reset_index()
    )
    out["fully_satisfied"] = out["fully_satisfied"].astype(int)
    keys = [(methods.index(m), order.index(g)) for m, g in zip(out["method"], out["group"])]
    return out.iloc[sorted(range(len(out)), key=keys.__getitem__)].reset_index(drop=True)


def group_markdown(frame: pd.DataFrame) -> str:
    """Two method-by-group tables: full success (rate and count) and the mean share of
    constraints satisfied."""
    groups = list(dict.fromkeys(frame["group"]))
    methods = list(dict.fromkeys(frame["method"]))
    cells = {(r.method, r.group): r for r in frame.itertuples(index=False)}

    def table(cell) -> str:
        rows = [{"method": m, **{g: cell(cells[(m, g)]) if (m, g) in cells else "" for g in groups}} for m in methods]
        return markdown_table(pd.DataFrame(rows, columns=["method", *groups]))

    text = (
        "Instructions fully satisfied, per dataset group\n\n"
        + table(lambda r: f"{r.full_success:.3f} ({r.fully_satisfied}/{r.instructions})")
        + "\n\nMean share of an instruction's constraints satisfied, per dataset group\n\n"
        + table(lambda r: f"{r.constraints_satisfied:.3f}")
    )
    for column in ("siglip", "clip"):
        if column in frame.columns:
            text += f"\n\nMean {METRIC_NAMES[column]} score, per dataset group\n\n" + table(
                lambda r, c=column: "" if pd.isna(getattr(r, c)) else f"{getattr(r, c):.3f}"
            )
        else:
            text += f"\n\n{METRIC_NAMES[column]}: not measured ({METRIC_HINT[column]})."
    return text


def group_table_command(tables: list[str], groups: list[str], output: str, metrics: list[str] = ()) -> pd.DataFrame:
    """``capframe groups``: :func:`group_table` for ``SCENE=GROUP`` specs (and ``capframe
    metrics`` CSVs), written to ``output`` (CSV) and ``<stem>.md``, and printed."""
    pairs = [parse_group_spec(g) for g in groups]
    mapping = dict(pairs)
    clashes = sorted({s for s, g in pairs if mapping[s] != g})
    if clashes:
        raise InputError(f"scenes {clashes} are given more than one group")
    frame = group_table(tables, mapping, read_metrics(list(metrics)) if metrics else None)
    _write_tables(output, frame, group_markdown(frame))
    return frame


# --- scenes ----------------------------------------------------------------------------------------

_IMAGE_SUFFIX_SET = {s.lower() for s in IMAGE_SUFFIXES}


def count_views(scene_dir: Path) -> int | None:
    """Training views of a scene: its images (``images/``, sub-folders included), else the entries
    of ``cameras.json``; None when it has neither."""
    images = scene_dir / "images"
    if images.is_dir():
        return sum(
            1
            for p in images.rglob("*")
            if p.suffix.lower() in _IMAGE_SUFFIX_SET and not any(part.startswith(".") for part in p.relative_to(images).parts)
        )
    if (scene_dir / "cameras.json").is_file():
        cameras = read_json(scene_dir / "cameras.json")
        return len(cameras) if isinstance(cameras, list) else None
    return None


def count_gaussians(ply: Path) -> int | None:
    """The vertex count in a PLY header (the file's data is not read); None without the file."""
    if not ply.is_file():
        return None
    with open(ply, "rb") as f:
        _, elements = _parse_header(f, str(ply))
    vertex = [e.count for e in elements if e.name == "vertex"]
    if not vertex:
        raise InputError("PLY has no 'vertex' element", source=str(ply))
    return vertex[0]


def _stat(record: dict, key: str, field: str, source: str) -> float:
    value = record.get(key)
    if value is None:
        return math.nan
    if not isinstance(value, dict) or not isinstance(value.get(field), (int, float)):
        raise InputError(f"'{key}' is {value!r}; expected {{'mean': number, 'max': number}}", source=source)
    return float(value[field])


def scene_rows(scenes_root: str | Path, colmap_root: str | Path, gravity_root: str | Path) -> pd.DataFrame:
    """One row per scene folder of ``scenes_root`` (hidden folders skipped): views, Gaussians,
    COLMAP (``<colmap_root>/<scene>/colmap.json``: registered/total, rotation error mean/max in
    degrees, position error mean/max in % of the scene scale) and gravity
    (``<gravity_root>/<scene>.json``: the angle between its up and ``ground_truth.json``'s up, its
    confidence; ``gravity_skipped`` when the file records an aligned scene)."""
    scenes_root, colmap_root, gravity_root = Path(scenes_root), Path(colmap_root), Path(gravity_root)
    if not scenes_root.is_dir():
        raise InputError("scenes folder not found; expected one scene directory per scene", source=str(scenes_root))
    rows = []
    for scene_dir in _visible_dirs(scenes_root):
        scene = scene_dir.name
        row = {"scene": scene, "views": count_views(scene_dir), "gaussians": count_gaussians(scene_dir / "scene.ply")}
        colmap_file = colmap_root / scene / "colmap.json"
        row["colmap"] = colmap_file.is_file()
        if row["colmap"]:
            record, source = read_json(colmap_file), str(colmap_file)
            if not isinstance(record, dict):
                raise InputError("expected a JSON object (capframe colmap's record)", source=source)
            row["registered"] = record.get("images_registered")
            row["images"] = record.get("images_total")
            row["rotation_error_mean_deg"] = _stat(record, "rotation_error_deg", "mean", source)
            row["rotation_error_max_deg"] = _stat(record, "rotation_error_deg", "max", source)
            row["position_error_mean_pct"] = 100 * _stat(record, "position_error_rel", "mean", source)
            row["position_error_max_pct"] = 100 * _stat(record, "position_error_rel", "max", source)
        gravity_file = gravity_root / f"{scene}.json"
        row["gravity"] = gravity_file.is_file()
        if row["gravity"]:
            record, source = read_json(gravity_file), str(gravity_file)
            if not isinstance(record, dict) or "up" not in record:
                raise InputError("lacks 'up'; expected capframe gravity's record", source=source)
            up = np.asarray(record["up"], dtype=np.float64)
            if up.shape != (3,) or not np.isfinite(up).all() or np.linalg.norm(up) == 0:
                raise InputError(f"'up' is {record['up']!r}; expected a non-zero direction", source=source)
            row["gravity_skipped"] = bool(record.get("skipped", False))
            row["gravity_error_deg"] = vector_angle_deg(up, read_ground_truth(scene_dir).up)
            row["gravity_confidence"] = record.get("confidence", math.nan)
        rows.append(row)
    if not rows:
        raise InputError("holds no scene folders", source=str(scenes_root))
    columns = [
        "scene",
        "views",
        "gaussians",
        "colmap",
        "registered",
        "images",
        "rotation_error_mean_deg",
        "rotation_error_max_deg",
        "position_error_mean_pct",
        "position_error_max_pct",
        "gravity",
        "gravity_skipped",
        "gravity_error_deg",
        "gravity_confidence",
    ]
    frame = pd.DataFrame(rows).reindex(columns=columns)
    for column in ("views", "gaussians", "registered", "images"):
        frame[column] = frame[column].astype("Int64")
    frame["gravity_skipped"] = frame["gravity_skipped"].astype("boolean")
    return frame


MEAN_ROW = "mean (gravity estimated)"


def scene_table(scenes_root: str | Path, colmap_root: str | Path, gravity_root: str | Path) -> pd.DataFrame:
    """:func:`scene_rows` and a bottom line, ``scene = MEAN_ROW``: the mean gravity error and
    confidence over the scenes whose gravity was estimated (ran and not skipped)."""
    frame = scene_rows(scenes_root, colmap_root, gravity_root)
    needed = frame[frame["gravity"] & ~frame["gravity_skipped"].fillna(False).astype(bool)]
    bottom = {
        "scene": MEAN_ROW,
        "gravity_error_deg": needed["gravity_error_deg"].mean() if len(needed) else math.nan,
        "gravity_confidence": needed["gravity_confidence"].mean() if len(needed) else math.nan,
    }
    return pd.concat([frame, pd.DataFrame([bottom])], ignore_index=True)


def scene_markdown(frame: pd.DataFrame) -> str:
    def registered(row) -> str:
        return f"{row.registered}/{row.images}" if row.colmap and not pd.isna(row.registered) else ""

    def flag(value) -> str:
        return "" if pd.isna(value) else ("yes" if value else "no")

    gravity = []
    for row in frame.itertuples(index=False):
        skipped = not pd.isna(row.gravity_skipped) and bool(row.gravity_skipped)
        gravity.append("" if row.scene == MEAN_ROW else ("skipped" if skipped else flag(row.gravity)))
    view = pd.DataFrame(
        {
            "Scene": frame["scene"],
            "Views": frame["views"],
            "Gaussians": frame["gaussians"],
            "COLMAP": [flag(v) for v in frame["colmap"]],
            "Registered": [registered(r) for r in frame.itertuples(index=False)],
            "Rot. err. mean/max (deg)": _pairs(frame, "rotation_error_mean_deg", "rotation_error_max_deg"),
            "Pos. err. mean/max (% scale)": _pairs(frame, "position_error_mean_pct", "position_error_max_pct"),
            "Gravity": gravity,
            "Gravity err. (deg)": frame["gravity_error_deg"],
            "Confidence": frame["gravity_confidence"],
        }
    )
    view = view.astype(object).where(view.notna(), None)
    return markdown_table(view, {"Gravity err. (deg)": ".2f", "Confidence": ".2f"})


def _pairs(frame: pd.DataFrame, mean: str, worst: str) -> list[str]:
    """``"mean / max"`` cells (two decimals), empty where either is missing."""
    return ["" if pd.isna(a) or pd.isna(b) else f"{a:.2f} / {b:.2f}" for a, b in zip(frame[mean], frame[worst])]


def scene_table_command(scenes_root: str, colmap_root: str, gravity_root: str, output: str) -> pd.DataFrame:
    """``capframe scene-table``: :func:`scene_table` to ``output`` (CSV) and ``<stem>.md``, printed."""
    frame = scene_table(scenes_root, colmap_root, gravity_root)
    _write_tables(output, frame, scene_markdown(frame))
    return frame


# --- runtime ---------------------------------------------------------------------------------------

# Per-scene stages, in pipeline order. Those in SHARED_STAGES serve the method (and the baselines),
# the others build the benchmark (scenes, instructions).
SCENE_STAGES = ("synth", "instructions", "colmap", "gravity", "views")
SHARED_STAGES = ("colmap", "gravity", "views")
# Per-instruction stages of the method, in order; a variant reuses the default method's output of
# each stage before the first one it overrides (workflow/rules/common.smk, stage_key).
METHOD_STAGES = ("coarse", "qe", "segment", "associate", "orient", "translate", "refine")
# Per-instruction stages that evaluate a method rather than run it: not in its cost.
EVALUATION_STAGES = ("check",)
# Benchmarks of the table-building jobs themselves (workflow/rules/evaluate.smk).
TABLES_STAGE = "tables"
# Methods fed the ground truth (oracle: Refine from ground-truth labels, reading the synthetic
# scene directly). They run no shared per-scene stage, no Retrieve or Translate, and are not
# methods a user can run: they cost only their own jobs and sit on no Pareto front.
GROUND_TRUTH_METHODS = ("oracle",)


def read_benchmark(path: str | Path, column: str = "s") -> float:
    """Seconds of one Snakemake ``benchmark:`` TSV: its ``column`` (``s``: wall; ``cpu_time``: CPU
    of the job's processes), the mean over the rows when the rule was benchmarked with repeats;
    :class:`InputError` naming the file otherwise."""
    try:
        table = pd.read_csv(path, sep="\t")
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as err:
        raise InputError(f"not a Snakemake benchmark TSV ({err})", source=str(path)) from None
    if column not in table.columns or table.empty:
        raise InputError(
            f"no {column!r} column with a row (columns {list(table.columns)}); expected a Snakemake benchmark TSV",
            source=str(path),
        )
    seconds = pd.to_numeric(table[column], errors="coerce")
    if seconds.isna().any():
        raise InputError(f"{column!r} holds {table[column].tolist()}; expected seconds", source=str(path))
    return float(seconds.mean())


def benchmark_records(root: str | Path) -> pd.DataFrame:
    """Every benchmark TSV under ``root`` as a row (stage, method, scene, instruction, seconds).

    Layouts (workflow/rules/*.smk): ``<stage>/<scene>.tsv`` (per scene: synth, instructions,
    colmap, gravity, views), ``<stage>/<method>/<scene>/<id>.tsv`` (per instruction: retrieve,
    translate, refine, check, ...) and ``<stage>/<scene>/<id>.tsv`` (per instruction, no method).
    ``tables/<name>.tsv`` (the jobs that build these tables, per run rather than per scene) is
    left out; files in another layout are skipped with a note on stderr.
    """
    root = Path(root)
    if not root.is_dir():
        raise InputError("benchmarks folder not found; expected Snakemake benchmark TSVs under it", source=str(root))
    rows, skipped = [], []
    for path in sorted(root.rglob("*.tsv")):
        parts = path.relative_to(root).with_suffix("").parts
        if any(p.startswith(".") for p in parts) or parts[0] == TABLES_STAGE:
            continue
        if len(parts) == 2:
            stage, method, scene, instruction = parts[0], None, parts[1], None
        elif len(parts) == 3:
            stage, method, scene, instruction = parts[0], None, parts[1], parts[2]
        elif len(parts) == 4:
            stage, method, scene, instruction = parts
        else:
            skipped.append(str(path))
            continue
        rows.append(
            {"stage": stage, "method": method, "scene": scene, "instruction": instruction, "seconds": read_benchmark(path)}
        )
    if skipped:
        print(
            f"capframe runtime: skipped {len(skipped)} benchmark files in an unknown layout, e.g. {skipped[0]}", file=sys.stderr
        )
    if not rows:
        raise InputError("holds no benchmark TSVs (<stage>/<scene>.tsv or <stage>/<method>/<scene>/<id>.tsv)", source=str(root))
    return pd.DataFrame(rows, columns=["stage", "method", "scene", "instruction", "seconds"])


def _column(stage: str, method: str | None) -> str:
    return f"{stage}/{method}" if isinstance(method, str) else stage  # None (NaN in a frame): per scene


def _column_order(column: str) -> tuple:
    stage, _, method = column.partition("/")
    if stage in SCENE_STAGES:
        return (0, SCENE_STAGES.index(stage), "")
    stages = METHOD_STAGES + ("baseline",) + EVALUATION_STAGES
    rank = stages.index(stage) if stage in stages else len(METHOD_STAGES) + 1
    # a method's stages side by side: default method first, then the others by name
    return (1, method != DEFAULT_METHOD, method, rank, stage) if stage not in EVALUATION_STAGES else (2, method, stage)


def runtime_per_scene(records: pd.DataFrame) -> pd.DataFrame:
    """Per scene: its instruction count ``n_instructions`` (distinct ids among its per-instruction
    benchmarks; the column ``instructions`` is that stage's seconds), the
    seconds of each stage summed over the scene's jobs (``<stage>`` or ``<stage>/<method>``),
    and their total."""
    records = records.assign(column=[_column(s, m) for s, m in zip(records["stage"], records["method"])])
    table = records.pivot_table(index="scene", columns="column", values="seconds", aggfunc="sum")
    table = table[sorted(table.columns, key=_column_order)]
    table["total"] = table.sum(axis=1)
    counts = records.dropna(subset=["instruction"]).groupby("scene")["instruction"].nunique()
    table.insert(0, "n_instructions", counts.reindex(table.index).fillna(0).astype(int))
    table.columns.name = None
    return table.reset_index()


# Stages of the default method whose jobs a method reuses instead of running its own: a variant
# "capframe-<name>" reuses every stage before the first it overrides, "retrieve" (the retrieved
# view unrefined, workflow/rules/method.smk) is Retrieve's coarse and QE jobs.
RETRIEVE_METHOD = "retrieve"


def reused_stages(method: str) -> tuple[str, ...]:
    """The default method's per-instruction stages ``method`` may reuse (see above)."""
    if method.startswith(DEFAULT_METHOD + "-"):
        return METHOD_STAGES
    return ("coarse", "qe") if method == RETRIEVE_METHOD else ()


def runtime_per_method(records: pd.DataFrame) -> pd.DataFrame:
    """Per method: the median (and mean) seconds per instruction, and the median of each part.

    The rule: an instruction of method ``M`` costs
      * the seconds of M's own per-instruction jobs (``<stage>/M/<scene>/<id>.tsv``, every stage
        but ``check``, which evaluates rather than runs it); for a stage M reuses (a variant
        ``capframe-<name>`` without a job of its own for ``coarse`` ... ``translate``, common.smk
        ``stage_key``; ``retrieve`` for ``coarse`` and ``qe``, :func:`reused_stages`) the
        default method's job for that instruction is counted instead;
      * plus, for every method but the oracle, the shared per-scene jobs (``colmap``,
        ``gravity``, ``views``) of its scene divided by the scene's instruction count (the
        distinct instruction ids among the scene's per-instruction benchmarks). ``synth`` and
        ``instructions`` build the benchmark and are not counted.
    An instruction is one of M's when M has at least one job of its own for it.
    """
    per_instruction = records.dropna(subset=["method", "instruction"])
    cost = per_instruction[~per_instruction["stage"].isin(EVALUATION_STAGES)]
    keyed = cost[["stage", "method", "scene", "instruction", "seconds"]].itertuples(index=False)
    seconds = {(stage, m, scene, i): v for stage, m, scene, i, v in keyed}
    scene_counts = records.dropna(subset=["instruction"]).groupby("scene")["instruction"].nunique()
    per_scene = records[records["instruction"].isna() & records["stage"].isin(SHARED_STAGES)]
    shared = per_scene.groupby("scene")["seconds"].sum()
    rows = []
    for method in sorted(cost["method"].unique(), key=lambda m: (m != DEFAULT_METHOD, m)):
        own = cost[cost["method"] == method]
        reused = reused_stages(method)
        stages = sorted(
            set(own["stage"]) | set(reused),
            key=lambda s: (METHOD_STAGES.index(s) if s in METHOD_STAGES else len(METHOD_STAGES), s),
        )
        for scene, instruction in sorted(set(zip(own["scene"], own["instruction"]))):
            row = {"method": method, "scene": scene, "instruction": instruction}
            for stage in stages:
                value = seconds.get((stage, method, scene, instruction))
                if value is None and stage in reused:
                    value = seconds.get((stage, DEFAULT_METHOD, scene, instruction))
                row[stage] = math.nan if value is None else value
            if method not in GROUND_TRUTH_METHODS:
                row["shared"] = shared.get(scene, 0.0) / scene_counts[scene]
            row["total"] = sum(v for k, v in row.items() if k not in ("method", "scene", "instruction") and not math.isnan(v))
            rows.append(row)
    frame = pd.DataFrame(rows)
    if frame.empty:
        return pd.DataFrame(columns=["method", "instructions", "median_s", "mean_s"])
    parts = [c for c in frame.columns if c not in ("method", "scene", "instruction", "total")]
    grouped = frame.groupby("method", sort=False)
    out = grouped.agg(instructions=("instruction", "size"), median_s=("total", "median"), mean_s=("total", "mean"))
    for part in parts:
        out[f"{part}_median_s"] = grouped[part].median()
    return out.reset_index()


def runtime_markdown(per_scene: pd.DataFrame, per_method: pd.DataFrame) -> str:
    return (
        "Seconds per scene (each stage summed over the scene's jobs)\n\n"
        + markdown_table(per_scene, {c: ".1f" for c in per_scene.columns if c not in ("scene", "n_instructions")})
        + "\n\nSeconds per instruction, per method (own jobs + shared per-scene jobs / the scene's instructions)\n\n"
        + markdown_table(per_method, {c: ".2f" for c in per_method.columns if c.endswith("_s")})
    )


def pareto_front(seconds: np.ndarray, score: np.ndarray) -> np.ndarray:
    """Indices of the points no other point beats on both time (lower) and ``score`` (higher),
    fastest first."""
    order = np.lexsort((-score, seconds))
    front, best = [], -np.inf
    for i in order:
        if score[i] > best:
            front.append(int(i))
            best = score[i]
    return np.asarray(front, dtype=int)


# The error axis of the error-against-run-time plot: the methods table's mean view error.
PARETO_ERROR = "view_error_deg"


def pareto_points(per_method: pd.DataFrame, methods: pd.DataFrame) -> pd.DataFrame:
    """Per method in both tables, fastest first: median end-to-end seconds per instruction
    (``per_method``, see :func:`runtime_per_method`), full-success rate and mean view error
    (``methods``, the ``capframe compare`` summary), and whether it is on the Pareto front of
    success against seconds (``front_success``) and of error against seconds (``front_error``),
    fronts taken over the methods not in :data:`GROUND_TRUTH_METHODS`."""
    columns = ["method", "full_success"] + ([PARETO_ERROR] if PARETO_ERROR in methods.columns else [])
    points = per_method[["method", "median_s"]].merge(methods[columns], on="method", how="inner")
    points = points.dropna(subset=["median_s", "full_success"]).sort_values("median_s", kind="stable").reset_index(drop=True)
    runnable = ~points["method"].isin(GROUND_TRUTH_METHODS).to_numpy()
    fronts = [("front_success", "full_success", 1.0)] + ([("front_error", PARETO_ERROR, -1.0)] if PARETO_ERROR in points else [])
    for front, value, sign in fronts:
        eligible = np.flatnonzero(runnable & points[value].notna().to_numpy())
        on = eligible[pareto_front(points["median_s"].to_numpy(float)[eligible], sign * points[value].to_numpy(float)[eligible])]
        points[front] = False
        points.loc[on, front] = True
    return points


def pareto_plot(points: pd.DataFrame) -> bytes:
    """PNG of :func:`pareto_points`: full success (and, where known, mean view error) against
    median seconds per instruction, log scale; front points ringed and joined by a step line,
    ground-truth methods grey. Points are numbered fastest first, with a key beside the panels
    (names would overlap: the variants of a method cluster)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter

    panels = [("full_success", "front_success", "instructions fully satisfied")]
    if PARETO_ERROR in points and points[PARETO_ERROR].notna().any():
        panels.append((PARETO_ERROR, "front_error", "mean view error (deg)"))
    fig, axes = plt.subplots(
        1, len(panels) + 1, figsize=(5.0 * len(panels) + 1.9, 3.8), dpi=120, width_ratios=[5.0] * len(panels) + [1.9]
    )
    numbers = {name: k + 1 for k, name in enumerate(points["method"])}
    for ax, (value, front, label) in zip(axes, panels):
        shown = points.dropna(subset=[value])
        on = shown[shown[front]].sort_values("median_s")
        ground_truth = shown["method"].isin(GROUND_TRUTH_METHODS)
        ax.scatter(shown["median_s"], shown[value], color=np.where(ground_truth, "tab:gray", "tab:blue"), zorder=2)
        ax.scatter(on["median_s"], on[value], s=140, facecolors="none", edgecolors="tab:red", zorder=3, label="Pareto front")
        ax.step(on["median_s"], on[value], where="post", color="tab:red", lw=1, zorder=1)
        for row in shown.itertuples(index=False):
            ax.annotate(
                str(numbers[row.method]),
                (row.median_s, getattr(row, value)),
                textcoords="offset points",
                xytext=(4, 3),
                fontsize=7,
            )
        ax.set_xscale("log")
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
        ax.xaxis.set_minor_formatter(FuncFormatter(lambda x, _: f"{x:g}" if f"{x:g}"[0] in "25" else ""))
        ax.set_xlabel("median seconds per instruction (end to end)")
        ax.set_ylabel(label)
        if value == "full_success":
            ax.set_ylim(-0.05, 1.05)
        ax.legend(loc="best", fontsize=8)
    key = axes[-1]
    key.axis("off")
    key.text(
        0.0,
        1.0,
        "\n".join(f"{k:>2}  {name}" for name, k in numbers.items()),
        va="top",
        ha="left",
        family="monospace",
        fontsize=8,
        transform=key.transAxes,
    )
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    return buffer.getvalue()


# The MLLM counters of a job (capframe.backends.mllm.cache.CachedChat.stats), as its stage clock
# records them (StageClock.counters: a stage's timing sidecar, a result's ``timings``).
MLLM_COUNTERS = (
    "mllm_calls",
    "mllm_cache_hits",
    "mllm_cache_misses",
    "mllm_prompt_tokens",
    "mllm_completion_tokens",
    "mllm_model_seconds",
)
# Folders of ``results/`` whose per-instruction jobs record MLLM counters, and the stage each is:
# the stage verbs' sidecars ``<folder>/<method>/<scene>/<id>.timings.json`` and the methods'
# ``<folder>/<method>/<scene>/<id>/result.json``.
SIDECAR_STAGES = {
    "parse": "parse",
    "coarse": "coarse",
    "retrieve": "qe",
    "segment": "segment",
    "associate": "associate",
    "orient": "orient",
}
RESULT_STAGES = {"refine": "refine", "baselines": "baseline"}


def _counters(values: dict, source: str) -> dict | None:
    """The MLLM counters of a timings mapping; None when it has none (no MLLM ran)."""
    if not isinstance(values, dict) or "mllm_calls" not in values:
        return None
    bad = [k for k in MLLM_COUNTERS if not isinstance(values.get(k), (int, float)) or isinstance(values.get(k), bool)]
    if bad:
        raise InputError(f"MLLM counters {bad} are not numbers", source=source)
    return {k: values[k] for k in MLLM_COUNTERS}


def mllm_records(root: str | Path) -> pd.DataFrame:
    """Every job's MLLM counters under a results folder ``root`` as rows (stage, method, scene,
    counters...): the stage verbs' timing sidecars (:data:`SIDECAR_STAGES`), the methods'
    ``result.json`` timings (:data:`RESULT_STAGES`) and the judges' records
    (``judges/<scene>.json``, one stage ``judge/<entry>`` per judge)."""
    root = Path(root)
    rows = []
    for folder, stage in SIDECAR_STAGES.items():
        for path in sorted((root / folder).glob("*/*/*.timings.json")):
            counters = _counters(read_json(path), str(path))
            if counters is not None:
                rows.append({"stage": stage, "method": path.parts[-3], "scene": path.parts[-2]} | counters)
    for folder, stage in RESULT_STAGES.items():
        for path in sorted((root / folder).glob("*/*/*/result.json")):
            counters = _counters(read_json(path).get("timings", {}), str(path))
            if counters is not None:
                rows.append({"stage": stage, "method": path.parts[-4], "scene": path.parts[-3]} | counters)
    for path in sorted((root / "judges").glob("*.json")):
        record = read_json(path)
        for entry, info in record.get("judges", {}).items():
            counters = _counters(info.get("mllm", {}), str(path))
            if counters is not None:
                rows.append({"stage": f"judge/{entry}", "method": None, "scene": record.get("scene", path.stem)} | counters)
    return pd.DataFrame(rows, columns=["stage", "method", "scene", *MLLM_COUNTERS])


def mllm_per_scene(records: pd.DataFrame) -> pd.DataFrame:
    """Per scene and stage (``<stage>/<method>`` for a method's stage): the MLLM counters summed
    over the jobs, and the share of requests answered from the response cache."""
    records = records.assign(column=[_column(s, m) for s, m in zip(records["stage"], records["method"])])
    out = records.groupby(["scene", "column"], sort=True)[list(MLLM_COUNTERS)].sum().reset_index()
    out = out.rename(columns={"column": "stage"})
    calls = out["mllm_calls"].where(out["mllm_calls"] > 0)
    out["cache_hit_rate"] = out["mllm_cache_hits"] / calls
    for column in MLLM_COUNTERS[:-1]:
        out[column] = out[column].astype(int)
    return out


def runtime_command(
    benchmarks: str, output: str, methods_table: str | None = None, results_root: str | None = None
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``capframe runtime``: the per-scene table to ``output`` (CSV), the per-method table to
    ``<stem>_methods.csv``, both in ``<stem>.md``; prints the Markdown. With ``methods_table``
    (``capframe compare``'s CSV) also the error-against-run-time points (``<stem>_pareto.csv``,
    in the Markdown) and their plot (``<stem>_pareto.png``). With ``results_root`` also the MLLM
    counters per scene and stage (:func:`mllm_records`: ``<stem>_mllm.csv``, in the Markdown)."""
    records = benchmark_records(benchmarks)
    per_scene, per_method = runtime_per_scene(records), runtime_per_method(records)
    out = Path(output)
    atomic_write(out.with_name(out.stem + "_methods.csv"), per_method.to_csv(index=False))
    markdown = runtime_markdown(per_scene, per_method)
    if methods_table is not None:
        methods = pd.read_csv(methods_table)
        if "method" not in methods.columns or "full_success" not in methods.columns:
            raise InputError("lacks 'method' or 'full_success'; expected capframe compare's CSV", source=methods_table)
        points = pareto_points(per_method, methods)
        atomic_write(out.with_name(out.stem + "_pareto.csv"), points.to_csv(index=False))
        atomic_write(out.with_name(out.stem + "_pareto.png"), pareto_plot(points))
        markdown += (
            "\n\nError against run time (median end-to-end seconds per instruction; front: on the Pareto front)\n\n"
            + markdown_table(points, {"median_s": ".2f", PARETO_ERROR: ".1f"})
        )
    if results_root is not None:
        calls = mllm_records(results_root)
        if calls.empty:
            markdown += "\n\nMLLM requests: none (no stage ran an MLLM backend)"
            table = pd.DataFrame(columns=["scene", "stage", *MLLM_COUNTERS, "cache_hit_rate"])
        else:
            table = mllm_per_scene(calls)
            markdown += (
                "\n\nMLLM requests per scene and stage (calls, answered from the response cache, asked of the model, "
                "tokens, the model's seconds)\n\n" + markdown_table(table, {"mllm_model_seconds": ".1f", "cache_hit_rate": ".3f"})
            )
        atomic_write(out.with_name(out.stem + "_mllm.csv"), table.to_csv(index=False))
    _write_tables(out, per_scene, markdown)
    return per_scene, per_method
