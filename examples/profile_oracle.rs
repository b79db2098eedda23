//! Where an oracle run's time goes: every integral of both models timed
//! alone, in order, on one thread (set `RAYON_NUM_THREADS=1` for strictly
//! one), with its value, bar and evaluations. Shared tables are built by the
//! first integral that needs them, so later ones may be cheaper.
//!
//! `cargo run --release --example profile_oracle -- SCENE [f64|BITS] [REL_TOL]`

use mcrt_noise::model::correlations::{self, Which};
use mcrt_noise::model::field::Field;
use mcrt_noise::model::finite::{FiniteField, Functional};
use mcrt_noise::model::moments;
use mcrt_noise::oracle::Precision;
use mcrt_noise::quad::{CheckRule, Estimate, Options};
use mcrt_noise::Scene;
use rug::Float;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().ok_or("usage: profile_oracle SCENE [f64|BITS] [REL_TOL]")?;
    let scene = Scene::from_toml_str(&std::fs::read_to_string(path)?)?;
    let precision = Precision::parse(args.get(1).map_or("f64", String::as_str))?;
    let tol = match args.get(2) {
        Some(t) => t.parse()?,
        None => precision.default_tol_for(&scene),
    };
    println!("{path}: {precision:?}, rel. tolerance {tol:e}");
    match precision {
        Precision::F64 => profile(&scene, &0.0f64, tol),
        Precision::Bits(b) => profile(&scene, &Float::with_val(b, 0), tol),
    }
}

fn profile<T: CheckRule>(scene: &Scene, like: &T, tol: f64) -> Result<(), Box<dyn std::error::Error>> {
    let field = Field::from_scene(scene, like)?;
    let r = like.lit(scene.estimator.radius);
    let o = Options::rel(tol).declared();
    let time = |name: &str, run: &dyn Fn() -> Result<Estimate<T>, String>| {
        let t0 = Instant::now();
        let out = run();
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        match out {
            Ok(e) => println!(
                "{name:28} {ms:10.1} ms  {:.10e} ± {:.1e}  {} evaluations",
                e.value.to_f64(),
                e.error.to_f64(),
                e.evaluations
            ),
            Err(why) => println!("{name:28} {ms:10.1} ms  {why}"),
        }
    };
    let s = |e: mcrt_noise::model::OracleError| e.to_string();
    time("small-sphere mean", &|| moments::mean_luminance(&field, &o).map_err(s));
    time("small-sphere M2", &|| moments::m2(&field, &r, &o).map_err(s));
    time("small-sphere P", &|| moments::p_single(&field, &o).map_err(s));
    time("small-sphere Q", &|| moments::q_pair(&field, &o).map_err(s));
    time("small-sphere (23) exact", &|| correlations::exact(&field, &r, Which::Eq23, &o).map_err(s));
    time("small-sphere (24) exact", &|| correlations::exact(&field, &r, Which::Eq24, &o).map_err(s));
    time("small-sphere (25) R -> 0", &|| correlations::asymptotic(&field, &r, Which::Eq23, &o).map_err(s)?);
    time("small-sphere (26) R -> 0", &|| correlations::asymptotic(&field, &r, Which::Eq24, &o).map_err(s)?);
    if let Some(ff) = FiniteField::from_scene(scene, &field) {
        for (name, which) in [
            ("finite-sphere mean", Functional::Mean),
            ("finite-sphere M2", Functional::Second),
            ("finite-sphere C23", Functional::Pair23),
            ("finite-sphere C24", Functional::Pair24),
        ] {
            time(name, &|| ff.ray_total(which, &o).map_err(s));
        }
        let t0 = Instant::now();
        let (p, q) = ff.p_and_q(&o);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        let ev = |e: &Result<Estimate<T>, _>| e.as_ref().map_or(0, |e| e.evaluations);
        println!("{:28} {ms:10.1} ms  {} + {} evaluations", "finite-sphere P and Q", ev(&p), ev(&q));
    }
    Ok(())
}
