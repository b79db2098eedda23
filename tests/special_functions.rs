//! Special functions: f64 within 4 ulp of MPFR over their whole domains, the
//! same generic code accurate at 256 bits, and a pinned sweep summary.
//!
//! Tolerance policy: f64 error ≤ `prec::SPECIAL_MAX_ULPS` (4 ulp) at every
//! sweep point; at 256 bits ≤ 2⁻²⁴⁰ relative (16 bits of slack for rounding
//! accumulated in the series). Snapshots round ulps to 2 significant digits.

use mcrt_noise::prec::SPECIAL_MAX_ULPS;
use mcrt_noise::reports::accuracy::{sweep, SpecialFn};
use rug::Float;

fn two_sig(v: f64) -> String {
    format!("{:.1e}", v)
}

#[test]
fn f64_sweep_within_4_ulps_and_pinned() {
    let mut summary = String::new();
    for f in SpecialFn::ALL {
        for seg in sweep(f, 100_000) {
            assert!(
                seg.max_ulps <= SPECIAL_MAX_ULPS,
                "{} on {}: {} ulps at x = {:e}",
                seg.function,
                seg.segment,
                seg.max_ulps,
                seg.max_at
            );
            summary.push_str(&format!(
                "{} | {} | points {} | max {} ulp | median {} ulp\n",
                seg.function,
                seg.segment,
                seg.points,
                two_sig(seg.max_ulps),
                two_sig(seg.median_ulps)
            ));
        }
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("special_function_sweep", summary);
    });
}

#[test]
fn generic_code_is_accurate_at_256_bits() {
    let bits = 256;
    let xs = [
        1e-300,
        1e-20,
        1e-3,
        0.1,
        0.3,
        0.49,
        0.5,
        0.6,
        0.75,
        0.9,
        0.999,
        1.0 - 1e-12,
        1.0 - 2f64.powi(-53),
        2.0,
        10.0,
        700.0,
    ];
    for f in SpecialFn::ALL {
        for &x in &xs {
            let is_overlap = matches!(f, SpecialFn::OverlapA | SpecialFn::OverlapAIntegral | SpecialFn::OverlapAMoment);
            if is_overlap && x > 2.0 {
                continue;
            }
            let got = f.eval_mpfr(&Float::with_val(bits, x));
            let reference = f.reference(x, 4096);
            if reference.is_zero() {
                assert!(got.is_zero(), "{} at {x:e}: {got} not 0", f.name());
                continue;
            }
            let rel = (Float::with_val(4096, &got - &reference) / &reference).abs().to_f64();
            assert!(rel <= 2f64.powi(-240), "{} at {x:e}: rel {rel:e} at 256 bits", f.name());
        }
    }
}

#[test]
fn special_values_and_domain_edges() {
    use mcrt_noise::special::*;
    use std::f64::consts::PI;
    assert_eq!(overlap_a(&0.0), PI / 2.0);
    assert_eq!(overlap_a(&1.0), 0.0);
    assert_eq!(overlap_a(&5.0), 0.0);
    assert!(overlap_a(&-0.1).is_nan());
    assert_eq!(overlap_a_integral(&1.0), 2.0 / 3.0);
    assert_eq!(overlap_a_moment(&3.0), PI / 16.0);
    assert_eq!(exp_int_e1(&0.0), f64::INFINITY);
    assert!(exp_int_e1(&f64::NAN).is_nan());
    assert_eq!(exp_int_tail2(&0.0), f64::INFINITY);
    // Continuity across the internal switch points, to a few ulps.
    for (f, x) in [
        (SpecialFn::OverlapA, 0.5),
        (SpecialFn::OverlapAMoment, 0.75),
        (SpecialFn::ExpIntE1, 0.5),
        (SpecialFn::ExpIntTail2, 0.45),
    ] {
        let below = f.eval_f64(x - 1e-15);
        let at = f.eval_f64(x);
        assert!(((below - at) / at).abs() < 1e-13, "{} jumps at {x}", f.name());
    }
}

