"""The scene directory: what every stage reads a scene from (contract: docs/scene-directory.md).

::

    scene.ply          Inria 3DGS PLY (absent only for a COLMAP import without a trained 3DGS)
    cameras.json       Inria cameras.json, the training cameras (absent when the scene has no poses yet)
    images/            training images, named <img_name>.<ext>
    sparse/0/          optional COLMAP model
    scene.json         optional {"format": 1, "up": [x, y, z] | null, "aligned": bool}
    semantics.json     optional {"objects": [{id, name, aliases, symmetric, front}, ...]}
    labels.npy         with semantics.json: (N,) int32 label id per Gaussian, -1 unlabelled
    gravity.json       optional, written by the gravity stage
    ground_truth.json  synthetic scenes only; evaluation only, never read by the method (nor here)

:func:`import_scene` turns an Inria 3DGS output, a COLMAP dataset, a nerfstudio dataset or a single
3DGS file (``.ply``, ``.compressed.ply``, ``.splat``, ``.spz``) into this layout; :func:`load_scene_dir`
reads it.
"""

from __future__ import annotations

import dataclasses
import io
import os
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from ._io import as_direction, atomic_directory, atomic_write, read_json, require_keys, write_json
from .cameras_json import read_cameras_json, write_cameras_json
from .colmap import read_colmap
from .formats import read_gaussians
from .model import Camera, GaussianScene
from .nerfstudio import read_transforms_json
from .ply import read_ply, write_ply

SCENE_FORMAT = 1


@dataclass
class SceneMeta:
    """Contents of ``scene.json``.

    Attributes:
        up: (3,) unit world-up vector, or ``None`` until the gravity stage has estimated it.
        aligned: whether the scene's world has been gravity-aligned.
    """

    up: np.ndarray | None = None
    aligned: bool = False


@dataclass
class SemanticObject:
    """One labelled object of the semantic sidecar.

    Attributes:
        id: label id used in ``labels.npy`` (>= 0).
        name: the object's name; subjects are matched by name or alias, never by position.
        aliases: other names for it.
        symmetric: whether the object has no canonical front.
        front: (3,) unit world direction the object faces, or ``None`` (symmetric or unannotated).
    """

    id: int
    name: str
    aliases: list[str] = field(default_factory=list)
    symmetric: bool = False
    front: np.ndarray | None = None


@dataclass
class SceneDir:
    """A loaded scene directory.

    Attributes:
        root: the directory.
        gaussians: the Gaussians (labels attached when the scene has a semantic sidecar), or
            ``None`` when there is no ``scene.ply`` or it was not asked for.
        cameras: training cameras (from ``cameras.json``, else ``sparse/0``, else ``transforms.json``).
        images_dir: ``root/images`` if it exists.
        metadata: ``scene.json`` (defaults when absent).
        semantics: the objects of ``semantics.json``, or ``None`` without a semantic sidecar.
    """

    root: Path
    gaussians: GaussianScene | None
    cameras: list[Camera]
    images_dir: Path | None
    metadata: SceneMeta
    semantics: list[SemanticObject] | None


def read_scene_meta(path: str | Path) -> SceneMeta:
    """Read ``scene.json``; :class:`InputError` naming it for an unknown format or invalid fields."""
    source = str(path)
    data = read_json(path)
    require_keys(data, ("format",), "scene.json", source)
    if data["format"] != SCENE_FORMAT:
        raise InputError(f"'format' is {data['format']!r}; this version reads format {SCENE_FORMAT}", source=source)
    aligned = data.get("aligned", False)
    if not isinstance(aligned, bool):
        raise InputError(f"'aligned' is {aligned!r}; expected true or false", source=source)
    up = data.get("up")
    return SceneMeta(up=None if up is None else as_direction(up, "'up'", source), aligned=aligned)


def write_scene_meta(meta: SceneMeta, path: str | Path) -> None:
    """Write ``scene.json``, atomically."""
    up = None if meta.up is None else np.asarray(meta.up, dtype=np.float64).tolist()
    write_json(path, {"format": SCENE_FORMAT, "up": up, "aligned": bool(meta.aligned)})


