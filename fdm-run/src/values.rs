//! A run's settings read from text (`sim-cli`'s options): each parser
//! checks the value's range and says what is wrong in one line, echoing the
//! text given ([`Echo`]: control characters escaped, cut short), so a
//! command line's error stays readable. The limits are the run library's
//! ([`MAX_FPS`], [`MAX_FRAMES`], [`MAX_FLEET`], [`MAX_THREADS`], the start's
//! [`MAX_ALTITUDE_FT`], [`MAX_SPEED_KT`], [`MAX_HEADING_DEG`], FlightGear's
//! [`MAX_MP_PORT`], defined here).
//!
//! The DIS numbers and markings are `dis`'s (feature `dis`).

use fdm_core::script::Echo;

use crate::scenario::{MAX_ALTITUDE_FT, MAX_HEADING_DEG, MAX_SPEED_KT};
use crate::{MAX_FPS, MAX_FRAMES};

/// Largest multiplayer input port FlightGear 2020.3 accepts: it keeps the
/// receive and send ports in signed 16-bit integers, so 32768 and above read
/// as negative and it logs "Cannot enable multiplayer mode: No receiver port
/// specified." (measured live, docs/flightgear-check.md). `fgfs::with_multiplayer`
/// sends FlightGear's own multiplayer output to PORT + 1, which must fit too.
pub const MAX_MP_PORT: u16 = 32_766;

/// Largest accepted fleet (a Palmer entity takes about 600 bytes with its
/// display components, so this is some 6 GB).
pub const MAX_FLEET: u64 = 10_000_000;

/// Most threads a fleet may be flown on.
pub const MAX_THREADS: usize = 1024;

/// Why a value was refused; `text` is the value as given, echoed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ValueError {
    /// Not a finite number.
    #[error("`{text}` is not a finite number")]
    NotFinite {
        /// The text given.
        text: String,
    },
    /// A finite number outside `lo..=hi`; `unit` ends the message.
    #[error("`{text}` is outside {lo}..{hi}{unit}")]
    Outside {
        /// The text given.
        text: String,
        /// The least value accepted.
        lo: f64,
        /// The greatest value accepted.
        hi: f64,
        /// The unit, with its leading space (" degrees").
        unit: &'static str,
    },
    /// Not a finite number in `lo..=hi`; `what` says what it should be.
    #[error("`{text}` is not {what} in {lo}..{hi}")]
    NotInRange {
        /// The text given.
        text: String,
        /// What the value is ("an altitude in feet").
        what: &'static str,
        /// The least value accepted.
        lo: f64,
        /// The greatest value accepted.
        hi: f64,
    },
    /// Not a whole number in `lo..=hi`; `what` says what it should be.
    #[error("`{text}` is not {what} in {lo}..={hi}")]
    NotWhole {
        /// The text given.
        text: String,
        /// What the value is ("a number of aircraft").
        what: &'static str,
        /// The least value accepted.
        lo: u64,
        /// The greatest value accepted.
        hi: u64,
    },
    /// Not a positive finite number.
    #[error("`{text}` is not a positive finite number")]
    NotPositive {
        /// The text given.
        text: String,
    },
    /// A negative duration.
    #[error("must not be negative")]
    Negative,
    /// A whole frame rate out of `1..=MAX_FPS`.
    #[error("must be a whole number from 1 to {MAX_FPS}")]
    FpsOutOfRange,
    /// Not a whole frame rate.
    #[error("`{text}` is not a whole number of frames per second (1..{MAX_FPS})")]
    NotFps {
        /// The text given.
        text: String,
    },
    /// More frames than [`MAX_FRAMES`].
    #[error("must be at most {MAX_FRAMES}")]
    TooManyFrames,
    /// Not a whole number of frames.
    #[error("`{text}` is not a whole number of frames (0..{MAX_FRAMES})")]
    NotFrames {
        /// The text given.
        text: String,
    },
    /// A multiplayer port FlightGear would ignore.
    #[error(
        "`{text}` is too large: FlightGear 2020.3 stores multiplayer ports as signed 16-bit \
         numbers and ignores 32768 and above; use 1..{MAX_MP_PORT} (e.g. 5000)"
    )]
    PortTooLarge {
        /// The text given, as given.
        text: String,
    },
    /// Not a multiplayer port.
    #[error("`{text}` is not a port number (1..{MAX_MP_PORT})")]
    NotPort {
        /// The text given, as given.
        text: String,
    },
    /// Not a number of seconds in `(0, max]`.
    #[error("`{text}` is not a number of seconds in (0, {max}]")]
    NotSeconds {
        /// The text given.
        text: String,
        /// The longest accepted.
        max: f64,
    },
    /// Not a DIS marking.
    #[error("`{text}` is not a DIS marking (at most 11 printable ASCII characters)")]
    NotMarking {
        /// The text given.
        text: String,
    },
}

