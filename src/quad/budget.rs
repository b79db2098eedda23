//! One evaluation budget (and an optional deadline) per top-level
//! computation, shared by every nested level and every pass.
//!
//! Each level of a nested integral used to have its own budget, so an inner
//! level that could not converge multiplied into a stall (2·10⁶ inner
//! evaluations at each of ~10⁵ outer nodes). Now every call of an
//! integrand, at whatever depth (a plain function, a table or closed form
//! standing for an inner integral, or an inner integral itself), is charged
//! to the [`Budget`] carried by the [`Options`](super::Options) it was
//! computed with; `Options` clones (and the inner options every level
//! derives with `..opts.clone()`) share it. A nested integral's calls are
//! thus counted once per level: the outer calls add to the inner ones a
//! fraction of a percent.
//! The engine checks it before every refinement step and, within a step,
//! every [`CHECK_EVERY`] integrand calls of each level (a first step of a
//! rule over many pieces, at 1024 bits, took 90 s between two checks), and
//! fails with `NOT CONVERGED: … budget …` once it is spent. An integral
//! that meets its goal having spent more than the budget (its first step
//! sufficed, between two checks) fails too: no result needs more than its
//! budget (`kernel --max-evals 1` printed a value after 128 evaluations).
//!
//! A computation whose cost is close to the budget may end either way when
//! its passes run on two threads (their counts interleave). A computation
//! needing well under the budget is unaffected and deterministic.

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Default number of integrand evaluations of one top-level computation:
/// ~20 s of f64 evaluations on two idle cores of the reference machine
/// (5·10⁷/s), so that a default run ends, converged or not, within about a
/// minute there. It is a count, so its time is the machine's: 50
/// single-scattering point lights spend it in 43–49 s wall, 51–53 CPU-s on
/// the reference machine's 2 cores shared with another job, and in 68 s,
/// 131 CPU-s on the outside probe's (`tests/probe_numerics.rs`). The
/// heaviest bundled computation (the order-1 oracle of
/// `point-isotropic-order1` at 10⁻⁶) takes 4.7·10⁸. (It was 2·10⁹ until
/// issue 11's re-probe: `sweep` on the order-1 scene then took 112 s, and
/// 50 single-scattering lights 98 s, before either ended.)
pub const DEFAULT_EVALUATIONS: u64 = 1_000_000_000;

/// Default number of integrand evaluations of one top-level computation in
/// MPFR: ~3 min of 128-bit evaluations on two cores of the reference machine
/// (~6 µs each, ~3·10⁵/s), where [`DEFAULT_EVALUATIONS`] would be hours. The
/// heaviest bundled MPFR computation, the oracle of `point-isotropic` at 192
/// bits (both models), takes 9.5·10⁶; an order-1 scene at 128 bits needs
/// more and ends as `NOT CONVERGED` naming the budget (`docs/accuracy-cost.md`).
#[cfg(feature = "mpfr")]
pub const DEFAULT_EVALUATIONS_MPFR: u64 = 50_000_000;

/// A shared evaluation budget: cheap to clone (clones share the count).
///
/// ```
/// use mcrt_noise::quad::{integrate, Budget, Domain, Options};
/// let f = |x: &f64| (-x * x).exp();
/// let ample = Budget::new(1_000_000);
/// let opts = Options::rel(1e-12).with_budget(ample.clone());
/// assert!(integrate(f, &Domain::finite(0.0, 1.0), &opts).is_ok());
/// // A tenth of what it needed: NOT CONVERGED, naming the budget.
/// let opts = Options::rel(1e-12).with_budget(Budget::new(ample.used() / 10));
/// let fail = integrate(f, &Domain::finite(0.0, 1.0), &opts).unwrap_err();
/// assert!(fail.reason.contains("evaluation budget"));
/// ```
#[derive(Clone)]
pub struct Budget(Arc<State>);

struct State {
    limit: u64,
    used: AtomicU64,
    deadline: Option<(Instant, Duration)>,
    spent: AtomicBool,
}

impl Budget {
    /// A budget of `limit` integrand evaluations, no deadline.
    pub fn new(limit: u64) -> Budget {
        Budget(Arc::new(State { limit, used: AtomicU64::new(0), deadline: None, spent: AtomicBool::new(false) }))
    }

