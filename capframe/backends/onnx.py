"""Image encoders on ONNX Runtime (CPU): the export (``capframe models export``) and the session
the backends run when the models config names an ONNX file.

The export uses the TorchScript exporter (``torch.onnx.export(dynamo=False)``, opset 17): the
dynamo exporter needs ``onnxscript``, which the project does not carry. The batch axis is
dynamic; the other input sizes are those of the model's image processor. A NaFlex encoder takes
its patch grid as an input (``spatial_shapes``): transformers 5 resizes the position
embeddings with tensor arithmetic, so one export serves every aspect ratio (tested). Its patch
axis is fixed, though (the TorchScript exporter bakes the pooling head's sequence length into a
reshape), so it is exported at the model's largest patch budget and shorter sequences are padded:
padded patches are masked out, which leaves the features exactly unchanged.

Sessions never busy-wait (``allow_spinning`` 0: spinning threads would burn a shared machine's
cores between calls) and use the configured number of intra-op threads.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from ..scene._io import atomic_write

OPSET = 17
OUTPUT = "features"


def session(path: str | Path, threads: int | None = None):
    """An onnxruntime CPU session of the file at ``path`` with ``threads`` intra-op threads (None:
    the library's default) and no busy-waiting (spinning threads doubled latency on a shared
    2-core machine); :class:`InputError` when it is missing or not a model onnxruntime can load."""
    import onnxruntime as ort

    path = Path(path)
    if not path.is_file():
        raise InputError("ONNX file not found (write it with `capframe models export`)", source=str(path))
    options = ort.SessionOptions()
    if threads is not None:
        options.intra_op_num_threads = threads
        options.inter_op_num_threads = 1
    options.add_session_config_entry("session.intra_op.allow_spinning", "0")
    options.add_session_config_entry("session.inter_op.allow_spinning", "0")
    options.log_severity_level = 3  # errors only: its warnings name graph internals
    try:
        return ort.InferenceSession(str(path), options, providers=["CPUExecutionProvider"])
    except Exception as err:  # onnxruntime raises its own exception types for unreadable files
        raise InputError(f"onnxruntime cannot load it ({str(err).splitlines()[0]})", source=str(path)) from None


class OnnxEncoder:
    """An exported image encoder: model inputs (NumPy or torch) -> (B, D) float32 features.

    Args:
        path: the ONNX file.
        inputs: the input names the model takes, in order (checked against the file).
        threads: intra-op threads (None: the library's default).
        features: the expected feature size D (checked against the file when it is static).
    """

    def __init__(self, path: str | Path, inputs: Sequence[str], threads: int | None = None, features: int | None = None):
        self.path = Path(path)
        self.session = session(path, threads)
        names = [i.name for i in self.session.get_inputs()]
        if names != list(inputs):
            raise InputError(f"takes inputs {names}; this model's image encoder takes {list(inputs)}", source=str(path))
        width = self.session.get_outputs()[0].shape[-1]
        if features is not None and isinstance(width, int) and width != features:
            raise InputError(f"outputs {width} features; the model's image encoder outputs {features}", source=str(path))
        self.inputs = list(inputs)
        # NaFlex: the exported sequence length, to which shorter patch sequences are padded.
        self.patches = self.session.get_inputs()[0].shape[1] if "pixel_attention_mask" in self.inputs else None

    def __call__(self, batch: dict) -> np.ndarray:
        """(B, D) features of one batch of model inputs."""
        feed = {name: _numpy(batch[name]) for name in self.inputs}
        if self.patches is not None:
            feed = self._padded(feed)
        return self.session.run(None, feed)[0].astype(np.float32, copy=False)

    def _padded(self, feed: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """NaFlex inputs padded along the patch axis to the exported length (masked out)."""
        missing = self.patches - feed["pixel_values"].shape[1]
        if missing < 0:
            raise InputError(
                f"takes {self.patches} patches; these images have {feed['pixel_values'].shape[1]} (export it again)",
                source=str(self.path),
            )
        for name in ("pixel_values", "pixel_attention_mask"):
            widths = [(0, 0)] * feed[name].ndim
            widths[1] = (0, missing)
            feed[name] = np.pad(feed[name], widths)
        return feed


def _numpy(value) -> np.ndarray:
    if isinstance(value, torch.Tensor):
        value = value.detach().cpu()
        return value.float().numpy() if value.is_floating_point() else value.numpy()
    return np.asarray(value)


class _Encoder(torch.nn.Module):
    """The function to export as a module: positional inputs -> features."""

    def __init__(self, owner: torch.nn.Module, forward: Callable[..., torch.Tensor]):
        super().__init__()
        self.owner = owner  # registers the weights
        self.encode = forward

    def forward(self, *inputs: torch.Tensor) -> torch.Tensor:
        return self.encode(*inputs)


# A protobuf message cannot exceed 2 GiB: weights above this go to one external data file beside
# the model (``<name>.data``), which onnxruntime reads from the model's folder (SAM ViT-H's image
# encoder alone is ~2.5 GB in float32).
EXTERNAL_DATA_BYTES = 2**31 - 2**26


def export(
    module: torch.nn.Module,
    forward: Callable[..., torch.Tensor],
    example: dict[str, torch.Tensor],
    path: str | Path,
    external_data_bytes: int = EXTERNAL_DATA_BYTES,
) -> None:
    """Write ``forward`` (the image encoder of ``module``, taking ``example``'s tensors in order)
    to ``path`` as ONNX with a dynamic batch axis, atomically. NaFlex inputs (a
    ``pixel_attention_mask`` among them) also get a dynamic patch axis: the patch budget varies
    per image (FG-CLIP 2).

    Args:
        module: the model whose weights ``forward`` uses (exported in float32).
        forward: inputs -> (B, D) features.
        example: input name -> an example tensor (batch of 1 or more).
        path: the ONNX file to write.
        external_data_bytes: weights larger than this in all are written to ``<path>.data``
            beside ``path`` (which then holds the graph only), written before the model file.
    """
    import tempfile
    import warnings

    import onnx

    path = Path(path)
    names = list(example)
    axes = {name: {0: "batch"} for name in [*names, OUTPUT]}
    with tempfile.TemporaryDirectory(dir=path.parent, prefix=f".{path.name}.") as folder:
        # A file, not a buffer: for a model over 2 GiB the exporter itself writes external data.
        traced = Path(folder) / "traced.onnx"
        with warnings.catch_warnings(), torch.no_grad():
            # The TorchScript exporter warns about traced Python conditions: the model's shape checks.
            warnings.simplefilter("ignore")
            torch.onnx.export(
                # In eval mode: the exporter restores the wrapper's mode, and with it the model's, afterwards.
                _Encoder(module, forward).eval(),
                tuple(example.values()),
                str(traced),
                dynamo=False,
                opset_version=OPSET,
                input_names=names,
                output_names=[OUTPUT],
                dynamic_axes=axes,
            )
        model = onnx.load(str(traced))
        weights = sum(tensor.ByteSize() for tensor in model.graph.initializer)
        if weights <= external_data_bytes:
            atomic_write(path, model.SerializeToString())
            return
        data = Path(folder) / f"{path.name}.data"
        onnx.save_model(
            model, str(Path(folder) / path.name), save_as_external_data=True, all_tensors_to_one_file=True, location=data.name
        )
        os.replace(data, path.parent / data.name)
        os.replace(Path(folder) / path.name, path)


def parity(encoder: OnnxEncoder, forward: Callable[..., torch.Tensor], batch: dict[str, torch.Tensor]) -> float:
    """Largest absolute difference between onnxruntime's and PyTorch's features of ``batch``."""
    with torch.no_grad():
        reference = forward(*[batch[name] for name in encoder.inputs]).float().numpy()
    return float(np.abs(encoder(batch) - reference).max())
