"""The Python package (python/, PyO3) against the command line, on shipped scenes at few
photons: the same numbers bit for bit (images, irradiance, profiles, poses, locate and
register results), the same error messages, the GIL released while it simulates, and the
dataset loader's checks.

Needs `pip install ./python` in the venv (`.ci/run` does it) and the release binary
(`cargo build --release`, or the path in $GLASSSCAN).
"""

import json
import os
import pickle
import shutil
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import OpenEXR
import pandas as pd
import pytest
from PIL import Image
from plyfile import PlyData

import glassscan

REPO = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GLASSSCAN", REPO / "target" / "release" / "glassscan"))
SCENE = REPO / "scenes" / "edge_study_bare.toml"
PHOTONS = 16384


def cli(*args, check=True):
    return subprocess.run([str(BINARY), *map(str, args)], cwd=REPO, check=check,
                          capture_output=True, text=True)


def cli_error(*args):
    """The message the command line prints after `error: `, and its exit code."""
    done = cli(*args, check=False)
    lines = [l for l in done.stderr.splitlines() if l.startswith("error: ")]
    assert lines, done.stderr
    return lines[-1][len("error: "):], done.returncode


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    out = tmp_path_factory.mktemp("scan")
    cli("scan", SCENE, "--poses", 2, "--scan-angle-deg", 45, "--photons", PHOTONS,
        "--seed", 7, "--out", out, "--force")
    return out


@pytest.fixture(scope="module")
def scene():
    return glassscan.Scene.load(SCENE, poses=2, scan_angle_deg=45)


@pytest.fixture(scope="module")
def dataset_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("ds") / "ds"
    cli("dataset", REPO / "scenes" / "edge_study.toml", "--count", 3, "--out", out,
        "--photons", PHOTONS, "--seed", 5)
    return out


def read_exr(path):
    with OpenEXR.File(str(path)) as exr:
        return {name: c.pixels.copy() for name, c in exr.channels().items()}


@pytest.mark.parametrize("pose", [0, 1])
def test_simulate_equals_scan_bit_for_bit(scan, scene, pose):
    sim = scene.simulate(pose, photons=PHOTONS, seed=7)
    stem = scan / f"pose_{pose:03d}"
    # Image: the PNG holds DN << 6 (10-bit ADC).
    png = np.array(Image.open(f"{stem}.png"))
    assert sim.image.dtype == np.uint16 and sim.image.shape == png.shape
    assert np.array_equal(sim.image, png >> 6)
    assert np.array_equal(glassscan.read_image(f"{stem}.png"), sim.image)
    # Irradiance: every layer of the EXR, bit for bit.
    exr = read_exr(f"{stem}.exr")
    assert set(exr) == {"irradiance"} | {f"class.{k}" for k in sim.irradiance if k != "total"}
    assert exr["irradiance"].tobytes() == sim.irradiance["total"].tobytes()
    for name, layer in sim.irradiance.items():
        if name != "total":
            assert exr[f"class.{name}"].tobytes() == layer.tobytes(), name
    assert sim.irradiance["total"].max() > 0
    # Profile: pandas' reading of the CSV holds the same numbers (NaN where invalid).
    csv = pd.read_csv(f"{stem}_profile.csv", keep_default_na=False, na_values=["NaN"])
    frame = sim.profile_frame()
    assert list(frame.columns) == list(csv.columns)
    for column in csv.columns:
        expected = csv[column].to_numpy()
        got = frame[column].to_numpy()
        if expected.dtype.kind == "f":
            assert np.array_equal(got, expected, equal_nan=True), column
        else:
            assert (got == expected).all(), column
    assert glassscan.read_profile(f"{stem}_profile.csv").tobytes() == sim.profile.tobytes()
    assert sim.profile["valid"].sum() > 300
    # Ground truth: the manifest's poses and p_e.
    manifest = json.loads((scan / "manifest.json").read_text())["poses"][pose]
    matrix = np.array(manifest["sensor_pose"]["matrix_mm"]).reshape(4, 4)
    assert np.array_equal(sim.ground_truth["sensor_pose"], matrix)
    assert np.allclose(sim.ground_truth["edge_point_mm"], manifest["edge_point_mm"],
                       rtol=0, atol=1e-9)
    ideal = sim.ground_truth["ideal_profile"]
    assert len(ideal) > 500 and set(ideal["part"]) <= {"top_face", "bottom_face", "edge", "solid"}


