"""Inria 3DGS PLY reader/writer."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from _scene_helpers import inria_names, random_inria_columns, random_scene, write_ply_by_hand

from capframe.errors import InputError
from capframe.scene import read_ply, write_ply

FIELDS = ("means", "quats", "log_scales", "opacity_logits", "sh")


@pytest.mark.parametrize("degree", [0, 1, 3])
def test_write_then_read_is_bit_exact(tmp_path, degree):
    scene = random_scene(n=37, degree=degree, seed=degree)
    write_ply(scene, tmp_path / "s.ply")
    back = read_ply(tmp_path / "s.ply")
    for name in FIELDS:
        ours, theirs = getattr(scene, name), getattr(back, name)
        assert theirs.dtype == torch.float32 and theirs.shape == ours.shape
        assert torch.equal(theirs.view(torch.int32), ours.view(torch.int32)), name  # bit for bit, -0.0 included
    assert back.sh_degree == degree and back.labels is None


@pytest.mark.parametrize("degree", [0, 3])
def test_read_then_write_reproduces_an_inria_file_byte_for_byte(tmp_path, degree):
    write_ply_by_hand(tmp_path / "inria.ply", random_inria_columns(41, degree, seed=7))
    write_ply(read_ply(tmp_path / "inria.ply"), tmp_path / "again.ply")
    assert (tmp_path / "again.ply").read_bytes() == (tmp_path / "inria.ply").read_bytes()


def test_f_rest_is_channel_major(tmp_path):
    degree, n = 2, 3
    k = (degree + 1) ** 2 - 1
    columns = random_inria_columns(n, degree)
    for c in range(3):
        for j in range(k):
            columns[f"f_rest_{c * k + j}"] = np.full(n, 100 * c + j, np.float32)
        columns[f"f_dc_{c}"] = np.full(n, -1 - c, np.float32)
    write_ply_by_hand(tmp_path / "s.ply", columns)
    sh = read_ply(tmp_path / "s.ply").sh
    for c in range(3):
        assert torch.all(sh[:, 0, c] == -1 - c)
        for j in range(k):
            assert torch.all(sh[:, 1 + j, c] == 100 * c + j)


def test_reordered_properties_with_extras_and_other_types(tmp_path):
    columns = random_inria_columns(20, 3, seed=3)
    write_ply_by_hand(tmp_path / "ref.ply", columns)
    reference = read_ply(tmp_path / "ref.ply")
    rng = np.random.default_rng(0)
    shuffled = {name: columns[name] for name in rng.permutation(list(columns))}
    shuffled["red"] = rng.integers(0, 255, 20).astype(np.uint8)  # gsplat/nerfstudio-style extras
    shuffled["gs_id"] = np.arange(20, dtype=np.int32)
    shuffled["confidence"] = rng.standard_normal(20)
    types = {"red": "uchar", "gs_id": "int", "confidence": "double", "x": "double", "opacity": "double"}
    for fmt in ("binary_little_endian", "binary_big_endian", "ascii"):
        write_ply_by_hand(tmp_path / f"{fmt}.ply", shuffled, types=types, fmt=fmt)
        scene = read_ply(tmp_path / f"{fmt}.ply")
        for name in FIELDS:
            assert torch.equal(getattr(scene, name), getattr(reference, name)), (fmt, name)


def test_file_without_normals_and_without_f_rest(tmp_path):
    columns = random_inria_columns(5, 0)
    for name in ("nx", "ny", "nz"):
        del columns[name]
    write_ply_by_hand(tmp_path / "s.ply", columns)
    scene = read_ply(tmp_path / "s.ply")
    assert scene.sh.shape == (5, 1, 3)
    assert torch.equal(scene.means[:, 0], torch.from_numpy(columns["x"]))


def _expect_error(path, *fragments):
    with pytest.raises(InputError) as info:
        read_ply(path)
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    for fragment in fragments:
        assert fragment in message, message
    return message


def test_truncated_file(tmp_path):
    write_ply_by_hand(tmp_path / "s.ply", random_inria_columns(10, 3))
    data = (tmp_path / "s.ply").read_bytes()
    (tmp_path / "s.ply").write_bytes(data[:-10])
    _expect_error(tmp_path / "s.ply", "truncated")
    (tmp_path / "h.ply").write_bytes(data[:40])  # cut inside the header
    _expect_error(tmp_path / "h.ply", "truncated")


def test_missing_properties_are_listed(tmp_path):
    columns = random_inria_columns(4, 0)
    for name in ("opacity", "rot_2"):
        del columns[name]
    write_ply_by_hand(tmp_path / "s.ply", columns)
    _expect_error(tmp_path / "s.ply", "missing", "opacity", "rot_2")


def test_nan_in_means(tmp_path):
    columns = random_inria_columns(6, 1)
    columns["y"][4] = np.nan
    write_ply_by_hand(tmp_path / "s.ply", columns)
    _expect_error(tmp_path / "s.ply", "means", "non-finite", "Gaussian 4")


def test_inf_in_scales(tmp_path):
    columns = random_inria_columns(6, 1)
    columns["scale_2"][1] = np.inf
    write_ply_by_hand(tmp_path / "s.ply", columns)
    _expect_error(tmp_path / "s.ply", "log_scales", "non-finite")


def test_all_zero_quaternion(tmp_path):
    columns = random_inria_columns(6, 0)
    for name in ("rot_0", "rot_1", "rot_2", "rot_3"):
        columns[name][2] = 0.0
    write_ply_by_hand(tmp_path / "s.ply", columns)
    _expect_error(tmp_path / "s.ply", "quaternion")


def test_wrong_f_rest_count(tmp_path):
    columns = random_inria_columns(3, 1)
    del columns["f_rest_8"]
    write_ply_by_hand(tmp_path / "s.ply", columns)
    _expect_error(tmp_path / "s.ply", "8 f_rest_* properties")


def test_not_a_ply(tmp_path):
    (tmp_path / "s.ply").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(100))
    _expect_error(tmp_path / "s.ply", "not a PLY")
    _expect_error(tmp_path / "absent.ply", "not found")


def test_writer_refuses_non_finite_values(tmp_path):
    scene = random_scene(n=4, degree=0)
    scene.opacity_logits[1] = float("nan")
    with pytest.raises(InputError, match="opacity_logits"):
        write_ply(scene, tmp_path / "s.ply")
    assert not (tmp_path / "s.ply").exists()


def test_writer_header_matches_reference_order(tmp_path):
    write_ply(random_scene(n=2, degree=3), tmp_path / "s.ply")
    header = (tmp_path / "s.ply").read_bytes().split(b"end_header\n")[0].decode().splitlines()
    assert header[:3] == ["ply", "format binary_little_endian 1.0", "element vertex 2"]
    assert [line.split()[-1] for line in header[3:]] == inria_names(3)
