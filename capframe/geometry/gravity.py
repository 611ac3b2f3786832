"""World up (gravity) of a scene, from its training cameras and from straight edges in its images.

**Cameras** (:func:`camera_up_consensus`). A photographer holds the camera level: with no roll the
camera x-axis (world direction ``R[0, :]``) is horizontal whatever the pitch, so up is the direction
most orthogonal to all x-axes, found with a RANSAC over pairs (``x_i × x_j``) and a least-squares
refit on the inliers. Its sign agrees with the cameras' up axes ``-R[1, :]``. When the x-axes leave
a direction undetermined (all parallel: a single view, a dolly or a tilt-only sweep with one
heading), a weak prior that the capture is level on average (``up ⟂`` the forward axes, within
:data:`PITCH_PRIOR_DEG`) fills it in, so such captures fall back to the cameras' mean up axis
with a low confidence instead of an arbitrary direction.

**Lines** (:func:`vanishing_up`). Each line segment (OpenCV's fast line detector) of a training
image spans, with the camera centre, an interpretation plane; its world normal
``n = Rᵀ · normalize(K⁻¹p₁ × K⁻¹p₂)`` is orthogonal to the 3D direction ``v`` of the edge, up to a
noise that grows as the segment gets shorter. Pooled over the images, dominant directions
(``n · v ≈ 0`` for many segments) are found greedily by RANSAC over pairs of normals and refitted on
their inliers (weights 1/σ²). Up is the direction closest to the camera consensus, or failing one
near it, the cross product of two orthogonal (horizontal) ones; the consensus also gives its sign.

**Uncertainty and fusion.** Each estimate carries an information matrix ``H`` (1/rad², in the plane
tangent to its up): the Hessian of its least-squares cost scaled by the residual variance, so a
direction the data leave loose has little information. ``sigma_deg`` is the larger standard
deviation it implies, and ``confidence`` is the probability, under that Gaussian error model, that
the error is below :data:`CONFIDENCE_TOLERANCE_DEG` (times a sign certainty for cameras that all
look nearly straight up or down). :func:`estimate_gravity` fuses the two by inverse covariance
(the up minimising ``Σ eᵀHe`` over both estimates' angular errors ``e``, so lines fix the pitch
direction a forward capture leaves loose), unless they disagree by more than
``max(FUSION_MIN_GATE_DEG, 3·sqrt(σ_c² + σ_v²))``; then the cameras alone are used and the lines
are reported as not used. The sign certainty is the cameras'.

**Files.** ``gravity.json``::

    {"format": 1, "up": [x, y, z], "sigma_deg": s, "confidence": c, "skipped": false,
     "sources": {"cameras": {...}, "vanishing_points": {...} | null}}

``skipped`` is true (and ``sources`` null) when ``scene.json`` already records a gravity-aligned
up. :func:`world_up` is what every stage reads: ``scene.json``'s up, else ``gravity.json``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from ..errors import InputError
from ..scene import Camera, load_scene_dir
from ..scene._io import as_direction, json_text, read_json, require_keys, write_json
from ..scene.directory import read_scene_meta

GRAVITY_FORMAT = 1

CAMERA_INLIER_DEG = 5.0  # a camera rolled more than this is an outlier of the consensus
ROLL_SIGMA_FLOOR_DEG = 0.5  # least roll noise assumed, so perfect poses do not claim infinite precision
PITCH_PRIOR_DEG = 30.0  # spread of a capture's mean pitch; only weighs where the x-axes are silent
SIGN_MARGIN = math.sin(math.radians(10.0))  # mean up-axis component below which the sign is doubtful
MAX_PAIRS = 2000  # RANSAC hypotheses (all pairs when there are fewer)
MIN_PAIR_SIN = math.sin(math.radians(3.0))  # nearly parallel pairs give ill-defined hypotheses

LINE_LONG_SIDE = 640  # images are shrunk to this long side before line detection
MIN_SEGMENT_FRACTION = 0.06  # shortest segment, as a fraction of the image diagonal (texture makes short ones)
SEGMENT_PIXEL_SIGMA = 0.5  # endpoint noise of a detected segment, working pixels
LINE_SIGMA_FLOOR_DEG = 0.2  # least angular noise of a segment's interpretation plane, however long
LINE_INLIER_SIGMAS = 3.0  # a segment supports v when |n·v| is within this many of its σ ...
LINE_INLIER_CAP_DEG = 2.5  # ... and within this angle
MAX_DIRECTIONS = 4  # dominant directions extracted greedily
MIN_DIRECTION_SEGMENTS = 12  # support a direction needs (segments) ...
MIN_DIRECTION_IMAGES = 2  # ... seen in this many images
ORTHOGONAL_DEG = 3.0  # two directions this close to orthogonal complete a Manhattan frame
CANDIDATE_GATE_SIGMAS = 3.0  # a line candidate is up only within this many σ of the cameras' up,
CANDIDATE_GATE_DEG = (5.0, 30.0)  # clipped to this range of angles
MAX_LINE_SIGMA_DEG = 3.0  # a looser candidate is no vanishing direction worth reporting

FUSION_MIN_GATE_DEG = 2.0  # lines within this angle of the cameras are always consistent with them
CONFIDENCE_TOLERANCE_DEG = 2.0  # confidence: probability of an error below this angle


@dataclass
class GravityEstimate:
    """One estimate of the world up.

    Attributes:
        up: (3,) unit world-up vector.
        information: (3, 3) information matrix in 1/rad², in the plane tangent to ``up``
            (``information @ up == 0``); its inverse there is the covariance of ``up``.
        residual_deg: RMS residual of the inliers (roll of a camera, angle between a segment's
            interpretation plane and its direction), degrees.
        inlier_share: inliers / observations (cameras or segments).
        count: number of inliers.
        sign_certainty: in [0.5, 1]: 0.5 when nothing tells up from down, 1 when that is clear.
        details: source-specific figures for the report (JSON-ready).
    """

    up: np.ndarray
    information: np.ndarray
    residual_deg: float
    inlier_share: float
    count: int
    sign_certainty: float = 1.0
    details: dict = field(default_factory=dict)

    @property
    def sigma_deg(self) -> float:
        """Standard deviation of ``up`` along its least certain tangent direction, degrees (≤ 90)."""
        return _sigma_deg(self.information, self.up)

    @property
    def confidence(self) -> float:
        return confidence_of(self.sigma_deg, self.sign_certainty)

    def to_dict(self) -> dict:
        return {
            "up": self.up.tolist(),
            "sigma_deg": self.sigma_deg,
            "confidence": self.confidence,
            "residual_deg": self.residual_deg,
            "inlier_share": self.inlier_share,
            "count": self.count,
            **self.details,
        }


def confidence_of(sigma_deg: float, sign_certainty: float = 1.0) -> float:
    """Probability that an estimate with standard deviation ``sigma_deg`` (per tangent axis) is
    within :data:`CONFIDENCE_TOLERANCE_DEG` of the truth, times ``sign_certainty``."""
    ratio = CONFIDENCE_TOLERANCE_DEG / sigma_deg
    return (1.0 - math.exp(-0.5 * ratio**2)) * sign_certainty


# --- shared least squares -------------------------------------------------------------------------


def _tangent(u: np.ndarray) -> np.ndarray:
    """(3, 3) projector onto the plane orthogonal to the unit vector ``u``."""
    return np.eye(3) - np.outer(u, u)


def _sigma_deg(information: np.ndarray, up: np.ndarray) -> float:
    """Larger tangent standard deviation implied by ``information`` (3, 3) at ``up`` (3,), degrees,
    capped at 90 (a direction without information)."""
    P = _tangent(up)
    eig = np.linalg.eigvalsh(P @ information @ P)[1:]  # the smallest is the zero along up
    weakest = eig[0]
    return 90.0 if weakest <= 1.0 / (math.pi / 2) ** 2 else math.degrees(1.0 / math.sqrt(weakest))


def _normal_fit(M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit u minimising uᵀMu for a (3, 3) scatter M, and the information of that fit: the Hessian
    of the Rayleigh quotient on the sphere, ``P (M - uᵀMu I) P`` (3, 3)."""
    values, vectors = np.linalg.eigh(M)
    u = vectors[:, 0]
    P = _tangent(u)
    return u, P @ (M - values[0] * np.eye(3)) @ P


