"""The MLLM endpoint client, its response cache, its factory and ``capframe models check``,
against a small scripted HTTP server in this process (no model, no network).

The server answers each request with the next entry of its script (the last one repeats) and
records what it received, so each test asserts both what the client sent (the schema in the
dialect's field, the images) and what it did with every kind of answer or fault."""

from __future__ import annotations

import base64
import io
import json
import logging
import socket
import sys
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import numpy as np
import pytest
from PIL import Image

from capframe.backends.mllm.cache import CachedChat
from capframe.backends.mllm.chat import ChatRequest
from capframe.backends.mllm.endpoint import EndpointChat, public_url
from capframe.backends.models import ModelSettings
from capframe.errors import InputError, ModelError

SCHEMA = {
    "type": "object",
    "properties": {"score": {"type": "integer", "minimum": 0, "maximum": 100}, "reason": {"type": "string"}},
    "required": ["score", "reason"],
    "additionalProperties": False,
}
GOOD = {"score": 42, "reason": "centred"}
KEY = "sk-test-5f3a9c0e1d"


def _image(height: int, width: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (height, width, 3), dtype=np.uint8)


def _request(images: tuple = (), user: str = "How well centred is the subject?", version: str = "v1") -> ChatRequest:
    return ChatRequest(
        system="You are a photography judge.",
        user=user,
        schema=SCHEMA,
        schema_name="score",
        prompt_version=version,
        images=images,
        max_tokens=64,
    )


# --- the scripted server ---------------------------------------------------------------------------


def chat(content: str, usage: tuple[int, int] = (10, 5)):
    """A chat-completions answer whose message is ``content``."""
    body = {
        "id": "x",
        "object": "chat.completion",
        "created": 0,
        "model": "m",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": content}, "finish_reason": "stop"}],
        "usage": {"prompt_tokens": usage[0], "completion_tokens": usage[1], "total_tokens": sum(usage)},
    }
    return lambda h: h.reply(200, json.dumps(body).encode())


def ollama(content: str):
    """An Ollama /api/chat answer."""
    message = {"role": "assistant", "content": content}
    body = {"model": "m", "message": message, "done": True, "prompt_eval_count": 7, "eval_count": 3}
    return lambda h: h.reply(200, json.dumps(body).encode())


def status(code: int, headers: dict | None = None, message: str = "refused"):
    body = json.dumps({"error": {"message": message}}).encode()
    return lambda h: h.reply(code, body, headers)


def truncated(h):
    """Promise 500 bytes, send 20, close."""
    h.send_response(200)
    h.send_header("Content-Type", "application/json")
    h.send_header("Content-Length", "500")
    h.end_headers()
    h.wfile.write(b'{"id": "x", "choices')
    h.wfile.flush()
    h.close_connection = True


def slow(seconds: float, then):
    def reply(h):
        time.sleep(seconds)
        then(h)

    return reply


class Server:
    """A ThreadingHTTPServer on 127.0.0.1 (random port) replying by ``script``."""

    def __init__(self, script: list):
        self.script = list(script)
        self.received: list[dict] = []  # {"path", "headers", "body", "time"}
        self.lock = threading.Lock()
        self.in_flight = self.most_in_flight = 0
        server = self

        class Handler(BaseHTTPRequestHandler):
            counted = False  # this request is counted in flight

            def done(self):
                # Out of flight before its answer leaves: a client that gets it may send its next
                # request before this thread would otherwise get back to the count.
                if self.counted:
                    with server.lock:
                        server.in_flight -= 1
                    self.counted = False

            def reply(self, code: int, body: bytes, headers: dict | None = None):
                self.done()
                self.send_response(code)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                for name, value in (headers or {}).items():
                    self.send_header(name, value)
                self.end_headers()
                self.wfile.write(body)

            def _serve(self, body):
                self.body = body
                with server.lock:
                    headers = {k.lower(): v for k, v in self.headers.items()}
                    server.received.append({"path": self.path, "headers": headers, "body": body, "time": time.perf_counter()})
                    answer = server.script.pop(0) if len(server.script) > 1 else server.script[0]
                    server.in_flight += 1
                    server.most_in_flight = max(server.most_in_flight, server.in_flight)
                    self.counted = True
                try:
                    answer(self)
                finally:
                    self.done()

            def do_POST(self):
                self._serve(json.loads(self.rfile.read(int(self.headers["Content-Length"]))))

            def do_GET(self):
                self._serve(None)

            def log_message(self, *args):
                pass

        self.errors: list[BaseException] = []

        class Quiet(ThreadingHTTPServer):
            def handle_error(self, request, client_address):
                # A client that gives up (a timeout, a closed connection) is part of what is
                # tested; socketserver would print its traceback into the stderr under test.
                server.errors.append(sys.exc_info()[1])

        self.httpd = Quiet(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        threading.Thread(target=self.httpd.serve_forever, args=(0.05,), daemon=True).start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.httpd.server_port}/v1"

    def close(self):
        self.httpd.shutdown()
        self.httpd.server_close()


