use mcrt_noise::kernel::*;
use mcrt_noise::quad::Options;
use rug::Float;
use std::time::Instant;
fn main() {
    let cases: [(f64, bool, f64, &str); 6] = [ // (θ or δ, from pole, R, ref)
        (1.0, false, 1e-3, "1.5828197124289608462e-3"),
        (std::f64::consts::FRAC_PI_2, false, 1e-3, "1.332548290594632370694605e-3"),
        (std::f64::consts::FRAC_PI_2, false, 1e-9, "1.333333332547935170291441e-9"),
        (1e-6, true, 1e-3, "0.785148163413269578752875"),
        (1e-6, true, 1e-9, "1.3317639581824350088917e-3"),
        (1e-6, false, 1e-9, "1.3317639581824350088917e-3"),
    ];
    for (th, pole, r, refs) in cases {
        let reference = Float::with_val(200, Float::parse(refs).unwrap());
        let angle = if pole { Angle::from_pole(&th) } else { Angle::from_theta(&th) };
        let t0 = Instant::now();
        let res = kernel_integral(&angle, &r, &Options::rel(1e-13));
        let dt = t0.elapsed();
        match res {
            Ok(e) => println!("f64 θ={th} R={r}: {:.17e} ± {:.1e} evals {} relerr {:.2e} time {:?} pieces {}", e.value, e.error, e.evaluations, ((e.value - reference.to_f64())/reference.to_f64()).abs(), dt, e.pieces),
            Err(f) => println!("f64 θ={th} R={r}: {f}"),
        }
        let t0 = Instant::now();
        let res = kernel_integral_bare(&angle, &r, &Options::rel(1e-13));
        match res {
            Ok(e) => println!("  bare: {:.17e} ± {:.1e} evals {} relerr {:.2e} time {:?} found {}", e.value, e.error, e.evaluations, ((e.value - reference.to_f64())/reference.to_f64()).abs(), t0.elapsed(), e.found_breakpoints),
            Err(f) => println!("  bare: {f}"),
        }
        let p = 128;
        let dec = |v: f64| if v == std::f64::consts::FRAC_PI_2 { Float::with_val(p, rug::float::Constant::Pi) / 2u32 } else { Float::with_val(p, Float::parse(format!("{v:e}")).unwrap()) };
        let thf = dec(th);
        let angle = if pole { Angle::from_pole(&thf) } else { Angle::from_theta(&thf) };
        let t0 = Instant::now();
        match kernel_integral(&angle, &dec(r), &Options::rel(1e-32)) {
            Ok(e) => { let rel = ((e.value.clone() - reference.clone())/reference.clone()).abs(); println!("  128: {:.30e} ± {:.1e} evals {} relerr {:.2e} time {:?}", e.value.to_f64(), e.error.to_f64(), e.evaluations, rel.to_f64(), t0.elapsed()) }
            Err(f) => println!("  128: {f}"),
        }
    }
}
