//! Scripted controls: the `START-END action` rule files of `sim-cli --script`.
//!
//! One rule per line, frames counted from 1 with both ends inclusive
//! (`7-7 flaps-down` is a single frame). `#` starts a comment and blank lines
//! are ignored. On every frame, the rules that cover it are applied in file
//! order, as if that key had been pressed once on that frame, before the step.
//!
//! The same parser serves both models; the model decides which action names
//! exist through [`ScriptAction`].
//!
//! ```
//! use fdm_core::bourg::BourgAction;
//! use fdm_core::script::Script;
//!
//! let script: Script<BourgAction> =
//!     Script::parse("1-5 thrust-up   # full power\n6-246 pitch-up\n").unwrap();
//! let on_frame_3: Vec<_> = script.actions_at(3).collect();
//! assert_eq!(on_frame_3, [BourgAction::ThrustUp]);
//! assert_eq!(script.actions_at(247).count(), 0);
//! ```

use alloc::vec::Vec;
use core::fmt;

pub use crate::model::ScriptAction;

/// One script rule: apply `action` on every frame in `first_frame..=last_frame`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rule<A> {
    /// First frame the rule applies to (1-based, inclusive).
    pub first_frame: u64,
    /// Last frame the rule applies to (inclusive, `>= first_frame`).
    pub last_frame: u64,
    /// The action applied once per covered frame.
    pub action: A,
}

impl<A> Rule<A> {
    /// Whether the rule covers `frame` (1-based).
    #[must_use]
    pub fn covers(&self, frame: u64) -> bool {
        self.first_frame <= frame && frame <= self.last_frame
    }
}

/// A parsed script: rules in file order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Script<A> {
    rules: Vec<Rule<A>>,
}

impl<A> Default for Script<A> {
    fn default() -> Self {
        Self { rules: Vec::new() }
    }
}

/// What is wrong with a script line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ScriptErrorKind {
    /// The line is not `START-END ACTION`.
    Malformed,
    /// A frame number is not a non-negative integer that fits in `u64`.
    BadFrame(
        /// The offending text.
        alloc::string::String,
    ),
    /// `START` is 0; frames are counted from 1.
    StartBelowOne,
    /// `END < START`.
    EndBeforeStart {
        /// The rule's start frame.
        start: u64,
        /// The rule's end frame.
        end: u64,
    },
    /// The action name is not one of the model's actions.
    UnknownAction(
        /// The name as written.
        alloc::string::String,
    ),
}

/// A script parse error: which line (1-based) and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    /// 1-based line number in the script text.
    pub line: usize,
    /// What is wrong.
    pub kind: ScriptErrorKind,
    /// The valid action names, for the message.
    pub valid_actions: &'static [&'static str],
}

impl fmt::Display for ScriptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: ", self.line)?;
        match &self.kind {
            ScriptErrorKind::Malformed => {
                f.write_str("expected `START-END ACTION` (e.g. `1-5 thrust-up`)")
            }
            ScriptErrorKind::BadFrame(text) => write!(f, "`{text}` is not a frame number"),
            ScriptErrorKind::StartBelowOne => f.write_str("frames are counted from 1"),
            ScriptErrorKind::EndBeforeStart { start, end } => {
                write!(f, "range {start}-{end} ends before it starts")
            }
            ScriptErrorKind::UnknownAction(name) => {
                write!(f, "unknown action `{name}` (valid: ")?;
                for (i, valid) in self.valid_actions.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    f.write_str(valid)?;
                }
                f.write_str(")")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ScriptError {}

fn parse_frame(text: &str) -> Result<u64, ScriptErrorKind> {
    let text = text.trim();
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(ScriptErrorKind::BadFrame(text.into()));
    }
    text.parse()
        .map_err(|_| ScriptErrorKind::BadFrame(text.into()))
}

impl<A: ScriptAction> Script<A> {
    /// Parses script text. The first bad line is reported; nothing is returned for a
    /// script with any error, so a run never starts on half a script.
    ///
    /// # Errors
    /// [`ScriptError`] naming the 1-based line and the problem.
    pub fn parse(text: &str) -> Result<Self, ScriptError> {
        let mut rules = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let rule = Self::parse_rule(line).map_err(|kind| ScriptError {
                line: index + 1,
                kind,
                valid_actions: A::NAMES,
            })?;
            rules.push(rule);
        }
        Ok(Self { rules })
    }

    fn parse_rule(line: &str) -> Result<Rule<A>, ScriptErrorKind> {
        let mut words = line.split_whitespace();
        let (Some(range), Some(action), None) = (words.next(), words.next(), words.next()) else {
            return Err(ScriptErrorKind::Malformed);
        };
        let (start, end) = range.split_once('-').ok_or(ScriptErrorKind::Malformed)?;
        let start = parse_frame(start)?;
        let end = parse_frame(end)?;
        if start < 1 {
            return Err(ScriptErrorKind::StartBelowOne);
        }
        if end < start {
            return Err(ScriptErrorKind::EndBeforeStart { start, end });
        }
        let action =
            A::from_name(action).ok_or_else(|| ScriptErrorKind::UnknownAction(action.into()))?;
        Ok(Rule {
            first_frame: start,
            last_frame: end,
            action,
        })
    }

    /// Builds a script from rules (already validated by the caller).
    #[must_use]
    pub fn from_rules(rules: Vec<Rule<A>>) -> Self {
        Self { rules }
    }

    /// The rules in file order.
    #[must_use]
    pub fn rules(&self) -> &[Rule<A>] {
        &self.rules
    }

    /// The actions to apply on `frame` (1-based), in file order.
    pub fn actions_at(&self, frame: u64) -> impl Iterator<Item = A> + '_ {
        self.rules
            .iter()
            .filter(move |rule| rule.covers(frame))
            .map(|rule| rule.action)
    }

    /// The last frame any rule covers (0 for an empty script).
    #[must_use]
    pub fn last_frame(&self) -> u64 {
        self.rules.iter().map(|r| r.last_frame).max().unwrap_or(0)
    }
}
