"""Loading user-supplied model weights, checked before use.

Two kinds of weights: a transformers directory (``config.json``, the weights as safetensors or a
PyTorch ``.bin``, the processor's files) and an ONNX file. Every problem a user can cause is one
:class:`~capframe.errors.InputError` line naming the models-config entry and the file: a missing
path, the wrong kind of checkpoint (a SAM directory given for GroundingDINO), weights that lack
tensors or whose shapes disagree with ``config.json``. transformers itself would only warn about
missing tensors and initialise them at random, so the loading report is checked here.

Nothing is downloaded: weights are read with ``local_files_only``.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from typing import Any

from ..errors import InputError
from .models import ModelSettings

# File names a transformers checkpoint directory keeps its weights in (one of them).
WEIGHT_FILES = ("model.safetensors", "model.safetensors.index.json", "pytorch_model.bin", "pytorch_model.bin.index.json")


def torch_device_dtype(entry: str, settings: ModelSettings):
    """The ``(torch.device, torch.dtype)`` of an entry; :class:`InputError` for a CUDA device on a
    machine without one."""
    import torch

    try:
        device = torch.device(settings.device)
    except RuntimeError:
        raise InputError(f"models config entry {entry!r}: device {settings.device!r} is not a torch device") from None
    if device.type == "cuda" and not torch.cuda.is_available():
        raise InputError(f"models config entry {entry!r}: device {settings.device!r}, but torch sees no CUDA device here")
    return device, getattr(torch, settings.dtype)


@contextlib.contextmanager
def quiet_transformers():
    """transformers' loading report is a page-long table and its progress bar a stderr line per
    model; our own message is one line."""
    from transformers.utils import logging

    level, bars = logging.get_verbosity(), logging.is_progress_bar_enabled()
    logging.set_verbosity_error()
    logging.disable_progress_bar()
    try:
        yield
    finally:
        logging.set_verbosity(level)
        if bars:
            logging.enable_progress_bar()


def _checkpoint_dir(entry: str, settings: ModelSettings, model_type: str) -> Path:
    """The entry's weights directory, checked for a ``config.json`` of ``model_type`` and a
    weights file."""
    if settings.weights is None:
        raise InputError(f"models config entry {entry!r} needs weights: a local transformers directory")
    root = Path(settings.weights)
    if not root.is_dir():
        raise InputError(f"models config entry {entry!r}: weights {root} is not a directory (a transformers checkpoint)")
    config = root / "config.json"
    try:
        found = json.loads(config.read_text()).get("model_type")
    except OSError:
        raise InputError(
            f"has no config.json; expected a transformers {model_type} checkpoint ({entry!r})", source=str(root)
        ) from None
    except (json.JSONDecodeError, AttributeError):
        raise InputError(f"is not a JSON object of model settings ({entry!r})", source=str(config)) from None
    if found != model_type:
        raise InputError(
            f"is a {found!r} checkpoint; models config entry {entry!r} needs a {model_type!r} one", source=str(config)
        )
    if not any((root / name).is_file() for name in WEIGHT_FILES):
        raise InputError(f"has no weights file; expected one of {', '.join(WEIGHT_FILES)} ({entry!r})", source=str(root))
    return root


def load_transformers(entry: str, settings: ModelSettings, model_type: str, model_class: type) -> tuple[Any, Any]:
    """``(model, processor)`` of a transformers checkpoint directory, in eval mode on the entry's
    device and dtype.

    Args:
        entry: the models-config entry (named in messages).
        settings: its settings (``weights`` is the directory).
        model_type: the ``config.json`` ``model_type`` required (``"sam"``, ``"grounding-dino"``).
        model_class: the transformers class to instantiate (``SamModel``...).
    """
    from transformers import AutoProcessor

    root = _checkpoint_dir(entry, settings, model_type)
    device, dtype = torch_device_dtype(entry, settings)
    with quiet_transformers():
        try:
            processor = AutoProcessor.from_pretrained(root, local_files_only=True)
        except (OSError, ValueError, TypeError, KeyError) as err:
            message = str(err).splitlines()[0] if str(err) else type(err).__name__
            raise InputError(f"has no readable processor files (preprocessor/tokenizer): {message}", source=str(root)) from None
        model = load_pretrained(model_class, root, dtype)
    return model.to(device).eval(), processor


def load_pretrained(model_class: type, root: Path, dtype) -> Any:
    """``model_class`` from the checkpoint directory ``root``, every tensor loaded:
    :class:`InputError` naming the folder when it cannot be loaded, or when config.json and the
    weights disagree (missing or misshapen tensors, which transformers would leave random)."""
    try:
        model, info = model_class.from_pretrained(root, local_files_only=True, output_loading_info=True, dtype=dtype)
    except (OSError, RuntimeError, ValueError) as err:
        mismatch = "size mismatch" in str(err) or "ignore_mismatched_sizes" in str(err)
        why = "the weights' shapes disagree with config.json" if mismatch else str(err).splitlines()[0]
        raise InputError(f"cannot be loaded as {model_class.__name__}: {why}", source=str(root)) from None
    missing = sorted(info["missing_keys"]) + sorted(k for k, *_ in info["mismatched_keys"])
    if missing:
        raise InputError(
            f"the weights lack or misshape {len(missing)} of the model's tensors (e.g. {missing[0]}); "
            f"config.json and the weights disagree",
            source=str(root),
        )
    return model


def onnx_session(entry: str, settings: ModelSettings):
    """An onnxruntime CPU session of the entry's ONNX file (:func:`capframe.backends.onnx.session`:
    ``threads`` intra-op threads, no busy-waiting)."""
    from .onnx import session

    if settings.weights is None:
        raise InputError(f"models config entry {entry!r} needs weights: an ONNX file")
    path = Path(settings.weights)
    if not path.is_file():
        raise InputError(f"models config entry {entry!r}: weights {path} is not a file (an ONNX model)")
    return session(path, settings.threads)
