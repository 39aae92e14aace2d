//! The Palmer state vector and the flight data derived from it.

use core::f64::consts::PI;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::math::{atan, atan2, sqrt};
use crate::units::wrap_degrees_360;

/// Time, position and velocity of a Palmer aircraft in the earth frame
/// (x forward/north, y left/west, z up; metres, metres per second, seconds).
///
/// The model is a point mass: there is no attitude state. [`Default`] and
/// [`PalmerState::at_rest`] are all zero: standing on the runway at the origin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerState {
    /// Simulated time, s.
    pub time_s: f64,
    /// Position `[x, y, z]`, m; `z` is the altitude above the ground plane.
    pub position_m: Vector3<f64>,
    /// Velocity `[vx, vy, vz]`, m/s.
    pub velocity_mps: Vector3<f64>,
}

impl PalmerState {
    /// The thesis's initial state: [`at_rest`](Self::at_rest).
    #[must_use]
    pub const fn initial() -> Self {
        Self::at_rest()
    }

    /// At rest at the origin at time 0 (the model's initial state, docs/palmer-model.md).
    #[must_use]
    pub const fn at_rest() -> Self {
        Self {
            time_s: 0.0,
            position_m: Vector3::new(0.0, 0.0, 0.0),
            velocity_mps: Vector3::new(0.0, 0.0, 0.0),
        }
    }

    /// Whether time, position and velocity are all finite.
    #[must_use]
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.time_s.is_finite()
            && self.position_m.iter().all(|v| v.is_finite())
            && self.velocity_mps.iter().all(|v| v.is_finite())
    }

    /// Airspeed `sqrt(vx² + vy² + vz²)`, m/s (no wind, so also the ground-relative
    /// speed). Same operation order as the model's `vtotal`.
    #[must_use]
    #[inline]
    pub fn airspeed_mps(&self) -> f64 {
        let [vx, vy, vz] = self.velocity();
        sqrt(vx * vx + vy * vy + vz * vz)
    }

    /// Climb angle `atan(vz / vh)` with `vh = sqrt(vx² + vy²)`, degrees; 0 when
    /// `vh == 0` (at rest, or moving straight up or down).
    #[must_use]
    #[inline]
    pub fn climb_angle_deg(&self) -> f64 {
        let [vx, vy, vz] = self.velocity();
        let vh = sqrt(vx * vx + vy * vy);
        if vh == 0.0 {
            0.0
        } else {
            atan(vz / vh) * 180.0 / PI
        }
    }

    /// Climb rate `vz`, m/s (positive up).
    #[must_use]
    #[inline]
    pub fn climb_rate_mps(&self) -> f64 {
        self.velocity_mps.z
    }

    /// Heading angle of the book: the direction of `(vx, vy)` measured from +x
    /// toward +y (north toward west, i.e. counter-clockwise seen from above),
    /// degrees in `[0, 360)`; 0 when not moving horizontally.
    ///
    /// This is `atan2(vy, vx)` mapped into `[0, 360)`, equivalent to the book's
    /// quadrant-by-quadrant computation. For a compass heading use
    /// [`PalmerState::compass_heading_deg`].
    #[must_use]
    #[inline]
    pub fn heading_deg(&self) -> f64 {
        let (vx, vy) = (self.velocity_mps.x, self.velocity_mps.y);
        // Like the model's `cosT = 1, sinT = 0` when `vh == 0` (atan2 would give
        // 180 for `(-0.0, 0.0)`).
        if vx == 0.0 && vy == 0.0 {
            return 0.0;
        }
        let mut radians = atan2(vy, vx);
        if radians < 0.0 {
            radians += 2.0 * PI;
        }
        wrap_degrees_360(radians * 180.0 / PI)
    }

    /// Compass heading: clockwise from north (+x), degrees in `[0, 360)`; 90 is
    /// east (-y). This is `-heading_deg()` mod 360, what FlightGear expects.
    #[must_use]
    #[inline]
    pub fn compass_heading_deg(&self) -> f64 {
        compass_from_heading_deg(self.heading_deg())
    }

    /// Straight-line (3-D) distance from the earth-frame origin, the starting
    /// point of a run, m.
    #[must_use]
    #[inline]
    pub fn distance_from_origin_m(&self) -> f64 {
        let [x, y, z] = [self.position_m.x, self.position_m.y, self.position_m.z];
        sqrt(x * x + y * y + z * z)
    }

    /// Altitude `z` above the ground plane, m.
    #[must_use]
    #[inline]
    pub fn altitude_m(&self) -> f64 {
        self.position_m.z
    }

    /// All derived flight data at once.
    #[must_use]
    #[inline]
    pub fn flight_data(&self) -> FlightData {
        flight_data(self)
    }

    #[inline]
    fn velocity(&self) -> [f64; 3] {
        [
            self.velocity_mps.x,
            self.velocity_mps.y,
            self.velocity_mps.z,
        ]
    }
}

impl Default for PalmerState {
    /// [`PalmerState::at_rest`].
    fn default() -> Self {
        Self::at_rest()
    }
}

