"""A warm start for the workflow's many short ``capframe`` jobs.

Each per-instruction stage is its own job and process, and a fresh process spends 1-2 s of CPU
importing torch and the library before doing milliseconds to seconds of work. A *warm server*
imports them once per workflow run; each ``capframe`` command then connects to it over a Unix
socket and runs in a process forked from it, with the command's own argv, working directory,
environment and standard streams. Nothing else changes: the same :func:`capframe.cli.main` runs,
files are written by the same code, exit codes and one-line errors are the same.

Per request the server forks a *monitor*, which forks the *worker* that runs the command, waits
for it and sends its exit status back; the server itself never runs a command (each worker
starts from the same freshly imported state) and never runs a thread (fork is safe). The client
forwards SIGINT and SIGTERM to the worker, so an interrupted workflow stops its jobs as before.

Opt-in through :data:`SOCKET_ENV`: the workflow starts a server for its run (``warm_start`` in
config/config.yaml) and sets the variable; without it, or when nothing answers on the socket (a
cluster node, a server gone), the command runs in its own process as usual.
"""

from __future__ import annotations

import array
import gc
import importlib
import json
import os
import select
import signal
import socket
import struct
import sys
import traceback
from collections.abc import Callable

SOCKET_ENV = "CAPFRAME_WARM_SOCKET"
# Imported once by the server: what the workflow's stage verbs import on their own.
PRELOAD = (
    "numpy",
    "torch",
    "pandas",
    "capframe.scene",
    "capframe.render.torch_backend",
    "capframe.pipeline.stages",
    "capframe.pipeline.ground",
    "capframe.refine.optimize",
    "capframe.baselines.run",
    "capframe.evaluate.check",
    "capframe.evaluate.tables",
    "capframe.backends.oracle",
    "capframe.translate.parse",
)
_HEADER = struct.Struct("!I")
# How often the server checks that the process that started it is still there.
_PARENT_POLL_S = 1.0
# torch's intra-op threads where a job's environment names none (set by serve()).
_DEFAULT_THREADS = 1


def _send(connection: socket.socket, message: dict, fds: list[int] | None = None) -> None:
    body = json.dumps(message).encode()
    data = _HEADER.pack(len(body)) + body
    if fds:
        connection.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, array.array("i", fds))])
    else:
        connection.sendall(data)


def _receive(connection: socket.socket, with_fds: int = 0) -> tuple[dict | None, list[int]]:
    """One message (None at end of stream) and the file descriptors sent with it."""
    fds: list[int] = []
    if with_fds:
        data, ancillary, _, _ = connection.recvmsg(65536, socket.CMSG_SPACE(with_fds * array.array("i").itemsize))
        for level, kind, payload in ancillary:
            if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
                fds.extend(array.array("i", payload[: len(payload) - len(payload) % array.array("i").itemsize]))
    else:
        data = connection.recv(_HEADER.size)
    while 0 < len(data) < _HEADER.size:
        more = connection.recv(_HEADER.size - len(data))
        if not more:
            return None, fds
        data += more
    if not data:
        return None, fds
    (size,) = _HEADER.unpack(data[: _HEADER.size])
    body = data[_HEADER.size :]
    while len(body) < size:
        more = connection.recv(size - len(body))
        if not more:
            return None, fds
        body += more
    return json.loads(body), fds


# --- client ---------------------------------------------------------------------------------


def run_warm(argv: list[str]) -> int | None:
    """Run ``capframe argv`` in the warm server named by :data:`SOCKET_ENV`: its exit status, or
    None when there is no server to run it (the caller then runs the command itself)."""
    path = os.environ.get(SOCKET_ENV)
    if not path:
        return None
    finished = request(path, argv)
    return None if finished is None else int(finished["status"])


def request(path: str, argv: list[str]) -> dict | None:
    """Run ``capframe argv`` in the server listening on ``path`` with this process's directory,
    environment and standard streams, forwarding SIGINT and SIGTERM to it meanwhile.

    Returns:
        ``{"status": exit status, "cpu_s": the worker's CPU seconds}``, or None when no server
        answered and nothing ran.
    """
    connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        connection.connect(path)
    except OSError:
        connection.close()
        return None
    with connection:
        message = {"argv": argv, "cwd": os.getcwd(), "env": dict(os.environ), "umask": _umask()}
        _send(connection, message, fds=[0, 1, 2])
        started, _ = _receive(connection)
        if started is None:
            return None  # the server closed before starting the command: nothing ran
        worker = int(started["pid"])

        def forward(signum, frame):
            try:
                os.kill(worker, signum)
            except ProcessLookupError:
                pass

        previous = {signum: signal.signal(signum, forward) for signum in (signal.SIGINT, signal.SIGTERM)}
        try:
            finished, _ = _receive(connection)
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
    if finished is None:
        print("capframe: error: the warm server stopped while running this command", file=sys.stderr)
        return {"status": 1, "cpu_s": float("nan")}
    return finished


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# --- server ---------------------------------------------------------------------------------


