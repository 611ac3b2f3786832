"""Free space (capframe.scene.occupancy): a floor, a closed box and a camera, built by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from conftest import make_camera

from capframe.constraints import Constraints, SubjectConstraint
from capframe.errors import InputError
from capframe.measure import ConstraintChecker, Subject
from capframe.scene import GaussianScene
from capframe.scene.occupancy import (
    _convex_hull,
    _distance_to,
    _distance_within,
    build_occupancy,
    cached_occupancy,
    up_frame,
)

IDENTITY = torch.tensor([1.0, 0.0, 0.0, 0.0])


def plane(centre, u, v, half: float, step: float) -> torch.Tensor:
    """(P, 3) points of a square of half-size ``half`` spanned by unit ``u``, ``v`` around ``centre``."""
    s = torch.arange(-half, half + 1e-9, step, dtype=torch.float64)
    a, b = torch.meshgrid(s, s, indexing="ij")
    u, v, centre = (torch.as_tensor(x, dtype=torch.float64) for x in (u, v, centre))
    return centre + a.reshape(-1, 1) * u + b.reshape(-1, 1) * v


def world(transform=lambda p: p, scale: float = 1.0) -> tuple[GaussianScene, np.ndarray]:
    """A floor (z = 0, half-size 10) and a closed box of side 2 centred at (0, 0, 2), z up, as
    small round opaque Gaussians spaced 0.1 apart; ``transform`` moves the points (a rigid motion)."""
    floor = plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 10.0, 0.1)
    box = [plane((0, 0, 2 + s), (1, 0, 0), (0, 1, 0), 1.0, 0.1) for s in (-1, 1)]
    box += [plane((s, 0, 2), (0, 1, 0), (0, 0, 1), 1.0, 0.1) for s in (-1, 1)]
    box += [plane((0, s, 2), (1, 0, 0), (0, 0, 1), 1.0, 0.1) for s in (-1, 1)]
    means = transform(torch.cat([floor, *box])) * scale
    n = len(means)
    gaussians = GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), torch.full((n, 3), 0.06 * scale), torch.full((n,), 0.9), torch.rand(n, 3)
    )
    return gaussians, np.array([0.0, 0.0, 1.0])


def camera_at(centre) -> object:
    return make_camera(eye=tuple(centre), target=(0.0, 0.0, 2.0), up=(0.0, 0.0, -1.0))


@pytest.fixture(scope="module")
def grid():
    gaussians, up = world()
    return build_occupancy(gaussians, up, [camera_at((6.0, 0.0, 3.0))])


def test_floor_box_and_free_space(grid):
    assert grid.floor_top >= 0
    clearance = grid.clearance(torch.tensor([[6.0, 0.0, 3.0], [0.0, 0.0, 2.0], [6.0, 0.0, -2.0], [0.0, 0.0, 0.0]]))
    above, inside_box, below_floor, under_box = clearance.tolist()
    assert above > 2.0  # the camera: 3 above the floor, 5 from the box
    assert inside_box < 0  # the hollow box's inside is not reachable: not free
    assert below_floor < 0 and under_box < 0


def test_clearance_is_the_distance_to_the_nearest_surface(grid):
    """Away from corners the signed distance is exact up to a voxel (the surface sits within
    the Gaussians' spread of their plane)."""
    for point, distance in [((6.0, 0.0, 3.0), 3.0), ((4.0, 0.0, 2.0), 2.0), ((0.0, 0.0, 4.5), 1.5), ((-1.6, 0.0, 2.0), 0.6)]:
        assert grid.clearance(torch.tensor(point)).item() == pytest.approx(distance, abs=1.5 * grid.voxel)


def gradient_matching_finite_differences(field, point, h: float, atol: float) -> torch.Tensor:
    """The autograd gradient of the scalar ``field`` at the (3,) ``point``, asserted equal (to
    ``atol``) to its central differences of step ``h``."""
    point = torch.tensor(point, dtype=torch.float64, requires_grad=True)
    field(point).backward()
    numeric = [
        (field(point.detach() + h * e) - field(point.detach() - h * e)).item() / (2 * h)
        for e in torch.eye(3, dtype=torch.float64)
    ]
    np.testing.assert_allclose(point.grad.numpy(), numeric, atol=atol)
    return point.grad


def test_clearance_gradient_matches_finite_differences(grid):
    gradient = gradient_matching_finite_differences(grid.clearance, [3.3, 1.7, 2.9], 1e-4, 1e-6)
    assert gradient.norm() > 0.5  # a distance field: gradient norm near 1


def test_clearance_scales_with_the_scene_and_follows_a_tilted_world(grid):
    angle = np.radians(25.0)
    R = torch.tensor([[1, 0, 0], [0, np.cos(angle), -np.sin(angle)], [0, np.sin(angle), np.cos(angle)]], dtype=torch.float64)
    offset = torch.tensor([5.0, -3.0, 10.0], dtype=torch.float64)
    scale = 40.0
    gaussians, up = world(lambda p: p @ R.T + offset, scale=scale)
    moved = build_occupancy(
        gaussians,
        R.numpy() @ up,
        [camera_at((scale * (R @ torch.tensor([6.0, 0.0, 3.0], dtype=torch.float64) + offset)).tolist())],
    )
    probes = torch.tensor(
        [[6.0, 0.0, 3.0], [0.0, 0.0, 2.0], [6.0, 0.0, -2.0], [4.0, 0.0, 2.0], [0.0, 0.0, 4.5]], dtype=torch.float64
    )
    here = grid.clearance(probes)
    there = moved.clearance(scale * (probes @ R.T + offset)) / scale
    np.testing.assert_array_equal(here.sign().numpy(), there.sign().numpy())
    np.testing.assert_allclose(there, here, atol=2 * grid.voxel)


def test_a_scene_without_cameras_is_free_from_above():
    gaussians, up = world()
    grid = build_occupancy(gaussians, up)
    assert grid.clearance(torch.tensor([0.0, 0.0, 6.0])).item() > 0
    assert grid.clearance(torch.tensor([0.0, 0.0, 2.0])).item() < 0


def test_segment_blocked_by_the_box(grid):
    assert grid.segment_blocked(np.array([6.0, 0.0, 2.0]), np.array([-6.0, 0.0, 2.0])) > 0
    assert grid.segment_blocked(np.array([6.0, 0.0, 5.0]), np.array([-6.0, 0.0, 5.0])) == 0


def room(walls: tuple[str, ...], kerb: float = 0.0) -> GaussianScene:
    """A floor (half-size 4) with walls 2.5 high on the named sides of the square [-3, 3]^2
    (``+x``, ``-x``, ``+y``, ``-y``) and a box of side 1 (a sofa, say) standing in its middle;
    with ``kerb`` > 0, a kerb that high runs along the outside of each wall, 0.5 beyond it, on
    the floor that reaches past the walls."""
    parts = [plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 4.0, 0.1)]
    for wall in walls:
        sign, axis = (1.0 if wall[0] == "+" else -1.0), "xy".index(wall[1])
        centre = [0.0, 0.0, 1.25]
        centre[axis] = 3.0 * sign
        along = (0, 1, 0) if axis == 0 else (1, 0, 0)
        points = plane(centre, along, (0, 0, 1), 3.0, 0.1)
        parts.append(points[(points[:, 2] >= 0.0) & (points[:, 2] <= 2.5)])
        if kerb > 0:
            centre[axis] = 3.5 * sign
            points = plane(centre, along, (0, 0, 1), 3.0, 0.1)
            parts.append(points[(points[:, 2] >= 0.0) & (points[:, 2] <= kerb)])
    parts += [plane((0, 0, 0.5 + s), (1, 0, 0), (0, 1, 0), 0.5, 0.1) for s in (-0.5, 0.5)]
    parts += [plane((s, 0, 0.5), (0, 1, 0), (0, 0, 1), 0.5, 0.1) for s in (-0.5, 0.5)]
    parts += [plane((0, s, 0.5), (1, 0, 0), (0, 0, 1), 0.5, 0.1) for s in (-0.5, 0.5)]
    means = torch.cat(parts)
    n = len(means)
    return GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), torch.full((n, 3), 0.06), torch.full((n,), 0.9), torch.rand(n, 3)
    )


