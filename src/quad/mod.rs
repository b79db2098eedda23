//! Adaptive quadrature that is never silently wrong, in f64 and MPFR.
//!
//! [`integrate`] computes ∫ₐᵇ f over a finite or semi-infinite interval and
//! returns either an [`Estimate`] (value, error bar, evaluation count) whose
//! error bar has been *cross-checked*, or a [`Failure`] that says why no bar
//! could be given (the best guess travels with it, clearly labelled). The two
//! cannot be confused: a `Failure` is an `Err`.
//!
//! How a result is earned (details and limits: `docs/quadrature.md`):
//! 1. **Pieces.** The interval is cut at the caller's breakpoints; a
//!    semi-infinite piece [a, ∞) is mapped to [0, 1) (rationally, or
//!    exponentially when the caller declares a decay rate).
//! 2. **Structure scan** ([`Structure::Unknown`], the default). The integrand
//!    is sampled on a grid that is geometric towards every piece's ends and
//!    uniform inside; every change between zero and non-zero is located by
//!    bisection to the working precision and becomes a breakpoint, and any
//!    non-finite value is an error. This is how the kink at t = 2R/sin ϑ of the
//!    paper's kernel (23) is found when nobody passes it.
//! 3. **Primary rule:** tanh–sinh on each piece, refined level by level,
//!    pieces bisected at a level cap, under global error control.
//! 4. **Cross-check:** the same pieces integrated again by an unrelated rule
//!    (adaptive Gauss–Legendre with nodes computed at the working
//!    precision: 10 points and bisection in f64, prec/2 points against
//!    prec/4 in MPFR), in a smoothing substitution. The reported bar is max(e_p, |p − c| + e_c).
//! 5. **All-zero guard:** if every sample was exactly zero, no bound can be
//!    given (the support may be narrower than the scan resolves): `Failure`.
//!
//! Nesting: [`integrate_nested`] runs a scale pass, a primary pass and an
//! independent check pass (check rule at every level); inner error bars are
//! integrated into the outer one, evaluation counts add up, and an inner
//! `Failure` fails the outer integral.
//!
//! For deep nests at loose goals, where each level's cost is its floor per
//! piece, a caller may choose [`Rule::Kronrod`] (7–15-point Gauss–Kronrod
//! panels, cross-checked by [`Rule::KronrodCheck`], 10–21 points in another
//! substitution) instead of the pair above (`docs/quadrature.md`).

mod budget;
mod check;
mod control;
mod kronrod;
mod mapped;
mod nested;
mod nodes;
pub(crate) use nodes::{cached, gauss_legendre};
mod scan;
mod tanh_sinh;

use crate::real::Real;
#[cfg(feature = "mpfr")]
pub use budget::DEFAULT_EVALUATIONS_MPFR;
pub use budget::{Budget, CHECK_EVERY, DEFAULT_EVALUATIONS};
pub use check::CheckRule;
pub(crate) use mapped::{Mapped, Piece, TailMap};
pub use nested::{integrate_nested, integrate_within_pass};
use std::fmt;

/// What the caller knows of the integrand's structure.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Structure {
    /// Breakpoints, if any, are hints: the engine scans for more and refuses
    /// to vouch for an integrand that was zero at every sample.
    #[default]
    Unknown,
    /// The caller has derived every kink, jump and edge of support and passes
    /// them as breakpoints; the integrand is smooth (or has only integrable
    /// endpoint singularities) inside each piece. No scan is made. The
    /// cross-check still runs.
    Declared,
}

/// Accuracy goals and limits of one integration.
#[derive(Debug, Clone)]
pub struct Options {
    /// Relative tolerance on the value.
    pub rel_tol: f64,
    /// Absolute tolerance (the goal is max(abs_tol, rel_tol·|I|)).
    pub abs_tol: f64,
    /// Budget of integrand calls at this level (a cap per level; the whole
    /// computation shares `budget`).
    pub max_evals: u64,
    /// The evaluation budget (and optional deadline) of the whole
    /// computation, shared by every level and pass that clones these options.
    pub budget: Budget,
    /// Whether the breakpoints are hints ([`Structure::Unknown`], a scan runs) or complete.
    pub structure: Structure,
    /// Run the cross-check (on by default; turning it off is for benchmarks
    /// that separate the two rules' costs, never for reported values).
    pub cross_check: bool,
    /// Refuse an integrand that was zero at every sample (on by default).
    /// [`integrate_nested`] turns it off in the options it hands to inner
    /// integrals, where exact zeros are ordinary (f64 underflow of e^{−s} far
    /// out); the guard then acts on the outer integral, which is zero
    /// everywhere exactly when every inner one is.
    pub zero_guard: bool,
    /// Which rule computes the value; the other one ([`Rule::other`])
    /// cross-checks it. [`integrate_nested`] runs its second, independent
    /// pass with that other rule at every level.
    pub rule: Rule,
}

