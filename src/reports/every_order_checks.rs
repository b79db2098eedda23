//! The reference tracer against the exact Var L of every scattering order
//! (`docs/model.md` §10.3: orders up to n ≥ 2 and `"all"` at q = 1, N_B =
//! 1, point lights in an isotropic medium), with no allowance: the points, their rows and their
//! table, shared by `tests/every_order_variance.rs` (which asserts on them)
//! and `mcrt-noise tracer-checks` (which prints them).

use crate::oracle::{every_order_mean, ValueWithBar};
use crate::quad::Budget;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light, ScatteringOrders, Scene};
use std::fmt::Write;

/// The oracle's goal at these points: its bars are then below a tenth of
/// the tracer's.
pub const GOAL: f64 = 1e-4;

/// One point: the orders, albedo, R, N_F, the lights' positions (flux 1
/// each), trials, seed, and whether the tracer must reject Var L without
/// the same-path pairs there.
#[derive(Debug, Clone, Copy)]
pub struct EveryOrderPoint {
    /// `effects.scattering_orders`.
    pub orders: ScatteringOrders,
    /// The medium's albedo.
    pub albedo: f64,
    /// The sphere radius R.
    pub radius: f64,
    /// N_F.
    pub forward: u64,
    /// The point lights' positions (flux 1 each).
    pub lights: &'static [[f64; 3]],
    /// The tracer's trials.
    pub trials: u64,
    /// The tracer's seed.
    pub seed: u64,
    /// Whether Var L without the same-path pairs must be rejected (z > 6).
    pub rejects_without_pairs: bool,
}

const README: &[[f64; 3]] = &[[1.0, 0.0, 1.0]];

#[allow(clippy::too_many_arguments)]
const fn point(
    orders: ScatteringOrders,
    albedo: f64,
    radius: f64,
    forward: u64,
    lights: &'static [[f64; 3]],
    trials: u64,
    seed: u64,
    rejects: bool,
) -> EveryOrderPoint {
    EveryOrderPoint { orders, albedo, radius, forward, lights, trials, seed, rejects_without_pairs: rejects }
}

const ALL: ScatteringOrders = ScatteringOrders::All;

/// Thirteen points: ten of every order (`"all"`) — albedo 0.5 to 0.95, R
/// 0.05 to 0.5, N_F 1 to 200, one and two lights, a light 0.1 from the
/// camera line and one 3.6 free paths away — and three of finite orders 2
/// and 5, whose pairs count the segments left after each; where one path's
/// revisits of a sphere matter (N_F 1 and 2) Var L without the same-path
/// pairs must be rejected.
pub const EVERY_ORDER_POINTS: [EveryOrderPoint; 13] = [
    point(ALL, 0.8, 0.2, 20, README, 1_000_000, 61, false),
    point(ALL, 0.8, 0.2, 1, README, 1_000_000, 62, true),
    point(ALL, 0.95, 0.3, 2, README, 600_000, 63, true),
    point(ALL, 0.5, 0.2, 5, README, 600_000, 64, false),
    point(ALL, 0.8, 0.05, 200, README, 200_000, 65, false),
    point(ALL, 0.8, 0.5, 20, README, 400_000, 66, false),
    point(ALL, 0.8, 0.1, 10, &[[1.0, 0.0, 1.0], [-0.5, 0.4, 2.0]], 400_000, 67, false),
    point(ALL, 0.5, 0.05, 20, &[[0.1, 0.0, 1.0]], 400_000, 68, false),
    point(ALL, 0.9, 0.5, 20, &[[3.0, 0.0, 2.0]], 900_000, 69, false),
    point(ALL, 0.95, 0.2, 1, &[[0.5, 0.0, 0.5]], 600_000, 70, true),
    point(ScatteringOrders::Limited(2), 0.8, 0.2, 1, README, 2_000_000, 71, true),
    point(ScatteringOrders::Limited(5), 0.95, 0.3, 2, README, 600_000, 72, true),
    point(ScatteringOrders::Limited(5), 0.5, 0.05, 200, &[[1.0, 0.0, 1.0], [-0.5, 0.4, 2.0]], 200_000, 73, false),
];

