//! The run loops, written once for every model against the [`Flight`] trait.
//!
//! [`crate::flight::ModelFlight`] implements [`Flight`] for any
//! [`CliModel`] (one aircraft entity in an `fdm_ecs::Simulation`);
//! [`run_model`] builds it from the validated configuration and hands it to
//! [`fly`]. Everything here (script replay, CSV, JSON report, progress bar,
//! terminal, keys, pacing, HUD) is model-agnostic and tested with a fake model.

use std::io::{self, Write};
use std::net::SocketAddrV4;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use crossterm::event::{self, Event};
use fdm_core::script::Script;

use crate::config::{Mode, ModelConfig, RunConfig};
use crate::csv::CsvWriter;
use crate::error::CliError;
use crate::flight::ModelFlight;
use crate::hud::{render_hud, HudData, HudWriter, LinkStats, LoopStatus};
use crate::keys::{map_key, AppCommand, Input, KeyAction};
use crate::models::{CliModel, Details};
use crate::pacer::FramePacer;
use crate::progress::StderrProgress;
use crate::report::Report;
use crate::snapshot::Snapshot;
use crate::terminal::TerminalGuard;

/// One aircraft the loops can fly: the seam between the CLI and the ECS.
pub trait Flight {
    /// The model's control vocabulary (keys and script actions).
    type Action: KeyAction;
    /// The model's own report fields.
    type Details: Details;

    /// The model's title for the HUD.
    const TITLE: &'static str;

    /// Advances one frame of fixed dt: apply `actions` in order as key presses
    /// (for Bourg after returning the rudder, ailerons and elevators to neutral),
    /// step the model, and send the FlightGear datagram if a target is configured.
    /// A failed send must not be an error: count it in [`Self::link_stats`].
    ///
    /// # Errors
    /// Anything that makes continuing pointless; the run stops with exit status 1.
    fn step(&mut self, actions: &[Self::Action]) -> anyhow::Result<()>;

    /// Puts the model back to its initial state and controls (interactive R key).
    ///
    /// # Errors
    /// As [`Self::step`].
    fn reset(&mut self) -> anyhow::Result<()>;

    /// The current state, for the report, the CSV rows and the HUD.
    fn snapshot(&self) -> Snapshot<Self::Details>;

    /// Datagram counters, or `None` when nothing is sent.
    fn link_stats(&self) -> Option<LinkStats>;

    /// A one-line description of the first failed datagram send, returned once (later
    /// failures are only counted in [`Self::link_stats`]). The loops print it on
    /// stderr at most once per run, never per frame; a failing link is never fatal.
    fn take_link_failure(&mut self) -> Option<String> {
        None
    }
}

/// The stderr line for a link failure (see [`Flight::take_link_failure`]).
fn link_warning(message: &str) -> String {
    format!("sim-cli: warning: {}", crate::error::one_line(message))
}

/// Steps frame `frame` (1-based): the script's actions for that frame in file order,
/// then `keys`, then one model step, then the CSV row.
fn step_frame<F: Flight, W: Write>(
    flight: &mut F,
    script: &Script<F::Action>,
    frame: u64,
    keys: &[F::Action],
    buffer: &mut Vec<F::Action>,
    csv: Option<&mut CsvWriter<W>>,
) -> Result<(), CliError> {
    buffer.clear();
    buffer.extend(script.actions_at(frame));
    buffer.extend_from_slice(keys);
    flight
        .step(buffer)
        .with_context(|| format!("frame {frame}"))?;
    if let Some(csv) = csv {
        csv.write_record(frame, &flight.snapshot())?;
    }
    Ok(())
}

