//! The report: built from the tables of a small run, well-formed, every section present,
//! every number equal to the CSV it came from and every count recounted from its table;
//! channel wavelengths from the tables; missing pages named; and, in headless Chromium,
//! readable plots (text ≥ 12 px, no overlapping labels), counts on the rendered page
//! equal to their tables, previews present. Screenshots are kept under
//! `target/tmp/report-artefacts/`.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use common::{database_dir, scratch, Scratch, SPECULAR_SCENE};
use nklut::report::{self, csvdata::CsvTable};

const PAGES: [&str; 4] = ["3d/metals/gold", "3d/metals/copper", "3d/liquids/water", "3d/crystals/diamond"];

fn nklut(out: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nklut"))
        .args(["--db", &database_dir().display().to_string(), "--out", &out.display().to_string()])
        .args(args)
        .output()
        .unwrap()
}

/// Run the stages the report reads for `pages` (with `extra` flags, e.g. --channels);
/// returns the folder and validate's stdout.
fn stages(out: &Path, pages: &[&str], extra: &[&str]) -> String {
    let selection: Vec<&str> = pages.iter().flat_map(|p| ["--page", p]).collect();
    let mut validate_stdout = String::new();
    for stage in report::STAGES {
        let output = nklut(out, &[&[stage], selection.as_slice(), extra].concat());
        assert!(output.status.success(), "nklut {stage} failed: {}", String::from_utf8_lossy(&output.stderr));
        if stage == "validate" {
            validate_stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        }
    }
    validate_stdout
}

fn build_report(name: &str) -> (Scratch, String) {
    let out = scratch(name);
    let validate = stages(&out, &PAGES, &[]);
    let selection: Vec<&str> = PAGES.iter().flat_map(|p| ["--page", p]).collect();
    let output = nklut(&out, &[&["report"], selection.as_slice()].concat());
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    (out, validate)
}