@pytest.fixture
def serve():
    servers = []

    def start(*script):
        servers.append(Server(list(script)))
        return servers[-1]

    yield start
    for server in servers:
        server.close()


def client(server: Server, **fields) -> EndpointChat:
    """An EndpointChat on ``server`` without waits between attempts."""
    settings = ModelSettings(**({"endpoint": server.url, "model": "qwen-test", "timeout_s": 5.0} | fields))
    chat = EndpointChat(settings, "mllm")
    chat.backoff_s = 0.0
    return chat


def _decoded(b64: str) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(b64))).convert("RGB"))


# --- success in every dialect ----------------------------------------------------------------------


@pytest.mark.parametrize("dialect", ["openai", "vllm", "vllm-legacy", "none", "ollama"])
def test_each_dialect_sends_its_schema_field_and_the_images(serve, dialect):
    server = serve(ollama(json.dumps(GOOD)) if dialect == "ollama" else chat(json.dumps(GOOD)))
    images = (_image(30, 40, 1), _image(20, 24, 2))
    reply = client(server, dialect=dialect).complete(_request(images))
    assert reply.data == GOOD and reply.attempts == 1 and not reply.cached
    assert (reply.prompt_tokens, reply.completion_tokens) == ((7, 3) if dialect == "ollama" else (10, 5))
    [sent] = server.received
    body = sent["body"]
    assert body["model"] == "qwen-test"
    assert body["messages"][0] == {"role": "system", "content": "You are a photography judge."}
    user = body["messages"][1]
    if dialect == "ollama":
        assert sent["path"] == "/api/chat"  # the server's root, not /v1
        assert body["format"] == SCHEMA and body["stream"] is False and body["options"]["num_predict"] == 64
        assert user["content"] == _request().user
        sent_images = [_decoded(b64) for b64 in user["images"]]  # raw base64, no data: prefix
    else:
        assert sent["path"] == "/v1/chat/completions" and body["max_tokens"] == 64
        schema_fields = {
            "openai": ("response_format", {"type": "json_schema", "json_schema": {"name": "score", "schema": SCHEMA}}),
            "vllm": ("structured_outputs", {"json": SCHEMA}),
            "vllm-legacy": ("guided_json", SCHEMA),
        }
        others = {"response_format", "structured_outputs", "guided_json", "format"}
        if dialect in schema_fields:
            name, value = schema_fields[dialect]
            assert body[name] == value
            others.discard(name)
        assert not others & set(body)
        *parts, text = user["content"]
        assert text == {"type": "text", "text": _request().user}
        urls = [part["image_url"]["url"] for part in parts]
        assert all(url.startswith("data:image/png;base64,") for url in urls)
        sent_images = [_decoded(url.split(",", 1)[1]) for url in urls]
    # small images go losslessly, in order
    assert len(sent_images) == 2 and all(np.array_equal(a, b) for a, b in zip(sent_images, images))
    assert sent["headers"]["authorization"] == "Bearer EMPTY"  # no key named: never OPENAI_API_KEY


def test_an_oversized_image_is_downscaled_before_sending(serve):
    server = serve(chat(json.dumps(GOOD)))
    client(server, image_side=64).complete(_request((_image(1000, 2000),)))
    url = server.received[0]["body"]["messages"][1]["content"][0]["image_url"]["url"]
    assert _decoded(url.split(",", 1)[1]).shape == (32, 64, 3)


