use mcrt_noise::kernel::*;
use mcrt_noise::quad::Options;
use std::time::Instant;
fn main() {
    let a = Angle::from_theta(&1.0f64);
    for check in [true, false] {
        let mut o = Options::rel(1e-13);
        o.cross_check = check;
        let t0 = Instant::now();
        let e = kernel_integral(&a, &1e-3, &o).unwrap();
        println!("check={check} evals {} time {:?} v {:e}", e.evaluations, t0.elapsed(), e.value);
    }
}