def test_the_adaptive_count_equals_scan_photons_auto(tmp_path, scene):
    # `photons="auto"` is `--photons auto`: the pose stops at the same photon count, and the
    # image is the same bit for bit.
    cli("scan", SCENE, "--poses", 2, "--scan-angle-deg", 45, "--photons", "auto",
        "--seed", 7, "--out", tmp_path, "--force")
    manifest = json.loads((tmp_path / "manifest.json").read_text())["poses"][1]
    sim = scene.simulate(1, photons="auto", seed=7)
    assert sim.stats["photons"] == manifest["stats"]["photons"]
    assert sim.stats["photons"] in (1 << 17, 1 << 18)
    png = np.array(Image.open(tmp_path / "pose_001.png"))
    assert np.array_equal(sim.image, png >> 6)


def test_results_do_not_depend_on_the_thread_count(scene):
    one = scene.simulate(1, photons=PHOTONS, seed=11, threads=1)
    two = scene.simulate(1, photons=PHOTONS, seed=11, threads=2)
    assert one.image.tobytes() == two.image.tobytes()
    assert one.irradiance["total"].tobytes() == two.irradiance["total"].tobytes()
    assert one.profile.tobytes() == two.profile.tobytes()


def test_simulate_releases_the_gil(scene):
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    ticker = threading.Thread(target=tick)
    ticker.start()
    time.sleep(0.05)
    start = time.perf_counter()
    scene.simulate(0, photons=4 * PHOTONS, seed=2)
    end = time.perf_counter()
    done.set()
    ticker.join()
    during = [t for t in ticks if start < t < end]
    # Holding the GIL, the other thread could not tick at all during the call.
    assert end - start > 0.05
    assert len(during) >= 5, (len(during), end - start)


def test_overrides_are_checked_with_the_command_lines_messages(tmp_path):
    message, code = cli_error("scan", SCENE, "--out", tmp_path / "x", "--scan-angle-deg", 95)
    assert code == 2
    with pytest.raises(glassscan.InputError) as e:
        glassscan.Scene.load(SCENE, scan_angle_deg=95)
    assert str(e.value) == message
    with pytest.raises(glassscan.InputError, match="--threshold"):
        glassscan.Scene.load(SCENE, threshold=5000)
    scene = glassscan.Scene.load(SCENE, exposure_ms=0.25, threshold="auto", peak_select="last")
    assert scene.settings["exposure_ms"] == 0.25


def test_bad_scene_files_raise_the_command_lines_message(tmp_path):
    bad = tmp_path / "bad.toml"
    text = SCENE.read_text().replace("[scan]", "[scan]\nscan_angle_deg = \"steep\"", 1)
    bad.write_text(text)
    message, code = cli_error("scan", bad, "--out", tmp_path / "o")
    assert code == 2 and "bad.toml" in message
    with pytest.raises(glassscan.InputError) as e:
        glassscan.Scene.load(bad)
    assert str(e.value) == message
    with pytest.raises(glassscan.InputError) as e:
        glassscan.Scene.from_toml(text, path=bad)
    assert str(e.value) == message
    missing, _ = cli_error("scan", tmp_path / "none.toml", "--out", tmp_path / "o")
    with pytest.raises(glassscan.InputError) as e:
        glassscan.Scene.load(tmp_path / "none.toml")
    assert str(e.value) == missing
    assert issubclass(glassscan.InputError, glassscan.GlassscanError)


