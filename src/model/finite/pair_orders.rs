//! The orders a forward path simulates, as the same-path pairs need them
//! (`multiple_pairs`, `docs/model.md` §10.3): which start densities the
//! pair sum convolves with, how many parts of G (`fresh_hits`) each level
//! of remaining segments has, and which level each start reads.
//!
//! With orders up to n a path has segments 0..=n; what follows segment j
//! is a fresh path of at most m = n − j segments (level m, G_m with m − 1
//! parts), and segment j starts at the light (j = 0), at a·c₁ (j = 1) or
//! at a^j c_j. With every order there is one level (G with parts a·I and
//! C′ * H) and three starts: the light, a·c₁ and C′ = Σ_{j≥2} a^j c_j.

use super::start_density::StartDensity;
use crate::model::OracleError;
use crate::quad::CheckRule;

/// Where the segments of one term of the pair sum start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Start {
    /// Segment 0, at the light.
    Light,
    /// Segment 1, at a·c₁.
    FirstInteraction,
    /// The segments starting at [`PairOrders::densities`]`[i]`.
    Beyond(usize),
}

/// The orders of the pairs (module docs).
pub(super) struct PairOrders<T> {
    /// Every order: C′ = Σ_{j≥2} a^j c_j (one); orders up to n: a^j c_j,
    /// j = 2..n − 1 (index j − 2), which are also part j of G.
    pub densities: Vec<StartDensity<T>>,
    /// Per level, the parts of G after a segment of it: every order, [2]
    /// (G = H + a·I + C′ * H); orders up to n, a segment followed by at
    /// most m more has m − 1 parts, m = 1..=n (index m − 1).
    pub levels: Vec<usize>,
    /// (start, level index) per term: every order, every start with the
    /// one level; orders up to n, segment j (0..n − 1) with level n − j.
    pub terms: Vec<(Start, usize)>,
    albedo: T,
}

impl<T: CheckRule> PairOrders<T> {
    /// The orders of `density` (the field's start density of orders ≥ 2:
    /// 2..=n or every order from 2 on) in a medium of albedo `albedo`.
    pub fn of(density: &StartDensity<T>, albedo: &T) -> Result<Self, OracleError> {
        let Some(n) = density.last_order() else {
            let terms = vec![(Start::Light, 0), (Start::FirstInteraction, 0), (Start::Beyond(0), 0)];
            return Ok(PairOrders { densities: vec![density.clone()], levels: vec![2], terms, albedo: albedo.clone() });
        };
        let n = n as usize;
        let densities = (2..n as u32).map(|j| StartDensity::new(albedo, j, Some(j))).collect::<Result<Vec<_>, _>>()?;
        let levels = (1..=n).map(|m| m - 1).collect();
        let mut terms = vec![(Start::Light, n - 1), (Start::FirstInteraction, n - 2)];
        terms.extend((2..n).map(|j| (Start::Beyond(j - 2), n - j - 1)));
        Ok(PairOrders { densities, levels, terms, albedo: albedo.clone() })
    }

    /// The terms of the pair sum of the fresh path that follows a beam ray's
    /// first scattering (`multiple_beam_pairs`): a path of one segment fewer
    /// than these orders' (its segment 0 is the beam's segment 1), i.e. a
    /// point light of orders n − 1: (light, level n − 2), (a·c₁, level
    /// n − 3) where n ≥ 3, and (a^j c_j, level n − j − 2) for j = 2..n − 2,
    /// read from the same densities and levels; with every order the same
    /// terms as [`PairOrders::terms`].
    pub fn fresh_terms(&self) -> Vec<(Start, usize)> {
        if self.every() {
            return self.terms.clone();
        }
        // The fresh path's orders m = n − 1 ≥ 1 (levels 1..=n are built).
        let m = self.levels.len() - 1;
        let mut terms = vec![(Start::Light, m - 1)];
        if m >= 2 {
            terms.push((Start::FirstInteraction, m - 2));
        }
        terms.extend((2..m).map(|j| (Start::Beyond(j - 2), m - j - 1)));
        terms
    }

    /// Whether these are every order (`"all"`).
    pub fn every(&self) -> bool {
        self.densities.first().is_some_and(|d| d.last_order().is_none())
    }

    /// The most parts any level's G has.
    pub fn most_parts(&self) -> usize {
        self.levels.iter().copied().max().unwrap_or(0)
    }

    /// A bound of G with `parts` parts beyond its tables: the hits of a
    /// fresh path, at most its segments (parts + 1; each hits at most
    /// once), or with every order their expected number 1/(1 − a).
    pub fn most_hits(&self, parts: usize) -> T {
        let one = self.albedo.lit(1.0);
        if self.every() {
            one.clone() / (one - self.albedo.clone())
        } else {
            self.albedo.lit((parts + 1) as f64)
        }
    }

    /// The rate G's and the pair sum's tables are scaled by beyond R, in
    /// units of σ: ν with every order, 1 for a finite one.
    pub fn decay(&self) -> T {
        if self.every() {
            self.densities[0].decay()
        } else {
            self.albedo.lit(1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orders(last: Option<u32>) -> PairOrders<f64> {
        PairOrders::of(&StartDensity::new(&0.8, 2, last).unwrap(), &0.8).unwrap()
    }

    /// The levels and terms pinned for orders 2 and 4 and every order
    /// (module docs): segment j of n reads level n − j (index n − j − 1),
    /// whose G has n − j − 1 parts; the densities are the single orders
    /// 2..n − 1.
    #[test]
    fn segments_read_the_level_of_what_follows_them() {
        use Start::{Beyond, FirstInteraction, Light};
        let two = orders(Some(2));
        assert_eq!(two.levels, vec![0, 1]);
        assert_eq!(two.terms, vec![(Light, 1), (FirstInteraction, 0)]);
        assert!(two.densities.is_empty() && !two.every());
        let four = orders(Some(4));
        assert_eq!(four.levels, vec![0, 1, 2, 3]);
        assert_eq!(four.terms, vec![(Light, 3), (FirstInteraction, 2), (Beyond(0), 1), (Beyond(1), 0)]);
        let singles: Vec<_> = four.densities.iter().map(|d| d.last_order()).collect();
        assert_eq!(singles, vec![Some(2), Some(3)]);
        assert_eq!((four.most_parts(), four.most_hits(0), four.most_hits(3), four.decay()), (3, 1.0, 4.0, 1.0));
        let all = orders(None);
        assert_eq!(
            (all.levels.clone(), all.terms.clone()),
            (vec![2], vec![(Light, 0), (FirstInteraction, 0), (Beyond(0), 0)])
        );
        assert!(all.every() && (all.most_hits(2) - 5.0).abs() < 1e-12 && all.decay() < 1.0);
    }

    /// The fresh path after a beam's first scattering has one segment
    /// fewer: its terms are those of the orders one below, read from the
    /// same densities and levels (and every order's own terms).
    #[test]
    fn a_beams_fresh_path_reads_the_terms_of_one_order_less() {
        use Start::{Beyond, FirstInteraction, Light};
        assert_eq!(orders(Some(2)).fresh_terms(), vec![(Light, 0)]);
        assert_eq!(orders(Some(3)).fresh_terms(), orders(Some(2)).terms);
        assert_eq!(orders(Some(5)).fresh_terms(), orders(Some(4)).terms);
        assert_eq!(
            orders(Some(5)).fresh_terms(),
            vec![(Light, 3), (FirstInteraction, 2), (Beyond(0), 1), (Beyond(1), 0)]
        );
        assert_eq!(orders(None).fresh_terms(), orders(None).terms);
    }
}
