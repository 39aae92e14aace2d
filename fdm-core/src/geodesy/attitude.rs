//! Attitude (roll, pitch, heading) in FlightGear's conventions, and the two
//! models' conversions to it.
//!
//! FlightGear's `phi`, `theta`, `psi` are the aerospace Z-Y-X Euler angles of
//! the body axes (x forward, y right wing, z down) relative to the local
//! north-east-down frame: heading `psi` about down (clockwise from true north
//! seen from above), then pitch `theta` about the new right axis (nose up
//! positive), then roll `phi` about the forward axis (right wing down
//! positive). The body-to-NED rotation matrix is
//! `C = Rz(heading) · Ry(pitch) · Rx(roll)`.

use nalgebra::{Matrix3, Vector3};

use crate::math::{atan2, hypot, sin_cos};

/// Aircraft attitude as FlightGear displays it, in degrees.
///
/// Relative to the north-east-down frame the angles refer to: for the
/// functions in this module that is the model's own earth frame (north = +x,
/// the tangent plane at the origin); [`GeodeticOrigin::attitude_at`] re-expresses it
/// relative to true north and the local horizontal at the aircraft.
///
/// [`GeodeticOrigin::attitude_at`]: super::GeodeticOrigin::attitude_at
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Attitude {
    /// Bank angle, degrees, right wing down positive, in `[-180, 180]`.
    pub roll_deg: f64,
    /// Pitch angle of the nose above the horizontal, degrees, nose up
    /// positive, in `[-90, 90]`.
    pub pitch_deg: f64,
    /// Heading of the nose, degrees clockwise from north, in `[0, 360)`.
    pub heading_deg: f64,
}

impl Attitude {
    /// The body-to-NED rotation matrix `Rz(heading) · Ry(pitch) · Rx(roll)`:
    /// its columns are the body's forward, right-wing and down axes in
    /// north-east-down components.
    #[must_use]
    pub fn body_to_ned(&self) -> Matrix3<f64> {
        rot_z(self.heading_deg.to_radians())
            * rot_y(self.pitch_deg.to_radians())
            * rot_x(self.roll_deg.to_radians())
    }

    /// The Euler angles of a body-to-NED rotation matrix (the inverse of
    /// [`Attitude::body_to_ned`] for pitch in `(-90, 90)`, outside the
    /// gimbal-lock band below).
    ///
    /// At pitch ±90° (gimbal lock, nose straight up or down) roll and heading
    /// are not separable: roll is reported as 0 and the whole rotation about
    /// the vertical goes into the heading. The same goes for a nose within
    /// 1e-12 rad (6e-11°) of vertical, i.e. `cos(pitch) = hypot(c[(0, 0)],
    /// c[(1, 0)])` at most 1e-12: the entries roll and heading would be taken
    /// from are that small too, and their rounding errors would show in the
    /// angles. NaN entries give NaN angles; never panics.
    #[must_use]
    pub fn from_body_to_ned(c: &Matrix3<f64>) -> Self {
        let cos_pitch = hypot(c[(0, 0)], c[(1, 0)]);
        let pitch = atan2(-c[(2, 0)], cos_pitch);
        let (roll, heading) = if cos_pitch > 1e-12 {
            (atan2(c[(2, 1)], c[(2, 2)]), atan2(c[(1, 0)], c[(0, 0)]))
        } else {
            (0.0, atan2(-c[(0, 1)], c[(1, 1)]))
        };
        Self {
            roll_deg: roll.to_degrees(),
            pitch_deg: pitch.to_degrees(),
            heading_deg: normalize_heading_deg(heading.to_degrees()),
        }
    }
}

/// Maps any angle in degrees into `[0, 360)` (a compass heading). NaN and
/// infinities give NaN. `-0.0` and tiny negative angles that would round to
/// 360 give `0.0`.
#[must_use]
pub fn normalize_heading_deg(angle_deg: f64) -> f64 {
    crate::units::wrap_degrees_360(angle_deg)
}

/// Velocity (or any vector) from a model's earth frame (x north, y west,
/// z up) to north-east-down components: `(x, -y, -z)`. Units pass through
/// (FlightGear's `v_north`/`v_east`/`v_down` want ft/s: divide Palmer's m/s by
/// [`METRES_PER_FOOT`](super::METRES_PER_FOOT); Bourg's are already ft/s).
///
/// These are components along the model's axes, i.e. relative to north at the
/// origin; [`GeodeticOrigin::local_ned`](super::GeodeticOrigin::local_ned)
/// rotates them into the local NED frame at the aircraft.
#[must_use]
pub fn ned_from_model(v: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, -v.y, -v.z)
}

/// Compass direction of travel over the ground, degrees clockwise from the
/// model's north (+x) in `[0, 360)`, from a model-frame velocity (x north,
/// y west, z up; any unit): `atan2(-vy, vx)` mapped to `[0, 360)`.
///
/// With no horizontal speed the direction is undefined; like Palmer's model
/// (which then uses `cos T = 1, sin T = 0`), this returns 0 (north).
#[must_use]
pub fn ground_track_deg(velocity: Vector3<f64>) -> f64 {
    if velocity.x == 0.0 && velocity.y == 0.0 {
        0.0
    } else {
        normalize_heading_deg(atan2(-velocity.y, velocity.x).to_degrees())
    }
}

