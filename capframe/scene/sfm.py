"""Structure from motion for scenes without poses (pycolmap), and Sim(3) alignment of cameras.

:func:`reconstruct` recovers the training cameras of a folder of images with COLMAP's incremental
pipeline (SIFT on the CPU, exhaustive or sequential matching, incremental mapping, one shared
camera). Rendered images take a pinhole camera; photos as shot take a distortion model
(``SIMPLE_RADIAL``, ``OPENCV``) and are then undistorted, so every later stage sees pinhole
cameras and straight lines. :func:`colmap_command` (``capframe colmap``) turns a scene directory
without poses, or a plain folder of photos, into a posed one. A real 3DGS is trained on the
recovered poses afterwards, so its Gaussians live in COLMAP's world. A synthetic scene's
Gaussians live in the generator's world instead; the evaluation verb ``capframe align-truth``
(:mod:`capframe.evaluate.alignment`) maps the recovered cameras into that world; no stage of the
method reads the ground truth (DESIGN §4).

:func:`umeyama_sim3` and :func:`align_cameras` are the general tools: fit ``X' = s R X + t`` to
point pairs, and move cameras into the new world so that every point projects where it did.
"""

from __future__ import annotations

import platform
import shutil
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pycolmap
import torch

from ..errors import InputError
from ..geometry.lie import rotation_angle_deg
from ._io import IMAGE_SUFFIXES, atomic_directory, write_json
from .cameras_json import write_cameras_json
from .colmap import read_colmap
from .directory import SceneMeta, _place_images, write_scene_meta
from .model import Camera

MATCHERS = ("auto", "exhaustive", "sequential")
# One camera shared by all images: a pinhole for renders and undistorted images; a radial (k1) or
# OpenCV (fx, fy, cx, cy, k1, k2, p1, p2) distortion for photos as shot.
CAMERA_MODELS = ("SIMPLE_PINHOLE", "SIMPLE_RADIAL", "OPENCV")
# Exhaustive matching costs n(n-1)/2 pairs; beyond this many images "auto" matches sequentially.
EXHAUSTIVE_MAX_IMAGES = 60
# Sequential matching pairs each image with those 1, 2, 4, ..., 2^(SEQUENTIAL_OVERLAP-1) places
# later in name order (COLMAP's quadratic overlap, which in pycolmap 4 replaces the linear one):
# O(n log n) pairs whose long steps give wide baselines and some loop closure without a vocabulary
# tree. On an 80-view synthetic walkthrough it registered all views, faster and more accurately
# than the 10 next images.
SEQUENTIAL_OVERLAP = 10
MIN_REGISTERED = 3
# Files copied (hard-linked where possible) into an aligned synthetic scene: they live in the
# ground-truth world, which the aligned cameras now share.
_IMAGE_SUFFIXES = {s.lower() for s in IMAGE_SUFFIXES}


@dataclass
class SfmResult:
    """What :func:`reconstruct` recovered.

    Attributes:
        cameras: the registered views, sorted by name (T_cw in the reconstruction's world).
        image_names: every input image, relative to the image folder (``/``-separated), sorted.
        reconstruction: the pycolmap model (the largest one the mapper built; undistorted, with
            a ``PINHOLE`` camera, when the camera model has distortion).
        sparse_dir: where that model was written (binary): ``work_dir/sparse/0``, or
            ``work_dir/undistorted/sparse`` next to the undistorted images.
        estimated_camera: the shared camera bundle adjustment refined, before undistortion:
            ``{"model", "params", "width", "height"}`` (params in COLMAP's order for the model).
        mean_reprojection_error: mean reprojection error of the 3D points' observations, pixels.
        num_points3D: number of triangulated 3D points.
        matcher: ``"exhaustive"`` or ``"sequential"``, the matching that ran.
        timings: wall time per step in seconds (``extract_s``, ``match_s``, ``map_s``,
            ``undistort_s`` when the images were undistorted, ``total_s``).
    """

    cameras: list[Camera]
    image_names: list[str]
    reconstruction: pycolmap.Reconstruction
    sparse_dir: Path
    mean_reprojection_error: float
    num_points3D: int
    matcher: str
    estimated_camera: dict
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def unregistered(self) -> list[str]:
        """Input image names (without extension) that have no recovered pose."""
        registered = {c.name for c in self.cameras}
        stems = [str(Path(n).with_suffix("").as_posix()) for n in self.image_names]
        return [s for s in stems if s not in registered]

    def stats(self) -> dict:
        """The figures ``colmap.json`` records."""
        return {
            "images_total": len(self.image_names),
            "images_registered": len(self.cameras),
            "unregistered": self.unregistered,
            "mean_reprojection_error_px": self.mean_reprojection_error,
            "num_points3D": self.num_points3D,
            "matcher": self.matcher,
            "estimated_camera": self.estimated_camera,
            "camera": {
                "fx": self.cameras[0].K[0, 0],
                "fy": self.cameras[0].K[1, 1],
                "cx": self.cameras[0].K[0, 2],
                "cy": self.cameras[0].K[1, 2],
                "width": self.cameras[0].width,
                "height": self.cameras[0].height,
            },
            "timings": self.timings,
        }


