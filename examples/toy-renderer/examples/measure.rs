//! Renders the scene of `/tmp/toy/scene.toml` (σ_ext 1, albedo 0.8, HG g = 0.5, point light at (1, 0, 1),
//! camera at the origin looking +z, R = 0.2, q = 0.5, N_F = 20, N_B = 4) with every [`Bug`], and compares mean and
//! Var L with the oracle's finite-sphere prediction.
//!
//! Usage: `measure [ITERATIONS] [SEED] [ORACLE_MEAN ORACLE_VAR]`.

use std::time::Instant;

use toy_renderer::{render_range, Bug, ToyScene};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let m: u64 = args.first().map_or(1_000_000, |a| a.parse().expect("ITERATIONS"));
    let seed: u64 = args.get(1).map_or(1, |a| a.parse().expect("SEED"));
    // `mcrt-noise oracle /tmp/toy/scene.toml`, finite-sphere column.
    let oracle_mean: f64 = args.get(2).map_or(9.7594513594e-4, |a| a.parse().expect("ORACLE_MEAN"));
    let oracle_var: f64 = args.get(3).map_or(9.3288085230e-6, |a| a.parse().expect("ORACLE_VAR"));
    let scene = ToyScene::example();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get() as u64);
    println!("M = {m}, seed {seed}, {threads} threads; oracle mean {oracle_mean:.6e}, Var L {oracle_var:.6e}");
    println!(
        "{:<16} {:>24} {:>24} {:>8} {:>8} {:>9} {:>9} {:>10}",
        "bug", "mean ± se", "Var L ± se", "z mean", "z Var", "Δmean", "ΔVar", "iter/s"
    );
    for bug in Bug::ALL {
        let start = Instant::now();
        let values: Vec<f64> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|t| {
                    let scene = &scene;
                    scope.spawn(move || render_range(scene, bug, m * t / threads..m * (t + 1) / threads, seed))
                })
                .collect();
            handles.into_iter().flat_map(|h| h.join().expect("thread")).collect()
        });
        let rate = m as f64 / start.elapsed().as_secs_f64();

        let n = m as f64;
        let mean = values.iter().sum::<f64>() / n;
        let (mut m2, mut m4) = (0.0, 0.0);
        for &x in &values {
            let d2 = (x - mean) * (x - mean);
            m2 += d2;
            m4 += d2 * d2;
        }
        let var = m2 / (n - 1.0);
        let (mu2, mu4) = (m2 / n, m4 / n);
        let se_mean = (var / n).sqrt();
        // Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)).
        let se_var = (mu4 / n - mu2 * mu2 * (n - 3.0) / (n * (n - 1.0))).sqrt();
        println!(
            "{:<16} {:>24} {:>24} {:>8.2} {:>8.2} {:>+8.2}% {:>+8.2}% {:>10.3e}",
            format!("{bug:?}"),
            format!("{mean:.5e} ± {se_mean:.1e}"),
            format!("{var:.5e} ± {se_var:.1e}"),
            (mean - oracle_mean) / se_mean,
            (var - oracle_var) / se_var,
            100.0 * (mean / oracle_mean - 1.0),
            100.0 * (var / oracle_var - 1.0),
            rate,
        );
    }
}
