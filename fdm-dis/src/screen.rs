//! The fleet publisher's screen ([`crate::FleetPublisher::publish_screened`]):
//! which aircraft certainly have nothing due this frame, decided from a
//! cheap [`Rough`] frame of each and a compact copy of what its tracker last
//! sent ([`ScreenRef`]), in straight-line arithmetic with no transcendental
//! function. Both are kept eight aircraft to a block, field by field
//! ([`RoughLanes`], [`ScreenLanes`]), and screened eight at a time
//! ([`ScreenLanes::quiet_lanes`], the operations of the one-aircraft
//! reference `ScreenRef::quiet` lane by lane).
//!
//! The screen never decides what is sent: an aircraft it cannot clear takes
//! the exact path ([`crate::Tracker::update`] on its full view), whose
//! decision and bytes are the ones a fleet without a screen makes. What the
//! screen must never do is clear an aircraft for which the exact path would
//! have sent a PDU or counted an error, so every comparison it makes has a
//! margin larger than everything that separates its numbers from the exact
//! path's (each bound is argued where it is used):
//!
//! * **time**: the time since the last PDU and the heartbeat are the exact
//!   path's operations on the same numbers (same bits), compared as there;
//! * **position**: the receivers' extrapolation (`P₀ + V₀ Δt + ½ A₀ Δt²`)
//!   and the aircraft's ECEF location differ from the exact path's only by
//!   rounding, a few units in the last place of the largest magnitude
//!   involved; the margin is 1 µm plus 1e-13 of that magnitude;
//! * **orientation**: the exact path extrapolates the last PDU's matrix
//!   with a sine and cosine (`C₀ · exp([ω]× Δt)`) and measures the angle of
//!   the rotation to the true orientation with an `atan2`. Here the cosine
//!   of that angle is `(tr(Rᵀ N) − 1)/2` with `N = C₀ᵀ C_ecef←ned B` (`B`
//!   the rough body-to-NED matrix, within [`ROUGH_TOLERANCE`] of the exact
//!   one) and `R = I + A [ω]× + B' [ω]×²`, whose `A = sin θ/θ` and
//!   `B' = (1 − cos θ)/θ²` are their Taylor series in `θ²` (for `θ` up to
//!   0.5 rad, to 4e-14); the aircraft is cleared when that cosine is above
//!   the threshold's by 1e-7, against an error below 1e-8 (see
//!   `ScreenRef::quiet`).
//!
//! Anything else (the first PDU, a clock that went back, a state that is not
//! certainly finite, a turn of more than 0.5 rad since the last PDU,
//! thresholds below about 0.03° that leave no room for the margin) is not
//! cleared.

use fdm_core::math;
use nalgebra::Matrix3;

use crate::dead_reckoning::{DrThresholds, HEARTBEAT_SLACK_S};
use crate::tracker::{Placement, Rough, Tracker};

/// How far, element by element, a rough body-to-NED matrix may be from the
/// one the exact path makes (`FlightView::attitude`'s
/// [`body_to_ned`](fdm_core::geodesy::Attitude::body_to_ned)) for the fleet
/// screen ([`Rough`]) to stay conservative.
pub const ROUGH_TOLERANCE: f64 = 1e-9;

/// The margin on the cosine of the orientation error.
const COS_MARGIN: f64 = 1e-7;

/// Largest `θ²` (rad²) of the extrapolated turn that the series cover
/// (θ ≤ 0.5 rad): the first term left out, `θ¹²/13!`, is below 4e-14.
const MAX_TURN_SQ: f64 = 0.25;

/// `(−1)ᵏ/(2k + first)!` for `k = 0..6`.
const fn series(first: u32) -> [f64; 6] {
    let mut c = [0.0; 6];
    let mut factorial = 1.0;
    let mut n = 1;
    while n <= first {
        factorial *= n as f64;
        n += 1;
    }
    let mut k = 0;
    while k < 6 {
        c[k] = if k % 2 == 0 { 1.0 } else { -1.0 } / factorial;
        factorial *= ((first + 2 * k as u32 + 1) * (first + 2 * k as u32 + 2)) as f64;
        k += 1;
    }
    c
}

/// The coefficients of `sin θ/θ` in powers of `θ²`: `(−1)ᵏ/(2k+1)!`.
const SIN_SERIES: [f64; 6] = series(1);
/// The coefficients of `(1 − cos θ)/θ²` in powers of `θ²`: `(−1)ᵏ/(2k+2)!`.
const COS_SERIES: [f64; 6] = series(2);

