//! The Gymnasium tasks' per-step numbers (`afit_fdm.gym`), computed in Rust:
//! the observations, rewards and termination flags of every aircraft. (How
//! each model's controls follow from an action, and what the tasks read of
//! its state, are the model's: `fdm_run::model::AgentModel`.)
//!
//! Each formula is the one `afit_fdm.gym` computed with NumPy before
//! (`tests/test_task_kernel.py` keeps that code as the oracle and compares
//! bit for bit), written with the same operations in the same order:
//! NumPy's `%` is [`np_remainder`] (Python's floor modulo), `np.minimum` and
//! `np.clip` propagate NaN ([`np_minimum`], [`np_clip`]), `np.degrees` is
//! `x * (180 / π)` ([`f64::to_degrees`]).
//!
//! Two functions are not NumPy's: the track's `atan2` and the horizontal
//! speed's `hypot` are `fdm_core::math`'s ([`atan2_lanes`], [`hypot_lanes`]:
//! fdlibm's `atan2` and musl's `hypot`, pure Rust, several aircraft at once
//! with the scalar functions' bits), so the observations are the same bits
//! on every machine, as the models' states are. NumPy's `arctan2` and
//! `hypot` are not: they call the platform's C library (and `arctan2` runs
//! NumPy's own SIMD kernel on CPUs with AVX-512), which differs between
//! machines in the last bit. The oracle computes those two functions with
//! the same `fdm_core::math` functions (`afit_fdm._afit_fdm._math_atan2`
//! and `_math_hypot`, one argument pair at a time) and every other
//! operation with NumPy.
//!
//! [`observe_block`] computes a block of aircraft stage by stage over the
//! block's lanes (every operation correctly rounded and none fused, so a
//! lane's bits do not depend on the lanes beside it): the divisions, float32
//! roundings and clips of eight aircraft can share vector instructions.

use fdm_core::math::{atan2_lanes, hypot_lanes};

/// Knots per metre per second (`3600.0 / 1852.0`).
pub const KT_PER_MPS: f64 = 3600.0 / 1852.0;
/// Observations are clipped to `-OBS_LIMIT..=OBS_LIMIT`.
pub const OBS_LIMIT: f32 = 10.0;
/// Observations before the controls: altitude error, heading error, climb
/// rate, ground speed, sine and cosine of the track.
pub const KINEMATIC_OBS: usize = 6;

/// A task of `afit_fdm.gym`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Task {
    /// `heading-altitude`: hold a target altitude and heading.
    HeadingAltitude,
    /// `climb`: climb to and level off at a target altitude.
    Climb,
}

impl Task {
    /// The task named `name` (`heading-altitude` or `climb`).
    ///
    /// # Errors
    /// Another name.
    pub fn named(name: &str) -> Result<Self, String> {
        match name {
            "heading-altitude" => Ok(Self::HeadingAltitude),
            "climb" => Ok(Self::Climb),
            other => Err(format!(
                "task: {other:?} is not 'heading-altitude' or 'climb'"
            )),
        }
    }
}

/// NumPy's float remainder (`np.remainder`, Python's `%`): the C `fmod`,
/// moved into the divisor's sign; a zero result takes the divisor's sign.
#[must_use]
pub fn np_remainder(a: f64, b: f64) -> f64 {
    let m = fmod(a, b);
    if m == 0.0 {
        0.0_f64.copysign(b)
    } else if (b < 0.0) != (m < 0.0) {
        m + b
    } else {
        m
    }
}

/// C's `fmod(a, b)` for `b > 0` (Rust's `%`), without the library call
/// where the result is a plain difference: `a` itself for `|a| < b`, and
/// `a ∓ b` for `b <= |a| < 2b`, which is exact (Sterbenz's lemma: `a` and
/// `b` within a factor of 2), as `fmod`'s result always is. The tasks'
/// angles are all in that range.
#[must_use]
fn fmod(a: f64, b: f64) -> f64 {
    let size = a.abs();
    if b > 0.0 && size < b {
        a
    } else if b > 0.0 && size < 2.0 * b {
        if a > 0.0 {
            a - b
        } else {
            // fmod keeps the sign of `a`, also for a zero result.
            let m = a + b;
            if m == 0.0 {
                -0.0
            } else {
                m
            }
        }
    } else {
        a % b
    }
}

