"""``capframe bench startup``: what starting a ``capframe`` job costs beside the work it does, in
a process of its own and through the warm server (:mod:`capframe.warm`).

CPU seconds (user + system) are measured, not wall time, so that other load on the machine
matters less; each figure is the median of ``repeats`` runs:

- *cold*: a short stage command (``capframe parse`` on a small synthetic scene) as its own process;
- *warm*: the same command through the server: the client process (interpreter, connect) plus
  the worker the server forked for it (its copy-on-write faults included);
- *warm start-up*: ``capframe --version`` through the server, client plus worker: a command that
  does nothing, i.e. the start-up cost of a job in warm mode;
- *cold start-up*: cold minus warm plus warm start-up (the imports the warm server saves, plus
  the interpreter's own start).

With ``benchmarks`` (a workflow run's Snakemake benchmark folder, run without the warm server),
the per-instruction jobs' CPU seconds give the per-instruction overhead: the jobs per instruction
times the start-up cost, over the instruction's CPU seconds (its work is the cold run's CPU
seconds minus the cold start-ups).
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..warm import SOCKET_ENV, request, server_environment

INSTRUCTION = "the teddy bear seen from its left, slightly above"
# A small tabletop scene, generated without photos (the parse stage reads its vocabulary).
SCENE_ARGS = ["--seed", "1", "--preset", "tabletop", "--capture", "orbit", "--views", "8", "--no-images"]
START_TIMEOUT_S = 300


def _cpu(who: int) -> float:
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def _command(scene: Path, output: Path) -> list[str]:
    return ["parse", str(scene), INSTRUCTION, "-o", str(output)]


def _subprocess(argv: list[str], env: dict, repeats: int) -> tuple[float, float]:
    """Median CPU and wall seconds of ``capframe argv`` as a child process."""
    cpu, wall = [], []
    for _ in range(repeats):
        start_cpu, start_wall = _cpu(resource.RUSAGE_CHILDREN), time.perf_counter()
        subprocess.run([sys.executable, "-m", "capframe.cli", *argv], env=env, check=True, capture_output=True)
        cpu.append(_cpu(resource.RUSAGE_CHILDREN) - start_cpu)
        wall.append(time.perf_counter() - start_wall)
    return sorted(cpu)[len(cpu) // 2], sorted(wall)[len(wall) // 2]


def _worker_cpu(path: Path, argv: list[str], repeats: int) -> float:
    """Median CPU seconds of the worker the server forks for ``argv``."""
    samples = []
    for _ in range(repeats):
        with open(os.devnull, "w") as null:
            saved = os.dup(2)
            os.dup2(null.fileno(), 2)  # the worker writes its progress lines to our stderr
            try:
                finished = request(str(path), argv)
            finally:
                os.dup2(saved, 2)
                os.close(saved)
        if finished is None or finished["status"] != 0:
            raise RuntimeError(f"the warm server did not run capframe {' '.join(argv)}")
        samples.append(float(finished["cpu_s"]))
    return sorted(samples)[len(samples) // 2]


def _start_server(path: Path) -> subprocess.Popen:
    command = [sys.executable, "-m", "capframe.cli", "warm-server", str(path), "--parent", str(os.getpid())]
    server = subprocess.Popen(command, env=server_environment(os.environ), stdin=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + START_TIMEOUT_S
    while not path.exists():
        if server.poll() is not None or time.monotonic() > deadline:
            server.kill()
            raise RuntimeError("the warm server did not start")
        time.sleep(0.1)
    return server


def per_instruction_cpu(benchmarks: str | Path) -> tuple[float, float]:
    """(jobs per instruction, CPU seconds per instruction) over the per-instruction jobs of a
    workflow run's benchmark folder (every method and evaluation job of an instruction)."""
    from ..evaluate.tables import read_benchmark

    jobs, cpu, instructions = 0, 0.0, set()
    for path in Path(benchmarks).rglob("*.tsv"):
        parts = path.relative_to(benchmarks).with_suffix("").parts
        if parts[0] == "tables" or len(parts) < 3:
            continue  # per-run and per-scene jobs
        jobs += 1
        cpu += read_benchmark(path, "cpu_time")
        instructions.add((parts[-2], parts[-1]))
    if not instructions:
        raise ValueError(f"{benchmarks}: no per-instruction benchmark files")
    return jobs / len(instructions), cpu / len(instructions)


def bench_startup(benchmarks: str | Path | None = None, repeats: int = 5) -> dict:
    """The start-up figures (CPU seconds per job; see the module docstring)."""
    with tempfile.TemporaryDirectory(prefix="cfw-") as folder:
        folder = Path(folder)
        scene, path = folder / "scene", folder / "s.sock"
        subprocess.run([sys.executable, "-m", "capframe.cli", "synth", str(scene), *SCENE_ARGS], check=True, capture_output=True)
        argv = _command(scene, folder / "parsed.json")
        cold_env = {k: v for k, v in os.environ.items() if k != SOCKET_ENV}
        cold_cpu, cold_wall = _subprocess(argv, cold_env, repeats)
        server = _start_server(path)
        try:
            warm_env = cold_env | {SOCKET_ENV: str(path)}
            client_cpu, warm_wall = _subprocess(argv, warm_env, repeats)
            worker_cpu = _worker_cpu(path, argv, repeats)
            idle_client_cpu, _ = _subprocess(["--version"], warm_env, repeats)
            idle_worker_cpu = _worker_cpu(path, ["--version"], repeats)
        finally:
            server.terminate()
            server.wait()
    warm_startup = idle_client_cpu + idle_worker_cpu
    figures = {
        "cold_cpu_s": cold_cpu,
        "cold_wall_s": cold_wall,
        "warm_cpu_s": client_cpu + worker_cpu,
        "warm_wall_s": warm_wall,
        "cold_startup_cpu_s": cold_cpu - (client_cpu + worker_cpu) + warm_startup,
        "warm_startup_cpu_s": warm_startup,
    }
    if benchmarks is not None:
        jobs, cpu = per_instruction_cpu(benchmarks)
        work = cpu - jobs * figures["cold_startup_cpu_s"]
        figures |= {
            "jobs_per_instruction": jobs,
            "instruction_cpu_s_cold": cpu,
            "instruction_work_cpu_s": work,
            "overhead_cold": jobs * figures["cold_startup_cpu_s"] / cpu,
            "overhead_warm": jobs * warm_startup / (work + jobs * warm_startup),
        }
    return figures