#[test]
fn laplace_series_of_a_matches_quadrature() {
    use mcrt_noise::quad::{integrate, Domain, Options};
    use mcrt_noise::special::{overlap_a, overlap_a_laplace};
    for beta in [-2.0, -0.5, 0.0, 1e-3, 0.1, 1.0, 2.0] {
        let (v, bound) = overlap_a_laplace(&beta).unwrap();
        let q = integrate(|x: &f64| overlap_a(x) * (-beta * x).exp(), &Domain::finite(0.0, 1.0), &Options::rel(1e-14))
            .unwrap();
        assert!(
            (v - q.value).abs() <= bound + q.error,
            "β = {beta}: series {v} ± {bound:e}, quadrature {} ± {:e}",
            q.value,
            q.error
        );
        // Useful: below the 64-ulp floor of the oracle's inner integrals.
        assert!(bound <= 1e-14 * v.abs(), "β = {beta}: bound {bound:e}");
    }
    assert!(overlap_a_laplace(&5.0f64).is_none(), "f64 must refuse large β");
    let bits = 128;
    for beta in [-3.0, 0.5, 10.0, 50.0] {
        let b = Float::with_val(bits, beta);
        let (v, bound) = overlap_a_laplace(&b).unwrap();
        let q = integrate(
            |x: &Float| overlap_a(x) * (-(b.clone() * x.clone())).exp(),
            &Domain::finite(Float::with_val(bits, 0), Float::with_val(bits, 1)),
            &Options::rel(1e-34),
        )
        .unwrap();
        let diff = Float::with_val(bits, &v - &q.value).abs().to_f64();
        assert!(diff <= bound.to_f64() + q.error.to_f64(), "β = {beta}: diff {diff:e}, bound {:e}", bound.to_f64());
        assert!(bound.to_f64() <= 1e-35 * v.to_f64().abs(), "β = {beta}: bound {:e}", bound.to_f64());
    }
}

/// The finite-sphere model's special functions of several arguments, f64
/// against MPFR references from the naive formulas (`accuracy::multi_arg_sweep`),
/// within their stated bounds.
#[test]
fn finite_sphere_functions_within_their_bounds() {
    for s in mcrt_noise::reports::accuracy::multi_arg_sweep(20_000) {
        println!("{} | {} | max {:.2} ulp | median {:.2} ulp", s.function, s.domain, s.max_ulps, s.median_ulps);
        assert!(s.max_ulps <= s.bound, "{}: {} ulps above the bound {}", s.function, s.max_ulps, s.bound);
    }
}

/// E(m) at 128 bits against 40-digit values from mpmath (`ellipe`), an
/// independent implementation.
#[test]
fn elliptic_e_at_128_bits_matches_mpmath() {
    use mcrt_noise::special::complete_elliptic_e;
    for (kp, reference) in [
        ("0.70710678118654752440084436210484903928", "1.35064388104767550252017473533872584135"),
        ("1e-1", "1.015993545025223935639448275295414094783"),
        ("1e-3", "1.000003897026172061152689118414336731108"),
        ("1e-6", "1.000000000007350902459544729574893536402"),
    ] {
        let k = Float::with_val(128, Float::parse(kp).unwrap());
        let got = complete_elliptic_e(&k);
        let want = Float::with_val(140, Float::parse(reference).unwrap());
        let rel = (Float::with_val(140, &got - &want) / &want).abs().to_f64();
        assert!(rel <= 2f64.powi(-120), "k′ = {kp}: rel {rel:e}");
    }
}

/// e^{x}E₁(x) in f64 (`exp_int_e1_scaled`, the fraction without its
/// e^{−x}) against e^{x}·E₁(x) at 512 bits (no underflow there), past the
/// point where E₁ underflows in f64 (x ≈ 745): within 10⁻¹⁴ relative.
#[test]
fn scaled_exponential_integral_matches_the_unscaled_one() {
    use mcrt_noise::special::{exp_int_e1, exp_int_e1_scaled};
    for x in [1e-6, 0.01, 0.3, 0.49, 0.5, 0.51, 1.0, 10.0, 100.0, 700.0, 745.0, 1e3, 1e5] {
        let got = exp_int_e1_scaled(&x);
        let big = Float::with_val(512, x);
        let reference = (big.clone().exp() * exp_int_e1(&big)).to_f64();
        let rel = (got - reference).abs() / reference;
        assert!(rel <= 1e-14, "x = {x:e}: {got:e} vs {reference:e} (rel {rel:e})");
    }
    assert_eq!(exp_int_e1_scaled(&0.0), f64::INFINITY);
    assert!(exp_int_e1_scaled(&-1.0).is_nan());
}
