use mcrt_noise::model::field::Field;
use mcrt_noise::quad::{Options, Rule};
fn main() {
    let text = std::fs::read_to_string("scenes/point-isotropic-order1.toml").unwrap();
    let scene = mcrt_scene::Scene::from_toml_str(&text).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let at = field.scattered[0].at(&-0.5, &1.0, &field.sigma_sc);
    println!("psi_u {}", at.frame.psi_u);
    for psi in [1.107148717781902, 1.1071487172440904, 1.0] {
        for rule in [Rule::TanhSinh, Rule::Check] {
            let o = Options { cross_check: false, zero_guard: false, rule, abs_tol: 0.0, ..Options::rel(2.5e-13).declared() };
            match at.source(&psi, &1.0, &field.phase, &o) {
                Ok(e) => println!("{psi} {rule:?}: {} ± {:e} evals {}", e.value, e.error, e.evaluations),
                Err(f) => println!("{psi} {rule:?}: {f}"),
            }
        }
    }
}
