"""The paper's image-text metrics of every method's final frame: ``capframe metrics``.

Per method and instruction, the score of the result's ``render.png`` against the instruction's
text by two image-text models of the models config, each loaded once per job:

================  ===========  ===============================================================
models config     column       score
================  ===========  ===============================================================
``metrics-clip``  ``clip``     CLIP (the paper's ViT-H/14): the cosine of the L2-normalised
                               image and text embeddings, in [-1, 1]
``metrics-siglip`` ``siglip``  SigLIP 2: the sigmoid probability
                               ``sigmoid(exp(logit_scale) * cos + logit_bias)``, in (0, 1)
================  ===========  ===============================================================

(:meth:`capframe.backends.image_text.ImageTextModel.score`.) Either entry may be absent; its
column is then absent too, never filled with a stand-in. The text is the instruction as written
(a paraphrase variant is scored against the original text, as the paper's sensitivity table is).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..render.image import read_rgb
from ..scene._io import atomic_write, read_json

# Column -> (models config entry, image-text backend whose convention the score follows).
METRICS = {"clip": ("metrics-clip", "clip"), "siglip": ("metrics-siglip", "siglip")}
# What a reader is told when a metric's column is absent.
METRIC_HINT = {column: f"set `{entry}` in the models config" for column, (entry, _) in METRICS.items()}
METRIC_NAMES = {"clip": "CLIP", "siglip": "SigLIP 2"}


def configured_metrics(models) -> list[str]:
    """The metric columns whose models-config entry exists (``models``: a
    :class:`~capframe.backends.models.ModelsConfig`), in :data:`METRICS` order."""
    return [column for column, (entry, _) in METRICS.items() if entry in models.entries]


def read_render(path: Path) -> np.ndarray:
    """(H, W, 3) uint8 pixels of a result's ``render.png``; :class:`InputError` naming it otherwise."""
    return read_rgb(path, "render")


def pair_scores(model, images: list[np.ndarray], texts: list[str]) -> np.ndarray:
    """(N,) score of ``images[i]`` against ``texts[i]`` in ``model``'s convention: the images
    embedded in batches, each distinct text once."""
    import torch

    distinct = list(dict.fromkeys(texts))
    image_embeddings = torch.from_numpy(model.embed_images(images)).to(model.device)
    scores = model.score(image_embeddings, model.embed_texts(distinct)).float().cpu().numpy()
    return scores[np.arange(len(texts)), [distinct.index(t) for t in texts]].astype(np.float64)


def parse_pair(spec: str, what: str, form: str, example: str) -> tuple[str, str]:
    """A command-line ``KEY=VALUE`` (``form`` names the two, e.g. ``NAME=DIR``) as the stripped
    (key, value); :class:`InputError` naming the spec as ``what`` otherwise."""
    key, sep, value = spec.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise InputError(f"{what} {spec!r}: expected {form}, e.g. {example}")
    return key.strip(), value.strip()


def parse_method_spec(spec: str) -> tuple[str, Path]:
    """``NAME=DIR`` as (method, folder holding ``<id>/render.png``)."""
    name, folder = parse_pair(spec, "method", "NAME=DIR", "capframe=results/refine/capframe/<scene>")
    return name, Path(folder)


def instruction_texts(constraints: str | Path) -> dict[str, str]:
    """Instruction id -> text of a ``constraints.json`` (``capframe instructions``)."""
    data = read_json(constraints)
    if not isinstance(data, dict) or not all(isinstance(e, dict) and isinstance(e.get("text"), str) for e in data.values()):
        raise InputError("expected instruction id -> {'text': ..., ...} (capframe instructions)", source=str(constraints))
    return {key: entry["text"] for key, entry in data.items()}


def method_renders(methods: list[tuple[str, Path]], ids: list[str]) -> list[tuple[str, str, Path]]:
    """(method, instruction id, render.png) for every method and id; :class:`InputError` naming the
    first render that is missing (the workflow runs this only once every result exists)."""
    rows = []
    for method, folder in methods:
        for key in ids:
            path = folder / key / "render.png"
            if not path.is_file():
                raise InputError(f"no render.png for instruction {key!r} of method {method!r}", source=str(path.parent))
            rows.append((method, key, path))
    return rows


def metrics_table(
    scene: str, constraints: str | Path, methods: list[tuple[str, Path]], models, columns: list[str]
) -> pd.DataFrame:
    """One row per (method, instruction): ``method, scene, instruction`` and a score per metric
    column of ``columns`` (keys of :data:`METRICS`), each model loaded once."""
    from ..backends.image_text import ImageTextModel

    texts = instruction_texts(constraints)
    rows = method_renders(methods, sorted(texts))
    frame = pd.DataFrame([{"method": m, "scene": scene, "instruction": i} for m, i, _ in rows])
    images = [read_render(path) for _, _, path in rows]
    for column in columns:
        entry, backend = METRICS[column]
        model = ImageTextModel(backend, models.settings(entry))
        frame[column] = pair_scores(model, images, [texts[i] for _, i, _ in rows]) if rows else []
        del model  # one model in memory at a time (ViT-H/14 and SigLIP 2 so400m are large)
    return frame


def metrics_command(scene: str, constraints: str, methods: list[str], models_path: str | None, output: str) -> pd.DataFrame:
    """``capframe metrics``: :func:`metrics_table` of the configured metrics to ``output`` (CSV);
    :class:`InputError` when the models config names none of them."""
    from ..backends.models import read_models_config

    models = read_models_config(models_path)
    columns = configured_metrics(models)
    if not columns:
        entries = ", ".join(entry for entry, _ in METRICS.values())
        raise InputError(f"the models config has none of the metrics' entries ({entries})", source=models_path)
    specs = [parse_method_spec(m) for m in methods]
    names = [n for n, _ in specs]
    if len(set(names)) != len(names):
        raise InputError(f"methods {names} repeat; give each method once")
    frame = metrics_table(scene, constraints, specs, models, columns)
    atomic_write(output, frame.to_csv(index=False))
    summary = frame.groupby("method", sort=False)[columns].mean()
    print(summary.to_string(float_format=lambda v: f"{v:.4f}"))
    return frame


def read_metrics(paths: list[str | Path]) -> pd.DataFrame:
    """The rows of several ``capframe metrics`` CSVs (no metric column when ``paths`` is empty)."""
    if not paths:
        return pd.DataFrame(columns=["method", "scene", "instruction"])
    frames = []
    for path in paths:
        frame = pd.read_csv(path)
        if not {"method", "scene", "instruction"} <= set(frame.columns):
            raise InputError("lacks method, scene or instruction; expected capframe metrics' CSV", source=str(path))
        frames.append(frame)
    frame = pd.concat(frames, ignore_index=True)
    frame["instruction"] = frame["instruction"].astype(str)
    return frame
