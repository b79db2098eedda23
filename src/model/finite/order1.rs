//! The finite-sphere model's variance for single-scattered light
//! (`scattering_orders = 1`): isotropic media (`docs/model.md` §9.6; a
//! beam's single-scattered light is `scattered_beam`, §9.8, and its
//! correlations of two spheres are not derived), and μ, M₂ and P of point
//! lights in a Henyey–Greenstein medium (§9.9, §9.10: `scattered_hg`,
//! `same_path_hg`; their correlations of two spheres are not derived).
//!
//! A forward path now has two segments, the uncollided one (𝒞₀ at the
//! spheres it hits) and, with probability albedo, the scattered one (𝒞₁),
//! so every moment of §9.1 is a sum over the pair of segments:
//!
//! - ⟨𝒞⟩ = ⟨𝒞₀⟩ + ⟨𝒞₁⟩ (P and Q from it, `FiniteField::order1_mean_with_bar`);
//! - ⟨𝒞²⟩ = ⟨𝒞₀²⟩ + ⟨𝒞₁²⟩ + 2⟨𝒞₀𝒞₁⟩: the last, one path hitting the
//!   same sphere with both segments, is `PointLight::same_path_moment`
//!   (`PointLight::same_path_moment_hg` in a Henyey–Greenstein medium);
//! - ⟨𝒞(s)𝒞(s′)⟩ = ⟨𝒞₀𝒞₀⟩ + ⟨𝒞₁𝒞₁⟩ + ⟨𝒞₀(s)𝒞₁(s′)⟩ + ⟨𝒞₁(s)𝒞₀(s′)⟩:
//!   one scattered segment meeting two spheres, and the two segments of
//!   one path meeting one sphere each (to come, §9.6).
//!
//! In an isotropic medium f = 1/4π on every segment, so each moment is
//! (c f)^k times a probability of hits.

use super::cross_segments::CrossPair;
use super::point::{cap_half_angle, PointLight};
use super::ray::Functional;
use super::scattered_table::ScatteredTables;
use super::second_hit::{weighted_second_hit, with_table_bar, SecondHitTable, SecondHitTables};
use super::{FiniteField, FiniteIntegrals, FiniteLight};
use crate::model::field::graded_about;
use crate::model::OracleError;
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome, Rule};
use mcrt_scene::Phase;

