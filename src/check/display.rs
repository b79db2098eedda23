//! The verdict in words: its rows, its reasons and what it shows. No number
//! is printed as 0, inf or NaN in place of a result.

use super::options::{short, CHECKS, TAIL_SHARE};
use super::samples::Measured;
use super::statistics::Null;
use super::verdict::{count_text, disagrees, QuantityCheck, Ratio, Status, TailCheck, Verdict};
use super::Predicted;
use std::fmt;

impl fmt::Display for Ratio {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ± {:.1e} (s.e.) ± {:.1e} (bars)", fixed(self.value, 5), self.standard_error, self.bar)
    }
}

/// `x` with `decimals` decimals where that shows its leading digits (|x| in
/// [10⁻², 10⁵)), else in exponent notation with as many.
fn fixed(x: f64, decimals: usize) -> String {
    if (1e-2..1e5).contains(&x.abs()) {
        format!("{x:.decimals$}")
    } else {
        format!("{x:.decimals$e}")
    }
}

/// The ratio with its errors, or why it is not given.
fn ratio_text(ratio: Option<Ratio>, m: Measured, p: Predicted) -> String {
    ratio.map_or_else(|| format!("beyond the range of a double: {:.3e}/{:.3e}", m.value, p.value), |r| r.to_string())
}

/// A z-score: two decimals, or in exponent notation when large.
pub(super) fn z_text(z: f64) -> String {
    if z.abs() < 1e4 {
        format!("{z:+.2}")
    } else {
        format!("{z:+.3e}")
    }
}

/// A relative error in per cent: three decimals, or three significant
/// digits when smaller than 0.01 % (never a bare 0.000 %).
fn percent(d: f64) -> String {
    let p = d * 100.0;
    if p.abs() >= 0.01 {
        format!("{p:.3} %")
    } else {
        format!("{p:.2e} %")
    }
}

/// A rate with two significant digits.
fn short_rate(r: f64) -> String {
    format!("{r:.1e}")
}

/// Why the tail test failed.
pub(super) fn tail_failure(tail: &TailCheck, count: u64, null: &Null) -> String {
    let largest = if tail.largest_exact {
        format!("the largest value, L = {:.6e},", tail.largest)
    } else {
        format!("the largest value, at least {:.6e} (√(Σ L⁴/Σ L²): the power sums came without it),", tail.largest)
    };
    format!(
        "{largest} is larger than a correct renderer's largest of {count} values but with probability ≤ {:.1e} (the \
         Markov and Cantelli bounds with the predicted mean {:.4e} and Var L {:.4e}, for any distribution of L), below \
         the tail test's rate {:.1e}",
        tail.probability_bound, null.mean, null.variance, tail.rate
    )
}

/// Why `q` disagrees with the prediction, if it does. A failing mean beside
/// a measured Var L well above the prediction says that the variance widens
/// the mean's scatter too (the mean's z is scaled by the predicted Var L).
pub(super) fn disagreement(q: &QuantityCheck, z_limit: f64, variance_ratio: Option<f64>) -> Option<String> {
    let m = q.measured?;
    disagrees(q, z_limit).then(|| {
        let z = q.z.map_or(format!("|z| beyond the range of a double ({:.1e}), far beyond", f64::MAX), |z| {
            format!("z = {}, beyond", z_text(z))
        });
        let ratio = ratio_text(q.ratio, m, q.predicted);
        let widened = match variance_ratio {
            Some(r) if q.name == "mean L" && r >= 1.5 => format!(
                " (the mean's z is scaled by the predicted Var L; the measured Var L is {} times it, which widens \
                 the mean's scatter as well: read this beside the Var L row)",
                fixed(r, 2)
            ),
            _ => String::new(),
        };
        format!(
            "{}: measured {:.6e} ± {:.2e} (s.e.) against predicted {:.6e} ± {:.1e} (bars) (ratio {ratio}): {z} the \
             limit ±{z_limit:.2}{widened}",
            q.name,
            m.value,
            m.standard_error,
            q.predicted.value,
            q.predicted.total_bar() + q.rounding_bar,
        )
    })
}

