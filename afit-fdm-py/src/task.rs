//! The Gymnasium tasks' per-step numbers (`afit_fdm.gym`), computed in Rust:
//! the action array scaled to the controls, and the observations, rewards
//! and termination flags of every aircraft.
//!
//! Each formula is the one `afit_fdm.gym` computed with NumPy before
//! (`tests/test_task_kernel.py` keeps that code as the oracle and compares
//! bit for bit), written with the same operations in the same order:
//! NumPy's `%` is [`np_remainder`] (Python's floor modulo), `np.minimum` and
//! `np.clip` propagate NaN ([`np_minimum`], [`np_clip`]), `np.degrees` is
//! `x * (180 / π)` ([`f64::to_degrees`]), `np.hypot` is the C library's
//! `hypot` ([`f64::hypot`]). One function differs by machine: NumPy's
//! `arctan2` runs its own SIMD kernel on CPUs with AVX-512 (within 1 ulp of
//! the C library's `atan2`, which it calls elsewhere); this module calls the
//! C library's `atan2` ([`f64::atan2`]) on every machine.

/// Feet per metre, as `afit_fdm.gym` computes it (`1.0 / 0.3048`).
pub const FT_PER_M: f64 = 1.0 / 0.3048;
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

/// What the tasks read of an aircraft's state, in the units of
/// `afit_fdm.gym`'s `_kinematics`.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics {
    /// Altitude, ft.
    pub alt_ft: f64,
    /// Climb rate, ft/s.
    pub vz_fps: f64,
    /// The model's north velocity (Palmer m/s, Bourg ft/s).
    pub vx: f64,
    /// The model's west velocity (Palmer m/s, Bourg ft/s).
    pub vy: f64,
    /// Horizontal speed in the velocity's own units, `vx.hypot(vy)`.
    pub speed: f64,
    /// Ground speed, m/s.
    pub ground_mps: f64,
}

/// One aircraft's observation (`obs`, the kinematic part and then
/// `controls`), reward and whether its episode ended by status, as
/// `_Task.observe` computed them.
#[allow(clippy::too_many_arguments)]
pub fn observe(
    task: Task,
    k: &Kinematics,
    target_alt_ft: f64,
    target_heading_deg: f64,
    controls: &[f64],
    airborne: bool,
    obs: &mut [f32],
) -> (f64, bool) {
    let ground_kt = k.ground_mps * KT_PER_MPS;
    // y points west: the track is clockwise from north toward east (-y).
    let track_deg = np_remainder((-k.vy).atan2(k.vx).to_degrees(), 360.0);
    let alt_err = target_alt_ft - k.alt_ft;
    let hdg_err = np_remainder(target_heading_deg - track_deg + 180.0, 360.0) - 180.0;
    let moving = k.ground_mps > 0.0;
    // The track's sine and cosine divide the velocity by the horizontal
    // speed in the velocity's own units (Bourg's ft/s, not the m/s of
    // `ground_mps`): a unit vector for both models.
    let safe = if moving { k.speed } else { 1.0 };
    #[allow(clippy::cast_possible_truncation)] // float32 observations, as NumPy casts
    {
        let kinematic = [
            alt_err / 1000.0,
            hdg_err / 180.0,
            k.vz_fps / 20.0,
            ground_kt / 200.0,
            if moving { -k.vy / safe } else { 0.0 },
            if moving { k.vx / safe } else { 1.0 },
        ];
        for (o, v) in obs.iter_mut().zip(kinematic.iter().chain(controls)) {
            *o = np_clip_f32(*v as f32);
        }
    }
    let (a_err, h_err) = (alt_err.abs(), hdg_err.abs());
    let reward = match task {
        Task::HeadingAltitude => {
            1.0 - 0.5 * np_minimum(a_err / 500.0, 1.0) - 0.5 * np_minimum(h_err / 45.0, 1.0)
        }
        Task::Climb => {
            let near = 1.0
                - 0.7 * np_minimum(a_err / 1000.0, 1.0)
                - 0.3 * np_minimum(k.vz_fps.abs() / 10.0, 1.0);
            let far = 0.3 * (1.0 - np_minimum(a_err / 2000.0, 1.0));
            if a_err <= 200.0 {
                near
            } else {
                far
            }
        }
    };
    let ended = !airborne;
    (if ended { 0.0 } else { reward }, ended)
}

/// Bourg's all-or-nothing surfaces from an action: +1 above 1/3, -1 below
/// -1/3, else 0 (NaN too), as `_surface`.
#[must_use]
pub fn surface(a: f64) -> f64 {
    if a > 1.0 / 3.0 {
        1.0
    } else if a < -1.0 / 3.0 {
        -1.0
    } else {
        0.0
    }
}

/// Palmer's controls from one aircraft's clipped actions: throttle,
/// alpha_deg, bank_deg, flaps_deg (control indices 0..4).
#[must_use]
pub fn palmer_controls(a: &[f64]) -> [(usize, f64); 4] {
    let flaps = if a[3] < -1.0 / 3.0 {
        0.0
    } else if a[3] <= 1.0 / 3.0 {
        20.0
    } else {
        40.0
    };
    [
        (0, (a[0] + 1.0) * 0.5),
        (1, 2.0 + 18.0 * a[1]),
        (2, 20.0 * a[2]),
        (3, flaps),
    ]
}

/// Bourg's controls from one aircraft's clipped actions: thrust_lb,
/// elevator, aileron, rudder, pitch_trim (control indices 0, 1, 2, 3, 5).
#[must_use]
pub fn bourg_controls(a: &[f64]) -> [(usize, f64); 5] {
    [
        (0, 1500.0 * (a[0] + 1.0)),
        (1, surface(a[1])),
        (2, surface(a[2])),
        (3, surface(a[3])),
        (5, a[4]),
    ]
}
