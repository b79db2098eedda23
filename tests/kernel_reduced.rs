//! The `kernel` command's path, [`kernel_integral_reduced`]: the series with
//! its bound as the primary pass, the 1-D quadrature as the independent
//! check. Against the same independent references as the 2-D engine
//! (`tests/quadrature.rs`): the 20–25-digit values and a 1024-bit
//! quadrature-free series. Tolerances: the goal (1e-13 f64, 1e-30 at 128
//! bits) and the result's own bar plus the reference's last digit.

use mcrt_noise::kernel::{
    kernel_integral_reduced, kernel_series_reference, parse_decimal, Angle, KernelMethod, ACCEPTANCE_CASES,
};
use mcrt_noise::prec::mpfr_default_tol;
use mcrt_noise::quad::Options;
use rug::Float;

fn angle(spec: &str, pole: bool, bits: u32) -> Angle<Float> {
    let v = parse_decimal(spec, bits).unwrap();
    if pole {
        Angle::from_pole(&v)
    } else {
        Angle::from_theta(&v)
    }
}

fn digits_of(text: &str) -> f64 {
    let mantissa = text.split(['e', 'E']).next().unwrap();
    let digits = mantissa.chars().filter(|c| c.is_ascii_digit()).collect::<String>();
    10f64.powi(1 - digits.trim_start_matches('0').len() as i32)
}

/// c·T of a case: the series applies in f64 when it is ≤ 2.
fn c_t(a: &Angle<f64>, r: f64) -> f64 {
    (1.0 + a.abs_cos) * 2.0 * r / a.sin
}

#[test]
fn f64_meets_1e13_on_every_acceptance_case_within_its_bar() {
    let mut series_cases = 0;
    for (label, theta, pole, r, reference) in ACCEPTANCE_CASES {
        let a = angle(theta, pole, 53);
        let a = Angle { sin: a.sin.to_f64(), abs_cos: a.abs_cos.to_f64() };
        let r = parse_decimal(r, 53).unwrap().to_f64();
        let (e, method) =
            kernel_integral_reduced(&a, &r, &Options::rel(1e-13)).unwrap_or_else(|f| panic!("{label}: {f}"));
        let exact = parse_decimal(reference, 53).unwrap().to_f64();
        let diff = (e.value - exact).abs();
        assert!(diff <= 1e-13 * exact, "{label}: {} vs {exact}", e.value);
        assert!(diff <= e.error + exact * digits_of(reference), "{label}: bar {:e} below the error {diff:e}", e.error);
        // The series is the primary exactly where it converges without
        // cancelling digits (cT ≤ 2 in f64).
        let expected =
            if c_t(&a, r) <= 2.0 { KernelMethod::SeriesCheckedByQuadrature } else { KernelMethod::Quadrature };
        assert_eq!(method, expected, "{label}: cT = {}", c_t(&a, r));
        series_cases += (method == KernelMethod::SeriesCheckedByQuadrature) as usize;
    }
    assert!(series_cases >= 3, "the series path was taken on {series_cases} cases");
}

#[test]
fn at_128_bits_meets_1e30_against_the_1024_bit_series() {
    let bits = 128;
    for (label, theta, pole, r, _) in ACCEPTANCE_CASES {
        let a = angle(theta, pole, bits);
        let rr = parse_decimal(r, bits).unwrap();
        let (e, _) = kernel_integral_reduced(&a, &rr, &Options::rel(mpfr_default_tol(bits)))
            .unwrap_or_else(|f| panic!("{label}: {f}"));
        let p = 1024;
        let a_ref = angle(theta, pole, p);
        let reference = kernel_series_reference(&a_ref.sin, &a_ref.abs_cos, &parse_decimal(r, p).unwrap(), p);
        let diff = Float::with_val(p, &e.value - &reference).abs();
        assert!(diff.to_f64() <= 1e-30 * reference.to_f64(), "{label}: 128-bit error {diff}");
        assert!(diff <= e.error, "{label}: bar {} below the error {diff}", e.error);
    }
}

/// On a grid of (ϑ, R) that crosses the series' limit cT = 2 (both paths
/// taken), every value lies within its bar of a 256-bit series reference,
/// and the bar meets the goal.
#[test]
fn the_two_passes_agree_across_the_series_limit() {
    for theta in [0.05, 0.3, 1.0, std::f64::consts::FRAC_PI_2, 2.5, 3.1] {
        for r in [1e-9, 1e-4, 1e-2, 0.3, 1.0, 3.0] {
            let a = Angle::from_theta(&theta);
            let (e, _) = kernel_integral_reduced(&a, &r, &Options::rel(1e-13))
                .unwrap_or_else(|f| panic!("ϑ {theta}, R {r}: {f}"));
            let p = 256;
            let reference = kernel_series_reference(
                &Float::with_val(p, a.sin),
                &Float::with_val(p, a.abs_cos),
                &Float::with_val(p, r),
                p,
            )
            .to_f64();
            let diff = (e.value - reference).abs();
            assert!(
                diff <= e.error + 2.0 * f64::EPSILON * reference,
                "ϑ {theta}, R {r}: {} ± {:e} vs {reference}",
                e.value,
                e.error
            );
            assert!(e.error <= 1e-13 * reference, "ϑ {theta}, R {r}: bar {:e}", e.error);
        }
    }
}
