"""``capframe models check``: every entry of a models config tried without running a job.

Per entry: the files it names exist; an endpoint answers ``/models`` and lists the entry's model;
an MLLM (an endpoint, or local Qwen-VL weights) answers a tiny schema with a small image, through
the same client, dialect and validation as a job. One line per entry, ``ok`` or its fault.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from ..errors import InputError, ModelError
from .models import PATH_FIELDS, ModelSettings, read_models_config

# transformers model types the local MLLM backend loads (capframe.backends.mllm.local).
LOCAL_MLLM_TYPES = ("qwen2_5_vl", "qwen3_vl", "qwen3_vl_moe")
SMOKE_SCHEMA = {
    "type": "object",
    "properties": {"colour": {"type": "string", "enum": ["red", "green", "blue"]}},
    "required": ["colour"],
}


def smoke_request():
    """A tiny structured question with one 32x32 red image: the schema smoke call."""
    from .mllm.chat import ChatRequest

    red = np.zeros((32, 32, 3), np.uint8)
    red[..., 0] = 255
    return ChatRequest(
        system="You answer with JSON only.",
        user='What colour is this image? Answer {"colour": "red"}, {"colour": "green"} or {"colour": "blue"}.',
        schema=SMOKE_SCHEMA,
        schema_name="smoke",
        prompt_version="smoke-1",
        images=(red,),
        max_tokens=32,
    )


def _local_mllm(settings: ModelSettings) -> bool:
    """Whether ``settings.weights`` is a transformers folder of a model type the local MLLM loads."""
    config = Path(settings.weights or "") / "config.json"
    try:
        return json.loads(config.read_text()).get("model_type") in LOCAL_MLLM_TYPES
    except (OSError, ValueError, AttributeError):
        return False


def check_entry(name: str, settings: ModelSettings) -> str:
    """What was verified of entry ``name``, in a few words; :class:`InputError` or
    :class:`ModelError` (one line) at its first fault."""
    for key in PATH_FIELDS:
        path = getattr(settings, key)
        if path is not None and not Path(path).exists():
            raise InputError(f"entry {name!r}: {key} {path} does not exist")
    if settings.endpoint is not None:
        from .mllm.endpoint import EndpointChat

        chat = EndpointChat(settings, name)
        served = chat.served_models()
        if settings.model not in served:
            fault = f"the server does not list model {settings.model!r}; it lists {served[:10]}"
            raise ModelError(f"MLLM entry {name!r} ({chat.endpoint}): {fault}")
    elif _local_mllm(settings):
        try:
            from .mllm.local import LocalChat
        except ImportError as err:
            raise ModelError(f"entry {name!r}: the local MLLM backend cannot be loaded ({err})") from None
        chat = LocalChat(settings)
    else:
        return "files found"
    start = time.perf_counter()
    reply = chat.complete(smoke_request())
    return f"{chat.identity}: schema answer {reply.data} in {time.perf_counter() - start:.2f} s, {reply.attempts} request(s)"


def check_models(path: str | Path) -> int:
    """Print one line per entry of the models config at ``path`` (``NAME: ok (...)`` or
    ``NAME: FAULT``); the number of faulty entries."""
    config = read_models_config(path)
    if not config.entries:
        raise InputError("has no entries", source=str(path))
    faults = 0
    width = max(map(len, config.entries))
    for name, settings in config.entries.items():
        try:
            line = f"ok ({check_entry(name, settings)})"
        except (InputError, ModelError) as err:
            faults += 1
            line = str(err)
        print(f"{name + ':':<{width + 1}} {line}", flush=True)
    return faults
