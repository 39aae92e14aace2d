//! Keyboard → controls (thesis appendix B; each model's key table is the
//! run library's, `fdm_run::model::pilot::KeyBindings`, here read from
//! crossterm's keys), plus the application keys Q/Esc (quit), P (pause),
//! R (reset).
//!
//! One key event is one press. Terminals report a held key as repeated press
//! events; with the kitty keyboard protocol crossterm may report `Repeat` kinds
//! instead, so both count, and `Release` is ignored.

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use fdm_core::script::ScriptAction;
use fdm_run::model::pilot::{Key, KeyBindings};

/// What the application does with a key that is not a model control.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AppCommand {
    /// Q, Esc or Ctrl-C: leave (in raw mode Ctrl-C arrives as a key, not a signal).
    Quit,
    /// P: pause or resume the simulation.
    Pause,
    /// R: put the model back to its initial state and frame 0.
    Reset,
}

/// A mapped key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input<A> {
    /// An application command.
    App(AppCommand),
    /// A model control, applied on the next frame.
    Action(A),
}

/// A model's action vocabulary, bound to keys.
pub trait KeyAction: ScriptAction {
    /// One-line key help for the HUD.
    const KEY_HELP: &'static str;
    /// The action a key (without modifiers; letters case-insensitive) stands for.
    fn from_key(code: KeyCode) -> Option<Self>;
}

/// The run library's key table ([`KeyBindings`]) read from crossterm's keys.
impl<A: KeyBindings> KeyAction for A {
    const KEY_HELP: &'static str = <A as KeyBindings>::KEY_HELP;

    fn from_key(code: KeyCode) -> Option<Self> {
        let key = match (code, letter(code)) {
            (_, Some(c)) => Key::Char(c),
            (KeyCode::Up, _) => Key::Up,
            (KeyCode::Down, _) => Key::Down,
            (KeyCode::Left, _) => Key::Left,
            (KeyCode::Right, _) => Key::Right,
            _ => return None,
        };
        A::for_key(key)
    }
}

/// The lower-case letter of a character key (keys are case-insensitive).
#[must_use]
pub fn letter(code: KeyCode) -> Option<char> {
    match code {
        KeyCode::Char(c) => Some(c.to_ascii_lowercase()),
        _ => None,
    }
}

/// Help for the application keys, appended to [`KeyAction::KEY_HELP`].
pub const APP_KEY_HELP: &str = "P pause  R reset  Q/Esc quit";