/// `c₀ + c₁ t + … + c₅ t⁵` by Estrin's scheme (three levels instead of
/// Horner's five dependent steps).
#[inline(always)]
fn estrin(c: &[f64; 6], t: f64) -> f64 {
    let t2 = t * t;
    (c[0] + c[1] * t) + t2 * ((c[2] + c[3] * t) + t2 * (c[4] + c[5] * t))
}

/// Largest velocity component (model frame, m/s) the screen clears: the
/// ECEF velocity is then below `√3 · 1e149 < 1e150` in every component, the
/// tracker's bound for rates made only when due.
const SLOW_M_S: f64 = 1e149;

/// Shortest frame the screen clears, seconds (the tracker's bound for rates
/// made only when due).
const MIN_FRAME_S: f64 = 1e-6;

/// What the screen keeps of one tracker: the last PDU as receivers
/// extrapolate it, the thresholds, and the previous frame's time; refreshed
/// from the tracker after every exact update ([`ScreenRef::refresh`]).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ScreenRef {
    /// A PDU was sent and the previous frame is certainly usable for lazy
    /// rates; `false` clears nothing.
    screenable: bool,
    /// The last PDU's time.
    sent_time: f64,
    /// Its location less the origin's ECEF position.
    sent_rel: [f64; 3],
    /// `|location|∞ + |origin|∞`, for the position margin.
    sent_scale: f64,
    /// Its velocity, acceleration (zero unless a V model) and angular
    /// velocity (zero unless an R model), the wire's `f32`s (the exact path
    /// widens them as they are used here).
    v: [f32; 3],
    a: [f32; 3],
    w: [f32; 3],
    /// `C₀ᵀ · C_ecef←ned`, row by row.
    p: [f64; 9],
    /// The previous frame's time.
    prev_time: f64,
    /// The screen cleared frames whose exact previous frame the tracker
    /// does not have yet (see `Tracker::restore_previous`).
    pub(crate) stale: bool,
    /// Quiet frames cleared since the tracker last counted.
    pub(crate) pending: u64,
}

/// The per-frame constants of the screen: the origin, and the thresholds
/// it screens for (the fleet's, when every tracker has the same; a tracker
/// with others is never cleared).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    /// The origin's ECEF position.
    ecef0: [f64; 3],
    ecef0_scale: f64,
    /// ENU to ECEF at the origin, row by row.
    enu_to_ecef: [f64; 9],
    /// The thresholds screened for.
    thresholds: Option<DrThresholds>,
    /// The position threshold, metres.
    position_m: f64,
    /// `cos(orientation threshold) + COS_MARGIN`.
    cos_min: f64,
    /// `heartbeat − slack`, as the exact path computes it.
    heartbeat_s: f64,
}

impl Frame {
    pub(crate) fn new(placement: &Placement, thresholds: Option<DrThresholds>) -> Self {
        let o = placement.origin();
        let e = o.ecef_m();
        let m = o.enu_to_ecef();
        let (position_m, cos_min, heartbeat_s) =
            thresholds.map_or((f64::NAN, f64::NAN, f64::NAN), |t| {
                (
                    t.position_m,
                    math::cos(t.orientation_deg.to_radians()) + COS_MARGIN,
                    t.heartbeat_s - HEARTBEAT_SLACK_S,
                )
            });
        Self {
            ecef0: [e.x, e.y, e.z],
            ecef0_scale: e.x.abs().max(e.y.abs()).max(e.z.abs()),
            enu_to_ecef: rows(&m),
            thresholds,
            position_m,
            cos_min,
            heartbeat_s,
        }
    }
}