@pytest.mark.parametrize("walls", [("+x", "-x", "+y", "-y"), ("+x", "-x", "+y")])
def test_a_room_has_a_ceiling_at_its_walls_top(walls):
    """Closed or open on one side, a camera stays in the room: not over the walls, not behind
    them; inside, the free space reaches up to the walls' top."""
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(room(walls), up, [make_camera(eye=(0.0, -2.0, 1.2), target=(0.0, 0.0, 0.5), up=(0.0, 0.0, -1.0))])
    assert grid.ceiling > grid.floor_top >= 0
    over_wall, behind_wall, high_inside, low_inside = grid.clearance(
        torch.tensor([[0.0, 3.0, 3.0], [0.0, 3.6, 1.2], [1.5, 1.5, 3.2], [1.5, 1.5, 1.8]])
    ).tolist()
    assert over_wall < 0 and behind_wall < 0 and high_inside < 0
    assert low_inside > 0.5


def test_past_an_open_side_the_free_space_lies_between_the_walls_planes():
    """A room open on its -y side (walls at x = ±3 and y = 3): a camera may back out past the
    opening (the walls beside it go on where the capture did not see them), but not round behind
    the side walls' planes, nor over them."""
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(room(("+x", "-x", "+y")), up, [camera_at((0.0, -2.0, 1.2))])
    backed_out, aside = grid.clearance(torch.tensor([[0.0, -4.5, 1.2], [1.5, -4.5, 1.2]], dtype=torch.float64)).tolist()
    assert backed_out > 1.0 and aside > 1.0  # the sofa box is 1.14 away, the +x wall's plane 1.5
    behind = grid.clearance(torch.tensor([[3.8, -3.9, 1.2], [-4.5, -4.5, 1.2], [3.6, 0.0, 1.2]], dtype=torch.float64))
    assert (behind < 0).all()