def read_semantics(path: str | Path) -> list[SemanticObject]:
    """Read ``semantics.json``: ``id`` and ``name`` are required, ``aliases`` (default ``[]``),
    ``symmetric`` (default false) and ``front`` (default null) optional. Ids and names must be unique."""
    source = str(path)
    data = read_json(path)
    require_keys(data, ("objects",), "semantics.json", source)
    if not isinstance(data["objects"], list):
        raise InputError("'objects' is not a list", source=source)
    objects = []
    for i, entry in enumerate(data["objects"]):
        require_keys(entry, ("id", "name"), f"object {i}", source)
        oid, name = entry["id"], entry["name"]
        aliases, symmetric, front = entry.get("aliases", []), entry.get("symmetric", False), entry.get("front")
        if isinstance(oid, bool) or not isinstance(oid, int) or oid < 0:
            raise InputError(f"object {i}: 'id' is {oid!r}; expected an integer >= 0", source=source)
        if not isinstance(name, str) or not name:
            raise InputError(f"object {i}: 'name' is {name!r}; expected a non-empty string", source=source)
        if not isinstance(aliases, list) or not all(isinstance(a, str) for a in aliases):
            raise InputError(f"object {i} ('{name}'): 'aliases' is {aliases!r}; expected a list of strings", source=source)
        if not isinstance(symmetric, bool):
            raise InputError(f"object {i} ('{name}'): 'symmetric' is {symmetric!r}; expected true or false", source=source)
        front = None if front is None else as_direction(front, f"object {i} ('{name}') 'front'", source)
        objects.append(SemanticObject(oid, name, aliases, symmetric, front))
    for key in ("id", "name"):
        values = [getattr(o, key) for o in objects]
        duplicates = sorted({v for v in values if values.count(v) > 1}, key=str)
        if duplicates:
            raise InputError(f"duplicate object {key}s {duplicates}; expected unique", source=source)
    return objects


def read_labels(path: str | Path, num_gaussians: int, objects: list[SemanticObject]) -> torch.Tensor:
    """Read ``labels.npy``: (N,) integer label ids, -1 or an object's id, N = ``num_gaussians``.

    Returns an (N,) int64 tensor; :class:`InputError` naming the file otherwise.
    """
    source = str(path)
    try:
        labels = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as err:
        raise InputError(f"not a readable .npy array ({err})", source=source) from None
    if labels.ndim != 1 or not np.issubdtype(labels.dtype, np.integer):
        raise InputError(f"holds a {labels.dtype} array of shape {labels.shape}; expected (N,) integers", source=source)
    if len(labels) != num_gaussians:
        raise InputError(f"has {len(labels)} labels but scene.ply has {num_gaussians} Gaussians", source=source)
    unknown = sorted(set(np.unique(labels).tolist()) - {-1} - {o.id for o in objects})
    if unknown:
        raise InputError(f"label ids {unknown[:10]} are not in semantics.json (and not -1)", source=source)
    return torch.from_numpy(labels.astype(np.int64))


def write_semantics(objects: list[SemanticObject], labels: np.ndarray | torch.Tensor, root: str | Path) -> None:
    """Write the semantic sidecar (``semantics.json`` and ``labels.npy`` as int32) into ``root``."""
    root = Path(root)
    write_json(
        root / "semantics.json",
        {
            "objects": [
                {
                    "id": o.id,
                    "name": o.name,
                    "aliases": list(o.aliases),
                    "symmetric": o.symmetric,
                    "front": None if o.front is None else np.asarray(o.front, dtype=np.float64).tolist(),
                }
                for o in objects
            ]
        },
    )
    buffer = io.BytesIO()
    np.save(buffer, np.asarray(labels, dtype=np.int32))
    atomic_write(root / "labels.npy", buffer.getvalue())


