"""A response cache on disk around any :class:`~capframe.backends.mllm.chat.ChatModel`, so that
a resumed or repeated run never asks a model the same question twice.

A request's key is the SHA-256 of the model's identity, the cache's ``tag`` (settings that change
answers without changing the model, such as the image size sent), the prompt version, the
schema, the system and user texts, the images' content hashes and the answer's token budget.
Each answer is one JSON file, ``<folder>/<key[:2]>/<key>.json``, written atomically; a file that
cannot be read, is not such a record or no longer validates against the schema is a miss, and is
rewritten. The files hold the answer and what it cost, never a key or an endpoint's credentials.
"""

from __future__ import annotations

import hashlib
import json
import threading
import time
from pathlib import Path

from ...scene._io import atomic_write
from .chat import ChatModel, ChatReply, ChatRequest, validate_reply
from .images import image_hash

FORMAT = 1
# Misses are asked of the inner model this many at a time, each group recorded before the next:
# a failure loses at most one group's answers, and a group still keeps a server's concurrency busy.
CHUNK = 32


class CachedChat:
    """``inner`` answered from, and recorded in, the cache folder ``folder``.

    A hit returns the recorded answer with ``cached=True, attempts=0, seconds=0``. The counters
    (:meth:`stats`) add up every request since the object was made: hits, misses, the tokens and
    model seconds of the misses.
    """

    def __init__(self, inner: ChatModel, folder: str | Path, tag: str = ""):
        self.inner = inner
        self.folder = Path(folder)
        self.tag = tag
        self.identity = inner.identity
        self._lock = threading.Lock()
        self._counts = {"hits": 0, "misses": 0, "prompt_tokens": 0, "completion_tokens": 0, "seconds": 0.0}

    def key(self, request: ChatRequest) -> str:
        """The request's cache key (hex SHA-256; see the module docstring)."""
        fields = {
            "identity": self.identity,
            "tag": self.tag,
            "prompt_version": request.prompt_version,
            "schema": request.schema,
            "system": request.system,
            "user": request.user,
            "images": [image_hash(image) for image in request.images],
            "max_tokens": request.max_tokens,
        }
        return hashlib.sha256(json.dumps(fields, sort_keys=True).encode()).hexdigest()

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"

    def complete(self, request: ChatRequest) -> ChatReply:
        return self.complete_many([request])[0]

    def complete_many(self, requests: list[ChatRequest]) -> list[ChatReply]:
        """Replies in order: hits from the cache, the misses asked of ``inner`` in groups of
        :data:`CHUNK` (its concurrency applies within a group), each group recorded at once."""
        keys = [self.key(r) for r in requests]
        replies: list[ChatReply | None] = [self._read(key, r) for key, r in zip(keys, requests)]
        missing = [i for i, reply in enumerate(replies) if reply is None]
        for start in range(0, len(missing), CHUNK):
            group = missing[start : start + CHUNK]
            for i, reply in zip(group, self.inner.complete_many([requests[i] for i in group])):
                self._write(keys[i], requests[i], reply)
                replies[i] = reply
        with self._lock:
            self._counts["hits"] += len(requests) - len(missing)
            self._counts["misses"] += len(missing)
            for i in missing:
                self._counts["prompt_tokens"] += replies[i].prompt_tokens
                self._counts["completion_tokens"] += replies[i].completion_tokens
                self._counts["seconds"] += replies[i].seconds
        return replies

    def stats(self) -> dict:
        """The counters for a stage's timing sidecar: ``mllm_calls``, ``mllm_cache_hits``,
        ``mllm_cache_misses``, ``mllm_prompt_tokens``, ``mllm_completion_tokens`` and
        ``mllm_model_seconds`` (wall time of the misses, retries included)."""
        with self._lock:
            counts = dict(self._counts)
        return {
            "mllm_calls": counts["hits"] + counts["misses"],
            "mllm_cache_hits": counts["hits"],
            "mllm_cache_misses": counts["misses"],
            "mllm_prompt_tokens": counts["prompt_tokens"],
            "mllm_completion_tokens": counts["completion_tokens"],
            "mllm_model_seconds": counts["seconds"],
        }

    def _read(self, key: str, request: ChatRequest) -> ChatReply | None:
        """The recorded reply of ``key``, or None: absent, unreadable, not a record of this
        request, or an answer that no longer validates (each a miss, never an error)."""
        try:
            record = json.loads(self.path(key).read_bytes())
            if not isinstance(record, dict) or record.get("format") != FORMAT or record.get("key") != key:
                return None
            text = record["text"]
            data = validate_reply(text, request.schema)
            tokens = int(record.get("prompt_tokens", 0)), int(record.get("completion_tokens", 0))
        except (OSError, ValueError, KeyError, TypeError):
            return None
        return ChatReply(
            data=data,
            text=text,
            model=self.identity,
            prompt_tokens=tokens[0],
            completion_tokens=tokens[1],
            seconds=0.0,
            attempts=0,
            cached=True,
        )

    def _write(self, key: str, request: ChatRequest, reply: ChatReply) -> None:
        """Record ``reply`` under ``key`` (atomically: a crash leaves the old file or none)."""
        record = {
            "format": FORMAT,
            "key": key,
            "model": self.identity,
            "prompt_version": request.prompt_version,
            "schema_name": request.schema_name,
            "text": reply.text,
            "prompt_tokens": reply.prompt_tokens,
            "completion_tokens": reply.completion_tokens,
            "seconds": reply.seconds,
            "attempts": reply.attempts,
            "written": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        }
        atomic_write(self.path(key), json.dumps(record, indent=1) + "\n")