def test_the_hull_of_points_is_counter_clockwise_without_collinear_points():
    """The convex hull of a square's corners, its edge midpoints and its centre is its corners,
    counter-clockwise from the lowest-leftmost."""
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 0], [2, 1], [1, 2], [0, 1], [1, 1]], dtype=np.float64)
    np.testing.assert_array_equal(_convex_hull(square), [[0, 0], [2, 0], [2, 2], [0, 2]])


def test_the_ceiling_is_a_plane_at_the_walls_top_not_above_their_top_voxel():
    """The walls' top row of Gaussians lies at 2.45 (rows 0.1 apart from 1.25, cut at 2.5), in a
    voxel whose top lies higher: a camera over the walls' top is out of free space, one below it
    keeps the depth below the top as its clearance, whichever voxel it falls in."""
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(room(("+x", "-x", "+y", "-y")), up, [camera_at((0.0, -2.0, 1.2))])
    assert grid.ceiling_height == pytest.approx(2.45, abs=1e-6)
    assert grid.origin[2] + grid.ceiling * grid.voxel > 2.45 + grid.voxel / 4  # the layer above the top voxel
    for h in (2.25, 2.4):
        assert grid.clearance(torch.tensor([1.5, 1.5, h])).item() == pytest.approx(2.45 - h, abs=1e-6)
    assert grid.clearance(torch.tensor([1.5, 1.5, 2.47])).item() < 0


def test_a_camera_over_the_walls_leaves_the_ceiling_to_its_layer():
    """A training camera above the walls (a room shot from over its open top) lifts the
    ceiling over it, and no plane at the walls' top bounds the clearance then."""
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(room(("+x", "-x", "+y", "-y")), up, [camera_at((0.0, -2.0, 3.0))])
    assert np.isnan(grid.ceiling_height) and grid.clearance(torch.tensor([0.0, -2.0, 2.9])).item() > 0


def test_beyond_the_grid_past_a_room_open_side_is_out_of_free_space():
    """A room open on its -y side: a camera past the open side, beyond the grid (which holds the
    room and the training camera with a padding), is outside the room; a box standing alone on a
    floor (no room) leaves the space beyond its grid free."""
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(room(("+x", "-x", "+y")), up, [camera_at((0.0, -2.0, 1.2))])
    far = torch.tensor([0.0, -20.0, 1.2], dtype=torch.float64)
    g = grid.grid_coordinates(far)
    assert ((g < -0.5) | (g > torch.tensor(grid.sdf.shape) - 0.5)).any() and grid.clearance(far).item() < 0
    near = torch.tensor([0.0, -3.5, 1.2], dtype=torch.float64)
    assert grid.clearance(near).item() > 0
    gaussians, _ = world()
    alone = build_occupancy(gaussians, up, [camera_at((6.0, 0.0, 3.0))])
    assert alone.clearance(torch.tensor([40.0, 0.0, 3.0], dtype=torch.float64)).item() > 0


def test_a_low_fringe_beyond_the_walls_does_not_open_the_room():
    """A kerb 0.3 high outside each wall (12% of the walls' height: the fringe a floor reaching
    past the walls carries) is not the room's outermost structure: the room keeps its ceiling,
    and the space over the walls and behind them stays out of free space."""
    up = np.array([0.0, 0.0, 1.0])
    camera = make_camera(eye=(0.0, -2.0, 1.2), target=(0.0, 0.0, 0.5), up=(0.0, 0.0, -1.0))
    grid = build_occupancy(room(("+x", "-x", "+y"), kerb=0.3), up, [camera])
    assert grid.ceiling > grid.floor_top >= 0
    points = torch.tensor([[3.0, 0.0, 3.0], [3.3, 0.0, 1.2], [1.5, 1.5, 1.8]])
    over_wall, behind_wall, low_inside = grid.clearance(points).tolist()
    assert over_wall < 0 and behind_wall < 0 and low_inside > 0.5


def test_no_ceiling_without_walls(grid):
    """A box standing alone on a floor (the module's world) and a single wall are no room."""
    assert grid.ceiling == -1
    up = np.array([0.0, 0.0, 1.0])
    one_wall = build_occupancy(room(("+y",)), up, [camera_at((0.0, -2.0, 1.2))])
    assert one_wall.ceiling == -1 and one_wall.clearance(torch.tensor([0.0, 0.0, 3.5])).item() > 0


