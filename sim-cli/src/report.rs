//! The model state as the CLI sees it ([`Snapshot`]), and the `--headless --json`
//! final report built from it ([`Report`], cli.md "Headless JSON report").
//!
//! # Numbers
//! serde_json writes `f64` with the shortest representation that parses back to the
//! same bits (ryu). That is the "17 significant digits" guarantee of cli.md without
//! the noise digits: any correctly rounding parser (Python's `json`, Rust's `str::parse`)
//! gets the identical `f64` back. The tests below check this on random bit patterns.
//! Bourg's `f32` values are widened with `f64::from`, which is exact, so the printed
//! number is the `f32` value itself and `x as f32` on the parsed number restores it.
//! Non-finite numbers (a diverged model) are written as JSON `null`, because JSON
//! has no NaN or infinity.
//!
//! Readers in Rust: serde_json's own parser is correctly rounded only with its
//! `float_roundtrip` feature (enabled by this crate); without it, values can come back
//! one ulp off (seen in this module's tests, e.g. 1234.5678901234567).

use serde::{Deserialize, Serialize};

/// Geodetic position as sent to FlightGear.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GeodeticReport {
    /// Latitude, degrees north.
    pub lat_deg: f64,
    /// Longitude, degrees east.
    pub lon_deg: f64,
    /// Altitude above the WGS-84 ellipsoid, metres.
    pub alt_m: f64,
}

/// Attitude as sent to FlightGear, degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AttitudeReport {
    /// Roll, right wing down positive.
    pub roll: f64,
    /// Pitch, nose up positive.
    pub pitch: f64,
    /// Heading, clockwise from true north, in [0, 360).
    pub heading: f64,
}

/// The part of the state both models have.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CommonState {
    /// Simulated time, seconds: Palmer's own clock (the sum of its f64 steps, so
    /// 600 steps of 0.1 s give 60.00000000000058); for Bourg, whose model keeps no
    /// clock, frames since the start (or the last reset) / fps.
    pub time_s: f64,
    /// Position [x, y, z] in the model's earth frame (x north, y west, z up);
    /// Palmer metres, Bourg feet.
    pub position: [f64; 3],
    /// Velocity [vx, vy, vz] in the same frame; Palmer m/s, Bourg ft/s.
    pub velocity: [f64; 3],
    /// Geodetic position.
    pub geodetic: GeodeticReport,
    /// Attitude as sent to FlightGear.
    pub attitude_deg: AttitudeReport,
}

/// Palmer's controls as the model holds them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerControlsReport {
    /// Throttle fraction, 0..1.
    pub throttle: f64,
    /// Angle of attack, degrees.
    pub alpha_deg: f64,
    /// Bank, degrees, positive right.
    pub bank_deg: f64,
    /// Flap setting, degrees (0, 20 or 40).
    pub flaps_deg: f64,
}

/// Palmer-only state (all `f64` in the model).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerDetails {
    /// Airspeed, m/s.
    pub airspeed: f64,
    /// Current controls.
    pub controls: PalmerControlsReport,
    /// Climb angle, degrees.
    pub climb_angle_deg: f64,
    /// Climb rate (vz), m/s.
    pub climb_rate: f64,
    /// The model's heading angle, degrees in [0, 360), measured from +x toward +y
    /// (i.e. toward the west; not a compass heading, see `attitude_deg.heading`).
    pub heading_deg: f64,
}

/// Bourg-only state. The model is `f32`; every float here is the model's `f32`
/// widened exactly with `f64::from` (see [`widen`], [`widen3`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgDetails {
    /// Speed |velocity|, ft/s.
    pub speed: f64,
    /// Euler angles [x roll, y pitch (positive nose-down), z yaw] in degrees, exactly as
    /// `MakeEulerAnglesFromQ` computes them.
    pub euler_deg: [f64; 3],
    /// Thrust, lb.
    pub thrust_lb: f64,
    /// Landing flaps down.
    pub flaps: bool,
    /// Any wing element past its stall angle on the last step.
    pub stalling: bool,
}

/// The model-specific part; serialised with the `model` tag ("palmer" / "bourg")
/// next to the variant's fields, so the tag and the fields can never disagree.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum ModelDetails {
    /// Palmer's Cessna 172.
    Palmer(PalmerDetails),
    /// Bourg's 6-DoF aircraft.
    Bourg(BourgDetails),
}

/// Everything the CLI needs to know about the model at one instant: the seam the
/// integrator fills from the ECS world once per frame (see `Flight::snapshot`).
/// The JSON report, the CSV rows and the HUD are all derived from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot {
    /// State both models have.
    pub common: CommonState,
    /// Model-specific state.
    pub details: ModelDetails,
}

