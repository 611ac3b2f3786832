"""The MLLM roles (capframe.backends.mllm: parser, QE, judges, paraphrases) driven by a scripted
chat model: what each request carries (prompt version, schema, images, no method names), how a
valid answer becomes our structures (the same ParsedInstruction as the rule parser), and that a
meaningless answer is refused in one line naming the field."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

from capframe.backends import ROLES, BackendContext, read_models_config
from capframe.backends.mllm.chat import ChatReply, ChatRequest, validate_reply
from capframe.backends.mllm.judge import MLLMJudge, MLLMParaphraser, blind_order
from capframe.backends.mllm.parser import UNKNOWN, MLLMParser, frame_box, layout_entry, named_elevation, view_side
from capframe.backends.mllm.prompts import NAMES, load
from capframe.backends.mllm.qe import MLLMQE, adaptive_cut
from capframe.constraints import REGIONS, SHOT_SIZES
from capframe.errors import InputError, ModelError
from capframe.handoff import read_parsed, write_parsed
from capframe.retrieve.qe import rank_kept
from capframe.scene import SemanticObject
from capframe.translate.instruction import ParsedInstruction, ParsedSubject
from capframe.translate.labels import labels_from_constraints
from capframe.translate.parse import RuleParser
from capframe.translate.vocabulary import Vocabulary

SCENE = Vocabulary.from_semantics(
    [
        SemanticObject(0, "teddy bear", ["bear", "plush toy"], False),
        SemanticObject(1, "vase", ["flower vase"], True),
        SemanticObject(2, "television", ["tv"], False),
    ]
)


class ScriptedChat:
    """A :class:`~capframe.backends.mllm.ChatModel` answering prepared JSON, keyed by prompt name
    (a list is consumed in order); every request is recorded and every answer is validated against
    the request's schema, as the real models do."""

    identity = "scripted-model"

    def __init__(self, answers: dict[str, object]):
        self.answers = {k: list(v) if isinstance(v, list) else [v] for k, v in answers.items()}
        self.requests: list[ChatRequest] = []

    def complete(self, request: ChatRequest) -> ChatReply:
        self.requests.append(request)
        name = request.prompt_version.rsplit("-v", 1)[0]
        queue = self.answers[name]
        answer = queue.pop(0) if len(queue) > 1 else queue[0]
        text = json.dumps(answer)
        return ChatReply(validate_reply(text, request.schema), text, self.identity)

    def complete_many(self, requests: list[ChatRequest]) -> list[ChatReply]:
        return [self.complete(r) for r in requests]


BOX_KEYS = ("center_x", "center_y", "width", "height")


def bear_answers(box=None, azimuth=90.0, region="left", elevation=20.0, explicit=False) -> dict:
    """Answers for "A close-up of the teddy bear on the left, seen from its right, from slightly above"."""
    return {
        "subjects": {"subjects": [{"name": "teddy bear", "mention": "the teddy bear"}]},
        "layout": {"subjects": {"teddy bear": {"region": region, "shot": "close-up", "box": box}}},
        "orientation": {
            "subjects": {"teddy bear": {"symmetric": False, "azimuth_deg": azimuth, "either_side": False}},
            "elevation_deg": elevation,
            "elevation_explicit": explicit,
            "roll_deg": None,
        },
    }


BEAR = "A close-up of the teddy bear on the left, seen from its right, from slightly above."


# --- prompts -------------------------------------------------------------------------------------


def test_every_prompt_file_is_versioned_with_a_valid_schema_and_its_tables_match_the_constraints():
    import jsonschema

    for name in NAMES:
        prompt = load(name)
        assert prompt.version.startswith(f"{name}-v") and prompt.version.rsplit("-v", 1)[1].isdigit()
        jsonschema.Draft202012Validator.check_schema(prompt.schema)
    layout = load("layout").schema["$defs"]["subject"]["properties"]
    assert set(layout["region"]["enum"]) == {*REGIONS, None}
    assert set(layout["shot"]["enum"]) == {*SHOT_SIZES, None}


