//! The pixel variance of one iteration, (7)–(9), from the integrals of
//! [`super::moments`] and [`super::correlations`], exactly and in the R → 0
//! form of §4.4 with D₁…D₅ made explicit.
//!
//! With μ = ⟨⟨Ĉ⟩⟩ (15), A′ = ⟨⟨Ĉ²⟩⟩ = q M₂ + 2(1−q) C₂₃ (16),
//! B′ = ⟨⟨Ĉ⟩_F²⟩_B = q P + 2(1−q) Q (17), C′ = ⟨⟨Ĉ⟩_B²⟩_F = C₂₄ (18):
//!
//! Var L = (A′ − μ²)/(N_F N_B) + (1/N_B)(1 − 1/N_F)(B′ − μ²) + (1/N_F)(1 − 1/N_B)(C′ − μ²)
//!
//! (7)–(9) exactly. The paper's total in §4.4 keeps only −μ²/(N_F N_B) of the
//! three −μ² terms; the relative-noise formula there inherits it. Here
//!
//! Var L/μ² ≈ (1/(R² N_F)) [(q D₁ + σR(1−q) D₂)/N_B + (1 − 1/N_B) σR D₃]
//!          + (1/N_B)(1 − 1/N_F)(q D₄ + (1−q) D₅) + 1/(N_F N_B) − 1/N_F − 1/N_B
//!
//! with D₁ = R² M₂/μ², D₂ = 2R C₂₃^asym/(σμ²), D₃ = R C₂₄^asym/(σμ²),
//! D₄ = P/μ², D₅ = 2Q/μ²: all independent of R, q and the ray counts —
//! except that with scattered light M₂ holds the same-path double hits M₂ₓ
//! (E9, O(1/R)), so that D₁ = D₁⁽⁰⁾ + σR·RM₂ₓ/(σμ²) is then first order in R
//! (the formula stays exact in it).

use super::correlations::{self, Which};
use super::cross_segment;
use super::field::Field;
use super::moments;
use super::OracleError;
use crate::quad::{CheckRule, Estimate, Options};
use crate::real::Real;

/// A value with its error bar.
#[derive(Debug, Clone)]
pub struct Valued<T> {
    /// The value.
    pub value: T,
    /// Bound on |value − exact|.
    pub error: T,
}

impl<T: Real> From<&Estimate<T>> for Valued<T> {
    fn from(e: &Estimate<T>) -> Self {
        Valued { value: e.value.clone(), error: e.error.clone() }
    }
}

/// Every integral of the model for one scene, each times e^{c₀} (every W
/// carried as W·e^{c₀}, `Field::shift`).
#[derive(Debug, Clone)]
pub struct Integrals<T> {
    /// ⟨⟨L⟩⟩ (15).
    pub mean: Estimate<T>,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩ ds, the single-sphere part of (16), with the
    /// same-path double hits [`Integrals::m2_same_path`] included.
    pub m2: Estimate<T>,
    /// M₂ₓ, the part of `m2` from one path hitting a sphere with two
    /// segments (E9; zero for uncollided light).
    pub m2_same_path: Estimate<T>,
    /// P = ∫σe^{−σs}⟨𝒞⟩² ds, the single-sphere part of (17).
    pub p: Estimate<T>,
    /// The integrals of two spheres of one camera ray (Q, (23), (24) and
    /// their R → 0 forms); `None` when not computed
    /// ([`Integrals::compute_single_sphere`]).
    pub pairs: Option<PairIntegrals<T>>,
}