def _read_cameras(root: Path, images_dir: Path | None) -> list[Camera]:
    if (root / "cameras.json").is_file():
        return read_cameras_json(root / "cameras.json", images_dir)
    if (root / "sparse" / "0").is_dir():
        return read_colmap(root / "sparse" / "0", images_dir)
    if (root / "transforms.json").is_file():
        return read_transforms_json(root / "transforms.json")
    return []


def load_scene_dir(path: str | Path, load_gaussians: bool = True) -> SceneDir:
    """Load a scene directory (docs/scene-directory.md). ``ground_truth.json`` is never read.

    With ``load_gaussians=False`` the PLY (and ``labels.npy``, whose length needs it) is skipped,
    for stages that only need cameras and images. Raises :class:`InputError` naming the offending
    file; a directory with neither ``scene.ply`` nor cameras is not a scene.
    """
    root = Path(path)
    if not root.is_dir():
        raise InputError("scene directory not found", source=str(root))
    images_dir = root / "images" if (root / "images").is_dir() else None
    cameras = _read_cameras(root, images_dir)
    ply = root / "scene.ply"
    if not ply.is_file() and not cameras:
        raise InputError(
            "not a scene directory: no scene.ply and no cameras (cameras.json, sparse/0 or transforms.json)",
            source=str(root),
        )
    metadata = read_scene_meta(root / "scene.json") if (root / "scene.json").is_file() else SceneMeta()
    has_semantics, has_labels = (root / "semantics.json").is_file(), (root / "labels.npy").is_file()
    if has_semantics != has_labels:
        present, absent = ("semantics.json", "labels.npy") if has_semantics else ("labels.npy", "semantics.json")
        raise InputError(f"has {present} but no {absent}; the semantic sidecar needs both", source=str(root))
    semantics = read_semantics(root / "semantics.json") if has_semantics else None
    gaussians = read_ply(ply) if load_gaussians and ply.is_file() else None
    if gaussians is not None and semantics is not None:
        gaussians = dataclasses.replace(gaussians, labels=read_labels(root / "labels.npy", len(gaussians), semantics))
    return SceneDir(root, gaussians, cameras, images_dir, metadata, semantics)


# --- import ---------------------------------------------------------------------------------------

_LAYOUTS = (
    "an Inria 3DGS output (point_cloud/iteration_<N>/point_cloud.ply + cameras.json), "
    "a COLMAP dataset (sparse/0/ or sparse/ with cameras, images, points3D .bin/.txt; images/), "
    "a nerfstudio dataset (transforms.json), "
    "or a 3DGS file (.ply, .compressed.ply, .splat, .spz)"
)


def _latest_inria_ply(src: Path) -> Path | None:
    """``point_cloud/iteration_<N>/point_cloud.ply`` with the highest N, if any."""
    found = []
    for folder in (src / "point_cloud").glob("iteration_*"):
        match = re.fullmatch(r"iteration_(\d+)", folder.name)
        if match and (folder / "point_cloud.ply").is_file():
            found.append((int(match.group(1)), folder / "point_cloud.ply"))
    return max(found)[1] if found else None


def _inria_images_dir(src: Path) -> Path | None:
    """The training images of an Inria output: ``<source_path>/<images>`` from its ``cfg_args``
    (a printed argparse Namespace), if that folder exists. A relative ``source_path`` was relative
    to the training run's working folder, unknown here; it is tried from here and from ``src``."""
    cfg = src / "cfg_args"
    if not cfg.is_file():
        return None
    text = cfg.read_text(errors="replace")
    source_path = re.search(r"\bsource_path=(['\"])(.*?)\1", text)
    images = re.search(r"\bimages=(['\"])(.*?)\1", text)
    if source_path is None:
        return None
    base = Path(source_path.group(2))
    for folder in [base] if base.is_absolute() else [Path.cwd() / base, src / base]:
        candidate = folder / (images.group(2) if images else "images")
        if candidate.is_dir():
            return candidate
    return None


def _colmap_model_dir(src: Path) -> Path | None:
    for folder in (src / "sparse" / "0", src / "sparse"):
        if any((folder / f"cameras{suffix}").is_file() for suffix in (".bin", ".txt")):
            return folder
    return None


