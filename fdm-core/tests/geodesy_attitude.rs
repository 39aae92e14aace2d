//! FlightGear attitude conventions: Bourg's Euler angles checked against the
//! model's own quaternion definitions, Palmer's point-mass attitude checked
//! against the model's lift-vector formula, and the heading sent checked
//! against the direction of travel over the ground computed from successive
//! geodetic positions with Karney's geodesics (geographiclib-rs).

use fdm_core::geodesy::{
    bourg_attitude, ground_track_deg, ned_from_model, normalize_heading_deg, palmer_attitude,
    Attitude, GeodeticOrigin, WGS84_A_M, WGS84_F,
};
use geographiclib_rs::{Geodesic, InverseGeodesic};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;

/// Signed difference of two angles in degrees, in (-180, 180].
fn angle_diff_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// NWU (model earth, and body x forward / y left / z up) to NED / FRD.
fn t() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0))
}

#[test]
fn heading_normalization() {
    let cases = [
        (0.0, 0.0),
        (-0.0, 0.0),
        (360.0, 0.0),
        (720.0, 0.0),
        (-90.0, 270.0),
        (450.5, 90.5),
        (-1e-20, 0.0), // would round to 360.0
        (359.999_999_999_999_9, 359.999_999_999_999_9),
    ];
    for (input, expected) in cases {
        let h = normalize_heading_deg(input);
        assert_eq!(h, expected, "{input}");
        assert!(
            h.is_sign_positive() && (0.0..360.0).contains(&h),
            "{input} -> {h}"
        );
    }
    assert!(normalize_heading_deg(f64::NAN).is_nan());
    assert!(normalize_heading_deg(f64::INFINITY).is_nan());
}

#[test]
fn ground_track_is_compass_direction_of_model_velocity() {
    // x north, y west.
    let cases = [
        ((1.0, 0.0), 0.0),
        ((0.0, -1.0), 90.0),
        ((-1.0, 0.0), 180.0),
        ((0.0, 1.0), 270.0),
        ((1.0, -1.0), 45.0),
        ((1.0, 1.0), 315.0),
        ((0.0, 0.0), 0.0), // Palmer's convention at rest
    ];
    for ((vx, vy), expected) in cases {
        let track = ground_track_deg(Vector3::new(vx, vy, 7.0));
        assert!((track - expected).abs() < 1e-12, "({vx}, {vy}) -> {track}");
    }
    // Just west of north: close to 360, never 360 itself.
    let track = ground_track_deg(Vector3::new(1.0, 1e-12, 0.0));
    assert!(track > 359.999 && track < 360.0, "{track}");
    assert_eq!(
        ned_from_model(Vector3::new(1.0, 2.0, 3.0)),
        Vector3::new(1.0, -2.0, -3.0)
    );
}

#[test]
fn attitude_matrix_round_trip_and_gimbal_lock() {
    for roll in [-179.0, -45.0, 0.0, 30.0, 180.0] {
        for pitch in [-89.0, -10.0, 0.0, 45.0, 89.9] {
            for heading in [0.0, 0.5, 90.0, 200.0, 359.5] {
                let a = Attitude {
                    roll_deg: roll,
                    pitch_deg: pitch,
                    heading_deg: heading,
                };
                let c = a.body_to_ned();
                assert!((c.transpose() * c - Matrix3::identity()).norm() < 1e-15);
                let b = Attitude::from_body_to_ned(&c);
                assert!(angle_diff_deg(b.roll_deg, roll).abs() < 1e-9, "{a:?} {b:?}");
                assert!((b.pitch_deg - pitch).abs() < 1e-9, "{a:?} {b:?}");
                assert!(
                    angle_diff_deg(b.heading_deg, heading).abs() < 1e-9,
                    "{a:?} {b:?}"
                );
            }
        }
    }
    // Heading 0 is north: the nose (first column) points north; pitch 10°
    // raises it (negative down component); roll 20° lowers the right wing.
    let c = Attitude {
        roll_deg: 20.0,
        pitch_deg: 10.0,
        heading_deg: 0.0,
    }
    .body_to_ned();
    assert!(c[(0, 0)] > 0.9 && c[(2, 0)] < 0.0 && c[(2, 1)] > 0.0, "{c}");
    // Nose straight up: roll folds into heading, the matrix is preserved.
    let up = Attitude {
        roll_deg: 30.0,
        pitch_deg: 90.0,
        heading_deg: 10.0,
    };
    let b = Attitude::from_body_to_ned(&up.body_to_ned());
    assert_eq!(b.roll_deg, 0.0);
    assert!((b.pitch_deg - 90.0).abs() < 1e-6);
    assert!((b.body_to_ned() - up.body_to_ned()).norm() < 1e-7, "{b:?}");
}

