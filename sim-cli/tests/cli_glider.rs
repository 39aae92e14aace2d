//! A third model flown from `sim-cli` (cargo feature `glider`: `cargo test -p
//! afit-fdm-cli --features glider --test cli_glider`): the point-mass glider of
//! `fdm-ecs/examples/third_model.rs`, added by one module
//! (`sim-cli/src/models/glider/`) and one line of the model registry
//! (`sim-cli/src/models/mod.rs`). Through the built binary: its subcommand
//! and help are there, derived from the registry; it flies headless with
//! the options every model shares; its report, CSV and recording name it;
//! the recording replays to the same bits; `plot` reads its CSV; `study`
//! flies studies of it (the CLI's registry is the list the study file's
//! `model` is looked up in); `fleet` (both kernels) and `fgfs-command` take
//! it by name.

mod support;

use support::{csv_body, report, scratch, sim, sim_ok, text, write_file};

#[test]
fn the_glider_is_a_subcommand_with_help_from_the_registry() {
    let help = sim_ok(&["--help"]);
    assert!(
        help.contains("Fly Palmer's Cessna 172, Bourg's 6-DoF aircraft or a point-mass glider"),
        "{help}"
    );
    let glider_line = help
        .lines()
        .find(|l| l.trim_start().starts_with("glider "))
        .unwrap_or_else(|| panic!("no glider subcommand: {help}"));
    assert!(glider_line.contains("Fly a point-mass glider"), "{help}");
    assert!(
        help.contains("`sim-cli palmer --help`, `sim-cli bourg --help` or `sim-cli glider --help`"),
        "{help}"
    );
    // The model subcommands come first, in the registry's order.
    let order: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take(4)
        .map(|l| l.split_whitespace().next().unwrap_or(""))
        .collect();
    assert_eq!(order, ["palmer", "bourg", "glider", "fgfs-command"]);

    let help = sim_ok(&["glider", "--help"]);
    for option in [
        "--lift-coefficient",
        "--fps",
        "--headless",
        "--csv",
        "--record",
        "--acmi",
    ] {
        assert!(help.contains(option), "glider help lacks {option}: {help}");
    }
    assert!(!help.contains("--throttle"), "{help}");

    let out = sim(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        "sim-cli: error: missing subcommand: palmer, bourg, glider, fgfs-command, fleet, study, \
         plot, replay or dis-listen (see --help)\n"
    );
    // --model's values and their help are the registry's too.
    let help = sim_ok(&["fleet", "--help"]);
    assert!(help.contains("- glider: a point-mass glider"), "{help}");
}

