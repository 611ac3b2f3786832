"""The Snakemake workflow parses, validates its config and plans the expected jobs."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("tabletop-orbit", "room-forward", "outdoor-orbit", "room-walkthrough")  # the default suite


def dry_run(tmp_path, *extra: str) -> str:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "-n",
        "--nolock",
        "--cores",
        "2",
        "--directory",
        str(ROOT),
        "--snakefile",
        str(ROOT / "Snakefile"),
        *extra,
    ]
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    return done.stdout


def test_dry_run_schedules_every_scene_of_the_suite(tmp_path):
    # A fresh results folder: every scene is to be generated and instructed.
    out = dry_run(tmp_path, "--config", "suite=config/suites/default.yaml", "--forceall")
    for scene in SCENES:
        assert f"results/scenes/{scene}" in out and f"results/instructions/{scene}/constraints.json" in out


def test_captured_suite_is_picked_by_the_config_switch(tmp_path):
    # `--config suite=config/suites/captured.yaml` runs the captured objects' suite (issue 19);
    # its scenes name the captured objects, passed to capframe synth as one quoted list.
    out = dry_run(tmp_path, "--config", "suite=config/suites/captured.yaml", "--forceall", "--printshellcmds")
    scenes = re.findall(r"capframe synth results/scenes/(cap-[a-z-]+) ", out)
    assert len(set(scenes)) == 6 and not any(f"results/scenes/{scene}" in out for scene in SCENES)
    assert "--objects 'tarot box,donut,mug,toy car'" in out


def test_bad_config_is_rejected_by_the_schema(tmp_path):
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "-n",
        "--nolock",
        "--cores",
        "1",
        "--snakefile",
        str(ROOT / "Snakefile"),
        "--directory",
        str(ROOT),
        "--config",
        "refine={'iterations': -1, 'long_side': 160}",
    ]
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    output = done.stdout + done.stderr
    assert done.returncode != 0 and "Error validating config" in output and "iterations" in output


def _fake_generated_suite(work: Path) -> None:
    """A working directory where the default suite's scenes and instruction sheets exist (scene
    folders with only a semantic sidecar, one instruction per scene), so a dry run sees past the
    instructions checkpoint."""
    shutil.copytree(ROOT / "config", work / "config")
    semantics = {
        "objects": [{"id": 0, "name": "teddy bear", "aliases": ["plush toy"]}, {"id": 1, "name": "ball", "symmetric": True}]
    }
    for scene in SCENES:
        (work / "results" / "scenes" / scene).mkdir(parents=True)
        (work / "results" / "scenes" / scene / "semantics.json").write_text(json.dumps(semantics))
    time.sleep(0.05)  # the sheets are newer than the scenes
    for scene in SCENES:
        # tabletop-orbit's instruction asks for a view side of an asymmetric subject: orientation runs
        text = "the teddy bear, seen from its left" if scene == "tabletop-orbit" else "a photo of the ball"
        sheet = work / "results" / "instructions" / scene
        sheet.mkdir(parents=True)
        (sheet / "constraints.json").write_text(json.dumps({f"{scene}-000": {"text": text, "constraints": {}}}))
        (sheet / "instructions.tsv").write_text("id\n")


def planned_outputs(work: Path, *extra: str) -> str:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "-n",
        "--nolock",
        "--cores",
        "2",
        "--directory",
        str(work),
        "--snakefile",
        str(ROOT / "Snakefile"),
        *extra,
        "--rerun-triggers",
        "mtime",
    ]
    done = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return done.stdout


def test_scenes_get_only_the_stages_they_need(tmp_path):
    """COLMAP only without poses, gravity only when not aligned: the posed, aligned tabletop gets
    neither, the tilted outdoor scene gets gravity, the unposed walkthrough gets both."""
    _fake_generated_suite(tmp_path)
    out = planned_outputs(tmp_path)
    assert "results/colmap/room-walkthrough" in out
    assert "results/gravity/room-walkthrough.json" in out and "results/gravity/outdoor-orbit.json" in out
    for scene in ("tabletop-orbit", "room-forward"):
        assert f"results/colmap/{scene}" not in out and f"results/gravity/{scene}.json" not in out
    assert "results/colmap/outdoor-orbit" not in out
    for scene in SCENES:
        assert f"results/refine/capframe/{scene}/{scene}-000" in out
    assert "results/tables/methods.csv" in out
    # every instruction's retrieved view is checked unrefined, as method "retrieve"
    for scene in SCENES:
        assert f"results/check/retrieve/{scene}/{scene}-000.json" in out


def _jobs(plan: str) -> dict[str, int]:
    """Job counts of a dry run's summary table."""
    import re

    table = plan[plan.index("Job stats:") :]
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+)$", table, re.M) if m.group(1) not in ("total",)}


