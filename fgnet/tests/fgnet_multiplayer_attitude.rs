//! The multiplayer orientation field against expectations derived without
//! quaternions.
//!
//! The field is the rotation from the ECEF frame to the body frame as a
//! rotation vector `v`. Its rotation matrix `R(v)` (Rodrigues' formula,
//! written out below) maps each ECEF basis vector onto the matching body
//! axis, written in ECEF: column `i` of `R(v)` is body axis `i`. The expected
//! body axes come from plain trigonometry:
//!
//! * local north, east and down at geodetic latitude `φ`, longitude `λ`:
//!   `N = (-sinφ cosλ, -sinφ sinλ, cosφ)`, `E = (-sinλ, cosλ, 0)`,
//!   `D = (-cosφ cosλ, -cosφ sinλ, -sinφ)`;
//! * body axes from heading `ψ`, pitch `θ`, roll `ϕ` (yaw, then pitch, then
//!   roll), as rows of the usual NED-to-body direction cosine matrix:
//!   `x = cθcψ N + cθsψ E − sθ D`,
//!   `y = (sϕsθcψ − cϕsψ) N + (sϕsθsψ + cϕcψ) E + sϕcθ D`,
//!   `z = (cϕsθcψ + sϕsψ) N + (cϕsθsψ − sϕcψ) E + cϕcθ D`.

use std::f64::consts::{FRAC_PI_2, PI};

use fgnet::{
    attitude_from_ecef_angle_axis, ecef_angle_axis_from_attitude, HorizontalAttitudeDeg,
    MultiplayerPosition,
};
use proptest::prelude::*;

