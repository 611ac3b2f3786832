"""COLMAP benchmark on real photos: ``capframe colmap`` and ``capframe gravity`` on a capture whose
cameras were published (default: the 97-photo snowmiku capture in ``../shared/data/real/photos``,
see its README for the source and licence).

The photos (as shot, distorted) go through ``capframe colmap`` with one shared ``SIMPLE_RADIAL``
camera, exhaustive matching and :data:`THREADS` threads, then ``capframe gravity`` on its output.
Printed:

* registration: photos registered / photos, and the wall time of each COLMAP step.
* poses, after the similarity (:func:`~capframe.scene.sfm.umeyama_sim3` on the camera centres)
  that maps the recovered centres onto the published ones: rotation error (geodesic angle,
  degrees) and centre distance relative to the capture's extent (:func:`capture_extent`, the
  3DGS trainer's ``cameras_extent``), median and max over the registered photos.
* focal length: the estimated one (photo pixels) against the published one times photo width /
  published width. The published intrinsics are those of the images undistorted at full size,
  which undistortion cropped (snowmiku: 4032 wide as shot, 3958 published), so this rescaling is
  approximate: it overstates the published focal by that crop (1.9 % for snowmiku).
* gravity: the estimated up, turned into the published world by the alignment's rotation, against
  two definitions of that world's up (:func:`reference_ups`), since the published world (COLMAP's)
  has no gravity of its own: the normal of the dominant plane of the published points (a bed, a
  floor, a table: the horizontal when that surface is level), and the mean up axis of the
  published cameras (unbiased only when the capture's pitches cancel, e.g. a full orbit at one
  height). Also the camera-only estimate, and what the camera consensus gives on the published
  poses themselves: the error owed to the no-roll assumption rather than to COLMAP.
"""

from __future__ import annotations

import contextlib
import math
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..geometry.gravity import camera_up_consensus, gravity_command
from ..scene import Camera, load_scene_dir
from ..scene.cameras_json import read_cameras_json
from ..scene.colmap import read_points3D_bin
from ..scene.sfm import MIN_REGISTERED, align_cameras, colmap_command, pose_errors, umeyama_sim3

CAPTURE = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "real" / "photos" / "snowmiku"
PHOTOS = CAPTURE / "images_1008px"
REFERENCE = CAPTURE / "cameras.json"
POINTS = CAPTURE / "points3D.bin"
THREADS = 2  # the machine's cores; the run is then not bit-repeatable (sfm.reconstruct)
# Phone photos downscaled 4x: one radial term suffices. OPENCV's eight parameters overfit: on the
# test's 16 photos fx/fy came out 837/861 px and the rotation error median 1.7 deg (0.6 deg here).
CAMERA_MODEL = "SIMPLE_RADIAL"
# On snowmiku, sequential matching (quadratic overlap, about 10 pairs per photo against
# exhaustive's 4,656 pairs) left the last 4 photos in a model of their own (93/97 registered,
# rotation error max 1.18 deg); exhaustive matching registered all 97 (max 0.85 deg).
MATCHER = "exhaustive"
PLANE_THRESHOLD = 0.01  # plane inlier distance, relative to the points' median distance from their median
PLANE_ITERATIONS = 2000


def capture_extent(cameras: list[Camera]) -> float:
    """The 3DGS trainer's ``cameras_extent``: 1.1 × the largest distance of a camera centre from
    the centres' mean, in the cameras' world units."""
    centers = np.array([c.center for c in cameras])
    return 1.1 * float(np.linalg.norm(centers - centers.mean(0), axis=1).max())


def mean_camera_up(cameras: list[Camera]) -> np.ndarray:
    """Unit mean (3,) of the cameras' up axes in the world, ``-R[1, :]`` (OpenCV's y points down)."""
    up = -np.mean([c.R[1] for c in cameras], axis=0)
    return up / np.linalg.norm(up)


def dominant_plane_normal(
    points: np.ndarray,
    viewpoints: np.ndarray,
    threshold: float = PLANE_THRESHOLD,
    iterations: int = PLANE_ITERATIONS,
    seed: int = 0,
) -> tuple[np.ndarray, float]:
    """Unit normal (3,) of the plane through the most of ``points`` (N, 3), and its inlier share.

    RANSAC over triples (``iterations``, seeded), inliers within ``threshold`` × the points' median
    distance from their median, then a least-squares refit (smallest singular vector of the
    centred inliers). The sign puts most ``viewpoints`` (M, 3), e.g. camera centres, on the
    positive side: a surface seen from above gets an upward normal. Raises :class:`InputError`
    for fewer than 3 points.
    """
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 3:
        raise InputError(f"points of shape {points.shape}; a plane needs (N, 3) with N >= 3")
    rng = np.random.default_rng(seed)
    tolerance = threshold * float(np.median(np.linalg.norm(points - np.median(points, 0), axis=1)))
    triples = points[rng.integers(0, len(points), (iterations, 3))]
    normals = np.cross(triples[:, 1] - triples[:, 0], triples[:, 2] - triples[:, 0])
    length = np.linalg.norm(normals, axis=1)
    keep = length > 0
    normals, anchors = normals[keep] / length[keep, None], triples[keep, 0]
    best, inliers = -1, None
    for n, a in zip(normals, anchors):  # one hypothesis at a time: N × iterations would not fit in memory
        mask = np.abs((points - a) @ n) < tolerance
        if mask.sum() > best:
            best, inliers = int(mask.sum()), mask
    for _ in range(3):  # refit, then re-collect the inliers of the refitted plane
        centre = points[inliers].mean(0)
        n = np.linalg.svd(points[inliers] - centre)[2][2]
        inliers = np.abs((points - centre) @ n) < tolerance
    if np.sum((np.asarray(viewpoints) - centre) @ n > 0) < len(viewpoints) / 2:
        n = -n
    return n, float(inliers.mean())


