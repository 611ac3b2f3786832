"""Small random fixtures for the scene I/O tests (Gaussians, cameras, reference-style files)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import torch

from capframe.geometry import look_at
from capframe.scene import Camera, GaussianScene


def random_scene(n: int = 50, degree: int = 3, seed: int = 0) -> GaussianScene:
    """n random float32 Gaussians with SH degree ``degree``."""
    g = torch.Generator().manual_seed(seed)
    quats = torch.randn(n, 4, generator=g)
    return GaussianScene.from_activated(
        means=torch.randn(n, 3, generator=g),
        quats=quats / quats.norm(dim=-1, keepdim=True),
        scales=torch.exp(torch.randn(n, 3, generator=g) * 0.3 - 3.0),
        opacities=torch.rand(n, generator=g),
        colors_or_sh=torch.randn(n, (degree + 1) ** 2, 3, generator=g) * 0.3,
    )


def random_cameras(k: int = 5, seed: int = 0) -> list[Camera]:
    """k cameras on a ring looking at the origin, with distinct, non-square intrinsics."""
    rng = np.random.default_rng(seed)
    cameras = []
    for i in range(k):
        angle = 2 * math.pi * i / k
        f64 = dict(dtype=torch.float64)
        eye = torch.tensor([3 * math.cos(angle), 3 * math.sin(angle), 0.5 + rng.uniform(-0.3, 0.3)], **f64)
        up = torch.tensor([0.0, 0.0, 1.0], **f64)
        T_cw = look_at(eye, torch.zeros(3, **f64), up, roll=float(rng.uniform(-0.2, 0.2))).numpy()
        width, height = 64 + 2 * i, 48 + i
        cx, cy = width / 2 + rng.uniform(-2, 2), height / 2 + rng.uniform(-2, 2)
        K = np.array([[70.0 + i, 0, cx], [0, 72.5 + i, cy], [0, 0, 1]])
        cameras.append(Camera(T_cw=T_cw, K=K, width=width, height=height, name=f"view_{i:03d}"))
    return cameras


INRIA_HEAD = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
INRIA_TAIL = ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]


def inria_names(degree: int) -> list[str]:
    """Property order of the reference writer for SH degree ``degree``."""
    return INRIA_HEAD + [f"f_rest_{i}" for i in range(3 * ((degree + 1) ** 2 - 1))] + INRIA_TAIL


def random_inria_columns(n: int, degree: int, seed: int = 0) -> dict[str, np.ndarray]:
    """Random float32 columns of an Inria PLY (zero normals, non-degenerate quaternions)."""
    rng = np.random.default_rng(seed)
    columns = {name: rng.standard_normal(n).astype(np.float32) for name in inria_names(degree)}
    for name in ("nx", "ny", "nz"):
        columns[name] = np.zeros(n, np.float32)
    columns["rot_0"] = np.abs(columns["rot_0"]) + np.float32(0.5)
    return columns


def write_ply_by_hand(
    path: Path, columns: dict[str, np.ndarray], types: dict[str, str] | None = None, fmt: str = "binary_little_endian"
) -> None:
    """A PLY with one vertex element, written without capframe: properties in ``columns`` order,
    each of PLY type ``types[name]`` (default float), in ``fmt`` (binary either endian, or ascii)."""
    types = types or {}
    np_types = {"float": "f4", "double": "f8", "uchar": "u1", "int": "i4"}
    names = list(columns)
    n = len(next(iter(columns.values())))
    header = f"ply\nformat {fmt} 1.0\nelement vertex {n}\n"
    header += "".join(f"property {types.get(name, 'float')} {name}\n" for name in names) + "end_header\n"
    if fmt == "ascii":
        rows = zip(*(columns[name].tolist() for name in names))
        body = "".join(" ".join(repr(v) for v in row) + "\n" for row in rows).encode()
    else:
        endian = "<" if fmt == "binary_little_endian" else ">"
        dtype = np.dtype([(name, endian + np_types[types.get(name, "float")]) for name in names])
        table = np.empty(n, dtype=dtype)
        for name in names:
            table[name] = columns[name]
        body = table.tobytes()
    path.write_bytes(header.encode("ascii") + body)


def inria_cameras_entries(cameras: list[Camera]) -> list[dict]:
    """cameras.json entries as the reference trainer writes them (no cx, cy): position is the
    camera centre, rotation the camera-to-world rotation, both computed here from T_cw."""
    entries = []
    for i, cam in enumerate(cameras):
        c2w = np.linalg.inv(cam.T_cw)
        entries.append(
            {
                "id": i,
                "img_name": cam.name,
                "width": cam.width,
                "height": cam.height,
                "position": c2w[:3, 3].tolist(),
                "rotation": [row.tolist() for row in c2w[:3, :3]],
                "fy": float(cam.K[1, 1]),
                "fx": float(cam.K[0, 0]),
            }
        )
    return entries


def centred(cameras: list[Camera]) -> list[Camera]:
    """The cameras with their principal points moved to the image centre (Inria's assumption)."""
    out = []
    for cam in cameras:
        K = cam.K.copy()
        K[0, 2], K[1, 2] = cam.width / 2, cam.height / 2
        out.append(Camera(T_cw=cam.T_cw, K=K, width=cam.width, height=cam.height, name=cam.name))
    return out


def touch_images(folder: Path, cameras: list[Camera], suffix: str = ".png") -> None:
    """Placeholder image files named after the cameras (content distinct per file)."""
    folder.mkdir(parents=True, exist_ok=True)
    for cam in cameras:
        (folder / f"{cam.name}{suffix}").write_bytes(f"image {cam.name}".encode())


def assert_same_cameras(a, b, atol=1e-12):
    assert [c.name for c in a] == [c.name for c in b]
    for x, y in zip(a, b):
        np.testing.assert_allclose(x.T_cw, y.T_cw, rtol=0, atol=atol)
        np.testing.assert_allclose(x.K, y.K, rtol=0, atol=atol)
        assert (x.width, x.height) == (y.width, y.height)
