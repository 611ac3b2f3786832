"""The paper's tables: image-text metrics, blind MLLM judges, Table 1 and the metric and MLLM
columns of Tables 2-4 (capframe.evaluate.metrics, .judging, .quantitative, .tables)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import torch
from PIL import Image
from test_tables import pose, write_result, write_scene

from capframe.backends.mllm.chat import ChatReply
from capframe.backends.mllm.judge import MLLMJudge, blind_order
from capframe.errors import InputError
from capframe.evaluate.judging import judge_command, judge_scene, read_judgements
from capframe.evaluate.metrics import metrics_command, metrics_table
from capframe.evaluate.quantitative import quantitative_table
from capframe.evaluate.tables import group_table, mllm_per_scene, mllm_records, sensitivity_markdown, sensitivity_table

METHODS = ("capframe", "ivs", "svs", "splatraj", "chatcam")
TEXTS = {
    "s-000": "a close-up of the teddy bear on the right, seen from its left",
    "s-001": "the mug in the lower left third, camera slightly above",
    "s-002": "a wide shot of the toy car, centred",
    "s-003": "the teddy bear and the mug side by side, from the front",
    "s-004": "a top-down view of the toy car",
    "s-005": "the mug on the left, dutch angle",
}


class FakeJudgeChat:
    """A chat model that records every request: ratings are 1 + the picture's first pixel mod 5
    (so each method's rating is known), picks are always the first picture ("Image 1")."""

    identity = "fake-judge"

    def __init__(self):
        self.requests = []
        self.batches = []

    def complete(self, request):
        self.requests.append(request)
        if request.schema_name == "judge_rate":
            data = {"reason": "ok", "score": 1 + int(request.images[0][0, 0, 0]) % 5}
        else:
            data = {"reason": "first", "best": 1}
        return ChatReply(data=data, text=json.dumps(data), model=self.identity)

    def complete_many(self, requests):
        self.batches.append(len(requests))
        return [self.complete(r) for r in requests]


def write_renders(root: Path, methods=METHODS, ids=TEXTS, size=(24, 16)) -> dict[str, dict[str, Path]]:
    """A distinct flat picture per (method, instruction): ``root/<method>/<id>/render.png``."""
    renders = {}
    for m, method in enumerate(methods):
        for k, key in enumerate(ids):
            folder = root / method / key
            folder.mkdir(parents=True)
            pixels = np.full((size[1], size[0], 3), 10 * m + k, dtype=np.uint8)
            Image.fromarray(pixels).save(folder / "render.png")
            renders.setdefault(key, {})[method] = folder / "render.png"
    return renders


def test_judge_messages_never_name_a_method(tmp_path):
    chat = FakeJudgeChat()
    judge_scene({"judge": MLLMJudge(chat)}, TEXTS, write_renders(tmp_path), seed=0)
    assert len(chat.requests) == len(TEXTS) * (len(METHODS) + 1)
    # an instruction's ratings are asked together (a local model batches them, an endpoint runs them concurrently)
    assert chat.batches == [len(METHODS)] * len(TEXTS)
    for request in chat.requests:
        words = (request.system + "\n" + request.user).lower()
        assert not [m for m in METHODS if m in words], words
        # the pictures carry no label either: plain renders, as written
        assert all(image.shape == (16, 24, 3) for image in request.images)


def test_the_pick_shows_the_pictures_in_the_recorded_order(tmp_path):
    chat = FakeJudgeChat()
    renders = write_renders(tmp_path)
    record = judge_scene({"judge": MLLMJudge(chat)}, TEXTS, renders, seed=3)
    picks = [r for r in chat.requests if r.schema_name == "judge_pick"]
    for request, key in zip(picks, sorted(TEXTS)):
        order = record[key]["order"]
        shown = [int(image[0, 0, 0]) for image in request.images]
        expected = [int(np.asarray(Image.open(renders[key][m]))[0, 0, 0]) for m in order]
        assert shown == expected


def test_order_differs_between_instructions_and_is_reproducible(tmp_path):
    renders = write_renders(tmp_path)
    first = judge_scene({"judge": MLLMJudge(FakeJudgeChat())}, TEXTS, renders, seed=0)
    again = judge_scene({"judge": MLLMJudge(FakeJudgeChat())}, TEXTS, renders, seed=0)
    other = judge_scene({"judge": MLLMJudge(FakeJudgeChat())}, TEXTS, renders, seed=1)
    orders = [tuple(first[k]["order"]) for k in sorted(TEXTS)]
    assert len(set(orders)) > 1, "every instruction was shown the same order"
    assert all(sorted(o) == sorted(METHODS) for o in orders)
    assert orders == [tuple(again[k]["order"]) for k in sorted(TEXTS)]
    assert orders == [tuple(blind_order(list(METHODS), TEXTS[k], 0)) for k in sorted(TEXTS)]
    assert orders != [tuple(other[k]["order"]) for k in sorted(TEXTS)]


def test_a_judge_that_always_picks_the_first_picture_picks_by_the_order(tmp_path):
    """Picks map back through the recorded order: "Image 1" is a different method per
    instruction, so the win rates spread over the methods exactly as the orders' first entries."""
    record = judge_scene({"judge": MLLMJudge(FakeJudgeChat())}, TEXTS, write_renders(tmp_path), seed=0)
    firsts = [record[k]["order"][0] for k in sorted(TEXTS)]
    assert [record[k]["judges"]["judge"]["best"] for k in sorted(TEXTS)] == firsts
    assert all(record[k]["judges"]["judge"]["best_image"] == 1 for k in TEXTS)
    assert len(set(firsts)) > 1
    # ratings belong to their method: the fake rates 1 + first pixel mod 5 = 1 + (10 m + k) mod 5
    for k, key in enumerate(sorted(TEXTS)):
        ratings = record[key]["judges"]["judge"]["ratings"]
        assert ratings == {m: 1 + (10 * i + k) % 5 for i, m in enumerate(METHODS)}
    path = tmp_path / "judges.json"
    path.write_text(json.dumps({"format": 1, "scene": "s", "seed": 0, "judges": {}, "instructions": record}))
    rows = read_judgements([path])
    share = rows.groupby("method")["picked"].mean()
    for method in METHODS:
        assert share[method] == pytest.approx(firsts.count(method) / len(TEXTS))


@pytest.fixture(scope="module")
def tiny_metric_models(tmp_path_factory):
    from capframe.backends.tiny import tiny_image_text

    root = tmp_path_factory.mktemp("metric-models")
    tiny_image_text(root / "clip", "clip")
    tiny_image_text(root / "siglip", "siglip")
    config = root / "models.yaml"
    config.write_text("metrics-clip: {weights: clip, batch_size: 4}\nmetrics-siglip: {weights: siglip, batch_size: 4}\n")
    return config


def test_metrics_follow_the_stated_conventions(tmp_path, tiny_metric_models):
    """CLIP: the cosine of the normalised embeddings; SigLIP 2: sigmoid(exp(scale) cos + bias),
    each checked against the model's own towers on one render and its instruction."""
    from capframe.backends.image_text import ImageTextModel
    from capframe.backends.models import read_models_config

    ids = {"s-000": TEXTS["s-000"], "s-001": TEXTS["s-001"]}
    write_renders(tmp_path / "r", methods=("capframe", "ivs"), ids=ids, size=(40, 30))
    constraints = tmp_path / "constraints.json"
    constraints.write_text(json.dumps({k: {"text": t, "constraints": {}} for k, t in ids.items()}))
    models = read_models_config(tiny_metric_models)
    methods = [("capframe", tmp_path / "r" / "capframe"), ("ivs", tmp_path / "r" / "ivs")]
    frame = metrics_table("s", constraints, methods, models, ["clip", "siglip"])
    assert len(frame) == 4 and list(frame.columns) == ["method", "scene", "instruction", "clip", "siglip"]
    row = frame[(frame["method"] == "ivs") & (frame["instruction"] == "s-001")].iloc[0]
    image = np.asarray(Image.open(tmp_path / "r" / "ivs" / "s-001" / "render.png").convert("RGB"))
    for column, backend in (("clip", "clip"), ("siglip", "siglip")):
        model = ImageTextModel(backend, models.settings(f"metrics-{column}"))
        inputs = model.processor(images=[Image.fromarray(image)], return_tensors="pt")
        with torch.no_grad():
            a = model.model.get_image_features(pixel_values=inputs["pixel_values"]).pooler_output[0]
        b = model.embed_texts([ids["s-001"]])[0]
        cos = float(a @ b / a.norm() / b.norm())
        if column == "clip":
            expected = cos
        else:
            expected = 1 / (1 + math.exp(-(cos * math.exp(float(model.model.logit_scale)) + float(model.model.logit_bias))))
            assert 0 < row[column] < 1
        assert row[column] == pytest.approx(expected, abs=1e-5)
    assert frame["clip"].between(-1, 1).all() and frame["clip"].nunique() == 4


def test_metrics_need_their_models_and_every_render(tmp_path, tiny_metric_models):
    constraints = tmp_path / "constraints.json"
    constraints.write_text(json.dumps({"s-000": {"text": TEXTS["s-000"], "constraints": {}}}))
    other = tmp_path / "models.yaml"
    other.write_text("judge: {endpoint: http://127.0.0.1:9/v1, model: m}\n")
    with pytest.raises(InputError, match="none of the metrics' entries"):
        metrics_command("s", str(constraints), [f"capframe={tmp_path}"], str(other), str(tmp_path / "m.csv"))
    with pytest.raises(InputError, match="no render.png for instruction 's-000' of method 'capframe'"):
        metrics_command("s", str(constraints), [f"capframe={tmp_path}"], str(tiny_metric_models), str(tmp_path / "m.csv"))
    assert not (tmp_path / "m.csv").exists()


def aggregate_csv(path: Path, method: str, outcomes: dict[tuple[str, str], tuple[bool, float]]) -> Path:
    rows = [
        {"method": method, "scene": s, "instruction": i, "all_satisfied": ok, "constraints_satisfied": share}
        for (s, i), (ok, share) in outcomes.items()
    ]
    pd.DataFrame(rows).to_csv(path, index=False)
    return path


def test_table1_merges_metrics_judges_and_the_user_study(tmp_path):
    tables = [
        aggregate_csv(tmp_path / "capframe.csv", "capframe", {("a", "a-0"): (True, 1.0), ("a", "a-1"): (False, 0.5)}),
        aggregate_csv(tmp_path / "ivs.csv", "ivs", {("a", "a-0"): (False, 0.25), ("a", "a-1"): (False, 0.75)}),
        aggregate_csv(tmp_path / "oracle.csv", "oracle", {("a", "a-0"): (True, 1.0), ("a", "a-1"): (True, 1.0)}),
    ]
    metrics = tmp_path / "metrics.csv"
    pd.DataFrame(
        [
            {"method": m, "scene": "a", "instruction": i, "clip": c, "siglip": s}
            for m, i, c, s in [
                ("capframe", "a-0", 0.3, 0.6),
                ("capframe", "a-1", 0.1, 0.2),
                ("ivs", "a-0", -0.2, 0.1),
                ("ivs", "a-1", 0.0, 0.3),
                ("oracle", "a-0", 0.2, 0.5),
                ("oracle", "a-1", 0.2, 0.5),
            ]
        ]
    ).to_csv(metrics, index=False)
    verdict = {
        "a-0": {"judge": {"ratings": {"capframe": 5, "ivs": 2}, "best": "capframe"}},
        "a-1": {"judge": {"ratings": {"capframe": 3, "ivs": 4}, "best": "ivs"}},
    }
    judged = tmp_path / "judges.json"
    judged.write_text(
        json.dumps(
            {
                "format": 1,
                "scene": "a",
                "judges": {"judge": {"model": "m"}},
                "instructions": {k: {"order": ["ivs", "capframe"], "judges": v} for k, v in verdict.items()},
            }
        )
    )
    # the user-study importer's interface: method,rating_mean,rating_n,preference_share
    study = tmp_path / "userstudy.csv"
    study.write_text("method,rating_mean,rating_n,preference_share\ncapframe,4.5,66,0.75\nivs,2.5,66,0.25\n")

    frame, notes = quantitative_table(tables, [metrics], [judged], study)
    assert notes == []
    row = frame.set_index("method")
    assert row.loc["capframe", "full_success"] == 0.5 and row.loc["ivs", "constraints_satisfied"] == 0.5
    assert row.loc["capframe", "clip"] == pytest.approx(0.2) and row.loc["ivs", "siglip"] == pytest.approx(0.2)
    assert row.loc["capframe", "judge_as"] == 4.0 and row.loc["ivs", "judge_as"] == 3.0
    assert row.loc["capframe", "judge_wr"] == 0.5 and row.loc["ivs", "judge_wr"] == 0.5
    assert row.loc["capframe", "rating_mean"] == 4.5 and row.loc["ivs", "preference_share"] == 0.25
    # not judged, not in the study: empty cells, and the columns stay
    assert pd.isna(row.loc["oracle", "judge_as"]) and pd.isna(row.loc["oracle", "rating_mean"])

    bare, notes = quantitative_table(tables, [], [], None)
    assert list(bare.columns) == ["method", "instructions", "full_success", "constraints_satisfied"]
    assert any("CLIP" in n and "metrics-clip" in n for n in notes) and any("SigLIP 2" in n for n in notes)
    assert any("judge" in n for n in notes) and any("capframe userstudy import" in n for n in notes)

    study.write_text("method,rating_mean,rating_n,preference_share\nsplatraj,3.0,10,1.0\n")
    with pytest.raises(InputError, match=r"methods \['splatraj'\] are not in the table's methods"):
        quantitative_table(tables, [], [], study)
    study.write_text("method,rating,preference_share\ncapframe,3.0,1.0\n")
    with pytest.raises(InputError, match="lacks columns"):
        quantitative_table(tables, [], [], study)


def test_groups_and_sensitivity_add_the_metric_columns(tmp_path):
    tables = [
        aggregate_csv(tmp_path / "retrieve.csv", "retrieve", {("a", "a-0"): (False, 0.5), ("b", "b-0"): (False, 0.0)}),
        aggregate_csv(tmp_path / "capframe.csv", "capframe", {("a", "a-0"): (True, 1.0), ("b", "b-0"): (True, 1.0)}),
    ]
    metrics = pd.DataFrame(
        [
            {"method": "retrieve", "scene": "a", "instruction": "a-0", "siglip": 0.1},
            {"method": "retrieve", "scene": "b", "instruction": "b-0", "siglip": 0.3},
            {"method": "capframe", "scene": "a", "instruction": "a-0", "siglip": 0.4},
            {"method": "capframe", "scene": "b", "instruction": "b-0", "siglip": 0.8},
        ]
    )
    frame = group_table(tables, {"a": "lerf", "b": "dl3dv"}, metrics).set_index(["method", "group"])
    assert frame.loc[("retrieve", "lerf"), "siglip"] == pytest.approx(0.1)
    assert frame.loc[("capframe", "all"), "siglip"] == pytest.approx(0.6)
    assert "clip" not in frame.columns

    # sensitivity: ΔSigLIP 2 is the variant's score minus the reference's, averaged over the
    # instructions both have; an instruction only one of them has a score for is left out
    write_scene(tmp_path, "s1")
    for method in ("capframe", "capframe-noise"):
        for key in ("a", "b", "c"):
            write_result(tmp_path, method, "s1", key, pose(np.eye(3), [0.0, 0.0, -5.0]))
    scores = {("capframe", "a"): 0.5, ("capframe", "b"): 0.25, ("capframe-noise", "a"): 0.25}
    scores |= {("capframe-noise", "b"): 0.5, ("capframe-noise", "c"): 0.9}
    metrics = pd.DataFrame([{"method": m, "scene": "s1", "instruction": i, "siglip": v} for (m, i), v in scores.items()])
    row = sensitivity_table(
        tmp_path / "refine" / "capframe",
        [("noise", tmp_path / "refine" / "capframe-noise")],
        tmp_path / "check",
        tmp_path / "scenes",
        metrics,
    ).iloc[0]
    assert row["delta_siglip"] == pytest.approx(((0.25 - 0.5) + (0.5 - 0.25)) / 2) and "delta_clip" not in row
    markdown = sensitivity_markdown(
        sensitivity_table(
            tmp_path / "refine" / "capframe",
            [("noise", tmp_path / "refine" / "capframe-noise")],
            tmp_path / "check",
            tmp_path / "scenes",
        )
    )
    assert "ΔSigLIP 2: not measured (set `metrics-siglip` in the models config)" in markdown


def test_mllm_counters_are_summed_per_scene_and_stage(tmp_path):
    counters = {
        "mllm_calls": 4,
        "mllm_cache_hits": 1,
        "mllm_cache_misses": 3,
        "mllm_prompt_tokens": 40,
        "mllm_completion_tokens": 90,
        "mllm_model_seconds": 1.5,
    }
    for key in ("a-0", "a-1"):
        path = tmp_path / "retrieve" / "capframe" / "a" / f"{key}.timings.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"retrieve_s": 2.0, "total_s": 2.5} | counters))
    (tmp_path / "coarse" / "capframe" / "a").mkdir(parents=True)
    (tmp_path / "coarse" / "capframe" / "a" / "a-0.timings.json").write_text(json.dumps({"coarse_s": 0.1, "total_s": 0.2}))
    (tmp_path / "judges").mkdir()
    (tmp_path / "judges" / "a.json").write_text(
        json.dumps({"scene": "a", "judges": {"judge": {"mllm": counters | {"mllm_calls": 7}}}})
    )
    table = mllm_per_scene(mllm_records(tmp_path)).set_index("stage")
    assert list(table.index) == ["judge/judge", "qe/capframe"]
    assert table.loc["qe/capframe", "mllm_calls"] == 8 and table.loc["qe/capframe", "mllm_completion_tokens"] == 180
    assert table.loc["qe/capframe", "cache_hit_rate"] == pytest.approx(0.25)
    assert table.loc["judge/judge", "mllm_calls"] == 7
    (tmp_path / "judges" / "a.json").write_text(
        json.dumps({"scene": "a", "judges": {"judge": {"mllm": counters | {"mllm_calls": None}}}})
    )
    with pytest.raises(InputError, match="are not numbers"):
        mllm_records(tmp_path)


def test_judge_needs_a_judge_entry_and_a_judge_record(tmp_path):
    constraints = tmp_path / "constraints.json"
    constraints.write_text(json.dumps({"s-000": {"text": TEXTS["s-000"], "constraints": {}}}))
    models = tmp_path / "models.yaml"
    models.write_text("metrics-clip: {weights: clip}\n")
    args = (
        "s",
        str(constraints),
        [f"capframe={tmp_path}", f"ivs={tmp_path}"],
        str(models),
        str(tmp_path),
        str(tmp_path / "j.json"),
    )
    with pytest.raises(InputError, match=r"has no judge entry \(judge, judge-2\)"):
        judge_command(*args)
    assert not (tmp_path / "j.json").exists()
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": 1, "scene": "s", "instructions": {"s-000": {"judges": {"judge": {"best": "ivs"}}}}}))
    with pytest.raises(InputError, match="bad.json: not a capframe judge record: KeyError 'ratings'"):
        read_judgements([bad])
