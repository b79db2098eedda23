//! Readable output of the CLI: the oracle's report table, the `kernel`
//! command and the kernel's acceptance rows.

use super::cost::angle_f64;
use crate::kernel::{
    kernel_integral, kernel_integral_bare, kernel_integral_reduced, parse_decimal, Angle, KernelMethod,
    ACCEPTANCE_CASES,
};
use crate::prec::mpfr_default_tol;
use crate::quad::{Options, Outcome};
use std::fmt::Write;
use std::time::{Duration, Instant};

/// A pair integral that Var L weighs 0 and the run did not compute.
const NOT_COMPUTED: &str = "not needed (weight 0)";

/// What the small-sphere column shows where that model cannot form Var L
/// (`Report::variance` is `None`: a beam's single-scattered light with
/// q < 1 or N_B > 1).
const NOT_DERIVED: &str = "not derived (§9.8)";

/// How the `kernel` command prints numbers of its working precision: the
/// value and cross-check to all digits, the bar to 4 (at the working
/// precision: a bar of 3.6e-502 at 1024 bits was printed as f64, `0.000e0`).
struct Shown<V, B> {
    value: V,
    bar: B,
}

fn print_outcome<T: crate::real::Real>(
    label: &str,
    out: &Outcome<T>,
    shown: Shown<impl Fn(&T) -> String, impl Fn(&T) -> String>,
    dt: Duration,
    method: &str,
) -> Result<(), KernelCliError> {
    let Shown { value: show, bar } = shown;
    match out {
        Ok(e) => {
            println!("{label} = {}", show(&e.value));
            println!("  error bar   {} (cross-check {})", bar(&e.error), show(&e.check_value));
            println!(
                "  evaluations {}  pieces {}  breakpoints found {}  time {:.3} ms",
                e.evaluations,
                e.pieces,
                e.found_breakpoints,
                dt.as_secs_f64() * 1e3
            );
            println!("  method      {method}");
            Ok(())
        }
        Err(f) => Err(KernelCliError::Failure(format!("{label}: {f}"))),
    }
}

/// Which computation of I(ϑ, R) the `kernel` command runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelPath {
    /// [`kernel_integral_reduced`]: the series checked by 1-D quadrature (the default).
    Reduced,
    /// [`kernel_integral`]: the 2-D integral by the nested engine, kink declared.
    Nested,
    /// [`kernel_integral_bare`]: the 2-D integral, structure unknown.
    Bare,
}

/// Why the `kernel` command printed no value.
#[derive(Debug, Clone, PartialEq)]
pub enum KernelCliError {
    /// A flag's value cannot be used (`--precision`, `--theta`, `--radius`):
    /// the flag, the value and what is allowed are named. Usage (exit 2).
    Flag(String),
    /// The integral did not converge (`NOT CONVERGED: …` with the reason):
    /// a computed failure (exit 1).
    Failure(String),
}

