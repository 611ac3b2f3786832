"""nerfstudio ``transforms.json`` (the dataset format of ``ns-process-data`` and ``ns-train``).

Each frame has ``file_path`` (relative to the JSON's folder) and ``transform_matrix``, a
camera-to-world pose in OpenGL camera axes (x right, y up, z back). Intrinsics ``fl_x``, ``fl_y``,
``cx``, ``cy``, ``w``, ``h`` sit at the top level or per frame (a frame's value wins); nerfstudio
puts pixel centres at integer + 0.5 like us, so they carry over unchanged.

When nerfstudio converts a COLMAP model it also re-axes the world (swapping and negating world
axes so that +z is COLMAP's -y) and records that 3x4 map as ``applied_transform``:
``c2w_json = [applied_transform; 0 0 0 1] @ c2w_colmap``. Undoing it returns poses to the
COLMAP world, the world the 3DGS PLY was trained in.
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath

import numpy as np

from ..errors import InputError
from ._io import (
    as_array,
    as_float,
    as_size,
    check_unique_names,
    intrinsics,
    make_camera,
    read_json,
    require_keys,
    resolve_image,
)
from .cameras_json import OPENCV_TO_OPENGL
from .model import Camera

_INTRINSICS = ("fl_x", "fl_y", "cx", "cy", "w", "h")
_DISTORTION = ("k1", "k2", "k3", "k4", "p1", "p2")
# nerfstudio camera_model values with a pinhole projection (given zero distortion); the others
# (OPENCV_FISHEYE, EQUIRECTANGULAR) are not pinholes at all.
_PINHOLE_MODELS = ("OPENCV", "PINHOLE", "SIMPLE_PINHOLE")


def _frame_intrinsics(i: int, frame: dict, top: dict, source: str) -> tuple[np.ndarray, int, int]:
    """K (3, 3), width and height of frame ``i``; a frame's own values override the top level's."""
    params = {key: frame.get(key, top.get(key)) for key in (*_INTRINSICS, *_DISTORTION, "camera_model")}
    missing = [key for key in _INTRINSICS if params[key] is None]
    if missing:
        raise InputError(f"frame {i} has no {', '.join(missing)} (at the top level or in the frame)", source=source)
    model = params["camera_model"] or "OPENCV"
    if model not in _PINHOLE_MODELS:
        raise InputError(f"frame {i}: camera_model {model!r} is not a pinhole; expected one of {_PINHOLE_MODELS}", source=source)
    distortion = {k: as_float(params[k], f"frame {i} {k!r}", source) for k in _DISTORTION if params[k] is not None}
    if any(distortion.values()):
        raise InputError(f"frame {i} has non-zero distortion {distortion}; undistort the images first", source=source)
    fx, fy, cx, cy = (as_float(params[k], f"frame {i} {k!r}", source) for k in _INTRINSICS[:4])
    return (
        intrinsics(fx, fy, cx, cy),
        as_size(params["w"], f"frame {i} 'w'", source),
        as_size(params["h"], f"frame {i} 'h'", source),
    )


def _frame_pose(i: int, rows: object, world_from_json: np.ndarray, source: str) -> np.ndarray:
    """T_cw (4, 4), OpenCV axes, of a ``transform_matrix`` (3x4 or 4x4 OpenGL camera-to-world)."""
    n_rows = 3 if isinstance(rows, list) and len(rows) == 3 else 4
    c2w_gl = np.eye(4)
    c2w_gl[:n_rows] = as_array(rows, (n_rows, 4), f"frame {i} 'transform_matrix'", source)
    if not np.array_equal(c2w_gl[3], [0, 0, 0, 1]):
        raise InputError(f"frame {i}: 'transform_matrix' last row is {c2w_gl[3].tolist()}, expected [0, 0, 0, 1]", source=source)
    c2w = world_from_json @ c2w_gl @ OPENCV_TO_OPENGL
    T_cw = np.eye(4)
    T_cw[:3, :3] = c2w[:3, :3].T
    T_cw[:3, 3] = -c2w[:3, :3].T @ c2w[:3, 3]
    return T_cw


def read_transforms_json(path: str | Path, undo_applied_transform: bool = True) -> list[Camera]:
    """Cameras of a nerfstudio ``transforms.json``, as OpenCV world-to-camera poses, sorted by name.

    A camera's name is its image's file stem; ``image_path`` is the image (``file_path`` resolved
    against the JSON's folder) when it exists. With ``undo_applied_transform`` (default) a recorded
    ``applied_transform`` is inverted so poses are in the original (COLMAP/PLY) world; without it,
    poses stay in the JSON's world. Raises :class:`InputError` naming the file for missing
    intrinsics, non-pinhole models, non-zero distortion, or invalid poses.
    """
    source = str(path)
    data = read_json(path)
    require_keys(data, ("frames",), "the top level", source)
    if not isinstance(data["frames"], list):
        raise InputError("'frames' is not a list", source=source)
    world_from_json = np.eye(4)
    if undo_applied_transform and "applied_transform" in data:
        applied = as_array(data["applied_transform"], (3, 4), "'applied_transform'", source)
        if abs(np.linalg.det(applied[:, :3])) < 1e-12:
            raise InputError(f"'applied_transform' {applied.tolist()} is not invertible", source=source)
        world_from_json = np.linalg.inv(np.vstack([applied, [0.0, 0.0, 0.0, 1.0]]))
    cameras = []
    for i, frame in enumerate(data["frames"]):
        require_keys(frame, ("file_path", "transform_matrix"), f"frame {i}", source)
        K, width, height = _frame_intrinsics(i, frame, data, source)
        T_cw = _frame_pose(i, frame["transform_matrix"], world_from_json, source)
        file_path = str(frame["file_path"])
        image_path = resolve_image(Path(path).parent, file_path)
        cameras.append(make_camera(T_cw, K, width, height, PurePosixPath(file_path).stem, image_path, source))
    cameras.sort(key=lambda c: c.name)
    check_unique_names([c.name for c in cameras], source)
    return cameras