fn rows(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

fn max_abs(v: [f64; 3]) -> f64 {
    v[0].abs().max(v[1].abs()).max(v[2].abs())
}

impl ScreenRef {
    /// The screen's copy of `tracker` as it is now (nothing pending).
    pub(crate) fn refresh(tracker: &Tracker, placement: &Placement, frame: &Frame) -> Self {
        let reckoner = tracker.publisher.reckoner();
        let (Some(sent), Some(prev)) = (reckoner.last_sent(), tracker.previous) else {
            return Self::default();
        };
        let algorithm = reckoner.algorithm();
        let c = reckoner.last_sent_body_to_ecef().transpose() * placement.model_ned_to_ecef();
        let l = sent.location_m;
        let prev_ok = prev.body_to_ecef.iter().all(|c| c.is_finite())
            && prev.velocity_ecef_m_s.iter().all(|c| c.abs() < 1e150);
        Self {
            screenable: prev_ok && frame.thresholds == Some(reckoner.thresholds()),
            sent_time: sent.time_s,
            sent_rel: [
                l.x - frame.ecef0[0],
                l.y - frame.ecef0[1],
                l.z - frame.ecef0[2],
            ],
            sent_scale: max_abs([l.x, l.y, l.z]) + frame.ecef0_scale,
            v: sent.velocity_m_s,
            a: if algorithm.accelerates() {
                sent.acceleration_m_s2
            } else {
                [0.0; 3]
            },
            w: if algorithm.rotates() {
                sent.angular_velocity_rad_s
            } else {
                [0.0; 3]
            },
            p: rows(&c),
            prev_time: prev.time_s,
            stale: false,
            pending: 0,
        }
    }

    /// Whether the aircraft of this copy with this rough frame is certainly
    /// quiet: straight-line arithmetic, no transcendental function.
    ///
    /// The orientation bound: `C_ecef←ned` is orthonormal, so the rough
    /// ECEF matrix is within `√3 · tol` of the exact path's in every
    /// element, `N` (its product with `C₀ᵀ`, whose rows have norm 1) within
    /// `3 · tol`, and `tr(Rᵀ N)` (the nine elements of `R` have absolute
    /// values summing to at most `3√3`) within `16 · tol`: the cosine is
    /// within `8 · tol` = 8e-9 of the exact path's, plus rounding and the
    /// series' truncation (below 1e-12 together),
    /// below the margin of 1e-7. The exact path's angle is then below the
    /// threshold by at least `9e-8` in cosine, far more than its `atan2`'s
    /// rounding, so it finds no orientation error.
    ///
    /// The screen runs [`ScreenLanes::quiet_lanes`], eight aircraft at a time; this is
    /// its reference, one aircraft at a time (the test
    /// `the_lanes_screen_is_the_scalar_screen`).
    #[allow(clippy::similar_names, clippy::many_single_char_names)]
    #[cfg(test)]
    pub(crate) fn quiet(&self, r: &Rough, frame: &Frame) -> bool {
        let s = self;
        // Time: the exact path's operations, the exact path's comparisons.
        let t = r.time_s;
        let elapsed = t - s.sent_time;
        let frame_s = t - s.prev_time;
        let time_ok = (elapsed >= 0.0) & (elapsed < frame.heartbeat_s) & (frame_s >= MIN_FRAME_S);

        // Finite and slow: everything the exact path would place is finite
        // (an infinity or NaN anywhere makes the sum's product with 0 NaN),
        // and its rates would be made lazily.
        let b = &r.body_to_ned;
        let p = &r.position_m;
        let v = &r.velocity_mps;
        let finite =
            (b[0] + b[1] + b[2] + b[3] + b[4] + b[5] + b[6] + b[7] + b[8] + p.x + p.y + p.z) * 0.0
                == 0.0;
        let state_ok = finite & (max_abs([v.x, v.y, v.z]) < SLOW_M_S);

        // Position: the extrapolated location less the true one, both
        // relative to the origin's ECEF position (ENU = (−y, x, z)).
        let m = &frame.enu_to_ecef;
        let (ex, ey, ez) = (-p.y, p.x, p.z);
        let rx = m[0] * ex + m[1] * ey + m[2] * ez;
        let ry = m[3] * ex + m[4] * ey + m[5] * ez;
        let rz = m[6] * ex + m[7] * ey + m[8] * ez;
        let half_e2 = 0.5 * elapsed * elapsed;
        let (v, a) = (s.v.map(f64::from), s.a.map(f64::from));
        let dx = s.sent_rel[0] + v[0] * elapsed + a[0] * half_e2 - rx;
        let dy = s.sent_rel[1] + v[1] * elapsed + a[1] * half_e2 - ry;
        let dz = s.sent_rel[2] + v[2] * elapsed + a[2] * half_e2 - rz;
        let scale =
            s.sent_scale + max_abs(v) * elapsed + max_abs(a) * half_e2 + max_abs([rx, ry, rz]);
        let limit = frame.position_m - (1e-6 + 1e-13 * scale);
        let position_ok = (limit > 0.0) & (dx * dx + dy * dy + dz * dz < limit * limit);

        // Orientation: the cosine of the error angle (N = P · B, ω = w Δt).
        let (tt, cos) = s.orientation_cos(b, elapsed);
        let orientation_ok = (tt <= MAX_TURN_SQ) & (cos > frame.cos_min);

        s.screenable & time_ok & state_ok & position_ok & orientation_ok
    }

    /// The cosine of the angle between the receivers' orientation of the
    /// last PDU turned by its angular velocity over `elapsed` seconds and
    /// the orientation whose body-to-NED matrix (model frame) is `b`, and the
    /// square of that turn, `θ²` (rad²): `N = P · B`, `ω = w Δt`,
    /// `cos = (tr(Rᵀ N) − 1)/2` with `R = I + A [ω]× + B' [ω]×²` and the
    /// series for `A` and `B'`. For `θ² ≤ 0.25` and `b` exact it is the
    /// exact path's cosine within rounding and the series' truncation
    /// (below 1e-12 together; tested).
    #[allow(clippy::similar_names, clippy::many_single_char_names)]
    #[cfg(test)]
    fn orientation_cos(&self, b: &Matrix3<f64>, elapsed: f64) -> (f64, f64) {
        let q = &self.p;
        let n = |i: usize, j: usize| {
            q[3 * i] * b[(0, j)] + q[3 * i + 1] * b[(1, j)] + q[3 * i + 2] * b[(2, j)]
        };
        let (n00, n01, n02) = (n(0, 0), n(0, 1), n(0, 2));
        let (n10, n11, n12) = (n(1, 0), n(1, 1), n(1, 2));
        let (n20, n21, n22) = (n(2, 0), n(2, 1), n(2, 2));
        let wx = f64::from(self.w[0]) * elapsed;
        let wy = f64::from(self.w[1]) * elapsed;
        let wz = f64::from(self.w[2]) * elapsed;
        let tt = wx * wx + wy * wy + wz * wz;
        // sin θ/θ = Σ (−θ²)ᵏ/(2k+1)!, (1 − cos θ)/θ² = Σ (−θ²)ᵏ/(2k+2)!,
        // k ≤ 5: the first term left out is below 4e-14 for θ² ≤ 0.25, and
        // it multiplies terms below 1 in the cosine.
        let a = estrin(&SIN_SERIES, tt);
        let bb = estrin(&COS_SERIES, tt);
        let tr = n00 + n11 + n22;
        let s1 = wx * (n21 - n12) + wy * (n02 - n20) + wz * (n10 - n01);
        let quad = wx * (n00 * wx + n01 * wy + n02 * wz)
            + wy * (n10 * wx + n11 * wy + n12 * wz)
            + wz * (n20 * wx + n21 * wy + n22 * wz);
        let cos = (tr + a * s1 + bb * (quad - tt * tr) - 1.0) * 0.5;
        (tt, cos)
    }
}

/// Aircraft per block of the screen: its copies of the trackers
/// (`ScreenLanes`) and the rough frames it reads ([`RoughLanes`]) are kept
/// eight aircraft to a block, field by field, so that it screens eight
/// aircraft per instruction (one AVX-512 register of `f64`s).
pub const ROUGH_LANES: usize = 8;

const L: usize = ROUGH_LANES;

/// The [`Rough`] frames of up to [`ROUGH_LANES`] consecutive aircraft, field
/// by field (structure of arrays): lane `k` of every field is aircraft
/// `k`'s, and `ok[k]` says whether it has one (`false`: that aircraft takes
/// the exact path). What a model's rough frames fill for the screen
/// ([`crate::ScreenedPiece::publish_lanes`]) without making a [`Rough`] per
/// aircraft; each lane's numbers are bound as a [`Rough`]'s are (time,
/// position and velocity the view's bits, the body-to-NED matrix within
/// [`ROUGH_TOLERANCE`] of the view's). The values of a lane that is not `ok`
/// are never read for a decision.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RoughLanes {
    /// Whether lane `k` holds an aircraft's rough frame.
    pub ok: [bool; ROUGH_LANES],
    /// Simulation time, seconds (the view's bits).
    pub time_s: [f64; ROUGH_LANES],
    /// Position in the model frame, metres, component by component (x, y,
    /// z; the view's bits).
    pub position_m: [[f64; ROUGH_LANES]; 3],
    /// Velocity in the model frame, m/s, component by component (the
    /// view's bits).
    pub velocity_mps: [[f64; ROUGH_LANES]; 3],
    /// Body-to-NED rotation in the model frame, element `(i, j)` at
    /// `3 i + j` (row by row), within [`ROUGH_TOLERANCE`].
    pub body_to_ned: [[f64; ROUGH_LANES]; 9],
}

