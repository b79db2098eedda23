//! One trial of the estimator: one iteration of one pixel (issue
//! "Reference tracer", paper §2–3), simulating only what the scene calls for.
//!
//! - N_B camera rays from the camera origin along u. Only the first camera
//!   segment is simulated: sub-steps ζ ~ Exp(σ_ext/q) (1), (2); after each an
//!   integration sphere of radius R is placed at the ray's position; then the
//!   segment ends with probability q (no draw when q = 1). Every sphere
//!   carries the weight q.
//! - N_F forward rays, each carrying the total flux 𝓕 (5): a light chosen in
//!   proportion to its flux (no draw for a single light), a point light
//!   emitting isotropically, a beam uniformly over its disk along its
//!   direction; free paths ~ Exp(σ_ext); at each interaction, scattering with
//!   probability albedo (no draw when albedo = 1), else absorption; the new
//!   direction from the phase function; no segment after more than
//!   `effects.scattering_orders` scatterings (order 0 draws no roulette and
//!   no phase sample).
//! - A segment adds q·𝒞 to every sphere it hits (`hits`), 𝒞 = σ_sc f 𝓕 /
//!   (σ_ext π R²) (5), f at the scattering-angle cosine −u·v between the
//!   segment's direction v and the direction back to the camera.
//! - L = (1/(N_F N_B)) Σ_i Σ_j Ĉ(i, j) (6): the sum over all segments of all
//!   forward rays and all spheres of all camera rays.

use crate::hits::{hits_brute_force, hits_sorted, Line, Segment};
use crate::limits::{self, ldexp, split, Work};
use crate::rng::{Draw, DrawCounts, Stream};
use crate::sampling::{disk_point, exponential, hg_cosine, rotate, uniform_direction};
use mcrt_scene::{Light, Phase, ScatteringOrders, Scene};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt;

/// How a segment's hits are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HitMethod {
    /// Interval on the camera line and binary search in sorted centres.
    Sorted,
    /// Every (segment, sphere) pair tested (test oracle).
    BruteForce,
}

/// What a run did, summed over its trials.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counters {
    pub trials: u64,
    pub forward_rays: u64,
    pub forward_segments: u64,
    pub sphere_placements: u64,
    /// Sorted method: segments whose hit interval was searched in the
    /// centres (non-empty interval); brute force: (segment, sphere) pairs.
    pub candidate_tests: u64,
    pub hits: u64,
    /// Trials whose L > 0 (at least one hit that added light). The mean and
    /// variance are resolved only from `run::MIN_NONZERO_TRIALS` such trials
    /// on: with few nonzero values their standard errors mean nothing.
    pub nonzero_trials: u64,
    /// Phase-function evaluations for 𝒞 that went through Henyey–Greenstein.
    pub hg_evaluations: u64,
    pub draws: DrawCounts,
}

impl Counters {
    /// Adds another tally to this one.
    pub fn add(&mut self, o: &Counters) {
        self.trials += o.trials;
        self.forward_rays += o.forward_rays;
        self.forward_segments += o.forward_segments;
        self.sphere_placements += o.sphere_placements;
        self.candidate_tests += o.candidate_tests;
        self.hits += o.hits;
        self.nonzero_trials += o.nonzero_trials;
        self.hg_evaluations += o.hg_evaluations;
        self.draws.add(&o.draws);
    }