/// Converts the book's heading (counter-clockwise from +x toward +y, degrees) to
/// a compass heading (clockwise from north, degrees in `[0, 360)`):
/// `-heading` mod 360.
///
/// ```
/// use fdm_core::palmer::compass_from_heading_deg;
///
/// assert_eq!(compass_from_heading_deg(0.0), 0.0);
/// assert_eq!(compass_from_heading_deg(90.0), 270.0); // flying west
/// assert_eq!(compass_from_heading_deg(270.0), 90.0); // flying east
/// ```
#[must_use]
#[inline]
pub fn compass_from_heading_deg(heading_deg: f64) -> f64 {
    wrap_degrees_360(-heading_deg)
}

/// Flight data derived from a [`PalmerState`] (what the book's GUI versions
/// display). See the same-named methods of [`PalmerState`] for definitions.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct FlightData {
    /// Airspeed, m/s (× 3.6 for km/h).
    pub airspeed_mps: f64,
    /// Climb angle, degrees (0 when not moving horizontally).
    pub climb_angle_deg: f64,
    /// Climb rate `vz`, m/s.
    pub climb_rate_mps: f64,
    /// Heading from +x toward +y, degrees in `[0, 360)`.
    pub heading_deg: f64,
    /// Compass heading, clockwise from north, degrees in `[0, 360)`.
    pub compass_heading_deg: f64,
    /// Straight-line distance from the origin, m.
    pub distance_from_origin_m: f64,
    /// Altitude `z`, m.
    pub altitude_m: f64,
}