impl RoughLanes {
    /// Puts `rough` in lane `lane` (`None`: no rough frame there).
    ///
    /// # Panics
    /// When `lane` is not below [`ROUGH_LANES`].
    pub fn set(&mut self, lane: usize, rough: Option<&Rough>) {
        let Some(r) = rough else {
            self.ok[lane] = false;
            return;
        };
        self.ok[lane] = true;
        self.time_s[lane] = r.time_s;
        for c in 0..3 {
            self.position_m[c][lane] = r.position_m[c];
            self.velocity_mps[c][lane] = r.velocity_mps[c];
        }
        for (e, b) in self.body_to_ned.iter_mut().enumerate() {
            b[lane] = r.body_to_ned[(e / 3, e % 3)];
        }
    }

    /// The rough frame in lane `lane`, `None` when it has none.
    ///
    /// # Panics
    /// When `lane` is not below [`ROUGH_LANES`].
    #[must_use]
    pub fn get(&self, lane: usize) -> Option<Rough> {
        self.ok[lane].then(|| Rough {
            time_s: self.time_s[lane],
            position_m: nalgebra::Vector3::from_fn(|c, _| self.position_m[c][lane]),
            velocity_mps: nalgebra::Vector3::from_fn(|c, _| self.velocity_mps[c][lane]),
            body_to_ned: Matrix3::from_fn(|i, j| self.body_to_ned[3 * i + j][lane]),
        })
    }
}

