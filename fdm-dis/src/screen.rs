//! The fleet publisher's screen ([`crate::FleetPublisher::publish_screened`]):
//! which aircraft certainly have nothing due this frame, decided from a
//! cheap [`Rough`] frame of each and a compact copy of what its tracker last
//! sent ([`ScreenRef`], kept in an array beside the trackers), in
//! straight-line arithmetic with no transcendental function.
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
//!   [`ScreenRef::quiet_lanes`]).
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

    /// Takes a frame the screen cleared at time `time_s`.
    pub(crate) fn cleared(&mut self, time_s: f64) {
        self.prev_time = time_s;
        self.stale = true;
        self.pending += 1;
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
    #[allow(clippy::similar_names, clippy::many_single_char_names)]
    #[inline]
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
    #[inline(always)]
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

#[cfg(test)]
mod tests {
    use super::*;
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
}
