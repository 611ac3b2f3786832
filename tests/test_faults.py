"""The fault suite (issue #21): what a hostile user can feed ``capframe``, one case per item.

Every refusal is exit status 2 with one line on stderr naming the file, field or value, no Python
traceback, and nothing written or lost (the working folder is compared before and after). Cases
where the right answer is to do the work (a scene path that is not UTF-8, a ``.jpg`` output)
check that it is done.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from _synth_helpers import build_scene
from PIL import Image

from capframe.cli import main
from capframe.scene import SceneMeta
from capframe.scene.directory import write_scene_meta

INSTRUCTION = "a medium shot of the teddy bear on the right of the frame, seen from its front, from slightly above"


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory) -> Path:
    """A small labelled scene (four objects, six training views of 160x120) with a world up."""
    root = tmp_path_factory.mktemp("faults") / "scene"
    gt = build_scene(root)
    write_scene_meta(SceneMeta(up=np.asarray(gt["up"]), aligned=True), root / "scene.json")
    return root


@pytest.fixture(scope="module")
def camera_json(scene_dir) -> Path:
    """A training view of the scene as a camera.json."""
    from capframe.scene import load_scene_dir, write_camera_json

    path = scene_dir.parent / "camera.json"
    write_camera_json(load_scene_dir(scene_dir, load_gaussians=False).cameras[0], path)
    return path


def snapshot(root: Path) -> dict[str, tuple[int, int]]:
    """Every file and folder under ``root``: size and modification time."""
    return {str(p.relative_to(root)): (p.stat().st_size, p.stat().st_mtime_ns) for p in root.rglob("*")}


@contextlib.contextmanager
def nothing_changes(root: Path):
    """Assert that nothing under ``root`` is written, changed or removed inside the block."""
    before = snapshot(root)
    yield
    assert snapshot(root) == before


def run(capsys, *argv) -> tuple[int, str, str]:
    """``capframe ARGV`` in this process: exit status, stdout, stderr."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exit:  # a usage error, from argparse
        code = exit.code
    out, err = capsys.readouterr()
    return code, out, err


def assert_refused(result: tuple[int, str, str], *names: str) -> str:
    """Exit status 2, no traceback, and the error as one line (after any progress lines) that
    names each of ``names``. Returns the line."""
    code, _, err = result
    lines = err.strip().splitlines()
    assert code == 2, err
    assert "Traceback" not in err
    assert lines and lines[-1].startswith("capframe") and "error:" in lines[-1], err
    assert all(line.startswith("[") for line in lines[:-1]), err  # only progress lines before it
    for name in names:
        assert name in lines[-1], (name, lines[-1])
    return lines[-1]