/// Why quantities are not resolved, one sentence per reason (quantities
/// sharing a reason named together).
pub(super) fn unresolved(checks: &[QuantityCheck]) -> Vec<String> {
    let mut out: Vec<(Vec<&str>, &str)> = Vec::new();
    for q in checks {
        if let Some(why) = &q.not_resolved {
            match out.iter_mut().find(|(_, w)| *w == why.as_str()) {
                Some((names, _)) => names.push(q.name),
                None => out.push((vec![q.name], why)),
            }
        }
    }
    out.into_iter().map(|(names, why)| format!("{}: {why}", names.join(" and "))).collect()
}

/// The reason of `q`'s unmet target, with the samples that would meet it.
pub(super) fn unmet_target(q: &QuantityCheck, n: u64) -> Option<String> {
    let target = q.target_relative_error;
    if q.detectable_relative_error.is_some_and(|d| d <= target) {
        return None;
    }
    let need = match q.samples_for_target {
        Some(count) => format!("{} samples would (standard errors fall like 1/√M)", count_text(count)),
        None => "the bars alone exceed it, so no number of samples can".to_string(),
    };
    let detects = q.detectable_relative_error.map_or("no error of any size with certainty".to_string(), percent);
    Some(format!(
        "{}: too few samples to resolve the target {}: these {n} samples detect {detects}; {need}",
        q.name,
        percent(target)
    ))
}

/// What the verdict shows, in words.
pub(super) fn statement(v: &Verdict) -> String {
    let alpha = v.false_alarm_rate;
    let mut out = match v.status {
        Status::Fail => {
            let disagreeing: Vec<&str> = v.checks.iter().filter(|q| disagrees(q, v.z_limit)).map(|q| q.name).collect();
            let mut parts = Vec::new();
            if v.tail.is_some_and(|t| !t.pass) {
                parts.push("a value larger than a correct renderer produces".to_string());
            }
            if !disagreeing.is_empty() {
                parts.push(format!(
                    "the renderer's {} {} from the prediction by more than the bars and chance explain",
                    disagreeing.join(" and "),
                    if disagreeing.len() == 1 { "differs" } else { "differ" }
                ));
            }
            format!(
                "{} (a correct renderer fails this check with probability ≤ {}, family-wise)",
                parts.join("; and "),
                short(alpha)
            )
        }
        Status::NotResolved => {
            "nothing yet: these samples cannot tell a correct renderer from a wrong one at the stated targets and \
             rate (see the reasons: each says what would resolve it)"
                .to_string()
        }
        Status::Pass => pass_statement(v),
    };
    if v.nonzero.is_none() && !v.checks.is_empty() {
        out.push_str(&format!(
            "; sparsity could not be checked: the power sums came without the number of nonzero values, so this \
             verdict may rest on fewer than {} of them (give \"nonzero\" in the power-sums file, or \
             Samples::with_nonzero)",
            super::MIN_NONZERO
        ));
    }
    let all_largest = (super::TOP_VALUES as u64).min(v.samples) as usize;
    if v.status == Status::Pass && v.largest_values_known < all_largest {
        out.push_str(&format!(
            "; only {} of the {all_largest} largest values were given, so a handful's joint influence was bounded over \
             those alone (give \"largest\" in the power-sums file, or Samples::with_extremes)",
            v.largest_values_known
        ));
    }
    out
}

fn pass_statement(v: &Verdict) -> String {
    let [m, var] = [&v.checks[0], &v.checks[1]];
    let detects: Vec<String> = [("mean", m), ("Var L", var)]
        .iter()
        .filter_map(|(name, q)| {
            q.detectable_relative_error.map(|d| format!("whose {name} is off by {} or more", percent(d)))
        })
        .collect();
    let influence = v.checks.iter().filter_map(|q| q.influence).fold(0.0, f64::max);
    format!(
        "a renderer {} (either way) fails this check with probability ≥ {:.0} %; a correct one fails with \
         probability ≤ {} (family-wise; the measured rates: docs/library.md); no single value moves a z by more \
         than {}",
        detects.join(", or "),
        v.power * 100.0,
        short(v.false_alarm_rate),
        z_text(influence).trim_start_matches('+')
    )
}

