//! Special functions of the seed paper, written once over [`Real`](crate::real::Real)
//! so the same code runs in f64 and in MPFR at any precision.
//!
//! | function | definition | paper |
//! |---|---|---|
//! | [`overlap_a`] | A(x) = arccos x − x√(1−x²), 0 for x ≥ 1 | §4.3, after (21) |
//! | [`overlap_a_integral`] | ∫₀ˣ A(y) dy | appendix, I₁ |
//! | [`overlap_a_moment`] | ∫₀ˣ A(y) y dy | appendix, bound on I₂ₐ |
//! | [`exp_int_e1`] | E₁(x) = ∫₁^∞ e^{−xt}/t dt | appendix, "Ei(1, X)" |
//! | [`isotropic_arc`] | 2∫_{tan(ψ/2)}^∞ e^{−a(u − u₀)}/(1 + u²) du = 2 Im[e^{z}E₁(z)] | single-scattered source (isotropic) |
//! | [`exp_int_tail2`] | X⁻¹(e^{−X} − X E₁(X)) = ∫_X^∞ u⁻² e^{−u} du | appendix, bound on I₂ |
//! | [`overlap_a_gap`] | A(1 − u), the unit disc's segment of height u | finite spheres |
//! | [`complete_elliptic_e`] | E(m) = ∫₀^{π/2} √(1 − m sin²θ) dθ, from k′ = √(1 − m) | finite spheres (HG azimuth) |
//! | [`hg_ring`] | ∫₀^{2π} f(cos)^k dχ of Henyey–Greenstein f on a circle of directions | finite spheres (HG caps), same-path kernel |
//! | [`disc_overlap`] | area common to two discs | finite spheres (beams) |
//! | [`arc_in_disc`] | angle of a circle inside a disc | finite spheres (beams, single scattering) |
//! | [`exp_segment`] | ∫₀^L e^{−rx} dx | finite spheres (per-ray functionals) |
//! | [`exp_triangle`] | ∫∫_{0<x<x′<L} e^{−(r₂−r₁)x − r₁x′} dx dx′ | finite spheres (per-ray functionals) |
//!
//! Accuracy in f64 (measured against MPFR at ≥ 256 bits): `docs/accuracy.md`.

mod complex_e1;
mod elliptic;
mod expint;
mod exponential;
mod hg_ring;
mod lens;
mod overlap;
mod series;

pub use complex_e1::isotropic_arc;
pub use elliptic::complete_elliptic_e;
pub use expint::{exp_int_e1, exp_int_e1_scaled, exp_int_tail2};
pub use exponential::{exp_segment, exp_triangle};
pub use hg_ring::hg_ring;
pub use lens::{arc_in_disc, arc_in_disc_gaps, disc_overlap};
#[cfg(feature = "mpfr")]
pub(crate) use overlap::laplace_sum;
pub use overlap::{overlap_a, overlap_a_gap, overlap_a_integral, overlap_a_laplace, overlap_a_moment};