def _pair_hypotheses(vectors: np.ndarray, rng: np.random.Generator, p: np.ndarray | None = None) -> np.ndarray:
    """Unit cross products of pairs of rows of ``vectors`` (n, 3): every pair when there are at most
    :data:`MAX_PAIRS`, else that many random pairs (drawn with probabilities ``p``). Nearly parallel
    pairs are dropped. Returns (m, 3), possibly empty."""
    n = len(vectors)
    if n * (n - 1) // 2 <= MAX_PAIRS:
        i, j = np.triu_indices(n, k=1)
    else:
        i, j = rng.choice(n, MAX_PAIRS, p=p), rng.choice(n, MAX_PAIRS, p=p)
    cross = np.cross(vectors[i], vectors[j])
    norm = np.linalg.norm(cross, axis=1)
    keep = norm > MIN_PAIR_SIN
    return cross[keep] / norm[keep, None]


def _best_hypothesis(hypotheses: np.ndarray, vectors: np.ndarray, thresholds: np.ndarray) -> np.ndarray:
    """The hypothesis h (3,) with the lowest MSAC cost ``Σ min((h·v / t)², 1)`` over the rows v of
    ``vectors`` (n, 3), each with its inlier threshold t (n,)."""
    residual = np.minimum(((hypotheses @ vectors.T) / thresholds) ** 2, 1.0)
    return hypotheses[np.argmin(residual.sum(axis=1))]


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two unit vectors (3,), degrees; atan2 keeps small angles exact."""
    return math.degrees(math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b)))


def _log_map(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Tangent vector (3,) at the unit ``u`` pointing to the unit ``w``, as long as their angle (radians)."""
    along = w - (u @ w) * u
    norm = np.linalg.norm(along)
    return np.zeros(3) if norm == 0 else along / norm * math.atan2(norm, float(u @ w))


