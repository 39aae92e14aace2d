//! The interactive heads-up display: [`HudData`] (what to show), [`render_hud`] (a pure
//! function to text lines, unit-tested) and [`HudWriter`] (draws lines with crossterm).

use std::io::{self, Write};
use std::net::SocketAddrV4;

use crossterm::cursor::MoveTo;
use crossterm::style::Print;
use crossterm::terminal::{Clear, ClearType};
use crossterm::QueueableCommand;

use fdm_core::model::{DisplayStatus, FlightStatus};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use fdm_run::LinkStats;

use crate::models::{tenths, Details};
use crate::snapshot::Snapshot;

/// The status as the HUD shows it ([`DisplayStatus::label`]): the flight
/// status's label, or `STALL` while the model reports a stall in the air.
#[must_use]
pub fn status_label(status: FlightStatus, stalling: bool) -> &'static str {
    DisplayStatus::new(status, stalling).label()
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
    /// Height above the ground plane through the origin, m.
    pub height_m: f64,
    /// Vertical speed, m/s, positive up.
    pub climb_rate_mps: f64,
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
            height_m: snapshot.height_m(),
            climb_rate_mps: snapshot.climb_rate_mps(),
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

/// Feet per minute per metre per second.
const FPM_PER_MPS: f64 = 60.0 / METRES_PER_FOOT;

/// One item of a HUD line in three widths: `full` (the 80-column layout,
/// padded so values do not jump), `compact` (no padding) and `short` (no
/// secondary units, abbreviated names).
#[derive(Debug, Clone, PartialEq)]
struct Field {
    full: String,
    compact: String,
    short: String,
}

impl Field {
    fn new(full: String, compact: String, short: String) -> Self {
        Self {
            full,
            compact,
            short,
        }
    }

    /// The same text at every width.
    fn fixed(text: String) -> Self {
        Self::new(text.clone(), text.clone(), text)
    }
}

/// The widest form of `fields` that fits in `width` columns: full fields
/// separated by three spaces, compact ones by two, short ones by one; the
/// short form (which the writer then clips) if none fits.
fn fit(fields: &[Field], width: usize) -> String {
    /// Picks one form of a field.
    type Form = fn(&Field) -> &str;
    let forms: [(Form, &str); 3] = [
        (|f| &f.full, "   "),
        (|f| &f.compact, "  "),
        (|f| &f.short, " "),
    ];
    let mut line = String::new();
    for (form, separator) in forms {
        line = fields.iter().map(form).collect::<Vec<_>>().join(separator);
        if line.len() <= width {
            break;
        }
    }
    line
}

