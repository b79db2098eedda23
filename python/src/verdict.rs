//! `check` and `plan`, and what they return.

use crate::errors::{json_to_py, OptionsError};
use crate::fork::parallel_guard;
use crate::prediction::Prediction;
use crate::samples::Samples;
use mcrt_noise::check::{plan as plan_samples, Plan as RustPlan, Status};
use mcrt_noise::{check as check_samples, CheckOptions, Verdict as RustVerdict};
use pyo3::exceptions::PyAssertionError;
use pyo3::prelude::*;

fn options_from(false_alarm_rate: f64, power: f64, target_mean: f64, target_variance: f64) -> PyResult<CheckOptions> {
    let err = |e: mcrt_noise::scene::FieldError| OptionsError::new_err(e.to_string());
    CheckOptions::new(false_alarm_rate)
        .map_err(err)?
        .with_power(power)
        .map_err(err)?
        .with_targets(target_mean, target_variance)
        .map_err(err)
}

/// The check's verdict: PASS, FAIL or NOT RESOLVED, with every z-score,
/// limit and detectable error. `str()` is the CLI's text.
#[pyclass(module = "mcrt_noise", frozen)]
pub struct Verdict {
    inner: RustVerdict,
}

impl Verdict {
    fn quantity(&self, name: &str) -> Option<&mcrt_noise::check::QuantityCheck> {
        self.inner.checks.iter().find(|c| c.name == name)
    }
}

#[pymethods]
impl Verdict {
    /// "pass", "fail" or "not resolved".
    #[getter]
    fn status(&self) -> &'static str {
        match self.inner.status {
            Status::Pass => "pass",
            Status::Fail => "fail",
            Status::NotResolved => "not resolved",
        }
    }

    /// Whether the check passed.
    #[getter]
    fn passed(&self) -> bool {
        self.inner.pass
    }

    /// Whether the samples decided (a pass or a failure).
    #[getter]
    fn resolved(&self) -> bool {
        self.inner.resolved()
    }

    /// The mean's z-score (None where the samples give none: too few, no spread).
    #[getter]
    fn z_mean(&self) -> Option<f64> {
        self.quantity("mean L").and_then(|c| c.z)
    }

    /// Var L's z-score (None where the samples give none).
    #[getter]
    fn z_variance(&self) -> Option<f64> {
        self.quantity("Var L").and_then(|c| c.z)
    }

    /// The |z| limit both z-tests use.
    #[getter]
    fn z_limit(&self) -> f64 {
        self.inner.z_limit
    }

    /// The relative error of the mean a check of these samples detects
    /// with the stated power, either way (None where it failed or did not
    /// resolve).
    #[getter]
    fn detectable_mean_error(&self) -> Option<f64> {
        self.quantity("mean L").and_then(|c| c.detectable_relative_error)
    }

    /// The same for Var L.
    #[getter]
    fn detectable_variance_error(&self) -> Option<f64> {
        self.quantity("Var L").and_then(|c| c.detectable_relative_error)
    }

    /// Why it failed, one line each.
    #[getter]
    fn failures(&self) -> Vec<String> {
        self.inner.failures.clone()
    }

    /// What would resolve it, one line each.
    #[getter]
    fn unresolved(&self) -> Vec<String> {
        self.inner.unresolved.clone()
    }

    /// Raises AssertionError with the whole verdict unless it passed (for
    /// pytest).
    fn assert_pass(&self) -> PyResult<()> {
        if self.inner.pass {
            Ok(())
        } else {
            Err(PyAssertionError::new_err(self.inner.to_string()))
        }
    }

    /// Everything, as the CLI's `--json` gives it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.inner)
    }

    fn __bool__(&self) -> bool {
        self.inner.pass
    }

    fn __str__(&self) -> String {
        self.inner.to_string()
    }

    fn __repr__(&self) -> String {
        format!("<Verdict {}>", self.inner.status.label())
    }
}

/// Checks `samples` against `prediction` at the family-wise false-alarm
/// rate `false_alarm_rate`, able to detect relative errors `target_mean`
/// and `target_variance` with probability `power`.
#[pyfunction]
#[pyo3(signature = (prediction, samples, *, false_alarm_rate = 1e-3, power = 0.9, target_mean = 0.1, target_variance = 0.2))]
pub(crate) fn _check_samples(
    py: Python<'_>,
    prediction: &Prediction,
    samples: &Samples,
    false_alarm_rate: f64,
    power: f64,
    target_mean: f64,
    target_variance: f64,
) -> PyResult<Verdict> {
    let options = options_from(false_alarm_rate, power, target_mean, target_variance)?;
    parallel_guard()?;
    let samples = samples.snapshot();
    let inner = py.detach(|| check_samples(&prediction.inner, &samples, &options));
    Ok(Verdict { inner })
}

/// About how many samples a check needs, from a pilot of the renderer's
/// values.
#[pyclass(module = "mcrt_noise", frozen)]
pub struct Plan {
    inner: RustPlan,
}

#[pymethods]
impl Plan {
    /// About how many samples the check needs (None where the pilot cannot tell).
    #[getter]
    fn samples(&self) -> Option<f64> {
        self.inner.samples
    }

    /// The pilot's size.
    #[getter]
    fn pilot_samples(&self) -> u64 {
        self.inner.pilot_samples
    }

    /// Everything, as the CLI's `check --plan --json` gives it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.inner)
    }

    fn __str__(&self) -> String {
        self.inner.to_string()
    }
}

/// The sample planner: how many values the check needs for its targets.
#[pyfunction]
#[pyo3(signature = (prediction, pilot, *, false_alarm_rate = 1e-3, power = 0.9, target_mean = 0.1, target_variance = 0.2))]
pub(crate) fn _plan_samples(
    prediction: &Prediction,
    pilot: &Samples,
    false_alarm_rate: f64,
    power: f64,
    target_mean: f64,
    target_variance: f64,
) -> PyResult<Plan> {
    let options = options_from(false_alarm_rate, power, target_mean, target_variance)?;
    parallel_guard()?;
    Ok(Plan { inner: plan_samples(&prediction.inner, &pilot.snapshot(), &options) })
}
