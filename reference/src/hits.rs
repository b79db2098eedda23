//! Which integration spheres a forward segment hits.
//!
//! All spheres of a trial sit on the camera line x(s) = o + s·u (centres at
//! sorted distances s_k). A segment from p₀ along the unit v, of length ℓ,
//! hits the sphere at s when the closest approach of its *line* to x(s) is at
//! most R and the closest point lies within the segment:
//!
//! - distance: |(x(s) − p₀) × v|² = |B + s·A|² ≤ R², with A = u × v and
//!   B = (o − p₀) × v: an interval [s_c − δ, s_c + δ] about the closest
//!   approach s_c = −(A·B)/|A|², δ = √((R² − d²_min)/|A|²);
//! - closest point within the segment: t*(s) = (x(s) − p₀)·v = (o − p₀)·v +
//!   s (u·v) ∈ [0, ℓ], another interval (or all s, or none, when u·v = 0).
//!
//! The spheres in the intersection are found by two binary searches in the
//! sorted positions ([`hits_sorted`]). [`hits_brute_force`] tests every
//! (segment, sphere) pair directly and serves as the test oracle.

use glam::DVec3;

/// A forward-ray segment: start, unit direction, length.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub start: DVec3,
    pub dir: DVec3,
    pub length: f64,
}

/// The camera line and the sphere radius.
#[derive(Debug, Clone, Copy)]
pub struct Line {
    pub origin: DVec3,
    /// Unit view direction u.
    pub dir: DVec3,
    pub radius: f64,
}

/// The closed interval of camera-line positions s whose sphere the segment
/// hits, or `None`. Degenerate cases are explicit: a segment parallel to the
/// line (A = 0) is within R of every centre or of none; one perpendicular to
/// it (u·v = 0) has the same t* for every s.
pub fn hit_interval(line: &Line, seg: &Segment) -> Option<(f64, f64)> {
    let w0 = line.origin - seg.start;
    let a_vec = line.dir.cross(seg.dir);
    let b_vec = w0.cross(seg.dir);
    let a = a_vec.length_squared();
    let r2 = line.radius * line.radius;
    // Step 1: distance from the segment's line at most R.
    let (mut lo, mut hi) = if a > 0.0 {
        let s_c = -a_vec.dot(b_vec) / a;
        let d2_min = (b_vec + a_vec * s_c).length_squared();
        if d2_min > r2 {
            return None;
        }
        let delta = ((r2 - d2_min) / a).sqrt();
        (s_c - delta, s_c + delta)
    } else if b_vec.length_squared() <= r2 {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        return None;
    };
    // Step 2: the closest point within the segment, 0 ≤ t*(s) ≤ ℓ.
    let t0 = w0.dot(seg.dir);
    let mu = line.dir.dot(seg.dir);
    if mu > 0.0 {
        lo = lo.max(-t0 / mu);
        hi = hi.min((seg.length - t0) / mu);
    } else if mu < 0.0 {
        lo = lo.max((seg.length - t0) / mu);
        hi = hi.min(-t0 / mu);
    } else if !(0.0..=seg.length).contains(&t0) {
        return None;
    }
    (lo <= hi).then_some((lo, hi))
}

/// Number of sphere centres (sorted positions `centres`) the segment hits,
/// by [`hit_interval`] and two binary searches; `None` when the interval is
/// empty (no search made).
pub fn hits_sorted(line: &Line, seg: &Segment, centres: &[f64]) -> Option<u64> {
    let (lo, hi) = hit_interval(line, seg)?;
    let first = centres.partition_point(|&s| s < lo);
    let end = centres.partition_point(|&s| s <= hi);
    Some(end.saturating_sub(first) as u64)
}

/// Number of sphere centres the segment hits, testing every pair: closest
/// point t* = (c − p₀)·v within [0, ℓ] and |c − p₀ − t* v|² ≤ R².
pub fn hits_brute_force(line: &Line, seg: &Segment, centres: &[f64]) -> u64 {
    let r2 = line.radius * line.radius;
    centres
        .iter()
        .filter(|&&s| {
            let c = line.origin + line.dir * s;
            let t = (c - seg.start).dot(seg.dir);
            (0.0..=seg.length).contains(&t) && (c - seg.start - seg.dir * t).length_squared() <= r2
        })
        .count() as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line() -> Line {
        Line { origin: DVec3::ZERO, dir: DVec3::Z, radius: 0.1 }
    }

    #[test]
    fn perpendicular_segment_hits_the_spheres_it_passes_within_r() {
        // Along x at z = 1, y = 0.05: within R of centres with |s − 1| ≤ √(0.01 − 0.0025).
        let seg = Segment { start: DVec3::new(-1.0, 0.05, 1.0), dir: DVec3::X, length: 2.0 };
        let (lo, hi) = hit_interval(&line(), &seg).unwrap();
        let half = (0.01f64 - 0.0025).sqrt();
        assert!((lo - (1.0 - half)).abs() < 1e-15 && (hi - (1.0 + half)).abs() < 1e-15);
        let centres = [0.8, 0.95, 1.0, 1.05, 1.2];
        assert_eq!(hits_sorted(&line(), &seg, &centres), Some(3));
        assert_eq!(hits_brute_force(&line(), &seg, &centres), 3);
    }

    #[test]
    fn perpendicular_segment_that_stops_short_hits_nothing() {
        let seg = Segment { start: DVec3::new(-1.0, 0.0, 1.0), dir: DVec3::X, length: 0.5 };
        assert_eq!(hit_interval(&line(), &seg), None);
    }

    #[test]
    fn parallel_segment_hits_the_centres_along_its_length() {
        let seg = Segment { start: DVec3::new(0.05, 0.0, 0.5), dir: DVec3::Z, length: 1.0 };
        let centres = [0.2, 0.6, 1.4, 1.6];
        assert_eq!(hits_sorted(&line(), &seg, &centres), Some(2));
        assert_eq!(hits_brute_force(&line(), &seg, &centres), 2);
        let far = Segment { start: DVec3::new(0.2, 0.0, 0.5), dir: DVec3::Z, length: 1.0 };
        assert_eq!(hits_sorted(&line(), &far, &centres), None);
    }

    #[test]
    fn antiparallel_segment_is_handled_like_a_parallel_one() {
        let seg = Segment { start: DVec3::new(0.0, 0.05, 1.5), dir: -DVec3::Z, length: 1.0 };
        let centres = [0.2, 0.6, 1.4, 1.6];
        assert_eq!(hits_sorted(&line(), &seg, &centres), Some(2));
        assert_eq!(hits_brute_force(&line(), &seg, &centres), 2);
    }
}
