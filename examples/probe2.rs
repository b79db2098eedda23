use mcrt_noise::quad::*;
use mcrt_noise::special::overlap_a;

use rug::Float;
fn main() {
    let p = 128;
    let s = Float::with_val(p, 40.12515468181775f64);
    let th = Float::with_val(p, 1.0);
    let r = Float::with_val(p, 1e-3);
    let (sn, cs) = (th.clone().sin(), th.clone().cos());
    let edge = r.clone() * 2u32 / sn.clone();
    let f = |t: &Float| { let x = t.clone() * sn.clone() / (r.clone() * 2u32); overlap_a(&x) * (-(t.clone() * (cs.clone() + 1u32) + s.clone())).exp() };
    for bp in [true, false] {
        let mut d = Domain::semi_infinite(Float::with_val(p, 0));
        if bp { d = d.with_breakpoints([edge.clone()]); }
        let o = Options::rel(1e-34).with_abs_tol(1.6e-38);
        let o = if bp { o.declared() } else { o };
        match integrate(f, &d, &o) { Ok(e) => println!("bp={bp} {:.40e} ± {:e} check {:.40e} pieces {} evals {}", e.value, e.error.to_f64(), e.check_value, e.pieces, e.evaluations), Err(e) => println!("bp={bp} {e}") }
    }
}
