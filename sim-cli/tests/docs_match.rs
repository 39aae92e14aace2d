//! The documents cannot drift from the binary: every ```` ```console ```` block
//! of README.md and docs/*.md is run, and the JSON report's and the CSV's
//! fields documented in docs/cli.md are exactly the ones the binary writes.
//!
//! A console block holds commands (`$ sim-cli ARGS`, run with the built
//! binary, or `$ head -N FILE`, the first N lines of a file an earlier command
//! wrote) each followed by what it shows: its stderr, then its stdout. The
//! commands of a document run in order in one scratch directory in which
//! `examples/` and `reference/` are the workspace's, so relative paths read
//! the repository and the files they write stay out of it. Redaction: in the
//! expected text, `[..]` matches any run of characters within a line (for
//! times, thread counts, rates) and a line `...` any number of lines. Every
//! command must exit with status 0.
//!
//! And no document shows a command's output anywhere else: a code block of
//! another kind in which a `$ ` command line is followed by output fails
//! `shown_output_is_always_checked` (make it a console block).

mod support;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use support::{report, scratch, text};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn documents() -> Vec<PathBuf> {
    let mut paths = vec![workspace().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(workspace().join("docs"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    paths.extend(docs);
    paths
}

/// One `$ command` and the stdout it should print.
struct Example {
    at: String,
    args: Vec<String>,
    expected: Vec<String>,
}

/// Splits a command line on blanks, honouring '...' and "..." quotes.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quote = None;
    let mut started = false;
    for c in line.chars() {
        match (quote, c) {
            (None, '\'' | '"') => {
                quote = Some(c);
                started = true;
            }
            (Some(q), _) if c == q => quote = None,
            (None, c) if c.is_whitespace() => {
                if started {
                    out.push(std::mem::take(&mut word));
                    started = false;
                }
            }
            _ => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        out.push(word);
    }
    out
}

fn examples(path: &Path) -> Vec<Example> {
    let doc = std::fs::read_to_string(path).unwrap();
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let mut out: Vec<Example> = Vec::new();
    let mut in_block = None::<usize>; // indentation of the open console fence
    for (n, line) in doc.lines().enumerate() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        match in_block {
            None if trimmed == "```console" => in_block = Some(indent),
            None => {}
            Some(_) if trimmed == "```" => in_block = None,
            Some(fence) => {
                let body = line.get(fence..).unwrap_or(trimmed);
                if let Some(command) = body.strip_prefix("$ ") {
                    let args = words(command);
                    let args = match args.first().map(String::as_str) {
                        Some("sim-cli") => args[1..].to_vec(),
                        Some("head") => args,
                        _ => panic!(
                            "{name}:{}: console examples run sim-cli or head -N FILE",
                            n + 1
                        ),
                    };
                    out.push(Example {
                        at: format!("{name}:{}", n + 1),
                        args,
                        expected: Vec::new(),
                    });
                } else {
                    let example = out.last_mut().unwrap_or_else(|| {
                        panic!("{name}:{}: output before any `$ sim-cli` line", n + 1)
                    });
                    example.expected.push(body.to_owned());
                }
            }
        }
    }
    assert!(in_block.is_none(), "{name}: unclosed console block");
    out
}

/// `line` matches `pattern`, where `[..]` in the pattern matches any text.
fn line_matches(pattern: &str, line: &str) -> bool {
    let mut parts = pattern.split("[..]");
    let first = parts.next().unwrap_or("");
    let Some(mut rest) = line.strip_prefix(first) else {
        return false;
    };
    let parts: Vec<&str> = parts.collect();
    for (i, part) in parts.iter().enumerate() {
        if i + 1 == parts.len() {
            return rest.ends_with(part);
        }
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => return false,
        }
    }
    rest.is_empty()
}

/// `lines` match `patterns`, where a pattern line `...` matches any lines.
fn lines_match(patterns: &[String], lines: &[&str]) -> bool {
    match patterns.split_first() {
        None => lines.is_empty(),
        Some((p, rest)) if p == "..." => {
            (0..=lines.len()).any(|skip| lines_match(rest, &lines[skip..]))
        }
        Some((p, rest)) => {
            !lines.is_empty() && line_matches(p, lines[0]) && lines_match(rest, &lines[1..])
        }
    }
}

/// A scratch directory to run a document's examples in: `examples/` and
/// `reference/` link to the workspace's.
fn run_directory() -> support::Scratch {
    let dir = scratch("docs");
    for name in ["examples", "reference"] {
        std::os::unix::fs::symlink(workspace().join(name), dir.join(name)).unwrap();
    }
    dir
}

/// What `example` shows when run in `dir`: stderr then stdout.
fn run_example(example: &Example, dir: &Path) -> String {
    if example.args.first().map(String::as_str) == Some("head") {
        let [_, lines, file] = &example.args[..] else {
            panic!("{}: `head -N FILE`", example.at);
        };
        let n: usize = lines
            .strip_prefix('-')
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{}: `head -N FILE`", example.at));
        let content = std::fs::read_to_string(dir.join(file))
            .unwrap_or_else(|e| panic!("{}: {file}: {e}", example.at));
        return content.lines().take(n).map(|l| format!("{l}\n")).collect();
    }
    let out = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(&example.args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("run sim-cli");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}: stderr {}",
        example.at,
        text(&out.stderr)
    );
    text(&out.stderr) + &text(&out.stdout)
}

