"""Refine losses. Each takes tensors and returns a scalar (or a dict of scalars), is finite with
finite gradients everywhere including the degenerate cases of DESIGN §5, and measures image
distances in units of the image's long side so the losses do not depend on the resolution.

Camera poses are ``T_cw`` (4, 4) with OpenCV axes; the world up ``up`` is a unit (3,) vector.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import torch
from torch import Tensor

from ..geometry.camera import camera_axes, camera_center, view_angles, view_direction
from ..render.masks import bbox_fractions

_TINY = 1e-12
_POLE_FADE = math.sin(math.radians(5.0))  # the azimuth term fades within about this of the poles


class Frame(NamedTuple):
    """Where the photo lies on the canvas a mask was rendered on, in pixels. Refine renders the
    subject masks with a guard band around the frame, so mass beyond the frame counts."""

    x: float
    y: float
    width: int
    height: int

    @classmethod
    def whole(cls, mask: Tensor) -> Frame:
        return cls(0.0, 0.0, mask.shape[1], mask.shape[0])


@dataclass(frozen=True)
class Box:
    """A normalised layout box ``[x0, y0, x1, y1]`` (frame fractions), rotated by ``angle_deg``
    about its centre (counter-clockwise as seen on screen, like the scene under a positive roll)."""

    x0: float
    y0: float
    x1: float
    y1: float
    angle_deg: float = 0.0

    def on(self, frame: Frame) -> tuple[Tensor, Tensor, float]:
        """Centre (2,) and half-sizes (2,) in canvas pixels, and the angle in radians."""
        w, h = frame.width, frame.height
        centre = torch.tensor([frame.x + (self.x0 + self.x1) / 2 * w, frame.y + (self.y0 + self.y1) / 2 * h], dtype=torch.float64)
        half = torch.tensor([(self.x1 - self.x0) / 2 * w, (self.y1 - self.y0) / 2 * h], dtype=torch.float64)
        return centre, half, math.radians(self.angle_deg)


def to_box_frame(points: Tensor, centre: Tensor, angle: float) -> Tensor:
    """Pixel points (..., 2) in the frame of a box rotated by ``angle`` about ``centre``.

    The scene under a roll appears rotated counter-clockwise on screen: in image axes (y down)
    that maps an offset (dx, dy) to (dx cos + dy sin, -dx sin + dy cos); this applies the inverse.
    """
    c, s = math.cos(angle), math.sin(angle)
    d = points - centre.to(points.dtype)
    return torch.stack([c * d[..., 0] - s * d[..., 1], s * d[..., 0] + c * d[..., 1]], -1)


def box_indicator(box: Box, canvas_width: int, canvas_height: int, frame: Frame | None = None, dtype=torch.float32) -> Tensor:
    """(H, W) canvas: 1 for pixel centres inside the (rotated) box, else 0."""
    centre, half, angle = box.on(frame or Frame(0.0, 0.0, canvas_width, canvas_height))
    ys, xs = torch.meshgrid(
        torch.arange(canvas_height, dtype=torch.float64) + 0.5,
        torch.arange(canvas_width, dtype=torch.float64) + 0.5,
        indexing="ij",
    )
    local = to_box_frame(torch.stack([xs, ys], -1), centre, angle)
    return (local.abs() <= half).all(-1).to(dtype)


def soft_centroid(mask: Tensor) -> tuple[Tensor, Tensor]:
    """Mask-weighted mean pixel position (2,) and the mask's mass. (H, W) -> (2,), ()."""
    height, width = mask.shape
    xs = torch.arange(width, dtype=mask.dtype, device=mask.device) + 0.5
    ys = torch.arange(height, dtype=mask.dtype, device=mask.device) + 0.5
    mass = mask.sum()
    safe = mass.clamp_min(_TINY)
    return torch.stack([(mask.sum(0) * xs).sum() / safe, (mask.sum(1) * ys).sum() / safe]), mass


def mask_extent(mask: Tensor, centroid: Tensor, mass: Tensor, frame: Frame | None = None) -> Tensor:
    """Estimated shot size of a mask: ``max(bbox width / W, bbox height / H)`` of the frame, from
    its second moments (a filled ellipse spans 4 standard deviations), as a smooth maximum.
    (H, W) -> ()."""
    height, width = mask.shape
    frame = frame or Frame.whole(mask)
    xs = torch.arange(width, dtype=mask.dtype, device=mask.device) + 0.5
    ys = torch.arange(height, dtype=mask.dtype, device=mask.device) + 0.5
    safe = mass.clamp_min(_TINY)
    var_x = (mask.sum(0) * (xs - centroid[0]) ** 2).sum() / safe
    var_y = (mask.sum(1) * (ys - centroid[1]) ** 2).sum() / safe
    spans = 4.0 * torch.sqrt(torch.stack([var_x / frame.width**2, var_y / frame.height**2]) + _TINY)
    return 0.02 * torch.logsumexp(spans / 0.02, 0)  # within 0.014 of the larger span


