//! `Samples`: exact power sums of a renderer's values, from NumPy arrays,
//! iterables or chunks.

use crate::errors::{sample_error, SampleError};
use mcrt_noise::Samples as RustSamples;
use numpy::{PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Exact power sums Σ Lᵏ (k = 1…6) of a renderer's per-iteration values, the
/// count of nonzero values and the extremes: any order of addition and any
/// merge give the same bits, so values can stream in chunks (10⁸ and more).
#[pyclass(module = "mcrt_noise")]
#[derive(Clone, Default)]
pub struct Samples {
    pub(crate) inner: RustSamples,
}

/// Adds a chunk of values to `samples`, the GIL released: split over the
/// threads and merged (exact, so the same bits whatever the split).
fn add_values(py: Python<'_>, samples: &mut RustSamples, values: &[f64]) -> PyResult<()> {
    const CHUNK: usize = 1 << 16;
    let offset = samples.count();
    let parts: Vec<Result<RustSamples, mcrt_noise::SampleError>> = py.detach(|| {
        use rayon::prelude::*;
        values
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut part = RustSamples::new();
                part.extend(chunk.iter().copied()).map(|()| part)
            })
            .collect()
    });
    for (i, part) in parts.into_iter().enumerate() {
        match part {
            Ok(part) => *samples = std::mem::take(samples).merge(&part),
            Err(e) => return Err(sample_error(renumbered(e, offset + (i * CHUNK) as u64))),
        }
    }
    Ok(())
}

/// A chunk's error with its index counted from the first value ever added.
fn renumbered(e: mcrt_noise::SampleError, offset: u64) -> mcrt_noise::SampleError {
    use mcrt_noise::SampleError as E;
    match e {
        E::NotFinite { index, value } => E::NotFinite { index: index + offset, value },
        E::Negative { index, value } => E::Negative { index: index + offset, value },
        other => other,
    }
}

/// `values` as a contiguous 1-D float64 array: a NumPy array of that kind
/// as it is, any other array-like through `numpy.asarray`, an iterator
/// through `numpy.fromiter` (read once).
fn float64_array<'py>(values: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArray1<'py, f64>> {
    if let Ok(array) = values.extract::<PyReadonlyArray1<'py, f64>>() {
        if array.is_contiguous() {
            return Ok(array);
        }
    }
    let np = values.py().import("numpy")?;
    let float64 = np.getattr("float64")?;
    let array = if values.hasattr("__len__")? || values.hasattr("__array__")? {
        np.call_method1("asarray", (values, &float64))?
    } else {
        np.call_method1("fromiter", (values, &float64))?
    };
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        let shape = array.getattr("shape")?;
        return Err(SampleError::new_err(format!(
            "values: an array of shape {shape}: must be one-dimensional (one value per iteration)"
        )));
    }
    np.call_method1("ascontiguousarray", (array,))?
        .extract()
        .map_err(|e: pyo3::CastError| PyValueError::new_err(e.to_string()))
}

#[pymethods]
impl Samples {
    #[new]
    fn new() -> Samples {
        Samples::default()
    }

    /// Adds one iteration's value L (finite, >= 0).
    fn push(&mut self, value: f64) -> PyResult<()> {
        self.inner.push(value).map_err(sample_error)
    }

    /// Adds every value of `values` (a NumPy array, any array-like or
    /// iterable of floats), the GIL released, stopping with `SampleError`
    /// at the first that cannot be a pixel value (that value's chunk of
    /// 65 536 is then not added).
    fn extend(&mut self, values: &Bound<'_, PyAny>) -> PyResult<()> {
        let array = float64_array(values)?;
        let slice = array.as_slice().map_err(|e| PyValueError::new_err(e.to_string()))?;
        add_values(values.py(), &mut self.inner, slice)
    }

    /// These samples and `other`'s together (exact).
    fn merge(&self, other: &Samples) -> Samples {
        Samples { inner: self.inner.clone().merge(&other.inner) }
    }

    /// Power sums made elsewhere: `count` values, Σ Lᵏ for k = 1…6 and a
    /// bound on their relative error (0 if exact).
    #[staticmethod]
    #[pyo3(signature = (count, sums, sums_relative_error = 0.0))]
    fn from_power_sums(count: u64, sums: [f64; 6], sums_relative_error: f64) -> PyResult<Samples> {
        RustSamples::from_power_sums(count, sums, sums_relative_error)
            .map(|inner| Samples { inner })
            .map_err(sample_error)
    }

    /// How many values.
    #[getter]
    fn count(&self) -> u64 {
        self.inner.count()
    }

    /// How many are nonzero (None for power sums made elsewhere).
    #[getter]
    fn nonzero(&self) -> Option<u64> {
        self.inner.nonzero()
    }

    /// The sample mean and its standard error, or None below two values.
    #[getter]
    fn mean(&self) -> Option<(f64, f64)> {
        self.inner.mean().map(|m| (m.value, m.standard_error))
    }

    /// The unbiased sample variance and its standard error, or None.
    #[getter]
    fn variance(&self) -> Option<(f64, f64)> {
        self.inner.variance().map(|m| (m.value, m.standard_error))
    }

    fn __len__(&self) -> usize {
        usize::try_from(self.inner.count()).unwrap_or(usize::MAX)
    }

    fn __repr__(&self) -> String {
        format!("Samples(count={})", self.inner.count())
    }
}
