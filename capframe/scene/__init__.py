"""Scene model and readers/writers (Inria PLY, cameras.json, COLMAP, transforms.json; readers for
PlayCanvas compressed PLY, .splat and .spz), and the scene directory contract (docs/scene-directory.md)."""

from .cameras_json import (
    read_camera_json,
    read_cameras_json,
    write_camera_json,
    write_camera_path_json,
    write_cameras_json,
)
from .colmap import colmap_image_line, read_colmap, write_colmap
from .directory import SceneDir, SceneMeta, SemanticObject, import_scene, load_scene_dir
from .formats import read_gaussians
from .model import Camera, GaussianScene, rgb_to_sh_dc, scene_extent, scene_scale, sh_degree_of
from .nerfstudio import read_transforms_json
from .playcanvas import read_compressed_ply
from .ply import read_ply, write_ply
from .splat import read_splat
from .spz import read_spz

__all__ = [
    "Camera",
    "GaussianScene",
    "rgb_to_sh_dc",
    "sh_degree_of",
    "scene_extent",
    "scene_scale",
    "read_ply",
    "write_ply",
    "read_gaussians",
    "read_compressed_ply",
    "read_splat",
    "read_spz",
    "read_cameras_json",
    "write_cameras_json",
    "read_camera_json",
    "write_camera_json",
    "write_camera_path_json",
    "read_colmap",
    "write_colmap",
    "colmap_image_line",
    "read_transforms_json",
    "SceneDir",
    "SceneMeta",
    "SemanticObject",
    "load_scene_dir",
    "import_scene",
]
