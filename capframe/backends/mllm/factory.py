"""The chat model of a models-config entry: an endpoint or local weights, behind the response
cache, built once per backend context and shared by every role that asks."""

from __future__ import annotations

from pathlib import Path

from ...errors import InputError
from ..models import ModelSettings
from ..protocols import BackendContext
from .cache import CachedChat
from .chat import ChatModel

# The models-config entry the MLLM roles read unless told another.
DEFAULT_ENTRY = "mllm"
# The response cache's folder inside the per-scene cache.
CACHE_FOLDER = "mllm"


def chat_model(context: BackendContext, entry: str = DEFAULT_ENTRY) -> ChatModel:
    """The cached chat model of models-config entry ``entry``, one instance per ``context``
    (so every role of a job shares its cache counters and, for local weights, one loaded model)."""
    return context.shared(
        f"mllm-chat:{entry}", lambda: build_chat(context.models.settings(entry), entry, context.cache_dir / CACHE_FOLDER)
    )


def build_chat(settings: ModelSettings, entry: str, cache_folder: str | Path) -> CachedChat:
    """``entry``'s chat model (:class:`~.endpoint.EndpointChat` for an ``endpoint``,
    :class:`~.local.LocalChat` for ``weights``) answering through a :class:`CachedChat` in
    ``cache_folder``. The cache's tag holds the settings that change answers but not the model's
    identity: the image size sent, the answer's token cap and, for local weights, the device and
    dtype they run in."""
    if settings.endpoint is not None and settings.weights is not None:
        raise InputError(f"entry {entry!r}: give either endpoint (a server) or weights (local), not both")
    if settings.endpoint is not None:
        from .endpoint import EndpointChat

        inner = EndpointChat(settings, entry)
    else:
        inner = _LocalOnFirstMiss(settings, entry)
    tag = f"image_side={settings.image_side} max_new_tokens={settings.max_new_tokens}"
    if settings.weights is not None:
        tag += f" device={settings.device} dtype={settings.dtype}"  # a local model's numerics
    return CachedChat(inner, cache_folder, tag=tag)


class _LocalOnFirstMiss:
    """Local weights loaded on the first request the cache cannot answer, so that a rerun answered
    wholly from the cache never loads the model (tens of seconds per job for a real one).

    Attributes:
        identity: the weights folder (absolute), known without loading: the cache key needs it.
        loaded: the :class:`~.local.LocalChat` once built, else None.
    """

    def __init__(self, settings: ModelSettings, entry: str):
        from ..weights import torch_device_dtype
        from .local import qwen_folder

        self.settings, self.entry = settings, entry
        self.identity = str(qwen_folder(settings.weights, entry))  # the folder's faults, now
        torch_device_dtype(entry, settings)  # and the device's (a CUDA device on a machine without one)
        self.loaded = None

    def _chat(self):
        if self.loaded is None:
            from .local import LocalChat  # transformers and xgrammar load only for local weights

            self.loaded = LocalChat(self.settings, self.entry)
        return self.loaded

    def complete(self, request):
        return self._chat().complete(request)

    def complete_many(self, requests):
        return self._chat().complete_many(requests)
