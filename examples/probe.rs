use mcrt_noise::accuracy::*;
fn main() {
    for (f, x) in [(SpecialFn::OverlapAIntegral, 1.4120480812370443e-300), (SpecialFn::OverlapAMoment, 2.5289884570516835e-154), (SpecialFn::OverlapAMoment, 1e-10)] {
        println!("{:?} {x:e} got {:e} ref {:?} ulps {}", f, f.eval_f64(x), debug_ref(f,x), ulps_at(f, x));
    }
}
