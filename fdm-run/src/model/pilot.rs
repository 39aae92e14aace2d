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
