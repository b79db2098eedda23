//! The C API of `mcrt-noise`: predict one pixel's mean and noise, and check a
//! renderer's per-iteration values against the prediction, from C or C++.
//!
//! A thin layer over the library (`mcrt_noise::{predict, check}`), mirroring
//! the Python package: opaque handles (`McrtScene`, `McrtPrediction`,
//! `McrtSamples`, `McrtVerdict`) made by the calls below and released by
//! their `_free` functions; every fallible call returns an [`McrtStatus`]
//! and, on failure, leaves the library's message (the CLI's, naming the
//! field, value and allowed range) for [`mcrt_last_error`] on the calling
//! thread. Nothing panics across the boundary: a panic is caught and
//! reported as [`McrtStatus::Panic`]. The header `include/mcrt_noise.h` is
//! generated from this file by cbindgen and checked by `tests/header.rs`;
//! `tests/check.c` is the C test CI compiles and runs
//! (`scripts/check-c-api`).

#![allow(clippy::missing_safety_doc)] // every function's "Safety" is in its docs, as C users read them

use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use mcrt_noise::check::Status;
use mcrt_noise::{check, predict, CheckOptions, Prediction, Samples, Scene, Verdict};

/// What a call did: `MCRT_STATUS_OK`, or why it failed (`mcrt_last_error()` has the message).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum McrtStatus {
    /// Done.
    Ok = 0,
    /// A null pointer, or text that is not UTF-8.
    InvalidArgument = 1,
    /// The scene is invalid (every invalid value named) or unreadable.
    InvalidScene = 2,
    /// The oracle cannot predict this scene (not covered, not converged
    /// within its budget, or beyond f64).
    PredictFailed = 3,
    /// A value that cannot be a pixel value (negative, not finite).
    InvalidSample = 4,
    /// A check option out of its range.
    InvalidOption = 5,
    /// A bug in mcrt-noise: a panic, caught at the boundary.
    Panic = 6,
}

/// The verdict of a check.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum McrtVerdictStatus {
    /// Every quantity resolved, within its limit, and able to detect its target.
    Pass = 0,
    /// Evidence of a bug: a quantity beyond its limit, or a value larger
    /// than any correct renderer produces.
    Fail = 1,
    /// The samples cannot tell; the verdict's text says what would.
    NotResolved = 2,
}

/// A predicted quantity: its value and two bounds on its error (the
/// quadrature's and the model's; the model bar is 0 where the model is
/// exact at the scene's R).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McrtPredicted {
    /// The predicted value.
    pub value: f64,
    /// Bound on the quadrature's error.
    pub quadrature_bar: f64,
    /// Bound on the model's own error.
    pub model_bar: f64,
}

/// The check's options (`mcrt_check_options_default` gives the library's:
/// false-alarm rate 1e-3, power 0.9, targets 0.1 and 0.2).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McrtCheckOptions {
    /// Family-wise false-alarm rate, in [1e-300, 0.5].
    pub false_alarm_rate: f64,
    /// Probability of detecting the targets, in [0.5, 1).
    pub power: f64,
    /// Relative error of the mean a pass must be able to detect (finite, > 0).
    pub target_mean: f64,
    /// Relative error of Var L a pass must be able to detect (finite, > 0).
    pub target_variance: f64,
}

