"""The paper's MLLM judges of every method's final frame: ``capframe judge``.

Per instruction each configured judge (models config entries ``judge`` and ``judge-2``: any
OpenAI-compatible endpoint or local weights, as every MLLM role) rates every method's
``render.png`` 1-5 against the instruction (the alignment score, AS) and picks the best of them
(the win rate, WR: the share of instructions in which a method's frame was picked). The judge is
blind: it sees pictures only, "Image 1" to "Image N" in an order drawn from the seed and the
instruction (:func:`capframe.backends.mllm.judge.blind_order`), different per instruction and the
same on every rerun; the order is recorded with each pick, so a pick maps back to its method. Every
request goes through the response cache in the scene's cache folder, so a rerun asks nothing twice.

The record, ``results/judges/<scene>.json``::

    {"format": 1, "scene": S, "seed": 0, "methods": [...],
     "judges": {"judge": {"model": ..., "prompts": [...], "mllm": {counters}}, ...},
     "instructions": {ID: {"text": ..., "order": [methods as shown, Image 1 first],
                           "judges": {"judge": {"ratings": {method: 1-5}, "reasons": {method: ...},
                                                "best": method, "best_image": k, "reason": ...}}}}}
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..backends.mllm.judge import blind_order
from ..errors import InputError
from ..scene._io import read_json, write_json
from .metrics import instruction_texts, method_renders, parse_method_spec, read_render

FORMAT = 1
# The models config entries of the two judges (the registry's ``judge`` role: ``mllm``, ``mllm-2``).
JUDGE_ENTRIES = ("judge", "judge-2")
JUDGE_HINT = "set `judge` (and `judge-2`) in the models config"


def configured_judges(models) -> list[str]:
    """The judge entries the models config has, in :data:`JUDGE_ENTRIES` order."""
    return [entry for entry in JUDGE_ENTRIES if entry in models.entries]


def judge_instruction(judge, text: str, frames: dict, seed: int) -> dict:
    """One judge's ratings of every frame (method -> (H, W, 3) uint8) and its blind pick.

    Returns ``{"ratings", "reasons", "best", "best_image", "reason"}``: ``best_image`` is the
    1-based number of the picture the judge answered, in the order it was shown
    (:func:`blind_order` of the methods, the text and the seed)."""
    ratings = dict(zip(frames, judge.assess_many(list(frames.values()), text)))
    pick = judge.pick(frames, text, seed)
    return {
        "ratings": {method: r.score for method, r in ratings.items()},
        "reasons": {method: r.reason for method, r in ratings.items()},
        "best": pick.best,
        "best_image": pick.order.index(pick.best) + 1,
        "reason": pick.reason,
    }


def judge_scene(judges: dict, texts: dict[str, str], renders: dict[str, dict[str, Path]], seed: int) -> dict:
    """Every judge (entry -> :class:`~capframe.backends.mllm.judge.MLLMJudge`) on every
    instruction (id -> {method -> render.png}); the ``instructions`` part of the record."""
    out = {}
    for key in sorted(renders):
        frames = {method: read_render(path) for method, path in renders[key].items()}
        verdicts = {entry: judge_instruction(judge, texts[key], frames, seed) for entry, judge in judges.items()}
        # Every judge is shown the same order (drawn from the seed and the text): recorded once.
        out[key] = {"text": texts[key], "order": blind_order(list(frames), texts[key], seed), "judges": verdicts}
    return out


def judge_command(
    scene: str,
    constraints: str,
    methods: list[str],
    models_path: str | None,
    cache: str,
    output: str,
    seed: int = 0,
) -> dict:
    """``capframe judge``: every configured judge on every instruction of ``constraints`` and every
    method (``NAME=DIR`` with ``DIR/<id>/render.png``), recorded to ``output`` (JSON)."""
    from ..backends.mllm.factory import CACHE_FOLDER, build_chat
    from ..backends.mllm.judge import MLLMJudge
    from ..backends.models import read_models_config

    models = read_models_config(models_path)
    entries = configured_judges(models)
    if not entries:
        raise InputError(f"the models config has no judge entry ({', '.join(JUDGE_ENTRIES)})", source=models_path)
    specs = [parse_method_spec(m) for m in methods]
    names = [n for n, _ in specs]
    if len(specs) < 2 or len(set(names)) != len(names):
        raise InputError(f"methods {names}: a judge picks among at least two distinct methods")
    texts = instruction_texts(constraints)
    renders: dict[str, dict[str, Path]] = {}
    for method, key, path in method_renders(specs, sorted(texts)):
        renders.setdefault(key, {})[method] = path
    chats = {entry: build_chat(models.settings(entry), entry, Path(cache) / CACHE_FOLDER) for entry in entries}
    judges = {entry: MLLMJudge(chat) for entry, chat in chats.items()}
    instructions = judge_scene(judges, texts, renders, seed)
    record = {
        "format": FORMAT,
        "scene": scene,
        "seed": seed,
        "methods": names,
        "judges": {
            entry: {
                "model": chats[entry].identity,
                "prompts": [p.version for p in judges[entry].prompts.values()],
                "mllm": chats[entry].stats(),
            }
            for entry in entries
        },
        "instructions": instructions,
    }
    write_json(output, record)
    for entry in entries:
        stats = chats[entry].stats()
        print(
            f"{entry}: {len(instructions)} instructions, {stats['mllm_calls']} requests, "
            f"{stats['mllm_cache_hits']} from the cache, {stats['mllm_model_seconds']:.1f} s"
        )
    return record


def read_judgements(paths: list[str | Path]) -> pd.DataFrame:
    """One row per (judge, scene, instruction, method) of ``capframe judge`` records: ``rating``
    and ``picked`` (whether the judge picked this method's frame)."""
    rows = []
    for path in paths:
        record = read_json(path)
        if not isinstance(record, dict) or record.get("format") != FORMAT or "instructions" not in record:
            raise InputError("not a capframe judge record (format 1)", source=str(path))
        try:
            for key, entry in record["instructions"].items():
                for judge, verdict in entry["judges"].items():
                    for method, rating in verdict["ratings"].items():
                        rows.append(
                            {
                                "judge": judge,
                                "scene": record["scene"],
                                "instruction": key,
                                "method": method,
                                "rating": float(rating),
                                "picked": verdict["best"] == method,
                            }
                        )
        except (KeyError, TypeError, AttributeError, ValueError) as err:
            raise InputError(f"not a capframe judge record: {type(err).__name__} {err}", source=str(path)) from None
    return pd.DataFrame(rows, columns=["judge", "scene", "instruction", "method", "rating", "picked"])


def judge_models(paths: list[str | Path]) -> dict[str, str]:
    """Judge entry -> the model it ran (its identity), from ``capframe judge`` records."""
    found: dict[str, str] = {}
    for path in paths:
        for entry, info in read_json(path).get("judges", {}).items():
            found.setdefault(entry, info["model"])
    return found
