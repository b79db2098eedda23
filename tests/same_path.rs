//! The same-path kernel K(μ) = ∫ p(v₁·v₂) f(−u·v₂) cot(θ/2) dω₂ (E9,
//! `docs/model.md` §3b; `model::same_path::kernel`) against independent
//! computations:
//!
//! - isotropic media: 1/8 in closed form, and Henyey–Greenstein with g → 0
//!   tends to it;
//! - Henyey–Greenstein: a 2-D quadrature over v₂ with every vector formed in
//!   Cartesian coordinates and every factor from them (p(v₁·v₂), f(−u·v₂),
//!   cot(θ/2) with cos θ = −v₁·v₂), not from the ring's closed form, its
//!   angle γ or the simplification cot(θ/2) sin θ = 1 + cos θ;
//! - the geometry behind K: the volume of the interaction points from which
//!   both segments hit, (4/3)R³cot(θ/2), against a Monte Carlo count of
//!   points in both half-cylinders (binomial standard error);
//! - the average over v₁ in closed form: for any phase function,
//!   (1/4π)∫K dω₁ = (1/2)∫₀^π p(−cos θ)(1 + cos θ) dθ (rotation invariance
//!   and ∫f dω = 1).
//!
//! Tolerances: the sum of the two computations' bars (the quadrature's
//! cross-checked bounds, inner bars included), plus 10⁻¹³ relative for
//! the closed form's rounding; the kernel's own bar (asked 10⁻¹¹) must be
//! within 10⁻⁹ relative.

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
            integrate(
                |chi: &f64| {
                    let v2: Vec<f64> =
                        (0..3).map(|i| ct * w[i] + st * (chi.cos() * e1[i] + chi.sin() * e2[i])).collect();
                    // Every factor from the vectors: p(v₁·v₂), f(−u·v₂) and
                    // cot(θ/2) = |v₂ − v₁|/|v₂ + v₁| (cos θ = −v₁·v₂), times
                    // the sin θ of dω₂.
                    // v₂ ∓ (−v₁) as offsets (cos θ ∓ 1)(−v₁) + sin θ e(χ), so
                    // that v₂ → −v₁ keeps its digits.
                    let s2 = 2.0 * (theta / 2.0).sin().powi(2);
                    let norm = |along: f64| {
                        (0..3)
                            .map(|i| (along * w[i] + st * (chi.cos() * e1[i] + chi.sin() * e2[i])).powi(2))
                            .sum::<f64>()
                            .sqrt()
                    };
                    let cot_half = norm(2.0 - s2) / norm(-s2);
                    let dot = -(0..3).map(|i| w[i] * v2[i]).sum::<f64>();
                    phase_eval(&phase, &dot) * phase_eval(&phase, &-v2[2]) * cot_half * st
                },
                &Domain::finite(0.0, 2.0 * PI).with_breakpoints([PI]),
                o,
            )
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

/// The interaction points from which a first segment along v₁ and a second
/// along v₂ both hit the sphere (radius 1 at the origin): in the
/// half-cylinder ahead of the centre along v₁ and in the one behind it
/// along v₂. Their volume is (4/3)cot(θ/2), cos θ = −v₁·v₂: counted by
/// Monte Carlo in a box that holds the region, within 5 binomial standard
/// errors (a wrong sign of cos θ would be off by a factor cot²(θ/2)).
#[test]
fn both_segments_hit_from_a_region_of_volume_four_thirds_cot_half_theta() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(9);
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for cos_v1v2 in [-0.5f64, 0.3, 0.8] {
        let v1 = [0.0, 0.0, 1.0];
        let v2 = [(1.0 - cos_v1v2 * cos_v1v2).sqrt(), 0.0, cos_v1v2];
        let cot_half = ((1.0 - cos_v1v2) / (1.0 + cos_v1v2)).sqrt();
        let exact = 4.0 / 3.0 * cot_half;
        // The region's farthest point lies within √(1 + cot²(θ/2)) of the centre.
        let half = (1.0 + cot_half * cot_half).sqrt() * 1.01;
        let (n, mut inside) = (2_000_000u64, 0u64);
        for _ in 0..n {
            let x = [rng.random_range(-half..half), rng.random_range(-half..half), rng.random_range(-half..half)];
            let (t1, t2, xx) = (dot(&x, &v1), dot(&x, &v2), dot(&x, &x));
            if t1 >= 0.0 && t2 <= 0.0 && xx - t1 * t1 <= 1.0 && xx - t2 * t2 <= 1.0 {
                inside += 1;
            }
        }
        let box_volume = (2.0 * half).powi(3);
        let p = inside as f64 / n as f64;
        let (volume, se) = (p * box_volume, (p * (1.0 - p) / n as f64).sqrt() * box_volume);
        println!("v1·v2 = {cos_v1v2}: counted {volume:.4} ± {se:.4}, (4/3)cot(θ/2) = {exact:.4}");
        assert!((volume - exact).abs() <= 5.0 * se, "v1·v2 = {cos_v1v2}: {volume} ± {se} against {exact}");
    }
}