def reference_ups(reference: list[Camera], points: np.ndarray | None) -> dict[str, np.ndarray]:
    """The published world's up by each definition (module docstring): ``"plane"`` (when
    ``points`` are given) and ``"camera_mean"``."""
    ups = {"camera_mean": mean_camera_up(reference)}
    if points is not None:
        ups["plane"] = dominant_plane_normal(points, np.array([c.center for c in reference]))[0]
    return ups


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two directions (3,), degrees."""
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    return math.degrees(math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b)))


def compare_poses(cameras: list[Camera], reference: list[Camera]) -> dict:
    """Errors of recovered ``cameras`` against the same-named ``reference`` cameras after the
    similarity that maps their centres onto the reference's.

    Returns ``views`` (compared), ``alignment`` ``(s, R, t)``, ``extent`` (:func:`capture_extent`
    of ``reference``) and :func:`pose_errors` with positions relative to that extent. Raises
    :class:`InputError` when fewer than 3 names match.
    """
    truth = {c.name: c for c in reference}
    matched = [c for c in cameras if c.name in truth]
    if len(matched) < MIN_REGISTERED:
        raise InputError(f"only {len(matched)} recovered views are named as a reference camera (need at least {MIN_REGISTERED})")
    s, R, t = umeyama_sim3(np.array([c.center for c in matched]), np.array([truth[c.name].center for c in matched]))
    extent = capture_extent(reference)
    errors = pose_errors(align_cameras(matched, s, R, t), reference, extent)
    return {"views": len(matched), "alignment": (s, R, t), "extent": extent, **errors}


def bench_colmap(
    photos: str | Path | None = None,
    reference: str | Path | None = None,
    points: str | Path | None = None,
    out_dir: str | Path = "results/bench/colmap",
) -> dict:
    """Run the benchmark (module docstring) on ``photos`` (a folder of photos or a scene directory)
    against the Inria ``reference`` cameras.json and, for the plane up, the COLMAP ``points``
    (``points3D.bin``; None skips it unless the defaults are used). Writes the COLMAP scene and its
    gravity file to ``out_dir/<photos' folder name>`` (replaced). Returns the figures."""
    defaults = photos is None
    if not defaults and reference is None:
        raise InputError("bench colmap on other photos needs --reference (their published cameras.json)", source=str(photos))
    photos = PHOTOS if defaults else Path(photos)
    reference = REFERENCE if reference is None else Path(reference)
    points = POINTS if points is None and defaults else points
    if not photos.is_dir():
        raise InputError("photo folder not found (the default capture lives in ../shared/data/real)", source=str(photos))
    ref_cameras = read_cameras_json(reference)
    ref_points = None if points is None else read_points3D_bin(points)
    scene = Path(out_dir) / photos.name
    shutil.rmtree(scene, ignore_errors=True)
    with contextlib.redirect_stdout(sys.stderr):  # the verbs' summaries; stdout carries the figures
        record = colmap_command(photos, scene, matcher=MATCHER, camera_model=CAMERA_MODEL, num_threads=THREADS)
        start = time.perf_counter()
        gravity = gravity_command(scene)
        gravity_s = time.perf_counter() - start
    cameras = load_scene_dir(scene, load_gaussians=False).cameras
    poses = compare_poses(cameras, ref_cameras)
    R = poses["alignment"][1]
    ups = reference_ups(ref_cameras, ref_points)
    estimates = {"": np.array(gravity["up"]), "cameras_only_": np.array(gravity["sources"]["cameras"]["up"])}
    published = camera_up_consensus(ref_cameras).up  # already in the published world
    estimated = record["estimated_camera"]
    focal = estimated["params"][0]
    published_focal = float(np.median([c.K[0, 0] for c in ref_cameras])) * estimated["width"] / ref_cameras[0].width
    figures = {
        "photos": record["images_total"],
        "registered": record["images_registered"],
        "registration_rate": record["images_registered"] / record["images_total"],
        "colmap_s": record["timings"]["total_s"],
        **{f"colmap_{k}": v for k, v in record["timings"].items() if k != "total_s"},
        "matcher": MATCHER,
        "threads": THREADS,
        "reprojection_error_px": record["mean_reprojection_error_px"],
        "rotation_error_median_deg": poses["rotation_error_deg"]["median"],
        "rotation_error_max_deg": poses["rotation_error_deg"]["max"],
        "position_error_median_rel": poses["position_error_rel"]["median"],
        "position_error_max_rel": poses["position_error_rel"]["max"],
        "extent": poses["extent"],
        "camera_model": estimated["model"],
        "focal_px": focal,
        "published_focal_rescaled_px": published_focal,
        "focal_ratio": focal / published_focal,
        "gravity_s": gravity_s,
        "gravity_lines_used": bool((gravity["sources"]["vanishing_points"] or {}).get("used", False)),
    }
    for definition, up in ups.items():
        for prefix, estimate in estimates.items():
            figures[f"gravity_{prefix}error_vs_{definition}_deg"] = angle_deg(R @ estimate, up)
        figures[f"published_consensus_error_vs_{definition}_deg"] = angle_deg(published, up)
    if len(ups) == 2:
        figures["reference_ups_angle_deg"] = angle_deg(ups["plane"], ups["camera_mean"])
    return figures


__all__ = ["bench_colmap", "capture_extent", "compare_poses", "dominant_plane_normal", "mean_camera_up", "reference_ups"]
