//! The text of `mcrt-noise optimize`: the best parameters with the bias and
//! noise parts of their RMSE, the alternatives beside them, the gain over
//! q = 1, and the sensitivity of the optimum.

use crate::tuning::alternatives::SMALL_SPHERE_NOTE;
use crate::tuning::search::Scored;
use crate::tuning::sensitivity::Range;
use crate::tuning::{Alternative, Optimum, Searched};
use std::fmt::Write;

/// A parameter set and its predicted error on one line (`q` shown as
/// `q_shown` when given: the cylinder limit has no finite q).
fn line(s: &Scored, q_shown: Option<&str>) -> String {
    let p = s.parameters;
    let r = s.rmse;
    let q = q_shown.map_or_else(|| fmt_q(p.q), str::to_string);
    let bias = match (r.relative_bias, r.relative_bias_error) {
        (Some(b), Some(e)) => format!("bias {b:.3e} ± {e:.1e}"),
        _ => "bias not predicted".to_string(),
    };
    format!(
        "q = {:<9} R = {:<10} N_F = {:<9} N_B = {:<7} rel. RMSE {:.4e} ± {:.1e} ({bias}, noise {:.3e} ± {:.1e}; M = {} iterations of {:.4e} ± {:.1e} s)",
        q,
        format!("{:.4e}", p.radius),
        p.forward_rays,
        p.camera_rays,
        r.relative,
        r.error,
        r.relative_noise,
        r.relative_noise_error,
        r.iterations,
        r.seconds_per_iteration,
        r.seconds_per_iteration_error
    )
}

/// q to 4 significant digits (q is in [1e-6, 1]: `{:.4}` printed
/// q = 1e-5 as `0.0000`).
fn fmt_q(q: f64) -> String {
    if q == 1.0 {
        "1".into()
    } else {
        significant(q)
    }
}

/// A positive number to 4 significant digits: plain in [0.1, 1000),
/// scientific beyond (a ratio of 3e-7 was printed `0.000`).
fn significant(x: f64) -> String {
    if (0.1..1000.0).contains(&x.abs()) {
        let decimals = 3 - x.abs().log10().floor() as i32;
        format!("{x:.*}", decimals.max(0) as usize)
    } else {
        format!("{x:.3e}")
    }
}

fn range(name: &str, r: &Range, integer: bool) -> String {
    let v = |x: f64| if integer { format!("{x:.0}") } else { format!("{x:.4e}") };
    let lo = if r.lo_at_bound { format!("{} (the bound)", v(r.lo)) } else { v(r.lo) };
    let hi = if r.hi_at_bound { format!("{} (the bound)", v(r.hi)) } else { v(r.hi) };
    format!("  {name:<4} [{lo}, {hi}]")
}

