//! Library values as numpy arrays and dicts, in the units and with the names of the files the
//! command line writes, so a Python result and the CLI's file hold the same numbers bit for bit.

use glassscan::dataset::ideal_profile::IdealPoint;
use glassscan::geometry::pose::{pose_to_matrix_mm, Pose};
use glassscan::io::ply::PointCloud;
use glassscan::sensor::image::Image;
use glassscan::sensor::path_class::PathClass;
use glassscan::sensor::profile::Profile;
use glassscan::transport::Irradiance;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// An image as a (rows, columns) array, row 0 at the top.
pub fn image<'py, T: numpy::Element + Clone>(
    py: Python<'py>,
    img: &Image<T>,
) -> Bound<'py, PyArray2<T>> {
    Array2::from_shape_vec((img.height, img.width), img.data.clone())
        .expect("an image holds width × height values")
        .into_pyarray(py)
}

/// An f64 image as f32, as the EXR stores it.
fn image_f32<'py>(py: Python<'py>, img: &Image<f64>) -> Bound<'py, PyArray2<f32>> {
    let data: Vec<f32> = img.data.iter().map(|&v| v as f32).collect();
    Array2::from_shape_vec((img.height, img.width), data)
        .expect("an image holds width × height values")
        .into_pyarray(py)
}

/// The irradiance layers (W/m², f32 as in the EXR): `total` and one per path class name.
pub fn irradiance<'py>(py: Python<'py>, irr: &Irradiance) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("total", image_f32(py, &irr.total))?;
    for c in PathClass::ALL {
        d.set_item(c.name(), image_f32(py, &irr.by_class[c.index()]))?;
    }
    Ok(d)
}

/// The layers of an irradiance EXR under the same names as [`irradiance`]: `irradiance` →
/// `total`, `class.<name>` → `<name>`; any other channel keeps its name.
pub fn exr_layers<'py>(
    py: Python<'py>,
    layers: Vec<(String, Image<f32>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, img) in layers {
        let key = match name.as_str() {
            "irradiance" => "total".to_string(),
            other => other.strip_prefix("class.").unwrap_or(other).to_string(),
        };
        d.set_item(key, image(py, &img))?;
    }
    Ok(d)
}

/// A profile's columns, named and valued as in the profile CSV (`io::profile_csv`): invalid
/// points hold NaN in `row_px`, `x_mm` and `z_mm`; `label` is the path class name or "".
pub fn profile<'py>(py: Python<'py>, profile: &Profile) -> PyResult<Bound<'py, PyDict>> {
    let p = &profile.points;
    let position = |f: fn(&glassscan::sensor::profile::ProfilePoint) -> f64| -> Vec<f64> {
        p.iter()
            .map(|q| if q.valid { f(q) } else { f64::NAN })
            .collect()
    };
    let d = PyDict::new(py);
    let column: Vec<u32> = p.iter().map(|q| q.column as u32).collect();
    d.set_item("column", column.into_pyarray(py))?;
    let reflection: Vec<u8> = p.iter().map(|q| q.reflection).collect();
    d.set_item("reflection", reflection.into_pyarray(py))?;
    d.set_item("row_px", position(|q| q.row).into_pyarray(py))?;
    d.set_item("x_mm", position(|q| q.x_mm).into_pyarray(py))?;
    d.set_item("z_mm", position(|q| q.z_mm).into_pyarray(py))?;
    let intensity: Vec<u16> = p.iter().map(|q| q.intensity).collect();
    d.set_item("intensity_dn", intensity.into_pyarray(py))?;
    let width: Vec<u32> = p.iter().map(|q| q.width).collect();
    d.set_item("width_px", width.into_pyarray(py))?;
    let threshold: Vec<u16> = p.iter().map(|q| q.threshold).collect();
    d.set_item("threshold_dn", threshold.into_pyarray(py))?;
    let m0: Vec<f64> = p.iter().map(|q| q.m0).collect();
    d.set_item("m0_dn", m0.into_pyarray(py))?;
    let m1: Vec<f64> = p.iter().map(|q| q.m1).collect();
    d.set_item("m1_dn_px", m1.into_pyarray(py))?;
    let labels = PyList::new(py, p.iter().map(|q| q.label.map_or("", PathClass::name)))?;
    d.set_item("label", labels)?;
    let valid: Vec<bool> = p.iter().map(|q| q.valid).collect();
    d.set_item("valid", valid.into_pyarray(py))?;
    let saturated: Vec<bool> = p.iter().map(|q| q.saturated).collect();
    d.set_item("saturated", saturated.into_pyarray(py))?;
    Ok(d)
}

/// The name a unit enum variant serialises to (the snake_case of the JSON and CSV files).
fn serde_name<T: serde::Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => s,
        other => unreachable!("a unit enum variant serialises to a string, got {other:?}"),
    }
}

/// The ideal profile's columns, as in `ideal_profile.csv`.
pub fn ideal_profile<'py>(py: Python<'py>, ideal: &[IdealPoint]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ray: Vec<u32> = ideal.iter().map(|p| p.ray as u32).collect();
    d.set_item("ray", ray.into_pyarray(py))?;
    let angle: Vec<f64> = ideal.iter().map(|p| p.fan_angle_deg).collect();
    d.set_item("fan_angle_deg", angle.into_pyarray(py))?;
    let x: Vec<f64> = ideal.iter().map(|p| p.x_mm).collect();
    d.set_item("x_mm", x.into_pyarray(py))?;
    let z: Vec<f64> = ideal.iter().map(|p| p.z_mm).collect();
    d.set_item("z_mm", z.into_pyarray(py))?;
    d.set_item(
        "object",
        PyList::new(py, ideal.iter().map(|p| p.object.as_str()))?,
    )?;
    d.set_item(
        "label",
        PyList::new(py, ideal.iter().map(|p| serde_name(&p.label)))?,
    )?;
    d.set_item(
        "part",
        PyList::new(py, ideal.iter().map(|p| serde_name(&p.part)))?,
    )?;
    let glass: Vec<bool> = ideal.iter().map(|p| p.glass).collect();
    d.set_item("glass", glass.into_pyarray(py))?;
    Ok(d)
}

/// A pose as its 4 × 4 homogeneous matrix, translation in mm.
pub fn pose_matrix<'py>(py: Python<'py>, pose: &Pose) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((4, 4), pose_to_matrix_mm(pose).to_vec())
        .expect("16 values")
        .into_pyarray(py)
}

/// A point cloud's columns: `points` (N × 3, mm), and `colors` (N × 3), `label`, `intensity`
/// where the file has them.
pub fn point_cloud<'py>(py: Python<'py>, cloud: &PointCloud) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("points", triples(py, &cloud.points))?;
    if !cloud.colors.is_empty() {
        d.set_item("colors", triples(py, &cloud.colors))?;
    }
    if !cloud.labels.is_empty() {
        d.set_item("label", cloud.labels.clone().into_pyarray(py))?;
    }
    if !cloud.intensities.is_empty() {
        d.set_item("intensity", cloud.intensities.clone().into_pyarray(py))?;
    }
    Ok(d)
}

/// One row of three per item (N × 3).
fn triples<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    items: &[[T; 3]],
) -> Bound<'py, PyArray2<T>> {
    let flat: Vec<T> = items.iter().flatten().copied().collect();
    Array2::from_shape_vec((items.len(), 3), flat)
        .expect("three per item")
        .into_pyarray(py)
}
