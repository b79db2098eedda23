use mcrt_noise::model::angular::{Direction, Features, Measure, Pole};
use mcrt_noise::model::field::Field;
use mcrt_noise::quad::{Estimate, Options, Rule};
use std::time::Instant;
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let text = std::fs::read_to_string(path).unwrap();
    let scene = mcrt_scene::Scene::from_toml_str(&text).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let none = || Pole { floor: None, marks: Vec::new() };
    let (n0, npi) = mcrt_noise::model::scattered::source_features(&field.phase, &0.0);
    let features = Features { plus: none(), minus: none(), equator_jump: false, source_near_0: n0, source_near_pi: npi };
    static GC: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let g = |d: &Direction<f64>, o: &Options| { GC.fetch_add(1, std::sync::atomic::Ordering::Relaxed); Ok(Estimate::known(field.phase_at(&d.mu), 0.0, 1, o.rule)) };
    for x in [-0.9, 0.0, 0.5, 3.0] {
        let at = field.scattered[0].at(&x, &field.sigma_ext, &field.sigma_sc);
        for rule in [Rule::TanhSinh, Rule::Check] {
            for tol in [1e-6, 1e-10] {
                let t = Instant::now();
                let table = at.source_table(&field.sigma_ext, &field.phase, tol, rule).unwrap();
                let t1 = t.elapsed();
                let l1 = |p: &f64, pc: &f64, sp: &f64| table.radiance(p, pc, sp);
                let o = Options { rule, cross_check: false, zero_guard: false, ..Options::rel(tol).declared() };
                GC.store(0, std::sync::atomic::Ordering::Relaxed);
                let e = at.frame.view_integral(&features, Measure::Solid, &g, &l1, &o).unwrap();
                println!("g calls {}", GC.load(std::sync::atomic::Ordering::Relaxed));
                let t2 = t.elapsed();
                let o2 = Options { rule, cross_check: false, zero_guard: false, ..Options::rel(tol).declared() };
                let chi = at.integral(&field.sigma_ext, &field.phase, &features, &g, &o2).unwrap();
                let t3 = t.elapsed();
                println!("x {x} {rule:?} tol {tol:e}: table {:?} ({} evals, rel {:e}) view {} ± {:e} ({} evals) {:?} | chi {} ± {:e} {:?}  diff {:e}",
                    t1, table.evaluations, table.rel_error, e.value, e.error, e.evaluations, t2 - t1, chi.value, chi.error, t3 - t2, (e.value/chi.value - 1.0));
            }
        }
    }
}
