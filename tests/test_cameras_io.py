"""cameras.json (Inria), camera.json (capframe) and camera_path.json (nerfstudio)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from _scene_helpers import assert_same_cameras, centred, inria_cameras_entries, random_cameras, touch_images

from capframe.errors import InputError
from capframe.scene import (
    read_camera_json,
    read_cameras_json,
    write_camera_json,
    write_camera_path_json,
    write_cameras_json,
)


def test_cameras_json_round_trip(tmp_path):
    cameras = random_cameras(6)
    write_cameras_json(cameras, tmp_path / "cameras.json")
    assert_same_cameras(read_cameras_json(tmp_path / "cameras.json"), cameras)
    entry = json.loads((tmp_path / "cameras.json").read_text())[2]
    np.testing.assert_allclose(entry["position"], cameras[2].center, atol=1e-12)  # centre, not t
    np.testing.assert_allclose(np.array(entry["rotation"]), cameras[2].R.T, atol=0)  # camera-to-world


def test_reads_reference_cameras_json_with_centred_principal_point(tmp_path):
    cameras = random_cameras(4, seed=2)
    (tmp_path / "cameras.json").write_text(json.dumps(inria_cameras_entries(cameras)))
    assert_same_cameras(read_cameras_json(tmp_path / "cameras.json"), centred(cameras), atol=1e-9)


def test_images_are_resolved_by_name(tmp_path):
    cameras = random_cameras(3)
    touch_images(tmp_path / "images", cameras[:2], suffix=".jpg")
    write_cameras_json(cameras, tmp_path / "cameras.json")
    loaded = read_cameras_json(tmp_path / "cameras.json", tmp_path / "images")
    assert loaded[0].image_path == str(tmp_path / "images" / "view_000.jpg")
    assert loaded[2].image_path is None


@pytest.mark.parametrize(
    "key, value, fragment",
    [
        ("position", [0.0, float("nan"), 1.0], "'position' has non-finite"),
        ("fx", float("inf"), "non-finite"),
        ("rotation", [[1, 0, 0], [0, 1, 0]], "'rotation'"),
        ("rotation", [[1, 0, 0], [0, 1, 0], [0, 0, -1]], "not a proper rotation"),
        ("width", 0, "'width'"),
        ("fy", -5.0, "focal lengths"),
    ],
)
def test_invalid_camera_names_file_and_camera(tmp_path, key, value, fragment):
    entries = inria_cameras_entries(random_cameras(3))
    entries[1][key] = value
    (tmp_path / "cameras.json").write_text(json.dumps(entries))  # json writes NaN/Infinity literals
    with pytest.raises(InputError) as info:
        read_cameras_json(tmp_path / "cameras.json")
    message = str(info.value)
    assert str(tmp_path / "cameras.json") in message and "view_001" in message and fragment in message
    assert "\n" not in message


def test_missing_keys_and_bad_files(tmp_path):
    entries = inria_cameras_entries(random_cameras(2))
    del entries[0]["fx"], entries[0]["rotation"]
    (tmp_path / "a.json").write_text(json.dumps(entries))
    with pytest.raises(InputError, match=r"camera 0 lacks 'rotation', 'fx'"):
        read_cameras_json(tmp_path / "a.json")
    (tmp_path / "b.json").write_text("[{")
    with pytest.raises(InputError, match="not valid JSON"):
        read_cameras_json(tmp_path / "b.json")
    (tmp_path / "c.json").write_text(json.dumps(inria_cameras_entries(random_cameras(2)) * 2))
    with pytest.raises(InputError, match="duplicate camera names"):
        read_cameras_json(tmp_path / "c.json")


def test_camera_json_round_trip(tmp_path):
    cam = random_cameras(3)[1]
    write_camera_json(cam, tmp_path / "camera.json")
    back = read_camera_json(tmp_path / "camera.json")
    np.testing.assert_array_equal(back.T_cw, cam.T_cw)
    np.testing.assert_array_equal(back.K, cam.K)
    assert (back.name, back.width, back.height) == (cam.name, cam.width, cam.height)
    data = json.loads((tmp_path / "camera.json").read_text())
    np.testing.assert_allclose(data["position"], cam.center, atol=1e-12)
    assert data["fov_y_deg"] == pytest.approx(math.degrees(2 * math.atan(cam.height / 2 / cam.K[1, 1])))


def test_camera_json_with_bad_pose_names_the_file(tmp_path):
    cam = random_cameras(1)[0]
    write_camera_json(cam, tmp_path / "camera.json")
    data = json.loads((tmp_path / "camera.json").read_text())
    data["T_cw"][0][0] = 2.0
    (tmp_path / "camera.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="camera.json: .*proper rotation"):
        read_camera_json(tmp_path / "camera.json")


def test_camera_path_json_converts_back_to_our_pose(tmp_path):
    cameras = [cam.resized(64, 48) for cam in random_cameras(4)]
    write_camera_path_json(cameras, tmp_path / "camera_path.json", fps=2.0)
    data = json.loads((tmp_path / "camera_path.json").read_text())
    assert data["camera_type"] == "perspective"
    assert (data["render_width"], data["render_height"], data["seconds"]) == (64, 48, 2.0)
    for cam, entry in zip(cameras, data["camera_path"]):
        c2w_gl = np.array(entry["camera_to_world"]).reshape(4, 4)
        # OpenGL camera axes (x right, y up, z back) -> OpenCV (x right, y down, z forward)
        c2w_cv = c2w_gl @ np.diag([1.0, -1.0, -1.0, 1.0])
        np.testing.assert_allclose(np.linalg.inv(c2w_cv), cam.T_cw, atol=1e-12)
        # nerfstudio: focal = (H / 2) / tan(fov / 2)
        assert 24 / math.tan(math.radians(entry["fov"]) / 2) == pytest.approx(cam.K[1, 1], rel=1e-12)
        assert entry["aspect"] == pytest.approx(64 / 48)


def test_camera_path_needs_one_image_size(tmp_path):
    with pytest.raises(InputError, match="different image sizes"):
        write_camera_path_json(random_cameras(2), tmp_path / "camera_path.json")
    assert not (tmp_path / "camera_path.json").exists()
