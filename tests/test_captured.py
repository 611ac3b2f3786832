"""Captured 3DGS objects in the synth catalog (config/captured.yaml, files in ../shared/data/real):
the annotation file's contract, the upright turn on hand-checkable axes, and on the real files:
size, base, upright and front as annotated, and a scene whose labels, front and scale match."""

from __future__ import annotations

import math

import numpy as np
import pytest

from capframe.errors import InputError
from capframe.scene import load_scene_dir
from capframe.synth.captured import (
    CapturedSource,
    captured_arrays,
    floater_fraction,
    load_captured,
    robust_box,
    upright_rotation,
)
from capframe.synth.generator import build_scene, write_scene
from capframe.synth.objects import CATALOG, PARAMETRIC, build_object, catalog_names

SOURCES = {s.name: s for s in load_captured()}
needs_real = pytest.mark.skipif(
    not all(s.path.is_file() for s in SOURCES.values()), reason="real test data not found (shared/data/real)"
)


def one_line_error(fn, *args) -> str:
    with pytest.raises(InputError) as info:
        fn(*args)
    assert "\n" not in str(info.value)
    return str(info.value)


@pytest.mark.parametrize(
    "up,front,axis,image",
    [
        ("-y", None, (0, -1, 0), (0, 0, 1)),
        ("+z", None, (0, 0, 1), (0, 0, 1)),
        ("-z", None, (0, 0, -1), (0, 0, 1)),
        ("+x", None, (1, 0, 0), (0, 0, 1)),
        ("+z", 90.0, (0, 1, 0), (1, 0, 0)),  # a front at azimuth 90 (+y) is turned onto +x
        ("-y", 180.0, (0, -1, 0), (0, 0, 1)),  # the yaw keeps up
    ],
)
def test_upright_rotation_on_axes(up, front, axis, image):
    R = upright_rotation(up, front)
    assert np.allclose(R @ R.T, np.eye(3)) and np.linalg.det(R) == pytest.approx(1.0)
    assert np.allclose(R @ np.asarray(axis, dtype=float), image, atol=1e-12)


def test_catalog_keeps_parametric_order_and_adds_the_captured_objects():
    names = catalog_names()
    assert tuple(names[: len(PARAMETRIC)]) == tuple(sorted(PARAMETRIC))  # the parametric random streams are unchanged
    assert set(names[len(PARAMETRIC) :]) == set(SOURCES)
    for name, source in SOURCES.items():
        spec = CATALOG[name]
        assert spec.captured == source and spec.symmetric == (source.front_deg is None)
    vocabulary = [n for s in CATALOG.values() for n in (s.name, *s.aliases)]
    assert len(vocabulary) == len(set(vocabulary))  # no name or alias answers for two objects


def test_malformed_annotation_files_are_one_line_errors(tmp_path):
    entry = (
        "{name: x, aliases: [], file: a.splat, up: -y, front_deg: null, size_m: 1, measure: height, "
        "color: red, target: 9, credits: c}"
    )
    cases = {
        "objects: []": "root",
        f"root: .\nobjects: [{entry.replace('up: -y', 'up: y')}]": "objects[0].up: 'y'",
        f"root: .\nobjects: [{entry.replace('measure: height', 'measure: depth')}]": "measure",
        f"root: .\nobjects: [{entry.replace('size_m: 1', 'size_m: -1')}]": "size_m -1",
        f"root: .\nobjects: [{entry.replace(', credits: c', '')}]": "expected exactly",
        "root: .\nobjects: [": "cannot read",
    }
    for text, expected in cases.items():
        path = tmp_path / "captured.yaml"
        path.write_text(text)
        message = one_line_error(load_captured, path)
        assert str(path) in message and expected in message, message


def test_absent_file_is_a_one_line_error_naming_it(tmp_path):
    source = CapturedSource("ghost", (), tmp_path / "nothing.splat", "-y", None, 1.0, "height", "red", 10, "")
    message = one_line_error(captured_arrays, source)
    assert "nothing.splat" in message and "not found" in message


@needs_real
@pytest.mark.parametrize("name", sorted(SOURCES))
def test_captured_object_is_upright_at_its_real_size(name):
    source = SOURCES[name]
    obj = build_object(name, seed=0, density=0.5)
    g = obj.gaussians
    assert len(g) == round(source.target * 0.5) and obj.color == source.color
    for field in ("means", "quats", "scales", "opacities", "rgb", "normals"):
        assert np.isfinite(getattr(g, field)).all(), field
    assert np.allclose(np.linalg.norm(g.normals, axis=1), 1.0)
    assert g.means[:, 2].min() == 0.0  # stands on z = 0
    lo, hi = robust_box(g.means)
    measured = hi[2] - lo[2] if source.measure == "height" else (hi - lo)[:2].max()
    # Scaled on all cleaned Gaussians; the thinned half spans nearly the same box.
    assert measured == pytest.approx(source.size_m, rel=0.03)
    assert np.abs((lo + hi)[:2] / 2).max() < 0.03 * (hi - lo).max()  # centred over the origin
    assert g.emissive.all()  # the capture's colours carry its lighting; none is baked on top
    assert 0.0 <= floater_fraction(source) < 0.01


