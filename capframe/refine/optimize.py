"""The pose optimiser: Adam on a left-multiplied se(3) increment.

The increment is expressed about the primary subject: ``T = P exp(tau) P^-1 T0`` where ``P``
translates the initial camera frame's origin to the subject's centroid (when the subject starts
behind the camera ``P`` is the identity, so a rotation turns the camera towards it). This is the left
increment ``exp(Ad_P tau)`` in other coordinates; in these, a pure rotation orbits the camera
around the subject and leaves the subject's image position and depth unchanged, so changing the
view side no longer fights the layout terms (with ``exp(tau) T0`` an orbit is a narrow valley
coupling rotation and translation, which Adam crosses in many small zig-zag steps).

The translational part of ``tau`` is expressed in units of the scene scale, so the learning rates
(and the trajectory) are the same for a scene measured in centimetres or kilometres. The layout
losses render only the subjects' Gaussians (masks, no colours) at a low resolution; the final
frame is rendered once, at full resolution, by the caller.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import torch
from torch import Tensor

from ..geometry.camera import camera_center
from ..geometry.lie import se3_exp
from ..render import PreparedGaussians, indexed, prepare, render
from ..render.lod import SCENE_CELL, LodView, cached_hierarchy, ray_cosine, subject_owner
from ..render.torch_backend import EPS2D, SIGMA_MAX
from ..scene.model import Camera, GaussianScene
from ..scene.occupancy import Occupancy
from ..translate.labels import PseudoLabels, min_in_frame_share
from .candidates import subject_floor_margin, view_centre
from .losses import Box, Frame, aim_loss, box_indicator, clearance_loss, layout_terms, target_ray, upright_loss, view_loss


@dataclass
class LossWeights:
    """Weights of the loss terms: the paper's for its terms; ``size``, ``framing`` and ``hidden``
    are ours.

    ``occlusion`` applies only in the occlusion phase (see :class:`RefineConfig`).
    ``clearance`` pushes the camera out of a subject it starts inside, where the saturated mask
    gives the layout terms no gradient. ``free_space`` keeps the camera out of any geometry (walls,
    floors, objects; with a scene occupancy). ``hidden`` is the penalty of a subject out of view; it
    must exceed the layout loss of a subject that just entered the view (about ``center +
    inside + outside``), or the blend between the two would be a barrier at the edge of the view."""

    center: float = 1.0
    inside: float = 6.0
    outside: float = 2.0
    size: float = 4.0
    framing: float = 6.0
    upright: float = 2.0
    view: float = 2.0
    look_at: float = 2.0
    hidden: float = 12.0
    clearance: float = 10.0
    free_space: float = 10.0
    occlusion: float = 6.0


@dataclass
class RefineConfig:
    """Optimiser settings.

    Attributes:
        iterations: maximum number of Adam steps.
        lr_rotation: learning rate of the rotation (radians).
        lr_translation: learning rate of the translation, in scene-scale units.
        long_side: optimisation resolution (long side in pixels).
        patience: stop when the best loss improved by less than ``rel_tol`` of itself over this
            many iterations (relative to the loss level, so any scale of loss works).
        rel_tol: see ``patience``.
        mask_floor_px: mask mass (in pixels) below which a subject counts as out of view and
            its layout terms give way to the "hidden" penalty (blended smoothly).
        settle: stop once every pseudo-label clause has held for this many consecutive steps.
        yaw_scan: start from the best of this many rotations about the world up through the
            subject (1 disables the scan).
        guard: the subject masks are rendered with a band of this fraction of the frame on each
            side, so a subject cut off by the frame edge leaks out of its box instead of looking
            like a smaller subject inside it.
        roll_tolerance_deg: roll error under which the upright clause holds.
        occlusion_iterations: if another object hides a subject at the end (visible share below
            ``min_visible``), continue for at most this many steps with the occlusion term,
            rendering the whole scene each step (0 disables the phase). ``iterations`` bounds
            both phases together.
        min_visible: see ``occlusion_iterations``.
        occlusion_long_side: the occlusion phase measures visible shares on a canvas of this long
            side (guard band included as for the masks); a share is an area ratio that needs
            fewer pixels than the layout, and the phase renders every possible occluder at each
            step. 0 or at least ``long_side``: the optimisation resolution.
        lod_pixels: the subject masks and the occlusion phase render a level-of-detail cut
            (:mod:`capframe.render.lod`) whose merged cells span at most this many pixels at
            their nearest depth; 0 renders every Gaussian.
        threads: torch intra-op threads while optimising. The tensors are small, so threads gain
            little, and on a busy machine (parallel workflow jobs) their synchronisation makes
            every small op wait for a descheduled thread; one is the default.
    """

    iterations: int = 1500
    lr_rotation: float = 0.007
    lr_translation: float = 0.005
    long_side: int = 160
    patience: int = 60
    rel_tol: float = 1e-2
    mask_floor_px: float = 4.0
    settle: int = 8
    yaw_scan: int = 8
    guard: float = 0.25
    roll_tolerance_deg: float = 1.0
    occlusion_iterations: int = 300
    occlusion_long_side: int = 80
    min_visible: float = 0.6
    lod_pixels: float = 2.0
    threads: int = 1
    weights: LossWeights = field(default_factory=LossWeights)


@dataclass
class RefineResult:
    """Outcome of one refinement.

    Attributes:
        T_cw: (4, 4) float64 best pose found.
        iterations: Adam steps taken (over both phases).
        stop_reason: "satisfied" (every pseudo-label clause held for ``settle`` steps),
            "converged" (loss below 1e-4 of its initial value), "plateau" or "max_iterations".
        terms: loss terms at the best pose.
        trajectory: (E, 4, 4) pose of every evaluation, the start first (E is ``iterations`` + 1,
            + 1 more when the occlusion phase ran).
        losses: (E,) total loss per evaluation.
        history: per loss term, (iterations + 1,) unweighted values per step.
        seconds: wall time of the optimisation.
        occlusion_seconds: the part of ``seconds`` spent on the occlusion phase: the visibility
            check at the end of the first phase and, when a subject was hidden, the second phase.
        start_loss, start_terms: the total loss and its terms at the pose Refine was given, before
            its yaw scan (the trajectory starts after the scan, which may turn the start away);
            None when unmeasured.
        nudge_deg: the turn (azimuth, elevation) in degrees that moved ``T_cw`` on the subject's
            view sphere after Refine (:mod:`capframe.refine.nudge`; ``trajectory`` ends before
            it); None when none did.
    """

    T_cw: np.ndarray
    iterations: int
    stop_reason: str
    terms: dict[str, float]
    trajectory: np.ndarray
    losses: np.ndarray
    history: dict[str, np.ndarray]
    seconds: float
    occlusion_seconds: float = 0.0
    start_loss: float | None = None
    start_terms: dict[str, float] | None = None
    nudge_deg: tuple[float, float] | None = None


CULL_CHUNK = 1 << 20  # Gaussians per chunk of the occluder cull: bounds its float64 temporaries


class _Objective:
    """The total loss as a function of the pose, with everything pose-independent precomputed."""

    def __init__(
        self,
        scene: GaussianScene,
        camera: Camera,
        labels: PseudoLabels,
        config: RefineConfig,
        dtype: torch.dtype,
        occupancy: Occupancy | None = None,
    ):
        self.config, self.labels, self.dtype, self.occupancy = config, labels, dtype, occupancy
        self.unpadded = camera
        w, h = camera.width, camera.height
        gx, gy = round(config.guard * w), round(config.guard * h)
        self.camera = camera.padded(gx, gy)  # the canvas
        self.frame = Frame(float(gx), float(gy), w, h)
        index = np.concatenate([s.gaussians for s in labels.subjects])
        owner = np.concatenate([np.full(len(s.gaussians), k) for k, s in enumerate(labels.subjects)])
        # Pose-independent work once; the near plane stays relative to the whole scene.
        self.subjects = LodView(
            cached_hierarchy(scene, torch.as_tensor(index, dtype=torch.long), torch.as_tensor(owner), dtype),
            len(labels.subjects),
            self.camera,
            config.lod_pixels,
        )
        self.up = torch.as_tensor(labels.up, dtype=torch.float64)
        self.K = torch.as_tensor(camera.K, dtype=torch.float64)
        self.roll = math.radians(labels.roll_deg)
        self.boxes, self.regions, self.indicators, self.rays = [], [], [], []
        self.min_in_frame = [min_in_frame_share(s.extent) for s in labels.subjects]
        for s in labels.subjects:
            box = Box(*s.box, labels.box_angle_deg) if s.box is not None else None
            region = Box(*s.region, labels.box_angle_deg) if s.region is not None else None
            self.boxes.append(box)
            self.regions.append(region)
            self.indicators.append(
                box_indicator(box, self.camera.width, self.camera.height, self.frame, dtype) if box is not None else None
            )
            aim = region or box
            point = ((aim.x0 + aim.x1) / 2, (aim.y0 + aim.y1) / 2) if aim is not None else (0.5, 0.5)
            self.rays.append(target_ray(point, self.K, w, h))
        self.centroids = [torch.as_tensor(s.centroid, dtype=torch.float64) for s in labels.subjects]
        # Subject radius: 90th percentile of its Gaussians' distances to the centroid.
        self.radii = [
            float((scene.means[torch.as_tensor(s.gaussians, dtype=torch.long)].double() - c).norm(dim=-1).quantile(0.9))
            for s, c in zip(labels.subjects, self.centroids)
        ]
        self.fronts = [None if s.front is None else torch.as_tensor(s.front, dtype=torch.float64) for s in labels.subjects]
        # View angles are measured around each subject's view centre (the middle of its height),
        # and the camera keeps a floor margin bounded by the primary subject's height.
        spans = [view_centre(scene, s, np.asarray(labels.up, dtype=np.float64)) for s in labels.subjects]
        self.view_centres = [torch.as_tensor(centre, dtype=torch.float64) for centre, _ in spans]
        self.floor_margin = subject_floor_margin(spans[0][1]) if spans else None
        self.occluders: Occluders | None = None  # set by prepare_occlusion
        self.penalise_occlusion = False

    def clauses_hold(self, terms: dict[str, Tensor]) -> bool:
        """Whether every pseudo-label clause holds: each subject in view and enough of it inside
        the frame, its centroid in its region, its extent in its interval and the camera at an
        acceptable view angle, and the roll within the tolerance. Reads the unweighted terms of
        the last evaluation."""
        h_chord = 2.0 * math.sin(math.radians(self.config.roll_tolerance_deg) / 2.0)
        return (
            float(terms["hidden"]) == 0.0
            and float(terms["clearance"]) == 0.0
            and float(terms.get("free_space", 0.0)) == 0.0
            and float(terms.get("occlusion", 0.0)) == 0.0
            and float(terms["center"]) < 1e-5
            and float(terms["size"]) < 1e-6
            and float(terms["framing"]) < 1e-6
            and float(terms.get("view", 0.0)) < 1e-5 * len(self.labels.subjects)
            and float(terms["upright"]) < h_chord
        )

    def __call__(self, T_cw: Tensor) -> tuple[Tensor, dict[str, Tensor]]:
        wts, cfg = self.config.weights, self.config
        masks = self._masks(T_cw)  # (subjects, H, W)
        terms: dict[str, Tensor] = {}
        total = T_cw.new_zeros(())

        def add(name: str, weight: float, value: Tensor) -> None:
            nonlocal total
            terms[name] = terms.get(name, T_cw.new_zeros(())) + value.detach()
            total = total + weight * value.to(torch.float64)

        for k, label in enumerate(self.labels.subjects):
            layout = layout_terms(
                masks[k], self.boxes[k], self.regions[k], label.extent, self.indicators[k], self.frame, self.min_in_frame[k]
            )
            # Out of view the layout terms carry no signal: they are blended out and a constant
            # "hidden" penalty in, while look-at aims the centroid along the ray of its target
            # point from anywhere (behind the camera included).
            gate = (masks[k].sum() / cfg.mask_floor_px).clamp(0.0, 1.0).to(torch.float64)
            add("center", wts.center, gate * layout["center"])
            add("inside", wts.inside, gate * layout["inside"])
            add("outside", wts.outside, gate * layout["outside"])
            add("size", wts.size, gate * layout["size"])
            add("framing", wts.framing, gate * layout["framing"])
            add("hidden", wts.hidden, 1.0 - gate)
            add("look_at", wts.look_at, aim_loss(T_cw, self.centroids[k], self.rays[k]))
            add("clearance", wts.clearance, clearance_loss(T_cw, self.centroids[k], 1.2 * self.radii[k]))
            if label.view is not None:
                add(
                    "view",
                    wts.view,
                    view_loss(
                        T_cw,
                        self.view_centres[k],
                        self.fronts[k],
                        self.up,
                        label.view.azimuths_deg,
                        label.view.azimuth_tolerance_deg,
                        label.view.elevation_range_deg,
                    ),
                )
        add("upright", wts.upright, upright_loss(T_cw, self.up, self.roll))
        if self.occupancy is not None:
            add("free_space", wts.free_space, free_space_loss(T_cw, self.occupancy, self.floor_margin))
        if self.penalise_occlusion:
            visible = self._visible(T_cw)
            add("occlusion", wts.occlusion, (self.config.min_visible + 0.1 - visible).clamp_min(0.0).sum())
        return total, terms

    def _masks(self, T_cw: Tensor) -> Tensor:
        """The subjects' own masks (subjects, H, W) at ``T_cw``, each rendered without the rest of the scene."""
        gaussians, membership = self.subjects.around(camera_center(T_cw.detach()))
        out = render(gaussians, self.camera, T_cw=T_cw, extra=membership, colors=False, dtype=self.dtype, backend="cpu")
        return out.extra.permute(2, 0, 1)

    def prepare_occlusion(self, scene: GaussianScene) -> None:
        """Keep the whole scene for :meth:`visible_shares` and the occlusion term, which render
        only its possible occluders (:class:`Occluders`), on the occlusion canvas
        (``occlusion_long_side``)."""
        cfg, camera = self.config, self.unpadded
        if 0 < cfg.occlusion_long_side < max(camera.width, camera.height):
            camera = camera.with_long_side(cfg.occlusion_long_side)
        self.occlusion_camera = camera.padded(round(cfg.guard * camera.width), round(cfg.guard * camera.height))
        count = len(self.labels.subjects)
        self.occlusion_subjects = LodView(self.subjects.hierarchy, count, self.occlusion_camera, cfg.lod_pixels)
        self.occluders = Occluders(scene, self.labels, self.occlusion_camera, self.dtype, self.subjects.extent, cfg.lod_pixels)

    def _visible(self, T_cw: Tensor) -> Tensor:
        """Share of each subject's own mask left visible by the rest of the scene, on the
        occlusion canvas: (subjects,)."""
        centre = camera_center(T_cw.detach())
        options = dict(T_cw=T_cw, colors=False, dtype=self.dtype, backend="cpu")
        gaussians, membership = self.occlusion_subjects.around(centre)
        own = render(gaussians, self.occlusion_camera, extra=membership, **options).extra.sum((0, 1))
        gaussians, membership = self.occluders.around(centre)
        seen = render(gaussians, self.occlusion_camera, extra=membership, **options).extra.sum((0, 1))
        return (seen / own.clamp_min(1e-6)).clamp(0.0, 1.0).to(torch.float64)

    def visible_shares(self, T_cw: Tensor) -> list[float]:
        """Visible share of each subject at ``T_cw``, without gradient (after :meth:`prepare_occlusion`)."""
        with torch.no_grad():
            return self._visible(T_cw).tolist()