/// A validated scene.
pub struct McrtScene(Scene);
/// A prediction: mean and Var L of one iteration, with their bars.
pub struct McrtPrediction(Prediction);
/// Exact power sums of a renderer's per-iteration values.
pub struct McrtSamples(Samples);
/// A verdict, with its text and JSON.
pub struct McrtVerdict {
    verdict: Verdict,
    text: CString,
    json: CString,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Keeps `message` for `mcrt_last_error` (not during the thread's exit,
/// when its storage is gone: then the message is dropped, never a panic).
fn set_error(message: &str) {
    let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
    let _ = LAST_ERROR.try_with(|e| *e.borrow_mut() = message);
}

/// Runs `body`, turning an error into its status (the message kept for
/// `mcrt_last_error`) and a panic into `McrtStatus::Panic`.
fn guarded(body: impl FnOnce() -> Result<(), (McrtStatus, String)>) -> McrtStatus {
    let outcome = catch_unwind(AssertUnwindSafe(|| match body() {
        Ok(()) => McrtStatus::Ok,
        Err((status, message)) => {
            set_error(&message);
            status
        }
    }));
    outcome.unwrap_or_else(|_| {
        let _ = catch_unwind(|| set_error(PANIC_MESSAGE));
        McrtStatus::Panic
    })
}

const PANIC_MESSAGE: &str = "a panic inside mcrt-noise (a bug: please report it with the scene and the values)";

/// `message` for a null handle given to an accessor, which then returns
/// its neutral value (NaN, 0 or an empty string).
fn null_handle(name: &str) {
    set_error(&format!("{name}: a null pointer"));
}

unsafe fn text_arg<'a>(text: *const c_char, name: &str) -> Result<&'a str, (McrtStatus, String)> {
    if text.is_null() {
        return Err((
            McrtStatus::InvalidArgument,
            format!("{name}: a null pointer: must be a NUL-terminated UTF-8 string"),
        ));
    }
    CStr::from_ptr(text).to_str().map_err(|e| (McrtStatus::InvalidArgument, format!("{name}: not UTF-8 ({e})")))
}

unsafe fn handle<'a, T>(ptr: *const T, name: &str) -> Result<&'a T, (McrtStatus, String)> {
    ptr.as_ref().ok_or_else(|| (McrtStatus::InvalidArgument, format!("{name}: a null pointer")))
}

/// Sets `*out` to null (where `out` is not null) before a call's work, so
/// that a failed call leaves null there, never an old pointer.
unsafe fn clear<T>(out: *mut *mut T) {
    if !out.is_null() {
        *out = std::ptr::null_mut();
    }
}

unsafe fn put<T>(out: *mut *mut T, value: T, name: &str) -> Result<(), (McrtStatus, String)> {
    if out.is_null() {
        return Err((McrtStatus::InvalidArgument, format!("{name}: a null pointer")));
    }
    *out = Box::into_raw(Box::new(value));
    Ok(())
}

/// The most values one `McrtSamples` holds: counts stay exact as doubles.
const MAX_COUNT: u64 = 1 << 53;

fn within_count(have: u64, adding: u64) -> Result<(), (McrtStatus, String)> {
    match have.checked_add(adding) {
        Some(total) if total <= MAX_COUNT => Ok(()),
        _ => Err((
            McrtStatus::InvalidArgument,
            format!("count = {have} + {adding}: at most 2^53 = {MAX_COUNT} values in one McrtSamples"),
        )),
    }
}

#[cfg(unix)]
fn path_from_bytes(bytes: &[u8]) -> std::path::PathBuf {
    use std::os::unix::ffi::OsStrExt;
    std::path::PathBuf::from(std::ffi::OsStr::from_bytes(bytes))
}

#[cfg(not(unix))]
fn path_from_bytes(bytes: &[u8]) -> std::path::PathBuf {
    std::path::PathBuf::from(String::from_utf8_lossy(bytes).into_owned())
}

/// The message of the last failed call on this thread (empty if none):
/// owned by the library, valid until the next failing call on this thread.
#[no_mangle]
pub extern "C" fn mcrt_last_error() -> *const c_char {
    LAST_ERROR.try_with(|e| e.borrow().as_ptr()).unwrap_or(c"".as_ptr())
}

/// Validates a scene given as TOML text (`docs/scene-format.md`) and stores
/// it in `*out` (release it with `mcrt_scene_free`).
///
/// # Safety
/// `text` is a NUL-terminated string; `out` points to writable storage.
#[no_mangle]
pub unsafe extern "C" fn mcrt_scene_from_toml(text: *const c_char, out: *mut *mut McrtScene) -> McrtStatus {
    clear(out);
    guarded(|| {
        let text = text_arg(text, "text")?;
        let scene = Scene::from_toml_str(text).map_err(|e| (McrtStatus::InvalidScene, e.to_string()))?;
        put(out, McrtScene(scene), "out")
    })
}

/// Reads and validates a scene file (at most 1 MiB; the path in the
/// file system's bytes) and stores it in `*out`.
///
/// # Safety
/// `path` is a NUL-terminated string; `out` points to writable storage.
#[no_mangle]
pub unsafe extern "C" fn mcrt_scene_from_file(path: *const c_char, out: *mut *mut McrtScene) -> McrtStatus {
    clear(out);
    guarded(|| {
        if path.is_null() {
            return Err((McrtStatus::InvalidArgument, "path: a null pointer: must be a NUL-terminated string".into()));
        }
        let path = path_from_bytes(CStr::from_ptr(path).to_bytes());
        let text = mcrt_noise::scene::limits::read_scene_text(&path).map_err(|e| (McrtStatus::InvalidScene, e))?;
        let path = path.display();
        let scene = Scene::from_toml_str(&text).map_err(|e| (McrtStatus::InvalidScene, format!("{path}: {e}")))?;
        put(out, McrtScene(scene), "out")
    })
}

/// Releases a scene (null: nothing).
///
/// # Safety
/// `scene` was made by this library and is not used after.
#[no_mangle]
pub unsafe extern "C" fn mcrt_scene_free(scene: *mut McrtScene) {
    if !scene.is_null() {
        drop(Box::from_raw(scene));
    }
}

/// Predicts one iteration's mean and Var L (`docs/library.md`: milliseconds
/// for uncollided light, seconds to minutes with scattered light) and
/// stores the prediction in `*out` (release it with `mcrt_prediction_free`).
///
/// # Safety
/// `scene` is a live scene; `out` points to writable storage.
#[no_mangle]
pub unsafe extern "C" fn mcrt_predict(scene: *const McrtScene, out: *mut *mut McrtPrediction) -> McrtStatus {
    clear(out);
    guarded(|| {
        let scene = handle(scene, "scene")?;
        let prediction = predict(&scene.0).map_err(|e| match e {
            mcrt_noise::PredictError::Scene(e) => (McrtStatus::InvalidScene, e.to_string()),
            other => (McrtStatus::PredictFailed, other.to_string()),
        })?;
        put(out, McrtPrediction(prediction), "out")
    })
}

fn predicted(p: mcrt_noise::Predicted) -> McrtPredicted {
    McrtPredicted { value: p.value, quadrature_bar: p.quadrature_bar, model_bar: p.model_bar }
}

/// The predicted mean ⟨⟨L⟩⟩ of one iteration, with its bars (NaN in
/// every field for a null `prediction`, with a message).
///
/// # Safety
/// `prediction` is a live prediction or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_prediction_mean(prediction: *const McrtPrediction) -> McrtPredicted {
    prediction_part(prediction, |p| p.mean)
}

unsafe fn prediction_part(
    prediction: *const McrtPrediction,
    part: impl Fn(&Prediction) -> mcrt_noise::Predicted,
) -> McrtPredicted {
    match prediction.as_ref() {
        Some(p) => predicted(part(&p.0)),
        None => {
            null_handle("prediction");
            McrtPredicted { value: f64::NAN, quadrature_bar: f64::NAN, model_bar: f64::NAN }
        }
    }
}

/// The predicted Var L of one iteration, with its bars (NaN for a null
/// `prediction`, with a message).
///
/// # Safety
/// `prediction` is a live prediction or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_prediction_variance(prediction: *const McrtPrediction) -> McrtPredicted {
    prediction_part(prediction, |p| p.variance)
}

