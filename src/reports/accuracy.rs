//! Accuracy of the f64 special functions, measured in ulps against MPFR.
//!
//! The references are the *naive* closed forms (and MPFR's own `eint`),
//! evaluated at a precision raised by the bits their cancellation can lose,
//! and confirmed by a second evaluation 128 bits higher: an independent
//! source, not the series and fractions under test.

use crate::special;
use rayon::prelude::*;
use rug::float::Constant;
use rug::Float;
use std::fmt::Write;

/// One function under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecialFn {
    /// A(x) = arccos x − x√(1 − x²), 0 for x ≥ 1 ([`special::overlap_a`]).
    OverlapA,
    /// ∫₀ˣ A(y) dy ([`special::overlap_a_integral`]).
    OverlapAIntegral,
    /// ∫₀ˣ A(y) y dy ([`special::overlap_a_moment`]).
    OverlapAMoment,
    /// E₁(x) = ∫₁^∞ e^{−xt}/t dt ([`special::exp_int_e1`]).
    ExpIntE1,
    /// x⁻¹(e⁻ˣ − x E₁(x)) = ∫ₓ^∞ u⁻² e^{−u} du ([`special::exp_int_tail2`]).
    ExpIntTail2,
}

impl SpecialFn {
    /// Every function, in the order of the report.
    pub const ALL: [SpecialFn; 5] = [
        SpecialFn::OverlapA,
        SpecialFn::OverlapAIntegral,
        SpecialFn::OverlapAMoment,
        SpecialFn::ExpIntE1,
        SpecialFn::ExpIntTail2,
    ];

