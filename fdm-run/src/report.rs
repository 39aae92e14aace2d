//! What a run reports when it ends: the final [`Report`] (one JSON object,
//! `sim-cli --headless --json`, docs/cli.md "Headless JSON report", and its
//! human summary), built from a [`Snapshot`] of the run ([`Run::snapshot`]):
//! the state every model has ([`CommonState`]: clock, position and velocity
//! in the model's unit, WGS-84 position, attitude) and the model's own
//! fields, its [`Details`] ([`ReportModel`]).
//!
//! # Numbers
//! serde_json writes `f64` with the shortest representation that parses back to the
//! same bits (ryu). That is the "17 significant digits" guarantee of docs/cli.md without
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

use std::fmt::Debug;

use fdm_core::model::{DisplayStatus, FlightStatus};
use fdm_core::units::METRES_PER_FOOT;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::csv::CsvModel;
use crate::{LinkStats, Run};

/// A model whose runs report their end ([`Report`]): its own report
/// fields, taken from its aircraft, controls and state.
pub trait ReportModel: CsvModel {
    /// The model's own report fields (JSON next to the common ones, a
    /// summary line).
    type Details: Details;

    /// The model's report fields now.
    fn details(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        state: &Self::State,
    ) -> Self::Details;
}

/// A model's own report fields.
pub trait Details: Serialize + DeserializeOwned + Copy + Debug + PartialEq {
    /// The JSON `model` field (the model's name): `"palmer"`, `"bourg"`.
    const MODEL: &'static str;
    /// The unit of the native position: `"m"` or `"ft"`.
    const POSITION_UNIT: &'static str;

    /// The human summary's model-specific line(s), without a trailing newline.
    fn summary(&self) -> String;
}

impl<M: ReportModel> Run<M> {
    /// The run's state, view and placement ([`Run::placement`]: NaN if the
    /// aircraft were gone) as a report sees them (the start's before the
    /// first frame).
    #[must_use]
    pub fn snapshot(&self) -> Snapshot<M::Details> {
        let start = &self.scenario().start;
        let state = self.state().unwrap_or(start.state);
        let controls = self.controls().unwrap_or(start.controls);
        let view = self.view();
        let crate::Placement { geodetic, attitude } = self.placement();
        Snapshot {
            common: CommonState {
                time_s: view.time_s,
                position: M::native_position(&state),
                velocity: M::native_velocity(&state),
                geodetic: GeodeticReport {
                    lat_deg: geodetic.lat_deg,
                    lon_deg: geodetic.lon_deg,
                    alt_m: geodetic.alt_m,
                },
                attitude_deg: AttitudeReport {
                    roll: attitude.roll_deg,
                    pitch: attitude.pitch_deg,
                    heading: attitude.heading_deg,
                },
            },
            details: M::details(&start.aircraft, &controls, &state),
            status: self.status(),
            stalling: view.stalling,
            airspeed_mps: view.airspeed_mps,
        }
    }
}

/// The `--headless --json` report: one JSON object, the model's fields next to
/// the common ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(bound = "D: Details")]
pub struct Report<D> {
    /// The model's name, `"palmer"` or `"bourg"` ([`Details::MODEL`]).
    pub model: String,
    /// The model-specific fields.
    #[serde(flatten)]
    pub details: D,
    /// Frames per second of the run (dt = 1/fps), a whole number.
    pub fps: u32,
    /// Frames stepped.
    pub frames: u64,
    /// The flight status at the end: `on_ground`, `airborne`, `landed_safe`,
    /// `landed_rough`, `crashed`, or `stalling` ([`Snapshot::status_code`]).
    pub status: String,
    /// The state both models have.
    #[serde(flatten)]
    pub common: CommonState,
    /// FlightGear datagram counters, when the run had `--fg`: datagrams
    /// handed to the OS and sends that failed (e.g. "connection refused"
    /// reported back for an earlier datagram).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fg: Option<LinkStats>,
    /// Real-time pacing, when the run had `--realtime`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub realtime: Option<RealtimeReport>,
    /// DIS output counters, when the run had `--dis` (`dis::DisReport`,
    /// feature `dis`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg(feature = "dis")]
    pub dis: Option<crate::dis::DisReport>,
}

/// The JSON report's `realtime` object (the run library's, shared with
/// `sim-cli fleet`'s report).
pub use crate::pacer::RealtimeReport;