/// The `--headless --json` report: one JSON object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// `model` plus the model-specific fields.
    #[serde(flatten)]
    pub details: ModelDetails,
    /// Frames per second of the run (dt = 1/fps), a whole number.
    pub fps: u32,
    /// Frames stepped.
    pub frames: u64,
    /// The state both models have.
    #[serde(flatten)]
    pub common: CommonState,
}

impl Report {
    /// The report of a run of `frames` frames at `fps` ending in `snapshot`.
    #[must_use]
    pub fn new(fps: u32, frames: u64, snapshot: &Snapshot) -> Self {
        Self {
            details: snapshot.details,
            fps,
            frames,
            common: snapshot.common,
        }
    }

    /// The model name ("palmer" or "bourg").
    #[must_use]
    pub fn model_name(&self) -> &'static str {
        self.details.model_name()
    }

    /// The report as one line of JSON.
    ///
    /// # Errors
    /// Only if serde_json fails, which it does not for these types.
    pub fn to_json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }

    /// A short human-readable summary (several lines, no trailing newline), for
    /// headless runs without `--json`.
    #[must_use]
    pub fn human_summary(&self) -> String {
        let c = &self.common;
        let unit = match self.details {
            ModelDetails::Palmer(_) => "m",
            ModelDetails::Bourg(_) => "ft",
        };
        let mut s = format!(
            "{}: {} frames at {} fps, t = {} s\n\
             position  x {:.3}  y {:.3}  z {:.3} {unit}\n\
             velocity  x {:.3}  y {:.3}  z {:.3} {unit}/s\n\
             geodetic  lat {:.7}  lon {:.7}  alt {:.2} m\n\
             attitude  roll {:.2}  pitch {:.2}  heading {:.2} deg",
            self.model_name(),
            self.frames,
            self.fps,
            c.time_s,
            c.position[0],
            c.position[1],
            c.position[2],
            c.velocity[0],
            c.velocity[1],
            c.velocity[2],
            c.geodetic.lat_deg,
            c.geodetic.lon_deg,
            c.geodetic.alt_m,
            hundredths(c.attitude_deg.roll),
            hundredths(c.attitude_deg.pitch),
            heading_2dp(c.attitude_deg.heading),
        );
        match self.details {
            ModelDetails::Palmer(p) => s.push_str(&format!(
                "\nairspeed  {:.3} m/s  climb {:.2} deg, {:.3} m/s\n\
                 controls  throttle {:.0} %  alpha {} deg  bank {} deg  flaps {} deg",
                p.airspeed,
                p.climb_angle_deg,
                p.climb_rate,
                p.controls.throttle * 100.0,
                p.controls.alpha_deg,
                p.controls.bank_deg,
                p.controls.flaps_deg,
            )),
            ModelDetails::Bourg(b) => s.push_str(&format!(
                "\nspeed     {:.3} ft/s  thrust {} lb  flaps {}  stalling {}",
                b.speed,
                b.thrust_lb,
                if b.flaps { "down" } else { "up" },
                if b.stalling { "yes" } else { "no" },
            )),
        }
        s
    }
}

/// `x` for a display with two decimals, except that values that show as zero are
/// +0.0 (no "-0.00").
fn hundredths(x: f64) -> f64 {
    if (x * 100.0).round() == 0.0 {
        0.0
    } else {
        x
    }
}

/// A heading in [0, 360) rounded to 0.01 degree for display, wrapping so that
/// 359.996 shows as 0.00 rather than 360.00.
fn heading_2dp(deg: f64) -> f64 {
    let rounded = (deg * 100.0).round() / 100.0;
    if rounded >= 360.0 {
        rounded - 360.0
    } else {
        rounded
    }
}

impl ModelDetails {
    /// The model name ("palmer" or "bourg"), as in the JSON `model` field.
    #[must_use]
    pub fn model_name(&self) -> &'static str {
        match self {
            Self::Palmer(_) => "palmer",
            Self::Bourg(_) => "bourg",
        }
    }
}

/// Widens an `f32` to `f64` exactly (every `f32` is an `f64`), for Bourg's values.
#[must_use]
pub fn widen(x: f32) -> f64 {
    f64::from(x)
}