def _exp_map(u: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The unit vector reached from ``u`` (3,) along the tangent ``step`` (3,) by its length in radians."""
    angle = np.linalg.norm(step)
    return u if angle == 0 else math.cos(angle) * u + math.sin(angle) * step / angle


def _rms_deg(cos_to_normal: np.ndarray, weights: np.ndarray) -> float:
    """Weighted RMS of angles ``asin|c|`` in degrees: the tilt of vectors out of the fitted plane."""
    angles = np.arcsin(np.clip(np.abs(cos_to_normal), 0.0, 1.0))
    return math.degrees(math.sqrt(np.sum(weights * angles**2) / np.sum(weights)))


# --- cameras --------------------------------------------------------------------------------------


def camera_up_consensus(cameras: list[Camera], inlier_deg: float = CAMERA_INLIER_DEG, seed: int = 0) -> GravityEstimate:
    """World up as the direction most orthogonal to the cameras' x-axes (module docstring).

    Cameras rolled by more than ``inlier_deg`` are outliers (RANSAC over pairs of x-axes, then up to
    five refits on the inliers). ``details`` holds ``cameras`` (the total). Raises
    :class:`InputError` for an empty list; any non-empty list gives a finite estimate.
    """
    if not cameras:
        raise InputError("no cameras to estimate the world up from")
    R = np.stack([c.R for c in cameras])
    x, up_axes, z = R[:, 0], -R[:, 1], R[:, 2]
    threshold = math.sin(math.radians(inlier_deg))
    ones = np.ones(len(x))
    hypotheses = _pair_hypotheses(x, np.random.default_rng(seed))
    if len(hypotheses):
        u = _best_hypothesis(hypotheses, x, np.full(len(x), threshold))
        inliers = np.abs(x @ u) < threshold
        sigma_r = max(_rms_deg(x[inliers] @ u, ones[inliers]), ROLL_SIGMA_FLOOR_DEG)
    else:  # every x-axis parallel: the prior decides the loose direction
        inliers, sigma_r = ones.astype(bool), ROLL_SIGMA_FLOOR_DEG
    for _ in range(5):
        xi, zi = x[inliers], z[inliers]
        # Roll residuals (x·u) weigh 1/σ_r² each; the level prior (z·u) is one observation for
        # the whole capture, since photographers pitch consistently rather than independently.
        M = xi.T @ xi / math.radians(sigma_r) ** 2 + zi.T @ zi / len(zi) / math.radians(PITCH_PRIOR_DEG) ** 2
        u, information = _normal_fit(M)
        new_inliers = np.abs(x @ u) < threshold
        if not new_inliers.any() or np.array_equal(new_inliers, inliers):
            break
        inliers = new_inliers
        sigma_r = max(_rms_deg(x[inliers] @ u, ones[inliers]), ROLL_SIGMA_FLOOR_DEG)
    margin = float(np.mean(up_axes[inliers] @ u))
    if margin < 0:
        u, margin = -u, -margin
    return GravityEstimate(
        up=u,
        information=information,
        residual_deg=_rms_deg(x[inliers] @ u, ones[inliers]),
        inlier_share=float(inliers.mean()),
        count=int(inliers.sum()),
        sign_certainty=0.5 + 0.5 * min(1.0, margin / SIGN_MARGIN),
        details={"cameras": len(cameras)},
    )


# --- lines ----------------------------------------------------------------------------------------


def detect_segments(gray: np.ndarray, min_length: float) -> np.ndarray:
    """Straight segments of an 8-bit grey image (H, W) longer than ``min_length`` pixels, as
    (m, 4) float64 endpoints ``x1, y1, x2, y2`` in continuous pixel coordinates (pixel centres at
    integer + 0.5, DESIGN §3; OpenCV puts them at integers)."""
    detector = cv2.ximgproc.createFastLineDetector(length_threshold=max(int(min_length), 2))
    found = detector.detect(gray)
    if found is None:
        return np.zeros((0, 4))
    return found.reshape(-1, 4).astype(np.float64) + 0.5


def segment_normals(segments: np.ndarray, camera: Camera) -> np.ndarray:
    """World unit normals (m, 3) of the interpretation planes of ``segments`` (m, 4) seen by ``camera``
    (its K must match the image the segments come from)."""
    K_inv = np.linalg.inv(camera.K)
    ones = np.ones((len(segments), 1))
    rays1 = np.hstack([segments[:, :2], ones]) @ K_inv.T
    rays2 = np.hstack([segments[:, 2:], ones]) @ K_inv.T
    n = np.cross(rays1, rays2)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return n @ camera.R  # Rᵀ n for each row


def _image_lines(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """World normals (m, 3) of the segments of ``camera``'s image and the standard deviation (m,)
    of each normal across its edge, radians: endpoint noise of :data:`SEGMENT_PIXEL_SIGMA` turns the
    segment by about 2σ/length, floored at :data:`LINE_SIGMA_FLOOR_DEG`."""
    gray = cv2.imread(str(camera.image_path), cv2.IMREAD_GRAYSCALE)
    if gray is None:
        raise InputError("not a readable image", source=str(camera.image_path))
    height, width = gray.shape
    scale = min(1.0, LINE_LONG_SIDE / max(width, height))
    if scale < 1.0:
        width, height = max(1, round(width * scale)), max(1, round(height * scale))
        gray = cv2.resize(gray, (width, height), interpolation=cv2.INTER_AREA)
    segments = detect_segments(gray, MIN_SEGMENT_FRACTION * math.hypot(width, height))
    lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    sigmas = np.maximum(2.0 * SEGMENT_PIXEL_SIGMA / lengths, math.radians(LINE_SIGMA_FLOOR_DEG))
    # resized() also covers an image stored at another size than the camera's intrinsics.
    return segment_normals(segments, camera.resized(width, height)), sigmas


@dataclass
class _Direction:
    """A dominant 3D line direction: unit ``v`` (3,), its ``information`` (3, 3), the boolean mask
    of its supporting segments, their RMS residual (degrees) and the number of images they span."""

    v: np.ndarray
    information: np.ndarray
    inliers: np.ndarray
    residual_deg: float
    images: int


def _fit_direction(
    normals: np.ndarray, sigmas: np.ndarray, inliers: np.ndarray, images: int
) -> tuple[np.ndarray, np.ndarray, float]:
    """Weighted least-squares direction orthogonal to the inlier normals (weights 1/σ²).

    Its information is scaled by the residuals' reduced χ² when that exceeds 1 (noisier than
    modelled) and divided by the number of ``images``: the same few edges recur in every view, so
    their errors (blur, a rounded corner) do not average out across images; only the spread of
    viewpoints, already in the scatter, adds information. Returns (v, information, RMS residual in
    degrees)."""
    n, w = normals[inliers], 1.0 / sigmas[inliers] ** 2
    v, information = _normal_fit((n * w[:, None]).T @ n)
    chi2 = float(np.sum(w * (n @ v) ** 2)) / max(len(n) - 2, 1)
    return v, information / (max(chi2, 1.0) * images), _rms_deg(n @ v, w)


def dominant_directions(normals: np.ndarray, sigmas: np.ndarray, image_ids: np.ndarray, seed: int = 0) -> list[_Direction]:
    """Up to :data:`MAX_DIRECTIONS` 3D directions, most supported first, each orthogonal to many
    interpretation-plane normals (m, 3) with standard deviations ``sigmas`` (m,) radians, from
    images ``image_ids`` (m,). A segment supports v when ``|n·v| < LINE_INLIER_SIGMAS σ``. Each
    direction is a RANSAC over pairs of the normals not yet explained (drawn by weight 1/σ²) plus
    refits on its inliers; the search stops at the first with too little support."""
    rng = np.random.default_rng(seed)
    thresholds = np.minimum(LINE_INLIER_SIGMAS * sigmas, math.sin(math.radians(LINE_INLIER_CAP_DEG)))
    free = np.ones(len(normals), dtype=bool)
    found = []
    while len(found) < MAX_DIRECTIONS and free.sum() >= MIN_DIRECTION_SEGMENTS:
        index = np.flatnonzero(free)
        p = sigmas[index] ** -2.0
        hypotheses = _pair_hypotheses(normals[index], rng, p / p.sum())
        if not len(hypotheses):
            break
        v = _best_hypothesis(hypotheses, normals[index], thresholds[index])
        inliers = free & (np.abs(normals @ v) < thresholds)
        for _ in range(3):
            images = len(np.unique(image_ids[inliers]))
            if inliers.sum() < MIN_DIRECTION_SEGMENTS or images < MIN_DIRECTION_IMAGES:
                break
            v, information, residual = _fit_direction(normals, sigmas, inliers, images)
            inliers = free & (np.abs(normals @ v) < thresholds)
        images = len(np.unique(image_ids[inliers]))
        if inliers.sum() < MIN_DIRECTION_SEGMENTS or images < MIN_DIRECTION_IMAGES:
            break
        found.append(_Direction(v, information, inliers, residual, images))
        free &= ~inliers
    return found


def _up_candidates(directions: list[_Direction]) -> list[tuple[np.ndarray, np.ndarray, list[int]]]:
    """Candidates for up: each dominant direction, and the normal of each pair of nearly orthogonal
    ones (two horizontal directions of a Manhattan frame). Returns (up, information, direction
    indices) triples; a pair's information is isotropic with variance σ₁² + σ₂²."""
    candidates = [(d.v, d.information, [i]) for i, d in enumerate(directions)]
    for i, a in enumerate(directions):
        for j in range(i + 1, len(directions)):
            b = directions[j]
            if abs(a.v @ b.v) < math.sin(math.radians(ORTHOGONAL_DEG)):
                u = np.cross(a.v, b.v)
                u /= np.linalg.norm(u)
                variance = sum(math.radians(_sigma_deg(d.information, d.v)) ** 2 for d in (a, b))
                candidates.append((u, _tangent(u) / variance, [i, j]))
    return candidates