/// Releases a prediction (null: nothing).
///
/// # Safety
/// `prediction` was made by this library and is not used after.
#[no_mangle]
pub unsafe extern "C" fn mcrt_prediction_free(prediction: *mut McrtPrediction) {
    if !prediction.is_null() {
        drop(Box::from_raw(prediction));
    }
}

/// New, empty samples (release them with `mcrt_samples_free`).
#[no_mangle]
pub extern "C" fn mcrt_samples_new() -> *mut McrtSamples {
    Box::into_raw(Box::new(McrtSamples(Samples::new())))
}

/// Adds `count` values (finite, >= 0): exact power sums, so any order and
/// any merge give the same bits. On `MCRT_STATUS_INVALID_SAMPLE` the values before
/// the offending one (counted from the first value ever added) are added.
///
/// # Safety
/// `samples` is live; `values` points to `count` doubles (or is null with
/// `count` 0).
#[no_mangle]
pub unsafe extern "C" fn mcrt_samples_extend(
    samples: *mut McrtSamples,
    values: *const f64,
    count: usize,
) -> McrtStatus {
    guarded(|| {
        let samples = samples.as_mut().ok_or((McrtStatus::InvalidArgument, "samples: a null pointer".to_string()))?;
        if count == 0 {
            return Ok(());
        }
        if values.is_null() {
            return Err((McrtStatus::InvalidArgument, format!("values: a null pointer with count = {count}")));
        }
        within_count(samples.0.count(), count as u64)?;
        let values = std::slice::from_raw_parts(values, count);
        samples.0.extend(values.iter().copied()).map_err(|e| (McrtStatus::InvalidSample, e.to_string()))
    })
}