/// The integrals of two spheres of one camera ray, each times e^{c₀}: what
/// (7)–(9) weigh 0 when q = 1 and N_B = 1 (one sphere per camera ray, one
/// camera ray per iteration).
#[derive(Debug, Clone)]
pub struct PairIntegrals<T> {
    /// Q = ∫∫_{t>0}⟨𝒞⟩(s)⟨𝒞⟩(s+t)σ²e^{−σ(s+t)} ds dt, the pair part of (17).
    pub q: Estimate<T>,
    /// C₂₃, the integral (23) at radius R: exact for the one-segment part,
    /// plus the cross-segment term [`PairIntegrals::c23_cross`] of
    /// single-scattered light where it is added (an R → 0 form).
    pub c23: Estimate<T>,
    /// C₂₄, the integral (24) at radius R: exact for the one-segment part,
    /// plus [`PairIntegrals::c24_cross`] where it is added, as for `c23`.
    pub c24: Estimate<T>,
    /// X₂₃, the part of `c23` from the two segments of one path meeting one
    /// sphere each (E10; its R → 0 form, `cross_segment`): `None` for
    /// uncollided light; `Some(Err(why))` where it is not added (`cross_term`:
    /// Henyey–Greenstein media, R outside the form's checked range, a
    /// failure, or a form not positive).
    pub c23_cross: Option<Result<Estimate<T>, String>>,
    /// X₂₄, the part of `c24` likewise.
    pub c24_cross: Option<Result<Estimate<T>, String>>,
    /// (25), the R → 0 form of (23), or why it does not exist.
    pub c23_asym: Result<Estimate<T>, String>,
    /// (26), the R → 0 form of (24), or why it does not exist.
    pub c24_asym: Result<Estimate<T>, String>,
}

impl<T: CheckRule> Integrals<T> {
    /// Computes all integrals for spheres of radius `r`. The evaluations of
    /// the field's along-ray tables (single-scattered light), which every
    /// integral reads, are charged to the mean once, at the end (as the
    /// finite-sphere model's order-1 tables are, and its Henyey–Greenstein
    /// ⟨𝒞⟩ tables to P): with a field used for one computation the counts
    /// are then complete and do not depend on which thread built a table.
    pub fn compute(field: &Field<T>, r: &T, opts: &Options) -> Result<Integrals<T>, OracleError> {
        Integrals::compute_all(field, r, opts, false).map(|(ints, _)| ints)
    }

    /// [`Integrals::compute`] for a scene whose Var L weighs the pair
    /// integrals 0 (q = 1 and N_B = 1): they are computed (they give
    /// D₁…D₅ and the noise at other settings), but where they fail the
    /// failure is returned beside μ, M₂ and P, with `pairs` `None`,
    /// instead of failing the whole computation, since Var L does not
    /// need them.
    pub fn compute_with_optional_pairs(
        field: &Field<T>,
        r: &T,
        opts: &Options,
    ) -> Result<(Integrals<T>, Option<OracleError>), OracleError> {
        Integrals::compute_all(field, r, opts, true)
    }

    /// Both of the above: every integral, the pairs' failure returned
    /// beside the rest where they are `optional`.
    fn compute_all(
        field: &Field<T>,
        r: &T,
        opts: &Options,
        optional: bool,
    ) -> Result<(Integrals<T>, Option<OracleError>), OracleError> {
        let opts = opts.clone().declared();
        let o = &opts;
        // Independent integrals, computed side by side (each is
        // deterministic, so the result does not depend on the threads).
        // One tree, so that the moments fill the time a thread would
        // otherwise wait for the longest correlation pass; (23) before (24),
        // so that (24) mostly finds the angular work of the same nodes done.
        let (pairs, single) =
            rayon::join(|| PairIntegrals::compute(field, r, o), || Integrals::single_sphere_parts(field, r, o));
        let (mut ints, failed) = Integrals::assemble(single, pairs, optional)?;
        ints.mean.evaluations += field.table_evaluations();
        Ok((ints, failed))
    }

    /// μ, M₂, P and the pair integrals as one result; the failures in the
    /// order of the fields (the mean's first), a failure of the pairs
    /// returned beside the rest where they are `optional`.
    fn assemble(
        single: Result<Integrals<T>, OracleError>,
        pairs: Result<PairIntegrals<T>, OracleError>,
        optional: bool,
    ) -> Result<(Integrals<T>, Option<OracleError>), OracleError> {
        let mut ints = single?;
        match pairs {
            Ok(p) => ints.pairs = Some(p),
            Err(e) if optional => return Ok((ints, Some(e))),
            Err(e) => return Err(e),
        }
        Ok((ints, None))
    }

