//! The bounds of a valid scene, in one place (`docs/scene-format.md`,
//! "Bounds"). Every value inside them is something the oracle and the
//! tracer compute without overflow, without NaN and within bounded memory
//! and work per iteration; a scene outside them is refused by validation
//! with the field, the value and the bound named.
//!
//! Lengths are bounded in units of 1/σ_ext (mean free paths): the physics
//! depends on σ_ext × length only. Scales (flux, σ_ext) are bounded so that
//! the worst products stay finite: the per-hit contribution
//! 𝒞 = albedo f 𝓕/(πR²) = albedo f 𝓕σ²/(π(σR)²) is at most
//! 1.6e11 (f at |g| = [`MAX_ABS_G`]) × 1e10 × 1e20 × 1e24 / π ≈ 5e64 per unit
//! of flux range, so that a trial's L (about 𝒞 × 1/q hits per forward-ray
//! segment) stays near 1e71 or below and the tracer's fourth power sums
//! (Var L's standard error) below 1e300 even over 10¹² trials. (σ_ext·R
//! reaches 1e-11 in an optically thin test, `tests/scattered.rs`.)

/// σ_ext (1/length) in [MIN_SIGMA_EXT, MAX_SIGMA_EXT].
pub const MIN_SIGMA_EXT: f64 = 1e-10;
/// See [`MIN_SIGMA_EXT`].
pub const MAX_SIGMA_EXT: f64 = 1e10;

/// Each light's flux in [MIN_FLUX, MAX_FLUX].
pub const MIN_FLUX: f64 = 1e-10;
/// See [`MIN_FLUX`].
pub const MAX_FLUX: f64 = 1e10;

/// |g| of Henyey–Greenstein at most this: f(±1) ≤ 2/(4π(1 − |g|)²) ≈ 1.6e11.
pub const MAX_ABS_G: f64 = 1.0 - 1e-6;

/// Every coordinate of a position, beam centre or camera origin, and a
/// beam's radius: σ_ext·|x| ≤ MAX_OPTICAL_COORDINATE. Differences and norms
/// then never overflow, and a coordinate is resolved to 1e6 × 2⁻⁵³ ≈ 1e-10
/// mean free paths, finer than the smallest sphere.
pub const MAX_OPTICAL_COORDINATE: f64 = 1e6;

/// The sphere radius R: σ_ext·R in [MIN_OPTICAL_RADIUS, MAX_OPTICAL_RADIUS].
pub const MIN_OPTICAL_RADIUS: f64 = 1e-12;
/// See [`MIN_OPTICAL_RADIUS`].
pub const MAX_OPTICAL_RADIUS: f64 = 1e3;

/// A beam's disk radius: σ_ext·a at least this (and at most
/// [`MAX_OPTICAL_COORDINATE`]); its irradiance 𝓕/(πa²) stays below 1e40 σ².
pub const MIN_OPTICAL_BEAM_RADIUS: f64 = 1e-10;

/// Each light's optical distance from the camera, σ_ext × (distance from the
/// camera origin to the light's nearest point: the point light, or the
/// nearest point of a beam's disk), at most this. Every path from the light
/// via the camera ray to the camera is at least that long, so its light is
/// attenuated by at least e^{−τ}; e^{−745} underflows f64 to 0, and at 600
/// (e^{−600} ≈ 2.6e-261) the 47 decades left keep the mean luminance a normal
/// f64 for every flux, σ_ext and geometry factor inside these bounds.
pub const MAX_OPTICAL_DISTANCE: f64 = 600.0;

/// q at least this: a camera ray places on average 1/q integration spheres
/// (the tracer stores them, 8 bytes each): at most 10⁶ per camera ray.
pub const MIN_Q: f64 = 1e-6;

/// N_F at most this: one iteration traces N_F forward rays (work, not
/// memory; ~10 s per iteration at the tracer's ~10⁷ segments/s).
pub const MAX_FORWARD_RAYS: i64 = 100_000_000;

/// N_B at most this.
pub const MAX_CAMERA_RAYS: i64 = 1_000_000;

/// N_B/q, the expected number of spheres of one iteration (all stored at
/// once by the tracer, 8 bytes each: 80 MB), at most this.
pub const MAX_SPHERES_PER_ITERATION: f64 = 1e7;

/// Largest number of scattering orders accepted as a number (beyond, use "all").
pub const MAX_ORDERS: i64 = 1_000_000;

/// The largest scene file read (a scene file is a few hundred bytes; this
/// bounds what a wrong path, `/dev/zero` say, can make a reader allocate).
pub const MAX_SCENE_FILE_BYTES: u64 = 1 << 20;

/// The text of the scene file at `path`, at most [`MAX_SCENE_FILE_BYTES`]
/// long, or a message naming the path and what went wrong.
///
/// ```
/// use mcrt_scene::limits::read_scene_text;
/// let err = read_scene_text(std::path::Path::new("/no/such/scene.toml")).unwrap_err();
/// assert!(err.starts_with("/no/such/scene.toml: cannot read"));
/// ```
pub fn read_scene_text(path: &std::path::Path) -> Result<String, String> {
    use std::io::Read;
    let cannot = |e: std::io::Error| format!("{}: cannot read: {e}", path.display());
    let mut text = String::new();
    std::fs::File::open(path)
        .map_err(cannot)?
        .take(MAX_SCENE_FILE_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(cannot)?;
    if text.len() as u64 > MAX_SCENE_FILE_BYTES {
        return Err(format!(
            "{}: longer than {MAX_SCENE_FILE_BYTES} bytes: not a scene file (they are a few hundred bytes)",
            path.display()
        ));
    }
    Ok(text)
}
