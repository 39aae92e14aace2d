//! Scripted controls: the `START-END action` rule files of `sim-cli --script`.
//!
//! One rule per line, frames counted from 1 with both ends inclusive
//! (`7-7 flaps-down` is a single frame). `#` starts a comment and blank lines
//! are ignored. On every frame, the rules that cover it are applied in file
//! order, as if that key had been pressed once on that frame, before the step.
//!
//! The same parser serves both models; the model decides which action names
//! exist through [`ScriptAction`]. A leading UTF-8 byte-order mark is skipped.
//!
//! # Replaying a script
//!
//! [`Script::actions_at`] answers for any frame by scanning every rule, which is
//! fine for a single look-up but quadratic over a run (frames × rules). A run
//! that goes through frames in order keeps a [`ScriptCursor`] instead: it sweeps
//! the rules sorted by start frame and keeps the started, unfinished ones in file
//! order, so a whole run costs time linear in frames plus rules (plus the actions
//! it returns, times a logarithm for each rule that starts or ends). Both give the
//! same actions in the same order for every frame.
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
//!
//! // The same answers frame after frame, in linear time.
//! use fdm_core::script::ScriptCursor;
//! let mut cursor = ScriptCursor::new();
//! for frame in 1..=300 {
//!     assert!(cursor.actions(&script, frame).eq(script.actions_at(frame)));
//! }
//! ```

use alloc::collections::{BTreeSet, BinaryHeap};
use alloc::vec::Vec;
use core::cmp::Reverse;
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
    /// Indices into `rules`, sorted by `first_frame` (stable: file order among
    /// equal starts); the sweep order of [`ScriptCursor`].
    by_start: Vec<usize>,
}

impl<A> Default for Script<A> {
    fn default() -> Self {
        Self {
            rules: Vec::new(),
            by_start: Vec::new(),
        }
    }
}

/// Echoed input text in messages: control characters, NUL, escape sequences and
/// invisible format characters (such as a byte-order mark or a bidirectional
/// override) are shown escaped (`\u{1b}`, `\0`, `\n`, `\u{feff}`), and only the
/// first `max_chars` characters are shown, followed by `…` when there were more.
/// Quotes are left as they are; a backslash is doubled so the result is unambiguous.
///
/// ```
/// use fdm_core::script::Echo;
/// assert_eq!(Echo::new("a\u{1b}[2Jb", 80).to_string(), "a\\u{1b}[2Jb");
/// assert_eq!(Echo::new("abcdef", 3).to_string(), "abc…");
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Echo<'a> {
    text: &'a str,
    max_chars: usize,
}

impl<'a> Echo<'a> {
    /// Characters shown by [`Echo::short`].
    pub const DEFAULT_MAX_CHARS: usize = 80;

    /// Shows at most `max_chars` characters of `text`, escaped.
    #[must_use]
    pub fn new(text: &'a str, max_chars: usize) -> Self {
        Self { text, max_chars }
    }

    /// Shows at most [`Self::DEFAULT_MAX_CHARS`] characters of `text`, escaped.
    #[must_use]
    pub fn short(text: &'a str) -> Self {
        Self::new(text, Self::DEFAULT_MAX_CHARS)
    }
}

impl fmt::Display for Echo<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut chars = self.text.chars();
        for c in chars.by_ref().take(self.max_chars) {
            match c {
                '\'' | '"' => fmt::Write::write_char(f, c)?,
                _ => write!(f, "{}", c.escape_debug())?,
            }
        }
        if chars.next().is_some() {
            f.write_str("…")?;
        }
        Ok(())
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
                // The example names one of this model's own actions.
                let example = self.valid_actions.first().copied().unwrap_or("ACTION");
                write!(f, "expected `START-END ACTION` (e.g. `1-5 {example}`)")
            }
            ScriptErrorKind::BadFrame(text) => {
                write!(f, "`{}` is not a frame number", Echo::short(text))
            }
            ScriptErrorKind::StartBelowOne => f.write_str("frames are counted from 1"),
            ScriptErrorKind::EndBeforeStart { start, end } => {
                write!(f, "range {start}-{end} ends before it starts")
            }
            ScriptErrorKind::UnknownAction(name) => {
                write!(f, "unknown action `{}` (valid: ", Echo::short(name))?;
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
    /// script with any error, so a run never starts on half a script. A leading
    /// UTF-8 byte-order mark (U+FEFF, as some editors write) is skipped.
    ///
    /// # Errors
    /// [`ScriptError`] naming the 1-based line and the problem.
    pub fn parse(text: &str) -> Result<Self, ScriptError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
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
        Ok(Self::from_rules(rules))
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
        let mut by_start: Vec<usize> = (0..rules.len()).collect();
        // Stable, so rules with the same start stay in file order.
        by_start.sort_by_key(|&i| rules[i].first_frame);
        Self { rules, by_start }
    }

    /// The rules in file order.
    #[must_use]
    pub fn rules(&self) -> &[Rule<A>] {
        &self.rules
    }

    /// The actions to apply on `frame` (1-based), in file order.
    ///
    /// This scans every rule (time proportional to the number of rules); to go
    /// through a run frame by frame use a [`ScriptCursor`], which gives the same
    /// actions in linear total time.
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