# --- parser --------------------------------------------------------------------------------------


def test_parser_requests_carry_version_schema_and_the_scene_names():
    chat = ScriptedChat(bear_answers())
    MLLMParser(chat).parse(BEAR, SCENE)
    versions = [r.prompt_version for r in chat.requests]
    assert versions == ["subjects-v4", "layout-v3", "orientation-v2"]
    subjects = chat.requests[0]
    assert subjects.schema["properties"]["subjects"]["items"]["properties"]["name"] == {"enum": [*SCENE.names, UNKNOWN]}
    assert "plush toy" in subjects.user and BEAR in subjects.user  # aliases shown: a synonym can be read
    assert subjects.schema["properties"]["subjects"]["maxItems"] == 3  # no more subjects than objects
    for r in chat.requests[1:]:  # one entry per parsed subject, by construction
        keyed = r.schema["properties"]["subjects"]
        assert list(keyed["properties"]) == keyed["required"] == ["teddy bear"] and keyed["additionalProperties"] is False
        assert r.images == ()
    layout = chat.requests[1].schema["properties"]["subjects"]["properties"]["teddy bear"]
    assert [b["properties"]["region"] for b in layout["anyOf"]] == [*({"const": r} for r in REGIONS), {"type": "null"}]


def test_a_canned_answer_parses_like_the_rule_parser():
    parsed = MLLMParser(ScriptedChat(bear_answers())).parse(BEAR, SCENE)
    rules = RuleParser().parse(BEAR, SCENE)
    assert parsed == rules  # equality leaves the parser's provenance out
    assert parsed.subjects[0].view == "right" and parsed.elevation == "slightly above"
    assert parsed.parser == {
        "backend": "mllm",
        "model": "scripted-model",
        "prompts": ["subjects-v4", "layout-v3", "orientation-v2"],
    }
    assert parsed.to_dict()["parser"]["prompts"][0] == "subjects-v4" and "parser" not in rules.to_dict()


def test_two_subjects_roll_explicit_elevation_and_either_side():
    text = "The vase and the television in profile, from 35 degrees above, dutch angle"
    answers = {
        "subjects": {
            "subjects": [
                {"name": "vase", "mention": "the vase"},
                {"name": "television", "mention": "the television"},
                {"name": "vase", "mention": "it"},  # named twice: one subject
            ]
        },
        "layout": {"subjects": {n: {"region": None, "shot": None, "box": None} for n in ("television", "vase")}},
        "orientation": {
            "subjects": {
                "vase": {"symmetric": True, "azimuth_deg": None, "either_side": False},
                "television": {"symmetric": False, "azimuth_deg": -90.0, "either_side": True},
            },
            "elevation_deg": 35.0,
            "elevation_explicit": True,
            "roll_deg": 15.0,
        },
    }
    parsed = MLLMParser(ScriptedChat(answers)).parse(text, SCENE)
    assert [(s.name, s.role, s.symmetric, s.view) for s in parsed.subjects] == [
        ("vase", "primary", True, None),
        ("television", "secondary", False, "side"),
    ]
    assert (parsed.elevation, parsed.elevation_deg, parsed.roll_deg) == (None, 35.0, 15.0)


def test_angle_mapping_conventions():
    # DESIGN §3: +90 is the subject's own right; the mirror is allowed only with either_side.
    assert [view_side(a) for a in (0, 90, -90, 180, -180, 45, -135, 20, 170)] == [
        "front", "right", "left", "back", "back", "front-right", "back-left", "front-slight-right", "back",
    ]  # fmt: skip
    assert [view_side(a, True) for a in (90, -90, 45, -140, 5)] == [
        "side",
        "side",
        "three-quarter",
        "back-three-quarter",
        "front",
    ]
    assert [named_elevation(e) for e in (0, 20, 40, 70, 85, -20, -40, -70)] == [
        "eye level", "slightly above", "high angle", "bird's-eye", "top-down", "slightly below", "low angle", "worm's-eye",
    ]  # fmt: skip


