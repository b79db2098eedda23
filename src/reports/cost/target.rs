//! Speed targets of the cost report: each row states its target and
//! whether this run met it, and every miss is listed at the top of the
//! report, so a regression is visible the day it happens.

use std::fmt::Write;

/// A row's speed target and the issue that set it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Target {
    /// Wall time at most `seconds`.
    AtMost { seconds: f64, source: &'static str },
    /// A rate (per second) at least `per_second`.
    AtLeast { per_second: f64, unit: &'static str, source: &'static str },
    /// A benchmark row without a target.
    None,
}

impl Target {
    /// The "target" cell.
    pub(crate) fn cell(&self) -> String {
        match self {
            Target::AtMost { seconds, source } => format!("≤ {} ({source})", duration(*seconds)),
            Target::AtLeast { per_second, unit, source } => format!("≥ {per_second:.0e} {unit}/s ({source})"),
            Target::None => "—".into(),
        }
    }

    /// Whether `measured` (seconds for `AtMost`, a rate for `AtLeast`; `None`
    /// when the computation failed) meets the target; `None` without one.
    pub(crate) fn met(&self, measured: Option<f64>) -> Option<bool> {
        match (self, measured) {
            (Target::None, _) => None,
            (_, None) => Some(false),
            (Target::AtMost { seconds, .. }, Some(t)) => Some(t <= *seconds),
            (Target::AtLeast { per_second, .. }, Some(r)) => Some(r >= *per_second),
        }
    }
}

/// A wall time in the unit that reads best.
pub(crate) fn duration(seconds: f64) -> String {
    if seconds < 1e-3 {
        format!("{:.3} ms", seconds * 1e3)
    } else if seconds < 1.0 {
        format!("{:.1} ms", seconds * 1e3)
    } else {
        format!("{seconds:.2} s")
    }
}

/// The targets of one report: the "met" cells and the list of misses.
#[derive(Debug, Default)]
pub(crate) struct Ledger {
    checked: usize,
    missed: Vec<String>,
}

impl Ledger {
    /// The "met" cell of `row` (a label for the list of misses), recording a miss.
    pub(crate) fn judge(&mut self, row: &str, target: Target, measured: Option<f64>) -> &'static str {
        match target.met(measured) {
            None => "—",
            Some(true) => {
                self.checked += 1;
                "yes"
            }
            Some(false) => {
                self.checked += 1;
                let got = match (target, measured) {
                    (_, None) => "no result".to_string(),
                    (Target::AtLeast { unit, .. }, Some(r)) => format!("{r:.3e} {unit}/s"),
                    (_, Some(t)) => duration(t),
                };
                self.missed.push(format!("{row}: {got}, target {}", target.cell()));
                "**MISSED**"
            }
        }
    }

    /// The summary paragraph for the top of the report.
    pub(crate) fn summary(&self) -> String {
        let mut s = String::new();
        if self.missed.is_empty() {
            writeln!(s, "**Every one of the {} targets below was met on this run.**", self.checked).unwrap();
        } else {
            writeln!(s, "**{} of the {} targets below were missed on this run:**", self.missed.len(), self.checked)
                .unwrap();
            writeln!(s).unwrap();
            for m in &self.missed {
                writeln!(s, "- {m}").unwrap();
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_computation_misses_its_target_and_is_listed() {
        let mut ledger = Ledger::default();
        let t = Target::AtMost { seconds: 0.05, source: "issue 11" };
        assert_eq!(ledger.judge("fast", t, Some(0.01)), "yes");
        assert_eq!(ledger.judge("slow", t, Some(0.2)), "**MISSED**");
        assert_eq!(ledger.judge("failed", t, None), "**MISSED**");
        assert_eq!(ledger.judge("benchmark", Target::None, Some(9.0)), "—");
        let rate = Target::AtLeast { per_second: 1e5, unit: "trials", source: "issue 4" };
        assert_eq!(ledger.judge("tracer", rate, Some(2e5)), "yes");
        let summary = ledger.summary();
        assert!(summary.contains("2 of the 4 targets"), "{summary}");
        assert!(summary.contains("slow: 200.0 ms") && summary.contains("failed: no result"), "{summary}");
    }
}