class Occluders:
    """The Gaussians that can change the subjects' visible shares for any camera centre within
    ``reach`` of the centre they were culled for: culled once, again only when the camera leaves
    that ball (the occlusion phase moves it little), so its steps render the Gaussians between the
    camera and the subjects instead of the whole scene.

    A Gaussian changes a subject's composited mask only where its footprint covers a pixel of the
    subject's footprint. The footprint box of a Gaussian at camera depth ``z`` is that of
    :func:`~capframe.render.torch_backend.may_touch_frame`: ``3 sqrt(1 + t^2) |L|_F f / z`` plus
    the 2D dilation and one pixel per axis (``|L|_F``: the root of the summed squared scales,
    ``t``: the projection's clamped slope). A pixel's ray at that depth therefore passes within
    ``sqrt(2) (3 sqrt(1 + t^2) |L|_F + z (3 sqrt(eps2d) + 1) / f)`` of the Gaussian's mean, its
    *reach*. The rays through the subjects' pixels, from any centre in the ball, run inside the
    convex hull of the ball and the subjects' bounding sphere widened by their reach (:attr:`body`),
    and on beyond the sphere's centre within twice that radius of it (to the subjects' far side);
    every Gaussian within its own reach of that region is kept, the rest skipped. Subjects are
    always kept. With ``pixels`` > 0 the cull runs on a level-of-detail cut of the whole scene
    (:func:`~capframe.render.lod.cached_hierarchy`, built once per query; cells never mix subjects
    and the rest) valid for every centre in the ball: far clutter is drawn as merged cells, and a
    merged cell's reach is that of its own covariance.
    """

    def __init__(
        self, scene: GaussianScene, labels: PseudoLabels, camera: Camera, dtype: torch.dtype, extent: float, pixels: float = 0.0
    ):
        self.scene, self.dtype, self.extent, self.pixels = scene, dtype, extent, pixels
        K, W, H = camera.K, camera.width, camera.height
        self.focal, self.cosine = float(max(K[0, 0], K[1, 1])), ray_cosine(K, W, H)
        # The largest clamped slope of the canvas (clamped_slopes: 30% beyond the borders).
        slope = max(
            (max(K[0, 2], W - K[0, 2]) + 0.15 * W) / K[0, 0],
            (max(K[1, 2], H - K[1, 2]) + 0.15 * H) / K[1, 1],
        )
        sigmas = math.sqrt(2.0 * SIGMA_MAX) * 1.01
        self.reach_per_spread = math.sqrt(2.0) * sigmas * math.sqrt(1.0 + slope**2)
        with torch.no_grad():
            self.means = scene.means.detach().to(torch.float64)
            self.reach_fixed = self.reach_per_spread * scene.scales.detach().to(torch.float64).norm(dim=1)  # (N,)
        # Reach per unit of depth: the dilation and the one-pixel slack at the smallest focal length.
        self.reach_per_depth = math.sqrt(2.0) * (sigmas * math.sqrt(EPS2D) + 1.0) / float(min(K[0, 0], K[1, 1]))
        subjects = [torch.as_tensor(label.gaussians, dtype=torch.long) for label in labels.subjects]
        self.owner = subject_owner(len(scene), subjects)
        self.subjects = len(labels.subjects)
        members = self.owner >= 0
        lo, hi = self.means[members].min(0).values, self.means[members].max(0).values
        self.target = (lo + hi) / 2
        self.sphere = float(((self.means[members] - self.target).norm(dim=1) + self.reach_fixed[members]).max())
        self.hierarchy = cached_hierarchy(scene, None, self.owner, dtype, SCENE_CELL) if pixels > 0 else None
        self.centre: Tensor | None = None

    def around(self, centre: Tensor) -> tuple[PreparedGaussians, Tensor]:
        """The prepared occluders (subjects included) for a camera at ``centre`` (3,) and their
        (M, subjects) membership, culled again when ``centre`` left the last ball."""
        if self.centre is None or float((centre - self.centre).norm()) > self.reach:
            self._cull(centre.to(torch.float64))
        return self.gaussians, self.membership

    def _cull(self, centre: Tensor) -> None:
        axis = self.target - centre
        distance = float(axis.norm())
        self.reach = 0.1 * self.sphere
        self.body = self.sphere + self.reach_per_depth * (distance + self.reach + self.sphere)
        self.centre = centre
        if self.hierarchy is not None:  # merged far away, valid anywhere in the ball
            source, owner, _ = self.hierarchy.cut(centre, self.focal, self.pixels, self.reach, self.cosine)
            all_means = source.means
            reach_fixed = self.reach_per_spread * source.spreads()
        else:
            source, owner, all_means, reach_fixed = None, self.owner, self.means, self.reach_fixed
        # The convex hull of the ball and the subjects' sphere: radius reach at the centre growing
        # linearly to body at the target, over the cosine of the cone's half-angle.
        slope = min((self.body - self.reach) / max(distance, 1e-300), 0.99)
        widen = 1.0 / math.sqrt(1.0 - slope**2)
        keep = []
        for start in range(0, len(all_means), CULL_CHUNK):
            means = all_means[start : start + CULL_CHUNK]
            offset = means - centre
            t = offset @ axis / max(distance**2, 1e-300)
            gap = (offset - t.clamp(0.0, 1.0)[:, None] * axis).norm(dim=1)
            radius = widen * (self.reach + (self.body - self.reach) * t.clamp(0.0, 1.0))
            radius = torch.where(t > 1.0, torch.full_like(t, 2.0 * self.body), radius)
            own = reach_fixed[start : start + CULL_CHUNK] + self.reach_per_depth * (offset.norm(dim=1) + self.reach)
            keep.append(start + ((gap <= radius + own) | (owner[start : start + CULL_CHUNK] >= 0)).nonzero()[:, 0])
        index = torch.cat(keep)
        if source is None:
            self.gaussians = prepare(self.scene.subset(index), self.dtype, extent=self.extent)
        else:
            self.gaussians = source.subset(index)
        self.gaussians = indexed(self.gaussians)  # rendered at every step until the next cull
        owner = owner[index]
        self.membership = torch.zeros(len(owner), self.subjects, dtype=self.dtype)
        inside = owner >= 0
        self.membership[inside.nonzero()[:, 0], owner[inside]] = 1.0


