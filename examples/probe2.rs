use mcrt_noise::model::correlations::{self, Which};
use mcrt_noise::model::field::Field;
use mcrt_noise::model::moments;
use mcrt_noise::quad::Options;
use std::time::Instant;
fn main() {
    let text = std::fs::read_to_string("scenes/point-isotropic-order1.toml").unwrap();
    let scene = mcrt_scene::Scene::from_toml_str(&text).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let rel: f64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let o = Options::rel(rel).declared();
    let t = Instant::now();
    let e = moments::mean_luminance(&field, &o).unwrap();
    println!("mean {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    let t = Instant::now();
    let e = moments::m2(&field, &0.01, &o).unwrap();
    println!("m2 {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    let t = Instant::now();
    let e = moments::p_single(&field, &o).unwrap();
    println!("p {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    let t = Instant::now();
    let e = correlations::asymptotic(&field, &0.01, Which::Eq23, &o).unwrap().unwrap();
    println!("asym23 {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    let t = Instant::now();
    let e = correlations::exact(&field, &0.01, Which::Eq23, &o).unwrap();
    println!("views {} check {}", mcrt_noise::model::scattered::VIEWS.load(std::sync::atomic::Ordering::Relaxed), mcrt_noise::model::scattered::VIEWS_CHECK.load(std::sync::atomic::Ordering::Relaxed));
    println!("corr23 {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    if std::env::args().nth(2).is_some() {
        let t = Instant::now();
        let e = moments::q_pair(&field, &o).unwrap();
        println!("q {} ± {:e} evals {} {:?}", e.value, e.error, e.evaluations, t.elapsed());
    }
}
