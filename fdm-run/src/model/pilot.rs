//! What a front end needs of a model to fly it by hand, as data: what it
//! flies, its start options and the controls at frame 0 made from them, its
//! keys, and the controls line of a head-up display ([`PilotModel`]).
//!
//! A front end (`sim-cli`) builds its subcommand's options from the table
//! [`PilotModel::START_OPTIONS`] with whatever argument parser it uses, reads
//! its key presses as [`Key`]s and looks them up in the action type's
//! [`KeyBindings::KEYS`], and shows the report fields' [`ControlsLine`]; it
//! never names a model. The library's models implement these in their
//! adapter modules ([`palmer`](super::palmer), [`bourg`](super::bourg)); a
//! model outside the library crates implements them in its own module.

use fdm_core::model::ScriptAction;

use crate::input::Echo;
use crate::report::ReportModel;
use crate::values::{parse_in_range, parse_number, ValueError};

/// A model a pilot flies from a front end: a [`ReportModel`] whose actions
/// are bound to keys ([`KeyBindings`]) and whose report fields make the
/// head-up display's controls line ([`ControlsLine`]), with what it flies
/// and its start options.
pub trait PilotModel: ReportModel<Action: KeyBindings, Details: ControlsLine> {
    /// What the model flies, in a few words for help texts: `Palmer's Cessna 172`.
    const AIRCRAFT: &'static str;
    /// The one-line help of the model's command (`sim-cli palmer`).
    const ABOUT: &'static str;
    /// The model's own start options, in the order help texts list them.
    const START_OPTIONS: &'static [StartOption];

    /// The controls at frame 0 from the values of [`Self::START_OPTIONS`],
    /// in the table's order (each of the kind its option parses to).
    ///
    /// # Errors
    /// A one-line message for values the model refuses (a usage error).
    fn start_controls(values: &[OptionValue]) -> Result<Self::Controls, String>;
}

/// One start option: `--LONG`, with a value or as a flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartOption {
    /// The option's long name, without the dashes: `throttle`. Also its
    /// identity in [`Self::conflicts_with`].
    pub long: &'static str,
    /// Its help line.
    pub help: &'static str,
    /// What it takes.
    pub kind: OptionKind,
    /// The long names of options it cannot be given with (other start
    /// options, or the front end's own: `sim-cli`'s `trim`).
    pub conflicts_with: &'static [&'static str],
}

impl StartOption {
    /// A number option (`default`: the text it has when not given, or none).
    #[must_use]
    pub const fn number(
        long: &'static str,
        value_name: &'static str,
        help: &'static str,
        range: NumberRange,
        default: Option<&'static str>,
    ) -> Self {
        let kind = OptionKind::Number {
            value_name,
            range,
            default,
        };
        Self::new(long, help, kind)
    }

    /// An option taking one of `choices`, `default` when not given.
    #[must_use]
    pub const fn choice(
        long: &'static str,
        value_name: &'static str,
        help: &'static str,
        choices: Choices,
        default: &'static str,
    ) -> Self {
        let kind = OptionKind::Choice {
            value_name,
            choices,
            default,
        };
        Self::new(long, help, kind)
    }

    /// A flag: set when given.
    #[must_use]
    pub const fn flag(long: &'static str, help: &'static str) -> Self {
        Self::new(long, help, OptionKind::Flag)
    }

    /// This option, not to be given with the options named `others`.
    #[must_use]
    pub const fn conflicting(self, others: &'static [&'static str]) -> Self {
        Self {
            conflicts_with: others,
            ..self
        }
    }

    const fn new(long: &'static str, help: &'static str, kind: OptionKind) -> Self {
        Self {
            long,
            help,
            kind,
            conflicts_with: &[],
        }
    }
}

/// What a start option takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OptionKind {
    /// A number in a range ([`OptionValue::Number`], or
    /// [`OptionValue::Absent`] when not given and without a default).
    Number {
        /// The value's name in help texts: `DEG`.
        value_name: &'static str,
        /// The numbers accepted.
        range: NumberRange,
        /// The value when the option is not given, as text (parsed as if
        /// given; shown by help texts), or none.
        default: Option<&'static str>,
    },
    /// One of fixed choices ([`OptionValue::Choice`]).
    Choice {
        /// The value's name in help texts: `0|20|40`.
        value_name: &'static str,
        /// The choices.
        choices: Choices,
        /// The choice when the option is not given.
        default: &'static str,
    },
    /// A flag ([`OptionValue::Flag`]).
    Flag,
}

