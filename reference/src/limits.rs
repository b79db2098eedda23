//! What the tracer refuses, and why: every bound of the tracer, in one
//! place. A scene that passes `mcrt-scene`'s validation may still ask for
//! more than one process can do (a renderer may also build a `Scene` in
//! code); [`Tracer::new`](crate::Tracer::new) checks these before any trial
//! runs, and `trace`'s callers check a run with [`check_run`].
//!
//! - **Lengths.** The hit test squares lengths (R², |B + sA|²) and the walk
//!   adds free paths −ln(U)/σ_ext ≤ 38/σ_ext for up to 10⁶ orders, in
//!   doubles. Every coordinate, the beams' radii, R and the mean free path
//!   1/σ_ext must be at most [`MAX_LENGTH`] = 2⁴⁰⁰ (sums of 10⁶ paths stay
//!   below 2⁴²⁶, their squares below 2⁸⁵², finite), and R at least
//!   [`MIN_RADIUS`] = 2⁻⁵⁰⁰ (R² ≥ 2⁻¹⁰⁰⁰, a normal double). Beyond these
//!   the paths or the hit test would be inf/NaN or 0: the scene is refused,
//!   the field named.
//! - **Memory of one trial.** The spheres of one trial are held in a list
//!   of doubles: N_B camera rays, each a geometric number of sub-steps of
//!   mean 1/q. The expected count N_B/q must be at most
//!   [`MAX_SPHERES_PER_TRIAL`] = 2²⁰ (8 MiB). The list reaches 1 GiB
//!   (2²⁶ spheres with the vector's doubling) only at 64 times its mean,
//!   with probability below e⁻⁶⁴ ≈ 10⁻²⁸ per trial: the memory of a run is
//!   bounded by about 1 GiB per thread. Forward rays are walked one at a
//!   time and never stored.
//! - **Work of one trial.** The expected number of forward segments,
//!   N_F · Σ_{k=0}^{K} albedoᵏ (K the scattering-order limit), must be at
//!   most [`MAX_SEGMENTS_PER_TRIAL`] = 2²⁴ (about a second of one core):
//!   beyond, a single trial would run for minutes to years with no progress
//!   to show.
//! - **Work of one run.** Trials × (rays + segments + spheres per trial),
//!   expected, must be at most [`MAX_RUN_WORK`] = 2⁶⁰: every counter and
//!   draw tally (at most 4 draws per unit) then fits a u64, and so does the
//!   merge of shards of one run (checked when merging).
//!
//! L itself never overflows: it is computed as L/2^E with E from the scene
//! (`Tracer::scale_exponent`), and its power sums are exact at any E.

use mcrt_scene::{Light, ScatteringOrders, Scene};

/// Largest coordinate, beam radius, sphere radius or mean free path 1/σ_ext (2⁴⁰⁰ ≈ 2.6·10¹²⁰).
pub const MAX_LENGTH: f64 = 2.5822498780869086e120;
/// Smallest sphere radius R (2⁻⁵⁰⁰ ≈ 3.1·10⁻¹⁵¹): R² is then a normal double.
pub const MIN_RADIUS: f64 = 3.054936363499605e-151;
/// Largest expected number of integration spheres of one trial, N_B/q (2²⁰).
pub const MAX_SPHERES_PER_TRIAL: f64 = 1048576.0;
/// Largest expected number of forward segments of one trial (2²⁴).
pub const MAX_SEGMENTS_PER_TRIAL: f64 = 16777216.0;
/// Largest expected work of one run, trials × (rays + segments + spheres) (2⁶⁰).
pub const MAX_RUN_WORK: f64 = 1152921504606846976.0;

/// Expected work of one trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Work {
    /// Integration spheres placed, N_B/q.
    pub spheres: f64,
    /// Forward rays, N_F.
    pub rays: f64,
    /// Forward segments, N_F times the expected segments of one ray.
    pub segments: f64,
}

impl Work {
    /// The expected work of one trial of `scene` (no bound checked).
    pub fn of(scene: &Scene) -> Work {
        let est = &scene.estimator;
        let a = scene.medium.albedo;
        // Segments of one ray: 1 + the scatterings, each with probability albedo, at most K.
        let per_ray = match scene.effects.scattering_orders {
            ScatteringOrders::Limited(k) if a >= 1.0 => f64::from(k) + 1.0,
            ScatteringOrders::Limited(k) => -((f64::from(k) + 1.0) * (a - 1.0).ln_1p()).exp_m1() / (1.0 - a),
            ScatteringOrders::All if a >= 1.0 => f64::INFINITY,
            ScatteringOrders::All => 1.0 / (1.0 - a),
        };
        let rays = est.forward_rays as f64;
        Work { spheres: est.camera_rays as f64 / est.q, rays, segments: rays * per_ray }
    }

    /// Rays + segments + spheres: the unit of [`MAX_RUN_WORK`].
    pub fn total(&self) -> f64 {
        self.spheres + self.rays + self.segments
    }
}

/// x ≤ bound (false for NaN).
fn at_most(x: f64, bound: f64) -> bool {
    x <= bound
}

/// `2^k` written for the messages.
fn pow2(x: f64) -> String {
    format!("2^{} = {x:.3e}", x.log2().round())
}

