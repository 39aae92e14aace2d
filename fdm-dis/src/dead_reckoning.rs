//! Sender-side dead reckoning: decide when an aircraft's Entity State PDU
//! must go out.
//!
//! Every receiver extrapolates the last PDU it got with the announced
//! dead-reckoning model. The sender runs the same extrapolation on what it
//! last sent ([`WireState`], the wire's rounded values) and compares it with
//! the true state each frame. It sends when
//!
//! 1. nothing has been sent yet, or the clock went backwards;
//! 2. the extrapolated position is more than `position_m` (default 1 m) from
//!    the true one;
//! 3. the extrapolated orientation differs from the true one by more than
//!    `orientation_deg` (default 3°), measured as the angle of the single
//!    rotation between the two;
//! 4. `heartbeat_s` (default 5 s) has passed since the last PDU, so that
//!    receivers that joined late, or lost a datagram, catch up and do not
//!    time the entity out.
//!
//! Otherwise receivers' pictures are within the thresholds, and nothing is
//! sent.

use nalgebra::{Matrix3, Vector3};

use crate::entity::{DrAlgorithm, WireState};
use crate::error::DisOutputError;
use crate::frames::{
    rotation_angle_between, rotation_from_scaled_axis, rotation_sin_cos, EcefState,
};

/// When to send, configurable per entity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrThresholds {
    /// Largest tolerated distance between extrapolated and true position,
    /// metres (default 1).
    pub position_m: f64,
    /// Largest tolerated rotation between extrapolated and true orientation,
    /// degrees (default 3).
    pub orientation_deg: f64,
    /// Longest time between two PDUs of one entity, seconds (default 5).
    pub heartbeat_s: f64,
}

impl Default for DrThresholds {
    fn default() -> Self {
        Self {
            position_m: 1.0,
            orientation_deg: 3.0,
            heartbeat_s: 5.0,
        }
    }
}

impl DrThresholds {
    /// Checks that every threshold is positive and finite.
    ///
    /// # Errors
    /// [`DisOutputError::BadThreshold`] naming the field.
    pub fn validate(&self) -> Result<(), DisOutputError> {
        for (name, v) in [
            ("position_m", self.position_m),
            ("orientation_deg", self.orientation_deg),
            ("heartbeat_s", self.heartbeat_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(DisOutputError::BadThreshold(name));
            }
        }
        Ok(())
    }
}

/// Why a PDU is due.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SendReason {
    /// Nothing was sent for this entity yet.
    First,
    /// The time went backwards (a restarted simulation): start afresh.
    ClockReset,
    /// The extrapolated position is off by more than the threshold.
    PositionError,
    /// The extrapolated orientation is off by more than the threshold.
    OrientationError,
    /// The heartbeat interval has passed.
    Heartbeat,
}

/// Slack on the heartbeat comparison, seconds, so that a time accumulated
/// from steps that are not exact in binary (250 × 0.02 s is
/// 4.999 999 999 999 9…) does not push the heartbeat one frame late.
pub(crate) const HEARTBEAT_SLACK_S: f64 = 1e-9;

/// Where a dead-reckoning model puts the entity `dt_s` seconds after `sent`:
/// ECEF location (m) and body-to-ECEF orientation matrix.
///
/// * position: `P₀ + V₀ Δt` (P models) or `P₀ + V₀ Δt + ½ A₀ Δt²`
///   (V models);
/// * orientation: held (F models), or `C₀ · exp([ω]× Δt)` (R models): the
///   body turns at its sent body-axis angular velocity ω, which is the
///   rotation the standard's dead-reckoning matrix describes.
#[must_use]
pub fn extrapolate(
    algorithm: DrAlgorithm,
    sent: &WireState,
    dt_s: f64,
) -> (Vector3<f64>, Matrix3<f64>) {
    extrapolate_from(algorithm, sent, &sent.orientation().body_to_ecef(), dt_s)
}