def test_arguments_that_are_not_whole_numbers_in_range_name_themselves():
    scene = glassscan.Scene.load(SCENE, poses=1)
    for kwargs, name in [
        ({"photons": -1}, "photons"),
        ({"photons": 1e6}, "photons"),
        ({"seed": -1}, "seed"),
        ({"seed": 2**70}, "seed"),
        ({"max_depth": 2**40}, "max_depth"),
        ({"threads": -2}, "threads"),
    ]:
        with pytest.raises(glassscan.InputError, match=f"^{name} must be"):
            scene.simulate(0, **kwargs)
    for pose in (-1, 0.5):
        with pytest.raises(glassscan.InputError, match="^pose must be"):
            scene.simulate(pose, photons=4096)
    # The constructor takes the native scene; a path or name gets the way to load one.
    with pytest.raises(TypeError, match=r"Scene\.load"):
        glassscan.Scene("edge_study")


def test_a_shipped_scene_loads_by_name_from_any_directory(tmp_path, monkeypatch):
    # As the command line's SCENE: away from the repository the name reads the copy shipped
    # in the binary, the same scene as the file.
    monkeypatch.chdir(tmp_path)
    by_name = glassscan.Scene.load("edge_study_bare", poses=1)
    by_file = glassscan.Scene.load(SCENE, poses=1)
    assert Path(by_name.path) == Path("scenes/edge_study_bare.toml")
    a, b = by_name.simulate(0, photons=4096, seed=1), by_file.simulate(0, photons=4096, seed=1)
    assert a.image.tobytes() == b.image.tobytes()
    with pytest.raises(glassscan.InputError, match="shipped scenes: car_side_window"):
        glassscan.Scene.load("edge_studdy")


def test_from_toml_equals_load():
    a = glassscan.Scene.load(SCENE, poses=1)
    b = glassscan.Scene.from_toml(SCENE.read_text(), path=SCENE, poses=1)
    sa, sb = a.simulate(0, photons=4096, seed=1), b.simulate(0, photons=4096, seed=1)
    assert sa.image.tobytes() == sb.image.tobytes()


@pytest.fixture(scope="module")
def located(tmp_path_factory):
    out = tmp_path_factory.mktemp("locate")
    args = ["--poses", 4, "--photons", PHOTONS, "--seed", 3, "--perturb", "1,-0.5,0,0,0,0.2"]
    done = cli("locate", SCENE, *args, "--json", "--out", out / "cli")
    return json.loads(done.stdout), out


def test_locate_equals_the_command_line(located):
    expected, out = located
    got = glassscan.locate(SCENE, poses=4, photons=PHOTONS, seed=3,
                           perturb=(1, -0.5, 0, 0, 0, 0.2), out=out / "py")
    for summary in (expected, got):
        summary.pop("timings_s")
    estimate = got["estimate"].pop("matrix_mm")
    assert estimate.shape == (4, 4)
    assert np.array_equal(estimate.ravel(), expected["estimate"].pop("matrix_mm"))
    assert got == expected
    # The files of --out too, byte for byte (but the summary, which holds the timings).
    files = sorted(p.relative_to(out / "cli") for p in (out / "cli").rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(out / "py") for p in (out / "py").rglob("*")
                           if p.is_file())
    assert Path("bips.csv") in files and len(files) > 6
    for name in files:
        if name != Path("summary.json"):
            assert (out / "py" / name).read_bytes() == (out / "cli" / name).read_bytes(), name


def test_register_equals_the_command_line(located):
    _, out = located
    bips = out / "cli" / "bips.csv"
    expected = json.loads(cli("register", SCENE, bips, "--json").stdout)
    points = pd.read_csv(bips)[["x_mm", "y_mm", "z_mm"]].dropna().to_numpy()
    got = glassscan.register(SCENE, points)
    assert got["estimate"]["translation_mm"] == expected["estimate"]["translation_mm"]
    assert got["estimate"]["rotation_deg"] == expected["estimate"]["rotation_deg"]
    assert np.array_equal(got["estimate"]["matrix_mm"].ravel(),
                          expected["estimate"]["matrix_mm"])
    for key in ("converged", "iterations", "rms_mm", "condition", "difference_from_scene_pose"):
        assert got[key] == expected[key], key
    with pytest.raises(glassscan.InputError, match="N × 3"):
        glassscan.register(SCENE, points[:, :2])
    # Points the command line's CSV reader refuses (beyond ±100 m) are refused here too.
    with pytest.raises(glassscan.InputError, match="row 2 .* within ±1e5"):
        glassscan.register(SCENE, np.vstack([points[:2], [[1e300, 0.0, 0.0]], points[2:]]))


