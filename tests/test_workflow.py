"""The Snakemake workflow parses, validates its config and plans the expected jobs."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def dry_run(tmp_path, *extra: str) -> str:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [sys.executable, "-m", "snakemake", "-n", "--nolock", "--cores", "2", "--directory", str(ROOT),
           "--snakefile", str(ROOT / "Snakefile"), *extra]
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    return done.stdout


def test_dry_run_schedules_every_scene_of_the_suite(tmp_path):
    # A fresh results folder: every scene is to be generated and instructed.
    out = dry_run(tmp_path, "--config", "suite=config/suites/default.yaml", "--forceall")
    for scene in ("tabletop-orbit", "room-forward", "outdoor-orbit", "room-walkthrough"):
        assert f"results/scenes/{scene}" in out and f"results/instructions/{scene}/constraints.json" in out


def test_bad_config_is_rejected_by_the_schema(tmp_path):
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [sys.executable, "-m", "snakemake", "-n", "--nolock", "--cores", "1", "--snakefile", str(ROOT / "Snakefile"),
           "--directory", str(ROOT), "--config", "refine={'iterations': -1, 'long_side': 160}"]
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    output = done.stdout + done.stderr
    assert done.returncode != 0 and "Error validating config" in output and "iterations" in output


def _fake_generated_suite(work: Path) -> None:
    """A working directory where the default suite's scenes and instruction sheets exist (empty
    scene folders, one instruction per scene), so a dry run sees past the instructions checkpoint."""
    import json
    import shutil
    import time

    shutil.copytree(ROOT / "config", work / "config")
    scenes = ("tabletop-orbit", "room-forward", "outdoor-orbit", "room-walkthrough")
    for scene in scenes:
        (work / "results" / "scenes" / scene).mkdir(parents=True)
    time.sleep(0.05)  # the sheets are newer than the scenes
    for scene in scenes:
        sheet = work / "results" / "instructions" / scene
        sheet.mkdir(parents=True)
        (sheet / "constraints.json").write_text(json.dumps({f"{scene}-000": {"text": "a photo of the ball", "constraints": {}}}))
        (sheet / "instructions.tsv").write_text("id\n")


def planned_outputs(work: Path, *extra: str) -> str:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [sys.executable, "-m", "snakemake", "-n", "--nolock", "--cores", "2", "--directory", str(work),
           "--snakefile", str(ROOT / "Snakefile"), *extra, "--rerun-triggers", "mtime"]
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
    for scene in ("tabletop-orbit", "room-forward", "outdoor-orbit", "room-walkthrough"):
        assert f"results/refine/capframe/{scene}/{scene}-000" in out
    assert "results/tables/methods.csv" in out


def _jobs(plan: str) -> dict[str, int]:
    """Job counts of a dry run's summary table."""
    import re

    table = plan[plan.index("Job stats:"):]
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+)$", table, re.M) if m.group(1) not in ("total",)}


def test_a_variant_reruns_only_the_stages_it_changes(tmp_path):
    """After the default method has run, a variant that changes one refine weight schedules only
    its own refine, check and aggregate jobs; one that changes retrieval also retrieves and
    translates again, but never re-renders the per-scene views."""
    import time

    import yaml

    _fake_generated_suite(tmp_path)
    scenes = ("tabletop-orbit", "room-forward", "outdoor-orbit", "room-walkthrough")
    time.sleep(0.05)
    for scene in scenes:  # what a completed default run leaves, newer than the sheets
        for path in (f"results/colmap/{scene}/scene.json", f"results/gravity/{scene}.json", f"results/views/{scene}/label_views.npz",
                     f"results/retrieve/capframe/{scene}/{scene}-000.json", f"results/translate/capframe/{scene}/{scene}-000.json"):
            (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / path).write_text("{}")
            time.sleep(0.01)
    config = yaml.safe_load((tmp_path / "config" / "config.yaml").read_text())
    config["variants"] = {"weighted": {"refine": {"weights": "view=0.5"}}, "top3": {"retrieve": {"topk": 3}}}
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(config))

    weighted = _jobs(planned_outputs(tmp_path, "results/tables/capframe-weighted.csv"))
    assert weighted == {"refine_method": 4, "check": 4, "aggregate": 1}
    top3 = _jobs(planned_outputs(tmp_path, "results/tables/capframe-top3.csv"))
    assert top3 == {"retrieve": 4, "translate": 4, "refine_method": 4, "check": 4, "aggregate": 1}


def _planned_jobs(plan: str) -> list[tuple[list[str], list[str]]]:
    """(inputs, outputs) of every job a dry run printed."""
    jobs = []
    for block in re.split(r"^(?:local)?(?:rule|checkpoint) \w+:$", plan, flags=re.M)[1:]:
        fields = {m.group(1): [p.strip() for p in m.group(2).split(",")] for m in re.finditer(r"^\s+(input|output): (.*)$", block, re.M)}
        jobs.append((fields.get("input", []), fields.get("output", [])))
    return jobs


def _fake_completed_run(work: Path) -> None:
    """Create every output the workflow plans, each newer than its inputs, as a completed run
    leaves them. Paths without a suffix are directory outputs, dated by Snakemake's
    ``.snakemake_timestamp`` marker."""
    _fake_generated_suite(work)
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
                marker.write_text("{}")
                os.utime(marker, (stamp, stamp))
        pending = [job for job in pending if job not in ready]


def test_deleting_one_result_reruns_only_what_is_built_from_it(tmp_path):
    """After a completed run nothing is to be done; deleting one instruction's refine output
    reruns that refine, its check and image grid, and the tables that gather them."""
    _fake_completed_run(tmp_path)
    assert "Nothing to be done" in planned_outputs(tmp_path)
    shutil.rmtree(tmp_path / "results/refine/capframe/room-forward/room-forward-000")
    plan = planned_outputs(tmp_path)
    assert _jobs(plan) == {"refine_method": 1, "check": 1, "grid": 1, "aggregate": 1, "compare": 1, "runtime": 1, "all": 1}
    assert "results/check/capframe/room-forward/room-forward-000.json" in plan
    assert "results/report/grid/room-forward/room-forward-000.png" in plan


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
    done = subprocess.run([sys.executable, "-m", "snakemake", "--lint", "--snakefile", str(ROOT / "Snakefile"), "--directory", str(ROOT)],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)  # fmt: skip
    lints = re.findall(r"^\s+\* (.+?):?$", done.stdout + done.stderr, re.M)
    assert lints, "snakemake --lint printed nothing: the parsing of its output is stale"
    assert {lint.rstrip(".:") for lint in lints} == {"Specify a conda environment or container for each rule"}
