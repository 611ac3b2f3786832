"""The Snakemake workflow parses, validates its config and plans the expected jobs."""

from __future__ import annotations

import os
import subprocess
import sys
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
           "--snakefile", str(ROOT / "Snakefile"), "--rerun-triggers", "mtime", *extra]
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
        assert f"results/ground/{scene}/{scene}-000" in out
    assert "results/tables/methods.csv" in out