def free_space_loss(T_cw: Tensor, occupancy: Occupancy, floor_margin: float | None = None) -> Tensor:
    """``max(0, -slack / margin)`` of the camera centre (:meth:`Occupancy.slack`, keeping
    ``floor_margin`` above the floor when given): zero while the camera keeps its margin of free
    space, growing linearly (in margins) into walls, floors and objects. ()"""
    slack = occupancy.slack(camera_center(T_cw).unsqueeze(0), floor_margin)[0]
    return (-slack / occupancy.margin).clamp_min(0.0)


def _yaw_scan(
    objective: _Objective, T0: Tensor, pivot: Tensor, up: Tensor, steps: int
) -> tuple[Tensor, float, tuple[float, dict[str, float]] | None]:
    """The best of ``steps`` rotations of the start about the world up through the pivot.

    Gradient descent cannot undo some starts: two subjects in swapped order sit at a stationary
    point of the layout loss along the orbit, and a view side behind the subject is a long walk.
    A coarse scan of the orbit (or of the heading, when the pivot is the camera) fixes both for
    a few forward renders. Returns the start pose, its yaw in degrees, and the loss and its
    terms at ``T0`` itself (the scan's first rotation; None without a scan).
    """
    if steps <= 1:
        return T0, 0.0, None
    axis = T0[:3, :3] @ up  # world up in the camera frame
    unpivot_T0 = torch.linalg.inv(pivot) @ T0
    best, at_start = (math.inf, T0, 0.0), None
    with torch.no_grad():
        for k in range(steps):
            angle = 2.0 * math.pi * k / steps
            twist = torch.cat([axis * angle, torch.zeros(3, dtype=torch.float64)])
            T = pivot @ se3_exp(twist) @ unpivot_T0
            loss, terms = objective(T)
            loss = float(loss)
            if k == 0:
                at_start = (loss, {name: float(term) for name, term in terms.items()})
            if loss < best[0] - 1e-9:
                best = (loss, T, math.degrees(angle))
    return best[1], best[2], at_start


