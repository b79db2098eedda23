use mcrt_noise::accuracy::*;
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(3000);
    for f in SpecialFn::ALL {
        for s in sweep(f, n) {
            println!("{:22} {:38} max {:6.2} at {:e}  median {:.2}", s.function, s.segment, s.max_ulps, s.max_at, s.median_ulps);
        }
    }
}
