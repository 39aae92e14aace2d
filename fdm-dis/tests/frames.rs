//! The frame conversions against cases derived by hand, and round trips.
//!
//! Hand derivations (φ latitude, λ longitude; ECEF x to 0°/0°, z to the
//! north pole):
//!
//! * Local NED axes in ECEF: `N = (-sin φ cos λ, -sin φ sin λ, cos φ)`,
//!   `E = (-sin λ, cos λ, 0)`, `D = (-cos φ cos λ, -cos φ sin λ, -sin φ)`.
//!   At 0°/0° that is N = +z, E = +y, D = -x, so `C_ecef←ned(0, 0)` has
//!   columns (0,0,1), (0,1,0), (-1,0,0), which is exactly `Ry(-90°)`.
//! * Hence at 0°/0° any NED attitude gives
//!   `C_ecef←body = Ry(-90°) · Rz(heading) · Ry(pitch) · Rx(roll)`, and the
//!   DIS angles follow by re-factoring that product as `Rz(ψ) Ry(θ) Rx(φ)`:
//!   - heading north, level: `Ry(-90°)` itself: ψ = 0, θ = -90°, φ = 0
//!     (body x along ECEF +z, the nose points at the north pole; this is DIS
//!     gimbal lock, where φ is taken as 0);
//!   - pitch 30° up heading north: `Ry(-90°) Ry(30°) = Ry(-60°)`:
//!     (0, -60°, 0);
//!   - heading east, level: body x = E = +y, y = south = -z, z = D = -x;
//!     `Rz(90°) Rx(-90°)` has exactly these columns: (90°, 0, -90°);
//!   - heading east, roll 45° right: `Rz(90°) Rx(-90°) Rx(45°)`:
//!     (90°, 0, -45°);
//!   - heading west, level: x = -y, y = N = +z, z = -x: `Rz(-90°) Rx(90°)`:
//!     (-90°, 0, 90°);
//!   - heading south, level: x = -z, y = -y, z = -x: `Rz(180°) Ry(90°)`:
//!     (180°, 90°, 0) (gimbal lock the other way).
//! * At 0°/90° E: N = +z, E = -x, D = -y. Heading east level: x = -x,
//!   y = south = -z, z = -y: `Rz(180°) Rx(-90°)`: (±180°, 0, -90°).
//! * At 90° N/0°: N = -x, E = +y, D = -z. Heading 0 level: x = -x, y = +y,
//!   z = -z: that is `diag(-1, 1, -1) = Rz(180°) Rx(180°)`: (180°, 0, 180°).
//! * Velocity at 0°/0°: `v = vN·N + vE·E + vD·D = (-vD, vE, vN)`.
//! * Location: `(N + h) cos φ cos λ, (N + h) cos φ sin λ, (N(1-e²) + h) sin φ`,
//!   so 0°/0°/h gives (a + h, 0, 0) and the pole gives (0, 0, b + h).
//!
//! Tolerances: the hand cases are exact in real numbers; in `f64` the trig
//! of degree arguments (cos 90° = 6.1e-17, …) leaves errors of a few
//! 1e-16 per matrix entry, so angles are compared to 1e-12 rad and
//! positions to 1e-6 m (a few ulps of 6.4e6 m is 1e-9 m).

use approx::assert_abs_diff_eq;
use fdm_dis::geodesy::{Attitude, Geodetic, WGS84_A_M, WGS84_B_M};
use fdm_dis::{
    ecef_vector_to_ned, local_from_ecef, rotation_angle_between, AircraftState, DisEuler,
    DrAlgorithm, WireState,
};
use nalgebra::Vector3;
use proptest::prelude::*;

const ANGLE_TOL_RAD: f64 = 1e-12;

fn state(lat: f64, lon: f64, alt: f64, heading: f64, pitch: f64, roll: f64) -> AircraftState {
    AircraftState::new(
        0.0,
        Geodetic {
            lat_deg: lat,
            lon_deg: lon,
            alt_m: alt,
        },
        Attitude {
            heading_deg: heading,
            pitch_deg: pitch,
            roll_deg: roll,
        },
        Vector3::zeros(),
    )
}