    /// The function as printed in the report.
    pub fn name(self) -> &'static str {
        match self {
            SpecialFn::OverlapA => "A(x)",
            SpecialFn::OverlapAIntegral => "∫₀ˣ A(y) dy",
            SpecialFn::OverlapAMoment => "∫₀ˣ A(y) y dy",
            SpecialFn::ExpIntE1 => "E₁(x)",
            SpecialFn::ExpIntTail2 => "x⁻¹(e⁻ˣ − x E₁(x))",
        }
    }

    /// The f64 implementation under test.
    pub fn eval_f64(self, x: f64) -> f64 {
        match self {
            SpecialFn::OverlapA => special::overlap_a(&x),
            SpecialFn::OverlapAIntegral => special::overlap_a_integral(&x),
            SpecialFn::OverlapAMoment => special::overlap_a_moment(&x),
            SpecialFn::ExpIntE1 => special::exp_int_e1(&x),
            SpecialFn::ExpIntTail2 => special::exp_int_tail2(&x),
        }
    }

    /// The same implementation at the precision of `x` (MPFR).
    pub fn eval_mpfr(self, x: &Float) -> Float {
        match self {
            SpecialFn::OverlapA => special::overlap_a(x),
            SpecialFn::OverlapAIntegral => special::overlap_a_integral(x),
            SpecialFn::OverlapAMoment => special::overlap_a_moment(x),
            SpecialFn::ExpIntE1 => special::exp_int_e1(x),
            SpecialFn::ExpIntTail2 => special::exp_int_tail2(x),
        }
    }

    /// Sweep segments: (label, lo, hi, log-spaced?). Log spacing is for the
    /// hard ends; `1-` segments are spaced in u = 1 − x.
    fn segments(self) -> &'static [Segment] {
        const OVERLAP: &[Segment] = &[
            Segment { label: "x ∈ [1e-300, 0.5], log-spaced", lo: 1e-300, hi: 0.5, spacing: Spacing::Log },
            Segment {
                label: "1 − x ∈ [2⁻⁵³, 0.5], log-spaced",
                lo: 1.1102230246251565e-16,
                hi: 0.5,
                spacing: Spacing::LogFromOne,
            },
            Segment { label: "x ∈ [0, 1.5], uniform", lo: 0.0, hi: 1.5, spacing: Spacing::Uniform },
        ];
        const EXPINT: &[Segment] = &[
            Segment { label: "x ∈ [1e-300, 700], log-spaced", lo: 1e-300, hi: 700.0, spacing: Spacing::Log },
            Segment { label: "x ∈ [0, 5], uniform", lo: 0.0, hi: 5.0, spacing: Spacing::Uniform },
        ];
        match self {
            SpecialFn::ExpIntE1 | SpecialFn::ExpIntTail2 => EXPINT,
            _ => OVERLAP,
        }
    }

    /// Reference value at `prec` bits from the naive closed form.
    pub fn reference(self, x: f64, prec: u32) -> Float {
        let xf = Float::with_val(prec, x);
        let one = Float::with_val(prec, 1);
        if matches!(self, SpecialFn::OverlapA | SpecialFn::OverlapAIntegral | SpecialFn::OverlapAMoment) && x >= 1.0 {
            let pi = Float::with_val(prec, Constant::Pi);
            return match self {
                SpecialFn::OverlapA => Float::with_val(prec, 0),
                SpecialFn::OverlapAIntegral => Float::with_val(prec, 2) / 3u32,
                _ => pi / 16u32,
            };
        }
        let w = Float::with_val(prec, &one - Float::with_val(prec, &xf * &xf));
        let sw = w.clone().sqrt();
        let acos = xf.clone().acos();
        match self {
            SpecialFn::OverlapA => acos - Float::with_val(prec, &xf * &sw),
            SpecialFn::OverlapAIntegral => {
                let w32 = Float::with_val(prec, &w * &sw);
                Float::with_val(prec, &xf * &acos) - sw + w32 / 3u32 + Float::with_val(prec, 2) / 3u32
            }
            SpecialFn::OverlapAMoment => {
                let pi = Float::with_val(prec, Constant::Pi);
                let x2 = Float::with_val(prec, &xf * &xf);
                let a = (one.clone() - Float::with_val(prec, 4 * &x2)) * acos;
                let b = xf * (one + Float::with_val(prec, 2 * &x2)) * sw;
                (pi / 2u32 - a - b) / 8u32
            }
            SpecialFn::ExpIntE1 => -Float::with_val(prec, -&xf).eint(),
            SpecialFn::ExpIntTail2 => {
                let e1 = -Float::with_val(prec, -&xf).eint();
                let ex = Float::with_val(prec, -&xf).exp();
                (ex - Float::with_val(prec, &xf * &e1)) / xf
            }
        }
    }

    /// Bits the naive reference can lose to cancellation at x, plus 256.
    fn reference_prec(self, x: f64) -> u32 {
        let lg = |v: f64| if v > 0.0 && v < 1.0 { -v.log2() } else { 0.0 };
        let lost = match self {
            SpecialFn::ExpIntE1 => 0.0,
            SpecialFn::ExpIntTail2 => x.max(1.0).log2() * 2.0 + 8.0,
            _ => 3.0 * lg(x) + 3.0 * lg(1.0 - x),
        };
        256 + lost.ceil() as u32
    }
}

#[derive(Debug, Clone, Copy)]
enum Spacing {
    Log,
    LogFromOne,
    Uniform,
}

#[derive(Debug, Clone, Copy)]
struct Segment {
    label: &'static str,
    lo: f64,
    hi: f64,
    spacing: Spacing,
}

impl Segment {
    /// The i-th of n midpoint-stratified points.
    fn point(&self, i: usize, n: usize) -> f64 {
        let t = (i as f64 + 0.5) / n as f64;
        match self.spacing {
            Spacing::Uniform => self.lo + t * (self.hi - self.lo),
            Spacing::Log => (self.lo.ln() + t * (self.hi.ln() - self.lo.ln())).exp(),
            Spacing::LogFromOne => 1.0 - (self.lo.ln() + t * (self.hi.ln() - self.lo.ln())).exp(),
        }
    }
}