/// Adds `other`'s values to `into` (exact).
///
/// # Safety
/// Both are live samples.
#[no_mangle]
pub unsafe extern "C" fn mcrt_samples_merge(into: *mut McrtSamples, other: *const McrtSamples) -> McrtStatus {
    guarded(|| {
        if into.is_null() {
            return Err((McrtStatus::InvalidArgument, "into: a null pointer".to_string()));
        }
        // `other` may be `into` itself: copy it before `into` is borrowed mutably.
        let other = handle(other, "other")?.0.clone();
        let into = &mut *into;
        within_count(into.0.count(), other.count())?;
        into.0 = std::mem::take(&mut into.0).merge(&other);
        Ok(())
    })
}

/// How many values the samples hold (0 for null, with a message).
///
/// # Safety
/// `samples` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_samples_count(samples: *const McrtSamples) -> u64 {
    samples.as_ref().map_or_else(
        || {
            null_handle("samples");
            0
        },
        |s| s.0.count(),
    )
}

/// Releases samples (null: nothing).
///
/// # Safety
/// `samples` was made by this library and is not used after.
#[no_mangle]
pub unsafe extern "C" fn mcrt_samples_free(samples: *mut McrtSamples) {
    if !samples.is_null() {
        drop(Box::from_raw(samples));
    }
}

/// The library's default check options.
#[no_mangle]
pub extern "C" fn mcrt_check_options_default() -> McrtCheckOptions {
    let d = CheckOptions::default();
    let (target_mean, target_variance) = d.targets();
    McrtCheckOptions { false_alarm_rate: d.false_alarm_rate(), power: d.power(), target_mean, target_variance }
}

fn options(o: &McrtCheckOptions) -> Result<CheckOptions, (McrtStatus, String)> {
    let invalid = |e: mcrt_noise::scene::FieldError| (McrtStatus::InvalidOption, e.to_string());
    CheckOptions::new(o.false_alarm_rate)
        .map_err(invalid)?
        .with_power(o.power)
        .map_err(invalid)?
        .with_targets(o.target_mean, o.target_variance)
        .map_err(invalid)
}

/// Checks `samples` against `prediction` (`options` null: the defaults)
/// and stores the verdict in `*out` (release it with `mcrt_verdict_free`).
///
/// # Safety
/// `prediction` and `samples` are live; `options` is null or points to
/// options; `out` points to writable storage.
#[no_mangle]
pub unsafe extern "C" fn mcrt_check(
    prediction: *const McrtPrediction,
    samples: *const McrtSamples,
    options_or_null: *const McrtCheckOptions,
    out: *mut *mut McrtVerdict,
) -> McrtStatus {
    clear(out);
    guarded(|| {
        let prediction = handle(prediction, "prediction")?;
        let samples = handle(samples, "samples")?;
        let opts = match options_or_null.as_ref() {
            Some(o) => options(o)?,
            None => CheckOptions::default(),
        };
        let verdict = check(&prediction.0, &samples.0, &opts);
        let text = CString::new(verdict.to_string().replace('\0', " ")).unwrap_or_default();
        let json = serde_json::to_string_pretty(&verdict).map_err(|e| (McrtStatus::Panic, e.to_string()))?;
        let json = CString::new(json).unwrap_or_default();
        put(out, McrtVerdict { verdict, text, json }, "out")
    })
}

/// The verdict behind `verdict`, or None (with a message) for null.
unsafe fn verdict_of<'a>(verdict: *const McrtVerdict) -> Option<&'a McrtVerdict> {
    let v = verdict.as_ref();
    if v.is_none() {
        null_handle("verdict");
    }
    v
}