/// `from_body_to_ned`'s gimbal-lock band (its doc): a nose whose horizontal
/// part, `cos(pitch)`, is at most 1e-12 reports roll 0 and puts the rotation
/// about the vertical into the heading; just above 1e-12, roll and heading
/// are taken apart again. Either way the angles give back the matrix.
#[test]
fn gimbal_lock_starts_where_cos_pitch_is_1e_12() {
    // Ry(pitch) · Rx(30°) with cos(pitch) given exactly and sin(pitch) = 1
    // (1 - cos² rounds to 1 for these cosines): the nose a hair below
    // straight up, rolled 30°.
    let (sr, cr) = 30.0_f64.to_radians().sin_cos();
    let matrix = |cp: f64| Matrix3::new(cp, sr, cr, 0.0, cr, -sr, -1.0, cp * sr, cp * cr);
    let locked = matrix(1e-12);
    let a = Attitude::from_body_to_ned(&locked);
    assert_eq!(a.roll_deg, 0.0, "{a:?}");
    assert!((a.heading_deg - 330.0).abs() < 1e-9, "{a:?}");
    assert!((a.pitch_deg - 90.0).abs() < 1e-9, "{a:?}");
    assert!((a.body_to_ned() - locked).norm() < 1e-11, "{a:?}");

    let free = matrix(f64::from_bits(1e-12_f64.to_bits() + 1));
    let b = Attitude::from_body_to_ned(&free);
    assert!((b.roll_deg - 30.0).abs() < 1e-9, "{b:?}");
    assert_eq!(b.heading_deg, 0.0, "{b:?}");
    assert!((b.pitch_deg - 90.0).abs() < 1e-9, "{b:?}");
    assert!((b.body_to_ned() - free).norm() < 1e-11, "{b:?}");
}

// ---------------------------------------------------------------- Bourg

/// Bourg's `MakeQFromEulerAngles` (docs/bourg-model.md: x roll, y pitch, z yaw, degrees),
/// in f64: (n, x, y, z).
fn bourg_quaternion(euler_deg: Vector3<f64>) -> [f64; 4] {
    let (r, p, y) = (
        euler_deg.x.to_radians(),
        euler_deg.y.to_radians(),
        euler_deg.z.to_radians(),
    );
    let (cr, sr) = ((0.5 * r).cos(), (0.5 * r).sin());
    let (cp, sp) = ((0.5 * p).cos(), (0.5 * p).sin());
    let (cy, sy) = ((0.5 * y).cos(), (0.5 * y).sin());
    [
        cy * cp * cr + sy * sp * sr,
        cy * cp * sr - sy * sp * cr,
        cy * sp * cr + sy * cp * sr,
        sy * cp * cr - cy * sp * sr,
    ]
}