/// The quadrature rules of the engine, in two pairs that cross-check each
/// other: tanh–sinh and [`Rule::Check`] (the default), and for deep nests
/// at loose goals [`Rule::Kronrod`] and [`Rule::KronrodCheck`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum Rule {
    /// Tanh–sinh, refined level by level (the default primary rule).
    #[default]
    TanhSinh,
    /// Adaptive bisection of Gauss–Legendre panels in a smoothing
    /// substitution (`check` module).
    Check,
    /// Adaptive bisection of 7–15-point Gauss–Kronrod panels in another
    /// smoothing substitution (`kronrod` module): 15 evaluations a panel,
    /// for nested integrals at loose goals. Cross-checked by
    /// [`Rule::KronrodCheck`]. Its nodes are f64 constants: above 53 bits
    /// tanh–sinh runs instead, and the estimate names it.
    Kronrod,
    /// The cross-check of [`Rule::Kronrod`]: 10–21-point Gauss–Kronrod
    /// panels in the check rule's substitution; above 53 bits the check
    /// rule runs instead.
    KronrodCheck,
}

impl Rule {
    /// The rule that cross-checks this one.
    pub fn other(self) -> Rule {
        match self {
            Rule::TanhSinh => Rule::Check,
            Rule::Check => Rule::TanhSinh,
            Rule::Kronrod => Rule::KronrodCheck,
            Rule::KronrodCheck => Rule::Kronrod,
        }
    }
    /// The rule that runs at the precision `bits`: the Gauss–Kronrod pair
    /// only up to 53 bits (its nodes are f64 constants), tanh–sinh and the
    /// check rule above.
    fn at_precision(self, bits: u32) -> Rule {
        match self {
            Rule::Kronrod if bits > 53 => Rule::TanhSinh,
            Rule::KronrodCheck if bits > 53 => Rule::Check,
            other => other,
        }
    }
    fn name<T: CheckRule>(self) -> &'static str {
        match self {
            Rule::TanhSinh => "tanh-sinh",
            Rule::Check => T::CHECK_NAME,
            Rule::Kronrod => "Gauss-Kronrod (7-15 points, bisection)",
            Rule::KronrodCheck => "Gauss-Kronrod (10-21 points, bisection)",
        }
    }
}

impl Options {
    /// Relative tolerance `rel_tol`, no absolute floor, unknown structure.
    pub fn rel(rel_tol: f64) -> Options {
        Options {
            rel_tol,
            abs_tol: 0.0,
            max_evals: 2_000_000,
            budget: Budget::default(),
            structure: Structure::Unknown,
            cross_check: true,
            zero_guard: true,
            rule: Rule::TanhSinh,
        }
    }

    /// These options with [`Structure::Declared`]: the caller's breakpoints are complete, no scan.
    pub fn declared(mut self) -> Options {
        self.structure = Structure::Declared;
        self
    }

    /// These options with the absolute tolerance `abs_tol`.
    pub fn with_abs_tol(mut self, abs_tol: f64) -> Options {
        self.abs_tol = abs_tol;
        self
    }

    /// These options with `budget` shared by every level computed with them.
    pub fn with_budget(mut self, budget: Budget) -> Options {
        self.budget = budget;
        self
    }

    /// These options with an evaluation budget of `max_evals` at this level.
    pub fn with_max_evals(mut self, max_evals: u64) -> Options {
        self.max_evals = max_evals;
        self
    }
}

