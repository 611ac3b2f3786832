"""Instruction generator: determinism, satisfiable constraint sets, paraphrases, files, grammar doc."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
import torch
from _synth_helpers import build_scene

from capframe.cli import main
from capframe.constraints import Constraints, SubjectConstraint
from capframe.errors import InputError
from capframe.geometry import look_at, view_direction
from capframe.synth.instructions import (
    ELEVATION_PHRASES,
    EXPLICIT_ELEVATION_PHRASES,
    KINDS,
    REGION_PHRASES,
    ROLL_PHRASES,
    VIEW_PHRASES,
    generate_instructions,
    grammar_markdown,
    incompatibility,
    write_instructions,
)
from capframe.synth.witness import look_at_np, view_direction_np

ROOT = Path(__file__).resolve().parents[1]


def ground_truth(scale: float = 1.0, offset=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0)) -> dict:
    """A hand-written ground truth: two same-named armchairs, an asymmetric bear, a symmetric vase."""
    up = np.asarray(up, dtype=np.float64) / np.linalg.norm(up)
    # A rotation taking +z to `up` (Rodrigues), so the layout is the same in every world.
    z = np.array([0.0, 0.0, 1.0])
    v, c = np.cross(z, up), float(z @ up)
    Vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    R = np.eye(3) + Vx + Vx @ Vx / (1 + c)
    place = lambda p: (R @ np.asarray(p) * scale + np.asarray(offset)).tolist()  # noqa: E731
    turn = lambda d: (R @ np.asarray(d, dtype=np.float64)).tolist()  # noqa: E731
    objects = [
        ("teddy bear", "brown", (0, 0, 0.3), 0.3, (0, -1, 0), ["bear", "plush toy"]),
        ("armchair", "red", (1.3, 0.7, 0.35), 0.35, (-1, 0, 0), ["chair"]),
        ("armchair", "blue", (-1.3, 0.8, 0.35), 0.35, (1, -0.3, 0), ["chair"]),
        ("vase", "white", (0.5, -1.1, 0.2), 0.2, None, []),
    ]
    return {
        "up": up.tolist(),
        "scale": 7.0 * scale,
        "objects": [
            {
                "id": i,
                "name": n,
                "aliases": a,
                "color": col,
                "center": place(ctr),
                "radius": r * scale,
                "front": None if f is None else turn(f),
                "label": i,
            }
            for i, (n, col, ctr, r, f, a) in enumerate(objects)
        ],
    }


def as_rows(instructions):
    return [(i.id, i.text, tuple(i.paraphrases), repr(i.constraints.to_dict()), i.kind) for i in instructions]


def test_same_seed_same_output_and_seeds_differ():
    gt = ground_truth()
    a, b = generate_instructions(gt, 10, seed=5), generate_instructions(gt, 10, seed=5)
    assert as_rows(a) == as_rows(b)
    assert as_rows(generate_instructions(gt, 10, seed=6)) != as_rows(a)
    assert [i.id for i in a] == [f"scene-{k:03d}" for k in range(10)]


def test_invariant_to_scaling_translating_and_tilting_the_world():
    reference = as_rows(generate_instructions(ground_truth(), 12, seed=2))
    moved = ground_truth(scale=250.0, offset=(1e4, -3e3, 42.0), up=(0.3, -0.2, 1.0))
    assert as_rows(generate_instructions(moved, 12, seed=2)) == reference


def test_kinds_are_mixed_and_constraint_sets_are_valid_and_satisfiable():
    gt = ground_truth()
    symmetric = {"teddy bear": False, "red armchair": False, "blue armchair": False, "vase": True}
    seen_views, seen_kinds = set(), []
    for seed in range(6):
        instructions = generate_instructions(gt, 12, seed=seed)
        assert {i.kind for i in instructions} == set(KINDS)
        assert len({repr(i.constraints.to_dict()) for i in instructions}) == 12  # no repeats within a scene
        for ins in instructions:
            c = ins.constraints
            assert Constraints.from_dict(json.loads(json.dumps(c.to_dict()))) == c
            assert incompatibility(c, symmetric) is None and ins.witness is not None
            assert c.subjects[0].role == "primary" and all(s.role == "secondary" for s in c.subjects[1:])
            assert (len(c.subjects) == 2) == (ins.kind == "two-subject")
            for s in c.subjects:
                assert s.name in symmetric  # colour-qualified names for the two armchairs
                if s.view is not None:
                    assert not symmetric[s.name], f"view side asked of symmetric {s.name}: {ins.text}"
                    seen_views.add(s.view)
            seen_kinds.append(ins.kind)
    assert len(seen_views) >= 6


def test_only_asymmetric_subjects_get_views_in_a_symmetric_scene():
    gt = ground_truth()
    for o in gt["objects"]:
        o["front"] = None
    instructions = generate_instructions(gt, 12, seed=0)
    assert all(s.view is None for i in instructions for s in i.constraints.subjects)
    assert not {"layout+view", "view+elevation"} & {i.kind for i in instructions}
    single = {"up": [0, 0, 1], "scale": 5.0, "objects": [gt["objects"][3]]}
    kinds = {i.kind for i in generate_instructions(single, 8, seed=0)}
    assert "two-subject" not in kinds and "layout+view" not in kinds


def test_paraphrases_differ_in_text_and_share_constraints():
    for ins in generate_instructions(ground_truth(), 12, seed=1):
        texts = [ins.text, *ins.paraphrases]
        assert len(ins.paraphrases) == 3 and len(set(texts)) == 4
        assert all(t[0].isupper() and t.endswith(".") and "\t" not in t and "{" not in t for t in texts)
        assert ins.paraphrase_ids() == [f"{ins.id}.p{k}" for k in (1, 2, 3)]


def _says(templates: list[str], text: str, **values: str) -> bool:
    """Whether one of the phrase templates occurs in ``text`` (placeholders match any words)."""
    for template in templates:
        pattern = re.escape(template.format(**{**{"X": "\x00", "P": "\x00", "obj": "\x00", "d": "\x00"}, **values}))
        if re.search(pattern.replace(re.escape("\x00"), ".+?"), text, flags=re.IGNORECASE):
            return True
    return False


def test_text_says_what_the_constraints_ask():
    names = {
        "teddy bear": ["teddy bear", "bear", "plush toy"],
        "vase": ["vase"],
        "red armchair": ["red armchair", "red chair"],
        "blue armchair": ["blue armchair", "blue chair"],
    }
    found_alias = False
    for ins in generate_instructions(ground_truth(), 24, seed=4):
        c = ins.constraints
        for text in [ins.text, *ins.paraphrases]:
            lower = text.lower()
            for s in c.subjects:  # by name, with colour when names repeat, or by a unique alias
                assert any(n in lower for n in names[s.name]), (s.name, text)
                assert s.region is None or _says(REGION_PHRASES[s.region], text), text
                assert s.view is None or _says(VIEW_PHRASES[s.view], text), text
            assert c.elevation is None or _says(ELEVATION_PHRASES[c.elevation], text), text
            if c.elevation_deg is not None:
                side = "above" if c.elevation_deg > 0 else "below"
                assert _says(EXPLICIT_ELEVATION_PHRASES[side], text, d=f"{abs(c.elevation_deg):g}"), text
            if c.roll_deg is not None:
                direction = "level" if c.roll_deg == 0 else "clockwise" if c.roll_deg > 0 else "counter-clockwise"
                assert _says(ROLL_PHRASES[direction], text, d=f"{abs(c.roll_deg):g}"), text  # DESIGN §3 sign
                other = {"clockwise": "counter-clockwise", "counter-clockwise": "clockwise"}.get(direction)
                assert other is None or not _says(ROLL_PHRASES[other], text, d=f"{abs(c.roll_deg):g}"), text
        found_alias |= any(a in " ".join(ins.paraphrases).lower() for a in ("the bear", "plush toy", "chair "))
        assert "plush toy" not in ins.text and " chair " not in ins.text  # originals use reference names
    assert found_alias


def test_judgement_rules():
    sym = {"bear": False, "vase": True, "box": True}

    def one(**k):
        subject = {x: k.pop(x) for x in ("region", "shot", "view") if x in k}
        return Constraints([SubjectConstraint("bear", **subject)], **k)

    assert incompatibility(one(region="upper left", shot="close-up"), sym)
    assert incompatibility(one(region="left", shot="close-up"), sym) is None
    assert incompatibility(one(elevation="bird's-eye", roll_deg=10.0), sym)
    assert incompatibility(one(elevation="bird's-eye", region="bottom"), sym)
    assert incompatibility(one(elevation="low angle", shot="wide"), sym)
    assert incompatibility(one(elevation="worm's-eye"), sym)
    assert incompatibility(Constraints([SubjectConstraint("vase", view="left")]), sym)
    two = Constraints(
        [SubjectConstraint("bear", region="left", shot="close-up"), SubjectConstraint("vase", "secondary", "right")]
    )
    assert incompatibility(two, sym)


def test_numpy_twins_match_geometry():
    rng = np.random.default_rng(0)
    for _ in range(5):
        eye, target, up = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        up /= np.linalg.norm(up)
        roll = float(rng.uniform(-1, 1))
        expected = look_at(*(torch.tensor(v) for v in (eye, target, up)), roll).numpy()
        np.testing.assert_allclose(look_at_np(eye, target, up, roll), expected, atol=1e-12)
        a, e = rng.uniform(-180, 180), rng.uniform(-89, 89)
        expected = view_direction(
            torch.tensor(np.radians(a)), torch.tensor(np.radians(e)), torch.tensor(target), torch.tensor(up)
        )
        np.testing.assert_allclose(view_direction_np(a, e, target, up), expected.numpy(), atol=1e-12)


def test_write_instructions_files(tmp_path):
    scene = tmp_path / "tabletop_1"
    build_scene(scene, per_object=20, floor=False)
    out = tmp_path / "out"
    instructions = write_instructions(scene, out, count=5, seed=3)
    with open(out / "instructions.tsv", newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t", quoting=csv.QUOTE_NONE))
    assert list(rows[0]) == ["id", "scene", "text", "paraphrase_of", "kind"] and len(rows) == 5 * 4
    originals = [r for r in rows if not r["paraphrase_of"]]
    assert [r["id"] for r in originals] == [f"tabletop_1-{k:03d}" for k in range(5)]
    assert all(r["scene"] == "tabletop_1" for r in rows)
    data = json.loads((out / "constraints.json").read_text())
    assert list(data) == [r["id"] for r in originals]
    for ins, row in zip(instructions, originals):
        entry = data[row["id"]]
        assert entry["text"] == row["text"] == ins.text and entry["scene"] == "tabletop_1" and entry["kind"] == row["kind"]
        assert Constraints.from_dict(entry["constraints"]) == ins.constraints
        paraphrase_rows = [r for r in rows if r["paraphrase_of"] == row["id"]]
        assert [r["text"] for r in paraphrase_rows] == entry["paraphrases"]
        assert [r["id"] for r in paraphrase_rows] == [f"{row['id']}.p{k}" for k in (1, 2, 3)]
    # The CLI verb writes the same files; errors are one line and exit 2.
    assert main(["instructions", str(scene), "-o", str(tmp_path / "cli"), "--count", "5", "--seed", "3"]) == 0
    assert (tmp_path / "cli" / "constraints.json").read_text() == (out / "constraints.json").read_text()
    (scene / "ground_truth.json").unlink()
    with pytest.raises(InputError, match="ground_truth.json not found"):
        write_instructions(scene, out, count=2, seed=0)


def test_bad_ground_truth_is_an_input_error():
    gt = ground_truth()
    with pytest.raises(InputError, match="count"):
        generate_instructions(gt, 0, seed=0)
    gt["objects"][2]["color"] = "red"  # two red armchairs cannot be told apart
    with pytest.raises(InputError, match="share a name and a colour"):
        generate_instructions(gt, 3, seed=0)
    with pytest.raises(InputError, match="radius"):
        generate_instructions({"up": [0, 0, 1], "objects": [{"name": "x", "center": [0, 0, 0], "radius": -1}]}, 1, 0)


def test_grammar_doc_is_in_sync():
    assert (ROOT / "docs" / "instruction-grammar.md").read_text() == grammar_markdown() + "\n"
    assert set(VIEW_PHRASES) == set(__import__("capframe.constraints", fromlist=["VIEW_SIDES"]).VIEW_SIDES)


def test_verifier_rejections_drop_constraint_sets():
    calls = []

    def reject_views(camera, constraints):
        calls.append(constraints)
        return all(s.view is None for s in constraints.subjects)

    instructions = generate_instructions(ground_truth(), 6, seed=0, verify=reject_views)
    assert calls and all(i.witness is not None for i in instructions)
    assert all(s.view is None for i in instructions for s in i.constraints.subjects)
    nothing = generate_instructions(ground_truth(), 1, seed=0, verify=lambda camera, c: False)
    assert nothing[0].witness is None and nothing[0].constraints.subjects[0].region == "center"