def _fake_method_run(work: Path) -> None:
    """What a completed default run of the method leaves before Refine, newer than the sheets
    (orientation only for tabletop-orbit)."""
    time.sleep(0.05)
    for scene in SCENES:
        stem = f"{scene}/{scene}-000.json"
        files = {
            f"results/colmap/{scene}/scene.json": "{}",
            f"results/gravity/{scene}.json": "{}",
            f"results/views/{scene}/label_views.npz": "",
            f"results/views/{scene}/occupancy.npz": "",
            f"results/parse/capframe/{stem}": json.dumps({"needs": {"orientation": scene == "tabletop-orbit"}}),
            f"results/coarse/capframe/{stem}": "{}",
            f"results/retrieve/capframe/{stem}": "{}",
            f"results/associate/capframe/{stem}": "{}",
            f"results/orient/capframe/{stem}": "{}",
            f"results/translate/capframe/{stem}": "{}",
        }
        if scene != "tabletop-orbit":
            del files[f"results/orient/capframe/{stem}"]
        for path, text in files.items():
            (work / path).parent.mkdir(parents=True, exist_ok=True)
            (work / path).write_text(text)
            time.sleep(0.01)


def _with_variants(work: Path, variants: dict) -> None:
    import yaml

    config = yaml.safe_load((work / "config" / "config.yaml").read_text())
    config["variants"] = variants
    (work / "config" / "config.yaml").write_text(yaml.safe_dump(config))


def test_a_variant_reruns_only_the_stages_it_changes(tmp_path):
    """After the default method has run, a variant that changes one refine weight schedules only
    its own refine, check and aggregate jobs; one that changes top-K questions the coarse
    stage's views again (QE) and redoes what follows, but reuses the coarse scores and never
    re-renders the per-scene views."""
    _fake_generated_suite(tmp_path)
    _fake_method_run(tmp_path)
    _with_variants(tmp_path, {"weighted": {"refine": {"weights": "view=0.5"}}, "top3": {"retrieve": {"topk": 3}}})

    weighted = _jobs(planned_outputs(tmp_path, "results/tables/capframe-weighted.csv"))
    assert weighted == {"refine_method": 4, "check": 4, "aggregate": 1}
    top3 = _jobs(planned_outputs(tmp_path, "results/tables/capframe-top3.csv"))
    assert top3 == {"qe": 4, "associate": 4, "orient": 1, "translate": 4, "refine_method": 4, "check": 4, "aggregate": 1}


def test_instructions_get_only_the_translate_stages_they_need(tmp_path):
    """Orientation runs only for the instruction with an asymmetric subject and a view cue, and
    not at all for a variant that drops orientation (the parse checkpoint's ``needs`` decides);
    segmentation only for an associator or an orientation estimator that reads masks (label ids
    and annotated fronts need none)."""
    _fake_generated_suite(tmp_path)
    _fake_method_run(tmp_path)
    for stage in ("orient", "translate"):
        shutil.rmtree(tmp_path / "results" / stage)
    _with_variants(
        tmp_path,
        {
            "masks": {"backends": {"associator": "knn"}},
            "no-orientation": {"translate": {"drop": "orientation"}},
            "oa": {"backends": {"orient": "orient-anything"}},
        },
    )

    default = planned_outputs(tmp_path, "results/tables/capframe.csv")
    assert _jobs(default)["orient"] == 1 and "results/orient/capframe/tabletop-orbit/tabletop-orbit-000.json" in default
    assert "segment" not in _jobs(default)
    masks = _jobs(planned_outputs(tmp_path, "results/tables/capframe-masks.csv"))
    assert masks["segment"] == masks["associate"] == 4 and masks["orient"] == 1 and "coarse" not in masks and "qe" not in masks
    oa = planned_outputs(tmp_path, "results/tables/capframe-oa.csv")
    assert _jobs(oa)["segment"] == _jobs(oa)["orient"] == 1  # masks for the one instruction that orients
    [orient_inputs] = [inputs for inputs, outputs in _planned_jobs(oa) if any("results/orient/" in o for o in outputs)]
    assert any(i.startswith("results/segment/") and i.endswith("tabletop-orbit-000.npz") for i in orient_inputs)
    dropped = _jobs(planned_outputs(tmp_path, "results/tables/capframe-no-orientation.csv"))
    assert "orient" not in dropped and dropped["translate"] == 4 and "associate" not in dropped