fn material_html(out: &Path, page: &str) -> String {
    fs::read_to_string(out.join(format!("report/materials/{page}.html"))).unwrap()
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

fn no_external_resource(html: &str) {
    let stripped = html.replace("http://www.w3.org/2000/svg", "");
    assert!(!stripped.contains("http://") && !stripped.contains("https://") && !stripped.contains("src=\"//"));
}

#[test]
fn report_is_well_formed_complete_and_traceable() {
    let (out, _) = build_report("content");
    let index = fs::read_to_string(out.join("report/index.html")).unwrap();
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    check_well_formed(&index);
    no_external_resource(&index);
    for section in
        ["id=\"overview\"", "id=\"cost\"", "id=\"summaries\"", "id=\"materials\"", "id=\"fallback\"", "id=\"unusual\"", "id=\"effects\""]
    {
        assert!(index.contains(section), "missing section {section}");
    }
    assert!(index.contains("Materials (4)"));
    // Tables other stages have not written are named, not errors.
    for absent in ["effects_errors.csv", "ao_errors.csv"] {
        assert!(index.contains(&format!("<code>{absent}</code> is absent")), "{absent}");
    }
    for page in PAGES {
        assert!(index.contains(&format!("href=\"materials/{page}.html\"")), "no link to {page}");
        assert!(markdown.contains(page));
        let html = material_html(&out, page);
        check_well_formed(&html);
        no_external_resource(&html);
        for section in
            ["id=\"previews\"", "id=\"angle\"", "id=\"delta-e\"", "id=\"fresnel\"", "id=\"indices\"", "id=\"colours\"", "id=\"errors\""]
        {
            assert!(html.contains(section), "{page}: missing {section}");
        }
        assert!(html.contains("--sheet:url(data:image/png;base64,"), "{page}: no embedded preview");
        let png = fs::read(out.join(format!("report/previews/{page}.png"))).unwrap();
        assert!(html.contains(&nklut::report::preview::data_uri(&png)), "{page}: the written preview is the embedded one");
    }
    // Numbers shown are the CSV's numbers, formatted by the report's one format.
    for (file, columns) in report::TRACED_COLUMNS {
        let table = CsvTable::load(&out.join(file)).unwrap().unwrap_or_else(|| panic!("{file} missing"));
        for row in table.rows.iter().filter(|r| PAGES.contains(&table.text(r, "page"))) {
            let html = material_html(&out, table.text(row, "page"));
            for column in *columns {
                let value = table.number(row, column).unwrap_or_else(|| panic!("{file}:{column}"));
                assert!(html.contains(&report::shown(column, value)), "{file} {column} = {value} not shown");
            }
        }
    }
    // Gold's red fit sits on the search bound, its spectral F0 red is out of gamut: both said.
    let gold = material_html(&out, "3d/metals/gold");
    assert!(gold.contains("reached the edge of the search box"), "the bound is explained");
    assert!(gold.contains("outside [0, 1] of linear sRGB"), "the gamut is explained");
}

/// Recount a figure the report printed from the table it names.
fn recount(out: &Path, table: &str, key: &str) -> usize {
    let t = CsvTable::load(&out.join(table)).unwrap().unwrap_or_else(|| panic!("{table} is cited but absent"));
    let count = |f: &dyn Fn(&Vec<String>) -> bool| t.rows.iter().filter(|r| f(r)).count();
    match (table, key) {
        (_, "rows") => t.rows.len(),
        ("excluded.csv", k) if k.starts_with("reason=") => count(&|r| t.text(r, "reason") == &k[7..]),
        ("materials.csv", "sparse") => count(&|r| t.text(r, "sparse") == "true"),
        ("colors.csv", "out-of-gamut") => count(&|r| ["r", "g", "b"].iter().any(|c| t.text(r, &format!("out_of_gamut_{c}")) == "true")),
        ("colors.csv", "extrapolated") => count(&|r| t.number(r, "extrapolated_share").unwrap() > 0.0),
        ("colors.csv", "fit-at-bound") => {
            use nklut::color::fit::{K_MAX, N_BOUNDS};
            count(&|r| {
                ["r", "g", "b"].iter().any(|c| {
                    let n = t.number(r, &format!("effective_n_{c}")).unwrap();
                    let k = t.number(r, &format!("effective_k_{c}")).unwrap();
                    (n - N_BOUNDS.0).abs() < 1e-9 || (n - N_BOUNDS.1).abs() < 1e-4 || (k - K_MAX).abs() < 1e-4
                })
            })
        }
        ("errors.csv", k) if k.starts_with("fallback") => {
            let reason = k.strip_prefix("fallback=");
            let pairs: BTreeSet<(String, String)> = t
                .rows
                .iter()
                .filter(|r| t.text(r, "method") == "schlick_compensated" && t.text(r, "precision") == "f64")
                .filter(|r| match reason {
                    Some(reason) => t.text(r, "fallback") == reason,
                    None => !t.text(r, "fallback").is_empty(),
                })
                .map(|r| (t.text(r, "page").to_string(), t.text(r, "channel").to_string()))
                .collect();
            pairs.len()
        }
        _ => panic!("the report prints a count ({table}, {key}) this test cannot recount"),
    }
}

#[test]
fn report_uses_the_channel_wavelengths_of_its_tables() {
    let out = scratch("channels");
    stages(&out, &["3d/metals/gold"], &["--channels", "650,550,450"]);
    let output = nklut(&out, &["report", "--page", "3d/metals/gold"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let index = fs::read_to_string(out.join("report/index.html")).unwrap();
    assert!(index.contains("red 650 nm, green 550 nm, blue 450 nm"));
    let gold = material_html(&out, "3d/metals/gold");
    for text in ["n red (650 nm)", "n green (550 nm)", "n blue (450 nm)", "red channel, 650 nm", "blue channel, 450 nm"] {
        assert!(gold.contains(text), "{text}");
    }
    // Printed wavelengths read "685 nm" ("n red (685 nm)", "red channel, 685 nm"); a chart's
    // coordinates may hold the digits.
    assert!(!gold.contains("685 nm") && !index.contains("685 nm"), "no default wavelength is printed");
    // The n shown is the one ingest evaluated at 650 nm, not a re-ingest at 685 nm.
    let nk = nklut(&out, &["nk", "3d/metals/gold", "--nm", "650"]);
    let n: f64 = String::from_utf8_lossy(&nk.stdout).split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!(gold.contains(&format!("<td>{}</td>", nklut::report::html::index(n))), "n at 650 nm = {n}");
    // errors.csv from a run at other wavelengths: the report refuses to mix them.
    let validate = nklut(&out, &["validate", "--page", "3d/metals/gold"]);
    assert!(validate.status.success());
    let mixed = nklut(&out, &["report", "--page", "3d/metals/gold"]);
    assert!(!mixed.status.success());
    let message = String::from_utf8_lossy(&mixed.stderr);
    assert!(message.contains("errors.csv") && message.contains("different --channels"), "{message}");
}

#[test]
fn report_selects_like_every_command_and_names_missing_pages() {
    let out = scratch("selection");
    stages(&out, &["3d/metals/gold", "3d/liquids/water"], &[]);
    // No selection: every page of the tables, as for every other command.
    let all = nklut(&out, &["report"]);
    assert!(all.status.success(), "{}", String::from_utf8_lossy(&all.stderr));
    let index = fs::read_to_string(out.join("report/index.html")).unwrap();
    assert!(index.contains("Materials (2)"));
    assert!(out.join("report/materials/3d/liquids/water.html").exists());
    // The report is written as one set: a narrower run leaves no page of the wider one.
    let gold_only = nklut(&out, &["report", "--page", "3d/metals/gold"]);
    assert!(gold_only.status.success());
    assert!(!out.join("report/materials/3d/liquids/water.html").exists() && !out.join("report/previews/3d/liquids/water.png").exists());
    assert!(out.join("report/materials/3d/metals/gold.html").exists());
    assert!(
        !fs::read_dir(&out).unwrap().any(|e| e.unwrap().file_name().to_string_lossy().starts_with(".report.")),
        "no staging folder left"
    );
    // A page the tables lack: named, and the command fails.
    let missing = nklut(&out, &["report", "--page", "3d/metals/gold", "--page", "3d/metals/silver", "--page", "3d/plastics/PMMA"]);
    assert!(!missing.status.success(), "a missing page must fail");
    let message = String::from_utf8_lossy(&missing.stderr);
    assert!(message.contains("3d/metals/silver (not in materials.csv"), "{message}");
    assert!(message.contains("3d/plastics/PMMA"), "{message}");
    assert!(!message.contains("3d/metals/gold "), "gold is there: {message}");
    let shelf = nklut(&out, &["report", "--shelf", "main"]);
    assert!(!shelf.status.success() && String::from_utf8_lossy(&shelf.stderr).contains("shelf main"));
}

#[test]
fn effects_and_engine_panels_appear_when_their_tables_exist() {
    let out = scratch("panels");
    stages(&out, &["3d/metals/gold", "3d/liquids/water"], &[]);
    fs::write(out.join("engine_params.csv"), "page,f0_srgb8,f82_tint_r,mean_delta_e2000_f82\n3d/metals/gold,#ffd27a,0.987654,1.23456\n")
        .unwrap();
    fs::write(out.join("effects_errors.csv"), "object,method,max_depth,mean_rel_error\nteapot,schlick,2,0.0123456\n").unwrap();
    // `make gpu` writes one folder per effects scene: its tables appear in that scene's
    // section.
    fs::create_dir_all(out.join("gpu-glass-sphere")).unwrap();
    fs::write(
        out.join("gpu-glass-sphere/effects_timing.csv"),
        "method,reflection_depth,shading_ms
exact,3,2.5
",
    )
    .unwrap();
    // Two devices' `gpu_timing.csv` (as `make report` copies them from benchmarks/devices/):
    // per method the median over materials relative to exact's.
    for (device, rows) in [
        (
            "phone-a",
            "exact,3d/metals/gold,2,0.4,10,complex\nexact,3d/metals/copper,4,0.2,10,complex\nschlick,3d/metals/gold,1,0.1,10,\nschlick,3d/metals/copper,2,0.1,10,\nexact,3d/liquids/water,1.6,0.32,10,dielectric\nschlick,3d/liquids/water,0.8,0.16,10,\n",
        ),
        ("laptop-b", "exact,3d/metals/gold,1,0,5,complex\nschlick,3d/metals/gold,0.25,0,5,\n"),
    ] {
        fs::create_dir_all(out.join("devices").join(device)).unwrap();
        let rows: String = rows.lines().map(|r| format!("{device} GPU,timestamp,{r}\n")).collect();
        fs::write(out.join("devices").join(device).join("gpu_timing.csv"), format!("adapter,timer,method,material,median_ms,spread_ms,repeats,formula\n{rows}"))
            .unwrap();
    }
    fs::write(out.join("devices/phone-a/image_errors.csv"), "material,method,mean_rel_error\nx,exact,0\nx,schlick,0.02\ny,schlick,0.04\n")
        .unwrap();
    // A spectral scene's comparison: a chart per material over depth, one line per index
    // source; a material on two objects (a glass at two thicknesses) gets a chart for each.
    fs::create_dir_all(out.join("gold-in-gold")).unwrap();
    fs::write(
        out.join("gold-in-gold/spectral_errors.csv"),
        "object,object_index,material,index_source,reflection_depth,refraction_depth,wavelengths,pixels,mean_delta_e2000\nsphere,0,3d/metals/gold,three-wavelength,1,0,96,100,2.5\nsphere,0,3d/metals/gold,three-wavelength,8,0,96,100,7.5\nsphere,0,3d/metals/gold,effective,1,0,96,100,0.5\nsphere,0,3d/metals/gold,effective,8,0,96,100,3.25\ncube,1,3d/glass/green,effective,1,0,96,50,0.125\ncube,2,3d/glass/green,effective,1,0,96,50,0.875\n",
    )
    .unwrap();
    let output = nklut(&out, &["report"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let index = fs::read_to_string(out.join("report/index.html")).unwrap();
    assert!(index.contains("From <code>nklut ingest</code> (materials.csv, written "), "the index says where its sections come from");
    assert!(
        index.contains("href=\"effects.html#scene-top\"") && index.contains("href=\"effects.html#scene-glass-sphere\""),
        "the index links each scene's section"
    );
    let effects = fs::read_to_string(out.join("report/effects.html")).unwrap();
    check_well_formed(&effects);
    assert!(
        effects.contains("<code>effects_errors.csv</code>: 1 rows × 4 columns")
            && effects.contains("<td>teapot</td><td>schlick</td><td>2</td><td>1.23 %</td>"),
        "a table in the report's number format"
    );
    assert!(
        effects.contains("<code>gpu-glass-sphere/effects_timing.csv</code>") && effects.contains("<td>exact</td><td>3</td><td>2.50</td>"),
        "a scene folder's table"
    );
    assert!(index.contains("<code>ao_errors.csv</code> is absent"));
    assert!(
        effects.contains("<h3>Three channels against the spectrum</h3>")
            && effects.contains("3d/metals/gold: ΔE2000, three channels vs spectrum"),
        "the spectral chart"
    );
    assert!(
        effects.contains("3d/glass/green (object 1, cube): ΔE2000") && effects.contains("3d/glass/green (object 2, cube): ΔE2000"),
        "one chart per object of a material on two objects"
    );
    assert!(
        effects.contains("src=\"pictures/gold-in-gold/spectral_frames/depth8-0_effective_delta_e.png\""),
        "the deepest depth's ΔE map, from the report's own copy"
    );
    // The spectral scene opens with its finding.
    assert!(effects.contains("<p class=\"finding\" id=\"finding-spectral-gold-in-gold\">"), "the spectral scene's finding");
    // Reader's order: the specular tables (top) before the spectral scene, the timing-only
    // folder last.
    let at = |id: &str| effects.find(&format!("<h2 id=\"{id}\">")).unwrap_or_else(|| panic!("{id}"));
    assert!(at("scene-top") < at("scene-gold-in-gold") && at("scene-gold-in-gold") < at("scene-glass-sphere"));
    // laptop-b before phone-a (folder order); schlick: 0.25/1 and median(1, 2)/median(2, 4).
    assert!(effects.contains("<th>laptop-b (× exact)</th><th>phone-a (× exact)</th>"), "device columns");
    assert!(effects.contains("<td>schlick</td><td>0.250</td><td>0.500</td>"), "device ratios");
    // The study's form: its Mali 400 row as published, with the study's anchors; phone-a
    // against exact on water by the dielectric formula (1.6 ms, IQR 0.32, 10 samples):
    // Schlick on water 0.8 → 0.50 (IQR 0.16/1.6 = 0.10), exact on gold by the complex
    // formula 2 → 1.25 (IQR 0.4/1.6 = 0.25; copper is not in materials.csv, so it has no
    // kind), Schlick on gold 1 → 0.62 (0.625 to two decimals; IQR 0.1/1.6 = 0.0625 → 0.06).
    assert!(effects.contains(
        "<td>Samsung Galaxy S3</td><td>Mali 400</td><td>the study, Table 6</td><td>dielectric formula / complex formula</td><td>1.00</td><td>0.42</td><td>2.89</td>"
    ));
    assert!(
        effects.contains(
            "<td>phone-a</td><td>phone-a GPU</td><td>measured here</td><td>dielectric / complex</td><td>1.00 (IQR 0.20, n 10)</td><td>0.50 (IQR 0.10, n 10)</td><td>1.25 (IQR 0.25, n 10)</td><td>0.62 (IQR 0.06, n 10)</td><td>–</td>"
        ),
        "our device in the study's form"
    );
    // Image error per device where it has the table: schlick's mean of 2 % and 4 %.
    assert!(
        effects.contains("<th>phone-a: mean relative error</th>") && effects.contains("<td>schlick</td><td>3.00 %</td>"),
        "device image errors"
    );
    // `--devices` reads another folder instead; one that is not there is an error.
    fs::create_dir_all(out.join("elsewhere")).unwrap();
    fs::rename(out.join("devices/laptop-b"), out.join("elsewhere/laptop-b")).unwrap();
    let output = nklut(&out, &["report", "--devices", &out.join("elsewhere").display().to_string()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let effects = fs::read_to_string(out.join("report/effects.html")).unwrap();
    assert!(effects.contains("<th>laptop-b (× exact)</th>") && !effects.contains("phone-a"), "only the named folder's devices");
    let output = nklut(&out, &["report", "--devices", &out.join("nowhere").display().to_string()]);
    assert!(!output.status.success() && String::from_utf8_lossy(&output.stderr).contains("nowhere: not a folder"));
    let gold = material_html(&out, "3d/metals/gold");
    assert!(gold.contains("id=\"paste\""), "paste-in panel");
    assert!(gold.contains("<td>f82_tint_r</td><td>0.988</td>") && gold.contains("<td>mean_delta_e2000_f82</td><td>1.23</td>"));
    assert!(gold.contains("f0_srgb8 = #ffd27a"));
}

/// What the audit script reads off the rendered page.
#[derive(serde::Deserialize, Debug)]
struct Audit {
    texts: Vec<Text>,
    overlaps: Vec<(String, String)>,
    counts: Vec<CountSpan>,
    previews: Vec<Preview>,
    captions: usize,
    legend_sizes: Vec<f64>,
}

#[derive(serde::Deserialize, Debug)]
struct Text {
    text: String,
    size: f64,
}

#[derive(serde::Deserialize, Debug)]
struct CountSpan {
    table: String,
    key: String,
    value: usize,
}

#[derive(serde::Deserialize, Debug)]
struct Preview {
    width: u32,
    height: u32,
}

/// Run after load in the browser: every SVG text's computed font size and the pairs of
/// texts of one plot whose boxes overlap, the counts, the preview images.
const AUDIT_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const out={texts:[],overlaps:[],counts:[],previews:[],captions:0,legend_sizes:[]};
for(const svg of document.querySelectorAll('svg')){const boxes=[];for(const t of svg.querySelectorAll('text')){const s=t.textContent.trim();if(!s)continue;const r=t.getBoundingClientRect();out.texts.push({text:s,size:parseFloat(getComputedStyle(t).fontSize)});boxes.push([s,r.left,r.right,r.top,r.bottom]);}
for(let i=0;i<boxes.length;i++)for(let j=i+1;j<boxes.length;j++){const a=boxes[i],b=boxes[j];if(a[1]<b[2]-0.5&&b[1]<a[2]-0.5&&a[3]<b[4]-0.5&&b[3]<a[4]-0.5)out.overlaps.push([a[0],b[0]]);}}
for(const c of document.querySelectorAll('.count'))out.counts.push({table:c.dataset.table,key:c.dataset.key,value:parseInt(c.textContent)});
for(const i of document.querySelectorAll('.sphere')){const r=i.getBoundingClientRect();out.previews.push({width:Math.round(r.width),height:Math.round(r.height)});}
out.captions=document.querySelectorAll('.sphere-cell .method').length;
for(const e of document.querySelectorAll('.legend li, .sphere-cell .method, .strip-axis span'))out.legend_sizes.push(parseFloat(getComputedStyle(e).fontSize));
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

fn chromium(args: &[String]) -> Output {
    Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--hide-scrollbars",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--virtual-time-budget=5000",
        ])
        .args(args)
        .output()
        .expect("chromium is not installed: scripts/test-deps installs Debian's chromium")
}

/// Render `html` in Chromium `width` px wide with `script` added before `</body>`; the
/// JSON the script leaves in `<pre id="nk-audit">`.
fn audit_json(html: &Path, profile: &Path, script: &str, width: u32) -> String {
    let audited = html.with_file_name(format!("audit-{}", html.file_name().unwrap().to_string_lossy()));
    fs::write(&audited, fs::read_to_string(html).unwrap().replace("</body>", &format!("{script}</body>"))).unwrap();
    let profile_arg = format!("--user-data-dir={}", profile.display());
    let url = format!("file://{}", audited.display());
    let dom = chromium(&[profile_arg, format!("--window-size={width},900"), "--dump-dom".into(), url]);
    assert!(dom.status.success(), "{}", String::from_utf8_lossy(&dom.stderr));
    let dom = String::from_utf8_lossy(&dom.stdout);
    let start = dom.find("<pre id=\"nk-audit\">").expect("the audit ran") + "<pre id=\"nk-audit\">".len();
    unescape(&dom[start..start + dom[start..].find("</pre>").unwrap()])
}

/// HTML text or an attribute value with the report's entities (`html::escape`) resolved,
/// `&amp;` last so an escaped entity stays as written.
fn unescape(text: &str) -> String {
    text.replace("&quot;", "\"").replace("&#39;", "'").replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
}

/// A screenshot of `html` `width` × `height` px from `top` px down the page.
fn screenshot(html: &Path, profile: &Path, shot: &Path, (width, height): (u32, u32), top: u32) {
    let shifted = html.with_file_name(format!("shot-{}", html.file_name().unwrap().to_string_lossy()));
    let page = fs::read_to_string(html).unwrap();
    fs::write(&shifted, page.replacen("</head>", &format!("<style>body{{margin-top:-{top}px !important}}</style></head>"), 1)).unwrap();
    let status = chromium(&[
        format!("--user-data-dir={}", profile.display()),
        format!("--window-size={width},{height}"),
        format!("--screenshot={}", shot.display()),
        format!("file://{}", shifted.display()),
    ]);
    assert!(status.status.success());
    let image = image::open(shot).unwrap().to_rgb8();
    let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 50, "{} has only {} colours", shot.display(), distinct.len());
    println!("screenshot kept: {}", shot.display());
}

/// Render `html` in Chromium with the audit script, keep a screenshot as `shot`.
fn audit(html: &Path, profile: &Path, shot: &Path) -> Audit {
    let json = audit_json(html, profile, AUDIT_SCRIPT, 1280);
    let shot_status = chromium(&[
        format!("--user-data-dir={}", profile.display()),
        "--window-size=1280,2400".into(),
        format!("--screenshot={}", shot.display()),
        format!("file://{}", html.display()),
    ]);
    assert!(shot_status.status.success());
    serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"))
}

fn check_readable(name: &str, audit: &Audit) {
    assert!(!audit.texts.is_empty(), "{name}: no plot text");
    let small: Vec<&Text> = audit.texts.iter().filter(|t| t.size < 12.0).collect();
    assert!(small.is_empty(), "{name}: plot text under 12 px: {small:?}");
    assert!(audit.overlaps.is_empty(), "{name}: overlapping plot labels: {:?}", audit.overlaps);
    assert!(audit.legend_sizes.iter().all(|s| *s >= 12.0), "{name}: legend text under 12 px: {:?}", audit.legend_sizes);
}

#[test]
fn rendered_report_is_readable_and_its_counts_are_its_tables() {
    let (out, validate_stdout) = build_report("browser");
    let artefacts = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-artefacts");
    fs::create_dir_all(&artefacts).unwrap();
    let profile = out.join("chromium-profile");

    let index = audit(&out.join("report/index.html"), &profile, &artefacts.join("index.png"));
    println!("index: {} plot texts, {} counts", index.texts.len(), index.counts.len());
    check_readable("index", &index);
    let keys: BTreeSet<(String, String)> = index.counts.iter().map(|c| (c.table.clone(), c.key.clone())).collect();
    for required in [
        ("materials.csv", "rows"),
        ("excluded.csv", "rows"),
        ("errors.csv", "fallback"),
        ("materials.csv", "sparse"),
        ("colors.csv", "out-of-gamut"),
        ("colors.csv", "fit-at-bound"),
    ] {
        assert!(keys.contains(&(required.0.to_string(), required.1.to_string())), "the index prints no {required:?}");
    }
    for c in &index.counts {
        assert_eq!(c.value, recount(&out, &c.table, &c.key), "{} {} on the page", c.table, c.key);
    }
    // The fallback figure also equals validate's own summary (no two of these pages share
    // a data file, so material channels are page-channels).
    let said: usize = validate_stdout
        .lines()
        .find_map(|l| l.strip_prefix("schlick_compensated: ").and_then(|r| r.split_whitespace().next()).and_then(|n| n.parse().ok()))
        .expect("validate prints its fallback count");
    let shown = index.counts.iter().find(|c| c.key == "fallback").unwrap().value;
    assert_eq!(shown, said, "the report and validate agree on compensated Schlick's fallbacks");
    assert!(shown >= 2, "gold's green and blue have no real exponent");

    let gold = audit(&out.join("report/materials/3d/metals/gold.html"), &profile, &artefacts.join("gold.png"));
    check_readable("gold", &gold);
    let spheres = gold.captions as u32;
    assert!(spheres >= 7, "reference, fitted, exact and the approximations: {spheres}");
    // One sphere box per curve, each shown at 256 px from the one sheet of spheres.
    assert_eq!(gold.previews.len(), spheres as usize, "a sphere per caption");
    assert!(gold.previews.iter().all(|p| (p.width, p.height) == (256, 256)), "{:?}", gold.previews);
    let sheet = image::open(out.join("report/previews/3d/metals/gold.png")).unwrap();
    assert_eq!((sheet.width(), sheet.height()), (spheres * 256, 256));
    for tick in ["0", "30", "60", "90"] {
        assert!(gold.texts.iter().filter(|t| t.text == tick).count() >= 4, "θ tick {tick} on every θ axis");
    }
    for shot in ["index.png", "gold.png"] {
        let image = image::open(artefacts.join(shot)).unwrap().to_rgb8();
        let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 50, "{shot} has only {} colours", distinct.len());
        println!("screenshot kept: {}", artefacts.join(shot).display());
    }
}

#[test]
fn the_audit_sees_small_and_overlapping_plot_text() {
    let out = scratch("audit");
    fs::create_dir_all(&out).unwrap();
    let page = out.join("bad.html");
    fs::write(
        &page,
        "<!DOCTYPE html><html><body><svg width=\"200\" height=\"100\"><text x=\"10\" y=\"50\" font-size=\"10\">label one</text><text x=\"20\" y=\"52\" font-size=\"10\">label two</text><text x=\"10\" y=\"90\" font-size=\"14\">apart</text></svg></body></html>",
    )
    .unwrap();
    let seen = audit(&page, &out.join("profile"), &out.join("bad.png"));
    assert_eq!(seen.texts.iter().filter(|t| t.size < 12.0).count(), 2, "{seen:?}");
    assert_eq!(seen.overlaps, vec![("label one".to_string(), "label two".to_string())]);
}

/// After `params`, each material page carries one copyable block per tool, the same text
/// as its paste-in file.
#[test]
fn material_pages_carry_a_block_per_tool() {
    let out = scratch("paste");
    stages(&out, &["3d/metals/gold"], &[]);
    let output = nklut(&out, &["params", "--page", "3d/metals/gold"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let output = nklut(&out, &["report", "--page", "3d/metals/gold"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let html = material_html(&out, "3d/metals/gold");
    let paste: serde_json::Value = serde_json::from_slice(&fs::read(out.join("params/nk_3d_metals_gold.json")).unwrap()).unwrap();
    for tool in ["blender", "unreal", "unity_hdrp", "threejs", "filament", "godot", "openpbr", "gltf"] {
        let text = paste["engines"][tool].as_str().unwrap();
        let escaped = text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&#39;");
        assert!(html.contains(&format!("data-tool=\"{tool}\">{escaped}</textarea>")), "{tool} block missing or different");
    }
}

/// A sphere on a slab under surfel ambient occlusion (brute force and the tree, 1–3 passes)
/// and screen-space GTAO.
const AO_SCENE: &str = "resolution: [48, 48]
camera: { axis: [-0.3, 1, 0.1], distance: 2.4, frames: 1, fov_y_degrees: 55 }
effects:
  ambient_occlusion: { passes: 2, hierarchy: true, bent_normals: false, gtao: { radius: 0.5, slices: 2, steps: 4 } }
lights:
  - { kind: directional, direction: [-0.4, -1, -0.3], colour: [0.6, 0.6, 0.6] }
  - { kind: ambient, colour: [0.5, 0.5, 0.5] }
objects:
  - { mesh: sphere, diffuse: [0.8, 0.8, 0.8] }
  - { mesh: cube, scale: [2.8, 0.05, 2.8], position: [0, -0.7655, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 1 }
measurements: [image_error]
";

/// An output folder as `make report` leaves it for the two scenes above: the stages for
/// their materials, `nklut effects` per scene into `<out>/<scene>/`, then the report.
fn effects_report(name: &str) -> Scratch {
    let out = scratch(name);
    stages(&out, &["3d/glass/BK7", "3d/crystals/diamond"], &[]);
    for (scene, text, extra) in [("specular", SPECULAR_SCENE, &[][..]), ("ao", AO_SCENE, &["--ao-rays", "16"][..])] {
        let file = out.join(format!("{scene}.yaml"));
        fs::write(&file, text).unwrap();
        let file = file.display().to_string();
        let output = nklut(&out.join(scene), &[&["effects", "--hero-size", "512"], extra, &[file.as_str()]].concat());
        assert!(output.status.success(), "effects {scene}: {}", String::from_utf8_lossy(&output.stderr));
    }
    let output = nklut(&out, &["report"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    out
}

/// `name="value"` pairs of one tag (values unescaped).
fn attributes(tag: &str) -> BTreeMap<String, String> {
    let mut found = BTreeMap::new();
    let mut rest = tag;
    while let Some(eq) = rest.find("=\"") {
        let name = rest[..eq].rsplit(|c: char| c.is_whitespace()).next().unwrap().to_string();
        let value_start = eq + 2;
        let value_end = value_start + rest[value_start..].find('"').unwrap();
        let value = unescape(&rest[value_start..value_end]);
        found.insert(name, value);
        rest = &rest[value_end + 1..];
    }
    found
}

/// A chart point's hover mark: its label (the `<title>`) and its attributes.
struct Mark {
    label: String,
    attributes: BTreeMap<String, String>,
}

/// One axis of a mark, resolved against its table.
struct Traced {
    table: String,
    column: String,
    rows: Vec<usize>,
    value: f64,
}

impl Mark {
    fn axis(&self, axis: &str) -> Option<Traced> {
        let get = |what: &str| self.attributes.get(&format!("data-{axis}{what}"));
        Some(Traced {
            table: get("-table")?.clone(),
            column: get("-column")?.clone(),
            rows: get("-rows")?.split_whitespace().map(|r| r.parse().unwrap()).collect(),
            value: get("")?.parse().unwrap(),
        })
    }
}

fn marks(html: &str) -> Vec<Mark> {
    html.split("<circle class=\"trace\"")
        .skip(1)
        .map(|rest| {
            let tag = &rest[..rest.find('>').unwrap()];
            let title = &rest[rest.find("<title>").unwrap() + 7..rest.find("</title>").unwrap()];
            Mark { label: unescape(title), attributes: attributes(tag) }
        })
        .collect()
}

/// Every chart point of the effects page is the mean of the rows it names: recomputed
/// here from the CSV (weighted as it says), and the rows are the ones its label names —
/// per chart type: Fresnel error against depth, total error against time, geometry error
/// against steps, AO error against passes and against time.
#[test]
fn effects_charts_trace_to_their_rows() {
    let out = effects_report("effects-trace");
    let html = fs::read_to_string(out.join("report/effects.html")).unwrap();
    check_well_formed(&html);
    no_external_resource(&html);
    let marks = marks(&html);
    let mut tables: BTreeMap<String, CsvTable> = BTreeMap::new();
    let mut by_column: BTreeMap<(String, String), Vec<(&Mark, Traced)>> = BTreeMap::new();
    for mark in &marks {
        for axis in ["x", "y"] {
            let Some(traced) = mark.axis(axis) else { continue };
            let table = tables.entry(traced.table.clone()).or_insert_with(|| CsvTable::load(&out.join(&traced.table)).unwrap().unwrap());
            let weight = mark.attributes.get(&format!("data-{axis}-weight"));
            let (mut sum, mut total) = (0.0, 0.0);
            for &r in &traced.rows {
                let row = &table.rows[r];
                let w: f64 = weight.map_or(1.0, |w| table.text(row, w).parse().unwrap());
                sum += w * table.text(row, &traced.column).parse::<f64>().unwrap();
                total += w;
            }
            let expected = sum / total;
            assert!(
                (traced.value - expected).abs() <= 1e-12 * expected.abs().max(1e-12),
                "{}: {} against {expected}",
                mark.label,
                traced.value
            );
            let name = traced.table.rsplit('/').next().unwrap().to_string();
            by_column.entry((name, traced.column.clone())).or_default().push((mark, traced));
        }
    }
    let errors = &tables["specular/effects_errors.csv"];
    let text = |r: usize, c: &str| errors.text(&errors.rows[r], c).to_string();
    let every = |points: &[(&Mark, Traced)]| -> Vec<usize> {
        let mut rows: Vec<usize> = points.iter().flat_map(|(_, t)| t.rows.clone()).collect();
        rows.sort_unstable();
        rows
    };
    // Fresnel error against depth: "material, method, depth r+t" at the finest search.
    for column in ["fresnel_mean_delta_e2000", "fresnel_mean_rel_error"] {
        let points = &by_column[&("effects_errors.csv".to_string(), column.to_string())];
        for (mark, traced) in points {
            let parts: Vec<&str> = mark.label.split(", ").collect();
            let (r, t) = parts[2].trim_start_matches("depth ").split_once('+').unwrap();
            for &row in &traced.rows {
                assert_eq!(
                    [
                        text(row, "material"),
                        text(row, "method"),
                        text(row, "reflection_depth"),
                        text(row, "refraction_depth"),
                        text(row, "linear_steps"),
                        text(row, "secant_steps")
                    ],
                    [parts[0], parts[1], r, t, "12", "4"].map(String::from),
                    "{}",
                    mark.label
                );
            }
        }
        let finest: Vec<usize> =
            (0..errors.rows.len()).filter(|&r| text(r, "linear_steps") == "12" && text(r, "secant_steps") == "4").collect();
        assert_eq!(every(points), finest, "{column}: each row at the finest search in one point");
        assert_eq!(points.len(), 2 * 2 * 4, "2 materials × 2 methods × 4 depth pairs");
    }
    // Total error against time: "method r+t linear/secant", x from the CPU timing table.
    let timing = &tables["specular/effects_cpu_timing.csv"];
    let cost = &by_column[&("effects_errors.csv".to_string(), "total_mean_delta_e2000".to_string())];
    for (mark, traced) in cost {
        // The hover title: the configuration, then its values on their own lines.
        let first_line = mark.label.lines().next().unwrap();
        let (method, rest) = first_line.split_once(' ').unwrap();
        let (depths, steps) = rest.split_once(' ').unwrap();
        let (r, t) = depths.split_once('+').unwrap();
        let (l, s) = steps.split_once('/').unwrap();
        let named = [method, r, t, l, s].map(String::from);
        let configuration = |table: &CsvTable, row: usize| {
            ["method", "reflection_depth", "refraction_depth", "linear_steps", "secant_steps"]
                .map(|c| table.text(&table.rows[row], c).to_string())
        };
        assert!(traced.rows.iter().all(|&row| configuration(errors, row) == named), "{}", mark.label);
        let x = mark.axis("x").unwrap();
        assert_eq!((x.table.as_str(), x.column.as_str()), ("specular/effects_cpu_timing.csv", "frame_ms"));
        assert!(!x.rows.is_empty() && x.rows.iter().all(|&row| configuration(timing, row) == named), "{}", mark.label);
    }
    assert_eq!(every(cost), (0..errors.rows.len()).collect::<Vec<_>>(), "every configuration has its point");
    assert_eq!(cost.len(), 2 * 4 * 4, "2 methods × 4 depth pairs × 4 step pairs");
    // Geometry error against steps: exact Fresnel at the deepest depths, per step pair.
    let geometry = &by_column[&("effects_errors.csv".to_string(), "geometry_mean_delta_e2000".to_string())];
    assert_eq!(geometry.len(), 4, "2 linear × 2 secant step counts");
    for (mark, traced) in geometry {
        let (l, rest) = mark.label.split_once(" linear + ").unwrap();
        let (s, _) = rest.split_once(" secant").unwrap();
        for &row in &traced.rows {
            assert_eq!(
                [
                    text(row, "method"),
                    text(row, "reflection_depth"),
                    text(row, "refraction_depth"),
                    text(row, "linear_steps"),
                    text(row, "secant_steps")
                ],
                ["exact", "2", "2", l, s].map(String::from),
                "{}",
                mark.label
            );
        }
        assert_eq!(traced.rows.len(), 2, "{}: one row per sphere", mark.label);
    }
    // Ambient occlusion: "technique, p pass(es)", weighted by surfels, against passes and time.
    let ao = &tables["ao/ao_errors.csv"];
    let passes = &by_column[&("ao_errors.csv".to_string(), "mean_error".to_string())];
    let mut seen_rows = Vec::new();
    for (mark, traced) in passes {
        let (technique, rest) = mark.label.split_once(", ").unwrap();
        let p = rest.split_once(' ').unwrap().0;
        for &row in &traced.rows {
            let hierarchy = ao.text(&ao.rows[row], "hierarchy") == "true";
            assert_eq!((hierarchy, ao.text(&ao.rows[row], "passes")), (technique == "tree", p), "{}", mark.label);
        }
        assert_eq!(mark.attributes.get("data-y-weight").map(String::as_str), Some("surfels"));
        seen_rows.extend(traced.rows.clone());
    }
    seen_rows.sort_unstable();
    seen_rows.dedup();
    let surfel_rows: Vec<usize> = (0..ao.rows.len()).filter(|&r| ao.text(&ao.rows[r], "technique") == "surfels").collect();
    assert_eq!(seen_rows, surfel_rows, "every surfel AO row in a point (GTAO's are per pixel only)");
    // GTAO's rows (one per object) in the per-pixel table beside the surfels', with their
    // per-pixel mean as the CSV has it.
    let gtao_rows: Vec<&Vec<String>> = ao.rows.iter().filter(|r| ao.text(r, "technique") == "gtao").collect();
    assert_eq!(gtao_rows.len(), 2);
    let per_pixel = &html[html.find("class=\"ao-per-pixel\"").expect("the per-pixel table")..];
    let per_pixel = &per_pixel[..per_pixel.find("</table>").unwrap()];
    for row in gtao_rows {
        let mean = report::html::number(ao.text(row, "pixel_mean_error").parse().unwrap());
        let cells = format!(
            "<td>{}</td><td>GTAO bare r 0.5, 2×4</td><td>–</td><td>{}</td><td>{mean}</td>",
            ao.text(row, "mesh"),
            ao.text(row, "pixels")
        );
        assert!(per_pixel.contains(&cells), "{cells} not in {per_pixel}");
    }
    let time = &by_column[&("ao_errors.csv".to_string(), "cpu_ms".to_string())];
    assert_eq!(time.len(), 2 * 3, "brute force and tree × 3 passes");
    for (mark, x) in time {
        assert_eq!(x.rows, mark.axis("y").unwrap().rows, "{}: time and error of the same rows", mark.label);
    }
}

/// What the effects audit reads off the rendered page at 1400 px.
#[derive(serde::Deserialize, Debug)]
struct EffectsAudit {
    viewport: f64,
    wide: Vec<String>,
    texts: Vec<Text>,
    overlaps: Vec<(String, String)>,
    panels: Vec<Panel>,
    heroes: Vec<Hero>,
    figures: Vec<Figure>,
    sections: Vec<Section>,
    legends: Vec<Legend>,
}

/// A colour bar of the error images: the scale its figure states and its picture's width.
#[derive(serde::Deserialize, Debug)]
struct Legend {
    scale: String,
    width: u32,
}

#[derive(serde::Deserialize, Debug)]
struct Panel {
    panel: String,
    label: String,
}

#[derive(serde::Deserialize, Debug)]
struct Hero {
    src: String,
    width: u32,
    height: u32,
    /// The width it is shown at, in CSS pixels.
    shown: f64,
}

#[derive(serde::Deserialize, Debug)]
struct Figure {
    table: String,
    row: usize,
    column: String,
    text: String,
}

#[derive(serde::Deserialize, Debug)]
struct Section {
    id: String,
    top: u32,
}

const EFFECTS_AUDIT: &str = r#"<script>window.addEventListener('load',()=>{const W=document.documentElement.clientWidth;const out={viewport:W,wide:[],texts:[],overlaps:[],panels:[],heroes:[],figures:[],sections:[],legends:[]};
for(const f of document.querySelectorAll('figure[data-scale]')){const i=f.querySelector('img');out.legends.push({scale:f.dataset.scale,width:i?i.naturalWidth:0});}
for(const e of document.body.querySelectorAll('*')){const r=e.getBoundingClientRect();if(r.width>0&&r.right>W+0.5&&!(e.parentElement&&e.parentElement.closest('.wide')))out.wide.push(e.tagName+'.'+e.className+' right '+Math.round(r.right));}
if(document.documentElement.scrollWidth>W)out.wide.push('page scrolls sideways: '+document.documentElement.scrollWidth);
for(const svg of document.querySelectorAll('svg')){const boxes=[];for(const t of svg.querySelectorAll('text')){const s=t.textContent.trim();if(!s)continue;const r=t.getBoundingClientRect();out.texts.push({text:s,size:parseFloat(getComputedStyle(t).fontSize)});boxes.push([s,r.left,r.right,r.top,r.bottom]);}
for(let i=0;i<boxes.length;i++)for(let j=i+1;j<boxes.length;j++){const a=boxes[i],b=boxes[j];if(a[1]<b[2]-0.5&&b[1]<a[2]-0.5&&a[3]<b[4]-0.5&&b[3]<a[4]-0.5)out.overlaps.push([a[0],b[0]]);}}
for(const f of document.querySelectorAll('.panels figure')){const b=f.querySelector('figcaption b');out.panels.push({panel:f.dataset.panel||'',label:b?b.textContent.trim():''});}
for(const i of document.querySelectorAll('img.hero'))out.heroes.push({src:i.getAttribute('src'),width:i.naturalWidth,height:i.naturalHeight,shown:i.getBoundingClientRect().width});
for(const s of document.querySelectorAll('span.figure[data-table]'))out.figures.push({table:s.dataset.table,row:parseInt(s.dataset.row),column:s.dataset.column,text:s.textContent});
for(const h of document.querySelectorAll('h2[id]'))out.sections.push({id:h.id,top:Math.round(h.getBoundingClientRect().top+window.scrollY)});
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

/// The effects page in Chromium at 1400 px: nothing wider than the window, chart text
/// ≥ 12 px without overlaps, every hero panel labelled, every figure printed equal to
/// effects_hero.csv in the report's format, hero frames ≥ 512 px; a screenshot of each
/// section kept under `target/tmp/report-artefacts/`.
#[test]
fn effects_page_reads_at_1400_px_and_its_figures_are_its_tables() {
    let out = effects_report("effects-browser");
    let page = out.join("report/effects.html");
    let profile = out.join("chromium-profile");
    let json = audit_json(&page, &profile, EFFECTS_AUDIT, 1400);
    let audit: EffectsAudit = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"));
    assert!(audit.viewport >= 1380.0, "{}", audit.viewport);
    assert!(audit.wide.is_empty(), "wider than the window: {:?}", audit.wide);
    assert!(audit.texts.len() > 50, "chart text: {}", audit.texts.len());
    let small: Vec<&Text> = audit.texts.iter().filter(|t| t.size < 12.0).collect();
    assert!(small.is_empty(), "chart text under 12 px: {small:?}");
    assert!(audit.overlaps.is_empty(), "overlapping chart text: {:?}", audit.overlaps);
    let mut hero_rows = 0;
    let (mut hero_images, mut hero_figures, mut against_exact) = (0, 0, 0);
    for scene in ["specular", "ao"] {
        let hero = CsvTable::load(&out.join(scene).join("effects_hero.csv")).unwrap().unwrap();
        hero_rows += hero.rows.len();
        let filled = |column: &str| hero.rows.iter().filter(|r| !hero.text(r, column).is_empty()).count();
        hero_images += filled("file") + filled("error_file") + filled("exact_error_file");
        hero_figures += 5 * filled("error_file") + 3 * filled("exact_error_file");
        against_exact += filled("exact_error_file");
        for row in &hero.rows {
            let panel = hero.text(row, "panel");
            assert!(
                audit.panels.iter().any(|p| p.panel == panel && p.label == hero.text(row, "label")),
                "{scene} {panel}: no panel labelled {:?}",
                hero.text(row, "label")
            );
        }
    }
    assert_eq!(audit.panels.len(), hero_rows, "one panel per row of effects_hero.csv");
    assert!(audit.panels.iter().all(|p| !p.label.is_empty()));
    // Reference, exact and schlick; no AO, 1–3 passes: each frame, the error image against
    // the reference of each but the references, and against exact of schlick alone.
    assert_eq!(against_exact, 1, "schlick against exact");
    assert_eq!(
        (audit.heroes.len(), hero_images),
        (2 * hero_rows - 2 + against_exact, 2 * hero_rows - 2 + against_exact),
        "{:?}",
        audit.heroes
    );
    for hero in &audit.heroes {
        assert!(hero.width.max(hero.height) >= 512, "{} is {}×{}", hero.src, hero.width, hero.height);
        // At 1400 px a picture of 512 px or more shows at its natural size.
        assert!((hero.shown - f64::from(hero.width)).abs() < 0.5, "{} shown {} px wide, natural {}", hero.src, hero.shown, hero.width);
    }
    assert_eq!(audit.figures.len(), hero_figures, "five figures per panel but the references, three more against exact");
    // One legend per kind of error image, each stating its table's scale: against exact and
    // against the reference for the specular scene, against the reference for AO; every
    // scale of the rule a 1-2-5 step.
    let specular = CsvTable::load(&out.join("specular/effects_hero.csv")).unwrap().unwrap();
    let schlick = specular.rows.iter().find(|r| specular.text(r, "panel") == "schlick").unwrap();
    let ao = CsvTable::load(&out.join("ao/effects_hero.csv")).unwrap().unwrap();
    let ao_scale = ao.number(&ao.rows[0], "error_scale").unwrap();
    assert!(ao.rows.iter().all(|r| ao.number(r, "error_scale") == Some(ao_scale)), "one scale over the AO set");
    let mut expected: Vec<String> =
        ["exact_error_scale", "error_scale"].iter().map(|c| format!("{}", specular.number(schlick, c).unwrap())).collect();
    expected.push(format!("{ao_scale}"));
    let mut stated: Vec<String> = audit.legends.iter().map(|l| l.scale.clone()).collect();
    stated.sort();
    expected.sort();
    assert_eq!(stated, expected, "{:?}", audit.legends);
    assert!(audit.legends.iter().all(|l| l.width == 512), "{:?}", audit.legends);
    for (column, scale) in [
        ("exact_error_scale", specular.number(schlick, "exact_error_scale").unwrap()),
        ("error_scale", specular.number(schlick, "error_scale").unwrap()),
        ("AO error_scale", ao_scale),
    ] {
        let mantissa = scale / 10f64.powf(scale.log10().floor());
        assert!([1.0, 2.0, 5.0].iter().any(|k| (mantissa - k).abs() < 1e-9), "{column} {scale} is not a 1-2-5 step");
    }
    for figure in &audit.figures {
        let table = CsvTable::load(&out.join(&figure.table)).unwrap().unwrap();
        let raw = table.text(&table.rows[figure.row], &figure.column);
        let value: f64 = raw.parse().unwrap();
        let expected = match figure.column.as_str() {
            "mean_delta_e2000" | "exact_mean_delta_e2000" => report::html::delta_e(value),
            "mean_rel_error" => report::html::percent(value),
            "pixels" => raw.to_string(),
            _ => report::html::number(value),
        };
        assert_eq!(figure.text, expected, "{} row {} {}", figure.table, figure.row, figure.column);
    }
    let artefacts = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-artefacts");
    fs::create_dir_all(&artefacts).unwrap();
    assert_eq!(audit.sections.iter().filter(|s| s.id.starts_with("scene-")).count(), 2, "{:?}", audit.sections);
    for section in &audit.sections {
        screenshot(&page, &profile, &artefacts.join(format!("effects-{}.png", section.id)), (1400, 1400), section.top);
    }
}

/// Reads the cross-device tables off the rendered effects page: the per-device-and-method
/// rows and the study-form rows, cell texts.
const DEVICES_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const rows=(c)=>[...document.querySelectorAll(`table.${c} tbody tr`)].map(tr=>[...tr.children].map(td=>td.textContent));
const out={methods:rows('device-methods'),study:rows('study-form'),effects:rows('device-effects')};
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

/// The columns that tell one effects configuration from another (with the method).
const EFFECTS_CONFIGURATION: [&str; 6] = ["effect", "reflection_depth", "refraction_depth", "linear_steps", "secant_steps", "resolution"];

/// An effects configuration's cells, in the order of [`EFFECTS_CONFIGURATION`].
type EffectsConfiguration = [String; 6];

/// The median of `values` (mean of the middle two), computed here apart from the report.
fn median_of(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    }
}

/// The committed device results (`benchmarks/devices/`: lavapipe through the native runner,
/// SwiftShader through the browser bench) in the report's cross-device section, read off the
/// page Chromium rendered: one row per device and method, and each ratio equal to the one
/// computed here from the input files (CSV and the browser's JSON) to the 3 digits shown.
#[test]
fn cross_device_section_shows_native_and_browser_results_as_their_files_say() {
    let out = scratch("report-devices");
    stages(&out, &["3d/metals/gold", "3d/liquids/water", "3d/crystals/diamond"], &[]);
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices");
    // Per device, method → the pass times of its rows, from the files themselves.
    let mut expected: BTreeMap<String, BTreeMap<String, Vec<f64>>> = BTreeMap::new();
    // Per device, the effects_timing rows: (method, configuration) → shading ms.
    let mut effects: BTreeMap<String, Vec<(String, EffectsConfiguration, f64)>> = BTreeMap::new();
    let mut sources = 0;
    for entry in fs::read_dir(&committed).unwrap().flatten() {
        let path = entry.path();
        // A folder by its whole name (dots and all), a file by its stem.
        let name = if path.is_dir() { entry.file_name() } else { path.file_stem().unwrap().to_os_string() };
        let name = name.to_string_lossy().into_owned();
        let times = expected.entry(name.clone()).or_default();
        if path.is_dir() {
            let mut reader = csv::Reader::from_path(path.join("gpu_timing.csv")).unwrap();
            let headers = reader.headers().unwrap().clone();
            let at = |h: &str| headers.iter().position(|x| x == h).unwrap();
            let (method, median) = (at("method"), at("median_ms"));
            for record in reader.records() {
                let record = record.unwrap();
                times.entry(record[method].to_string()).or_default().push(record[median].parse().unwrap());
            }
            if let Ok(mut reader) = csv::Reader::from_path(path.join("effects_timing.csv")) {
                let headers = reader.headers().unwrap().clone();
                for record in reader.records() {
                    let record = record.unwrap();
                    let cell = |h: &str| record[headers.iter().position(|x| x == h).unwrap()].to_string();
                    let configuration = EFFECTS_CONFIGURATION.map(&cell);
                    effects.entry(name.clone()).or_default().push((cell("method"), configuration, cell("shading_ms").parse().unwrap()));
                }
            }
            sources += 1;
        } else if path.extension().is_some_and(|x| x == "json") {
            let result: serde_json::Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
            assert_eq!(result["complete"], true, "{name}");
            for row in result["gpu_timing"].as_array().unwrap() {
                times.entry(row["method"].as_str().unwrap().to_string()).or_default().push(row["median_ms"].as_f64().unwrap());
            }
            for row in result["effects_timing"].as_array().unwrap() {
                let cell = |h: &str| match &row[h] {
                    serde_json::Value::String(text) => text.clone(),
                    other => other.to_string(),
                };
                let configuration = EFFECTS_CONFIGURATION.map(&cell);
                effects.entry(name.clone()).or_default().push((cell("method"), configuration, row["shading_ms"].as_f64().unwrap()));
            }
            sources += 1;
        } else {
            expected.remove(&name);
        }
    }
    assert!(sources >= 2, "a native and a browser result are committed");
    let folder = out.join("devices");
    fs::create_dir_all(&folder).unwrap();
    for entry in fs::read_dir(&committed).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            fs::create_dir_all(folder.join(entry.file_name())).unwrap();
            // The device's top-level tables (a folder may keep further runs in sub-folders).
            for file in fs::read_dir(&path).unwrap().flatten().filter(|f| f.path().is_file()) {
                fs::copy(file.path(), folder.join(entry.file_name()).join(file.file_name())).unwrap();
            }
        } else if path.extension().is_some_and(|x| x == "json") {
            fs::copy(&path, folder.join(entry.file_name())).unwrap();
        }
    }
    let output = nklut(&out, &["report", "--page", "3d/metals/gold", "--page", "3d/liquids/water", "--page", "3d/crystals/diamond"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let json = audit_json(&out.join("report/effects.html"), &out.join("profile"), DEVICES_SCRIPT, 1400);
    let seen: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rows = seen["methods"].as_array().unwrap();
    let shown: usize = expected.values().map(|methods| methods.len()).sum();
    assert_eq!(rows.len(), shown, "one row per device and method: {rows:?}");
    for row in rows {
        let cells: Vec<&str> = row.as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
        let (device, method) = (cells[0], cells[3]);
        let times = expected.get(device).unwrap_or_else(|| panic!("{device:?} not among {:?}", expected.keys()));
        let ms = median_of(times[method].clone());
        let close = |shown: &str, want: f64| {
            let value: f64 = shown.parse().unwrap_or_else(|_| panic!("{device} {method}: {shown:?}"));
            assert!((value - want).abs() <= 5e-3 * want.abs() + 1e-4, "{device} {method}: shown {value}, files give {want}");
        };
        close(cells[4], ms);
        close(cells[5], ms / median_of(times["exact"].clone()));
        if let Some(fetch) = times.get("texture") {
            close(cells[6], ms / median_of(fetch.clone()));
        }
        assert_eq!(cells[1].starts_with("browser"), !committed.join(device).is_dir(), "{device}: source {}", cells[1]);
    }
    // Reflections and refractions: one row per device and configuration of the files'
    // effects_timing rows, the shading time and its ratio to exact's in the same
    // configuration computed here.
    let shown_effects = seen["effects"].as_array().unwrap();
    assert_eq!(shown_effects.len(), effects.values().map(Vec::len).sum::<usize>(), "{shown_effects:?}");
    assert!(effects.len() >= 2, "a native and a browser effects_timing are committed: {:?}", effects.keys());
    let mut shown_rows = shown_effects.iter();
    for (device, rows) in &effects {
        for (method, configuration, ms) in rows {
            let cells: Vec<&str> = shown_rows.next().unwrap().as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
            let [effect, reflection, refraction, linear, secant, resolution] = configuration.clone();
            assert_eq!(
                (cells[0], cells[2], cells[3]),
                (
                    device.as_str(),
                    method.as_str(),
                    format!("{effect} · {reflection}/{refraction} · {linear}/{secant} · {resolution}").as_str()
                )
            );
            let exact = rows.iter().find(|(m, c, _)| m == "exact" && c == configuration).map(|(_, _, ms)| *ms).unwrap();
            let close = |shown: &str, want: f64| {
                let value: f64 = shown.parse().unwrap_or_else(|_| panic!("{device} {method}: {shown:?}"));
                assert!(
                    (value - want).abs() <= 5e-3 * want.abs() + 1e-4,
                    "{device} {method} {configuration:?}: shown {value}, files give {want}"
                );
            };
            close(cells[5], *ms);
            close(cells[6], ms / exact);
        }
    }
    // The study's form: its five devices, then one row per device measured here.
    let study = seen["study"].as_array().unwrap();
    let ours: Vec<&str> = study.iter().filter(|r| r[2] == "measured here").map(|r| r[0].as_str().unwrap()).collect();
    assert_eq!(ours, expected.keys().map(String::as_str).collect::<Vec<_>>());
}

/// Reads every bar of the AO histograms off the rendered effects page: its chart's object,
/// technique and passes, its table row, series, count and share, and its rendered height.
const HISTOGRAM_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const out=[];
for(const f of document.querySelectorAll('figure.histogram'))for(const b of f.querySelectorAll('rect.bar'))out.push({mesh:f.dataset.mesh,technique:f.dataset.technique,passes:f.dataset.passes,table:b.dataset.table,row:parseInt(b.dataset.row),series:b.dataset.series,count:parseInt(b.dataset.count),share:parseFloat(b.dataset.share),height:b.getBoundingClientRect().height});
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

#[derive(serde::Deserialize, Debug)]
struct HistogramBar {
    mesh: String,
    technique: String,
    passes: String,
    table: String,
    row: usize,
    series: String,
    count: u64,
    share: f64,
    height: f64,
}

/// The AO histograms on the page Chromium rendered are `ao_histogram.csv`: one chart per
/// object and technique at its largest pass count, one bar per row of its vertex and pixel
/// histograms, each bar's count the row's, its share the count over its histogram's total
/// (recounted here from the CSV), its rendered height proportional to that share within
/// 0.01 px, and each vertex histogram counting every surfel of its object (`ao_errors.csv`).
#[test]
fn ao_histogram_bars_are_its_counts() {
    let out = scratch("effects-histogram");
    stages(&out, &["3d/metals/gold"], &[]);
    let file = out.join("ao.yaml");
    fs::write(&file, AO_SCENE).unwrap();
    let output = nklut(&out.join("ao"), &["effects", "--ao-rays", "16", &file.display().to_string()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let output = nklut(&out, &["report"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let page = out.join("report/effects.html");
    let json = audit_json(&page, &out.join("chromium-profile"), HISTOGRAM_SCRIPT, 1400);
    let bars: Vec<HistogramBar> = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"));
    let table = CsvTable::load(&out.join("ao/ao_histogram.csv")).unwrap().unwrap();
    let errors = CsvTable::load(&out.join("ao/ao_errors.csv")).unwrap().unwrap();
    // Both techniques ran 1–3 passes: each is drawn at 3.
    let passes = table.distinct("passes").into_iter().map(|p| p.parse::<u32>().unwrap()).max().unwrap().to_string();
    assert_eq!(passes, "3");
    // The histograms drawn: vertex and pixel, at the largest pass count, every row once.
    let drawn: Vec<usize> = (0..table.rows.len())
        .filter(|&r| {
            let row = &table.rows[r];
            table.text(row, "passes") == passes && ["vertex", "pixel"].contains(&table.text(row, "weighting"))
        })
        .collect();
    let mut rows: Vec<usize> = bars.iter().map(|b| b.row).collect();
    rows.sort_unstable();
    assert_eq!(rows, drawn, "one bar per row of the drawn histograms");
    let meshes = table.distinct("mesh").len();
    assert_eq!(meshes, 2, "sphere and slab");
    assert_eq!(drawn.len(), meshes * 2 * 2 * 40, "objects × techniques × (vertex, pixel) × 40 bins");
    let key = |r: usize, what: &str| table.text(&table.rows[r], what).to_string();
    // Each histogram's total count, from the CSV.
    let mut totals: BTreeMap<(String, String, String), u64> = BTreeMap::new();
    for &r in &drawn {
        *totals.entry((key(r, "mesh"), key(r, "technique"), key(r, "weighting"))).or_default() += key(r, "count").parse::<u64>().unwrap();
    }
    let mut pixels_per_share: BTreeMap<(String, String), f64> = BTreeMap::new();
    for bar in &bars {
        assert_eq!(bar.table, "ao/ao_histogram.csv");
        let r = bar.row;
        assert_eq!(
            (bar.mesh.as_str(), bar.technique.as_str(), bar.passes.as_str()),
            (key(r, "mesh").as_str(), key(r, "technique").as_str(), passes.as_str())
        );
        assert_eq!(bar.series, if key(r, "weighting") == "vertex" { "per vertex" } else { "per covered pixel" });
        assert_eq!(bar.count, key(r, "count").parse::<u64>().unwrap(), "row {r}");
        let total = totals[&(key(r, "mesh"), key(r, "technique"), key(r, "weighting"))];
        let share = bar.count as f64 / total as f64;
        assert!((bar.share - share).abs() < 1e-12, "row {r}: share {} against {share}", bar.share);
        // Heights in one chart are proportional to the shares: the tallest bar sets the scale.
        let tallest =
            bars.iter().filter(|b| b.mesh == bar.mesh && b.technique == bar.technique).max_by(|a, b| a.share.total_cmp(&b.share)).unwrap();
        let scale = *pixels_per_share.entry((bar.mesh.clone(), bar.technique.clone())).or_insert(tallest.height / tallest.share);
        assert!(scale > 100.0, "the tallest bar is drawn ({} px for {})", tallest.height, tallest.share);
        assert!((bar.height - share * scale).abs() < 0.01, "row {r}: {} px for share {share} at {scale} px per share", bar.height);
    }
    // A vertex histogram counts every surfel of its object once.
    for ((mesh, technique, weighting), total) in &totals {
        if weighting == "vertex" {
            let row = errors.rows.iter().find(|row| errors.text(row, "mesh") == mesh).unwrap();
            assert_eq!(*total, errors.text(row, "surfels").parse::<u64>().unwrap(), "{mesh} {technique}");
        }
    }
}

/// Where the data mislead, the material page says so above the values, with the numbers
/// behind it: water's red absorption depth is λ/(4πk) at 685 nm, computed here from
/// `materials.csv`'s k (2.035 m on this snapshot), and PVP's largest k over 390–700 nm is
/// under 0.01 although its depths make it opaque. A page without a caveat shows none.
#[test]
fn material_pages_show_the_caveats_of_pages_whose_data_mislead() {
    let out = scratch("caveats");
    let pages = ["3d/liquids/water", "3d/plastics/pvp", "3d/metals/gold"];
    stages(&out, &pages, &[]);
    let selection: Vec<&str> = pages.iter().flat_map(|p| ["--page", p]).collect();
    for stage in ["params", "report"] {
        let output = nklut(&out, &[&[stage], selection.as_slice()].concat());
        assert!(output.status.success(), "nklut {stage}: {}", String::from_utf8_lossy(&output.stderr));
    }
    let materials = CsvTable::load(&out.join("materials.csv")).unwrap().expect("materials.csv");
    let water = materials.rows.iter().find(|r| materials.text(r, "page") == "3d/liquids/water").unwrap();
    let k_red = materials.number(water, "k_red").unwrap();
    let depth_m = 685e-9 / (4.0 * std::f64::consts::PI * k_red);
    let water_html = material_html(&out, "3d/liquids/water");
    assert!(
        water_html.contains("<p class=\"note caveat\">Caveat: transparent_absorbs:")
            && water_html.contains(&format!("red depth {depth_m:.3} m")),
        "water's caveat with its red depth {depth_m:.3} m"
    );
    let pvp_html = material_html(&out, "3d/plastics/pvp");
    assert!(
        pvp_html.contains("<p class=\"note caveat\">Caveat: opaque_low_k:") && pvp_html.contains("k &lt; 0.01 everywhere"),
        "PVP's caveat"
    );
    assert!(!material_html(&out, "3d/metals/gold").contains("Caveat:"), "gold's data do not mislead");
}

/// A device result for the specular scene of [`effects_report`]: `gpu_timing.csv` (copied
/// from the committed lavapipe folder) and `effects_timing.csv` with one row per
/// configuration of `effects_errors.csv` (method, depths, steps, map size, layers) whose
/// shading time is `1 + the row's place` ms (distinct, hand-set), and a row of a map size
/// the scene does not have.
fn write_test_device(out: &Path, name: &str, errors: &CsvTable, map_size: Option<&str>) -> BTreeMap<Vec<String>, f64> {
    let folder = out.join("devices").join(name);
    fs::create_dir_all(&folder).unwrap();
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices/lavapipe-llvmpipe-llvm-15.0.6-vulkan/gpu_timing.csv");
    fs::copy(committed, folder.join("gpu_timing.csv")).unwrap();
    let mut csv = String::from("adapter,backend,timer,method,effect,reflection_depth,refraction_depth,linear_steps,secant_steps,map_size,layers,cube_maps,resolution,repeats,map_update_ms,shading_ms,shading_spread_ms,frame_ms\n");
    let mut times = BTreeMap::new();
    for row in &errors.rows {
        let configuration: Vec<String> =
            ["method", "reflection_depth", "refraction_depth", "linear_steps", "secant_steps", "map_size", "layers"]
                .iter()
                .map(|c| errors.text(row, c).to_string())
                .collect();
        if times.contains_key(&configuration) {
            continue;
        }
        let ms = 1.0 + times.len() as f64;
        let c = &configuration;
        let size = map_size.unwrap_or(&c[5]);
        csv.push_str(&format!(
            "test GPU,Vulkan,timestamp,{},reflection,{},{},{},{},{size},{},2,64x64,5,2.0,{ms},0.1,{}\n",
            c[0],
            c[1],
            c[2],
            c[3],
            c[4],
            c[6],
            ms + 2.0
        ));
        times.insert(configuration, ms);
    }
    fs::write(folder.join("effects_timing.csv"), csv).unwrap();
    times
}

/// The figures of a finding as the page carries them: `data-key` → `data-value`.
fn finding_figures(html: &str, id: &str) -> BTreeMap<String, f64> {
    let start = html.find(&format!("id=\"finding-{id}\"")).unwrap_or_else(|| panic!("no finding {id}"));
    let item = &html[start..start + html[start..].find("</p>").unwrap()];
    item.split("data-key=\"")
        .skip(1)
        .map(|rest| {
            let key = &rest[..rest.find('"').unwrap()];
            let value = rest.split("data-value=\"").nth(1).unwrap();
            (unescape(key), value[..value.find('"').unwrap()].parse().unwrap())
        })
        .collect()
}

/// The effects page answers in the reader's order: the specular scene before the AO scene
/// (whose name sorts first), each opening with its finding, whose figures are recomputed
/// here from the CSVs; the total error against time is drawn against the GPU time of each
/// device that timed the scene's configurations — one chart per device, every point's time
/// the device's row and its error the pixel-weighted mean of its rows — and the CPU twin's
/// chart is gone (it is only a fallback); a device that timed other maps gets no chart.
/// Points are coloured by method (2 colours) and shaped by depth (4 shapes).
#[test]
fn effects_scenes_come_in_the_readers_order_and_time_on_each_device() {
    let out = effects_report("effects-order");
    let errors = CsvTable::load(&out.join("specular/effects_errors.csv")).unwrap().unwrap();
    let times = write_test_device(&out, "test-gpu", &errors, None);
    write_test_device(&out, "other-maps", &errors, Some("512"));
    let output = nklut(&out, &["report"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let html = fs::read_to_string(out.join("report/effects.html")).unwrap();
    check_well_formed(&html);
    assert!(html.contains("<meta name=\"viewport\""));
    let at = |needle: &str| html.find(needle).unwrap_or_else(|| panic!("{needle}"));
    assert!(at("<h2 id=\"scene-specular\">") < at("<h2 id=\"scene-ao\">"), "specular effects first");
    // Each scene opens with its finding, right under its heading.
    for (scene, id) in [("specular", "search-specular"), ("ao", "ao-ao")] {
        let heading = format!("<h2 id=\"scene-{scene}\">scene {scene}</h2>\n<p class=\"finding\" id=\"finding-{id}\">");
        assert!(html.contains(&heading), "{heading}");
    }
    // The search finding, recomputed.
    let figures = finding_figures(&html, "search-specular");
    let column = |name: &str, skip_exact: bool| -> Vec<f64> {
        errors.rows.iter().filter(|r| !skip_exact || errors.text(r, "method") != "exact").map(|r| errors.number(r, name).unwrap()).collect()
    };
    let max = |v: Vec<f64>| v.into_iter().fold(f64::NAN, f64::max);
    assert_eq!(figures["search:specular:fresnel-max"], max(column("fresnel_mean_delta_e2000", true)));
    assert_eq!(figures["search:specular:geometry-max"], max(column("geometry_mean_delta_e2000", false)));
    // The AO finding, recomputed: the surfel-weighted mean error per (technique, passes),
    // the smallest; its CPU time; GTAO's pixel-weighted per-pixel error beside the surfels'.
    let ao = CsvTable::load(&out.join("ao/ao_errors.csv")).unwrap().unwrap();
    let weighted = |rows: &[&Vec<String>], column: &str, weight: &str| {
        let sum: f64 = rows.iter().map(|r| ao.number(r, column).unwrap() * ao.number(r, weight).unwrap()).sum();
        sum / rows.iter().map(|r| ao.number(r, weight).unwrap()).sum::<f64>()
    };
    let mut groups: BTreeMap<(String, String), Vec<&Vec<String>>> = BTreeMap::new();
    for row in ao.rows.iter().filter(|r| ao.text(r, "technique") != "gtao") {
        groups.entry((ao.text(row, "hierarchy").to_string(), ao.text(row, "passes").to_string())).or_default().push(row);
    }
    let (best, rows) =
        groups.iter().min_by(|a, b| weighted(a.1, "mean_error", "surfels").total_cmp(&weighted(b.1, "mean_error", "surfels"))).unwrap();
    let figures = finding_figures(&html, "ao-ao");
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-12);
    assert!(close(figures["ao:ao:best"], weighted(rows, "mean_error", "surfels")), "{best:?}: {figures:?}");
    let cpu: Vec<f64> = rows.iter().map(|r| ao.number(r, "cpu_ms").unwrap()).collect();
    assert!(close(figures["ao:ao:best-cpu-ms"], cpu.iter().sum::<f64>() / cpu.len() as f64));
    let gtao: Vec<&Vec<String>> = ao.rows.iter().filter(|r| ao.text(r, "technique") == "gtao").collect();
    assert!(close(figures["ao:ao:gtao-pixel"], weighted(&gtao, "pixel_mean_error", "pixels")));
    assert!(close(figures["ao:ao:surfel-pixel"], weighted(rows, "pixel_mean_error", "pixels")));
    let text = &html[at("id=\"finding-ao-ao\"")..];
    let technique = if best.0 == "true" { "tree" } else { "brute force" };
    assert!(text.starts_with(&format!(
        "id=\"finding-ao-ao\">In ao, surfel ambient occlusion is closest to the ray-traced reference with the {technique} and {} pass(es)",
        best.1
    )));

    // The error-against-time charts of the specular scene: one per matching device.
    let section = &html[at("<h2 id=\"scene-specular\">")..at("<h2 id=\"scene-ao\">")];
    let charts: Vec<&str> = section.split("<svg class=\"chart cost\"").skip(1).map(|c| &c[..c.find("</svg>").unwrap()]).collect();
    assert_eq!(charts.len(), 1, "one device timed these configurations");
    assert!(!section.contains("effects_cpu_timing.csv\" data-x-column"), "no CPU-twin chart where a device timed the scene");
    assert!(section.contains("GPU time of the shading pass on test gpu (ms), log scale"), "the time axis names the device");
    let chart_marks = marks(charts[0]);
    assert_eq!(chart_marks.len(), times.len(), "a point per configuration");
    for mark in &chart_marks {
        let x = mark.axis("x").unwrap();
        assert_eq!((x.table.as_str(), x.column.as_str()), ("devices/test-gpu/effects_timing.csv", "shading_ms"));
        let y = mark.axis("y").unwrap();
        let configuration: Vec<String> =
            ["method", "reflection_depth", "refraction_depth", "linear_steps", "secant_steps", "map_size", "layers"]
                .iter()
                .map(|c| errors.text(&errors.rows[y.rows[0]], c).to_string())
                .collect();
        assert_eq!(x.value, times[&configuration], "{}", mark.label);
        let rows: Vec<usize> = (0..errors.rows.len())
            .filter(|&r| {
                ["method", "reflection_depth", "refraction_depth", "linear_steps", "secant_steps"]
                    .iter()
                    .enumerate()
                    .all(|(i, c)| errors.text(&errors.rows[r], c) == configuration[i])
            })
            .collect();
        assert_eq!(y.rows, rows, "{}", mark.label);
        let pixels: f64 = rows.iter().map(|&r| errors.number(&errors.rows[r], "pixels").unwrap()).sum();
        let mean: f64 = rows
            .iter()
            .map(|&r| errors.number(&errors.rows[r], "total_mean_delta_e2000").unwrap() * errors.number(&errors.rows[r], "pixels").unwrap())
            .sum::<f64>()
            / pixels;
        assert!(close(y.value, mean), "{}: {} against {mean}", mark.label, y.value);
        assert!(mark.label.contains('\n') && mark.label.contains("GPU time of the shading pass"), "hover shows the values: {}", mark.label);
    }
    // Colour by method, shape by depth: 2 fills, 4 marker forms.
    let markers: Vec<&str> = charts[0].split("class=\"marker\"").skip(1).collect();
    assert_eq!(markers.len(), times.len());
    let fills: std::collections::BTreeSet<&str> =
        markers.iter().map(|m| m.split("fill=\"").nth(1).unwrap().split('"').next().unwrap()).collect();
    assert_eq!(fills.len(), 2, "{fills:?}");
    let forms: std::collections::BTreeSet<String> = charts[0]
        .split('<')
        .filter(|e| e.contains("class=\"marker\""))
        .map(|e| {
            let tag = e.split_whitespace().next().unwrap().to_string();
            let points: Vec<(f64, f64)> = e.split("points=\"").nth(1).map_or(Vec::new(), |p| {
                p.split('"')
                    .next()
                    .unwrap()
                    .split(' ')
                    .map(|xy| {
                        let (x, y) = xy.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect()
            });
            // A polygon's form: its vertices relative to the first, rounded.
            let form: Vec<String> = points.iter().map(|(x, y)| format!("{:.0},{:.0}", x - points[0].0, y - points[0].1)).collect();
            format!("{tag} {}", form.join(" "))
        })
        .collect();
    assert_eq!(forms.len(), 4, "one form per depth: {forms:?}");
    assert!(section.contains("Pareto front (joined and labelled): "), "the front named");
}

/// Reads every chart of a page: its texts' boxes (relative to the chart) and sizes, the
/// texts that leave the chart (clipped) or overlap another, its scales and plotting area,
/// its points' values, its curves and bars; and every legend's entries with their drawn
/// style.
const CRAFT_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const out={charts:[],legends:[]};
for(const svg of document.querySelectorAll('svg')){const sb=svg.getBoundingClientRect();if(sb.width<100||sb.height<60)continue;
const c={classes:svg.getAttribute('class')||'',xlog:svg.dataset.xScale==='log',ylog:svg.dataset.yScale==='log',plot:(svg.dataset.plot||'').split(' ').filter(s=>s).map(Number),texts:[],clipped:[],overlaps:[],marks:[],curves:svg.querySelectorAll('polyline[stroke-width="2"]').length,bars:[]};
const boxes=[];for(const t of svg.querySelectorAll('text')){const s=t.textContent.trim();if(!s)continue;const r=t.getBoundingClientRect();
c.texts.push({text:s,left:r.left-sb.left,right:r.right-sb.left,top:r.top-sb.top,bottom:r.bottom-sb.top,size:parseFloat(getComputedStyle(t).fontSize)});
if(r.left<sb.left-0.5||r.right>sb.right+0.5||r.top<sb.top-0.5||r.bottom>sb.bottom+0.5)c.clipped.push(s);boxes.push([s,r.left,r.right,r.top,r.bottom]);}
for(let i=0;i<boxes.length;i++)for(let j=i+1;j<boxes.length;j++){const a=boxes[i],b=boxes[j];if(a[1]<b[2]-0.5&&b[1]<a[2]-0.5&&a[3]<b[4]-0.5&&b[3]<a[4]-0.5)c.overlaps.push([a[0],b[0]]);}
for(const m of svg.querySelectorAll('circle.trace'))c.marks.push(m.dataset.y===undefined?null:parseFloat(m.dataset.y));
for(const b of svg.querySelectorAll('rect.bar'))c.bars.push(parseFloat(b.dataset.share));out.charts.push(c);}
for(const ul of document.querySelectorAll('ul.legend')){const entries=[];for(const li of ul.querySelectorAll('li')){const s=li.querySelector('svg');if(!s)continue;const e=s.firstElementChild;
entries.push({name:li.textContent.trim(),style:[e.tagName,e.getAttribute('points')||e.getAttribute('d')||'',e.getAttribute('stroke')||'',e.getAttribute('fill')||'',e.getAttribute('stroke-dasharray')||''].join('|')});}out.legends.push(entries);}
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

#[derive(serde::Deserialize, Debug)]
struct Craft {
    charts: Vec<CraftChart>,
    legends: Vec<Vec<LegendEntry>>,
}

#[derive(serde::Deserialize, Debug)]
struct CraftChart {
    classes: String,
    xlog: bool,
    ylog: bool,
    plot: Vec<f64>,
    texts: Vec<CraftText>,
    clipped: Vec<String>,
    overlaps: Vec<(String, String)>,
    marks: Vec<Option<f64>>,
    curves: usize,
    bars: Vec<f64>,
}

#[derive(serde::Deserialize, Debug)]
struct CraftText {
    text: String,
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
    size: f64,
}

#[derive(serde::Deserialize, Debug)]
struct LegendEntry {
    name: String,
    style: String,
}

/// Whether a tick label reads as a number (`0.05`, `2 %`).
fn numeric(text: &str) -> bool {
    text.trim_end_matches(" %").parse::<f64>().is_ok()
}

/// What is wrong with the charts of one page, in words (nothing: well made). Counts of log
/// charts and of charts over unordered depths go to `seen`.
fn chart_craft_problems(page: &str, craft: &Craft, seen: &mut BTreeMap<&'static str, usize>) -> Vec<String> {
    let mut problems = Vec::new();
    for (i, chart) in craft.charts.iter().enumerate() {
        let name = format!("{page} chart {i} ({})", chart.texts.iter().map(|t| t.text.as_str()).take(3).collect::<Vec<_>>().join(" / "));
        for t in chart.texts.iter().filter(|t| t.size < 12.0) {
            problems.push(format!("{name}: text {:?} at {} px", t.text, t.size));
        }
        if !chart.clipped.is_empty() {
            problems.push(format!("{name}: clipped text {:?}", chart.clipped));
        }
        if !chart.overlaps.is_empty() {
            problems.push(format!("{name}: overlapping text {:?}", chart.overlaps));
        }
        // Log axes say so and carry three labelled ticks or more (numbers below the
        // plotting area for x, left of it for y).
        if chart.xlog || chart.ylog {
            *seen.entry("log charts").or_default() += 1;
            let [left, top, right, bottom] = chart.plot[..] else {
                problems.push(format!("{name}: a log chart without its plotting area"));
                continue;
            };
            let named = chart.texts.iter().filter(|t| t.text.contains("log scale")).count();
            let wanted = usize::from(chart.xlog) + usize::from(chart.ylog);
            if named < wanted {
                problems.push(format!("{name}: {named} axis names say \"log scale\", {wanted} axes are log"));
            }
            let x_ticks = chart
                .texts
                .iter()
                .filter(|t| numeric(&t.text) && t.top >= bottom - 1.0 && t.left >= left - 40.0 && t.right <= right + 40.0)
                .count();
            let y_ticks = chart
                .texts
                .iter()
                .filter(|t| {
                    numeric(&t.text)
                        && t.right <= left + 1.0
                        && (t.top + t.bottom) / 2.0 >= top - 1.0
                        && (t.top + t.bottom) / 2.0 <= bottom + 1.0
                })
                .count();
            if chart.xlog && x_ticks < 3 {
                problems.push(format!("{name}: {x_ticks} x tick labels on a log axis"));
            }
            if chart.ylog && y_ticks < 3 {
                problems.push(format!("{name}: {y_ticks} y tick labels on a log axis"));
            }
        }
        // No chart of one point or of zeros only.
        let values: Vec<f64> = chart.marks.iter().flatten().copied().filter(|v| v.is_finite()).collect();
        if !chart.marks.is_empty() && chart.marks.len() < 2 {
            problems.push(format!("{name}: a single point"));
        }
        if !values.is_empty() && values.iter().all(|v| *v == 0.0) {
            problems.push(format!("{name}: every point is 0"));
        }
        if !chart.bars.is_empty() && (chart.bars.len() < 2 || chart.bars.iter().all(|b| *b == 0.0)) {
            problems.push(format!("{name}: bars {:?}", chart.bars));
        }
        // No line across depth categories that are not ordered (1+2 beside 2+1).
        let mut depths: Vec<(f64, (u32, u32))> = chart
            .texts
            .iter()
            .filter_map(|t| {
                let (r, x) = t.text.split_once('+')?;
                Some((t.left, (r.parse().ok()?, x.parse().ok()?)))
            })
            .collect();
        depths.sort_by(|a, b| a.0.total_cmp(&b.0));
        let ordered = depths.windows(2).all(|w| w[0].1 .0 <= w[1].1 .0 && w[0].1 .1 <= w[1].1 .1);
        if depths.len() >= 2 && !ordered {
            *seen.entry("unordered depth charts").or_default() += 1;
            if chart.curves > 0 {
                problems.push(format!(
                    "{name}: {} lines join unordered depths {:?}",
                    chart.curves,
                    depths.iter().map(|d| d.1).collect::<Vec<_>>()
                ));
            }
        }
        if chart.classes.contains("chart") {
            *seen.entry("tagged charts").or_default() += 1;
        }
    }
    // Every legend entry drawn in its own style.
    for legend in &craft.legends {
        for (i, a) in legend.iter().enumerate() {
            for b in &legend[i + 1..] {
                if a.style == b.style {
                    problems.push(format!("{page}: legend entries {:?} and {:?} share a style", a.name, b.name));
                }
            }
        }
    }
    problems
}

/// Reads the page's layout: the window's width, the page's scroll width, the elements
/// wider than the window outside a box that scrolls sideways, and text under 12 px; what a
/// closed `<details>` holds (its summary aside) is not on screen and not read (Chromium
/// lays it out all the same).
const LAYOUT_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const W=document.documentElement.clientWidth;const out={width:W,scroll:document.documentElement.scrollWidth,wide:[],small:[],scrolled:[]};
const boxed=e=>{for(let p=e.parentElement;p&&p!==document.body;p=p.parentElement){const o=getComputedStyle(p).overflowX;if(o==='auto'||o==='scroll')return true;}return false;};
for(const e of document.body.querySelectorAll('*')){if(e.closest('#nk-audit')||e.parentElement&&e.parentElement.closest('details:not([open])')&&!e.closest('summary'))continue;const r=e.getBoundingClientRect();if(r.width>0&&r.right>W+0.5&&!boxed(e)&&out.wide.length<20)out.wide.push(e.tagName.toLowerCase()+'.'+(e.getAttribute('class')||'')+' right '+Math.round(r.right));
if(r.width>0&&(r.right>W+0.5||e.scrollWidth>e.clientWidth+1&&['auto','scroll'].includes(getComputedStyle(e).overflowX))&&out.scrolled.length<20)out.scrolled.push(e.tagName.toLowerCase()+'.'+(e.getAttribute('class')||'')+' right '+Math.round(r.right)+' content '+e.scrollWidth);
const own=[...e.childNodes].some(n=>n.nodeType===3&&n.textContent.trim());if(own&&r.width>0){const f=parseFloat(getComputedStyle(e).fontSize);if(f<12&&out.small.length<20)out.small.push(e.tagName.toLowerCase()+' '+f+' '+e.textContent.trim().slice(0,40));}}
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

#[derive(serde::Deserialize, Debug)]
struct Layout {
    width: f64,
    scroll: f64,
    wide: Vec<String>,
    small: Vec<String>,
    /// Elements past the window's right edge or scrolling inside their own box, boxed or
    /// not: none at 1000 px and more.
    scrolled: Vec<String>,
}

/// The layout audit of `html` rendered `width` px wide: the page (with [`LAYOUT_SCRIPT`])
/// in an iframe of that width — headless Chromium keeps its window at 500 px or more, an
/// iframe is the width a phone gives — whose audit the framing page copies out.
fn layout_json(html: &Path, profile: &Path, width: u32) -> String {
    let name = html.file_name().unwrap().to_string_lossy().into_owned();
    let audited = html.with_file_name(format!("audit-{name}"));
    fs::write(&audited, fs::read_to_string(html).unwrap().replace("</body>", &format!("{LAYOUT_SCRIPT}</body>"))).unwrap();
    let frame = html.with_file_name(format!("frame-{name}"));
    fs::write(
        &frame,
        format!(
            "<!DOCTYPE html><html><body style=\"margin:0\"><iframe id=\"f\" src=\"audit-{name}\" width=\"{width}\" height=\"900\" style=\"border:0;display:block\"></iframe><script>\
const f=document.getElementById('f');f.addEventListener('load',()=>{{const tick=()=>{{const d=f.contentDocument;const p=d&&d.getElementById('nk-audit');\
if(p){{const q=document.createElement('pre');q.id='nk-audit';q.textContent=p.textContent;document.body.appendChild(q);}}else setTimeout(tick,50);}};tick();}});</script></body></html>"
        ),
    )
    .unwrap();
    let dom = chromium(&[
        format!("--user-data-dir={}", profile.display()),
        "--allow-file-access-from-files".into(),
        format!("--window-size={},900", width.max(500) + 40),
        "--dump-dom".into(),
        format!("file://{}", frame.display()),
    ]);
    assert!(dom.status.success(), "{}", String::from_utf8_lossy(&dom.stderr));
    let dom = String::from_utf8_lossy(&dom.stdout);
    let start = dom.find("<pre id=\"nk-audit\">").unwrap_or_else(|| panic!("the layout audit of {name} at {width} px ran"))
        + "<pre id=\"nk-audit\">".len();
    unescape(&dom[start..start + dom[start..].find("</pre>").unwrap()])
}

/// Forces every picture to load, then reads each `<img>`'s natural width and every link.
const PICTURES_SCRIPT: &str = r#"<script>window.addEventListener('load',async()=>{const imgs=[...document.images];for(const i of imgs)i.loading='eager';
await Promise.all(imgs.map(i=>i.complete&&i.naturalWidth>0?null:new Promise(r=>{i.addEventListener('load',r);i.addEventListener('error',r);setTimeout(r,4000);})));
const out={images:imgs.map(i=>({src:i.getAttribute('src').slice(0,80),width:i.naturalWidth})),links:[...document.querySelectorAll('a[href]')].map(a=>a.getAttribute('href'))};
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

#[derive(serde::Deserialize, Debug)]
struct Pictures {
    images: Vec<PictureSeen>,
    links: Vec<String>,
}

#[derive(serde::Deserialize, Debug)]
struct PictureSeen {
    src: String,
    width: u32,
}

/// `from` copied to `to` with every link resolved (the report's folder is a link into
/// `.sets/`; a copy must hold files).
fn copy_resolved(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap().flatten() {
        let path = entry.path();
        let target = to.join(entry.file_name());
        if fs::metadata(&path).unwrap().is_dir() {
            copy_resolved(&path, &target);
        } else {
            fs::copy(&path, &target).unwrap();
        }
    }
}

/// The HTML files under `dir`, relative to it, sorted.
fn html_files(dir: &Path, under: &Path, out: &mut Vec<String>) {
    for entry in fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if fs::metadata(&path).unwrap().is_dir() {
            html_files(&path, under, out);
        } else if path.extension().is_some_and(|x| x == "html")
            && !["audit-", "frame-", "shot-"].iter().any(|p| entry.file_name().to_string_lossy().starts_with(p))
        {
            out.push(path.strip_prefix(under).unwrap().display().to_string());
        }
    }
    out.sort();
}

/// The 3d shelf's report as `make report` leaves it: the stages over the shelf, the two
/// effects scenes of [`effects_report`] (one folder each), the committed device results in
/// `devices/`, the recommendations with them, then the report.
#[test]
fn the_3d_shelf_report_is_well_made_self_contained_and_reads_on_a_phone() {
    let out = scratch("shelf-report");
    for stage in ["ingest", "colors", "params", "validate"] {
        let output = nklut(&out, &[stage, "--shelf", "3d"]);
        assert!(output.status.success(), "{stage}: {}", String::from_utf8_lossy(&output.stderr));
    }
    for (scene, text, extra) in [("specular", SPECULAR_SCENE, &[][..]), ("ao", AO_SCENE, &["--ao-rays", "16"][..])] {
        let file = out.join(format!("{scene}.yaml"));
        fs::write(&file, text).unwrap();
        let file = file.display().to_string();
        let output = nklut(&out.join(scene), &[&["effects", "--hero-size", "512"], extra, &[file.as_str()]].concat());
        assert!(output.status.success(), "effects {scene}: {}", String::from_utf8_lossy(&output.stderr));
    }
    copy_resolved(&Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices"), &out.join("devices"));
    for stage in ["recommend", "report"] {
        let output = nklut(&out, &[stage, "--shelf", "3d"]);
        assert!(output.status.success(), "{stage}: {}", String::from_utf8_lossy(&output.stderr));
    }
    let report = out.join("report");
    let mut pages = Vec::new();
    html_files(&report, &report, &mut pages);
    assert!(pages.len() >= 40, "index, effects and the shelf's material pages: {pages:?}");
    let profile = out.join("chromium-profile");

    // Chart craft, every chart of every page.
    let mut problems = Vec::new();
    let mut seen = BTreeMap::new();
    let mut charts = 0;
    for page in &pages {
        let json = audit_json(&report.join(page), &profile, CRAFT_SCRIPT, 1400);
        let craft: Craft = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{page}: {e}: {json}"));
        charts += craft.charts.len();
        problems.extend(chart_craft_problems(page, &craft, &mut seen));
    }
    println!("{charts} charts on {} pages: {seen:?}", pages.len());
    // Two per material page (F(θ) per channel, ΔE2000 over θ), the index's two cost charts,
    // the effects page's; among them log charts and charts over the specular scene's
    // unordered depths (1+1 … 2+2).
    if charts < 2 * (pages.len() - 2) + 10 || seen.get("log charts").copied().unwrap_or(0) < 3 {
        problems.push(format!("{charts} charts: fewer than the pages hold ({seen:?})"));
    }
    if seen.get("unordered depth charts").copied().unwrap_or(0) < 2 {
        problems.push(format!("the specular scene's depths 1+1 … 2+2 are not drawn: {seen:?}"));
    }

    // Layout at 1400, 1000 and 390 px: no sideways scroll, nothing wider than the window
    // outside a box that scrolls (at 1000 px and more nothing wider at all, and no box that
    // scrolls), text ≥ 12 px.
    for page in ["index.html", "effects.html", "materials/3d/metals/gold.html", "materials/3d/glass/BK7.html"] {
        assert!(pages.iter().any(|p| p == page), "{page}");
        let html = fs::read_to_string(report.join(page)).unwrap();
        if !html.contains("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">") {
            problems.push(format!("{page}: no viewport meta tag"));
        }
        for width in [1400, 1000, 390] {
            let json = layout_json(&report.join(page), &profile, width);
            let layout: Layout = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{page}: {e}: {json}"));
            assert!((layout.width - f64::from(width)).abs() <= 20.0, "{page} at {width}: the window is {} px", layout.width);
            if layout.scroll > layout.width {
                problems.push(format!("{page} at {width} px: scrolls sideways ({} > {})", layout.scroll, layout.width));
            }
            if !layout.wide.is_empty() {
                problems.push(format!("{page} at {width} px: wider than the window: {:?}", layout.wide));
            }
            if !layout.small.is_empty() {
                problems.push(format!("{page} at {width} px: text under 12 px: {:?}", layout.small));
            }
            if width >= 1000 && !layout.scrolled.is_empty() {
                problems.push(format!("{page} at {width} px: wider than the window, in a box or not: {:?}", layout.scrolled));
            }
        }
    }

    // `report/` alone, copied elsewhere with its links resolved, shows every picture: each
    // <img> loads (natural width > 0), each link to a picture is a file inside the copy.
    let copy = out.join("elsewhere/report");
    copy_resolved(&report, &copy);
    let mut images = 0;
    for page in ["index.html", "effects.html", "materials/3d/metals/gold.html"] {
        let json = audit_json(&copy.join(page), &profile, PICTURES_SCRIPT, 1400);
        let seen: Pictures = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{page}: {e}: {json}"));
        for image in &seen.images {
            images += 1;
            if image.width == 0 {
                problems.push(format!("copied {page}: picture {} does not load", image.src));
            }
        }
        let folder = copy.join(page).parent().unwrap().to_path_buf();
        for link in seen.links.iter().filter(|l| [".png", ".jpg", ".exr"].iter().any(|x| l.ends_with(x))) {
            let target = folder.join(link);
            let inside = target.canonicalize().map(|t| t.starts_with(copy.canonicalize().unwrap())).unwrap_or(false);
            if !inside {
                problems.push(format!("copied {page}: link {link} is not a file inside the copy"));
            }
        }
    }
    if images < 20 {
        problems.push(format!("{images} pictures: fewer than the hero frames, error images, crops and the colour bar"));
    }
    assert!(problems.is_empty(), "{} problems:\n{}", problems.len(), problems.join("\n"));
}

/// A device's `ao_timing` rows of the AO scene give one error-against-GPU-time chart with
/// both techniques on it: the surfels (brute force and tree, 1–3 passes: each its own
/// point) and the scene's GTAO configuration, timed at two frame sizes (the smaller
/// counts) — a row of another scene and a GTAO row of other steps count nowhere. Each
/// point's x is its timing row's median, its y the pixel-weighted per-pixel error of its
/// rows of `ao_errors.csv`, recomputed here; the table beside it gives GTAO's time to
/// convergence.
#[test]
fn ao_error_against_gpu_time_has_both_techniques_per_device() {
    let out = effects_report("ao-cost");
    let ao = CsvTable::load(&out.join("ao/ao_errors.csv")).unwrap().unwrap();
    let folder = out.join("devices").join("test-ao");
    fs::create_dir_all(&folder).unwrap();
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices/lavapipe-llvmpipe-llvm-15.0.6-vulkan/gpu_timing.csv");
    fs::copy(committed, folder.join("gpu_timing.csv")).unwrap();
    let mut csv = String::from("adapter,driver,mesh,surfels,emitters,tree_nodes,passes,dispatches,width,height,covered_pixels,slices,steps,preset,radius,frames,timer,repeats,median_ms,spread_ms,convergence_ms,fitted_exponent\n");
    let mut expected: Vec<(String, f64)> = Vec::new();
    for (i, (emitters, passes)) in
        [("brute_force", 1), ("brute_force", 2), ("brute_force", 3), ("hierarchy", 1), ("hierarchy", 2), ("hierarchy", 3)]
            .into_iter()
            .enumerate()
    {
        let ms = 10.0 * (i + 1) as f64;
        csv.push_str(&format!("test,t,ao,0,{emitters},0,{passes},1,0,0,0,0,0,,,0,timestamp,3,{ms},0.1,,\n"));
        expected.push((format!("{emitters} {passes}"), ms));
    }
    csv.push_str("test,t,ao,0,gtao,0,1,1,256,256,900,2,4,bare,0.5,1,timestamp,3,3.5,0.1,3.5,\n");
    csv.push_str("test,t,ao,0,gtao,0,1,1,1024,1024,9000,2,4,bare,0.5,1,timestamp,3,50,0.1,50,\n");
    csv.push_str("test,t,ao,0,gtao,0,1,1,256,256,900,2,5,bare,0.5,1,timestamp,3,4,0.1,4,\n");
    csv.push_str("test,t,other,0,gtao,0,1,1,64,64,900,2,4,bare,0.5,1,timestamp,3,0.5,0.1,0.5,\n");
    expected.push(("gtao".into(), 3.5));
    fs::write(folder.join("ao_timing.csv"), csv).unwrap();
    let output = nklut(&out, &["report"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let html = fs::read_to_string(out.join("report/effects.html")).unwrap();
    check_well_formed(&html);
    let section = &html[html.find("<h4>Error against GPU time on test ao</h4>").expect("the device's AO chart")..];
    let section = &section[..section.find("</table>").unwrap()];
    let chart_marks = marks(section);
    assert_eq!(chart_marks.len(), expected.len(), "a point per timed configuration");
    let timing = CsvTable::load(&folder.join("ao_timing.csv")).unwrap().unwrap();
    for mark in &chart_marks {
        let x = mark.axis("x").unwrap();
        assert_eq!((x.table.as_str(), x.column.as_str()), ("devices/test-ao/ao_timing.csv", "median_ms"));
        assert_eq!(x.rows.len(), 1, "{}", mark.label);
        let row = &timing.rows[x.rows[0]];
        let key = if timing.text(row, "emitters") == "gtao" {
            "gtao".to_string()
        } else {
            format!("{} {}", timing.text(row, "emitters"), timing.text(row, "passes"))
        };
        let ms = expected.iter().find(|(k, _)| *k == key).unwrap_or_else(|| panic!("{key} is not a configuration")).1;
        assert_eq!(x.value, ms, "{}", mark.label);
        let y = mark.axis("y").unwrap();
        assert_eq!((y.table.as_str(), y.column.as_str()), ("ao/ao_errors.csv", "pixel_mean_error"));
        let rows: Vec<usize> = (0..ao.rows.len())
            .filter(|&r| {
                let row = &ao.rows[r];
                if key == "gtao" {
                    ao.text(row, "technique") == "gtao"
                } else {
                    let emitters = if ao.text(row, "hierarchy") == "true" { "hierarchy" } else { "brute_force" };
                    ao.text(row, "technique") != "gtao" && format!("{emitters} {}", ao.text(row, "passes")) == key
                }
            })
            .collect();
        assert_eq!(y.rows, rows, "{}", mark.label);
        let weight: f64 = rows.iter().map(|&r| ao.number(&ao.rows[r], "pixels").unwrap()).sum();
        let mean = rows
            .iter()
            .map(|&r| ao.number(&ao.rows[r], "pixel_mean_error").unwrap() * ao.number(&ao.rows[r], "pixels").unwrap())
            .sum::<f64>()
            / weight;
        assert!((y.value - mean).abs() <= 1e-12 * mean.abs().max(1e-12), "{}: {} against {mean}", mark.label, y.value);
    }
    // Two techniques, two colours (every marker's stroke: a cross has no fill); GTAO's row
    // in the table with its frame and convergence.
    let colours: std::collections::BTreeSet<&str> =
        section.split("class=\"marker\"").skip(1).map(|m| m.split("stroke=\"").nth(1).unwrap().split('"').next().unwrap()).collect();
    assert_eq!(colours.len(), 2, "{colours:?}");
    assert!(section.contains("<td>GTAO bare r 0.5, 2×4</td><td>256×256</td><td>3.50</td><td>3.50</td>"), "{section}");
}