/// Size of one unit in the last place at the magnitude of `r` (2⁻¹⁰⁷⁴ for
/// subnormals and 0).
pub fn ulp(r: f64) -> f64 {
    let r = r.abs();
    if r < f64::MIN_POSITIVE {
        return f64::from_bits(1);
    }
    // Exponent of r, minus the 52 fraction bits, built bit by bit (powi would
    // overflow through 2^1048 on the way to 2^-1048).
    let k = ((r.to_bits() >> 52) & 0x7ff) as i64 - 1023 - 52;
    if k >= -1022 {
        f64::from_bits(((k + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (k + 1074))
    }
}

/// Error of `f(x)` in ulps of the exact value, against a reference confirmed
/// at two precisions. Panics if the two references disagree in f64 (the
/// reference itself would be unreliable).
pub fn ulps_at(func: SpecialFn, x: f64) -> f64 {
    let p = func.reference_prec(x);
    let r1 = func.reference(x, p);
    let r2 = func.reference(x, p + 128);
    assert_eq!(r1.to_f64(), r2.to_f64(), "{} reference unstable at x = {x:e}", func.name());
    let got = func.eval_f64(x);
    let diff = (Float::with_val(p + 128, got) - &r2).abs();
    (diff / ulp(r2.to_f64())).to_f64()
}

/// Summary of one sweep segment.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SegmentSummary {
    /// The function's [`SpecialFn::name`].
    pub function: &'static str,
    /// The segment's label: its range of x and spacing.
    pub segment: &'static str,
    /// Points on the segment.
    pub points: usize,
    /// Largest error, in ulps of the exact value.
    pub max_ulps: f64,
    /// The x of the largest error (NaN when every error was 0).
    pub max_at: f64,
    /// Median error, in ulps.
    pub median_ulps: f64,
}

/// Sweeps `func` over its segments with `points` points in all.
pub fn sweep(func: SpecialFn, points: usize) -> Vec<SegmentSummary> {
    let segs = func.segments();
    let per = points.div_ceil(segs.len());
    segs.iter()
        .map(|seg| {
            let mut errs: Vec<(f64, f64)> = (0..per)
                .into_par_iter()
                .map(|i| {
                    let x = seg.point(i, per);
                    (ulps_at(func, x), x)
                })
                .collect();
            let (max_ulps, max_at) = errs.iter().copied().fold((0.0, f64::NAN), |a, b| if b.0 > a.0 { b } else { a });
            errs.sort_by(|a, b| a.0.total_cmp(&b.0));
            SegmentSummary {
                function: func.name(),
                segment: seg.label,
                points: per,
                max_ulps,
                max_at,
                median_ulps: errs[per / 2].0,
            }
        })
        .collect()
}

/// Accuracy of one special function of several arguments (the
/// finite-sphere model's), over a seeded sample of its domain.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MultiSummary {
    /// The function, as printed.
    pub function: &'static str,
    /// The sampled domain of its arguments, as printed.
    pub domain: &'static str,
    /// Points sampled.
    pub points: usize,
    /// Largest error, in ulps of the exact value.
    pub max_ulps: f64,
    /// Median error, in ulps.
    pub median_ulps: f64,
    /// The bound the tests hold it to.
    pub bound: f64,
}

/// A deterministic point of [0, 1)² … from an index (a Halton-like
/// sequence in bases 2, 3, 5), so that the sweeps are reproducible.
fn halton(i: usize, base: usize) -> f64 {
    let (mut f, mut r, mut k) = (1.0, 0.0, i + 1);
    while k > 0 {
        f /= base as f64;
        r += f * (k % base) as f64;
        k /= base;
    }
    r
}

fn log_uniform(t: f64, lo: f64, hi: f64) -> f64 {
    (lo.ln() + t * (hi.ln() - lo.ln())).exp()
}

/// The references, by the naive formulas at a precision that absorbs their
/// cancellation (confirmed at 128 bits more).
mod naive {
    use rug::float::Constant;
    use rug::Float;

    pub fn segment(r: f64, l: f64, p: u32) -> Float {
        let x = Float::with_val(p, r) * Float::with_val(p, l);
        (Float::with_val(p, 1) - (-x).exp()) / Float::with_val(p, r)
    }

    pub fn triangle(r1: f64, r2: f64, l: f64, p: u32) -> Float {
        if r1 == r2 {
            let rl = Float::with_val(p, r1) * Float::with_val(p, l);
            let r = Float::with_val(p, r1);
            return (Float::with_val(p, 1) - (Float::with_val(p, 1) + rl.clone()) * (-rl).exp()) / (r.clone() * r);
        }
        (segment(r1, l, p) - segment(r2, l, p)) / (Float::with_val(p, r2) - Float::with_val(p, r1))
    }