/// Runs of spaces squeezed to one.
fn squeeze(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The model's control line (free text from
/// [`Details::hud_controls`]) shortened: spaces squeezed, the usual names
/// abbreviated.
fn abbreviate_controls(text: &str) -> String {
    const SHORT: [(&str, &str); 6] = [
        ("THROTTLE", "THR"),
        ("THRUST", "THR"),
        ("ALPHA", "AOA"),
        ("FLAPS", "FLP"),
        ("BANK", "BNK"),
        (" deg", ""),
    ];
    let mut out = squeeze(text);
    for (long, short) in SHORT {
        out = out.replace(long, short);
    }
    out
}

/// `help` (items separated by two spaces) packed into lines of at most `width`
/// columns, the first starting with `first`, the others indented as deep.
fn wrap_help(first: &str, help: &str, width: usize) -> Vec<String> {
    let indent = " ".repeat(first.len());
    let mut prefix = first;
    let mut lines = Vec::new();
    let mut items = String::new();
    for item in help.split("  ").map(str::trim).filter(|i| !i.is_empty()) {
        if !items.is_empty() && prefix.len() + items.len() + 2 + item.len() > width {
            lines.push(format!("{prefix}{items}"));
            items.clear();
            prefix = &indent;
        }
        if !items.is_empty() {
            items.push_str("  ");
        }
        items.push_str(item);
    }
    lines.push(format!("{prefix}{items}"));
    lines
}

/// The HUD as text lines for a terminal `width` columns wide (ASCII only, so
/// width = number of chars). At 80 columns and more every line has its full
/// form; narrower, each line falls back to a compact and then a short form
/// (see `Field`), and the key help wraps, before the writer clips anything.
#[must_use]
pub fn render_hud(d: &HudData, width: u16) -> Vec<String> {
    let width = usize::from(width);
    let short_model = d.model.split_whitespace().next().unwrap_or(d.model);
    let mut title = vec![
        Field::new(
            format!("sim-cli  {}", d.model),
            d.model.to_owned(),
            short_model.to_owned(),
        ),
        Field::fixed(format!("t {:.2} s", d.time_s)),
        Field::new(
            format!("frame {} @ {} fps", d.run.frame, d.run.fps),
            format!("frame {} @ {} fps", d.run.frame, d.run.fps),
            format!("#{}", d.run.frame),
        ),
    ];
    if d.run.paused {
        title.push(Field::fixed("[PAUSED]".to_owned()));
    }
    let alt_ft = d.altitude_m / METRES_PER_FOOT;
    let kt = d.airspeed_mps * KNOTS_PER_MPS;
    let position = [
        Field::new(
            format!("ALT {alt_ft:6.0} ft ({:.1} m)", d.altitude_m),
            format!("ALT {alt_ft:.0} ft ({:.1} m)", d.altitude_m),
            format!("ALT {alt_ft:.0}ft"),
        ),
        Field::new(
            format!("SPD {kt:5.1} kt ({:.1} m/s)", d.airspeed_mps),
            format!("SPD {kt:.1} kt ({:.1} m/s)", d.airspeed_mps),
            format!("SPD {kt:.0}kt"),
        ),
        Field::fixed(format!("HDG {:03}", compass(d.heading_deg))),
    ];
    let hgt_ft = d.height_m / METRES_PER_FOOT;
    let fpm = d.climb_rate_mps * FPM_PER_MPS;
    // Whole feet per minute; -0 (a tiny sink) shows as +0.
    let fpm = if fpm.round() == 0.0 { 0.0 } else { fpm };
    let vertical = [
        Field::new(
            format!("HGT {hgt_ft:6.0} ft ({:.1} m)", d.height_m),
            format!("HGT {hgt_ft:.0} ft ({:.1} m)", d.height_m),
            format!("HGT {hgt_ft:.0}ft"),
        ),
        Field::new(
            format!(
                "V/S {fpm:+6.0} ft/min ({:+.1} m/s)",
                tenths(d.climb_rate_mps)
            ),
            format!("V/S {fpm:+.0} ft/min"),
            format!("VS {fpm:+.0}fpm"),
        ),
    ];
    let (roll, pitch) = (tenths(d.roll_deg), tenths(d.pitch_deg));
    let attitude = [
        Field::new(
            format!("ROLL {roll:+6.1} deg"),
            format!("ROLL {roll:+.1} deg"),
            format!("R{roll:+.1}"),
        ),
        Field::new(
            format!("PITCH {pitch:+6.1} deg"),
            format!("PITCH {pitch:+.1} deg"),
            format!("P{pitch:+.1}"),
        ),
        // The status is never abbreviated: it is what matters most.
        Field::fixed(d.status.to_owned()),
    ];
    let controls = [Field::new(
        d.controls.clone(),
        squeeze(&d.controls),
        abbreviate_controls(&d.controls),
    )];
    let link_field = match (d.fg_target, d.link) {
        (None, _) => Field::fixed("FG off".to_owned()),
        (Some(t), Some(s)) => Field::new(
            format!("FG {t}  sent {}  failed {}", s.sent, s.failed),
            format!("FG {t} sent {} failed {}", s.sent, s.failed),
            format!("FG sent {} fail {}", s.sent, s.failed),
        ),
        (Some(t), None) => Field::new(format!("FG {t}"), format!("FG {t}"), "FG on".to_owned()),
    };
    let link = [
        link_field,
        Field::new(
            format!("overruns {}", d.run.overruns),
            format!("overruns {}", d.run.overruns),
            format!("ovr {}", d.run.overruns),
        ),
    ];
    let mut lines = vec![
        fit(&title, width),
        fit(&position, width),
        fit(&vertical, width),
        fit(&attitude, width),
        fit(&controls, width),
        fit(&link, width),
        String::new(),
    ];
    let keys = format!("keys: {}", d.key_help);
    let app = format!("      {}", crate::keys::APP_KEY_HELP);
    if keys.len() <= width && app.len() <= width {
        lines.extend([keys, app]);
    } else {
        lines.extend(wrap_help("keys: ", d.key_help, width));
        lines.extend(wrap_help("      ", crate::keys::APP_KEY_HELP, width));
    }
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
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use std::net::Ipv4Addr;

    fn palmer_hud() -> HudData {
        HudData::from_snapshot(
            Palmer::TITLE,
            &fdm_run::model::palmer::PalmerDetails::sample_snapshot(),
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
        let lines = render_hud(&palmer_hud(), 80);
        assert_eq!(
            lines,
            [
                "sim-cli  Palmer Cessna 172   t 60.00 s   frame 369 @ 30 fps",
                "ALT   1148 ft (349.8 m)   SPD 108.1 kt (55.6 m/s)   HDG 000",
                "HGT    324 ft (98.8 m)   V/S    -49 ft/min (-0.2 m/s)",
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
        let mut snapshot = fdm_run::model::bourg::BourgDetails::sample_snapshot();
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
        let lines = render_hud(&d, 80);
        assert!(lines[0].starts_with("sim-cli  Bourg 6-DoF"));
        assert!(lines[0].ends_with("[PAUSED]"));
        // 183.12346 ft/s = 55.816 m/s = 108.5 kt
        assert!(lines[1].contains("SPD 108.5 kt (55.8 m/s)"), "{}", lines[1]);
        assert!(lines[3].ends_with("STALL"));
        assert_eq!(lines[4], "THRUST 3000 lb   FLAPS down   TRIM +0.00");
        assert_eq!(lines[5], "FG off   overruns 0");
    }

    #[test]
    fn no_negative_zero() {
        let mut d = palmer_hud();
        d.roll_deg = -1e-16;
        d.pitch_deg = -0.04;
        let lines = render_hud(&d, 80);
        assert_eq!(lines[3], "ROLL   +0.0 deg   PITCH   +0.0 deg   flying");
        d.climb_rate_mps = -1e-3;
        assert!(render_hud(&d, 80)[2].ends_with("V/S     +0 ft/min (+0.0 m/s)"));
        assert_eq!(tenths(-0.06), -0.06);
    }

    #[test]
    fn narrow_terminals_abbreviate_before_clipping() {
        let mut d = palmer_hud();
        d.status = "landed (rough)";
        d.run.paused = true;
        for width in [60_u16, 40] {
            let lines = render_hud(&d, width);
            for line in &lines {
                assert!(line.len() <= usize::from(width), "{width}: {line:?}");
            }
            let all = lines.join("\n");
            // Every value the 80-column HUD shows is still there.
            for needle in [
                "t 60.00 s",
                "[PAUSED]",
                "1148",
                "108",
                "HDG 000",
                "324",
                "-49",
                "+5.0",
                "+2.5",
                "landed (rough)",
                "75 %",
                "+4.0",
                "369",
                "E/D throttle",
                "Q/Esc quit",
            ] {
                assert!(all.contains(needle), "{width}: no {needle:?} in\n{all}");
            }
        }
        assert_eq!(
            render_hud(&d, 60)[..6],
            [
                "Palmer Cessna 172  t 60.00 s  frame 369 @ 30 fps  [PAUSED]",
                // Exactly 60 columns: the full form still fits.
                "ALT   1148 ft (349.8 m)   SPD 108.1 kt (55.6 m/s)   HDG 000",
                "HGT    324 ft (98.8 m)   V/S    -49 ft/min (-0.2 m/s)",
                "ROLL   +5.0 deg   PITCH   +2.5 deg   landed (rough)",
                "THROTTLE 75 % ALPHA +4.0 deg BANK +5.0 deg FLAPS 20 deg",
                "FG 127.0.0.1:5500  sent 369  failed 2   overruns 1",
            ]
        );
        assert_eq!(
            render_hud(&d, 40),
            [
                "Palmer t 60.00 s #369 [PAUSED]",
                "ALT 1148ft SPD 108kt HDG 000",
                "HGT 324 ft (98.8 m)  V/S -49 ft/min",
                "R+5.0 P+2.5 landed (rough)",
                "THR 75 % AOA +4.0 BNK +5.0 FLP 20",
                "FG sent 369 fail 2 ovr 1",
                "",
                "keys: E/D throttle",
                "      P pause  R reset  Q/Esc quit",
            ]
        );
    }

    #[test]
    fn key_help_wraps_in_narrow_terminals() {
        let help = "E/D throttle  Down/Up alpha +/-  Left/Right bank  K flaps down  L flaps up";
        assert_eq!(
            wrap_help("keys: ", help, 40),
            [
                "keys: E/D throttle  Down/Up alpha +/-",
                "      Left/Right bank  K flaps down",
                "      L flaps up",
            ]
        );
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

    /// The HUD samples in README.md ("Flying from the keyboard") are what
    /// `render_hud` draws for the quantities they show, so the README cannot
    /// drift from the HUD (it once lacked Bourg's TRIM field and T/G keys).
    #[test]
    fn readme_hud_samples_are_what_the_hud_draws() {
        use crate::keys::KeyAction;
        use crate::models::Details;
        use fdm_core::bourg::BourgAction;
        use fdm_core::palmer::PalmerAction;
        use fdm_run::model::bourg::BourgDetails;
        use fdm_run::model::palmer::{PalmerControlsReport, PalmerDetails};

        let readme = include_str!("../../README.md");
        let section = &readme[readme
            .find("## Flying from the keyboard")
            .expect("README section")..];
        let samples: Vec<Vec<&str>> = section
            .split("```text\n")
            .skip(1)
            .take(3)
            .map(|block| block.split("\n```").next().unwrap().lines().collect())
            .collect();

        let link = |port, sent, failed, overruns, frame| {
            (
                Some(SocketAddrV4::new(Ipv4Addr::LOCALHOST, port)),
                Some(LinkStats { sent, failed }),
                LoopStatus {
                    frame,
                    fps: 30,
                    overruns,
                    paused: false,
                },
            )
        };
        let palmer_controls = PalmerDetails {
            airspeed: 45.4,
            controls: PalmerControlsReport {
                throttle: 1.0,
                alpha_deg: 5.0,
                bank_deg: 15.0,
                flaps_deg: 0.0,
                brakes: false,
            },
            climb_angle_deg: 0.0,
            climb_rate: 0.0,
            heading_deg: 0.0,
        }
        .hud_controls();
        let (fg_target, link_stats, run) = link(5597, 1477, 4, 34, 1481);
        let mut palmer = HudData {
            model: Palmer::TITLE,
            time_s: 49.37,
            altitude_m: 359.3,
            airspeed_mps: 45.4,
            height_m: 108.1,
            climb_rate_mps: 4.049,
            heading_deg: 33.0,
            roll_deg: 15.2,
            pitch_deg: 10.0,
            controls: palmer_controls,
            status: status_label(FlightStatus::Airborne, false),
            fg_target,
            link: link_stats,
            run,
            key_help: PalmerAction::KEY_HELP,
        };
        assert_eq!(render_hud(&palmer, 80), samples[0], "README's Palmer HUD");

        let bourg_controls = BourgDetails {
            speed: 0.0,
            euler_deg: [0.0; 3],
            thrust_lb: 1000.0,
            flaps: false,
            stalling: false,
            pitch_trim: 0.0,
        }
        .hud_controls();
        let (fg_target, link_stats, run) = link(5598, 321, 4, 3, 325);
        let bourg = HudData {
            model: Bourg::TITLE,
            time_s: 10.83,
            altitude_m: 861.1,
            airspeed_mps: 34.47,
            height_m: 610.0,
            climb_rate_mps: 2.13,
            heading_deg: 11.0,
            roll_deg: 78.6,
            pitch_deg: 10.3,
            controls: bourg_controls,
            status: status_label(FlightStatus::Airborne, false),
            fg_target,
            link: link_stats,
            run,
            key_help: BourgAction::KEY_HELP,
        };
        assert_eq!(render_hud(&bourg, 80), samples[1], "README's Bourg HUD");

        // The Palmer flight 0.07 s earlier, in 40 columns.
        palmer.time_s = 49.30;
        palmer.run.frame = 1479;
        palmer.altitude_m = 359.05;
        palmer.height_m = 107.8;
        palmer.climb_rate_mps = 3.968;
        palmer.pitch_deg = 9.9;
        palmer.link = Some(LinkStats {
            sent: 1476,
            failed: 3,
        });
        palmer.run.overruns = 33;
        assert_eq!(
            render_hud(&palmer, 40),
            samples[2],
            "README's 40-column HUD"
        );
    }
}