/// Integration interval: `[lo, hi]`, or `[lo, ∞)` when `hi` is `None`.
#[derive(Debug, Clone)]
pub struct Domain<T> {
    /// Lower limit (finite).
    pub lo: T,
    /// Upper limit, finite and above `lo`; `None` for ∞.
    pub hi: Option<T>,
    /// Interior points where the integrand is not smooth (kinks, jumps, edges
    /// of support). Points outside (lo, hi) are ignored.
    pub breakpoints: Vec<T>,
    /// A known exponential decay rate λ of the integrand. For [lo, ∞) the
    /// tail's variable is then u = 1 − e^{−λ(t − lo)} (so e^{−λt} dt is flat
    /// in u) instead of the default rational map u = (t − lo)/(1 + t − lo),
    /// which suits algebraic decay, and the tail is cut at decay lengths; a
    /// finite domain longer than 2·4^K decay lengths is cut at them too.
    pub decay: Option<T>,
}

impl<T: Real> Domain<T> {
    /// `[lo, hi]`, no breakpoints, no decay rate (needs lo < hi, both finite).
    pub fn finite(lo: T, hi: T) -> Self {
        Domain { lo, hi: Some(hi), breakpoints: Vec::new(), decay: None }
    }
    /// `[lo, ∞)`, no breakpoints, no decay rate (algebraic tail map).
    pub fn semi_infinite(lo: T) -> Self {
        Domain { lo, hi: None, breakpoints: Vec::new(), decay: None }
    }
    /// Declares exponential decay at rate `rate` > 0.
    pub fn with_decay(mut self, rate: T) -> Self {
        self.decay = Some(rate);
        self
    }
    /// Adds `points` to the breakpoints (kinks, jumps, edges of support).
    pub fn with_breakpoints(mut self, points: impl IntoIterator<Item = T>) -> Self {
        self.breakpoints.extend(points);
        self
    }
}

/// A converged, cross-checked integral.
#[derive(Debug, Clone)]
pub struct Estimate<T> {
    /// The integral's value, from the primary rule.
    pub value: T,
    /// Bound on |value − exact|: the larger of the primary rule's estimate and
    /// its distance to the cross-check, plus propagated inner errors.
    pub error: T,
    /// Integrand evaluations, counting those of nested inner integrals.
    pub evaluations: u64,
    /// The cross-check's value (equal to `value` when the check was off).
    pub check_value: T,
    /// Pieces the primary rule ended with.
    pub pieces: usize,
    /// Breakpoints found by the structure scan (beyond those passed in).
    pub found_breakpoints: usize,
    /// The rule that computed `value`.
    pub rule: Rule,
}

impl<T: Real> Estimate<T> {
    /// The sum of two independent estimates: values, bars, check values and
    /// evaluations add.
    pub fn plus(self, other: Estimate<T>) -> Estimate<T> {
        Estimate {
            value: self.value + other.value,
            error: self.error + other.error,
            evaluations: self.evaluations + other.evaluations,
            check_value: self.check_value + other.check_value,
            ..self
        }
    }

    /// This estimate times the constant `k` (value, bar and check value).
    pub fn scaled(self, k: &T) -> Estimate<T> {
        Estimate {
            value: self.value * k.clone(),
            error: self.error * k.abs(),
            check_value: self.check_value * k.clone(),
            ..self
        }
    }

    /// A value obtained without quadrature (a closed form, a convergent
    /// series, an exact zero, a sum of known parts), with its bar and the
    /// evaluations it cost.
    pub fn known(value: T, error: T, evaluations: u64, rule: Rule) -> Self {
        Estimate { check_value: value.clone(), value, error, evaluations, pieces: 0, found_breakpoints: 0, rule }
    }
}

/// An integral for which no error bar can be vouched for.
#[derive(Debug, Clone)]
pub struct Failure<T> {
    /// Why no bar could be given (printed after `NOT CONVERGED: `).
    pub reason: String,
    /// The best value available, *not* to be reported as a result.
    pub best_guess: Option<T>,
    /// Error estimate at the time of failure, if any.
    pub error_estimate: Option<T>,
    /// Integrand evaluations spent before failing.
    pub evaluations: u64,
}

