//! The interactive loop: keys in, HUD out, one frame per 1/fps of wall time;
//! [`Session`] holds its state apart from the terminal and the clock.

use std::io;
use std::net::SocketAddrV4;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use crossterm::event::{self, Event};
use fdm_run::LinkStats;

use super::Flight;
use crate::error::CliError;
use crate::hud::{render_hud, HudData, HudWriter, LoopStatus};
use crate::keys::{map_key, AppCommand, Input, KeyAction};
use crate::pacer::FramePacer;
use crate::terminal::TerminalGuard;

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
}

impl<A> Default for Session<A> {
    fn default() -> Self {
        Self {
            frame: 0,
            total_frames: 0,
            paused: false,
            pending: Vec::new(),
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
    /// frame 0 (the script starts over; the run hands its outputs the initial
    /// state again, e.g. a new CSV row 0).
    ///
    /// # Errors
    /// A failing reset or output.
    pub fn handle<F: Flight<Action = A>>(
        &mut self,
        input: Input<A>,
        flight: &mut F,
    ) -> Result<Flow, CliError> {
        match input {
            Input::App(AppCommand::Quit) => return Ok(Flow::Quit),
            Input::App(AppCommand::Pause) => self.paused = !self.paused,
            Input::App(AppCommand::Reset) => {
                flight.reset().context("reset")?;
                self.frame = 0;
                self.pending.clear();
            }
            Input::Action(action) => {
                if !self.paused {
                    self.pending.push(action);
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// Steps one frame with the queued keys (after the flight's script's
    /// rules for the frame, [`Flight::step`]), unless paused.
    ///
    /// # Errors
    /// As [`run_headless`](super::run_headless).
    pub fn advance<F: Flight<Action = A>>(&mut self, flight: &mut F) -> Result<(), CliError> {
        if self.paused {
            return Ok(());
        }
        self.frame += 1;
        self.total_frames += 1;
        let result = flight.step(&self.pending);
        self.pending.clear();
        Ok(result.with_context(|| format!("frame {}", self.frame))?)
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
    /// The first datagram send failure, if any (see [`super::Links::take_failure`]),
    /// kept for after the terminal is restored: stderr under the HUD is not readable.
    pub link_failure: Option<String>,
}

/// Flies interactively until Q, Esc or Ctrl-C: keys in, HUD out, one frame per
/// 1/fps seconds of wall time. The terminal is restored on every exit path.
///
/// # Errors
/// Terminal I/O failures and the first failing step or output.
pub fn run_interactive<F: Flight>(
    flight: &mut F,
    fps: u32,
    fg: Option<SocketAddrV4>,
) -> Result<InteractiveSummary, CliError> {
    let guard = TerminalGuard::enter().context("setting up the terminal")?;
    let mut out = io::stdout();
    let mut hud = HudWriter::new();
    let mut session = Session::new();
    let mut link_failure = None;
    let links = flight.links();
    let mut pacer = FramePacer::new(FramePacer::period_for(fps), Instant::now());
    'run: loop {
        // A signal (a closed terminal window, `kill`) ends the flight like Q:
        // the caller finishes every output (crate::signals).
        if crate::signals::stop_requested().is_some() {
            break 'run;
        }
        // Drain every key that arrived during the last frame without blocking.
        while event::poll(Duration::ZERO).context("reading the keyboard")? {
            match event::read().context("reading the keyboard")? {
                Event::Key(key) => {
                    if let Some(input) = map_key::<F::Action>(&key) {
                        if session.handle(input, flight)? == Flow::Quit {
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
        session.advance(flight)?;
        if let Some(message) = links.take_failure() {
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
            links.fg_stats(),
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
        link: links.fg_stats(),
        link_failure,
    })
}
