//! The generated `docs/model-error.md`: the finite-sphere model (exact at
//! any R for uncollided light) against the small-sphere model of §4.3, over
//! R from 1 down to 10⁻⁴: how wrong the small-sphere model is at the radii
//! renderers use, and the order at which it becomes exact.

use crate::oracle::{run, Precision, ValueWithBar};
use crate::reports::sweep::{finite_table, fit_finite_order, sweep, FiniteRatio, Row};
use mcrt_scene::{Phase, Scene};
use std::fmt::Write;
use std::path::Path;

/// Radii of the documented comparison.
pub const MODEL_RADII: [f64; 9] = [1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 1e-3, 1e-4];

/// The compared scenes: (bundled scene, label).
pub const MODEL_SCENES: [(&str, &str); 4] = [
    ("point-isotropic", "point light, isotropic medium"),
    ("point-hg-forward", "point light, Henyey–Greenstein g = 0.9"),
    ("point-hg-backward", "point light, Henyey–Greenstein g = −0.5"),
    ("beam-isotropic", "beam, isotropic medium"),
];

/// SVG: log₁₀|finite/small − 1| of the mean and of Var L against log₁₀ R.
pub fn figure(title: &str, rows: &[Row]) -> Result<String, String> {
    use poloto::build;
    let pts = |pick: fn(&crate::reports::sweep::FiniteColumns) -> ValueWithBar| -> Vec<[f64; 2]> {
        rows.iter()
            .filter_map(|r| {
                let v = pick(r.finite.as_ref()?);
                let gap = (v.value - 1.0).abs();
                (gap > v.error && gap > 0.0).then(|| [r.radius.log10(), gap.log10()])
            })
            .collect()
    };
    let (mean, var) = (pts(|f| f.mean_ratio), pts(|f| f.variance_ratio));
    // Room right of R = 1, so that its points do not sit on the legend.
    let plots =
        poloto::plots!(build::plot("mean").line(mean), build::plot("Var L").scatter(var), build::markers([0.3], []));
    poloto::frame_build()
        .data(plots)
        .build_and_label((title.to_string(), "log₁₀ R", "log₁₀ |finite/small-sphere − 1|"))
        .append_to(poloto::header().light_theme())
        .render_string()
        .map_err(|e| e.to_string())
}

/// The bundled scene of the single-scattering section, run with q = 1 and
/// N_B = 1 (where the finite-sphere model covers order 1).
pub const ORDER1_SCENE: &str = "point-isotropic-order1";

/// The bundled beam scene of the single-scattering headline row, run at
/// order 1 with q = 1 and N_B = 1 (a headline row only: the sweeps' (23),
/// (24) of a beam's single-scattered light lack the cross-segment pairs).
pub const ORDER1_BEAM_SCENE: &str = "beam-isotropic";

/// The bundled scene of the every-order section (`"all"`, q = 0.5, N_B = 8:
/// the mean only, which is all the small-sphere model of every order has).
pub const EVERY_ORDER_SCENE: &str = "point-isotropic-all";

/// Radii of the every-order section.
pub const EVERY_ORDER_RADII: [f64; 7] = [0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 1e-3];

/// The scenes the document reads from its scenes directory.
pub fn scene_names() -> Vec<&'static str> {
    MODEL_SCENES.iter().map(|(name, _)| *name).chain([ORDER1_SCENE, EVERY_ORDER_SCENE]).collect()
}

/// [`ORDER1_SCENE`] with q = 1 and N_B = 1.
fn order1_scene(scenes_dir: &Path) -> Result<Scene, String> {
    let mut scene = bundled(scenes_dir, ORDER1_SCENE)?;
    scene.estimator.q = 1.0;
    scene.estimator.camera_rays = 1;
    Ok(scene)
}

/// [`ORDER1_BEAM_SCENE`] at order 1 with q = 1 and N_B = 1.
fn order1_beam_scene(scenes_dir: &Path) -> Result<Scene, String> {
    let mut scene = bundled(scenes_dir, ORDER1_BEAM_SCENE)?;
    scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
    scene.estimator.q = 1.0;
    scene.estimator.camera_rays = 1;
    Ok(scene)
}

