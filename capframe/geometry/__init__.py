"""Geometry: SE(3)/so(3) maps, quaternions, pinhole cameras, view angles and roll (DESIGN §3)."""

from .camera import (
    any_horizontal,
    camera_axes,
    camera_center,
    camera_roll,
    look_at,
    pose_deviation,
    project,
    subject_frame,
    view_angles,
    view_direction,
    world_to_camera,
)
from .lie import hat, left_update, rotation_angle_deg, se3_exp, se3_log, so3_exp, so3_log
from .quaternion import quat_multiply, quat_to_rotmat, rotmat_to_quat

__all__ = [
    "any_horizontal",
    "camera_axes",
    "camera_center",
    "camera_roll",
    "look_at",
    "pose_deviation",
    "project",
    "subject_frame",
    "view_angles",
    "view_direction",
    "world_to_camera",
    "hat",
    "left_update",
    "rotation_angle_deg",
    "se3_exp",
    "se3_log",
    "so3_exp",
    "so3_log",
    "quat_multiply",
    "quat_to_rotmat",
    "rotmat_to_quat",
]