def test_up_frame_is_a_rotation_with_up_last():
    for up in ([0, 0, 1], [0, -1, 0], [0.3, -0.2, 0.93]):
        R = up_frame(np.array(up, dtype=float))
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        np.testing.assert_allclose(R[2], np.array(up) / np.linalg.norm(up))


def test_cache_is_reused_and_rebuilt_when_the_scene_changes(tmp_path):
    gaussians, up = world()
    first = cached_occupancy(gaussians, up, [], tmp_path)
    stamp = (tmp_path / "occupancy.npz").stat().st_mtime_ns
    again = cached_occupancy(gaussians, up, [], tmp_path)
    assert (tmp_path / "occupancy.npz").stat().st_mtime_ns == stamp
    np.testing.assert_array_equal(first.sdf, again.sdf)
    gaussians.means[:, 2] += 1.0
    cached_occupancy(gaussians, up, [], tmp_path)
    assert (tmp_path / "occupancy.npz").stat().st_mtime_ns != stamp


def test_a_scene_of_faint_gaussians_is_refused():
    gaussians, up = world()
    gaussians.opacity_logits[:] = -5.0
    with pytest.raises(InputError, match="no Gaussian has an opacity"):
        build_occupancy(gaussians, up)


def test_the_floor_is_a_plane_at_its_own_height_not_its_voxel_layers_top(grid):
    """The floor's voxel layer reaches most of a voxel above the floor (the grid starts a padding
    below its lowest points); the clearance above the floor is the height above the plane of the
    floor's Gaussians (their 1-sigma points reach 0.06), so a camera a voxel above the floor is
    free, while an object lower than a voxel (a toy car in a large scene) stays an obstacle."""
    assert grid.floor_height == pytest.approx(0.06, abs=0.02)
    for h in (0.8 * grid.voxel, 1.5 * grid.voxel):
        assert grid.clearance(torch.tensor([6.0, -3.0, h])).item() == pytest.approx(h - 0.06, abs=1e-6)
    assert grid.clearance(torch.tensor([6.0, -3.0, -0.1])).item() < 0
    gaussians, up = world()
    side = torch.arange(0.0, 2.0 * grid.voxel, 0.02, dtype=torch.float64)
    height = torch.arange(0.0, 0.9 * grid.voxel, 0.02, dtype=torch.float64)
    x, y, z = torch.meshgrid(side + 6.0, side - 3.0, height, indexing="ij")
    block = torch.stack([x.reshape(-1), y.reshape(-1), z.reshape(-1)], 1).float()
    n = len(block)
    small = GaussianScene.from_activated(
        torch.cat([gaussians.means, block]),
        IDENTITY.expand(len(gaussians) + n, 4).clone(),
        torch.cat([gaussians.scales, torch.full((n, 3), 0.02)]),
        torch.cat([gaussians.opacities, torch.full((n,), 0.9)]),
        torch.rand(len(gaussians) + n, 3),
    )
    with_block = build_occupancy(small, up, [camera_at((6.0, 0.0, 3.0))])
    assert with_block.clearance(torch.tensor([6.0 + grid.voxel, -3.0 + grid.voxel, 0.4 * grid.voxel])).item() < 0
    assert with_block.clearance(torch.tensor([6.0, 3.0, 0.8 * grid.voxel])).item() > with_block.margin


def test_a_camera_keeps_a_quarter_voxel_above_the_floor_plane_and_a_voxel_from_voxel_surfaces(grid):
    """The floor plane is placed by the floor's own Gaussians, the voxels only to half a voxel
    (and another grid of the scene places them up to a voxel away): 0.3 voxel above the plane,
    far from the box, is free (slack 0.05 voxel), 0.2 is not; beside the box's side the slack is
    the voxel clearance less a voxel (not free 0.6 voxel off)."""
    v = grid.voxel
    floor = [grid.floor_height + h * v for h in (0.3, 0.2)]
    slack = grid.slack(torch.tensor([[6.0, -3.0, floor[0]], [6.0, -3.0, floor[1]]], dtype=torch.float64))
    np.testing.assert_allclose(slack.numpy(), [0.05 * v, -0.05 * v], atol=1e-9)
    side = torch.tensor([[1.0 + 0.3 * v, 0.0, 2.0], [1.0 + 0.6 * v, 0.0, 2.0]], dtype=torch.float64)
    clearance, slack = grid.clearance(side), grid.slack(side)
    np.testing.assert_allclose(slack.numpy(), clearance.numpy() - grid.voxel, atol=1e-12)
    assert slack[1] < 0 < grid.slack(torch.tensor([6.0, -3.0, 2.0], dtype=torch.float64))


