//! The multiplayer orientation field: rotation vector in ECEF from and to
//! geodetic latitude/longitude plus local heading, pitch and roll.
//!
//! Quaternions are `[w, x, y, z]`, multiplied with the Hamilton product, and
//! follow SimGear's formulas term for term (see the docs of
//! [`crate::multiplayer`] for the conventions). Everything is `f64`; degrees become
//! radians as `deg * π / 180` and back as `rad * 180 / π`. The sines, cosines
//! and arc functions are [`fdm_core::math`]'s (pure Rust), not the platform's
//! libm, so the bytes on the wire are the same on every machine.

use core::f64::consts::PI;

use fdm_core::math;

/// Attitude relative to the local horizontal frame (x north, y east,
/// z down), degrees: yaw about z, then pitch about the new y, then roll
/// about the new x.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HorizontalAttitudeDeg {
    /// True heading, degrees clockwise from north. Any value is accepted;
    /// [`attitude_from_ecef_angle_axis`] returns it in `[0, 360)`.
    pub heading_deg: f64,
    /// Pitch, degrees, nose up positive; `[-90, 90]` when read back.
    pub pitch_deg: f64,
    /// Roll (bank), degrees, right wing down positive; `(-180, 180]` when
    /// read back.
    pub roll_deg: f64,
}

type Quat = [f64; 4];

fn deg2rad(deg: f64) -> f64 {
    deg * PI / 180.0
}

fn rad2deg(rad: f64) -> f64 {
    rad * 180.0 / PI
}

/// Hamilton product `a * b`.
fn mul(a: Quat, b: Quat) -> Quat {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

fn conj(q: Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}

/// ECEF → local horizontal (x north, y east, z down): SimGear's
/// `SGQuatd::fromLonLatRad(lon, lat)`, i.e. a turn about z by `lon`
/// followed by a turn about the new y by `-π/2 - lat`.
fn from_lon_lat_rad(lon: f64, lat: f64) -> Quat {
    let zd2 = 0.5 * lon;
    let yd2 = -0.25 * PI - 0.5 * lat;
    let (szd2, czd2) = math::sin_cos(zd2);
    let (syd2, cyd2) = math::sin_cos(yd2);
    [czd2 * cyd2, -szd2 * syd2, czd2 * syd2, szd2 * cyd2]
}

/// Local horizontal → body: SimGear's `SGQuatd::fromYawPitchRoll(z, y, x)`,
/// i.e. `qz(yaw) * qy(pitch) * qx(roll)`.
fn from_yaw_pitch_roll(z: f64, y: f64, x: f64) -> Quat {
    let (szd2, czd2) = math::sin_cos(0.5 * z);
    let (syd2, cyd2) = math::sin_cos(0.5 * y);
    let (sxd2, cxd2) = math::sin_cos(0.5 * x);
    let cxcy = cxd2 * cyd2;
    let cxsy = cxd2 * syd2;
    let sxcy = sxd2 * cyd2;
    let sxsy = sxd2 * syd2;
    [
        czd2 * cxcy + szd2 * sxsy,
        czd2 * sxcy - szd2 * cxsy,
        czd2 * cxsy + szd2 * sxcy,
        szd2 * cxcy - czd2 * sxsy,
    ]
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|c| c * c).sum::<f64>().sqrt()
}

/// SimGear's `getAngleAxis(SGVec3&)`: angle `2·acos(w/|q|)` in `[0, 2π]`,
/// axis the normalised imaginary part, returned multiplied together. A zero
/// quaternion, `w = 1` and `w = -1` (no rotation) give the zero vector.
fn angle_axis(q: Quat) -> [f64; 3] {
    let nrm = norm(&q);
    if nrm <= f64::MIN_POSITIVE {
        return [0.0; 3];
    }
    let r_nrm = 1.0 / nrm;
    let half = math::acos((r_nrm * q[0]).clamp(-1.0, 1.0));
    let s_ang = math::sin(half);
    let axis = if s_ang.abs() <= f64::MIN_POSITIVE {
        [1.0, 0.0, 0.0]
    } else {
        let k = r_nrm / s_ang;
        [k * q[1], k * q[2], k * q[3]]
    };
    let angle = 2.0 * half;
    axis.map(|c| c * angle)
}