/// Runs `frames` frames as fast as possible and returns the final report. Writes
/// the initial state as CSV frame 0 and a row after every step. The caller
/// finishes (flushes) the CSV writer.
///
/// # Errors
/// The first failing step or CSV write ([`CliError::Runtime`]).
pub fn run_headless<F: Flight, W: Write>(
    flight: &mut F,
    script: &Script<F::Action>,
    fps: u32,
    frames: u64,
    mut csv: Option<&mut CsvWriter<W>>,
    progress: &mut StderrProgress,
) -> Result<Report<F::Details>, CliError> {
    if let Some(csv) = csv.as_deref_mut() {
        csv.write_record(0, &flight.snapshot())?;
    }
    let mut buffer = Vec::new();
    for frame in 1..=frames {
        step_frame(flight, script, frame, &[], &mut buffer, csv.as_deref_mut())?;
        if let Some(message) = flight.take_link_failure() {
            progress.message(&link_warning(&message));
        }
        progress.tick(frame);
    }
    progress.finish();
    Ok(Report::new(fps, frames, &flight.snapshot()))
}

/// Whether the interactive loop goes on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Keep flying.
    Continue,
    /// The user quit.
    Quit,
}

/// The interactive loop's state apart from the terminal and the clock, so that
/// pause, reset and key handling are testable without a terminal.
#[derive(Debug)]
pub struct Session<A> {
    frame: u64,
    total_frames: u64,
    paused: bool,
    pending: Vec<A>,
    buffer: Vec<A>,
}

impl<A> Default for Session<A> {
    fn default() -> Self {
        Self {
            frame: 0,
            total_frames: 0,
            paused: false,
            pending: Vec::new(),
            buffer: Vec::new(),
        }
    }
}

impl<A: KeyAction> Session<A> {
    /// A session at frame 0, running.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Frames since the start or the last reset (the script's frame counter).
    #[must_use]
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Frames stepped in total, across resets.
    #[must_use]
    pub fn total_frames(&self) -> u64 {
        self.total_frames
    }

    /// Whether the simulation is paused.
    #[must_use]
    pub fn paused(&self) -> bool {
        self.paused
    }

