"""World-up estimation: camera consensus, vanishing directions of drawn edges, fusion, files, CLI."""

from __future__ import annotations

import json
import math

import cv2
import numpy as np
import pytest
from conftest import make_scene

from capframe.cli import main
from capframe.errors import InputError
from capframe.geometry.gravity import GravityEstimate, camera_up_consensus, estimate_gravity, vanishing_up, world_up
from capframe.scene import Camera, write_cameras_json, write_ply
from capframe.scene.directory import SceneMeta, write_scene_meta

K = np.array([[300.0, 0.0, 160.0], [0.0, 300.0, 120.0], [0.0, 0.0, 1.0]])


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b)))


def random_up(rng: np.random.Generator) -> np.ndarray:
    """A world up tilted away from every axis."""
    up = rng.normal(size=3)
    return up / np.linalg.norm(up)


def horizontal_basis(up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    e1 = np.cross(up, [0.3, -0.5, 0.8])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(up, e1)


def camera(up, heading, pitch, roll=0.0, center=(0.0, 0.0, 0.0), name="v", image_path=None) -> Camera:
    """Camera looking along ``heading`` (radians, about ``up``) pitched by ``pitch`` (radians, > 0
    looks up) and rolled by ``roll`` (radians, DESIGN §3 sign); its x-axis is horizontal at zero roll."""
    e1, e2 = horizontal_basis(up)
    h = math.cos(heading) * e1 + math.sin(heading) * e2
    forward = math.cos(pitch) * h + math.sin(pitch) * up
    right = np.cross(h, up)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    R = np.stack([c * right + s * down, -s * right + c * down, forward])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, -R @ np.asarray(center, dtype=np.float64)
    return Camera(T, K, 320, 240, name=name, image_path=image_path)


def level_cameras(up, n, rng, pitch_deg=(-60.0, 30.0)) -> list[Camera]:
    pitches = np.radians(rng.uniform(*pitch_deg, n))
    return [
        camera(up, rng.uniform(0, 2 * math.pi), p, center=rng.normal(size=3) * 5, name=f"v{i}") for i, p in enumerate(pitches)
    ]


# --- camera consensus -----------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(4))
def test_consensus_recovers_the_up_of_level_cameras(seed):
    rng = np.random.default_rng(seed)
    up = random_up(rng)
    estimate = camera_up_consensus(level_cameras(up, 12, rng))
    assert angle_deg(estimate.up, up) < 0.1
    assert estimate.inlier_share == 1.0 and estimate.residual_deg < 0.01
    assert estimate.confidence > 0.99


def test_consensus_ignores_a_fifth_of_rolled_cameras():
    rng = np.random.default_rng(5)
    up = random_up(rng)
    cameras = level_cameras(up, 20, rng)
    for i in range(0, 20, 5):  # rolled by 20-40 degrees either way
        roll = math.radians(rng.uniform(20, 40)) * rng.choice([-1, 1])
        cameras[i] = camera(up, rng.uniform(0, 2 * math.pi), math.radians(-20), roll, name=f"r{i}")
    estimate = camera_up_consensus(cameras)
    assert angle_deg(estimate.up, up) < 1.0
    assert estimate.inlier_share == pytest.approx(0.8)


def test_consensus_sign_is_right_when_every_camera_looks_steeply_down():
    rng = np.random.default_rng(6)
    up = random_up(rng)
    estimate = camera_up_consensus(level_cameras(up, 10, rng, pitch_deg=(-88.0, -70.0)))
    assert angle_deg(estimate.up, up) < 0.1  # not 180


def test_cameras_straight_down_give_the_axis_but_a_doubtful_sign():
    up = random_up(np.random.default_rng(7))
    cameras = [camera(up, h, -math.pi / 2) for h in np.linspace(0, 3, 6)]
    estimate = camera_up_consensus(cameras)
    assert abs(estimate.up @ up) > math.cos(math.radians(0.1))
    assert estimate.confidence <= 0.5


def test_degenerate_captures_give_finite_low_confidence_estimates():
    rng = np.random.default_rng(8)
    up = random_up(rng)
    single = camera(up, 1.0, math.radians(-25))
    # One heading, several pitches (a tilt sweep): every x-axis is the same, pitch is unobserved.
    sweep = [camera(up, 1.0, math.radians(p)) for p in (-30, -20, -10)]
    for cameras in ([single], sweep, [single, single]):
        estimate = camera_up_consensus(cameras)
        assert np.isfinite(estimate.up).all() and np.isfinite(estimate.sigma_deg)
        assert abs(estimate.up @ single.R[0]) < 1e-9  # what the x-axes do say holds exactly
        assert estimate.confidence < 0.2
    # Alone, a camera's own up axis is the best guess.
    assert angle_deg(camera_up_consensus([single]).up, -single.R[1]) < 1e-6
    assert angle_deg(camera_up_consensus(sweep).up, up) < 25  # the level prior, not an arbitrary axis
    with pytest.raises(InputError, match="no cameras"):
        camera_up_consensus([])


# --- vanishing directions -------------------------------------------------------------------------


def _corner(centre: np.ndarray, frame: np.ndarray, i: int, j: int, k: int) -> np.ndarray:
    """Corner (i, j, k) in {0, 1}^3 of a box standing on the floor, centred at ``centre`` in plan."""
    return centre + (i - 0.5) * frame[0] + (j - 0.5) * frame[1] + k * frame[2]


def box_edges(up, rng, count=4, size=(0.4, 1.0)) -> list[tuple[np.ndarray, np.ndarray]]:
    """Edges (pairs of 3D endpoints) of ``count`` boxes standing on the floor, each yawed at random,
    with sides drawn from ``size``."""
    e1, e2 = horizontal_basis(up)
    edges = []
    for _ in range(count):
        yaw = rng.uniform(0, math.pi / 2)
        a = math.cos(yaw) * e1 + math.sin(yaw) * e2
        b = np.cross(up, a)
        centre = rng.uniform(-1.5, 1.5) * e1 + rng.uniform(-1.5, 1.5) * e2
        sides = rng.uniform(*size, 3)
        frame = np.stack([sides[0] * a, sides[1] * b, sides[2] * up])  # rows: the box's edge vectors
        for i, j, k in np.ndindex(2, 2, 2):
            for di, dj, dk in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                if max(i + di, j + dj, k + dk) <= 1:
                    edges.append((_corner(centre, frame, i, j, k), _corner(centre, frame, i + di, j + dj, k + dk)))
    return edges


def draw_edges(cam: Camera, edges) -> None:
    """Write ``cam``'s image (to its image_path): the edges as anti-aliased white lines on grey."""
    image = np.full((cam.height, cam.width), 40, np.uint8)
    for p, q in edges:
        uv = []
        for point in (p, q):
            x = cam.R @ point + cam.t
            uv.append(np.round(((K @ x)[:2] / x[2] - 0.5) * 16).astype(int))  # OpenCV: centres at integers
        cv2.line(image, tuple(map(int, uv[0])), tuple(map(int, uv[1])), 230, 1, cv2.LINE_AA, shift=4)
    cv2.imwrite(cam.image_path, image)


def orbit_views(folder, up, edges, rng, views=8) -> list[Camera]:
    """Level cameras around the origin, 6 units away, looking 15-35 degrees down, with their images."""
    e1, e2 = horizontal_basis(up)
    cameras = []
    for v in range(views):
        heading = 2 * math.pi * v / views + rng.uniform(-0.2, 0.2)
        pitch = math.radians(rng.uniform(-35, -15))
        back = -(math.cos(heading) * e1 + math.sin(heading) * e2) * math.cos(pitch) - math.sin(pitch) * up
        cam = camera(up, heading, pitch, center=6.0 * back + 0.5 * up, name=f"v{v}", image_path=str(folder / f"v{v}.png"))
        draw_edges(cam, edges)
        cameras.append(cam)
    return cameras


def loose_prior(up: np.ndarray, off_deg: float, sigma_deg: float) -> GravityEstimate:
    """An estimate ``off_deg`` away from ``up`` claiming ``sigma_deg``: it only picks and signs."""
    axis = np.cross(up, horizontal_basis(up)[0])
    a = math.radians(off_deg)
    wrong = math.cos(a) * up + math.sin(a) * axis
    return GravityEstimate(wrong, (np.eye(3) - np.outer(wrong, wrong)) / math.radians(sigma_deg) ** 2, 0.0, 1.0, 1)


def test_vanishing_directions_of_box_edges_recover_up(tmp_path):
    rng = np.random.default_rng(9)
    up = random_up(rng)
    cameras = orbit_views(tmp_path, up, box_edges(up, rng), rng)
    estimate = vanishing_up(cameras, prior=loose_prior(up, 4.0, 3.0))
    assert estimate is not None and not estimate.details["manhattan_pair"]
    assert angle_deg(estimate.up, up) < 1.0  # the lines, not the 4-degree-off prior
    # The sign follows the prior, even a prior pointing almost sideways.
    assert vanishing_up(cameras, prior=loose_prior(-up, 8.0, 10.0)).up @ up < 0


def test_two_orthogonal_floor_directions_give_up_without_vertical_edges(tmp_path):
    rng = np.random.default_rng(15)
    up = random_up(rng)
    a, b = horizontal_basis(up)
    offsets = np.linspace(-2.0, 2.0, 9)
    grid = [(2.0 * a + t * b, -2.0 * a + t * b) for t in offsets] + [(t * a + 2.0 * b, t * a - 2.0 * b) for t in offsets]
    cameras = orbit_views(tmp_path, up, grid, rng)
    estimate = vanishing_up(cameras, prior=loose_prior(up, 4.0, 3.0))
    assert estimate is not None and estimate.details["manhattan_pair"]
    assert angle_deg(estimate.up, up) < 1.0


def test_vanishing_up_needs_straight_edges(tmp_path):
    rng = np.random.default_rng(10)
    up = random_up(rng)
    cameras = orbit_views(tmp_path, up, [], rng, views=4)
    assert vanishing_up(cameras, prior=loose_prior(up, 0.0, 1.0)) is None
    assert vanishing_up([camera(up, 0.0, 0.0)], prior=loose_prior(up, 0.0, 1.0)) is None  # no image at all


def test_lines_fix_the_pitch_that_a_dolly_capture_leaves_open(tmp_path):
    """One heading, cameras sliding sideways and pitched 10-30 degrees down: the x-axes only give
    up's component along them, the level prior is off by the mean pitch; vertical edges fix it."""
    rng = np.random.default_rng(16)
    up = random_up(rng)
    root = tmp_path / "scene"
    (root / "images").mkdir(parents=True)
    e1, e2 = horizontal_basis(up)
    edges = box_edges(up, rng, size=(0.8, 2.0))
    cameras = []
    for v, pitch in enumerate(np.radians(np.linspace(-30, -10, 6))):
        centre = -6.0 * e1 + 2.5 * up + (v - 2.5) * 0.4 * e2
        cam = camera(up, 0.0, pitch, center=centre, name=f"v{v}", image_path=str(root / "images" / f"v{v}.png"))
        draw_edges(cam, edges)
        cameras.append(cam)
    write_cameras_json(cameras, root / "cameras.json")
    write_scene_meta(SceneMeta(), root / "scene.json")
    result = estimate_gravity(root)
    cams, lines = result["sources"]["cameras"], result["sources"]["vanishing_points"]
    assert angle_deg(np.array(cams["up"]), up) > 5.0 and cams["confidence"] < 0.2
    assert lines["used"] and angle_deg(np.array(result["up"]), up) < 1.0
    assert result["confidence"] > cams["confidence"]
    assert estimate_gravity(root, use_lines=False)["up"] == cams["up"]


# --- files and the command ------------------------------------------------------------------------


def tilted_scene(root, up, aligned=False):
    """A scene directory of level cameras (no images); scene.json records ``up`` only when aligned."""
    rng = np.random.default_rng(11)
    root.mkdir()
    write_cameras_json(level_cameras(up, 10, rng), root / "cameras.json")
    write_scene_meta(SceneMeta(up=up if aligned else None, aligned=aligned), root / "scene.json")


def test_world_up_prefers_scene_json_then_the_gravity_file(tmp_path):
    up = random_up(np.random.default_rng(12))
    root = tmp_path / "scene"
    tilted_scene(root, up)
    message = r"scene: no world up: scene.json has up = null and there is no gravity.json; run `capframe gravity "
    with pytest.raises(InputError, match=message):
        world_up(root)
    (root / "gravity.json").write_text(json.dumps({"format": 1, "up": (2 * up).tolist()}))
    np.testing.assert_allclose(world_up(root), up, atol=1e-12)
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"format": 1, "up": [0.0, 0.0, -1.0]}))
    np.testing.assert_allclose(world_up(root, other), [0.0, 0.0, -1.0])
    with pytest.raises(InputError, match="missing.json"):
        world_up(root, tmp_path / "missing.json")
    other.write_text(json.dumps({"format": 2, "up": [0.0, 0.0, 1.0]}))
    with pytest.raises(InputError, match="other.json.*format"):
        world_up(root, other)
    write_scene_meta(SceneMeta(up=np.array([1.0, 0.0, 0.0])), root / "scene.json")
    np.testing.assert_allclose(world_up(root, other), [1.0, 0.0, 0.0])  # scene.json wins


