//! Fingerprints of a flight: a 64-bit hash of a state's bits and one of the
//! maths in use, for recordings and study results to carry, so that a replay
//! on another machine (or with another build) can say plainly that it is not
//! flying the same flight instead of silently flying another one.
//!
//! Both hashes are FNV-1a (64-bit) over little-endian bytes: no allocation, no
//! platform dependence, and stable across releases unless the state layout or
//! the maths change (which is what they are for). They are not cryptographic.
//!
//! ```
//! use fdm_core::fingerprint::{self, Fingerprint};
//! use fdm_core::palmer::{step, PalmerAircraft, PalmerControls, PalmerState};
//!
//! let cessna = PalmerAircraft::cessna_172();
//! let controls = PalmerControls { throttle: 1.0, ..PalmerControls::default() };
//! let mut state = PalmerState::at_rest();
//! for _ in 0..100 {
//!     state = step(&cessna, &controls, &state, 0.1);
//! }
//! let recorded = Fingerprint::of_palmer(&state);
//! // ... later, replayed elsewhere:
//! assert_eq!(Fingerprint::of_palmer(&state), recorded);
//! assert_eq!(recorded.maths, fingerprint::maths());
//! ```

use crate::bourg::BourgState;
use crate::math;
use crate::palmer::PalmerState;

/// FNV-1a 64-bit hasher over the bits of numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hasher(u64);

impl Default for Hasher {
    fn default() -> Self {
        Self::new()
    }
}

impl Hasher {
    /// The FNV-1a offset basis.
    #[must_use]
    pub const fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    /// Feeds bytes.
    #[must_use]
    pub const fn bytes(mut self, bytes: &[u8]) -> Self {
        let mut i = 0;
        while i < bytes.len() {
            self.0 ^= bytes[i] as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
            i += 1;
        }
        self
    }

    /// Feeds the bits of an f64 (so `-0.0` and `0.0` differ, as do NaN payloads).
    #[must_use]
    pub const fn f64(self, x: f64) -> Self {
        self.bytes(&x.to_bits().to_le_bytes())
    }

    /// Feeds the bits of an f32.
    #[must_use]
    pub const fn f32(self, x: f32) -> Self {
        self.bytes(&x.to_bits().to_le_bytes())
    }

    /// Feeds a boolean as one byte.
    #[must_use]
    pub const fn bool(self, b: bool) -> Self {
        self.bytes(&[b as u8])
    }

    /// The hash so far.
    #[must_use]
    pub const fn finish(self) -> u64 {
        self.0
    }
}

/// A hash of the maths in use: every [`crate::math`] function evaluated on a
/// fixed set of probe inputs, including inputs where the functions of common
/// libms disagree in the last bit (so a build whose maths differ gets another
/// fingerprint). The same on every target with the same fdm-core maths.
#[must_use]
pub fn maths() -> u64 {
    let mut h = Hasher::new();
    let probes_f64: [f64; 10] = [
        0.1,
        0.3,
        0.7,
        0.9,
        1.3,
        2.5,
        -0.45,
        1e-3,
        core::f64::consts::FRAC_PI_4,
        3.1,
    ];
    for &x in &probes_f64 {
        h = h
            .f64(math::sqrt(x.abs()))
            .f64(math::pow(x.abs() + 0.5, 5.25))
            .f64(math::pow(x.abs() * 7.0, x))
            .f64(math::sin(x))
            .f64(math::cos(x))
            .f64(math::atan(x * 9.0))
            .f64(math::atan2(x, 0.75))
            .f64(math::asin(x / 4.0))
            .f64(math::acos(x / 4.0))
            .f64(math::tan(x))
            .f64(math::hypot(x, 1.5))
            .f64(math::cbrt(x * 11.0))
            .f64(math::fma(x, 3.0, 0.1));
        let y = x as f32;
        h = h
            .f32(math::sqrtf(y.abs()))
            .f32(math::sinf(y))
            .f32(math::cosf(y))
            .f32(math::asinf(y / 4.0))
            .f32(math::atan2f(y, 0.75));
    }
    // Inputs of asinf's exception table and of its polynomial's branches.
    for bits in [
        0x3d00_0000_u32,
        0x3e80_0000,
        0x3f10_0000,
        0x3f7c_0000,
        0x3f80_0000,
    ] {
        h = h.f32(math::asinf(f32::from_bits(bits)));
    }
    h.finish()
}

/// [`maths()`] of this version of fdm-core's maths, the same on every target.
pub const MATHS_FINGERPRINT: u64 = 0x4bad_06c3_cb1a_9349;

/// The fingerprint of a flight at one instant: its state's bits and the
/// maths that flew it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    /// Hash of the state's bits.
    pub state: u64,
    /// [`maths()`] of the build that computed the state.
    pub maths: u64,
}

impl Fingerprint {
    /// The fingerprint of a Palmer state: time, position, velocity.
    #[must_use]
    pub fn of_palmer(state: &PalmerState) -> Self {
        Self {
            state: palmer_state(state),
            maths: maths(),
        }
    }

    /// The fingerprint of a Bourg state: time, position, velocities,
    /// angular velocity, orientation and the stall flag.
    #[must_use]
    pub fn of_bourg(state: &BourgState) -> Self {
        Self {
            state: bourg_state(state),
            maths: maths(),
        }
    }
}

/// [`Fingerprint::of_palmer`]'s state hash alone (a few dozen multiplications,
/// cheap enough to take every frame; [`maths()`] evaluates every maths
/// function and is meant to be taken once).
#[must_use]
pub fn palmer_state(state: &PalmerState) -> u64 {
    let mut h = Hasher::new().bytes(b"palmer").f64(state.time_s);
    for v in state.position_m.iter().chain(state.velocity_mps.iter()) {
        h = h.f64(*v);
    }
    h.finish()
}

/// [`Fingerprint::of_bourg`]'s state hash alone (see [`palmer_state`]).
#[must_use]
pub fn bourg_state(state: &BourgState) -> u64 {
    let mut h = Hasher::new().bytes(b"bourg").f64(state.time_s);
    for v in state
        .position_ft
        .iter()
        .chain(state.velocity_ftps.iter())
        .chain(state.velocity_body_ftps.iter())
        .chain(state.angular_velocity_radps.iter())
        .chain(state.orientation.coords.iter())
    {
        h = h.f32(*v);
    }
    h.bool(state.stalling).finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        assert_eq!(Hasher::new().finish(), 0xcbf2_9ce4_8422_2325);
        assert_eq!(Hasher::new().bytes(b"a").finish(), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(
            Hasher::new().bytes(b"foobar").finish(),
            0x8594_4171_f739_67e8
        );
    }

    #[test]
    fn a_state_differing_in_one_bit_has_another_fingerprint() {
        let a = PalmerState::at_rest();
        let mut b = a;
        b.position_m.x = f64::from_bits(b.position_m.x.to_bits() ^ 1);
        assert_ne!(Fingerprint::of_palmer(&a), Fingerprint::of_palmer(&b));
        assert_eq!(Fingerprint::of_palmer(&a), Fingerprint::of_palmer(&a));
        let s = BourgState::initial();
        let mut t = s;
        t.stalling = !t.stalling;
        assert_ne!(
            Fingerprint::of_bourg(&s).state,
            Fingerprint::of_bourg(&t).state
        );
    }

    #[test]
    fn the_maths_fingerprint_is_the_recorded_one() {
        // Recorded on x86-64; the same on every target (proven by running this
        // test on aarch64 under qemu in CI and without std in libm-check).
        assert_eq!(maths(), MATHS_FINGERPRINT, "{:#x}", maths());
    }
}