/// The report of an optimisation of `scene_label`.
pub fn text(scene_label: &str, o: &Optimum) -> String {
    let mut s = String::new();
    let memory = o.max_spheres.map_or(String::new(), |m| format!(", at most {m} spheres per iteration"));
    writeln!(s, "{scene_label}: budget {} s of one core{memory}", o.budget).unwrap();
    writeln!(s, "costs: {}", o.costs.source).unwrap();
    if o.searched == Searched::StandardMethod && !matches!(o.scattering_orders.as_str(), "0" | "1") {
        writeln!(s, "model: finite-sphere, exact at every R for every scattering order at q = 1 and N_B = 1 (the standard method), the only q and N_B where it gives Var L of every order (other q and N_B need the correlations of two spheres of every order, not yet in the oracle: docs/model.md §10.4): bias b(R) predicted; q = 1 and N_B = 1 held, R searched over [{:.3e}, {:.3e}]", o.radius_range.0, o.radius_range.1).unwrap();
    } else if o.searched == Searched::StandardMethod {
        writeln!(s, "model: finite-sphere, exact at every R for uncollided and single-scattered light at q = 1 and N_B = 1 (the standard method), the only q and N_B where it gives Var L of single-scattered light (other q and N_B need the correlations of two spheres, not yet in the oracle: docs/model.md §9.7): bias b(R) predicted; q = 1 and N_B = 1 held, R searched over [{:.3e}, {:.3e}]", o.radius_range.0, o.radius_range.1).unwrap();
    } else if o.bias_predicted {
        writeln!(s, "model: finite-sphere (exact at every R for uncollided light): bias b(R) predicted; R searched over [{:.3e}, {:.3e}]", o.radius_range.0, o.radius_range.1).unwrap();
    } else {
        let within = o.radius_range_requested.map_or(String::new(), |(lo, hi)| {
            format!(" (within --radius-range [{lo:.3e}, {hi:.3e}], which is not searched)")
        });
        if o.best.rmse.relative_bias.is_some() {
            writeln!(s, "model: small-sphere for Var L (the finite-sphere model gives this scene's exact mean, hence the bias at its R, the same for every q, N_F, N_B, but not yet its Var L: docs/model.md §9.9): R is held at the scene's {}{within} and only q, N_F, N_B are chosen", o.radius_range.0).unwrap();
        } else {
            writeln!(s, "model: small-sphere (the scene has scattered light whose Var L the finite-sphere model does not cover, and its exact mean is not computed here: a beam in a Henyey–Greenstein medium, or its computation failed): the bias is NOT predicted, so R is held at the scene's {}{within} and only q, N_F, N_B are chosen, for the noise alone", o.radius_range.0).unwrap();
        }
    }
    writeln!(s, "RMSE = √(bias² + Var L/M)/μ(0), M = ⌊T/τ⌋; the bars are the quadrature's and the time's standard errors (the cost fit's and the rates'; the cost model's own accuracy: docs/choosing-parameters.md)").unwrap();
    writeln!(s).unwrap();
    let standard = o.searched == Searched::StandardMethod;
    let label = if standard { "best at q = 1, N_B = 1 (finite-sphere model, exact)" } else { "best" };
    writeln!(s, "{label}: {}", line(&o.best, None)).unwrap();
    writeln!(s).unwrap();
    let every_order = !matches!(o.scattering_orders.as_str(), "0" | "1");
    if standard && every_order {
        writeln!(s, "beside it (ratio: its RMSE over the best's, every one by the finite-sphere model of every order at q = 1, N_B = 1; the small-sphere model has no Var L of every order):").unwrap();
    } else if standard {
        writeln!(s, "beside it (ratio: its RMSE over the best's; a ratio below 1 is a prediction of the small-sphere model, whose own error at the scene's R is not in its bar):").unwrap();
    } else {
        writeln!(s, "beside it (ratio: its RMSE over the best's; the cylinder limit is another integration volume, with its own cost, and may beat the spheres):").unwrap();
    }
    for a in &o.alternatives {
        match &a.scored {
            Ok(x) => {
                let ratio = x.rmse.relative / o.best.rmse.relative;
                let shown = line(x, a.name.starts_with("q → 0").then_some("→ 0"));
                writeln!(s, "  {}  (ratio {})\n    {shown}\n    {}", a.name, significant(ratio), a.note).unwrap();
            }
            Err(why) => writeln!(s, "  {}: {why}", a.name).unwrap(),
        }
    }
    let (lo, hi) = o.radius_range;
    let [small, inside, outside] =
        if standard { below_the_best(&o.alternatives, o.best.rmse.relative, (lo, hi)) } else { Default::default() };
    if !inside.is_empty() {
        writeln!(s, "\nbelow the best: {} (by the same exact model, at a radius inside the searched range: the search over R — a grid of 4 radii per decade, then golden section about its best — missed it)", inside.join("; ")).unwrap();
    }
    if !outside.is_empty() {
        writeln!(s, "\nbelow the best: {} (by the same exact model, at a radius outside the searched range [{lo:.3e}, {hi:.3e}]: widen --radius-range to search there)", outside.join("; ")).unwrap();
    }
    if !small.is_empty() {
        writeln!(s, "\nbelow the best: {} (the small-sphere model predicts less error with other q and N_B at the scene's R; the finite-sphere model does not yet give Var L there, so the gap is not proven)", small.join("; ")).unwrap();
    }
    if let Some(Ok(q1)) = o.alternatives.iter().find(|a| a.name.starts_with("q = 1")).map(|a| a.scored.as_ref()) {
        writeln!(
            s,
            "\ngain over q = 1: its RMSE is {}× the best's{}",
            significant(q1.rmse.relative / o.best.rmse.relative),
            if o.best.parameters.q == 1.0 { " (the optimum is q = 1 itself)" } else { "" }
        )
        .unwrap();
    }
    writeln!(s, "\nsensitivity: each parameter's contiguous range around the optimum with RMSE within 10 % of the best, the others at the optimum:")
        .unwrap();
    let held = if matches!(o.scattering_orders.as_str(), "0" | "1") {
        "held at 1 (the finite-sphere model of single-scattered light)"
    } else {
        "held at 1 (the finite-sphere model of every scattering order)"
    };
    match &o.sensitivity.q {
        Some(q) => writeln!(s, "{}", range("q", q, false)).unwrap(),
        None => writeln!(s, "  q    {held}").unwrap(),
    }
    match &o.sensitivity.radius {
        Some(r) => writeln!(s, "{}", range("R", r, false)).unwrap(),
        None => writeln!(s, "  R    held at the scene's (bias not predicted)").unwrap(),
    }
    writeln!(s, "{}", range("N_F", &o.sensitivity.forward_rays, true)).unwrap();
    match &o.sensitivity.camera_rays {
        Some(n_b) => writeln!(s, "{}", range("N_B", n_b, true)).unwrap(),
        None => writeln!(s, "  N_B  {held}").unwrap(),
    }
    s
}