def test_a_table_top_is_a_flat_surface_at_its_own_height_and_what_stands_on_it_is_not():
    """A table top (flat Gaussians at z = 1.03, 4 x 4) over the floor, with a cube 0.1 high
    standing on it: the top's columns carry a surface at its samples' height, so a camera a
    third of a voxel over the top is free (its voxel reaches up to a voxel higher), while over
    the cube, lower than a voxel, it is not; beside the table the floor plane bounds it."""
    floor = plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 8.0, 0.1)
    top = plane((0, 0, 1.03), (1, 0, 0), (0, 1, 0), 2.0, 0.05)
    cube = torch.cat([plane((0.5, 0.5, 1.03 + h), (1, 0, 0), (0, 1, 0), 0.05, 0.025) for h in (0.05, 0.1)])
    means = torch.cat([floor, top, cube])
    n = len(means)
    scales = torch.full((n, 3), 0.05)
    scales[len(floor) : len(floor) + len(top), 2] = 0.002  # the top's Gaussians are flat
    gaussians = GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), scales, torch.full((n,), 0.9), torch.rand(n, 3)
    )
    up = np.array([0.0, 0.0, 1.0])
    grid = build_occupancy(gaussians, up, [camera_at((6.0, 0.0, 3.0))])
    v = grid.voxel
    i, j, _ = grid.grid_coordinates(torch.tensor([-1.0, -1.0, 1.03], dtype=torch.float64)).round().long().tolist()
    assert grid.surface_layer[i, j] >= 0 and grid.surface_height[i, j] == pytest.approx(1.032, abs=1e-3)
    over_top, over_cube = torch.tensor([[-1.0, -1.0, 1.032 + v / 3], [0.5, 0.5, 1.032 + v / 3]], dtype=torch.float64)
    assert grid.clearance(over_top).item() == pytest.approx(v / 3, abs=1e-6) and grid.slack(over_top).item() > 0
    assert grid.slack(over_cube).item() < 0
    assert grid.clearance(torch.tensor([-1.0, -1.0, 1.0])).item() < 0  # in the top
    beside = torch.tensor([3.0, 0.0, 0.5], dtype=torch.float64)
    assert grid.clearance(beside).item() == pytest.approx(0.5 - grid.floor_height, abs=1e-6)


def small_subject_on_a_table() -> tuple[GaussianScene, torch.Tensor]:
    """A floor (16 x 16), a table top (flat, 4 x 4, z = 1) and on it a closed cube of side 0.6
    centred at (0, 0, 1.3): a subject two and a half voxels of the scene grid high. Returns the
    scene and the cube's Gaussian indices."""
    floor = plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 8.0, 0.1)
    top = plane((0, 0, 1.0), (1, 0, 0), (0, 1, 0), 2.0, 0.03)
    cube = [plane((0, 0, 1.3 + s), (1, 0, 0), (0, 1, 0), 0.3, 0.02) for s in (-0.3, 0.3)]
    cube += [plane((s, 0, 1.3), (0, 1, 0), (0, 0, 1), 0.3, 0.02) for s in (-0.3, 0.3)]
    cube += [plane((0, s, 1.3), (1, 0, 0), (0, 0, 1), 0.3, 0.02) for s in (-0.3, 0.3)]
    parts = [floor, top, torch.cat(cube)]
    means = torch.cat(parts)
    n = len(means)
    scales = torch.cat([torch.full((len(floor), 3), 0.05), torch.tensor([[0.03, 0.03, 0.002]]).expand(len(top), 3)])
    scales = torch.cat([scales, torch.full((len(parts[2]), 3), 0.015)])
    gaussians = GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), scales, torch.full((n,), 0.9), torch.rand(n, 3)
    )
    return gaussians, torch.arange(n - len(parts[2]), n)


@pytest.fixture(scope="module")
def table_grids():
    gaussians, cube = small_subject_on_a_table()
    grid = build_occupancy(gaussians, np.array([0.0, 0.0, 1.0]), [camera_at((6.0, 0.0, 3.0))])
    return grid, grid.around(gaussians, cube), gaussians


