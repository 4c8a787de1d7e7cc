//! The whole database through every command that writes tables (ingest, colors, params,
//! validate, bake): no NaN or infinity
//! reaches any table, and the counts the README states are the ones a run gives.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::Command;

mod common;
use common::{database, database_dir, non_finite_cells, non_finite_tables};

use nklut::ingest::{ingest, Config, Selection};
use nklut::spectrum::Coverage;

fn nklut(out: &Path, args: &[&str]) {
    let output =
        Command::new(env!("CARGO_BIN_EXE_nklut")).arg("--db").arg(database_dir()).arg("--out").arg(out).args(args).output().unwrap();
    assert!(output.status.success(), "nklut {args:?}: {}", String::from_utf8_lossy(&output.stderr));
}

#[test]
fn the_scan_sees_non_finite_cells() {
    assert_eq!(non_finite_cells("a,b\n1,NaN\n2,inf\n"), ["nan", "inf"]);
    assert!(non_finite_cells("page,n\nmain/Inf/x,1.5\n").is_empty());
}

#[test]
fn every_table_of_every_command_over_the_whole_database_is_finite() {
    let out = tempfile::tempdir().unwrap();
    for command in ["ingest", "colors", "params", "validate", "bake"] {
        nklut(out.path(), &[command, "--all"]);
    }
    let tables = non_finite_tables(out.path());
    for (name, bad) in &tables {
        assert!(bad.is_empty(), "{name}: {} non-finite cells, e.g. {:?}", bad.len(), &bad[..bad.len().min(3)]);
    }
    assert!(tables.len() >= 10, "only {} tables scanned", tables.len());
}

/// The README's sentence "On this snapshot (N distinct pages): K kept; C `code`, …" and
/// the line after it with `--visible full`.
fn readme_counts() -> (BTreeMap<String, usize>, usize) {
    let readme = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let start = readme.find("On this snapshot").expect("README states the counts");
    let paragraph: String = readme[start..].split("\n\n").next().unwrap().replace('\n', " ");
    let words: Vec<&str> = paragraph.split_whitespace().collect();
    let mut counts = BTreeMap::new();
    let mut full_kept = 0;
    for pair in words.windows(2) {
        let Ok(number) = pair[0].trim_matches(|c: char| !c.is_ascii_digit()).parse::<usize>() else { continue };
        let label = pair[1].trim_matches(|c: char| c == ',' || c == ';' || c == '.' || c == ')');
        if label.starts_with('`') {
            counts.insert(label.trim_matches('`').to_string(), number);
        } else if label == "kept" && !counts.contains_key("kept") {
            counts.insert("kept".into(), number);
        } else if label == "kept" {
            full_kept = number;
        } else if label == "warnings" {
            counts.insert("warnings".into(), number);
        } else if label == "distinct" {
            counts.insert("pages".into(), number);
        }
    }
    (counts, full_kept)
}

#[test]
fn the_readme_states_the_counts_a_run_gives() {
    let db = database();
    let result = ingest(&db, &Selection::All, &Config::default()).unwrap();
    let mut counts: BTreeMap<String, usize> = result.excluded_by_reason().into_iter().map(|(code, n)| (code.to_string(), n)).collect();
    counts.insert("kept".into(), result.kept.len());
    counts.insert("pages".into(), result.selected);
    counts.insert("warnings".into(), result.warnings.len());
    let full = ingest(&db, &Selection::All, &Config { coverage: Coverage::Full, ..Config::default() }).unwrap();
    let (stated, stated_full) = readme_counts();
    assert_eq!(stated, counts, "README.md's counts differ from this run");
    assert_eq!(stated_full, full.kept.len(), "README.md's --visible full count differs");
}

/// The README's table of reason codes lists every code the ingest can give.
#[test]
fn the_readme_lists_every_reason_code() {
    let readme = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    for reason in nklut::db::Reason::ALL {
        assert!(readme.contains(&format!("| `{}` |", reason.code())), "README.md does not list {}", reason.code());
    }
}