impl<T: Real> fmt::Display for Failure<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "NOT CONVERGED: {}", self.reason)?;
        if let Some(v) = &self.best_guess {
            write!(f, " (unreliable best guess {:e}", v.to_f64())?;
            if let Some(e) = &self.error_estimate {
                write!(f, " ± {:e}", e.to_f64_up())?;
            }
            write!(f, ")")?;
        }
        write!(f, " after {} evaluations", self.evaluations)
    }
}

impl<T: Real> std::error::Error for Failure<T> {}

impl<T: Real> Failure<T> {
    /// The failure of an integral whose value is scaled by `k`: its best
    /// guess and error estimate scaled alike (as [`Estimate::scaled`]).
    pub fn scaled(self, k: &T) -> Failure<T> {
        Failure {
            best_guess: self.best_guess.map(|v| v * k.clone()),
            error_estimate: self.error_estimate.map(|e| e * k.abs()),
            ..self
        }
    }

    /// The failure of one part of a sum: its best guess is not the sum's.
    pub fn of_a_part(self) -> Failure<T> {
        Failure { best_guess: None, error_estimate: None, ..self }
    }
}

/// Result of an integration.
pub type Outcome<T> = Result<Estimate<T>, Failure<T>>;

/// One sample of an integrand: its value, the error bar of that value (0 for
/// a plain function, the inner integral's bar when nested) and the
/// evaluations it cost.
#[derive(Debug, Clone)]
pub struct Sample<T> {
    /// The integrand's value at the node.
    pub value: T,
    /// Bar of `value` (0 for a plain function).
    pub error: T,
    /// Integrand evaluations this sample cost (1 for a plain function).
    pub evaluations: u64,
}

/// ∫ f over `domain` for a plain integrand `f(x) -> T`.
pub fn integrate<T: CheckRule, F: FnMut(&T) -> T>(mut f: F, domain: &Domain<T>, opts: &Options) -> Outcome<T> {
    integrate_samples(&mut |x: &T| Ok(Sample { error: x.lit(0.0), value: f(x), evaluations: 1 }), domain, opts)
}

/// The integrand as the engine sees it, on a piece in its own variable.
pub(crate) type SampleFn<'a, T> = dyn FnMut(&T) -> Result<Sample<T>, Failure<T>> + 'a;

fn integrate_samples<T: CheckRule>(f: &mut SampleFn<'_, T>, domain: &Domain<T>, opts: &Options) -> Outcome<T> {
    validate(domain, opts)?;
    let graded = with_decay_lengths(domain);
    let domain = graded.as_ref().unwrap_or(domain);
    let out = match split_tail(domain) {
        Some(split) => integrate_split(f, domain, split, opts),
        None => integrate_pieces(f, domain, opts),
    };
    out.and_then(|e| within_budget(e, opts))
}

/// A converged estimate, unless the computation has spent more than its
/// budget (its first step met the goal between two checks of the budget):
/// then a failure naming the budget, the estimate as its best guess.
fn within_budget<T: Real>(e: Estimate<T>, opts: &Options) -> Outcome<T> {
    match opts.budget.overrun() {
        None => Ok(e),
        Some(reason) => Err(Failure {
            reason: format!("{reason}; the integral met its goal only past it"),
            best_guess: Some(e.value),
            error_estimate: Some(e.error),
            evaluations: e.evaluations,
        }),
    }
}

/// The cuts of a decaying tail, in decay lengths: 1, 4, 16, … 4^K with
/// e^{−4^K} below eps² at the precision of `like` (4^K > 2·prec·ln 2).
pub(crate) fn decay_lengths<T: Real>(like: &T) -> Vec<f64> {
    let needed = 2.0 * like.prec() as f64 * std::f64::consts::LN_2;
    let mut lengths = vec![1.0f64];
    while *lengths.last().expect("non-empty") < needed {
        lengths.push(lengths.last().expect("non-empty") * 4.0);
    }
    lengths
}

