"""A tiny synthetic scene directory with ground truth, built in a tilted, offset, scaled world."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import torch

from capframe.geometry import look_at, view_direction
from capframe.scene import Camera, GaussianScene, SemanticObject, write_cameras_json, write_ply
from capframe.scene.directory import write_semantics

# Objects in a local frame with +z up; (name, colour, centre, radius, front or None).
LOCAL_OBJECTS = [
    ("teddy bear", "brown", (0.0, 0.0, 0.3), 0.3, (0.0, -1.0, 0.0)),
    ("armchair", "red", (1.3, 0.7, 0.35), 0.35, (-1.0, 0.0, 0.0)),
    ("armchair", "blue", (-1.3, 0.8, 0.35), 0.35, (1.0, -0.3, 0.0)),
    ("vase", "white", (0.5, -1.1, 0.2), 0.2, None),
]
ALIASES = {"teddy bear": ["bear", "plush toy"], "armchair": ["chair"], "vase": ["pot"]}
COLORS = {"brown": (0.5, 0.3, 0.1), "red": (0.9, 0.1, 0.1), "blue": (0.1, 0.2, 0.9), "white": (0.9, 0.9, 0.9)}


def world_transform(tilt_deg: float = 20.0, scale: float = 2.0, offset=(5.0, -3.0, 10.0)):
    """Local -> world: rotate by tilt_deg about a skew axis, scale, offset. Returns (R, s, t)."""
    axis = np.array([1.0, 2.0, 0.5])
    axis /= np.linalg.norm(axis)
    a = math.radians(tilt_deg)
    Kx = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + math.sin(a) * Kx + (1 - math.cos(a)) * Kx @ Kx
    return R, scale, np.asarray(offset, dtype=np.float64)


def _ball(n: int, radius: float, g: torch.Generator) -> torch.Tensor:
    d = torch.randn(n, 3, generator=g, dtype=torch.float64)
    d = d / d.norm(dim=1, keepdim=True)
    return d * radius * torch.rand(n, 1, generator=g, dtype=torch.float64) ** (1 / 3)


def build_scene(
    root: Path,
    *,
    per_object: int = 160,
    floor: bool = True,
    seed: int = 0,
    tilt_deg: float = 20.0,
    scale: float = 2.0,
    offset=(5.0, -3.0, 10.0),
    objects=LOCAL_OBJECTS,
) -> dict:
    """Write scene.ply, cameras.json, semantics.json, labels.npy and ground_truth.json into ``root``.

    Every object is a ball of small Gaussians (opaque, radius 0.85 r plus the Gaussians' spread);
    the floor (label -1) is a disc of flat Gaussians at local z = 0. Returns the ground truth dict.
    """
    root.mkdir(parents=True, exist_ok=True)
    R, s, t = world_transform(tilt_deg, scale, offset)
    to_world = lambda p: (np.asarray(p, dtype=np.float64) @ R.T) * s + t  # noqa: E731
    g = torch.Generator().manual_seed(seed)
    means, scales, colors, labels = [], [], [], []
    gt_objects, semantics = [], []
    for i, (name, color, centre, radius, front) in enumerate(objects):
        means.append(_ball(per_object, 0.85 * radius, g) + torch.tensor(centre, dtype=torch.float64))
        scales.append(torch.full((per_object, 3), 0.09 * radius, dtype=torch.float64))
        colors.append(torch.tensor(COLORS[color]).expand(per_object, 3))
        labels.append(torch.full((per_object,), i))
        world_front = None if front is None else (np.asarray(front, dtype=np.float64) @ R.T).tolist()
        gt_objects.append(
            {
                "id": i,
                "name": name,
                "aliases": ALIASES.get(name, []),
                "color": color,
                "center": to_world(centre).tolist(),
                "radius": radius * s,
                "front": world_front,
                "label": i,
            }
        )
        semantics.append(
            SemanticObject(
                i,
                f"{color} {name}" if name == "armchair" else name,
                ALIASES.get(name, []),
                front is None,
                None if front is None else np.asarray(world_front),
            )
        )
    if floor:
        n = 400
        r = 3.0 * torch.rand(n, generator=g, dtype=torch.float64).sqrt()
        a = 2 * math.pi * torch.rand(n, generator=g, dtype=torch.float64)
        means.append(torch.stack([r * torch.cos(a), r * torch.sin(a), torch.full_like(r, -0.02)], 1))
        sc = torch.full((n, 3), 0.15, dtype=torch.float64)
        sc[:, 2] = 0.005
        scales.append(sc)
        colors.append(torch.tensor([0.4, 0.4, 0.4]).expand(n, 3))
        labels.append(torch.full((n,), -1))
    local = torch.cat(means)
    world = torch.from_numpy(to_world(local.numpy()))
    n = len(world)
    quat = torch.tensor(_rotmat_to_quat(R), dtype=torch.float64).expand(n, 4).clone()
    scene = GaussianScene.from_activated(
        world.float(), quat.float(), (torch.cat(scales) * s).float(), torch.full((n,), 0.95), torch.cat(colors).float()
    )
    write_ply(scene, root / "scene.ply")
    write_semantics(semantics, torch.cat(labels).numpy(), root)
    up = (np.array([0.0, 0.0, 1.0]) @ R.T).tolist()
    cams = []
    for k in range(6):
        eye = to_world([3.5 * math.cos(k), 3.5 * math.sin(k), 1.2])
        T = look_at(torch.tensor(eye), torch.tensor(to_world([0, 0, 0.3])), torch.tensor(up, dtype=torch.float64))
        cams.append(Camera(T.numpy(), np.array([[140.0, 0, 80], [0, 140.0, 60], [0, 0, 1]]), 160, 120, name=f"v{k}"))
    write_cameras_json(cams, root / "cameras.json")
    gt = {"up": up, "scale": 3.5 * s, "objects": gt_objects}
    (root / "ground_truth.json").write_text(json.dumps(gt, indent=1))
    return gt


def _rotmat_to_quat(R: np.ndarray) -> list[float]:
    from capframe.geometry import rotmat_to_quat

    return rotmat_to_quat(torch.tensor(R)).tolist()


def obj(gt: dict, name: str, color: str | None = None) -> dict:
    return next(o for o in gt["objects"] if o["name"] == name and (color is None or o["color"] == color))


def point_camera(
    C,
    S,
    up,
    *,
    roll: float = 0.0,
    point: tuple[float, float] = (0.5, 0.5),
    width: int = 160,
    height: int = 120,
    focal: float = 140.0,
) -> Camera:
    """A camera at ``C`` rolled by ``roll`` degrees whose image of the world point ``S`` is the
    normalised ``point`` (the look-at target is shifted by a few fixed-point steps)."""
    f64 = dict(dtype=torch.float64)
    C, S, up = (torch.as_tensor(np.asarray(v, dtype=np.float64)) for v in (C, S, up))
    K = torch.tensor([[focal, 0, width / 2], [0, focal, height / 2], [0, 0, 1]], **f64)
    target = S.clone()
    for _ in range(20):
        T = look_at(C, target, up, math.radians(roll))
        q = T[:3, :3] @ S + T[:3, 3]
        uv = (K @ (q / q[2]))[:2] / torch.tensor([width, height], **f64)
        err = torch.tensor(point, **f64) - uv
        target = target - (err[0] * width * T[0, :3] + err[1] * height * T[1, :3]) * (target - C).norm() / focal
    return Camera(T.numpy(), K.numpy(), width, height, name="test")


def aim_camera(
    gt: dict,
    subject: dict,
    *,
    azimuth: float,
    elevation: float,
    distance: float,
    roll: float = 0.0,
    point: tuple[float, float] = (0.5, 0.5),
    **size,
) -> Camera:
    """A camera at (azimuth, elevation) degrees and ``distance`` radii around ``subject`` (view
    angles of DESIGN §3 with the subject's front; an arbitrary horizontal front if it has none),
    rolled by ``roll`` degrees, with the subject's centre imaged at the normalised ``point``."""
    f64 = dict(dtype=torch.float64)
    up = torch.tensor(gt["up"], **f64)
    front = subject["front"]
    if front is None:
        front = torch.linalg.cross(up, torch.tensor([1.0, 0.0, 0.0], **f64)).tolist()
    d = view_direction(
        torch.tensor(math.radians(azimuth), **f64), torch.tensor(math.radians(elevation), **f64), torch.tensor(front, **f64), up
    )
    S = np.asarray(subject["center"])
    C = S + distance * subject["radius"] * d.numpy()
    return point_camera(C, S, gt["up"], roll=roll, point=point, **size)
