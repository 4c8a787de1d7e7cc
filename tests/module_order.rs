//! The module map of `src/lib.rs` holds: every `crate::` import of a module points to a
//! module before it in the pipeline order, or to a leaf.

use std::fs;
use std::path::Path;

/// The pipeline order of `src/lib.rs`'s doc comment.
const ORDER: [&str; 12] =
    ["db", "spectrum", "ingest", "fresnel", "color", "validate", "bake", "params", "report", "scene", "effects", "gpu"];
/// Modules any module may use.
const LEAVES: [&str; 6] = ["budget", "encoding", "output", "progress", "minimise", "memo"];
/// Stages that sit side by side (neither may use the other).
const SIBLINGS: [&str; 3] = ["validate", "bake", "params"];

fn sources(dir: &Path, found: &mut Vec<(String, String)>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, found);
        } else if path.extension().is_some_and(|e| e == "rs") {
            found.push((path.display().to_string(), fs::read_to_string(&path).unwrap()));
        }
    }
}

/// The top-level module a file under src/ belongs to.
fn module_of(path: &str) -> Option<String> {
    let relative = path.split("src/").nth(1)?;
    let first = relative.split('/').next()?;
    Some(first.trim_end_matches(".rs").to_string())
}

#[test]
fn imports_point_down_the_pipeline() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &mut files);
    let rank = |m: &str| ORDER.iter().position(|o| *o == m);
    let mut wrong = Vec::new();
    for (path, text) in &files {
        let Some(module) = module_of(path) else { continue };
        let Some(own) = rank(&module) else { continue };
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for used in
                line.split("crate::").skip(1).map(|rest| rest.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap_or(""))
            {
                if used == module || LEAVES.contains(&used) {
                    continue;
                }
                let sideways = SIBLINGS.contains(&used) && SIBLINGS.contains(&module.as_str());
                match rank(used) {
                    Some(other) if other < own && !sideways => {}
                    _ => wrong.push(format!("{path}: {module} uses {used}: {}", line.trim())),
                }
            }
        }
    }
    assert!(wrong.is_empty(), "imports against the module order:\n{}", wrong.join("\n"));
}