#[test]
fn the_glider_flies_headless_and_reports_as_itself() {
    let v = report(&["glider", "--headless", "--frames", "90", "--json"]);
    assert_eq!(v["model"], "glider");
    assert_eq!(v["frames"], 90);
    assert_eq!(v["status"], "airborne");
    assert_eq!(v["lift_coefficient"], 0.6);
    assert_eq!(v["time_s"], 2.999999999999999);
    let z = v["position"][2].as_f64().unwrap();
    assert!(z < 600.0 && z > 500.0, "{v}");

    // A bad value of its own option is a usage error, in the CLI's words.
    let out = sim(&[
        "glider",
        "--headless",
        "--frames",
        "1",
        "--lift-coefficient",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("`2` is not a lift coefficient in 0..1.4"),
        "{stderr}"
    );
    // A script of its own actions, counted from frame 1.
    let dir = scratch("glider-script");
    let script = write_file(&dir, "bank.txt", "1-6 bank-right\n");
    let v = report(&[
        "glider",
        "--headless",
        "--frames",
        "30",
        "--json",
        "--script",
        &script,
    ]);
    assert_eq!(v["bank_deg"], 30.0);
}

/// The CSV and the recording name the model (from the registry), `sim-cli
/// plot` replots the CSV, and the recording replays to the recorded
/// flight's report and CSV, byte for byte; the ACMI file names it too.
#[test]
fn the_glider_records_replays_and_writes_its_outputs() {
    let dir = scratch("glider-outputs");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let (rec, csv, acmi, plot) = (path("g.rec"), path("g.csv"), path("g.acmi"), path("g.svg"));
    let flown = sim_ok(&[
        "glider",
        "--headless",
        "--frames",
        "120",
        "--json",
        "--lift-coefficient",
        "0.9",
        "--record",
        &rec,
        "--csv",
        &csv,
        "--acmi",
        &acmi,
        "--plot",
        &plot,
    ]);
    let header = std::fs::read_to_string(&csv).unwrap();
    let header = csv_body(&header, "glider").lines().next().unwrap();
    assert!(
        header.ends_with(",airspeed,lift_coefficient,bank_deg,status"),
        "{header}"
    );
    let recording = std::fs::read(&rec).unwrap();
    assert!(
        recording.windows(6).any(|w| w == b"glider"),
        "the recording names its model"
    );
    let acmi_text = std::fs::read_to_string(&acmi).unwrap();
    assert!(acmi_text.contains("Name=Glider"), "{acmi_text}");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(
        svg.contains("Point-mass glider"),
        "the plot's title is the model's"
    );

    // `sim-cli plot` reads the glider's CSV (its model line names it; the
    // glider is in the CLI's registry, not the run library's) and draws
    // the run's own plot but for the title, which names the file.
    let replot = path("replot.svg");
    sim_ok(&["plot", &csv, "-o", &replot]);
    let replotted = std::fs::read_to_string(&replot).unwrap();
    assert!(
        replotted.contains(&format!("Point-mass glider from {csv}: 121 samples")),
        "the replot's title names the model and the file"
    );
    let without_title = |svg: &str| {
        let start = svg.find("<text").expect("a title");
        let end = start + svg[start..].find("</text>").expect("closed");
        format!("{}{}", &svg[..start], &svg[end..])
    };
    assert_eq!(without_title(&replotted), without_title(&svg));

    let replay_csv = path("replay.csv");
    let replayed = sim_ok(&["replay", &rec, "--json", "--csv", &replay_csv]);
    assert_eq!(replayed, flown);
    assert_eq!(
        std::fs::read(&replay_csv).unwrap(),
        std::fs::read(&csv).unwrap()
    );
}

#[test]
fn fleets_and_fgfs_take_the_glider_by_name() {
    for kernel in ["lanes", "ecs"] {
        let out = sim_ok(&[
            "fleet",
            "--model",
            "glider",
            "--aircraft",
            "16",
            "--frames",
            "30",
            "--kernel",
            kernel,
            "--json",
        ]);
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["model"], "glider", "{out}");
        assert_eq!(v["aircraft"], 16);
        assert_eq!(v["diverged"], 0, "{out}");
    }
    let line = sim_ok(&["fgfs-command", "glider"]);
    assert!(line.contains("--aircraft=ufo"), "{line}");
}

/// A study of the glider: the study file's `model` is looked up in the
/// CLI's registry (the glider is not in the run library's), the batch flies
/// on the lanes fleets, and `--run I` flies run I alone to the batch's row,
/// with its own CSV naming the model.
#[test]
fn the_glider_is_studied_by_name() {
    let dir = scratch("glider-study");
    let file = write_file(
        &dir,
        "g.toml",
        r#"
model = "glider"
runs = 8
seed = 5
duration_s = 4.0
measures = ["final_x_m", "max_height_m"]
[controls]
lift_coefficient = 0.8
[[dispersion]]
key = "controls.bank_deg"
distribution = "uniform"
low = -20.0
high = 20.0
"#,
    );
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    let o = sim(&["study", &file, "--out", out_s]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = runs.lines().collect();
    assert_eq!(
        lines[0],
        "run,status,final_x_m,max_height_m,input.controls.bank_deg,fingerprint"
    );
    assert_eq!(lines.len(), 1 + 8);
    let flight_csv = dir.join("run-3-flight.csv");
    let o = sim(&[
        "study",
        &file,
        "--out",
        out_s,
        "--run",
        "3",
        "--csv",
        flight_csv.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let alone = std::fs::read_to_string(out.join("run-3.csv")).unwrap();
    let alone: Vec<&str> = alone.lines().collect();
    assert_eq!(alone, [lines[0], lines[4]]);
    let flight = std::fs::read_to_string(&flight_csv).unwrap();
    assert_eq!(csv_body(&flight, "glider").lines().count(), 1 + 121);
}