def test_a_synonym_the_model_reads_is_reported_and_an_unknown_subject_names_the_closest():
    answers = bear_answers()
    answers["subjects"] = {"subjects": [{"name": "teddy bear", "mention": "the plush critter"}]}
    parsed = MLLMParser(ScriptedChat(answers)).parse("a close-up of the plush critter on the left", SCENE)
    assert parsed.subjects[0].name == "teddy bear"
    assert parsed.corrected == [{"said": "plush critter", "read": "teddy bear"}]
    answers["subjects"] = {"subjects": [{"name": UNKNOWN, "mention": "the teddi baer"}]}
    with pytest.raises(InputError, match=r"subject 'the teddi baer' is not in this scene; closest: \['teddy bear'\]"):
        MLLMParser(ScriptedChat(answers)).parse("the teddi baer", SCENE)


def test_the_subject_schema_lists_exactly_the_scene_s_names_or_is_free_without_any():
    objects = ["armchair", "coffee table", "red mug", "lamp"]
    scene = Vocabulary.from_semantics([SemanticObject(i, n, [], False) for i, n in enumerate(objects)])
    chat = ScriptedChat(bear_answers() | {"subjects": {"subjects": [{"name": "lamp", "mention": "the lamp"}]}})
    with pytest.raises(ValueError, match="'lamp' is a required property"):  # the scripted layout is the bear's
        MLLMParser(chat).parse("the lamp", scene)
    name = chat.requests[0].schema["properties"]["subjects"]["items"]["properties"]["name"]
    assert name == {"enum": sorted(objects) + ["unknown"]}
    # Open vocabulary (a scene without names, grounded by name): a short free string.
    answers = {
        "subjects": {"subjects": [{"name": "Giraffe ", "mention": "the giraffe"}]},
        "layout": {"subjects": {"giraffe": {"region": None, "shot": "wide", "box": None}}},
        "orientation": {
            "subjects": {"giraffe": {"symmetric": False, "azimuth_deg": 0, "either_side": False}},
            "elevation_deg": None,
            "elevation_explicit": False,
            "roll_deg": None,
        },
    }
    chat = ScriptedChat(answers)
    parsed = MLLMParser(chat).parse("a wide shot of the giraffe from the front", Vocabulary([]))
    assert chat.requests[0].schema["properties"]["subjects"]["items"]["properties"]["name"] == {
        "type": "string",
        "minLength": 1,
        "maxLength": 40,
    }
    assert "none listed" in chat.requests[0].user
    assert [(s.name, s.shot, s.view) for s in parsed.subjects] == [("giraffe", "wide", "front")] and parsed.corrected == []


def _layout_answers(rng: np.random.Generator) -> list[dict]:
    """Layout answers at every corner of every branch's bounds, and random ones inside them."""
    out = []
    for branch in layout_entry(load("layout").schema["$defs"]["subject"])["anyOf"]:
        region = branch["properties"]["region"].get("const")
        bounds = next(b for b in branch["properties"]["box"]["anyOf"] if b.get("type") == "object")["properties"]
        ranges = [(bounds[k]["minimum"], bounds[k]["maximum"]) for k in BOX_KEYS]
        corners = [[r[(c >> k) & 1] for k, r in enumerate(ranges)] for c in range(16)]
        drawn = [[rng.uniform(*r) for r in ranges] for _ in range(8)]
        out += [{"region": region, "shot": None, "box": dict(zip(BOX_KEYS, v))} for v in corners + drawn]
    return out + [{"region": None, "shot": None, "box": None}]  # no cue at all


