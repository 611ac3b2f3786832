"""Sensitivity, scene and runtime tables from hand-built result folders, records and benchmark TSVs."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from capframe.cli import main
from capframe.errors import InputError
from capframe.evaluate.tables import (
    ALL_GROUPS,
    MEAN_ROW,
    benchmark_records,
    group_table_command,
    pareto_front,
    pareto_points,
    parse_variant_spec,
    read_benchmark,
    rotation_delta_deg,
    runtime_command,
    scene_table_command,
    sensitivity_command,
    vector_angle_deg,
)

K = [[100.0, 0.0, 32.0], [0.0, 100.0, 24.0], [0.0, 0.0, 1.0]]


def rot_z(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def pose(R: np.ndarray, center) -> np.ndarray:
    """T_cw of a camera with rotation R (world to camera) and centre C: t = -R C."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = -R @ np.asarray(center, dtype=np.float64)
    return T


def write_json(path, value) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(value))


def write_result(root, method, scene, instruction, T) -> None:
    write_json(
        root / "refine" / method / scene / instruction / "result.json",
        {"T_cw": T.tolist(), "K": K, "width": 64, "height": 48, "instruction_id": instruction},
    )


def write_check(root, method, scene, instruction, ok: bool) -> None:
    write_json(root / "check" / method / scene / f"{instruction}.json", {"all_satisfied": ok, "rows": []})


def write_scene(root, scene, scale=4.0, up=(0.0, 0.0, 1.0), views=3, gaussians=None) -> None:
    folder = root / "scenes" / scene
    write_json(
        folder / "ground_truth.json",
        {"up": list(up), "scale": scale, "objects": [{"name": "ball", "center": [0, 0, 0], "radius": 1}]},
    )
    (folder / "images").mkdir(parents=True)
    for i in range(views):
        (folder / "images" / f"v{i:02d}.png").write_bytes(b"")
    if gaussians is not None:
        (folder / "scene.ply").write_bytes(
            f"ply\nformat binary_little_endian 1.0\nelement vertex {gaussians}\nproperty float x\nend_header\n".encode()
        )


# --- sensitivity -----------------------------------------------------------------------------------


def test_rotation_and_vector_angles_are_exact():
    assert rotation_delta_deg(np.eye(3), rot_z(90)) == pytest.approx(90.0, abs=1e-12)
    assert rotation_delta_deg(rot_z(179.9), np.eye(3)) == pytest.approx(179.9, abs=1e-9)
    assert rotation_delta_deg(rot_z(1e-6), np.eye(3)) == pytest.approx(1e-6, rel=1e-6)
    assert vector_angle_deg([0, 0, 1], [1, 0, 1]) == pytest.approx(45.0)
    assert vector_angle_deg([0, 0, 1], [0, 0, -2]) == pytest.approx(180.0)  # a flipped up is 180 degrees off


def test_sensitivity_deltas_on_hand_built_poses(tmp_path, capsys):
    write_scene(tmp_path, "s1", scale=4.0)
    base = pose(np.eye(3), [0.0, 0.0, -5.0])
    for i in ("a", "b"):
        write_result(tmp_path, "capframe", "s1", i, base)
        write_check(tmp_path, "capframe", "s1", i, i == "a")
    # a: rotated 90 degrees about z, same centre; b: same rotation, centre moved by 2 units (scale 4)
    write_result(tmp_path, "capframe-top3", "s1", "a", pose(rot_z(90), [0.0, 0.0, -5.0]))
    write_result(tmp_path, "capframe-top3", "s1", "b", pose(np.eye(3), [2.0, 0.0, -5.0]))
    write_check(tmp_path, "capframe-top3", "s1", "a", True)
    write_check(tmp_path, "capframe-top3", "s1", "b", True)
    out = tmp_path / "tables" / "sensitivity.csv"
    frame = sensitivity_command(
        str(tmp_path / "refine" / "capframe"),
        [f"top3={tmp_path / 'refine' / 'capframe-top3'}"],
        str(tmp_path / "check"),
        str(tmp_path / "scenes"),
        str(out),
    )
    row = frame.iloc[0]
    assert (row["group"], row["perturbation"], row["instructions"]) == ("Top-K images", "Top-3 images", 2)
    assert row["delta_R_deg"] == pytest.approx((90.0 + 0.0) / 2)
    assert row["delta_t_rel"] == pytest.approx((0.0 + 0.5) / 2)
    assert row["full_success"] == 1.0 and row["reference_success"] == 0.5 and row["full_success_change"] == 0.5
    assert pd.read_csv(out)["delta_R_deg"].iloc[0] == pytest.approx(45.0)
    markdown = out.with_suffix(".md").read_text()
    assert "| Top-K images | Top-3 images | 2 | 45.00 | 0.250 | 1.000 | +0.500 |" in markdown
    assert markdown.strip() in capsys.readouterr().out