/// A finite number.
///
/// # Errors
/// [`ValueError::NotFinite`].
pub fn parse_finite(text: &str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(ValueError::NotFinite {
            text: Echo::short(text).to_string(),
        }),
    }
}

/// A finite number in `lo..=hi`; `unit` (with its leading space) ends the
/// message.
///
/// # Errors
/// [`ValueError::NotFinite`], or [`ValueError::Outside`] echoing the text as
/// given (1e308 printed as a float has 309 digits).
pub fn parse_in_range(text: &str, lo: f64, hi: f64, unit: &'static str) -> Result<f64, ValueError> {
    let v = parse_finite(text)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(ValueError::Outside {
            text: Echo::short(text.trim()).to_string(),
            lo,
            hi,
            unit,
        })
    }
}

/// A finite number in `lo..=hi` that is `what` ("an altitude in feet").
///
/// # Errors
/// [`ValueError::NotInRange`].
pub fn parse_number(text: &str, lo: f64, hi: f64, what: &'static str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (lo..=hi).contains(&v) => Ok(v),
        _ => Err(ValueError::NotInRange {
            text: Echo::short(text.trim()).to_string(),
            what,
            lo,
            hi,
        }),
    }
}

/// A whole number in `lo..=hi` that fits in `T`; `what` says what it is ("a
/// number of aircraft").
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_whole<T: TryFrom<u64>>(
    text: &str,
    lo: u64,
    hi: u64,
    what: &'static str,
) -> Result<T, ValueError> {
    text.trim()
        .parse::<u64>()
        .ok()
        .filter(|v| (lo..=hi).contains(v))
        .and_then(|v| T::try_from(v).ok())
        .ok_or_else(|| ValueError::NotWhole {
            text: Echo::short(text).to_string(),
            what,
            lo,
            hi,
        })
}

/// A positive finite number (a threshold, a heartbeat).
///
/// # Errors
/// [`ValueError::NotPositive`].
pub fn parse_positive(text: &str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(ValueError::NotPositive {
            text: Echo::short(text).to_string(),
        }),
    }
}

/// A number of seconds in `(0, max]`.
///
/// # Errors
/// [`ValueError::NotSeconds`].
pub fn parse_seconds(text: &str, max: f64) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= max => Ok(v),
        _ => Err(ValueError::NotSeconds {
            text: Echo::short(text).to_string(),
            max,
        }),
    }
}

/// A frame rate: a whole number from 1 to [`MAX_FPS`]. Whole, because the
/// frame rate is the ECS's `Resources::new(fps: u32)` and both models derive
/// dt from it (docs/cli.md: dt = 1/N, `1.0f32 / N as f32` for Bourg).
///
/// # Errors
/// [`ValueError::FpsOutOfRange`], [`ValueError::NotFps`].
pub fn parse_fps(text: &str) -> Result<u32, ValueError> {
    match text.trim().parse::<u32>() {
        Ok(v) if (1..=MAX_FPS).contains(&v) => Ok(v),
        Ok(_) => Err(ValueError::FpsOutOfRange),
        Err(_) => Err(ValueError::NotFps {
            text: Echo::short(text).to_string(),
        }),
    }
}

/// A number of frames: a whole number from 0 to [`MAX_FRAMES`].
///
/// # Errors
/// [`ValueError::TooManyFrames`], [`ValueError::NotFrames`].
pub fn parse_frames(text: &str) -> Result<u64, ValueError> {
    match text.trim().parse::<u64>() {
        Ok(v) if v <= MAX_FRAMES => Ok(v),
        Ok(_) => Err(ValueError::TooManyFrames),
        Err(_) => Err(ValueError::NotFrames {
            text: Echo::short(text).to_string(),
        }),
    }
}

/// A duration: finite seconds, >= 0 (the frame limit is checked once the
/// frame rate is known: [`crate::scenario::frames_for_duration`]).
///
/// # Errors
/// [`ValueError::NotFinite`], [`ValueError::Negative`].
pub fn parse_duration(text: &str) -> Result<f64, ValueError> {
    let v = parse_finite(text)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(ValueError::Negative)
    }
}