def unwritable_folder(tmp_path: Path) -> Path:
    """A folder this process cannot create files in (root ignores permission bits: /sys then)."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    if os.access(folder, os.W_OK):
        return Path("/sys")
    return folder


# --- one output-path check, used by every verb before any work ---------------------------------


@pytest.mark.parametrize("verb", ["render", "import", "ground"])
@pytest.mark.parametrize("case", ["is a folder", "unwritable", "under a file"])
def test_bad_output_paths_are_refused_before_any_work(scene_dir, camera_json, tmp_path, capsys, verb, case):
    work = tmp_path / "work"
    work.mkdir()
    (work / "a-file").write_text("keep me")
    (work / "a-folder").mkdir()
    (work / "a-folder" / "kept").write_text("keep me")
    output = {
        "is a folder": work / "a-folder",
        "unwritable": unwritable_folder(tmp_path) / "out",
        "under a file": work / "a-file" / "out",
    }[case]
    if verb == "render" and case != "is a folder":
        output = output.with_suffix(".png")
    argv = {
        "render": ["render", scene_dir, "--camera", camera_json, "-o", output],
        "import": ["import", scene_dir / "scene.ply", output],
        "ground": ["ground", scene_dir, INSTRUCTION, "-o", output, "--cache", work / "cache"],
    }[verb]
    expected = {"is a folder": "folder", "unwritable": "cannot write in", "under a file": "is a file, not a folder"}[case]
    with nothing_changes(work):
        assert_refused(run(capsys, *argv), str(output), expected)


def test_ground_output_that_exists_is_refused_before_the_search(scene_dir, tmp_path, capsys):
    output = tmp_path / "result"
    output.mkdir()
    (output / "result.json").write_text("{}")
    with nothing_changes(tmp_path):  # not even the per-scene cache: the search never started
        assert_refused(
            run(capsys, "ground", scene_dir, INSTRUCTION, "-o", output, "--cache", tmp_path / "cache"),
            str(output),
            "already exists",
        )


def test_every_verb_with_an_output_declares_it(capsys):
    """The output check runs for a verb only if its parser declares its outputs."""
    import argparse

    from capframe.cli import build_parser
    from capframe.scene._io import OUTPUTS

    def verbs(parser, prefix=""):
        """(name, parser) of every verb, nested ones (``models export``) included."""
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from verbs(sub, f"{prefix}{name} ")
        if prefix and not any(isinstance(a, argparse._SubParsersAction) for a in parser._actions):
            yield prefix.strip(), parser

    names = []
    for name, parser in verbs(build_parser()):
        names.append(name)
        dests = {a.dest for a in parser._actions if a.dest in ("output", "dst", "out_dir")}
        declared = parser.get_default("outputs") or {}
        assert set(declared) == dests, name
        assert set(declared.values()) <= set(OUTPUTS), name
    assert {"occupancy", "align-truth", "models export"} <= set(names)


# --- inputs that are not what they say ----------------------------------------------------------


def test_camera_that_is_a_folder_is_one_line(scene_dir, tmp_path, capsys):
    with nothing_changes(tmp_path):
        assert_refused(
            run(capsys, "render", scene_dir, "--camera", tmp_path, "-o", tmp_path / "out.png"), str(tmp_path), "folder"
        )


def test_scene_path_that_is_not_utf8_grounds_with_its_default_cache(scene_dir, tmp_path, capsys, monkeypatch):
    """The default per-scene cache is named after the scene path's bytes, not its UTF-8 encoding."""
    scene = Path(os.fsdecode(bytes(tmp_path) + b"/sc\xffene"))
    shutil.copytree(scene_dir, scene)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    code, out, err = run(capsys, "ground", scene, "the teddy bear", "-o", tmp_path / "out", "--iterations", "20")
    assert code == 0 and "Traceback" not in err, err
    assert (tmp_path / "out" / "result.json").is_file()
    (cache,) = (tmp_path / "xdg" / "capframe").iterdir()
    assert os.fsencode(cache.name).startswith(b"sc\xffene-")


# --- one memory estimate before any render ---------------------------------------------------------


def test_render_too_large_for_memory_is_refused_before_loading_the_scene(scene_dir, camera_json, tmp_path, capsys):
    huge = json.loads(camera_json.read_text())
    huge["width"], huge["height"] = 100_000, 75_000
    (tmp_path / "huge.json").write_text(json.dumps(huge))
    with nothing_changes(tmp_path):
        line = assert_refused(
            run(capsys, "render", scene_dir, "--camera", tmp_path / "huge.json", "-o", tmp_path / "x.png"),
            "huge.json",
            "100000x75000",
            "GiB",
        )
    assert "--long-side" in line


@pytest.mark.parametrize("verb", ["ground", "baseline"])
def test_training_cameras_too_large_to_render_are_refused_before_the_search(scene_dir, tmp_path, capsys, verb):
    """The result is rendered at the size of the training view it starts from: a scene whose
    cameras are 100000x100000 fails before retrieval, not after the whole search."""
    scene = tmp_path / "scene"
    shutil.copytree(scene_dir, scene)
    cameras = json.loads((scene / "cameras.json").read_text())
    for camera in cameras:
        camera["width"] = camera["height"] = 100_000
    (scene / "cameras.json").write_text(json.dumps(cameras))
    argv = [verb, *(["svs"] if verb == "baseline" else []), scene, INSTRUCTION, "-o", tmp_path / "out", "--cache", tmp_path / "c"]
    with nothing_changes(tmp_path):
        assert_refused(run(capsys, *argv), str(scene), "100000x100000")


# --- weak spots -----------------------------------------------------------------------------------


@pytest.mark.parametrize("value", ["0", "-5", "ten"])
def test_long_side_must_be_positive(scene_dir, camera_json, tmp_path, capsys, value):
    with nothing_changes(tmp_path):
        assert_refused(
            run(capsys, "render", scene_dir, "--camera", camera_json, "-o", tmp_path / "x.png", "--long-side", value),
            "--long-side",
            repr(value),
        )


def test_jpeg_output_is_a_jpeg_and_other_suffixes_are_refused(scene_dir, camera_json, tmp_path, capsys):
    code, _, err = run(capsys, "render", scene_dir, "--camera", camera_json, "-o", tmp_path / "x.jpg", "--long-side", 80)
    assert code == 0, err
    with Image.open(tmp_path / "x.jpg") as image:
        assert image.format == "JPEG" and image.size == (80, 60)
    with nothing_changes(tmp_path):
        assert_refused(run(capsys, "render", scene_dir, "--camera", camera_json, "-o", tmp_path / "x.gif"), "x.gif", ".gif")