    pub fn lens(r1: f64, r2: f64, d: f64, p: u32) -> Float {
        let (a, b, dd) = (Float::with_val(p, r1), Float::with_val(p, r2), Float::with_val(p, d));
        let d1 = (dd.clone() * dd.clone() + a.clone() * a.clone() - b.clone() * b.clone())
            / (Float::with_val(p, 2) * dd.clone());
        let d2 = dd - d1.clone();
        let seg = |r: &Float, h: &Float| {
            let x = h.clone() / r.clone();
            let s = (Float::with_val(p, 1) - x.clone() * x.clone()).sqrt();
            r.clone() * r.clone() * (x.clone().acos() - x * s)
        };
        seg(&a, &d1) + seg(&b, &d2)
    }

    pub fn elliptic(kp: f64, p: u32) -> Float {
        let (mut a, mut b) = (Float::with_val(p, 1), Float::with_val(p, kp));
        let mut c2 = Float::with_val(p, 1) - b.clone() * b.clone();
        let mut w = Float::with_val(p, 0.5);
        let mut sum = w.clone() * c2.clone();
        for _ in 0..200 {
            let c = (a.clone() - b.clone()) / 2u32;
            let na = (a.clone() + b.clone()) / 2u32;
            b = (a * b).sqrt();
            a = na;
            c2 = c.clone() * c;
            w *= 2u32;
            sum += w.clone() * c2.clone();
            if c2.is_zero() || c2.get_exp().unwrap_or(0) < -(2 * p as i32) {
                break;
            }
        }
        Float::with_val(p, Constant::Pi) / (Float::with_val(p, 2) * a) * (Float::with_val(p, 1) - sum)
    }
}

/// ulps of `got` against a reference computed at `p` and `p + 128` bits
/// (which must agree in f64).
fn multi_ulps(got: f64, reference: impl Fn(u32) -> Float, p: u32, what: &str) -> f64 {
    let (r1, r2) = (reference(p), reference(p + 128));
    assert_eq!(r1.to_f64(), r2.to_f64(), "{what}: reference unstable");
    let diff = (Float::with_val(p + 128, got) - &r2).abs();
    (diff / ulp(r2.to_f64())).to_f64()
}

/// Sweeps the finite-sphere model's special functions of several
/// arguments: `points` seeded points each.
pub fn multi_arg_sweep(points: usize) -> Vec<MultiSummary> {
    use crate::special::{complete_elliptic_e, disc_overlap, exp_segment, exp_triangle};
    let summarise = |function, domain, bound, mut errs: Vec<f64>| {
        errs.sort_by(f64::total_cmp);
        MultiSummary {
            function,
            domain,
            points: errs.len(),
            max_ulps: errs.last().copied().unwrap_or(0.0),
            median_ulps: errs[errs.len() / 2],
            bound,
        }
    };
    let idx: Vec<usize> = (0..points).collect();
    let seg: Vec<f64> = idx
        .par_iter()
        .map(|&i| {
            let (r, l) = (log_uniform(halton(i, 2), 1e-3, 1e3), log_uniform(halton(i, 3), 1e-12, 1e3));
            multi_ulps(exp_segment(&r, Some(&l)), |p| naive::segment(r, l, p), 320, "F₁")
        })
        .collect();
    let tri: Vec<f64> = idx
        .par_iter()
        .map(|&i| {
            let r1 = log_uniform(halton(i, 2), 1e-3, 1e3);
            let ratio = if i % 8 == 0 { 1.0 } else { 1.0 + log_uniform(halton(i, 5), 1e-12, 10.0) };
            let l = log_uniform(halton(i, 3), 1e-9, 1e3);
            let r2 = r1 * ratio;
            multi_ulps(exp_triangle(&r1, &r2, Some(&l)), |p| naive::triangle(r1, r2, l, p), 512, "F₂")
        })
        .collect();
    let lens: Vec<f64> = idx
        .par_iter()
        .map(|&i| {
            let r2 = log_uniform(halton(i, 2), 1e-8, 1e2);
            let (lo, hi) = ((1.0 - r2).abs(), 1.0 + r2);
            // Half the points graded towards either end of the overlap range.
            let t = halton(i, 3);
            let d = match i % 4 {
                0 => lo + (hi - lo) * log_uniform(t, 1e-12, 1.0),
                1 => hi - (hi - lo) * log_uniform(t, 1e-12, 1.0),
                _ => lo + (hi - lo) * t,
            };
            if !(d > lo && d < hi) {
                return 0.0;
            }
            multi_ulps(disc_overlap(&1.0, &r2, &d), |p| naive::lens(1.0, r2, d, p), 1024, "lens")
        })
        .collect();
    let ell: Vec<f64> = idx
        .par_iter()
        .map(|&i| {
            let kp = log_uniform(halton(i, 2), 1e-12, 1.0);
            multi_ulps(complete_elliptic_e(&kp), |p| naive::elliptic(kp, p), 320, "E")
        })
        .collect();
    vec![
        summarise("F₁(r, L) = ∫₀^L e^{−rx} dx", "r ∈ [1e-3, 1e3], L ∈ [1e-12, 1e3], log-spaced", 4.0, seg),
        summarise(
            "F₂(r₁, r₂, L)",
            "r₁ ∈ [1e-3, 1e3], r₂/r₁ − 1 ∈ {0} ∪ [1e-12, 10], L ∈ [1e-9, 1e3], log-spaced",
            8.0,
            tri,
        ),
        summarise("disc overlap (1, r₂, D)", "r₂ ∈ [1e-8, 1e2] log-spaced, D graded to both ends", 8.0, lens),
        summarise("E(m) from k′ = √(1 − m)", "k′ ∈ [1e-12, 1], log-spaced", 8.0, ell),
    ]
}

