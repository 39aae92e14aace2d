//! Terminal handling for interactive runs: the RAII [`TerminalGuard`], the panic hook
//! that restores the terminal before printing, and the "is this a terminal" check.
//!
//! The terminal is restored exactly once whichever way the run ends (normal return,
//! error, panic): a global flag records whether it is in raw mode, and every restore
//! path swaps the flag off first.

use std::io::{self, IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};

use crossterm::cursor::{Hide, Show};
use crossterm::execute;
use crossterm::terminal::{
    disable_raw_mode, enable_raw_mode, Clear, ClearType, EnterAlternateScreen, LeaveAlternateScreen,
};

use crate::error::CliError;

/// Whether raw mode / the alternate screen are on and must be undone.
static ACTIVE: AtomicBool = AtomicBool::new(false);

/// Raw mode + alternate screen + hidden cursor for as long as it lives.
#[derive(Debug)]
pub struct TerminalGuard {
    // Not constructible outside `enter`, so every guard matches one setup.
    _private: (),
}

impl TerminalGuard {
    /// Enters raw mode and the alternate screen and hides the cursor.
    ///
    /// # Errors
    /// The I/O error of the first step that failed; anything already changed is undone.
    pub fn enter() -> io::Result<Self> {
        enable_raw_mode()?;
        ACTIVE.store(true, Ordering::SeqCst);
        let guard = Self { _private: () };
        // If this fails, dropping `guard` restores raw mode.
        execute!(
            io::stdout(),
            EnterAlternateScreen,
            Hide,
            Clear(ClearType::All)
        )?;
        Ok(guard)
    }
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

/// Undoes [`TerminalGuard::enter`] if it is in effect; safe to call any number of
/// times, from any path (drop, panic hook).
pub fn restore() {
    if ACTIVE.swap(false, Ordering::SeqCst) {
        // Best effort: there is nowhere to report a failure to restore the terminal.
        let mut out = io::stdout();
        let _ = execute!(out, Show, LeaveAlternateScreen);
        let _ = out.flush();
        let _ = disable_raw_mode();
    }
}

/// Installs a panic hook that restores the terminal and prints one short line
/// instead of Rust's default message and backtrace hint. A panic is a bug in
/// `sim-cli`; `main` turns it into exit status 1.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        restore();
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .copied()
            .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
            .unwrap_or("unknown panic");
        let location = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let _ = writeln!(
            io::stderr(),
            "sim-cli: internal error: {}{location} (this is a bug; please report it)",
            crate::error::one_line(message)
        );
    }));
}

/// Checks that interactive mode can work: keys come from stdin and the HUD goes to
/// stdout, so both must be terminals.
///
/// # Errors
/// [`CliError::Usage`] pointing to `--headless`.
pub fn require_terminal() -> Result<(), CliError> {
    let stream = if !io::stdin().is_terminal() {
        "stdin"
    } else if !io::stdout().is_terminal() {
        "stdout"
    } else {
        return Ok(());
    };
    Err(CliError::usage(format!(
        "interactive mode needs a terminal on {stream}; use --headless with --frames N or --duration SECONDS"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restore_without_enter_is_a_no_op() {
        restore();
        restore();
        assert!(!ACTIVE.load(Ordering::SeqCst));
    }
}
