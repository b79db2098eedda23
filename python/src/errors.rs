//! The Python exceptions, and the conversions every module shares.

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(mcrt_noise, SceneError, PyValueError, "An invalid scene: every invalid value named, with its range.");
create_exception!(
    mcrt_noise,
    PredictError,
    PyRuntimeError,
    "The oracle cannot predict this scene (not covered, not converged within its budget, or beyond f64)."
);
create_exception!(
    mcrt_noise,
    SampleError,
    PyValueError,
    "A value that cannot be an iteration's pixel value (negative, not finite), or power sums no values have."
);
create_exception!(mcrt_noise, OptionsError, PyValueError, "An invalid check option, named with its allowed range.");

pub(crate) fn scene_error(e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(e.to_string())
}

pub(crate) fn sample_error(e: mcrt_noise::SampleError) -> PyErr {
    SampleError::new_err(e.to_string())
}

/// A serialisable value as the plain Python value its JSON decodes to.
pub(crate) fn json_to_py<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}
