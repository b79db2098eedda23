//! Tests of `multiple_pairs`: the pair tables within their bars, point
//! lights' and a beam's.
use super::*;
use crate::model::field::Field;
use mcrt_scene::{ScatteringOrders, Scene};

/// The README scene (`point-isotropic`: σ = 1, the light at (1, 0, 1))
/// with the orders given, q = 1, one camera ray, the albedo and R given,
/// its tables made to reach the pairs' distances (as `every_order_mean`
/// does).
fn every_order_field(orders: ScatteringOrders, albedo: f64, radius: f64) -> FiniteField<f64> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.medium.albedo = albedo;
    s.estimator.radius = radius;
    s.estimator.q = 1.0;
    s.estimator.camera_rays = 1;
    s.effects.scattering_orders = orders;
    let mut first = s.clone();
    first.effects.scattering_orders = ScatteringOrders::Limited(1);
    let field = Field::from_scene(&first, &0.0f64).unwrap();
    let mut ff = FiniteField::of_first_segments(&s, &field);
    ff.cover_pair_distances();
    ff
}

/// The orders of `ff`, the options of a pass of a 10⁻⁴ computation (its
/// inner goal: `integrate_nested`'s 20) and the pair tables built for it.
fn pass_tables(ff: &FiniteField<f64>, albedo: f64) -> (PairOrders<f64>, Options, Arc<PairTable<f64>>) {
    let density = ff.higher_orders().unwrap();
    let pair_orders = PairOrders::of(density, &albedo).unwrap();
    let opts = Options::rel(1e-4 / 20.0).with_budget(crate::quad::Budget::new(20_000_000_000)).declared();
    let (scattered, multiple, tables) = (ScatteredTables::default(), MultipleTables::default(), PairTables::default());
    let t =
        ff.pair_tables(&tables, (&scattered, &multiple), density, &pair_orders, &opts).expect("pair tables at 1e-4");
    (pair_orders, opts, t)
}

/// The tables of 𝒦(d) and of the pair sum, built for a pass of a 10⁻⁴
/// computation (`EVERY_ORDER_VARIANCE_TOL`; G from the pass's I(D) and
/// (C′ * H)(D) tables, asserted),
/// against their one-level integrals at 10⁻⁹ (the pair sum's at 10⁻⁷)
/// with the other rule, each reading the table below
/// it as the table does: 𝒦 on both sides of d = R, near the centre and
/// far out, at every level of remaining segments; the pair sum across
/// the light's distances from the camera ray; every order at albedo 0.5
/// and 0.95, and orders up to 4 (four levels, G's parts 2 and 3 from
/// tables of their own) at albedo 0.8. Each value within the table's
/// (chained) bar plus the reference's.
#[test]
fn the_pair_tables_are_within_their_bars() {
    let all = ScatteringOrders::All;
    for (orders, albedo, r) in [(all, 0.5, 0.2), (all, 0.95, 0.3), (ScatteringOrders::Limited(4), 0.8, 0.2)] {
        let ff = every_order_field(orders, albedo, r);
        let (pair_orders, opts, t) = pass_tables(&ff, albedo);
        assert!(t.g_from_shared, "a {albedo}, R {r}: G did not come from the I(D) and (C′ * H)(D) tables");
        assert_eq!(t.levels.len(), if orders == all { 1 } else { 4 });
        let mut checked = 0;
        let fine = Options { rule: opts.rule.other(), ..Options::rel(1e-9).declared() };
        let mut worst = 0.0f64;
        let mut check = |what: &str, d: f64, got: f64, bar: f64, direct: Estimate<f64>| {
            let off = (got / direct.value - 1.0).abs();
            let allowed = bar + direct.error / direct.value + 1e-14;
            worst = worst.max(off / allowed);
            assert!(off <= allowed, "a {albedo}, R {r}, {what} at {d}: off {off:e}, allowed {allowed:e}");
            checked += 1;
        };
        for level in &t.levels {
            for d in [1e-3 * r, 0.5 * r, 0.999 * r, 1.001 * r, 2.0 * r, 1.5, 5.0] {
                let Some((got, bar)) = level.revisit.hits(&1.0, &r, &d, &0.0) else { continue };
                let direct = revisit(&1.0, &r, &level.after, &d, &0.0, &fine, false).unwrap();
                check("𝒦", d, got, bar, direct);
            }
        }
        let (lo, hi) = super::super::scattered_table::light_distance_range(&ff).unwrap();
        let pairs = t.pairs.as_ref().expect("a pair-sum table");
        for d in [lo * 1.001, 0.5 * (lo + hi), 0.9 * hi] {
            let Some((got, bar)) = pairs.hits(&1.0, &r, &d, &0.0) else { continue };
            // 10⁻⁷: the samples read T from the pass's tail table, whose
            // bar (~10⁻⁸ of the sum here) a finer goal could not meet.
            let coarser = Options { rel_tol: 1e-7, ..fine.clone() };
            let direct = pair_sum(&1.0, &r, &albedo, &pair_orders, &pair_orders.terms, &t, &d, &0.0, &coarser).unwrap();
            check("pair sum", d, got, bar, direct);
        }
        println!(
            "{orders:?}, a {albedo}, R {r}: 𝒦 bar {:.1e}, pairs bar {:.1e}, worst {worst:.2} of allowed ({checked} \
             values)",
            t.revisit_rel(),
            pairs.rel_error
        );
    }
}