    /// Handles one key. Control keys are queued for the next frame; while paused
    /// they are ignored, so nothing changes behind a frozen display. Reset returns to
    /// frame 0 (the script starts over) and writes the initial state as a new CSV row 0.
    ///
    /// # Errors
    /// A failing reset or CSV write.
    pub fn handle<F: Flight<Action = A>, W: Write>(
        &mut self,
        input: Input<A>,
        flight: &mut F,
        csv: Option<&mut CsvWriter<W>>,
    ) -> Result<Flow, CliError> {
        match input {
            Input::App(AppCommand::Quit) => return Ok(Flow::Quit),
            Input::App(AppCommand::Pause) => self.paused = !self.paused,
            Input::App(AppCommand::Reset) => {
                flight.reset().context("reset")?;
                self.frame = 0;
                self.pending.clear();
                if let Some(csv) = csv {
                    csv.write_record(0, &flight.snapshot())?;
                }
            }
            Input::Action(action) => {
                if !self.paused {
                    self.pending.push(action);
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// Steps one frame with the queued keys, unless paused.
    ///
    /// # Errors
    /// As [`run_headless`].
    pub fn advance<F: Flight<Action = A>, W: Write>(
        &mut self,
        flight: &mut F,
        script: &Script<A>,
        csv: Option<&mut CsvWriter<W>>,
    ) -> Result<(), CliError> {
        if self.paused {
            return Ok(());
        }
        self.frame += 1;
        self.total_frames += 1;
        let result = step_frame(
            flight,
            script,
            self.frame,
            &self.pending,
            &mut self.buffer,
            csv,
        );
        self.pending.clear();
        result
    }
}

/// What an interactive run did, for the closing message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InteractiveSummary {
    /// Frames stepped, across resets.
    pub frames: u64,
    /// Frames that missed their deadline.
    pub overruns: u64,
    /// Final datagram counters.
    pub link: Option<LinkStats>,
    /// The first datagram send failure, if any (see [`Flight::take_link_failure`]),
    /// kept for after the terminal is restored: stderr under the HUD is not readable.
    pub link_failure: Option<String>,
}

/// Flies interactively until Q, Esc or Ctrl-C: keys in, HUD out, one frame per
/// 1/fps seconds of wall time. The terminal is restored on every exit path.
///
/// # Errors
/// Terminal I/O failures and the first failing step or CSV write.
pub fn run_interactive<F: Flight, W: Write>(
    flight: &mut F,
    script: &Script<F::Action>,
    fps: u32,
    fg: Option<SocketAddrV4>,
    mut csv: Option<&mut CsvWriter<W>>,
) -> Result<InteractiveSummary, CliError> {
    let guard = TerminalGuard::enter().context("setting up the terminal")?;
    let mut out = io::stdout();
    let mut hud = HudWriter::new();
    let mut session = Session::new();
    let mut link_failure = None;
    if let Some(csv) = csv.as_deref_mut() {
        csv.write_record(0, &flight.snapshot())?;
    }
    let mut pacer = FramePacer::new(FramePacer::period_for(fps), Instant::now());
    'run: loop {
        // Drain every key that arrived during the last frame without blocking.
        while event::poll(Duration::ZERO).context("reading the keyboard")? {
            match event::read().context("reading the keyboard")? {
                Event::Key(key) => {
                    if let Some(input) = map_key::<F::Action>(&key) {
                        if session.handle(input, flight, csv.as_deref_mut())? == Flow::Quit {
                            break 'run;
                        }
                    }
                }
                Event::Resize(..) => {
                    crossterm::execute!(
                        out,
                        crossterm::terminal::Clear(crossterm::terminal::ClearType::All)
                    )
                    .context("drawing the HUD")?;
                    hud = HudWriter::new();
                }
                _ => {}
            }
        }
        session.advance(flight, script, csv.as_deref_mut())?;
        if let Some(message) = flight.take_link_failure() {
            link_failure.get_or_insert(message);
        }
        // Some ptys report 0x0; treat that like an unknown size.
        let (width, height) = crossterm::terminal::size()
            .ok()
            .filter(|&(w, h)| w > 0 && h > 0)
            .unwrap_or((80, 24));
        let data = HudData::from_snapshot(
            F::TITLE,
            &flight.snapshot(),
            fg,
            flight.link_stats(),
            LoopStatus {
                frame: session.frame(),
                fps,
                overruns: pacer.overruns(),
                paused: session.paused(),
            },
            F::Action::KEY_HELP,
        );
        hud.draw(&mut out, &render_hud(&data, width), width, height)
            .context("drawing the HUD")?;
        let sleep = pacer.finish_frame(Instant::now());
        if !sleep.is_zero() {
            std::thread::sleep(sleep);
        }
    }
    drop(guard);
    Ok(InteractiveSummary {
        frames: session.total_frames(),
        overruns: pacer.overruns(),
        link: flight.link_stats(),
        link_failure,
    })
}

/// Writes `text` and a newline to stdout, turning a closed pipe into an error
/// instead of the panic `println!` would raise.
fn print_stdout(text: &str) -> Result<(), CliError> {
    let mut out = io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .context("writing to stdout")?;
    Ok(())
}

/// Flies `flight` as configured: headless (report on stdout: JSON with `--json`,
/// else a short summary) or interactive (a one-line summary on stderr at the end).
///
/// # Errors
/// Whatever the loop or the output reports.
pub fn fly<F: Flight>(
    mut flight: F,
    script: &Script<F::Action>,
    run: RunConfig,
) -> Result<(), CliError> {
    let RunConfig {
        fps,
        mode,
        mut csv,
        fg,
        origin: _,
        // Taken by `run_model`, which wraps the flight (crate::plot::fly_plotted).
        plot: _,
    } = run;
    match mode {
        Mode::Headless { frames, json } => {
            let mut progress = StderrProgress::new(frames);
            let report = run_headless(
                &mut flight,
                script,
                fps,
                frames,
                csv.as_mut(),
                &mut progress,
            )?;
            if let Some(csv) = csv {
                csv.finish()?;
            }
            let text = if json {
                report.to_json().context("encoding the JSON report")?
            } else {
                report.human_summary()
            };
            print_stdout(&text)
        }
        Mode::Interactive => {
            let summary = run_interactive(&mut flight, script, fps, fg, csv.as_mut())?;
            if let Some(csv) = csv {
                csv.finish()?;
            }
            if let Some(message) = &summary.link_failure {
                eprintln!("{}", link_warning(message));
            }
            let link = summary.link.map_or_else(String::new, |l| {
                format!(", {} packets sent, {} failed", l.sent, l.failed)
            });
            eprintln!(
                "sim-cli: flew {} frames, {} overruns{link}",
                summary.frames, summary.overruns
            );
            Ok(())
        }
    }
}

/// Flies one aircraft of model `M` ([`ModelFlight`]) as configured.
///
/// # Errors
/// As [`ModelFlight::new`] and [`fly`].
pub fn run_model<M: CliModel>(mut config: ModelConfig<M>) -> Result<(), CliError> {
    let flight = ModelFlight::new(&config.run, config.start)?;
    match config.run.plot.take() {
        None => fly(flight, &config.script, config.run),
        Some(plot) => crate::plot::fly_plotted(flight, &config.script, config.run, plot),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::palmer::PalmerDetails;
    use crate::snapshot::samples;
    use fdm_core::palmer::PalmerAction;

    /// A stand-in model: records the actions of every step; position x counts steps.
    #[derive(Default)]
    struct Fake {
        steps: Vec<Vec<PalmerAction>>,
        resets: u32,
        fail_at: Option<usize>,
        link_failures: Vec<String>,
    }

    impl Flight for Fake {
        type Action = PalmerAction;
        type Details = PalmerDetails;

        const TITLE: &'static str = "Fake";

        fn step(&mut self, actions: &[PalmerAction]) -> anyhow::Result<()> {
            if self.fail_at == Some(self.steps.len() + 1) {
                anyhow::bail!("model diverged");
            }
            self.steps.push(actions.to_vec());
            Ok(())
        }

        fn reset(&mut self) -> anyhow::Result<()> {
            self.steps.clear();
            self.resets += 1;
            Ok(())
        }

        fn snapshot(&self) -> Snapshot<PalmerDetails> {
            let mut s = samples::palmer();
            s.common.time_s = self.steps.len() as f64 * 0.1;
            s.common.position = [self.steps.len() as f64, 0.0, 0.0];
            s.details.controls.throttle = self.steps.iter().flatten().count() as f64;
            s
        }

        fn link_stats(&self) -> Option<LinkStats> {
            None
        }

        fn take_link_failure(&mut self) -> Option<String> {
            self.link_failures.pop()
        }
    }

    fn script(text: &str) -> Script<PalmerAction> {
        Script::parse(text).unwrap()
    }

    #[test]
    fn headless_applies_script_rules_on_their_frames() {
        use PalmerAction::*;
        let mut flight = Fake::default();
        let script = script("2-3 throttle-up\n3-3 flaps-down\n5-9 alpha-up\n");
        let mut progress = StderrProgress::with_enabled(4, false);
        let report =
            run_headless::<_, Vec<u8>>(&mut flight, &script, 10, 4, None, &mut progress).unwrap();
        assert_eq!(
            flight.steps,
            [
                vec![],
                vec![ThrottleUp],
                vec![ThrottleUp, FlapsDown],
                vec![]
            ]
        );
        assert_eq!(report.frames, 4);
        assert_eq!(report.fps, 10);
        assert_eq!(report.common.position[0], 4.0);
    }

    #[test]
    fn headless_zero_frames_reports_the_initial_state() {
        let mut flight = Fake::default();
        let mut progress = StderrProgress::with_enabled(0, false);
        let report =
            run_headless::<_, Vec<u8>>(&mut flight, &Script::default(), 30, 0, None, &mut progress)
                .unwrap();
        assert_eq!((report.frames, report.common.time_s), (0, 0.0));
        assert!(flight.steps.is_empty());
    }

    #[test]
    fn headless_csv_has_initial_row_and_one_row_per_frame() {
        let mut flight = Fake::default();
        let mut csv = CsvWriter::new(Vec::new(), "mem");
        let mut progress = StderrProgress::with_enabled(3, false);
        run_headless(
            &mut flight,
            &Script::default(),
            10,
            3,
            Some(&mut csv),
            &mut progress,
        )
        .unwrap();
        let text = String::from_utf8(csv.finish().unwrap()).unwrap();
        let frames: Vec<&str> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap())
            .collect();
        assert_eq!(frames, ["0", "1", "2", "3"]);
        assert!(text.lines().nth(2).unwrap().starts_with("1,0.1,1,"));
    }

    #[test]
    fn step_errors_name_the_frame_and_exit_1() {
        let mut flight = Fake {
            fail_at: Some(3),
            ..Fake::default()
        };
        let mut progress = StderrProgress::with_enabled(5, false);
        let err =
            run_headless::<_, Vec<u8>>(&mut flight, &Script::default(), 10, 5, None, &mut progress)
                .unwrap_err();
        assert_eq!(err.exit_code(), 1);
        assert_eq!(err.one_line(), "frame 3: model diverged");
    }

    #[test]
    fn session_keys_pause_reset_quit() {
        use PalmerAction::*;
        let mut flight = Fake::default();
        let script = script("1-1 flaps-down\n");
        let mut csv = CsvWriter::new(Vec::new(), "mem");
        let mut s = Session::new();
        fn handle(
            s: &mut Session<PalmerAction>,
            f: &mut Fake,
            csv: &mut CsvWriter<Vec<u8>>,
            input: Input<PalmerAction>,
        ) -> Flow {
            s.handle(input, f, Some(csv)).unwrap()
        }

        // Frame 1: script first, then keys in the order pressed.
        handle(&mut s, &mut flight, &mut csv, Input::Action(ThrottleUp));
        handle(&mut s, &mut flight, &mut csv, Input::Action(ThrottleUp));
        s.advance(&mut flight, &script, Some(&mut csv)).unwrap();
        assert_eq!(flight.steps, [vec![FlapsDown, ThrottleUp, ThrottleUp]]);

        // Paused: no steps, keys ignored.
        handle(&mut s, &mut flight, &mut csv, Input::App(AppCommand::Pause));
        handle(&mut s, &mut flight, &mut csv, Input::Action(AlphaUp));
        s.advance(&mut flight, &script, Some(&mut csv)).unwrap();
        assert_eq!((s.frame(), flight.steps.len(), s.paused()), (1, 1, true));
        handle(&mut s, &mut flight, &mut csv, Input::App(AppCommand::Pause));
        s.advance(&mut flight, &script, Some(&mut csv)).unwrap();
        assert_eq!(flight.steps[1], []);

        // Reset: model reset, frame 0, the script starts over.
        handle(&mut s, &mut flight, &mut csv, Input::App(AppCommand::Reset));
        assert_eq!((s.frame(), flight.resets), (0, 1));
        s.advance(&mut flight, &script, Some(&mut csv)).unwrap();
        assert_eq!(flight.steps, [vec![FlapsDown]]);
        assert_eq!(s.total_frames(), 3);

        assert_eq!(
            handle(&mut s, &mut flight, &mut csv, Input::App(AppCommand::Quit)),
            Flow::Quit
        );
        let text = String::from_utf8(csv.finish().unwrap()).unwrap();
        let frames: Vec<&str> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap())
            .collect();
        // Rows are only written by steps and resets (the loop writes the first row 0).
        assert_eq!(frames, ["1", "2", "0", "1"]);
    }

    #[test]
    fn link_failures_are_taken_but_never_fatal() {
        let mut flight = Fake {
            link_failures: vec!["nobody listens".to_owned()],
            ..Fake::default()
        };
        let mut progress = StderrProgress::with_enabled(3, false);
        let report =
            run_headless::<_, Vec<u8>>(&mut flight, &Script::default(), 30, 3, None, &mut progress)
                .unwrap();
        assert_eq!(report.frames, 3);
        assert!(flight.link_failures.is_empty());
        assert_eq!(
            link_warning("sending to 127.0.0.1:5500 failed\non frame 1"),
            "sim-cli: warning: sending to 127.0.0.1:5500 failed on frame 1"
        );
    }
}
