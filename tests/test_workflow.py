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
