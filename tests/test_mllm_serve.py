"""The endpoint client (:class:`capframe.backends.mllm.endpoint.EndpointChat`) against a real
``transformers serve`` process on 127.0.0.1, serving a tiny random-weight model from its local
folder, offline.

``transformers serve`` ignores ``response_format`` (it logs "Ignoring unsupported fields"), and a
random model answers no JSON: the client's own validation, its retries with the fault fed back
and its final error are exercised against a real server, whose access log counts the requests.

The served model is the tiny text-only Qwen3: ``transformers serve`` loads a Qwen-VL folder
through ``AutoProcessor``, which needs torchvision for the video processor. The Qwen3-VL server
runs where torchvision is installed and is skipped, saying so, elsewhere."""

from __future__ import annotations

import importlib.util
import os
import re
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from capframe.backends.mllm.chat import ChatRequest
from capframe.backends.mllm.endpoint import EndpointChat
from capframe.backends.models import ModelSettings
from capframe.backends.tiny import tiny_qwen3, tiny_qwen3_vl
from capframe.errors import ModelError

# Startup (imports, loading the tiny model) takes 10-20 s on a shared CPU; a server not answering
# /v1/models by then has failed.
STARTUP_S = 180
SCHEMA = {
    "type": "object",
    "properties": {"score": {"type": "integer", "minimum": 0, "maximum": 100}},
    "required": ["score"],
    "additionalProperties": False,
}
POST = re.compile(r'"POST /v1/chat/completions HTTP/1\.1" (\d{3})')


class Server:
    """A ``transformers serve`` process and its log (stdout and stderr)."""

    def __init__(self, process: subprocess.Popen, url: str, model: str, log: Path):
        self.process, self.url, self.model, self.log = process, url, model, log

    def posts(self) -> list[str]:
        """The HTTP status of every chat-completions request the server has answered."""
        return POST.findall(self.log.read_text(errors="replace"))

    def tail(self, lines: int = 30) -> str:
        return "\n".join(self.log.read_text(errors="replace").splitlines()[-lines:])


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _serve(folder: Path, log: Path):
    """A running ``transformers serve`` of ``folder`` (a generator: the process is stopped at its
    end, whatever the test did)."""
    if not all(importlib.util.find_spec(name) for name in ("fastapi", "uvicorn", "accelerate")):
        pytest.skip("transformers serve needs fastapi, uvicorn and accelerate (the test extra: pip install -e .[test])")
    port = _free_port()
    env = os.environ | {"HF_HUB_OFFLINE": "1", "TRANSFORMERS_OFFLINE": "1", "HF_HOME": str(log.parent / "hf-home")}
    command = [sys.executable, "-m", "transformers.cli.transformers", "serve", str(folder)]
    command += ["--host", "127.0.0.1", "--port", str(port), "--device", "cpu", "--log-level", "info"]
    with open(log, "wb") as out:
        process = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT, env=env)
    server = Server(process, f"http://127.0.0.1:{port}/v1", str(folder), log)
    try:
        deadline = time.monotonic() + STARTUP_S
        while not _answers(server.url + "/models"):
            if process.poll() is not None:
                pytest.fail(f"transformers serve exited with status {process.returncode}:\n{server.tail()}")
            if time.monotonic() > deadline:
                pytest.fail(f"transformers serve did not answer /v1/models within {STARTUP_S} s:\n{server.tail()}")
            time.sleep(0.5)
        yield server
    finally:  # however the test ended
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=15)


def _answers(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=2) as response:
            return response.status == 200
    except OSError:
        return False


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    root = tmp_path_factory.mktemp("serve")
    yield from _serve(tiny_qwen3(root / "qwen3"), root / "serve.log")


def _request(images: tuple = ()) -> ChatRequest:
    return ChatRequest(
        system="You rate photographs.",
        user="How well centred is the subject?",
        schema=SCHEMA,
        schema_name="score",
        prompt_version="test-1",
        images=images,
        max_tokens=12,
    )


def _check_answered_or_failed(server: Server, dialect: str, retries: int, images: tuple = ()) -> None:
    """One request through :class:`EndpointChat`: either a validated reply after at most
    ``1 + retries`` requests, or a ModelError naming the endpoint and model after exactly that
    many; the server's log holds one successful POST per attempt."""
    settings = ModelSettings(endpoint=server.url, model=server.model, dialect=dialect, retries=retries, timeout_s=60)
    chat = EndpointChat(settings, "judge")
    before = len(server.posts())
    try:
        reply = chat.complete(_request(images))
    except ModelError as err:
        message = str(err)
        assert "\n" not in message
        assert f"MLLM entry 'judge' ({server.url}, model {server.model}): invalid answer:" in message
        assert f"(after {1 + retries} requests)" in message
        attempts = 1 + retries
    else:
        assert SCHEMA["properties"]["score"]["minimum"] <= reply.data["score"] <= 100
        assert 1 <= reply.attempts <= 1 + retries and reply.completion_tokens > 0
        attempts = reply.attempts
    # The access log line may trail the response by a moment.
    deadline = time.monotonic() + 5
    while len(server.posts()) - before < attempts and time.monotonic() < deadline:
        time.sleep(0.1)
    assert server.posts()[before:] == ["200"] * attempts, server.tail()


@pytest.mark.parametrize("dialect, retries", [("none", 2), ("openai", 0)])
def test_client_against_transformers_serve(server, dialect, retries):
    """``none`` is how a models config names ``transformers serve``; with ``openai`` the server
    receives ``response_format`` and ignores it, and the client still refuses the answer."""
    assert server.model in {model for model in EndpointChat(ModelSettings(endpoint=server.url, model="x"), "m").served_models()}
    _check_answered_or_failed(server, dialect, retries)
    if dialect == "openai":
        assert "Ignoring unsupported fields in the request: {'response_format'}" in server.log.read_text()


@pytest.mark.skipif(
    importlib.util.find_spec("torchvision") is None,
    reason="transformers serve loads a Qwen-VL folder through AutoProcessor, whose video processor needs torchvision "
    "(not installed; not a capframe dependency)",
)
def test_qwen3_vl_server_with_an_image(tmp_path):
    serving = _serve(tiny_qwen3_vl(tmp_path / "qwen3-vl"), tmp_path / "serve.log")
    server = next(serving)
    try:
        image = np.random.default_rng(0).integers(0, 256, (48, 64, 3), dtype=np.uint8)
        _check_answered_or_failed(server, "none", 1, (image,))
    finally:
        serving.close()