/// A FlightGear multiplayer input port, 1 to [`MAX_MP_PORT`].
///
/// # Errors
/// [`ValueError::PortTooLarge`] (FlightGear would ignore it),
/// [`ValueError::NotPort`].
pub fn parse_mp_port(text: &str) -> Result<u16, ValueError> {
    match text.trim().parse::<u16>() {
        Ok(p) if (1..=MAX_MP_PORT).contains(&p) => Ok(p),
        Ok(p) if p > MAX_MP_PORT => Err(ValueError::PortTooLarge {
            text: text.to_owned(),
        }),
        _ => Err(ValueError::NotPort {
            text: text.to_owned(),
        }),
    }
}

/// A fleet's size: 1 to [`MAX_FLEET`] aircraft.
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_fleet_size(text: &str) -> Result<u64, ValueError> {
    parse_whole(text, 1, MAX_FLEET, "a number of aircraft")
}

/// A fleet's frames: 1 to [`MAX_FRAMES`].
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_fleet_frames(text: &str) -> Result<u64, ValueError> {
    parse_whole(text, 1, MAX_FRAMES, "a number of frames")
}

/// A fleet's threads: 1 to [`MAX_THREADS`].
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_threads(text: &str) -> Result<usize, ValueError> {
    let max = u64::try_from(MAX_THREADS).unwrap_or(u64::MAX);
    parse_whole(text, 1, max, "a number of threads")
}

/// A start's altitude: 0 to [`MAX_ALTITUDE_FT`] feet.
///
/// # Errors
/// [`ValueError::NotInRange`].
pub fn parse_altitude_ft(text: &str) -> Result<f64, ValueError> {
    parse_number(text, 0.0, MAX_ALTITUDE_FT, "an altitude in feet")
}

/// A start's true airspeed: 0 to [`MAX_SPEED_KT`] knots.
///
/// # Errors
/// [`ValueError::NotInRange`].
pub fn parse_speed_kt(text: &str) -> Result<f64, ValueError> {
    parse_number(text, 0.0, MAX_SPEED_KT, "a speed in knots")
}

