//! Palmer's wheel brakes through the built `sim-cli` (docs/palmer-model.md
//! "Wheel brakes"): `--brakes` holds the aircraft at rest against full power,
//! the report says so, and the script actions `brakes-on` / `brakes-off` are
//! recorded and replayed byte for byte (the recording's header carries the
//! brakes in its compact controls).

mod support;

use support::{report, scratch, sim, sim_ok, text, triple, write_file};

#[test]
fn brakes_hold_at_full_power_and_show_in_the_report() {
    let held = report(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "30",
        "--throttle",
        "1",
        "--brakes",
    ]);
    // Exactly at rest: the friction cancels the thrust (tolerance 0).
    assert_eq!(triple(&held["position"]), [0.0; 3], "{held}");
    assert_eq!(held["controls"]["brakes"], true, "{held}");
    let free = report(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "30",
        "--throttle",
        "1",
    ]);
    assert!(triple(&free["position"])[0] > 1.0, "{free}");
    // Off, the report is as it was before the brakes existed.
    assert!(free["controls"].get("brakes").is_none(), "{free}");
}

/// Tolerance 0: the JSON and CSV print every f64 in its shortest round-trip
/// form, so equal text is equal bits.
#[test]
fn braked_flights_replay_byte_for_byte() {
    let dir = scratch("brakes");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    // Held at full power, released for the take-off roll, braked again.
    let script = write_file(&dir, "brakes.txt", "31-31 brakes-off\n90-90 brakes-on\n");
    let (rec, csv1, csv2) = (path("b.rec"), path("1.csv"), path("2.csv"));
    let original = sim_ok(&[
        "palmer",
        "--headless",
        "--json",
        "--fps",
        "10",
        "--frames",
        "300",
        "--throttle",
        "1",
        "--brakes",
        "--script",
        &script,
        "--csv",
        &csv1,
        "--record",
        &rec,
    ]);
    let replayed = sim_ok(&["replay", &rec, "--json", "--csv", &csv2]);
    assert_eq!(original, replayed);
    assert_eq!(std::fs::read(&csv1).unwrap(), std::fs::read(&csv2).unwrap());
    let r: serde_json::Value = serde_json::from_str(&original).unwrap();
    assert_eq!(r["controls"]["brakes"], true, "{r}");
    // It rolled after frame 31, and the brakes stopped it again, at full
    // power (below 0.01 m/s, the stop of fdm-core/tests/wheel_brakes.rs: the
    // friction takes at most the whole speed per Runge-Kutta stage, so the
    // last of it fades geometrically).
    assert!(triple(&r["position"])[0] > 10.0, "{r}");
    let v = triple(&r["velocity"]);
    assert!(
        (0.0..0.01).contains(&v[0]) && v[1] == 0.0 && v[2] == 0.0,
        "{r}"
    );
}

#[test]
fn the_keys_help_names_the_brakes() {
    let out = sim(&["palmer", "--help"]);
    let help = text(&out.stdout);
    assert!(help.contains("--brakes"), "{help}");
}