@pytest.mark.parametrize(
    "weights, named", [("inside=1e400", "1e400"), ("inside=abc", "abc"), ("inside=-1", "-1"), ("insde=2", "insde")]
)
def test_refine_weights_must_be_known_finite_and_non_negative(scene_dir, camera_json, tmp_path, capsys, weights, named):
    labels = tmp_path / "labels.json"
    labels.write_text("{}")
    with nothing_changes(tmp_path):
        assert_refused(
            run(
                capsys, "refine", scene_dir, "--labels", labels, "--init", camera_json, "-o", tmp_path / "r", "--weights", weights
            ),
            "--weights",
            named,
        )


def test_a_10000_character_instruction_prints_short_lines(scene_dir, tmp_path, capsys):
    """Progress lines, the report and errors quote long input clipped (its start and end)."""
    from capframe.errors import CLIP_CHARS, MESSAGE_CHARS

    text = ("the teddy bear " + "very " * 2000)[:10_000]
    code, out, err = run(capsys, "ground", scene_dir, text, "-o", tmp_path / "out", "--iterations", "20")
    assert code == 0, err[-2000:]
    assert max(len(line) for line in (out + err).splitlines()) < CLIP_CHARS + 40
    nonsense = ("blorp " * 2000)[:10_000]
    with nothing_changes(tmp_path):
        line = assert_refused(run(capsys, "ground", scene_dir, nonsense, "-o", tmp_path / "out2"), "no subject in 'blorp")
    assert len(line) < MESSAGE_CHARS and "10000 characters in all" in line


def test_the_retrieve_row_of_the_methods_table_has_run_times(scene_dir, staged, tmp_path, capsys):
    """The retrieved view's result records its job's time like every method's result, so the
    methods table has no NaN median for Retrieve (it recorded none)."""
    code, _, err = run(capsys, "retrieved-view", scene_dir, "--retrieval", staged / "retrieval.json", "-o", tmp_path / "view")
    assert code == 0, err
    check = tmp_path / "check" / "scene" / "i0.json"
    check.parent.mkdir(parents=True)
    check.write_text(json.dumps({"all_satisfied": True, "satisfied": 1, "applicable": 1, "rows": []}))
    argv = ["aggregate", "--method", "retrieve", "--checks", check, "--results", tmp_path / "view" / "result.json"]
    assert run(capsys, *argv, "-o", tmp_path / "retrieve.csv")[0] == 0
    assert run(capsys, "compare", tmp_path / "retrieve.csv", "-o", tmp_path / "methods.csv")[0] == 0
    table = (tmp_path / "methods.md").read_text()
    assert "retrieve" in table and "NaN" not in table


def test_unknown_refine_weight_is_rejected_by_the_config_schema():
    """The schema's weight names are exactly the optimiser's loss terms."""
    import dataclasses
    import re

    import yaml

    from capframe.refine import LossWeights

    schema = yaml.safe_load((Path(__file__).resolve().parents[1] / "workflow/schemas/config.schema.yaml").read_text())
    pattern = schema["properties"]["variants"]["additionalProperties"]["properties"]["refine"]["properties"]["weights"]["pattern"]
    names = [f.name for f in dataclasses.fields(LossWeights)]
    assert re.fullmatch(pattern, ",".join(f"{n}=0.5" for n in names))
    assert not re.fullmatch(pattern, "insde=2")
    assert not re.fullmatch(pattern, "inside=-1")


# --- no NaN passed on ---------------------------------------------------------------------------


def test_json_we_write_never_holds_nan_or_infinity(tmp_path):
    from capframe.errors import InputError
    from capframe.scene._io import write_json

    with pytest.raises(InputError, match=r"result.json: loss_terms.view is nan"):
        write_json(tmp_path / "result.json", {"loss_terms": {"upright": 0.0, "view": float("nan")}})
    with pytest.raises(InputError, match=r"up\[0\] is inf"):
        write_json(tmp_path / "x.json", {"up": [float("inf"), 0.0, 1.0]})
    assert not list(tmp_path.iterdir())
    write_json(tmp_path / "ok.json", {"a": [1.0, 2]})
    assert json.loads((tmp_path / "ok.json").read_text()) == {"a": [1.0, 2]}


