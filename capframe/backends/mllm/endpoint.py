"""A :class:`~capframe.backends.mllm.chat.ChatModel` over any OpenAI-compatible server (vLLM,
SGLang, Ollama, llama.cpp, ``transformers serve``, a hosted API), through the ``openai`` package.

Each request sends the system prompt, the images (downscaled to the entry's ``image_side``) and
the user text, and asks for the schema in the entry's ``dialect``:

======================  ========================================================================
``openai``              ``response_format = {"type": "json_schema", "json_schema": {name, schema}}``
``vllm``                ``structured_outputs = {"json": schema}`` (vLLM >= 0.12)
``vllm-legacy``         ``guided_json = schema`` (vLLM < 0.12)
``ollama``              Ollama's native ``/api/chat`` (the endpoint's root, without ``/v1``):
                        ``format = schema``, images as raw base64 in the message's ``images``
``none``                nothing asked (``transformers serve`` ignores ``response_format``)
======================  ========================================================================

Whatever the server promised, the answer is validated here
(:func:`~capframe.backends.mllm.chat.validate_reply`). One request may take ``1 + retries``
attempts: an invalid answer is fed back to the model as a new user turn naming the fault, and
a transient fault (no connection, a timeout, a truncated or malformed body, HTTP 429, 408 or
5xx) is retried after a short wait (a 429's or 503's ``Retry-After``, capped). Then, or at once
for a refusal (401, 403, other 4xx), a :class:`~capframe.errors.ModelError` names the entry,
endpoint, model and fault in one line. The ``openai`` package's own retries are off, so this
bound is the only one.

The API key is read from the environment variable the entry names; it is never logged, never
part of :attr:`EndpointChat.identity` or of an error message (scrubbed from a server's echo).
"""

from __future__ import annotations

import email.utils
import os
import time
from concurrent.futures import ThreadPoolExecutor
from urllib.parse import urlsplit, urlunsplit

from ...errors import InputError, ModelError
from ..models import ModelSettings
from .chat import ChatReply, ChatRequest, validate_reply
from .images import data_url, encode

# Sent as the bearer token when the entry names no key: the openai package would otherwise read
# OPENAI_API_KEY, and send a key meant for one server to another. vLLM's docs use this word.
NO_KEY = "EMPTY"
# Longest wait before another attempt that a server's Retry-After may ask for, and the wait
# after a transient fault without one (doubled on each attempt).
RETRY_AFTER_CAP_S = 30.0
BACKOFF_S = 0.5
# Longest excerpt of a server's error text quoted in a ModelError.
SERVER_TEXT_CHARS = 200
FEEDBACK = "Your previous answer was rejected: {error}. Reply again with only a JSON value that matches the schema, nothing else."


class _Transient(Exception):
    """A fault worth another attempt, and the seconds to wait first (None: the backoff)."""

    def __init__(self, message: str, wait: float | None = None):
        super().__init__(message)
        self.wait = wait


def public_url(url: str) -> str:
    """``url`` without user name, password or trailing slash: what may appear in an identity,
    a cache key or a message."""
    parts = urlsplit(url)
    host = parts.hostname or ""
    netloc = f"[{host}]" if ":" in host else host
    if parts.port is not None:
        netloc += f":{parts.port}"
    return urlunsplit((parts.scheme, netloc, parts.path.rstrip("/"), parts.query, "")) or url


def _api_key(settings: ModelSettings, entry: str) -> str | None:
    """The key in the environment variable ``settings.api_key_env`` (None when it names none);
    :class:`InputError` naming the variable (never a value) when it is unset or empty."""
    if settings.api_key_env is None:
        return None
    key = os.environ.get(settings.api_key_env, "")
    if not key:
        raise InputError(f"entry {entry!r}: api_key_env names {settings.api_key_env}, which is not set in the environment")
    return key


def _retry_after(headers) -> float | None:
    """Seconds a ``Retry-After`` header asks to wait (a number or an HTTP date), or None."""
    value = headers.get("retry-after") if headers is not None else None
    if not value:
        return None
    try:
        return max(0.0, float(value))
    except ValueError:
        pass
    try:
        return max(0.0, email.utils.parsedate_to_datetime(value).timestamp() - time.time())
    except (TypeError, ValueError):
        return None


def _count(value) -> int:
    """A token count a server reported (0 when it reported none or something else)."""
    return value if isinstance(value, int) and not isinstance(value, bool) and value >= 0 else 0


