"""The models config: where each model backend finds its weights or server, and how it runs.

A YAML file (``config/models.yaml``, ``--models``) mapping a backend name to its settings::

    fg-clip:
      weights: /models/fg-clip-base      # a local weights directory or file
      device: cuda
      dtype: float16
      batch_size: 32
    qwen3-vl:
      endpoint: http://localhost:8000/v1  # an OpenAI-compatible server
      model: Qwen/Qwen3-VL-8B-Instruct
      api_key_env: OPENAI_API_KEY        # the key is read from this variable, never stored
    detector:
      weights: /models/centernet_coco.onnx  # an ONNX file
      threshold: 0.3                      # detection score threshold
      threads: 1                          # onnxruntime intra-op threads
    orient-anything:
      weights: /models/orient-anything/ronormsigma1/dino_weight.pt
      config: /models/dinov2-large       # the DINOv2 config and image processor
      onnx: /models/orient-anything.onnx # from `capframe models export`: images run on onnxruntime
      min_confidence: 0.5

An entry is named after a backend or after a model a backend is built from (``grounded-sam``
reads ``grounding-dino`` and ``sam``; ``detector`` reads ``detector`` and, when present, ``sam``).
Backends that need no model (the oracle tier, the rule parser) have no entry. The fields are
documented in ``docs/models.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path

from ..errors import InputError

DTYPES = ("float32", "float16", "bfloat16")
# Structured-output dialects of OpenAI-compatible servers: ``openai`` (``response_format``
# json_schema: OpenAI, SGLang, vLLM, Ollama's /v1), ``vllm`` (``structured_outputs``, vLLM >=
# 0.12), ``vllm-legacy`` (``guided_json``), ``ollama`` (native /api/chat ``format``), ``none``
# (not asked; the answer is still validated, e.g. ``transformers serve``).
DIALECTS = ("openai", "vllm", "vllm-legacy", "ollama", "none")
# Fields that name local files: a relative path is relative to the config file, so a config and
# its weights move together.
PATH_FIELDS = ("weights", "config", "onnx")


@dataclass(frozen=True)
class ModelSettings:
    """One backend's entry of the models config (docs/models.md has every field).

    Attributes:
        weights: a local weights directory or file (relative paths are read from the models
            config's folder, as are ``config`` and ``onnx``).
        config: a model config directory, when ``weights`` is a bare checkpoint file (Orient
            Anything: the DINOv2 directory with ``config.json`` and ``preprocessor_config.json``).
        onnx: an ONNX file of the model's image encoder (``capframe models export``); images are
            then encoded by onnxruntime on the CPU.
        min_confidence: Orient Anything: views whose estimate is less confident are ignored.
        dialect: MLLM endpoint: how structured output is asked for (:data:`DIALECTS`).
        image_side: MLLM: images are downscaled so that their long side is at most this.
        concurrency: MLLM endpoint: requests in flight at once when scoring many views.
        retries: MLLM: further attempts after an invalid answer or a transient server fault.
        max_new_tokens: MLLM: the longest answer, in tokens.
    """

    weights: str | None = None
    endpoint: str | None = None
    model: str | None = None
    api_key_env: str | None = None
    device: str = "cpu"
    dtype: str = "float32"
    batch_size: int = 8
    timeout_s: float = 60.0
    threshold: float | None = None  # a detector's score threshold (None: the backend's default)
    threads: int | None = None  # CPU threads of an onnxruntime session (None: the library's default)
    config: str | None = None
    onnx: str | None = None
    min_confidence: float = 0.5
    # MLLM backends (capframe.backends.mllm): the server's structured-output dialect, the long
    # side images are downscaled to, concurrent requests, retries after an invalid or failed
    # answer, and the longest answer.
    dialect: str = "openai"
    image_side: int = 768
    concurrency: int = 4
    retries: int = 2
    max_new_tokens: int = 512


@dataclass(frozen=True)
class ModelsConfig:
    """Backend name -> :class:`ModelSettings`; ``source`` names the file for messages."""

    entries: dict[str, ModelSettings] = field(default_factory=dict)
    source: str | None = None

    def settings(self, backend: str) -> ModelSettings:
        """The settings of ``backend``; :class:`InputError` when the config has none."""
        if backend not in self.entries:
            if self.source is None:
                raise InputError(f"backend {backend!r} needs an entry in the models config; none was given (--models)")
            raise InputError(f"backend {backend!r} needs an entry in the models config; {self.source} has {sorted(self.entries)}")
        return self.entries[backend]


def _settings(name: str, entry: object, source: str) -> ModelSettings:
    """One entry checked field by field: known keys, types, a dtype and a positive batch size."""
    if not isinstance(entry, dict):
        raise InputError(f"entry {name!r} must be a mapping of settings, got {type(entry).__name__}", source=source)
    known = {f.name: f for f in fields(ModelSettings)}
    unknown = sorted(set(entry) - set(known))
    if unknown:
        raise InputError(f"entry {name!r}: unknown keys {unknown}; expected some of {sorted(known)}", source=source)
    for key, value in entry.items():
        expected = {
            "batch_size": int,
            "timeout_s": (int, float),
            "threshold": (int, float),
            "threads": int,
            "min_confidence": (int, float),
            "image_side": int,
            "concurrency": int,
            "retries": int,
            "max_new_tokens": int,
        }.get(key, str)
        if not isinstance(value, expected) or isinstance(value, bool):
            raise InputError(
                f"entry {name!r}: {key} = {value!r} is not a {getattr(expected, '__name__', 'number')}", source=source
            )
    folder = Path(source).parent
    paths = {key: str(folder / Path(entry[key]).expanduser()) for key in PATH_FIELDS if isinstance(entry.get(key), str)}
    settings = ModelSettings(**(entry | paths))
    if settings.dtype not in DTYPES:
        raise InputError(f"entry {name!r}: dtype {settings.dtype!r}; expected one of {list(DTYPES)}", source=source)
    if settings.batch_size < 1 or settings.timeout_s <= 0:
        raise InputError(f"entry {name!r}: batch_size and timeout_s must be positive", source=source)
    if settings.threshold is not None and not 0 < settings.threshold < 1:
        raise InputError(f"entry {name!r}: threshold {settings.threshold} must lie in (0, 1)", source=source)
    if settings.threads is not None and settings.threads < 1:
        raise InputError(f"entry {name!r}: threads {settings.threads} must be at least 1", source=source)
    if not 0 <= settings.min_confidence <= 1:
        raise InputError(f"entry {name!r}: min_confidence {settings.min_confidence} is not in [0, 1]", source=source)
    if settings.dialect not in DIALECTS:
        raise InputError(f"entry {name!r}: dialect {settings.dialect!r}; expected one of {list(DIALECTS)}", source=source)
    if min(settings.image_side, settings.concurrency, settings.max_new_tokens) < 1 or settings.retries < 0:
        raise InputError(
            f"entry {name!r}: image_side, concurrency and max_new_tokens must be >= 1 and retries >= 0", source=source
        )
    if settings.weights is None and settings.endpoint is None:
        raise InputError(f"entry {name!r}: give weights (a local path) or endpoint (a server URL)", source=source)
    return settings


def read_models_config(path: str | Path | None) -> ModelsConfig:
    """The models config at ``path`` (an empty one for None), validated entry by entry."""
    if path is None:
        return ModelsConfig()
    import yaml

    source = str(path)
    try:
        data = yaml.safe_load(Path(path).read_text()) or {}
    except OSError as err:
        raise InputError(f"cannot read the models config ({err.strerror})", source=source) from None
    except yaml.YAMLError as err:
        raise InputError(f"is not valid YAML ({str(err).splitlines()[0]})", source=source) from None
    if not isinstance(data, dict):
        raise InputError("must map backend names to their settings", source=source)
    entries = {str(name): _settings(str(name), entry, source) for name, entry in data.items()}
    return ModelsConfig(entries, source)
