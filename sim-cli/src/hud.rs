//! The interactive heads-up display: [`HudData`] (what to show), [`render_hud`] (a pure
//! function to text lines, unit-tested) and [`HudWriter`] (draws lines with crossterm).

use std::io::{self, Write};
use std::net::SocketAddrV4;

use crossterm::cursor::MoveTo;
use crossterm::style::Print;
use crossterm::terminal::{Clear, ClearType};
use crossterm::QueueableCommand;

use fdm_core::model::FlightStatus;
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};

use crate::models::{tenths, Details};
use crate::snapshot::Snapshot;

/// The status as the HUD shows it: the flight status's label, or `STALL`
/// while the model reports a stall in the air.
#[must_use]
pub fn status_label(status: FlightStatus, stalling: bool) -> &'static str {
    if stalling && status == FlightStatus::Airborne {
        "STALL"
    } else {
        status.label()
    }
}

/// Datagram counters of the FlightGear sender.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LinkStats {
    /// Datagrams handed to the OS.
    pub sent: u64,
    /// Send attempts that failed (e.g. ICMP port unreachable reported back).
    pub failed: u64,
}

/// State of the run loop, as opposed to the model.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoopStatus {
    /// Frames stepped since the start or the last reset.
    pub frame: u64,
    /// Frame rate.
    pub fps: u32,
    /// Frames that missed their real-time deadline.
    pub overruns: u64,
    /// The simulation is paused.
    pub paused: bool,
}

/// Everything the HUD shows.
#[derive(Debug, Clone, PartialEq)]
pub struct HudData {
    /// Model display name.
    pub model: &'static str,
    /// Simulated time, s.
    pub time_s: f64,
    /// Geodetic altitude, m.
    pub altitude_m: f64,
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
    /// Heading as sent to FlightGear, degrees clockwise from north.
    pub heading_deg: f64,
    /// Roll, degrees, right wing down positive.
    pub roll_deg: f64,
    /// Pitch, degrees, nose up positive.
    pub pitch_deg: f64,
    /// The model's control line.
    pub controls: String,
    /// Flight status as shown ([`status_label`]).
    pub status: &'static str,
    /// Where packets go, if anywhere.
    pub fg_target: Option<SocketAddrV4>,
    /// Packet counters, if the sender reports them.
    pub link: Option<LinkStats>,
    /// Run loop state.
    pub run: LoopStatus,
    /// Key help for the model's controls.
    pub key_help: &'static str,
}

impl HudData {
    /// Builds the HUD contents for a model titled `model` (e.g.
    /// [`Model::TITLE`](fdm_core::model::Model::TITLE)) from a snapshot plus
    /// what only the loop and the sender know.
    #[must_use]
    pub fn from_snapshot<D: Details>(
        model: &'static str,
        snapshot: &Snapshot<D>,
        fg_target: Option<SocketAddrV4>,
        link: Option<LinkStats>,
        run: LoopStatus,
        key_help: &'static str,
    ) -> Self {
        let c = &snapshot.common;
        Self {
            model,
            time_s: c.time_s,
            altitude_m: c.geodetic.alt_m,
            airspeed_mps: snapshot.airspeed_mps,
            heading_deg: c.attitude_deg.heading,
            roll_deg: c.attitude_deg.roll,
            pitch_deg: c.attitude_deg.pitch,
            controls: snapshot.details.hud_controls(),
            status: status_label(snapshot.status, snapshot.stalling),
            fg_target,
            link,
            run,
            key_help,
        }
    }
}

/// Whole degrees in 0..360 for a compass display (359.6 shows as 000, not 360).
fn compass(deg: f64) -> i64 {
    if deg.is_finite() {
        (deg.round() as i64).rem_euclid(360)
    } else {
        0
    }
}

/// The HUD as text lines (ASCII only, so width = number of chars).
#[must_use]
pub fn render_hud(d: &HudData) -> Vec<String> {
    let paused = if d.run.paused { "   [PAUSED]" } else { "" };
    let mut lines = vec![
        format!(
            "sim-cli  {}   t {:.2} s   frame {} @ {} fps{paused}",
            d.model, d.time_s, d.run.frame, d.run.fps
        ),
        format!(
            "ALT {:6.0} ft ({:.1} m)   SPD {:5.1} kt ({:.1} m/s)   HDG {:03}",
            d.altitude_m / METRES_PER_FOOT,
            d.altitude_m,
            d.airspeed_mps * KNOTS_PER_MPS,
            d.airspeed_mps,
            compass(d.heading_deg)
        ),
        format!(
            "ROLL {:+6.1} deg   PITCH {:+6.1} deg   {}",
            tenths(d.roll_deg),
            tenths(d.pitch_deg),
            d.status
        ),
    ];
    lines.push(d.controls.clone());
    let link = match (d.fg_target, d.link) {
        (None, _) => "FG off".to_owned(),
        (Some(t), Some(s)) => format!("FG {t}  sent {}  failed {}", s.sent, s.failed),
        (Some(t), None) => format!("FG {t}"),
    };
    lines.push(format!("{link}   overruns {}", d.run.overruns));
    lines.push(String::new());
    lines.push(format!("keys: {}", d.key_help));
    lines.push(format!("      {}", crate::keys::APP_KEY_HELP));
    lines
}

