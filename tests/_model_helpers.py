"""Tiny random-weight model backends written offline, and a models config naming them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from capframe.backends.tiny import TINY_IMAGE_TEXT, tiny_image_text, tiny_orient_anything

# Entry name in the models config -> tiny model kind; an entry is a backend name, so the NaFlex
# SigLIP gets a config of its own.
KINDS = list(TINY_IMAGE_TEXT)


def write_tiny_models(root: Path) -> dict[str, Path]:
    """Every tiny image-text model (one folder per kind), Orient Anything in both layouts, and a
    models config per image-text kind and Orient Anything layout (``<root>/<name>.yaml``, its
    single entry named after the backend, paths relative to the config). Returns name -> config."""
    configs = {}
    for kind, backend in TINY_IMAGE_TEXT.items():
        tiny_image_text(root / kind, kind)
        configs[kind] = root / f"{kind}.yaml"
        configs[kind].write_text(f"{backend}: {{weights: {kind}, batch_size: 2}}\n")
    for width in (722, 902):
        weights, config = tiny_orient_anything(root / f"oa{width}", width)
        configs[f"oa{width}"] = root / f"oa{width}.yaml"
        configs[f"oa{width}"].write_text(
            f"orient-anything: {{weights: {weights.relative_to(root)}, config: {config.relative_to(root)}}}\n"
        )
    return configs


def pictures(*sizes: tuple[int, int], seed: int = 0) -> list[np.ndarray]:
    """Random (H, W, 3) uint8 pictures of the given (width, height) sizes."""
    rng = np.random.default_rng(seed)
    return [rng.integers(0, 256, (h, w, 3), dtype=np.uint8) for w, h in sizes]