def list_images(image_dir: str | Path) -> list[str]:
    """Image files under ``image_dir`` (sub-folders included, hidden entries skipped) as sorted
    ``/``-separated relative names; sorted names are the capture order sequential matching assumes."""
    root = Path(image_dir)
    names = []
    for path in root.rglob("*"):
        relative = path.relative_to(root)
        hidden = any(part.startswith(".") for part in relative.parts)
        if path.suffix.lower() in _IMAGE_SUFFIXES and path.is_file() and not hidden:
            names.append(relative.as_posix())
    return sorted(names)


@contextmanager
def _colmap_log(verbose: bool) -> Iterator[None]:
    """COLMAP logs every step at INFO level (hundreds of lines); show warnings and errors only
    unless ``verbose``, and restore the process-wide level afterwards."""
    level = pycolmap.logging.minloglevel
    pycolmap.logging.minloglevel = level if verbose else max(level, int(pycolmap.logging.WARNING))
    try:
        yield
    finally:
        pycolmap.logging.minloglevel = level


def reconstruct(
    image_dir: str | Path,
    work_dir: str | Path,
    *,
    matcher: str = "auto",
    camera_model: str = "SIMPLE_PINHOLE",
    num_threads: int = 1,
    seed: int = 0,
    verbose: bool = False,
) -> SfmResult:
    """Recover the camera of every image in ``image_dir`` by incremental structure from motion.

    Steps (pycolmap): SIFT extraction on the CPU into ``work_dir/database.db``; matching, exhaustive
    up to :data:`EXHAUSTIVE_MAX_IMAGES` images and sequential in name order beyond (``matcher``
    forces one); incremental mapping. All images share one camera of ``camera_model``, refined by
    bundle adjustment (principal point fixed at the image centre): ``SIMPLE_PINHOLE`` (one focal
    length) for images rendered or undistorted from one camera, ``SIMPLE_RADIAL`` or ``OPENCV`` for
    photos as shot. Images of another size than the first are not registered. The largest model
    is kept and written (binary) to ``work_dir/sparse/0``; with a distortion model, the registered
    images and the model are then undistorted into ``work_dir/undistorted`` (``images/`` and a
    ``PINHOLE`` ``sparse/``, cropped to valid pixels; COLMAP's image_undistorter), and the result's
    cameras, model and image paths are those.

    Determinism: the RANSAC and mapper seeds are fixed to ``seed``. SIFT extraction on the CPU is
    deterministic; with ``num_threads=1`` (the default) the whole run is repeatable with the same
    pycolmap build and images. With more threads, multi-threaded bundle adjustment and matching
    change the order of floating-point sums and of work, so poses may differ slightly between
    runs. The reconstruction's world (origin, orientation, scale) is arbitrary in any case.

    Args:
        image_dir: folder of images (sub-folders allowed); camera names are the images' relative
            paths without extension, as in a scene directory.
        work_dir: folder for the database and the model; created if missing.
        matcher: ``"auto"``, ``"exhaustive"`` or ``"sequential"``.
        camera_model: one of :data:`CAMERA_MODELS`.
        num_threads: threads for every step.
        seed: random seed of RANSAC and the mapper.
        verbose: let COLMAP log at INFO level (default: warnings and errors only).

    Raises :class:`InputError` naming ``image_dir`` when it holds no images or fewer than
    :data:`MIN_REGISTERED` register, and for an unknown matcher or camera model.
    """
    image_dir, work_dir = Path(image_dir), Path(work_dir)
    source = str(image_dir)
    if matcher not in MATCHERS:
        raise InputError(f"matcher {matcher!r}; expected one of {list(MATCHERS)}")
    if camera_model not in CAMERA_MODELS:
        raise InputError(f"camera model {camera_model!r}; expected one of {list(CAMERA_MODELS)}")
    names = list_images(image_dir) if image_dir.is_dir() else []
    if not names:
        raise InputError(f"no images ({', '.join(sorted(_IMAGE_SUFFIXES))}); nothing to reconstruct", source=source)
    if matcher == "auto":
        matcher = "exhaustive" if len(names) <= EXHAUSTIVE_MAX_IMAGES else "sequential"
    work_dir.mkdir(parents=True, exist_ok=True)
    database = work_dir / "database.db"
    database.unlink(missing_ok=True)  # a stale database would add its images to this run
    pycolmap.set_random_seed(seed)
    t0 = time.perf_counter()
    with _colmap_log(verbose):
        _extract(database, image_dir, names, camera_model, num_threads)
        t1 = time.perf_counter()
        _match(database, matcher, num_threads, seed)
        t2 = time.perf_counter()
        reconstruction = _map(database, image_dir, work_dir / "models", num_threads, seed)
    t3 = time.perf_counter()
    timings = {"extract_s": t1 - t0, "match_s": t2 - t1, "map_s": t3 - t2}
    registered = 0 if reconstruction is None else reconstruction.num_reg_images()
    if registered < MIN_REGISTERED:
        raise InputError(
            f"only {registered} of {len(names)} images registered (need at least {MIN_REGISTERED}); "
            "the images may overlap too little or lack texture",
            source=source,
        )
    sparse_dir = work_dir / "sparse" / "0"
    if sparse_dir.exists():
        shutil.rmtree(sparse_dir)
    sparse_dir.mkdir(parents=True)
    reconstruction.write_binary(str(sparse_dir))
    camera = next(iter(reconstruction.cameras.values()))
    estimated = {
        "model": camera.model.name,
        "params": [float(v) for v in camera.params],
        "width": int(camera.width),
        "height": int(camera.height),
    }
    images_dir = image_dir
    if camera_model != "SIMPLE_PINHOLE":
        with _colmap_log(verbose):
            sparse_dir, images_dir = _undistort(sparse_dir, image_dir, work_dir / "undistorted", num_threads)
        reconstruction = pycolmap.Reconstruction(str(sparse_dir))
        timings["undistort_s"] = time.perf_counter() - t3
    timings["total_s"] = time.perf_counter() - t0
    return SfmResult(
        cameras=read_colmap(sparse_dir, images_dir),
        image_names=names,
        reconstruction=reconstruction,
        sparse_dir=sparse_dir,
        mean_reprojection_error=float(reconstruction.compute_mean_reprojection_error()),
        num_points3D=int(reconstruction.num_points3D()),
        matcher=matcher,
        estimated_camera=estimated,
        timings=timings,
    )


