//! `predict` and what it returns.

use crate::errors::{json_to_py, OptionsError, PredictError, SceneError};
use crate::fork::parallel_guard;
use crate::scene::Scene;
use mcrt_noise::check::predict_with;
use mcrt_noise::oracle::Precision;
use mcrt_noise::Prediction as RustPrediction;
use pyo3::prelude::*;

/// A predicted quantity: its value and two bounds on its error.
#[pyclass(module = "mcrt_noise", frozen, get_all)]
#[derive(Clone, Copy)]
pub struct Predicted {
    /// The predicted value.
    value: f64,
    /// Bound on the quadrature's error.
    quadrature_bar: f64,
    /// Bound on the model's own error (0 where the model is exact at R).
    model_bar: f64,
}

#[pymethods]
impl Predicted {
    /// quadrature_bar + model_bar.
    #[getter]
    fn total_bar(&self) -> f64 {
        self.quadrature_bar + self.model_bar
    }

    fn __repr__(&self) -> String {
        format!(
            "Predicted(value={:e}, quadrature_bar={:e}, model_bar={:e})",
            self.value, self.quadrature_bar, self.model_bar
        )
    }
}

impl From<mcrt_noise::Predicted> for Predicted {
    fn from(p: mcrt_noise::Predicted) -> Self {
        Predicted { value: p.value, quadrature_bar: p.quadrature_bar, model_bar: p.model_bar }
    }
}

/// The mean and Var L of one iteration, with their bars, the model that
/// gave them and the bias b(R) = μ(R) − μ(0).
#[pyclass(module = "mcrt_noise", frozen)]
pub struct Prediction {
    pub(crate) inner: RustPrediction,
}

#[pymethods]
impl Prediction {
    /// The mean ⟨⟨L⟩⟩ of one iteration.
    #[getter]
    fn mean(&self) -> Predicted {
        self.inner.mean.into()
    }

    /// Var L of one iteration.
    #[getter]
    fn variance(&self) -> Predicted {
        self.inner.variance.into()
    }

    /// The model that produced the prediction, as the CLI names it.
    #[getter]
    fn model(&self) -> String {
        self.inner.model.to_string()
    }

    /// The bias b(R) = μ(R) − μ(0) as (value, bar), or None where the
    /// small-sphere mean μ(0) is not computed.
    #[getter]
    fn bias(&self) -> Option<(f64, f64)> {
        self.inner.bias.map(|b| (b.value, b.error))
    }

    /// Everything, the oracle's report included, as the CLI's JSON gives it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.inner)
    }

    fn __repr__(&self) -> String {
        format!(
            "Prediction(model={:?}, mean={}, variance={})",
            self.model(),
            self.mean().__repr__(),
            self.variance().__repr__()
        )
    }
}

/// Predicts one iteration's mean and Var L (and the bias) for a scene.
///
/// `rel_tol` is the quadrature's relative goal in (0, 1) (None: the
/// oracle's default). Computes on its own thread with the GIL released
/// (milliseconds for uncollided light, seconds to minutes with scattered
/// light: `docs/library.md`); Ctrl-C returns at once with
/// `KeyboardInterrupt` (the computation then finishes in the background,
/// within its evaluation budget, and is dropped).
#[pyfunction]
#[pyo3(signature = (scene, *, rel_tol = None))]
pub(crate) fn predict(py: Python<'_>, scene: &Scene, rel_tol: Option<f64>) -> PyResult<Prediction> {
    if let Some(tol) = rel_tol {
        if !(tol > 0.0 && tol < 1.0) {
            return Err(OptionsError::new_err(format!(
                "rel_tol = {tol:e}: must be in (0, 1), or None for the default"
            )));
        }
    }
    parallel_guard()?;
    let scene = scene.inner.clone();
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .name("mcrt-noise-predict".into())
        .spawn(move || {
            // The receiver may be gone (Ctrl-C): nothing to tell then.
            let _ = send.send(predict_with(&scene, Precision::F64, rel_tol));
        })
        .map_err(|e| PredictError::new_err(format!("cannot start the prediction's thread: {e}")))?;
    let mut receive = receive;
    let result = loop {
        // The receiver is Send but not Sync: it travels into the detached closure and back.
        let (got, back) = py.detach(move || (receive.recv_timeout(std::time::Duration::from_millis(100)), receive));
        receive = back;
        match got {
            Ok(result) => break result,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PredictError::new_err(
                    "the prediction's thread ended without a result (a bug: please report it)",
                ))
            }
        }
    };
    result.map(|inner| Prediction { inner }).map_err(|e| match e {
        mcrt_noise::PredictError::Scene(e) => SceneError::new_err(e.to_string()),
        other => PredictError::new_err(other.to_string()),
    })
}
