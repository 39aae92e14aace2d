//! `--plot` and `sim-cli plot` on the built binary: the SVG is well-formed XML, has
//! every panel, axis unit and series, and a plot redrawn from the run's CSV draws
//! exactly the same lines as the plot of the run itself.

mod support;

use quick_xml::events::Event;
use quick_xml::Reader;
use support::{scratch, sim, text};

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

#[track_caller]
fn run_ok(args: &[&str]) {
    let out = sim(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        text(&out.stderr)
    );
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
    run_ok(&[
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
    run_ok(&["plot", csv, "-o", replot]);
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
    run_ok(&[
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
    run_ok(&["plot", csv, "--output", replot]);
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
