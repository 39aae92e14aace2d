//! The CSV and report writers through their public API, for behaviour the
//! end-to-end tests do not reach (found by mutation testing, docs/testing.md).
//! Each expectation comes from the writer's documented contract, not from a
//! value the code printed.

use sim_cli::csv::CsvWriter;

/// `has_header` is false on a new writer and true once the header is out, and
/// only the header line has been written at that point.
#[test]
fn has_header_follows_the_header_line() {
    let mut w = CsvWriter::new(Vec::new(), "mem");
    assert!(!w.has_header());
    w.write_header(&["x"]).unwrap();
    assert!(w.has_header());
    w.write_row(0, 0.5, &[2.0]).unwrap();
    assert!(w.has_header());
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    assert_eq!(text, "frame,time_s,x\n0,0.5,2\n");
}