def vanishing_up(
    cameras: list[Camera], prior: GravityEstimate | None = None, max_images: int = 60, seed: int = 0
) -> GravityEstimate | None:
    """World up from vanishing directions of straight edges in the cameras' images (module docstring).

    ``prior`` (default: :func:`camera_up_consensus` of ``cameras``) picks the candidate closest to
    it within :data:`CANDIDATE_GATE_SIGMAS` of its σ (clipped to :data:`CANDIDATE_GATE_DEG`),
    a single direction before a Manhattan pair, and gives its sign. At most ``max_images`` images,
    evenly spaced, are read; cameras without an image are skipped. Returns ``None`` when no image,
    no supported direction near the prior, or only one looser than :data:`MAX_LINE_SIGMA_DEG`.
    ``details`` holds ``images``, ``segments``, ``directions`` (found) and ``manhattan_pair``.
    """
    prior = camera_up_consensus(cameras) if prior is None else prior
    with_images = [c for c in cameras if c.image_path is not None]
    if not with_images:
        return None
    picked = [with_images[i] for i in np.unique(np.linspace(0, len(with_images) - 1, max_images).round().astype(int))]
    normals, sigmas, image_ids = [], [], []
    for k, camera in enumerate(picked):
        n, sigma = _image_lines(camera)
        normals.append(n)
        sigmas.append(sigma)
        image_ids.append(np.full(len(n), k))
    normals, sigmas, image_ids = np.concatenate(normals), np.concatenate(sigmas), np.concatenate(image_ids)
    directions = dominant_directions(normals, sigmas, image_ids, seed)
    candidates = _up_candidates(directions)
    if not candidates:
        return None
    angles = [_angle_deg(u if u @ prior.up >= 0 else -u, prior.up) for u, _, _ in candidates]
    gate = min(max(CANDIDATE_GATE_SIGMAS * prior.sigma_deg, CANDIDATE_GATE_DEG[0]), CANDIDATE_GATE_DEG[1])
    in_gate = [k for k, angle in enumerate(angles) if angle <= gate]
    if not in_gate:
        return None
    # A vertical direction measures up directly, a Manhattan pair only through two horizontal fits.
    direct = [k for k in in_gate if len(candidates[k][2]) == 1]
    best = min(direct or in_gate, key=angles.__getitem__)
    if _sigma_deg(candidates[best][1], candidates[best][0]) > MAX_LINE_SIGMA_DEG:
        return None
    u, information, used = candidates[best]
    inliers = np.any([directions[i].inliers for i in used], axis=0)
    residual = math.sqrt(np.mean([directions[i].residual_deg ** 2 for i in used]))
    return GravityEstimate(
        up=u if u @ prior.up >= 0 else -u,
        information=information,
        residual_deg=residual,
        inlier_share=float(inliers.mean()),
        count=int(inliers.sum()),
        details={
            "images": len(picked),
            "segments": len(normals),
            "directions": len(directions),
            "manhattan_pair": len(used) == 2,
        },
    )


