"""Every result folder the method and the baselines write, in one place.

A method's result folder holds what ``capframe check`` and the image grid read
(:func:`write_camera_result`): ``result.json`` (the camera's ``T_cw`` 4x4, ``K``, ``width``,
``height`` and the method's fields), ``camera.json`` and ``render.png`` (the frame at full
resolution). Refine adds (:func:`write_refine_outputs`):

* in ``result.json``: iterations, stop reason, loss terms at the final pose, per-stage wall times
  and the device;
* ``trajectory.npz``: pose per iteration (``poses``), total loss (``loss``) and each loss term;
* ``losses.csv``: the loss curves;
* ``path.png``: top view of the camera path (along the world up) with the subjects.

``capframe ground`` adds (:func:`write_ground_result`) the parsed instruction, the retrieval
(questions and per-view answers), the chosen initial view, the per-clause report (with the
camera's clearance), the refined candidates, the closed-form starts with why each was kept or
dropped (``solved``) and the :func:`feasibility` verdict to ``result.json``, and ``labels.json``
(the pseudo labels), ``camera_path.json`` (nerfstudio), ``colmap_image.txt`` (one ``images.txt``
line) and, with several candidates, ``candidates/<rank>/`` with each one's ``camera.json`` and
``render.png``.

Folders are written atomically, as one folder: nothing is written on an error.
"""

from __future__ import annotations

import dataclasses
import json
import platform
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageDraw

from ..handoff import Retrieved
from ..measure import CheckReport, ConstraintChecker, format_report
from ..refine.candidates import Candidate
from ..refine.nudge import DISTANCE_SHARES, ViewSphere, angle_misses, orbited
from ..refine.optimize import RefineConfig, RefineResult
from ..refine.search import search_cameras
from ..render import render
from ..render.image import save_png
from ..scene import Camera, SceneDir, colmap_image_line, write_camera_json, write_camera_path_json
from ..scene._io import atomic_directory, write_json
from ..scene.occupancy import Occupancy
from ..translate.instruction import ParsedInstruction
from ..translate.labels import PseudoLabels, write_pseudo_labels
from .stages import GroundOptions, Refined, StageClock, own_checker, own_report


def write_camera_result(out: Path, camera: Camera, image: torch.Tensor, fields: dict) -> dict:
    """``result.json`` (the camera's ``T_cw``, ``K``, ``width``, ``height``, then ``fields``),
    ``camera.json`` and ``render.png`` (``image``: (H, W, 3) in [0, 1]) in ``out``. Returns
    ``result.json``'s content."""
    summary = {"T_cw": camera.T_cw.tolist(), "K": camera.K.tolist(), "width": camera.width, "height": camera.height, **fields}
    write_json(out / "result.json", summary)
    write_camera_json(camera, out / "camera.json")
    save_png(image, out / "render.png")
    return summary


def write_refine_outputs(
    out: Path,
    camera: Camera,
    result: RefineResult,
    labels: PseudoLabels,
    config: RefineConfig,
    timings: dict,
    image: torch.Tensor,
    extra: dict | None = None,
) -> None:
    """A refinement's files (see the module docstring) in ``out``; ``extra`` adds fields to
    ``result.json``."""
    fields = {
        "iterations": result.iterations,
        "stop_reason": result.stop_reason,
        "loss_terms": result.terms,
        "loss": float(result.losses.min()),
        "timings": timings,
        "device": platform.processor() or platform.machine(),
        "threads": config.threads,
        "config": dataclasses.asdict(config),
        "subjects": [s.name for s in labels.subjects],
        **(extra or {}),
    }
    write_camera_result(out, camera, image, fields)
    np.savez_compressed(out / "trajectory.npz", poses=result.trajectory, loss=result.losses, **result.history)
    names = list(result.history)
    rows = ["iteration,loss," + ",".join(names)]
    rows += [
        f"{i},{result.losses[i]:.6g}," + ",".join(f"{result.history[n][i]:.6g}" for n in names) for i in range(len(result.losses))
    ]
    (out / "losses.csv").write_text("\n".join(rows) + "\n")
    path_plot(result.trajectory, labels).save(out / "path.png")