def test_every_layout_answer_the_schema_admits_is_a_box_the_pipeline_takes():
    """The schema alone keeps a box inside the frame, ordered and centred in its region: every
    answer it admits (its bounds' corners, random draws) parses, and the box keeps its centre."""
    chat = ScriptedChat(bear_answers())
    MLLMParser(chat).parse(BEAR, SCENE)
    schema = chat.requests[1].schema
    for entry in _layout_answers(np.random.default_rng(0)):
        answer = {"subjects": {"teddy bear": entry}}
        assert validate_reply(json.dumps(answer), schema) == answer
        subject = MLLMParser(ScriptedChat(bear_answers() | {"layout": answer})).parse(BEAR, SCENE).subjects[0]
        assert subject.region == entry["region"]
        if entry["box"] is None:
            assert subject.box is None
            continue
        x0, y0, x1, y1 = subject.box
        assert 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1
        given = entry["box"]
        assert (x0 + x1) / 2 == pytest.approx(given["center_x"], abs=1e-12)
        assert (y0 + y1) / 2 == pytest.approx(given["center_y"], abs=1e-12)
        if entry["region"] is not None:
            rx0, ry0, rx1, ry1 = REGIONS[entry["region"]]
            assert rx0 <= given["center_x"] <= rx1 and ry0 <= given["center_y"] <= ry1
    # A box past the frame's edge is shrunk about its centre; one inside is kept as it is.
    assert frame_box(0.25, 0.5, 0.25, 0.5) == (0.125, 0.25, 0.375, 0.75)
    assert frame_box(0.25, 0.75, 1.0, 1.0) == (0.0, 0.5, 0.5, 1.0)


@pytest.mark.parametrize(
    "field, answer, fault",
    [
        (
            "subjects",
            {"subjects": [{"name": "teddy", "mention": "the bear"}]},
            r"at subjects/0/name: \"teddy\" is not one of the 4 allowed values; closest: \"teddy bear\"",
        ),
        ("layout", {"subjects": {}}, r"at subjects: 'teddy bear' is a required property"),
        (
            "layout",  # centred at x = 0.75, outside its region: no branch of the schema admits it
            {"subjects": {"teddy bear": {"region": "left", "shot": None, "box": dict(zip(BOX_KEYS, (0.75, 0.3, 0.3, 0.4)))}}},
            r"at subjects/teddy bear",
        ),
        (
            "orientation",
            {"subjects": {"teddy bear": {"symmetric": False, "azimuth_deg": 200, "either_side": False}}}
            | {"elevation_deg": None, "elevation_explicit": False, "roll_deg": None},
            r"at subjects/teddy bear/azimuth_deg: 200 is greater than the maximum of 180",
        ),
    ],
)
def test_an_answer_the_pipeline_would_refuse_is_outside_the_schema(field, answer, fault):
    """What the parser must refuse is said by the schema, so the chat model's validation refuses
    it (and feeds the fault back to the model on a retry), naming the field."""
    with pytest.raises(ValueError, match=f"^the answer does not match the schema {fault}"):
        MLLMParser(ScriptedChat(bear_answers() | {field: answer})).parse(BEAR, SCENE)


def test_not_a_number_is_not_json():
    for word in ("NaN", "Infinity", "-Infinity"):
        with pytest.raises(ValueError, match=f"^the answer is not JSON \\({word} is not a JSON number\\)$"):
            validate_reply(f'{{"azimuth_deg": {word}}}', {"type": "object"})


class Unchecked(ScriptedChat):
    """A chat model that does not validate (so the roles' own meaning checks are what refuses)."""

    def complete(self, request):
        self.requests.append(request)
        data = self.answers[request.prompt_version.rsplit("-v", 1)[0]][0]
        return ChatReply(data, json.dumps(data), self.identity)


@pytest.mark.parametrize(
    "field, answer, message",
    [
        ("subjects", {"subjects": [{"name": "giraffe", "mention": "x"}]}, r"subjects\[0\]\.name 'giraffe' is not a scene object"),
        ("layout", {"subjects": {}}, r"subjects has no entry for \['teddy bear'\]"),
        ("orientation", {"subjects": {"teddy bear": {}, "vase": {}}}, r"subjects\.vase is not a parsed subject"),
    ],
)
def test_a_meaningless_answer_is_refused_even_from_a_model_that_does_not_validate(field, answer, message):
    with pytest.raises(ModelError, match=message):
        MLLMParser(Unchecked(bear_answers() | {field: answer})).parse(BEAR, SCENE)