def refine_pose(
    scene: GaussianScene,
    camera: Camera,
    labels: PseudoLabels,
    scale: float,
    config: RefineConfig | None = None,
    dtype: torch.dtype = torch.float32,
    occupancy: Occupancy | None = None,
) -> RefineResult:
    """Optimise ``camera``'s pose so the subjects satisfy their pseudo labels.

    Args:
        scene: the Gaussians.
        camera: the initial camera (its image size and intrinsics are kept).
        labels: pseudo labels from Translate.
        scale: the scene scale (translation steps are relative to it).
        occupancy: the scene's free space; with it the camera is kept out of geometry.
    """
    config = config or RefineConfig()
    threads = torch.get_num_threads()
    torch.set_num_threads(config.threads)
    try:
        return _refine(scene, camera, labels, scale, config, dtype, occupancy)
    finally:
        torch.set_num_threads(threads)


def _refine(
    scene: GaussianScene,
    camera: Camera,
    labels: PseudoLabels,
    scale: float,
    config: RefineConfig,
    dtype: torch.dtype,
    occupancy: Occupancy | None,
) -> RefineResult:
    start = time.perf_counter()
    objective = _Objective(scene, camera.with_long_side(config.long_side), labels, config, dtype, occupancy)
    run = PoseDescent(objective, scale, config)
    T = run.descend(torch.as_tensor(camera.T_cw, dtype=torch.float64), config.iterations, scan=True)
    # Other objects may hide a subject that satisfies every clause: only then pay for full-scene
    # renders, continuing from the best pose with the occlusion term on.
    remaining = min(config.occlusion_iterations, config.iterations - run.steps)
    occlusion_start = time.perf_counter()
    if remaining > 0:
        objective.prepare_occlusion(scene)
        if min(objective.visible_shares(T)) < config.min_visible:
            objective.penalise_occlusion = True
            # Scan again, now with the whole scene in the objective: it finds an orbit position
            # where nothing stands in front of the subject (the current pose is one candidate).
            T = run.descend(T, remaining, scan=True)
    return run.result(T, start, time.perf_counter() - occlusion_start)


