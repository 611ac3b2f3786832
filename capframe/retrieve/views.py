"""Label renders of the training views, measured once per scene (the embedded perception tier).

For every training view and every object of the semantic sidecar this records what a perfect
segmenter would report: the object's visible share, the share inside the frame, the centre of its
visible mask, its projected size, plus the view's label map and rendered depth (for the
mask back-projection path of Translate). Every instruction on the scene reuses the file.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from ..render import NEAR_FRACTION, prepare
from ..render.masks import subject_masks
from ..scene import Camera, SceneDir
from ..scene._io import write_npz

VIEWS_LONG_SIDE = 160  # measurement resolution (longer side, pixels)
FORMAT = 1


@dataclass
class ViewMeasurements:
    """What each training view shows of each labelled object. V views, O objects, H x W pixels.

    Attributes:
        view_names: (V,) training view names.
        object_names: (O,) sidecar object names, in sidecar order.
        cameras: (V,) the views at the measurement resolution.
        visible_fraction: (V, O) share of the object's in-frame alpha not hidden by others.
        in_frame: (V, O) share of the object's projection inside the frame.
        centroid: (V, O, 2) centre of the visible mask, normalised (x, y); NaN when not visible.
        extent: (V, O) max(bbox width / W, bbox height / H) of the object's own mask.
        pixels: (V, O) pixels of the object's own mask in the frame.
        label_map: (V, H, W) int16 object index (column of the arrays above) or -1.
        depth: (V, H, W) float32 alpha-normalised depth, 0 where nothing is rendered.
    """

    view_names: list[str]
    object_names: list[str]
    cameras: list[Camera]
    visible_fraction: np.ndarray
    in_frame: np.ndarray
    centroid: np.ndarray
    extent: np.ndarray
    pixels: np.ndarray
    label_map: np.ndarray
    depth: np.ndarray

    def object_index(self, name: str) -> int:
        return self.object_names.index(name)


def measure_views(
    scene: SceneDir, long_side: int = VIEWS_LONG_SIDE, cameras: list[Camera] | None = None, objects: list[str] | None = None
) -> ViewMeasurements:
    """Render and measure every training view of ``scene`` (which needs Gaussians and a semantic
    sidecar), or the given ``cameras`` (candidate poses of a view search), all of one image size;
    every labelled object, or only those named in ``objects`` (each costs one render per view;
    the others still occlude)."""
    gaussians = scene.gaussians
    objects = [o for o in scene.semantics if objects is None or o.name in objects]
    members = torch.stack([gaussians.labels == o.id for o in objects], 1)
    prepared = prepare(gaussians)
    near = NEAR_FRACTION * prepared.extent
    named = scene.cameras if cameras is None else cameras
    cameras = [c.with_long_side(long_side) for c in named]
    n_views, n_objects = len(cameras), len(objects)
    H, W = cameras[0].height, cameras[0].width
    fields = {k: np.zeros((n_views, n_objects)) for k in ("visible_fraction", "in_frame", "extent", "pixels")}
    centroid = np.full((n_views, n_objects, 2), np.nan)
    label_map = np.full((n_views, H, W), -1, dtype=np.int16)
    depth = np.zeros((n_views, H, W), dtype=np.float32)
    for v, camera in enumerate(cameras):
        if (camera.height, camera.width) != (H, W):
            raise InputError(
                f"view {camera.name!r} is {camera.width}x{camera.height}, the first is {W}x{H}; retrieval expects one image size",
                source=str(scene.root),
            )
        masks, full = subject_masks(prepared, camera, members, near=near)
        for o, mask in enumerate(masks):
            fields["visible_fraction"][v, o] = mask.visible_fraction
            fields["in_frame"][v, o] = mask.in_frame
            fields["extent"][v, o] = mask.extent()
            fields["pixels"][v, o] = mask.pixels
            if (c := mask.centroid()) is not None:
                centroid[v, o] = c
        share = full.extra.cpu()  # (H, W, O) each object's visible alpha
        best = share.max(-1)
        label_map[v] = np.where(best.values.numpy() > 0.5, best.indices.numpy(), -1)
        depth[v] = full.depth.cpu().numpy()
    return ViewMeasurements(
        [c.name for c in named], [o.name for o in objects], cameras, centroid=centroid, label_map=label_map, depth=depth, **fields
    )


def scene_fingerprint(scene: SceneDir, long_side: int) -> str:
    """Changes whenever the measurements would: the PLY, the labels, the cameras, the resolution."""
    h = hashlib.sha256(f"{FORMAT}:{long_side}".encode())
    for name in ("scene.ply", "labels.npy", "semantics.json"):
        stat = (scene.root / name).stat()
        h.update(f"{name}:{stat.st_size}:{stat.st_mtime_ns}".encode())
    for c in scene.cameras:
        h.update(c.name.encode() + np.ascontiguousarray(c.T_cw).tobytes() + np.ascontiguousarray(c.K).tobytes())
        h.update(f"{c.width}x{c.height}".encode())
    return h.hexdigest()[:16]


def save_view_measurements(m: ViewMeasurements, path: str | Path, fingerprint: str) -> None:
    """Write ``m`` as one ``.npz``, atomically."""
    meta = {
        "format": FORMAT,
        "fingerprint": fingerprint,
        "view_names": m.view_names,
        "object_names": m.object_names,
        "cameras": [
            {"name": c.name, "T_cw": c.T_cw.tolist(), "K": c.K.tolist(), "width": c.width, "height": c.height} for c in m.cameras
        ],
    }
    write_npz(
        path,
        meta,
        visible_fraction=m.visible_fraction,
        in_frame=m.in_frame,
        centroid=m.centroid,
        extent=m.extent,
        pixels=m.pixels,
        label_map=m.label_map,
        depth=m.depth,
    )


def load_view_measurements(path: str | Path, fingerprint: str | None = None) -> ViewMeasurements | None:
    """Read a file of :func:`save_view_measurements`; None when it is absent or stale (another
    fingerprint), :class:`InputError` when it is unreadable."""
    path = Path(path)
    if not path.is_file():
        return None
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            if meta.get("format") != FORMAT or (fingerprint is not None and meta.get("fingerprint") != fingerprint):
                return None
            arrays = {k: data[k] for k in ("visible_fraction", "in_frame", "centroid", "extent", "pixels", "label_map", "depth")}
    except (OSError, ValueError, KeyError) as err:
        raise InputError(f"unreadable view measurements ({err}); delete the file to recompute it", source=str(path)) from None
    cameras = [
        Camera(np.asarray(c["T_cw"]), np.asarray(c["K"]), c["width"], c["height"], name=c["name"]) for c in meta["cameras"]
    ]
    return ViewMeasurements(meta["view_names"], meta["object_names"], cameras, **arrays)


def cached_view_measurements(scene: SceneDir, cache_dir: str | Path, long_side: int = VIEWS_LONG_SIDE) -> ViewMeasurements:
    """The scene's measurements from ``cache_dir/label_views.npz``, computed and written when absent
    or stale."""
    fingerprint = scene_fingerprint(scene, long_side)
    path = Path(cache_dir) / "label_views.npz"
    measurements = load_view_measurements(path, fingerprint)
    if measurements is None:
        measurements = measure_views(scene, long_side)
        save_view_measurements(measurements, path, fingerprint)
    return measurements


def views_command(scene_dir: str | Path, output: str | Path, long_side: int = VIEWS_LONG_SIDE) -> None:
    """``capframe views``: measure the training views of a scene into ``output``."""
    from ..scene import load_scene_dir

    scene = load_scene_dir(scene_dir)
    if scene.gaussians is None or not scene.cameras or scene.semantics is None:
        raise InputError("needs scene.ply, training cameras and a semantic sidecar to measure its views", source=str(scene_dir))
    save_view_measurements(measure_views(scene, long_side), output, scene_fingerprint(scene, long_side))
    print(f"{output}: {len(scene.cameras)} views x {len(scene.semantics)} objects")