def _planned_jobs(plan: str) -> list[tuple[list[str], list[str]]]:
    """(inputs, outputs) of every job a dry run printed."""
    jobs = []
    for block in re.split(r"^(?:local)?(?:rule|checkpoint) \w+:$", plan, flags=re.M)[1:]:
        fields = {
            m.group(1): [p.strip() for p in m.group(2).split(",")] for m in re.finditer(r"^\s+(input|output): (.*)$", block, re.M)
        }
        jobs.append((fields.get("input", []), fields.get("output", [])))
    return jobs


def _fake_completed_run(work: Path, configure=None) -> None:
    """Create every output the workflow plans, each newer than its inputs, as a completed run
    leaves them (after ``configure(work)`` edits the config, if given). Paths without a suffix
    are directory outputs, dated by Snakemake's ``.snakemake_timestamp`` marker."""
    _fake_generated_suite(work)
    if configure is not None:
        configure(work)
    pending = _planned_jobs(planned_outputs(work))
    stamp = time.time() - 10_000.0
    for stage in ("scenes", "instructions"):  # the scenes, then their sheets
        stamp += 10.0
        for path in (work / "results" / stage).rglob("*"):
            os.utime(path, (stamp, stamp))
    while pending:
        ready = [job for job in pending if not any(p in out for p in job[0] for _, out in pending)]
        assert ready, "the planned jobs form a cycle"
        stamp += 10.0
        for _, outputs in ready:
            for name in outputs:
                path = work / name
                marker = path if path.suffix else path / ".snakemake_timestamp"
                marker.parent.mkdir(parents=True, exist_ok=True)
                # A parse file is read by the workflow itself (fronts_input): it needs "needs". No
                # instruction asks for orientation here: the plan had no orientation job.
                marker.write_text('{"needs": {"orientation": false}}' if name.startswith("results/parse/") else "{}")
                os.utime(marker, (stamp, stamp))
        pending = [job for job in pending if job not in ready]


def test_deleting_one_result_reruns_only_what_is_built_from_it(tmp_path):
    """After a completed run nothing is to be done; deleting one instruction's refine output
    reruns that refine, its check and image grid, and the tables that gather them."""
    _fake_completed_run(tmp_path)
    assert "Nothing to be done" in planned_outputs(tmp_path)
    shutil.rmtree(tmp_path / "results/refine/capframe/room-forward/room-forward-000")
    plan = planned_outputs(tmp_path)
    assert _jobs(plan) == {
        "refine_method": 1,
        "check": 1,
        "grid": 1,
        "aggregate": 1,
        "compare": 1,
        "groups": 1,
        "quantitative": 1,
        "runtime": 1,
        "all": 1,
    }
    assert "results/check/capframe/room-forward/room-forward-000.json" in plan
    assert "results/report/grid/room-forward/room-forward-000.png" in plan


def _with_models(work: Path, entries: str) -> None:
    """A models config with ``entries`` (YAML), named by the workflow config."""
    import yaml

    (work / "config" / "models-test.yaml").write_text(entries)
    config = yaml.safe_load((work / "config" / "config.yaml").read_text())
    config["models"] = "config/models-test.yaml"
    (work / "config" / "config.yaml").write_text(yaml.safe_dump(config))


METRIC_AND_JUDGE_MODELS = (
    "metrics-clip: {weights: clip}\nmetrics-siglip: {weights: siglip}\njudge: {weights: qwen}\n"
    "judge-2: {endpoint: http://127.0.0.1:8000/v1, model: m}\n"
)