/// Bourg's `QVRotate(q, v)`: vector part of (q * v) * ~q, body -> earth
/// (the model rotates its body forces to earth with it).
fn qv_rotate(q: [f64; 4], v: Vector3<f64>) -> Vector3<f64> {
    let [n, x, y, z] = q;
    // q * v (the original's quaternion-times-vector).
    let a = [
        -(x * v.x + y * v.y + z * v.z),
        n * v.x + y * v.z - z * v.y,
        n * v.y + z * v.x - x * v.z,
        n * v.z + x * v.y - y * v.x,
    ];
    // (q*v) * ~q, with ~q = (n, -x, -y, -z); vector part only.
    let (bn, bx, by, bz) = (n, -x, -y, -z);
    Vector3::new(
        a[0] * bx + a[1] * bn + a[2] * bz - a[3] * by,
        a[0] * by + a[2] * bn + a[3] * bx - a[1] * bz,
        a[0] * bz + a[3] * bn + a[1] * by - a[2] * bx,
    )
}

/// For Bourg's Euler angles, rotate the body axes to the earth frame with the
/// model's own quaternion operations and read off FlightGear's angles
/// directly from the vectors: heading = compass direction of the nose,
/// pitch = elevation of the nose, roll = atan2(height of the left wing tip,
/// height of the body's up axis), positive when the right wing is down.
#[test]
fn bourg_attitude_agrees_with_the_models_quaternion() {
    let mut worst = 0.0_f64;
    let mut count = 0;
    for roll in (-170..=170).step_by(17) {
        for pitch in (-85..=85).step_by(17) {
            for yaw in (-175..=175).step_by(25) {
                let euler = Vector3::new(roll as f32, pitch as f32, yaw as f32 + 0.25);
                let q = bourg_quaternion(euler.map(f64::from));
                let fwd = qv_rotate(q, Vector3::x());
                let left = qv_rotate(q, Vector3::y());
                let up = qv_rotate(q, Vector3::z());

                let heading = normalize_heading_deg((-fwd.y).atan2(fwd.x).to_degrees());
                let pitch_up = fwd.z.asin().to_degrees();
                let roll_rwd = left.z.atan2(up.z).to_degrees();

                let a = bourg_attitude(euler);
                let errs = [
                    angle_diff_deg(a.heading_deg, heading).abs(),
                    (a.pitch_deg - pitch_up).abs(),
                    angle_diff_deg(a.roll_deg, roll_rwd).abs(),
                ];
                worst = errs.iter().fold(worst, |w, e| w.max(*e));
                assert!(
                    errs.iter().all(|e| *e < 1e-9),
                    "{euler} -> {a:?} vs {errs:?}"
                );
                assert!((0.0..360.0).contains(&a.heading_deg));

                // The whole matrix: FlightGear's body-to-NED equals T·R·T.
                let r = Matrix3::from_columns(&[fwd, left, up]);
                assert!((a.body_to_ned() - t() * r * t()).norm() < 1e-12, "{euler}");
                count += 1;
            }
        }
    }
    assert!(count > 1000);
    assert!(worst < 1e-9, "{worst:e}");
}

#[test]
fn bourg_signs_physically() {
    // Positive model roll: the left wing tip rises, so the right wing is down.
    let q = bourg_quaternion(Vector3::new(30.0, 0.0, 0.0));
    assert!(qv_rotate(q, Vector3::y()).z > 0.4);
    assert_eq!(bourg_attitude(Vector3::new(30.0, 0.0, 0.0)).roll_deg, 30.0);
    // Negative model pitch: the nose rises; FlightGear pitch is positive.
    let q = bourg_quaternion(Vector3::new(0.0, -5.0, 0.0));
    assert!(qv_rotate(q, Vector3::x()).z > 0.08);
    assert_eq!(bourg_attitude(Vector3::new(0.0, -5.0, 0.0)).pitch_deg, 5.0);
    // Positive yaw: the nose swings from north towards west (+y): heading 270.
    let q = bourg_quaternion(Vector3::new(0.0, 0.0, 90.0));
    assert!(qv_rotate(q, Vector3::x()).y > 0.99);
    assert_eq!(
        bourg_attitude(Vector3::new(0.0, 0.0, 90.0)).heading_deg,
        270.0
    );
    assert_eq!(
        bourg_attitude(Vector3::new(0.0, 0.0, -90.0)).heading_deg,
        90.0
    );
    assert_eq!(bourg_attitude(Vector3::new(0.0, 0.0, 0.0)).heading_deg, 0.0);
    assert_eq!(
        bourg_attitude(Vector3::new(0.0, 0.0, -0.0)).heading_deg,
        0.0
    );
    // f32 values are widened exactly.
    let a = bourg_attitude(Vector3::new(0.1_f32, -0.2, 0.3));
    assert_eq!(a.roll_deg, f64::from(0.1_f32));
    assert_eq!(a.pitch_deg, f64::from(0.2_f32));
    assert_eq!(a.heading_deg, 360.0 - f64::from(0.3_f32));
    assert!(bourg_attitude(Vector3::new(f32::NAN, 0.0, 0.0))
        .roll_deg
        .is_nan());
}