# --- fusion and files -----------------------------------------------------------------------------


def fuse(cameras: GravityEstimate, lines: GravityEstimate | None) -> tuple[np.ndarray, np.ndarray, bool]:
    """Inverse-covariance fusion of the two estimates (module docstring). Returns the fused up (3,),
    its information (3, 3), and whether ``lines`` was used (not when None or inconsistent)."""
    if lines is None:
        return cameras.up, cameras.information, False
    gate = max(FUSION_MIN_GATE_DEG, 3.0 * math.hypot(cameras.sigma_deg, lines.sigma_deg))
    if _angle_deg(cameras.up, lines.up) > gate:
        return cameras.up, cameras.information, False
    # Gauss-Newton on the sphere: the camera estimate can be far off (a loose pitch), so steps
    # use exact angles (log/exp maps), not a single linearisation at the camera estimate.
    up = cameras.up
    for _ in range(20):
        P = _tangent(up)
        H_cameras, H_lines = P @ cameras.information @ P, P @ lines.information @ P
        information = H_cameras + H_lines
        step = np.linalg.pinv(information) @ (H_cameras @ _log_map(up, cameras.up) + H_lines @ _log_map(up, lines.up))
        up = _exp_map(up, step)
        if np.linalg.norm(step) < 1e-12:
            break
    P = _tangent(up)
    return up, P @ information @ P, True