/// PASS, FAIL or NOT RESOLVED (NOT RESOLVED for null, with a message).
///
/// # Safety
/// `verdict` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_status(verdict: *const McrtVerdict) -> McrtVerdictStatus {
    match verdict_of(verdict).map(|v| v.verdict.status) {
        Some(Status::Pass) => McrtVerdictStatus::Pass,
        Some(Status::Fail) => McrtVerdictStatus::Fail,
        Some(Status::NotResolved) | None => McrtVerdictStatus::NotResolved,
    }
}

/// 1 if the check passed, else 0 (0 for null, with a message).
///
/// # Safety
/// `verdict` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_passed(verdict: *const McrtVerdict) -> c_int {
    c_int::from(verdict_of(verdict).is_some_and(|v| v.verdict.pass))
}

unsafe fn quantity_z(verdict: *const McrtVerdict, name: &str, out: *mut f64) -> c_int {
    let z = verdict_of(verdict).and_then(|v| v.verdict.checks.iter().find(|c| c.name == name)?.z);
    match (z, out.is_null()) {
        (Some(z), false) => {
            *out = z;
            1
        }
        _ => 0,
    }
}

/// The mean's z-score in `*z`: returns 1, or 0 where the samples give none
/// (too few values, no spread; or a null argument).
///
/// # Safety
/// `verdict` is live or null; `z` points to a double or is null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_z_mean(verdict: *const McrtVerdict, z: *mut f64) -> c_int {
    quantity_z(verdict, "mean L", z)
}

/// Var L's z-score in `*z`: returns 1, or 0 where the samples give none.
///
/// # Safety
/// `verdict` is live or null; `z` points to a double or is null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_z_variance(verdict: *const McrtVerdict, z: *mut f64) -> c_int {
    quantity_z(verdict, "Var L", z)
}

/// The |z| limit of both z-tests (NaN for null, with a message).
///
/// # Safety
/// `verdict` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_z_limit(verdict: *const McrtVerdict) -> f64 {
    verdict_of(verdict).map_or(f64::NAN, |v| v.verdict.z_limit)
}

/// The whole verdict as the CLI prints it (UTF-8, owned by the verdict;
/// "" for null, with a message).
///
/// # Safety
/// `verdict` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_text(verdict: *const McrtVerdict) -> *const c_char {
    verdict_of(verdict).map_or(c"".as_ptr(), |v| v.text.as_ptr())
}

/// The whole verdict as the CLI's `check --json` prints it (owned by the
/// verdict; "" for null, with a message).
///
/// # Safety
/// `verdict` is live or null.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_json(verdict: *const McrtVerdict) -> *const c_char {
    verdict_of(verdict).map_or(c"".as_ptr(), |v| v.json.as_ptr())
}

/// Releases a verdict (null: nothing).
///
/// # Safety
/// `verdict` was made by this library and is not used after.
#[no_mangle]
pub unsafe extern "C" fn mcrt_verdict_free(verdict: *mut McrtVerdict) {
    if !verdict.is_null() {
        drop(Box::from_raw(verdict));
    }
}

/// The reference tracer's values of iterations `start .. start + count` of
/// stream `seed`, written to `out`: what a correct renderer gives, for tests
/// and examples (bit-identical at any thread count).
///
/// # Safety
/// `scene` is live; `out` points to `count` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn mcrt_reference_values(
    scene: *const McrtScene,
    seed: u64,
    start: u64,
    count: usize,
    out: *mut f64,
) -> McrtStatus {
    use mcrt_noise::reference::{HitMethod, Tracer};
    use rayon::prelude::*;
    guarded(|| {
        let scene = handle(scene, "scene")?;
        if count == 0 {
            return Ok(());
        }
        if out.is_null() {
            return Err((McrtStatus::InvalidArgument, format!("out: a null pointer with count = {count}")));
        }
        if u64::try_from(count).ok().and_then(|n| start.checked_add(n)).is_none() {
            return Err((
                McrtStatus::InvalidArgument,
                format!("start = {start}, count = {count}: start + count must be below 2^64"),
            ));
        }
        let tracer = Tracer::new(&scene.0).map_err(|e| (McrtStatus::InvalidScene, e.to_string()))?;
        let out = std::slice::from_raw_parts_mut(out, count);
        out.par_iter_mut()
            .enumerate()
            .for_each(|(k, value)| *value = tracer.trial(seed, start + k as u64, HitMethod::Sorted).0);
        Ok(())
    })
}
