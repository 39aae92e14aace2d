//! The multiplayer orientation at its edges: nose straight up or down (the
//! Euler angles' gimbal lock, where the pitch is clamped to ±90°) and a
//! heading of exactly 0 (never reported as 360). The expectations are the
//! documented ranges of `attitude_from_ecef_angle_axis` (heading in
//! `[0, 360)`, pitch in `[-90, 90]`), for attitudes built by its inverse.

use fgnet::{attitude_from_ecef_angle_axis, ecef_angle_axis_from_attitude, HorizontalAttitudeDeg};

/// Places from the equator to near the poles, both hemispheres, both sides
/// of the date line.
const PLACES: [(f64, f64); 7] = [
    (0.0, 0.0),
    (21.963792, -159.335883),
    (39.8264, -84.0483),
    (-33.9, 151.2),
    (64.0, -22.6),
    (-89.0, 179.9),
    (0.0, 90.0),
];

fn round_trip(lat: f64, lon: f64, attitude: HorizontalAttitudeDeg) -> HorizontalAttitudeDeg {
    attitude_from_ecef_angle_axis(ecef_angle_axis_from_attitude(lat, lon, attitude), lat, lon)
}

#[test]
fn nose_straight_up_or_down_comes_back_as_plus_or_minus_90_degrees() {
    let mut clamped = 0;
    for (lat, lon) in PLACES {
        for pitch in [90.0, -90.0] {
            for heading in [0.0, 45.0, 180.0, 300.0] {
                let back = round_trip(
                    lat,
                    lon,
                    HorizontalAttitudeDeg {
                        heading_deg: heading,
                        pitch_deg: pitch,
                        roll_deg: 0.0,
                    },
                );
                // Within the rounding of the round trip (1e-9° would be far
                // tighter than the f32 on the wire; a pitch of 90° loses
                // about half the digits through asin near 1).
                assert!(
                    (back.pitch_deg - pitch).abs() < 1e-5,
                    "pitch {pitch} at ({lat}, {lon}) heading {heading}: back {}",
                    back.pitch_deg
                );
                // Never beyond the documented range.
                assert!((-90.0..=90.0).contains(&back.pitch_deg), "{back:?}");
                if back.pitch_deg.abs() == 90.0 {
                    clamped += 1;
                }
            }
        }
    }
    // Some of these reach the clamp exactly (the sine rounds to ±1 or past
    // it), so the clamp's own value is checked above, not just asin's.
    assert!(clamped > 0, "no case reached the pitch clamp");
}

#[test]
fn a_heading_of_zero_is_zero_not_360() {
    let mut exact_zero = 0;
    for (lat, lon) in PLACES {
        let back = round_trip(lat, lon, HorizontalAttitudeDeg::default());
        assert!((0.0..360.0).contains(&back.heading_deg), "{back:?}");
        // North is 0, or a hair under 360 when rounding lands just west of
        // north; never 360 itself and never a hair above 0 turned into 360.
        assert!(
            back.heading_deg < 1e-9 || back.heading_deg > 360.0 - 1e-9,
            "{back:?} at ({lat}, {lon})"
        );
        if back.heading_deg == 0.0 {
            exact_zero += 1;
        }
    }
    assert!(exact_zero > 0, "no case came back as exactly 0");
}

#[test]
fn quarter_and_half_turns_come_back_as_sent() {
    // Headings and rolls of exactly 90° and 180°, where one of the two terms
    // each Euler angle is an arc tangent of can be exactly 0: the angle must
    // still come back as sent, not be taken for an undefined one.
    for (lat, lon) in PLACES {
        for (heading, roll) in [
            (180.0, 0.0),
            (90.0, 0.0),
            (270.0, 0.0),
            (0.0, 180.0),
            (0.0, 90.0),
            (0.0, -90.0),
            (180.0, 180.0),
        ] {
            let sent = HorizontalAttitudeDeg {
                heading_deg: heading,
                pitch_deg: 0.0,
                roll_deg: roll,
            };
            let back = round_trip(lat, lon, sent);
            let same_angle = |a: f64, b: f64| {
                let d = (a - b).rem_euclid(360.0);
                d.min(360.0 - d) < 1e-6
            };
            assert!(
                same_angle(back.heading_deg, heading)
                    && same_angle(back.roll_deg, roll)
                    && back.pitch_deg.abs() < 1e-6,
                "{sent:?} at ({lat}, {lon}) came back as {back:?}"
            );
        }
    }
}