def _colour_height(name: str, mask) -> float:
    g = build_object(name, seed=0).gaussians
    return float(g.means[mask(g.rgb), 2].mean() / g.means[:, 2].max())


@needs_real
def test_captured_up_axes_put_the_pot_and_the_dough_at_the_bottom():
    green = lambda c: (c[:, 1] > c[:, 0] + 0.05) & (c[:, 1] > c[:, 2] + 0.05)  # noqa: E731
    white = lambda c: c.min(1) > 0.75  # noqa: E731
    pink = lambda c: (c[:, 0] > 0.6) & (c[:, 2] > 0.5) & (c[:, 1] < c[:, 0] - 0.15)  # noqa: E731
    assert (
        _colour_height("rubber plant", green) > 0.55 and _colour_height("rubber plant", white) < 0.35
    )  # leaves over a white pot
    assert _colour_height("donut", pink) > 0.6  # the icing on top


@needs_real
def test_captured_fronts_face_plus_x():
    """The annotated fronts, on colour facts seen in the renders from four sides: the box's printed
    title and the guitar's sunburst top are brighter than their backs; the biker's skin-coloured
    face is ahead of the rest of his head."""
    for name in ("tarot box", "electric guitar"):
        g = build_object(name, seed=0).gaussians
        front = g.means[:, 0] > np.median(g.means[:, 0])
        assert g.rgb[front].mean() > 1.2 * g.rgb[~front].mean(), name
    g = build_object("biker", seed=0).gaussians
    head = g.means[:, 2] > 0.85 * g.means[:, 2].max()
    c = g.rgb
    skin = head & (c[:, 0] > 0.35) & (c[:, 0] > c[:, 1] + 0.05) & (c[:, 1] > c[:, 2])
    assert skin.sum() > 100 and g.means[skin, 0].mean() > g.means[head, 0].mean() + 0.01


@needs_real
def test_captured_objects_synthesise_with_labels_front_and_scale(tmp_path):
    scale = 4.0
    scene = build_scene(
        seed=7, preset="tabletop", objects=["tarot box", "donut", "mug"], views=4, scale=scale, density=0.3, resolution=(64, 48)
    )
    write_scene(scene, tmp_path / "s", images=None)
    loaded = load_scene_dir(tmp_path / "s")
    labels = loaded.gaussians.labels.numpy()
    means = loaded.gaussians.means.double().numpy()
    gt = scene.ground_truth
    up = np.asarray(gt["up"])
    by_name = {o["name"]: o for o in gt["objects"]}
    for name in ("tarot box", "donut"):
        o, source = by_name[name], SOURCES[name]
        a, b = o["gaussians"]
        assert b - a == round(source.target * 0.3)
        assert (labels[a:b] == o["label"]).all() and (labels == o["label"]).sum() == b - a  # every one, and no other
        semantic = next(s for s in loaded.semantics if s.id == o["id"])
        assert semantic.name == name and set(source.aliases) <= set(semantic.aliases)
        # Untilted (up = +z) and yawed: the height is along z, the width is the box's largest.
        assert np.allclose(up, [0.0, 0.0, 1.0])
        lo, hi = robust_box(means[a:b])
        yaw = math.radians(o["yaw_deg"])
        axes = np.array([[math.cos(yaw), math.sin(yaw)], [-math.sin(yaw), math.cos(yaw)]])
        local_lo, local_hi = robust_box(np.c_[means[a:b, :2] @ axes.T, means[a:b, 2]])
        size = hi[2] - lo[2] if source.measure == "height" else (local_hi - local_lo)[:2].max()
        assert size == pytest.approx(scale * source.size_m, rel=0.05)
    box = by_name["tarot box"]
    yaw = math.radians(box["yaw_deg"])
    assert np.allclose(box["front"], [math.cos(yaw), math.sin(yaw), 0.0])  # the annotated front (+x) turned by the yaw
    assert np.allclose(next(s for s in loaded.semantics if s.name == "tarot box").front, box["front"])
    assert by_name["donut"]["front"] is None and by_name["donut"]["symmetric"]
