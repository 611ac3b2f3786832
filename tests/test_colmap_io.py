"""COLMAP models (via pycolmap) and nerfstudio transforms.json."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from _scene_helpers import assert_same_cameras, random_cameras, touch_images

from capframe.errors import InputError
from capframe.scene import colmap_image_line, read_colmap, read_transforms_json, write_colmap


def quat_to_R(w, x, y, z):
    """Rotation matrix of a unit quaternion (Hamilton, scalar first, as COLMAP)."""
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


@pytest.mark.parametrize("text", [False, True])
def test_colmap_round_trip(tmp_path, text):
    cameras = random_cameras(5)[::-1]  # written out of order; read back sorted by name
    touch_images(tmp_path / "images", cameras)
    write_colmap(cameras, tmp_path / "sparse" / "0", text=text)
    suffix = ".txt" if text else ".bin"
    assert all((tmp_path / "sparse" / "0" / f"{s}{suffix}").is_file() for s in ("cameras", "images", "points3D"))
    loaded = read_colmap(tmp_path / "sparse" / "0", tmp_path / "images")
    assert_same_cameras(loaded, sorted(cameras, key=lambda c: c.name))
    assert loaded[1].image_path == str(tmp_path / "images" / "view_001.png")


def test_missing_model_file_names_folder_and_file(tmp_path):
    write_colmap(random_cameras(2), tmp_path / "sparse" / "0")
    (tmp_path / "sparse" / "0" / "images.bin").unlink()
    with pytest.raises(InputError) as info:
        read_colmap(tmp_path / "sparse" / "0")
    folder = tmp_path / "sparse" / "0"
    assert str(info.value) == f"{folder}: missing images.bin (or images.txt); expected a COLMAP sparse model"
    with pytest.raises(InputError, match="folder not found"):
        read_colmap(tmp_path / "sparse" / "1")


def _text_model(folder, camera_line):
    folder.mkdir(parents=True)
    (folder / "cameras.txt").write_text(camera_line + "\n")
    (folder / "images.txt").write_text("1 1 0 0 0 0.5 -0.25 2 1 a.jpg\n\n")
    (folder / "points3D.txt").write_text("")


def test_distortion_accepted_only_when_zero(tmp_path):
    _text_model(tmp_path / "zero", "1 OPENCV 640 480 500 510 320.5 240.5 0 0 0 0")
    (cam,) = read_colmap(tmp_path / "zero")
    np.testing.assert_array_equal(cam.K, [[500, 0, 320.5], [0, 510, 240.5], [0, 0, 1]])
    np.testing.assert_array_equal(cam.T_cw, [[1, 0, 0, 0.5], [0, 1, 0, -0.25], [0, 0, 1, 2], [0, 0, 0, 1]])
    assert cam.name == "a"
    _text_model(tmp_path / "radial", "1 SIMPLE_RADIAL 640 480 500 320 240 0.01")
    with pytest.raises(InputError, match="radial: camera 1 .SIMPLE_RADIAL. has distortion .*image_undistorter"):
        read_colmap(tmp_path / "radial")
    _text_model(tmp_path / "fisheye", "1 OPENCV_FISHEYE 640 480 500 500 320 240 0 0 0 0")
    with pytest.raises(InputError, match="OPENCV_FISHEYE model, not a pinhole"):
        read_colmap(tmp_path / "fisheye")


def test_images_txt_line_matches_the_pose(tmp_path):
    for i, cam in enumerate(random_cameras(4, seed=5)):
        fields = colmap_image_line(cam, image_id=i + 1, camera_id=3).split()
        assert fields[0] == str(i + 1) and fields[8] == "3" and fields[9] == f"{cam.name}.png"
        q = np.array([float(v) for v in fields[1:5]])
        assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-12
        np.testing.assert_allclose(quat_to_R(*q), cam.R, atol=1e-12)
        np.testing.assert_allclose([float(v) for v in fields[5:8]], cam.t, atol=0)


def test_images_txt_line_is_read_by_colmap(tmp_path):
    cameras = random_cameras(3, seed=1)
    folder = tmp_path / "model"
    folder.mkdir()
    lines = []
    for i, c in enumerate(cameras):
        fx, fy, cx, cy = (repr(float(v)) for v in c.K[[0, 1, 0, 1], [0, 1, 2, 2]])
        lines.append(f"{i + 1} PINHOLE {c.width} {c.height} {fx} {fy} {cx} {cy}\n")
    (folder / "cameras.txt").write_text("".join(lines))
    images = [colmap_image_line(c, image_id=i + 1, camera_id=i + 1) + "\n\n" for i, c in enumerate(cameras)]
    (folder / "images.txt").write_text("".join(images))
    (folder / "points3D.txt").write_text("")
    assert_same_cameras(read_colmap(folder), cameras)


# nerfstudio's COLMAP -> transforms.json conversion (nerfstudio/process_data/colmap_utils.py,
# colmap_to_json), re-derived here from its documented steps: c2w = inv(w2c); flip the camera's
# y and z axes (OpenCV -> OpenGL); permute world rows and negate one; record that world map as
# applied_transform. Current nerfstudio permutes rows [0, 2, 1]; older releases used [1, 0, 2].
@pytest.mark.parametrize("rows", [[0, 2, 1], [1, 0, 2]])
def test_transforms_json_from_nerfstudio_conversion_matches_colmap(tmp_path, rows):
    cameras = random_cameras(5, seed=4)
    touch_images(tmp_path / "images", cameras, suffix=".jpg")
    cameras = [dataclasses.replace(c, image_path=str(tmp_path / "images" / f"{c.name}.jpg")) for c in cameras]
    write_colmap(cameras, tmp_path / "sparse" / "0")  # records the images as <name>.jpg
    from_colmap = read_colmap(tmp_path / "sparse" / "0", tmp_path / "images")

    frames = []
    for cam in from_colmap:
        c2w = np.linalg.inv(cam.T_cw)
        c2w[0:3, 1:3] *= -1
        c2w = c2w[rows + [3], :]
        c2w[2, :] *= -1
        frame = {"file_path": f"images/{cam.name}.jpg", "transform_matrix": c2w.tolist(), "colmap_im_id": 1}
        frame.update(
            {
                "fl_x": cam.K[0, 0],
                "fl_y": cam.K[1, 1],
                "cx": cam.K[0, 2],
                "cy": cam.K[1, 2],
                "w": cam.width,
                "h": cam.height,
                "k1": 0.0,
                "k2": 0.0,
                "p1": 0.0,
                "p2": 0.0,
            }
        )
        frames.append(frame)
    applied = np.eye(4)[:3, :][rows, :]
    applied[2, :] *= -1
    data = {"camera_model": "OPENCV", "frames": frames[::-1], "applied_transform": applied.tolist()}
    (tmp_path / "transforms.json").write_text(json.dumps(data))

    from_json = read_transforms_json(tmp_path / "transforms.json")
    assert_same_cameras(from_json, from_colmap, atol=1e-9)
    assert [c.image_path for c in from_json] == [c.image_path for c in from_colmap]
    assert from_colmap[0].image_path == str(tmp_path / "images" / "view_000.jpg")

    # Without undoing, poses stay in nerfstudio's re-axed world: centres are mapped by applied_transform.
    kept = read_transforms_json(tmp_path / "transforms.json", undo_applied_transform=False)
    for a, b in zip(kept, from_colmap):
        np.testing.assert_allclose(a.center, applied[:, :3] @ b.center + applied[:, 3], atol=1e-9)


def test_transforms_json_top_level_intrinsics_and_errors(tmp_path):
    cam = random_cameras(1)[0]
    c2w_gl = np.linalg.inv(cam.T_cw) @ np.diag([1.0, -1.0, -1.0, 1.0])
    base = {
        "fl_x": cam.K[0, 0],
        "fl_y": cam.K[1, 1],
        "cx": cam.K[0, 2],
        "cy": cam.K[1, 2],
        "w": cam.width,
        "h": cam.height,
        "frames": [{"file_path": "x/view.png", "transform_matrix": c2w_gl[:3].tolist()}],  # 3x4 is accepted too
    }
    path = tmp_path / "transforms.json"
    path.write_text(json.dumps(base))
    (loaded,) = read_transforms_json(path)
    np.testing.assert_allclose(loaded.T_cw, cam.T_cw, atol=1e-12)
    assert loaded.name == "view" and loaded.image_path is None

    for change, fragment in [
        ({"fl_y": None}, "frame 0 has no fl_y"),
        ({"camera_model": "OPENCV_FISHEYE"}, "not a pinhole"),
        ({"k1": 0.05}, "non-zero distortion"),
    ]:
        data = {k: v for k, v in {**base, **change}.items() if v is not None}
        path.write_text(json.dumps(data))
        with pytest.raises(InputError, match=fragment) as info:
            read_transforms_json(path)
        assert str(path) in str(info.value)