// ---------------------------------------------------------------- Palmer

/// The body axes of the airframe that would fly Palmer's point-mass state,
/// built from the model's own formulas (docs/palmer-model.md, right-hand side steps 10–11): velocity
/// direction (cosT cosP, sinT cosP, sinP) with T measured from +x towards +y
/// (west) and the lift direction (the coefficient of `lift` in Fx, Fy, Fz);
/// the nose is alpha above the velocity, towards the lift. Returns FRD axes
/// in NED components as matrix columns.
fn palmer_body_from_lift_vector(v: Vector3<f64>, alpha_deg: f64, bank_deg: f64) -> Matrix3<f64> {
    let vh = v.x.hypot(v.y);
    let vt = v.norm();
    let (cos_p, sin_p) = if vt == 0.0 {
        (1.0, 0.0)
    } else {
        (vh / vt, v.z / vt)
    };
    let (cos_t, sin_t) = if vh == 0.0 {
        (1.0, 0.0)
    } else {
        (v.x / vh, v.y / vh)
    };
    let (sin_w, cos_w) = bank_deg.to_radians().sin_cos();
    let v_hat = Vector3::new(cos_t * cos_p, sin_t * cos_p, sin_p);
    let lift_hat = Vector3::new(
        sin_t * sin_w - cos_t * sin_p * cos_w,
        -cos_t * sin_w - sin_t * sin_p * cos_w,
        cos_p * cos_w,
    );
    let (sa, ca) = alpha_deg.to_radians().sin_cos();
    let fwd = v_hat * ca + lift_hat * sa;
    let up = -v_hat * sa + lift_hat * ca;
    let left = up.cross(&fwd);
    Matrix3::from_columns(&[t() * fwd, -(t() * left), -(t() * up)])
}

#[test]
fn palmer_wings_level_is_track_and_climb_plus_alpha() {
    for track in [0.0, 0.1, 45.0, 90.0, 179.9, 180.0, 270.0, 359.9] {
        for climb in [-10.0_f64, 0.0, 3.0, 12.0] {
            for alpha in [-5.0, 0.0, 4.0, 15.0] {
                let (st, ct) = f64::to_radians(track).sin_cos();
                let (sg, cg) = climb.to_radians().sin_cos();
                // Compass track: north = +x, east = -y.
                let v = Vector3::new(ct * cg, -st * cg, sg) * 45.0;
                let a = palmer_attitude(v, alpha, 0.0);
                assert_eq!(a.roll_deg, 0.0, "{v}");
                assert!((a.pitch_deg - (climb + alpha)).abs() < 1e-12, "{a:?}");
                assert!(angle_diff_deg(a.heading_deg, track).abs() < 1e-12, "{a:?}");
                assert!((a.heading_deg - ground_track_deg(v)).abs() < 1e-12, "{a:?}");
                assert!((0.0..360.0).contains(&a.heading_deg));
            }
        }
    }
}