def test_dataset_samples_are_the_files(dataset_dir):
    ds = glassscan.Dataset(dataset_dir)
    assert len(ds) == 3 and list(ds.indices) == [0, 1, 2]
    sample = ds[-1]
    d = dataset_dir / ds.manifest[2]["directory"]
    assert sample["index"] == 2
    assert np.array_equal(sample["image"], np.array(Image.open(d / "image.png")) >> 6)
    exr = read_exr(d / "irradiance.exr")
    assert sample["irradiance"]["total"].tobytes() == exr["irradiance"].tobytes()
    csv = pd.read_csv(d / "profile.csv", keep_default_na=False, na_values=["NaN"])
    assert np.array_equal(sample["profile"]["z_mm"], csv["z_mm"].to_numpy(), equal_nan=True)
    assert list(sample["profile"]["label"]) == list(csv["label"])
    ply = PlyData.read(str(d / "points.ply"))["vertex"]
    assert np.array_equal(sample["points"]["points"][:, 0], ply["x"])
    assert np.array_equal(sample["points"]["label"], ply["label"])
    ideal = pd.read_csv(d / "ideal_profile.csv")
    assert np.array_equal(sample["ideal_profile"]["x_mm"], ideal["x_mm"].to_numpy())
    assert list(sample["ideal_profile"]["object"]) == list(ideal["object"])
    truth = sample["ground_truth"]
    assert truth["sensor_pose"]["matrix_mm"].shape == (4, 4)
    assert np.array_equal(truth["edge_point_mm"], ds.manifest[2]["edge_point_mm"])
    assert [s["index"] for s in ds] == [0, 1, 2]
    assert [s["index"] for s in ds[1:]] == [1, 2]
    with pytest.raises(IndexError):
        ds[3]


def test_a_dataset_pickles_for_dataloader_workers(dataset_dir):
    ds = glassscan.Dataset(dataset_dir, fields=["image", "ground_truth"])
    again = pickle.loads(pickle.dumps(ds))
    assert len(again) == 3
    assert np.array_equal(again[0]["image"], ds[0]["image"])
    assert set(again[0]) == {"index", "manifest", "image", "ground_truth"}


def test_damaged_and_incomplete_datasets_are_refused(dataset_dir, tmp_path):
    copy = tmp_path / "ds"
    shutil.copytree(dataset_dir, copy)
    glassscan.Dataset(copy, verify="hashes")
    sample = copy / "sample_000001"
    # Same size, other bytes: only the hash check sees it.
    data = bytearray((sample / "profile.csv").read_bytes())
    data[-2] = ord("0") if data[-2] != ord("0") else ord("1")
    (sample / "profile.csv").write_bytes(bytes(data))
    glassscan.Dataset(copy)
    with pytest.raises(glassscan.InputError, match="profile.csv.*SHA-256"):
        glassscan.Dataset(copy, verify="hashes")
    # A truncated file: the size check sees it; the message names the file.
    with open(sample / "image.png", "r+b") as f:
        f.truncate(100)
    with pytest.raises(glassscan.InputError, match=r"sample_000001.image\.png"):
        glassscan.Dataset(copy)
    # A sample in no manifest: refused unless allow_missing.
    shutil.rmtree(copy)
    shutil.copytree(dataset_dir, copy)
    manifests = sorted(copy.glob("manifest*.jsonl"))
    lines = manifests[0].read_text().splitlines(keepends=True)
    manifests[0].write_text("".join(lines[:-1]))
    with pytest.raises(glassscan.InputError, match="1 of 3 samples are in no manifest"):
        glassscan.Dataset(copy)
    assert len(glassscan.Dataset(copy, allow_missing=True)) == 2
    with pytest.raises(glassscan.InputError, match="not a glassscan dataset"):
        glassscan.Dataset(tmp_path)
