"""Evaluation: geometric (ground-truth) checks of result cameras on synthetic scenes."""

from .check import CheckReport, CheckRow, GroundTruthChecker, check_camera, check_command
from .ground_truth import GroundTruth, GTObject, parse_ground_truth, read_ground_truth

__all__ = [
    "CheckReport",
    "CheckRow",
    "GroundTruthChecker",
    "check_camera",
    "check_command",
    "GroundTruth",
    "GTObject",
    "parse_ground_truth",
    "read_ground_truth",
]