    /// μ, M₂ and P alone (`pairs` is `None`): all that Var L needs when
    /// q = 1 and N_B = 1, where (7)–(9) weigh the pair integrals 0. With
    /// single-scattered light they are the costly part (4-D angular
    /// integrals, ~97 % of the evaluations on `point-isotropic-order1`).
    pub fn compute_single_sphere(field: &Field<T>, r: &T, opts: &Options) -> Result<Integrals<T>, OracleError> {
        let mut ints = Integrals::single_sphere_parts(field, r, &opts.clone().declared())?;
        ints.mean.evaluations += field.table_evaluations();
        Ok(ints)
    }

    fn single_sphere_parts(field: &Field<T>, r: &T, o: &Options) -> Result<Integrals<T>, OracleError> {
        let ((mean, m2), p) = rayon::join(
            || {
                rayon::join(
                    || moments::mean_luminance(field, o),
                    || {
                        let (single, same) =
                            rayon::join(|| moments::m2(field, r, o), || moments::m2_same_path(field, r, o));
                        Ok::<_, OracleError>((single?, same?))
                    },
                )
            },
            || moments::p_single(field, o),
        );
        let mean = mean?;
        let (m2, m2_same_path) = m2?;
        Ok(Integrals { mean, m2: m2.plus(m2_same_path.clone()), m2_same_path, p: p?, pairs: None })
    }

    /// Total evaluations of the integrand over all integrals.
    pub fn evaluations(&self) -> u64 {
        self.mean.evaluations
            + self.m2.evaluations
            + self.p.evaluations
            + self.pairs.as_ref().map_or(0, PairIntegrals::evaluations)
    }
}

impl<T: CheckRule> PairIntegrals<T> {
    /// Q, (23), (24), (25) and (26) side by side.
    fn compute(field: &Field<T>, r: &T, o: &Options) -> Result<PairIntegrals<T>, OracleError> {
        let with_cross = |which: Which| {
            let (exact, cross) =
                rayon::join(|| correlations::exact(field, r, which, o), || cross_term(field, r, which, o));
            Ok::<_, OracleError>((exact?, cross))
        };
        let (((c23, c24), (c23_asym, c24_asym)), q) = rayon::join(
            || {
                rayon::join(
                    || rayon::join(|| with_cross(Which::Eq23), || with_cross(Which::Eq24)),
                    || {
                        rayon::join(
                            || correlations::asymptotic(field, r, Which::Eq23, o),
                            || correlations::asymptotic(field, r, Which::Eq24, o),
                        )
                    },
                )
            },
            || moments::q_pair(field, o),
        );
        let ((c23, c23_cross), (c24, c24_cross)) = (c23?, c24?);
        let with = |e: Estimate<T>, x: &Option<Result<Estimate<T>, String>>| match x {
            Some(Ok(x)) => e.plus(x.clone()),
            _ => e,
        };
        Ok(PairIntegrals {
            q: q?,
            c23: with(c23, &c23_cross),
            c24: with(c24, &c24_cross),
            c23_cross,
            c24_cross,
            c23_asym: c23_asym?,
            c24_asym: c24_asym?,
        })
    }

    /// Total evaluations of the integrand over these integrals.
    pub fn evaluations(&self) -> u64 {
        let asym = |a: &Result<Estimate<T>, String>| a.as_ref().map_or(0, |e| e.evaluations);
        self.q.evaluations + self.c23.evaluations + self.c24.evaluations + asym(&self.c23_asym) + asym(&self.c24_asym)
    }
}

/// The cross-segment term of (23) or (24) where there is one (single-scattered
/// point lights), else `None`; `Some(Err(why))` where it is not added: not
/// derived (Henyey–Greenstein media), outside its R → 0 form's checked
/// range ([`cross_segment::MAX_SCALE`]: σR or R over a light's distance from
/// the camera line), its computation failed, or it is not positive beyond
/// its bar (the term itself is positive). Never fails: every reason not to
/// add the term is reported with it.
fn cross_term<T: CheckRule>(field: &Field<T>, r: &T, which: Which, o: &Options) -> Option<Result<Estimate<T>, String>> {
    let x = match cross_segment::cross_segment(field, r, which, o) {
        Ok(Some(x)) => x,
        Ok(None) => return None,
        Err(e) => return Some(Err(format!("{e}; not added"))),
    };
    Some(if x.value.clone() - x.error.clone() > r.lit(0.0) {
        Ok(x)
    } else {
        Err(format!(
            "its R → 0 form (times e^{{c₀}}) is {:.3e} ± {:.1e}, not positive: estimator.radius = {} is not small \
             against 1/σ and the lights' distances from the camera line, where the form holds; not added",
            x.value.to_f64(),
            x.error.to_f64(),
            r.to_f64()
        ))
    })
}