def test_a_small_subject_gets_a_finer_grid_where_a_low_close_camera_is_free(table_grids):
    """0.15 over the table top and 0.2 in front of the cube the scene grid (voxel 0.21) keeps no
    camera (a voxel from the cube); the finer grid (voxel 0.6 / 16) does, while the cube's inside
    and the table top's underside stay out of free space."""
    grid, detailed, _ = table_grids
    assert detailed.detail is not None and grid.detail is None
    assert detailed.detail.voxel == pytest.approx(0.6 / 16, rel=0.05)
    low_front = torch.tensor([0.5, 0.0, 1.15], dtype=torch.float64)
    assert grid.slack(low_front).item() < 0 < detailed.slack(low_front).item()
    # The top's own samples are left to the flat surface's rule in both grids: near the cube a
    # camera may stand as low over the top as far from it, and not under it.
    for x in (0.5, 0.8):
        low = torch.tensor([x, 0.0, 1.08], dtype=torch.float64)
        assert detailed.slack(low).item() == pytest.approx(0.08 - grid.height_kept(), abs=0.01)
        assert detailed.clearance(low - torch.tensor([0.0, 0.0, 0.1], dtype=torch.float64)).item() < 0
    for inside in ([0.0, 0.0, 1.3], [0.1, -0.1, 1.2], [0.8, 0.0, 0.98]):  # in the cube, in the cube, in the top
        assert detailed.clearance(torch.tensor(inside, dtype=torch.float64)).item() < 0
    far = torch.tensor([4.0, 3.0, 2.0], dtype=torch.float64)  # beyond the finer grid: the scene grid's
    assert detailed.slack(far).item() == grid.slack(far).item()


def test_a_subject_large_for_the_scene_grid_gets_no_finer_grid(table_grids):
    grid, _, gaussians = table_grids
    assert grid.around(gaussians, torch.arange(1000)).detail is None  # a strip of the floor, 16 long
    assert grid.around(gaussians, torch.zeros(0, dtype=torch.long)).detail is None


def test_the_finer_clearance_blends_into_the_scene_grid_continuously(table_grids):
    """Across the finer grid's face (1.2 from the cube's centre) the clearance has no jump, and
    its gradient in the blend matches finite differences."""
    _, detailed, _ = table_grids
    x = torch.linspace(0.9, 2.0, 600, dtype=torch.float64)
    line = torch.stack([x, torch.full_like(x, 0.2), torch.full_like(x, 1.6)], -1)
    steps = detailed.clearance(line).diff().abs()
    assert steps.max().item() < 5 * (x[1] - x[0]).item()
    point = [1.12, 0.2, 1.6]  # in the blend
    assert 0 < detailed.detail._inner_weight(torch.tensor(point, dtype=torch.float64)).item() < 1
    gradient_matching_finite_differences(detailed.slack, point, 1e-5, 1e-5)


def test_distances_within_a_reach_are_exact_and_capped_beyond():
    rng = np.random.default_rng(3)
    mask = rng.random((20, 18, 16)) < 0.004
    mask[3, 4, 5] = True
    exact = _distance_to(mask)
    near = _distance_within(mask, 5)
    within = exact <= 5
    np.testing.assert_allclose(near[within], exact[within], atol=1e-5)
    assert (near[~within] == 5).all() and (~within).any()


def test_the_checker_judges_clearance_with_the_finer_grid_around_a_small_primary(table_grids):
    """0.1 from the cube's side, at its mid-height, the scene grid puts a camera inside geometry
    (its boundary lies half a voxel from the cube's voxels); the checker's clearance row builds the
    finer grid around the cube and finds it free, and keeps the scene grid's verdict when the
    primary is large (a strip of the floor)."""
    grid, _, gaussians = table_grids
    n = len(gaussians)
    cube = torch.zeros(n, dtype=torch.bool)
    cube[small_subject_on_a_table()[1]] = True
    strip = torch.zeros(n, dtype=torch.bool)
    strip[:1000] = True
    objects = {"cube": Subject(0, "cube", np.array([0.0, 0.0, 1.3]), 0.5, None)}
    objects["floor"] = Subject(1, "floor", np.array([0.0, -7.0, 0.0]), 5.0, None)
    checker = ConstraintChecker(gaussians, objects, {0: cube, 1: strip}, np.array([0.0, 0.0, 1.0]), occupancy=grid)
    camera = make_camera(eye=(0.4, 0.0, 1.3), target=(0.0, 0.0, 1.3), up=(0.0, 0.0, -1.0))
    assert grid.clearance(torch.as_tensor(camera.center)).item() < 0
    row = checker.check(camera, Constraints([SubjectConstraint("cube")])).row("clearance")
    assert row.satisfied and row.measured > 0
    row = checker.check(camera, Constraints([SubjectConstraint("floor"), SubjectConstraint("cube", "secondary")])).row(
        "clearance"
    )
    assert not row.satisfied


def table_share(points: np.ndarray, centre: np.ndarray, top: float = 1.0, half: float = 2.0, foot: float = 0.3) -> float:
    """The share of ``points`` a camera at ``centre`` below the top sees past it, from the table's
    exact extent: a line of sight crossing z = ``top`` over the table (|x|, |y| <= ``half``) or
    over the cube's foot (a disc of its lowest points' radius, ``foot`` * sqrt 2) is hidden."""
    share = np.minimum((top - centre[2]) / (points[:, 2] - centre[2]), 1.0)
    crossing = centre + share[:, None] * (points - centre)
    over_top = (np.abs(crossing[:, :2]) <= half).all(1)
    over_foot = np.linalg.norm(crossing[:, :2], axis=1) <= foot * math.sqrt(2)
    return float(1.0 - (over_top | over_foot).mean())