def test_gravity_command_estimates_and_writes_the_up(tmp_path, capsys):
    up = random_up(np.random.default_rng(13))
    root = tmp_path / "scene"
    tilted_scene(root, up)
    assert main(["gravity", str(root)]) == 0
    out = capsys.readouterr().out
    assert len(out.strip().splitlines()) == 1 and "confidence" in out
    written = json.loads((root / "gravity.json").read_text())
    assert written["format"] == 1 and written["skipped"] is False
    assert angle_deg(np.array(written["up"]), up) < 0.1 and written["confidence"] > 0.9
    assert written["sources"]["vanishing_points"] is None  # no images
    assert written["sources"]["cameras"]["inlier_share"] == 1.0
    np.testing.assert_allclose(world_up(root), written["up"], atol=1e-12)
    assert main(["gravity", str(root), "-o", str(tmp_path / "g.json"), "--json", "--no-lines"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads((tmp_path / "g.json").read_text())


def test_gravity_command_skips_an_aligned_scene(tmp_path):
    up = random_up(np.random.default_rng(14))
    root = tmp_path / "scene"
    tilted_scene(root, up, aligned=True)
    assert main(["gravity", str(root), "-o", str(tmp_path / "g.json")]) == 0
    written = json.loads((tmp_path / "g.json").read_text())
    assert written["skipped"] is True and written["sources"] is None
    np.testing.assert_allclose(written["up"], up, atol=1e-12)


def test_gravity_command_without_cameras_asks_for_the_colmap_stage(tmp_path, capsys):
    root = tmp_path / "scene"
    root.mkdir()
    write_ply(make_scene(10), root / "scene.ply")
    assert main(["gravity", str(root)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(root) in err and "COLMAP" in err
    assert not (root / "gravity.json").exists()
