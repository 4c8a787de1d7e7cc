//! The layers hold. Between crates Cargo enforces the direction (a crate cannot name one
//! above it); inside each crate, every `crate::` import of a module points to a module
//! before it in the crate's order (its `lib.rs` doc comment), or to a leaf. And the light
//! crates stay light: `nklut-optics` depends on neither polars, nor wgpu, nor obvhs;
//! `nklut-tables` and `nklut-effects` depend on neither polars nor the pipeline.

use std::fs;
use std::path::Path;

/// Each crate's modules in their order, its leaves, and the stages that sit side by side
/// (neither may use the other).
struct Layers {
    krate: &'static str,
    order: &'static [&'static str],
    leaves: &'static [&'static str],
    siblings: &'static [&'static str],
}

const CRATES: [Layers; 4] = [
    Layers {
        krate: "optics",
        order: &["db", "spectrum", "fresnel", "color", "appearance"],
        leaves: &["encoding", "minimise", "memo"],
        siblings: &[],
    },
    Layers {
        krate: "tables",
        order: &["ingest"],
        leaves: &["output", "progress", "budget", "stats", "escape", "texel", "image_files", "models", "atomic", "memo_file"],
        siblings: &[],
    },
    Layers {
        krate: "pipeline",
        order: &["ingest", "colors", "validate", "bake", "params", "report", "recommend"],
        leaves: &["output", "progress", "budget", "stats", "escape"],
        siblings: &["validate", "bake", "params"],
    },
    // The effects crate's root is the effects themselves; `scene` is the data below them.
    Layers {
        krate: "effects",
        order: &[
            "scene",
            "upsample",
            "optics",
            "geometry",
            "packet",
            "trace",
            "spectral",
            "distance_map",
            "image_error",
            "labels",
            "colour_bar",
            "pictures",
            "hero",
            "experiment",
            "spectral_errors",
            "ao",
            "command",
        ],
        leaves: &[],
        siblings: &[],
    },
];

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

/// The top-level module a file under a crate's src/ belongs to.
fn module_of(path: &str) -> Option<String> {
    let relative = path.split("src/").nth(1)?;
    let first = relative.split('/').next()?;
    Some(first.trim_end_matches(".rs").to_string())
}

#[test]
fn imports_point_down_each_crate_s_layers() {
    let mut wrong = Vec::new();
    for layers in &CRATES {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates").join(layers.krate).join("src");
        let mut files = Vec::new();
        sources(&root, &mut files);
        assert!(!files.is_empty(), "no sources under {}", root.display());
        let rank = |m: &str| layers.order.iter().position(|o| *o == m);
        for (path, text) in &files {
            let Some(module) = module_of(path) else { continue };
            let Some(own) = rank(&module) else { continue };
            for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for used in
                    line.split("crate::").skip(1).map(|rest| rest.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap_or(""))
                {
                    if used == module || layers.leaves.contains(&used) {
                        continue;
                    }
                    let sideways = layers.siblings.contains(&used) && layers.siblings.contains(&module.as_str());
                    match rank(used) {
                        Some(other) if other < own && !sideways => {}
                        _ => wrong.push(format!("{path}: {module} uses {used}: {}", line.trim())),
                    }
                }
            }
        }
    }
    assert!(wrong.is_empty(), "imports against the layers:\n{}", wrong.join("\n"));
}

/// The normal dependencies of `krate` (`cargo tree` from the lock file), one per line.
fn dependency_tree(krate: &str) -> String {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(["tree", "--offline", "--locked", "-p", krate, "-e", "normal", "--prefix", "none"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let tree = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(tree.lines().next().is_some_and(|l| l.starts_with(krate)), "{tree}");
    tree
}

/// `cargo tree` of the optics crate (its normal dependencies, from the lock file): none of
/// the heavy crates of the layers above.
#[test]
fn the_optics_crate_pulls_neither_polars_nor_wgpu() {
    let tree = dependency_tree("nklut-optics");
    for heavy in ["polars", "wgpu", "obvhs", "nklut-tables", "nklut-pipeline", "plotters", "exr "] {
        assert!(!tree.lines().any(|l| l.starts_with(heavy)), "nklut-optics depends on {heavy}:\n{tree}");
    }
}

/// The effects and the crate of tables below them build without polars, the pipeline or
/// the report's charts: the pipeline hands its Parquet encoder to the effects' command.
#[test]
fn the_effects_crate_pulls_neither_polars_nor_the_pipeline() {
    for krate in ["nklut-tables", "nklut-effects"] {
        let tree = dependency_tree(krate);
        for heavy in ["polars", "nklut-pipeline", "plotters", "wgpu"] {
            assert!(!tree.lines().any(|l| l.starts_with(heavy)), "{krate} depends on {heavy}:\n{tree}");
        }
    }
}

/// The optics crate's example prints per-channel F of a page: gold's red F0 is high and
/// its blue F0 low (the colour of gold), each line one channel.
#[test]
fn the_optics_crate_s_example_runs() {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(["run", "--quiet", "--offline", "-p", "nklut-optics", "--example", "channel_fresnel", "--", "3d/metals/gold"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let f0: Vec<f64> =
        text.lines().map(|l| l.split("F(0°) ").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap()).collect();
    assert_eq!(f0.len(), 3, "{text}");
    assert!(f0[0] > 0.9 && f0[2] < 0.5, "{text}");
}