/// A start's heading: -[`MAX_HEADING_DEG`] to [`MAX_HEADING_DEG`] degrees.
///
/// # Errors
/// [`ValueError::NotInRange`].
pub fn parse_heading_deg(text: &str) -> Result<f64, ValueError> {
    parse_number(
        text,
        -MAX_HEADING_DEG,
        MAX_HEADING_DEG,
        "a heading in degrees",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The message of a refused value, as a command line shows it.
    fn refused<T: std::fmt::Debug>(parsed: Result<T, ValueError>) -> String {
        parsed.unwrap_err().to_string()
    }

    #[test]
    fn value_parsers() {
        assert!(parse_fps("0").is_err());
        assert!(parse_fps("-1").is_err());
        assert!(parse_fps("NaN").is_err());
        assert!(parse_fps("inf").is_err());
        assert!(parse_fps("10001").is_err());
        assert!(parse_fps("29.97").is_err());
        assert!(parse_fps("1e9").is_err());
        assert_eq!(parse_fps("1"), Ok(1));
        assert_eq!(parse_fps("10000"), Ok(10_000));
        assert!(parse_frames("-1").is_err());
        assert!(parse_frames("1.5").is_err());
        assert!(parse_frames("1000000001").is_err());
        assert_eq!(parse_frames("0"), Ok(0));
        assert!(parse_duration("-0.1").is_err());
        assert!(parse_duration("nan").is_err());
    }

    /// Every parser at the ends of its documented range (accepted, the
    /// number given) and just past them (refused, with the message a
    /// command line shows).
    #[test]
    fn each_range_is_accepted_to_its_ends() {
        assert_eq!(parse_finite(" -2.5 "), Ok(-2.5));
        assert_eq!(refused(parse_finite("inf")), "`inf` is not a finite number");
        assert_eq!(parse_in_range("0", 0.0, 1.0, ""), Ok(0.0));
        assert_eq!(parse_in_range(" 1 ", 0.0, 1.0, ""), Ok(1.0));
        assert_eq!(
            refused(parse_in_range("-0.5", 0.0, 1.0, " degrees")),
            "`-0.5` is outside 0..1 degrees"
        );
        assert!(matches!(
            parse_in_range("nan", 0.0, 1.0, ""),
            Err(ValueError::NotFinite { .. })
        ));

        assert_eq!(parse_altitude_ft("0"), Ok(0.0));
        assert_eq!(parse_altitude_ft("100000"), Ok(100_000.0));
        assert!(parse_altitude_ft("100000.5").is_err());
        assert_eq!(parse_speed_kt("0"), Ok(0.0));
        assert_eq!(parse_speed_kt("1000"), Ok(1000.0));
        assert_eq!(
            refused(parse_speed_kt("1000.5")),
            "`1000.5` is not a speed in knots in 0..1000"
        );
        assert_eq!(parse_heading_deg("-360"), Ok(-360.0));
        assert_eq!(parse_heading_deg("360"), Ok(360.0));
        assert_eq!(
            refused(parse_heading_deg("-360.5")),
            "`-360.5` is not a heading in degrees in -360..360"
        );
        assert!(parse_heading_deg("inf").is_err());

        assert_eq!(parse_whole::<u8>("255", 0, 1000, "a byte"), Ok(255));
        assert_eq!(
            refused(parse_whole::<u8>("256", 0, 1000, "a byte")),
            "`256` is not a byte in 0..=1000"
        );
        assert_eq!(parse_fleet_size("1"), Ok(1));
        assert_eq!(parse_fleet_size("10000000"), Ok(MAX_FLEET));
        assert!(parse_fleet_size("10000001").is_err());
        assert_eq!(parse_fleet_frames("1"), Ok(1));
        assert_eq!(parse_fleet_frames("1000000000"), Ok(MAX_FRAMES));
        assert_eq!(
            refused(parse_fleet_frames("0")),
            "`0` is not a number of frames in 1..=1000000000"
        );
        assert!(parse_fleet_frames("1000000001").is_err());
        assert_eq!(parse_threads("1"), Ok(1));
        assert_eq!(parse_threads("1024"), Ok(1024));
        assert_eq!(
            refused(parse_threads("1025")),
            "`1025` is not a number of threads in 1..=1024"
        );
        assert!(parse_threads("0").is_err());

        assert_eq!(parse_positive("1e-300"), Ok(1e-300));
        for bad in ["0", "-1", "inf", "x"] {
            assert_eq!(
                refused(parse_positive(bad)),
                format!("`{bad}` is not a positive finite number")
            );
        }
        assert_eq!(parse_seconds("60", 60.0), Ok(60.0));
        assert_eq!(parse_seconds("0.001", 60.0), Ok(0.001));
        for bad in ["0", "60.5", "nan", "-1"] {
            assert_eq!(
                refused(parse_seconds(bad, 60.0)),
                format!("`{bad}` is not a number of seconds in (0, 60]")
            );
        }

        assert_eq!(
            refused(parse_fps("0")),
            "must be a whole number from 1 to 10000"
        );
        assert_eq!(
            refused(parse_fps("29.97")),
            "`29.97` is not a whole number of frames per second (1..10000)"
        );
        assert_eq!(parse_frames("1000000000"), Ok(MAX_FRAMES));
        assert_eq!(
            refused(parse_frames("1000000001")),
            "must be at most 1000000000"
        );
        assert_eq!(
            refused(parse_frames("x")),
            "`x` is not a whole number of frames (0..1000000000)"
        );
        assert_eq!(parse_duration("0"), Ok(0.0));
        assert_eq!(parse_duration("2.5"), Ok(2.5));
        assert_eq!(refused(parse_duration("-0.1")), "must not be negative");

        assert_eq!(parse_mp_port("1"), Ok(1));
        assert_eq!(parse_mp_port("32766"), Ok(MAX_MP_PORT));
        assert!(refused(parse_mp_port("32767"))
            .starts_with("`32767` is too large: FlightGear 2020.3 stores multiplayer ports"));
        for bad in ["0", "65536", "-1", "x"] {
            assert_eq!(
                refused(parse_mp_port(bad)),
                format!("`{bad}` is not a port number (1..32766)")
            );
        }
    }

    #[test]
    fn values_are_echoed_short_and_without_control_characters() {
        let err = parse_fps("\u{1b}[31mred").unwrap_err().to_string();
        assert!(!err.chars().any(char::is_control), "{err}");
        let long = "9".repeat(10_000);
        assert!(parse_frames(&long).unwrap_err().to_string().len() < 200);
        assert_eq!(
            parse_in_range("1e308", 0.0, 1.0, " (fraction of full power)")
                .unwrap_err()
                .to_string(),
            "`1e308` is outside 0..1 (fraction of full power)"
        );
        assert_eq!(
            parse_fleet_size("0").unwrap_err().to_string(),
            "`0` is not a number of aircraft in 1..=10000000"
        );
        assert_eq!(
            parse_altitude_ft("-1").unwrap_err().to_string(),
            "`-1` is not an altitude in feet in 0..100000"
        );
    }
}
