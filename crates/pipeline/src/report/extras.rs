//! Sections that appear when other stages' tables exist: the effects gallery (multiple
//! reflections and ambient occlusion: error tables and rendered frames beside their
//! references) on the index, and the engine-parameter panel on material pages. An
//! absent table is named with the command that writes it, never an error.

use std::fmt::Write;
use std::path::Path;

use super::csvdata::CsvTable;
use super::html::{delta_e, escape, href, markdown_text, number, percent, TableText};
use super::inputs::Inputs;

/// A cell of a table whose columns the report does not know in advance, in the report's
/// number format by the column's name: relative errors as percent, ΔE with 2 decimals,
/// other numbers with 3 significant digits, text as is.
pub fn cell(column: &str, text: &str) -> String {
    let Ok(value) = text.parse::<f64>() else { return text.to_string() };
    let column = column.to_ascii_lowercase();
    if column.contains("delta_e") || column.contains("de2000") {
        delta_e(value)
    } else if column.contains("rel_error") || column.ends_with("_rel") {
        percent(value)
    } else if text.contains('.') || text.contains('e') {
        number(value)
    } else {
        text.to_string()
    }
}

/// A whole table in the report's format.
fn generic_table(table: &CsvTable) -> TableText {
    let mut out = TableText::new(&table.headers.iter().map(String::as_str).collect::<Vec<_>>());
    for row in &table.rows {
        out.row(table.headers.iter().zip(row).map(|(h, v)| cell(h, v)).collect());
    }
    out
}

/// The gallery's tables and the command that writes each.
const GALLERY: [(&str, &str); 4] = [
    (
        "effects_errors.csv",
        "multiple reflections and refractions: image error per depth and step counts (`make effects` on the CPU, `make gpu` on the GPU)",
    ),
    (
        "effects_timing.csv",
        "multiple reflections and refractions: GPU time of the map update and the shading pass per configuration (`make gpu`)",
    ),
    ("ao_errors.csv", "ambient occlusion: error per passes and hierarchy (`make effects`)"),
    ("ao_timing.csv", "ambient occlusion: GPU time against surfel count (`make effects`)"),
];

/// Folders where the effects write their frames, at the top of the output folder or in a
/// scene's folder one level down.
const FRAME_FOLDERS: [&str; 3] = ["effects_frames", "effects_gpu_frames", "ao_frames"];

/// PNG frames under `out/<folder>` and `out/<scene>/<folder>`, sorted (a reference sorts
/// beside its result when they share a stem), as paths relative to `out`.
pub fn frames(out: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let scenes: Vec<String> = std::iter::once(String::new()).chain(super::inputs::scene_folders(out)).collect();
    for folder in scenes.iter().flat_map(|scene| FRAME_FOLDERS.map(|f| out.join(scene).join(f))) {
        let mut stack = vec![folder];
        while let Some(dir) = stack.pop() {
            let Ok(entries) = std::fs::read_dir(&dir) else { continue };
            for entry in entries.flatten() {
                let path = entry.path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "png") {
                    if let Ok(relative) = path.strip_prefix(out) {
                        found.push(relative.to_string_lossy().replace('\\', "/"));
                    }
                }
            }
        }
    }
    found.sort();
    found
}

/// The effects gallery of the index: each present table, each absent one named, frames.
pub fn gallery(inputs: &Inputs, frames: &[String]) -> (String, String) {
    let mut html = String::from("<h2 id=\"effects\">Effects gallery</h2>\n");
    let mut markdown = String::from("\n## Effects gallery\n\n");
    for (name, what) in GALLERY {
        let found: Vec<(&String, &CsvTable)> =
            inputs.extra.iter().filter(|(path, _)| *path == name || path.ends_with(&format!("/{name}"))).collect();
        if found.is_empty() {
            let _ = writeln!(html, "<p class=\"absent\"><code>{}</code> is absent: {}.</p>", escape(name), escape(what));
            let _ = writeln!(markdown, "`{name}` is absent: {what}.\n");
        }
        for (path, table) in found {
            let text = generic_table(table);
            let _ = write!(html, "<h3>{}</h3><p class=\"note\">{}</p>{}", escape(path), escape(what), text.html("effects"));
            let _ = write!(markdown, "### {}\n\n{}\n", markdown_text(path), text.markdown());
        }
    }
    if frames.is_empty() {
        html.push_str("<p class=\"absent\">No rendered frames (PNG under effects_frames/, effects_gpu_frames/ or ao_frames/ of the output folder or of a scene folder in it).</p>\n");
    } else {
        html.push_str("<div class=\"frames\">");
        for frame in frames {
            let _ = write!(
                html,
                "<figure><img loading=\"lazy\" src=\"../{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>",
                href(frame),
                escape(frame),
                escape(frame)
            );
        }
        html.push_str("</div>\n");
    }
    (html, markdown)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_tables_follow_the_number_format() {
        assert_eq!(cell("mean_rel_error", "0.0123456"), "1.23 %");
        assert_eq!(cell("mean_delta_e2000", "1.23456"), "1.23");
        assert_eq!(cell("median_ms", "0.123456"), "0.123");
        assert_eq!(cell("passes", "3"), "3");
        assert_eq!(cell("mesh", "bunny"), "bunny");
    }
}