/// Markdown table of f64 special-function errors in ulps.
pub fn accuracy_markdown(points: usize) -> Result<String, String> {
    let mut s = String::new();
    writeln!(s, "# Accuracy of the f64 special functions").unwrap();
    writeln!(s).unwrap();
    writeln!(
        s,
        "Generated by `cargo run --release -- accuracy --points {points} --out docs/accuracy.md`; do not edit by hand."
    )
    .unwrap();
    writeln!(s).unwrap();
    writeln!(s, "Error of the f64 implementation (`src/special/`) in units in the last place of the exact value, against MPFR references: the naive closed forms (and MPFR's `eint` for E₁) evaluated at 256 bits plus the bits their cancellation can lose at that x, each confirmed by a second evaluation 128 bits higher. Points are midpoint-stratified on each segment, log-spaced towards the hard ends (x → 0, x → 1⁻, large x). Target: ≤ 4 ulp everywhere.").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| function | segment | points | max ulps | at x | median ulps |").unwrap();
    writeln!(s, "|---|---|---:|---:|---:|---:|").unwrap();
    let per_fn = points;
    let mut worst: f64 = 0.0;
    for f in SpecialFn::ALL {
        for seg in sweep(f, per_fn) {
            worst = worst.max(seg.max_ulps);
            writeln!(
                s,
                "| {} | {} | {} | {:.2} | {:.17e} | {:.2} |",
                seg.function, seg.segment, seg.points, seg.max_ulps, seg.max_at, seg.median_ulps
            )
            .unwrap();
        }
    }
    writeln!(s).unwrap();
    writeln!(s, "Worst case over all functions: {worst:.2} ulp.").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "## Functions of several arguments (the finite-sphere model)").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "Against the naive formulas at 320–1024 bits (enough to absorb their cancellation), confirmed 128 bits higher, at {points} points each of a deterministic low-discrepancy sample (Halton) of the stated domain. `tests/special_functions.rs` holds each to its bound.").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| function | domain | points | max ulps | median ulps | bound |").unwrap();
    writeln!(s, "|---|---|---:|---:|---:|---:|").unwrap();
    for m in multi_arg_sweep(points) {
        writeln!(
            s,
            "| {} | {} | {} | {:.2} | {:.2} | {} |",
            m.function, m.domain, m.points, m.max_ulps, m.median_ulps, m.bound
        )
        .unwrap();
    }
    Ok(s)
}