def estimate_gravity(scene_dir: str | Path, use_lines: bool = True) -> dict:
    """The ``gravity.json`` contents for a scene directory (module docstring): the recorded up,
    ``skipped``, when ``scene.json`` says the world is aligned; else the fusion of the camera
    consensus and (with ``use_lines``) the vanishing directions. Raises :class:`InputError` when the
    scene has no cameras."""
    scene = load_scene_dir(scene_dir, load_gaussians=False)
    if scene.metadata.aligned and scene.metadata.up is not None:
        up = scene.metadata.up
        return {
            "format": GRAVITY_FORMAT,
            "up": up.tolist(),
            "sigma_deg": 0.0,
            "confidence": 1.0,
            "skipped": True,
            "sources": None,
        }
    if not scene.cameras:
        raise InputError(
            "no training cameras (cameras.json, sparse/0 or transforms.json) to estimate the world up "
            "from; run the COLMAP stage first",
            source=str(scene.root),
        )
    cameras = camera_up_consensus(scene.cameras)
    lines = vanishing_up(scene.cameras, prior=cameras) if use_lines else None
    up, information, lines_used = fuse(cameras, lines)
    sigma = _sigma_deg(information, up)
    sources = {"cameras": {**cameras.to_dict(), "angle_deg": _angle_deg(cameras.up, up)}, "vanishing_points": None}
    if lines is not None:
        sources["vanishing_points"] = {**lines.to_dict(), "angle_deg": _angle_deg(lines.up, up), "used": lines_used}
    return {
        "format": GRAVITY_FORMAT,
        "up": up.tolist(),
        "sigma_deg": sigma,
        "confidence": confidence_of(sigma, cameras.sign_certainty),
        "skipped": False,
        "sources": sources,
    }


