//! The finite-sphere model: the estimator's exact mean, variance and bias at
//! any sphere radius R, for uncollided light (scattering order 0) from point
//! lights and beams. Derivation: `docs/model.md` §9.
//!
//! The small-sphere model of §4.3 ([`super::moments`], [`super::correlations`])
//! takes the phase function and the attenuation at a sphere's centre and
//! lets one segment cross whole spheres; it is exact only as R → 0. Here
//! nothing is approximated: the moments (13)–(18) of the estimator as the
//! reference tracer runs it (`docs/tracer.md`) are integrals over one
//! forward ray, and for an uncollided ray the integrals over its free path
//! and over the spheres' positions are closed forms of its *hit interval*
//! on the camera line ([`ray`]). What remains is a 2-D integral over the
//! ray's direction (point light, [`point`]) or its starting point on the
//! disk (beam, [`beam`]), with every kink declared to the quadrature
//! engine, which cross-checks it as always.
//!
//! - μ = ⟨⟨Ĉ⟩⟩, M₂, C₂₃, C₂₄: ray-centric ([`Functional`]);
//! - P = ∫σe^{−σs}⟨𝒞⟩_R², Q (17): sphere-centric, from ⟨𝒞⟩_R(s), the mean
//!   contribution of one ray to a sphere at s, in closed form for isotropic
//!   media and beams and by quadrature over the sphere's cap (tabled along
//!   the ray per pass) for Henyey–Greenstein media (`tables`).
//!
//! Then (7)–(9) hold as they stand (`super::noise::variance`), and the bias
//! is b(R) = μ(R) − μ(0), μ(0) the small-sphere mean, the luminance of the
//! simulated orders.

pub mod angles;
pub mod beam;
mod beam_pairs;
mod beam_ring;
pub mod cross_segments;
mod fresh_hits;
mod hit_cumulants;
mod multiple;
mod multiple_beam;
mod multiple_beam_pairs;
mod multiple_pairs;
pub mod order1;
mod pair_orders;
pub mod point;
pub mod ray;
mod same_path_hg;
pub mod scattered;
mod scattered_beam;
mod scattered_hg;
mod scattered_table;
mod second_hit;
pub mod start_density;
mod tables;
pub mod virtual_lights;

pub(super) use super::once_per_pass::OncePerPass;
pub(crate) use multiple::every_order_phase_refusal;

use super::along::{lowest_quadratic_path, pair_scale_exponent, MeanSource, RayLine};
use super::angular::Direction;
use super::beam_source::{beam_scattered_path, BeamFrame};
use super::field::{beam_interval, Field};
use super::OracleError;
use crate::quad::{decay_lengths, CheckRule, Domain, Estimate, Options, Outcome};
use crate::real::Real;
use beam::BeamLight;
use mcrt_scene::{DVec3, Light, Phase, ScatteringOrders, Scene};
pub use order1::Weighed;
use point::PointLight;
pub use ray::Functional;

/// One light of the finite-sphere model.
#[derive(Debug, Clone)]
pub enum FiniteLight<T> {
    /// A point light (`docs/model.md` §9.2).
    Point(PointLight<T>),
    /// A collimated disk beam (`docs/model.md` §9.3).
    Beam(BeamLight<T>),
}