def path_plot(trajectory: np.ndarray, labels: PseudoLabels, size: int = 480) -> Image.Image:
    """Top view along the world up: the camera path (grey), start (blue) and end (red) frustums,
    and the subjects' centroids (green)."""
    up = labels.up / np.linalg.norm(labels.up)
    a = np.cross(up, [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(up, a)
    centres = -np.einsum("nji,nj->ni", trajectory[:, :3, :3], trajectory[:, :3, 3])
    forwards = trajectory[:, 2, :3]
    subjects = np.stack([s.centroid for s in labels.subjects])
    points = np.concatenate([centres, subjects])
    xy = np.stack([points @ a, points @ b], 1)
    lo, hi = xy.min(0), xy.max(0)
    span = max(float((hi - lo).max()), 1e-9) * 1.3
    mid = (lo + hi) / 2

    def to_px(p):
        q = (np.array([p @ a, p @ b]) - mid) / span * (size - 20) + size / 2
        return float(q[0]), float(size - q[1])

    img = Image.new("RGB", (size, size), "white")
    draw = ImageDraw.Draw(img)
    draw.line([to_px(c) for c in centres], fill=(150, 150, 150), width=2)
    for k, colour in ((0, (40, 90, 220)), (len(centres) - 1, (220, 40, 40))):
        tip = centres[k] + forwards[k] * span * 0.08
        draw.line([to_px(centres[k]), to_px(tip)], fill=colour, width=3)
        x, y = to_px(centres[k])
        draw.ellipse([x - 4, y - 4, x + 4, y + 4], fill=colour)
    for s in subjects:
        x, y = to_px(s)
        draw.ellipse([x - 6, y - 6, x + 6, y + 6], fill=(40, 170, 60))
    return img


def write_ground_result(
    out_dir: str | Path,
    scene: SceneDir,
    labels: PseudoLabels,
    retrieved: Retrieved,
    refined: Refined,
    options: GroundOptions,
    clock: StageClock,
    occupancy: Occupancy | None = None,
) -> dict:
    """Report on Refine's poses with the method's own pseudo labels (and their clearance with
    ``occupancy``), render the best (every candidate when ranking several) and write the folder.
    Returns ``result.json``'s content."""
    refined, reports = closest_answer(scene, labels, retrieved.parsed, refined, occupancy)
    cameras = refined.cameras
    images = [render(scene.gaussians, c).rgb for c in cameras[: 1 if len(cameras) == 1 else None]]
    verdict = overall_verdict(reports[0].all_satisfied, retrieved.parsed.not_understood())
    clock.done("report", "own labels: " + verdict)
    timings = clock.total()
    extra = {
        "understood": retrieved.parsed.understood,
        "not_understood": retrieved.parsed.not_understood(),
        "verdict": verdict,
        "instruction": retrieved.parsed.to_dict(),
        "retrieval": retrieved.retrieval,
        "init_view": refined.runs[0][0].name,
        "report": reports[0].to_dict(),
        "candidates": [
            {
                "rank": k,
                "init_view": start.name,
                "loss": float(r.losses.min()),
                "T_cw": r.T_cw.tolist(),
                "own_all_satisfied": rep.all_satisfied,
                **({"nudge_deg": list(r.nudge_deg)} if r.nudge_deg is not None else {}),
            }
            for k, ((start, r), rep) in enumerate(zip(refined.runs, reports))
        ],
        "solved": [c.to_dict() for c in refined.solved],
        "feasibility": feasibility(reports[0], refined.solved),
        "options": options.record(),
        "up": retrieved.up.tolist(),
    }
    with atomic_directory(out_dir) as tmp:
        write_refine_outputs(tmp, cameras[0], refined.runs[0][1], labels, options.refine, timings, images[0], extra)
        write_pseudo_labels(labels, tmp / "labels.json")
        write_camera_path_json([cameras[0]], tmp / "camera_path.json")
        (tmp / "colmap_image.txt").write_text(colmap_image_line(cameras[0], 1) + "\n")
        if len(cameras) > 1:
            for k, (camera, image) in enumerate(zip(cameras, images)):
                write_camera_json(camera, tmp / "candidates" / str(k) / "camera.json")
                save_png(image, tmp / "candidates" / str(k) / "render.png")
    if clock.enabled:
        print(format_report(reports[0]), file=sys.stderr)
    return json.loads((Path(out_dir) / "result.json").read_text())


def closest_answer(
    scene: SceneDir, labels: PseudoLabels, parsed: ParsedInstruction, refined: Refined, occupancy: Occupancy | None = None
) -> tuple[Refined, list[CheckReport]]:
    """Refine's poses and their own reports, the answer first (:func:`report_order`). When no
    refined pose satisfies every clause, those that miss only an asked angle by a few degrees
    join them moved into it (:func:`nudged_runs`); when still none does, the views Refine started
    from join them unrefined
    (:func:`unrefined`): Refine's loss does not see a subject hidden by other objects (an asked
    height may lie under a table top), and it trades an asked angle against the layout where
    free space bounds the distance (a ceiling over a top-down view), so a start chosen for
    showing the subjects at the asked angles may fail fewer clauses than where Refine ended; a
    camera that shows the subject, reported as failing what it fails, is closer to the request
    than one that does not. When the answer still fails a clause, a camera drawn around it inside
    every accepted interval that satisfies them all (:func:`searched_run`) comes first."""
    checker = own_checker(scene, labels, occupancy)
    reports = [own_report(checker, parsed, c) for c in refined.cameras]
    if not any(r.all_satisfied for r in reports):
        nudged = nudged_runs(refined, reports, checker, labels, occupancy)
        reports += [own_report(checker, parsed, start.with_pose(result.T_cw)) for start, result in nudged]
        refined = Refined(refined.runs + nudged, refined.solved)
    if not any(r.all_satisfied for r in reports):
        starts = [(start, unrefined(start, result)) for start, result in refined.runs]
        reports += [own_report(checker, parsed, start) for start, _ in starts]
        refined = Refined(refined.runs + starts, refined.solved)
    order = report_order(reports)
    if refined.runs and not reports[order[0]].all_satisfied:
        found = searched_run(refined.runs[order[0]], reports[order[0]], checker, parsed, labels, occupancy)
        if found is not None:
            refined = Refined(refined.runs + [found[0]], refined.solved)
            reports.append(found[1])
            order = [len(reports) - 1] + order
    return Refined([refined.runs[k] for k in order], refined.solved), [reports[k] for k in order]


def searched_run(
    run: tuple[Camera, RefineResult],
    report: CheckReport,
    checker: ConstraintChecker,
    parsed: ParsedInstruction,
    labels: PseudoLabels,
    occupancy: Occupancy | None = None,
) -> tuple[tuple[Camera, RefineResult], CheckReport] | None:
    """A camera drawn inside the accepted intervals around the answer ``run`` that satisfies
    every clause by its own report (:mod:`capframe.refine.search`), as a run with the stop
    reason ``searched``, and that report; None when no draw does."""
    start, result = run
    primary = labels.subjects[0]
    subject = checker.resolve(primary.name)
    found = search_cameras(
        start.with_pose(result.T_cw),
        report,
        primary.name,
        ViewSphere(subject.center, np.asarray(primary.centroid), subject.front, labels.up),
        lambda camera: own_report(checker, parsed, camera),
        occupancy,
    )
    if found is None:
        return None
    camera, measured = found
    return (start, dataclasses.replace(result, T_cw=camera.T_cw, stop_reason="searched", nudge_deg=None)), measured


def nudged_runs(
    refined: Refined,
    reports: list[CheckReport],
    checker: ConstraintChecker,
    labels: PseudoLabels,
    occupancy: Occupancy | None = None,
) -> list[tuple[Camera, RefineResult]]:
    """Refine's poses that miss only an asked angle of the primary subject, and by a few degrees,
    moved into it on the subject's view sphere (:mod:`capframe.refine.nudge`), with the turn in
    ``nudge_deg``: Refine's hinge terms settle against its layout terms just outside an interval.
    With ``occupancy`` the moved camera comes nearer (:data:`DISTANCE_SHARES`) until it is in
    free space, and is dropped when it never is. The caller reports on them like any pose; a
    turn that breaks another clause ranks below."""
    primary = labels.subjects[0]
    subject = checker.resolve(primary.name)
    shares = DISTANCE_SHARES if occupancy is not None else (1.0,)
    runs = []
    for (start, result), report in zip(refined.runs, reports):
        turn = angle_misses(report, primary.name)
        if turn is None:
            continue
        for share in shares:
            camera = orbited(
                start.with_pose(result.T_cw), subject.center, np.asarray(primary.centroid), subject.front, labels.up, turn, share
            )
            if camera is not None and (occupancy is None or float(occupancy.clearance(torch.as_tensor(camera.center))) > 0):
                runs.append((start, dataclasses.replace(result, T_cw=camera.T_cw, stop_reason="nudged", nudge_deg=turn)))
                break
    return runs


def shows_subjects(report: CheckReport) -> bool:
    """No ``visibility`` row of ``report`` fails."""
    return not any(r.constraint == "visibility" and r.satisfied is False for r in report.rows)


def unrefined(start: Camera, result: RefineResult) -> RefineResult:
    """The camera ``start`` that Refine ran from to ``result``, as a result of no step: its own
    pose, not the trajectory's first (Refine's yaw scan may have turned it before the first step),
    with the loss Refine measured there (``result.start_loss``; the trajectory's first when
    unmeasured, as for a run without a scan, which starts at the given pose)."""
    if result.start_terms is None:
        loss, terms = float(result.losses[0]), {n: float(v[0]) for n, v in result.history.items() if np.isfinite(v[0])}
    else:
        loss, terms = float(result.start_loss), dict(result.start_terms)
    return RefineResult(
        np.asarray(start.T_cw, dtype=np.float64),
        0,
        "unrefined",
        terms,
        np.asarray(start.T_cw, dtype=np.float64)[None],
        np.array([loss]),
        {name: np.array([value]) for name, value in terms.items()},
        0.0,
        start_loss=loss,
        start_terms=terms,
    )


def report_order(reports: list[CheckReport]) -> list[int]:
    """The order of Refine's poses by their own reports: unchanged when the first satisfies every
    clause; else a pose in free space first, then one that shows its subjects (no failing
    ``visibility`` row: a camera that does not show the subject answers nothing), then the
    fewest failing clauses, then the nearest to meeting them (:func:`shortfall`: an infeasible
    request returns the closest feasible camera), Refine's order breaking ties. Refine ranks by
    its loss, which does not see a subject hidden by other objects; the report does."""
    if not reports or reports[0].all_satisfied:
        return list(range(len(reports)))

    def failing(report: CheckReport, constraint: str | None = None) -> int:
        return sum(r.satisfied is False and constraint in (None, r.constraint) for r in report.rows)

    return sorted(
        range(len(reports)),
        key=lambda k: (
            failing(reports[k], "clearance") > 0,
            not shows_subjects(reports[k]),
            failing(reports[k]),
            round(shortfall(reports[k]), 2),
            k,
        ),
    )


def shortfall(report: CheckReport) -> float:
    """How far ``report``'s failing clauses are from holding, summed: an angle's error over a
    right angle (a view 90 degrees off weighs as a subject a whole frame off its region), any
    other error (frame fractions) as it is, 1 for an error that is undefined."""
    return sum(
        1.0 if r.error is None else r.error / 90.0 if r.unit == "deg" else r.error for r in report.rows if r.satisfied is False
    )


def overall_verdict(all_satisfied: bool, not_understood: list[str]) -> str:
    """The one-line verdict on an instruction: whether every parsed clause holds, and never
    "all clauses hold" when words that may ask something were not understood."""
    if not all_satisfied:
        return "some clauses fail"
    if not_understood:
        return f"parsed clauses hold, but partly understood: not understood {not_understood}"
    return "all clauses hold"


def feasibility(report: CheckReport, solved: list[Candidate]) -> dict:
    """Which clauses the returned camera fails by its own measure, and why the instruction may be
    infeasible: every closed-form camera inside geometry (no free space at the asked view),
    occluded (something stands between every asked view and the subject) or too close (the free
    space at the asked view is too near the subject to frame it). ``feasible`` is False
    only when a clause fails and the solve found no free, unoccluded camera."""
    failing = [{"constraint": r.constraint, "subject": r.subject, "note": r.note} for r in report.rows if r.satisfied is False]
    reasons = sorted({c.status for c in solved if c.status != "kept"})
    blocked = bool(solved) and all(c.status != "kept" for c in solved)
    why = {
        "inside geometry": "no free space at the asked view",
        "occluded": "the subject is occluded from every asked view",
        "too close": "no free space far enough to frame the subject at the asked view",
    }
    return {
        "feasible": not (failing and blocked),
        "failing": failing,
        "reasons": [why[r] for r in reasons] if blocked else [],
    }


def write_refine_result(
    out_dir: str | Path, scene: SceneDir, labels: PseudoLabels, refined: Refined, config: RefineConfig, clock: StageClock
) -> dict:
    """Refine alone (``capframe refine --init CAMERA``): the best pose rendered at full resolution
    and written with its refinement files. Returns ``result.json``'s content."""
    camera = refined.cameras[0]
    image = render(scene.gaussians, camera, backend="auto").rgb
    clock.done("final_render", f"{camera.width}x{camera.height}")
    with atomic_directory(out_dir) as tmp:
        write_refine_outputs(tmp, camera, refined.runs[0][1], labels, config, clock.total(), image)
    return json.loads((Path(out_dir) / "result.json").read_text())


def write_retrieved_view(out_dir: str | Path, scene: SceneDir, retrieved: Retrieved, camera: Camera, clock: StageClock) -> dict:
    """Retrieve's answer on its own, ``camera`` (the view Refine starts from), written like a
    method's result so the benchmark checks the pose before refinement beside the pose after it.

    ``result.json``'s ``timings`` are this job's, as every method's are its own job's (loading and
    the full-resolution render; Refine's are its refinement's): the coarse and QE jobs that chose
    the view carry their cost in their benchmark files (``capframe runtime`` adds them up).
    Returns its content.
    """
    image = render(scene.gaussians, camera).rgb
    clock.done("final_render", f"{camera.width}x{camera.height}")
    fields = {"method": "retrieve", "init_view": camera.name, "instruction": retrieved.parsed.to_dict(), "timings": clock.total()}
    with atomic_directory(out_dir) as tmp:
        return write_camera_result(tmp, camera, image, fields)