/// SimGear's `SGQuatd::fromAngleAxis(const SGVec3&)`.
fn from_angle_axis(v: [f64; 3]) -> Quat {
    let n = norm(&v);
    if n <= f64::MIN_POSITIVE {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let (s, c) = math::sin_cos(0.5 * n);
    let k = s / n;
    [c, k * v[0], k * v[1], k * v[2]]
}

/// SimGear's `getEulerRad`: (yaw in `[0, 2π)`, pitch, roll).
fn euler_rad(q: Quat) -> (f64, f64, f64) {
    let [w, x, y, z] = q;
    let (sqw, sqx, sqy, sqz) = (w * w, x * x, y * y, z * z);
    let tiny = |a: f64, b: f64| a.abs() <= f64::MIN_POSITIVE && b.abs() <= f64::MIN_POSITIVE;

    let num = 2.0 * (y * z + w * x);
    let den = sqw - sqx - sqy + sqz;
    let roll = if tiny(num, den) {
        0.0
    } else {
        math::atan2(num, den)
    };

    let tmp = 2.0 * (x * z - w * y);
    let pitch = if tmp <= -1.0 {
        0.5 * PI
    } else if 1.0 <= tmp {
        -0.5 * PI
    } else {
        -math::asin(tmp)
    };

    let num = 2.0 * (x * y + w * z);
    let den = sqw + sqx - sqy - sqz;
    let yaw = if tiny(num, den) {
        0.0
    } else {
        let psi = math::atan2(num, den);
        if psi < 0.0 {
            psi + 2.0 * PI
        } else {
            psi
        }
    };
    (yaw, pitch, roll)
}

/// The multiplayer orientation field (rotation vector from the ECEF frame to
/// the body frame, radians, in ECEF) for an aircraft at geodetic
/// `latitude_deg`, `longitude_deg` with `attitude` relative to the local
/// horizontal.
///
/// Computed as FlightGear's sender does, in `f64`:
/// `fromLonLatDeg(lon, lat) * fromYawPitchRollDeg(heading, pitch, roll)`,
/// then angle-axis with the angle in `[0, 2π]`. Round to `f32` for the wire
/// (as [`MultiplayerPosition::set_orientation_from_attitude`](super::MultiplayerPosition::set_orientation_from_attitude)
/// does). Non-finite inputs give non-finite output; nothing panics.
///
/// ```
/// use fgnet::{ecef_angle_axis_from_attitude, HorizontalAttitudeDeg};
/// // Level, facing north, at lat 0 lon 0: body x = north = ECEF +z,
/// // body z = down = ECEF -x. That is a -90° turn about ECEF y.
/// let v = ecef_angle_axis_from_attitude(0.0, 0.0, HorizontalAttitudeDeg::default());
/// assert!((v[1] + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// assert!(v[0].abs() < 1e-15 && v[2].abs() < 1e-15);
/// ```
#[must_use]
pub fn ecef_angle_axis_from_attitude(
    latitude_deg: f64,
    longitude_deg: f64,
    attitude: HorizontalAttitudeDeg,
) -> [f64; 3] {
    let ec2hl = from_lon_lat_rad(deg2rad(longitude_deg), deg2rad(latitude_deg));
    let hl2body = from_yaw_pitch_roll(
        deg2rad(attitude.heading_deg),
        deg2rad(attitude.pitch_deg),
        deg2rad(attitude.roll_deg),
    );
    angle_axis(mul(ec2hl, hl2body))
}

/// Inverse of [`ecef_angle_axis_from_attitude`]: heading in `[0, 360)`,
/// pitch in `[-90, 90]`, roll in `(-180, 180]` degrees, from the orientation
/// field and the aircraft's geodetic latitude and longitude.
///
/// This is what FlightGear computes on receive for
/// `orientation/true-heading-deg`, `pitch-deg` and `roll-deg`
/// (`conj(fromLonLat) * fromAngleAxis(v)`, then Euler angles), except that
/// FlightGear does it in `f32` and here it is `f64`. At pitch ±90° heading
/// and roll are not separable; what comes back then is one valid split.
///
/// ```
/// use fgnet::{attitude_from_ecef_angle_axis, ecef_angle_axis_from_attitude, HorizontalAttitudeDeg};
/// let sent = HorizontalAttitudeDeg { heading_deg: 280.0, pitch_deg: 5.0, roll_deg: -20.0 };
/// let v = ecef_angle_axis_from_attitude(37.6, -122.4, sent);
/// let back = attitude_from_ecef_angle_axis(v, 37.6, -122.4);
/// assert!((back.heading_deg - 280.0).abs() < 1e-9);
/// assert!((back.pitch_deg - 5.0).abs() < 1e-9);
/// assert!((back.roll_deg + 20.0).abs() < 1e-9);
/// ```
#[must_use]
pub fn attitude_from_ecef_angle_axis(
    angle_axis_rad: [f64; 3],
    latitude_deg: f64,
    longitude_deg: f64,
) -> HorizontalAttitudeDeg {
    let ec2hl = from_lon_lat_rad(deg2rad(longitude_deg), deg2rad(latitude_deg));
    let hl2body = mul(conj(ec2hl), from_angle_axis(angle_axis_rad));
    let (yaw, pitch, roll) = euler_rad(hl2body);
    // A yaw a hair below 0 becomes exactly 2π when SimGear's wrap adds 2π
    // (found by a test: heading 0 at 89° S came back as 360.0); keep the
    // documented [0, 360).
    let heading_deg = rad2deg(yaw);
    HorizontalAttitudeDeg {
        heading_deg: if heading_deg >= 360.0 {
            heading_deg - 360.0
        } else {
            heading_deg
        },
        pitch_deg: rad2deg(pitch),
        roll_deg: rad2deg(roll),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed forms above equal the products of elementary rotations
    /// they stand for: `fromLonLat = qz(lon) * qy(-π/2 - lat)` and
    /// `fromYawPitchRoll = qz(yaw) * qy(pitch) * qx(roll)`.
    #[test]
    fn closed_forms_are_products_of_elementary_turns() {
        let qx = |a: f64| [(a / 2.0).cos(), (a / 2.0).sin(), 0.0, 0.0];
        let qy = |a: f64| [(a / 2.0).cos(), 0.0, (a / 2.0).sin(), 0.0];
        let qz = |a: f64| [(a / 2.0).cos(), 0.0, 0.0, (a / 2.0).sin()];
        for &(lon, lat) in &[(0.3, -1.1), (-2.9, 0.7), (1.0, 1.5)] {
            let a = from_lon_lat_rad(lon, lat);
            let b = mul(qz(lon), qy(-PI / 2.0 - lat));
            for i in 0..4 {
                assert!((a[i] - b[i]).abs() < 1e-15, "{a:?} {b:?}");
            }
        }
        for &(z, y, x) in &[(0.3, -1.1, 2.0), (-2.9, 0.7, -0.4), (4.0, 1.5, 3.1)] {
            let a = from_yaw_pitch_roll(z, y, x);
            let b = mul(mul(qz(z), qy(y)), qx(x));
            for i in 0..4 {
                assert!((a[i] - b[i]).abs() < 1e-15, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn angle_axis_round_trips_and_keeps_the_sign_of_w() {
        // w < 0: the angle is reported above π, not flipped.
        let q = from_angle_axis([0.0, 0.0, 4.0]);
        assert!(q[0] < 0.0);
        let v = angle_axis(q);
        assert!(
            (v[2] - 4.0).abs() < 1e-14 && v[0] == 0.0 && v[1] == 0.0,
            "{v:?}"
        );
        assert_eq!(angle_axis([0.0; 4]), [0.0; 3]);
        assert_eq!(from_angle_axis([0.0; 3]), [1.0, 0.0, 0.0, 0.0]);
        // Identity either way round: w = 1 takes the "undefined axis" branch
        // (sin 0 = 0) and gives angle 0; w = -1 gives acos = π whose f64 sine
        // is 1.2e-16, not 0, so the axis is the zero imaginary part.
        assert_eq!(angle_axis([1.0, 0.0, 0.0, 0.0]), [0.0; 3]);
        assert_eq!(angle_axis([-1.0, 0.0, 0.0, 0.0]), [0.0; 3]);
    }

    /// SimGear's `getEulerRad` takes `atan2` of each angle's numerator and
    /// denominator unless both are zero (or subnormal): a half turn about a
    /// body axis, whose numerator is exactly 0 and denominator -1, is that
    /// angle at π; a quarter turn, whose denominator is exactly 0, is π/2.
    #[test]
    fn euler_angles_where_a_numerator_or_denominator_is_exactly_zero() {
        let h = 0.5_f64.sqrt();
        // Half and quarter turns about x (roll), then about z (yaw).
        assert_eq!(euler_rad([0.0, 1.0, 0.0, 0.0]), (0.0, -0.0, PI));
        let (yaw, _, roll) = euler_rad([h, h, 0.0, 0.0]);
        assert_eq!((yaw, roll), (0.0, 0.5 * PI));
        let (yaw, _, roll) = euler_rad([0.0, 0.0, 0.0, 1.0]);
        assert_eq!((yaw, roll), (PI, 0.0));
        let (yaw, _, roll) = euler_rad([h, 0.0, 0.0, h]);
        assert_eq!((yaw, roll), (0.5 * PI, 0.0));
        // Both zero (no rotation about that axis can be read): 0.
        assert_eq!(euler_rad([0.0; 4]), (0.0, -0.0, 0.0));
    }

    /// `getAngleAxis` normalises the quaternion first (the angle is
    /// `2·acos(w/|q|)`): a quaternion and any positive multiple of it give
    /// the same rotation vector.
    #[test]
    fn angle_axis_normalises_the_quaternion() {
        let h = 0.5_f64.sqrt();
        let unit = angle_axis([h, h, 0.0, 0.0]);
        assert!((unit[0] - 0.5 * PI).abs() < 1e-15, "{unit:?}");
        for scale in [1e-3, 2.0_f64.sqrt(), 7.0, 1e6] {
            let v = angle_axis([h * scale, h * scale, 0.0, 0.0]);
            for i in 0..3 {
                assert!((v[i] - unit[i]).abs() < 1e-14, "{scale}: {v:?} {unit:?}");
            }
        }
    }
}