def test_sensitivity_compares_the_intersection_and_groups_like_the_paper(tmp_path):
    write_scene(tmp_path, "s1", scale=2.0)
    write_scene(tmp_path, "s2", scale=10.0)
    base = pose(np.eye(3), [0.0, 0.0, -5.0])
    for scene, i in (("s1", "a"), ("s1", "b"), ("s2", "c")):
        write_result(tmp_path, "capframe", scene, i, base)
    # no-layout misses b and adds d (no reference): only a and c are compared
    write_result(tmp_path, "capframe-no-layout", "s1", "a", pose(np.eye(3), [1.0, 0.0, -5.0]))  # 1/2
    write_result(tmp_path, "capframe-no-layout", "s2", "c", pose(rot_z(30), [0.0, 0.0, -5.0]))  # 30 deg
    write_result(tmp_path, "capframe-no-layout", "s2", "d", pose(rot_z(80), [9.0, 0.0, -5.0]))
    write_result(tmp_path, "capframe-paraphrase", "s1", "a", base)
    refine = tmp_path / "refine"
    frame = sensitivity_command(
        str(refine / "capframe"),
        [f"no-layout={refine / 'capframe-no-layout'}", f"capframe-paraphrase={refine / 'capframe-paraphrase'}"],
        str(tmp_path / "check"),
        str(tmp_path / "scenes"),
        str(tmp_path / "s.csv"),
    )
    assert frame["group"].tolist() == ["Input text", "Pseudo labels"]  # paper order, not argument order
    layout = frame.set_index("variant").loc["no-layout"]
    assert layout["instructions"] == 2 and layout["only_reference"] == 1 and layout["only_variant"] == 1
    assert layout["delta_R_deg"] == pytest.approx(15.0) and layout["delta_t_rel"] == pytest.approx(0.25)
    assert layout["perturbation"] == "Layout label removal"
    assert layout["checked"] == 0 and math.isnan(layout["full_success"])  # no check reports: unknown, not 0


def test_sensitivity_bad_input_names_it(tmp_path):
    with pytest.raises(InputError, match="'top3'.*NAME=DIR"):
        parse_variant_spec("top3")
    missing = tmp_path / "refine" / "capframe"
    with pytest.raises(InputError, match="reference folder not found") as err:
        sensitivity_command(str(missing), [f"top3={tmp_path}"], str(tmp_path), str(tmp_path), str(tmp_path / "s.csv"))
    assert str(missing) in str(err.value) and "\n" not in str(err.value)
    write_result(tmp_path, "capframe", "s1", "a", np.eye(4))
    with pytest.raises(InputError, match="variant 'top5' folder not found"):
        sensitivity_command(str(missing), [f"top5={tmp_path / 'nowhere'}"], str(tmp_path), str(tmp_path), str(tmp_path / "s.csv"))