def test_complete_many_keeps_order_and_bounds_concurrency(serve):
    # each answer echoes the question's number; the first answers wait (up to 5 s) until three
    # requests are in flight at once, so that a loaded machine's slow thread start cannot hide
    # the concurrency, while a client that sent fewer at once would still show fewer
    def echo(h):
        number = int(h.body["messages"][1]["content"].split()[-1])
        deadline = time.monotonic() + 5.0
        while server.most_in_flight < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        chat(json.dumps({"score": number, "reason": "n"}))(h)

    server = serve(echo)
    replies = client(server, concurrency=3).complete_many([_request(user=f"question {i}") for i in range(10)])
    assert [r.data["score"] for r in replies] == list(range(10))
    assert server.most_in_flight == 3


# --- faults ----------------------------------------------------------------------------------------


def _one_line_naming(err: pytest.ExceptionInfo, *words: str) -> str:
    message = str(err.value)
    assert "\n" not in message
    for word in ("'mllm'", "qwen-test", "127.0.0.1", *words):
        assert word in message, (word, message)
    return message


def _free_port() -> int:
    """A port nothing listens on (bound, then released)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def test_unreachable_endpoint_is_one_line_after_the_bounded_retries():
    settings = ModelSettings(endpoint=f"http://127.0.0.1:{_free_port()}/v1", model="qwen-test", retries=2, timeout_s=2.0)
    chat = EndpointChat(settings, "mllm")
    chat.backoff_s = 0.01
    with pytest.raises(ModelError) as err:
        chat.complete(_request())
    _one_line_naming(err, "connection failed", "after 3 requests")


@pytest.mark.parametrize("code, words", [(401, ("HTTP 401", "CAPFRAME_TEST_KEY")), (400, ("HTTP 400", "invalid key ***"))])
def test_refusals_are_never_retried_and_the_key_never_shown(serve, monkeypatch, caplog, capsys, code, words):
    monkeypatch.setenv("CAPFRAME_TEST_KEY", KEY)
    server = serve(status(code, message=f"invalid key {KEY}"))  # a server that echoes the key
    caplog.set_level(logging.DEBUG)
    with pytest.raises(ModelError) as err:
        client(server, api_key_env="CAPFRAME_TEST_KEY", retries=3).complete(_request())
    message = _one_line_naming(err, *words)
    assert len(server.received) == 1
    assert server.received[0]["headers"]["authorization"] == f"Bearer {KEY}"
    captured = capsys.readouterr()
    assert KEY not in message + caplog.text + captured.out + captured.err


def test_an_unset_key_variable_is_an_input_error_naming_it(monkeypatch):
    monkeypatch.delenv("CAPFRAME_TEST_KEY", raising=False)
    settings = ModelSettings(endpoint="http://127.0.0.1:9/v1", model="m", api_key_env="CAPFRAME_TEST_KEY")
    with pytest.raises(InputError, match="CAPFRAME_TEST_KEY, which is not set"):
        EndpointChat(settings, "mllm")


def test_429_waits_for_retry_after_then_succeeds(serve):
    server = serve(status(429, {"Retry-After": "0.3"}), chat(json.dumps(GOOD)))
    reply = client(server).complete(_request())
    assert reply.data == GOOD and reply.attempts == 2
    assert server.received[1]["time"] - server.received[0]["time"] >= 0.3


def test_retry_after_is_capped(serve):
    server = serve(status(429, {"Retry-After": "3600"}), chat(json.dumps(GOOD)))
    chat_model = client(server)
    chat_model.retry_after_cap_s = 0.05
    start = time.perf_counter()
    assert chat_model.complete(_request()).attempts == 2
    assert time.perf_counter() - start < 2


@pytest.mark.parametrize(
    "fault, words",
    [
        (status(503), "HTTP 503"),
        (truncated, "connection failed"),
        (lambda h: h.reply(200, b"<html>gateway</html>"), "not valid JSON"),
        (lambda h: h.reply(200, b'{"object": "error"}'), "no choices[0].message.content"),
    ],
    ids=["503", "truncated body", "body not JSON", "body without an answer"],
)
def test_transient_faults_are_retried_then_named(serve, fault, words):
    server = serve(fault, chat(json.dumps(GOOD)))
    reply = client(server, retries=1).complete(_request())
    assert reply.data == GOOD and reply.attempts == 2
    server = serve(fault)
    with pytest.raises(ModelError) as err:
        client(server, retries=1).complete(_request())
    _one_line_naming(err, words, "after 2 requests")
    assert len(server.received) == 2


def test_a_timeout_is_retried_within_the_bound(serve):
    server = serve(slow(1.0, chat(json.dumps(GOOD))), chat(json.dumps(GOOD)))
    reply = client(server, timeout_s=0.3, retries=1).complete(_request())
    assert reply.attempts == 2 and reply.data == GOOD
    server = serve(slow(1.0, chat(json.dumps(GOOD))))
    start = time.perf_counter()
    with pytest.raises(ModelError) as err:
        client(server, timeout_s=0.3, retries=1).complete(_request())
    _one_line_naming(err, "no answer within timeout_s = 0.3 s", "after 2 requests")
    assert time.perf_counter() - start < 1.5


def test_other_4xx_stop_at_once_with_the_server_text(serve):
    server = serve(status(400, message="response_format is not supported"))
    with pytest.raises(ModelError) as err:
        client(server, retries=3).complete(_request())
    _one_line_naming(err, "HTTP 400", "response_format is not supported", "dialect 'openai'")
    assert len(server.received) == 1


@pytest.mark.parametrize(
    "bad, fault",
    [("Sure! The score is 42.", "not JSON"), (json.dumps({"score": 420, "reason": "x"}), "at score: 420 is greater")],
    ids=["not JSON", "outside the schema"],
)
def test_an_invalid_answer_is_fed_back_then_the_valid_one_kept(serve, bad, fault):
    server = serve(chat(bad, (10, 5)), chat(json.dumps(GOOD), (30, 6)))
    reply = client(server).complete(_request())
    assert reply.data == GOOD and reply.attempts == 2 and reply.text == json.dumps(GOOD)
    assert (reply.prompt_tokens, reply.completion_tokens) == (40, 11)  # both attempts
    first, second = (r["body"]["messages"] for r in server.received)
    assert second[: len(first)] == first
    assistant, feedback = second[len(first) :]
    assert assistant == {"role": "assistant", "content": bad}
    assert feedback["role"] == "user" and fault in feedback["content"]


@pytest.mark.parametrize("dialect", ["vllm", "none"])
def test_a_subject_outside_the_scene_s_names_is_fed_back_with_the_closest_then_parsed(serve, dialect):
    """The subject parser over a server: the schema it sends lists the scene's names (an enum the
    server's decoder may ignore, as ``none`` does); an answer outside it is rejected here and asked
    again with the fault, naming the closest names, fed back; the valid second answer is parsed."""
    from capframe.backends.mllm.parser import MLLMParser
    from capframe.scene import SemanticObject
    from capframe.translate.vocabulary import Vocabulary

    scene = Vocabulary.from_semantics([SemanticObject(i, n, [], False) for i, n in enumerate(("teddy bear", "mug", "toy car"))])
    outside = {"subjects": [{"mention": "the teddy", "name": "teddy"}]}
    inside = {"subjects": [{"mention": "the teddy", "name": "teddy bear"}]}
    layout = {"subjects": {"teddy bear": {"region": "left", "shot": None, "box": None}}}
    orientation = {"subjects": {"teddy bear": {"symmetric": False, "azimuth_deg": None, "either_side": False}}}
    orientation |= {"elevation_deg": None, "elevation_explicit": False, "roll_deg": None}
    server = serve(*(chat(json.dumps(a)) for a in (outside, inside, layout, orientation)))
    parsed = MLLMParser(client(server, dialect=dialect, concurrency=1)).parse("the teddy on the left", scene)
    assert [(s.name, s.region) for s in parsed.subjects] == [("teddy bear", "left")]
    first, second = (r["body"] for r in server.received[:2])
    names = {"enum": ["mug", "teddy bear", "toy car", "unknown"]}
    if dialect == "vllm":
        assert first["structured_outputs"]["json"]["properties"]["subjects"]["items"]["properties"]["name"] == names
    else:
        assert "structured_outputs" not in first and "response_format" not in first
    assert second["messages"][-2] == {"role": "assistant", "content": json.dumps(outside)}
    feedback = second["messages"][-1]["content"]
    assert 'at subjects/0/name: "teddy" is not one of the 4 allowed values; closest: "teddy bear", ' in feedback


def test_an_always_invalid_answer_fails_after_exactly_one_plus_retries_requests(serve):
    server = serve(chat(json.dumps({"score": "high"})))
    with pytest.raises(ModelError) as err:
        client(server, retries=2).complete(_request())
    _one_line_naming(err, "invalid answer", "does not match the schema", "after 3 requests")
    assert len(server.received) == 3


def test_public_url_drops_credentials():
    assert public_url("https://user:pw@example.org:8443/v1/") == "https://example.org:8443/v1"


# --- the response cache --------------------------------------------------------------------------


def test_cache_hits_ask_the_server_nothing_and_keys_follow_the_request(serve, tmp_path, monkeypatch):
    monkeypatch.setenv("CAPFRAME_TEST_KEY", KEY)
    server = serve(chat(json.dumps(GOOD)))
    cached = CachedChat(client(server, api_key_env="CAPFRAME_TEST_KEY"), tmp_path / "mllm")
    image = _image(16, 16, 3)
    first = cached.complete(_request((image,)))
    assert not first.cached and first.attempts == 1 and len(server.received) == 1
    again = cached.complete(_request((image.copy(),)))
    assert (again.cached, again.attempts, again.seconds, again.data) == (True, 0, 0.0, GOOD)
    assert len(server.received) == 1
    cached.complete(_request((image,), version="v2"))  # another prompt version
    other = image.copy()
    other[0, 0, 0] ^= 1
    cached.complete(_request((other,)))  # one pixel differs
    assert len(server.received) == 3
    stats = cached.stats()
    assert stats.pop("mllm_model_seconds") > first.seconds > 0
    assert stats == {
        "mllm_calls": 4,
        "mllm_cache_hits": 1,
        "mllm_cache_misses": 3,
        "mllm_prompt_tokens": 30,
        "mllm_completion_tokens": 15,
    }
    files = sorted((tmp_path / "mllm").rglob("*.json"))
    assert len(files) == 3 and not list((tmp_path / "mllm").rglob("*.tmp"))
    assert all(KEY not in f.read_text() for f in files)


def test_a_corrupt_cache_file_is_a_miss_and_rewritten(serve, tmp_path):
    server = serve(chat(json.dumps(GOOD)))
    cached = CachedChat(client(server), tmp_path)
    cached.complete(_request())
    key = cached.key(_request())
    path = cached.path(key)
    outside_schema = {"format": 1, "key": key, "text": json.dumps({"score": "high"})}
    for corrupt in ('{"format": 1, "key": ', "[]", json.dumps({"format": 1, "key": "other"}), json.dumps(outside_schema)):
        path.write_text(corrupt)
        reply = cached.complete(_request())
        assert not reply.cached and reply.data == GOOD
        assert json.loads(path.read_text())["text"] == json.dumps(GOOD)
    assert len(server.received) == 5


def test_cached_complete_many_mixes_hits_and_misses_in_order(serve, tmp_path):
    server = serve(chat(json.dumps(GOOD)))
    cached = CachedChat(client(server, concurrency=2), tmp_path)
    requests = [_request(user=f"q{i}") for i in range(5)]
    cached.complete_many(requests[::2])
    replies = cached.complete_many(requests)
    assert [r.cached for r in replies] == [True, False, True, False, True]
    assert len(server.received) == 5


# --- the factory and `capframe models check` ------------------------------------------------------


def test_factory_shares_one_cached_endpoint_per_context(serve, tmp_path):
    from capframe.backends import BackendContext
    from capframe.backends.mllm.factory import build_chat, chat_model
    from capframe.backends.models import ModelsConfig

    server = serve(chat(json.dumps(GOOD)))
    models = ModelsConfig({"mllm": ModelSettings(endpoint=server.url, model="qwen-test")}, "models.yaml")
    context = BackendContext(scene=None, up=np.array([0.0, 0.0, 1.0]), cache_dir=tmp_path, models=models)
    model = chat_model(context)
    assert isinstance(model, CachedChat) and chat_model(context) is model
    assert model.identity == f"{server.url} qwen-test" and model.folder == tmp_path / "mllm"
    with pytest.raises(InputError, match="either endpoint"):
        build_chat(ModelSettings(endpoint=server.url, model="m", weights="/w"), "mllm", tmp_path)
    with pytest.raises(InputError, match="'qwen' needs an entry"):
        chat_model(context, "qwen")


def _models_answer(h):
    h.reply(200, json.dumps({"object": "list", "data": [{"id": "qwen-test", "object": "model"}]}).encode())


def test_models_check_prints_one_line_per_entry(serve, tmp_path, capsys):
    from capframe.cli import main

    def route(h):
        (_models_answer if h.command == "GET" else chat(json.dumps({"colour": "red"})))(h)

    server = serve(route)
    weights = tmp_path / "detector.onnx"
    weights.write_bytes(b"onnx")
    config = tmp_path / "models.yaml"
    config.write_text(f"mllm:\n  endpoint: {server.url}\n  model: qwen-test\ndetector:\n  weights: detector.onnx\n")
    assert main(["models", "check", "--models", str(config)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2 and lines[0].startswith("mllm:") and "ok" in lines[0] and "'colour': 'red'" in lines[0]
    assert lines[1].startswith("detector:") and "ok (files found)" in lines[1]
    smoke = server.received[-1]["body"]
    assert smoke["response_format"]["json_schema"]["schema"]["required"] == ["colour"]

    config.write_text(
        f"mllm:\n  endpoint: {server.url}\n  model: other-model\ndetector:\n  weights: missing.onnx\n"
        f"down:\n  endpoint: http://127.0.0.1:{_free_port()}/v1\n  model: m\n  retries: 0\n  timeout_s: 2\n"
    )
    assert main(["models", "check", "--models", str(config)]) == 3
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert len(lines) == 3
    assert "does not list model 'other-model'" in lines[0] and "qwen-test" in lines[0]
    assert "missing.onnx does not exist" in lines[1]
    assert lines[2].startswith("down:") and "connection failed" in lines[2]
    assert "3 entries" in err and len(err.splitlines()) == 1


def test_answers_recorded_before_a_failure_are_not_asked_again(serve, tmp_path, monkeypatch):
    import capframe.backends.mllm.cache as cache

    monkeypatch.setattr(cache, "CHUNK", 2)
    server = serve(chat(json.dumps(GOOD)), chat(json.dumps(GOOD)), status(400), chat(json.dumps(GOOD)))
    cached = CachedChat(client(server, concurrency=1), tmp_path)
    requests = [_request(user=f"q{i}") for i in range(3)]
    with pytest.raises(ModelError):
        cached.complete_many(requests)
    assert len(list(tmp_path.rglob("*.json"))) == 2 and not list(tmp_path.rglob("*.tmp"))
    replies = cached.complete_many(requests)
    assert [r.cached for r in replies] == [True, True, False] and len(server.received) == 4


def test_bench_mllm_counts_its_calls(monkeypatch):
    import capframe.bench.mllm as bench

    monkeypatch.setattr(bench, "CALLS", 8)
    monkeypatch.setattr(bench, "REPEATS", 1)
    figures = bench.bench_mllm()
    # text: warm-up + 1 run of 8; images: 2 of 2; the cache: 8 misses, then 16 hits
    assert figures["server requests"] == 16 + 4 + 8
    assert figures["calls through the cache"] == 24 and figures["cache hit rate"] == pytest.approx(2 / 3)
    assert all(value > 0 for value in figures.values())


def test_ground_with_its_endpoint_down_fails_in_one_line_and_writes_nothing(tmp_path):
    """The issue's acceptance: ``capframe ground --parser mllm`` against a server that is down
    exits with the model error's status in one line, within its timeout and retries, and leaves
    no result folder."""
    import subprocess
    import sys

    import yaml
    from _synth_helpers import build_scene

    from capframe.scene import SceneMeta
    from capframe.scene.directory import write_scene_meta

    scene = tmp_path / "scene"
    truth = build_scene(scene, per_object=40)
    write_scene_meta(SceneMeta(up=np.asarray(truth["up"]), aligned=True), scene / "scene.json")
    endpoint = f"http://127.0.0.1:{_free_port()}/v1"
    models = tmp_path / "models.yaml"
    models.write_text(yaml.safe_dump({"mllm": {"endpoint": endpoint, "model": "qwen-test", "retries": 1, "timeout_s": 2}}))
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "capframe.cli", "ground", str(scene), "the bear from its left", "-o", str(tmp_path / "out")]
        + ["--parser", "mllm", "--models", str(models), "--cache", str(tmp_path / "cache")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 3, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("capframe: model error:") and endpoint in lines[0], done.stderr
    assert not (tmp_path / "out").exists()
    # Start-up and the scene's loading aside, two 2-second attempts and a short back-off.
    assert time.monotonic() - start < 120