/// Estimator parameters as numbers of the working precision.
#[derive(Debug, Clone)]
pub struct Counts<T> {
    /// q, the probability that a camera ray ends after a sub-step (1), (2).
    pub q: T,
    /// N_F, forward rays per iteration.
    pub n_f: T,
    /// N_B, camera rays through the pixel per iteration.
    pub n_b: T,
}

/// Var L of one iteration, (7)–(9), as Var L·e^{c₀} from the *shifted* integrals (every W carried as W·e^{c₀},
/// `Field::shift`): μ, M₂, C₂₃, C₂₄, P and Q are then e^{c₀} times their
/// values (P and Q formed so, `along::RayLine`), μ² is e^{2c₀} times its
/// value, and `k` = e^{−c₀}. The error bar is propagated linearly from
/// every integral's bar.
#[allow(clippy::too_many_arguments)]
pub fn variance<T: Real>(
    mean: &Valued<T>,
    m2: &Valued<T>,
    c23: &Valued<T>,
    p: &Valued<T>,
    q_pair: &Valued<T>,
    c24: &Valued<T>,
    n: &Counts<T>,
    k: &T,
) -> Valued<T> {
    let one = mean.value.lit(1.0);
    let two = mean.value.lit(2.0);
    let (q, nf, nb) = (n.q.clone(), n.n_f.clone(), n.n_b.clone());
    let one_minus_q = one.clone() - q.clone();
    let nfnb = nf.clone() * nb.clone();
    let w_a = one.clone() / nfnb.clone();
    let w_b = one.clone() / nb.clone() - one.clone() / nfnb.clone();
    let w_c = one.clone() / nf.clone() - one.clone() / nfnb.clone();
    let w_mu2 = one.clone() / nfnb - one.clone() / nb - one / nf;
    let a = q.clone() * m2.value.clone() + two.clone() * one_minus_q.clone() * c23.value.clone();
    let b = q.clone() * p.value.clone() + two.clone() * one_minus_q.clone() * q_pair.value.clone();
    let mu2 = k.clone() * mean.value.clone() * mean.value.clone();
    let value = w_a.clone() * a + w_b.clone() * b + w_c.clone() * c24.value.clone() + w_mu2.clone() * mu2;
    let err_a = q.clone() * m2.error.clone() + two.clone() * one_minus_q.clone() * c23.error.clone();
    let err_b = q * p.error.clone() + two.clone() * one_minus_q * q_pair.error.clone();
    let error = w_a.abs() * err_a
        + w_b.abs() * err_b
        + w_c.abs() * c24.error.clone()
        + w_mu2.abs() * two * k.clone() * mean.value.abs() * mean.error.clone();
    Valued { value, error }
}

/// D₁…D₅ of the asymptotic relative-noise formula at the end of §4.4 (the
/// paper leaves them implicit; definitions in the module doc), from
/// the shifted integrals; `inv_k` = e^{c₀} undoes the shift. `None` when
/// the pair integrals were not computed or (25), (26) do not exist.
pub fn d_constants<T: Real>(ints: &Integrals<T>, r: &T, sigma: &T, inv_k: &T) -> Option<[T; 5]> {
    let pairs = ints.pairs.as_ref()?;
    let (c23a, c24a) = (pairs.c23_asym.as_ref().ok()?, pairs.c24_asym.as_ref().ok()?);
    let mu2 = ints.mean.value.clone() * ints.mean.value.clone();
    let two = r.lit(2.0);
    Some([
        inv_k.clone() * r.clone() * r.clone() * ints.m2.value.clone() / mu2.clone(),
        inv_k.clone() * two.clone() * r.clone() * c23a.value.clone() / (sigma.clone() * mu2.clone()),
        inv_k.clone() * r.clone() * c24a.value.clone() / (sigma.clone() * mu2.clone()),
        inv_k.clone() * ints.p.value.clone() / mu2.clone(),
        inv_k.clone() * two * pairs.q.value.clone() / mu2,
    ])
}