/// Draws HUD lines at the top of the screen, each cleared to the end of the line,
/// and blanks lines left over from a longer previous frame.
#[derive(Debug, Default)]
pub struct HudWriter {
    previous_lines: u16,
}

impl HudWriter {
    /// A writer for a freshly cleared screen.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Draws `lines`, truncated to `width` columns and `height` rows, then flushes.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn draw(
        &mut self,
        out: &mut impl Write,
        lines: &[String],
        width: u16,
        height: u16,
    ) -> io::Result<()> {
        let rows = u16::try_from(lines.len()).unwrap_or(u16::MAX).min(height);
        for (row, line) in (0..rows).zip(lines) {
            let visible: String = line.chars().take(usize::from(width)).collect();
            out.queue(MoveTo(0, row))?
                .queue(Print(visible))?
                .queue(Clear(ClearType::UntilNewLine))?;
        }
        for row in rows..self.previous_lines.min(height) {
            out.queue(MoveTo(0, row))?
                .queue(Clear(ClearType::CurrentLine))?;
        }
        self.previous_lines = rows;
        out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::snapshot::samples;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use std::net::Ipv4Addr;

    fn palmer_hud() -> HudData {
        HudData::from_snapshot(
            Palmer::TITLE,
            &samples::palmer(),
            Some(SocketAddrV4::new(Ipv4Addr::LOCALHOST, 5500)),
            Some(LinkStats {
                sent: 369,
                failed: 2,
            }),
            LoopStatus {
                frame: 369,
                fps: 30,
                overruns: 1,
                paused: false,
            },
            "E/D throttle",
        )
    }

    #[test]
    fn palmer_text() {
        let lines = render_hud(&palmer_hud());
        assert_eq!(
            lines,
            [
                "sim-cli  Palmer Cessna 172   t 60.00 s   frame 369 @ 30 fps",
                "ALT   1148 ft (349.8 m)   SPD 108.1 kt (55.6 m/s)   HDG 000",
                "ROLL   +5.0 deg   PITCH   +2.5 deg   flying",
                "THROTTLE  75 %   ALPHA  +4.0 deg   BANK  +5.0 deg   FLAPS 20 deg",
                "FG 127.0.0.1:5500  sent 369  failed 2   overruns 1",
                "",
                "keys: E/D throttle",
                "      P pause  R reset  Q/Esc quit",
            ]
        );
    }

    #[test]
    fn bourg_text_paused_without_fg() {
        let mut snapshot = samples::bourg();
        snapshot.stalling = true;
        let d = HudData::from_snapshot(
            Bourg::TITLE,
            &snapshot,
            None,
            None,
            LoopStatus {
                frame: 5,
                fps: 30,
                overruns: 0,
                paused: true,
            },
            "",
        );
        let lines = render_hud(&d);
        assert!(lines[0].starts_with("sim-cli  Bourg 6-DoF"));
        assert!(lines[0].ends_with("[PAUSED]"));
        // 183.12346 ft/s = 55.816 m/s = 108.5 kt
        assert!(lines[1].contains("SPD 108.5 kt (55.8 m/s)"), "{}", lines[1]);
        assert!(lines[2].ends_with("STALL"));
        assert_eq!(lines[3], "THRUST 3000 lb   FLAPS down");
        assert_eq!(lines[4], "FG off   overruns 0");
    }

    #[test]
    fn no_negative_zero() {
        let mut d = palmer_hud();
        d.roll_deg = -1e-16;
        d.pitch_deg = -0.04;
        let lines = render_hud(&d);
        assert_eq!(lines[2], "ROLL   +0.0 deg   PITCH   +0.0 deg   flying");
        assert_eq!(tenths(-0.06), -0.06);
    }

    #[test]
    fn compass_wraps() {
        assert_eq!(compass(359.6), 0);
        assert_eq!(compass(-1.0), 359);
        assert_eq!(compass(f64::NAN), 0);
    }

    #[test]
    fn writer_truncates_and_clears_leftovers() {
        let mut w = HudWriter::new();
        let mut out = Vec::new();
        w.draw(&mut out, &["abcdef".to_owned(), "x".to_owned()], 3, 10)
            .unwrap();
        let text = String::from_utf8_lossy(&out).into_owned();
        assert!(text.contains("abc") && !text.contains("abcd"));
        let mut out = Vec::new();
        w.draw(&mut out, &["y".to_owned()], 80, 10).unwrap();
        // Row 2 (index 1) is blanked: MoveTo(0,1) is ESC[2;1H.
        let text = String::from_utf8_lossy(&out).into_owned();
        assert!(text.contains("\x1b[2;1H"), "{text:?}");
    }
}