@pytest.fixture(scope="module")
def staged(scene_dir, tmp_path_factory) -> Path:
    """The method's stage files for INSTRUCTION, one verb each (the workflow's rules): parsed,
    coarse, retrieval, subjects, fronts and labels .json in one folder (with the views cache)."""
    folder = tmp_path_factory.mktemp("staged")
    cache = ["--cache", folder / "cache"]
    for argv in (
        ["parse", scene_dir, INSTRUCTION, "-o", folder / "parsed.json"],
        ["coarse", scene_dir, "--parsed", folder / "parsed.json", "-o", folder / "coarse.json"],
        ["qe", scene_dir, "--coarse", folder / "coarse.json", "-o", folder / "retrieval.json"],
        ["associate", scene_dir, "--retrieval", folder / "retrieval.json", "-o", folder / "subjects.json"],
        ["orient", scene_dir, "--retrieval", folder / "retrieval.json", "-o", folder / "fronts.json"],
    ):
        assert main([str(a) for a in argv + cache]) == 0
    argv = ["translate", scene_dir, "--retrieval", folder / "retrieval.json", "--subjects", folder / "subjects.json"]
    assert main([str(a) for a in [*argv, "--fronts", folder / "fronts.json", "-o", folder / "labels.json"]]) == 0
    return folder