/// The bars of [`d_constants`]: each D's relative bar is its integral's
/// plus twice the mean's (D = const·integral/μ²).
pub fn d_errors<T: Real>(ints: &Integrals<T>, d: &[T; 5]) -> Option<[T; 5]> {
    let pairs = ints.pairs.as_ref()?;
    let (c23a, c24a) = (pairs.c23_asym.as_ref().ok()?, pairs.c24_asym.as_ref().ok()?);
    let mean_rel = ints.mean.error.clone() / ints.mean.value.abs();
    let rel = |e: &Estimate<T>| e.error.clone() / e.value.abs() + mean_rel.clone() * mean_rel.lit(2.0);
    let rels = [rel(&ints.m2), rel(c23a), rel(c24a), rel(&ints.p), rel(&pairs.q)];
    Some(std::array::from_fn(|i| d[i].abs() * rels[i].clone()))
}

/// The bar of [`relative_from_d`] from the D's bars: the formula is linear
/// in the D's with non-negative coefficients.
pub fn relative_from_d_error<T: Real>(d_error: &[T; 5], r: &T, sigma: &T, n: &Counts<T>) -> T {
    let zero: [T; 5] = std::array::from_fn(|_| r.lit(0.0));
    relative_from_d(d_error, r, sigma, n) - relative_from_d(&zero, r, sigma, n)
}

/// The asymptotic relative noise of §4.4 from D₁…D₅. Deviation: the
/// constant term is 1/(N_F N_B) − 1/N_F − 1/N_B, not −1/(N_F N_B) (E8).
pub fn relative_from_d<T: Real>(d: &[T; 5], r: &T, sigma: &T, n: &Counts<T>) -> T {
    let one = r.lit(1.0);
    let (q, nf, nb) = (n.q.clone(), n.n_f.clone(), n.n_b.clone());
    let sr = sigma.clone() * r.clone();
    let head = (q.clone() * d[0].clone() + sr.clone() * (one.clone() - q.clone()) * d[1].clone()) / nb.clone()
        + (one.clone() - one.clone() / nb.clone()) * sr * d[2].clone();
    head / (r.clone() * r.clone() * nf.clone())
        + (one.clone() / nb.clone())
            * (one.clone() - one.clone() / nf.clone())
            * (q.clone() * d[3].clone() + (one.clone() - q) * d[4].clone())
        + one.clone() / (nf.clone() * nb.clone())
        - one.clone() / nf
        - one / nb
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quad::Rule;

    fn known(v: f64) -> Estimate<f64> {
        Estimate::known(v, 1e-12, 10, Rule::TanhSinh)
    }

    fn single() -> Integrals<f64> {
        Integrals { mean: known(1.0), m2: known(2.0), m2_same_path: known(0.0), p: known(3.0), pairs: None }
    }

    fn failure(what: &'static str) -> OracleError {
        OracleError::Quadrature { what, reason: "NOT CONVERGED".into(), guess: None, evaluations: 7 }
    }

    /// Where the pairs weigh nothing their failure is returned beside μ,
    /// M₂ and P; where they count it fails the whole; a failure of μ, M₂ or
    /// P fails it either way.
    #[test]
    fn a_failure_of_the_pairs_fails_only_where_they_count() {
        let (ints, failed) = Integrals::assemble(Ok(single()), Err(failure("(23)")), true).unwrap();
        assert!(ints.pairs.is_none() && ints.p.value == 3.0);
        assert!(failed.unwrap().to_string().contains("(23)"));
        let err = Integrals::assemble(Ok(single()), Err(failure("(23)")), false).unwrap_err();
        assert!(err.to_string().contains("(23)"));
        for optional in [true, false] {
            let err = Integrals::<f64>::assemble(Err(failure("mean")), Err(failure("(23)")), optional).unwrap_err();
            assert!(err.to_string().contains("mean"), "{err}");
        }
    }
}