/// Compares DIS angles with the expected ones in degrees; ψ and φ modulo 360°.
fn assert_euler(got: DisEuler, psi: f64, theta: f64, phi: f64, what: &str) {
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    for (name, g, w) in [
        ("psi", got.psi_rad, psi.to_radians()),
        ("theta", got.theta_rad, theta.to_radians()),
        ("phi", got.phi_rad, phi.to_radians()),
    ] {
        let d = wrap(g - w).abs();
        assert!(
            d < ANGLE_TOL_RAD,
            "{what}: {name} = {}°, expected {w}° (diff {d:e} rad)",
            g.to_degrees(),
            w = w.to_degrees()
        );
    }
}

#[test]
fn orientation_hand_cases() {
    let cases = [
        // lat, lon, heading, pitch, roll -> psi, theta, phi (degrees)
        (
            (0.0, 0.0, 0.0, 0.0, 0.0),
            (0.0, -90.0, 0.0),
            "0/0 north level",
        ),
        (
            (0.0, 0.0, 0.0, 30.0, 0.0),
            (0.0, -60.0, 0.0),
            "0/0 north pitch 30",
        ),
        (
            (0.0, 0.0, 90.0, 0.0, 0.0),
            (90.0, 0.0, -90.0),
            "0/0 east level",
        ),
        (
            (0.0, 0.0, 90.0, 0.0, 45.0),
            (90.0, 0.0, -45.0),
            "0/0 east roll 45",
        ),
        (
            (0.0, 0.0, 270.0, 0.0, 0.0),
            (-90.0, 0.0, 90.0),
            "0/0 west level",
        ),
        (
            (0.0, 0.0, 180.0, 0.0, 0.0),
            (180.0, 90.0, 0.0),
            "0/0 south level",
        ),
        (
            (0.0, 90.0, 90.0, 0.0, 0.0),
            (180.0, 0.0, -90.0),
            "0/90 east level",
        ),
        (
            (90.0, 0.0, 0.0, 0.0, 0.0),
            (180.0, 0.0, 180.0),
            "pole heading 0",
        ),
    ];
    for ((lat, lon, h, p, r), (psi, theta, phi), what) in cases {
        let e = state(lat, lon, 1000.0, h, p, r).to_ecef().unwrap();
        assert_euler(e.orientation, psi, theta, phi, what);
        // The angles rebuild the matrix they came from.
        let back = e.orientation.body_to_ecef();
        assert!(
            rotation_angle_between(&back, &e.body_to_ecef) < ANGLE_TOL_RAD,
            "{what}"
        );
    }
}

/// At θ = ±90° (gimbal lock), as documented: φ is 0 and the whole
/// rotation about z goes into ψ, the same rotation. The orientations
/// `Rz(ψ) Ry(±90°) Rx(φ)` for several ψ and φ (only ψ ∓ φ matters) come
/// back with θ = ±90° and φ = 0, and their angles make the same matrix.
/// The limit is exact: cos θ = 1e-12 exactly is gimbal lock (φ = 0, the
/// roll in ψ), 2e-12 is not (φ read as atan2(c₂₁, c₂₂)).
#[test]
fn gimbal_lock_puts_the_whole_turn_about_z_in_psi() {
    for theta_deg in [90.0_f64, -90.0] {
        for (psi_deg, phi_deg) in [
            (30.0_f64, 0.0_f64),
            (-70.0, 25.0),
            (0.0, 40.0),
            (120.0, -150.0),
        ] {
            let e = DisEuler {
                psi_rad: psi_deg.to_radians(),
                theta_rad: theta_deg.to_radians(),
                phi_rad: phi_deg.to_radians(),
            };
            let c = e.body_to_ecef();
            let back = DisEuler::from_body_to_ecef(&c);
            let what = format!("({psi_deg}, {theta_deg}, {phi_deg})");
            assert_eq!(back.phi_rad, 0.0, "{what}");
            assert!(
                (back.theta_rad - theta_deg.to_radians()).abs() < 1e-7,
                "{what}: {back:?}"
            );
            assert!((back.body_to_ecef() - c).amax() < 1e-12, "{what}: {back:?}");
            // Nose up, ψ - φ; nose down, ψ + φ (Ry(±90°) Rx(φ) = Rz(∓φ) Ry(±90°)).
            let psi = if theta_deg > 0.0 {
                psi_deg - phi_deg
            } else {
                psi_deg + phi_deg
            };
            assert_euler(back, psi, theta_deg, 0.0, &what);
        }
    }
    // Ry(θ) Rx(30°) with cos θ = 1e-12 and 2e-12 exactly (sin θ rounds to 1).
    let (s, c) = 30.0_f64.to_radians().sin_cos();
    let tilted = |cos_theta: f64| {
        nalgebra::Matrix3::new(
            cos_theta,
            s,
            c,
            0.0,
            c,
            -s,
            -1.0,
            cos_theta * s,
            cos_theta * c,
        )
    };
    let at = DisEuler::from_body_to_ecef(&tilted(1e-12));
    assert_eq!(at.phi_rad, 0.0, "{at:?}");
    assert!((at.psi_rad + 30.0_f64.to_radians()).abs() < 1e-12, "{at:?}");
    let above = DisEuler::from_body_to_ecef(&tilted(2e-12));
    assert!(
        (above.phi_rad - 30.0_f64.to_radians()).abs() < 1e-12,
        "{above:?}"
    );
    assert_eq!(above.psi_rad, 0.0, "{above:?}");
}