def edited(staged: Path, name: str, tmp_path: Path, edit, keep_path: bool = False) -> Path:
    """A copy of the stage file ``name`` changed by ``edit(data)``: in ``tmp_path``, or in place
    with its modification time kept (``keep_path``: what Snakemake cannot see)."""
    source = staged / name
    data = json.loads(source.read_text())
    edit(data)
    target = source if keep_path else tmp_path / name
    stat = source.stat()
    target.write_text(json.dumps(data, indent=2))  # json writes NaN as a bare literal, as a hand edit might
    if keep_path:
        os.utime(target, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    return target


def test_coarse_file_with_no_kept_view_is_refused(scene_dir, staged, tmp_path, capsys):
    coarse = edited(staged, "coarse.json", tmp_path, lambda d: d.update(kept=[]))
    with nothing_changes(tmp_path), nothing_changes(staged):
        assert_refused(run(capsys, "qe", scene_dir, "--coarse", coarse, "-o", tmp_path / "q.json"), str(coarse), "kept is []")


def test_stage_file_naming_an_unknown_subject_is_refused(scene_dir, staged, tmp_path, capsys):
    def rename(data):
        data["instruction"]["subjects"][0]["name"] = "unicorn"

    retrieval = edited(staged, "retrieval.json", tmp_path, rename)
    for verb in ("associate", "orient"):
        with nothing_changes(tmp_path), nothing_changes(staged):
            argv = [verb, scene_dir, "--retrieval", retrieval, "-o", tmp_path / "out.json", "--cache", staged / "cache"]
            assert_refused(run(capsys, *argv), str(retrieval), "instruction.subjects[0].name", "'unicorn'")


def _set(path: str, value):
    """An edit that sets the field at ``path`` (keys and list indices, dot-separated) to ``value``."""

    def edit(data):
        *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
        for key in parents:
            data = data[key]
        data[last] = value

    return edit


NAN = float("nan")


@pytest.mark.parametrize(
    "name, field, value, named",
    [
        ("coarse.json", "up", [NAN, 0.0, 1.0], "up[0] is nan"),
        ("coarse.json", "up", [0.0, 0.0, 0.0], "up is the zero vector"),
        ("coarse.json", "coarse.v0", NAN, "coarse.v0 is nan"),
        ("retrieval.json", "up", [NAN, 0.0, 1.0], "up[0] is nan"),
        ("retrieval.json", "up", [0.0, 0.0, 0.0], "up is the zero vector"),
        ("retrieval.json", "retrieval.views.0.score", NAN, "retrieval.views[0].score is nan"),
        ("retrieval.json", "starts", [], "starts is []"),
        ("subjects.json", "subjects.teddy bear.centroid", [NAN, 0.0, 0.0], "subjects.teddy bear.centroid[0] is nan"),
        ("fronts.json", "fronts.teddy bear", [0.0, 0.0, 0.0], "fronts.teddy bear"),
        ("labels.json", "up", [NAN, 0.0, 1.0], "up[0] is nan"),
        ("labels.json", "subjects.0.centroid", [1.0, float("inf"), 0.0], "subjects[0].centroid[1] is inf"),
        ("labels.json", "roll_deg", NAN, "roll_deg is nan"),
        ("labels.json", "subjects.0.box", [0.6, 0.2, 0.6, 0.8], "subjects[0].box is [0.6, 0.2, 0.6, 0.8]"),
        ("labels.json", "subjects.0.region", [0.7, 0.2, 0.5, 0.8], "subjects[0].region"),
        ("labels.json", "subjects.0.box", None, "subjects[0].extent"),
    ],
)
def test_stage_files_with_nan_or_no_direction_are_refused(scene_dir, staged, tmp_path, capsys, name, field, value, named):
    """Every stage file is read by one validated reader: no NaN, infinity or zero up flows on."""
    bad = edited(staged, name, tmp_path, _set(field, value))
    files = {n: staged / n for n in ("coarse.json", "retrieval.json", "subjects.json", "fronts.json", "labels.json")}
    files[name] = bad
    out = tmp_path / "out"
    argv = {
        "coarse.json": ["qe", scene_dir, "--coarse", files["coarse.json"], "-o", out, "--cache", staged / "cache"],
        "retrieval.json": [
            "associate",
            scene_dir,
            "--retrieval",
            files["retrieval.json"],
            "-o",
            out,
            "--cache",
            staged / "cache",
        ],
        "subjects.json": ["translate", scene_dir, "--retrieval", files["retrieval.json"], "--subjects", files["subjects.json"]],
        "fronts.json": ["translate", scene_dir, "--retrieval", files["retrieval.json"], "--subjects", files["subjects.json"]],
        "labels.json": ["refine", scene_dir, "--labels", files["labels.json"], "--init", files["retrieval.json"]],
    }[name]
    if name in ("subjects.json", "fronts.json"):
        argv += ["--fronts", files["fronts.json"], "-o", out]
    elif name == "labels.json":
        argv += ["-o", out]
    with nothing_changes(tmp_path), nothing_changes(staged):
        assert_refused(run(capsys, *argv), str(bad), named)


def test_stage_file_changed_after_the_files_made_from_it_is_refused(scene_dir, staged, tmp_path, capsys):
    """A retrieval.json edited in place with its time kept (Snakemake sees nothing): the labels
    made from it name themselves as the file to rebuild, and so does a retrieval.json whose
    coarse.json changed."""
    saved = {name: (staged / name).read_bytes() for name in ("retrieval.json", "coarse.json")}
    try:
        edited(staged, "retrieval.json", tmp_path, lambda d: d.update(starts=d["starts"][::-1]), keep_path=True)
        retrieval = staged / "retrieval.json"
        argv = ["refine", scene_dir, "--labels", staged / "labels.json", "--init", retrieval, "-o", tmp_path / "r"]
        with nothing_changes(tmp_path), nothing_changes(staged):
            line = assert_refused(run(capsys, *argv), "labels.json", "inputs.retrieval", str(staged / "retrieval.json"))
            assert line.endswith(f"rebuild {staged / 'labels.json'}")
        (staged / "retrieval.json").write_bytes(saved["retrieval.json"])
        edited(staged, "coarse.json", tmp_path, lambda d: d.update(kept=d["kept"][::-1]), keep_path=True)
        argv = ["orient", scene_dir, "--retrieval", retrieval, "-o", tmp_path / "f.json", "--cache", staged / "cache"]
        with nothing_changes(tmp_path), nothing_changes(staged):
            line = assert_refused(run(capsys, *argv), "inputs.coarse", str(staged / "coarse.json"))
            assert line.endswith(f"rebuild {staged / 'retrieval.json'}")
    finally:
        for name, content in saved.items():
            (staged / name).write_bytes(content)


def test_labels_whose_front_is_along_the_up_are_refused(scene_dir, staged, tmp_path, capsys):
    """A front with no horizontal part has no azimuth: the closed-form starts and the view loss
    would place cameras at NaN."""
    up = json.loads((staged / "labels.json").read_text())["up"]
    labels = edited(staged, "labels.json", tmp_path, _set("subjects.0.front", [-x for x in up]))
    argv = ["refine", scene_dir, "--labels", labels, "--init", staged / "retrieval.json", "-o", tmp_path / "out"]
    with nothing_changes(tmp_path), nothing_changes(staged):
        assert_refused(run(capsys, *argv), str(labels), "subjects[0].front", "along the up")


# --- free space, closed-form starts, benches and model export (added to main after #21) ---------


@pytest.fixture(scope="module")
def occupancy_file(scene_dir, tmp_path_factory) -> Path:
    """The scene's occupancy.npz, written by capframe occupancy."""
    path = tmp_path_factory.mktemp("occupancy") / "occupancy.npz"
    assert main([str(a) for a in ("occupancy", scene_dir, "-o", path)]) == 0
    return path


def _rewritten_occupancy(source: Path, target: Path, **changes) -> Path:
    """A copy of the occupancy file ``source`` at ``target`` with arrays (or ``meta`` keys, as
    ``meta_<key>``) replaced."""
    with np.load(source) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(str(arrays["meta"]))
    for key, value in changes.items():
        if key.startswith("meta_"):
            meta[key[len("meta_") :]] = value
        else:
            arrays[key] = value
    arrays["meta"] = np.array(json.dumps(meta))
    with open(target, "wb") as f:
        np.savez(f, **arrays)
    return target


def test_occupancy_and_model_export_check_their_output_first(scene_dir, tmp_path, capsys):
    (tmp_path / "a-folder").mkdir()
    with nothing_changes(tmp_path):
        assert_refused(run(capsys, "occupancy", scene_dir, "-o", tmp_path / "a-folder"), str(tmp_path / "a-folder"), "folder")
        # Refused for its output before the models config (which does not exist) is read.
        argv = ["models", "export", "clip", "--models", tmp_path / "none.yaml", "-o", tmp_path / "a-folder"]
        assert_refused(run(capsys, *argv), str(tmp_path / "a-folder"), "folder")


@pytest.mark.parametrize(
    "case, named",
    [
        ("missing", "not found"),
        ("folder", "is a folder"),
        ("not npz", "is not an occupancy file"),
        ("nan sdf", "sdf holds NaN"),
        ("shapes", "free is bool of shape"),
        ("voxel", "voxel is -1.0"),
        ("rotation", "rotation is not a rotation matrix"),
        ("another scene", "was built from another scene"),
    ],
)
def test_occupancy_file_that_is_not_this_scenes_is_refused(scene_dir, staged, occupancy_file, tmp_path, capsys, case, named):
    """``capframe refine --occupancy``: one line naming the file, before any refinement."""
    bad = tmp_path / "occupancy.npz"
    with np.load(occupancy_file) as data:
        sdf, free = data["sdf"], data["free"]
    if case == "folder":
        bad.mkdir()
    elif case == "not npz":
        bad.write_bytes(b"PK\x03\x04 not really a zip")
    elif case == "nan sdf":
        _rewritten_occupancy(occupancy_file, bad, sdf=np.where(sdf > 0, np.float32("nan"), sdf))
    elif case == "shapes":
        _rewritten_occupancy(occupancy_file, bad, free=free[:-1])
    elif case == "voxel":
        _rewritten_occupancy(occupancy_file, bad, meta_voxel=-1.0)
    elif case == "rotation":
        _rewritten_occupancy(occupancy_file, bad, rotation=2 * np.eye(3))
    elif case == "another scene":
        _rewritten_occupancy(occupancy_file, bad, meta_gaussians="0123456789abcdef")
    argv = ["refine", scene_dir, "--labels", staged / "labels.json", "--init", staged / "retrieval.json"]
    argv += ["--occupancy", bad, "-o", tmp_path / "out"]
    with nothing_changes(tmp_path), nothing_changes(staged):
        assert_refused(run(capsys, *argv), str(bad), named)


def test_occupancy_file_of_this_scene_is_read(scene_dir, occupancy_file):
    from capframe.scene import load_scene_dir
    from capframe.scene.occupancy import gaussians_fingerprint, load_occupancy

    scene = load_scene_dir(scene_dir)
    grid = load_occupancy(occupancy_file, gaussians=gaussians_fingerprint(scene.gaussians))
    assert grid is not None and grid.free.any() and np.isfinite(grid.sdf).all()


def test_solved_starts_write_no_nan(scene_dir):
    """result.json's ``solved`` entries: a number that is not finite (a degenerate placement) is null."""
    from capframe.refine.candidates import Candidate
    from capframe.scene import load_scene_dir
    from capframe.scene._io import json_text

    camera = load_scene_dir(scene_dir, load_gaussians=False).cameras[0]
    entry = Candidate(camera, 30.0, float("nan"), 2.0, float("inf"), 0.0, 0.0, 0.0, "inside geometry").to_dict()
    assert entry["elevation_deg"] is None and entry["clearance"] is None and entry["azimuth_deg"] == 30.0
    assert "NaN" not in json_text(entry, "solved")


def test_bench_checks_its_results_folder_first_and_prints_null_for_unmeasured(tmp_path, capsys, monkeypatch):
    import capframe.bench.render

    monkeypatch.chdir(tmp_path)
    (tmp_path / "results").write_text("a file where the results folder goes")
    with nothing_changes(tmp_path):
        assert_refused(run(capsys, "bench", "ground"), "results/bench", "is a file, not a folder")
    monkeypatch.setattr(capframe.bench.render, "bench_render", lambda: {"seconds": 0.5, "not_measured": float("nan")})
    code, out, _ = run(capsys, "bench", "render", "--json")
    assert code == 0 and json.loads(out) == {"seconds": 0.5, "not_measured": None} and "NaN" not in out


# --- shell injection and path escape in the workflow --------------------------------------------

ROOT = Path(__file__).resolve().parents[1]


def snakemake_dry_run(work: Path, *extra: str) -> subprocess.CompletedProcess:
    """``snakemake -n`` of the project's workflow in ``work`` (which holds its config/)."""
    import sys

    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}")
    cmd = [sys.executable, "-m", "snakemake", "-n", "--nolock", "--cores", "1", "--snakefile", str(ROOT / "Snakefile")]
    return subprocess.run(
        [*cmd, "--directory", str(work), *extra], cwd=work, env=env, capture_output=True, text=True, timeout=300
    )


