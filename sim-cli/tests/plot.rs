//! `--plot` and `sim-cli plot` on the built binary: the SVG is well-formed XML, has
//! every panel, axis unit and series, and a plot redrawn from the run's CSV draws
//! exactly the same lines as the plot of the run itself.

mod support;

use quick_xml::events::Event;
use quick_xml::Reader;
use support::{scratch, sim, sim_ok, text};

/// What an SVG holds: its text labels and the number of points of each polyline.
struct Svg {
    texts: Vec<String>,
    polylines: Vec<usize>,
}

/// Parses `svg` as XML (panicking on malformed XML) and collects texts and polylines.
fn parse(svg: &str) -> Svg {
    let mut reader = Reader::from_str(svg);
    let mut texts = Vec::new();
    let mut polylines = Vec::new();
    let mut depth = 0_i32;
    let mut current = String::new();
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Start(_) => {
                depth += 1;
                current.clear();
            }
            Event::End(_) => {
                depth -= 1;
                let t = current.trim();
                if !t.is_empty() {
                    texts.push(t.to_owned());
                }
                current.clear();
            }
            Event::Empty(e) if e.name().as_ref() == b"polyline" => {
                let points = e
                    .try_get_attribute("points")
                    .expect("attribute")
                    .expect("polyline has points");
                let points = points.unescape_value().expect("points");
                polylines.push(points.split_whitespace().count());
            }
            Event::Text(t) => current.push_str(&t.decode().expect("text")),
            // quick-xml reports `&amp;` and the like as events of their own.
            Event::GeneralRef(r) => {
                let name = r.decode().expect("entity");
                let c = quick_xml::escape::resolve_xml_entity(&name).expect("a predefined entity");
                current.push_str(c);
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0, "unbalanced tags");
    Svg { texts, polylines }
}

/// Removes the first text element (the title, which names the source).
fn without_title(svg: &str) -> String {
    let start = svg.find("<text").expect("a title");
    let end = start + svg[start..].find("</text>").expect("closed");
    format!("{}{}", &svg[..start], &svg[end..])
}

#[test]
fn palmer_plot_has_every_panel_and_series_and_matches_the_csv_replot() {
    let dir = scratch("plot");
    // `&` and `<` in the file name must not break the XML of the title.
    let csv = dir.join("a&b<c.csv");
    let svg = dir.join("run.svg");
    let replot = dir.join("replot.svg");
    let (csv, svg, replot) = (
        csv.to_str().unwrap(),
        svg.to_str().unwrap(),
        replot.to_str().unwrap(),
    );
    sim_ok(&[
        "palmer",
        "--headless",
        "--fps",
        "10",
        "--frames",
        "300",
        "--throttle",
        "1",
        "--alpha",
        "5",
        "--bank",
        "5",
        "--csv",
        csv,
        "--plot",
        svg,
    ]);
    sim_ok(&["plot", csv, "-o", replot]);
    let run = std::fs::read_to_string(svg).unwrap();
    let again = std::fs::read_to_string(replot).unwrap();
    let parsed = parse(&run);
    for needle in [
        "Palmer Cessna 172: 301 samples, t = 0.00 to 30.00 s",
        "Height above the ground plane",
        "height (ft)",
        "Airspeed",
        "airspeed (kt)",
        "Attitude",
        "roll (deg, right wing down +)",
        "pitch (deg, nose up +)",
        "Heading",
        "heading (deg true, unwrapped)",
        "Status",
        "on ground",
        "flying",
        "Ground track",
        "east of origin (m)",
        "north of origin (m)",
        "time (s)",
    ] {
        assert!(
            parsed.texts.iter().any(|t| t == needle),
            "no {needle:?} in {:?}",
            parsed.texts
        );
    }
    // Height, airspeed, roll, pitch, heading and the track: 301 points each; the
    // status step line has 2 points per sample but the first.
    let full = parsed.polylines.iter().filter(|&&n| n == 301).count();
    assert_eq!(full, 6, "{:?}", parsed.polylines);
    assert!(parsed.polylines.contains(&601), "{:?}", parsed.polylines);
    // The CSV round trip loses nothing: every line of the replot is the same
    // (the status recomputed from the CSV included); only the title differs.
    let replot_parsed = parse(&again);
    assert!(
        replot_parsed.texts[0].starts_with("Palmer Cessna 172 from "),
        "{}",
        replot_parsed.texts[0]
    );
    assert!(replot_parsed.texts[0].ends_with("a&b<c.csv: 301 samples, t = 0.00 to 30.00 s"));
    assert_eq!(without_title(&run), without_title(&again));
}