#[test]
fn palmer_banked_attitude_matches_the_models_lift_vector() {
    let mut count = 0;
    for track in (0..360).step_by(30) {
        for climb in [-15.0_f64, 0.0, 8.0] {
            for bank in [-20.0, -7.0, 0.0, 5.0, 20.0] {
                for alpha in [-16.0, 0.0, 4.0, 10.0, 20.0] {
                    let (st, ct) = f64::from(track).to_radians().sin_cos();
                    let (sg, cg) = climb.to_radians().sin_cos();
                    let v = Vector3::new(ct * cg, -st * cg, sg) * 60.0;
                    let a = palmer_attitude(v, alpha, bank);
                    let expected = palmer_body_from_lift_vector(v, alpha, bank);
                    assert!(
                        (a.body_to_ned() - expected).norm() < 1e-12,
                        "v {v} alpha {alpha} bank {bank}: {a:?}"
                    );
                    count += 1;
                }
            }
        }
    }
    assert_eq!(count, 12 * 3 * 5 * 5);
}

/// Straight up or straight down (no horizontal speed): the model's own
/// conventions, track 0 (`cos T = 1, sin T = 0`) and the flight-path angle
/// `atan2(vz, 0)`, ±90° (docs/palmer-model.md, step 10), as in the lift-vector
/// airframe; wings level, the nose is `climb + alpha`.
#[test]
fn palmer_vertical_flight_climbs_at_90_degrees() {
    for vz in [30.0, -30.0] {
        for bank in [-20.0, 0.0, 5.0, 20.0] {
            for alpha in [-16.0, -5.0, 0.0, 4.0, 10.0] {
                let v = Vector3::new(0.0, 0.0, vz);
                let a = palmer_attitude(v, alpha, bank);
                let expected = palmer_body_from_lift_vector(v, alpha, bank);
                assert!(
                    (a.body_to_ned() - expected).norm() < 1e-12,
                    "v {v} alpha {alpha} bank {bank}: {a:?}"
                );
            }
        }
    }
    let up = palmer_attitude(Vector3::new(0.0, 0.0, 30.0), -10.0, 0.0);
    assert!((up.pitch_deg - 80.0).abs() < 1e-12, "{up:?}");
    assert!(up.roll_deg == 0.0 && up.heading_deg == 0.0, "{up:?}");
    let down = palmer_attitude(Vector3::new(0.0, 0.0, -30.0), 10.0, 0.0);
    assert!((down.pitch_deg + 80.0).abs() < 1e-12, "{down:?}");
    assert!(down.roll_deg == 0.0 && down.heading_deg == 0.0, "{down:?}");
}

#[test]
fn palmer_signs_and_the_documented_example() {
    // Flying north, positive bank: the model's lateral lift component
    // (-cosT sinW - sinT sinP cosW) is negative, i.e. towards -y = east, a
    // right turn; FlightGear must show the right wing down (roll > 0).
    let bank: f64 = 15.0;
    assert!(-bank.to_radians().sin() < 0.0);
    let a = palmer_attitude(Vector3::new(50.0, 0.0, 0.0), 0.0, bank);
    assert!(
        (a.roll_deg - 15.0).abs() < 1e-12 && a.heading_deg.abs() < 1e-12,
        "{a:?}"
    );

    // The numbers quoted in `palmer_attitude`'s documentation.
    let a = palmer_attitude(Vector3::new(50.0, 0.0, 0.0), 10.0, 20.0);
    assert!((a.heading_deg - 3.45).abs() < 0.005, "{a:?}");
    assert!((a.pitch_deg - 9.39).abs() < 0.005, "{a:?}");
    assert!((a.roll_deg - 20.28).abs() < 0.005, "{a:?}");
    // Banking left mirrors it.
    let b = palmer_attitude(Vector3::new(50.0, 0.0, 0.0), 10.0, -20.0);
    assert!(
        (b.heading_deg - (360.0 - a.heading_deg)).abs() < 1e-12,
        "{b:?}"
    );
    assert!((b.roll_deg + a.roll_deg).abs() < 1e-12, "{b:?}");

    // At rest on the runway the model uses track 0 and climb 0.
    let rest = palmer_attitude(Vector3::zeros(), 3.0, 0.0);
    assert_eq!(rest.roll_deg, 0.0);
    assert!(
        (rest.pitch_deg - 3.0).abs() < 1e-12 && rest.heading_deg == 0.0,
        "{rest:?}"
    );

    let nan = palmer_attitude(Vector3::new(f64::NAN, 1.0, 0.0), 3.0, 0.0);
    assert!(
        nan.heading_deg.is_nan() && nan.pitch_deg.is_nan(),
        "{nan:?}"
    );
}