type V3 = [f64; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(k: f64, a: V3) -> V3 {
    [k * a[0], k * a[1], k * a[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `R(v) e`: Rodrigues' rotation of `e` by angle `|v|` about `v/|v|`.
fn rotate(v: V3, e: V3) -> V3 {
    let angle = dot(v, v).sqrt();
    if angle == 0.0 {
        return e;
    }
    let k = scale(1.0 / angle, v);
    let (s, c) = angle.sin_cos();
    add(
        add(scale(c, e), scale(s, cross(k, e))),
        scale((1.0 - c) * dot(k, e), k),
    )
}

/// Body x, y, z axes in ECEF according to `v`.
fn axes_from_angle_axis(v: V3) -> [V3; 3] {
    [
        rotate(v, [1.0, 0.0, 0.0]),
        rotate(v, [0.0, 1.0, 0.0]),
        rotate(v, [0.0, 0.0, 1.0]),
    ]
}

/// Body x, y, z axes in ECEF from the module-doc formulas.
fn axes_expected(lat_deg: f64, lon_deg: f64, a: HorizontalAttitudeDeg) -> [V3; 3] {
    let (sf, cf) = lat_deg.to_radians().sin_cos();
    let (sl, cl) = lon_deg.to_radians().sin_cos();
    let n = [-sf * cl, -sf * sl, cf];
    let e = [-sl, cl, 0.0];
    let d = [-cf * cl, -cf * sl, -sf];
    let (sp, cp) = a.heading_deg.to_radians().sin_cos();
    let (st, ct) = a.pitch_deg.to_radians().sin_cos();
    let (sr, cr) = a.roll_deg.to_radians().sin_cos();
    let comb = |cn: f64, ce: f64, cd: f64| add(add(scale(cn, n), scale(ce, e)), scale(cd, d));
    [
        comb(ct * cp, ct * sp, -st),
        comb(sr * st * cp - cr * sp, sr * st * sp + cr * cp, sr * ct),
        comb(cr * st * cp + sr * sp, cr * st * sp - sr * cp, cr * ct),
    ]
}

fn att(heading_deg: f64, pitch_deg: f64, roll_deg: f64) -> HorizontalAttitudeDeg {
    HorizontalAttitudeDeg {
        heading_deg,
        pitch_deg,
        roll_deg,
    }
}

fn max_axis_error(a: [V3; 3], b: [V3; 3]) -> f64 {
    let mut m = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            m = m.max((a[i][j] - b[i][j]).abs());
        }
    }
    m
}

/// Hand-worked cases. At latitude 0, longitude 0 the local frame is
/// north = ECEF +z, east = ECEF +y, down = ECEF −x.
///
/// Tolerance 1e-15 on unit-vector components and on the rotation vector:
/// a few f64 roundings of trigonometric values of size 1 (f64 epsilon is
/// 2.2e-16).
#[test]
fn hand_worked_orientations() {
    let x = [1.0, 0.0, 0.0];
    let y = [0.0, 1.0, 0.0];
    let z = [0.0, 0.0, 1.0];
    let neg = |v: V3| scale(-1.0, v);
    let cases: [(f64, f64, HorizontalAttitudeDeg, [V3; 3]); 5] = [
        // Level, nose north at (0, 0): nose +z, right wing (east) +y, belly −x.
        (0.0, 0.0, att(0.0, 0.0, 0.0), [z, y, neg(x)]),
        // Heading 90 (east): nose +y, right wing points south −z, belly −x.
        (0.0, 0.0, att(90.0, 0.0, 0.0), [y, neg(z), neg(x)]),
        // Nose 90° up at (0, 0): nose points up +x, belly points north +z.
        (0.0, 0.0, att(0.0, 90.0, 0.0), [x, y, z]),
        // At (0, 90E): north +z, east −x, down −y; heading 0, roll 90 right
        // wing down: right wing points down −y, belly points west +x.
        (0.0, 90.0, att(0.0, 0.0, 90.0), [z, neg(y), x]),
        // North pole, longitude 0, heading 0: "north" along the meridian
        // continues over the pole towards −x; east +y; down −z.
        (90.0, 0.0, att(0.0, 0.0, 0.0), [neg(x), y, neg(z)]),
    ];
    for (lat, lon, a, expected) in cases {
        let v = ecef_angle_axis_from_attitude(lat, lon, a);
        let got = axes_from_angle_axis(v);
        let err = max_axis_error(got, expected);
        assert!(
            err < 1e-15,
            "lat {lat} lon {lon} {a:?}: v {v:?} axes {got:?}, want {expected:?}"
        );
        // The hand expectations agree with the general formula too.
        assert!(max_axis_error(axes_expected(lat, lon, a), expected) < 1e-15);
    }

    // Level north at (0, 0) maps x→z, z→−x, y→y: a −90° turn about ECEF y.
    let v = ecef_angle_axis_from_attitude(0.0, 0.0, att(0.0, 0.0, 0.0));
    assert!(
        (v[0]).abs() < 1e-15 && (v[1] + FRAC_PI_2).abs() < 1e-15 && v[2].abs() < 1e-15,
        "{v:?}"
    );
    // Pitch 90 at (0, 0) puts the body axes on the ECEF axes (third case
    // above): no rotation, so the zero vector.
    let v = ecef_angle_axis_from_attitude(0.0, 0.0, att(0.0, 90.0, 0.0));
    assert!(dot(v, v).sqrt() < 1e-15, "{v:?}");
}

/// The angle is `2·acos(w)` without flipping the quaternion to `w ≥ 0`, so
/// the rotation vector's length lies in `[0, 2π]` and can exceed π.
#[test]
fn rotation_vector_length_can_exceed_pi() {
    let mut longest = 0.0f64;
    for h in (0..360).step_by(15) {
        for r in (-180..180).step_by(15) {
            let v = ecef_angle_axis_from_attitude(10.0, 20.0, att(f64::from(h), 5.0, f64::from(r)));
            longest = longest.max(dot(v, v).sqrt());
        }
    }
    assert!(longest > PI && longest <= 2.0 * PI, "{longest}");
}

/// Heading difference folded into (−180, 180].
fn heading_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// Tolerance for the f64 rotation vector, per unit-vector component or in
/// radians of rotation. FlightGear's angle-axis step takes
/// `half = acos(w)` and `axis = imag / sin(half)`. `w` carries a few f64
/// roundings (≲ 1e-15); acos amplifies that by 1/sin(half), and dividing by
/// `sin(half)` amplifies the resulting error in `half` again by
/// cot(half) ≤ 1/sin(half); the vector's length is at most 2π. So the
/// error is about 6e-15 / sin²(half), worst where the total rotation is
/// near 0 or 2π; 1e-14 · (1 + 1/sin²(half)) bounds it with margin. Over
/// 2·10⁶ random attitudes (pitch within ±89°, release build) the largest
/// axis error measured was 2.7e-12 and the largest ratio of error to this
/// bound 0.19 (0.17 for the round trip bound below).
fn f64_rotation_tolerance_rad(v: V3) -> f64 {
    let half = 0.5 * dot(v, v).sqrt();
    1e-14 * (1.0 + 1.0 / half.sin().powi(2))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The rotation vector reproduces the trigonometric body axes, within
    /// [`f64_rotation_tolerance_rad`] per component.
    #[test]
    fn axes_match_trigonometry(
        lat in -90.0f64..=90.0, lon in -180.0f64..=180.0,
        h in 0.0f64..360.0, p in -90.0f64..=90.0, r in -180.0f64..=180.0,
    ) {
        let a = att(h, p, r);
        let v = ecef_angle_axis_from_attitude(lat, lon, a);
        let err = max_axis_error(axes_from_angle_axis(v), axes_expected(lat, lon, a));
        let tol = f64_rotation_tolerance_rad(v);
        prop_assert!(err < tol, "err {err:e} > {tol:e} at lat {lat} lon {lon} {a:?}, v {v:?}");
        let len = dot(v, v).sqrt();
        prop_assert!((0.0..=2.0 * PI).contains(&len), "|v| = {len}");
    }

    /// f64 round trip. Pitch stays within ±89°: at ±90° only the difference
    /// of heading and roll is defined. The rotation error of the forward
    /// step ([`f64_rotation_tolerance_rad`]) reaches the angles amplified by
    /// up to 1/cos(pitch) (heading and roll through atan2 of a nearly
    /// vertical nose, pitch through asin near ±1), hence that factor plus
    /// 2 for the rest.
    #[test]
    fn round_trip_f64(
        lat in -90.0f64..=90.0, lon in -180.0f64..=180.0,
        h in 0.0f64..360.0, p in -89.0f64..=89.0, r in -179.999f64..=180.0,
    ) {
        let v = ecef_angle_axis_from_attitude(lat, lon, att(h, p, r));
        let back = attitude_from_ecef_angle_axis(v, lat, lon);
        let tol = (f64_rotation_tolerance_rad(v) * (2.0 + 1.0 / p.to_radians().cos())).to_degrees();
        prop_assert!(heading_diff(back.heading_deg, h).abs() < tol, "{back:?} vs {h}, tol {tol:e}");
        prop_assert!((0.0..360.0).contains(&back.heading_deg));
        prop_assert!((back.pitch_deg - p).abs() < tol, "{back:?} vs {p}, tol {tol:e}");
        prop_assert!(heading_diff(back.roll_deg, r).abs() < tol, "{back:?} vs {r}, tol {tol:e}");
    }

    /// Round trip through the f32 wire field, as FlightGear sees it. Each
    /// component is rounded to f32: at most 2^-24 relative of |v| ≤ 2π, so
    /// ≤ 3.8e-7 rad per component, ≤ 6.5e-7 rad of rotation (3.7e-5 deg).
    /// Pitch takes that directly; heading and roll take it times
    /// 1/cos(pitch) ≤ 5.8 for |pitch| ≤ 80°, so ≤ 2.2e-4 deg. Tolerances:
    /// 5e-5 deg for pitch, 3e-4 deg for heading and roll. Largest errors
    /// measured over 2·10⁶ random attitudes: heading 8.0e-5, pitch 1.6e-5,
    /// roll 8.2e-5 deg.
    #[test]
    fn round_trip_through_the_wire(
        lat in -90.0f64..=90.0, lon in -180.0f64..=180.0,
        h in 0.0f64..360.0, p in -80.0f64..=80.0, r in -179.999f64..=180.0,
        t in 0.0f64..1e6,
    ) {
        let mut m = MultiplayerPosition::new("MP1", "Aircraft/ufo/Models/ufo.xml").unwrap();
        m.time_s = t;
        m.set_orientation_from_attitude(lat, lon, att(h, p, r));
        let got = MultiplayerPosition::decode(&m.encode().unwrap()).unwrap();
        let back = got.attitude(lat, lon);
        prop_assert!(heading_diff(back.heading_deg, h).abs() < 3e-4, "{back:?} vs {h}");
        prop_assert!((back.pitch_deg - p).abs() < 5e-5, "{back:?} vs {p}");
        prop_assert!(heading_diff(back.roll_deg, r).abs() < 3e-4, "{back:?} vs {r}");
    }

    /// Any input, finite or not: no panic, and inputs small enough that
    /// `deg · π` cannot overflow give a finite vector.
    #[test]
    fn never_panics(
        lat in any::<f64>(), lon in any::<f64>(),
        h in any::<f64>(), p in any::<f64>(), r in any::<f64>(),
    ) {
        let v = ecef_angle_axis_from_attitude(lat, lon, att(h, p, r));
        if [lat, lon, h, p, r].iter().all(|x| x.abs() < 1e300) {
            prop_assert!(v.iter().all(|c| c.is_finite()), "{v:?}");
        }
        let _ = attitude_from_ecef_angle_axis(v, lat, lon);
        let _ = attitude_from_ecef_angle_axis([h, p, r], lat, lon);
    }
}
