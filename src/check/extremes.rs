//! The samples' smallest value and their few largest, kept exactly: one
//! value's influence on the verdict is scanned over [smallest, largest],
//! and the joint influence of the largest few bounds what a handful of
//! large values can do.

use mcrt_reference::exact::Dyadic;

/// How many of the largest values are kept ([`Extremes::largest`]).
pub const TOP_VALUES: usize = 8;

/// The smallest value and the [`TOP_VALUES`] largest (fewer when there are
/// fewer values, or when power sums came with fewer), in descending order.
/// Merging keeps the same values whatever the order: the union's smallest
/// and largest.
#[derive(Debug, Clone, PartialEq)]
pub struct Extremes {
    smallest: f64,
    largest: Vec<f64>,
}

impl Extremes {
    /// No values yet.
    pub fn empty() -> Extremes {
        Extremes { smallest: f64::INFINITY, largest: Vec::new() }
    }

    /// `smallest` and the largest values given (any order; at most
    /// [`TOP_VALUES`] kept).
    pub fn new(smallest: f64, largest: &[f64]) -> Extremes {
        let mut e = Extremes { smallest, largest: largest.to_vec() };
        e.tidy();
        e
    }

    /// Adds one value.
    pub fn push(&mut self, l: f64) {
        self.smallest = self.smallest.min(l);
        if self.largest.len() < TOP_VALUES || l > *self.largest.last().expect("TOP_VALUES > 0") {
            self.largest.push(l);
            self.tidy();
        }
    }

    /// These and `other`'s together.
    pub fn merge(&self, other: &Extremes) -> Extremes {
        let mut largest = self.largest.clone();
        largest.extend_from_slice(&other.largest);
        Extremes::new(self.smallest.min(other.smallest), &largest)
    }

    /// Descending, at most [`TOP_VALUES`].
    fn tidy(&mut self) {
        self.largest.sort_by(|a, b| b.total_cmp(a));
        self.largest.truncate(TOP_VALUES);
    }

    /// The smallest value (`None` before the first).
    pub fn smallest(&self) -> Option<f64> {
        self.smallest.is_finite().then_some(self.smallest)
    }

    /// The largest values known, in descending order.
    pub fn largest(&self) -> &[f64] {
        &self.largest
    }

    /// [smallest, largest] (`None` before the first value).
    pub fn range(&self) -> Option<(f64, f64)> {
        self.smallest().zip(self.largest.first().copied())
    }
}

/// Whether `count` values with power sums `sums` (Σ L … Σ L⁶, each known
/// to relative error `eps`) can have `smallest` as their smallest value and
/// `largest` (descending) as their largest: the values are ≥ 0 and finite,
/// at most [`TOP_VALUES`] and `count` of them, each ≥ `smallest`; the rest,
/// `count − t` values in [`smallest`, the t-th largest], must account for
/// what the sums leave, (count − t)·min^k ≤ S_k − Σ top^k ≤ (count − t)·
/// top_t^k for k = 1…6; and every value in [min, max] gives min·S_k ≤
/// S_{k+1} ≤ max·S_k. Formed exactly, each side allowing the sums'
/// error. Necessary conditions only: a renderer that misstates its
/// extremes within them is not caught, and the guarantees that rest on the
/// extremes (one value's influence, the tail test) assume them honest.
pub fn check_against_sums(
    smallest: f64,
    largest: &[f64],
    count: u64,
    sums: &[Dyadic; 6],
    eps: f64,
) -> Result<(), String> {
    if !(smallest >= 0.0 && smallest.is_finite()) {
        return Err(format!("min = {smallest:e}: must be finite and >= 0 (L is never negative)"));
    }
    let t = largest.len();
    if t == 0 || t > TOP_VALUES || t as u64 > count {
        return Err(format!(
            "largest: {t} values given: must be 1 to {} (the largest values, at most {TOP_VALUES} and at most count = \
             {count})",
            TOP_VALUES.min(count as usize)
        ));
    }
    if let Some(v) = largest.iter().find(|v| !(v.is_finite() && **v >= smallest)) {
        return Err(format!("largest value {v:e}: must be finite and >= min = {smallest:e}"));
    }
    let mut top = largest.to_vec();
    top.sort_by(|a, b| b.total_cmp(a));
    let (max, last) = (top[0], top[t - 1]);
    let rest = Dyadic::from(count - t as u64);
    let power = |x: f64, k: u32| Dyadic::from_f64(x).expect("finite").pow(k);
    let slack = Dyadic::from_f64(1.01 * eps + 8.0 * f64::EPSILON).expect("finite");
    let (max_d, smallest_d) = (Dyadic::from_f64(max).expect("finite"), Dyadic::from_f64(smallest).expect("finite"));
    for k in 1..=6u32 {
        let s = &sums[k as usize - 1];
        let top_sum = top.iter().fold(Dyadic::zero(), |acc, v| &acc + &power(*v, k));
        let tol = &(s + &top_sum) * &slack;
        let remainder = s - &top_sum;
        let low = &rest * &power(smallest, k);
        let high = &rest * &power(last, k);
        if &remainder + &tol < low || &remainder - &tol > high {
            return Err(format!(
                "min = {smallest:e}, largest = {top:?}: the sums cannot come from values with these extremes: \
                 Σ L^{k} less the largest values' must lie in [(count − {t})·min^{k}, (count − {t})·{last:e}^{k}]"
            ));
        }
        if k < 6 {
            let next = &sums[k as usize];
            let tol = &(next + &(s * &max_d)) * &slack;
            if next + &tol < s * &smallest_d || next - &tol > s * &max_d {
                return Err(format!(
                    "min = {smallest:e}, max = {max:e}: the sums cannot come from values in [min, max]: min·Σ L^{k} ≤ \
                     Σ L^{} ≤ max·Σ L^{k} fails",
                    k + 1
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extremes_do_not_depend_on_the_order() {
        let values: Vec<f64> = (0..40).map(|k| ((k * 37) % 41) as f64 * 0.5).collect();
        let mut one = Extremes::empty();
        values.iter().for_each(|v| one.push(*v));
        let (mut a, mut b) = (Extremes::empty(), Extremes::empty());
        values.iter().enumerate().for_each(|(i, v)| if i % 3 == 0 { a.push(*v) } else { b.push(*v) });
        assert_eq!(b.merge(&a), one);
        assert_eq!(one.largest(), &[20.0, 19.5, 19.0, 18.5, 18.0, 17.5, 17.0, 16.5]);
        assert_eq!(one.range(), Some((0.0, 20.0)));
        assert_eq!(Extremes::empty().range(), None);
    }
}
