//! Tables built once per quadrature pass of one computation, shared by
//! every integral of it that reads them (both models' along-ray tables of
//! single-scattered light, the finite-sphere model's I(D) and K(w)).

use crate::quad::{Estimate, Options, Rule};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The options of the tables of a pass with options `pass` of a nested
/// integral with options `opts`: the pass's, or where its goal is coarser
/// than the primary pass's inner goal (`integrate_nested`'s scale pass,
/// whose result sets only the inner integrals' floors), that goal: the
/// scale pass then builds (or reads) the primary pass's tables of its rule
/// instead of a coarser set that no later pass reads (about a third of
/// the pairs' table cost).
pub(crate) fn fine_tables(pass: &Options, opts: &Options) -> Options {
    capped_tables(pass, Some(primary_goal(opts)))
}

/// The primary pass's inner goal of a nested integral with options
/// `opts` (`integrate_nested`'s goal/20; where its floor makes that
/// coarser, [`fine_tables`] builds a table of its own for the scale pass:
/// no saving, no harm).
pub(crate) fn primary_goal(opts: &Options) -> f64 {
    opts.rel_tol / 20.0
}

/// The options a table of a pass with options `pass` is built (and keyed)
/// at: the pass's, its goal no coarser than `finest` where given
/// ([`fine_tables`]). Only the table's: the pass's own quadratures keep
/// `pass` (its goal and absolute floor).
pub(crate) fn capped_tables(pass: &Options, finest: Option<f64>) -> Options {
    match finest {
        Some(f) if f < pass.rel_tol => Options { rel_tol: f, ..pass.clone() },
        _ => pass.clone(),
    }
}

/// The key of a table: the pass's rule and tolerance.
type TableKey = (Rule, u64);

/// Tables built once per pass of one computation: the first caller of a
/// key builds its table, callers of the same key meanwhile wait for it
/// (no build makes a parallel call of its own, so waiting cannot
/// deadlock), so each is built — and charged to the budget — exactly once
/// whatever the thread count, and [`OncePerPass::evaluations`] sums the
/// builds, failed ones included, in a count that does not depend on which
/// thread built what. `None` where no table serves (the quadrature does).
/// Clones share the tables.
#[derive(Debug)]
pub(crate) struct OncePerPass<V> {
    cells: Arc<Mutex<HashMap<TableKey, Arc<OnceBuilt<V>>>>>,
}

/// One table of [`OncePerPass`], once built: the table (or `None`) and the
/// evaluations its build spent.
type OnceBuilt<V> = OnceLock<(Option<Arc<V>>, u64)>;

impl<V> Default for OncePerPass<V> {
    fn default() -> Self {
        OncePerPass { cells: Default::default() }
    }
}

impl<V> Clone for OncePerPass<V> {
    fn clone(&self) -> Self {
        OncePerPass { cells: self.cells.clone() }
    }
}

impl<V> OncePerPass<V> {
    /// The table of the pass with `opts` (its rule and tolerance), built by
    /// `build` (the table or `None`, and the evaluations it spent) if no
    /// caller built it before.
    pub(crate) fn get_or_build(&self, opts: &Options, build: impl FnOnce() -> (Option<V>, u64)) -> Option<Arc<V>> {
        self.get_or_build_at(opts.rule, opts.rel_tol, build)
    }

    /// [`OncePerPass::get_or_build`] for the pass with `rule` and the
    /// table tolerance `tol`.
    pub(crate) fn get_or_build_at(
        &self,
        rule: Rule,
        tol: f64,
        build: impl FnOnce() -> (Option<V>, u64),
    ) -> Option<Arc<V>> {
        let key = (rule, tol.to_bits());
        let cell = self.cells.lock().expect("no panic under the lock").entry(key).or_default().clone();
        cell.get_or_init(|| {
            let (table, spent) = build();
            (table.map(Arc::new), spent)
        })
        .0
        .clone()
    }

    /// Evaluations spent on every table built so far.
    pub(crate) fn evaluations(&self) -> u64 {
        let cells = self.cells.lock().expect("no panic under the lock");
        cells.values().filter_map(|c| c.get()).map(|(_, spent)| spent).sum()
    }

    /// `result` with [`OncePerPass::evaluations`] added: the one fixed
    /// place where an integral is charged the tables it and its siblings
    /// read (after all of them have finished).
    pub(crate) fn charge<T, E>(&self, result: Result<Estimate<T>, E>) -> Result<Estimate<T>, E> {
        result.map(|mut e| {
            e.evaluations += self.evaluations();
            e
        })
    }
}