impl<D: Details> Report<D> {
    /// The report of a run of `frames` frames at `fps` ending in `snapshot`.
    #[must_use]
    pub fn new(fps: u32, frames: u64, snapshot: &Snapshot<D>) -> Self {
        Self {
            model: D::MODEL.to_owned(),
            details: snapshot.details,
            fps,
            frames,
            status: snapshot.status_code().to_owned(),
            common: snapshot.common,
            fg: None,
            realtime: None,
            #[cfg(feature = "dis")]
            dis: None,
        }
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
        let unit = D::POSITION_UNIT;
        format!(
            "{}: {} frames at {} fps, t = {:.*} s\n\
             status    {}\n\
             position  x {:.3}  y {:.3}  z {:.3} {unit}\n\
             velocity  x {:.3}  y {:.3}  z {:.3} {unit}/s\n\
             geodetic  lat {:.7}  lon {:.7}  alt {:.2} m\n\
             attitude  roll {:.2}  pitch {:.2}  heading {:.2} deg\n{}{}",
            self.model,
            self.frames,
            self.fps,
            frame_decimals(self.fps),
            c.time_s,
            self.status,
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
            self.details.summary(),
            self.outputs_summary(),
        )
    }
}

/// Decimals that resolve one frame of `fps` in a time display: at least 2
/// (`t = 240.00 s`), 3 above 100 fps, 4 above 1000 fps. The human summary
/// rounds the model's clock (a sum of time steps, so 239.99999999998894 after
/// 7200 steps of 1/30 s) to that; the JSON report keeps every digit.
#[must_use]
pub fn frame_decimals(fps: u32) -> usize {
    match fps {
        0..=100 => 2,
        101..=1000 => 3,
        _ => 4,
    }
}

impl<D> Report<D> {
    /// The summary lines of the FlightGear counters and the pacing, if any.
    fn outputs_summary(&self) -> String {
        let mut s = String::new();
        if let Some(fg) = self.fg {
            s.push_str(&format!(
                "\nflightgear  {} datagrams sent, {} failed",
                fg.sent, fg.failed
            ));
        }
        if let Some(rt) = self.realtime {
            s.push_str(&format!("\nrealtime  {} overruns", rt.overruns));
        }
        #[cfg(feature = "dis")]
        if let Some(dis) = &self.dis {
            s.push('\n');
            s.push_str(&dis.summary());
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

/// The part of the state every model has.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CommonState {
    /// Simulated time, seconds: the model's own clock, the sum of its time
    /// steps (Palmer's `f64` steps: 600 steps of 0.1 s give
    /// 60.00000000000058; Bourg's `f32` steps widened: 900 steps of
    /// `1.0f32 / 30.0` give 30.000001430511475).
    pub time_s: f64,
    /// Position [x, y, z] in the model's earth frame (x north, y west, z up),
    /// in the model's own unit (Palmer metres, Bourg feet).
    pub position: [f64; 3],
    /// Velocity [vx, vy, vz] in the same frame and unit per second.
    pub velocity: [f64; 3],
    /// Geodetic position.
    pub geodetic: GeodeticReport,
    /// Attitude as sent to FlightGear.
    pub attitude_deg: AttitudeReport,
}

/// Everything the CLI needs to know about the aircraft at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot<D> {
    /// State every model has.
    pub common: CommonState,
    /// The model's own fields.
    pub details: D,
    /// Where the aircraft is in its flight (on the ground, flying, landed).
    pub status: FlightStatus,
    /// Whether the model reports a stall.
    pub stalling: bool,
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
}

impl<D> Snapshot<D> {
    /// The status and stall as displayed: the one vocabulary of labels
    /// (HUD, plot), codes (JSON report) and numbers (CSV `status` column),
    /// [`DisplayStatus`].
    #[must_use]
    pub fn display_status(&self) -> DisplayStatus {
        DisplayStatus::new(self.status, self.stalling)
    }

    /// The status as one word, for the JSON report's `status`
    /// ([`DisplayStatus::code`]).
    #[must_use]
    pub fn status_code(&self) -> &'static str {
        self.display_status().code()
    }
}

/// The flight status and stall flag of a CSV `status` number
/// ([`DisplayStatus::from_number`]); `None` for any other number.
#[must_use]
pub fn status_from_number(x: f64) -> Option<(FlightStatus, bool)> {
    DisplayStatus::from_number(x).map(|d| (d.status, d.stalling))
}

impl<D: Details> Snapshot<D> {
    /// Metres per unit of the native position ([`Details::POSITION_UNIT`]):
    /// 1 for `"m"`, [`METRES_PER_FOOT`] for `"ft"`, NaN for an unknown unit
    /// (shown as a gap rather than in the wrong unit).
    #[must_use]
    pub fn metres_per_unit() -> f64 {
        match D::POSITION_UNIT {
            "m" => 1.0,
            "ft" => METRES_PER_FOOT,
            _ => f64::NAN,
        }
    }