/// For [lo, ∞) with a declared decay rate λ: breakpoints at b + 4^k/λ,
/// k = 0 … K, beyond the last breakpoint b (or lo), and at lo + 4^k/λ too
/// when b lies beyond 2·4^K decay lengths (likewise for a finite domain
/// that long, which gets only the latter), with e^{−4^K} below the
/// working precision squared. The content of the tail then lies in finite
/// pieces on which both rules converge geometrically, and the mapped
/// remainder [b + 4^K/λ, ∞) holds nothing the goal can see. Without them,
/// an algebraic factor of the integrand (1/s², or ln s through the map)
/// becomes a logarithmic endpoint singularity of the mapped tail, on which
/// Gauss–Legendre converges only algebraically.
fn with_decay_lengths<T: Real>(domain: &Domain<T>) -> Option<Domain<T>> {
    let rate = domain.decay.as_ref()?;
    if !(rate.clone() > rate.lit(0.0)) || !rate.is_finite() {
        return None;
    }
    let lengths = decay_lengths(&domain.lo);
    let from_lo = || lengths.iter().map(|&k| domain.lo.clone() + rate.lit(k) / rate.clone());
    // A piece reaching far into the decay (a beam nearly parallel to the
    // camera ray leaves it 10⁶ decay lengths away) would hold its content
    // in a sliver at its start, which the check rule's first panel cannot
    // see: such a piece is cut at the decay lengths from lo.
    let reach = domain.lo.clone() + rate.lit(2.0 * lengths.last().expect("non-empty")) / rate.clone();
    if let Some(hi) = &domain.hi {
        return (*hi > reach).then(|| domain.clone().with_breakpoints(from_lo()));
    }
    let b = split_tail(domain).unwrap_or_else(|| domain.lo.clone());
    let mut extra: Vec<T> = lengths.iter().map(|&k| b.clone() + rate.lit(k) / rate.clone()).collect();
    if b > reach {
        extra.extend(from_lo());
    }
    Some(domain.clone().with_breakpoints(extra))
}

/// The last breakpoint of a semi-infinite domain, if any: [lo, ∞) is then
/// integrated as the finite [lo, b] (pieces in t itself) plus the tail
/// [b, ∞) alone in the mapped variable, so that the map (and a declared
/// decay rate) concerns the tail only and cannot squeeze the finite pieces
/// into the last ulps below u = 1.
fn split_tail<T: Real>(domain: &Domain<T>) -> Option<T> {
    if domain.hi.is_some() {
        return None;
    }
    domain.breakpoints.iter().filter(|p| p.is_finite() && **p > domain.lo).cloned().fold(None, |acc: Option<T>, p| {
        Some(match acc {
            Some(a) if a > p => a,
            _ => p,
        })
    })
}

/// ∫ over [lo, b] plus ∫ over [b, ∞); bars and counts add. The head meets
/// the relative goal (and half the absolute one); the tail, usually a small
/// remainder, is held to the goal at the head's scale, not its own (its own
/// relative goal can be below the rounding noise of a nested inner integral).
fn integrate_split<T: CheckRule>(f: &mut SampleFn<'_, T>, domain: &Domain<T>, b: T, opts: &Options) -> Outcome<T> {
    let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
    let head =
        Domain { lo: domain.lo.clone(), hi: Some(b.clone()), breakpoints: domain.breakpoints.clone(), decay: None };
    let tail = Domain { lo: b, hi: None, breakpoints: Vec::new(), decay: domain.decay.clone() };
    // The all-zero guard judges the whole domain: a zero tail is ordinary.
    let h = integrate_pieces(f, &head, &Options { zero_guard: false, ..half.clone() })?;
    let tail_abs = (opts.rel_tol * h.value.abs().to_f64() / 2.0).max(half.abs_tol);
    let t = integrate_pieces(f, &tail, &Options { zero_guard: false, abs_tol: tail_abs, ..half })?;
    if opts.zero_guard && opts.structure == Structure::Unknown && h.value.is_zero() && t.value.is_zero() {
        return Err(Failure {
            reason: "the integrand was exactly zero at every sample: a support narrower than the scan resolves cannot be excluded".into(),
            best_guess: Some(h.value.lit(0.0)),
            error_estimate: None,
            evaluations: h.evaluations + t.evaluations,
        });
    }
    Ok(Estimate {
        value: h.value + t.value,
        error: h.error + t.error,
        evaluations: h.evaluations + t.evaluations,
        check_value: h.check_value + t.check_value,
        pieces: h.pieces + t.pieces,
        found_breakpoints: h.found_breakpoints + t.found_breakpoints,
        rule: h.rule,
    })
}