/// Widens an `f32` vector to `f64` exactly.
#[must_use]
pub fn widen3(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

/// CSV column names (after `frame,time_s`) of a Palmer snapshot, in row order.
pub const PALMER_CSV_COLUMNS: &[&str] = &[
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "lat_deg",
    "lon_deg",
    "alt_m",
    "roll_deg",
    "pitch_deg",
    "fg_heading_deg",
    "airspeed",
    "throttle",
    "alpha_deg",
    "bank_deg",
    "flaps_deg",
    "climb_angle_deg",
    "climb_rate",
    "heading_deg",
];

/// CSV column names (after `frame,time_s`) of a Bourg snapshot, in row order.
/// `flaps` and `stalling` are written as 0 or 1.
pub const BOURG_CSV_COLUMNS: &[&str] = &[
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "lat_deg",
    "lon_deg",
    "alt_m",
    "roll_deg",
    "pitch_deg",
    "fg_heading_deg",
    "speed",
    "euler_x_deg",
    "euler_y_deg",
    "euler_z_deg",
    "thrust_lb",
    "flaps",
    "stalling",
];

impl crate::csv::CsvRecord for Snapshot {
    fn csv_columns(&self) -> &'static [&'static str] {
        match self.details {
            ModelDetails::Palmer(_) => PALMER_CSV_COLUMNS,
            ModelDetails::Bourg(_) => BOURG_CSV_COLUMNS,
        }
    }

    fn time_s(&self) -> f64 {
        self.common.time_s
    }

    fn csv_values(&self, out: &mut Vec<f64>) {
        let c = &self.common;
        out.extend_from_slice(&c.position);
        out.extend_from_slice(&c.velocity);
        out.extend_from_slice(&[
            c.geodetic.lat_deg,
            c.geodetic.lon_deg,
            c.geodetic.alt_m,
            c.attitude_deg.roll,
            c.attitude_deg.pitch,
            c.attitude_deg.heading,
        ]);
        match &self.details {
            ModelDetails::Palmer(p) => out.extend_from_slice(&[
                p.airspeed,
                p.controls.throttle,
                p.controls.alpha_deg,
                p.controls.bank_deg,
                p.controls.flaps_deg,
                p.climb_angle_deg,
                p.climb_rate,
                p.heading_deg,
            ]),
            ModelDetails::Bourg(b) => {
                out.push(b.speed);
                out.extend_from_slice(&b.euler_deg);
                out.extend_from_slice(&[
                    b.thrust_lb,
                    f64::from(u8::from(b.flaps)),
                    f64::from(u8::from(b.stalling)),
                ]);
            }
        }
    }
}

/// Sample snapshots for tests of the modules built on [`Snapshot`].
#[cfg(test)]
pub(crate) mod samples {
    use super::*;

    fn common() -> CommonState {
        CommonState {
            time_s: 60.000000000000746,
            position: [1234.5678901234567, -0.1, 98.76],
            velocity: [55.5, 1e-20, -0.25],
            geodetic: GeodeticReport {
                lat_deg: 39.8375,
                lon_deg: -84.0483,
                alt_m: 349.76,
            },
            attitude_deg: AttitudeReport {
                roll: 5.0,
                pitch: 2.5,
                heading: 359.5,
            },
        }
    }

    pub(crate) fn palmer() -> Snapshot {
        Snapshot {
            common: common(),
            details: ModelDetails::Palmer(PalmerDetails {
                airspeed: 55.6,
                controls: PalmerControlsReport {
                    throttle: 0.75,
                    alpha_deg: 4.0,
                    bank_deg: 5.0,
                    flaps_deg: 20.0,
                },
                climb_angle_deg: 3.1,
                climb_rate: 2.9,
                heading_deg: 0.5,
            }),
        }
    }

