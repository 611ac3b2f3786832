"""Camera JSON files: Inria ``cameras.json``, capframe ``camera.json``, nerfstudio ``camera_path.json``.

* Inria ``cameras.json`` (written by the reference 3DGS trainer): a list of
  ``{id, img_name, width, height, position, rotation, fx, fy}`` where ``position`` is the camera
  centre in world coordinates and ``rotation`` the 3x3 camera-to-world rotation (OpenCV axes),
  rows as nested lists. The principal point is the image centre unless the optional keys
  ``cx``, ``cy`` are present; our writer always writes them.
* capframe ``camera.json``: one camera, ``{name, width, height, K, T_cw, position, fov_y_deg}``;
  ``position`` and ``fov_y_deg`` are for people reading the file and are ignored on read.
* nerfstudio ``camera_path.json`` (input of ``ns-render camera-path``): write only.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._io import (
    as_array,
    as_size,
    check_unique_names,
    intrinsics,
    make_camera,
    read_json,
    require_keys,
    resolve_image,
    write_json,
)
from .model import Camera

# Right-multiplying a camera-to-world pose by this flips the camera's y and z axes, converting
# between OpenCV (x right, y down, z forward) and OpenGL (x right, y up, z back); it is its own inverse.
OPENCV_TO_OPENGL = np.diag([1.0, -1.0, -1.0, 1.0])


def _pose_from_center(R_wc: np.ndarray, center: np.ndarray) -> np.ndarray:
    """World-to-camera T_cw (4, 4) from a camera-to-world rotation (3, 3) and camera centre (3,)."""
    T = np.eye(4)
    T[:3, :3] = R_wc.T
    T[:3, 3] = -R_wc.T @ center
    return T


def fov_y_deg(camera: Camera) -> float:
    """Vertical field of view in degrees, ``2 atan(h / (2 fy))`` (exact for a centred principal point)."""
    return math.degrees(2.0 * math.atan(camera.height / (2.0 * camera.K[1, 1])))


def read_cameras_json(path: str | Path, images_dir: str | Path | None = None) -> list[Camera]:
    """Read an Inria ``cameras.json`` into cameras in file order.

    Each camera's ``image_path`` is ``images_dir/<img_name>[.ext]`` when that file exists
    (``None`` otherwise or without ``images_dir``). Raises :class:`InputError` naming the file and
    the camera for missing keys, wrong shapes, non-finite numbers, improper rotations, duplicate names.
    """
    source = str(path)
    data = read_json(path)
    if not isinstance(data, list):
        raise InputError(f"top level is {type(data).__name__}; expected a list of cameras", source=source)
    cameras = []
    for i, entry in enumerate(data):
        require_keys(entry, ("img_name", "width", "height", "position", "rotation", "fx", "fy"), f"camera {i}", source)
        name = entry["img_name"]
        if not isinstance(name, str) or not name:
            raise InputError(f"camera {i}: 'img_name' is {name!r}; expected a non-empty string", source=source)
        what = f"camera {i} ('{name}')"
        width = as_size(entry["width"], f"{what} 'width'", source)
        height = as_size(entry["height"], f"{what} 'height'", source)
        center = as_array(entry["position"], (3,), f"{what} 'position'", source)
        R_wc = as_array(entry["rotation"], (3, 3), f"{what} 'rotation'", source)
        K = as_array(
            [entry["fx"], entry["fy"], entry.get("cx", width / 2.0), entry.get("cy", height / 2.0)],
            (4,),
            f"{what} 'fx', 'fy', 'cx', 'cy'",
            source,
        )
        cameras.append(
            make_camera(
                _pose_from_center(R_wc, center), intrinsics(*K), width, height, name, resolve_image(images_dir, name), source
            )
        )
    check_unique_names([c.name for c in cameras], source)
    return cameras


def write_cameras_json(cameras: list[Camera], path: str | Path) -> None:
    """Write cameras as an Inria ``cameras.json`` (plus ``cx``, ``cy``), atomically, in list order."""
    write_json(
        path,
        [
            {
                "id": i,
                "img_name": cam.name,
                "width": cam.width,
                "height": cam.height,
                "position": cam.center.tolist(),
                "rotation": cam.R.T.tolist(),
                "fx": float(cam.K[0, 0]),
                "fy": float(cam.K[1, 1]),
                "cx": float(cam.K[0, 2]),
                "cy": float(cam.K[1, 2]),
            }
            for i, cam in enumerate(cameras)
        ],
    )


def read_camera_json(path: str | Path) -> Camera:
    """Read a capframe ``camera.json`` (one camera); :class:`InputError` naming the file if invalid."""
    source = str(path)
    data = read_json(path)
    require_keys(data, ("width", "height", "K", "T_cw"), "camera", source)
    name = data.get("name", "")
    if not isinstance(name, str):
        raise InputError(f"'name' is {name!r}; expected a string", source=source)
    return make_camera(
        as_array(data["T_cw"], (4, 4), "'T_cw'", source),
        as_array(data["K"], (3, 3), "'K'", source),
        as_size(data["width"], "'width'", source),
        as_size(data["height"], "'height'", source),
        name,
        None,
        source,
    )


def write_camera_json(camera: Camera, path: str | Path) -> None:
    """Write one camera as a capframe ``camera.json``, atomically."""
    write_json(
        path,
        {
            "name": camera.name,
            "width": camera.width,
            "height": camera.height,
            "K": camera.K.tolist(),
            "T_cw": camera.T_cw.tolist(),
            "position": camera.center.tolist(),
            "fov_y_deg": fov_y_deg(camera),
        },
    )


def write_camera_path_json(cameras: list[Camera], path: str | Path, fps: float = 24.0) -> None:
    """Write cameras as a nerfstudio ``camera_path.json`` for ``ns-render camera-path``, atomically.

    Each entry has ``camera_to_world`` (the 4x4 pose in OpenGL axes, flattened row-major), ``fov``
    (vertical, degrees) and ``aspect``. nerfstudio rebuilds ``fx = fy`` from ``fov`` and centres
    the principal point, so cameras with ``fx != fy`` or an off-centre principal point render
    slightly differently there. Poses are in this scene's world: a nerfstudio model trained with
    its dataparser's auto-orient/scale lives in a transformed world and needs that transform.
    All cameras must share one image size (nerfstudio has one render size per path).
    """
    if not cameras:
        raise InputError("no cameras to write", source=str(path))
    sizes = sorted({(c.width, c.height) for c in cameras})
    if len(sizes) > 1:
        raise InputError(f"cameras have different image sizes {sizes}; a camera path has one", source=str(path))
    width, height = sizes[0]
    write_json(
        path,
        {
            "camera_type": "perspective",
            "render_width": width,
            "render_height": height,
            "fps": fps,
            "seconds": len(cameras) / fps,
            "camera_path": [
                {
                    "camera_to_world": (cam.T_wc @ OPENCV_TO_OPENGL).reshape(-1).tolist(),
                    "fov": fov_y_deg(cam),
                    "aspect": width / height,
                }
                for cam in cameras
            ],
        },
    )