// ------------------------------------------ heading vs. track over the ground

/// Direction of travel between two nearby geodetic positions, from their
/// latitude, longitude and height alone (no use of the model frame): the
/// displacement in the local north-east-up frame at the midpoint is
/// `north = (M + h)·Δφ`, `east = (N + h)·cos φ·Δλ`, `up = Δh`, with the
/// meridian and prime-vertical radii of curvature M and N of WGS-84. Returns
/// (compass bearing in [0, 360), climb angle), degrees. Second-order accurate
/// about the midpoint.
fn bearing_and_climb_deg(origin: &GeodeticOrigin, a: Vector3<f64>, b: Vector3<f64>) -> (f64, f64) {
    let ga = origin.model_to_geodetic(a);
    let gb = origin.model_to_geodetic(b);
    let lat = (0.5 * (ga.lat_deg + gb.lat_deg)).to_radians();
    let h = 0.5 * (ga.alt_m + gb.alt_m);
    let e2 = WGS84_F * (2.0 - WGS84_F);
    let w = (1.0 - e2 * lat.sin().powi(2)).sqrt();
    let n = WGS84_A_M / w;
    let m = WGS84_A_M * (1.0 - e2) / (w * w * w);
    let north = (m + h) * (gb.lat_deg - ga.lat_deg).to_radians();
    let east = (n + h) * lat.cos() * angle_diff_deg(gb.lon_deg, ga.lon_deg).to_radians();
    let up = gb.alt_m - ga.alt_m;
    (
        normalize_heading_deg(east.atan2(north).to_degrees()),
        up.atan2(north.hypot(east)).to_degrees(),
    )
}

/// Initial azimuth, degrees in [0, 360), of the geodesic on the ellipsoid from
/// the foot of a to the foot of b (Karney's inverse problem, geographiclib-rs).
fn geodesic_bearing_deg(origin: &GeodeticOrigin, a: Vector3<f64>, b: Vector3<f64>) -> f64 {
    let ga = origin.model_to_geodetic(a);
    let gb = origin.model_to_geodetic(b);
    let (azi1, _azi2, _a12): (f64, f64, f64) =
        Geodesic::wgs84().inverse(ga.lat_deg, ga.lon_deg, gb.lat_deg, gb.lon_deg);
    normalize_heading_deg(azi1)
}