    pub(crate) fn bourg() -> Snapshot {
        Snapshot {
            common: common(),
            details: ModelDetails::Bourg(BourgDetails {
                speed: widen(183.123_46_f32),
                euler_deg: widen3([0.1_f32, -2.5, -0.3]),
                thrust_lb: 3000.0,
                flaps: true,
                stalling: false,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::samples::{bourg, palmer};
    use super::*;
    use crate::csv::CsvRecord;

    /// xorshift64*: a tiny deterministic generator so the tests need no extra crates.
    fn next(state: &mut u64) -> u64 {
        *state ^= *state >> 12;
        *state ^= *state << 25;
        *state ^= *state >> 27;
        state.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    #[test]
    fn palmer_report_has_the_contract_fields() {
        let v = serde_json::to_value(Report::new(10, 600, &palmer())).unwrap();
        for key in [
            "model",
            "fps",
            "frames",
            "time_s",
            "position",
            "velocity",
            "geodetic",
            "attitude_deg",
            "airspeed",
            "controls",
            "climb_angle_deg",
            "climb_rate",
            "heading_deg",
        ] {
            assert!(v.get(key).is_some(), "missing {key}");
        }
        assert_eq!(v["model"], "palmer");
        assert_eq!(v["frames"], 600);
        // A whole number: the integer 10, not 10.0.
        assert!(v["fps"].is_u64() && v["fps"] == 10, "{}", v["fps"]);
        assert_eq!(v["geodetic"]["alt_m"], 349.76);
        assert_eq!(v["attitude_deg"]["heading"], 359.5);
        assert_eq!(v["controls"]["flaps_deg"], 20.0);
        assert_eq!(v["position"][0], 1234.5678901234567);
        assert!(v.get("speed").is_none());
    }

    #[test]
    fn bourg_report_has_the_contract_fields() {
        let v = serde_json::to_value(Report::new(30, 900, &bourg())).unwrap();
        for key in [
            "model",
            "fps",
            "frames",
            "time_s",
            "position",
            "velocity",
            "geodetic",
            "attitude_deg",
            "speed",
            "euler_deg",
            "thrust_lb",
            "flaps",
            "stalling",
        ] {
            assert!(v.get(key).is_some(), "missing {key}");
        }
        assert_eq!(v["model"], "bourg");
        assert_eq!(v["flaps"], true);
        assert_eq!(v["stalling"], false);
        assert!(v.get("airspeed").is_none());
        // The widened f32 prints as the f32's exact value: narrowing restores it.
        assert_eq!(v["speed"].as_f64().unwrap() as f32, 183.123_46_f32);
    }

    #[test]
    fn report_json_round_trips_through_serde() {
        for snap in [palmer(), bourg()] {
            let report = Report::new(30, 7, &snap);
            let json = report.to_json().unwrap();
            assert!(!json.contains('\n'));
            let back: Report = serde_json::from_str(&json).unwrap();
            assert_eq!(back, report);
        }
    }

    #[test]
    fn f64_output_round_trips_bit_exactly() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut values: Vec<f64> = vec![
            0.1,
            1.0 / 3.0,
            -0.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::EPSILON,
            123_456_789.123_456_79,
        ];
        while values.len() < 200_000 {
            let x = f64::from_bits(next(&mut state));
            if x.is_finite() {
                values.push(x);
            }
        }
        for x in values {
            let text = serde_json::to_string(&x).unwrap();
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} printed as {text}");
            let back: f64 = serde_json::from_str(&text).unwrap();
            assert_eq!(
                back.to_bits(),
                x.to_bits(),
                "serde_json read {text} as {back:e}"
            );
            // Never more digits than the 17 significant digits cli.md allows for.
            let digits = text
                .split(['e', 'E'])
                .next()
                .unwrap()
                .chars()
                .filter(char::is_ascii_digit)
                .collect::<String>();
            assert!(digits.trim_start_matches('0').len() <= 17, "{text}");
        }
    }

    #[test]
    fn widened_f32_output_round_trips() {
        let mut state = 0x1234_5678_9abc_def1_u64;
        for _ in 0..100_000 {
            let x = f32::from_bits(next(&mut state) as u32);
            if !x.is_finite() {
                continue;
            }
            let wide = widen(x);
            let text = serde_json::to_string(&wide).unwrap();
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), wide.to_bits(), "{text}");
            assert_eq!((back as f32).to_bits(), x.to_bits(), "{text}");
        }
    }

    #[test]
    fn non_finite_numbers_become_null() {
        let mut snap = palmer();
        snap.common.position[2] = f64::NAN;
        let v = serde_json::to_value(Report::new(30, 1, &snap)).unwrap();
        assert!(v["position"][2].is_null());
    }

    #[test]
    fn csv_columns_match_values() {
        for snap in [palmer(), bourg()] {
            let mut values = Vec::new();
            snap.csv_values(&mut values);
            assert_eq!(values.len(), snap.csv_columns().len());
        }
        let mut values = Vec::new();
        bourg().csv_values(&mut values);
        assert_eq!(&values[values.len() - 2..], &[1.0, 0.0]);
    }

    #[test]
    fn human_summary_mentions_model_and_units() {
        let s = Report::new(30, 900, &bourg()).human_summary();
        assert!(s.starts_with("bourg: 900 frames at 30 fps"));
        assert!(s.contains("ft/s"));
        let s = Report::new(10, 600, &palmer()).human_summary();
        assert!(s.contains("throttle 75 %"));
        let mut snap = bourg();
        snap.common.attitude_deg.heading = 359.999_999;
        snap.common.attitude_deg.roll = -1e-9;
        let s = Report::new(30, 1, &snap).human_summary();
        assert!(s.contains("roll 0.00  pitch 2.50  heading 0.00 deg"), "{s}");
    }
}