fn bundled(scenes_dir: &Path, name: &str) -> Result<Scene, String> {
    let path = scenes_dir.join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    Scene::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// One headline case: the finite model against the small-sphere one at a
/// renderer's radius.
fn headline(s: &mut String, label: &str, scene: &Scene) -> Result<(), String> {
    let rep = run(scene, Precision::F64, None).map_err(|e| e.to_string())?;
    headline_row(s, label, scene, &rep)
}

/// The finite-sphere model's goal in the rows that need its correlations
/// of two spheres (q < 1 or N_B > 1) or, in a Henyey–Greenstein medium, its
/// same-path term (`Scope::FinitePairs`): the library's `predict`'s
/// ([`crate::prec::FINITE_PAIRS_PREDICTION_TOL`]); at the default
/// tolerance they would take hours.
const PAIRS_TOL: f64 = crate::prec::FINITE_PAIRS_PREDICTION_TOL;

/// [`headline`] with `Scope::FinitePairs` at [`PAIRS_TOL`]: an order-1 row
/// whose finite-sphere Var L needs the correlations of two spheres, or the
/// same-path term of a Henyey–Greenstein medium, with the largest budget
/// the library's prediction gives either
/// ([`crate::prec::FINITE_HG_PREDICTION_EVALUATIONS`]).
fn headline_with_pairs(s: &mut String, label: &str, scene: &Scene) -> Result<(), String> {
    use crate::oracle::{run_within_scoped, Scope};
    let budget = crate::quad::Budget::new(crate::prec::FINITE_HG_PREDICTION_EVALUATIONS);
    let rep = run_within_scoped(scene, Precision::F64, Some(PAIRS_TOL), &budget, Scope::FinitePairs)
        .map_err(|e| e.to_string())?;
    if let Some(why) = &rep.finite_not_used {
        return Err(format!("{label}: no finite-sphere Var L: {why}"));
    }
    headline_row(s, label, scene, &rep)
}

fn headline_row(s: &mut String, label: &str, scene: &Scene, rep: &crate::oracle::Report) -> Result<(), String> {
    let f = rep.finite.as_ref().ok_or("no finite-sphere model")?;
    let variance_ratio = f.variance_ratio.ok_or("no small-sphere Var L")?;
    let e = &scene.estimator;
    writeln!(
        s,
        "| {label} | {} | {} | {} | {} | {:+.4} % ± {:.0e} | {:+.4} % ± {:.0e} |",
        e.radius,
        e.q,
        e.forward_rays,
        e.camera_rays,
        100.0 * (f.mean_ratio.value - 1.0),
        100.0 * f.mean_ratio.error,
        100.0 * (variance_ratio.value - 1.0),
        100.0 * variance_ratio.error
    )
    .unwrap();
    Ok(())
}

/// The goal of the every-order section: the finest the model of every
/// order takes, so that the bias at R = 10⁻³ (~10⁻⁷ of the mean) is
/// resolved.
const EVERY_ORDER_GOAL: f64 = crate::oracle::EVERY_ORDER_TOL_RANGE.0;

/// b(R)/μ(0) of `scene` at its R (the mean of every order, exact at R,
/// against its small-sphere limit, `docs/model.md` §10.2), with its bar.
fn every_order_bias(scene: &Scene) -> Result<ValueWithBar, String> {
    let budget = crate::quad::Budget::new(crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS);
    let m = crate::oracle::every_order_mean(scene, Some(EVERY_ORDER_GOAL), &budget).map_err(|e| e.to_string())?;
    let (b, small) = (m.bias, m.small_sphere_mean);
    let value = b.value / small.value;
    Ok(ValueWithBar { value, error: b.error / small.value + value.abs() * small.error / small.value })
}

/// The every-order section: the relative bias b(R)/μ(0) of orders 2, 5
/// and `"all"` over [`EVERY_ORDER_RADII`], and its local order at the two
/// smallest radii (the small-sphere model has no Var L beyond order 1).
fn every_order_section(s: &mut String, scenes_dir: &Path) -> Result<(), String> {
    use mcrt_scene::ScatteringOrders::{All, Limited};
    let base = bundled(scenes_dir, EVERY_ORDER_SCENE)?;
    let orders = [Limited(2), Limited(5), All];
    writeln!(s, "\n## `{EVERY_ORDER_SCENE}`: every scattering order, point light, isotropic medium\n").unwrap();
    writeln!(
        s,
        "Albedo {}, q = {}, N_F = {}, N_B = {}; `scattering_orders` as in each column. The finite-sphere model of every \
         order (`docs/model.md` §10.2) against the small-sphere mean of the same orders (its R → 0 limit, §10.2): the \
         estimator's relative bias b(R)/μ(0), each at the tolerance {EVERY_ORDER_GOAL:e} with its bar. The small-sphere model \
         has no Var L beyond order 1 (the paper's is of orders 0 and 1: §10.4), so Var L has no column here; the \
         finite-sphere Var L of these orders at q = 1 and N_B = 1 is checked against the tracer in \
         [tracer-checks.md](tracer-checks.md).\n",
        base.medium.albedo, base.estimator.q, base.estimator.forward_rays, base.estimator.camera_rays
    )
    .unwrap();
    let mut table = vec![Vec::new(); orders.len()];
    for (column, &o) in orders.iter().enumerate() {
        for &r in &EVERY_ORDER_RADII {
            let mut scene = base.clone();
            (scene.effects.scattering_orders, scene.estimator.radius) = (o, r);
            table[column].push(every_order_bias(&scene)?);
        }
    }
    let name = |o: &mcrt_scene::ScatteringOrders| match o {
        All => "every order".to_string(),
        Limited(n) => format!("orders ≤ {n}"),
    };
    let header: Vec<String> = orders.iter().map(|o| format!("{}: b(R)/μ(0)", name(o))).collect();
    writeln!(s, "| R | {} |", header.join(" | ")).unwrap();
    writeln!(s, "|---:|{}", "---:|".repeat(orders.len())).unwrap();
    for (i, r) in EVERY_ORDER_RADII.iter().enumerate() {
        let cells: Vec<String> = table.iter().map(|c| format!("{:+.6e} ± {:.0e}", c[i].value, c[i].error)).collect();
        writeln!(s, "| {r:e} | {} |", cells.join(" | ")).unwrap();
    }
    // The local order at the two smallest radii.
    let n = EVERY_ORDER_RADII.len();
    let (r1, r2) = (EVERY_ORDER_RADII[n - 2], EVERY_ORDER_RADII[n - 1]);
    let fits: Vec<(String, f64, f64)> = orders
        .iter()
        .zip(&table)
        .map(|(o, c)| {
            let (b1, b2) = (c[n - 2], c[n - 1]);
            let slope = (b1.value.abs() / b2.value.abs()).ln() / (r1 / r2).ln();
            // Each bar moves the slope by at most its relative size over ln(r1/r2).
            let bar = (b1.error / b1.value.abs() + b2.error / b2.value.abs()) / (r1 / r2).ln();
            (name(o), slope, bar)
        })
        .collect();
    let second = fits.iter().all(|(_, slope, bar)| (slope - 2.0).abs() <= bar + 0.05);
    let slopes: Vec<String> = fits.iter().map(|(o, slope, bar)| format!("{o} {slope:.3} ± {bar:.0e}")).collect();
    let verdict = if second {
        "each within 0.05 (and its bar) of 2: second order in R, as for uncollided light"
    } else {
        "not all within 0.05 (and their bars) of 2 yet at these radii"
    };
    writeln!(
        s,
        "\nLocal order of b(R) between R = {r1:e} and {r2:e} (the bar is what the two values' bars allow): {} — {verdict}.",
        slopes.join(", ")
    )
    .unwrap();
    Ok(())
}

/// The document, writing one SVG per scene into `figures_dir` (referenced
/// relative to the document as `figures/…`).
pub fn markdown(scenes_dir: &Path, figures_dir: &Path) -> Result<String, String> {
    std::fs::create_dir_all(figures_dir).map_err(|e| format!("{}: {e}", figures_dir.display()))?;
    let mut s = String::new();
    writeln!(s, "# The small-sphere model's own error, from the finite-sphere model").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "Generated by `cargo run --release -- model-error --out docs/model-error.md` from the bundled scenes; do not edit by hand. The finite-sphere model (`docs/model.md` §9) computes the estimator's mean and Var L exactly at any R for uncollided light, and for single-scattered light in isotropic media (point lights and beams, at any q and N_B: §9.6–§9.8, §9.11) and for point lights in Henyey–Greenstein media at q = 1, N_B = 1 (§9.9, §9.10), and the mean of every scattering order for point lights in isotropic media (§10.2, its own section below); the small-sphere model (§3–§6) is the paper's, exact only as R → 0. Every number is an f64 oracle result at the default relative tolerance (1e−10; 1e−6 with scattered light; the rows marked † at 1e−3; the every-order section at 1e−8, as it says), with its propagated bar. The reference tracer agrees with the finite-sphere model without any allowance (`tests/tracer_vs_finite.rs`, [tracer-checks.md](tracer-checks.md)).").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "## At the radii renderers use").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| scene | R | q | N_F | N_B | mean: finite/small − 1 | Var L: finite/small − 1 |").unwrap();
    writeln!(s, "|---|---:|---:|---:|---:|---:|---:|").unwrap();
    let mut iso = bundled(scenes_dir, "point-isotropic")?;
    iso.estimator.radius = 0.2;
    headline(&mut s, "point light, isotropic", &iso)?;
    let mut hg = bundled(scenes_dir, "point-hg-forward")?;
    hg.estimator.radius = 0.2;
    hg.estimator.forward_rays = 20;
    hg.estimator.camera_rays = 2;
    headline(&mut s, "point light, HG g = 0.9", &hg)?;
    let mut near = iso.clone();
    near.lights[0] = mcrt_scene::Light::Point { position: mcrt_scene::DVec3::new(0.1, 0.0, 1.0), flux: 1.0 };
    headline(&mut s, "light 0.1 from the camera line (inside the spheres)", &near)?;
    near.medium.phase = Phase::HenyeyGreenstein { g: 0.99 };
    headline(&mut s, "the same, HG g = 0.99", &near)?;
    let mut single = order1_scene(scenes_dir)?;
    single.estimator.radius = 0.2;
    single.estimator.forward_rays = 20;
    headline(&mut s, "single-scattered light (order 1), isotropic", &single)?;
    let mut beam = order1_beam_scene(scenes_dir)?;
    beam.estimator.radius = 0.2;
    beam.estimator.forward_rays = 20;
    headline(&mut s, "single-scattered light of a beam (order 1), isotropic", &beam)?;
    let mut paired = bundled(scenes_dir, ORDER1_SCENE)?;
    (paired.estimator.radius, paired.estimator.forward_rays) = (0.2, 20);
    headline_with_pairs(&mut s, "single-scattered light (order 1), isotropic, with C₂₃, C₂₄ and Q †", &paired)?;
    let mut hg1 = bundled(scenes_dir, "point-hg-backward")?;
    hg1.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
    (hg1.estimator.radius, hg1.estimator.q, hg1.estimator.forward_rays, hg1.estimator.camera_rays) = (0.2, 1.0, 20, 1);
    headline_with_pairs(&mut s, "single-scattered light (order 1), HG g = −0.5 †", &hg1)?;
    writeln!(s).unwrap();
    writeln!(s, "† At the goal {PAIRS_TOL:e} (the library's `predict`'s for these integrals; `Scope::FinitePairs`, `mcrt-noise oracle --finite-pairs`), with the bars it reached. The first needs the finite-sphere correlations of two spheres (`docs/model.md` §9.7), the second the same-path term of a Henyey–Greenstein medium (§9.10); the small-sphere model beside them has its (23), (24) with the cross-segment terms of erratum E10 in the isotropic medium, and none in the Henyey–Greenstein one, where they are not derived (§3c). A Henyey–Greenstein medium at q < 1 or N_B > 1 has no row: the finite-sphere correlations there are derived but not computed (§9.12).").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "A forward-peaked medium magnifies the error (the phase function varies across a sphere); spheres that contain the light change the estimator altogether (with g = 0.99 the pixel's mean is ten times and its variance ten thousand times the small-sphere value: the light heading for the camera is collected by every sphere around it).").unwrap();
    let mut orders = Vec::new();
    let sections = MODEL_SCENES
        .iter()
        .map(|&(name, label)| Ok((name, label, bundled(scenes_dir, name)?)))
        .chain([order1_scene(scenes_dir)
            .map(|s| (ORDER1_SCENE, "single-scattered light (order 1), point light, isotropic medium", s))]);
    for section in sections {
        let (name, label, scene): (&str, &str, Scene) = section?;
        let rows = sweep(&scene, &MODEL_RADII).map_err(|e| e.to_string())?;
        if let (Some(m), Some(v)) =
            (fit_finite_order(&rows, FiniteRatio::Mean), fit_finite_order(&rows, FiniteRatio::Variance))
        {
            orders.push(format!(
                "`{name}` {:.2} ± {:.0e} (mean), {:.2} ± {:.0e} (Var L)",
                m.order, m.error, v.order, v.error
            ));
        }
        writeln!(s, "\n## `{name}`: {label}\n").unwrap();
        writeln!(
            s,
            "q = {}, N_F = {}, N_B = {}. The mean's relative difference is the estimator's relative bias b(R)/μ(0): μ(0), the small-sphere mean, is the luminance it converges to as R → 0.\n",
            scene.estimator.q, scene.estimator.forward_rays, scene.estimator.camera_rays
        )
        .unwrap();
        s.push_str(&finite_table(&rows));
        let svg = figure(name, &rows)?;
        let file = figures_dir.join(format!("model-error-{name}.svg"));
        std::fs::write(&file, svg).map_err(|e| format!("{}: {e}", file.display()))?;
        writeln!(s, "\n![|finite/small − 1| against R, {name}](figures/model-error-{name}.svg)").unwrap();
    }
    every_order_section(&mut s, scenes_dir)?;
    writeln!(s, "\n## Summary\n").unwrap();
    writeln!(s, "Observed orders of |finite/small − 1| (local slopes at the two smallest resolved radii, with how far they still moved over the previous decade): {}. For uncollided light the small-sphere model becomes exact at second order in R: at R = 10⁻⁶ the two differ by less than 10⁻¹⁰ (`tests/finite.rs`). With single-scattered light the mean still does, but Var L's gap falls more slowly, like R² ln(1/R) (the same-path hits of grazing first segments in M₂, `docs/model.md` §9.6: its fitted order rises towards 2 as R falls; at that model's default tolerance 10⁻⁶ the gaps below R = 10⁻² are within 100 of their bars and stay out of the fit).", orders.join("; ")).unwrap();
    Ok(s)
}