    /// This tally plus another, or `None` if a count would overflow a u64.
    pub fn checked_sum(&self, o: &Counters) -> Option<Counters> {
        let (a, b) = (&self.draws, &o.draws);
        Some(Counters {
            trials: self.trials.checked_add(o.trials)?,
            forward_rays: self.forward_rays.checked_add(o.forward_rays)?,
            forward_segments: self.forward_segments.checked_add(o.forward_segments)?,
            sphere_placements: self.sphere_placements.checked_add(o.sphere_placements)?,
            candidate_tests: self.candidate_tests.checked_add(o.candidate_tests)?,
            hits: self.hits.checked_add(o.hits)?,
            nonzero_trials: self.nonzero_trials.checked_add(o.nonzero_trials)?,
            hg_evaluations: self.hg_evaluations.checked_add(o.hg_evaluations)?,
            draws: DrawCounts {
                sub_step: a.sub_step.checked_add(b.sub_step)?,
                extinction: a.extinction.checked_add(b.extinction)?,
                light_choice: a.light_choice.checked_add(b.light_choice)?,
                emission_direction: a.emission_direction.checked_add(b.emission_direction)?,
                emission_position: a.emission_position.checked_add(b.emission_position)?,
                free_path: a.free_path.checked_add(b.free_path)?,
                roulette: a.roulette.checked_add(b.roulette)?,
                phase: a.phase.checked_add(b.phase)?,
            },
        })
    }
}

/// Why a scene cannot be traced.
#[derive(Debug, Clone, PartialEq)]
pub enum TraceError {
    /// `effects.scattering_orders = "all"` with albedo 1: in an infinite
    /// medium a forward path would never end.
    EndlessPaths,
    /// The scene has no light with positive flux.
    NoFlux,
    /// The scene fails `mcrt-scene`'s validation (a `Scene` built in code).
    InvalidScene(String),
    /// The scene is beyond one of the tracer's bounds (`limits`): the
    /// message names the field, its value and the bound.
    Bound(String),
}