@pytest.mark.parametrize("name", ["k;touch pwned;", "../../evil", "a b", ".hidden"])
def test_variant_names_that_are_not_safe_are_rejected_by_the_schema(tmp_path, name):
    import yaml

    shutil.copytree(ROOT / "config", tmp_path / "config")
    config = yaml.safe_load((tmp_path / "config" / "config.yaml").read_text())
    config["variants"] = {name: {"refine": {"iterations": 10}}}
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(config))
    with nothing_changes(tmp_path / "config"):
        done = snakemake_dry_run(tmp_path)
    assert done.returncode != 0 and "Error validating config" in done.stdout + done.stderr
    assert not (tmp_path / "pwned").exists() and not (tmp_path / "results").exists()


def test_suite_ids_that_are_not_safe_names_are_refused(tmp_path):
    from capframe.errors import InputError
    from capframe.synth.suite import load_suite

    entry = "{id: %s, group: lerf, seed: 1, preset: tabletop, capture: orbit, views: 8, scale: 1.0, tilt: 0, poses: true, "
    entry += "resolution: 80x60, density: 0.2, instructions: 1}"
    for bad in ("'../../evil'", "'x;touch pwned'", "'$(id)'"):
        (tmp_path / "suite.yaml").write_text("suite: s\nscenes:\n  - " + entry % bad + "\n")
        with pytest.raises(InputError, match="'id' is"):
            load_suite(tmp_path / "suite.yaml")