@pytest.mark.parametrize("centre", [(0.8, 0.3, 0.5), (2.5, 0.0, 0.5), (6.0, 0.0, 0.95), (3.0, 1.0, 0.97), (9.0, -2.0, 0.9)])
def test_a_camera_below_a_table_top_sees_what_stands_on_it_only_past_the_top(table_grids, centre):
    """Under the table (and beside it, lower than its top, looking at the cube in its middle) the
    cube is hidden; low and farther out, its upper part shows over the top's edge. The share
    matches the table's exact extent to a few points, also in a scene ten times larger."""
    grid, _, gaussians = table_grids
    cube = small_subject_on_a_table()[1]
    points = gaussians.means[cube].double().numpy()
    expected = table_share(points, np.array(centre))
    assert grid.seen_past_support(points, np.array(centre)) == pytest.approx(expected, abs=0.06)
    large, _ = small_subject_on_a_table()
    large = GaussianScene.from_activated(
        large.means * 10, large.quats, large.scales * 10, torch.sigmoid(large.opacity_logits), large.sh
    )
    larger = build_occupancy(large, np.array([0.0, 0.0, 1.0]), [camera_at((60.0, 0.0, 30.0))])
    assert larger.seen_past_support(10 * points, 10 * np.array(centre)) == pytest.approx(expected, abs=0.06)


def test_seen_past_support_asks_only_below_a_supported_base(table_grids):
    """Above the cube's base there is nothing to ask; a box hanging free (the world's box, a unit
    over the floor) stands on nothing, and its renders keep the verdict."""
    grid, _, gaussians = table_grids
    points = gaussians.means[small_subject_on_a_table()[1]].double().numpy()
    assert grid.seen_past_support(points, np.array([0.5, 0.0, 1.05])) is None
    floating, up = world()
    box = floating.means[-6 * 21 * 21 :].double().numpy()
    assert box[:, 2].min() == pytest.approx(1.0)
    free_grid = build_occupancy(floating, up, [camera_at((6.0, 0.0, 3.0))])
    assert free_grid.seen_past_support(box, np.array([3.0, 0.0, 0.5])) is None
    assert grid.seen_past_support(np.zeros((0, 3)), np.array([0.8, 0.3, 0.5])) is None


def test_the_support_top_is_the_table_top_under_the_subject(table_grids):
    """The cube stands on the table top (z = 1): its support's top is there, to a few hundredths,
    and ten times higher in a scene ten times larger; a box hanging free stands on nothing."""
    grid, _, gaussians = table_grids
    points = gaussians.means[small_subject_on_a_table()[1]].double().numpy()
    assert grid.support_top(points) == pytest.approx(1.0, abs=0.04)
    large, _ = small_subject_on_a_table()
    large = GaussianScene.from_activated(
        large.means * 10, large.quats, large.scales * 10, torch.sigmoid(large.opacity_logits), large.sh
    )
    larger = build_occupancy(large, np.array([0.0, 0.0, 1.0]), [camera_at((60.0, 0.0, 30.0))])
    assert larger.support_top(10 * points) == pytest.approx(10.0, abs=0.4)
    floating, up = world()
    free_grid = build_occupancy(floating, up, [camera_at((6.0, 0.0, 3.0))])
    assert free_grid.support_top(floating.means[-6 * 21 * 21 :].double().numpy()) is None


def test_the_checker_fails_a_subject_seen_through_its_support(table_grids):
    """The visibility row from under the table: with the occupancy it measures the share seen
    past the top (none) and says so; the clearance row passes (under a table is free space)."""
    grid, _, gaussians = table_grids
    n = len(gaussians)
    cube = torch.zeros(n, dtype=torch.bool)
    cube[small_subject_on_a_table()[1]] = True
    objects = {"cube": Subject(0, "cube", np.array([0.0, 0.0, 1.3]), 0.5, None)}
    checker = ConstraintChecker(gaussians, objects, {0: cube}, np.array([0.0, 0.0, 1.0]), occupancy=grid)
    camera = make_camera(eye=(0.8, 0.3, 0.5), target=(0.0, 0.0, 1.3), up=(0.0, 0.0, -1.0))
    report = checker.check(camera, Constraints([SubjectConstraint("cube")]))
    row = report.row("visibility")
    assert not row.satisfied and row.measured == 0.0 and row.details["seen_past_support"] == 0.0
    assert row.note == "subject is mostly seen through the surface it stands on"
    assert report.row("clearance").satisfied
    above = make_camera(eye=(1.5, 0.0, 1.8), target=(0.0, 0.0, 1.3), up=(0.0, 0.0, -1.0))
    row = checker.check(above, Constraints([SubjectConstraint("cube")])).row("visibility")
    assert row.satisfied and row.details["seen_past_support"] is None