def _summary(result: dict, output: Path) -> str:
    """One line: the up, its confidence, and each source's angle to it."""
    up = ", ".join(f"{v:+.4f}" for v in result["up"])
    if result["skipped"]:
        return f"up [{up}] from scene.json (aligned; nothing estimated) -> {output}"
    parts = [f"up [{up}]", f"confidence {result['confidence']:.2f}", f"sigma {result['sigma_deg']:.2f} deg"]
    cams = result["sources"]["cameras"]
    parts.append(f"cameras {cams['angle_deg']:.2f} deg off ({cams['count']}/{cams['cameras']} inliers)")
    lines = result["sources"]["vanishing_points"]
    if lines is None:
        parts.append("lines: none")
    else:
        state = "" if lines["used"] else ", not used: inconsistent"
        parts.append(f"lines {lines['angle_deg']:.2f} deg off ({lines['count']} segments{state})")
    return "; ".join(parts) + f" -> {output}"


def gravity_command(
    scene_dir: str | Path, output: str | Path | None = None, use_lines: bool = True, as_json: bool = False
) -> dict:
    """``capframe gravity``: estimate the world up of ``scene_dir`` and write it to ``output``
    (default ``SCENE_DIR/gravity.json``), atomically; print a one-line summary or the JSON."""
    result = estimate_gravity(scene_dir, use_lines=use_lines)
    output = Path(scene_dir) / "gravity.json" if output is None else Path(output)
    write_json(output, result)
    print(json_text(result, "the estimate", indent=None) if as_json else _summary(result, output))
    return result


def read_gravity(path: str | Path) -> np.ndarray:
    """The (3,) unit up of a ``gravity.json``; :class:`InputError` naming it when invalid."""
    source = str(path)
    data = read_json(path)
    require_keys(data, ("format", "up"), "gravity.json", source)
    if data["format"] != GRAVITY_FORMAT:
        raise InputError(f"'format' is {data['format']!r}; this version reads format {GRAVITY_FORMAT}", source=source)
    return as_direction(data["up"], "'up'", source)


def world_up(scene_dir: str | Path, gravity_path: str | Path | None = None) -> np.ndarray:
    """The (3,) world up every stage uses: ``scene.json``'s ``up`` when set; else the gravity file
    (``gravity_path``, default ``SCENE_DIR/gravity.json``); else :class:`InputError`."""
    root = Path(scene_dir)
    if not root.is_dir():
        raise InputError("scene directory not found", source=str(root))
    meta_path = root / "scene.json"
    if meta_path.is_file():
        up = read_scene_meta(meta_path).up
        if up is not None:
            return up
    gravity = root / "gravity.json" if gravity_path is None else Path(gravity_path)
    if gravity.is_file():
        return read_gravity(gravity)
    has_up = "scene.json has up = null" if meta_path.is_file() else "there is no scene.json"
    raise InputError(
        f"no world up: {has_up} and there is no {gravity.name if gravity_path is None else gravity}; "
        f"run `capframe gravity {root}`",
        source=str(root),
    )
