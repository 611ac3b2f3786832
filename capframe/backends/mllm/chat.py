"""The chat contract every MLLM backend serves, whatever runs the model.

A role (the subject parser, Question-Evaluation, a judge) builds a :class:`ChatRequest`: a system
prompt, a user text, images, and the JSON schema its answer must satisfy. A :class:`ChatModel`
(an OpenAI-compatible endpoint, local weights with schema-constrained decoding, a response cache
around either) returns a :class:`ChatReply` whose ``data`` has been validated against that schema
on our side, whatever the model or server promised.
"""

from __future__ import annotations

import difflib
import json
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from ...errors import clip

# The user turn that answers a model's invalid answer on a retry (both backends).
FEEDBACK = "Your previous answer was rejected: {error}. Reply again with only a JSON value that matches the schema, nothing else."
# How many of an enum's values an answer outside it is told (the nearest in spelling).
ENUM_CLOSEST = 3


@dataclass(frozen=True)
class ChatRequest:
    """One structured question to a multimodal model.

    Attributes:
        system: the system prompt (a versioned prompt file's text).
        user: the user turn's text.
        images: (H, W, 3) uint8 RGB images shown before the user text, in order.
        schema: the JSON schema (draft 2020-12) the answer must satisfy.
        schema_name: a short name for the schema (servers' ``json_schema.name``).
        prompt_version: the prompt file's version, part of every cache key and output.
        max_tokens: the longest answer, in tokens.
    """

    system: str
    user: str
    schema: dict
    schema_name: str
    prompt_version: str
    images: tuple[np.ndarray, ...] = ()
    max_tokens: int = 512


@dataclass
class ChatReply:
    """A schema-valid answer and what it cost.

    Attributes:
        data: the parsed, validated JSON answer.
        text: the model's raw answer text.
        model: the model's identity (endpoint + model name, or the weights folder).
        prompt_tokens, completion_tokens: as reported by the server or counted locally (0 if unknown).
        seconds: wall time spent on this request, retries included (0 for a cache hit).
        attempts: requests made (0 for a cache hit).
        cached: True when answered from the response cache.
    """

    data: dict
    text: str
    model: str
    prompt_tokens: int = 0
    completion_tokens: int = 0
    seconds: float = 0.0
    attempts: int = 1
    cached: bool = False
    extra: dict = field(default_factory=dict)


class ChatModel(Protocol):
    """Anything that answers :class:`ChatRequest` with a validated :class:`ChatReply`.

    ``identity`` names the model for cache keys and reports (never a key or secret).
    ``complete_many`` may run requests concurrently (bounded) and returns replies in order.
    Failures after the bounded retries raise :class:`~capframe.errors.ModelError`: one line
    naming the endpoint or weights, the model and the fault.
    """

    identity: str

    def complete(self, request: ChatRequest) -> ChatReply: ...

    def complete_many(self, requests: list[ChatRequest]) -> list[ChatReply]: ...


def validate_reply(text: str, schema: dict) -> dict:
    """``text`` parsed as JSON and checked against ``schema``.

    Raises:
        ValueError: one line naming the first fault (not JSON, or the schema path that fails);
            the caller feeds it back to the model on a retry. A value outside an enum (a scene
            object's name) is told the closest allowed values, not the whole list.
    """
    import jsonschema

    try:
        data = json.loads(text, parse_constant=_not_a_number)
    except json.JSONDecodeError as err:
        raise ValueError(f"the answer is not JSON ({err.msg} at character {err.pos})") from None
    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(schema).iter_errors(data))
    if error is not None:
        where = "/".join(str(p) for p in error.absolute_path) or "the top level"
        message = error.message
        if error.validator == "enum":
            allowed = [json.dumps(v) for v in error.validator_value]
            closest = difflib.get_close_matches(json.dumps(error.instance), allowed, n=ENUM_CLOSEST, cutoff=0.0)
            said = clip(json.dumps(error.instance))
            message = f"{said} is not one of the {len(allowed)} allowed values; closest: {', '.join(closest)}"
        raise ValueError(f"the answer does not match the schema at {where}: {message}")
    return data


def _not_a_number(word: str):
    """``json.loads``' hook for ``NaN`` and ``Infinity``, which Python reads and JSON forbids."""
    raise ValueError(f"the answer is not JSON ({word} is not a JSON number)")
