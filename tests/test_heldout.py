"""The held-out sets (config/suites/heldout.yaml + heldout/<scene>.yaml; heldout2, written after
the first had been used for tuning; heldout3, after the second had; heldout4, written before the
parser changes tuned on heldout3 landed; heldout5, before the changes tuned on heldout4 landed;
heldout6, before the changes tuned on heldout5 landed; heldout7, the blind one, before the
changes tuned on heldout6 landed; heldout8, blind too, before the changes tuned on heldout7 landed;
heldout9, blind too, before the changes tuned on heldout7 and heldout8 landed; heldout10, blind too,
before the changes tuned on heldout8 and heldout9 landed; heldout11, blind too, before the changes
tuned on heldout10 landed; heldout12, blind too, written before the changes tuned on heldout11 landed;
heldout13, blind too, written before the changes tuned on heldout11 landed, a development set since heldout16 was written;
heldout14, blind too, written before the changes tuned on heldout12 land, and heldout15, blind
too, written after heldout14 before the changes tuned on heldout12 land, both development sets
since heldout17 and phrasing4 were written; heldout16, blind too, written after heldout15 before
the changes tuned on heldout13 land, a development set since 2026-11-28; heldout17, blind too, written after
heldout16 before the changes tuned on heldout14 and heldout15 land, a development set since the third
session of 2026-11-28; heldout18,
blind too, written after heldout17 on 2026-11-28, a development set since that day's fourth session; heldout19, blind too,
written after heldout18 on 2026-11-28 (third session), a development set since that day's fifth session;
heldout20, blind too, written after heldout19 on 2026-11-28 (fifth session), a development set since that day's sixth;
heldout21, blind too, written after heldout20 on 2026-11-28 (sixth session), read by its writer only; the
parse-only corpus phrasing1, written blind before any
parser ran on it, a development corpus since heldout16 and phrasing3 were written; the parse-only
development corpus phrasing2, written blind to the method; the parse-only corpus phrasing3,
written blind to the method before any parser ran on it, a development corpus since 2026-11-28; and the parse-only
corpus phrasing4, blind too, written blind to the method before any parser ran on it, a development corpus
since the third session of 2026-11-28; and the parse-only corpora phrasing5, phrasing6, phrasing7 and phrasing8, development
phrase banks written blind to the method, saying view sides (phrasing5), elevation, shot size, frame
region and roll (phrasing6), how the subjects are named and told apart (phrasing7) and whole requests of
several clauses (a view, a height, a shot size, a place in the frame, a roll, a second subject;
phrasing8) in as many ways as people write them; the parse-only corpus phrasing9, blind too, written blind
to the method before any parser ran on it on 2026-11-28 (third session), a development corpus since that
day's fifth session; and the
parse-only corpus phrasing10, blind too, written blind to the method before any parser ran on it on
2026-11-28 (fourth session), a development corpus since that day's sixth session; and the parse-only corpus phrasing11, blind too,
written blind to the method before any parser ran on it on 2026-11-28 (fifth session), read by its
writer only):
their files are valid and
shaped as issue #15 asks, without generating a scene or running the method; the spec format's
errors are one line naming file, instruction and field; the judge's range rows and the clearance
verdicts on a tiny scene."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import torch
from _synth_helpers import aim_camera, build_scene, obj

from capframe.bench import resolve_suite
from capframe.evaluate import GroundTruthChecker
from capframe.evaluate.ground_truth import read_ground_truth
from capframe.evaluate.spec import KINDS, arc_deviation, clearance, judge, parse_spec, support_level
from capframe.synth.heldout import has_committed_instructions, load_heldout
from capframe.synth.suite import load_suite

SUITES = Path(__file__).resolve().parents[1] / "config" / "suites"


# name -> instructions per scene (the files' counts, so a dropped or added instruction is noticed)
COMMITTED = {
    "heldout": [15, 15, 14, 15, 14, 14],
    "heldout2": [15, 14, 15, 14, 14, 15],
    "heldout3": [14, 14, 14, 15, 14, 14],
    "heldout4": [15, 14, 15, 14, 14, 15],
    "heldout5": [15, 14, 15, 14, 15, 14],
    "heldout6": [15, 14, 15, 14, 15, 14],
    "heldout7": [15, 14, 15, 14, 15, 14],
    "heldout8": [15, 14, 15, 14, 15, 15],
    "heldout9": [15, 14, 15, 14, 15, 15],
    "heldout10": [15, 14, 15, 14, 15, 15],
    "heldout11": [15, 14, 15, 14, 15, 15],
    "heldout12": [15, 14, 15, 14, 15, 15],
    "heldout13": [15, 14, 15, 14, 15, 15],
    "heldout14": [15, 14, 15, 14, 15, 15],
    "heldout15": [15, 14, 15, 14, 15, 15],
    "heldout16": [15, 14, 15, 14, 15, 15],
    "heldout17": [15, 14, 15, 14, 15, 15],
    "heldout18": [15, 14, 15, 14, 15, 15],
    "heldout19": [15, 14, 15, 14, 15, 15],
    "heldout20": [15, 14, 15, 14, 15, 15],
    "heldout21": [15, 14, 15, 14, 15, 15],
}
# parse-only corpora (``bench ground --parse-only``): name -> instructions per scene. Their scenes are
# never generated and their feasibility was not searched (a flag says only: an unknown subject or
# conflicting clauses), so nothing here generates them; the rest is checked as for the held-out sets.
# phrasing3, phrasing4, phrasing5 ... phrasing8 (development phrase banks), phrasing9 (written blind to
# the method on 2026-11-28, third session; a development corpus since that day's fifth), phrasing10
# (written blind to the method on 2026-11-28, fourth session; a development corpus since that day's
# sixth) and phrasing11 (blind, written blind
# to the method on 2026-11-28, fifth session), 200 instructions each, are
# validated like the others; being parse-only they are never generated, so what needs a generated
# scene (ground truth, clearance) is skipped for them too.
PARSE_ONLY = {
    "phrasing1": [25] * 8,
    "phrasing2": [25] * 8,
    "phrasing3": [25] * 8,
    "phrasing4": [25] * 8,
    "phrasing5": [25] * 8,
    "phrasing6": [25] * 8,
    "phrasing7": [25] * 8,
    "phrasing8": [25] * 8,
    "phrasing9": [25] * 8,
    "phrasing10": [25] * 8,
    "phrasing11": [25] * 8,
}
# sets asked for object mixes that no earlier set's scenes has
NEW_MIXES = tuple(name for name in COMMITTED if name not in ("heldout", "heldout2"))


@pytest.mark.parametrize("name", sorted(COMMITTED))
def test_the_committed_set_is_valid_and_shaped_as_asked(name):
    suite = load_heldout(SUITES / f"{name}.yaml")  # validates every spec and subject
    cases = suite.cases()
    assert [len(suite.specs[s.id]) for s in suite.scenes] == COMMITTED[name]
    assert suite.name == name and len(suite.scenes) >= 6 and len(cases) >= 80
    assert all(len(suite.specs[s.id]) >= 10 for s in suite.scenes)
    assert {s.preset for s in suite.scenes} == {"tabletop", "room", "outdoor"}
    assert {s.capture for s in suite.scenes} == {"orbit", "forward", "walkthrough"}
    assert any(not s.poses for s in suite.scenes) and any(s.tilt != 0 for s in suite.scenes)
    others = [s for other in ("default", "full", *COMMITTED) if other != name for s in load_suite(SUITES / f"{other}.yaml")[1]]
    assert not {s.seed for s in suite.scenes} & {s.seed for s in others}, "held-out scenes must be freshly seeded"
    infeasible = [spec for _, spec in cases if not spec.feasible]
    assert 0.05 <= len(infeasible) / len(cases) <= 0.2
    assert {"phrasing", "view", "height", "size"} <= {spec.kind for _, spec in cases} <= set(KINDS)
    assert len({spec.text.lower() for _, spec in cases}) == len(cases), "every text is different"
    assert has_committed_instructions(SUITES / f"{name}.yaml") and not has_committed_instructions(SUITES / "default.yaml")


@pytest.mark.parametrize("name", sorted(PARSE_ONLY))
def test_the_parse_only_corpus_is_valid_and_shaped_as_asked(name):
    """Loadable (every spec and subject validated), the counts per scene, every preset and capture,
    seeds no other suite uses, 5-20 % infeasible (unknown subjects, conflicting clauses), every text
    different within the corpus and from every text of the held-out sets and of the other parse-only
    corpora. Generation-free: the scenes are valid suite scenes but a parse-only corpus is never
    generated, so no scene or ground truth is checked (what needs generation is skipped here)."""
    suite = load_heldout(SUITES / f"{name}.yaml")
    cases = suite.cases()
    assert suite.name == name and [len(suite.specs[s.id]) for s in suite.scenes] == PARSE_ONLY[name]
    assert {s.preset for s in suite.scenes} == {"tabletop", "room", "outdoor"}
    assert {s.capture for s in suite.scenes} == {"orbit", "forward", "walkthrough"}
    assert all(4 <= len(s.objects) <= 5 for s in suite.scenes)
    seeds = [s.seed for s in suite.scenes]
    others = [
        s
        for other in ("default", "full", *COMMITTED, *PARSE_ONLY)
        if other != name
        for s in load_suite(SUITES / f"{other}.yaml")[1]
    ]
    assert len(set(seeds)) == len(seeds) and not set(seeds) & {s.seed for s in others}, "freshly seeded scenes"
    infeasible = [spec for _, spec in cases if not spec.feasible]
    assert 0.05 <= len(infeasible) / len(cases) <= 0.2
    assert {spec.reason for spec in infeasible} <= {"unknown subject", "no free space"}
    assert {"phrasing", "view", "height", "size", "framing", "roll", "subject"} <= {spec.kind for _, spec in cases} <= set(KINDS)
    texts = {spec.text.lower() for _, spec in cases}
    assert len(texts) == len(cases), "every text is different"
    for other in (*COMMITTED, *PARSE_ONLY):
        if other != name:
            assert not texts & {spec.text.lower() for _, spec in load_heldout(SUITES / f"{other}.yaml").cases()}, other
    assert has_committed_instructions(SUITES / f"{name}.yaml")
    assert resolve_suite(name) == SUITES / f"{name}.yaml", "`bench ground --suite NAME --parse-only` resolves it"


ORDER = list(COMMITTED)  # written order (sorted names would put heldout10 before heldout2)


@pytest.mark.parametrize("earlier, later", [(a, b) for i, a in enumerate(ORDER) for b in ORDER[i + 1 :]])
def test_a_later_set_reuses_no_text_and_no_object_mix_of_an_earlier_one(earlier, later):
    first, second = load_heldout(SUITES / f"{earlier}.yaml"), load_heldout(SUITES / f"{later}.yaml")
    assert not {spec.text.lower() for _, spec in first.cases()} & {spec.text.lower() for _, spec in second.cases()}
    if later in NEW_MIXES:
        assert not {frozenset(s.objects) for s in first.scenes} & {frozenset(s.objects) for s in second.scenes}


def _write(tmp_path, instructions: str, count: int = 1) -> Path:
    suite = tmp_path / "s.yaml"
    suite.write_text(
        "suite: s\nspecs: s\nscenes:\n"
        "  - {id: a, group: g, seed: 1, preset: room, capture: orbit, objects: [sofa, vase],\n"
        f"     views: 3, scale: 1, tilt: 0, poses: true, resolution: 64x48, density: 1, instructions: {count}}}\n"
    )
    (tmp_path / "s").mkdir(exist_ok=True)
    (tmp_path / "s" / "a.yaml").write_text("scene: a\ninstructions:\n" + instructions)
    return suite


GOOD = "  - {id: a1, text: the sofa from behind, kind: view, feasible: true, subjects: [{name: sofa, view: back}]}\n"


@pytest.mark.parametrize(
    "instructions, count, message",
    [
        (GOOD.replace("view: back", "view: behind"), 1, r"a\.yaml: instruction 0 \('a1'\) subject 'sofa': 'view' is 'behind'"),
        (GOOD.replace("name: sofa", "name: armchair"), 1, r"a\.yaml: instruction 'a1': subject 'armchair' is not an object"),
        (GOOD.replace("name: sofa", "name: vase"), 1, r"subject 'vase' is symmetric"),
        (GOOD, 2, r"a\.yaml: holds 1 instructions; the suite's 'instructions' says 2"),
        (GOOD + GOOD, 2, r"instruction id 'a1' is used twice"),
        (GOOD.replace("feasible: true", "feasible: false"), 1, r"'reason' is None; an infeasible instruction needs one"),
        (GOOD.replace("kind: view", "kind: mood"), 1, r"'kind' is 'mood'; expected one of"),
        (GOOD.replace("view: back", "azimuth: [195, 165]"), 1, r"'azimuth' is \[195, 165\]; expected lo < hi"),
        (GOOD.replace("subjects:", "elevation: high angle, elevation_deg: 40, subjects:"), 1, r"give at most one of"),
        (GOOD.replace("text: the sofa from behind, ", ""), 1, r"instruction 0 \('a1'\): missing keys \['text'\]"),
        (
            GOOD.replace("feasible: true", "feasible: false, reason: unknown subject, absent: [sofa]"),
            1,
            r"'absent' name 'sofa' is an object of scene 'a'",
        ),
    ],
)
def test_spec_errors_name_the_file_the_instruction_and_the_field(tmp_path, instructions, count, message):
    from capframe.errors import InputError

    with pytest.raises(InputError, match=message) as err:
        load_heldout(_write(tmp_path, instructions, count))
    assert "\n" not in str(err.value)


def test_a_valid_spec_file_loads(tmp_path):
    suite = load_heldout(_write(tmp_path, GOOD))
    ((scene, spec),) = suite.cases()
    assert scene.id == "a" and spec.subject_names == ["sofa"] and spec.constraints.subjects[0].role == "primary"


def test_a_parse_only_corpus_is_refused_by_the_ground_bench(tmp_path, capsys, monkeypatch):
    """``parse_only: true`` loads as the flag; any other value is a one-line error; ``bench
    ground`` refuses such a corpus without ``--parse-only`` (its flags of feasibility were never
    searched, so a ground figure on it would not be a success rate), before generating anything."""
    from capframe.cli import main
    from capframe.errors import InputError

    suite = _write(tmp_path, GOOD)
    assert not load_heldout(suite).parse_only
    suite.write_text(suite.read_text().replace("specs: s\n", "specs: s\nparse_only: true\n"))
    assert load_heldout(suite).parse_only
    assert all(load_heldout(SUITES / f"{name}.yaml").parse_only for name in PARSE_ONLY)
    assert not any(load_heldout(SUITES / f"{name}.yaml").parse_only for name in COMMITTED)
    monkeypatch.chdir(tmp_path)  # where the bench would write results/bench/s
    assert main(["bench", "ground", "--suite", str(suite)]) == 2
    err = capsys.readouterr().err.strip()
    assert "suite 's' is a parse-only corpus" in err and "--parse-only" in err and "\n" not in err
    assert not (tmp_path / "results").exists()
    suite.write_text(suite.read_text().replace("parse_only: true", "parse_only: maybe"))
    with pytest.raises(InputError, match=r"s\.yaml: 'parse_only' is 'maybe'; expected true or false"):
        load_heldout(suite)


def test_arc_deviation_wraps_around():
    assert arc_deviation(180.0, 165.0, 195.0) == 0.0
    assert arc_deviation(-170.0, 165.0, 195.0) == 0.0  # -170 is 190
    assert arc_deviation(150.0, 165.0, 195.0) == pytest.approx(15.0)
    assert arc_deviation(-150.0, 165.0, 195.0) == pytest.approx(15.0)
    assert arc_deviation(0.0, -40.0, -10.0) == pytest.approx(10.0)
    assert arc_deviation(-60.0, -40.0, -10.0) == pytest.approx(20.0)


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    root = tmp_path_factory.mktemp("scene")
    gt = build_scene(root)
    return root, gt, GroundTruthChecker(root, long_side=96)


def test_judge_adds_azimuth_and_elevation_range_rows(world):
    root, gt, checker = world
    entry = {
        "id": "x",
        "text": "directly behind the bear, a little below",
        "kind": "view",
        "feasible": True,
        "subjects": [{"name": "teddy bear", "azimuth": [165, 195]}],
        "elevation_range": [-30, -8],
    }
    spec = parse_spec(entry, "tiny", "t.yaml", 0)
    behind = judge(checker, aim_camera(gt, obj(gt, "teddy bear"), azimuth=-172.0, elevation=-15.0, distance=5.0), spec)
    assert behind.row("azimuth").satisfied and behind.row("elevation").satisfied
    assert behind.row("azimuth").measured == pytest.approx(-172.0, abs=0.5) and behind.instruction_id == "x"
    aside = judge(checker, aim_camera(gt, obj(gt, "teddy bear"), azimuth=140.0, elevation=5.0, distance=5.0), spec)
    assert not aside.row("azimuth").satisfied and aside.row("azimuth").error == pytest.approx(25.0, abs=0.5)
    assert not aside.row("elevation").satisfied and aside.row("elevation").error == pytest.approx(13.0, abs=0.5)
    assert not aside.all_satisfied


def test_judge_of_a_subject_the_scene_lacks_fails_without_raising(world):
    # An unknown subject named alone: the spec has no known subject, so no camera satisfies it,
    # and the bench must go on (it once stopped a whole run).
    _, gt, checker = world
    entry = {"id": "u", "text": "the lantern, close", "kind": "subject", "feasible": False, "reason": "unknown subject"}
    spec = parse_spec(entry | {"subjects": [], "absent": ["lantern"]}, "tiny", "t.yaml", 0)
    report = judge(checker, aim_camera(gt, obj(gt, "teddy bear"), azimuth=0.0, elevation=10.0, distance=5.0), spec)
    assert not report.all_satisfied
    assert [(r.constraint, r.satisfied, r.target) for r in report.rows] == [("subject", False, {"absent": ["lantern"]})]


def test_clearance_below_the_support(world):
    root, gt, _ = world
    truth = read_ground_truth(root)
    bear = obj(gt, "teddy bear")
    up = np.asarray(gt["up"])
    level = support_level(truth)
    assert level == pytest.approx(min(np.dot(o["center"], up) - o["radius"] for o in gt["objects"]))
    above = np.asarray(bear["center"]) + 3 * bear["radius"] * up
    below = np.asarray(bear["center"]) - 3 * bear["radius"] * up
    assert clearance(truth, [], above) == [] and clearance(truth, [], below) == ["below the support"]
    assert math.isfinite(level)


def _spec(**entry):
    base = {"id": "x", "text": "t", "kind": "view", "feasible": True, "subjects": [{"name": "teddy bear"}]}
    return parse_spec(base | entry, "tiny", "t.yaml", 0)


def test_bench_reads_refusals_and_parse_differences():
    from capframe.bench.heldout import parse_differences, refusal_reason

    assert refusal_reason("subject 'cat' is not in this scene; known: ['mug']") == "refused: unknown subject"
    assert refusal_reason("conflicting view sides 'left' and 'three-quarter'") == "refused: parse"
    spec = _spec(subjects=[{"name": "teddy bear", "azimuth": [-40, -10], "shot": "close-up"}], elevation="bird's-eye")
    parsed = {
        "subjects": [{"name": "teddy bear", "view": "left", "shot": "close-up"}],
        "elevation": "high angle",
        "elevation_range_deg": [25.0, 60.0],
    }
    assert parse_differences(parsed, spec) == ["elevation", "view"]  # -90 is not in [-40, -10]; 42.5 not in [60, 90]
    parsed = {"subjects": [{"name": "teddy bear", "view": "front-left", "shot": "close-up"}], "elevation_range_deg": [60, 90]}
    assert parse_differences(parsed, spec) == ["view"]  # no named side lies in [-40, -10]
    spec = _spec(subjects=[{"name": "teddy bear", "azimuth": [-60, -30], "shot": "close-up"}], elevation="bird's-eye")
    assert parse_differences(parsed, spec) == []
    assert parse_differences({"subjects": [{"name": "mug"}]}, _spec(roll_deg=0)) == ["roll", "subjects"]
    # Either side (-90 or +90) is not "its right side" ([75, 105]); the right side is.
    right = _spec(subjects=[{"name": "teddy bear", "azimuth": [75, 105]}])
    assert parse_differences({"subjects": [{"name": "teddy bear", "view": "side"}]}, right) == ["view"]
    assert parse_differences({"subjects": [{"name": "teddy bear", "view": "right"}]}, right) == []
    # A narrower reading of the asked side is read right ("dead on" for "from the front"), a wider one not.
    plain, exact = (
        _spec(subjects=[{"name": "teddy bear", "view": "front"}]),
        _spec(subjects=[{"name": "teddy bear", "view": "front-exact"}]),
    )
    assert parse_differences({"subjects": [{"name": "teddy bear", "view": "front-exact"}]}, plain) == []
    assert parse_differences({"subjects": [{"name": "teddy bear", "view": "front"}]}, exact) == ["view"]
    assert parse_differences({"subjects": [{"name": "teddy bear", "view": "front-slight-left"}]}, plain) == ["view"]


def test_bench_keeps_going_past_a_failing_method_or_judge(monkeypatch, tmp_path):
    # A refusal, a bug in the method and a bug in the judge each become an outcome of their own;
    # none stops the benchmark (one judge error once lost a whole run).
    from capframe.bench import heldout as bench

    spec = _spec()
    results = iter(
        [("refused", "subject 'cat' is not in this scene", 0.1), ("error", "ValueError: boom", 0.2), ("done", "", 0.3)]
    )
    monkeypatch.setattr(bench, "_ground_one", lambda *args: next(results))

    def broken_judge(*args):
        raise KeyError("no row")

    monkeypatch.setattr(bench, "judge_result", broken_judge)
    outcomes = [bench._run_one(tmp_path, spec, tmp_path, None, None, []) for _ in range(3)]
    assert [(o.status, o.reasons) for o in outcomes] == [
        ("refused", ["refused: unknown subject"]),
        ("error", ["error: ValueError"]),
        ("error", ["error: judge KeyError"]),
    ]
    assert not (tmp_path / "checks").exists()


def test_bench_summary_counts_success_infeasible_kinds_reasons_and_clearance():
    from capframe.bench.heldout import Outcome, format_summary, summarise

    ok = Outcome(_spec(), "ok", own_all_satisfied=True, satisfied=2, applicable=2, seconds=1.0)
    under = Outcome(
        _spec(kind="height"), "ok", own_all_satisfied=True, clearance=["below the support"], satisfied=1, applicable=1
    )
    side = Outcome(_spec(id="y"), "failed", ["clause failed: view"], own_all_satisfied=True, satisfied=1, applicable=2)
    refused = Outcome(_spec(kind="phrasing"), "refused", ["refused: parse"], "conflict", seconds=0.2)
    wall = Outcome(
        _spec(feasible=False, reason="occluded by wall"), "failed", ["clause failed: visibility"], own_all_satisfied=False
    )
    cat = Outcome(
        _spec(kind="subject", feasible=False, reason="unknown subject", absent=["cat"], subjects=[]),
        "refused",
        ["refused: unknown subject"],
    )
    f = summarise([ok, under, side, refused, wall, cat])
    assert (f["feasible"], f["full_success"], f["full_success_free_camera"], f["infeasible_reported"]) == (4, 2, 1, 2)
    assert f["per_kind"]["view"] == {"feasible": 2, "ok": 1, "infeasible": 1, "reported": 1}
    assert f["failure_reasons"] == {"clause failed: view": 1, "refused: parse": 1}
    assert f["own_report_claims_success_on_failures"] == 1 and f["satisfied_but_not_free"] == 1
    assert f["clearance"] == {"below the support": 1} and f["cameras"] == 4
    text = format_summary(f)
    assert "full success (feasible)        2/4 (50.0%)" in text and "infeasible reported            2/2 (100.0%)" in text


def test_bench_suite_option_names_a_suite_or_fails_in_one_line(capsys):
    from capframe.bench import resolve_suite
    from capframe.cli import main

    for name in (*COMMITTED, *PARSE_ONLY):  # every committed set and parse-only corpus by its name
        assert resolve_suite(name) == SUITES / f"{name}.yaml"
    assert resolve_suite("heldout") == SUITES / "heldout.yaml" and resolve_suite(None) == SUITES / "default.yaml"
    assert main(["bench", "ground", "--suite", "nosuch"]) == 2
    err = capsys.readouterr().err.strip()
    known = f"known: {sorted(p.stem for p in SUITES.glob('*.yaml'))}"
    assert {"captured", "default", "full", *COMMITTED, *PARSE_ONLY} <= {p.stem for p in SUITES.glob("*.yaml")}
    assert f"--suite 'nosuch' is neither a file nor a suite name; {known}" in err and "\n" not in err
    assert main(["bench", "refine", "--suite", "heldout"]) == 2
    assert "bench refine needs generated instructions" in capsys.readouterr().err


def test_clearance_in_a_room_walls_ceiling_and_objects():
    from capframe.evaluate.ground_truth import Box, GroundTruth, GTObject, Room

    box = Box(np.array([1.0, 0.0, 0.5]), np.eye(3), np.array([0.3, 0.3, 0.5]))
    sofa = GTObject(0, "sofa", box.center, 0.6, 0, box=box)
    # a room 4 x 4 x 2.6, turned 90 degrees about the up: its local +x is the world +y
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    truth = GroundTruth(np.array([0.0, 0.0, 1.0]), 4.0, [sofa], Room(turn, np.array([4.0, 4.0, 2.6])))
    walls = ["+x", "+y", "-y"]
    assert clearance(truth, walls, np.array([0.0, 0.0, 1.5])) == []
    assert clearance(truth, walls, np.array([0.0, 2.5, 1.5])) == ["behind the +x wall"]
    assert clearance(truth, walls, np.array([0.0, -2.5, 1.5])) == []  # the open side (-x) has no wall
    assert clearance(truth, walls, np.array([0.0, 0.0, 3.0])) == ["above the walls (a real room's ceiling)"]
    assert clearance(truth, walls, np.array([1.0, 0.0, -0.1])) == ["below the support"]
    assert clearance(truth, walls, np.array([1.1, 0.1, 0.6])) == ["inside sofa"]


def test_a_camera_beside_a_table_lower_than_its_top_is_not_below_the_support():
    """A table top 2 x 1 (turned 90 degrees about the up) at height 0.5 over a floor at -0.24
    (the generator's ``table``): under the top or the floor counts, beside the table above the
    floor does not; without the table the top is an unbounded plane, as before."""
    from capframe.evaluate.ground_truth import Box, GroundTruth, GTObject, Table
    from capframe.evaluate.spec import below_support

    turn = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # rows: the top's axes
    top = Box(np.array([0.0, 0.0, 0.48]), turn, np.array([1.0, 0.5, 0.02]))
    mug = GTObject(0, "mug", np.array([0.0, 0.0, 0.6]), 0.1, 0, box=Box(np.array([0.0, 0.0, 0.6]), np.eye(3), np.full(3, 0.1)))
    truth = GroundTruth(np.array([0.0, 0.0, 1.0]), 3.0, [mug], table=Table(top, -0.24))
    assert truth.table.top_height == pytest.approx(0.5)
    beside, under, below_floor, inside_extent = (
        np.array([0.8, 0.0, 0.3]),  # 0.3 beyond the top's half width (0.5 along the world x)
        np.array([0.0, 0.9, 0.3]),  # within its half length (1.0 along the world y)
        np.array([0.8, 0.0, -0.3]),
        np.array([0.45, -0.95, 0.49]),
    )
    assert [below_support(truth, p) for p in (beside, under, below_floor, inside_extent)] == [False, True, True, True]
    assert clearance(truth, [], beside) == [] and clearance(truth, [], under) == ["below the support"]
    plane = GroundTruth(truth.up, 3.0, [mug])
    assert clearance(plane, [], beside) == ["below the support"]


def test_the_ground_truth_table_is_validated(tmp_path):
    from capframe.errors import InputError
    from capframe.evaluate.ground_truth import parse_ground_truth

    box = {"center": [0, 0, -0.02], "axes": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "half_extents": [1, 1, 0.02]}
    data = {"up": [0, 0, 1], "objects": [{"name": "mug", "center": [0, 0, 0.1], "radius": 0.1}]}
    assert parse_ground_truth(data | {"table": {"box": box, "floor_height": -0.7}}).table.top_height == pytest.approx(0.0)
    with pytest.raises(InputError, match=r"'table' 'floor_height' is 0.5; expected a finite height below the top") as err:
        parse_ground_truth(data | {"table": {"box": box, "floor_height": 0.5}}, "gt.json")
    assert "gt.json" in str(err.value) and "\n" not in str(err.value)
    tilted = box | {"axes": [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]}
    with pytest.raises(InputError, match=r"'table' 'box' 'axes' third row is \[-1.0, 0.0, 0.0\]; expected the up"):
        parse_ground_truth(data | {"table": {"box": tilted, "floor_height": -0.7}})


def test_inside_an_object_is_inside_its_closed_surface_not_only_its_box():
    """A hollow ball (radius 1, its surface sampled every 0.05) on a stick 1 long, like a tree's
    crown on its trunk: its centre and a point halfway to its surface are enclosed; a point under
    the ball beside the stick, and a corner of the box around the ball, are inside the box but in
    open air."""
    from capframe.evaluate.ground_truth import Box, GroundTruth, GTObject
    from capframe.scene import GaussianScene
    from capframe.scene.occupancy import enclosed

    golden = math.pi * (3.0 - math.sqrt(5.0))
    k = np.arange(1600)
    z = 1.0 - 2.0 * (k + 0.5) / len(k)
    ring = np.sqrt(1.0 - z * z)
    shell = np.stack([ring * np.cos(golden * k), ring * np.sin(golden * k), z + 2.0], 1)
    stick = np.stack([np.zeros(20), np.zeros(20), np.linspace(0.0, 1.0, 20)], 1)
    means = torch.as_tensor(np.concatenate([shell, stick]), dtype=torch.float32)
    n = len(means)
    identity = torch.tensor([1.0, 0.0, 0.0, 0.0]).expand(n, 4).clone()
    tree = GaussianScene.from_activated(means, identity, torch.full((n, 3), 0.04), torch.full((n,), 0.9), torch.rand(n, 3))
    centre, halfway, under, corner = (np.array(p) for p in ([0, 0, 2.0], [0.5, 0, 2.0], [0.6, 0, 0.6], [0.9, 0.9, 2.9]))
    assert [enclosed(tree, p) for p in (centre, halfway, under, corner)] == [True, True, False, False]
    box = Box(np.array([0.0, 0.0, 1.5]), np.eye(3), np.array([1.0, 1.0, 1.5]))
    obj = GTObject(0, "tree", np.array([0.0, 0.0, 1.5]), 1.6, 0, box=box)
    truth = GroundTruth(np.array([0.0, 0.0, 1.0]), 5.0, [obj])
    inside = lambda o, p: enclosed(tree, p)  # noqa: E731
    assert clearance(truth, [], under) == ["inside tree"]  # the box alone
    assert clearance(truth, [], under, inside) == [] and clearance(truth, [], halfway, inside) == ["inside tree"]


def test_bench_counts_partly_understood_apart_from_reported_infeasible():
    from capframe.bench.heldout import Outcome, format_summary, summarise

    partly = Outcome(_spec(), "ok", own_all_satisfied=True, not_understood=["tail lights"], satisfied=1, applicable=1)
    full = Outcome(_spec(id="y"), "ok", own_all_satisfied=True, satisfied=1, applicable=1)
    wall = Outcome(
        _spec(id="z", feasible=False, reason="occluded by wall"), "failed", own_all_satisfied=True, not_understood=["glow"]
    )
    f = summarise([partly, full, wall])
    assert (f["partly_understood"], f["partly_understood_feasible"]) == (2, 1)
    # Partly understood is not a report of infeasibility: the wall case claims success.
    assert f["infeasible_reported"] == 0 and f["infeasible_claimed_satisfied"] == 1
    assert not partly.reported_infeasible and partly.success
    assert "partly understood              2 instructions (1 feasible)" in format_summary(f)


def test_blind_progress_lines_carry_no_word_of_the_instruction():
    from capframe.bench.heldout import Outcome, _line

    refused = Outcome(
        _spec(id="h9-01", text="the zebra grazing by the teddy bear", feasible=False, reason="unknown subject", absent=["zebra"]),
        "refused",
        ["refused: unknown subject"],
        "subject 'zebra grazing' is not in this scene",
    )
    partly = Outcome(_spec(id="h9-02", text="bear from its flank"), "failed", ["clause failed: view"], not_understood=["flank"])
    seen = _line(refused) + _line(partly)
    assert "zebra" in seen and "flank" in seen  # the ordinary lines quote the instruction
    blind = [_line(refused, blind=True), _line(partly, blind=True)]
    assert blind[0] == "h9-01: INF reported refused 0.0 s refused: unknown subject"
    assert blind[1] == "h9-02: FAIL failed 0.0 s clause failed: view, partly understood"
    assert not any(w in " ".join(blind) for w in ("zebra", "grazing", "flank", "bear"))


def test_blind_applies_to_held_out_ground_only():
    from capframe.bench import run_bench
    from capframe.errors import InputError

    with pytest.raises(InputError, match="--blind applies to bench ground"):
        run_bench("render", blind=True)
    with pytest.raises(InputError, match="--blind applies to bench ground"):
        run_bench("ground", suite="heldout", parse_only=True, blind=True)
    with pytest.raises(InputError, match="default.yaml has none"):
        run_bench("ground", suite="default", blind=True)


def test_parse_only_bench_keeps_the_first_held_out_sets_parses(capsys):
    """The parse-only check on committed suites: no scene generated, every feasible parse of the
    development sets (the first four held-out sets) agrees with its spec, unknown subjects are
    refused, and the parse time is reported (a figure of the bench, not asserted here: a timed
    unit test fails on a loaded machine, as this one did at load 5)."""
    from capframe.bench.parse_only import bench_parse_only, format_parse_summary

    for name in ("heldout", "heldout2", "heldout3", "heldout4"):
        f = bench_parse_only(SUITES / f"{name}.yaml")
        assert f["parse_differs_feasible"] == 0 and f["refused_feasible"] == 0, f
        assert f["unknown_subject_refused"] == f["unknown_subject"] > 0
        assert 0 < f["median_parse_ms"] < math.inf
        assert f"suite {name}: {f['instructions']} instructions parsed" in format_parse_summary(f)


def test_parse_only_is_a_ground_option(capsys):
    from capframe.cli import main

    assert main(["bench", "render", "--parse-only"]) == 2
    assert "--parse-only applies to bench ground only" in capsys.readouterr().err
    assert main(["bench", "ground", "--suite", "heldout", "--parse-only", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["suite"] == "heldout" and out["parse_differs_feasible"] == 0
