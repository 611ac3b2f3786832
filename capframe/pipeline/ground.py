"""``capframe ground``: an instruction in, a camera out (Retrieve -> Translate -> Refine) in one
process."""

from __future__ import annotations

from pathlib import Path

from . import stages
from .outputs import write_ground_result
from .stages import GroundOptions, StageClock


def ground(
    scene_dir: str | Path, text: str, out_dir: str | Path, options: GroundOptions | None = None, progress: bool = True
) -> dict:
    """Find the camera for ``text`` in the scene at ``scene_dir`` and write it to ``out_dir``
    (every stage in one process; the folder is :func:`~capframe.pipeline.outputs.write_ground_result`'s).
    Returns the content of ``result.json``."""
    options = options or GroundOptions()
    clock = StageClock(progress)
    job = stages.open_job(scene_dir, options)
    job.check_final_render()
    parsed = stages.parse(job, text, clock)
    retrieved = stages.qe(job, stages.coarse(job, parsed, clock), options, clock)
    labels = stages.perceive(job, retrieved, options, clock)
    occupancy = stages.free_space(job.scene, job.up, options, clock, labels)
    starts = [job.scene.cameras[v] for v in job.view_indices(retrieved.starts)]
    refined = stages.refine(job.scene, labels, starts, options, clock, occupancy)
    return write_ground_result(out_dir, job.scene, labels, retrieved, refined, options, clock, occupancy)