/// Prints the script as rule lines (`START-END ACTION`, one per line, file order),
/// which [`Script::parse`] reads back to an equal script.
impl<A: ScriptAction> fmt::Display for Script<A> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for rule in &self.rules {
            writeln!(
                f,
                "{}-{} {}",
                rule.first_frame,
                rule.last_frame,
                rule.action.name()
            )?;
        }
        Ok(())
    }
}

/// A sweep over a [`Script`] for runs that go through frames in order: the same
/// actions as [`Script::actions_at`], in the same (file) order, in linear total time.
///
/// It holds no reference to the script, so it can live beside it (for example one
/// cursor per ECS entity next to a shared `Arc<Script>`); always pass it the same
/// script. Frames may skip ahead; going back (an interactive reset to frame 0)
/// restarts the sweep from the first rule, which costs one pass over the rules
/// that start before the new frame.
///
/// Cost per call: a logarithm for each rule that starts or ends since the previous
/// frame, plus the actions returned.
#[derive(Debug, Clone, Default)]
pub struct ScriptCursor {
    /// The frame of the last call (0 before the first).
    frame: u64,
    /// Next position in the script's start-sorted order to consider.
    next: usize,
    /// Indices (file order) of rules that started and have not ended.
    active: BTreeSet<usize>,
    /// `(last_frame, index)` of the active rules, earliest end first.
    ends: BinaryHeap<Reverse<(u64, usize)>>,
    /// Number of rules of the script this cursor swept (a cheap guard against
    /// being handed another script).
    rules_len: usize,
}

impl ScriptCursor {
    /// A cursor before frame 1.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Back to before frame 1.
    pub fn reset(&mut self) {
        self.frame = 0;
        self.next = 0;
        self.active.clear();
        self.ends.clear();
    }

