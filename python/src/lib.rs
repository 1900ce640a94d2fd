//! `glassscan._native`: the Python extension module (PyO3). It holds no physics of its own:
//! every call goes to the `glassscan` library, and every check and error message is the
//! command line's (`glassscan::cli::embed`). The Python package around it
//! (`pysrc/glassscan`) turns its dicts of arrays into the public API.
//!
//! One file per concept: `error` (exceptions), `arrays` (library values as numpy arrays),
//! `scene` (scenes, simulation, locate, register), `files` (a dataset's files).

mod arrays;
mod error;
mod files;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_PHOTONS", glassscan::transport::DEFAULT_PHOTONS)?;
    m.add("GlassscanError", py.get_type::<error::GlassscanError>())?;
    m.add("InputError", py.get_type::<error::InputError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(files::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_irradiance, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_profile, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_points, m)?)?;
    m.add_function(wrap_pyfunction!(files::index_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(files::path_classes, m)?)?;
    Ok(())
}