/// What makes the rough frames of a piece's aircraft lane by lane for
/// [`crate::ScreenedPiece::publish_lanes`]: `rough_lanes(first, states,
/// out)` fills `out`'s lanes `k < states.len()` with the rough frame of
/// aircraft `first + k` whose input is `states[k]` (`out.ok[k]` false where
/// it has none), for at most [`ROUGH_LANES`] inputs, `out` coming with every
/// `ok` false. Any `FnMut(usize, &[Option<S>], &mut RoughLanes)` is one; a
/// type of one's own whose method is `#[inline(always)]` is certainly
/// compiled into the screen's loop, with its instruction set (a closure or
/// a function passed by name may be called out of line, in the baseline
/// instruction set).
pub trait RoughFrames<S> {
    /// Fills `out` for aircraft `first..first + states.len()`.
    fn rough_lanes(&mut self, first: usize, states: &[Option<S>], out: &mut RoughLanes);
}

impl<S, F: FnMut(usize, &[Option<S>], &mut RoughLanes)> RoughFrames<S> for F {
    #[inline(always)]
    fn rough_lanes(&mut self, first: usize, states: &[Option<S>], out: &mut RoughLanes) {
        self(first, states, out);
    }
}

/// The screen's copies ([`ScreenRef`]) of [`ROUGH_LANES`] trackers, field by
/// field: lane `k` of every field is the `k`th aircraft's.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ScreenLanes {
    screenable: [bool; L],
    sent_time: [f64; L],
    sent_rel: [[f64; L]; 3],
    sent_scale: [f64; L],
    v: [[f32; L]; 3],
    a: [[f32; L]; 3],
    w: [[f32; L]; 3],
    p: [[f64; L]; 9],
    prev_time: [f64; L],
    pub(crate) stale: [bool; L],
    pub(crate) pending: [u64; L],
}

impl ScreenLanes {
    /// Lane `k`'s copy.
    pub(crate) fn get(&self, k: usize) -> ScreenRef {
        ScreenRef {
            screenable: self.screenable[k],
            sent_time: self.sent_time[k],
            sent_rel: [
                self.sent_rel[0][k],
                self.sent_rel[1][k],
                self.sent_rel[2][k],
            ],
            sent_scale: self.sent_scale[k],
            v: [self.v[0][k], self.v[1][k], self.v[2][k]],
            a: [self.a[0][k], self.a[1][k], self.a[2][k]],
            w: [self.w[0][k], self.w[1][k], self.w[2][k]],
            p: core::array::from_fn(|e| self.p[e][k]),
            prev_time: self.prev_time[k],
            stale: self.stale[k],
            pending: self.pending[k],
        }
    }

    /// Lane `k` becomes `r`.
    pub(crate) fn set(&mut self, k: usize, r: &ScreenRef) {
        self.screenable[k] = r.screenable;
        self.sent_time[k] = r.sent_time;
        self.sent_scale[k] = r.sent_scale;
        for c in 0..3 {
            self.sent_rel[c][k] = r.sent_rel[c];
            self.v[c][k] = r.v[c];
            self.a[c][k] = r.a[c];
            self.w[c][k] = r.w[c];
        }
        for (e, p) in self.p.iter_mut().enumerate() {
            p[k] = r.p[e];
        }
        self.prev_time[k] = r.prev_time;
        self.stale[k] = r.stale;
        self.pending[k] = r.pending;
    }