def test_instruction_ids_that_are_not_safe_names_stop_the_workflow(tmp_path):
    """Instruction ids come from a file (constraints.json) and become wildcards and paths too."""
    from test_workflow import _fake_generated_suite

    _fake_generated_suite(tmp_path)
    sheet = tmp_path / "results" / "instructions" / "tabletop-orbit" / "constraints.json"
    sheet.write_text(json.dumps({"x;touch pwned": {"text": "a photo of the ball", "constraints": {}}}))
    done = snakemake_dry_run(tmp_path, "--rerun-triggers", "mtime")
    assert (
        done.returncode != 0 and "'x;touch pwned'" in done.stdout + done.stderr and "not safe names" in done.stdout + done.stderr
    )
    assert not (tmp_path / "pwned").exists()


def test_every_shell_placeholder_is_quoted():
    """Inputs, outputs, logs, wildcards and params reach the shell as {...:q}: each is one quoted
    argument (or, for a list, one quoted argument per item), whatever characters it holds."""
    import re

    rules = [ROOT / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]
    placeholders = []
    for path in rules:
        for block in re.findall(r"^    shell:\n((?:        .*\n)+)", path.read_text(), re.M):
            placeholders += re.findall(r"\{([^{}]*)\}", block)
    assert len(placeholders) > 80, "no shell commands parsed: the pattern is stale"
    assert [p for p in placeholders if not p.endswith(":q")] == []


# --- an interrupted run resumes ------------------------------------------------------------------

TINY_SUITE = """suite: tiny
scenes:
  - {id: tiny, group: lerf, seed: 1, preset: tabletop, capture: orbit, objects: [teddy bear, mug],
     views: 8, scale: 1.0, tilt: 0, poses: true, resolution: 80x60, density: 0.2, instructions: 1}
"""


def _snakemake(work: Path, *extra: str, slow_coarse: bool = False, **popen) -> subprocess.Popen:
    """The project's workflow on the tiny suite in ``work``, with the default profile (which asks
    for --rerun-incomplete), running this checkout's capframe; with ``slow_coarse`` its coarse
    jobs first wait 5 s, so a signal sent while one runs lands while it runs (on a tiny scene
    the job itself takes well under a second)."""
    import sys

    path = f"{Path(sys.executable).parent}:{os.environ.get('PATH', '')}"
    if slow_coarse:
        wrapper = work / "bin" / "capframe"
        wrapper.parent.mkdir(exist_ok=True)
        wrapper.write_text(f'#!/bin/sh\n[ "$1" = coarse ] && sleep 5\nexec "{sys.executable}" -m capframe.cli "$@"\n')
        wrapper.chmod(0o755)
        path = f"{wrapper.parent}:{path}"
    env = dict(os.environ, PATH=path)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])
    cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(ROOT / "Snakefile"), "--directory", str(work)]
    cmd += ["--workflow-profile", str(ROOT / "workflow" / "profiles" / "default"), "--cores", "2", *extra]
    # The child gets the default SIGINT action: an earlier test in this process may have left
    # SIGINT ignored, and an ignored disposition survives exec (Snakemake would then never stop).
    return subprocess.Popen(
        [*cmd, "results/tables/capframe.csv"], cwd=work, env=env, text=True, preexec_fn=_default_sigint, **popen
    )