    /// A budget of `limit` evaluations that also ends `time` from now.
    /// (A deadline makes the outcome depend on the machine's speed: use it
    /// to bound a run's wall time, not in tests.)
    pub fn with_deadline(limit: u64, time: Duration) -> Budget {
        let deadline = Some((Instant::now() + time, time));
        Budget(Arc::new(State { limit, used: AtomicU64::new(0), deadline, spent: AtomicBool::new(false) }))
    }

    /// A budget of its own for one of several computations that share this
    /// one's limits: the same evaluation limit, counted afresh, and the
    /// same deadline (the same instant, not a new span).
    ///
    /// ```
    /// use mcrt_noise::quad::Budget;
    /// let all = Budget::new(1000);
    /// all.charge(900);
    /// let each = all.renewed();
    /// assert_eq!((each.limit(), each.used()), (1000, 0));
    /// ```
    pub fn renewed(&self) -> Budget {
        let s = &self.0;
        Budget(Arc::new(State {
            limit: s.limit,
            used: AtomicU64::new(0),
            deadline: s.deadline,
            spent: AtomicBool::new(false),
        }))
    }

    /// Charges `n` evaluations.
    pub fn charge(&self, n: u64) {
        self.0.used.fetch_add(n, Ordering::Relaxed);
    }

    /// Evaluations charged so far.
    pub fn used(&self) -> u64 {
        self.0.used.load(Ordering::Relaxed)
    }

    /// The evaluation limit.
    pub fn limit(&self) -> u64 {
        self.0.limit
    }

    /// Why the computation must stop, if it must: the evaluations or the
    /// time are spent.
    pub fn exhausted(&self) -> Option<String> {
        let used = self.used();
        if used >= self.0.limit {
            self.0.spent.store(true, Ordering::Relaxed);
            return Some(format!(
                "the computation's evaluation budget of {} is spent ({} evaluations over all its levels and passes)",
                self.0.limit, used
            ));
        }
        if let Some((at, time)) = self.0.deadline {
            if Instant::now() >= at {
                self.0.spent.store(true, Ordering::Relaxed);
                return Some(format!("the computation's time limit of {} s is spent", time.as_secs_f64()));
            }
        }
        None
    }

    /// Why a result computed with this budget must be refused, if it must:
    /// more evaluations were spent than the budget allows (the deadline is
    /// not judged here: a result finished is kept).
    pub fn overrun(&self) -> Option<String> {
        let used = self.used();
        (used > self.0.limit).then(|| {
            self.0.spent.store(true, Ordering::Relaxed);
            format!(
                "the computation's evaluation budget of {} is spent ({} evaluations over all its levels and passes)",
                self.0.limit, used
            )
        })
    }

    /// Whether [`Budget::exhausted`] ever said so.
    pub fn was_exhausted(&self) -> bool {
        self.0.spent.load(Ordering::Relaxed)
    }
}

impl Default for Budget {
    /// [`DEFAULT_EVALUATIONS`], no deadline.
    fn default() -> Budget {
        Budget::new(DEFAULT_EVALUATIONS)
    }
}

impl fmt::Debug for Budget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Budget")
            .field("limit", &self.0.limit)
            .field("used", &self.used())
            .field("deadline", &self.0.deadline.map(|d| d.1))
            .finish()
    }
}

/// Integrand calls of one level between two checks of the budget and the
/// deadline within a refinement step (one atomic add and one clock read
/// per batch: ~0.1 % of the cheapest f64 integrand's cost).
pub const CHECK_EVERY: u64 = 256;

/// Counts a level's integrand calls and charges them in batches (one
/// atomic add per [`CHECK_EVERY`] evaluations, not per evaluation).
pub(crate) struct Meter<'b> {
    budget: &'b Budget,
    pending: u64,
}

impl<'b> Meter<'b> {
    pub fn new(budget: &'b Budget) -> Self {
        Meter { budget, pending: 0 }
    }
    /// Counts one call; every [`CHECK_EVERY`] calls, charges them and
    /// says why the computation must stop, if it must.
    pub fn tick(&mut self) -> Option<String> {
        self.pending += 1;
        if self.pending < CHECK_EVERY {
            return None;
        }
        self.budget.charge(self.pending);
        self.pending = 0;
        self.budget.exhausted()
    }
}

impl Drop for Meter<'_> {
    fn drop(&mut self) {
        self.budget.charge(self.pending);
    }
}