    /// Height above the ground plane through the origin, m.
    #[must_use]
    pub fn height_m(&self) -> f64 {
        self.common.position[2] * Self::metres_per_unit()
    }

    /// Vertical speed, m/s, positive up.
    #[must_use]
    pub fn climb_rate_mps(&self) -> f64 {
        self.common.velocity[2] * Self::metres_per_unit()
    }
}

impl CommonState {
    /// A fixed state (the same in every call): 60 s into a flight, 98.76
    /// units up and sinking at 0.25 units/s, near Dayton, banked 5° right and
    /// pitched 2.5° up. For tests and examples of code that shows or
    /// formats a state (a HUD, a summary); each model's details have one too
    /// (e.g. [`PalmerDetails::sample_snapshot`](crate::model::palmer::PalmerDetails::sample_snapshot)).
    ///
    /// ```
    /// let s = fdm_run::report::CommonState::sample();
    /// assert_eq!(s.position[2], 98.76);
    /// ```
    #[must_use]
    pub fn sample() -> Self {
        Self {
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
}

/// Sample snapshots for tests of the modules built on [`Snapshot`].
#[cfg(test)]
pub(crate) mod samples {
    use super::Snapshot;
    use crate::model::bourg::BourgDetails;
    use crate::model::palmer::PalmerDetails;

    pub(crate) fn palmer() -> Snapshot<PalmerDetails> {
        PalmerDetails::sample_snapshot()
    }

    pub(crate) fn bourg() -> Snapshot<BourgDetails> {
        BourgDetails::sample_snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::bourg::BourgDetails;
    use crate::model::palmer::PalmerDetails;
    use samples::{bourg, palmer};

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
        let report = Report::new(30, 7, &palmer());
        let json = report.to_json().unwrap();
        assert!(!json.contains('\n'));
        assert!(
            json.starts_with(r#"{"model":"palmer","airspeed":"#),
            "{json}"
        );
        let back: Report<PalmerDetails> = serde_json::from_str(&json).unwrap();
        assert_eq!(back, report);
        let report = Report::new(30, 7, &bourg());
        let json = report.to_json().unwrap();
        let back: Report<BourgDetails> = serde_json::from_str(&json).unwrap();
        assert_eq!(back, report);
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
            // Never more digits than the 17 significant digits docs/cli.md allows for.
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
            let wide = f64::from(x);
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
    fn status_is_in_the_json_the_csv_and_the_summary() {
        assert_eq!(status_from_number(7.0), None);
        assert_eq!(status_from_number(0.5), None);
        use fdm_core::model::{FlightStatus, LandingState};
        let mut snap = palmer();
        for (status, stalling, code, number) in [
            (FlightStatus::OnGround, false, "on_ground", 0.0),
            (FlightStatus::Airborne, false, "airborne", 1.0),
            (
                FlightStatus::Landed(LandingState::Safe),
                false,
                "landed_safe",
                2.0,
            ),
            (
                FlightStatus::Landed(LandingState::Rough),
                false,
                "landed_rough",
                3.0,
            ),
            (
                FlightStatus::Landed(LandingState::Crash),
                false,
                "crashed",
                4.0,
            ),
            (FlightStatus::Diverged, false, "diverged", 5.0),
            (FlightStatus::Airborne, true, "stalling", 6.0),
            (
                FlightStatus::Landed(LandingState::Crash),
                true,
                "crashed",
                4.0,
            ),
        ] {
            (snap.status, snap.stalling) = (status, stalling);
            let report = Report::new(30, 1, &snap);
            let v = serde_json::to_value(&report).unwrap();
            assert_eq!(v["status"], code);
            assert!(report
                .human_summary()
                .contains(&format!("status    {code}\n")));
            // The CSV's `status` column (crate::csv::FlightRow).
            assert_eq!(
                crate::csv::status_number(status, stalling),
                number,
                "{code}"
            );
            let back = status_from_number(number).unwrap();
            let shown_stall = stalling && status == FlightStatus::Airborne;
            assert_eq!(back, (status, shown_stall), "{code}");
        }
    }

    /// The human summary carries the counters the JSON report has: the
    /// FlightGear datagrams sent and failed, the pacing overruns, one line
    /// each, and only when the run had that output.
    #[test]
    fn human_summary_lists_the_output_counters() {
        let plain = Report::new(30, 900, &bourg());
        let s = plain.human_summary();
        assert!(!s.contains("flightgear") && !s.contains("realtime"), "{s}");
        let mut report = plain.clone();
        report.fg = Some(LinkStats {
            sent: 8971,
            failed: 29,
        });
        report.realtime = Some(RealtimeReport { overruns: 517 });
        let s = report.human_summary();
        assert!(s.starts_with(&plain.human_summary()), "{s}");
        let extra: Vec<&str> = s[plain.human_summary().len()..].lines().collect();
        assert_eq!(extra.len(), 3, "{s}");
        assert!(extra[0].is_empty(), "{s}");
        let fg_line = extra[1];
        assert!(fg_line.starts_with("flightgear"), "{s}");
        assert!(
            fg_line.contains(" 8971 ") && fg_line.contains(" 29 "),
            "{s}"
        );
        assert!(
            extra[2].starts_with("realtime") && extra[2].contains(" 517 "),
            "{s}"
        );
    }

    /// Bourg's summary line carries its own report fields (docs/cli.md,
    /// "Headless output": speed, thrust, flaps and stall): the speed to 0.001
    /// ft/s, the thrust, flaps up or down, stalling or not, the pitch trim.
    #[test]
    fn bourg_summary_shows_speed_thrust_flaps_stall_and_trim() {
        let mut snap = bourg();
        let s = Report::new(30, 1, &snap).human_summary();
        let line = s.lines().find(|l| l.starts_with("speed")).unwrap_or("");
        for part in ["183.123 ft/s", "3000 lb", "flaps down", "stalling no"] {
            assert!(line.contains(part), "{part}: {s}");
        }
        snap.details.flaps = false;
        snap.details.stalling = true;
        snap.details.thrust_lb = 125.5;
        snap.details.pitch_trim = -0.25;
        let s = Report::new(30, 1, &snap).human_summary();
        let line = s.lines().find(|l| l.starts_with("speed")).unwrap_or("");
        for part in ["125.5 lb", "flaps up", "stalling yes", "-0.250"] {
            assert!(line.contains(part), "{part}: {s}");
        }
    }

    /// The summary's heading is the report's heading rounded to 0.01 degree,
    /// in [0, 360): values that round to 360.00 show as 0.00.
    #[test]
    fn human_summary_heading_is_rounded_to_hundredths() {
        let mut snap = palmer();
        for (heading, shown) in [
            (123.456, "123.46"),
            (7.004_999, "7.00"),
            (0.004, "0.00"),
            (359.994, "359.99"),
            (359.995_1, "0.00"),
            (180.0, "180.00"),
        ] {
            snap.common.attitude_deg.heading = heading;
            let s = Report::new(30, 1, &snap).human_summary();
            assert!(
                s.contains(&format!("heading {shown} deg")),
                "{heading}: {s}"
            );
        }
    }

    #[test]
    fn human_summary_mentions_model_and_units() {
        let s = Report::new(30, 900, &bourg()).human_summary();
        assert!(s.starts_with("bourg: 900 frames at 30 fps"));
        assert!(s.contains("ft/s"));
        let s = Report::new(10, 600, &palmer()).human_summary();
        assert!(s.contains("throttle 75 %"));
        // The sample's clock is 60.000000000000746: rounded to the frame here,
        // every digit in the JSON.
        assert!(
            s.starts_with("palmer: 600 frames at 10 fps, t = 60.00 s\n"),
            "{s}"
        );
        let json = Report::new(10, 600, &palmer()).to_json().unwrap();
        assert!(json.contains("\"time_s\":60.000000000000746"), "{json}");
        assert_eq!(
            [1, 30, 100, 101, 1000, 1001, 10_000].map(frame_decimals),
            [2, 2, 2, 3, 3, 4, 4]
        );
        let mut snap = bourg();
        snap.common.attitude_deg.heading = 359.999_999;
        snap.common.attitude_deg.roll = -1e-9;
        let s = Report::new(30, 1, &snap).human_summary();
        assert!(s.contains("roll 0.00  pitch 2.50  heading 0.00 deg"), "{s}");
    }
}

#[cfg(test)]
mod snapshot_tests {
    use super::samples;

    /// Height and vertical speed are in metres whatever the model's own unit:
    /// Bourg's feet are converted (0.3048 m per foot, exact), Palmer's metres
    /// pass through. The samples share position z = 98.76 and vz = -0.25 in
    /// their own units.
    #[test]
    fn heights_and_climb_rates_are_in_metres_for_every_model() {
        let bourg = samples::bourg();
        assert_eq!(bourg.height_m(), 98.76 * 0.3048);
        assert_eq!(bourg.climb_rate_mps(), -0.25 * 0.3048);
        let palmer = samples::palmer();
        assert_eq!(palmer.height_m(), 98.76);
        assert_eq!(palmer.climb_rate_mps(), -0.25);
    }
}