#[test]
fn console_examples_in_the_documents_print_what_they_show() {
    let mut count = 0;
    for path in documents() {
        let dir = run_directory();
        for example in examples(&path) {
            let shown = run_example(&example, &dir);
            let lines: Vec<&str> = shown.lines().collect();
            assert!(
                lines_match(&example.expected, &lines),
                "{}: the document shows\n{}\nbut the command printed\n{shown}",
                example.at,
                example.expected.join("\n")
            );
            count += 1;
        }
    }
    assert!(count >= 6, "README's console examples were found ({count})");
}

/// Where a document shows a command's output outside a console block, as
/// `(file:line, command)`.
fn unchecked_outputs(name: &str, doc: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut fence = None::<String>; // the open block's info string
    let mut command = None::<(usize, String)>;
    for (n, line) in doc.lines().enumerate() {
        let trimmed = line.trim();
        match &fence {
            None => {
                if let Some(info) = trimmed.strip_prefix("```") {
                    fence = Some(info.to_owned());
                    command = None;
                }
            }
            Some(_) if trimmed == "```" => fence = None,
            Some(info) if info != "console" => {
                if trimmed.starts_with("$ ") {
                    command = Some((n + 1, trimmed.to_owned()));
                } else if !trimmed.is_empty() {
                    if let Some((at, shown)) = command.take() {
                        out.push((format!("{name}:{at}"), shown));
                    }
                }
            }
            Some(_) => {}
        }
    }
    out
}

#[test]
fn shown_output_is_always_checked() {
    // The rule itself: an `sh` block with output is caught, a console block
    // or a command without output is not.
    let caught = unchecked_outputs("t", "```sh\n$ sim-cli x\nout\n```\n");
    assert_eq!(caught, [("t:2".to_owned(), "$ sim-cli x".to_owned())]);
    assert!(unchecked_outputs("t", "```console\n$ sim-cli x\nout\n```\n").is_empty());
    assert!(unchecked_outputs("t", "```sh\n$ sim-cli x   # comment\n```\n").is_empty());
    for path in documents() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let doc = std::fs::read_to_string(&path).unwrap();
        let found = unchecked_outputs(&name, &doc);
        assert!(
            found.is_empty(),
            "output shown outside a console block, so never checked: {found:?}"
        );
    }
}

#[test]
fn the_pattern_rules_hold() {
    assert!(line_matches("a [..] b", "a 12 b"));
    assert!(line_matches("[..]", "anything"));
    assert!(!line_matches("a [..] b", "a 12 c"));
    assert!(!line_matches("abc", "abcd"));
    let p = |v: &[&str]| v.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>();
    assert!(lines_match(&p(&["x", "...", "z"]), &["x", "y1", "y2", "z"]));
    assert!(lines_match(&p(&["x", "...", "z"]), &["x", "z"]));
    assert!(!lines_match(&p(&["x", "z"]), &["x", "y", "z"]));
    assert_eq!(
        words(r#"a 'b c' "d" e"#),
        ["a", "b c", "d", "e"].map(String::from)
    );
}

/// The field names in the first column of docs/cli.md's JSON report table,
/// per model column (`both`, `Palmer`, `Bourg`).
fn documented_report_fields(model: &str) -> BTreeSet<String> {
    let doc = std::fs::read_to_string(workspace().join("docs/cli.md")).unwrap();
    let table = &doc[doc.find("### Headless JSON report").unwrap()..];
    let table = &table[..table.find("\n### ").unwrap()];
    table
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let field = cells.get(1)?.strip_prefix('`')?.strip_suffix('`')?;
            let who = *cells.get(2)?;
            (who == "both" || who.eq_ignore_ascii_case(model)).then(|| field.to_owned())
        })
        .collect()
}

#[test]
fn the_json_report_has_exactly_the_documented_fields() {
    for model in ["palmer", "bourg"] {
        let r = report(&[model, "--headless", "--frames", "3", "--json"]);
        let written: BTreeSet<String> = r.as_object().unwrap().keys().cloned().collect();
        let documented = documented_report_fields(model);
        assert_eq!(written, documented, "{model}: docs/cli.md's JSON table");
    }
}

/// The CSV columns listed in docs/cli.md ("CSV output") for `model`.
fn documented_csv_columns(model: &str) -> Vec<String> {
    let doc = std::fs::read_to_string(workspace().join("docs/cli.md")).unwrap();
    let section = &doc[doc.find("### CSV output").unwrap()..];
    let section = &section[..section.find("\n### ").unwrap()];
    let bullets: Vec<String> = section
        .split("\n* ")
        .skip(1)
        .map(|b| b.replace('\n', " "))
        .collect();
    let columns_of = |bullet: &str| -> Vec<String> {
        let start = bullet.find('`').unwrap() + 1;
        let end = start + bullet[start..].find('`').unwrap();
        bullet[start..end].split(',').map(str::to_owned).collect()
    };
    let label = if model == "palmer" {
        "then Palmer:"
    } else {
        "or Bourg:"
    };
    let mut columns = columns_of(&bullets[0]);
    columns.extend(columns_of(
        bullets.iter().find(|b| b.starts_with(label)).unwrap(),
    ));
    columns.extend(columns_of(
        bullets.iter().find(|b| b.starts_with("last")).unwrap(),
    ));
    columns
}

#[test]
fn the_csv_has_exactly_the_documented_columns() {
    let dir = scratch("docs-csv");
    for model in ["palmer", "bourg"] {
        let csv = dir.join(format!("{model}.csv"));
        let out = support::sim(&[
            model,
            "--headless",
            "--frames",
            "1",
            "--csv",
            csv.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let written = std::fs::read_to_string(&csv).unwrap();
        let header: Vec<String> = support::csv_body(&written, model)
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(str::to_owned)
            .collect();
        assert_eq!(
            header,
            documented_csv_columns(model),
            "{model}: docs/cli.md's CSV columns"
        );
    }
}