impl EveryOrderPoint {
    /// `readme` (the README scene, `point-isotropic`: σ = 1, camera at the
    /// origin along z) with q = 1, N_B = 1 and this point's orders and
    /// values.
    pub fn scene(&self, readme: &Scene) -> Scene {
        let mut s = readme.clone();
        s.effects.scattering_orders = self.orders;
        s.medium.albedo = self.albedo;
        s.estimator.radius = self.radius;
        s.estimator.q = 1.0;
        s.estimator.camera_rays = 1;
        s.estimator.forward_rays = self.forward;
        s.lights =
            self.lights.iter().map(|&[x, y, z]| Light::Point { position: DVec3::new(x, y, z), flux: 1.0 }).collect();
        s
    }
}

/// One point's outcome: the exact Var L and its same-path pairs' share, the
/// tracer's Var L, and the z of the tracer against Var L with and without
/// the pairs.
#[derive(Debug, Clone, Copy)]
pub struct EveryOrderRow {
    /// The point.
    pub point: EveryOrderPoint,
    /// Var L, exact at R (the oracle at [`GOAL`]).
    pub exact: ValueWithBar,
    /// The same-path pairs' share of Var L, 2Σ⟨𝒞_j𝒞_k⟩/(N_F Var L).
    pub pairs_share: f64,
    /// The tracer's Var L with its standard error (as `error`).
    pub traced: ValueWithBar,
    /// z = (tracer − exact)/√(se² + bar²).
    pub z: f64,
    /// The same against Var L less its same-path pairs over N_F.
    pub z_without_pairs: f64,
}

impl EveryOrderRow {
    /// The tracer's relative standard error.
    pub fn relative_se(&self) -> f64 {
        self.traced.error / self.traced.value
    }
}

/// Runs the oracle and the tracer at `p` on `readme`'s geometry.
pub fn every_order_row(p: &EveryOrderPoint, readme: &Scene) -> Result<EveryOrderRow, String> {
    let s = p.scene(readme);
    let m = every_order_mean(&s, Some(GOAL), &Budget::new(20_000_000_000)).map_err(|e| e.to_string())?;
    let why = || m.variance_missing.clone().unwrap_or_default();
    let (v, pairs) = (m.variance.ok_or_else(why)?, m.same_path_pairs.ok_or_else(why)?);
    let tracer = Tracer::new(&s).map_err(|e| e.to_string())?;
    let t = trace(&tracer, p.seed, 0..p.trials, HitMethod::Sorted, &|_| {}).estimates().summary()?;
    let tv = t.variance;
    let z = (tv.value - v.value) / (tv.se.powi(2) + v.error.powi(2)).sqrt();
    // Without the pairs: M₂ less 2Σ⟨𝒞_j𝒞_k⟩, so Var L less that over N_F.
    let without = v.value - pairs.value / p.forward as f64;
    let z_without_pairs = (tv.value - without) / (tv.se.powi(2) + (v.error + pairs.error).powi(2)).sqrt();
    Ok(EveryOrderRow {
        point: *p,
        exact: v,
        pairs_share: pairs.value / p.forward as f64 / v.value,
        traced: ValueWithBar { value: tv.value, error: tv.se },
        z,
        z_without_pairs,
    })
}

/// The rows as a markdown table.
pub fn every_order_table(rows: &[EveryOrderRow]) -> String {
    let mut s = String::new();
    writeln!(s, "| orders | albedo | R | N_F | lights | trials | Var L exact (finite-sphere) | pairs' share | tracer | se | z | z without pairs |").unwrap();
    writeln!(s, "|---|---:|---:|---:|---|---:|---|---:|---|---:|---:|---:|").unwrap();
    for r in rows {
        let p = r.point;
        let lights: Vec<String> = p.lights.iter().map(|[x, y, z]| format!("({x}, {y}, {z})")).collect();
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {:.7e} ± {:.1e} | {:.2} % | {:.7e} ± {:.1e} | {:.2} % | {:+.2} | {:+.1} |",
            p.orders,
            p.albedo,
            p.radius,
            p.forward,
            lights.join(", "),
            p.trials,
            r.exact.value,
            r.exact.error,
            100.0 * r.pairs_share,
            r.traced.value,
            r.traced.error,
            100.0 * r.relative_se(),
            r.z,
            r.z_without_pairs
        )
        .unwrap();
    }
    s
}
