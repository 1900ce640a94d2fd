//! A dataset's files, read by the library's own readers (the ones `verify`, `score` and the
//! tests use), so Python sees exactly what was written.

use std::path::PathBuf;

use glassscan::dataset::integrity::Depth;
use glassscan::dataset::verify::verify_dataset_lines;
use glassscan::io::{exr, ply, png16, profile_csv};
use glassscan::sensor::path_class::PathClass;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::error::input;

/// The sensor image of a `.png` as digital numbers (the file's `sBIT` undone), uint16.
#[pyfunction]
pub fn read_image(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyArray2<u16>>> {
    let img = py
        .detach(|| png16::read_sensor_png16(&path))
        .map_err(input)?;
    Ok(arrays::image(py, &img))
}

/// The layers of an irradiance `.exr` (W/m², float32): `total` and one per path class.
#[pyfunction]
pub fn read_irradiance(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let layers = py.detach(|| exr::read_exr_layers(&path)).map_err(input)?;
    arrays::exr_layers(py, layers)
}

/// The columns of a profile CSV.
#[pyfunction]
pub fn read_profile(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let profile = profile_csv::read_profile_csv(&path).map_err(input)?;
    arrays::profile(py, &profile)
}

/// The points of a `.ply` (binary or ASCII): `points` (N × 3, mm), `colors`, `label`,
/// `intensity`.
#[pyfunction]
pub fn read_points(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let cloud = ply::read_ply(&path).map_err(input)?;
    arrays::point_cloud(py, &cloud)
}

/// Reads a dataset's `run.json` and manifests and checks every listed sample's files, by size
/// (`hashes` false) or also by SHA-256: the report (as `glassscan verify --json` prints it),
/// the run file and the manifest lines, as JSON texts.
#[pyfunction]
pub fn index_dataset(
    py: Python<'_>,
    path: PathBuf,
    hashes: bool,
) -> PyResult<(String, String, Vec<String>)> {
    let depth = if hashes { Depth::Hashes } else { Depth::Sizes };
    let (report, index) = py
        .detach(|| verify_dataset_lines(&path, depth))
        .map_err(input)?;
    Ok((
        json(&report),
        json(&index.run),
        index.lines.iter().map(json).collect(),
    ))
}

/// The path class names, in the order of the `label` numbers of `points.ply`.
#[pyfunction]
pub fn path_classes() -> Vec<&'static str> {
    PathClass::LABELS.iter().map(|c| c.name()).collect()
}

/// JSON text of a dataset record (all of them serialise: they were read from JSON).
fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("a dataset record serialises")
}