/// The numbers a start option accepts: finite, `low..=high`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumberRange {
    /// The least value.
    pub low: f64,
    /// The greatest value.
    pub high: f64,
    /// What a refusal says.
    pub note: RangeNote,
}

/// What the message refusing a number says besides the range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RangeNote {
    /// The unit, with its leading space (`" degrees"`):
    /// [`parse_in_range`]'s messages.
    Unit(&'static str),
    /// What the value is (`"a lift coefficient"`): [`parse_number`]'s
    /// message.
    What(&'static str),
}

impl NumberRange {
    /// The number `text` says, if in range.
    ///
    /// # Errors
    /// The refusal as [`parse_in_range`] or [`parse_number`] words it.
    pub fn parse(&self, text: &str) -> Result<f64, ValueError> {
        match self.note {
            RangeNote::Unit(unit) => parse_in_range(text, self.low, self.high, unit),
            RangeNote::What(what) => parse_number(text, self.low, self.high, what),
        }
    }
}

/// The fixed choices of a start option.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Choices {
    /// The choices as typed.
    pub values: &'static [&'static str],
    /// What a value is, for the refusal: `a flap setting (0, 20 or 40)`.
    pub what: &'static str,
}

impl Choices {
    /// The choice `text` is (around spaces).
    ///
    /// # Errors
    /// `` `TEXT` is not WHAT ``.
    pub fn parse(&self, text: &str) -> Result<&'static str, String> {
        let typed = text.trim();
        self.values
            .iter()
            .copied()
            .find(|&choice| choice == typed)
            .ok_or_else(|| format!("`{}` is not {}", Echo::short(text), self.what))
    }
}

/// The value of one start option, as [`PilotModel::start_controls`] takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OptionValue {
    /// A number ([`OptionKind::Number`]).
    Number(f64),
    /// A choice, as the table spells it ([`OptionKind::Choice`]).
    Choice(&'static str),
    /// A flag, set or not ([`OptionKind::Flag`]).
    Flag(bool),
    /// A number option without a default, not given.
    Absent,
}

/// The message for values that do not match a model's
/// [`PilotModel::START_OPTIONS`] (a front end's mistake, not the user's).
#[must_use]
pub fn unexpected_values(values: &[OptionValue]) -> String {
    format!("start options' values not as the model's table: {values:?}")
}

/// A key as a front end reports it: a letter or an arrow key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
    /// A character key, lowercase (a front end matches letters whatever
    /// their case).
    Char(char),
    /// The up arrow.
    Up,
    /// The down arrow.
    Down,
    /// The left arrow.
    Left,
    /// The right arrow.
    Right,
}

/// A model's actions bound to keys.
pub trait KeyBindings: ScriptAction {
    /// Each key and the action it stands for.
    const KEYS: &'static [(Key, Self)];
    /// One line of key help for a head-up display.
    const KEY_HELP: &'static str;

    /// The action `key` stands for, if any.
    #[must_use]
    fn for_key(key: Key) -> Option<Self> {
        Self::KEYS
            .iter()
            .find(|(bound, _)| *bound == key)
            .map(|&(_, action)| action)
    }
}

/// A model's report fields shown as a head-up display's controls line.
pub trait ControlsLine {
    /// The controls line: `THRUST  500 lb   FLAPS up   TRIM +0.00`.
    fn controls_line(&self) -> String;
}

