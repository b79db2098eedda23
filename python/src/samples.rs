//! `Samples`: exact power sums of a renderer's values, from NumPy arrays,
//! iterables or chunks, safe to share between threads.

use crate::errors::{sample_error, SampleError};
use crate::fork::parallel_guard;
use mcrt_noise::Samples as RustSamples;
use numpy::{PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::sync::{Mutex, MutexGuard};

/// The most values one `Samples` holds: counts stay exact as doubles.
pub(crate) const MAX_COUNT: u64 = 1 << 53;
/// Values summed between two looks for Ctrl-C (and per block read from an iterator).
const BLOCK: usize = 1 << 20;
/// Values one thread sums before the parts are merged.
const CHUNK: usize = 1 << 16;

/// Exact power sums Σ Lᵏ (k = 1…6) of a renderer's per-iteration values, the
/// count of nonzero values and the extremes: any order of addition and any
/// merge give the same bits, so values can stream in chunks (10⁸ and more),
/// from several threads at once.
#[pyclass(module = "mcrt_noise", frozen)]
#[derive(Default)]
pub struct Samples {
    inner: Mutex<RustSamples>,
}

impl Samples {
    fn wrap(inner: RustSamples) -> Samples {
        Samples { inner: Mutex::new(inner) }
    }

    /// The sums (a poisoned lock cannot happen: nothing panics while holding it).
    fn lock(&self) -> MutexGuard<'_, RustSamples> {
        self.inner.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// A copy of the sums as they are now, for a check.
    pub(crate) fn snapshot(&self) -> RustSamples {
        self.lock().clone()
    }

    /// Adds `part` (summed without the lock) under the lock, refusing a
    /// count beyond [`MAX_COUNT`].
    fn absorb(&self, part: &RustSamples) -> PyResult<()> {
        let mut sums = self.lock();
        let total = sums.count().saturating_add(part.count());
        if total > MAX_COUNT {
            return Err(SampleError::new_err(format!(
                "count = {total} after adding {} values: at most 2^53 = {MAX_COUNT} values",
                part.count()
            )));
        }
        *sums = std::mem::take(&mut *sums).merge(part);
        Ok(())
    }
}

/// The sums of `values`, the GIL released block by block (Ctrl-C is looked
/// at between blocks), each block split over the threads and merged (exact:
/// the same bits whatever the split). An invalid value fails the whole
/// call; its index counts from `offset`.
fn sums_of(py: Python<'_>, values: &[f64], offset: u64, into: &mut RustSamples) -> PyResult<()> {
    for (b, block) in values.chunks(BLOCK).enumerate() {
        let parts: Vec<Result<RustSamples, mcrt_noise::SampleError>> = py.detach(|| {
            use rayon::prelude::*;
            block
                .par_chunks(CHUNK)
                .map(|chunk| {
                    let mut part = RustSamples::new();
                    part.extend(chunk.iter().copied()).map(|()| part)
                })
                .collect()
        });
        for (i, part) in parts.into_iter().enumerate() {
            let part = part.map_err(|e| sample_error(renumbered(e, offset + (b * BLOCK + i * CHUNK) as u64)))?;
            *into = std::mem::take(into).merge(&part);
        }
        py.check_signals()?;
    }
    Ok(())
}

/// A chunk's error with its index counted within the values of the call.
fn renumbered(e: mcrt_noise::SampleError, offset: u64) -> mcrt_noise::SampleError {
    use mcrt_noise::SampleError as E;
    match e {
        E::NotFinite { index, value } => E::NotFinite { index: index + offset, value },
        E::Negative { index, value } => E::Negative { index: index + offset, value },
        other => other,
    }
}

/// `values` (array-like) as a contiguous 1-D float64 array: real numbers
/// only (float or integer dtypes; not masked, complex, boolean, object or
/// text), one value per iteration.
fn float64_array<'py>(values: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let py = values.py();
    let np = py.import("numpy")?;
    if values.is_instance(&np.getattr("ma")?.getattr("MaskedArray")?)? {
        return Err(SampleError::new_err(
            "values: a masked array: pass values.compressed() (the unmasked values) or fill the masked ones",
        ));
    }
    if let Ok(array) = values.extract::<PyReadonlyArray1<'py, f64>>() {
        if array.is_contiguous() {
            return Ok(array);
        }
    }
    let array =
        np.call_method1("asarray", (values,)).map_err(|e| SampleError::new_err(format!("values: {}", e.value(py))))?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(SampleError::new_err(format!(
            "values: an array of dtype {dtype}: must be real numbers (a float or integer dtype)"
        )));
    }
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        let shape = array.getattr("shape")?;
        return Err(SampleError::new_err(format!(
            "values: an array of shape {shape}: must be one-dimensional (one value per iteration)"
        )));
    }
    let contiguous = np.call_method1("ascontiguousarray", (array, np.getattr("float64")?))?;
    Ok(contiguous.extract()?)
}

