use mcrt_noise::kernel::*;
use mcrt_noise::quad::{Options, Rule};
use mcrt_noise::report::mpfr_default_tol;
use rug::Float;
use std::time::Instant;
fn main() {
    let bits = 128;
    let th = Float::with_val(bits, 1);
    let a = Angle::from_theta(&th);
    let r = parse_decimal("1e-3", bits).unwrap();
    for (check, rule) in [(true, Rule::TanhSinh), (false, Rule::TanhSinh), (false, Rule::Check)] {
        let mut o = Options::rel(mpfr_default_tol(bits));
        o.cross_check = check;
        o.rule = rule;
        let t0 = Instant::now();
        let e = kernel_integral(&a, &r, &o).unwrap();
        println!("check={check} {rule:?} evals {} time {:?}", e.evaluations, t0.elapsed());
    }
    // raw eval cost
    let x = Float::with_val(bits, 0.7);
    let t0 = Instant::now();
    let mut acc = Float::with_val(bits, 0);
    for _ in 0..10000 {
        acc += mcrt_noise::special::overlap_a(&x);
    }
    println!("A(0.7) {:?}/eval", t0.elapsed() / 10000);
    let x = Float::with_val(bits, 0.3);
    let t0 = Instant::now();
    for _ in 0..10000 {
        acc += mcrt_noise::special::overlap_a(&x);
    }
    println!("A(0.3) {:?}/eval", t0.elapsed() / 10000);
    let t0 = Instant::now();
    for _ in 0..10000 {
        acc += x.clone().exp();
    }
    println!("exp {:?}/eval", t0.elapsed() / 10000);
}