/// The alternatives with less predicted RMSE than `best`, by the
/// small-sphere model (not proven: its error at R is not in its bar), or by
/// the same exact model at a radius inside the searched `range` (a miss of
/// the search) or outside it: their names in that order.
fn below_the_best(alternatives: &[Alternative], best: f64, (lo, hi): (f64, f64)) -> [Vec<&str>; 3] {
    let mut out: [Vec<&str>; 3] = Default::default();
    for a in alternatives {
        let Ok(x) = &a.scored else { continue };
        if x.rmse.relative >= best {
            continue;
        }
        let r = x.parameters.radius;
        let which = if a.note.contains(SMALL_SPHERE_NOTE) || a.name.contains("small-sphere") {
            0
        } else if lo <= r && r <= hi {
            1
        } else {
            2
        };
        out[which].push(a.name.as_str());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{below_the_best, fmt_q, significant, Alternative, SMALL_SPHERE_NOTE};
    use crate::tuning::cost::{IterationCounts, Parameters};
    use crate::tuning::objective::Rmse;
    use crate::tuning::search::Scored;

    /// Alternatives below the best are told apart by what scored them and
    /// where their R lies: the small-sphere model's (by name or note), the
    /// exact model's inside the searched range (a miss of the search) and
    /// outside it (`--radius-range` too narrow); those at or above the best
    /// and those not scored are not listed.
    #[test]
    fn alternatives_below_the_best_are_told_apart() {
        let alt = |name: &str, note: &str, radius: f64, relative: f64| Alternative {
            name: name.into(),
            scored: Ok(Scored {
                parameters: Parameters { q: 1.0, radius, forward_rays: 1, camera_rays: 1 },
                rmse: Rmse {
                    relative,
                    error: 0.0,
                    relative_bias: None,
                    relative_bias_error: None,
                    relative_noise: relative,
                    relative_noise_error: 0.0,
                    iterations: 1,
                    seconds_per_iteration: 1.0,
                    seconds_per_iteration_error: 0.0,
                },
                counts: IterationCounts {
                    trials: 1.0,
                    forward_rays: 1.0,
                    camera_rays: 1.0,
                    segments: 1.0,
                    spheres: 1.0,
                    sort_work: 0.0,
                    search_work: 0.0,
                    hits: 0.0,
                    hg_evaluations: 0.0,
                },
            }),
            note: note.into(),
        };
        let own_note = format!("q = 0.5, R = 0.2; {SMALL_SPHERE_NOTE}");
        let alternatives = vec![
            alt("the scene's own parameters", &own_note, 0.2, 0.5),
            alt("R of the asymptotic rule", "", 0.09, 0.5),
            alt("q = 1 at R inside", "", 0.2, 0.5),
            alt("q, N_F, N_B free (small-sphere model)", "", 0.2, 0.5),
            alt("worse", "", 0.2, 2.0),
            Alternative { name: "not scored".into(), scored: Err("why".into()), note: String::new() },
        ];
        let [small, inside, outside] = below_the_best(&alternatives, 1.0, (0.15, 0.3));
        assert_eq!(small, ["the scene's own parameters", "q, N_F, N_B free (small-sphere model)"]);
        assert_eq!(inside, ["q = 1 at R inside"]);
        assert_eq!(outside, ["R of the asymptotic rule"]);
    }

    /// The outside probe, item 12: q = 1e-5 printed `q = 0.0000` and a ratio
    /// of 3e-7 `(ratio 0.000)`. Every value keeps 4 significant digits.
    #[test]
    fn small_values_keep_four_significant_digits() {
        for (x, shown) in [(1e-5, "1.000e-5"), (0.5, "0.5000"), (0.0123456, "1.235e-2"), (0.25, "0.2500")] {
            assert_eq!(fmt_q(x), shown);
        }
        for (x, shown) in
            [(2.954e-7, "2.954e-7"), (1.0, "1.000"), (100.005, "100.0"), (12.34, "12.34"), (5e3, "5.000e3")]
        {
            assert_eq!(significant(x), shown);
        }
    }
}