/// A beam's tables of the pairs of every order (`multiple_beam_pairs`,
/// docs/model.md §10.6), built for a pass of a 10⁻⁴ computation on the
/// README scene with `beam-isotropic`'s beam beside its light: the pair
/// sum 𝒮 of the fresh path after the beam's first scattering against its
/// one-level integral at 10⁻⁷ with the other rule (inside the sphere, on
/// both sides of R outside the window, and out to the shells' reach), each
/// within the table's (chained) bar plus the reference's; with every order
/// the fresh path is a point light's own, so 𝒮 equals the point light's
/// pair-sum table wherever both reach; the table of G that bounds the
/// shells' cut decreases with d (the bound's premise).
#[test]
fn a_beams_pair_tables_are_within_their_bars() {
    let all = ScatteringOrders::All;
    for (orders, albedo, r) in [(all, 0.8, 0.2), (ScatteringOrders::Limited(3), 0.8, 0.2)] {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/beam-isotropic.toml");
        let beam_scene = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let mut s = beam_scene.clone();
        s.medium.albedo = albedo;
        s.estimator.radius = r;
        s.effects.scattering_orders = ScatteringOrders::Limited(1);
        let readme = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
        let readme = Scene::from_toml_str(&std::fs::read_to_string(readme).unwrap()).unwrap();
        s.lights = readme.lights.iter().chain(&beam_scene.lights).cloned().collect();
        let field = Field::from_scene(&s, &0.0f64).unwrap();
        s.effects.scattering_orders = orders;
        let mut ff = FiniteField::of_first_segments(&s, &field);
        ff.cover_pair_distances();
        let (pair_orders, opts, t) = pass_tables(&ff, albedo);
        let sums = t.beams.as_ref().expect("a beam's pair tables");
        let fine = Options { rule: opts.rule.other(), ..Options::rel(1e-7).declared() };
        let terms = pair_orders.fresh_terms();
        let mut worst = 0.0f64;
        for d in [1e-3 * r, 0.5 * r, 0.999 * r, 1.001 * r, 2.0 * r, 1.5, 5.0, 30.0] {
            let (got, bar) = sums.sums.hits(&1.0, &r, &d, &0.0).expect("𝒮's table reaches d");
            let direct = pair_sum(&1.0, &r, &albedo, &pair_orders, &terms, &t, &d, &0.0, &fine).unwrap();
            let off = (got / direct.value - 1.0).abs();
            let allowed = bar + direct.error / direct.value + 1e-14;
            worst = worst.max(off / allowed);
            assert!(off <= allowed, "{orders:?}: 𝒮({d}) off {off:e}, allowed {allowed:e}");
        }
        if orders == all {
            let (lo, hi) = super::super::scattered_table::light_distance_range(&ff).unwrap();
            let pairs = t.pairs.as_ref().expect("the point light's pair-sum table");
            for d in [lo * 1.001, 0.5 * (lo + hi), 0.9 * hi] {
                let (a, bar_a) = pairs.hits(&1.0, &r, &d, &0.0).unwrap();
                let (b, bar_b) = sums.sums.hits(&1.0, &r, &d, &0.0).unwrap();
                assert!((a / b - 1.0).abs() <= bar_a + bar_b, "𝒮({d}): {a:e} against the point light's {b:e}");
            }
        }
        let mut last = f64::INFINITY;
        for d in [0.2 * r, 0.9 * r, 0.99 * r, 1.01 * r, 1.5 * r, 1.0, 3.0, 10.0, 40.0, 80.0] {
            let (g, _) = sums.hits.hits(&1.0, &r, &d, &0.0).expect("G's table reaches d");
            assert!(g > 0.0 && g < last, "{orders:?}: G({d}) = {g:e} after {last:e}");
            last = g;
        }
        println!("{orders:?}: 𝒮 bar {:.1e}, worst {worst:.2} of allowed", sums.sums.rel_error);
    }
}
