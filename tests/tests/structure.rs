//! The workspace's structure, checked on the source files themselves: what
//! issue 22 ("the run as a library, outputs as plugins, and a thin sim-cli")
//! asks of the crates above `fdm-core`, so that no later change undoes it
//! unnoticed and no reading of the code has to vouch for it.
//!
//! * **One place per model.** Above `fdm-core`, Palmer and Bourg are named by
//!   production code in two kinds of file only: the run library's registry
//!   (`fdm-run/src/model.rs`) and the model's one adapter module
//!   (`fdm-run/src/model/<model>.rs`). Every other crate (the fleets, the ECS,
//!   the CLI, the Python package, studies, outputs) is generic over the
//!   registry's traits, so adding a model is one module and one registry line.
//! * **A thin binary.** `sim-cli` (without the feature-gated glider, a model
//!   outside the library crates) has at most 3,000 production lines.
//!
//! "Production" leaves out comments (doc comments too), blank lines and
//! `#[cfg(test)]` items; tests, benches and examples are not production code.

use std::fs;
use std::path::{Path, PathBuf};

/// The workspace's root (this package is `tests/`).
fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let entries = fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The production lines of a Rust source: without blank lines, comment lines
/// and `#[cfg(test)]` items (a one-line item, or a block up to its closing
/// brace at the attribute's indentation).
fn production_lines(source: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut lines = source.lines();
    while let Some(line) = lines.next() {
        let code = line.trim_start();
        if code.starts_with("#[cfg(test)]") {
            let indent = &line[..line.len() - code.len()];
            let item = lines.next().unwrap_or_default();
            if item.trim_end().ends_with('{') {
                let close = format!("{indent}}}");
                for rest in lines.by_ref() {
                    if rest.trim_end() == close {
                        break;
                    }
                }
            }
            continue;
        }
        if code.is_empty()
            || code.starts_with("//")
            || code.starts_with("/*")
            || code.starts_with('*')
        {
            continue;
        }
        out.push(line);
    }
    out
}

/// Whether a line of code names one of the library's models.
fn names_a_model(line: &str) -> bool {
    const MODELS: [(&str, &str); 2] = [("palmer", "Palmer"), ("bourg", "Bourg")];
    MODELS.iter().any(|&(module, model)| {
        line.contains(&format!("{module}::"))
            || line.contains(&format!("\"{module}\""))
            || line
                .match_indices(model)
                .any(|(at, _)| !line[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_'))
    })
}

/// The production files of the crates above `fdm-core` that name a model,
/// as paths relative to the workspace.
fn files_naming_a_model() -> Vec<String> {
    let root = workspace();
    // Every workspace member (the root manifest's `members`) but fdm-core
    // itself and the test and bench support crates (`tests/`, `benches/`),
    // whose code is not production: a crate added later is checked too.
    let manifest = fs::read_to_string(root.join("Cargo.toml")).expect("the root manifest");
    let members = manifest
        .lines()
        .find_map(|l| l.trim().strip_prefix("members = ["))
        .and_then(|l| l.strip_suffix(']'))
        .expect("a one-line `members = [...]` in the root Cargo.toml");
    let crates: Vec<&str> = members
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !["fdm-core", "tests", "benches"].contains(m))
        .collect();
    assert!(
        crates.contains(&"sim-cli") && crates.contains(&"afit-fdm-py"),
        "{crates:?}"
    );
    let mut naming = Vec::new();
    for krate in crates {
        for file in rust_files(&root.join(krate).join("src")) {
            let source = fs::read_to_string(&file).expect("a readable source file");
            if production_lines(&source).iter().any(|l| names_a_model(l)) {
                let relative = file.strip_prefix(&root).expect("under the root");
                naming.push(relative.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    naming
}

#[test]
fn above_fdm_core_only_the_registry_and_each_models_module_name_a_model() {
    let allowed = [
        "fdm-run/src/model.rs",
        "fdm-run/src/model/palmer.rs",
        "fdm-run/src/model/bourg.rs",
    ];
    let naming = files_naming_a_model();
    let others: Vec<&String> = naming
        .iter()
        .filter(|f| !allowed.contains(&f.as_str()))
        .collect();
    assert!(
        others.is_empty(),
        "production code above fdm-core names Palmer or Bourg outside the registry \
         (fdm-run/src/model.rs) and the models' adapter modules (fdm-run/src/model/): {others:?}"
    );
    // The check sees the adapter modules (it would pass vacuously otherwise).
    for file in allowed {
        assert!(naming.iter().any(|f| f == file), "{file} names no model?");
    }
}

#[test]
fn sim_cli_is_at_most_3000_production_lines() {
    let root = workspace();
    let glider = root.join("sim-cli/src/models/glider");
    let lines: usize = rust_files(&root.join("sim-cli/src"))
        .iter()
        .filter(|f| !f.starts_with(&glider))
        .map(|f| production_lines(&fs::read_to_string(f).expect("readable")).len())
        .sum();
    assert!(lines > 1000, "{lines} lines: is sim-cli/src read at all?");
    assert!(
        lines <= 3000,
        "sim-cli has {lines} production lines (at most 3,000)"
    );
}

#[test]
fn the_measures_see_what_they_should() {
    let source = "use a;\n// a comment\n\n/// doc\nfn f() {}\n#[cfg(test)]\nuse b;\n\
                  #[cfg(test)]\nmod tests {\n    fn g() {}\n}\nfn h() {}\n";
    assert_eq!(
        production_lines(source),
        ["use a;", "fn f() {}", "fn h() {}"]
    );
    assert!(names_a_model("use fdm_core::palmer::Palmer;"));
    assert!(names_a_model("impl Model for Bourg {"));
    assert!(names_a_model("with(\"bourg\")"));
    assert!(!names_a_model("let s = state.bourged;"));
    assert!(!names_a_model("fn model_name() {}"));
}