/// `x` for a display with one decimal, except that values that show as zero are
/// +0.0, so a tiny negative roll does not flicker as "-0.0".
#[must_use]
pub fn tenths(x: f64) -> f64 {
    if (x * 10.0).round() == 0.0 {
        0.0
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::{Bourg, BourgAction};
    use fdm_core::palmer::{Palmer, PalmerAction};

    /// A value shown with one decimal that shows as zero is +0.0 (no
    /// "-0.0" for a tiny negative roll); every other value is itself.
    #[test]
    fn tenths_shows_no_negative_zero() {
        for x in [-0.04, -0.0, 0.0, 0.04, -1e-12] {
            assert_eq!(tenths(x).to_bits(), 0.0_f64.to_bits(), "{x}");
            assert_eq!(format!("{:+5.1}", tenths(x)), " +0.0", "{x}");
        }
        for x in [-0.06, 0.06, -3.0, 12.34, -19.96] {
            assert_eq!(tenths(x).to_bits(), x.to_bits(), "{x}");
        }
        assert_eq!(format!("{:+5.1}", tenths(-0.06)), " -0.1");
    }

    /// Each key stands for the action its model binds it to (docs/cli.md's
    /// keys), and a key bound to nothing for none.
    #[test]
    fn keys_stand_for_their_actions() {
        assert_eq!(
            PalmerAction::for_key(Key::Char('e')),
            Some(PalmerAction::ThrottleUp)
        );
        assert_eq!(
            PalmerAction::for_key(Key::Up),
            Some(PalmerAction::AlphaDown)
        );
        assert_eq!(
            PalmerAction::for_key(Key::Char('v')),
            Some(PalmerAction::BrakesOff)
        );
        assert_eq!(PalmerAction::for_key(Key::Char('t')), None);
        assert_eq!(
            BourgAction::for_key(Key::Char('t')),
            Some(BourgAction::TrimNoseUp)
        );
        assert_eq!(BourgAction::for_key(Key::Down), Some(BourgAction::PitchUp));
        assert_eq!(BourgAction::for_key(Key::Char('b')), None);
        // Every binding is found, each key bound once.
        for &(key, action) in PalmerAction::KEYS {
            assert_eq!(PalmerAction::for_key(key), Some(action), "{key:?}");
        }
        for &(key, action) in BourgAction::KEYS {
            assert_eq!(BourgAction::for_key(key), Some(action), "{key:?}");
        }
    }

    /// The start options' values are parsed and refused as their tables
    /// say: Palmer's throttle (a fraction, with its unit in the refusal),
    /// its flaps (one of three choices, around spaces), a range refused
    /// with what the value is; Bourg's thrust not with `--trim`.
    #[test]
    fn start_options_parse_and_refuse_their_values() {
        let options = Palmer::START_OPTIONS;
        let names: Vec<&str> = options.iter().map(|o| o.long).collect();
        assert_eq!(names, ["throttle", "alpha", "bank", "flaps", "brakes"]);
        let OptionKind::Number { range, default, .. } = options[0].kind else {
            panic!("{:?}", options[0]);
        };
        assert_eq!(default, Some("0"));
        assert_eq!(range.parse(" 0.25 "), Ok(0.25));
        assert!(range.parse("-0.5").is_err());
        assert_eq!(
            range.parse("2").unwrap_err().to_string(),
            "`2` is outside 0..1 (fraction of full power)"
        );
        let OptionKind::Choice { choices, .. } = options[3].kind else {
            panic!("{:?}", options[3]);
        };
        assert_eq!(choices.parse(" 20 "), Ok("20"));
        assert_eq!(choices.parse("40"), Ok("40"));
        assert_eq!(
            choices.parse("30"),
            Err("`30` is not a flap setting (0, 20 or 40)".to_string())
        );
        assert_eq!(options[4].kind, OptionKind::Flag);
        assert!(options.iter().all(|o| o.conflicts_with.is_empty()));

        let lift = NumberRange {
            low: 0.0,
            high: 1.4,
            note: RangeNote::What("a lift coefficient"),
        };
        assert_eq!(lift.parse("1.25"), Ok(1.25));
        assert_eq!(
            lift.parse("1.5").unwrap_err().to_string(),
            "`1.5` is not a lift coefficient in 0..1.4"
        );

        let [thrust] = Bourg::START_OPTIONS else {
            panic!("{:?}", Bourg::START_OPTIONS);
        };
        assert_eq!(thrust.long, "thrust-lb");
        assert_eq!(thrust.conflicts_with, ["trim"]);
    }

    /// Values that do not match a model's table are refused naming them.
    #[test]
    fn values_not_as_the_table_are_named() {
        let values = [OptionValue::Flag(true), OptionValue::Number(2.5)];
        let message = unexpected_values(&values);
        assert_eq!(
            message,
            "start options' values not as the model's table: [Flag(true), Number(2.5)]"
        );
        assert_eq!(Bourg::start_controls(&values), Err(message));
    }
}
