//! `mcrt_noise._native`: the one pyo3 layer over the `mcrt-noise` library.
//!
//! Everything here converts and delegates: scenes are validated by
//! `mcrt_scene`, predictions come from `mcrt_noise::predict_with`, verdicts
//! from `mcrt_noise::check`, and every message is the library's (so the
//! same as the CLI's). Errors map to Python exceptions: an invalid scene,
//! value or option to a `ValueError` subclass, a computation the oracle
//! cannot do to `PredictError` (a `RuntimeError`). Long computations release
//! the GIL. The Python package `mcrt_noise` (beside this crate) adds the
//! NumPy conversion of values and the type stubs.

mod errors;
mod prediction;
mod samples;
mod scene;
mod verdict;

use errors::{OptionsError, PredictError, SampleError, SceneError};
use mcrt_noise::reference::{HitMethod, Tracer};
use numpy::PyArray1;
use prediction::{predict, Predicted, Prediction};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use samples::Samples;
use scene::Scene;
use verdict::{_check_samples, _plan_samples, Plan, Verdict};

/// The reference tracer's per-iteration values of a scene (iterations
/// `start .. start + count` of stream `seed`): what a correct renderer
/// gives, for tests and examples. Bit-identical at any thread count.
#[pyfunction]
#[pyo3(signature = (scene, count, *, seed = 1, start = 0))]
fn reference_values<'py>(
    py: Python<'py>,
    scene: &Scene,
    count: u64,
    seed: u64,
    start: u64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    const MAX: u64 = 1 << 32;
    if count > MAX {
        return Err(PyValueError::new_err(format!("count = {count}: must be in [0, {MAX}]")));
    }
    let end = start
        .checked_add(count)
        .ok_or_else(|| PyValueError::new_err(format!("start = {start}: start + count must be below 2^64")))?;
    let tracer = Tracer::new(&scene.inner).map_err(|e| SceneError::new_err(e.to_string()))?;
    let values: Vec<f64> = py.detach(|| {
        use rayon::prelude::*;
        (start..end).into_par_iter().map(|i| tracer.trial(seed, i, HitMethod::Sorted).0).collect()
    });
    Ok(PyArray1::from_vec(py, values))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("PredictError", py.get_type::<PredictError>())?;
    m.add("SampleError", py.get_type::<SampleError>())?;
    m.add("OptionsError", py.get_type::<OptionsError>())?;
    m.add_class::<Scene>()?;
    m.add_class::<Predicted>()?;
    m.add_class::<Prediction>()?;
    m.add_class::<Samples>()?;
    m.add_class::<Verdict>()?;
    m.add_class::<Plan>()?;
    m.add_function(wrap_pyfunction!(predict, m)?)?;
    m.add_function(wrap_pyfunction!(_check_samples, m)?)?;
    m.add_function(wrap_pyfunction!(_plan_samples, m)?)?;
    m.add_function(wrap_pyfunction!(reference_values, m)?)?;
    Ok(())
}