    /// The frame of the last [`Self::actions`] call (0 before the first).
    #[must_use]
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// The actions to apply on `frame` (1-based), in file order: exactly
    /// `script.actions_at(frame)`.
    pub fn actions<'a, A: Copy>(
        &'a mut self,
        script: &'a Script<A>,
        frame: u64,
    ) -> impl Iterator<Item = A> + 'a {
        self.seek(script, frame);
        self.active.iter().map(move |&i| script.rules[i].action)
    }

    fn seek<A>(&mut self, script: &Script<A>, frame: u64) {
        if frame < self.frame || script.rules.len() != self.rules_len {
            self.reset();
            self.rules_len = script.rules.len();
        }
        self.frame = frame;
        // Rules that start by `frame`; those already over by then never enter.
        while let Some(&index) = script.by_start.get(self.next) {
            let rule = &script.rules[index];
            if rule.first_frame > frame {
                break;
            }
            self.next += 1;
            if rule.last_frame >= frame {
                self.active.insert(index);
                self.ends.push(Reverse((rule.last_frame, index)));
            }
        }
        // Rules that ended before `frame`.
        while let Some(&Reverse((last, index))) = self.ends.peek() {
            if last >= frame {
                break;
            }
            self.ends.pop();
            self.active.remove(&index);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bourg::BourgAction;
    use alloc::string::ToString;
    use alloc::vec;
    use proptest::prelude::*;

    /// The scan `actions_at` has always done, kept verbatim as the oracle for the cursor.
    fn naive<A: Copy>(rules: &[Rule<A>], frame: u64) -> Vec<A> {
        rules
            .iter()
            .filter(|rule| rule.first_frame <= frame && frame <= rule.last_frame)
            .map(|rule| rule.action)
            .collect()
    }

    fn rules_strategy() -> impl Strategy<Value = Vec<Rule<BourgAction>>> {
        let rule =
            (1_u64..60, 0_u64..40, 0..BourgAction::ALL.len()).prop_map(|(first, len, action)| {
                Rule {
                    first_frame: first,
                    last_frame: first + len,
                    action: BourgAction::ALL[action],
                }
            });
        proptest::collection::vec(rule, 0..40)
    }

    /// A frame sequence as runs see it: mostly +1, sometimes skipping ahead, sometimes
    /// back to frame 1 (an interactive reset), sometimes asking the same frame again.
    fn frames_strategy() -> impl Strategy<Value = Vec<u64>> {
        proptest::collection::vec(
            prop_oneof![8 => Just(1_u64), 1 => 2_u64..20, 1 => Just(0), 1 => Just(u64::MAX)],
            0..150,
        )
        .prop_map(|steps| {
            let mut frame = 0_u64;
            steps
                .into_iter()
                .map(|step| {
                    frame = match step {
                        u64::MAX => 1,
                        s => frame + s,
                    };
                    frame
                })
                .collect()
        })
    }

    proptest! {
        #[test]
        fn cursor_gives_the_naive_scan_for_every_frame(rules in rules_strategy(), frames in frames_strategy()) {
            let script = Script::from_rules(rules.clone());
            let mut cursor = ScriptCursor::new();
            for frame in frames {
                let swept: Vec<_> = cursor.actions(&script, frame).collect();
                prop_assert_eq!(&swept, &naive(&rules, frame), "frame {}", frame);
                let scanned: Vec<_> = script.actions_at(frame).collect();
                prop_assert_eq!(&scanned, &naive(&rules, frame), "frame {}", frame);
            }
        }

        #[test]
        fn printed_scripts_parse_back_equal(rules in rules_strategy()) {
            let script = Script::from_rules(rules);
            let text = script.to_string();
            prop_assert_eq!(Script::<BourgAction>::parse(&text), Ok(script));
        }
    }

    #[test]
    fn every_frame_in_order_matches_on_a_dense_script() {
        let rules: Vec<_> = (0..300_u64)
            .map(|i| Rule {
                first_frame: 1 + (i * 7919) % 97,
                last_frame: 1 + (i * 7919) % 97 + (i * 104_729) % 50,
                action: BourgAction::ALL[(i as usize) % BourgAction::ALL.len()],
            })
            .collect();
        let script = Script::from_rules(rules.clone());
        let mut cursor = ScriptCursor::new();
        for frame in 0..=160 {
            assert!(
                cursor.actions(&script, frame).eq(naive(&rules, frame)),
                "frame {frame}"
            );
        }
        assert_eq!(cursor.frame(), 160);
    }

    #[test]
    fn cursor_follows_a_new_script() {
        let a = Script::<BourgAction>::parse("1-9 thrust-up\n").unwrap();
        let b = Script::<BourgAction>::parse("1-9 thrust-down\n2-9 pitch-up\n").unwrap();
        let mut cursor = ScriptCursor::new();
        assert!(cursor.actions(&a, 3).eq([BourgAction::ThrustUp]));
        assert!(cursor
            .actions(&b, 4)
            .eq([BourgAction::ThrustDown, BourgAction::PitchUp]));
    }

    #[test]
    fn leading_byte_order_mark_is_skipped() {
        let script = Script::<BourgAction>::parse("\u{feff}1-2 thrust-up\n").unwrap();
        assert_eq!(script.rules().len(), 1);
        // Only a leading one: elsewhere it is part of a token, reported escaped.
        let err =
            Script::<BourgAction>::parse("1-2 thrust-up\n\u{feff}3-4 thrust-up\n").unwrap_err();
        assert_eq!(
            err.to_string(),
            "line 2: `\\u{feff}3` is not a frame number"
        );
    }

    #[test]
    fn echoed_text_is_escaped_and_truncated() {
        let err = Script::<BourgAction>::parse("1-2 a\u{1b}[2J\0b\n").unwrap_err();
        let message = err.to_string();
        assert!(
            message.starts_with("line 1: unknown action `a\\u{1b}[2J\\0b` (valid: "),
            "{message}"
        );
        assert!(!message.chars().any(char::is_control), "{message}");

        let long = vec!["x"; 10_000].concat();
        let err = Script::<BourgAction>::parse(&alloc::format!("1-2 {long}\n")).unwrap_err();
        let message = err.to_string();
        let shown = alloc::format!("`{}…`", &long[..Echo::DEFAULT_MAX_CHARS]);
        assert!(message.contains(&shown), "{message}");
        assert!(message.len() < 400, "{} bytes", message.len());
    }

    #[test]
    fn echo_keeps_printable_text() {
        assert_eq!(Echo::short("é'\"ü").to_string(), "é'\"ü");
        assert_eq!(Echo::short("a\\b").to_string(), "a\\\\b");
        assert_eq!(Echo::new("abc", 3).to_string(), "abc");
        assert_eq!(Echo::new("\u{202e}x", 80).to_string(), "\\u{202e}x");
    }
}
