//! `packbed._packbed`: the Python bindings of packbed's library front door.
//!
//! Thin by design: every call parses its arguments (settings arrive as JSON
//! text of the TOML schema, so that serde gives the same checks and messages
//! as a config file), runs the library off the GIL (`detached`) and hands
//! back numpy arrays or JSON text. The Python package in `python/packbed`
//! wraps these into the documented API; nothing here reimplements the library.

mod bed;
mod config;
mod detached;
mod ensemble;
mod errors;

use pyo3::prelude::*;

/// The system's allocator, with huge pages where a stage asks for them (as
/// the command's).
#[global_allocator]
static ALLOCATOR: packbed::Allocator = packbed::Allocator;

#[pymodule]
fn _packbed(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("PackbedError", py.get_type::<errors::PackbedError>())?;
    m.add("ConfigError", py.get_type::<errors::ConfigError>())?;
    m.add("DataError", py.get_type::<errors::DataError>())?;
    m.add("FileError", py.get_type::<errors::FileError>())?;
    m.add("SettingError", py.get_type::<errors::SettingError>())?;
    m.add("ImpossibleError", py.get_type::<errors::ImpossibleError>())?;
    m.add_class::<bed::Bed>()?;
    m.add_function(wrap_pyfunction!(config::resolve_config, m)?)?;
    m.add_function(wrap_pyfunction!(bed::deposit, m)?)?;
    m.add_function(wrap_pyfunction!(bed::read, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::merge, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::compare, m)?)?;
    Ok(())
}