/// The scene as the finite-sphere model needs it.
#[derive(Debug, Clone)]
pub struct FiniteField<T> {
    /// The scene's lights, in scene order.
    pub lights: Vec<FiniteLight<T>>,
    /// σ = σ_ext, extinction coefficient (1/length).
    pub sigma: T,
    /// Single-scattering albedo σ_sc/σ_ext.
    pub albedo: T,
    /// Phase function of the medium (1/sr), evaluated at the scattering-angle cosine −μ.
    pub phase: Phase,
    /// Total flux 𝓕 (5).
    pub total_flux: T,
    /// Sphere radius R.
    pub radius: T,
    /// c₀ = σ × a lower bound of every path light → sphere's closest point
    /// → camera (|y − o| − R for a point, the entry of the camera ray into
    /// the beam widened by R for a beam; with scattered light (orders ≥ 1)
    /// (max(dist(o, beam), depth of o) − R)⁺ for a beam, `docs/model.md`
    /// §9.8). Every ray functional and ⟨𝒞⟩_R is
    /// carried times e^{c₀}: a ray functional is then ≤ its value at c₀ = 0,
    /// and so is σe^{−σs}⟨𝒞⟩_R(s)e^{c₀}; ⟨𝒞⟩_R e^{c₀} alone is not bounded
    /// (≈ e^{σ(|y − o| − b)} at the foot of a light near the line), which
    /// is why the quadratic P and Q apply the weight one factor at a time
    /// (`along::RayLine`).
    pub shift: T,
    /// Origin of the along-ray variable, s = center + x (as [`Field::center`]).
    pub center: T,
    /// Whether the scene's forward paths scatter (orders ≥ 1): the
    /// along-ray domain then declares where single-scattered light bends.
    scattered: bool,
    /// Where the segments beyond the first start (orders ≥ 2: `multiple`),
    /// `None` for orders ≤ 1 — or the reason the orders are not modelled.
    higher: Option<Result<start_density::StartDensity<T>, String>>,
    tables: tables::Tables<T>,
    /// The along-ray range of the tables ([`FiniteField::table_range`]).
    range: (T, T),
    /// A distance from the centre the tables of I(D) and (C * H)(D) must
    /// reach from 0 as well as the lights' distances: the ends of segments
    /// through a sphere, where every order's same-path pairs read G
    /// (`multiple_pairs`; [`FiniteField::cover_pair_distances`]).
    pair_reach: Option<T>,
}