/// `np.minimum(a, b)`: NaN if either is NaN.
#[must_use]
pub fn np_minimum(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else if a <= b {
        a
    } else {
        b
    }
}

/// `np.clip(x, lo, hi)` (`lo <= hi`): NaN stays NaN, as [`f64::clamp`].
#[must_use]
pub fn np_clip(x: f64, lo: f64, hi: f64) -> f64 {
    x.clamp(lo, hi)
}

/// `np.clip` of a float32 observation to ±[`OBS_LIMIT`]: NaN stays NaN.
#[must_use]
pub fn np_clip_f32(x: f32) -> f32 {
    x.clamp(-OBS_LIMIT, OBS_LIMIT)
}

/// Aircraft per block of [`observe_block`].
pub const BLOCK: usize = 8;
/// Most observed controls per aircraft (Bourg's five).
pub const MAX_CONTROL_OBS: usize = 5;

/// What the tasks read of a block of aircraft (lane `l` is one aircraft),
/// in the units of `afit_fdm.gym`'s `_kinematics`.
#[derive(Debug, Clone, Copy)]
pub struct Block<const N: usize> {
    /// Altitude, ft.
    pub alt_ft: [f64; N],
    /// Climb rate, ft/s.
    pub vz_fps: [f64; N],
    /// The model's north velocity (Palmer m/s, Bourg ft/s).
    pub vx: [f64; N],
    /// The model's west velocity (Palmer m/s, Bourg ft/s).
    pub vy: [f64; N],
    /// Target altitude, ft.
    pub target_alt_ft: [f64; N],
    /// Target heading, degrees.
    pub target_heading_deg: [f64; N],
    /// Observed controls (`observed[c][l]`), the first `controls` rows.
    pub observed: [[f64; N]; MAX_CONTROL_OBS],
    /// Whether the aircraft is airborne.
    pub airborne: [bool; N],
}

impl<const N: usize> Default for Block<N> {
    /// A level aircraft flying north at 1 unit/s (what unused lanes hold).
    fn default() -> Self {
        Self {
            alt_ft: [0.0; N],
            vz_fps: [0.0; N],
            vx: [1.0; N],
            vy: [0.0; N],
            target_alt_ft: [0.0; N],
            target_heading_deg: [0.0; N],
            observed: [[0.0; N]; MAX_CONTROL_OBS],
            airborne: [true; N],
        }
    }
}

/// The outputs of the first `count` aircraft of a block: `obs` (`count`
/// rows of [`KINEMATIC_OBS`] + `controls` values), `reward` and `ended`
/// (whether the episode ended by status).
#[derive(Debug)]
pub struct BlockOut<'a> {
    /// Observations, row by row.
    pub obs: &'a mut [f32],
    /// Rewards.
    pub reward: &'a mut [f64],
    /// Ended by status.
    pub ended: &'a mut [bool],
}