def server_environment(environment: dict[str, str]) -> dict[str, str]:
    """``environment`` for starting a server: its imports fix the BLAS and OpenMP pools, so one
    thread each, as a one-thread job gets them (a job's own thread count is applied per command);
    never itself a client."""
    env = dict(environment, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    env.pop(SOCKET_ENV, None)
    return env


def serve(path: str, main: Callable[[list[str]], int], parent: int | None = None) -> None:
    """Import :data:`PRELOAD`, then run every request on ``path`` with ``main`` (the ``capframe``
    command's :func:`capframe.cli.main`) until the process ``parent``
    (default: the one that started the server) has gone, or SIGTERM. Name the parent where it
    may exit before the server starts (its pid would no longer be the server's parent's)."""
    global _DEFAULT_THREADS
    parent = os.getppid() if parent is None else parent
    for name in PRELOAD:
        importlib.import_module(name)
    import torch

    # Objects that exist now are never collected in a worker: its collector then leaves their
    # pages alone, and they stay shared with the server instead of being copied on first touch.
    gc.collect()
    gc.freeze()

    _DEFAULT_THREADS = torch.get_num_threads()
    if os.path.exists(path):
        os.unlink(path)  # a stale socket of a server that did not clean up
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path)
    listener.listen(64)
    # Monitors are reaped by the kernel; each monitor waits for its own worker.
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    try:
        while _alive(parent):
            ready, _, _ = select.select([listener], [], [], _PARENT_POLL_S)
            if not ready:
                continue
            connection, _ = listener.accept()
            if os.fork() == 0:
                listener.close()
                _monitor(connection, main)  # never returns
            connection.close()
    finally:
        listener.close()
        if os.path.exists(path):
            os.unlink(path)


def _alive(parent: int) -> bool:
    """Whether the process ``parent`` still exists (a zombie counts as gone)."""
    try:
        os.kill(parent, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{parent}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return True  # no /proc: existence is all we can tell


def _monitor(connection: socket.socket, main: Callable[[list[str]], int]) -> None:
    """Fork the worker for the request on ``connection``, tell the client its pid, wait for it and
    send its exit status (128 + N for a worker killed by signal N, as a shell reports it)."""
    status = 1
    try:
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        request, fds = _receive(connection, with_fds=3)
        if request is None or len(fds) != 3:
            os._exit(1)
        worker = os.fork()
        if worker == 0:
            connection.close()
            _work(request, fds, main)  # never returns
        for fd in fds:
            os.close(fd)
        _send(connection, {"pid": worker})
        _, wait_status, usage = os.wait4(worker, 0)
        status = os.waitstatus_to_exitcode(wait_status)
        status = 128 - status if status < 0 else status
        _send(connection, {"status": status, "cpu_s": usage.ru_utime + usage.ru_stime})
    except BaseException:  # a client gone: nothing to report to
        pass
    os._exit(0)


def _work(request: dict, fds: list[int], main: Callable[[list[str]], int]) -> None:
    """Become the client's command: its streams, directory, environment and argv; then run it."""
    code = 1
    try:
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        os.umask(int(request["umask"]))
        os.setpgid(0, 0)  # signals reach the worker through its client, not the server's group
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        sys.argv = ["capframe", *request["argv"]]
        _threads_from_environment()
        code = main(request["argv"])
    except SystemExit as exit_:
        code = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None else 1)
    except BaseException:
        traceback.print_exc()
        code = 1
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
    os._exit(code)


def _threads_from_environment() -> None:
    """torch's intra-op threads as a fresh process would take them from the job's environment
    (read by the OpenMP runtime when torch was imported, i.e. in the server's environment)."""
    import torch

    threads = os.environ.get("OMP_NUM_THREADS", "")
    torch.set_num_threads(int(threads) if threads.isdigit() and int(threads) > 0 else _DEFAULT_THREADS)
