"""Ground-truth check of a result camera against an instruction's constraints (synthetic scenes):
the measurements of :mod:`capframe.measure`, with each subject's Gaussians, centre and front read
from the scene's ``ground_truth.json``, ``scene.ply`` and ``labels.npy``, and the camera's
clearance from the free space of the Gaussians under the true up. Evaluation only: no stage of the
method reads the ground truth.
"""

from __future__ import annotations

import difflib
import re
from pathlib import Path

import numpy as np
import torch

from ..constraints import Constraints
from ..errors import InputError
from ..measure import CheckReport, CheckRow, ConstraintChecker, format_report
from ..scene import Camera, load_scene_dir, read_camera_json
from ..scene._io import json_text, read_json, write_json
from ..scene.occupancy import build_occupancy, cached_occupancy, enclosed
from .ground_truth import GroundTruth, GTObject, ground_truth_cameras, read_ground_truth

__all__ = ["CheckReport", "CheckRow", "GroundTruthChecker", "check_camera", "check_command", "format_report"]


class GroundTruthChecker(ConstraintChecker):
    """Loads a synthetic scene once (ground truth, Gaussians, labels) and checks cameras against it.

    Args:
        scene_dir: scene directory with ``ground_truth.json``, ``scene.ply``, ``semantics.json`` and
            ``labels.npy``.
        long_side, backend: as for :class:`ConstraintChecker`.
        cache_dir: where the ground truth's occupancy (for the clearance verdict: built from the
            Gaussians, the true up and the true training cameras) is cached; None builds it.
    """

    def __init__(
        self, scene_dir: str | Path, *, long_side: int | None = None, backend: str = "auto", cache_dir: str | Path | None = None
    ):
        self.scene_dir = Path(scene_dir)
        self.ground_truth: GroundTruth = read_ground_truth(scene_dir)
        scene = load_scene_dir(scene_dir)
        if scene.gaussians is None:
            raise InputError("has no scene.ply; the check renders subject masks from it", source=str(scene_dir))
        if scene.gaussians.labels is None:
            raise InputError(
                "has no semantic sidecar (semantics.json + labels.npy); the check needs per-Gaussian labels",
                source=str(scene_dir),
            )
        labels = scene.gaussians.labels
        objects = {o.name: o for o in self.ground_truth.objects}
        members = {o.id: labels == o.label for o in self.ground_truth.objects}
        up, cameras = self.ground_truth.up, ground_truth_cameras(scene_dir)
        occupancy = (
            cached_occupancy(scene.gaussians, up, cameras, cache_dir)
            if cache_dir
            else build_occupancy(scene.gaussians, up, cameras)
        )
        super().__init__(scene.gaussians, objects, members, up, long_side=long_side, backend=backend, occupancy=occupancy)

    def resolve(self, name: str) -> GTObject:
        return self.ground_truth.resolve(name)

    def enclosed(self, obj: GTObject, point: np.ndarray) -> bool:
        """Whether ``point`` lies inside the closed surface of ``obj``'s Gaussians
        (:func:`~capframe.scene.occupancy.enclosed`)."""
        index = torch.nonzero(self.members[obj.id].cpu()).flatten()
        return enclosed(self.gaussians.to(device="cpu").subset(index), np.asarray(point, dtype=np.float64))


def check_camera(scene_dir: str | Path, camera: Camera, constraints: Constraints, **options) -> CheckReport:
    """Check one camera against ``constraints`` in the synthetic scene ``scene_dir``.

    ``options`` go to :class:`GroundTruthChecker` (``long_side``, ``backend``); to check many
    cameras of one scene, build the checker once instead.
    """
    return GroundTruthChecker(scene_dir, **options).check(camera, constraints)


# --- files and the CLI verb ---------------------------------------------------------------------

_PARAPHRASE_ID = re.compile(r"^(?P<base>.+)\.p\d+$")


def read_result_camera(path: str | Path) -> tuple[Camera, str | None]:
    """A result file (``result.json`` or ``camera.json``: ``T_cw``, ``K``, ``width``, ``height``,
    optionally ``instruction_id``) as a camera and the instruction id it names (or None)."""
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(f"top level is {type(data).__name__}; expected a JSON object", source=str(path))
    instruction_id = data.get("instruction_id")
    if instruction_id is not None and not isinstance(instruction_id, str):
        raise InputError(f"'instruction_id' is {instruction_id!r}; expected a string", source=str(path))
    return read_camera_json(path), instruction_id


def load_constraints(path: str | Path, instruction_id: str | None) -> tuple[str | None, dict, Constraints]:
    """The constraints of ``instruction_id`` in a ``constraints.json``.

    The file is keyed by instruction id (``{"<id>": {"scene", "text", "paraphrases", "constraints"}}``);
    a paraphrase id ``<id>.p<k>`` selects its original's constraints. A file holding one bare
    constraints object (with ``subjects``) is accepted too. Without an id the file must hold one
    instruction. Returns (id, entry, constraints); :class:`InputError` naming the closest ids.
    """
    source = str(path)
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(f"top level is {type(data).__name__}; expected a JSON object keyed by instruction id", source=source)
    if "subjects" in data:
        return instruction_id, {}, Constraints.from_dict(data)
    if not data:
        raise InputError("holds no instructions", source=source)
    if instruction_id is None:
        if len(data) != 1:
            some = sorted(data)[:5]
            raise InputError(
                f"holds {len(data)} instructions; pass --id (or put instruction_id in the result), e.g. {some}", source=source
            )
        instruction_id = next(iter(data))
    key = instruction_id
    if key not in data and (m := _PARAPHRASE_ID.match(key)) and m.group("base") in data:
        key = m.group("base")
    if key not in data:
        close = difflib.get_close_matches(instruction_id, list(data), n=3, cutoff=0.3) or sorted(data)[:3]
        raise InputError(f"instruction id {instruction_id!r} is not in this file; closest: {close}", source=source)
    entry = data[key]
    if not isinstance(entry, dict) or "constraints" not in entry:
        raise InputError(f"entry {key!r} lacks 'constraints'", source=source)
    return instruction_id, entry, Constraints.from_dict(entry["constraints"])


def check_command(
    scene: str | Path,
    result: str | Path,
    constraints: str | Path,
    *,
    instruction_id: str | None = None,
    as_json: bool = False,
    output: str | Path | None = None,
    cache_dir: str | Path | None = None,
) -> CheckReport:
    """``capframe check``: check a result camera against one instruction's constraints and print a
    table (or, with ``as_json``, one JSON object); ``output`` also writes the JSON object to a
    file, atomically. The instruction id defaults to the result's ``instruction_id``; ``cache_dir``
    caches the scene's occupancy."""
    camera, result_id = read_result_camera(result)
    instruction_id, entry, cons = load_constraints(constraints, instruction_id or result_id)
    report = check_camera(scene, camera, cons, cache_dir=cache_dir)
    report.instruction_id = instruction_id
    report.text = entry.get("text")
    print(json_text(report.to_dict(), "the report", indent=None) if as_json else format_report(report))
    if output is not None:
        write_json(output, report.to_dict())
    return report
