use mcrt_noise::model::angular::{Direction, Features, Frame, Pole};
use mcrt_noise::quad::{Estimate, Options};
fn main() {
    let frame = Frame::new(-0.5f64 / 1.25f64.sqrt(), 1.0 / 1.25f64.sqrt());
    let features = Features {
        plus: Pole { floor: Some(0.0), marks: vec![] },
        minus: Pole { floor: Some(0.0), marks: vec![] },
        equator_jump: false,
        source_near_0: None,
        source_near_pi: None,
    };
    let g = |d: &Direction<f64>, o: &Options| Ok(Estimate::known(1.0 / d.sin, 0.0, 1, o.rule));
    for off in [-1.2188e-11, -5.5e-10, 1e-12] {
        for rule in [mcrt_noise::quad::Rule::TanhSinh, mcrt_noise::quad::Rule::Check] {
            let psi = frame.psi_u + off;
            let o = Options { cross_check: false, zero_guard: false, rule, abs_tol: 1e-17, ..Options::rel(2.5e-13).declared() };
            match frame.around(&psi, &features, &g, &o) {
                Ok(e) => println!("off {off:e} {rule:?}: {} ± {:e} evals {}", e.value, e.error, e.evaluations),
                Err(f) => println!("off {off:e} {rule:?}: {f}"),
            }
        }
    }
}