def _undistort(sparse_dir: Path, image_dir: Path, out_dir: Path, num_threads: int) -> tuple[Path, Path]:
    """Undistorted copies of the registered images and a ``PINHOLE`` model of them, in ``out_dir``
    (replaced); returns ``(model folder, image folder)``. The focal length is kept and the image
    cropped to the pixels that have a source (COLMAP's ``blank_pixels = 0``), as the 3DGS data
    converter does."""
    if out_dir.exists():
        shutil.rmtree(out_dir)
    pycolmap.undistort_images(out_dir, sparse_dir, image_dir, output_type="COLMAP", num_threads=num_threads)
    return out_dir / "sparse", out_dir / "images"


def _extract(database: Path, image_dir: Path, names: list[str], camera_model: str, num_threads: int) -> None:
    """SIFT features of ``names`` on the CPU, one shared camera of ``camera_model``."""
    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = camera_model
    options = pycolmap.FeatureExtractionOptions()
    options.num_threads = num_threads
    options.use_gpu = False
    pycolmap.extract_features(
        database,
        image_dir,
        image_names=names,
        camera_mode=pycolmap.CameraMode.SINGLE,
        reader_options=reader,
        extraction_options=options,
        device=pycolmap.Device.cpu,
    )


def _match(database: Path, matcher: str, num_threads: int, seed: int) -> None:
    """Match features between image pairs and verify them geometrically (seeded RANSAC)."""
    options = pycolmap.FeatureMatchingOptions()
    options.num_threads = num_threads
    options.use_gpu = False
    verification = pycolmap.TwoViewGeometryOptions()
    verification.ransac.random_seed = seed
    if matcher == "exhaustive":
        pycolmap.match_exhaustive(
            database, matching_options=options, verification_options=verification, device=pycolmap.Device.cpu
        )
    else:
        pairing = pycolmap.SequentialPairingOptions()
        pairing.overlap = SEQUENTIAL_OVERLAP
        pairing.quadratic_overlap = True
        pairing.num_threads = num_threads
        pycolmap.match_sequential(
            database,
            matching_options=options,
            pairing_options=pairing,
            verification_options=verification,
            device=pycolmap.Device.cpu,
        )