fn integrate_pieces<T: CheckRule>(f: &mut SampleFn<'_, T>, domain: &Domain<T>, opts: &Options) -> Outcome<T> {
    let lo = domain.lo.clone();
    // The piece variable: t itself, or u with t = lo + u/(1 − u).
    let tail = match (&domain.hi, &domain.decay) {
        (Some(_), _) => None,
        (None, Some(rate)) if rate.clone() > rate.lit(0.0) && rate.is_finite() => {
            Some((lo.clone(), TailMap::Exponential(rate.clone())))
        }
        (None, _) => Some((lo.clone(), TailMap::Rational)),
    };
    let to_piece_var = |t: &T| -> T {
        match &tail {
            None => t.clone(),
            Some((a, map)) => map.to_u(a, t),
        }
    };
    let (a, b) = match &domain.hi {
        Some(hi) => (lo.clone(), hi.clone()),
        None => (lo.lit(0.0), lo.lit(1.0)),
    };
    let mut cuts: Vec<T> = domain
        .breakpoints
        .iter()
        .filter(|p| p.is_finite() && **p > domain.lo && domain.hi.as_ref().is_none_or(|h| *p < h))
        .map(to_piece_var)
        .collect();
    let mut mapped = Mapped::new(f, tail.clone(), &opts.budget);

    let declared_count = cuts.len();
    if opts.structure == Structure::Unknown {
        cuts.extend(scan::find_edges(&mut mapped, &a, &b, &cuts)?);
    }
    cuts.sort_by(|x, y| x.partial_cmp(y).expect("finite breakpoints"));
    cuts.dedup_by(|x, y| x == y);
    let found = cuts.len().saturating_sub(declared_count);
    let edges = merged_edges(&a, &b, cuts);
    let pieces: Vec<Piece<T>> =
        edges.windows(2).filter(|w| w[0] < w[1]).map(|w| Piece { a: w[0].clone(), b: w[1].clone() }).collect();

    // Each rule aims at a quarter of the goal (see `reconcile`).
    let quarter = Options { rel_tol: opts.rel_tol / 4.0, abs_tol: opts.abs_tol / 4.0, ..opts.clone() };
    let run = |rule: Rule, mapped: &mut Mapped<'_, '_, T>| match rule {
        Rule::TanhSinh => tanh_sinh::integrate(mapped, &pieces, &quarter),
        Rule::Check => check::adaptive(mapped, &pieces, &quarter),
        Rule::Kronrod => kronrod::adaptive(&kronrod::G7_K15, check::Map::Cosine, mapped, &pieces, &quarter),
        Rule::KronrodCheck => kronrod::adaptive(&kronrod::G10_K21, check::Map::Cubic, mapped, &pieces, &quarter),
    };
    let bits = a.prec();
    let (rule, other) = (opts.rule.at_precision(bits), opts.rule.other().at_precision(bits));
    let primary = run(rule, &mut mapped)?;
    let check = if opts.cross_check { Some(run(other, &mut mapped)?) } else { None };
    if opts.structure == Structure::Unknown && opts.zero_guard && mapped.tally.all_zero {
        return Err(mapped.fail(
            "the integrand was exactly zero at every sample: a support narrower than the scan resolves cannot be excluded (pass its edges as breakpoints and declare the structure)".into(),
            Some((a.lit(0.0), a.lit(f64::INFINITY))),
        ));
    }
    let evaluations = mapped.tally.evaluations;
    let estimate = |r: &RuleResult<T>| Estimate {
        value: r.value.clone(),
        error: r.error.clone(),
        evaluations,
        check_value: r.value.clone(),
        pieces: r.pieces,
        found_breakpoints: found,
        rule,
    };
    let check = check.map(|c| Estimate { rule: other, ..estimate(&c) });
    reconcile(estimate(&primary), check, opts)
}