/// FlightGear attitude of Palmer's point-mass Cessna, relative to the model's
/// earth frame.
///
/// * `velocity_m_s`: `(vx, vy, vz)` in the model frame (x north, y west, z up),
///   m/s (any unit works; only the direction matters).
/// * `alpha_deg`: the commanded angle of attack, degrees.
/// * `bank_deg`: the bank angle, degrees, positive = right wing down, turning
///   towards -y (east when flying north), as in the model's force equations.
///
/// The point-mass model has no body axes: its lift is perpendicular to the
/// velocity, tilted by the bank angle about the velocity, and its thrust acts
/// along the velocity. What FlightGear should draw is the airframe that would
/// fly that way: no sideslip, nose `alpha` above the velocity vector in the
/// plane of symmetry (the plane of velocity and lift). So the body-to-NED
/// rotation is the wind-axis rotation followed by alpha about the wing axis:
///
/// `C = Rz(track) · Ry(climb) · Rx(bank) · Ry(alpha)`
///
/// with `track = atan2(-vy, vx)` (compass direction of travel) and
/// `climb = atan2(vz, hypot(vx, vy))` (flight-path angle), and the reported
/// angles are the Z-Y-X Euler angles of `C`. Consequences:
///
/// * Wings level (`bank = 0`): exactly `roll = 0`, `pitch = climb + alpha`,
///   `heading = track`. This is the attitude a pilot sees: in level cruise at
///   5° alpha the nose is 5° up.
/// * Banked: pitch, roll and heading differ slightly from `climb + alpha`,
///   `bank`, `track`, because alpha now tilts the nose partly into the turn
///   (for alpha 10°, bank 20°, level: heading = track + 3.45°,
///   pitch = 9.39°, roll = 20.28°).
///
/// At rest (zero velocity) the model itself uses `track = 0` (north) and
/// `climb = 0`; so does this function. Non-finite input gives NaN output.
///
/// The result is relative to the model's axes; what FlightGear should get at
/// the aircraft's position is
/// [`GeodeticOrigin::attitude_at`](super::GeodeticOrigin::attitude_at)`(position, result)`.
#[must_use]
pub fn palmer_attitude(velocity_m_s: Vector3<f64>, alpha_deg: f64, bank_deg: f64) -> Attitude {
    let (vx, vy, vz) = (velocity_m_s.x, velocity_m_s.y, velocity_m_s.z);
    let vh = hypot(vx, vy);
    // Same degenerate-case conventions as the model's rhs (step 10 of docs/palmer-model.md).
    let track = if vh == 0.0 { 0.0 } else { atan2(-vy, vx) };
    let climb = if vh == 0.0 && vz == 0.0 {
        0.0
    } else {
        atan2(vz, vh)
    };
    let c =
        rot_z(track) * rot_y(climb) * rot_x(bank_deg.to_radians()) * rot_y(alpha_deg.to_radians());
    Attitude::from_body_to_ned(&c)
}

/// FlightGear attitude of Bourg's 6-DoF aircraft from the model's Euler angles
/// (`euler_angles` of the model, degrees: x roll, y pitch, z yaw), relative to
/// the model's earth frame.
///
/// Returns `roll = euler.x`, `pitch = -euler.y`, `heading = (-euler.z) mod 360`
/// (in `[0, 360)`), each widened exactly from f32.
///
/// Why, from the model's own definitions: the earth frame is x north, y west,
/// z up and the body frame x forward, y left, z up. `MakeEulerAnglesFromQ`
/// decomposes the body-to-earth rotation as `R = Rz(yaw) · Ry(pitch) · Rx(roll)`
/// (roll = atan2(r32, r33), pitch = asin(-r31), yaw = atan2(r21, r11)).
/// FlightGear's frames are the same axes with y and z reversed:
/// NED = T · NWU and FRD = T · FLU with `T = diag(1, -1, -1)`, a 180° rotation
/// about x. So FlightGear's matrix is `T R T = Rz(-yaw) · Ry(-pitch) · Rx(roll)`
/// (conjugating by `T` keeps rotations about x and reverses those about y and
/// z), exactly, for all angles. Checking each sign physically:
///
/// * roll: `Rx(+roll)` turns the left wing (+y) towards +z (up), so the right
///   wing goes down: the model's positive roll is FlightGear's positive roll.
/// * pitch: `Ry(+pitch)` turns the nose (+x) towards -z (down): the model's
///   pitch is nose-down positive, so FlightGear's is `-euler.y`.
/// * yaw: `Rz(+yaw)` turns the nose from north (+x) towards +y (west), i.e.
///   anticlockwise seen from above; a compass heading is `-euler.z`.
///
/// In the model's gimbal-lock branch (|pitch| = 90°, roll forced to 0) the
/// same mapping still holds. NaN input gives NaN output.
///
/// The result is relative to the model's axes; what FlightGear should get at
/// the aircraft's position is
/// [`GeodeticOrigin::attitude_at`](super::GeodeticOrigin::attitude_at)`(position_m, result)`
/// (Bourg's position in feet times [`METRES_PER_FOOT`](super::METRES_PER_FOOT)).
#[must_use]
pub fn bourg_attitude(euler_deg: Vector3<f32>) -> Attitude {
    Attitude {
        roll_deg: f64::from(euler_deg.x),
        pitch_deg: -f64::from(euler_deg.y),
        heading_deg: normalize_heading_deg(-f64::from(euler_deg.z)),
    }
}

/// Rotation about x by `a` radians (right-handed).
pub(super) fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = sin_cos(a);
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// Rotation about y by `a` radians (right-handed).
pub(super) fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = sin_cos(a);
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation about z by `a` radians (right-handed).
pub(super) fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = sin_cos(a);
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}