class EndpointChat:
    """The chat contract over the OpenAI-compatible server of models-config entry ``entry_name``.

    Attributes:
        identity: ``"<endpoint> <model>"`` (the endpoint without credentials).
        settings: the entry (``endpoint``, ``model``, ``dialect``, ``image_side``, ``concurrency``,
            ``retries``, ``max_new_tokens``, ``timeout_s``, ``api_key_env``).
        backoff_s, retry_after_cap_s: the waits between attempts (:data:`BACKOFF_S`,
            :data:`RETRY_AFTER_CAP_S`).
    """

    backoff_s = BACKOFF_S
    retry_after_cap_s = RETRY_AFTER_CAP_S

    def __init__(self, settings: ModelSettings, entry_name: str):
        import openai

        if not settings.endpoint or not settings.model:
            raise InputError(f"entry {entry_name!r}: an MLLM endpoint needs both endpoint (a URL) and model (its name)")
        if urlsplit(settings.endpoint).scheme not in ("http", "https"):
            raise InputError(f"entry {entry_name!r}: endpoint {public_url(settings.endpoint)!r} is not an http(s) URL")
        self.settings = settings
        self.entry = entry_name
        self.endpoint = public_url(settings.endpoint)
        self.identity = f"{self.endpoint} {settings.model}"
        self._key = _api_key(settings, entry_name)
        self._openai = openai
        self.client = openai.OpenAI(
            api_key=self._key or NO_KEY, base_url=settings.endpoint, timeout=settings.timeout_s, max_retries=0
        )
        # Ollama's native API lives at the server's root; the OpenAI-compatible one under /v1.
        root = settings.endpoint.rstrip("/")
        self._ollama_url = (root[: -len("/v1")] if root.endswith("/v1") else root) + "/api/chat"

    # --- the contract ------------------------------------------------------------------------

    def complete(self, request: ChatRequest) -> ChatReply:
        """One validated answer to ``request`` (see the module docstring for the attempts)."""
        start = time.perf_counter()
        messages = self._messages(request)
        prompt_tokens = completion_tokens = 0
        attempts = 0
        while True:
            attempts += 1
            try:
                text, used_prompt, used_completion = self._send(messages, request)
            except _Transient as fault:
                message, wait = str(fault), fault.wait
            else:
                prompt_tokens += used_prompt
                completion_tokens += used_completion
                try:
                    data = validate_reply(text, request.schema)
                except ValueError as invalid:
                    # The model answered outside the schema: show it its answer and the fault, at once.
                    message, wait = f"invalid answer: {invalid}", 0.0
                    feedback = {"role": "user", "content": FEEDBACK.format(error=invalid)}
                    messages = [*messages, {"role": "assistant", "content": text}, feedback]
                else:
                    return ChatReply(
                        data=data,
                        text=text,
                        model=self.identity,
                        prompt_tokens=prompt_tokens,
                        completion_tokens=completion_tokens,
                        seconds=time.perf_counter() - start,
                        attempts=attempts,
                    )
            if attempts > self.settings.retries:
                raise self._error(f"{message} (after {attempts} requests)")
            time.sleep(min(self.backoff_s * 2 ** (attempts - 1), self.retry_after_cap_s) if wait is None else wait)

    def complete_many(self, requests: list[ChatRequest]) -> list[ChatReply]:
        """The replies to ``requests``, in order, with up to ``concurrency`` requests in flight.
        The first failure is raised; requests not yet started are then cancelled."""
        workers = min(self.settings.concurrency, len(requests))
        if workers <= 1:
            return [self.complete(r) for r in requests]
        pool = ThreadPoolExecutor(workers, thread_name_prefix="mllm")
        try:
            return list(pool.map(self.complete, requests))
        finally:
            pool.shutdown(wait=True, cancel_futures=True)

    def served_models(self) -> list[str]:
        """The model names the server lists at ``<endpoint>/models`` (one attempt; a fault is a
        :class:`ModelError`)."""
        try:
            answer = self._call(lambda: self.client.get("/models", cast_to=object))
        except _Transient as fault:
            raise self._error(str(fault)) from None
        listed = answer.get("data") if isinstance(answer, dict) else None
        if not isinstance(listed, list):
            raise self._error("the server's /models answer has no list of models (data)")
        return [str(model.get("id")) for model in listed if isinstance(model, dict)]

    # --- one request ---------------------------------------------------------------------------

    def _messages(self, request: ChatRequest) -> list[dict]:
        """The system turn and the user turn (images first, then the text) in the dialect's form."""
        side = self.settings.image_side
        if self.settings.dialect == "ollama":
            user = {"role": "user", "content": request.user}
            if request.images:
                user["images"] = [encode(image, side)[1] for image in request.images]
        elif request.images:
            parts = [{"type": "image_url", "image_url": {"url": data_url(image, side)}} for image in request.images]
            user = {"role": "user", "content": [*parts, {"type": "text", "text": request.user}]}
        else:
            user = {"role": "user", "content": request.user}
        return [{"role": "system", "content": request.system}, user]

    def _send(self, messages: list[dict], request: ChatRequest) -> tuple[str, int, int]:
        """One request: the answer text and the (prompt, completion) tokens the server reports.

        The body goes as a plain dict through the client's ``post`` (its auth, base URL, timeout
        and error classes) rather than ``chat.completions.create``, whose typed transform of the
        messages and parse into models cost 2.2 ms a call more (3.4 ms with a 640x480 image)
        against the benchmark's instant server; the dialects' fields are all top-level keys of
        the body, as ``extra_body`` would have merged them."""
        max_tokens = min(request.max_tokens, self.settings.max_new_tokens)
        dialect = self.settings.dialect
        body = {"model": self.settings.model, "messages": messages}
        if dialect == "ollama":
            body |= {"format": request.schema, "stream": False, "options": {"temperature": 0, "num_predict": max_tokens}}
            answer = self._call(lambda: self.client.post(self._ollama_url, cast_to=object, body=body))
            message = answer.get("message") if isinstance(answer, dict) else None
            if not isinstance(message, dict) or not isinstance(message.get("content"), str):
                raise _Transient("the server's answer has no message.content")
            return message["content"], _count(answer.get("prompt_eval_count")), _count(answer.get("eval_count"))
        body |= {"max_tokens": max_tokens, "temperature": 0}
        if dialect == "openai":
            body["response_format"] = {
                "type": "json_schema",
                "json_schema": {"name": request.schema_name, "schema": request.schema},
            }
        elif dialect == "vllm":
            body["structured_outputs"] = {"json": request.schema}
        elif dialect == "vllm-legacy":
            body["guided_json"] = request.schema
        answer = self._call(lambda: self.client.post("/chat/completions", cast_to=object, body=body))
        try:
            text = answer["choices"][0]["message"]["content"]
        except (KeyError, IndexError, TypeError):
            raise _Transient("the server's answer has no choices[0].message.content") from None
        usage = answer.get("usage") if isinstance(answer.get("usage"), dict) else {}
        return text or "", _count(usage.get("prompt_tokens")), _count(usage.get("completion_tokens"))

    def _call(self, send):
        """``send()``, its faults sorted: :class:`_Transient` to retry, :class:`ModelError` to stop."""
        openai = self._openai
        try:
            return send()
        except openai.APITimeoutError:
            raise _Transient(f"no answer within timeout_s = {self.settings.timeout_s:g} s") from None
        except openai.APIConnectionError as err:
            cause = err.__cause__ or err
            raise _Transient(f"connection failed ({type(cause).__name__}: {cause})") from None
        except openai.APIStatusError as err:
            status = err.status_code
            said = self._scrub(" ".join(str(err.message).split()))[:SERVER_TEXT_CHARS]
            if status in (401, 403):
                hint = (
                    f"check the key in {self.settings.api_key_env}"
                    if self.settings.api_key_env
                    else "name the variable holding the key in the entry's api_key_env"
                )
                raise self._error(f"the server refused the request (HTTP {status}); {hint}") from None
            if status in (408, 429) or status >= 500:
                wait = _retry_after(err.response.headers) if status in (429, 503) else None
                if wait is not None:
                    wait = min(wait, self.retry_after_cap_s)
                raise _Transient(f"HTTP {status}: {said}", wait) from None
            raise self._error(f"HTTP {status}: {said} (dialect {self.settings.dialect!r})") from None
        except ValueError as err:  # a body that is not JSON (json.JSONDecodeError)
            raise _Transient(f"the server's answer is not valid JSON ({type(err).__name__})") from None

    def _scrub(self, text: str) -> str:
        """``text`` with the API key, should a server echo it, replaced by ``***``."""
        return text.replace(self._key, "***") if self._key else text

    def _error(self, fault: str) -> ModelError:
        return ModelError(self._scrub(f"MLLM entry {self.entry!r} ({self.endpoint}, model {self.settings.model}): {fault}"))