impl std::fmt::Display for KernelCliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KernelCliError::Flag(m) | KernelCliError::Failure(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for KernelCliError {}

/// The `kernel` command.
pub fn kernel_cli(
    theta: &str,
    radius: &str,
    precision: crate::oracle::Precision,
    rel_tol: Option<f64>,
    path: KernelPath,
    budget: &crate::quad::Budget,
) -> Result<(), KernelCliError> {
    use crate::oracle::Precision;
    let label = format!("I({theta}, {radius})");
    let flag = |name: &'static str| move |e: String| KernelCliError::Flag(format!("--{name}: {e}"));
    match precision {
        Precision::F64 => {
            let angle = Angle::from_theta(&parse_decimal(theta, 53).map_err(flag("theta"))?.to_f64());
            let r = parse_decimal(radius, 53).map_err(flag("radius"))?.to_f64();
            let (out, dt, method) = run_kernel(&angle, &r, rel_tol.unwrap_or(1e-13), path, budget)?;
            let shown = Shown { value: |v: &f64| format!("{v:.17e}"), bar: |v: &f64| format!("{v:.3e}") };
            print_outcome(&label, &out, shown, dt, &method)
        }
        Precision::Bits(bits) => {
            let angle = Angle::from_theta(&parse_decimal(theta, bits).map_err(flag("theta"))?);
            let r = parse_decimal(radius, bits).map_err(flag("radius"))?;
            let tol = rel_tol.unwrap_or_else(|| mpfr_default_tol(bits));
            let (out, dt, method) = run_kernel(&angle, &r, tol, path, budget)?;
            let digits = (bits as f64 * std::f64::consts::LOG10_2) as usize;
            let shown = Shown {
                value: |v: &rug::Float| v.to_string_radix(10, Some(digits)),
                bar: |v: &rug::Float| v.to_string_radix(10, Some(4)),
            };
            print_outcome(&label, &out, shown, dt, &method)
        }
    }
}

/// I(ϑ, R) by `path` within `budget` (one for the run, as `oracle`'s), with
/// its wall time and a line naming the method.
pub fn run_kernel<T: crate::quad::CheckRule>(
    angle: &Angle<T>,
    r: &T,
    tol: f64,
    path: KernelPath,
    budget: &crate::quad::Budget,
) -> Result<(Outcome<T>, Duration, String), KernelCliError> {
    check_kernel_args(angle.sin.to_f64(), r.to_f64()).map_err(KernelCliError::Flag)?;
    let opts = Options::rel(tol).with_budget(budget.clone());
    let t0 = Instant::now();
    let (out, method) = match path {
        KernelPath::Reduced => match kernel_integral_reduced(angle, r, &opts) {
            Ok((e, m)) => (Ok(e), m.describe().to_string()),
            Err(f) => (Err(f), KernelMethod::SeriesCheckedByQuadrature.describe().to_string()),
        },
        KernelPath::Nested => {
            (kernel_integral(angle, r, &opts), "2-D nested quadrature, kink declared, cross-checked".into())
        }
        KernelPath::Bare => {
            (kernel_integral_bare(angle, r, &opts), "2-D nested quadrature, structure scanned, cross-checked".into())
        }
    };
    Ok((out, t0.elapsed(), method))
}

fn check_kernel_args(sin_theta: f64, r: f64) -> Result<(), String> {
    if !(sin_theta > 0.0) {
        return Err(format!("--theta: sin ϑ = {sin_theta:e}; must be in (0, π) (at the poles the kernel has no edge)"));
    }
    if !(r > 0.0 && r.is_finite()) {
        return Err(format!("--radius = {r:e}: must be finite and > 0"));
    }
    Ok(())
}

/// Rows of the acceptance table: (label, f64 value, f64 bar, rel. error vs reference).
pub fn acceptance_rows_f64() -> Vec<(String, Outcome<f64>, f64)> {
    ACCEPTANCE_CASES
        .iter()
        .map(|(label, theta, pole, r, reference)| {
            let angle = angle_f64(theta, *pole).expect("valid case");
            let r = parse_decimal(r, 53).expect("valid case").to_f64();
            let out = kernel_integral(&angle, &r, &Options::rel(1e-13));
            let reference = parse_decimal(reference, 53).expect("valid reference").to_f64();
            (label.to_string(), out, reference)
        })
        .collect()
}

fn pm(v: f64, e: f64) -> String {
    format!("{v:.10e} ± {e:.1e}")
}

/// The readable table of `mcrt-noise oracle`: both models side by side
/// where the finite-sphere one exists, then what only the small-sphere
/// model has (its R → 0 forms, the §4.4 formula, D₁…D₅).
pub fn oracle_table(r: &crate::oracle::Report) -> String {
    use crate::oracle::ValueWithBar;
    let mut s = String::new();
    let col = |v: &ValueWithBar| format!("{:<30}", pm(v.value, v.error));
    let int = |i: &crate::oracle::Integral| ValueWithBar { value: i.value, error: i.error };
    writeln!(
        s,
        "precision {}   rel. tolerance {:.1e}   R = {}   q = {}   N_F = {}   N_B = {}",
        r.precision, r.rel_tol, r.radius, r.q, r.forward_rays, r.camera_rays
    )
    .unwrap();
    writeln!(s, "prediction: {} model, {}", r.prediction.model, r.prediction.note).unwrap();
    // The small-sphere Var L, where that model can form it (`Report::variance`).
    let small_var = r.variance.as_ref().map(|v| v.exact);
    let small_missing = if r.variance.is_none() { NOT_DERIVED } else { NOT_COMPUTED };
    let small_rel = r.variance.as_ref().map(|v| ValueWithBar { value: v.relative, error: v.relative_error });
    match &r.finite {
        Some(f) => {
            writeln!(
                s,
                "{:<24} {:<30} {:<30} finite/small",
                "", "finite-sphere (exact at R)", "small-sphere (§4.3, R → 0)"
            )
            .unwrap();
            let row = |s: &mut String,
                       name: &str,
                       a: &ValueWithBar,
                       b: Option<&ValueWithBar>,
                       ratio: Option<&ValueWithBar>| {
                let ratio = ratio.map_or(String::new(), |q| pm(q.value, q.error));
                let b = b.map_or(format!("{small_missing:<30}"), col);
                writeln!(s, "{name:<24} {}{b}{ratio}", col(a)).unwrap();
            };
            row(&mut s, "mean luminance", &f.mean, Some(&r.mean_luminance), Some(&f.mean_ratio));
            row(&mut s, "Var L (one iteration)", &f.variance, small_var.as_ref(), f.variance_ratio.as_ref());
            row(&mut s, "relative noise Var/L²", &f.relative_noise, small_rel.as_ref(), None);
            for (name, exact, small) in [("(23) exact", &f.corr23, &r.corr23), ("(24) exact", &f.corr24, &r.corr24)] {
                let small = small.as_ref().map_or(format!("{small_missing:<30}"), |c| col(&int(&c.exact)));
                match exact {
                    Some(e) => writeln!(s, "{name:<24} {}{small}", col(&int(e))).unwrap(),
                    None => writeln!(s, "{name:<24} {NOT_COMPUTED:<30}{small}").unwrap(),
                }
            }
            writeln!(s, "{:<24} {}", "bias μ(R) − μ(0)", pm(f.bias.value, f.bias.error)).unwrap();
            if let Some(why) = &f.not_computed {
                writeln!(s, "{:<24} {why}", "not computed:").unwrap();
            }
        }
        None => {
            writeln!(s, "mean luminance           {}", pm(r.mean_luminance.value, r.mean_luminance.error)).unwrap();
            let or_not = |v: Option<ValueWithBar>| v.map_or(small_missing.to_string(), |v| pm(v.value, v.error));
            writeln!(s, "Var L (one iteration)    {}", or_not(small_var)).unwrap();
            writeln!(s, "relative noise Var/L²    {}", or_not(small_rel)).unwrap();
            for (name, c) in [("(23) exact", &r.corr23), ("(24) exact", &r.corr24)] {
                match c {
                    Some(c) => writeln!(s, "{name:<24} {}", pm(c.exact.value, c.exact.error)).unwrap(),
                    None => writeln!(s, "{name:<24} {NOT_COMPUTED}").unwrap(),
                }
            }
        }
    }
    if let Some(f) = &r.finite_mean {
        match (&f.mean, &f.bias, &f.missing) {
            (Some(m), Some(b), _) => {
                writeln!(s, "{:<24} {} (finite-sphere, exact at R: docs/model.md §9.5, §9.9; Var L above is the small-sphere model's)", "mean luminance μ(R)", pm(m.value, m.error)).unwrap();
                writeln!(s, "{:<24} {}", "bias μ(R) − μ(0)", pm(b.value, b.error)).unwrap();
            }
            (_, _, Some(why)) => writeln!(s, "{:<24} not computed: {why}", "mean luminance μ(R)").unwrap(),
            _ => {}
        }
    }
    if let Some(m) = &r.integral_m2_same_path {
        writeln!(
            s,
            "{:<24} {} (of M₂ = {}; not in the paper's (20): E9)",
            "M₂ same-path hits",
            pm(m.value, m.error),
            pm(r.integral_m2.value, r.integral_m2.error)
        )
        .unwrap();
    }
    for (name, c) in [("(23) cross-segment", &r.corr23), ("(24) cross-segment", &r.corr24)] {
        if let Some(why) = c.as_ref().and_then(|c| c.cross_segment_not_added.as_ref()) {
            writeln!(s, "{name:<24} {why}").unwrap();
        }
        if let Some(x) = c.as_ref().and_then(|c| c.cross_segment.as_ref()) {
            let of = c.as_ref().map_or(String::new(), |c| pm(c.exact.value, c.exact.error));
            writeln!(
                s,
                "{name:<24} {} (of {of}; two segments of one path, R → 0 form; not in the paper's (23), (24): E10)",
                pm(x.value, x.error)
            )
            .unwrap();
        }
    }
    writeln!(s, "small-sphere model, R → 0:").unwrap();
    if let Some(why) = &r.pairs_not_computed {
        writeln!(s, "  (23), (24), D1..D5       not computed: {why}").unwrap();
    }
    for (name, c) in [("(23)", &r.corr23), ("(24)", &r.corr24)] {
        let Some(c) = c else { continue };
        match (c.asymptotic.value, c.asymptotic.error, &c.asymptotic.missing) {
            (Some(v), Some(e), _) => {
                writeln!(s, "  {name} R→0 form        {}", pm(v, e)).unwrap();
                if let (Some(ratio), Some(bar)) = (c.ratio, c.ratio_error) {
                    writeln!(s, "  {name} exact/R→0       {}", pm(ratio, bar)).unwrap();
                }
            }
            (_, _, Some(why)) => writeln!(s, "  {name} R→0 form        does not exist: {why}").unwrap(),
            _ => {}
        }
    }
    let asymptotic = r.variance.as_ref().map(|v| (v.relative_asymptotic, v.relative_asymptotic_error));
    match asymptotic.unwrap_or((None, None)) {
        (Some(v), Some(e)) => writeln!(
            s,
            "  Var/L², §4.4 formula   {} (quadrature bar; as an estimate of Var/L² it is off by the O(R) gap of the ratios)",
            pm(v, e)
        )
        .unwrap(),
        _ if r.pairs_not_computed.is_some() => {}
        _ => writeln!(s, "  Var/L², §4.4 formula   does not exist for this scene").unwrap(),
    }
    if let (Some(d), Some(e)) = (r.d, r.d_error) {
        let shown: Vec<String> = d.iter().zip(e.iter()).map(|(v, e)| format!("{v:.6e} ± {e:.0e}")).collect();
        writeln!(s, "  D1..D5  {}", shown.join("  ")).unwrap();
    }
    let finite_evals = r.finite.as_ref().map_or(String::new(), |f| format!(" + {} (finite-sphere)", f.evaluations));
    writeln!(s, "evaluations {}{finite_evals}   time {:.1} ms", r.evaluations, r.wall_time_ms).unwrap();
    s
}