#[test]
fn body_axes_at_the_equator_heading_north() {
    // Body x (nose) = ECEF +z, body y (right wing) = ECEF +y, body z (down) = ECEF -x.
    let c = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        .to_ecef()
        .unwrap()
        .body_to_ecef;
    for (col, want) in [
        (0, [0.0, 0.0, 1.0]),
        (1, [0.0, 1.0, 0.0]),
        (2, [-1.0, 0.0, 0.0]),
    ] {
        for (i, w) in want.iter().enumerate() {
            assert_abs_diff_eq!(c[(i, col)], *w, epsilon = 1e-15);
        }
    }
}

#[test]
fn location_and_velocity_hand_cases() {
    let mut s = state(0.0, 0.0, 500.0, 0.0, 0.0, 0.0);
    s.velocity_ned_m_s = Vector3::new(100.0, 20.0, -5.0);
    s.acceleration_ned_m_s2 = Some(Vector3::new(1.0, 2.0, 3.0));
    let e = s.to_ecef().unwrap();
    assert_abs_diff_eq!(
        e.location_m,
        Vector3::new(WGS84_A_M + 500.0, 0.0, 0.0),
        epsilon = 1e-6
    );
    // (-vD, vE, vN)
    assert_abs_diff_eq!(
        e.velocity_m_s,
        Vector3::new(5.0, 20.0, 100.0),
        epsilon = 1e-12
    );
    assert_abs_diff_eq!(
        e.acceleration_m_s2,
        Vector3::new(-3.0, 2.0, 1.0),
        epsilon = 1e-12
    );

    let pole = state(90.0, 0.0, 250.0, 0.0, 0.0, 0.0).to_ecef().unwrap();
    assert_abs_diff_eq!(
        pole.location_m,
        Vector3::new(0.0, 0.0, WGS84_B_M + 250.0),
        epsilon = 1e-6
    );

    // 45° N, 0°: N = (-√½, 0, √½); 10 m/s north.
    let mut s = state(45.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    s.velocity_ned_m_s = Vector3::new(10.0, 0.0, 0.0);
    let h = 10.0 * std::f64::consts::FRAC_1_SQRT_2;
    assert_abs_diff_eq!(
        s.to_ecef().unwrap().velocity_m_s,
        Vector3::new(-h, 0.0, h),
        epsilon = 1e-12
    );

    // 0°, 90° E: east is ECEF -x.
    let mut s = state(0.0, 90.0, 0.0, 0.0, 0.0, 0.0);
    s.velocity_ned_m_s = Vector3::new(0.0, 7.0, 0.0);
    assert_abs_diff_eq!(
        s.to_ecef().unwrap().velocity_m_s,
        Vector3::new(-7.0, 0.0, 0.0),
        epsilon = 1e-12
    );
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let good = state(10.0, 20.0, 30.0, 40.0, 5.0, 6.0);
    assert!(good.to_ecef().is_ok());
    let mut s = good;
    s.position.lat_deg = f64::NAN;
    assert!(s.to_ecef().is_err());
    let mut s = good;
    s.position.lat_deg = 90.5;
    assert!(s.to_ecef().is_err());
    let mut s = good;
    s.velocity_ned_m_s.y = f64::INFINITY;
    assert!(s.to_ecef().is_err());
    let mut s = good;
    s.angular_velocity_body_rad_s = Some(Vector3::new(0.0, f64::NAN, 0.0));
    assert!(s.to_ecef().is_err());
    let mut s = good;
    s.time_s = f64::NEG_INFINITY;
    assert!(s.to_ecef().is_err());
}

fn heading_diff_deg(a: f64, b: f64) -> f64 {
    ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs()
}

proptest! {
    /// geodetic/NED → ECEF/DIS → geodetic/NED in f64: the geodesy's round
    /// trip is below 1e-8 m; the rotation is recovered to a few 1e-16 rad
    /// per entry, so 1e-11 rad on the rotation angle leaves a margin.
    #[test]
    fn round_trip_f64(
        lat in -89.9f64..89.9, lon in -180.0f64..180.0, alt in -400.0f64..20_000.0,
        heading in 0.0f64..360.0, pitch in -85.0f64..85.0, roll in -180.0f64..180.0,
        vn in -300.0f64..300.0, ve in -300.0f64..300.0, vd in -100.0f64..100.0,
    ) {
        let mut s = state(lat, lon, alt, heading, pitch, roll);
        s.velocity_ned_m_s = Vector3::new(vn, ve, vd);
        let e = s.to_ecef().unwrap();
        let (pos, att) = local_from_ecef(e.location_m, e.orientation);
        prop_assert!((pos.lat_deg - lat).abs() < 1e-9);
        prop_assert!((pos.lon_deg - lon).abs() < 1e-9);
        prop_assert!((pos.alt_m - alt).abs() < 1e-6);
        let angle = rotation_angle_between(&att.body_to_ned(), &s.attitude.body_to_ned());
        prop_assert!(angle < 1e-11, "rotation error {angle:e} rad");
        let v = ecef_vector_to_ned(pos, e.velocity_m_s);
        prop_assert!((v - s.velocity_ned_m_s).norm() < 1e-9);
    }

    /// Through the wire's f32 angles: each of ψ, θ, φ (|x| ≤ π < 4) is rounded
    /// by at most half an f32 ulp of [2, 4), 2^-23 ≈ 1.2e-7 rad, so the rotation is
    /// off by at most 3.6e-7 rad. Heading and roll read back from it move by
    /// up to that over cos(pitch): with |pitch| ≤ 60° at most 7.2e-7 rad =
    /// 4.1e-5°, inside the 1e-4° the interoperability test asks for.
    #[test]
    fn round_trip_through_wire_f32(
        lat in -89.9f64..89.9, lon in -180.0f64..180.0, alt in 0.0f64..12_000.0,
        heading in 0.0f64..360.0, pitch in -60.0f64..60.0, roll in -179.0f64..179.0,
    ) {
        let s = state(lat, lon, alt, heading, pitch, roll);
        let e = s.to_ecef().unwrap();
        let wire = WireState::new(&e, DrAlgorithm::Fpw);
        let angle = rotation_angle_between(&wire.orientation().body_to_ecef(), &e.body_to_ecef);
        prop_assert!(angle <= 3.6e-7, "rotation error {angle:e} rad");
        let (_, att) = local_from_ecef(wire.location_m, wire.orientation());
        prop_assert!(heading_diff_deg(att.heading_deg, heading) < 1e-4);
        prop_assert!((att.pitch_deg - pitch).abs() < 1e-4);
        prop_assert!(heading_diff_deg(att.roll_deg, roll) < 1e-4);
    }
}