impl Verdict {
    /// Panics with the whole verdict unless it passed: the one line a
    /// renderer's test needs.
    #[track_caller]
    pub fn assert_pass(&self) {
        assert!(self.pass, "{self}");
    }

    /// Whether the samples resolved the question: a pass or a failure
    /// (not [`Status::NotResolved`]).
    pub fn resolved(&self) -> bool {
        self.status != Status::NotResolved
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let spend = self.z_tests_spend.map_or(String::new(), |r| {
            format!(", which correlated {:+.2} spend {}", self.z_correlation, short_rate(r))
        });
        writeln!(
            f,
            "{}: {} samples against the {} model (|z| limit {:.2}: false-alarm rate ≤ {} family-wise; {} % of it on \
             the largest value, the rest Šidák over the {CHECKS} z-tests{spend})",
            self.status.label(),
            self.samples,
            self.model,
            self.z_limit,
            short(self.false_alarm_rate),
            TAIL_SHARE * 100.0,
        )?;
        if let (Some(shape), Some(tail)) = (self.shape, self.tail) {
            writeln!(
                f,
                "  shape: kurtosis {:.4e}, about {:.0} of the values carry the spread (M/kurtosis); largest value {}{:.4e} \
                 (tail bound {:.1e}, test at {:.1e})",
                shape.kurtosis,
                shape.count as f64 / shape.kurtosis,
                if tail.largest_exact { "" } else { "≥ " },
                tail.largest,
                tail.probability_bound,
                tail.rate
            )?;
        }
        for q in &self.checks {
            write_row(f, q, self.z_limit)?;
        }
        for r in &self.failures {
            writeln!(f, "  fails: {r}")?;
        }
        for r in &self.unresolved {
            writeln!(f, "  not resolved: {r}")?;
        }
        write!(f, "  what this check shows: {}", self.statement)
    }
}

fn write_row(f: &mut fmt::Formatter<'_>, q: &QuantityCheck, z_limit: f64) -> fmt::Result {
    write!(f, "  {:<6} predicted {:.8e} ± {:.1e} (quadrature)", q.name, q.predicted.value, q.predicted.quadrature_bar)?;
    // The finite-sphere model's bar is 0 because the model is exact: say so.
    if q.predicted.model_bar > 0.0 {
        write!(f, " ± {:.1e} (model)   ", q.predicted.model_bar)?;
    } else {
        write!(f, ", model exact   ")?;
    }
    let measured = |m: Measured| {
        let rounding =
            if q.rounding_bar > 0.0 { format!(" ± {:.1e} (rounding)", q.rounding_bar) } else { String::new() };
        format!("measured {:.8e} ± {:.1e} (s.e.){rounding}", m.value, m.standard_error)
    };
    match (q.measured, &q.not_resolved) {
        (Some(m), None) => {
            let z = q.z.map_or(format!("beyond ±{:.1e}", f64::MAX), z_text);
            let influence = q
                .influence
                .map_or(String::new(), |i| format!("   one value moves z ≤ {}", z_text(i).trim_start_matches('+')));
            let tail = if disagrees(q, z_limit) {
                format!("   beyond ±{z_limit:.2}")
            } else {
                q.detectable_relative_error.map_or_else(
                    || "   detects no error with certainty".to_string(),
                    |d| format!("   detects {}", percent(d)),
                )
            };
            writeln!(f, "{}   ratio {}   z {z}{influence}{tail}", measured(m), ratio_text(q.ratio, m, q.predicted))
        }
        (Some(m), Some(_)) => writeln!(
            f,
            "{}   ratio {}   z: not resolved (see the reasons)",
            measured(m),
            ratio_text(q.ratio, m, q.predicted)
        ),
        (None, Some(why)) => writeln!(f, "measured: not resolved ({why})"),
        (None, None) => unreachable!("a quantity without a measurement has its reason"),
    }
}