/// Maps a crossterm key event to an input, or `None` for keys that mean nothing.
/// Keys held with Ctrl or Alt are ignored (except Ctrl-C), so terminal shortcuts
/// such as Ctrl-D do not move controls.
#[must_use]
pub fn map_key<A: KeyAction>(event: &KeyEvent) -> Option<Input<A>> {
    if event.kind == KeyEventKind::Release {
        return None;
    }
    let ctrl = event.modifiers.contains(KeyModifiers::CONTROL);
    if ctrl && letter(event.code) == Some('c') {
        return Some(Input::App(AppCommand::Quit));
    }
    if ctrl || event.modifiers.contains(KeyModifiers::ALT) {
        return None;
    }
    match (event.code, letter(event.code)) {
        (KeyCode::Esc, _) | (_, Some('q')) => Some(Input::App(AppCommand::Quit)),
        (_, Some('p')) => Some(Input::App(AppCommand::Pause)),
        (_, Some('r')) => Some(Input::App(AppCommand::Reset)),
        _ => A::from_key(event.code).map(Input::Action),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::KeyEventState;
    use fdm_core::bourg::BourgAction;
    use fdm_core::palmer::PalmerAction;

    fn key(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    fn palmer(code: KeyCode) -> Option<Input<PalmerAction>> {
        map_key(&key(code))
    }

    fn bourg(code: KeyCode) -> Option<Input<BourgAction>> {
        map_key(&key(code))
    }

    #[test]
    fn palmer_table() {
        use PalmerAction::*;
        let table = [
            (KeyCode::Char('e'), ThrottleUp),
            (KeyCode::Char('E'), ThrottleUp),
            (KeyCode::Char('d'), ThrottleDown),
            (KeyCode::Down, AlphaUp),
            (KeyCode::Up, AlphaDown),
            (KeyCode::Left, BankLeft),
            (KeyCode::Right, BankRight),
            (KeyCode::Char('k'), FlapsDown),
            (KeyCode::Char('l'), FlapsUp),
            (KeyCode::Char('b'), BrakesOn),
            (KeyCode::Char('B'), BrakesOn),
            (KeyCode::Char('v'), BrakesOff),
        ];
        for (code, action) in table {
            assert_eq!(palmer(code), Some(Input::Action(action)), "{code:?}");
        }
        assert_eq!(palmer(KeyCode::Char('n')), None);
        assert_eq!(palmer(KeyCode::Char('x')), None);
    }

    #[test]
    fn bourg_table() {
        use BourgAction::*;
        let table = [
            (KeyCode::Char('e'), ThrustUp),
            (KeyCode::Char('D'), ThrustDown),
            (KeyCode::Down, PitchUp),
            (KeyCode::Up, PitchDown),
            (KeyCode::Left, RollLeft),
            (KeyCode::Right, RollRight),
            (KeyCode::Char('n'), YawLeft),
            (KeyCode::Char('m'), YawRight),
            (KeyCode::Char('k'), FlapsDown),
            (KeyCode::Char('l'), FlapsUp),
        ];
        for (code, action) in table {
            assert_eq!(bourg(code), Some(Input::Action(action)), "{code:?}");
        }
    }

    #[test]
    fn every_action_has_a_key() {
        use crossterm::event::KeyCode::*;
        let codes: Vec<KeyCode> = "abcdefghijklmnopqrstuvwxyz"
            .chars()
            .map(Char)
            .chain([Up, Down, Left, Right])
            .collect();
        for action in PalmerAction::ALL {
            assert!(codes
                .iter()
                .any(|&c| PalmerAction::from_key(c) == Some(*action)));
        }
        for action in BourgAction::ALL {
            assert!(codes
                .iter()
                .any(|&c| BourgAction::from_key(c) == Some(*action)));
        }
    }

    #[test]
    fn app_keys() {
        for code in [KeyCode::Char('q'), KeyCode::Char('Q'), KeyCode::Esc] {
            assert_eq!(palmer(code), Some(Input::App(AppCommand::Quit)));
        }
        assert_eq!(
            bourg(KeyCode::Char('p')),
            Some(Input::App(AppCommand::Pause))
        );
        assert_eq!(
            bourg(KeyCode::Char('R')),
            Some(Input::App(AppCommand::Reset))
        );
        let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(
            map_key::<BourgAction>(&ctrl_c),
            Some(Input::App(AppCommand::Quit))
        );
    }

    #[test]
    fn modifiers_and_kinds() {
        let ctrl_d = KeyEvent::new(KeyCode::Char('d'), KeyModifiers::CONTROL);
        assert_eq!(map_key::<PalmerAction>(&ctrl_d), None);
        let alt_e = KeyEvent::new(KeyCode::Char('e'), KeyModifiers::ALT);
        assert_eq!(map_key::<PalmerAction>(&alt_e), None);
        let shift_e = KeyEvent::new(KeyCode::Char('E'), KeyModifiers::SHIFT);
        assert_eq!(
            map_key::<PalmerAction>(&shift_e),
            Some(Input::Action(PalmerAction::ThrottleUp))
        );
        let kind = |kind| {
            KeyEvent::new_with_kind_and_state(
                KeyCode::Left,
                KeyModifiers::NONE,
                kind,
                KeyEventState::NONE,
            )
        };
        assert_eq!(
            map_key::<BourgAction>(&kind(KeyEventKind::Repeat)),
            Some(Input::Action(BourgAction::RollLeft))
        );
        assert_eq!(map_key::<BourgAction>(&kind(KeyEventKind::Release)), None);
    }
}
