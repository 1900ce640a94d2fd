"""Every file glassscan writes loads in one line of the library a dataset user reaches for.

Runs the release binary (built by `cargo build --release`, or the path in $GLASSSCAN) on a
shipped scene: one `scan` pose and a two-sample `dataset`, at few photons. Each test is the
one-line load, then checks that what came back is what the file is documented to hold.
"""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
import pandas as pd
import pytest
from PIL import Image
from plyfile import PlyData

REPO = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GLASSSCAN", REPO / "target" / "release" / "glassscan"))


def run(*args):
    subprocess.run([str(BINARY), *args], cwd=REPO, check=True, capture_output=True)


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    out = tmp_path_factory.mktemp("scan")
    run("scan", "scenes/edge_study_bare.toml", "--poses", "1", "--photons", "16384",
        "--out", str(out), "--force")
    return out


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    out = tmp_path_factory.mktemp("ds") / "ds"
    run("dataset", "scenes/edge_study.toml", "--count", "2", "--out", str(out),
        "--photons", "16384", "--seed", "3")
    return out


def test_profile_csv_with_pandas(scan):
    profile = pd.read_csv(scan / "pose_000_profile.csv")
    assert list(profile.columns) == [
        "column", "reflection", "row_px", "x_mm", "z_mm", "intensity_dn", "width_px",
        "threshold_dn", "m0_dn", "m1_dn_px", "label", "valid", "saturated"]
    assert profile["valid"].dtype == bool and profile["saturated"].dtype == bool
    valid = profile[profile["valid"]]
    assert len(valid) > 300
    assert valid["z_mm"].between(125, 390).all()
    assert profile.loc[~profile["valid"], "z_mm"].isna().all()


def test_sensor_png_with_pillow(scan):
    image = np.array(Image.open(scan / "pose_000.png"))
    assert image.dtype == np.uint16 and image.shape == (832, 640)
    # 10-bit DN left-aligned: the low 6 bits are zero, as the file's own text says.
    assert (image & 0x3F == 0).all()
    assert "DN = value >> 6" in Image.open(scan / "pose_000.png").info["Description"]


def test_irradiance_exr_with_openexr(scan):
    with OpenEXR.File(str(scan / "pose_000.exr")) as exr:
        total = exr.channels()["irradiance"].pixels
        header = dict(exr.header())
        by_class = sum(c.pixels.astype(np.float64) for name, c in exr.channels().items()
                       if name.startswith("class."))
    assert total.dtype == np.float32 and total.shape == (832, 640)
    assert total.max() > 0
    np.testing.assert_allclose(by_class, total, rtol=1e-5, atol=1e-6 * total.max())
    assert np.asarray(header["wavelengthNm"]).item() == pytest.approx(658.0)
    assert np.asarray(header["sensorToBaseMm"]).shape == (4, 4)
    assert "W/m^2" in header["comments"]


def test_scan_manifest_with_json(scan):
    manifest = json.loads((scan / "manifest.json").read_text())
    pose = manifest["poses"][0]["sensor_pose"]
    matrix = np.array(pose["matrix_mm"]).reshape(4, 4)
    np.testing.assert_allclose(matrix[:3, :3] @ matrix[:3, :3].T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(matrix[:3, 3], pose["translation_mm"])


def test_ground_truth_with_pandas_json_lines(sample):
    truth = pd.read_json(sample / "sample_000000" / "ground_truth.json", lines=True)
    assert len(truth) == 1 and truth.loc[0, "index"] == 0
    w, x, y, z = truth.loc[0, "sensor_pose"]["quaternion_wxyz"]
    assert w >= 0 and w * w + x * x + y * y + z * z == pytest.approx(1.0, abs=1e-12)


def test_manifest_with_pandas_json_lines(sample):
    manifest = pd.read_json(sample / "manifest.jsonl", lines=True)
    assert list(manifest["index"]) == [0, 1]


def test_ideal_profile_with_pandas(sample):
    ideal = pd.read_csv(sample / "sample_000000" / "ideal_profile.csv")
    assert list(ideal.columns) == [
        "ray", "fan_angle_deg", "x_mm", "z_mm", "object", "label", "part", "glass"]
    assert ideal["glass"].dtype == bool and ideal["glass"].any()
    assert {"pane", "table"} <= set(ideal["object"])


def test_points_ply_with_plyfile(sample):
    vertex = PlyData.read(sample / "sample_000000" / "points.ply")["vertex"]
    assert vertex.data.dtype.names == (
        "x", "y", "z", "red", "green", "blue", "label", "intensity")
    profile = pd.read_csv(sample / "sample_000000" / "profile.csv")
    assert len(vertex) == profile["valid"].sum()
    assert vertex["intensity"].dtype == np.uint16
    np.testing.assert_array_equal(vertex["intensity"], profile.loc[profile["valid"], "intensity_dn"])