/// Sums an iterator's values block by block (never all of them in memory).
fn sums_of_iterator(values: &Bound<'_, PyAny>, into: &mut RustSamples) -> PyResult<()> {
    let py = values.py();
    let not_iterable = |_| {
        SampleError::new_err(format!(
            "values: a {}: must be an array or an iterable of values",
            values.get_type().name().map(|n| n.to_string()).unwrap_or_default()
        ))
    };
    let iterator = values.try_iter().map_err(not_iterable)?;
    let (np, islice) = (py.import("numpy")?, py.import("itertools")?.getattr("islice")?);
    let float64 = np.getattr("float64")?;
    let mut offset = 0u64;
    loop {
        let block = np
            .call_method1("fromiter", (islice.call1((&iterator, BLOCK))?, &float64))
            .map_err(|e| SampleError::new_err(format!("values: {}", e.value(py))))?;
        let block: PyReadonlyArray1<'_, f64> = block.extract()?;
        let slice = block.as_slice().map_err(|e| SampleError::new_err(e.to_string()))?;
        if slice.is_empty() {
            return Ok(());
        }
        sums_of(py, slice, offset, into)?;
        offset += slice.len() as u64;
    }
}

#[pymethods]
impl Samples {
    #[new]
    fn new() -> Samples {
        Samples::default()
    }

    /// Adds one iteration's value L (finite, >= 0).
    fn push(&self, value: f64) -> PyResult<()> {
        let mut one = RustSamples::new();
        one.push(value).map_err(sample_error)?;
        self.absorb(&one)
    }

    /// Adds every value of `values` (a NumPy array, any array-like of real
    /// numbers, or an iterable of floats, read block by block), the GIL
    /// released: all of them, or none if one cannot be a pixel value
    /// (`SampleError` names it, its index counted within `values`).
    /// Threads may extend the same samples at once.
    fn extend(&self, values: &Bound<'_, PyAny>) -> PyResult<()> {
        parallel_guard()?;
        let mut part = RustSamples::new();
        if values.hasattr("__len__")? || values.hasattr("__array__")? {
            let array = float64_array(values)?;
            let slice = array.as_slice().map_err(|e| SampleError::new_err(e.to_string()))?;
            sums_of(values.py(), slice, 0, &mut part)?;
        } else {
            sums_of_iterator(values, &mut part)?;
        }
        self.absorb(&part)
    }

    /// These samples and `other`'s together (exact).
    fn merge(&self, other: &Samples) -> PyResult<Samples> {
        let merged = Samples::wrap(self.snapshot());
        merged.absorb(&other.snapshot())?;
        Ok(merged)
    }

    /// Power sums made elsewhere: `count` values (1 to 2^53), Σ Lᵏ for
    /// k = 1…6 and a bound on their relative error (0 if exact).
    #[staticmethod]
    #[pyo3(signature = (count, sums, sums_relative_error = 0.0))]
    fn from_power_sums(count: i128, sums: [f64; 6], sums_relative_error: f64) -> PyResult<Samples> {
        let count = u64::try_from(count)
            .ok()
            .filter(|c| (1..=MAX_COUNT).contains(c))
            .ok_or_else(|| SampleError::new_err(format!("count = {count}: must be in [1, 2^53 = {MAX_COUNT}]")))?;
        RustSamples::from_power_sums(count, sums, sums_relative_error).map(Samples::wrap).map_err(sample_error)
    }

    /// How many values.
    #[getter]
    fn count(&self) -> u64 {
        self.lock().count()
    }

    /// How many are nonzero (None for power sums made elsewhere).
    #[getter]
    fn nonzero(&self) -> Option<u64> {
        self.lock().nonzero()
    }

    /// The sample mean and its standard error, or None below 4 values.
    #[getter]
    fn mean(&self) -> Option<(f64, f64)> {
        self.lock().mean().map(|m| (m.value, m.standard_error))
    }

    /// The unbiased sample variance and its standard error, or None below 4 values.
    #[getter]
    fn variance(&self) -> Option<(f64, f64)> {
        self.lock().variance().map(|m| (m.value, m.standard_error))
    }

    fn __len__(&self) -> usize {
        usize::try_from(self.count()).unwrap_or(usize::MAX)
    }

    fn __repr__(&self) -> String {
        format!("Samples(count={})", self.count())
    }
}