def _place_images(cameras: list[Camera], images_dir: Path, copy: bool, source: str) -> None:
    """Link (or copy) each camera's image to ``images_dir/<name><ext>``; every camera needs one."""
    missing = [c.name for c in cameras if c.image_path is None]
    if missing:
        raise InputError(f"no image found for cameras {missing[:5]} ({len(missing)} in all)", source=source)
    for cam in cameras:
        target = Path(cam.image_path).resolve()
        link = images_dir / f"{cam.name}{Path(cam.image_path).suffix}"
        link.parent.mkdir(parents=True, exist_ok=True)
        if copy:
            shutil.copy2(target, link)
        else:
            os.symlink(target, link)


def import_scene(src: str | Path, dst: str | Path, copy_images: bool = False, ply: str | Path | None = None) -> Path:
    """Import ``src`` into a new scene directory ``dst`` and return ``dst``.

    ``src`` may be (a) an Inria 3DGS output folder: the highest ``point_cloud/iteration_<N>``
    PLY, ``cameras.json``, and the images found through ``cfg_args``'s ``source_path`` if that
    resolves; (b) a COLMAP dataset folder (``sparse/0`` or ``sparse``, ``images/``; the model is
    copied to ``sparse/0``); (c) a nerfstudio dataset folder (``transforms.json``, poses returned to
    the COLMAP world); (d) a single 3DGS file in any format :func:`read_gaussians` reads (no
    cameras: an object to frame from cameras of one's own). ``ply`` gives the 3DGS file (any of
    those formats) for (b) and (c), or overrides (a)'s; it must be in the same world as the
    cameras. Without one only the cameras are imported.

    The Gaussians are read and rewritten as an Inria PLY (so they are validated), cameras are written as ``cameras.json``,
    images are symlinked (or copied) as ``images/<name><ext>``, and ``scene.json`` records
    ``up = null``, ``aligned = false``. ``dst`` is written whole or not at all and must not
    already hold files. Raises :class:`InputError` when ``src`` matches no layout (listing them).
    """
    src, dst = Path(src), Path(dst)
    source = str(src)
    if src.is_file():
        gaussians = read_gaussians(src)
        with atomic_directory(dst) as tmp:
            write_ply(gaussians, tmp / "scene.ply")
            write_scene_meta(SceneMeta(), tmp / "scene.json")
        return dst
    if not src.is_dir():
        raise InputError("source folder or file not found", source=source)
    sparse_dir = None
    images_dir = src / "images" if (src / "images").is_dir() else None
    if (src / "point_cloud").is_dir():
        inria_ply = _latest_inria_ply(src)
        if inria_ply is None or not (src / "cameras.json").is_file():
            raise InputError(
                "looks like an Inria 3DGS output but lacks point_cloud/iteration_<N>/point_cloud.ply or cameras.json",
                source=source,
            )
        ply = inria_ply if ply is None else ply
        images_dir = _inria_images_dir(src)
        cameras = read_cameras_json(src / "cameras.json", images_dir)
    elif (sparse_dir := _colmap_model_dir(src)) is not None:
        cameras = read_colmap(sparse_dir, images_dir)
    elif (src / "transforms.json").is_file():
        cameras = read_transforms_json(src / "transforms.json")
    else:
        raise InputError(f"matches no importable layout; looked for {_LAYOUTS}", source=source)
    if not cameras and ply is None:
        raise InputError("has no posed cameras and no PLY was given; nothing to import", source=source)
    gaussians = read_gaussians(ply) if ply is not None else None
    with atomic_directory(dst) as tmp:
        if gaussians is not None:
            write_ply(gaussians, tmp / "scene.ply")
        if cameras:
            write_cameras_json(cameras, tmp / "cameras.json")
        if images_dir is not None or any(c.image_path for c in cameras):
            _place_images(cameras, tmp / "images", copy_images, source)
        if sparse_dir is not None:
            shutil.copytree(sparse_dir, tmp / "sparse" / "0")
        write_scene_meta(SceneMeta(), tmp / "scene.json")
    return dst
