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
    identity: the image size sent and the answer's token cap."""
    if settings.endpoint is not None and settings.weights is not None:
        raise InputError(f"entry {entry!r}: give either endpoint (a server) or weights (local), not both")
    if settings.endpoint is not None:
        from .endpoint import EndpointChat

        inner = EndpointChat(settings, entry)
    else:
        from .local import LocalChat  # transformers and xgrammar load only for local weights

        inner = LocalChat(settings)
    return CachedChat(inner, cache_folder, tag=f"image_side={settings.image_side} max_new_tokens={settings.max_new_tokens}")