class PoseDescent:
    """Adam steps on the pose, recording the trajectory, losses and loss terms across phases."""

    def __init__(self, objective: _Objective, scale: float, config: RefineConfig):
        self.objective, self.scale, self.config = objective, scale, config
        self.trajectory: list[np.ndarray] = []
        self.losses: list[float] = []
        self.history: dict[str, list[float]] = {}
        self.best_terms: dict[str, float] = {}
        self.stop_reason = "max_iterations"
        self.steps = 0  # Adam steps over all phases
        self.at_start: tuple[float, dict[str, float]] | None = None  # loss and terms at the given pose

    def result(self, T: Tensor, start: float, occlusion_seconds: float = 0.0) -> RefineResult:
        """The run as a :class:`RefineResult` with ``T`` its best pose (``start``: its
        ``time.perf_counter()`` at the beginning; ``occlusion_seconds``: the occlusion phase's share)."""
        return RefineResult(
            T_cw=T.numpy(),
            iterations=self.steps,
            stop_reason=self.stop_reason,
            terms=self.best_terms,
            trajectory=np.stack(self.trajectory),
            losses=np.asarray(self.losses),
            history={k: np.asarray(v) for k, v in self.history.items()},
            seconds=time.perf_counter() - start,
            occlusion_seconds=occlusion_seconds,
            start_loss=self.at_start[0] if self.at_start else None,
            start_terms=self.at_start[1] if self.at_start else None,
        )

    def descend(self, T0: Tensor, iterations: int, scan: bool) -> Tensor:
        """Optimise from ``T0`` for at most ``iterations`` steps, after a yaw scan if ``scan``;
        returns the best pose. Each call records one more evaluation than it takes steps."""
        config, objective = self.config, self.objective
        pivot = torch.eye(4, dtype=torch.float64)
        subject_in_camera = T0[:3, :3] @ objective.centroids[0] + T0[:3, 3]
        if subject_in_camera[2] > 0:  # behind the camera an orbit never brings it into view: turn instead
            pivot[:3, 3] = subject_in_camera
        if scan:
            T0, _, at_start = _yaw_scan(objective, T0, pivot, objective.up, config.yaw_scan)
            self.at_start = self.at_start or at_start  # the first phase's start is the given pose
        unpivot_T0 = torch.linalg.inv(pivot) @ T0
        rotation = torch.zeros(3, dtype=torch.float64, requires_grad=True)
        translation = torch.zeros(3, dtype=torch.float64, requires_grad=True)
        # beta2 = 0.99 (a ~100-step memory, not ~1000): the gradient scale drops by orders of
        # magnitude once an out-of-view subject enters the frame, and a long memory of the large
        # gradients before would leave the steps tiny afterwards.
        optimizer = torch.optim.Adam(
            [{"params": [rotation], "lr": config.lr_rotation}, {"params": [translation], "lr": config.lr_translation}],
            betas=(0.9, 0.99),
        )
        best_loss, best_T, best_history, settled = math.inf, T0, [], 0
        self.stop_reason = "max_iterations"
        for step in range(iterations + 1):
            T = pivot @ se3_exp(torch.cat([rotation, translation * self.scale])) @ unpivot_T0
            loss, terms = objective(T)
            value = float(loss.detach())
            self.trajectory.append(T.detach().numpy().copy())
            self.losses.append(value)
            for name, term in terms.items():
                self.history.setdefault(name, [math.nan] * (len(self.losses) - 1)).append(float(term))
            if value < best_loss:
                best_loss, best_T, self.best_terms = value, T.detach(), {k: float(v) for k, v in terms.items()}
            best_history.append(best_loss)
            settled = settled + 1 if objective.clauses_hold(terms) else 0
            if settled >= config.settle:
                self.stop_reason = "satisfied"
                break
            if best_loss <= 1e-4 * max(self.losses[-1 - step], 1e-12):
                self.stop_reason = "converged"
                break
            window_start = best_history[-1 - config.patience] if step >= config.patience else math.inf
            if window_start - best_loss < config.rel_tol * window_start:
                self.stop_reason = "plateau"
                break
            if step == iterations:
                break
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            optimizer.step()
            self.steps += 1
        for values in self.history.values():  # terms that appeared in a later phase
            values.extend([math.nan] * (len(self.losses) - len(values)))
        return best_T
