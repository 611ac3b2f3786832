"""MLLM client benchmark: what the endpoint client and the response cache cost per call, apart
from the model.

An in-process fake OpenAI-compatible server answers every chat completion at once with a
schema-valid answer and records the seconds its handler took. The client's own overhead per
call is the wall time of :meth:`EndpointChat.complete` less that handler time: building the
request, the ``openai`` package, HTTP over loopback, parsing and validating the answer (the
server's HTTP parsing and the loopback transfer count as the client's, so the figure errs high).
Encoding an image (downscale, JPEG or PNG, base64) is timed on its own, as is a cache hit.
Each figure is the fastest of a few repeats (the machine is shared).
"""

from __future__ import annotations

import json
import tempfile
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import numpy as np

from ..backends.mllm.cache import CachedChat
from ..backends.mllm.chat import ChatRequest
from ..backends.mllm.endpoint import EndpointChat
from ..backends.mllm.images import data_url
from ..backends.models import ModelSettings

CALLS = 100
REPEATS = 3
PICTURE = (480, 640)  # (height, width): a training view of a real capture, sent as JPEG
SCHEMA = {
    "type": "object",
    "properties": {"score": {"type": "integer", "minimum": 0, "maximum": 100}, "reason": {"type": "string"}},
    "required": ["score", "reason"],
}
ANSWER = json.dumps({"score": 73, "reason": "the subject is centred and seen from the front"})


class _FakeServer:
    """A chat-completions server on 127.0.0.1 answering :data:`ANSWER` at once; ``handler_s``
    adds up its handlers' seconds."""

    def __init__(self):
        self.handler_s = 0.0
        self.requests = 0
        self.lock = threading.Lock()
        body = json.dumps(
            {
                "id": "bench",
                "object": "chat.completion",
                "created": 0,
                "model": "bench",
                "choices": [{"index": 0, "message": {"role": "assistant", "content": ANSWER}, "finish_reason": "stop"}],
                "usage": {"prompt_tokens": 100, "completion_tokens": 20, "total_tokens": 120},
            }
        ).encode()
        server = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"  # keep-alive, as a real server
            # Headers and body leave in two writes: with Nagle's algorithm the body would wait
            # for the client's delayed ACK (40 ms on Linux).
            disable_nagle_algorithm = True

            def do_POST(self):
                start = time.perf_counter()
                self.rfile.read(int(self.headers.get("Content-Length", 0)))
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)
                with server.lock:
                    server.handler_s += time.perf_counter() - start
                    server.requests += 1

            def log_message(self, *args):
                pass

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)
        self.thread.start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.httpd.server_port}/v1"

    def close(self) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()


def _picture() -> np.ndarray:
    """A smooth (H, W, 3) uint8 picture with edges, compressing as a photograph would rather
    than as noise."""
    y, x = np.mgrid[: PICTURE[0], : PICTURE[1]].astype(np.float32)
    image = np.stack([x / PICTURE[1], y / PICTURE[0], 0.5 + 0.5 * np.sin(x / 23.0) * np.cos(y / 17.0)], -1) * 255
    image[(x - 320) ** 2 + (y - 240) ** 2 < 90**2] = (200, 40, 40)
    return image.astype(np.uint8)


def _request(i: int, images: tuple = ()) -> ChatRequest:
    return ChatRequest(
        system="You score how well a photograph answers a question.",
        user=f"Question {i}: is the red disc centred?",
        schema=SCHEMA,
        schema_name="score",
        prompt_version="bench-1",
        images=images,
    )


def _fastest_per_call(server: _FakeServer, run, calls: int) -> tuple[float, float]:
    """The fastest of :data:`REPEATS` runs of ``run()`` (after a warm-up): (wall seconds per
    call, server handler seconds per call) of that run."""
    run()
    best = None
    for _ in range(REPEATS):
        handler_before = server.handler_s
        start = time.perf_counter()
        run()
        wall = time.perf_counter() - start
        figures = (wall / calls, (server.handler_s - handler_before) / calls)
        best = figures if best is None or figures[0] < best[0] else best
    return best


def bench_mllm() -> dict:
    """Figures of the MLLM client against an instant fake server (see the module docstring)."""
    server = _FakeServer()
    try:
        settings = ModelSettings(endpoint=server.url, model="bench", concurrency=1, retries=0)
        chat = EndpointChat(settings, "bench")
        text_requests = [_request(i) for i in range(CALLS)]
        wall, handler = _fastest_per_call(server, lambda: [chat.complete(r) for r in text_requests], CALLS)
        picture = _picture()
        image_calls = CALLS // 4
        image_requests = [_request(i, (picture,)) for i in range(image_calls)]
        image_wall, image_handler = _fastest_per_call(server, lambda: [chat.complete(r) for r in image_requests], image_calls)
        encode_s = _fastest_per_call(server, lambda: [data_url(picture, settings.image_side) for _ in range(10)], 10)[0]
        with tempfile.TemporaryDirectory() as folder:
            cached = CachedChat(chat, folder)
            start = time.perf_counter()
            cached.complete_many(text_requests)  # all misses, recorded
            miss_s = (time.perf_counter() - start) / CALLS
            hit_s = _fastest_per_call(server, lambda: cached.complete_many(text_requests), CALLS)[0]
            stats = cached.stats()
    finally:
        server.close()
    return {
        "server requests": server.requests,
        "calls through the cache": stats["mllm_calls"],
        "cache hit rate": stats["mllm_cache_hits"] / stats["mllm_calls"],
        "client overhead ms/call (text)": 1000 * (wall - handler),
        "fake server ms/call": 1000 * handler,
        "client overhead ms/call (one image, encoding included)": 1000 * (image_wall - image_handler),
        f"image encoding ms/image ({PICTURE[1]}x{PICTURE[0]})": 1000 * encode_s,
        "cached miss ms/call (client + server + write)": 1000 * miss_s,
        "cache hit ms/call": 1000 * hit_s,
    }