def _default_sigint() -> None:
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _finished_jobs(log: str) -> list[tuple[str, str]]:
    """(rule, outputs) of every job a Snakemake log reports finished."""
    import re

    started = {
        jobid: (rule, outputs)
        for rule, outputs, jobid in re.findall(
            r"^(?:local)?(?:rule|checkpoint) (\w+):\n(?:    .*\n)*?    output: (.*)\n(?:    .*\n)*?    jobid: (\d+)$", log, re.M
        )
    }
    return [started[jobid] for jobid in re.findall(r"^Finished jobid: (\d+) ", log, re.M)]


def test_a_run_interrupted_after_a_checkpoint_resumes_every_job_once(tmp_path):
    """SIGINT reaches Snakemake while a job after the parse checkpoint runs: Snakemake lets it
    finish but records it as incomplete. The resumed run reruns exactly the jobs it did not see
    finish, every job of the target finishes once over both runs, and no incomplete marker is left."""
    import signal
    import time

    (tmp_path / "config" / "suites").mkdir(parents=True)
    (tmp_path / "config" / "suites" / "tiny.yaml").write_text(TINY_SUITE)
    config = "suite: config/suites/tiny.yaml\nrefine: {iterations: 30, long_side: 48}\nvariants: {}\n"
    (tmp_path / "config" / "config.yaml").write_text(config)
    logs = [tmp_path / "first.log", tmp_path / "resumed.log"]

    coarse_log = tmp_path / "results" / "logs" / "coarse" / "capframe" / "tiny" / "tiny-000.log"
    incomplete = tmp_path / ".snakemake" / "incomplete"
    # Where the signal lands in Snakemake's loop varies; a run it did not stop (exit 0, or no job
    # left incomplete) is started afresh, at most three times.
    for _ in range(3):
        shutil.rmtree(tmp_path / "results", ignore_errors=True)
        shutil.rmtree(tmp_path / ".snakemake", ignore_errors=True)
        with open(logs[0], "w") as out:
            first = _snakemake(tmp_path, slow_coarse=True, stdout=out, stderr=subprocess.STDOUT)

            def coarse_is_running() -> bool:  # started (its log) and registered by Snakemake (a marker)
                return coarse_log.exists() and incomplete.is_dir() and any(incomplete.iterdir())

            deadline = time.monotonic() + 300
            while not coarse_is_running() and first.poll() is None and time.monotonic() < deadline:
                time.sleep(0.1)
            assert first.poll() is None, "the run ended before the coarse job started"
            time.sleep(1.0)  # inside the coarse job's 5 s wait
            first.send_signal(signal.SIGINT)
            first.wait(timeout=300)
        if first.returncode != 0 and any(incomplete.iterdir()):
            break
    assert first.returncode != 0 and any(incomplete.iterdir()), "in three runs the interrupt hit no running job"

    with open(logs[1], "w") as out:
        assert _snakemake(tmp_path, stdout=out, stderr=subprocess.STDOUT).wait(timeout=600) == 0, logs[1].read_text()[-3000:]

    first_jobs, resumed_jobs = (_finished_jobs(log.read_text()) for log in logs)
    assert "coarse" in [rule for rule, _ in resumed_jobs]  # interrupted, so run again
    everything = first_jobs + resumed_jobs
    assert sorted(everything) == sorted(set(everything)), "a job finished twice"
    assert not any(incomplete.iterdir())
    nothing = _snakemake(tmp_path, "-n", stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    assert "Nothing to be done" in nothing.communicate(timeout=300)[0]


def test_an_interrupt_is_one_line_and_exit_130(monkeypatch, capsys):
    """Ctrl-C (or Snakemake's SIGINT to its jobs) ends a command without a traceback."""
    import capframe.cli as cli

    def interrupted(args):
        raise KeyboardInterrupt

    parser = cli.build_parser()
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    parser._subparsers._group_actions[0].choices["gravity"].set_defaults(func=interrupted)
    assert cli.main(["gravity", "scene"]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "interrupted" in err and "Traceback" not in err
