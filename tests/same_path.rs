//! The same-path kernel K(μ) = ∫ p(v₁·v₂) f(−u·v₂) cot(θ/2) dω₂ (E9,
//! `docs/model.md` §3b; `model::same_path::kernel`) against independent
//! computations:
//!
//! - isotropic media: 1/8 in closed form, and Henyey–Greenstein with g → 0
//!   tends to it;
//! - Henyey–Greenstein: a 2-D quadrature over v₂ with every vector formed in
//!   Cartesian coordinates (f(−u·v₂) from the dot product, not from the
//!   ring's closed form or its angle γ), cot(θ/2) sin θ = 1 + cos θ folded
//!   into the measure as in the derivation;
//! - the average over v₁ in closed form: for any phase function,
//!   (1/4π)∫K dω₁ = (1/2)∫₀^π p(−cos θ)(1 + cos θ) dθ (rotation invariance
//!   and ∫f dω = 1).
//!
//! Tolerances: the sum of the two computations' bars (the quadrature's
//! cross-checked bounds, inner bars included), plus 10⁻¹³ relative for
//! the closed form's rounding; the kernel's own bar must meet the 10⁻⁹
//! relative asked of it.

use mcrt_noise::model::field::phase_eval;
use mcrt_noise::model::same_path::kernel;
use mcrt_noise::quad::{integrate, integrate_nested, Domain, Estimate, Options, Outcome};
use mcrt_scene::Phase;
use std::f64::consts::PI;

fn options() -> Options {
    Options::rel(1e-11).declared()
}

fn kernel_at(g: f64, mu: f64) -> Estimate<f64> {
    let phase = Phase::HenyeyGreenstein { g };
    let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
    kernel(&phase, &mu, &sin, &options()).unwrap()
}

/// K by a 2-D quadrature in the polar frame about −v₁ with Cartesian
/// vectors: u = (0, 0, 1), v₁ = (sin ϑ, 0, μ).
fn kernel_cartesian(g: f64, mu: f64) -> Outcome<f64> {
    let phase = Phase::HenyeyGreenstein { g };
    let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
    let w = [-sin, 0.0, -mu]; // −v₁
    let e1 = [-mu, 0.0, sin]; // ⊥ w, in the (u, v₁) plane
    let e2 = [0.0, 1.0, 0.0];
    let width = 1.0 - g.abs();
    let mut cuts: Vec<f64> = (0..12).map(|k| width * 10f64.powi(k)).filter(|c| *c < PI).collect();
    cuts.extend(cuts.clone().iter().map(|c| PI - c));
    let gamma = if g > 0.0 { mu.acos() } else { (-mu).acos() };
    cuts.extend((0..12).flat_map(|k| [gamma - width * 10f64.powi(k), gamma + width * 10f64.powi(k)]));
    cuts.push(gamma);
    cuts.retain(|c| *c > 0.0 && *c < PI);
    integrate_nested(
        |theta: &f64, o: &Options| {
            let (ct, st) = (theta.cos(), theta.sin());
            let weight = (1.0 + ct) * phase_eval(&phase, &-ct);
            let ring = integrate(
                |chi: &f64| {
                    let v2: Vec<f64> =
                        (0..3).map(|i| ct * w[i] + st * (chi.cos() * e1[i] + chi.sin() * e2[i])).collect();
                    phase_eval(&phase, &-v2[2])
                },
                &Domain::finite(0.0, 2.0 * PI).with_breakpoints([PI]),
                o,
            )?;
            Ok(ring.scaled(&weight))
        },
        &Domain::finite(0.0, PI).with_breakpoints(cuts),
        &options(),
    )
}

#[test]
fn isotropic_kernel_is_one_eighth_and_hg_tends_to_it() {
    let e = kernel(&Phase::Isotropic, &0.3, &(0.91f64).sqrt(), &options()).unwrap();
    assert_eq!(e.value, 0.125);
    for mu in [-0.9, 0.0, 0.7] {
        let k = kernel_at(1e-9, mu);
        // K is linear in g near 0 with a coefficient of order 1.
        assert!((k.value - 0.125).abs() <= 1e-8 + k.error, "g = 1e-9, μ = {mu}: {}", k.value);
    }
}

#[test]
fn hg_kernel_matches_a_cartesian_quadrature() {
    for g in [0.9, 0.6, -0.5, -0.95] {
        for mu in [-0.999, -0.6, 0.0, 0.4, 0.99] {
            let k = kernel_at(g, mu);
            let c = kernel_cartesian(g, mu).unwrap();
            let diff = (k.value - c.value).abs();
            assert!(
                diff <= k.error + c.error + 1e-13 * k.value.abs(),
                "g = {g}, μ = {mu}: ring {} ± {:.1e}, Cartesian {} ± {:.1e}",
                k.value,
                k.error,
                c.value,
                c.error
            );
            assert!(k.error <= 1e-9 * k.value, "g = {g}, μ = {mu}: bar {:.1e} of {}", k.error, k.value);
        }
    }
}

#[test]
fn hg_kernel_averaged_over_first_directions_has_its_closed_form() {
    for g in [0.8, -0.5] {
        let phase = Phase::HenyeyGreenstein { g };
        // (1/4π)∫K dω₁ = (1/2)∫₀^π K dμ over μ ∈ [−1, 1] (azimuthal symmetry).
        let avg = integrate_nested(
            |mu: &f64, o: &Options| {
                let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
                Ok(kernel(&phase, mu, &sin, o)?.scaled(&0.5))
            },
            &Domain::finite(-1.0, 1.0),
            &Options::rel(1e-10).declared(),
        )
        .unwrap();
        let closed = integrate(
            |t: &f64| 0.5 * phase_eval(&phase, &-t.cos()) * (1.0 + t.cos()),
            &Domain::finite(0.0, PI).with_breakpoints([1e-3, 1e-2, 0.1, PI - 0.1, PI - 1e-2]),
            &Options::rel(1e-12),
        )
        .unwrap();
        let diff = (avg.value - closed.value).abs();
        assert!(
            diff <= avg.error + closed.error,
            "g = {g}: {} ± {:.1e} vs {} ± {:.1e}",
            avg.value,
            avg.error,
            closed.value,
            closed.error
        );
    }
}
