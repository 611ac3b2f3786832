"""The command line: rendering one view, and one-line errors for bad input."""

from __future__ import annotations

import json

import numpy as np
from conftest import make_camera, make_scene
from PIL import Image

from capframe.cli import main
from capframe.render import render
from capframe.render.image import to_uint8
from capframe.scene import write_camera_json, write_ply


def test_render_command_writes_the_rendered_view(tmp_path):
    scene, camera = make_scene(300), make_camera()
    write_ply(scene, tmp_path / "scene.ply")
    write_camera_json(camera, tmp_path / "camera.json")
    assert (
        main(
            [
                "render",
                str(tmp_path / "scene.ply"),
                "--camera",
                str(tmp_path / "camera.json"),
                "-o",
                str(tmp_path / "out.png"),
                "--backend",
                "torch",
            ]
        )
        == 0
    )
    written = np.asarray(Image.open(tmp_path / "out.png"))
    expected = to_uint8(render(scene, camera, backend="torch").rgb)
    assert written.shape == (camera.height, camera.width, 3)
    assert np.abs(written.astype(int) - expected.astype(int)).max() <= 1


def test_camera_with_non_finite_values_is_a_one_line_error(tmp_path, capsys):
    write_ply(make_scene(10), tmp_path / "scene.ply")
    write_camera_json(make_camera(), tmp_path / "camera.json")
    data = json.loads((tmp_path / "camera.json").read_text())
    data["T_cw"][0][3] = float("nan")
    (tmp_path / "camera.json").write_text(json.dumps(data))
    code = main(
        ["render", str(tmp_path / "scene.ply"), "--camera", str(tmp_path / "camera.json"), "-o", str(tmp_path / "out.png")]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert "camera.json" in err and "non-finite" in err
    assert not (tmp_path / "out.png").exists()


def test_malformed_ply_is_a_one_line_error(tmp_path, capsys):
    (tmp_path / "bad.ply").write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nend_header\n\x00\x00"
    )
    write_camera_json(make_camera(), tmp_path / "camera.json")
    code = main(["render", str(tmp_path / "bad.ply"), "--camera", str(tmp_path / "camera.json"), "-o", str(tmp_path / "out.png")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "bad.ply" in err


def test_an_interrupt_inside_compiled_code_exits_as_an_interrupt(tmp_path, capsys, monkeypatch):
    """Ctrl-C while numba compiles or loads a kernel reaches Python as a SystemError caused by the
    KeyboardInterrupt: the command still ends as interrupted (status 130, one line), while any
    other error still propagates."""
    import pytest

    import capframe.cli as cli

    def compiled_code_interrupted(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as interrupt:
            raise SystemError("CPUDispatcher(...) returned a result with an exception set") from interrupt

    argv = ["compare", str(tmp_path / "a.csv"), "-o", str(tmp_path / "out.csv")]
    monkeypatch.setattr(cli, "_cmd_compare", compiled_code_interrupted)
    assert main(argv) == 130
    assert capsys.readouterr().err.strip() == "capframe: interrupted; nothing was written for this command"

    def broken(args):
        raise SystemError("a real fault")

    monkeypatch.setattr(cli, "_cmd_compare", broken)
    with pytest.raises(SystemError, match="a real fault"):
        main(argv)


def test_the_command_lets_openmp_threads_sleep_unless_told_otherwise():
    """The command sets OMP_WAIT_POLICY=PASSIVE before torch loads its OpenMP runtime (spinning
    threads take the cores the compiled renderer's kernels run on); an explicit value wins, and
    once torch is loaded it is too late: nothing changes."""
    import os
    import subprocess
    import sys

    check = "from capframe.cli import passive_openmp; print(passive_openmp(), os.environ.get('OMP_WAIT_POLICY'))"
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    runs = [
        ("import os; " + check, env, ["True", "PASSIVE"]),
        ("import os; " + check, dict(env, OMP_WAIT_POLICY="active"), ["True", "active"]),
        ("import os, torch; " + check, env, ["False", "None"]),
    ]
    for source, environment, expected in runs:
        out = subprocess.run([sys.executable, "-c", source], env=environment, capture_output=True, text=True, check=True)
        assert out.stdout.split() == expected
