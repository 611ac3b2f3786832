"""Models benchmark: each image encoder's seconds per image with PyTorch and with onnxruntime,
side by side, on the CPU with the same number of threads.

The tiny random-weight models (:mod:`capframe.backends.tiny`) always run: they show the
runtimes' fixed costs, not a real model's. Every image-encoder backend of a models config given
with ``--models`` runs too (its real weights, its ``threads``). Each encoder is exported to a
temporary ONNX file, checked against PyTorch, then timed on a batch of pictures of the default
suite's size (320x240): the best of a few runs after a warm-up, divided by the batch size.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np
import torch

from ..backends.export import EXPORTABLE, ORIENT_ANYTHING, SAM, encoder_inputs, encoder_of, export_backend
from ..backends.models import ModelSettings, read_models_config
from ..backends.onnx import OnnxEncoder
from ..backends.tiny import TINY_IMAGE_TEXT, tiny_image_text, tiny_orient_anything, tiny_sam

BATCH = 8
REPEATS = 5
PICTURE = (240, 320)  # (height, width) of the default suite's training images


def _best_seconds(run, repeats: int = REPEATS) -> float:
    """The fastest of ``repeats`` runs of ``run()`` after one warm-up run."""
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def time_encoder(backend: str, settings: ModelSettings, folder: Path) -> dict:
    """PyTorch and onnxruntime seconds per image of ``backend``'s image encoder on the entry's
    ``threads`` (1 when unset), and their largest difference on the export's check images."""
    threads = settings.threads or 1
    difference = export_backend(backend, settings, folder / f"{backend}.onnx", threads)
    model, _, forward, names, _ = encoder_of(backend, settings)
    rng = np.random.default_rng(0)
    pictures = [rng.integers(0, 256, (*PICTURE, 3), dtype=np.uint8) for _ in range(BATCH)]
    [batch] = encoder_inputs(backend, model, pictures)
    encoder = OnnxEncoder(folder / f"{backend}.onnx", names, threads)
    default = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        with torch.no_grad():
            pytorch = _best_seconds(lambda: forward(*[batch[n] for n in names])) / BATCH
        onnx = _best_seconds(lambda: encoder(batch)) / BATCH
    finally:
        torch.set_num_threads(default)
    return {
        "threads": threads,
        "PyTorch s/image": pytorch,
        "onnxruntime s/image": onnx,
        "speed-up": pytorch / onnx,
        "max |difference|": difference,
    }


def bench_models(models: str | Path | None = None) -> dict:
    """Model label -> its figures (:func:`time_encoder`): the tiny models, then the configured ones."""
    figures = {}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cases = []
        for kind, backend in TINY_IMAGE_TEXT.items():
            cases.append((f"{kind} (tiny)", backend, ModelSettings(weights=str(tiny_image_text(folder / kind, kind)))))
        weights, config = tiny_orient_anything(folder / ORIENT_ANYTHING)
        cases.append((f"{ORIENT_ANYTHING} (tiny)", ORIENT_ANYTHING, ModelSettings(weights=str(weights), config=str(config))))
        cases.append((f"{SAM} (tiny)", SAM, ModelSettings(weights=str(tiny_sam(folder / SAM)))))
        configured = read_models_config(models)
        cases += [(name, name, configured.entries[name]) for name in configured.entries if name in EXPORTABLE]
        for label, backend, settings in cases:
            figures[label] = time_encoder(backend, settings, folder)
    return figures