# --- the layout box: parsed -> stage file -> pseudo labels ----------------------------------------


def test_a_box_round_trips_through_the_stage_file_and_becomes_the_labels_mask_box(tmp_path):
    box = [0.125, 0.25, 0.375, 0.75]  # centre (0.25, 0.5), size 0.25 x 0.5: exact in binary
    parsed = MLLMParser(ScriptedChat(bear_answers(box=dict(zip(BOX_KEYS, (0.25, 0.5, 0.25, 0.5)))))).parse(BEAR, SCENE)
    assert parsed.subjects[0].box == tuple(box)
    write_parsed(parsed, tmp_path / "parsed.json")
    back = read_parsed(tmp_path / "parsed.json")
    assert back == parsed and back.subjects[0].box == tuple(box) and back.parser == parsed.parser
    stored = json.loads((tmp_path / "parsed.json").read_text())["instruction"]["subjects"][0]
    assert stored["box"] == box and stored["layout"]["box"] == box

    grounded = {"teddy bear": (np.arange(3), np.zeros(3), np.array([1.0, 0.0, 0.0]))}
    up = np.array([0.0, 0.0, 1.0])
    with_box = labels_from_constraints(back.constraints(), grounded, up, {"teddy bear": back.subjects[0].box}).subjects[0]
    without = labels_from_constraints(back.constraints(), grounded, up).subjects[0]
    assert with_box.box == tuple(box) and without.box != tuple(box)
    x0, y0, x1, y1 = with_box.region  # the centroid's target lies inside the box
    assert box[0] < x0 < x1 < box[2] and box[1] < y0 < y1 < box[3]
    assert with_box.extent == without.extent  # the named shot size still sets the extent
    assert back.without("layout").subjects[0].box is None


