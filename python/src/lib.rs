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
mod fork;
mod prediction;
mod samples;
mod scene;
mod verdict;

use errors::{OptionsError, PredictError, SampleError, SceneError};
use fork::parallel_guard;
use mcrt_noise::reference::{HitMethod, Tracer};
use numpy::PyArray1;
use prediction::{predict, Predicted, Prediction};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use samples::Samples;
use scene::Scene;
use verdict::{_check_samples, _plan_samples, Plan, Verdict};

/// The most values `reference_values` gives in one call (800 MB).
const MAX_REFERENCE_VALUES: i128 = 100_000_000;

/// The reference tracer's per-iteration values of a scene (iterations
/// `start .. start + count` of stream `seed`, count at most 10⁸): what a
/// correct renderer gives, for tests and examples. Bit-identical at any
/// thread count; Ctrl-C is looked at every 65 536 values.
#[pyfunction]
#[pyo3(signature = (scene, count, *, seed = 1, start = 0))]
fn reference_values<'py>(
    py: Python<'py>,
    scene: &Scene,
    count: i128,
    seed: i128,
    start: i128,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let count = u64::try_from(count)
        .ok()
        .filter(|&c| i128::from(c) <= MAX_REFERENCE_VALUES)
        .ok_or_else(|| PyValueError::new_err(format!("count = {count}: must be in [0, {MAX_REFERENCE_VALUES}]")))?;
    let seed =
        u64::try_from(seed).map_err(|_| PyValueError::new_err(format!("seed = {seed}: must be in [0, 2^64)")))?;
    let start = u64::try_from(start)
        .ok()
        .filter(|s| s.checked_add(count).is_some())
        .ok_or_else(|| PyValueError::new_err(format!("start = {start}: must be in [0, 2^64 - count]")))?;
    parallel_guard()?;
    let tracer = Tracer::new(&scene.inner).map_err(|e| SceneError::new_err(e.to_string()))?;
    let mut values = vec![0.0; count as usize];
    const BLOCK: usize = 1 << 16;
    for (b, block) in values.chunks_mut(BLOCK).enumerate() {
        let first = start + (b * BLOCK) as u64;
        py.detach(|| {
            use rayon::prelude::*;
            block
                .par_iter_mut()
                .enumerate()
                .for_each(|(k, v)| *v = tracer.trial(seed, first + k as u64, HitMethod::Sorted).0);
        });
        py.check_signals()?;
    }
    Ok(PyArray1::from_vec(py, values))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Load NumPy's C API now: loaded lazily inside a call, a pending Ctrl-C
    // would interrupt the load and rust-numpy would panic.
    PyArray1::<f64>::zeros(py, 0, false);
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