    /// Which lanes are certainly quiet with these rough frames (a lane
    /// without one, `rough.ok[k]` false, is not): `ScreenRef::quiet`'s
    /// operations and comparisons lane by lane, in the same order (so the
    /// same bits and decisions; the test
    /// `the_lanes_screen_is_the_scalar_screen`), written as one loop over
    /// the lanes with no branch, which the compiler puts in vector
    /// registers. Always inlined, so that it is compiled with the
    /// instruction set of pulp's dispatch around it.
    // The lane index reads a dozen arrays at once: a range loop says so.
    #[allow(
        clippy::similar_names,
        clippy::many_single_char_names,
        clippy::needless_range_loop
    )]
    #[inline(always)]
    pub(crate) fn quiet_lanes(&self, r: &RoughLanes, frame: &Frame) -> [bool; L] {
        let s = self;
        let m = &frame.enu_to_ecef;
        let mut out = [false; L];
        for k in 0..L {
            // Time: the exact path's operations, the exact path's comparisons.
            let t = r.time_s[k];
            let elapsed = t - s.sent_time[k];
            let frame_s = t - s.prev_time[k];
            let time_ok =
                (elapsed >= 0.0) & (elapsed < frame.heartbeat_s) & (frame_s >= MIN_FRAME_S);

            // Finite and slow (as `quiet`).
            let b: [f64; 9] = core::array::from_fn(|e| r.body_to_ned[e][k]);
            let (px, py, pz) = (r.position_m[0][k], r.position_m[1][k], r.position_m[2][k]);
            let (vx, vy, vz) = (
                r.velocity_mps[0][k],
                r.velocity_mps[1][k],
                r.velocity_mps[2][k],
            );
            let finite =
                (b[0] + b[1] + b[2] + b[3] + b[4] + b[5] + b[6] + b[7] + b[8] + px + py + pz) * 0.0
                    == 0.0;
            let state_ok = finite & (max_abs([vx, vy, vz]) < SLOW_M_S);

            // Position (as `quiet`; ENU = (−y, x, z)).
            let (ex, ey, ez) = (-py, px, pz);
            let rx = m[0] * ex + m[1] * ey + m[2] * ez;
            let ry = m[3] * ex + m[4] * ey + m[5] * ez;
            let rz = m[6] * ex + m[7] * ey + m[8] * ez;
            let half_e2 = 0.5 * elapsed * elapsed;
            let v = [
                f64::from(s.v[0][k]),
                f64::from(s.v[1][k]),
                f64::from(s.v[2][k]),
            ];
            let a = [
                f64::from(s.a[0][k]),
                f64::from(s.a[1][k]),
                f64::from(s.a[2][k]),
            ];
            let dx = s.sent_rel[0][k] + v[0] * elapsed + a[0] * half_e2 - rx;
            let dy = s.sent_rel[1][k] + v[1] * elapsed + a[1] * half_e2 - ry;
            let dz = s.sent_rel[2][k] + v[2] * elapsed + a[2] * half_e2 - rz;
            let scale = s.sent_scale[k]
                + max_abs(v) * elapsed
                + max_abs(a) * half_e2
                + max_abs([rx, ry, rz]);
            let limit = frame.position_m - (1e-6 + 1e-13 * scale);
            let position_ok = (limit > 0.0) & (dx * dx + dy * dy + dz * dz < limit * limit);

            // Orientation (as `orientation_cos`: N = P · B, ω = w Δt).
            let q: [f64; 9] = core::array::from_fn(|e| s.p[e][k]);
            let n = |i: usize, j: usize| {
                q[3 * i] * b[j] + q[3 * i + 1] * b[3 + j] + q[3 * i + 2] * b[6 + j]
            };
            let (n00, n01, n02) = (n(0, 0), n(0, 1), n(0, 2));
            let (n10, n11, n12) = (n(1, 0), n(1, 1), n(1, 2));
            let (n20, n21, n22) = (n(2, 0), n(2, 1), n(2, 2));
            let wx = f64::from(s.w[0][k]) * elapsed;
            let wy = f64::from(s.w[1][k]) * elapsed;
            let wz = f64::from(s.w[2][k]) * elapsed;
            let tt = wx * wx + wy * wy + wz * wz;
            let sa = estrin(&SIN_SERIES, tt);
            let sb = estrin(&COS_SERIES, tt);
            let tr = n00 + n11 + n22;
            let s1 = wx * (n21 - n12) + wy * (n02 - n20) + wz * (n10 - n01);
            let quad = wx * (n00 * wx + n01 * wy + n02 * wz)
                + wy * (n10 * wx + n11 * wy + n12 * wz)
                + wz * (n20 * wx + n21 * wy + n22 * wz);
            let cos = (tr + sa * s1 + sb * (quad - tt * tr) - 1.0) * 0.5;
            let orientation_ok = (tt <= MAX_TURN_SQ) & (cos > frame.cos_min);

            out[k] = r.ok[k] & s.screenable[k] & time_ok & state_ok & position_ok & orientation_ok;
        }
        out
    }

    /// Takes the frames the screen cleared (lanes where `cleared`) at
    /// times `time_s`: each such lane's previous frame is that time, stale
    /// (the tracker does not have it), and one more quiet frame is pending.
    #[allow(clippy::needless_range_loop)] // one index into four arrays
    #[inline(always)]
    pub(crate) fn cleared(&mut self, cleared: &[bool; L], time_s: &[f64; L]) {
        for k in 0..L {
            let c = cleared[k];
            self.prev_time[k] = if c { time_s[k] } else { self.prev_time[k] };
            self.stale[k] |= c;
            self.pending[k] += u64::from(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dead_reckoning::DrThresholds;
    use crate::frames::{rotation_angle_between, rotation_from_scaled_axis};
    use fdm_core::geodesy::GeodeticOrigin;
    use nalgebra::Vector3;

    /// The screen's cosine of the orientation error against the exact
    /// path's (`C₀ · exp([ω]× Δt)` turned to the truth, the angle by
    /// `rotation_angle_between`), as the module docs promise: within 1e-12
    /// for every turn the screen takes (`θ` up to 0.5 rad), with the exact
    /// body-to-NED matrix. Random last orientations, sent angular
    /// velocities (the wire's `f32`s), times since the PDU and error
    /// rotations up to 10°, at two origins; `θ²` is `|w Δt|²`.
    #[test]
    fn the_orientation_cosine_is_the_exact_paths() {
        let mut unit = crate::tracker::tests::unit_xorshift(0x5EED_0F5C_4EE7_1234);
        let mut worst = 0.0f64;
        for origin in [
            GeodeticOrigin::default(),
            GeodeticOrigin::new(-33.9, 151.2, 40.0).unwrap(),
        ] {
            let placement = Placement::new(origin);
            let ned_to_ecef = *placement.model_ned_to_ecef();
            for _ in 0..20_000 {
                let mut u = [0.0; 12];
                u.iter_mut().for_each(|v| *v = unit());
                let vector = |k: usize, scale: f64| {
                    Vector3::new(u[k] - 0.5, u[k + 1] - 0.5, u[k + 2] - 0.5) * scale
                };
                let c0 = rotation_from_scaled_axis(vector(0, 6.0));
                let elapsed = 2.0 * u[3];
                let turn = 0.5 * u[4];
                #[allow(clippy::cast_possible_truncation)]
                let w = (vector(5, 2.0).normalize() * (turn / elapsed.max(1e-3))).map(|c| c as f32);
                let error = rotation_from_scaled_axis(
                    vector(8, 2.0).normalize() * (10f64.to_radians() * u[11]),
                );
                let extrapolated = c0 * rotation_from_scaled_axis(w.map(f64::from) * elapsed);
                let truth = extrapolated * error;
                let b = ned_to_ecef.transpose() * truth;
                let screen = ScreenRef {
                    p: rows(&(c0.transpose() * ned_to_ecef)),
                    w: w.into(),
                    ..ScreenRef::default()
                };
                let (tt, cos) = screen.orientation_cos(&b, elapsed);
                let wt = w.map(f64::from) * elapsed;
                assert!((tt - wt.norm_squared()).abs() <= 1e-15, "{tt}");
                if tt > MAX_TURN_SQ {
                    continue;
                }
                let exact = rotation_angle_between(&extrapolated, &truth).cos();
                worst = worst.max((cos - exact).abs());
            }
        }
        assert!(worst < 1e-12, "worst {worst:e}");
    }

    /// The screen's lanes ([`ScreenLanes::quiet_lanes`], what the fleet
    /// publisher runs, under pulp's dispatch as there) decide as the scalar
    /// screen ([`ScreenRef::quiet`], the reference) does, lane by lane:
    /// random copies and rough frames around every bound (positions within
    /// twice the threshold of the extrapolation, orientations within twice
    /// the threshold angle, turns around 0.5 rad, times around the
    /// heartbeat, before the last PDU and frames around the shortest), with
    /// NaN, infinities and huge velocities in some lanes and lanes without
    /// a rough frame, at two origins and two sets of thresholds. Both
    /// decisions come out thousands of times.
    #[test]
    fn the_lanes_screen_is_the_scalar_screen() {
        struct Quiet<'a>(&'a ScreenLanes, &'a RoughLanes, &'a Frame);
        impl pulp::WithSimd for Quiet<'_> {
            type Output = [bool; L];
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, _: S) -> [bool; L] {
                self.0.quiet_lanes(self.1, self.2)
            }
        }
        let mut unit = crate::tracker::tests::unit_xorshift(0x0DD_BA11_5EED_4321);
        let (mut quiet, mut loud) = (0, 0);
        for (origin, thresholds) in [
            (GeodeticOrigin::default(), DrThresholds::default()),
            (
                GeodeticOrigin::new(-33.9, 151.2, 40.0).unwrap(),
                DrThresholds {
                    position_m: 0.05,
                    orientation_deg: 0.2,
                    heartbeat_s: 1.0,
                },
            ),
        ] {
            let placement = Placement::new(origin);
            let frame = Frame::new(&placement, Some(thresholds));
            let ned_to_ecef = *placement.model_ned_to_ecef();
            let enu_to_ecef = placement.origin().enu_to_ecef();
            for _ in 0..4_000 {
                let mut refs = ScreenLanes::default();
                let mut rough = RoughLanes::default();
                for k in 0..L {
                    let mut u = [0.0; 24];
                    u.iter_mut().for_each(|v| *v = unit());
                    let vector = |k: usize, scale: f64| {
                        Vector3::new(u[k] - 0.5, u[k + 1] - 0.5, u[k + 2] - 0.5) * scale
                    };
                    let c0 = rotation_from_scaled_axis(vector(0, 6.0));
                    let elapsed = match (u[3] * 8.0) as u32 {
                        0 => thresholds.heartbeat_s - HEARTBEAT_SLACK_S + (u[4] - 0.5) * 1e-9,
                        1 => (u[4] - 0.7) * 1e-3,
                        _ => 6.0 * u[4],
                    };
                    let turn = 0.5 + (u[5] - 0.5) * 0.05;
                    let turn = if u[6] < 0.3 { turn } else { turn * u[6] };
                    #[allow(clippy::cast_possible_truncation)]
                    let w = (vector(7, 2.0).normalize() * (turn / elapsed.abs().max(1e-3)))
                        .map(|c| c as f32);
                    let angle = 2.0 * thresholds.orientation_deg.to_radians() * u[10];
                    let error = rotation_from_scaled_axis(vector(11, 2.0).normalize() * angle);
                    let extrapolated = c0 * rotation_from_scaled_axis(w.map(f64::from) * elapsed);
                    let b = ned_to_ecef.transpose() * extrapolated * error;
                    #[allow(clippy::cast_possible_truncation)]
                    let (v, a) = (
                        vector(14, 200.0).map(|c| c as f32),
                        vector(17, 4.0).map(|c| c as f32),
                    );
                    let sent_rel = vector(20, 2e4);
                    let offset = vector(0, 1.0).normalize() * (2.0 * thresholds.position_m * u[23]);
                    let rel = sent_rel
                        + v.map(f64::from) * elapsed
                        + a.map(f64::from) * (0.5 * elapsed * elapsed)
                        + offset;
                    let enu = enu_to_ecef.transpose() * rel;
                    let mut position = Vector3::new(enu.y, -enu.x, enu.z);
                    let mut velocity = vector(3, 300.0);
                    let time = 1000.0 + u[13] * 10.0;
                    let prev = match (u[12] * 6.0) as u32 {
                        0 => time - MIN_FRAME_S,
                        1 => time - MIN_FRAME_S * 0.999,
                        _ => time - 1.0 / 30.0,
                    };
                    match k {
                        1 if u[9] < 0.2 => position.x = f64::NAN,
                        2 if u[9] < 0.2 => velocity.y = f64::INFINITY,
                        3 if u[9] < 0.2 => velocity.z = -2e149,
                        _ => {}
                    }
                    let screen = ScreenRef {
                        screenable: u[2] > 0.05,
                        sent_time: time - elapsed,
                        sent_rel: sent_rel.into(),
                        sent_scale: 1e7 * u[1],
                        v: v.into(),
                        a: a.into(),
                        w: w.into(),
                        p: rows(&(c0.transpose() * ned_to_ecef)),
                        prev_time: prev,
                        stale: false,
                        pending: 0,
                    };
                    let r = Rough {
                        time_s: time,
                        position_m: position,
                        velocity_mps: velocity,
                        body_to_ned: b,
                    };
                    refs.set(k, &screen);
                    rough.set(k, (u[8] > 0.05).then_some(&r));
                }
                let got = pulp::Arch::new().dispatch(Quiet(&refs, &rough, &frame));
                for (k, got) in got.into_iter().enumerate() {
                    let want = rough.get(k).is_some_and(|r| refs.get(k).quiet(&r, &frame));
                    assert_eq!(got, want, "lane {k}: {:?} {:?}", refs.get(k), rough.get(k));
                    if want {
                        quiet += 1;
                    } else {
                        loud += 1;
                    }
                }
            }
        }
        assert!(quiet > 3_000 && loud > 3_000, "{quiet} quiet, {loud} not");
    }
}