/// Phase function f at the scattering-angle cosine −μ (5), from 1 ∓ μ so
/// that a Henyey–Greenstein peak at μ = ∓1 keeps its relative accuracy.
pub fn phase_of<T: Real>(phase: &Phase, dir: &Direction<T>) -> T {
    let like = &dir.mu;
    match *phase {
        Phase::Isotropic => like.lit(1.0) / (like.pi() * like.lit(4.0)),
        Phase::HenyeyGreenstein { g } => {
            let (g, one) = (like.lit(g), like.lit(1.0));
            // 1 + g² − 2g cos θ with cos θ = −μ.
            let denom = if g >= like.lit(0.0) {
                (one.clone() - g.clone()) * (one.clone() - g.clone())
                    + like.lit(2.0) * g.clone() * dir.one_plus_mu.clone()
            } else {
                (one.clone() + g.clone()) * (one.clone() + g.clone())
                    - like.lit(2.0) * g.clone() * dir.one_minus_mu.clone()
            };
            (one.clone() - g.clone()) * (one + g) / (like.pi() * like.lit(4.0) * denom.clone() * denom.sqrt())
        }
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// The model of `scene` (built beside its small-sphere `field`), or
    /// `None` when the scene has scattered light (orders ≥ 1), which the
    /// finite-sphere model does not cover.
    pub fn from_scene(scene: &Scene, field: &Field<T>) -> Option<FiniteField<T>> {
        if scene.effects.scattering_orders != ScatteringOrders::Limited(0) {
            return None;
        }
        Some(Self::of_first_segments(scene, field))
    }

    /// The model of the first (uncollided) segments of `scene`'s forward
    /// paths, whatever its scattering orders: the geometry that the
    /// single-scattered part ([`scattered`]) builds on.
    pub fn of_first_segments(scene: &Scene, field: &Field<T>) -> FiniteField<T> {
        let like = &field.sigma_ext;
        let (u, o) = (scene.camera.direction, scene.camera.origin);
        let r = scene.estimator.radius;
        let radius = like.lit(r);
        let lights = scene
            .lights
            .iter()
            .map(|light| match *light {
                Light::Point { position, flux } => {
                    let rel = position - o;
                    let (z, b) = (like.lit(rel.dot(u)), like.lit(rel.cross(u).length()));
                    FiniteLight::Point(PointLight::new(z, b, like.lit(flux), &radius))
                }
                Light::Beam { center, direction, radius: a, flux } => {
                    let frame = BeamFrame::new(o, u, center, direction);
                    FiniteLight::Beam(BeamLight::new(
                        like.lit(frame.mu),
                        like.lit(frame.sin),
                        like.lit(frame.xi0),
                        like.lit(frame.eta0),
                        like.lit(frame.depth0),
                        like.lit(a),
                        like.lit(flux),
                    ))
                }
            })
            .collect();
        let sigma = scene.medium.sigma_ext;
        let mut ff = FiniteField {
            lights,
            sigma: field.sigma_ext.clone(),
            albedo: field.albedo.clone(),
            phase: scene.medium.phase,
            total_flux: field.total_flux.clone(),
            radius,
            shift: like.lit(sigma * shortest_path(scene, o, u, r)),
            center: field.center.clone(),
            scattered: scene.effects.scattering_orders != ScatteringOrders::Limited(0),
            higher: higher_orders(scene, &field.albedo),
            tables: tables::Tables::default(),
            range: (like.lit(0.0), like.lit(0.0)),
            pair_reach: None,
        };
        ff.range = ff.along_range();
        ff
    }

    /// Makes the tables of I(D) and (C * H)(D) reach from the centre out to
    /// R + 50/σ as well, where Var L of every order reads G = H + aI +
    /// C′ * H at the ends of segments through a sphere (`docs/model.md`
    /// §10.3), so that one set of tables serves P and the pairs.
    pub fn cover_pair_distances(&mut self) {
        let reach = self.radius.clone() + self.sigma.lit(fresh_hits::FRESH_REACH) / self.sigma.clone();
        self.pair_reach = Some(reach);
    }

    /// The distance set by [`FiniteField::cover_pair_distances`], if any.
    pub(super) fn pair_reach(&self) -> Option<&T> {
        self.pair_reach.as_ref()
    }

    /// (albedo 𝓕/(πR²))^k (Φ/𝓕): the per-hit contribution 𝒞 = albedo f 𝓕/(πR²)
    /// (5) to the k-th power, without f, for a light of flux Φ chosen with
    /// probability Φ/𝓕.
    pub fn per_hit_power(&self, k: i32, flux: &T) -> T {
        let c = self.albedo.clone() * self.total_flux.clone() / (flux.pi() * self.radius.clone() * self.radius.clone());
        let ck = if k == 1 { c } else { c.clone() * c };
        ck * flux.clone() / self.total_flux.clone()
    }

    /// [`FiniteField::per_hit_power`] at the power of `which` (1 for the mean, else 2).
    pub fn per_hit(&self, which: Functional, flux: &T) -> T {
        self.per_hit_power(which.power(), flux)
    }

    /// The widths of the phase function's peaks at the poles: (at v = +u,
    /// g < 0; at v = −u, g > 0), 1 − |g|.
    pub fn phase_floors(&self) -> (Option<T>, Option<T>) {
        match self.phase {
            Phase::HenyeyGreenstein { g } if g > 0.0 => (None, Some(self.sigma.lit(1.0 - g))),
            Phase::HenyeyGreenstein { g } if g < 0.0 => (Some(self.sigma.lit(1.0 + g)), None),
            _ => (None, None),
        }
    }

    /// One ray-centric moment, summed over the lights (a light's failure
    /// carries no best guess of the sum when there are several).
    pub fn ray_total(&self, which: Functional, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let mut total: Option<Estimate<T>> = None;
        let several = self.lights.len() > 1;
        for light in &self.lights {
            let e = match light {
                FiniteLight::Point(p) => p.ray_integral(self, which, opts),
                FiniteLight::Beam(b) => b.ray_integral(self, which, opts),
            }
            .map_err(|f| if several { f.of_a_part() } else { f })
            .map_err(OracleError::quad(which.name()))?;
            total = Some(match total {
                None => e,
                Some(t) => t.plus(e),
            });
        }
        total.ok_or_else(|| OracleError::Unsupported("the scene has no light".into()))
    }

    /// Whether ⟨𝒞⟩_R has a closed form for every light (isotropic medium,
    /// or beams only).
    pub fn is_closed_form(&self) -> bool {
        self.phase == Phase::Isotropic || self.lights.iter().all(|l| matches!(l, FiniteLight::Beam(_)))
    }

    /// ⟨𝒞⟩_R·e^{c₀} at s = center + x where it has a closed form.
    fn mean_closed(&self, x: &T) -> T {
        self.lights.iter().fold(x.lit(0.0), |sum, light| {
            sum + match light {
                FiniteLight::Point(p) => p.moment_isotropic(self, x, 1),
                FiniteLight::Beam(b) => b.moment(self, x, 1),
            }
        })
    }

    /// ⟨𝒞⟩_R·e^{c₀} at x with its bar: beams in closed form, points of a
    /// Henyey–Greenstein medium from the tables of the pass (`opts.rule`,
    /// tolerance `table_tol`).
    fn mean_with_bar(&self, x: &T, table_tol: f64, opts: &Options) -> Outcome<T> {
        self.sum_over_lights(x, opts, |i, light| match light {
            FiniteLight::Beam(b) => Ok(Estimate::known(b.moment(self, x, 1), x.lit(0.0), 1, opts.rule)),
            FiniteLight::Point(p) => self.tables.mean(self, i, p, x, table_tol, opts),
        })
    }

    /// ⟨𝒞²⟩_R·e^{c₀} at x with its bar, sphere-centric: closed forms for
    /// beams and isotropic media, the cap quadrature otherwise (with the
    /// rule of `opts`).
    fn second_with_bar(&self, x: &T, opts: &Options) -> Outcome<T> {
        self.sum_over_lights(x, opts, |_, light| match light {
            FiniteLight::Beam(b) => Ok(Estimate::known(b.moment(self, x, 2), x.lit(0.0), 1, opts.rule)),
            FiniteLight::Point(p) => p.moment_cap(self, x, 2, opts),
        })
    }

    /// Σ over the lights of a value with a bar at x.
    fn sum_over_lights(
        &self,
        x: &T,
        opts: &Options,
        each: impl Fn(usize, &FiniteLight<T>) -> Outcome<T>,
    ) -> Outcome<T> {
        let mut total = Estimate::known(x.lit(0.0), x.lit(0.0), 0, opts.rule);
        for (i, light) in self.lights.iter().enumerate() {
            let e = each(i, light)?;
            total.value = total.value + e.value;
            total.error = total.error + e.error;
            total.evaluations += e.evaluations;
        }
        Ok(total)
    }

    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩_R ds, sphere-centric (a check of the ray-centric
    /// [`Functional::Second`]).
    pub fn second_sphere_centric(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        self.with_mean(|line, _| {
            line.integral_nested("finite-sphere ∫⟨𝒞²⟩, sphere-centric", opts, |x, o| {
                self.second_with_bar(x, o)
            })
        })
    }

    /// The along-ray domain [lo, hi) in x with every light's breakpoints and
    /// the decay e^{−σs} declared.
    pub fn ray_domain(&self, lo: &T, hi: Option<&T>) -> Domain<T> {
        let mut d = match hi {
            Some(h) => Domain::finite(lo.clone(), h.clone()).with_decay(self.sigma.clone()),
            None => Domain::semi_infinite(lo.clone()).with_decay(self.sigma.clone()),
        };
        for light in &self.lights {
            d = d.with_breakpoints(match light {
                FiniteLight::Point(p) => p.ray_breakpoints(self),
                FiniteLight::Beam(b) => b.ray_breakpoints(self),
            });
            if let (true, FiniteLight::Beam(b)) = (self.scattered, light) {
                d = d.with_breakpoints(b.scattered_breakpoints(self));
            }
        }
        d
    }

    /// [x_camera, last breakpoint + 4^K/σ]: where along-ray tables are used
    /// (the last of the engine's cuts of a decaying tail).
    pub(super) fn table_range(&self) -> (T, T) {
        self.range.clone()
    }

    /// [`FiniteField::table_range`], computed once.
    fn along_range(&self) -> (T, T) {
        let lo = -self.center.clone();
        let last = self.ray_domain(&lo, None).breakpoints.iter().cloned().fold(lo.clone(), |m, b| m.max_of(b));
        let longest = *decay_lengths(&lo).last().expect("non-empty");
        (lo.clone(), last + lo.lit(longest) / self.sigma.clone())
    }

    /// Runs `f` with the camera ray of this model ([`FiniteField::ray_domain`]).
    pub(super) fn with_line<R>(&self, f: impl FnOnce(&RayLine<'_, T>) -> R) -> R {
        let domain = |lo: &T, hi: Option<&T>| self.ray_domain(lo, hi);
        f(&RayLine {
            sigma: self.sigma.clone(),
            center: self.center.clone(),
            shift: self.shift.clone(),
            pair_scale: pair_scale_exponent(self.sigma.to_f64(), self.shift.to_f64(), self.quadratic_path()),
            domain: &domain,
        })
    }

    /// A lower bound of s + 2·(light → sphere path) over the camera ray and
    /// the lights, for P's and Q's scale ([`pair_scale_exponent`]): the
    /// path to a sphere is at least D − R; `None` with a beam (not formed:
    /// no scale).
    fn quadratic_path(&self) -> Option<f64> {
        let points = self.lights.iter().map(|light| match light {
            FiniteLight::Point(p) => Some((p.z.to_f64(), p.b.to_f64())),
            FiniteLight::Beam(_) => None,
        });
        lowest_quadratic_path(points).map(|m| m - 2.0 * self.radius.to_f64())
    }

    /// Runs `f` with the camera ray and this model's ⟨𝒞⟩_R.
    fn with_mean<R>(&self, f: impl FnOnce(&RayLine<'_, T>, &MeanSource<'_, T>) -> R) -> R {
        let plain = |x: &T| self.mean_closed(x);
        let with_bar = |x: &T, tol: f64, o: &Options| self.mean_with_bar(x, tol, o);
        let source = if self.is_closed_form() { MeanSource::Plain(&plain) } else { MeanSource::WithBar(&with_bar) };
        self.with_line(|line| f(line, &source))
    }

    /// ∫σe^{−σs}⟨𝒞⟩_R ds, sphere-centric: the mean luminance again, by an
    /// independent route (a check of the ray-centric [`Functional::Mean`]).
    pub fn mean_sphere_centric(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        self.with_mean(|line, mean| line.mean(mean, opts))
    }

    /// P and Q of (17) from ⟨𝒞⟩_R along the camera ray (times e^{c₀}).
    /// In a Henyey–Greenstein medium both read ⟨𝒞⟩_R from tables built
    /// once per pass (`tables`), whose evaluations are charged to P once
    /// both have finished (the counts then do not depend on which integral,
    /// on which thread, built a table). Every table the field has built so
    /// far is charged: a field serves one computation (as the oracle uses
    /// it), and a second call, or one after [`FiniteField::mean_sphere_centric`],
    /// charges tables it found built; a failed P carries no table count.
    pub fn p_and_q(&self, opts: &Options) -> (Result<Estimate<T>, OracleError>, Result<Estimate<T>, OracleError>) {
        let (p, q) = self.with_mean(|line, m| rayon::join(|| line.p_single(m, opts), || line.q_pair(m, opts)));
        let built = self.tables.evaluations();
        (
            p.map(|mut e| {
                e.evaluations += built;
                e
            }),
            q,
        )
    }

    /// Every integral of the model for the scene's R (each times e^{c₀}),
    /// computed side by side.
    pub fn integrals(&self, opts: &Options) -> Result<FiniteIntegrals<T>, OracleError> {
        let o = &opts.clone().declared();
        let (((mean, m2), (c23, c24)), (p, q)) = rayon::join(
            || {
                rayon::join(
                    || rayon::join(|| self.ray_total(Functional::Mean, o), || self.ray_total(Functional::Second, o)),
                    || rayon::join(|| self.ray_total(Functional::Pair23, o), || self.ray_total(Functional::Pair24, o)),
                )
            },
            || self.p_and_q(o),
        );
        Ok(FiniteIntegrals { mean: mean?, m2: m2?, c23: Some(c23?), c24: Some(c24?), p: p?, q: Some(q?) })
    }
}

/// The six integrals of the finite-sphere model, each times e^{c₀} (as
/// the small-sphere ones, `noise::variance`). Q, C₂₃ and C₂₄ are `None`
/// where they were not computed because the scene's Var L weighs them 0
/// (q = 1 and N_B = 1: one sphere per camera ray and one camera ray,
/// [`FiniteField::order1_unpaired`]).
#[derive(Debug, Clone)]
pub struct FiniteIntegrals<T> {
    /// μ(R) = ⟨⟨Ĉ⟩⟩ = ∫σe^{−σs}⟨𝒞⟩_R ds, the mean luminance, ray-centric.
    pub mean: Estimate<T>,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩_R ds, ray-centric.
    pub m2: Estimate<T>,
    /// P = ∫σe^{−σs}⟨𝒞⟩_R² ds, sphere-centric.
    pub p: Estimate<T>,
    /// Q = ∫∫_{s<s′}⟨𝒞⟩_R(s)⟨𝒞⟩_R(s′)σ²e^{−σs′}, sphere-centric.
    pub q: Option<Estimate<T>>,
    /// C₂₃ = ∫∫_{s<s′}⟨𝒞(s)𝒞(s′)⟩_R σ²e^{−σs′}, ray-centric.
    pub c23: Option<Estimate<T>>,
    /// C₂₄ = ∫∫⟨𝒞(s)𝒞(s′)⟩_R σ²e^{−σ(s+s′)}, ray-centric.
    pub c24: Option<Estimate<T>>,
}

impl<T: Real> FiniteIntegrals<T> {
    /// Total integrand evaluations over the integrals computed.
    pub fn evaluations(&self) -> u64 {
        let pairs = [&self.q, &self.c23, &self.c24].into_iter().flatten();
        [&self.mean, &self.m2, &self.p].into_iter().chain(pairs).map(|e| e.evaluations).sum()
    }

    /// Whether Q, C₂₃ and C₂₄ were computed (the Var L of any q, N_B).
    pub fn has_pairs(&self) -> bool {
        self.q.is_some() && self.c23.is_some() && self.c24.is_some()
    }
}

/// The start density of the segments beyond the first of `scene`'s paths
/// (segments 2..=n, or all of them), `None` for orders ≤ 1, or why it
/// cannot be built (an order beyond the cut's reach, every order without
/// absorption).
fn higher_orders<T: Real>(scene: &Scene, albedo: &T) -> Option<Result<start_density::StartDensity<T>, String>> {
    let last = match scene.effects.scattering_orders {
        ScatteringOrders::Limited(n) if n <= 1 => return None,
        ScatteringOrders::Limited(n) => Some(n),
        ScatteringOrders::All => None,
    };
    Some(start_density::StartDensity::new(albedo, 2, last).map_err(|e| match e {
        OracleError::Unsupported(why) => why,
        other => other.to_string(),
    }))
}

/// c₀/σ: a lower bound of every light → sphere → camera path (see
/// [`FiniteField::shift`]), 0 when no light can reach.
fn shortest_path(scene: &Scene, o: DVec3, u: DVec3, r: f64) -> f64 {
    let scattered = scene.effects.scattering_orders != ScatteringOrders::Limited(0);
    let paths = scene.lights.iter().filter_map(|light| match *light {
        Light::Point { position, .. } => Some(((position - o).length() - r).max(0.0)),
        // Single-scattered light: the path to the second segment's closest
        // point is at least R shorter than to the sphere's centre.
        Light::Beam { center, direction, radius, .. } if scattered => {
            Some((beam_scattered_path(o, center, direction, radius) - r).max(0.0))
        }
        Light::Beam { center, direction, radius, .. } => {
            let mu = u.dot(direction);
            let depth0 = (o - center).dot(direction);
            let (s_in, s_out) = beam_interval(o - center, u, direction, radius + r, depth0, mu);
            if s_out == Some(s_in) {
                return None;
            }
            Some((s_in * (1.0 + mu) + depth0).max(0.0))
        }
    });
    let shortest = paths.fold(f64::INFINITY, f64::min);
    if shortest.is_finite() {
        shortest
    } else {
        0.0
    }
}

/// The finite field of `scenes/point-isotropic-order1.toml` (the light at
/// (1, 0, 1)) at radius `radius` with the phase function `phase`: the
/// scene of the order-1 unit tests.
#[cfg(test)]
pub(super) fn order1_test_field(radius: f64, phase: Phase) -> FiniteField<f64> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.radius = radius;
    s.medium.phase = phase;
    let field = Field::from_scene(&s, &1.0f64).unwrap();
    FiniteField::of_first_segments(&s, &field)
}