/// Computes every [`FlightData`] field from `state`.
#[must_use]
#[inline]
pub fn flight_data(state: &PalmerState) -> FlightData {
    let heading_deg = state.heading_deg();
    FlightData {
        airspeed_mps: state.airspeed_mps(),
        climb_angle_deg: state.climb_angle_deg(),
        climb_rate_mps: state.climb_rate_mps(),
        heading_deg,
        compass_heading_deg: compass_from_heading_deg(heading_deg),
        distance_from_origin_m: state.distance_from_origin_m(),
        altitude_m: state.altitude_m(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moving(vx: f64, vy: f64, vz: f64) -> PalmerState {
        PalmerState {
            velocity_mps: Vector3::new(vx, vy, vz),
            ..PalmerState::at_rest()
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    #[test]
    fn at_rest_is_default_and_zero() {
        let s = PalmerState::default();
        assert_eq!(s, PalmerState::at_rest());
        assert_eq!(s.time_s, 0.0);
        assert_eq!(s.position_m, Vector3::zeros());
        assert_eq!(s.velocity_mps, Vector3::zeros());
        let d = s.flight_data();
        assert_eq!(d, FlightData::default());
    }

    #[test]
    fn airspeed_and_distance() {
        let s = moving(3.0, -4.0, 12.0);
        assert_eq!(s.airspeed_mps(), 13.0);
        let s = PalmerState {
            position_m: Vector3::new(2.0, 3.0, 6.0),
            ..s
        };
        assert_eq!(s.distance_from_origin_m(), 7.0);
        assert_eq!(s.altitude_m(), 6.0);
        assert_eq!(s.climb_rate_mps(), 12.0);
    }

    /// The straight-line distance `sqrt(x² + y² + z²)` from the origin, on
    /// whole-number triples whose distance is a whole number (exact in
    /// `f64`), none of the coordinates 2 (where `2 · 2`
    /// and `2 + 2` agree), with mixed signs.
    #[test]
    fn distance_is_the_straight_line_from_the_origin() {
        for ([x, y, z], d) in [
            ([1.0, 4.0, 8.0], 9.0),
            ([-8.0, 1.0, -4.0], 9.0),
            ([4.0, -7.0, 4.0], 9.0),
            ([-12.0, -3.0, 4.0], 13.0),
            ([0.0, 0.0, -5.0], 5.0),
        ] {
            let s = PalmerState {
                position_m: Vector3::new(x, y, z),
                ..PalmerState::at_rest()
            };
            assert_eq!(s.distance_from_origin_m(), d, "({x}, {y}, {z})");
            assert_eq!(s.flight_data().distance_from_origin_m, d);
        }
    }

    #[test]
    fn climb_angle() {
        assert!(close(moving(10.0, 0.0, 10.0).climb_angle_deg(), 45.0));
        assert!(close(moving(0.0, -10.0, -10.0).climb_angle_deg(), -45.0));
        assert_eq!(moving(5.0, 0.0, 0.0).climb_angle_deg(), 0.0);
        // vh == 0: defined as 0 even when moving vertically.
        assert_eq!(moving(0.0, 0.0, 7.0).climb_angle_deg(), 0.0);
    }

    #[test]
    fn heading_quadrants() {
        let cases = [
            // (vx, vy) -> heading (from +x toward +y), compass
            ((1.0, 0.0), 0.0, 0.0),
            ((1.0, 1.0), 45.0, 315.0),
            ((0.0, 1.0), 90.0, 270.0),
            ((-1.0, 1.0), 135.0, 225.0),
            ((-1.0, 0.0), 180.0, 180.0),
            ((-1.0, -1.0), 225.0, 135.0),
            ((0.0, -1.0), 270.0, 90.0),
            ((1.0, -1.0), 315.0, 45.0),
        ];
        for ((vx, vy), heading, compass) in cases {
            let s = moving(vx, vy, 0.0);
            assert!(
                close(s.heading_deg(), heading),
                "({vx}, {vy}): {}",
                s.heading_deg()
            );
            assert!(
                close(s.compass_heading_deg(), compass),
                "({vx}, {vy}): {}",
                s.compass_heading_deg()
            );
            let d = s.flight_data();
            assert_eq!(d.heading_deg, s.heading_deg());
            assert_eq!(d.compass_heading_deg, s.compass_heading_deg());
        }
    }

    #[test]
    fn heading_stays_in_range_at_the_edges() {
        // Not moving, or -0.0 components: 0, never -0.0.
        for (vx, vy) in [(0.0, 0.0), (0.0, -0.0), (1.0, -0.0), (-0.0, 0.0)] {
            let h = moving(vx, vy, 0.0).heading_deg();
            assert_eq!(h.to_bits(), 0.0_f64.to_bits(), "({vx}, {vy})");
            let c = moving(vx, vy, 0.0).compass_heading_deg();
            assert_eq!(c.to_bits(), 0.0_f64.to_bits(), "({vx}, {vy})");
        }
        // Just south of +x, turning toward -y: just below 360, not 360.
        let h = moving(1.0, -1e-300, 0.0).heading_deg();
        assert!((0.0..360.0).contains(&h), "{h}");
        let c = moving(1.0, 1e-300, 0.0).compass_heading_deg();
        assert!((0.0..360.0).contains(&c), "{c}");
        assert!(moving(-1.0, -0.0, 0.0).heading_deg() == 180.0);
    }

    /// A heading a hair north-west of +x (a small positive angle) keeps its
    /// relative precision: `atan2` of it is the angle itself and the degrees
    /// are two roundings away, so within 1e-14 of `(vy / vx) · 180 / π`
    /// (`atan(x) = x` to double precision below 1e-8). Mapping it into
    /// `[0, 360)` by way of 360 (`+ 2π`, then `- 360`) would keep only the
    /// absolute precision of 360, about 6e-14°, a relative error near 1e-5.
    #[test]
    fn a_small_heading_keeps_its_precision() {
        for vy in [1e-10, 3.5e-12, 1e-300] {
            let h = moving(1.0, vy, 0.0).heading_deg();
            let want = vy * 180.0 / PI;
            assert!(
                (h - want).abs() <= 1e-14 * want,
                "vy {vy}: heading {h}, want {want}"
            );
        }
    }

    /// The heading's bits are part of what a replay prints: rows of the
    /// golden replay CSV of the committed Palmer recording
    /// (`sim-cli/tests/golden/palmer_v3.replay.csv`, replayed bit for bit by
    /// `sim-cli/tests/golden.rs`, docs/recording.md), flying slightly east of
    /// north (`atan2 < 0`). Other orders of the same mapping into
    /// `[0, 360)` (adding 360° after the conversion to degrees, or taking
    /// 2π away instead of adding it) are as accurate to a few ulps but give
    /// other bits for up to 104 of that file's 151 rows. Exact (the CSV
    /// prints the shortest text that reads back as the same `f64`).
    #[test]
    fn headings_are_the_golden_replays_bits() {
        let rows = [
            // frame, vx, vy, heading_deg
            (
                30,
                "51.450835860914985",
                "-0.005154416180565983",
                "359.99426002926737",
            ),
            (
                33,
                "51.41836807430152",
                "-0.051481215575198955",
                "359.94263420832846",
            ),
            (
                143,
                "43.910433694847185",
                "-2.088809951805195",
                "357.27650508669814",
            ),
        ];
        for (frame, vx, vy, heading) in rows {
            let [vx, vy, heading]: [f64; 3] = [vx, vy, heading].map(|t| t.parse().unwrap());
            let h = moving(vx, vy, 0.0).heading_deg();
            assert_eq!(h.to_bits(), heading.to_bits(), "frame {frame}: {h}");
        }
    }

    #[test]
    fn compass_conversion() {
        assert_eq!(compass_from_heading_deg(0.0), 0.0);
        assert_eq!(compass_from_heading_deg(90.0), 270.0);
        assert_eq!(compass_from_heading_deg(180.0), 180.0);
        assert_eq!(compass_from_heading_deg(270.0), 90.0);
        assert_eq!(compass_from_heading_deg(359.5), 0.5);
        assert_eq!(compass_from_heading_deg(720.0), 0.0);
        assert!(compass_from_heading_deg(f64::NAN).is_nan());
    }

    #[test]
    fn serde_round_trip() {
        let s = PalmerState {
            time_s: 1.5,
            position_m: Vector3::new(1.0, -2.0, 3.25),
            velocity_mps: Vector3::new(40.0, 0.1, -0.5),
        };
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(
            json,
            r#"{"time_s":1.5,"position_m":[1.0,-2.0,3.25],"velocity_mps":[40.0,0.1,-0.5]}"#
        );
        assert_eq!(serde_json::from_str::<PalmerState>(&json).unwrap(), s);
    }
}