def test_a_bad_box_in_a_stage_file_is_refused_naming_the_subject(tmp_path):
    parsed = ParsedInstruction("the bear", [ParsedSubject("the bear", "teddy bear")])
    write_parsed(parsed, tmp_path / "parsed.json")
    data = json.loads((tmp_path / "parsed.json").read_text())
    data["instruction"]["subjects"][0]["box"] = [0.5, 0.5, 0.2, 0.9]
    (tmp_path / "parsed.json").write_text(json.dumps(data))
    with pytest.raises(
        InputError, match=r"parsed.json: instruction: subject 'teddy bear' box is \[0.5, 0.5, 0.2, 0.9\]; expected"
    ):
        read_parsed(tmp_path / "parsed.json")
    data["instruction"]["subjects"][0]["box"] = [0.1, 0.1, 1.2, 0.9]
    (tmp_path / "parsed.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match=r"instruction\.subjects\[0\]\.box\[2\]"):
        read_parsed(tmp_path / "parsed.json")


# --- Question-Evaluation -------------------------------------------------------------------------


@pytest.fixture
def views_context(tmp_path):
    """A context whose scene has four training views with photographs (320 x 200, one colour each)."""
    cameras = []
    for k in range(4):
        path = tmp_path / f"view{k}.png"
        Image.fromarray(np.full((200, 320, 3), 40 * k, dtype=np.uint8)).save(path)
        cameras.append(SimpleNamespace(name=f"view{k}", image_path=str(path)))
    return BackendContext(SimpleNamespace(cameras=cameras), np.array([0.0, 0.0, 1.0]), tmp_path / "cache")


QUESTIONS = {
    "questions": [
        {"kind": "visible", "subject": "teddy bear", "text": "Is the bear in the picture?"},
        {"kind": "region", "subject": "teddy bear", "text": "Is the bear on the left?"},
        {"kind": "view", "subject": "teddy bear", "text": "Is the bear seen from its right?"},
        {"kind": "roll", "subject": None, "text": "Is the camera tilted?"},  # not asked: overall
        {"kind": "overall", "subject": None, "text": "Does the picture match?"},
    ]
}


def answers(scores: list[int]) -> dict:
    return {"answers": {str(k + 1): {"reason": f"reason {k + 1}", "score": s} for k, s in enumerate(scores)}}


def test_qe_questions_map_to_our_kinds_with_the_parsed_targets(views_context):
    parsed = RuleParser().parse(BEAR, SCENE)
    chat = ScriptedChat({"qe-questions": QUESTIONS})
    questions = MLLMQE(chat, views_context).questions(parsed)
    assert [(q.kind, q.subject, q.target) for q in questions] == [
        ("visible", "teddy bear", {"shot": "close-up"}),
        ("region", "teddy bear", {"region": "left"}),
        ("view", "teddy bear", {"view": "right"}),
        ("overall", None, {}),
        ("overall", None, {}),
    ]
    request = chat.requests[0]
    assert request.prompt_version == "qe-questions-v2" and BEAR in request.user
    assert "region left" in request.user and "elevation slightly above" in request.user


def test_qe_scores_one_request_per_view_with_all_questions_and_records_reasons(views_context):
    parsed = RuleParser().parse(BEAR, SCENE)
    per_view = [[90, 80, 70, 60, 50], [10, 10, 10, 10, 10], [100, 100, 90, 90, 95], [50, 50, 50, 50, 50]]
    chat = ScriptedChat({"qe-questions": QUESTIONS, "qe-answers": [answers(s) for s in per_view]})
    qe = MLLMQE(chat, views_context)
    retrieval = rank_kept(parsed, qe, np.zeros(4), [0, 1, 2, 3], top_k=2)
    scoring = chat.requests[1:]
    assert len(scoring) == 4 and all(r.prompt_version == "qe-answers-v3" for r in scoring)
    assert scoring[0].schema["properties"]["answers"]["required"] == ["1", "2", "3", "4", "5"]
    assert all(len(r.images) == 1 and r.images[0].shape == (100, 160, 3) for r in scoring)  # long side 160
    assert [int(r.images[0][0, 0, 0]) for r in scoring] == [0, 40, 80, 120]  # each view's own picture
    assert all("5. Does the picture match?" in r.user for r in scoring)
    np.testing.assert_array_equal(retrieval.answers, np.array(per_view, dtype=float))
    # Means 70, 10, 95, 50: above 42 are views 2, 0, 3 with drops 25, 20 -> the cut keeps view 2
    # alone; it lies outside the coarse better half (positions 0, 1) but is kept as the best.
    assert retrieval.top == [2]
    out = retrieval.to_dict([f"view{k}" for k in range(4)])
    assert out["evaluator"] == {"backend": "mllm", "model": "scripted-model", "prompts": ["qe-questions-v2", "qe-answers-v3"]}
    assert out["views"][0]["view"] == "view2" and out["views"][0]["reasons"][0] == "reason 1"


@pytest.mark.parametrize(
    "answer, message",
    [
        (answers([50, 50, 50, 50]), r"answers \['1', '2', '3', '4'\]; expected questions \['1', '2', '3', '4', '5'\]"),
        (answers([50, 50, 50, 50, 101]), r"answers\.5\.score 101 is not in \[0, 100\]"),
    ],
)
def test_qe_refuses_an_answer_that_misses_a_question_or_leaves_the_scale(views_context, answer, message):
    parsed = RuleParser().parse(BEAR, SCENE)
    qe = MLLMQE(Unchecked({"qe-questions": QUESTIONS, "qe-answers": answer}), views_context)
    with pytest.raises(ModelError, match=f"qe-answers answer \\(qe-answers-v3\\) is invalid: view view0: {message}"):
        qe.answer(qe.questions(parsed), [0])


def test_adaptive_cut_on_hand_checked_scores():
    # sorted 90 (4), 80 (0), 78 (1), 50 (2) above 42; drops 10, 2, 28: the cut after three, capped
    # at K = 2 -> positions 4 and 0; 4 is outside the coarse better half (0, 1, 2).
    assert adaptive_cut(np.array([80, 78, 50, 30, 90, 10]), 2) == [0]
    # drops 5 then 30: the largest is after two -> both kept.
    assert adaptive_cut(np.array([90, 85, 55, 10, 5, 0]), 2) == [0, 1]
    # drops 30 then 5: cut after one.
    assert adaptive_cut(np.array([90, 60, 55, 10, 5, 0]), 2) == [0]
    # none or one above the threshold: the best alone (also outside the better half).
    assert adaptive_cut(np.array([10, 20, 30, 40]), 2) == [3]
    assert adaptive_cut(np.array([10, 20, 30, 95]), 2) == [3]
    # ties keep the coarse order.
    assert adaptive_cut(np.array([70, 70, 70, 10, 0, 0]), 2) == [0]


# --- judges and paraphrases ----------------------------------------------------------------------


def test_judge_rates_one_image_with_version_and_schema():
    chat = ScriptedChat({"judge-rate": {"reason": "bear on the left", "score": 4}})
    image = np.zeros((8, 8, 3), dtype=np.uint8)
    judge = MLLMJudge(chat)
    assert judge.rate(image, BEAR) == 4.0
    rating = judge.assess(image, BEAR)
    assert (rating.model, rating.prompt) == ("scripted-model", "judge-rate-v1")
    request = chat.requests[0]
    assert request.prompt_version == "judge-rate-v1" and request.schema["properties"]["score"] == {
        "type": "integer",
        "minimum": 1,
        "maximum": 5,
    }
    assert len(request.images) == 1 and BEAR in request.user


def test_judge_pick_is_blind_seeded_and_recorded():
    methods = {"capframe": 0, "ivs": 1, "svs": 2, "splatraj": 3}
    images = {m: np.full((4, 4, 3), k, dtype=np.uint8) for m, k in methods.items()}
    chat = ScriptedChat({"judge-pick": {"reason": "the second fits", "best": 2}})
    judge = MLLMJudge(chat)
    pick = judge.pick(images, BEAR, seed=7)
    request = chat.requests[0]
    text = (request.system + request.user).lower()
    assert not any(m in text for m in methods)  # method names never reach the judge
    assert [int(im[0, 0, 0]) for im in request.images] == [methods[m] for m in pick.order]  # shown in the recorded order
    assert pick.best == pick.order[1] and pick.seed == 7 and pick.prompt == "judge-pick-v1"
    assert request.schema["properties"]["best"]["maximum"] == 4 and "Image 4" in request.system
    assert judge.pick(images, BEAR, seed=7).order == pick.order  # the same seed, the same order
    orders = {tuple(blind_order(list(methods), f"instruction {k}", 7)) for k in range(20)}
    assert len(orders) > 5  # the order varies with the instruction
    with pytest.raises(InputError, match="at least two pictures"):
        judge.pick({"capframe": images["capframe"]}, BEAR, seed=0)


def test_paraphrases_are_distinct_and_unlike_the_instruction():
    good = {
        "paraphrases": [
            "Close up on the bear at left, viewed from its right, a little from above.",
            "Frame the bear tight on the left.",
        ]
    }
    chat = ScriptedChat({"paraphrase": good})
    assert MLLMParaphraser(chat).paraphrase(BEAR, 2) == good["paraphrases"]
    assert chat.requests[0].schema["properties"]["paraphrases"]["minItems"] == 2 and "2 different ways" in chat.requests[0].system
    same = {"paraphrases": [BEAR.upper(), "Frame the bear tight on the left."]}
    with pytest.raises(ModelError, match=r"paraphrase answer \(paraphrase-v1\) is invalid: expected 2 distinct"):
        MLLMParaphraser(ScriptedChat({"paraphrase": same})).paraphrase(BEAR, 2)


# --- registry ------------------------------------------------------------------------------------


def test_registry_builds_the_mllm_backends_on_one_chat_model_per_models_config_entry(tmp_path):
    models = tmp_path / "models.yaml"
    server = "{endpoint: 'http://127.0.0.1:9/v1', model: m%s}"
    models.write_text("\n".join(f"{entry}: {server % k}" for k, entry in enumerate(("mllm", "judge", "judge-2"))))
    scene = SimpleNamespace(cameras=[])
    context = BackendContext(scene, np.array([0.0, 0.0, 1.0]), tmp_path / "cache", read_models_config(models))
    assert list(ROLES["judge"].backends) == ["mllm", "mllm-2"]
    parser = ROLES["parser"].backends["mllm"](context)
    qe = ROLES["qe"].backends["mllm"](context)
    judges = [ROLES["judge"].backends[n](context) for n in ("mllm", "mllm-2")]
    assert parser.chat is qe.chat  # one model (and one cache's counters) per entry and job
    assert [c.identity for c in (parser.chat, *(j.chat for j in judges))] == [
        "http://127.0.0.1:9/v1 m0",
        "http://127.0.0.1:9/v1 m1",
        "http://127.0.0.1:9/v1 m2",
    ]
    assert context.shared_with("mllm-chat:") == [parser.chat, judges[0].chat, judges[1].chat]


def test_a_rerun_answers_every_role_request_from_the_response_cache(views_context, tmp_path):
    """The parser and QE through mllm-client's response cache: a second job asks the model nothing,
    and the stages' progress line says so."""
    from capframe.backends.mllm.cache import CachedChat
    from capframe.pipeline.stages import StageClock, model_calls

    parsed = RuleParser().parse(BEAR, SCENE)
    script = bear_answers() | {"qe-questions": QUESTIONS, "qe-answers": answers([60, 70, 80, 90, 100])}
    for run in range(2):
        context = BackendContext(views_context.scene, views_context.up, tmp_path / "cache")
        inner = ScriptedChat(script)
        chat = context.shared("mllm-chat:mllm", lambda inner=inner: CachedChat(inner, tmp_path / "cache" / "mllm"))
        MLLMParser(chat).parse(BEAR, SCENE)
        qe = MLLMQE(chat, context)
        qe.answer(qe.questions(parsed), [0, 1, 2, 3])
        clock = StageClock(enabled=False)
        line = model_calls(SimpleNamespace(backends=SimpleNamespace(context=context)), clock)
        timings = clock.total()  # result.json's timings carry the counters
        if run == 0:
            assert len(inner.requests) == 8 and line.startswith("; mllm: 8 requests, 0 from the cache, 8 asked")
            assert (timings["mllm_calls"], timings["mllm_cache_hits"], timings["mllm_cache_misses"]) == (8, 0, 8)
        else:
            assert inner.requests == [] and line.startswith("; mllm: 8 requests, 8 from the cache, 0 asked")
            assert (timings["mllm_cache_hits"], timings["mllm_cache_misses"], timings["mllm_model_seconds"]) == (8, 0, 0)


def test_a_model_s_overall_only_questions_are_scored_geometrically_by_the_oracle_s_own():
    """The baselines rank candidates with the oracle scorer on Retrieve's questions: when a
    model's questions are all ``overall`` (no geometric answer), it asks its own instead of
    averaging nothing (which was NaN)."""
    from capframe.backends.oracle import OracleScorer
    from capframe.backends.protocols import Question
    from capframe.retrieve.qe import GeometricQE, questions_for

    parsed = RuleParser().parse(BEAR, SCENE)
    oracle = OracleScorer.__new__(OracleScorer)  # its label renders are not needed to pick the questions
    oracle.labels, oracle.long_side = SimpleNamespace(scene=None), 160
    labels = SimpleNamespace(up=np.array([0.0, 0.0, 1.0]), subjects=[])
    overall = [Question("overall", "Does it match?"), Question("overall", "Is it nice?")]
    assert oracle.scorer(parsed, overall, labels).questions == questions_for(parsed)
    mixed = [Question("visible", "Is the bear there?", "teddy bear", {"shot": "close-up"}), overall[0]]
    assert oracle.scorer(parsed, mixed, labels).questions == mixed
    with pytest.raises(InputError, match="overall questions alone have no geometric answer"):
        GeometricQE(None, {}, labels.up).answer(overall, [0])
