//! packbed's errors as Python exceptions: every one a `ValueError` subclass
//! carrying the command's one-line message; a stop asked for by Ctrl-C comes
//! back as the `KeyboardInterrupt` that asked for it.

use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::PyErr;

create_exception!(
    _packbed,
    PackbedError,
    PyValueError,
    "Base of packbed's errors: what the user asked for cannot be done (a ValueError)."
);
create_exception!(
    _packbed,
    ConfigError,
    PackbedError,
    "The configuration (a TOML file, a dict or a keyword) is invalid; the message names the key."
);
create_exception!(
    _packbed,
    DataError,
    PackbedError,
    "A data file (bed file, PSD table) has bad content; the message names file and line."
);
create_exception!(
    _packbed,
    FileError,
    PackbedError,
    "A file or folder could not be read or written; the message names it."
);
create_exception!(
    _packbed,
    SettingError,
    PackbedError,
    "A setting of the call (runs, jobs, out, ...) is wrong; the message names it."
);
create_exception!(
    _packbed,
    ImpossibleError,
    PackbedError,
    "The request cannot be carried out (too large, a bed that cannot be built, ...)."
);

/// The Python exception of a library error, with its one-line message.
pub fn to_py(e: packbed::Error) -> PyErr {
    let message = e.to_string();
    match e {
        packbed::Error::Config(_) => ConfigError::new_err(message),
        packbed::Error::Data { .. } => DataError::new_err(message),
        packbed::Error::Io { .. } => FileError::new_err(message),
        packbed::Error::Setting { .. } => SettingError::new_err(message),
        packbed::Error::Impossible(_) => ImpossibleError::new_err(message),
        packbed::Error::Interrupted => PyKeyboardInterrupt::new_err(message),
    }
}

/// A configuration error with `message`.
pub fn config(message: impl Into<String>) -> PyErr {
    ConfigError::new_err(message.into())
}
