"""COLMAP sparse models (``cameras``, ``images``, ``points3D``; binary ``.bin`` or text ``.txt``).

COLMAP stores world-to-camera poses in OpenCV axes and puts the centre of the top-left pixel at
(0.5, 0.5), exactly our conventions (DESIGN §3), so poses and ``K`` carry over unchanged. Only
pinhole projections are supported: ``PINHOLE``, ``SIMPLE_PINHOLE``, and distortion models whose
distortion parameters are all zero (what ``colmap image_undistorter`` produces is ``PINHOLE``).
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath

import numpy as np
import pycolmap
import torch

from ..errors import InputError
from ..geometry import rotmat_to_quat
from ._io import atomic_directory, check_unique_names, make_camera, resolve_image
from .model import Camera

_PINHOLE_MODELS = {"SIMPLE_PINHOLE", "PINHOLE"}
# Models that reduce to a pinhole when all their extra (distortion) parameters are zero.
_DISTORTION_MODELS = {"SIMPLE_RADIAL", "RADIAL", "OPENCV", "FULL_OPENCV", "FOV", "SIMPLE_DIVISION", "DIVISION"}
_MODEL_FILES = ("cameras", "images", "points3D")
_UNDISTORT_HINT = "undistort the images first (colmap image_undistorter) and use the model it writes"


def _model_format(sparse_dir: Path, source: str) -> str:
    """``"binary"`` or ``"text"``, checked here so that errors name the missing file (pycolmap's do not)."""
    if not sparse_dir.is_dir():
        raise InputError("COLMAP model folder not found", source=source)
    for suffix, fmt in ((".bin", "binary"), (".txt", "text")):
        if all((sparse_dir / f"{stem}{suffix}").is_file() for stem in _MODEL_FILES):
            return fmt
    missing = [
        f"{stem}.bin (or {stem}.txt)"
        for stem in _MODEL_FILES
        if not any((sparse_dir / f"{stem}{suffix}").is_file() for suffix in (".bin", ".txt"))
    ]
    if missing:
        raise InputError(f"missing {', '.join(missing)}; expected a COLMAP sparse model", source=source)
    raise InputError("mixes .bin and .txt model files; convert with 'colmap model_converter'", source=source)


def _intrinsics(camera: pycolmap.Camera, source: str) -> np.ndarray:
    """K (3, 3) of a COLMAP camera with a pinhole projection, else :class:`InputError`."""
    model = camera.model.name
    distortion = np.asarray(camera.params)[camera.extra_params_idxs()]
    if model in _PINHOLE_MODELS or (model in _DISTORTION_MODELS and not distortion.any()):
        return np.asarray(camera.calibration_matrix(), dtype=np.float64)
    if model in _DISTORTION_MODELS:
        raise InputError(
            f"camera {camera.camera_id} ({model}) has distortion {distortion.tolist()}; {_UNDISTORT_HINT}",
            source=source,
        )
    raise InputError(f"camera {camera.camera_id} uses the {model} model, not a pinhole; {_UNDISTORT_HINT}", source=source)


def read_colmap(sparse_dir: str | Path, images_dir: str | Path | None = None) -> list[Camera]:
    """Cameras of the posed images of a COLMAP sparse model (e.g. ``sparse/0``), sorted by name.

    A camera's name is its image name without the extension (sub-folders kept, ``/``-separated);
    its ``image_path`` is ``images_dir/<image name>`` when that file exists. Images without a pose
    are skipped. Raises :class:`InputError` naming the folder for a missing folder or model file,
    an unreadable model, or a camera that is not a pinhole.
    """
    sparse_dir = Path(sparse_dir)
    source = str(sparse_dir)
    reconstruction = pycolmap.Reconstruction()
    read = reconstruction.read_binary if _model_format(sparse_dir, source) == "binary" else reconstruction.read_text
    try:
        read(str(sparse_dir))
    except (ValueError, RuntimeError) as err:
        raise InputError(f"cannot read the COLMAP model ({' '.join(str(err).split())})", source=source) from None
    K_of: dict[int, np.ndarray] = {}
    cameras = []
    for image in reconstruction.images.values():
        if not image.has_pose:
            continue
        if image.camera_id not in K_of:
            K_of[image.camera_id] = _intrinsics(reconstruction.cameras[image.camera_id], source)
        colmap_camera = reconstruction.cameras[image.camera_id]
        T_cw = np.eye(4)
        T_cw[:3, :] = image.cam_from_world().matrix()
        cameras.append(
            make_camera(
                T_cw,
                K_of[image.camera_id],
                colmap_camera.width,
                colmap_camera.height,
                str(PurePosixPath(image.name).with_suffix("")),
                resolve_image(images_dir, image.name),
                source,
            )
        )
    cameras.sort(key=lambda c: c.name)
    check_unique_names([c.name for c in cameras], source)
    return cameras


def read_points3D_bin(path: str | Path) -> np.ndarray:
    """Positions (N, 3) float64 of a COLMAP ``points3D.bin`` read on its own (pycolmap reads only
    whole models).

    Layout (COLMAP's binary model, little-endian): a uint64 count, then per point a uint64 id,
    3 float64 ``xyz``, 3 uint8 ``rgb``, a float64 error, a uint64 track length L and L pairs of
    uint32 (image id, 2D point index). Raises :class:`InputError` naming the file when it is
    missing or ends early.
    """
    source = str(path)
    try:
        data = Path(path).read_bytes()
    except OSError as err:
        raise InputError(f"cannot read ({err.strerror}); expected a COLMAP points3D.bin", source=source) from None
    head = np.dtype([("id", "<u8"), ("xyz", "<f8", 3), ("rgb", "u1", 3), ("error", "<f8"), ("track", "<u8")])
    if len(data) < 8:
        raise InputError(f"{len(data)} bytes; expected a COLMAP points3D.bin (a uint64 count first)", source=source)
    count = int(np.frombuffer(data, "<u8", 1)[0])
    xyz = np.empty((count, 3))
    offset = 8
    for i in range(count):  # records vary in length with their tracks
        if offset + head.itemsize > len(data):
            raise InputError(f"ends at point {i} of {count}; the file is truncated", source=source)
        record = np.frombuffer(data, head, 1, offset)[0]
        xyz[i] = record["xyz"]
        offset += head.itemsize + 8 * int(record["track"])
    if offset > len(data):
        raise InputError(f"the track of point {count - 1} ends past the file's end; the file is truncated", source=source)
    if offset < len(data):
        raise InputError(f"{len(data) - offset} bytes after point {count}; expected the end of the file", source=source)
    return xyz


def colmap_image_name(camera: Camera) -> str:
    """The image file name COLMAP records: the camera's name plus its image's extension
    (``.png`` when the camera has no image), so :func:`read_colmap` gives the name back."""
    suffix = Path(camera.image_path).suffix if camera.image_path else ".png"
    return f"{camera.name}{suffix}"


def write_colmap(cameras: list[Camera], sparse_dir: str | Path, text: bool = False) -> None:
    """Write cameras as a COLMAP sparse model with no 3D points: one ``PINHOLE`` camera and one
    posed image per :class:`Camera`, binary unless ``text``. Image names follow
    :func:`colmap_image_name`. ``sparse_dir`` is written whole or not at all and must not
    already hold files."""
    reconstruction = pycolmap.Reconstruction()
    for i, cam in enumerate(cameras, start=1):
        colmap_camera = pycolmap.Camera.create_from_model_name(i, "PINHOLE", 1.0, cam.width, cam.height)
        colmap_camera.params = [cam.K[0, 0], cam.K[1, 1], cam.K[0, 2], cam.K[1, 2]]
        reconstruction.add_camera_with_trivial_rig(colmap_camera)
        image = pycolmap.Image(name=colmap_image_name(cam), camera_id=i, image_id=i)
        reconstruction.add_image_with_trivial_frame(image, pycolmap.Rigid3d(cam.T_cw[:3, :]))
    with atomic_directory(sparse_dir) as tmp:
        (reconstruction.write_text if text else reconstruction.write_binary)(str(tmp))


def colmap_image_line(camera: Camera, image_id: int, camera_id: int = 1, name: str | None = None) -> str:
    """One ``images.txt`` line, ``IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME``: the world-to-camera
    rotation as a unit quaternion (``QW >= 0``) and translation, as COLMAP writes them.

    ``name`` defaults to :func:`colmap_image_name`. In a full ``images.txt`` each such line is
    followed by a line of 2D points (may be empty).
    """
    q = rotmat_to_quat(torch.from_numpy(camera.R)).tolist()
    numbers = " ".join(repr(float(v)) for v in (*q, *camera.t))  # repr: shortest exact round trip
    return f"{image_id} {numbers} {camera_id} {name or colmap_image_name(camera)}"
