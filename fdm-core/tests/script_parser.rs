//! The script parser (`fdm_core::script`, docs/cli.md "Script files") on the
//! inputs its checks exist for, and the `Script` accessors.

use fdm_core::palmer::PalmerAction;
use fdm_core::script::{Rule, Script, ScriptErrorKind};

fn kind(text: &str) -> ScriptErrorKind {
    Script::<PalmerAction>::parse(text).unwrap_err().kind
}

/// A frame number is unsigned decimal digits only: a sign, which Rust's
/// integer parser would accept, is refused, as is an empty number.
#[test]
fn frame_numbers_are_digits_only() {
    for (text, bad) in [
        ("+5-7 throttle-up", "+5"),
        ("5-+7 throttle-up", "+7"),
        ("-7 throttle-up", ""),
        ("5- throttle-up", ""),
        ("0x5-7 throttle-up", "0x5"),
        ("5-7.0 throttle-up", "7.0"),
        ("99999999999999999999-1 throttle-up", "99999999999999999999"),
    ] {
        assert_eq!(kind(text), ScriptErrorKind::BadFrame(bad.into()), "{text}");
    }
    let s = Script::<PalmerAction>::parse("05-007 throttle-up").unwrap();
    assert_eq!((s.rules()[0].first_frame, s.rules()[0].last_frame), (5, 7));
}

#[test]
fn rule_checks() {
    assert_eq!(kind("0-3 throttle-up"), ScriptErrorKind::StartBelowOne);
    assert_eq!(
        kind("3-2 throttle-up"),
        ScriptErrorKind::EndBeforeStart { start: 3, end: 2 }
    );
    assert_eq!(kind("3 throttle-up"), ScriptErrorKind::Malformed);
    assert_eq!(kind("1-2 throttle-up extra"), ScriptErrorKind::Malformed);
    assert_eq!(kind("1-2"), ScriptErrorKind::Malformed);
    assert_eq!(
        kind("1-2 thrust-up"),
        ScriptErrorKind::UnknownAction("thrust-up".into())
    );
    let err = Script::<PalmerAction>::parse("# c\n\n1-1 throttle-up\n2-1 alpha-up\n").unwrap_err();
    assert_eq!(err.line, 4);
}

/// `rules` gives the rules in file order, `from_rules` builds the same
/// script from them, `last_frame` is the largest end (0 when empty), and
/// `actions_at` covers both ends of each range.
#[test]
fn accessors() {
    let text = "3-9 throttle-up # full\n1-1 alpha-up\n12-12 flaps-down\n2-4 bank-left\n";
    let s = Script::<PalmerAction>::parse(text).unwrap();
    let want = [
        Rule {
            first_frame: 3,
            last_frame: 9,
            action: PalmerAction::ThrottleUp,
        },
        Rule {
            first_frame: 1,
            last_frame: 1,
            action: PalmerAction::AlphaUp,
        },
        Rule {
            first_frame: 12,
            last_frame: 12,
            action: PalmerAction::FlapsDown,
        },
        Rule {
            first_frame: 2,
            last_frame: 4,
            action: PalmerAction::BankLeft,
        },
    ];
    assert_eq!(s.rules(), want);
    assert_eq!(s.last_frame(), 12);
    let rebuilt = Script::from_rules(want.to_vec());
    assert_eq!(rebuilt.rules(), s.rules());
    for frame in 0..=13 {
        let a: Vec<_> = s.actions_at(frame).collect();
        let b: Vec<_> = rebuilt.actions_at(frame).collect();
        assert_eq!(a, b);
    }
    assert_eq!(
        s.actions_at(3).collect::<Vec<_>>(),
        [PalmerAction::ThrottleUp, PalmerAction::BankLeft]
    );
    assert_eq!(
        s.actions_at(9).collect::<Vec<_>>(),
        [PalmerAction::ThrottleUp]
    );
    assert_eq!(s.actions_at(10).count(), 0);
    assert_eq!(s.actions_at(0).count(), 0);
    assert_eq!(
        Script::<PalmerAction>::parse("# nothing\n")
            .unwrap()
            .last_frame(),
        0
    );
    assert_eq!(
        Script::<PalmerAction>::from_rules(Vec::new()).last_frame(),
        0
    );
}

/// docs/cli.md: an unknown action's message lists the valid ones: every
/// script name of the model, in its order, separated by ", ".
#[test]
fn an_unknown_actions_message_lists_every_valid_action_once() {
    use fdm_core::bourg::BourgAction;
    use fdm_core::model::ScriptAction;
    let err = Script::<PalmerAction>::parse("1-2 thrust-up").unwrap_err();
    let names = PalmerAction::NAMES.join(", ");
    let message = err.to_string();
    assert!(
        message.ends_with(&format!("unknown action `thrust-up` (valid: {names})")),
        "{message}"
    );
    let err = Script::<BourgAction>::parse("\n7-9 throttle-up").unwrap_err();
    let names = BourgAction::NAMES.join(", ");
    assert!(
        err.to_string()
            .ends_with(&format!("unknown action `throttle-up` (valid: {names})")),
        "{err}"
    );
}

/// `ScriptCursor::actions` is exactly `script.actions_at(frame)`, also when
/// one cursor is handed another script (with another number of rules) part
/// way through, and when frames go back.
#[test]
fn a_cursor_handed_another_script_gives_that_scripts_actions() {
    use fdm_core::script::ScriptCursor;
    let a = Script::<PalmerAction>::parse("1-10 throttle-up\n3-4 alpha-up\n").unwrap();
    let b =
        Script::<PalmerAction>::parse("1-3 bank-left\n2-9 flaps-down\n5-6 alpha-down\n").unwrap();
    let mut cursor = ScriptCursor::new();
    for (script, frame) in [
        (&a, 1),
        (&a, 3),
        (&b, 5),
        (&b, 6),
        (&a, 7),
        (&a, 2),
        (&b, 2),
    ] {
        let got: Vec<_> = cursor.actions(script, frame).collect();
        let want: Vec<_> = script.actions_at(frame).collect();
        assert_eq!(got, want, "frame {frame}");
        assert_eq!(cursor.frame(), frame);
    }
}
