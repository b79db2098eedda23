//! Where an oracle run's time goes: every integral of both models timed
//! alone, in order, with its value, bar and evaluations
//! (`mcrt_noise::reports::cost::profile::integral_costs`; the cost report
//! prints the same table). Shared tables are built by the first integral
//! that needs them, so later ones may be cheaper.
//!
//! `RAYON_NUM_THREADS=1 cargo run --release --example profile_oracle -- SCENE [f64|BITS] [REL_TOL]`

use mcrt_noise::oracle::Precision;
use mcrt_noise::reports::cost::profile::integral_costs;
use mcrt_noise::Scene;
use rug::Float;

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
    let costs = match precision {
        Precision::F64 => integral_costs(&scene, &0.0f64, tol)?,
        Precision::Bits(b) => integral_costs(&scene, &Float::with_val(b, 0), tol)?,
        other => return Err(format!("{other:?}: a precision this example does not know").into()),
    };
    for c in costs {
        match c.outcome {
            Ok((v, e, n)) => println!("{:28} {:10.1} ms  {v:.10e} ± {e:.1e}  {n} evaluations", c.name, c.seconds * 1e3),
            Err(why) => println!("{:28} {:10.1} ms  {why}", c.name, c.seconds * 1e3),
        }
    }
    Ok(())
}