/// The tracer's own bounds on a validated scene: `Err` names the field,
/// its value and the bound.
pub fn check_scene(scene: &Scene) -> Result<Work, String> {
    let too_long = |field: String, v: f64| {
        (!at_most(v.abs(), MAX_LENGTH)).then(|| {
            format!(
                "{field} = {v:e}: the tracer needs lengths of at most {} (its hit test squares them)",
                pow2(MAX_LENGTH)
            )
        })
    };
    let mut lengths: Vec<(String, f64)> = Vec::new();
    for (i, c) in scene.camera.origin.to_array().iter().enumerate() {
        lengths.push((format!("camera.origin[{i}]"), *c));
    }
    for (j, light) in scene.lights.iter().enumerate() {
        let (name, point, radius) = match *light {
            Light::Point { position, .. } => ("position", position, None),
            Light::Beam { center, radius, .. } => ("center", center, Some(radius)),
        };
        for (i, c) in point.to_array().iter().enumerate() {
            lengths.push((format!("lights[{j}].{name}[{i}]"), *c));
        }
        if let Some(r) = radius {
            lengths.push((format!("lights[{j}].radius"), r));
        }
    }
    lengths.push(("estimator.radius".into(), scene.estimator.radius));
    if let Some(msg) = lengths.into_iter().find_map(|(f, v)| too_long(f, v)) {
        return Err(msg);
    }
    let sigma = scene.medium.sigma_ext;
    if !at_most(1.0 / sigma, MAX_LENGTH) {
        return Err(format!(
            "medium.sigma_ext = {sigma:e}: the mean free path 1/sigma_ext must be at most {} (sigma_ext >= {:.3e}); \
             free paths would overflow",
            pow2(MAX_LENGTH),
            1.0 / MAX_LENGTH
        ));
    }
    let r = scene.estimator.radius;
    if !at_most(MIN_RADIUS, r) {
        return Err(format!(
            "estimator.radius = {r:e}: must be at least {} for the tracer (its hit test needs R² as a normal double)",
            pow2(MIN_RADIUS)
        ));
    }
    let work = Work::of(scene);
    let est = &scene.estimator;
    if !at_most(work.spheres, MAX_SPHERES_PER_TRIAL) {
        return Err(format!(
            "estimator.camera_rays / estimator.q = {} / {:e}: one trial places {:.3e} integration spheres on average; \
             at most {} are allowed (8 bytes each: the memory of one trial stays below 1 GiB); raise q or lower \
             camera_rays",
            est.camera_rays,
            est.q,
            work.spheres,
            pow2(MAX_SPHERES_PER_TRIAL)
        ));
    }
    if !at_most(work.segments, MAX_SEGMENTS_PER_TRIAL) {
        let orders = match scene.effects.scattering_orders {
            ScatteringOrders::Limited(k) => k.to_string(),
            ScatteringOrders::All => "\"all\"".into(),
        };
        let fields = if work.segments > work.rays {
            format!(
                "estimator.forward_rays = {}, effects.scattering_orders = {orders}, medium.albedo = {}",
                est.forward_rays, scene.medium.albedo
            )
        } else {
            format!("estimator.forward_rays = {}", est.forward_rays)
        };
        return Err(format!(
            "{fields}: one trial traces {:.3e} forward segments on average; at most {} are allowed per trial \
             (about a second of one core)",
            work.segments,
            pow2(MAX_SEGMENTS_PER_TRIAL)
        ));
    }
    Ok(work)
}

/// The bound on a run of `trials` trials of a scene whose trial does `work`.
pub fn check_run(work: &Work, trials: u64) -> Result<(), String> {
    let total = trials as f64 * work.total();
    if total <= MAX_RUN_WORK {
        return Ok(());
    }
    let most = (MAX_RUN_WORK / work.total()).floor();
    Err(format!(
        "--trials: {trials} trials of this scene are {total:.3e} units of work (rays + segments + spheres); at most \
         {} per run are allowed (the counters are u64), i.e. at most {most:.0} trials per run or shard",
        pow2(MAX_RUN_WORK)
    ))
}

/// x = m·2^e with m in [1, 2) for finite x > 0 (normal or subnormal); (0, 0) for 0.
pub fn split(x: f64) -> (f64, i32) {
    if x == 0.0 {
        return (0.0, 0);
    }
    let (y, bias) = if x.abs() < f64::MIN_POSITIVE { (x * 2f64.powi(64), -64) } else { (x, 0) };
    let bits = y.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32 - 1023;
    (f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52)), e + bias)
}

/// x·2ⁿ, exact whenever the result is a normal double (the steps move
/// monotonically towards it, so no intermediate is subnormal).
pub fn ldexp(mut x: f64, mut n: i32) -> f64 {
    while n > 1000 {
        x *= 2f64.powi(1000);
        n -= 1000;
    }
    while n < -1000 {
        x *= 2f64.powi(-1000);
        n += 1000;
    }
    x * 2f64.powi(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_are_the_stated_powers_of_two() {
        assert_eq!(MAX_LENGTH, ldexp(1.0, 400));
        assert_eq!(MIN_RADIUS, ldexp(1.0, -500));
        assert_eq!(MAX_SPHERES_PER_TRIAL, ldexp(1.0, 20));
        assert_eq!(MAX_SEGMENTS_PER_TRIAL, ldexp(1.0, 24));
        assert_eq!(MAX_RUN_WORK, ldexp(1.0, 60));
    }

    #[test]
    fn split_and_ldexp_are_exact() {
        for x in [1.0, 0.75, 3.0e300, 1e-300, 5e-324, f64::MAX, f64::MIN_POSITIVE] {
            let (m, e) = split(x);
            assert!((1.0..2.0).contains(&m), "{x:e}");
            assert_eq!(ldexp(m, e), x, "{x:e}");
        }
        assert_eq!(ldexp(1.5, 2000), f64::INFINITY);
        assert_eq!(ldexp(ldexp(1.5, 900), -1900), ldexp(1.5, -1000));
    }
}
