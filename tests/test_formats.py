"""Readers for 3DGS files in the wild (.splat, PlayCanvas compressed PLY, .spz, Inria PLY) on the real
files in ../shared/data/real/captured (see its README for sources and licences) and on small files
built here with hand-checkable values."""

from __future__ import annotations

import gzip
import json
import struct
from pathlib import Path

import numpy as np
import pytest
import torch
from PIL import Image

from capframe.cli import main
from capframe.errors import InputError
from capframe.geometry import look_at
from capframe.render import render
from capframe.scene import (
    Camera,
    import_scene,
    load_scene_dir,
    read_compressed_ply,
    read_gaussians,
    read_ply,
    read_splat,
    read_spz,
    write_camera_json,
    write_ply,
)
from capframe.scene.model import SH_C0

REAL = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "real" / "captured"
COUNTS = {
    "plant/plant.splat": 113_648,
    "academic_tarot_cards/academic_tarot_cards.splat": 114_865,
    "playcanvas/guitar.compressed.ply": 90_854,
    "playcanvas/biker.compressed.ply": 152_746,
    "playcanvas/biker.spz": 152_746,
    "donut-inria/fused.ply": 45_624,
}
FIELDS = ("means", "quats", "log_scales", "opacity_logits", "sh")
needs_real = pytest.mark.skipif(not REAL.is_dir(), reason=f"real test data not found at {REAL} (shared/data/real)")

_decoded: dict[str, object] = {}


def real(name: str):
    """The decoded real file ``name`` (decoded once per session)."""
    if name not in _decoded:
        _decoded[name] = read_gaussians(REAL / name)
    return _decoded[name]


def one_line_error(fn, *args) -> str:
    with pytest.raises(InputError) as info:
        fn(*args)
    message = str(info.value)
    assert "\n" not in message
    return message


def camera_at_bbox_centre(means: torch.Tensor, width: int = 64, height: int = 48) -> Camera:
    """A camera outside the robust (1-99 %) box of ``means``, looking at its centre, the box filling
    about half the frame."""
    lo, hi = means.quantile(0.01, dim=0).double(), means.quantile(0.99, dim=0).double()
    centre, size = (lo + hi) / 2, float((hi - lo).max())
    direction = torch.tensor([0.3, -0.4, -1.0], dtype=torch.float64)
    eye = centre + 1.6 * size * direction / direction.norm()
    T_cw = look_at(eye, centre, torch.tensor([0.0, -1.0, 0.0], dtype=torch.float64))
    f = 0.9 * width
    K = np.array([[f, 0, width / 2], [0, f, height / 2], [0, 0, 1]])
    return Camera(T_cw.numpy(), K, width, height, name="bbox")


# --- real files ----------------------------------------------------------------------------------


@needs_real
@pytest.mark.parametrize("name", COUNTS)
def test_real_file_decodes_to_valid_gaussians(name):
    scene = real(name)
    assert len(scene) == COUNTS[name]
    for field in FIELDS:
        value = getattr(scene, field)
        assert value.dtype == torch.float32 and torch.isfinite(value).all(), field
    norms = scene.quats.norm(dim=1)
    if name.endswith("fused.ply"):  # an Inria PLY keeps the trainer's raw quaternions, normalised at render time
        assert (norms > 0.1).all()
    else:
        assert torch.allclose(norms, torch.ones(len(scene)), atol=1e-5)
    opacities = scene.opacities
    assert (opacities > 0).all() and (opacities < 1).all()
    assert scene.sh_degree == 0  # none of these files carries higher bands
    extent = scene.means.quantile(0.99, dim=0) - scene.means.quantile(0.01, dim=0)
    assert (extent > 0.05).all() and (extent < 10).all()  # object-sized in their capture units