def test_metrics_and_judges_run_only_when_their_models_are_configured(tmp_path):
    """Without models the tables hold the ground-truth columns and no metrics or judges job is
    planned; with the entries, one metrics and one judges job per scene feed Table 1 (and the
    metrics Tables 2 and 3), the judges seeing the runnable methods only."""
    _fake_generated_suite(tmp_path)
    _fake_method_run(tmp_path)
    bare = _jobs(planned_outputs(tmp_path))
    assert "metrics" not in bare and "judge" not in bare and bare["quantitative"] == 1
    _with_models(tmp_path, "metrics-siglip: {weights: siglip}\n")
    plan = planned_outputs(tmp_path, "--printshellcmds")
    assert _jobs(plan)["metrics"] == 4 and "judge" not in _jobs(plan)
    _with_models(tmp_path, METRIC_AND_JUDGE_MODELS)
    plan = planned_outputs(tmp_path, "--printshellcmds")
    jobs = _jobs(plan)
    assert jobs["metrics"] == jobs["judge"] == 4
    [table] = [inputs for inputs, outputs in _planned_jobs(plan) if "results/tables/quantitative.csv" in outputs]
    assert {f"results/metrics/{s}.csv" for s in SCENES} | {f"results/judges/{s}.json" for s in SCENES} <= set(table)
    [groups] = [inputs for inputs, outputs in _planned_jobs(plan) if "results/tables/groups.csv" in outputs]
    assert "results/metrics/room-forward.csv" in groups and not any("judges" in i for i in groups)
    [judge] = re.findall(r"capframe judge --scene room-forward .*", plan)
    methods = re.findall(r"(\w[\w-]*)=results/", judge)
    assert methods == ["capframe", "ivs", "svs", "splatraj"]
    [metrics] = re.findall(r"capframe metrics --scene room-forward .*", plan)
    assert "retrieve=results/retrieved/room-forward" in metrics and "oracle=results/refine/oracle/room-forward" in metrics


def test_a_second_run_with_the_paper_tables_has_nothing_to_do(tmp_path):
    """After a completed run with metrics and judges, nothing is to be done; the user study's
    table, once imported, reruns Table 1 (and the runtime table that follows it) only."""
    _fake_completed_run(tmp_path, lambda work: _with_models(work, METRIC_AND_JUDGE_MODELS))
    assert (tmp_path / "results/judges/tabletop-orbit.json").exists()
    assert "Nothing to be done" in planned_outputs(tmp_path)
    time.sleep(0.05)
    (tmp_path / "results/tables/userstudy.csv").write_text("method,rating_mean,rating_n,preference_share\n")
    plan = planned_outputs(tmp_path)
    assert _jobs(plan) == {"quantitative": 1, "runtime": 1, "all": 1}
    assert "--userstudy" in planned_outputs(tmp_path, "--printshellcmds")


def test_slurm_profile_plans_the_same_jobs(tmp_path):
    """The SLURM profile loads (executor plugin, resources) and plans the workflow in a dry run."""
    _fake_generated_suite(tmp_path)
    out = planned_outputs(tmp_path, "--workflow-profile", str(ROOT / "workflow" / "profiles" / "slurm"))
    assert "results/colmap/room-walkthrough" in out and "results/tables/methods.csv" in out


def test_lint_finds_nothing_but_the_software_environment_notice():
    """`snakemake --lint`: the project installs its software with `make setup`, so the per-rule
    conda/container notice is the only accepted lint."""
    import re

    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    done = subprocess.run(
        [sys.executable, "-m", "snakemake", "--lint", "--snakefile", str(ROOT / "Snakefile"), "--directory", str(ROOT)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    lints = re.findall(r"^\s+\* (.+?):?$", done.stdout + done.stderr, re.M)
    assert lints, "snakemake --lint printed nothing: the parsing of its output is stale"
    assert {lint.rstrip(".:") for lint in lints} == {"Specify a conda environment or container for each rule"}


def test_every_rule_declares_a_log_and_a_benchmark():
    """Each job's output and timing are kept (`log:`, `benchmark:`); only the target rule `all`
    runs nothing."""
    files = [ROOT / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]
    rules = {}
    for path in files:
        for name, body in re.findall(r"^(?:rule|checkpoint) (\w+):\n((?:[ \t]+.*\n|\n)*)", path.read_text(), re.M):
            rules[name] = body
    assert len(rules) > 15, "no rules parsed: the pattern is stale"
    missing = sorted(n for n, body in rules.items() if n != "all" and not ("    log:" in body and "    benchmark:" in body))
    assert missing == []