/// [`extrapolate`] with `sent`'s orientation matrix `c0` given.
fn extrapolate_from(
    algorithm: DrAlgorithm,
    sent: &WireState,
    c0: &Matrix3<f64>,
    dt_s: f64,
) -> (Vector3<f64>, Matrix3<f64>) {
    let c0 = *c0;
    let v = Vector3::from(sent.velocity_m_s.map(f64::from));
    let a = Vector3::from(sent.acceleration_m_s2.map(f64::from));
    let mut position = sent.location_m + v * dt_s;
    if algorithm.accelerates() {
        position += a * (0.5 * dt_s * dt_s);
    }
    let orientation = if algorithm.rotates() {
        let w = Vector3::from(sent.angular_velocity_rad_s.map(f64::from));
        c0 * rotation_from_scaled_axis(w * dt_s)
    } else {
        c0
    };
    (position, orientation)
}

/// The errors of the receivers' picture at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrError {
    /// Seconds since the last PDU.
    pub elapsed_s: f64,
    /// Distance between extrapolated and true position, metres.
    pub position_m: f64,
    /// Rotation between extrapolated and true orientation, degrees.
    pub orientation_deg: f64,
}

/// One entity's sender-side dead-reckoning model.
#[derive(Debug, Clone, PartialEq)]
pub struct DeadReckoner {
    algorithm: DrAlgorithm,
    thresholds: DrThresholds,
    last_sent: Option<WireState>,
    /// `last_sent`'s orientation as a matrix, made once per PDU rather than
    /// once per frame (the same `sin_cos` calls, so the same bits).
    last_sent_body_to_ecef: Matrix3<f64>,
    /// See [`OrientationScreen`].
    screen: OrientationScreen,
}

/// A cheap test that an orientation error is certainly within the threshold,
/// so that the frames where nothing is due skip `atan2`.
///
/// The error angle is `atan2(s, c)` with `s ≥ 0` the sine and `c` the cosine
/// part of the rotation between the two orientations
/// ([`rotation_angle_between`]). For `c > 0` that is `atan(s / c)`, which is
/// increasing; so `s < c · tan(threshold) · (1 - 1e-9)` puts the angle below
/// the threshold by a relative margin of about 1e-9 / (1 + tan²), far more
/// than the few ulps of rounding in `atan2`, `to_degrees` and `tan`, and the
/// comparison [`DeadReckoner::check`] makes with the full angle gives
/// "not above the threshold" too. Anything else (`c ≤ 0`, NaN, a sine
/// near the bound) takes the full computation, so the decision is always the
/// one the full angle gives. Only thresholds up to 80° are screened (beyond,
/// `tan` grows so fast that the margin would be too thin to argue about).
#[derive(Debug, Clone, Copy, PartialEq)]
struct OrientationScreen {
    /// `tan(threshold) · (1 - 1e-9)`, or 0 to screen nothing.
    sine_per_cosine: f64,
}

impl OrientationScreen {
    fn new(orientation_deg: f64) -> Self {
        let sine_per_cosine = if orientation_deg <= 80.0 {
            fdm_core::math::tan(orientation_deg.to_radians()) * (1.0 - 1e-9)
        } else {
            0.0
        };
        Self { sine_per_cosine }
    }

    /// Whether the rotation taking `a` to `b` is certainly within the threshold.
    fn certainly_within(self, a: &Matrix3<f64>, b: &Matrix3<f64>) -> bool {
        let (sin, cos) = rotation_sin_cos(a, b);
        cos > 0.0 && sin < cos * self.sine_per_cosine
    }
}

impl DeadReckoner {
    /// A model that has sent nothing yet.
    ///
    /// # Errors
    /// As [`DrThresholds::validate`].
    pub fn new(algorithm: DrAlgorithm, thresholds: DrThresholds) -> Result<Self, DisOutputError> {
        thresholds.validate()?;
        Ok(Self {
            algorithm,
            thresholds,
            last_sent: None,
            last_sent_body_to_ecef: Matrix3::identity(),
            screen: OrientationScreen::new(thresholds.orientation_deg),
        })
    }

    /// The model in use.
    #[must_use]
    pub fn algorithm(&self) -> DrAlgorithm {
        self.algorithm
    }

    /// The thresholds in use.
    #[must_use]
    pub fn thresholds(&self) -> DrThresholds {
        self.thresholds
    }

