//! Tests of `multiple`: the tables of every order against their integrals.

use super::*;

/// The tables of every order from 2 on (built for a pass at 10⁻⁶)
/// against the d-integral at 10⁻⁸ with the other rule: on both sides of
/// D = R, near the table's ends (down to 10⁻⁴R) and far out, for R from
/// 10⁻³ to 10, albedo 0.5 and 0.99, a finite range and every order: each
/// value within the table's bar plus the reference's.
#[test]
fn the_multiple_table_is_within_its_bar() {
    let opts = Options::rel(1e-6).declared();
    // The last case reaches down to 10⁻⁴R, as the tables of every
    // order's same-path pairs do (`FiniteField::cover_pair_distances`).
    let cases = [
        (0.8, None, 0.2, 0.1),
        (0.99, None, 1e-3, 0.1),
        (0.5, Some(5), 10.0, 0.1),
        (0.8, Some(2), 0.05, 0.1),
        (0.5, None, 0.2, 1e-4),
    ];
    for (albedo, last, r, lowest) in cases {
        let density = StartDensity::new(&albedo, 2, last).unwrap();
        let (lo, hi) = (lowest * r, 30.0 + 3.0 * r);
        let reach = 2.0 * (hi + r) + 200.0;
        let (tail, _) = TailTable::build(&density, &reach, &opts);
        let tail = tail.expect("a tail table at 1e-6");
        let decay = density.decay();
        let g =
            |d: &f64, o: &Options| multiple_hits(&density, Some(&tail), &1.0, &r, d, &(decay * (d - r).max(0.0)), o);
        let (table, _) =
            ScatteredTable::build_with(g, &decay, &r, &lo, &hi, super::super::scattered_table::LOWEST, &opts);
        let table = table.expect("a table at 1e-6");
        // The reference: the d-integral at 10⁻⁸ with the other rule and
        // tables of its own (T by quadrature alone cancels at small D).
        // Towards D → 0 the shells' T values cancel and the reference's
        // own tables cannot reach 10⁻⁸ (its cross-check fills with their
        // bars): 10⁻⁷ there.
        let fine_goal = if lowest < 0.1 { 1e-7 } else { 1e-8 };
        let fine = Options { rule: opts.rule.other(), ..Options::rel(fine_goal).declared() };
        let (fine_tail, _) = TailTable::build(&density, &reach, &Options::rel(fine_goal).declared());
        let mut worst = 0.0f64;
        for d in [lo, 10.0 * lo, 100.0 * lo, 0.5 * r, 0.999 * r, 1.001 * r, 2.0 * r, 1.0, 7.0, 0.9 * hi] {
            let Some((got, bar)) = table.hits(&1.0, &r, &d, &0.0) else { continue };
            let direct = multiple_hits(&density, fine_tail.as_ref(), &1.0, &r, &d, &0.0, &fine).unwrap();
            let off = (got / direct.value - 1.0).abs();
            let allowed = bar + direct.error / direct.value + 1e-14;
            worst = worst.max(off / allowed);
            assert!(off <= allowed, "a {albedo}, {last:?}, R {r}, D {d}: off {off:e}, allowed {allowed:e}");
        }
        println!("a {albedo}, {last:?}, R {r}: bar {:.1e}, worst {worst:.2} of allowed", table.rel_error);
    }
}
