static G_CALLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
static J_QUAD: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
static J_EVALS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
use mcrt_noise::model::field::Field;
use mcrt_noise::model::moments;
use mcrt_noise::quad::Options;
use std::time::Instant;
fn main() {
    corr();
    return;
    let text = std::fs::read_to_string("scenes/point-isotropic-order1.toml").unwrap();
    let scene = mcrt_scene::Scene::from_toml_str(&text).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    for rel in [1e-6, 1e-8, 1e-10, 1e-12] {
        let o = Options::rel(rel).declared();
        let o = Options { cross_check: false, zero_guard: false, ..o };
        let t = Instant::now();
        let e = moments::mean_contribution_estimate(&field, &0.3, &o).unwrap();
        println!("mean rel {rel:e}: {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    }
}
#[allow(dead_code)]
fn unused() {}
pub fn corr() {
    use mcrt_noise::model::angular::Direction;
    use mcrt_noise::model::correlations::{pair_features, separation, Which};
    use mcrt_noise::quad::Estimate;
    let text = std::fs::read_to_string("scenes/point-isotropic-order1.toml").unwrap();
    let scene = mcrt_scene::Scene::from_toml_str(&text).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let r = 0.01;
    for x in [-0.99, -0.5, 0.3, 2.0] {
        let s_abs = field.s_of(&x);
        for rel in [5e-8] {
        for rule in [mcrt_noise::quad::Rule::TanhSinh, mcrt_noise::quad::Rule::Check] {
            let o = Options { rule, cross_check: false, zero_guard: false, abs_tol: rel * 1e-6, ..Options::rel(rel).declared() };
            let g = |d: &Direction<f64>, o: &Options| {
                G_CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let f = field.phase_at(&d.mu);
                let j = separation(&1.0, Which::Eq23, d.mu >= 0.0, &d.mu, &d.sin, &s_abs, &(2.0 * r), o)?;
                if j.evaluations > 1 { J_QUAD.fetch_add(1, std::sync::atomic::Ordering::Relaxed); J_EVALS.fetch_add(j.evaluations, std::sync::atomic::Ordering::Relaxed); }
                Ok(Estimate::known(f * f * j.value, f * f * j.error, j.evaluations, o.rule))
            };
            let at = field.scattered[0].at(&x, &1.0, &field.sigma_sc);
            let t = Instant::now();
            let e = at.view(&1.0, &field.phase, &pair_features(&field, &r, &s_abs), mcrt_noise::model::angular::Measure::Solid, &g, &o).unwrap();
            println!("g calls {} jquad {} jevals {}", G_CALLS.swap(0, std::sync::atomic::Ordering::Relaxed), J_QUAD.swap(0, std::sync::atomic::Ordering::Relaxed), J_EVALS.swap(0, std::sync::atomic::Ordering::Relaxed));
            println!("corr x {x} rel {rel:e} {rule:?}: {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
        }}
    }
}