def test_the_floor_plane_leaves_out_the_bases_of_what_stands_on_it():
    """Nine boxes (side 2, open at the bottom, as a capture leaves them, and densely sampled)
    stand on a floor (z = 0; its Gaussians' upper 1-sigma points at 0.12): their walls put three
    times the floor's samples into its voxel layer, but in their own columns, so the plane stays
    at the floor's samples (the walls lifted it to 0.26 before), and a camera a third of a voxel
    over the plane between the boxes is free."""
    floor = plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 16.0, 0.25)
    boxes = []
    for x in (-4.0, 0.0, 4.0):
        for y in (-4.0, 0.0, 4.0):
            boxes.append(plane((x, y, 2.0), (1, 0, 0), (0, 1, 0), 1.0, 0.02))
            boxes += [plane((x + s, y, 1.0), (0, 1, 0), (0, 0, 1), 1.0, 0.02) for s in (-1.0, 1.0)]
            boxes += [plane((x, y + s, 1.0), (1, 0, 0), (0, 0, 1), 1.0, 0.02) for s in (-1.0, 1.0)]
    post = plane((12.0, 12.0, 3.0), (1, 0, 0), (0, 0, 1), 3.0, 0.1)  # taller than the boxes: no walls
    means = torch.cat([floor, *boxes, post])
    n = len(means)
    scales = torch.cat([torch.full((len(floor), 3), 0.12), torch.full((n - len(floor), 3), 0.015)])
    gaussians = GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), scales, torch.full((n,), 0.9), torch.rand(n, 3)
    )
    grid = build_occupancy(gaussians, np.array([0.0, 0.0, 1.0]), [camera_at((10.0, 0.0, 3.0))])
    in_layers = means[:, 2] < grid.origin[2] + (grid.floor_top + 1) * grid.voxel
    assert in_layers[len(floor) : n - len(post)].sum() > 3 * in_layers[: len(floor)].sum()
    assert grid.floor_height == pytest.approx(0.12, abs=0.01)
    between = torch.tensor([2.0, 2.0, 0.12 + grid.voxel / 3], dtype=torch.float64)
    assert grid.clearance(between).item() == pytest.approx(grid.voxel / 3, abs=1e-6)


def test_a_camera_over_the_support_looks_past_it_at_a_raised_base():
    """A tall box (a bookcase on a plinth) whose walls end 0.03 over the floor (its base, the
    2% quantile of its heights, at 0.08): the floor lies within its reach below the base, so it
    stands on a support, but a camera crouching 0.04 over the floor (lower than the base, higher
    than the support's top) looks past nothing; the renders keep the verdict."""
    floor = plane((0, 0, 0), (1, 0, 0), (0, 1, 0), 8.0, 0.1)
    levels = (0.53, 1.53, 2.53, 3.53)  # four squares of side 1 stacked: walls from 0.03 to 4.03
    box = [plane((3.0 + s, 3.0, z), (0, 1, 0), (0, 0, 1), 0.5, 0.05) for s in (-0.5, 0.5) for z in levels]
    box += [plane((3.0, 3.0 + s, z), (1, 0, 0), (0, 0, 1), 0.5, 0.05) for s in (-0.5, 0.5) for z in levels]
    box = torch.cat([*box, plane((3.0, 3.0, 4.03), (1, 0, 0), (0, 1, 0), 0.5, 0.05)])
    means = torch.cat([floor, box])
    n = len(means)
    scales = torch.cat([torch.tensor([[0.05, 0.05, 0.005]]).expand(len(floor), 3), torch.full((len(box), 3), 0.02)])
    gaussians = GaussianScene.from_activated(
        means.float(), IDENTITY.expand(n, 4).clone(), scales, torch.full((n,), 0.9), torch.rand(n, 3)
    )
    grid = build_occupancy(gaussians, np.array([0.0, 0.0, 1.0]), [camera_at((-6.0, 0.0, 3.0))])
    subject = box.numpy()
    base = np.quantile(subject[:, 2], 0.02)
    reach = min(0.05 * (subject[:, 2].max() - base), 0.5 * grid.voxel)
    assert base - reach < grid.floor_height < 0.04 < base  # the floor is in reach of the base
    assert np.isfinite(grid.support_depth(np.array([[3.0, 4.0, base]]), reach)).all()
    assert grid.seen_past_support(subject, np.array([6.0, 3.0, 0.04])) is None
