"""The method as a pipeline of stages (:mod:`~capframe.pipeline.stages`, with their options) and
the result folders it writes (:mod:`~capframe.pipeline.outputs`); :func:`ground` runs them all in
one process. ``capframe ground``, the workflow's stage verbs and the baselines all run these
functions; argparse stays in :mod:`capframe.cli`."""

from .ground import ground
from .stages import GroundOptions, Job, Refined, StageClock, open_job

__all__ = ["GroundOptions", "Job", "Refined", "StageClock", "ground", "open_job"]
