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

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::entity::{DrAlgorithm, WireState};
use crate::error::DisOutputError;
use crate::frames::{rotation_angle_between, EcefState};

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
const HEARTBEAT_SLACK_S: f64 = 1e-9;

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
    let v = Vector3::from(sent.velocity_m_s.map(f64::from));
    let a = Vector3::from(sent.acceleration_m_s2.map(f64::from));
    let mut position = sent.location_m + v * dt_s;
    if algorithm.accelerates() {
        position += a * (0.5 * dt_s * dt_s);
    }
    let c0 = sent.orientation().body_to_ecef();
    let orientation = if algorithm.rotates() {
        let w = Vector3::from(sent.angular_velocity_rad_s.map(f64::from));
        c0 * Rotation3::from_scaled_axis(w * dt_s).into_inner()
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
        let (position, orientation) = extrapolate(self.algorithm, sent, elapsed_s);
        Some(DrError {
            elapsed_s,
            position_m: (position - truth.location_m).norm(),
            orientation_deg: rotation_angle_between(&orientation, &truth.body_to_ecef).to_degrees(),
        })
    }

    /// Whether a PDU is due for `truth`, and why (the first reason that holds
    /// in the order of [`SendReason`]). Does not change the model: call
    /// [`DeadReckoner::record_sent`] once the PDU is sent.
    #[must_use]
    pub fn check(&self, truth: &EcefState) -> Option<SendReason> {
        let Some(err) = self.error(truth) else {
            return Some(SendReason::First);
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

    /// Records that `sent` went out: receivers now extrapolate from it.
    pub fn record_sent(&mut self, sent: WireState) {
        self.last_sent = Some(sent);
    }
}