impl fmt::Display for TraceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TraceError::EndlessPaths => write!(
                f,
                "effects.scattering_orders = \"all\" with medium.albedo = 1: forward paths never end in an \
                 infinite medium; give a finite number of orders (an integer >= 0) or an albedo < 1"
            ),
            TraceError::NoFlux => write!(f, "lights: total flux is 0, nothing to trace"),
            TraceError::InvalidScene(why) | TraceError::Bound(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for TraceError {}

/// The scene prepared for tracing: constants of every trial.
#[derive(Debug, Clone)]
pub struct Tracer {
    scene: Scene,
    line: Line,
    /// σ_ext/q, the rate of the camera sub-steps.
    alpha: f64,
    /// Largest number of scatterings a forward ray may undergo.
    max_orders: Option<u32>,
    /// Cumulative flux fractions of the lights (choice in proportion to flux).
    cumulative: Vec<f64>,
    /// 𝒞 per unit of f, σ_sc 𝓕/(σ_ext π R²) (5) (inf or 0 if beyond a double).
    c_per_f: f64,
    /// q 𝒞/(f N_F N_B)/2^E: L/2^E = this × Σ_hits f, of order 1 for any scene.
    weight_scaled: f64,
    /// E, the power of two that L is computed in units of.
    scale_exp: i32,
    /// Expected work of one trial.
    work: Work,
}

impl Tracer {
    /// Prepares a scene: validated as a scene file is (a `Scene` built in
    /// code included), then checked against the tracer's own bounds
    /// (`limits`: lengths, memory and work of one trial).
    pub fn new(scene: &Scene) -> Result<Tracer, TraceError> {
        let scene = scene.validated().map_err(|e| TraceError::InvalidScene(e.to_string()))?;
        let medium = &scene.medium;
        let max_orders = match scene.effects.scattering_orders {
            ScatteringOrders::Limited(k) => Some(k),
            ScatteringOrders::All if medium.albedo >= 1.0 => return Err(TraceError::EndlessPaths),
            ScatteringOrders::All => None,
        };
        let work = limits::check_scene(&scene).map_err(TraceError::Bound)?;
        // Every factor as m·2^e, m in [1, 2): the products below are those of
        // the plain formula divided by 2^e, rounded identically wherever the
        // plain one stays normal, and never overflow.
        let flux_exp = scene.lights.iter().map(|l| split(l.flux()).1).max().unwrap_or(0);
        let total = scene.lights.iter().map(|l| ldexp(l.flux(), -flux_exp)).sum::<f64>();
        if total <= 0.0 {
            // Validated fluxes are finite and >= 0, so this is the all-zero case.
            return Err(TraceError::NoFlux);
        }
        let mut acc = 0.0;
        let cumulative = scene
            .lights
            .iter()
            .map(|l| {
                acc += ldexp(l.flux(), -flux_exp);
                acc / total
            })
            .collect();
        let est = &scene.estimator;
        let (total, e_total) = split(total);
        let [(albedo, e_albedo), (sigma, e_sigma), (radius, e_radius), (q, e_q), (nf, e_nf), (nb, e_nb)] =
            [medium.albedo, medium.sigma_ext, est.radius, est.q, est.forward_rays as f64, est.camera_rays as f64]
                .map(split);
        // 𝒞/f = σ_sc 𝓕/(σ_ext π R²) (5), σ_sc = albedo σ_ext.
        let c_scaled = (albedo * sigma) * total / (sigma * PI * radius * radius);
        let c_exp = e_albedo + e_sigma + e_total + flux_exp - e_sigma - 2 * e_radius;
        let weight_scaled = q * c_scaled / (nf * nb);
        Ok(Tracer {
            line: Line { origin: scene.camera.origin, dir: scene.camera.direction, radius: est.radius },
            alpha: medium.sigma_ext / est.q,
            max_orders,
            cumulative,
            c_per_f: ldexp(c_scaled, c_exp),
            weight_scaled,
            scale_exp: if albedo == 0.0 { 0 } else { c_exp + e_q - e_nf - e_nb },
            work,
            scene,
        })
    }

    /// E: the tracer computes L/2^E (`trial_scaled`), of order 1 for any
    /// scene, so that no L, L⁴ or power sum overflows or underflows.
    pub fn scale_exponent(&self) -> i32 {
        self.scale_exp
    }

    /// The expected work of one trial (within the bounds of `limits`).
    pub fn work(&self) -> Work {
        self.work
    }

    /// Whether a run of `trials` trials is within `limits::MAX_RUN_WORK`;
    /// the error names `--trials` and the largest allowed count.
    pub fn check_trials(&self, trials: u64) -> Result<(), TraceError> {
        limits::check_run(&self.work, trials).map_err(TraceError::Bound)
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// L of trial `index` of the run seeded with `seed`, and what it took
    /// (inf or 0 for a scene whose L is beyond a double; `trial_scaled` never is).
    pub fn trial(&self, seed: u64, index: u64, method: HitMethod) -> (f64, Counters) {
        let (l, counters) = self.trial_scaled(seed, index, method);
        (ldexp(l, self.scale_exp), counters)
    }

    /// L/2^E of trial `index` (E = [`Tracer::scale_exponent`]), and what it took.
    pub fn trial_scaled(&self, seed: u64, index: u64, method: HitMethod) -> (f64, Counters) {
        let mut stream = Stream::new(seed, index);
        let mut counters = Counters { trials: 1, ..Counters::default() };
        let centres = self.place_spheres(&mut stream, &mut counters);
        let mut sum_f = 0.0;
        for _ in 0..self.scene.estimator.forward_rays {
            sum_f += self.forward_ray(&mut stream, &centres, method, &mut counters);
        }
        counters.draws = stream.counts;
        let l = self.weight_scaled * sum_f;
        counters.nonzero_trials = u64::from(l > 0.0);
        (l, counters)
    }

    /// Sphere centres of all N_B camera rays (distances along u), sorted.
    fn place_spheres(&self, stream: &mut Stream, counters: &mut Counters) -> Vec<f64> {
        let q = self.scene.estimator.q;
        let mut centres = Vec::new();
        for _ in 0..self.scene.estimator.camera_rays {
            let mut s = 0.0;
            loop {
                // Step 1: a sub-step ζ ~ Exp(σ_ext/q), then a sphere there.
                s += exponential(stream, self.alpha, Draw::SubStep);
                centres.push(s);
                // Step 2: the segment ends with probability q (always at q = 1).
                if q >= 1.0 || stream.uniform(Draw::Extinction) < q {
                    break;
                }
            }
        }
        counters.sphere_placements += centres.len() as u64;
        centres.sort_by(f64::total_cmp);
        centres
    }

    /// One forward ray: Σ over its segments of hits × f(−u·v).
    fn forward_ray(&self, stream: &mut Stream, centres: &[f64], method: HitMethod, counters: &mut Counters) -> f64 {
        let mut sum_f = 0.0;
        self.walk_forward_ray(stream, counters, &mut |seg, counters| {
            let hits = self.hits(seg, centres, method, counters);
            if hits > 0 {
                sum_f += hits as f64 * self.phase_value(-self.line.dir.dot(seg.dir), counters);
            }
        });
        sum_f
    }

    /// Generates one forward ray's segments, in order, handing each to `visit`.
    pub fn walk_forward_ray(
        &self,
        stream: &mut Stream,
        counters: &mut Counters,
        visit: &mut dyn FnMut(&Segment, &mut Counters),
    ) {
        counters.forward_rays += 1;
        let medium = &self.scene.medium;
        let (mut pos, mut dir) = self.emit(stream);
        let mut order = 0u32;
        loop {
            // Step 1: the free path to the next interaction; the segment.
            let length = exponential(stream, medium.sigma_ext, Draw::FreePath);
            counters.forward_segments += 1;
            visit(&Segment { start: pos, dir, length }, counters);
            // Step 2: stop after the last order the scene asks for.
            if self.max_orders.is_some_and(|k| order >= k) {
                break;
            }
            // Step 3: scattering with probability albedo, else absorption.
            if medium.albedo < 1.0 && stream.uniform(Draw::Roulette) >= medium.albedo {
                break;
            }
            // Step 4: the new direction from the phase function.
            pos += dir * length;
            dir = match medium.phase {
                Phase::Isotropic => uniform_direction(stream, Draw::Phase),
                Phase::HenyeyGreenstein { g } => {
                    let cos = hg_cosine(stream, g);
                    rotate(stream, dir, cos)
                }
            };
            order += 1;
        }
    }

    /// The camera line and sphere radius.
    pub fn line(&self) -> &Line {
        &self.line
    }

    /// 𝒞 of a segment travelling along `dir` (5): σ_sc f(−u·v) 𝓕/(σ_ext π R²).
    pub fn contribution(&self, dir: glam::DVec3) -> f64 {
        self.c_per_f * self.scene.medium.phase.eval(-self.line.dir.dot(dir))
    }

    /// Emission point and direction of a light chosen in proportion to flux.
    pub fn emit(&self, stream: &mut Stream) -> (glam::DVec3, glam::DVec3) {
        let index = if self.cumulative.len() == 1 {
            0
        } else {
            let u = stream.uniform(Draw::LightChoice);
            self.cumulative.partition_point(|&c| c <= u).min(self.cumulative.len() - 1)
        };
        match self.scene.lights[index] {
            Light::Point { position, .. } => (position, uniform_direction(stream, Draw::EmissionDirection)),
            Light::Beam { center, direction, radius, .. } => (disk_point(stream, center, direction, radius), direction),
        }
    }

    fn hits(&self, seg: &Segment, centres: &[f64], method: HitMethod, counters: &mut Counters) -> u64 {
        let n = match method {
            HitMethod::Sorted => match hits_sorted(&self.line, seg, centres) {
                Some(n) => {
                    counters.candidate_tests += 1;
                    n
                }
                None => 0,
            },
            HitMethod::BruteForce => {
                counters.candidate_tests += centres.len() as u64;
                hits_brute_force(&self.line, seg, centres)
            }
        };
        counters.hits += n;
        n
    }

    /// f at the scattering-angle cosine; Henyey–Greenstein evaluations counted.
    fn phase_value(&self, cos: f64, counters: &mut Counters) -> f64 {
        if let Phase::HenyeyGreenstein { .. } = self.scene.medium.phase {
            counters.hg_evaluations += 1;
        }
        self.scene.medium.phase.eval(cos)
    }
}