def test_sensitivity_cli_prints_one_line_errors(tmp_path, capsys):
    code = main(["sensitivity", "--reference", str(tmp_path), "--variant", "top3", "-o", str(tmp_path / "s.csv")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "'top3'" in err


# --- scenes ----------------------------------------------------------------------------------------


def test_scene_table_errors_and_mean_gravity(tmp_path, capsys):
    write_scene(tmp_path, "aligned", views=4, gaussians=1234)
    write_scene(tmp_path, "tilted", views=5, up=(0.0, 0.0, 3.0))
    write_scene(tmp_path, "unposed", views=6, up=(0.0, 1.0, 0.0))
    write_json(tmp_path / "gravity" / "tilted.json", {"format": 1, "up": [0.0, 1.0, 1.0], "confidence": 0.9, "skipped": False})
    write_json(tmp_path / "gravity" / "unposed.json", {"format": 1, "up": [0.0, 1.0, 0.0], "confidence": 0.5, "skipped": False})
    write_json(
        tmp_path / "colmap" / "unposed" / "colmap.json",
        {
            "images_total": 6,
            "images_registered": 5,
            "rotation_error_deg": {"mean": 0.3, "max": 0.7},
            "position_error_rel": {"mean": 0.003, "max": 0.0125},
        },
    )
    out = tmp_path / "tables" / "scenes.csv"
    frame = scene_table_command(str(tmp_path / "scenes"), str(tmp_path / "colmap"), str(tmp_path / "gravity"), str(out))
    rows = frame.set_index("scene")
    assert rows.loc["aligned", "views"] == 4 and rows.loc["aligned", "gaussians"] == 1234
    assert not rows.loc["aligned", "colmap"] and not rows.loc["aligned", "gravity"]
    assert rows.loc["tilted", "gravity_error_deg"] == pytest.approx(45.0)
    assert rows.loc["unposed", "gravity_error_deg"] == pytest.approx(0.0)
    assert (rows.loc["unposed", "registered"], rows.loc["unposed", "images"]) == (5, 6)
    assert rows.loc["unposed", "position_error_max_pct"] == pytest.approx(1.25)
    assert frame["scene"].iloc[-1] == MEAN_ROW and frame["gravity_error_deg"].iloc[-1] == pytest.approx(22.5)
    markdown = out.with_suffix(".md").read_text()
    assert "| 5/6 | 0.30 / 0.70 | 0.30 / 1.25 | yes | 0.00 | 0.50 |" in markdown
    assert f"| {MEAN_ROW} |" in markdown and "| 22.50 | 0.70 |" in markdown
    assert pd.read_csv(out)["scene"].tolist()[-1] == MEAN_ROW
    assert "22.50" in capsys.readouterr().out


def test_scene_table_excludes_skipped_gravity_from_the_mean(tmp_path):
    write_scene(tmp_path, "a")
    write_scene(tmp_path, "b")
    write_json(tmp_path / "gravity" / "a.json", {"format": 1, "up": [0.0, 0.0, 1.0], "confidence": 1.0, "skipped": True})
    write_json(tmp_path / "gravity" / "b.json", {"format": 1, "up": [1.0, 0.0, 0.0], "confidence": 0.2, "skipped": False})
    frame = scene_table_command(
        str(tmp_path / "scenes"), str(tmp_path / "colmap"), str(tmp_path / "gravity"), str(tmp_path / "t.csv")
    )
    assert frame["gravity_error_deg"].iloc[-1] == pytest.approx(90.0)
    assert "| skipped |" in (tmp_path / "t.md").read_text()


# --- runtime ---------------------------------------------------------------------------------------

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def bench(root, relative: str, *seconds: float) -> None:
    path = root / relative
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER + "".join(f"{s}\t0:00:01\t1\t1\t1\t1\t0\t0\t0\t{s}\n" for s in seconds))


def test_benchmark_tsv_parsing_and_errors(tmp_path):
    bench(tmp_path, "one.tsv", 2.5)
    bench(tmp_path, "repeats.tsv", 1.0, 3.0)
    assert read_benchmark(tmp_path / "one.tsv") == 2.5
    assert read_benchmark(tmp_path / "repeats.tsv") == 2.0  # repeats of one job: their mean
    (tmp_path / "bad.tsv").write_text("x\ty\n1\t2\n")
    with pytest.raises(InputError, match="bad.tsv.*no 's' column"):
        read_benchmark(tmp_path / "bad.tsv")
    (tmp_path / "empty.tsv").write_text("")
    with pytest.raises(InputError, match="empty.tsv"):
        read_benchmark(tmp_path / "empty.tsv")
    with pytest.raises(InputError, match="benchmarks folder not found"):
        benchmark_records(tmp_path / "missing")


def test_runtime_sums_per_stage_and_amortises_shared_stages(tmp_path, capsys):
    b = tmp_path / "benchmarks"
    for scene, views in (("s1", 3.0), ("s2", 4.0)):
        bench(b, f"synth/{scene}.tsv", 10.0)
        bench(b, f"instructions/{scene}.tsv", 1.0)
        bench(b, f"views/{scene}.tsv", views)
    bench(b, "colmap/s2.tsv", 8.0)
    bench(b, "gravity/s2.tsv", 2.0)
    for scene, ids in (("s1", ("a", "b", "c")), ("s2", ("d", "e"))):
        for k, i in enumerate(ids):
            bench(b, f"coarse/capframe/{scene}/{i}.tsv", 0.25)
            bench(b, f"qe/capframe/{scene}/{i}.tsv", 0.75)
            bench(b, f"translate/capframe/{scene}/{i}.tsv", 2.0)
            bench(b, f"refine/capframe/{scene}/{i}.tsv", 3.0 + k)
            bench(b, f"check/capframe/{scene}/{i}.tsv", 0.5)
            # the noise variant overrides translate: it reuses the default coarse and qe
            bench(b, f"translate/capframe-noise/{scene}/{i}.tsv", 2.5)
            bench(b, f"refine/capframe-noise/{scene}/{i}.tsv", 4.0)
            bench(b, f"refine/oracle/{scene}/{i}.tsv", 1.5)
            # the unrefined retrieved view: its own job, and the default coarse and qe it reuses
            bench(b, f"retrieved/retrieve/{scene}/{i}.tsv", 0.5)
    bench(b, "tables/capframe.tsv", 99.0)  # a table job: neither a scene's nor a method's cost
    out = tmp_path / "tables" / "runtime.csv"
    per_scene, per_method = runtime_command(str(b), str(out))

    scenes = per_scene.set_index("scene")
    assert sorted(scenes.index) == ["s1", "s2"]
    assert scenes.loc["s1", "n_instructions"] == 3 and scenes.loc["s2", "n_instructions"] == 2
    assert scenes.loc["s1", "instructions"] == 1.0  # the instructions stage's seconds
    assert scenes.loc["s1", "refine/capframe"] == pytest.approx(3.0 + 4.0 + 5.0)
    assert scenes.loc["s2", "refine/capframe"] == pytest.approx(3.0 + 4.0)
    assert scenes.loc["s1", "check/capframe"] == pytest.approx(1.5)
    assert scenes.loc["s2", "colmap"] == 8.0 and math.isnan(scenes.loc["s1", "colmap"])
    s1_total = 10 + 1 + 3 + 3 * (1 + 2 + 0.5 + 2.5 + 4 + 1.5 + 0.5) + (3 + 4 + 5)
    assert scenes.loc["s1", "total"] == pytest.approx(s1_total)
    assert list(per_scene.columns[:7]) == ["scene", "n_instructions", "synth", "instructions", "colmap", "gravity", "views"]
    assert list(per_scene.columns[7:12]) == [
        "coarse/capframe",
        "qe/capframe",
        "translate/capframe",
        "refine/capframe",
        "translate/capframe-noise",
    ]
    assert per_scene.columns[-1] == "total"

    methods = per_method.set_index("method")
    assert per_method["method"].tolist()[0] == "capframe"
    # capframe on s1: (0.25 + 0.75) + 2 + refine (3, 4, 5) + views 3/3; on s2: 1 + 2 + refine (3, 4) + (8 + 2 + 4)/2
    capframe = sorted([1 + 2 + r + 1.0 for r in (3, 4, 5)] + [1 + 2 + r + 7.0 for r in (3, 4)])
    assert methods.loc["capframe", "instructions"] == 5
    assert methods.loc["capframe", "median_s"] == pytest.approx(np.median(capframe))
    assert methods.loc["capframe", "mean_s"] == pytest.approx(np.mean(capframe))
    noise = [1 + 2.5 + 4 + 1.0] * 3 + [1 + 2.5 + 4 + 7.0] * 2  # default coarse and qe reused
    assert methods.loc["capframe-noise", "median_s"] == pytest.approx(np.median(noise))
    assert methods.loc["capframe-noise", "coarse_median_s"] == 0.25 and methods.loc["capframe-noise", "qe_median_s"] == 0.75
    assert methods.loc["oracle", "median_s"] == 1.5  # no shared stages, check not counted
    assert math.isnan(methods.loc["oracle", "shared_median_s"])
    retrieve = [0.25 + 0.75 + 0.5 + 1.0] * 3 + [0.25 + 0.75 + 0.5 + 7.0] * 2
    assert methods.loc["retrieve", "median_s"] == pytest.approx(np.median(retrieve))
    assert methods.loc["retrieve", "qe_median_s"] == 0.75 and math.isnan(methods.loc["retrieve", "refine_median_s"])
    assert pd.read_csv(tmp_path / "tables" / "runtime_methods.csv")["method"].tolist() == per_method["method"].tolist()
    markdown = (tmp_path / "tables" / "runtime.md").read_text()
    assert "| s1 | 3 | 10.0 | 1.0 |" in markdown and markdown.strip() in capsys.readouterr().out


def test_runtime_skips_unknown_layouts_and_needs_tsvs(tmp_path, capsys):
    bench(tmp_path, "x/y/z/w/v.tsv", 1.0)
    with pytest.raises(InputError, match="holds no benchmark TSVs"):
        benchmark_records(tmp_path)
    assert "skipped 1 benchmark files" in capsys.readouterr().err


def test_pareto_front_keeps_points_nothing_beats():
    seconds = np.array([1.0, 2.0, 3.0, 0.5, 10.0])
    success = np.array([0.5, 0.4, 0.9, 0.1, 0.9])
    # 2 s / 0.4 is beaten by 1 s / 0.5; 10 s / 0.9 by 3 s / 0.9.
    assert pareto_front(seconds, success).tolist() == [3, 0, 2]


def test_pareto_points_join_end_to_end_seconds_with_success_and_error(tmp_path):
    """Seconds come from the runtime table (end to end), success and view error from the methods
    table; a method missing from either is left out; each front is computed on its own axis."""
    per_method = pd.DataFrame({"method": ["capframe", "retrieve", "ivs", "svs"], "median_s": [20.0, 3.0, 30.0, 60.0]})
    methods = pd.DataFrame(
        {
            "method": ["capframe", "retrieve", "ivs", "svs", "gt", "oracle"],
            "full_success": [0.9, 0.2, 0.1, 0.4, 1.0, 0.95],
            "view_error_deg": [10.0, 50.0, 60.0, 5.0, 1.0, 2.0],
        }
    )
    points = pareto_points(per_method, methods)
    assert points["method"].tolist() == ["retrieve", "capframe", "ivs", "svs"]  # fastest first; "gt" has no benchmarks
    points = points.set_index("method")
    assert points["front_success"].to_dict() == {"capframe": True, "retrieve": True, "ivs": False, "svs": False}
    assert points["front_error"].to_dict() == {"capframe": True, "retrieve": True, "ivs": False, "svs": True}
    # the oracle (ground-truth labels) is shown but never on a front, however fast and accurate
    with_oracle = pd.concat([per_method, pd.DataFrame({"method": ["oracle"], "median_s": [1.0]})])
    points = pareto_points(with_oracle, methods).set_index("method")
    assert not points.loc["oracle", "front_success"] and not points.loc["oracle", "front_error"]
    assert points["front_success"].sum() == 2 and points["front_error"].sum() == 3


def test_runtime_with_the_methods_table_writes_the_pareto_plot(tmp_path):
    b = tmp_path / "benchmarks"
    bench(b, "views/s1.tsv", 1.0)
    for method, seconds in (("capframe", 5.0), ("ivs", 2.0)):
        bench(b, f"refine/{method}/s1/a.tsv", seconds)
    pd.DataFrame({"method": ["capframe", "ivs"], "full_success": [0.75, 0.25], "view_error_deg": [12.0, 40.0]}).to_csv(
        tmp_path / "methods.csv", index=False
    )
    runtime_command(str(b), str(tmp_path / "runtime.csv"), str(tmp_path / "methods.csv"))
    points = pd.read_csv(tmp_path / "runtime_pareto.csv").set_index("method")
    assert points.loc["capframe", "median_s"] == 6.0 and points.loc["ivs", "median_s"] == 3.0  # + views / 1 instruction
    assert points["front_success"].all() and points["front_error"].all()
    assert (tmp_path / "runtime_pareto.png").stat().st_size > 1000
    assert "Error against run time" in (tmp_path / "runtime.md").read_text()
    (tmp_path / "bad.csv").write_text("method,seconds\ncapframe,1\n")
    with pytest.raises(InputError, match="bad.csv.*full_success"):
        runtime_command(str(b), str(tmp_path / "runtime.csv"), str(tmp_path / "bad.csv"))


# --- groups ----------------------------------------------------------------------------------------


def _instruction_table(path, method: str, rows: list[tuple[str, bool, float]]) -> str:
    frame = pd.DataFrame(
        [
            {"method": method, "scene": scene, "instruction": f"{scene}-{k}", "all_satisfied": ok, "constraints_satisfied": share}
            for k, (scene, ok, share) in enumerate(rows)
        ]
    )
    frame.to_csv(path, index=False)
    return str(path)


def test_group_table_compares_retrieve_and_refine_per_group(tmp_path, capsys):
    retrieve = _instruction_table(
        tmp_path / "retrieve.csv", "retrieve", [("a1", False, 0.5), ("a2", True, 1.0), ("b1", False, 0.0)]
    )
    refine = _instruction_table(
        tmp_path / "capframe.csv", "capframe", [("a1", True, 1.0), ("a2", True, 1.0), ("b1", False, 0.75)]
    )
    frame = group_table_command([retrieve, refine], ["b1=tanks", "a1=lerf", "a2=lerf"], str(tmp_path / "groups.csv"))
    assert frame["method"].tolist() == ["retrieve"] * 3 + ["capframe"] * 3  # rows in the tables' order
    assert frame["group"].tolist()[:3] == ["tanks", "lerf", ALL_GROUPS]  # groups in the specs' order
    cells = frame.set_index(["method", "group"])
    assert (
        cells.loc[("retrieve", "lerf"), "full_success"] == 0.5
        and cells.loc[("retrieve", "lerf"), "constraints_satisfied"] == 0.75
    )
    assert (
        cells.loc[("capframe", ALL_GROUPS), "fully_satisfied"] == 2 and cells.loc[("capframe", ALL_GROUPS), "instructions"] == 3
    )
    assert cells.loc[("capframe", "tanks"), "full_success"] == 0.0
    markdown = (tmp_path / "groups.md").read_text()
    assert "| capframe | 0.000 (0/1) | 1.000 (2/2) | 0.667 (2/3) |" in markdown and markdown.strip() in capsys.readouterr().out


def test_group_table_rejects_bad_specs_and_unknown_scenes(tmp_path):
    table = _instruction_table(tmp_path / "t.csv", "capframe", [("m360-garden", True, 1.0)])
    with pytest.raises(InputError, match="expected SCENE=GROUP"):
        group_table_command([table], ["m360-garden"], str(tmp_path / "g.csv"))
    with pytest.raises(InputError, match="more than one group"):
        group_table_command([table], ["m360-garden=mipnerf360", "m360-garden=tanks"], str(tmp_path / "g.csv"))
    with pytest.raises(InputError, match=r"t.csv.*\['m360-garden'\] have no --group; closest.*m360-gardens"):
        group_table_command([table], ["m360-gardens=mipnerf360", "tt-truck=tanks"], str(tmp_path / "g.csv"))
    pd.DataFrame({"method": ["capframe"], "instruction": ["x"], "all_satisfied": [True]}).to_csv(
        tmp_path / "old.csv", index=False
    )
    with pytest.raises(InputError, match=r"old.csv.*lacks columns \['scene', 'constraints_satisfied'\]"):
        group_table_command([str(tmp_path / "old.csv")], ["a=b"], str(tmp_path / "g.csv"))
    assert not (tmp_path / "g.csv").exists()