impl<T: CheckRule> PointLight<T> {
    /// ⟨𝒞₀𝒞₁⟩·e^{c₀} at s = center + x: one path hitting the sphere there
    /// with both its segments (isotropic media; `docs/model.md` §9.6). The
    /// first segment leaves the light along ψ of the cap about
    /// w = (x(s) − y)/D, passes the centre at p = D sin ψ, must reach its
    /// closest point (at D cos ψ: e^{−σD cos ψ}), then interacts u further
    /// and scatters (albedo) so that the second hits (K, [`super::second_hit::second_hit_after`]):
    ///
    ///   ⟨𝒞₀𝒞₁⟩ = albedo (c²Φ/𝓕) f² ½∫_cap sin ψ e^{−σD cos ψ} K dψ.
    ///
    /// For D > R the cap is integrated in w = √(R² − p²) ∈ [0, R]
    /// (sin ψ dψ = w dw/(D√(D² − R² + w²)), D cos ψ = √(D² − R² + w²)),
    /// in which the √-kink of K at the cap's rim (w = 0) is smooth; for
    /// D ≤ R (the sphere holds the light) in ψ ∈ [0, π/2]. Domain: any x,
    /// R > 0. Deviation: the paper has no such term (E9: §3b's small-sphere
    /// limit of it).
    pub(super) fn same_path_moment(
        &self,
        ff: &FiniteField<T>,
        x: &T,
        table: Option<&SecondHitTable<T>>,
        opts: &Options,
    ) -> Outcome<T> {
        let (big_d, _) = self.distance_to(ff, x);
        let (sigma, r) = (&ff.sigma, &ff.radius);
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front = ff.per_hit_power(2, &self.flux) * f.clone() * f * ff.albedo.clone() / x.lit(2.0);
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        // weight·K(w): the cap's measure and reach times the second hit.
        let weighted = |w: &T, weight: T, inner: &Options| weighted_second_hit(sigma, r, w, weight, table, inner);
        let e = if big_d > *r {
            let gap = (big_d.clone() - r.clone()) * (big_d.clone() + r.clone());
            integrate_within_pass(
                |w: &T, inner: &Options| {
                    let reach = (gap.clone() + w.clone() * w.clone()).sqrt();
                    let weight =
                        w.clone() / (big_d.clone() * reach.clone()) * (ff.shift.clone() - sigma.clone() * reach).exp();
                    weighted(w, weight, inner)
                },
                // w/√(D² − R² + w²) climbs from 0 to ~1 over w ~ √(D² − R²):
                // graded when the sphere nearly holds the light.
                &Domain::finite(x.lit(0.0), r.clone()).with_breakpoints(graded_about(&x.lit(0.0), &gap.sqrt(), r)),
                &o,
            )?
        } else {
            integrate_within_pass(
                |psi: &T, inner: &Options| {
                    let p = big_d.clone() * psi.sin();
                    let w = ((r.clone() - p.clone()) * (r.clone() + p)).sqrt();
                    let weight = psi.sin() * (ff.shift.clone() - sigma.clone() * big_d.clone() * psi.cos()).exp();
                    weighted(&w, weight, inner)
                },
                &Domain::finite(x.lit(0.0), cap_half_angle(&big_d, r)),
                &o,
            )?
        };
        Ok(with_table_bar(e, table, opts).scaled(&front))
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// Refuses what the order-1 moments μ, M₂ and P do not cover yet: a
    /// beam in a Henyey–Greenstein medium (isotropic media with any
    /// lights, point lights in a Henyey–Greenstein one: `scattered_hg`,
    /// `same_path_hg`).
    pub(super) fn order1_covered(&self) -> Result<(), OracleError> {
        if self.phase != Phase::Isotropic && self.lights.iter().any(|l| matches!(l, FiniteLight::Beam(_))) {
            return Err(OracleError::Unsupported(
                "the finite-sphere model of single-scattered light covers a beam in an isotropic medium only \
                 (medium.phase = \"isotropic\"); point lights in a Henyey–Greenstein medium are covered"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The options of the order-1 correlations of two spheres (the
    /// virtual-light share of C₂₃, C₂₄ and the cross-segment pairs), whoever
    /// calls them: their levels nest four and five deep, so their
    /// breakpoints are declared (no scan) and they run with [`pair_rule`]'s
    /// Gauss–Kronrod pair where the goal allows; without either the cost
    /// grows by orders of magnitude (§9.7, **Cost**).
    pub(super) fn pair_options(&self, opts: &Options) -> Options {
        Options { rule: pair_rule(&self.radius, opts), ..opts.clone() }.declared()
    }

    /// The options of an order-1 integral: in a Henyey–Greenstein medium
    /// the Gauss–Kronrod pair where the goal allows (its nests are three
    /// and four levels deep per camera-ray point, `order1::pair_rule`).
    fn order1_options(&self, opts: &Options) -> Options {
        if self.phase == Phase::Isotropic {
            opts.clone()
        } else {
            Options { rule: pair_rule(&self.radius, opts), ..opts.clone() }
        }
    }

    /// Refuses what the order-1 correlations of two spheres do not cover
    /// yet: Henyey–Greenstein media (§9.7 and §9.11 are computed for
    /// isotropic scattering; §9.12 derives them for these media, but no
    /// route tried is affordable yet).
    fn order1_pairs_covered(&self) -> Result<(), OracleError> {
        if self.phase != Phase::Isotropic {
            return Err(OracleError::Unsupported(
                "the finite-sphere correlations of two spheres (C₂₃, C₂₄) with single-scattered light cover \
                 isotropic media (medium.phase = \"isotropic\"); a Henyey–Greenstein medium is covered at q = 1 and \
                 N_B = 1, where they weigh nothing"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Σ over the lights (point lights and beams) of `each` (light, its share of the absolute
    /// goal), failures named `what`: the order-1 totals that are sums of
    /// per-light integrals ([`FiniteField::order1_virtual`],
    /// [`FiniteField::order1_cross`]).
    pub(super) fn order1_light_sum(
        &self,
        what: &'static str,
        opts: &Options,
        each: impl Fn(&FiniteLight<T>, &Options) -> Outcome<T>,
    ) -> Result<Estimate<T>, OracleError> {
        self.order1_pairs_covered()?;
        let share = Options { abs_tol: opts.abs_tol / self.lights.len() as f64, ..opts.clone() };
        let mut total: Option<Estimate<T>> = None;
        for light in &self.lights {
            let e = each(light, &share).map_err(OracleError::quad(what))?;
            total = Some(match total {
                None => e,
                Some(t) => t.plus(e),
            });
        }
        Ok(total.expect("order1_covered needs a light"))
    }

    /// (⟨𝒞₀⟩ + ⟨𝒞₁⟩)·e^{c₀} at x with its bar, summed over the (point)
    /// lights: the mean contribution of a path of order ≤ 1 to the sphere
    /// at s = center + x, for P and Q.
    pub(super) fn order1_mean_with_bar(&self, x: &T, tables: &ScatteredTables<T>, opts: &Options) -> Outcome<T> {
        let share = Options { abs_tol: opts.abs_tol / self.lights.len() as f64, ..opts.clone() };
        self.sum_over_lights(x, opts, |i, light| match light {
            FiniteLight::Point(p) if self.phase == Phase::Isotropic => {
                let e = p.scattered_moment(self, tables, x, 1, &share)?;
                Ok(Estimate::known(e.value + p.moment_isotropic(self, x, 1), e.error, e.evaluations, opts.rule))
            }
            FiniteLight::Point(p) => {
                let half = Options { abs_tol: share.abs_tol / 2.0, ..share.clone() };
                Ok(p.scattered_moment(self, tables, x, 1, &half)?.plus(p.moment_cap(self, x, 1, &half)?))
            }
            FiniteLight::Beam(b) => {
                let e = b.scattered_moment(self, tables, i, x, 1, &share)?;
                Ok(Estimate::known(e.value + b.moment(self, x, 1), e.error, e.evaluations, opts.rule))
            }
        })
    }

    /// (⟨𝒞₁²⟩ + 2⟨𝒞₀𝒞₁⟩)·e^{c₀} at x with its bar: the part of ⟨𝒞²⟩ that
    /// single scattering adds.
    fn order1_second_with_bar(
        &self,
        x: &T,
        second_hit: &SecondHitTables<T>,
        scattered: &ScatteredTables<T>,
        opts: &Options,
    ) -> Outcome<T> {
        let share = Options { abs_tol: opts.abs_tol / (2.0 * self.lights.len() as f64), ..opts.clone() };
        // K(w) serves isotropic media only.
        let table =
            (self.phase == Phase::Isotropic).then(|| second_hit.for_pass(&self.sigma, &self.radius, opts)).flatten();
        self.sum_over_lights(x, opts, |i, light| match light {
            FiniteLight::Point(p) => {
                let own = p.scattered_moment(self, scattered, x, 2, &share)?;
                let half = Options { abs_tol: share.abs_tol / 2.0, ..share.clone() };
                let both = if self.phase == Phase::Isotropic {
                    p.same_path_moment(self, x, table.as_deref(), &half)?
                } else {
                    p.same_path_moment_hg(self, x, &half)?
                };
                Ok(own.plus(both.scaled(&x.lit(2.0))))
            }
            FiniteLight::Beam(b) => {
                let own = b.scattered_moment(self, scattered, i, x, 2, &share)?;
                let half = Options { abs_tol: share.abs_tol / 2.0, ..share.clone() };
                let both = b.same_path_moment(self, x, table.as_deref(), &half)?;
                Ok(own.plus(both.scaled(&x.lit(2.0))))
            }
        })
    }

    /// ∫σe^{−σs}(⟨𝒞₁²⟩ + 2⟨𝒞₀𝒞₁⟩) ds·e^{c₀}: what single scattering adds
    /// to M₂ (the uncollided part is [`super::Functional::Second`]).
    pub fn order1_second_added(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let tables = ScatteredTables::default();
        tables.charge(self.order1_second_added_with(&tables, opts))
    }

    /// [`FiniteField::order1_second_added`] reading (and building) the I(D)
    /// tables `scattered`, whose evaluations the caller charges (its own K
    /// tables it charges itself).
    fn order1_second_added_with(
        &self,
        scattered: &ScatteredTables<T>,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        self.order1_covered()?;
        let opts = &self.order1_options(opts);
        let second_hit = SecondHitTables::default();
        second_hit.charge(self.with_line(|line| {
            line.integral_nested("finite-sphere ∫⟨𝒞²⟩, single-scattered part", opts, |x, o| {
                self.order1_second_with_bar(x, &second_hit, scattered, o)
            })
        }))
    }

    /// μ, M₂ and P of the order-1 model (each times e^{c₀}; Q, C₂₃, C₂₄
    /// `None`): all that Var L needs when q = 1 and N_B = 1, where (7)–(9)
    /// weigh the correlations of two spheres 0 (one sphere per camera ray,
    /// one camera ray: Var L = M₂/N_F + (1 − 1/N_F)P − μ²). Seconds at
    /// 10⁻⁶ where [`FiniteField::order1_integrals`] takes about a minute at 10⁻³
    /// (`docs/model.md` §9.6–§9.8). Isotropic media, point lights and beams;
    /// point lights in a Henyey–Greenstein medium, 10⁹–10¹⁰ evaluations at
    /// 10⁻³ (§9.10).
    pub fn order1_unpaired(&self, opts: &Options) -> Result<FiniteIntegrals<T>, OracleError> {
        let Order1Parts { mean, m2, p } = self.order1_unpaired_parts(opts)?;
        Ok(FiniteIntegrals { mean: mean?, m2: m2?, p: p?, q: None, c23: None, c24: None })
    }

    /// μ, M₂ and P of the order-1 model, each with its own outcome (the
    /// oracle keeps the exact mean when P fails); `Err` when the model does
    /// not cover the scene.
    ///
    /// The three share one set of I(D) tables, each built once whichever
    /// asks first, and charged to μ: counts that do not depend on the
    /// thread count.
    pub(crate) fn order1_unpaired_parts(&self, opts: &Options) -> Result<Order1Parts<T>, OracleError> {
        self.order1_covered()?;
        let o = &Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() }.declared();
        let tables = ScatteredTables::default();
        let ((mean, m2), p) = rayon::join(|| self.order1_mean_and_m2(&tables, o), || self.order1_p_with(&tables, o));
        Ok(Order1Parts { mean: tables.charge(mean), m2, p })
    }

    /// μ and M₂ of order 1, each the uncollided part plus what single
    /// scattering adds, with the options `o` of each part.
    fn order1_mean_and_m2(&self, tables: &ScatteredTables<T>, o: &Options) -> (Part<T>, Part<T>) {
        let ((mean0, mean1), (m20, m21)) = rayon::join(
            || rayon::join(|| self.ray_total(Functional::Mean, o), || self.scattered_mean_with(tables, o)),
            || rayon::join(|| self.ray_total(Functional::Second, o), || self.order1_second_added_with(tables, o)),
        );
        (sum(mean0, mean1), sum(m20, m21))
    }

    /// P of (17) from ⟨𝒞₀⟩ + ⟨𝒞₁⟩ (times e^{c₀}).
    pub fn order1_p(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let tables = ScatteredTables::default();
        tables.charge(self.order1_p_with(&tables, opts))
    }

    /// [`FiniteField::order1_p`] reading (and building) `tables`, whose
    /// evaluations the caller charges.
    fn order1_p_with(&self, tables: &ScatteredTables<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
        self.order1_covered()?;
        let opts = &self.order1_options(opts);
        let with_bar = |x: &T, _tol: f64, o: &Options| self.order1_mean_with_bar(x, tables, o);
        let source = crate::model::along::MeanSource::WithBar(&with_bar);
        self.with_line(|line| line.p_single(&source, opts))
    }

    /// P and Q of (17) from ⟨𝒞₀⟩ + ⟨𝒞₁⟩ (times e^{c₀}).
    pub fn order1_p_and_q(
        &self,
        opts: &Options,
    ) -> (Result<Estimate<T>, OracleError>, Result<Estimate<T>, OracleError>) {
        if let Err(e) = self.order1_covered() {
            return (Err(e.clone()), Err(e));
        }
        // One set of I(D) tables for both, charged to P.
        let tables = ScatteredTables::default();
        let (p, q) = self.order1_p_and_q_with(&tables, opts);
        (tables.charge(p), q)
    }

    /// [`FiniteField::order1_p_and_q`] reading (and building) `tables`,
    /// whose evaluations the caller charges.
    fn order1_p_and_q_with(&self, tables: &ScatteredTables<T>, opts: &Options) -> (Part<T>, Part<T>) {
        let opts = &self.order1_options(opts);
        let with_bar = |x: &T, _tol: f64, o: &Options| self.order1_mean_with_bar(x, tables, o);
        let source = crate::model::along::MeanSource::WithBar(&with_bar);
        self.with_line(|line| rayon::join(|| line.p_single(&source, opts), || line.q_pair(&source, opts)))
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// What single scattering adds to C₂₃ (`Pair23`) or C₂₄ (`Pair24`),
    /// times e^{c₀}: one scattered segment meeting both spheres (the
    /// virtual-light average of the order-0 pair functional,
    /// [`FiniteField::order1_virtual`]) plus the two segments of one path
    /// meeting one sphere each ([`FiniteField::order1_cross`]).
    pub fn order1_pair_added(&self, which: Functional, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let pair = match which {
            Functional::Pair23 => CrossPair::C23,
            Functional::Pair24 => CrossPair::C24,
            _ => return Err(OracleError::Unsupported(format!("{} is not a correlation", which.name()))),
        };
        // Both shares apply the pair options themselves (`pair_options`).
        let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
        let (one, two) = rayon::join(|| self.order1_virtual(which, &half), || self.order1_cross(pair, &half));
        Ok(one?.plus(two?))
    }

    /// Every integral of the order-1 model (uncollided plus single-scattered
    /// light; isotropic media, point lights and beams: Henyey–Greenstein
    /// media are refused, `order1_pairs_covered`), each times e^{c₀}.
    pub fn order1_integrals(&self, opts: &Options) -> Result<FiniteIntegrals<T>, OracleError> {
        self.order1_integrals_weighed(opts, Weighed::ALL)
    }

    /// [`FiniteField::order1_integrals`] with only the correlations that
    /// (7)–(9) weigh: C₂₃ when q < 1 (weight 2(1 − q)/(N_F N_B)), C₂₄ when
    /// N_B > 1 (weight 1/N_F − 1/(N_F N_B)); the others are `None`, which
    /// Var L takes as exact zeros. Q is computed always (beside P, seconds).
    /// Each correlation is about half the cost of the whole model.
    pub fn order1_integrals_weighed(
        &self,
        opts: &Options,
        weighed: Weighed,
    ) -> Result<FiniteIntegrals<T>, OracleError> {
        self.order1_pairs_covered()?;
        // Each integral is a sum of two parts: half the absolute goal each.
        let o = &Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() }.declared();
        // One set of I(D) tables for μ, M₂, P and Q, charged to μ.
        let tables = ScatteredTables::default();
        let correlation = |which: Functional, needed: bool| {
            needed.then(|| {
                let (ray, added) = rayon::join(|| self.ray_total(which, o), || self.order1_pair_added(which, o));
                sum(ray, added)
            })
        };
        let ((mean, m2), (c23, c24)) = rayon::join(
            || self.order1_mean_and_m2(&tables, o),
            || {
                rayon::join(
                    || correlation(Functional::Pair23, weighed.c23),
                    || correlation(Functional::Pair24, weighed.c24),
                )
            },
        );
        let (p, q) = self.order1_p_and_q_with(&tables, o);
        let mean = tables.charge(mean);
        Ok(FiniteIntegrals { mean: mean?, m2: m2?, p: p?, q: Some(q?), c23: c23.transpose()?, c24: c24.transpose()? })
    }
}

/// Which correlations of two spheres (7)–(9) weigh: the ones
/// [`FiniteField::order1_integrals_weighed`] computes.
///
/// ```
/// use mcrt_noise::model::finite::Weighed;
///
/// assert_eq!(Weighed::of(0.5, 1), Weighed { c23: true, c24: false });
/// assert_eq!(Weighed::of(1.0, 8), Weighed { c23: false, c24: true });
/// assert_eq!(Weighed::of(1.0, 1), Weighed::NONE);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Weighed {
    /// C₂₃: two spheres of one camera ray, weighed 2(1 − q)/(N_F N_B).
    pub c23: bool,
    /// C₂₄: spheres of two camera rays, weighed (1 − 1/N_B)/N_F.
    pub c24: bool,
}

impl Weighed {
    /// Both correlations.
    pub const ALL: Weighed = Weighed { c23: true, c24: true };

    /// Neither (q = 1 and N_B = 1: one sphere per camera ray, one camera
    /// ray).
    pub const NONE: Weighed = Weighed { c23: false, c24: false };

    /// The correlations with a non-zero weight at `q` and `camera_rays`
    /// (N_B).
    pub fn of(q: f64, camera_rays: u64) -> Weighed {
        Weighed { c23: q < 1.0, c24: camera_rays > 1 }
    }
}

/// The rule pair of the order-1 pair shares: Gauss–Kronrod
/// ([`Rule::Kronrod`], cross-checked by [`Rule::KronrodCheck`]) in f64 for
/// goals of [`KRONROD_TIGHTEST`] and looser, when the caller left the
/// default tanh–sinh; else the caller's. Those shares nest four levels
/// deep, and at the goals they run at each level costs its floor per piece
/// (61 evaluations for tanh–sinh's first estimate, 30 for the check rule,
/// 15 and 21 for the pair): at 10⁻³ the one-segment-two-spheres share of
/// C₂₃ took 1.13·10⁹ evaluations and 70 s at R = 0.5 with tanh–sinh
/// (1.23·10⁹ and 79 s at R = 0.2) and takes 2.1·10⁸ and 14 s with the pair
/// at both, the same values within their bars (`docs/model.md` §9.7,
/// **Cost**). Above 53 bits (`like`'s precision) the pair's f64 nodes
/// would not serve: tanh–sinh stays.
pub(super) fn pair_rule<T: CheckRule>(like: &T, opts: &Options) -> Rule {
    if opts.rule == Rule::TanhSinh && opts.rel_tol >= KRONROD_TIGHTEST && like.prec() <= 53 {
        Rule::Kronrod
    } else {
        opts.rule
    }
}

/// The tightest goal at which the order-1 pair shares use the
/// Gauss–Kronrod pair ([`pair_rule`]): tanh–sinh's double-exponential
/// convergence overtakes its floor per piece at tighter goals (on ln x
/// over [0, 1] at 10⁻¹⁰ the pair takes 930 evaluations, tanh–sinh and the
/// check rule 567; `tests/kronrod.rs`). It applies to the outer goal; the
/// inner levels run tighter (rel_tol/20, then /4 per level). Measured on
/// the pair shares at 10⁻³ and 10⁻⁴ only (`docs/model.md` §9.7).
const KRONROD_TIGHTEST: f64 = 1e-8;

/// One integral's outcome.
type Part<T> = Result<Estimate<T>, OracleError>;

/// The sum of an integral's two parts (uncollided and single-scattered).
fn sum<T: CheckRule>(a: Part<T>, b: Part<T>) -> Part<T> {
    Ok(a?.plus(b?))
}

/// μ, M₂ and P of the order-1 model (times e^{c₀}), each with its own
/// outcome ([`FiniteField::order1_unpaired_parts`]).
pub(crate) struct Order1Parts<T> {
    /// μ = μ₀ + μ₁.
    pub mean: Part<T>,
    /// M₂ with the single-scattered and same-path parts.
    pub m2: Part<T>,
    /// P of ⟨𝒞₀⟩ + ⟨𝒞₁⟩.
    pub p: Part<T>,
}