@needs_real
@pytest.mark.parametrize("name", ["plant/plant.splat", "academic_tarot_cards/academic_tarot_cards.splat"])
def test_splat_bounding_box_matches_its_meta_json(name):
    means = real(name).means.double()
    meta = json.loads((REAL / name).with_name("meta.json").read_text())["geometry"]["extent"]
    full = means.max(0).values - means.min(0).values
    assert torch.allclose(full / full.max(), torch.tensor(meta, dtype=torch.float64), atol=5e-4)
    # Floaters do not make the box: the box of the central 99 % is most of it on every axis.
    robust = means.quantile(0.995, dim=0) - means.quantile(0.005, dim=0)
    assert (robust / full > 0.8).all()


@needs_real
def test_every_3dgs_file_of_the_real_data_is_covered():
    """A 3DGS file added to shared/data/real joins the decode, render, round-trip and import tests."""
    found = {str(p.relative_to(REAL)) for p in REAL.rglob("*") if p.suffix.lower() in (".ply", ".splat", ".spz")}
    assert found == set(COUNTS)


@needs_real
def test_biker_spz_and_compressed_ply_agree():
    ply, spz = real("playcanvas/biker.compressed.ply"), real("playcanvas/biker.spz")
    assert len(ply) == len(spz)
    # The same splats in the same order; spz positions are 12-bit fixed point (step 2.4e-4), the
    # PLY's are 11/10/11-bit fractions of 256-splat chunk boxes.
    assert (ply.means - spz.means).abs().max() < 3e-4
    for q in (0.01, 0.5, 0.99):
        assert torch.allclose(ply.means.quantile(q, dim=0), spz.means.quantile(q, dim=0), atol=3e-4)
    assert ((ply.quats * spz.quats).sum(1).abs() > 0.999).all()  # q and -q are one rotation
    rgb_ply, rgb_spz = 0.5 + SH_C0 * ply.sh[:, 0], 0.5 + SH_C0 * spz.sh[:, 0]
    assert (rgb_ply - rgb_spz).abs().max() < 2 / 255
    assert (ply.opacities - spz.opacities).abs().max() < 1 / 255
    # spz log-scales are 8-bit steps of 1/16 from -10 up; below that they saturate.
    both = (ply.log_scales > -9.9) & (spz.log_scales > -9.9)
    assert (ply.log_scales - spz.log_scales)[both].abs().max() < 1 / 16


@needs_real
@pytest.mark.parametrize("name", COUNTS)
def test_real_file_renders_a_non_empty_view(name):
    scene = real(name)
    out = render(scene, camera_at_bbox_centre(scene.means), backend="torch")
    assert torch.isfinite(out.rgb).all() and torch.isfinite(out.alpha).all()
    assert float(out.alpha.mean()) > 0.05
    assert float((out.alpha > 0.5).float().mean()) > 0.02


@needs_real
@pytest.mark.parametrize("name", COUNTS)
def test_real_file_round_trips_through_the_ply_writer(tmp_path, name):
    scene = real(name)
    write_ply(scene, tmp_path / "scene.ply")
    back = read_ply(tmp_path / "scene.ply")
    for field in FIELDS:
        assert torch.equal(getattr(back, field).view(torch.int32), getattr(scene, field).view(torch.int32)), field


@needs_real
def test_truncated_real_files_are_one_line_errors(tmp_path):
    for name, reader in (("playcanvas/biker.spz", read_spz), ("playcanvas/guitar.compressed.ply", read_compressed_ply)):
        cut = tmp_path / Path(name).name
        cut.write_bytes((REAL / name).read_bytes()[:5000])
        assert str(cut) in one_line_error(reader, cut)


# --- import and render through the CLI ----------------------------------------------------------


@needs_real
@pytest.mark.parametrize("name", COUNTS)
def test_import_real_file_as_a_scene_directory(tmp_path, name):
    dst = import_scene(REAL / name, tmp_path / "scene")
    assert sorted(p.name for p in dst.iterdir()) == ["scene.json", "scene.ply"]
    loaded = load_scene_dir(dst)
    assert loaded.cameras == [] and loaded.metadata.up is None
    assert torch.equal(loaded.gaussians.means, real(name).means)