/// The piece ends a, cuts…, b, without pieces narrower than 8 ulps of
/// their position: two kinks that close (the ends of a hit window of width
/// 10⁻¹⁷ at the camera, say) are one kink at the working precision, and a
/// sliver piece between them is below what either rule can place nodes in
/// (tanh–sinh drops nodes within 4 ulps of an end), so it would only spend
/// the budget.
fn merged_edges<T: Real>(a: &T, b: &T, cuts: Vec<T>) -> Vec<T> {
    let close = |x: &T, y: &T| {
        let scale = x.abs().max_of(y.abs());
        (x.clone() - y.clone()).abs() <= scale * x.eps() * x.lit(8.0)
    };
    let mut edges = vec![a.clone()];
    for c in cuts {
        if !close(&c, edges.last().expect("non-empty")) && !close(&c, b) {
            edges.push(c);
        }
    }
    edges.push(b.clone());
    edges
}

/// Judges a primary result against its cross-check and the goal.
///
/// The reported bar is max(e_p, |p − c| + e_c): the check's bar e_c is the
/// conservative one (a bisection difference), so |p − exact| ≤ |p − c| + e_c
/// whenever the check is right, whatever the primary's own estimate e_p.
/// Each rule aims at a quarter of the goal: two sound results fit, with room
/// for the primary's sharp estimate to be short by a factor 2.
fn reconcile<T: CheckRule>(primary: Estimate<T>, check: Option<Estimate<T>>, opts: &Options) -> Outcome<T> {
    let goal = goal(&primary.value, opts);
    let fail = |reason: String, bar: T, p: &Estimate<T>| Failure {
        reason,
        best_guess: Some(p.value.clone()),
        error_estimate: Some(bar),
        evaluations: p.evaluations,
    };
    let Some(c) = check else {
        if primary.error > goal {
            let reason = format!("error bar {:e} above the goal {:e}", primary.error.to_f64(), goal.to_f64());
            return Err(fail(reason, primary.error.clone(), &primary));
        }
        return Ok(primary);
    };
    let diff = (c.value.clone() - primary.value.clone()).abs();
    let bar = primary.error.clone().max_of(diff.clone() + c.error.clone());
    if bar <= goal {
        return Ok(Estimate { error: bar, check_value: c.value, ..primary });
    }
    let reason = if diff > primary.error.clone() + c.error.clone() {
        format!(
            "cross-check disagrees by {:e}: {} {:e} ± {:e}, {} {:e} ± {:e}",
            diff.to_f64(),
            primary.rule.name::<T>(),
            primary.value.to_f64(),
            primary.error.to_f64(),
            c.rule.name::<T>(),
            c.value.to_f64(),
            c.error.to_f64()
        )
    } else {
        format!("error bar {:e} above the goal {:e}", bar.to_f64(), goal.to_f64())
    };
    Err(fail(reason, bar, &primary))
}

/// max(abs_tol, rel_tol·|value|) at the value's precision.
///
/// Never below 1024 underflow floors (f64: ~1.0·10⁻²⁸⁹ absolute, room for the
/// per-panel floors of hundreds of panels), under which no relative accuracy
/// exists.
pub(crate) fn goal<T: Real>(value: &T, opts: &Options) -> T {
    (value.abs() * value.lit(opts.rel_tol))
        .max_of(value.lit(opts.abs_tol))
        .max_of(value.underflow_floor() * value.lit(1024.0))
}

fn validate<T: Real>(domain: &Domain<T>, opts: &Options) -> Result<(), Failure<T>> {
    let bad = |reason: String| Failure { reason, best_guess: None, error_estimate: None, evaluations: 0 };
    if !domain.lo.is_finite() {
        return Err(bad(format!("lower limit {:e} is not finite", domain.lo.to_f64())));
    }
    if let Some(hi) = &domain.hi {
        if !hi.is_finite() || !(hi.clone() > domain.lo.clone()) {
            return Err(bad(format!(
                "upper limit {:e} must be finite and above the lower {:e}",
                hi.to_f64(),
                domain.lo.to_f64()
            )));
        }
    }
    if !(opts.rel_tol >= 0.0 && opts.abs_tol >= 0.0) || (opts.rel_tol == 0.0 && opts.abs_tol == 0.0) {
        return Err(bad(format!("tolerances rel {} abs {}: both >= 0 and one > 0", opts.rel_tol, opts.abs_tol)));
    }
    Ok(())
}

/// Result of one rule over all pieces.
#[derive(Debug, Clone)]
pub(crate) struct RuleResult<T> {
    pub value: T,
    pub error: T,
    pub pieces: usize,
}