#[test]
fn bourg_script_run_plots_and_replots_identically() {
    let dir = scratch("plot");
    let csv = dir.join("b.csv");
    let svg = dir.join("b.svg");
    let replot = dir.join("b2.svg");
    let (csv, svg, replot) = (
        csv.to_str().unwrap(),
        svg.to_str().unwrap(),
        replot.to_str().unwrap(),
    );
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/scripts/bourg_roll.txt"
    );
    sim_ok(&[
        "bourg",
        "--headless",
        "--frames",
        "450",
        "--script",
        script,
        "--csv",
        csv,
        "--plot",
        svg,
    ]);
    sim_ok(&["plot", csv, "--output", replot]);
    // The same file without its model line (as written before the line
    // existed): the legacy path finds Bourg by the header, the same plot.
    let written = std::fs::read_to_string(csv).unwrap();
    let legacy = dir.join("b-legacy.csv");
    let legacy_svg = dir.join("b-legacy.svg");
    std::fs::write(&legacy, support::csv_body(&written, "bourg")).unwrap();
    sim_ok(&[
        "plot",
        legacy.to_str().unwrap(),
        "-o",
        legacy_svg.to_str().unwrap(),
    ]);
    assert_eq!(
        without_title(&std::fs::read_to_string(&legacy_svg).unwrap()),
        without_title(&std::fs::read_to_string(replot).unwrap())
    );
    // A model line naming a model sim-cli does not have: a usage error
    // naming the file, its line and the models it has.
    let unknown = dir.join("b-unknown.csv");
    std::fs::write(
        &unknown,
        written.replacen("# model: bourg", "# model: cessna", 1),
    )
    .unwrap();
    let out = sim(&[
        "plot",
        unknown.to_str().unwrap(),
        "-o",
        legacy_svg.to_str().unwrap(),
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with(&format!(
            "sim-cli: error: {}:1: written by model `cessna`, which this reader does not know (palmer, bourg",
            unknown.display()
        )),
        "{stderr}"
    );
    let run = std::fs::read_to_string(svg).unwrap();
    let parsed = parse(&run);
    assert!(parsed.texts[0].starts_with("Bourg 6-DoF: 451 samples"));
    assert!(parsed.texts.iter().any(|t| t == "STALL"));
    assert_eq!(parsed.polylines.iter().filter(|&&n| n == 451).count(), 6);
    assert_eq!(
        without_title(&run),
        without_title(&std::fs::read_to_string(replot).unwrap())
    );
}

