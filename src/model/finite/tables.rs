//! ⟨𝒞⟩_R(s) of a point light in a Henyey–Greenstein medium along the
//! camera ray, as a piecewise Chebyshev table per pass (P and Q need it at
//! thousands of points, and each value is a quadrature over the sphere's
//! cap, `point::PointLight::moment_cap`). Each pass builds its own with its
//! own rule, so the two passes of P and Q stay independent; the table's
//! relative error joins every value's bar (`chebyshev`).
//!
//! Where the sphere starts to contain the light (d = R) ⟨𝒞⟩_R has a
//! square-root singularity on the outside ([`PointLight::containment_kinks`]):
//! there the table is built in y with x = k ± (y − k)²/w on [k, k ± w], in
//! which the function is analytic ([`KinkMap`]).

use super::point::PointLight;
use super::{FiniteField, OncePerPass};
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::model::field::phase_eval;
use crate::quad::{decay_lengths, CheckRule, Estimate, Failure, Options, Outcome, Rule};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// One built table: the interpolant in y and its variable map.
type Table<T> = Arc<(Piecewise<T>, KinkMap<T>)>;

/// One light's tables, one per (rule, tolerance), each built once (or its
/// failure kept).
type PerLight<T> = OncePerPass<Result<Table<T>, Failure<T>>>;

/// Tables per (light, rule, tolerance), each built once on first use
/// (callers of the same key wait for it: `once_per_pass`), its failure
/// kept.
#[derive(Debug, Clone)]
pub(super) struct Tables<T> {
    map: Arc<Mutex<HashMap<usize, PerLight<T>>>>,
}

/// The table's variable: y = x except on [k, k + w] (or [k − w, k]) on the
/// outside of each containment kink k, where x = k ± (y − k)²/w, so that
/// √(±(x − k)) = |y − k|/√w; the map fixes k and k ± w.
#[derive(Debug, Clone)]
struct KinkMap<T> {
    /// (k, w, side): side +1 maps [k, k + w], −1 maps [k − w, k].
    kinks: Vec<(T, T, i32)>,
}

impl<T: CheckRule> KinkMap<T> {
    fn mapped(&self, v: &T) -> Option<&(T, T, i32)> {
        self.kinks.iter().find(|(k, w, side)| {
            if *side > 0 {
                *v >= *k && *v <= k.clone() + w.clone()
            } else {
                *v <= *k && *v >= k.clone() - w.clone()
            }
        })
    }

    fn x_of(&self, y: &T) -> T {
        match self.mapped(y) {
            Some((k, w, side)) => {
                let d = y.clone() - k.clone();
                k.clone() + y.lit(f64::from(*side)) * d.clone() * d / w.clone()
            }
            None => y.clone(),
        }
    }

    fn y_of(&self, x: &T) -> T {
        match self.mapped(x) {
            Some((k, w, side)) => {
                let root = ((x.clone() - k.clone()).abs() * w.clone()).sqrt();
                k.clone() + x.lit(f64::from(*side)) * root
            }
            None => x.clone(),
        }
    }
}

impl<T> Default for Tables<T> {
    fn default() -> Self {
        Tables { map: Arc::new(Mutex::new(HashMap::new())) }
    }
}

impl<T> Tables<T> {
    /// Evaluations spent building every table so far (failed builds
    /// included), the same whichever thread built which.
    pub(super) fn evaluations(&self) -> u64 {
        self.map.lock().expect("no panic while holding the tables").values().map(|t| t.evaluations()).sum()
    }
}

impl<T: CheckRule> Tables<T> {
    /// ⟨𝒞⟩_R·e^{c₀} of light `index` (the point `p`) at x, with its bar.
    /// Beyond the table's range (past 4^K decay lengths, where the weight
    /// e^{−σs} leaves nothing a goal can see) the value is B/2 ± B/2 with
    /// B the isotropic closed form times max f/(1/4π), a bound. The table is
    /// built to `tol` with the rule and budget of `asking`, the options of
    /// the integral that needs the value.
    pub(super) fn mean(
        &self,
        ff: &FiniteField<T>,
        index: usize,
        p: &PointLight<T>,
        x: &T,
        tol: f64,
        asking: &Options,
    ) -> Outcome<T> {
        let (rule, budget) = (asking.rule, &asking.budget);
        let (lo, end) = ff.table_range();
        if *x > end {
            let f_max = phase_eval(&ff.phase, &x.lit(1.0)).max_of(phase_eval(&ff.phase, &x.lit(-1.0)));
            let half = p.moment_isotropic(ff, x, 1) * f_max * x.pi() * x.lit(2.0);
            return Ok(Estimate::known(half.clone(), half, 1, rule));
        }
        if *x < lo {
            return p.moment_cap(ff, x, 1, &sample_options(x, tol, rule, budget));
        }
        let table = self.get(ff, index, p, tol, rule, budget)?;
        let (table, map) = (&table.0, &table.1);
        let v = table.eval(&map.y_of(x));
        Ok(Estimate::known(v.clone(), v.abs() * table.rel_error.clone(), 1, rule))
    }

    fn get(
        &self,
        ff: &FiniteField<T>,
        index: usize,
        p: &PointLight<T>,
        tol: f64,
        rule: Rule,
        budget: &crate::quad::Budget,
    ) -> Result<Table<T>, crate::quad::Failure<T>> {
        let per_light = self.map.lock().expect("no panic while holding the tables").entry(index).or_default().clone();
        let built = per_light.get_or_build_at(rule, tol, || {
            let table = Self::build(ff, p, tol, rule, budget);
            let spent = match &table {
                Ok(t) => t.0.evaluations,
                Err(e) => e.evaluations,
            };
            (Some(table), spent)
        });
        (*built.expect("every build returns its outcome")).clone()
    }

    /// The table of [`Tables::get`], built.
    fn build(
        ff: &FiniteField<T>,
        p: &PointLight<T>,
        tol: f64,
        rule: Rule,
        budget: &crate::quad::Budget,
    ) -> Result<Table<T>, Failure<T>> {
        let (lo, end) = ff.table_range();
        let mut cuts: Vec<T> = p.ray_breakpoints(ff).into_iter().filter(|b| *b > lo && *b < end).collect();
        let last = cuts.iter().cloned().fold(lo.clone(), |m, b| m.max_of(b));
        for k in decay_lengths(&lo) {
            cuts.push(last.clone() + lo.lit(k) / ff.sigma.clone());
        }
        cuts.push(lo.clone());
        cuts.push(end.clone());
        // Each kink's mapped neighbourhood reaches R/2 outside it (the scale
        // of the cap's change), or half-way to the table's end: no other
        // kink of ⟨𝒞⟩_R lies there (the cuts inside are gradings, mapped).
        let mut kinks = Vec::new();
        for (k, side) in p.containment_kinks(ff) {
            if !(k > lo && k < end) {
                continue;
            }
            let room = if side > 0 { end.clone() - k.clone() } else { k.clone() - lo.clone() };
            let w = (ff.radius.clone() / k.lit(2.0)).min_of(room / k.lit(2.0));
            cuts.push(k.clone() + k.lit(f64::from(side)) * w.clone());
            kinks.push((k, w, side));
        }
        let map = KinkMap { kinks };
        let cuts: Vec<T> = cuts.iter().map(|c| map.y_of(c)).collect();
        let opts: Options = sample_options(&lo, tol, rule, budget);
        let table = Piecewise::build(|y: &T| p.moment_cap(ff, &map.x_of(y), 1, &opts), &cuts, tol / 4.0)?;
        Ok(Arc::new((table, map)))
    }
}