/// The observations (`obs`: the kinematic part and then the observed
/// controls), rewards and whether each episode ended by status of the first
/// `out.reward.len()` aircraft of block `b`, as `_Task.observe` computed
/// them: `ground_mps_per_speed` turns the horizontal speed in the
/// velocity's units into m/s (Palmer 1, Bourg 0.3048); `controls` observed
/// controls per aircraft.
#[inline(always)]
#[allow(clippy::cast_possible_truncation)] // float32 observations, as NumPy casts
pub fn observe_block<const N: usize>(
    task: Task,
    ground_mps_per_speed: f64,
    b: &Block<N>,
    controls: usize,
    out: BlockOut<'_>,
) {
    let n_obs = KINEMATIC_OBS + controls;
    let speed = hypot_lanes(b.vx, b.vy);
    // y points west: the track is clockwise from north toward east (-y).
    let track_rad = atan2_lanes(b.vy.map(|vy| -vy), b.vx);
    let track_deg = remainder_lanes(track_rad.map(f64::to_degrees), 360.0);
    let mut turn = [0.0; N];
    for (t, (target, track)) in turn
        .iter_mut()
        .zip(b.target_heading_deg.iter().zip(&track_deg))
    {
        *t = target - track + 180.0;
    }
    let turn = remainder_lanes(turn, 360.0);
    let mut kinematic = [[0.0; N]; KINEMATIC_OBS];
    let mut alt_err = [0.0; N];
    let mut hdg_err = [0.0; N];
    for l in 0..N {
        let ground_mps = speed[l] * ground_mps_per_speed;
        let ground_kt = ground_mps * KT_PER_MPS;
        alt_err[l] = b.target_alt_ft[l] - b.alt_ft[l];
        hdg_err[l] = turn[l] - 180.0;
        let moving = ground_mps > 0.0;
        // The track's sine and cosine divide the velocity by the horizontal
        // speed in the velocity's own units (Bourg's ft/s, not the m/s of
        // `ground_mps`): a unit vector for both models.
        let safe = if moving { speed[l] } else { 1.0 };
        kinematic[0][l] = alt_err[l] / 1000.0;
        kinematic[1][l] = hdg_err[l] / 180.0;
        kinematic[2][l] = b.vz_fps[l] / 20.0;
        kinematic[3][l] = ground_kt / 200.0;
        kinematic[4][l] = if moving { -b.vy[l] / safe } else { 0.0 };
        kinematic[5][l] = if moving { b.vx[l] / safe } else { 1.0 };
    }
    for (l, row) in out.obs.chunks_exact_mut(n_obs).enumerate().take(N) {
        let columns = kinematic.iter().chain(&b.observed[..controls]);
        for (o, column) in row.iter_mut().zip(columns) {
            *o = np_clip_f32(column[l] as f32);
        }
    }
    let mut reward = [0.0; N];
    match task {
        Task::HeadingAltitude => {
            for (r, (a, h)) in reward.iter_mut().zip(alt_err.iter().zip(&hdg_err)) {
                let (a_err, h_err) = (a.abs(), h.abs());
                *r = 1.0
                    - 0.5 * np_minimum(a_err / 500.0, 1.0)
                    - 0.5 * np_minimum(h_err / 45.0, 1.0);
            }
        }
        Task::Climb => {
            for (r, (a, vz)) in reward.iter_mut().zip(alt_err.iter().zip(&b.vz_fps)) {
                let a_err = a.abs();
                let near = 1.0
                    - 0.7 * np_minimum(a_err / 1000.0, 1.0)
                    - 0.3 * np_minimum(vz.abs() / 10.0, 1.0);
                let far = 0.3 * (1.0 - np_minimum(a_err / 2000.0, 1.0));
                *r = if a_err <= 200.0 { near } else { far };
            }
        }
    }
    for (l, (r, ended)) in out.reward.iter_mut().zip(out.ended.iter_mut()).enumerate() {
        *ended = !b.airborne[l];
        *r = if *ended { 0.0 } else { reward[l] };
    }
}

/// [`np_remainder`]`(a, b)` of every lane for `b > 0`: branch-free (selects
/// the compiler can put in vector registers) where `|a| < 2b` (the tasks'
/// angles always), [`np_remainder`] itself in any other lane (and NaN).
#[inline(always)]
fn remainder_lanes<const N: usize>(a: [f64; N], b: f64) -> [f64; N] {
    let mut out = [0.0; N];
    let mut near = [true; N];
    for ((o, n), &x) in out.iter_mut().zip(near.iter_mut()).zip(&a) {
        let size = x.abs();
        *n = size < 2.0 * b;
        // `fmod` as [`fmod`] computes it for `|a| < 2b` ...
        let below = x + b;
        let m = if size < b {
            x
        } else if x > 0.0 {
            x - b
        } else if below == 0.0 {
            -0.0
        } else {
            below
        };
        // ... moved into the divisor's sign as [`np_remainder`] does.
        *o = if m == 0.0 {
            0.0
        } else if m < 0.0 {
            m + b
        } else {
            m
        };
    }
    // One test of all the lanes (a vector compare) for the usual case, not
    // one branch per lane.
    if near.iter().fold(true, |all, &n| all & n) {
        return out;
    }
    for ((o, n), &x) in out.iter_mut().zip(&near).zip(&a) {
        if !n {
            *o = np_remainder(x, b);
        }
    }
    out
}