#[test]
fn bad_plot_inputs_are_usage_errors() {
    let dir = scratch("plot");
    let not_csv = dir.join("notes.csv");
    std::fs::write(&not_csv, "hello,world\n1,2\n").unwrap();
    let out_svg = dir.join("x.svg");
    for args in [
        vec![
            "plot",
            not_csv.to_str().unwrap(),
            "-o",
            out_svg.to_str().unwrap(),
        ],
        vec![
            "plot",
            "/nonexistent/in.csv",
            "-o",
            out_svg.to_str().unwrap(),
        ],
        vec![
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--plot",
            "/nonexistent-dir/x.svg",
        ],
    ] {
        let out = sim(&args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with("sim-cli: error: "), "{stderr}");
    }
    // Nothing was run, so no plot was written.
    assert!(!out_svg.exists());
    let csv = dir.join("same.csv");
    let out = sim(&[
        "palmer",
        "--headless",
        "--frames",
        "1",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("would overwrite the --csv file"));
}

/// Two hours at 100 fps (the size that once gave a 43 MB SVG with a 10 MB
/// attribute that rsvg-convert could not parse): the SVG is small, and when
/// `rsvg-convert` is installed (`.ci/run` installs it) an independent SVG
/// renderer opens it.
#[test]
fn a_two_hour_csv_at_100_fps_plots_small_enough_for_viewers() {
    use std::fmt::Write as _;
    let dir = scratch("plot-long");
    let csv = dir.join("long.csv");
    let svg = dir.join("long.svg");
    let mut rows = String::from("frame,time_s,x,y,z,vx,vy,vz,lat_deg,lon_deg,alt_m,roll_deg,pitch_deg,fg_heading_deg,airspeed,throttle,alpha_deg,bank_deg,flaps_deg,climb_angle_deg,climb_rate,heading_deg,status\n");
    let frames = 2 * 3600 * 100;
    for frame in 0..=frames {
        let t = f64::from(frame) / 100.0;
        let (x, y) = (2000.0 * (t / 90.0).cos(), 2000.0 * (t / 90.0).sin());
        let z = 300.0 + 20.0 * (t / 13.0).sin();
        let status = u8::from(frame > 0);
        writeln!(
            rows,
            "{frame},{t},{x},{y},{z},0,0,0,0,0,0,5,2,{},50,1,4,5,0,0,0,0,{status}",
            (t * 4.0) % 360.0
        )
        .unwrap();
    }
    std::fs::write(&csv, rows).unwrap();
    sim_ok(&["plot", csv.to_str().unwrap(), "-o", svg.to_str().unwrap()]);
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(drawn.len() < 2_000_000, "{} bytes", drawn.len());
    let parsed = parse(&drawn);
    assert!(parsed.texts[0].ends_with("720001 samples, t = 0.00 to 7200.00 s"));
    assert!(parsed.polylines.iter().all(|&n| n <= 4 * 1200 * 2 + 2));
    match std::process::Command::new("rsvg-convert")
        .arg(&svg)
        .arg("-o")
        .arg(dir.join("long.png"))
        .output()
    {
        Ok(out) => assert!(out.status.success(), "rsvg-convert: {}", text(&out.stderr)),
        Err(e) => eprintln!("rsvg-convert not run ({e}); install librsvg2-bin to check"),
    }
}

/// `yes 1,2,3 | sim-cli plot /dev/stdin` once grew by gigabytes a second:
/// the stream is read line by line and refused at its header.
#[test]
fn an_endless_pipe_is_refused_without_reading_it_all() {
    let dir = scratch("plot-pipe");
    let script = format!(
        r#"yes 1,2,3 | "$0" plot /dev/stdin -o {}"#,
        dir.join("x.svg").display()
    );
    let out = std::process::Command::new("sh")
        .args(["-c", &script, env!("CARGO_BIN_EXE_sim-cli")])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("no `frame` column"));
}

/// A named pipe that nobody writes to no longer hangs silently: sim-cli says
/// what it waits for, and plots once a writer comes.
#[cfg(unix)]
#[test]
fn a_fifo_without_a_writer_is_waited_for_out_loud() {
    use std::io::{Read as _, Write as _};
    use std::process::{Command, Stdio};
    let dir = scratch("plot-fifo");
    let fifo = dir.join("in.csv");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let svg = dir.join("x.svg");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["plot", fifo.to_str().unwrap(), "-o", svg.to_str().unwrap()])
        .stdin(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The note comes after a second; read its line before writing.
    let mut stderr = child.stderr.take().unwrap();
    let mut note = Vec::new();
    let mut byte = [0u8; 1];
    while stderr.read(&mut byte).unwrap() == 1 && byte[0] != b'\n' {
        note.push(byte[0]);
    }
    let note = String::from_utf8(note).unwrap();
    assert!(
        note.contains("waiting for a program to open the pipe"),
        "{note}"
    );
    let mut writer = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
    writer
        .write_all(b"frame,time_s,x,y,z,vz,roll_deg,pitch_deg,airspeed\n0,0,0,0,0,0,0,0,0\n1,0.1,1,0,1,0,0,0,1\n")
        .unwrap();
    drop(writer);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0));
    assert!(svg.exists());
}
