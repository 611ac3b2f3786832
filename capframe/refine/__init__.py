"""Refine: camera-pose optimisation from geometric pseudo labels."""

from .optimize import LossWeights, RefineConfig, RefineResult, refine_pose

__all__ = ["LossWeights", "RefineConfig", "RefineResult", "refine_pose"]
