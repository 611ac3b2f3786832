"""The backend seam: one registry whose names the CLI, the config schema and the workflow agree on,
any mix of roles running end to end, and models configs checked with one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from _synth_helpers import build_scene

from capframe.backends import ROLES, BackendContext, Backends, read_models_config, resolve_choices
from capframe.cli import build_parser, main
from capframe.errors import InputError
from capframe.refine.optimize import RefineConfig
from capframe.scene import SceneMeta, load_scene_dir
from capframe.scene.directory import write_scene_meta

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("backends") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


def test_config_schema_names_exactly_the_registry_backends():
    schema = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())
    roles = schema["$defs"]["backends"]["properties"]
    assert {role: spec["enum"] for role, spec in roles.items()} == {
        role: list(r.backends) for role, r in ROLES.items() if r.backends
    }


def test_every_stage_verb_offers_every_role_with_its_registry_option():
    verbs = build_parser()._subparsers._group_actions[0].choices
    for verb in ("parse", "coarse", "qe", "segment", "associate", "orient", "translate", "retrieve", "ground", "baseline"):
        options = {s for action in verbs[verb]._actions for s in action.option_strings}
        assert {r.option for r in ROLES.values() if r.backends} <= options, verb


def test_workflow_passes_the_registry_options():
    """The workflow builds each stage's backend options from the registry (common.smk)."""
    common = (ROOT / "workflow" / "rules" / "common.smk").read_text()
    assert "from capframe.backends.registry import MASK_ASSOCIATORS, ROLES, resolve_choices" in common
    assert "ROLES[role].option" in common


def test_choices_fill_defaults_and_reject_unknown_names_with_the_available_ones():
    chosen = resolve_choices({"associator": "knn", "qe": None})
    assert chosen["associator"] == "knn" and chosen["qe"] == "oracle" and chosen["parser"] == "rules"
    assert "judge" not in chosen  # no backend yet: left out unless chosen
    with pytest.raises(InputError, match=r"--qe 'gpt' is unknown; available: oracle, mllm$"):
        resolve_choices({"qe": "gpt"})
    with pytest.raises(InputError, match="--judge 'gpt' is unknown; available: mllm, mllm-2"):
        resolve_choices({"judge": "gpt"})


def test_a_backend_is_built_once_per_job_and_shared_state_once_per_context(scene_dir, tmp_path):
    scene = load_scene_dir(scene_dir)
    context = BackendContext(scene, np.array([0.0, 0.0, 1.0]), tmp_path / "cache")
    backends = Backends({}, context)
    assert backends["qe"] is backends["qe"]
    assert backends["coarse"].labels is backends["qe"].labels  # one label render of the views


def test_mixed_roles_run_end_to_end(scene_dir, tmp_path):
    """Rules parser + oracle QE + knn associator on the oracle segmenter's masks + oracle
    orientation, through the command line."""
    out = tmp_path / "out"
    args = ["ground", str(scene_dir), "the teddy bear on the right, seen from its front", "-o", str(out)]
    args += ["--parser", "rules", "--qe", "oracle", "--segmenter", "oracle", "--associator", "knn", "--orient", "oracle"]
    args += ["--cache", str(tmp_path / "cache"), "--iterations", "150", "--json"]
    assert main(args) == 0
    result = json.loads((out / "result.json").read_text())
    assert result["options"]["backends"] == {
        "parser": "rules",
        "coarse": "oracle",
        "qe": "oracle",
        "segmenter": "oracle",
        "associator": "knn",
        "orient": "oracle",
        "scorer": "oracle",
    }
    assert "segment_s" in result["timings"] and np.isfinite(np.asarray(result["T_cw"])).all()


def test_ground_options_reject_an_unknown_backend_before_any_work(scene_dir, tmp_path, capsys):
    from capframe.pipeline import GroundOptions, ground

    with pytest.raises(InputError, match="--orient 'orient-anything-v2' is unknown; available: oracle, orient-anything$"):
        ground(
            scene_dir,
            "the teddy bear",
            tmp_path / "o",
            GroundOptions(backends={"orient": "orient-anything-v2"}, refine=RefineConfig()),
        )
    assert not (tmp_path / "o").exists()


def test_models_config_is_read_and_checked(tmp_path):
    path = tmp_path / "models.yaml"
    path.write_text("fg-clip: {weights: /models/fg-clip, device: cuda, dtype: float16, batch_size: 32}\n")
    config = read_models_config(path)
    assert config.settings("fg-clip").batch_size == 32 and config.settings("fg-clip").dtype == "float16"
    with pytest.raises(InputError, match="backend 'sam' needs an entry in the models config"):
        config.settings("sam")
    path.write_text("orient-anything: {weights: oa/w.pt, config: /abs/dinov2, onnx: oa.onnx, threads: 2, min_confidence: 0.6}\n")
    settings = read_models_config(path).settings("orient-anything")
    assert settings.weights == str(tmp_path / "oa" / "w.pt") and settings.config == "/abs/dinov2"  # relative to the file
    assert settings.onnx == str(tmp_path / "oa.onnx") and settings.threads == 2 and settings.min_confidence == 0.6
    for text, message in (
        ("fg-clip: {weights: w, threads: 0}\n", "threads 0 must be at least 1"),
        ("fg-clip: {weights: w, threads: two}\n", "threads = 'two' is not a int"),
        ("fg-clip: {weights: w, min_confidence: 1.5}\n", "min_confidence 1.5 is not in \\[0, 1\\]"),
        ("fg-clip: {weights: w, dtyp: float16}\n", "unknown keys \\['dtyp'\\]"),
        ("fg-clip: {weights: w, dtype: int8}\n", "dtype 'int8'"),
        ("fg-clip: {weights: w, batch_size: 0}\n", "must be positive"),
        ("fg-clip: {device: cuda}\n", "give weights"),
        ("fg-clip: {weights: w, batch_size: many}\n", "batch_size = 'many' is not a int"),
        ("- a list\n", "must map backend names"),
        ("fg-clip: [unclosed\n", "is not valid YAML"),
    ):
        path.write_text(text)
        with pytest.raises(InputError, match=message) as err:
            read_models_config(path)
        assert str(path) in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(InputError, match="cannot read the models config"):
        read_models_config(tmp_path / "missing.yaml")