@needs_real
def test_cli_imports_an_spz_and_renders_it(tmp_path, capsys):
    assert main(["import", str(REAL / "playcanvas/biker.spz"), str(tmp_path / "biker")]) == 0
    scene = load_scene_dir(tmp_path / "biker").gaussians
    write_camera_json(camera_at_bbox_centre(scene.means), tmp_path / "camera.json")
    args = ["render", str(tmp_path / "biker"), "--camera", str(tmp_path / "camera.json"), "-o", str(tmp_path / "out.png")]
    assert main([*args, "--backend", "torch"]) == 0
    image = np.asarray(Image.open(tmp_path / "out.png"))
    assert image.shape == (48, 64, 3) and (image.max(axis=2) > 20).mean() > 0.05


# --- hand-built files ---------------------------------------------------------------------------


def splat_record(position, scale, rgba, quat_bytes) -> bytes:
    return struct.pack("<3f3f4B4B", *position, *scale, *rgba, *quat_bytes)


def test_two_splat_file_decodes_exactly(tmp_path):
    path = tmp_path / "two.splat"
    path.write_bytes(
        splat_record((1.5, -2.0, 0.25), (0.5, 2.0, 0.125), (255, 0, 51, 128), (192, 192, 128, 128))
        + splat_record((0.0, 1e3, -7.0), (1.0, 1.0, 1.0), (128, 128, 128, 255), (255, 128, 128, 128))
    )
    scene = read_splat(path)
    assert torch.equal(scene.means, torch.tensor([[1.5, -2.0, 0.25], [0.0, 1e3, -7.0]]))
    assert torch.allclose(scene.scales, torch.tensor([[0.5, 2.0, 0.125], [1.0, 1.0, 1.0]]))
    rgb = torch.tensor([[1.0, 0.0, 0.2], [128 / 255] * 3])
    assert torch.allclose(scene.sh[:, 0], (rgb - 0.5) / SH_C0, atol=1e-6) and scene.sh_degree == 0
    assert torch.allclose(scene.opacities, torch.tensor([128 / 255, 1.0]), atol=1e-6)
    # (192, 192, 128, 128) is (0.5, 0.5, 0, 0) -> normalised; (255, 128, 128, 128) is (127/128, 0, 0, 0).
    h = 0.5**0.5
    assert torch.allclose(scene.quats, torch.tensor([[h, h, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]), atol=1e-7)
    assert torch.equal(read_gaussians(path).means, scene.means)


def test_malformed_splat_files_are_one_line_errors(tmp_path):
    path = tmp_path / "bad.splat"
    path.write_bytes(splat_record((0, 0, 0), (1, 1, 1), (0, 0, 0, 0), (128, 128, 128, 255)) + b"\0")
    assert f"{path}: size 33 bytes is not a multiple of 32" in one_line_error(read_splat, path)
    path.write_bytes(b"")
    assert f"{path}: holds no Gaussians" in one_line_error(read_splat, path)
    path.write_bytes(splat_record((0, 0, 0), (0, 1, 1), (0, 0, 0, 0), (128, 128, 128, 255)))
    assert "non-finite 'log_scales'" in one_line_error(read_splat, path)


def spz_v3(positions, alphas, colors, log_scales, xyzw, sh=None, fractional_bits=12) -> bytes:
    """A gzipped version-3 .spz, packed by hand from the format description (xyzw unit quaternions)."""
    n, degree = len(positions), {None: 0, 3: 1}[None if sh is None else sh.shape[1]]
    fixed = np.round(np.asarray(positions) * (1 << fractional_bits)).astype(np.int32) & 0xFFFFFF
    pos = np.stack([fixed & 0xFF, (fixed >> 8) & 0xFF, fixed >> 16], axis=-1).astype(np.uint8)
    words = []
    for q in np.asarray(xyzw, dtype=np.float64):
        q = q if q[np.abs(q).argmax()] > 0 else -q
        big, word = int(np.abs(q).argmax()), 0
        for i in (0, 1, 2, 3):  # the last one packed ends up in the lowest bits
            if i != big:
                word = (word << 10) | (int(q[i] < 0) << 9) | int(round(abs(q[i]) / 0.5**0.5 * 511))
        words.append(word | (big << 30))
    body = struct.pack("<IIIBBBB", 0x5053474E, 3, n, degree, fractional_bits, 0, 0)
    body += pos.tobytes() + np.asarray(alphas, np.uint8).tobytes() + np.asarray(colors, np.uint8).tobytes()
    body += np.round((np.asarray(log_scales) + 10) * 16).astype(np.uint8).tobytes() + np.asarray(words, "<u4").tobytes()
    if sh is not None:
        body += np.asarray(sh, np.uint8).tobytes()
    return gzip.compress(body)


def test_hand_packed_spz_decodes_with_and_without_the_axis_turn(tmp_path):
    xyzw = np.array([[0.1, -0.2, 0.3, 0.0], [0.0, 0.6, 0.0, 0.8]])
    xyzw[0, 3] = np.sqrt(1 - 0.14)
    sh = np.full((2, 3, 3), 128, np.uint8)
    sh[0, 0] = (192, 64, 128)  # band 1, coefficient 0 (y-like): +0.5, -0.5, 0 per channel
    sh[0, 2] = (160, 160, 160)  # band 1, coefficient 2 (x-like): +0.25
    path = tmp_path / "two.spz"
    colors, log_scales = [[230] * 3, [25] * 3], [[-1, 0, 0.5]] * 2
    path.write_bytes(spz_v3([[1.5, -2.25, 0.125], [-0.5, 0.0, 3.0]], [128, 255], colors, log_scales, xyzw, sh))
    raw = read_spz(path, to_rdf=False)
    assert torch.equal(raw.means, torch.tensor([[1.5, -2.25, 0.125], [-0.5, 0.0, 3.0]]))
    assert torch.equal(raw.log_scales, torch.tensor([[-1.0, 0.0, 0.5]] * 2))
    assert torch.allclose(raw.opacities, torch.tensor([128 / 255, 1.0]), atol=1e-6)
    assert torch.allclose(raw.sh[:, 0, 0], torch.tensor([(230 / 255 - 0.5) / 0.15, (25 / 255 - 0.5) / 0.15]))
    wxyz = torch.tensor(xyzw[:, [3, 0, 1, 2]], dtype=torch.float32)
    assert ((raw.quats * wxyz).sum(1).abs() > 1 - 1e-5).all()
    assert torch.allclose(raw.sh[0, 1], torch.tensor([0.5, -0.5, 0.0])) and torch.allclose(raw.sh[0, 3], torch.full((3,), 0.25))
    # RUB -> RDF: y and z negate, and so do the y- and z-odd SH basis functions (band 1: y, z, x).
    turned = read_spz(path)
    assert torch.equal(turned.means, raw.means * torch.tensor([1.0, -1.0, -1.0]))
    assert torch.allclose(turned.quats, raw.quats * torch.tensor([1.0, 1.0, -1.0, -1.0]))
    assert torch.equal(turned.sh[:, 1:], raw.sh[:, 1:] * torch.tensor([-1.0, -1.0, 1.0])[:, None])


def test_malformed_spz_files_are_one_line_errors(tmp_path):
    path = tmp_path / "bad.spz"
    path.write_bytes(b"NOPE" + bytes(60))
    assert f"{path}: not an .spz file" in one_line_error(read_spz, path)
    path.write_bytes(spz_v3([[0, 0, 0]], [1], [1, 2, 3], [[0, 0, 0]], [[0, 0, 0, 1]])[:-9])
    assert str(path) in one_line_error(read_spz, path)
    path.write_bytes(gzip.compress(struct.pack("<IIIBBBB", 0x5053474E, 3, 0, 0, 12, 0, 0)))
    assert "holds no Gaussians" in one_line_error(read_spz, path)
    path.write_bytes(gzip.compress(struct.pack("<IIIBBBB", 0x5053474E, 7, 1, 0, 12, 0, 0)))
    assert "spz version 7" in one_line_error(read_spz, path)


def test_compressed_ply_matches_gsplat_export(tmp_path):
    """gsplat's own compressed-PLY writer is an independent encoder: decoding its output gives the
    Gaussians back within the quantisation steps (it sorts the splats, so they are matched by position)."""
    exporter = pytest.importorskip("gsplat.exporter")
    g = torch.Generator().manual_seed(0)
    n = 300
    means = torch.rand(n, 3, generator=g) * torch.tensor([1.0, 2.0, 0.5])
    log_scales = torch.rand(n, 3, generator=g) * 3 - 6
    quats = torch.randn(n, 4, generator=g)
    quats = quats / quats.norm(dim=1, keepdim=True)
    opacity_logits = torch.rand(n, generator=g) * 6 - 2
    sh0, shN = torch.rand(n, 1, 3, generator=g) * 2 - 1, torch.rand(n, 3, 3, generator=g) * 0.6 - 0.3
    exporter.export_splats(means, log_scales, quats, opacity_logits, sh0, shN, "ply_compressed", str(tmp_path / "g.ply"))
    scene = read_gaussians(tmp_path / "g.ply")
    assert len(scene) == n and scene.sh_degree == 1
    order = torch.cdist(scene.means, means).argmin(dim=1)
    assert sorted(order.tolist()) == list(range(n))
    assert (scene.means - means[order]).abs().max() < 2.0 / 1023  # 10-bit y step of a chunk box of size <= 2
    assert (scene.log_scales - log_scales[order]).abs().max() < 3.0 / 1023
    assert ((scene.quats * quats[order]).sum(1).abs() > 0.999).all()
    assert (scene.opacities - torch.sigmoid(opacity_logits[order])).abs().max() < 0.5 / 255 + 1e-6
    rgb, rgb_in = 0.5 + SH_C0 * scene.sh[:, 0], 0.5 + SH_C0 * sh0[order, 0]
    assert (rgb - rgb_in).abs().max() < 1 / 255
    assert (scene.sh[:, 1:] - shN[order]).abs().max() < 8 / 256  # 8-bit steps over [-4, 4]


def test_ply_with_no_gaussians_is_a_one_line_error(tmp_path):
    path = tmp_path / "empty.ply"
    names = ["x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2"]
    names += ["rot_0", "rot_1", "rot_2", "rot_3"]
    header = "ply\nformat binary_little_endian 1.0\nelement vertex 0\n" + "".join(f"property float {p}\n" for p in names)
    path.write_text(header + "end_header\n")
    assert f"{path}: holds no Gaussians" in one_line_error(read_gaussians, path)
    compressed = "ply\nformat binary_little_endian 1.0\nelement chunk 0\nproperty float min_x\nelement vertex 0\n"
    path.write_text(compressed + "property uint packed_position\nend_header\n")
    assert str(path) in one_line_error(read_gaussians, path)


def test_nerfstudio_rgb_export_reads_as_dc(tmp_path):
    """nerfstudio writes uchar red/green/blue instead of f_dc_* for a degree-0 model."""
    path = tmp_path / "ns.ply"
    props = [("x", "f4"), ("y", "f4"), ("z", "f4"), ("nx", "f4"), ("ny", "f4"), ("nz", "f4")]
    props += [("red", "u1"), ("green", "u1"), ("blue", "u1"), ("opacity", "f4")]
    props += [(f"scale_{i}", "f4") for i in range(3)] + [(f"rot_{i}", "f4") for i in range(4)]
    rows = np.zeros(2, dtype=[(p, "<" + t) for p, t in props])
    rows["red"], rows["green"], rows["blue"], rows["rot_0"] = [255, 0], [0, 51], [102, 255], 1.0
    types = {"f4": "float", "u1": "uchar"}
    header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n" + "".join(f"property {types[t]} {p}\n" for p, t in props)
    path.write_bytes((header + "end_header\n").encode() + rows.tobytes())
    rgb = torch.tensor([[1.0, 0.0, 0.4], [0.0, 0.2, 1.0]])
    assert torch.allclose(read_ply(path).sh[:, 0], (rgb - 0.5) / SH_C0, atol=1e-6)


def test_unknown_suffix_is_a_one_line_error(tmp_path):
    path = tmp_path / "scene.ksplat"
    path.write_bytes(b"\0" * 64)
    assert "unknown 3DGS file type '.ksplat'" in one_line_error(read_gaussians, path)