    /// What receivers last got, if anything.
    #[must_use]
    pub fn last_sent(&self) -> Option<&WireState> {
        self.last_sent.as_ref()
    }

    /// How far the receivers' extrapolation is from `truth` now (`None`
    /// before the first PDU).
    #[must_use]
    pub fn error(&self, truth: &EcefState) -> Option<DrError> {
        let sent = self.last_sent.as_ref()?;
        let elapsed_s = truth.time_s - sent.time_s;
        let (position, orientation) = self.extrapolate_sent(sent, elapsed_s);
        Some(DrError {
            elapsed_s,
            position_m: (position - truth.location_m).norm(),
            orientation_deg: rotation_angle_between(&orientation, &truth.body_to_ecef).to_degrees(),
        })
    }

    /// [`extrapolate`] of `sent` (the last PDU), with its orientation matrix
    /// made when it was sent.
    fn extrapolate_sent(&self, sent: &WireState, dt_s: f64) -> (Vector3<f64>, Matrix3<f64>) {
        extrapolate_from(self.algorithm, sent, &self.last_sent_body_to_ecef, dt_s)
    }

    /// Whether a PDU is due for `truth`, and why (the first reason that holds
    /// in the order of [`SendReason`]). Does not change the model: call
    /// [`DeadReckoner::record_sent`] once the PDU is sent.
    #[must_use]
    pub fn check(&self, truth: &EcefState) -> Option<SendReason> {
        self.check_at(truth.time_s, &truth.location_m, &truth.body_to_ecef)
    }

    /// [`DeadReckoner::check`] for the three things it reads of the true
    /// state: its time, ECEF location and body-to-ECEF orientation. The same
    /// decision, bit for bit; a frame where the orientation is certainly
    /// within its threshold skips the `atan2` of the error angle (see
    /// `OrientationScreen`), so a caller that has not yet made the DIS
    /// angles and rates of the state need not make them unless a PDU is due.
    #[must_use]
    pub fn check_at(
        &self,
        time_s: f64,
        location_m: &Vector3<f64>,
        body_to_ecef: &Matrix3<f64>,
    ) -> Option<SendReason> {
        let Some(sent) = self.last_sent.as_ref() else {
            return Some(SendReason::First);
        };
        let elapsed_s = time_s - sent.time_s;
        let (position, orientation) = self.extrapolate_sent(sent, elapsed_s);
        let position_m = (position - location_m).norm();
        let orientation_deg = if self.screen.certainly_within(&orientation, body_to_ecef) {
            // Within the threshold for certain: the exact angle only
            // matters when it is above.
            0.0
        } else {
            rotation_angle_between(&orientation, body_to_ecef).to_degrees()
        };
        let err = DrError {
            elapsed_s,
            position_m,
            orientation_deg,
        };
        let t = &self.thresholds;
        if err.elapsed_s < 0.0 {
            Some(SendReason::ClockReset)
        } else if err.position_m > t.position_m {
            Some(SendReason::PositionError)
        } else if err.orientation_deg > t.orientation_deg {
            Some(SendReason::OrientationError)
        } else if err.elapsed_s >= t.heartbeat_s - HEARTBEAT_SLACK_S {
            Some(SendReason::Heartbeat)
        } else {
            None
        }
    }

    /// `last_sent`'s orientation matrix, as [`DeadReckoner::check_at`]
    /// extrapolates it (the identity before the first PDU).
    pub(crate) fn last_sent_body_to_ecef(&self) -> &Matrix3<f64> {
        &self.last_sent_body_to_ecef
    }

    /// Records that `sent` went out: receivers now extrapolate from it.
    pub fn record_sent(&mut self, sent: WireState) {
        self.last_sent_body_to_ecef = sent.orientation().body_to_ecef();
        self.last_sent = Some(sent);
    }
}

/// The orientation screen of a threshold, for the tracker's tests.
#[cfg(test)]
pub(crate) fn screen_for_tests(
    orientation_deg: f64,
) -> impl Fn(&Matrix3<f64>, &Matrix3<f64>) -> bool {
    let screen = OrientationScreen::new(orientation_deg);
    move |a, b| screen.certainly_within(a, b)
}
