"""The warm server (capframe.warm): a command run through it behaves as the same command run in
its own process (files, exit status, one-line errors, working directory, environment, SIGINT),
and a missing or dead server falls back to running the command in place."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from _synth_helpers import build_scene

from capframe.scene import SceneMeta
from capframe.scene.directory import write_scene_meta
from capframe.warm import SOCKET_ENV

CAPFRAME = [sys.executable, "-m", "capframe.cli"]
# The server imports torch and the library: generous on a loaded two-core machine.
START_TIMEOUT_S = 120


def _wait_for(path: Path, process: subprocess.Popen) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while not path.exists():
        assert process.poll() is None, f"the warm server exited with {process.returncode}"
        assert time.monotonic() < deadline, "the warm server did not listen within the timeout"
        time.sleep(0.1)


@pytest.fixture(scope="module")
def server():
    """A warm server on a short socket path (Unix socket paths are limited to ~100 bytes)."""
    folder = Path(tempfile.mkdtemp(prefix="cfw-"))
    path = folder / "s.sock"
    process = subprocess.Popen([*CAPFRAME, "warm-server", str(path)], stdin=subprocess.DEVNULL)
    try:
        _wait_for(path, process)
        yield path
    finally:
        process.terminate()
        process.wait(timeout=30)
    assert not path.exists(), "the server left its socket behind"
    shutil.rmtree(folder)


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("warm") / "scene"
    truth = build_scene(root, per_object=40)
    write_scene_meta(SceneMeta(up=np.asarray(truth["up"]), aligned=True), root / "scene.json")
    return root


def _run(args: list[str], socket_path: Path | None, cwd: Path, **env: str) -> subprocess.CompletedProcess:
    environment = {k: v for k, v in os.environ.items() if k != SOCKET_ENV} | env
    if socket_path is not None:
        environment[SOCKET_ENV] = str(socket_path)
    return subprocess.run([*CAPFRAME, *args], cwd=cwd, env=environment, capture_output=True, text=True, timeout=600)


def test_same_files_status_and_streams_as_a_cold_process(server, scene_dir, tmp_path):
    # Relative paths: the command runs in the client's working directory, not the server's.
    args = ["parse", str(scene_dir), "the bear seen from its left, slightly above", "-o", "parsed.json"]
    (tmp_path / "cold").mkdir()
    (tmp_path / "warm").mkdir()
    cold = _run(args, None, tmp_path / "cold")
    warm = _run(args, server, tmp_path / "warm")
    assert cold.returncode == warm.returncode == 0, warm.stderr
    assert (tmp_path / "warm" / "parsed.json").read_bytes() == (tmp_path / "cold" / "parsed.json").read_bytes()
    assert "parse" in warm.stderr  # the stage's progress line reached the client's stderr


def test_errors_keep_their_one_line_and_exit_status(server, tmp_path):
    args = ["parse", str(tmp_path / "missing"), "the bear", "-o", "x.json"]
    cold, warm = _run(args, None, tmp_path), _run(args, server, tmp_path)
    assert warm.returncode == cold.returncode == 2
    assert warm.stderr == cold.stderr and len(warm.stderr.strip().splitlines()) == 1
    usage = _run(["no-such-verb"], server, tmp_path)
    assert usage.returncode == 2 and "invalid choice" in usage.stderr  # argparse's SystemExit


def test_the_commands_environment_reaches_it(server, scene_dir, tmp_path):
    # The default per-scene cache lies under $XDG_CACHE_HOME, read per command: a value set only
    # in the client must be the one the worker uses.
    cache = tmp_path / "xdg"
    args = ["ground", str(scene_dir), "the bear", "-o", "out", "--iterations", "5"]
    done = _run(args, server, tmp_path, XDG_CACHE_HOME=str(cache))
    assert done.returncode == 0, done.stderr
    assert list((cache / "capframe").glob("scene-*")), "the view cache was not written under the client's XDG_CACHE_HOME"


def test_sigint_reaches_the_command(server, tmp_path):
    environment = dict(os.environ, **{SOCKET_ENV: str(server)})
    client = subprocess.Popen(
        [*CAPFRAME, "bench", "render", "--json"], cwd=tmp_path, env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    time.sleep(5)  # connected and running (the bench renders for minutes)
    assert client.poll() is None
    client.send_signal(signal.SIGINT)
    _, stderr = client.communicate(timeout=60)
    assert client.returncode == 130, stderr
    assert b"interrupted" in stderr


def test_without_a_server_the_command_runs_in_place(scene_dir, tmp_path):
    args = ["parse", str(scene_dir), "the bear", "-o", "parsed.json"]
    done = _run(args, tmp_path / "nobody-listens.sock", tmp_path)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "parsed.json").is_file()


def test_the_server_stops_when_its_parent_is_gone(tmp_path):
    folder = Path(tempfile.mkdtemp(prefix="cfw-"))
    path = folder / "s.sock"
    # A parent that starts the server and exits at once, as a killed Snakemake would.
    starter = (
        "import os, subprocess; "
        f"command = {[*CAPFRAME, 'warm-server', str(path)]!r} + ['--parent', str(os.getpid())]; "
        "print(subprocess.Popen(command, stdin=subprocess.DEVNULL, start_new_session=True).pid)"
    )
    pid = int(subprocess.run([sys.executable, "-c", starter], capture_output=True, text=True, check=True).stdout)
    deadline = time.monotonic() + START_TIMEOUT_S
    while _running(pid):
        assert time.monotonic() < deadline, "an orphaned warm server kept running"
        time.sleep(0.2)
    assert not path.exists()
    shutil.rmtree(folder)


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # An exited child of a gone parent is reaped by init; a zombie counts as stopped.
    status = Path(f"/proc/{pid}/stat")
    return status.exists() and status.read_text().split()[2] != "Z"