def frame_crop(mask: Tensor, frame: Frame) -> Tensor:
    """The part of a canvas mask (H, W) that is the photo: (frame.height, frame.width)."""
    x, y = round(frame.x), round(frame.y)
    return mask[y : y + frame.height, x : x + frame.width]


def bbox_extent(mask: Tensor, frame: Frame | None = None) -> float:
    """The checker's shot size of a mask, ``max(bbox width / W, bbox height / H)`` inside the
    frame (0 when empty). No gradient. (H, W) -> float."""
    return max(bbox_fractions(frame_crop(mask.detach(), frame or Frame.whole(mask))))


def in_frame_share(mask: Tensor, mass: Tensor, frame: Frame) -> Tensor:
    """Share of a mask's mass inside the frame. (H, W), () -> ()."""
    return frame_crop(mask, frame).sum() / mass.clamp_min(_TINY)


def layout_terms(
    mask: Tensor,
    box: Box | None,
    region: Box | None,
    extent: tuple[float, float] | None = None,
    inside: Tensor | None = None,
    frame: Frame | None = None,
    min_in_frame: float | None = None,
) -> dict[str, Tensor]:
    """Layout losses of one subject's opacity mask (H, W) rendered on a canvas that holds the
    photo at ``frame`` (default: the whole mask).

    * ``center``: distance of the soft centroid to the (rotated) region, 0 inside, in units of
      the frame's long side;
    * ``inside``: 1 - the share of the mask inside the box;
    * ``outside``: the share of the mask outside the box;
    * ``size``: log-distance of the mask's extent to the ``extent`` interval ``(lo, hi)`` of a
      requested shot size, 0 inside. Its value is the checker's extent (:func:`bbox_extent`),
      its gradient that of the smooth :func:`mask_extent`: the bounding box has no useful
      gradient, and the second moments misjudge the extent of uneven shapes (a floor lamp's
      shade and foot make its 4 sigma span up to twice its height);
    * ``framing``: how far the share of the mask inside the frame falls short of
      ``min_in_frame``, 0 when it does not (or when ``min_in_frame`` is None).

    ``inside``/``outside`` as the paper defines them are the same share seen from both sides;
    both are kept so their weights match the paper's. ``inside`` may pass a precomputed
    :func:`box_indicator` of ``box``.
    """
    frame = frame or Frame.whole(mask)
    zero = mask.sum() * 0.0
    terms = {"center": zero, "inside": zero, "outside": zero, "size": zero, "framing": zero}
    centroid, mass = soft_centroid(mask)
    if region is not None:
        centre, half, angle = region.on(frame)
        outside_by = (to_box_frame(centroid, centre, angle).abs() - half.to(mask.dtype)).clamp_min(0.0)
        # sqrt of a sum of squares with a floor: its gradient stays finite at the box border.
        terms["center"] = torch.sqrt((outside_by * outside_by).sum() + _TINY) / max(frame.width, frame.height)
    if box is not None:
        indicator = box_indicator(box, mask.shape[1], mask.shape[0], frame, mask.dtype) if inside is None else inside
        share_in = (mask * indicator).sum() / mass.clamp_min(_TINY)
        terms["inside"] = 1.0 - share_in
        terms["outside"] = 1.0 - share_in
    if extent is not None:
        log_smooth = torch.log(mask_extent(mask, centroid, mass, frame))
        hard = bbox_extent(mask, frame)
        log_extent = log_smooth + (math.log(hard) - log_smooth).detach() if hard > 0.0 else log_smooth
        terms["size"] = (log_extent - math.log(extent[1])).clamp_min(0.0)
        if extent[0] > 0.0:  # a wide shot's interval starts at 0: no lower bound
            terms["size"] = terms["size"] + (math.log(extent[0]) - log_extent).clamp_min(0.0)
    if min_in_frame is not None:
        terms["framing"] = (min_in_frame - in_frame_share(mask, mass, frame)).clamp_min(0.0)
    return terms


def target_ray(point: tuple[float, float], K: Tensor, width: int, height: int) -> Tensor:
    """Unit camera-frame ray (3,) through a normalised image point."""
    u, v = point[0] * width, point[1] * height
    ray = torch.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], torch.ones((), dtype=K.dtype)])
    return ray / ray.norm()


def aim_loss(T_cw: Tensor, point: Tensor, ray: Tensor) -> Tensor:
    """Chord between the unit camera-frame direction to a world point and a target ray (about the
    angle between them, in radians, for small angles; 2 when opposite). Pulls the point onto the
    ray from anywhere, behind the camera included, with a gradient that does not fade near the
    target. ()."""
    p = T_cw[:3, :3] @ point + T_cw[:3, 3]
    return _chord(p / p.norm().clamp_min(_TINY), ray)