def _map(database: Path, image_dir: Path, models_dir: Path, num_threads: int, seed: int) -> pycolmap.Reconstruction | None:
    """Incremental mapping; the model with the most registered images, or ``None`` if none."""
    options = pycolmap.IncrementalPipelineOptions()
    options.num_threads = options.mapper.num_threads = num_threads
    options.random_seed = options.mapper.random_seed = options.triangulation.random_seed = seed
    # COLMAP drops models under 10 images; small captures are legitimate here, and the caller
    # demands MIN_REGISTERED views.
    options.min_model_size = MIN_REGISTERED
    models_dir.mkdir(parents=True, exist_ok=True)
    models = pycolmap.incremental_mapping(database, image_dir, models_dir, options=options)
    shutil.rmtree(models_dir)  # the kept model is written to sparse/0 by the caller
    return max(models.values(), key=lambda r: r.num_reg_images(), default=None)


# --- similarity alignment -------------------------------------------------------------------------


def umeyama_sim3(src: np.ndarray, dst: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Least-squares similarity ``dst ≈ s R src + t`` (Umeyama 1991).

    Args:
        src, dst: (N, 3) corresponding points, N >= 3, ``src`` not all on one line.

    Returns:
        ``(s, R, t)``: scale > 0, (3, 3) proper rotation (det +1, even when a reflection would
        fit better), (3,) translation; float64.

    Points are centred before the fit, so large offsets cost no precision. Raises
    :class:`InputError` for mismatched shapes, fewer than 3 pairs, or ``src`` points that
    coincide or are collinear (the rotation about their line is then undetermined).
    """
    src, dst = np.asarray(src, dtype=np.float64), np.asarray(dst, dtype=np.float64)
    if src.ndim != 2 or src.shape[1] != 3 or src.shape != dst.shape:
        raise InputError(f"point sets of shapes {src.shape} and {dst.shape}; expected two (N, 3) arrays")
    if len(src) < 3:
        raise InputError(f"{len(src)} point pairs; a similarity needs at least 3")
    mu_src, mu_dst = src.mean(0), dst.mean(0)
    a, b = src - mu_src, dst - mu_dst
    spread = np.linalg.svd(a, compute_uv=False)
    if spread[1] <= 1e-9 * spread[0] or spread[0] == 0:
        raise InputError("the source points coincide or lie on one line; a similarity is not determined")
    U, D, Vt = np.linalg.svd(b.T @ a / len(src))
    # Flip the weakest axis when the best orthogonal map is a reflection (Umeyama's S).
    S = np.diag([1.0, 1.0, np.sign(np.linalg.det(U) * np.linalg.det(Vt))])
    R = U @ S @ Vt
    s = float(np.trace(np.diag(D) @ S) / (a**2).sum(1).mean())
    return s, R, mu_dst - s * R @ mu_src


def align_cameras(cameras: list[Camera], s: float, R: np.ndarray, t: np.ndarray) -> list[Camera]:
    """The cameras moved into the world ``X' = s R X + t``, each imaging every point where it did.

    A camera ``x_c = R_c X + t_c`` sees ``X = R^T (X' - t) / s``, so
    ``s x_c = R_c R^T X' + (s t_c - R_c R^T t)``: a positive multiple of ``x_c``, hence the same
    pixel. The new pose is ``T_cw' = [R_c R^T, s t_c - R_c R^T t]`` (its centre is ``s R C + t``).

    Args:
        cameras: cameras in the old world.
        s: scale > 0; R: (3, 3) rotation; t: (3,) translation.
    """
    R, t = np.asarray(R, dtype=np.float64), np.asarray(t, dtype=np.float64)
    aligned = []
    for camera in cameras:
        T = np.eye(4)
        T[:3, :3] = camera.R @ R.T
        T[:3, 3] = s * camera.t - T[:3, :3] @ t
        aligned.append(camera.with_pose(T))
    return aligned


def pose_errors(cameras: list[Camera], reference: list[Camera], scale: float) -> dict:
    """Errors of ``cameras`` against the same-named ``reference`` cameras (each camera needs
    one), both in one world.

    Returns ``rotation_error_deg`` (geodesic angle between the rotations) and
    ``position_error_rel`` (centre distance / ``scale``), each as ``{"mean", "median", "max"}``, and
    ``per_view``: ``[{"name", "rotation_deg", "position_rel"}]``.
    """
    truth = {c.name: c for c in reference}
    per_view = []
    for camera in cameras:
        ref = truth[camera.name]
        angle = rotation_angle_deg(torch.from_numpy(camera.R), torch.from_numpy(ref.R))
        per_view.append(
            {
                "name": camera.name,
                "rotation_deg": float(angle),
                "position_rel": float(np.linalg.norm(camera.center - ref.center) / scale),
            }
        )
    summary = {}
    for key, out in (("rotation_deg", "rotation_error_deg"), ("position_rel", "position_error_rel")):
        values = np.array([v[key] for v in per_view])
        summary[out] = {"mean": float(values.mean()), "median": float(np.median(values)), "max": float(values.max())}
    return {**summary, "per_view": per_view}


def photo_folder(scene_dir: Path) -> Path:
    """The images ``capframe colmap`` reads: ``scene_dir/images`` when that folder exists (a scene
    directory), else ``scene_dir`` itself (a plain folder of photos)."""
    return scene_dir / "images" if (scene_dir / "images").is_dir() else scene_dir


def colmap_command(
    scene_dir: str | Path,
    out_dir: str | Path,
    matcher: str = "auto",
    camera_model: str = "SIMPLE_PINHOLE",
    num_threads: int = 1,
) -> dict:
    """``capframe colmap``: recover the poses of a scene's images and write a scene directory.

    ``scene_dir`` is a scene directory without poses (``images/``) or a folder of photos
    (:func:`photo_folder`). ``out_dir`` gets ``cameras.json`` (registered views), ``sparse/0``
    (the COLMAP model), ``images/`` (symlinks to the source images of the registered views, or the
    undistorted images themselves when ``camera_model`` has distortion), ``scene.json`` (``up:
    null, aligned: false``) and ``colmap.json`` (:meth:`SfmResult.stats`, device). The cameras are
    in COLMAP's world: a 3DGS must be trained on them before any stage renders (the benchmark's
    synthetic scenes are instead mapped into their ground-truth world by the evaluation verb
    ``capframe align-truth``).

    ``out_dir`` is written whole or not at all and must not already hold files. Prints a summary
    and returns the ``colmap.json`` record. Raises :class:`InputError` for a folder without
    images, fewer than 3 registered views, or an ``out_dir`` that holds files.
    """
    scene_dir, out_dir = Path(scene_dir), Path(out_dir)
    if not scene_dir.is_dir():
        raise InputError("scene directory not found", source=str(scene_dir))
    with atomic_directory(out_dir) as tmp, tempfile.TemporaryDirectory(prefix=f".{out_dir.name}.colmap-", dir=tmp.parent) as work:
        result = reconstruct(photo_folder(scene_dir), work, matcher=matcher, camera_model=camera_model, num_threads=num_threads)
        record = {
            "format": 1,
            **result.stats(),
            "device": platform.processor() or platform.machine(),
            "threads": num_threads,
        }
        # Undistorted images live in the temporary work folder: copy them, link the originals.
        undistorted = camera_model != "SIMPLE_PINHOLE"
        write_posed_scene(tmp, result.cameras, result.reconstruction, str(scene_dir), copy_images=undistorted)
        write_json(tmp / "colmap.json", record)
    print(
        f"{out_dir}: {record['images_registered']}/{record['images_total']} views registered, "
        f"{record['num_points3D']} points, reprojection error {record['mean_reprojection_error_px']:.2f} px "
        f"({record['timings']['total_s']:.1f} s)"
    )
    print("no scene.ply: train a 3DGS on these poses (cameras.json, sparse/0, images/) before rendering")
    return record


def write_posed_scene(
    out_dir: Path, cameras: list[Camera], reconstruction: pycolmap.Reconstruction, source: str, copy_images: bool = False
) -> None:
    """Write a scene directory's poses into ``out_dir`` (which must exist): ``cameras.json``,
    ``sparse/0`` (binary), ``images/`` symlinked to (or with ``copy_images``, copies of) each
    camera's ``image_path``, and a ``scene.json`` with no up and not aligned."""
    write_cameras_json(cameras, out_dir / "cameras.json")
    (out_dir / "sparse" / "0").mkdir(parents=True)
    reconstruction.write_binary(str(out_dir / "sparse" / "0"))
    _place_images(cameras, out_dir / "images", copy=copy_images, source=source)
    write_scene_meta(SceneMeta(), out_dir / "scene.json")


__all__ = [
    "SfmResult",
    "reconstruct",
    "list_images",
    "umeyama_sim3",
    "align_cameras",
    "pose_errors",
    "colmap_command",
    "photo_folder",
    "write_posed_scene",
    "MATCHERS",
    "CAMERA_MODELS",
]
