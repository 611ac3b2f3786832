"""Translate: subject grounding by labels and by back-projected 2D masks + KNN."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from _synth_helpers import build_scene

from capframe.errors import InputError
from capframe.retrieve.views import measure_views
from capframe.scene import load_scene_dir
from capframe.translate.grounding import back_project, ground_by_labels, ground_by_masks, knn_members


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    root = tmp_path_factory.mktemp("grounding") / "scene"
    gt = build_scene(root)
    return load_scene_dir(root), gt


def test_back_projection_inverts_projection(scene):
    s, _ = scene
    camera = s.cameras[0]
    rng = np.random.default_rng(0)
    u, v = rng.integers(0, camera.width, 50), rng.integers(0, camera.height, 50)
    depth = np.zeros((camera.height, camera.width))
    depth[v, u] = rng.uniform(1.0, 9.0, 50)
    mask = depth > 0
    points = back_project(mask, depth, camera)
    q = points @ camera.R.T + camera.t
    pix = q @ camera.K.T
    vv, uu = np.nonzero(mask)
    np.testing.assert_allclose(pix[:, :2] / pix[:, 2:], np.stack([uu + 0.5, vv + 0.5], 1), atol=1e-9)
    np.testing.assert_allclose(q[:, 2], depth[vv, uu], rtol=1e-12)


def test_knn_takes_only_near_neighbours():
    means = torch.tensor([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [10, 10, 10]], dtype=torch.float64)
    assert knn_members(np.array([[0.1, 0.0, 0.0]]), means, k=2, radius=1.5).tolist() == [0, 1]
    assert knn_members(np.array([[5.0, 5.0, 5.0]]), means, k=2, radius=1.5).tolist() == []
    assert knn_members(np.zeros((0, 3)), means).tolist() == []


def test_labels_grounding_reads_ids_and_fronts(scene):
    s, gt = scene
    bear = ground_by_labels("teddy bear", s.gaussians.labels, s.gaussians.means, s.semantics)
    truth = next(o for o in gt["objects"] if o["name"] == "teddy bear")
    assert (s.gaussians.labels[bear.gaussians] == truth["label"]).all()
    np.testing.assert_allclose(bear.front, truth["front"], atol=1e-9)
    assert ground_by_labels("vase", s.gaussians.labels, s.gaussians.means, s.semantics).front is None
    with pytest.raises(InputError, match="not in the semantic sidecar"):
        ground_by_labels("giraffe", s.gaussians.labels, s.gaussians.means, s.semantics)


@pytest.mark.parametrize("name", ["teddy bear", "red armchair", "vase"])
def test_mask_grounding_recovers_the_labelled_subject(scene, name):
    """Label masks of all views back-projected with rendered depth find the subject's Gaussians:
    nearly all of them are the subject's, the surface ones are found, and the centroid lands well
    inside it (it leans to the seen side, as in the paper's method)."""
    s, gt = scene
    m = measure_views(s)
    o = m.object_index(name)
    found = ground_by_masks(
        name, [m.label_map[v] == o for v in range(len(m.cameras))], list(m.depth), m.cameras, s.gaussians.means
    )
    truth = next(x for x in s.semantics if x.name == name)
    own = (s.gaussians.labels == truth.id).numpy()
    precision = own[found.gaussians].mean()
    recall = own[found.gaussians].sum() / own.sum()
    assert precision > 0.9 and recall > 0.4
    label_centroid = s.gaussians.means[torch.from_numpy(own)].double().mean(0).numpy()
    radius = next(o for o in gt["objects"] if o["id"] == truth.id)["radius"]
    assert np.linalg.norm(found.centroid - label_centroid) < 0.35 * radius


def test_empty_masks_are_an_error(scene):
    s, _ = scene
    empty = np.zeros((120, 160), dtype=bool)
    with pytest.raises(InputError, match="empty in every retrieved view"):
        ground_by_masks("vase", [empty], [np.ones((120, 160))], [s.cameras[0].with_long_side(160)], s.gaussians.means)