def clearance_loss(T_cw: Tensor, point: Tensor, radius: float) -> Tensor:
    """``max(0, 1 - d / radius)`` for the camera at distance ``d`` from ``point``: pushes the
    camera out of a subject with a gradient of constant size, zero outside the radius. ()"""
    offset = camera_center(T_cw) - point
    distance = torch.sqrt(offset @ offset + 1e-24)
    return (1.0 - distance / radius).clamp_min(0.0)


def _chord(a: Tensor, b: Tensor) -> Tensor:
    """|a - b| for unit vectors, with a floor that keeps the gradient finite at a = b."""
    d = a - b
    return torch.sqrt((d * d).sum() + 1e-12)


def upright_loss(T_cw: Tensor, up: Tensor, roll_rad: float = 0.0) -> Tensor:
    """Penalise the camera's roll about its forward axis away from ``roll_rad``, never its pitch.

    With ``(A, B) = (x0 . up, -y0 . up)`` for the camera axes un-rolled by the requested roll,
    ``A = -h sin(d)`` and ``B = h cos(d)`` where ``d`` is the roll error and ``h`` the length of
    ``up`` projected onto the image plane. The loss ``sqrt(A^2 + (h - B)^2) = h |2 sin(d/2)|`` is
    the chord of the roll error scaled by ``h``: zero at the asked roll for any pitch, largest
    upside down, vanishing where roll is undefined (looking straight up or down), with a
    gradient that does not fade near the target. Floors keep the gradient finite everywhere.
    """
    right, down, _ = camera_axes(T_cw)
    c, s = math.cos(roll_rad), math.sin(roll_rad)
    a = (c * right - s * down) @ up
    b = -((s * right + c * down) @ up)
    h = torch.sqrt(a * a + b * b + 1e-12)
    return torch.sqrt(a * a + (h - b) ** 2 + 1e-12)


def view_loss(
    T_cw: Tensor,
    subject: Tensor,
    front: Tensor | None,
    up: Tensor,
    azimuths_deg: tuple[float, ...],
    azimuth_tolerance_deg: float,
    elevation_range_deg: tuple[float, float] | None,
) -> Tensor:
    """Distance of the camera's direction from the subject, ``p``, to the acceptable view angles.

    * azimuth: the chord between the horizontal direction of ``p`` and ``d``, the nearest
      accepted direction (the direction itself inside an arc ``target +- tolerance``, else the
      nearest arc end), fading within a few degrees of straight above or below, where azimuth
      is undefined;
    * elevation: how far ``p . up`` lies outside ``[sin lo, sin hi]``.

    ``d`` is the exact minimiser of the chord over the arcs, so treating it as a constant gives
    the exact gradient (Danskin). Without a ``front`` only the elevation counts. ()
    """
    offset = camera_center(T_cw) - subject
    p = offset / offset.norm().clamp_min(_TINY)
    height = p @ up
    loss = p.new_zeros(())
    if elevation_range_deg is not None:
        lo, hi = (math.sin(math.radians(e)) for e in elevation_range_deg)
        loss = loss + (lo - height).clamp_min(0.0) + (height - hi).clamp_min(0.0)
    if front is not None and azimuths_deg:
        q = p - height * up
        q_sq = q @ q
        with torch.no_grad():
            azimuth, _ = view_angles(camera_center(T_cw.detach()), subject, front, up)
            nearest = _nearest_in_arcs(
                float(azimuth), [math.radians(a) for a in azimuths_deg], math.radians(azimuth_tolerance_deg)
            )
            d = view_direction(torch.as_tensor(nearest, dtype=p.dtype), torch.zeros((), dtype=p.dtype), front, up)
        gap = q / torch.sqrt(q_sq + 1e-12) - d
        # Full weight away from the poles, fading within a few degrees of them (where azimuth is
        # undefined); a cos(elevation) weight would make the pole a cheap escape from a large
        # azimuth error.
        weight = q_sq / (q_sq + _POLE_FADE**2)
        loss = loss + weight * torch.sqrt(gap @ gap + 1e-12)
    return loss


def _nearest_in_arcs(angle: float, centres: list[float], half_width: float) -> float:
    """The angle itself when inside any arc ``centre +- half_width``, else the nearest arc end."""
    best, best_gap = angle, math.inf
    for centre in centres:
        delta = math.remainder(angle - centre, 2 * math.pi)
        if abs(delta) <= half_width:
            return angle
        gap = abs(delta) - half_width
        if gap < best_gap:
            best, best_gap = centre + math.copysign(half_width, delta), gap
    return best


__all__ = [
    "Box",
    "Frame",
    "aim_loss",
    "box_indicator",
    "clearance_loss",
    "layout_terms",
    "mask_extent",
    "soft_centroid",
    "target_ray",
    "to_box_frame",
    "upright_loss",
    "view_loss",
]