/// Straight, level flight in the model frame: the heading sent equals the
/// direction of travel over the ground computed from successive geodetic
/// positions, for directions all round the compass including either side of
/// north, from several origins and aircraft positions up to 100 km away.
///
/// Two independent references:
/// * the local-frame formula above, from the positions 110 m before and
///   after (a central difference, so the answer refers to the aircraft's
///   position); it also gives the climb angle for the pitch check;
/// * Karney's geodesic from the aircraft's position to the one 110 m ahead.
///   Its azimuth is measured on the ellipsoid surface, below the aircraft:
///   at height h the feet of the normals move in a direction turned by
///   `h·(1/M - 1/N)·sin α·cos α` radians from the direction of travel α
///   (the meridian and prime-vertical radii M and N differ), at most
///   `e²·h/(2a(1 - e²))` at the equator: 1.5e-5° at 251 m, 6.3e-4° at
///   11 km. It is compared with that allowance.
///
/// At the origin the model-frame heading itself is right. Away from it the
/// model's north is not true north (meridian convergence), so the heading
/// must go through [`GeodeticOrigin::attitude_at`]; the raw heading's error
/// there is measured too. The local NED velocity is checked the same way.
#[test]
fn heading_sent_equals_direction_of_travel_over_the_ground() {
    let origins = [
        GeodeticOrigin::default(),
        GeodeticOrigin::new(65.0, -18.0, 20.0).unwrap(),
        GeodeticOrigin::new(-41.33, 179.9, 12.0).unwrap(),
        GeodeticOrigin::new(0.0, 0.0, 0.0).unwrap(),
    ];
    let positions = [
        Vector3::new(0.0, 0.0, 1_000.0),
        Vector3::new(0.0, -80_000.0, 1_500.0),   // 80 km east
        Vector3::new(42_000.0, 42_000.0, 300.0), // 59 km north-west
        Vector3::new(-90_000.0, 0.0, 3_000.0),   // 90 km south
    ];
    let tracks = [
        0.0, 0.05, 359.95, 30.0, 90.0, 135.0, 180.0, 200.0, 270.0, 315.0,
    ];
    let speed_m_s = 55.0;
    let dt_s = 2.0; // 110 m between successive positions
    let e2 = WGS84_F * (2.0 - WGS84_F);

    let (mut worst_heading, mut worst_pitch, mut worst_ned) = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut worst_geodesic_ratio = 0.0_f64;
    // Raw (uncorrected) heading error 80 km east of each origin.
    let mut raw_east = [0.0_f64; 4];
    for (o, origin) in origins.iter().enumerate() {
        for (k, &p0) in positions.iter().enumerate() {
            let h = origin.model_to_geodetic(p0).alt_m;
            for &track in &tracks {
                let (st, ct) = f64::to_radians(track).sin_cos();
                let v = Vector3::new(ct, -st, 0.0) * speed_m_s;
                let (bearing, climb) = bearing_and_climb_deg(origin, p0 - v * dt_s, p0 + v * dt_s);

                let palmer = palmer_attitude(v, 0.0, 0.0);
                let bourg = bourg_attitude(Vector3::new(0.0, 0.0, -track as f32));
                let sent = origin.attitude_at(p0, palmer);
                let sent_bourg = origin.attitude_at(p0, bourg);
                assert!((0.0..360.0).contains(&sent.heading_deg));

                let err = angle_diff_deg(sent.heading_deg, bearing).abs();
                assert!(
                    err < 1e-7,
                    "{:?} p0 {p0} track {track}: {sent:?} vs {bearing}",
                    origin.geodetic()
                );
                worst_heading = worst_heading.max(err);
                // Bourg's angles are f32: up to 1.5e-5° of rounding near 360°.
                let err_bourg = angle_diff_deg(sent_bourg.heading_deg, bearing).abs();
                assert!(err_bourg < 2e-5, "{sent_bourg:?} vs {bearing}");

                let raw_err = angle_diff_deg(palmer.heading_deg, bearing).abs();
                if k == 0 {
                    // At the origin no correction is needed.
                    assert!(raw_err < 1e-7, "{raw_err}");
                }
                if k == 1 {
                    raw_east[o] = raw_east[o].max(raw_err);
                }

                let pitch_err = (sent.pitch_deg - climb).abs();
                assert!(pitch_err < 1e-7, "{sent:?} vs climb {climb}");
                worst_pitch = worst_pitch.max(pitch_err);

                // Karney's geodesic bearing over the surface.
                let geo_err = angle_diff_deg(
                    sent.heading_deg,
                    geodesic_bearing_deg(origin, p0, p0 + v * dt_s),
                )
                .abs()
                .to_radians();
                // h·(1/M - 1/N)/2 at its largest (the equator).
                let allowance = e2 * h / (2.0 * WGS84_A_M * (1.0 - e2));
                // Measured up to 1.0016 × the allowance (on the equator at 45°:
                // the 110 m step's own curvature), hence the 1 % margin.
                assert!(
                    geo_err < 1e-9 + 1.01 * allowance,
                    "{geo_err:e} rad vs {allowance:e}"
                );
                worst_geodesic_ratio = worst_geodesic_ratio.max(geo_err / allowance);

                // Local NED velocity: same direction and climb, same speed.
                let ned = origin.local_ned(p0, v);
                let ned_bearing = normalize_heading_deg(ned.y.atan2(ned.x).to_degrees());
                let ned_climb = (-ned.z).atan2(ned.x.hypot(ned.y)).to_degrees();
                let e = angle_diff_deg(ned_bearing, bearing)
                    .abs()
                    .max((ned_climb - climb).abs());
                assert!(e < 1e-7, "{ned} vs {bearing}, {climb}");
                assert!((ned.norm() - speed_m_s).abs() < 1e-9);
                worst_ned = worst_ned.max(e);
            }
        }
    }
    eprintln!(
        "heading {worst_heading:e}°, pitch {worst_pitch:e}°, NED {worst_ned:e}°, \
         geodesic/allowance {worst_geodesic_ratio}, raw heading 80 km east {raw_east:?}°"
    );
    // Without the correction, 80 km east of the origin the heading would be
    // off by the meridian convergence, about Δlon·sin(lat): measured 0.601°
    // at Wright-Patterson, 1.538° at 65° N, 0.633° at 41° S. On the equator
    // there is no convergence, only the second-order effect of the vertical's
    // tilt τ = 80 km / R about north, τ²/4 = 0.0023° at most.
    assert!((raw_east[0] - 0.601).abs() < 0.001, "{raw_east:?}");
    assert!((raw_east[1] - 1.538).abs() < 0.001, "{raw_east:?}");
    assert!((raw_east[2] - 0.633).abs() < 0.001, "{raw_east:?}");
    assert!(raw_east[3] < 0.0023, "{raw_east:?}");
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Any straight, level flight within 100 km of the default origin, any
    /// angle of attack, wings level in the model frame. With alpha = 0 the
    /// heading and pitch sent equal the direction of travel and climb angle
    /// over the ground. With any alpha, FlightGear is shown the aircraft at
    /// that angle of attack and no sideslip relative to that same direction
    /// of travel (away from the origin the model's level is tilted against
    /// the local level by up to d/R, so the model's wings-level aircraft is
    /// slightly banked there and its nose heading differs from its track by
    /// about that tilt times tan(alpha)).
    #[test]
    fn heading_matches_bearing_anywhere_near_the_origin(
        x in -70_000.0..70_000.0_f64,
        y in -70_000.0..70_000.0_f64,
        z in 0.0..10_000.0_f64,
        track in 0.0..360.0_f64,
        alpha in -16.0..20.0_f64,
    ) {
        let origin = GeodeticOrigin::default();
        let p0 = Vector3::new(x, y, z);
        let (st, ct) = track.to_radians().sin_cos();
        let v = Vector3::new(ct, -st, 0.0) * 50.0;
        let (bearing, climb) = bearing_and_climb_deg(&origin, p0 - v * 2.0, p0 + v * 2.0);

        let sent = origin.attitude_at(p0, palmer_attitude(v, 0.0, 0.0));
        prop_assert!(angle_diff_deg(sent.heading_deg, bearing).abs() < 1e-7);
        prop_assert!((sent.pitch_deg - climb).abs() < 1e-7);
        prop_assert!((0.0..360.0).contains(&sent.heading_deg));

        // Direction of travel from the geodetic positions, in local NED, then
        // in the body axes FlightGear is sent (x forward, y right, z down).
        let (sb, cb) = bearing.to_radians().sin_cos();
        let (sc, cc) = climb.to_radians().sin_cos();
        let travel_ned = Vector3::new(cb * cc, sb * cc, -sc);
        let sent = origin.attitude_at(p0, palmer_attitude(v, alpha, 0.0));
        let body = sent.body_to_ned().transpose() * travel_ned;
        let alpha_seen = body.z.atan2(body.x).to_degrees();
        let beta_seen = body.y.asin().to_degrees();
        prop_assert!((alpha_seen - alpha).abs() < 1e-7, "alpha {} seen {}", alpha, alpha_seen);
        prop_assert!(beta_seen.abs() < 1e-7, "beta {}", beta_seen);
    }
}
