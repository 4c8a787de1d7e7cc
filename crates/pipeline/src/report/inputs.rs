//! The tables the report is built from, read from an output folder: which exist, the
//! channel wavelengths they were computed at, the pages a selection picks from them,
//! and the counts the report prints (each from the one table it belongs to).

use nklut_tables::gpu_tables::{gpu_timing, image_errors};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::SystemTime;

use anyhow::{bail, Result};

use super::csvdata::{CsvTable, MAX_TABLE_BYTES};
use crate::ingest::Selection;
use nklut_optics::fresnel::FitMemo;
use nklut_optics::spectrum::{Channels, CHANNEL_NAMES};
use nklut_tables::effects_tables::{
    ao_errors, ao_histogram, ao_timing, effects_cpu_timing, effects_errors, effects_hero, effects_timing, spectral_errors,
};
use nklut_tables::memo_file::MemoFile;

/// Tables written by the effects, ambient-occlusion, engine-parameter and recommend stages: shown
/// when present, named as absent otherwise.
pub const OPTIONAL_TABLES: [&str; 11] = [
    effects_errors::CSV,
    effects_cpu_timing::CSV,
    effects_hero::CSV,
    effects_timing::CSV,
    ao_errors::CSV,
    ao_timing::CSV,
    ao_histogram::CSV,
    spectral_errors::CSV,
    "engine_params.csv",
    "recommendations.csv",
    "method_errors.csv",
];

/// The stages' tables the index draws from and the command that writes each.
pub const STAGE_TABLES: [(&str, &str); 6] = [
    ("materials.csv", "nklut ingest"),
    ("excluded.csv", "nklut ingest"),
    ("colors.csv", "nklut colors"),
    ("errors.csv", "nklut validate"),
    ("cost.csv", "nklut validate"),
    ("gpu_timing.csv", "nklut gpu run"),
];

/// Where `make report` puts the GPU results committed under `benchmarks/devices/` (one
/// folder per adapter, each with the `gpu_timing.csv` of `nklut gpu run`).
pub const DEVICES_DIR: &str = "devices";

/// The columns of `errors.csv` the report shows or counts.
const ERROR_COLUMNS: [&str; 10] = [
    "page",
    "method",
    "variant",
    "precision",
    "channel",
    "wavelength_nm",
    "mean_rel_error",
    "max_abs_error",
    "excluded_samples",
    "fallback",
];

/// The rows of `errors.csv` the report reads: every analytic method, and the LUTs at the
/// default 256 texels (the whole size sweep is summarised by cost.csv).
pub fn shown_error_row(method: &str, variant: &str) -> bool {
    method != "lut" || variant.starts_with("N=256,")
}

/// The most bytes read from a table of one scene or one device (`effects_errors.csv`,
/// a device's `gpu_timing.csv`: kilobytes to a few megabytes).
pub const MAX_SCENE_TABLE_BYTES: u64 = 64 << 20;

/// The most bytes read from a stage's table other than `errors.csv` (`materials.csv`,
/// `excluded.csv`, `colors.csv`, `cost.csv`, `gpu_timing.csv`, `warnings.csv`): each is held
/// whole, and of the whole database the largest, `colors.csv`, is 1.8 MB (2 869 pages), so
/// 64 MiB leaves room for a database 35 times larger. A larger file is refused by name
/// from its stated size, before a byte is read. `errors.csv` (0.14 GB of the whole database)
/// is read up to [`MAX_TABLE_BYTES`], keeping only the rows and columns shown.
pub const MAX_STAGE_TABLE_BYTES: u64 = 64 << 20;

/// The tables the report reads.
pub struct Inputs {
    pub materials: CsvTable,
    pub excluded: CsvTable,
    pub colors: Option<CsvTable>,
    pub errors: Option<CsvTable>,
    pub cost: Option<CsvTable>,
    pub gpu_timing: Option<CsvTable>,
    pub warnings: Option<CsvTable>,
    /// The optional tables of `OPTIONAL_TABLES` that exist, by path relative to the output
    /// folder: at its top, or in a folder one level down (`make effects` writes one folder
    /// per scene, `make gpu` one per effects scene).
    pub extra: BTreeMap<String, CsvTable>,
    /// When each table read was written (its file's modification time), by path relative
    /// to the output folder: the tables of `extra` and the stages' own.
    pub written: BTreeMap<String, SystemTime>,
    /// What each device measured (`out/devices/<device>/`, or the folder `--devices`
    /// names), by device folder.
    pub devices: BTreeMap<String, DeviceTables>,
    /// The channel wavelengths `materials.csv` was evaluated at.
    pub channels: Channels,
    /// The `nvidia` fits `validate` kept (`.cache/nvidia-fits.bin`), read only: the
    /// curves fit what it lacks.
    pub fits: FitMemo,
    /// The paste-in files `params` wrote (`params/<name>.json`), by page id.
    pub paste: BTreeMap<String, serde_json::Value>,
}

impl Inputs {
    /// "From `command` (table, written …; …)." for the tables a section draws from (those
    /// read; the command of each from [`STAGE_TABLES`]).
    pub fn provenance(&self, tables: &[&str]) -> String {
        let mut parts = Vec::new();
        for table in tables {
            let Some(at) = self.written.get(*table) else { continue };
            let command = STAGE_TABLES.iter().find(|(name, _)| name == table).map_or("", |(_, c)| *c);
            parts.push(format!("`{command}` ({table}, written {})", super::html::utc(*at)));
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!("From {}.", parts.join("; "))
        }
    }

    /// Load from an output folder. `materials.csv` and `excluded.csv` are required, and the
    /// channel wavelengths of every table that records them must agree.
    pub fn load(out: &Path) -> Result<Self> {
        let stage = |name: &str| CsvTable::load_bounded(&out.join(name), MAX_STAGE_TABLE_BYTES);
        let required = |name: &str| -> Result<CsvTable> {
            match stage(name)? {
                Some(t) => Ok(t),
                None => bail!("{} is missing: run `nklut ingest` first", out.join(name).display()),
            }
        };
        let materials = required("materials.csv")?;
        let channels = table_channels(&materials).map_err(|e| anyhow::anyhow!("{}: {e}", out.join("materials.csv").display()))?;
        let errors = CsvTable::load_selected(&out.join("errors.csv"), MAX_TABLE_BYTES, &ERROR_COLUMNS, &|r| {
            shown_error_row(r.text("method"), r.text("variant"))
        })?;
        if let Some(errors) = &errors {
            check_error_wavelengths(errors, &channels).map_err(|e| anyhow::anyhow!("{}: {e}", out.join("errors.csv").display()))?;
        }
        let mut extra = BTreeMap::new();
        let mut written = BTreeMap::new();
        for name in STAGE_TABLES.iter().map(|(name, _)| *name) {
            if let Ok(at) = std::fs::metadata(out.join(name)).and_then(|m| m.modified()) {
                written.insert(name.to_string(), at);
            }
        }
        for folder in std::iter::once(String::new()).chain(scene_folders(out)) {
            for name in OPTIONAL_TABLES {
                let relative = if folder.is_empty() { name.to_string() } else { format!("{folder}/{name}") };
                if let Some(table) = CsvTable::load_bounded(&out.join(&relative), MAX_SCENE_TABLE_BYTES)? {
                    if let Ok(at) = std::fs::metadata(out.join(&relative)).and_then(|m| m.modified()) {
                        written.insert(relative.clone(), at);
                    }
                    extra.insert(relative, table);
                }
            }
        }
        let devices = read_devices(&out.join(DEVICES_DIR))?;
        Ok(Self {
            materials,
            excluded: required("excluded.csv")?,
            colors: stage("colors.csv")?,
            errors,
            cost: stage("cost.csv")?,
            gpu_timing: stage("gpu_timing.csv")?,
            warnings: stage("warnings.csv")?,
            extra,
            written,
            devices,
            channels,
            fits: FitMemo::load(out),
            paste: paste_files(out),
        })
    }
}

/// What one device measured: `gpu_timing.csv` (pass time per material and method) and, when
/// there, `image_errors.csv` (each method's image error against exact) and
/// `effects_timing.csv` (the reflection/refraction map update and shading pass per
/// configuration).
pub struct DeviceTables {
    pub timing: CsvTable,
    pub image_errors: Option<CsvTable>,
    pub effects_timing: Option<CsvTable>,
    /// `ao_timing` rows (the surfel passes and GTAO's configurations), where the device
    /// measured them.
    pub ao_timing: Option<CsvTable>,
    /// Where it came from: `native` (a folder of `nklut gpu run`'s tables) or the browser
    /// bench's result file, with the browser and, when the run stopped early, why.
    pub source: String,
}

/// The longest time a device result may state for one pass or frame (ms): a day. A
/// larger figure is a broken or forged result, not a measurement.
pub const MAX_DEVICE_MS: f64 = 86_400_000.0;

/// The largest relative image error a device result may state (a method off by 10⁶ times
/// the exact image is already meaningless).
pub const MAX_IMAGE_ERROR: f64 = 1e6;

/// A measured cell that is not a number in `0..=max` (empty cells are "not measured").
fn check_measured(table: &CsvTable, table_name: &str, column: &str, max: f64) -> Result<()> {
    for (row, cells) in table.rows.iter().enumerate() {
        let text = table.text(cells, column);
        if text.is_empty() {
            continue;
        }
        // A cell holds one number, or a space-separated list of them (`samples_ms`).
        for value in text.split_ascii_whitespace() {
            let shown = crate::escape::terminal(&value.chars().take(24).collect::<String>());
            match value.parse::<f64>() {
                Ok(x) if x.is_finite() && (0.0..=max).contains(&x) => {}
                Ok(x) if !x.is_finite() => bail!("{table_name} row {}: {column} holds {shown}, not a finite number", row + 1),
                Ok(x) if x < 0.0 => bail!("{table_name} row {}: {column} holds {shown}, below 0", row + 1),
                Ok(_) => bail!("{table_name} row {}: {column} holds {shown}, above the largest accepted ({max:e})", row + 1),
                Err(_) => bail!("{table_name} row {}: {column} holds {shown:?}, not a number", row + 1),
            }
        }
    }
    Ok(())
}

impl DeviceTables {
    /// Every time (`*_ms`) and image error (`*_error`) the device states is a finite number
    /// from 0 to [`MAX_DEVICE_MS`] or [`MAX_IMAGE_ERROR`]; anything else is refused by its
    /// table, row and column (a NaN, a negative or a 309-digit time would be printed as a
    /// measurement).
    pub fn check_measurements(&self) -> Result<()> {
        let tables = [
            ("gpu_timing", Some(&self.timing)),
            ("image_errors", self.image_errors.as_ref()),
            (effects_timing::STEM, self.effects_timing.as_ref()),
            (ao_timing::STEM, self.ao_timing.as_ref()),
        ];
        for (name, table) in tables {
            let Some(table) = table else { continue };
            for column in &table.headers {
                if column.ends_with("_ms") {
                    check_measured(table, name, column, MAX_DEVICE_MS)?;
                } else if column.ends_with("_error") {
                    check_measured(table, name, column, MAX_IMAGE_ERROR)?;
                }
            }
        }
        Ok(())
    }

    /// The median over the materials timed of `method`'s pass time (ms).
    pub fn median_ms(&self, method: &str) -> Option<f64> {
        let timing = &self.timing;
        crate::stats::median(
            &timing.rows_where(gpu_timing::METHOD.name, method).filter_map(|r| timing.value(r, gpu_timing::MEDIAN_MS)).collect::<Vec<_>>(),
        )
    }

    /// The path a chart's trace names for table `name` (`ao_timing.csv`) of device
    /// `device`: the file in its folder (native), or its result file (browser).
    pub fn table_path(&self, device: &str, name: &str) -> String {
        if self.source == "native" {
            format!("{DEVICES_DIR}/{device}/{name}")
        } else {
            format!("{DEVICES_DIR}/{device}.json")
        }
    }

    /// The mean over its rows (materials, objects) of `method`'s `mean_rel_error`, where the
    /// device measured image errors.
    pub fn mean_image_error(&self, method: &str) -> Option<f64> {
        let errors = self.image_errors.as_ref()?;
        let values: Vec<f64> =
            errors.rows_where(image_errors::METHOD.name, method).filter_map(|r| errors.value(r, image_errors::MEAN_REL_ERROR)).collect();
        (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
    }
}

/// The largest browser-bench result read (a scene of 30 methods × 20 materials is ~0.3 MB).
const MAX_DEVICE_JSON: u64 = 16 << 20;

/// The devices of `folder`: each sub-folder holding a `gpu_timing.csv` (native, `nklut gpu
/// run`), and each `*.json` file holding a browser bench's result (`nklut gpu web`), named
/// by its file stem; none when the folder is absent. A JSON file that is not a bench result
/// is an error naming it.
pub fn read_devices(folder: &Path) -> Result<BTreeMap<String, DeviceTables>> {
    let mut devices = BTreeMap::new();
    for device in scene_folders(folder) {
        let table = |name: &str| CsvTable::load_bounded(&folder.join(&device).join(name), MAX_SCENE_TABLE_BYTES);
        if let Some(timing) = table("gpu_timing.csv")? {
            let image_errors = table("image_errors.csv")?;
            let effects_timing = table(effects_timing::CSV)?;
            let ao_timing = table(ao_timing::CSV)?;
            let tables = DeviceTables { timing, image_errors, effects_timing, ao_timing, source: "native".into() };
            tables.check_measurements().map_err(|e| anyhow::anyhow!("{}: {e}", folder.join(&device).display()))?;
            devices.insert(device, tables);
        }
    }
    // Every entry named `*.json`, whatever it is: one that is not a regular file (a FIFO, a
    // device, a folder, a link that loops or dangles) is an error naming it, not skipped.
    let mut files: Vec<_> = std::fs::read_dir(folder)
        .map(|entries| entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "json")).collect())
        .unwrap_or_default();
    files.sort();
    for file in files {
        let bytes = nklut_optics::db::file::read_regular(&file, MAX_DEVICE_JSON)
            .map_err(|e| anyhow::anyhow!("{}: not a browser bench result: {e}", file.display()))?;
        let tables = browser_result(&bytes).map_err(|e| anyhow::anyhow!("{}: not a browser bench result: {e}", file.display()))?;
        tables.check_measurements().map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
        let name = file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        devices.insert(name, tables);
    }
    Ok(devices)
}

/// The tables of one browser bench result (`nklut-web-bench/1`): its rows under the columns
/// it lists, numbers as their JSON text, null as an empty cell.
pub fn browser_result(bytes: &[u8]) -> Result<DeviceTables> {
    let value: serde_json::Value = serde_json::from_slice(bytes)?;
    if value["format"] != "nklut-web-bench/1" {
        bail!("format is {}, not nklut-web-bench/1", value["format"]);
    }
    let table = |name: &str| -> Result<CsvTable> {
        let Some(columns) = value["columns"][name].as_array() else { bail!("no columns.{name}") };
        let headers: Vec<String> = columns.iter().map(|c| c.as_str().unwrap_or_default().to_string()).collect();
        let Some(rows) = value[name].as_array() else { bail!("no {name} rows") };
        let cell = |v: &serde_json::Value| match v {
            serde_json::Value::String(s) => s.clone(),
            serde_json::Value::Null => String::new(),
            other => other.to_string(),
        };
        let rows = rows.iter().map(|row| headers.iter().map(|h| cell(&row[h])).collect()).collect();
        Ok(CsvTable::from_rows(headers, rows))
    };
    let image_errors = table("image_errors")?;
    // Rows of the reflection/refraction timing, where the page ran a scene with those effects.
    let effects_timing =
        value[effects_timing::STEM].as_array().is_some_and(|rows| !rows.is_empty()).then(|| table(effects_timing::STEM)).transpose()?;
    // Rows of the ambient-occlusion timing, where the page ran a scene that names it.
    let ao_timing = value[ao_timing::STEM].as_array().is_some_and(|rows| !rows.is_empty()).then(|| table(ao_timing::STEM)).transpose()?;
    // The browser and its version as the rows' `driver` gives it (the whole `user_agent` is
    // in the file).
    let browser = browser_name(&value);
    let mut source = format!("browser: {browser}");
    if value["complete"] != true {
        source.push_str(&format!("; incomplete: {}", value["incomplete"].as_str().unwrap_or("stopped early")));
    }
    Ok(DeviceTables {
        timing: table("gpu_timing")?,
        image_errors: (!image_errors.rows.is_empty()).then_some(image_errors),
        effects_timing,
        ao_timing,
        source,
    })
}

/// The browser and its version: the `driver` of the F-only rows, else the browser token of
/// the `user_agent` string (as the page's script takes it: the last `Name/version`), else
/// the whole string.
fn browser_name(value: &serde_json::Value) -> String {
    if let Some(driver) = value["gpu_timing"][0]["driver"].as_str() {
        return driver.to_string();
    }
    let Some(identification) = value["user_agent"].as_str() else { return "unknown browser".into() };
    identification
        .split_whitespace()
        .rfind(|token| ["Edg/", "Firefox/", "Chrome/", "HeadlessChrome/", "Version/"].iter().any(|name| token.starts_with(name)))
        .unwrap_or(identification)
        .to_string()
}

/// The paste-in files under `out/params/`, by the page id each names (a file that does not
/// read as JSON with a `page` is left out: the page then shows no per-tool blocks).
fn paste_files(out: &Path) -> BTreeMap<String, serde_json::Value> {
    let folder = out.join(crate::params::PASTE_DIR);
    let Ok(entries) = std::fs::read_dir(&folder) else { return BTreeMap::new() };
    entries
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
        .filter_map(|e| nklut_optics::db::file::read_regular(&e.path(), 1 << 20).ok())
        .filter_map(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok())
        .filter_map(|value| Some((value["page"].as_str()?.to_string(), value)))
        .collect()
}

/// The folders directly under `out`, sorted by name (the per-scene output folders).
pub fn scene_folders(out: &Path) -> Vec<String> {
    let mut folders: Vec<String> = std::fs::read_dir(out)
        .map(|entries| entries.flatten().filter(|e| e.path().is_dir()).filter_map(|e| e.file_name().to_str().map(String::from)).collect())
        .unwrap_or_default();
    folders.retain(|f| !f.starts_with('.'));
    folders.sort();
    folders
}

/// The channel wavelengths of `materials.csv` (`lambda_red_nm` …): one value per column.
pub fn table_channels(materials: &CsvTable) -> Result<Channels> {
    let mut nm = [0.0; 3];
    for (c, name) in CHANNEL_NAMES.iter().enumerate() {
        let column = format!("lambda_{name}_nm");
        if !materials.has(&column) {
            bail!("no column {column}: written by an older nklut; run `nklut ingest` again");
        }
        let mut values: Vec<f64> = materials.rows.iter().map(|r| materials.number(r, &column).unwrap_or(f64::NAN)).collect();
        values.sort_by(f64::total_cmp);
        values.dedup();
        nm[c] = match values.as_slice() {
            [] => Channels::default().nanometres()[c],
            [one] if one.is_finite() && *one > 0.0 => *one,
            _ => bail!("column {column} holds {} different wavelengths ({values:?}); one run writes one", values.len()),
        };
    }
    Ok(Channels { red_nm: nm[0], green_nm: nm[1], blue_nm: nm[2] })
}

/// `errors.csv` records each row's channel wavelength: it must be the ingest's.
fn check_error_wavelengths(errors: &CsvTable, channels: &Channels) -> Result<()> {
    if !errors.has("wavelength_nm") {
        return Ok(());
    }
    let nm = channels.nanometres();
    for row in &errors.rows {
        let channel = errors.text(row, "channel");
        let Some(c) = CHANNEL_NAMES.iter().position(|n| *n == channel) else { continue };
        let value = errors.number(row, "wavelength_nm").unwrap_or(f64::NAN);
        if value != nm[c] {
            bail!(
                "{} ({channel}) was validated at {value} nm but materials.csv holds {} nm: the tables come from runs with different --channels; run validate again",
                errors.text(row, "page"),
                nm[c]
            );
        }
    }
    Ok(())
}

/// The page ids of `materials.csv` that `selection` picks, in table order. Every named
/// page and shelf must pick something; otherwise the error names each one missing and
/// why (excluded by ingest, with its reason, or not in the tables at all).
pub fn select_pages(materials: &CsvTable, excluded: &CsvTable, selection: &Selection) -> Result<Vec<String>> {
    let chosen: Vec<String> = materials
        .rows
        .iter()
        .filter(|r| selection.includes_id(materials.text(r, "shelf"), materials.text(r, "page")))
        .map(|r| materials.text(r, "page").to_string())
        .collect();
    let mut missing = Vec::new();
    for page in selection.named_pages() {
        if !chosen.contains(page) {
            missing.push(match excluded.rows_where("page", page).next() {
                Some(row) => format!("{page} (excluded by ingest: {}, {})", excluded.text(row, "reason"), excluded.text(row, "detail")),
                None => format!("{page} (not in materials.csv: run `nklut ingest --page {page}`)"),
            });
        }
    }
    for shelf in selection.named_shelves() {
        if !materials.rows.iter().any(|r| materials.text(r, "shelf") == shelf) {
            missing.push(format!("shelf {shelf} (no kept page of it in materials.csv: run `nklut ingest --shelf {shelf}`)"));
        }
    }
    if !missing.is_empty() {
        bail!("the tables do not contain {} of the selected pages: {}", missing.len(), missing.join("; "));
    }
    if chosen.is_empty() {
        bail!("materials.csv has no kept page: nothing to report");
    }
    Ok(chosen)
}

/// A count the report prints, with the table it comes from and what it counts, so a
/// reader (and the tests) can recount it: HTML `<span class="count" data-table data-key>`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Count {
    pub table: &'static str,
    /// What is counted: `rows`, `reason=<code>`, `sparse`, `fallback`, `fallback=<reason>`,
    /// `out-of-gamut`, `extrapolated`, `excluded-samples`.
    pub key: String,
    pub value: usize,
}

impl Count {
    pub fn html(&self) -> String {
        format!("<span class=\"count\" data-table=\"{}\" data-key=\"{}\">{}</span>", self.table, super::html::escape(&self.key), self.value)
    }
}

/// Rows of a table.
pub fn rows(table: &'static str, t: &CsvTable) -> Count {
    Count { table, key: "rows".into(), value: t.rows.len() }
}

/// Excluded pages per reason code, in code order.
pub fn exclusions_by_reason(excluded: &CsvTable) -> Vec<Count> {
    let mut by_reason: BTreeMap<&str, usize> = BTreeMap::new();
    for row in &excluded.rows {
        *by_reason.entry(excluded.text(row, "reason")).or_default() += 1;
    }
    by_reason.into_iter().map(|(reason, value)| Count { table: "excluded.csv", key: format!("reason={reason}"), value }).collect()
}

/// The (page, channel) pairs where compensated Schlick has no real exponent and falls
/// back to `schlick_nk`: rows of `errors.csv` with method `schlick_compensated`, f64
/// precision and a non-empty `fallback` (its reason).
pub fn compensation_fallbacks(errors: &CsvTable) -> Vec<(String, String, String)> {
    let mut found: Vec<(String, String, String)> = errors
        .rows
        .iter()
        .filter(|r| {
            errors.text(r, "method") == "schlick_compensated"
                && errors.text(r, "precision") == "f64"
                && !errors.text(r, "fallback").is_empty()
        })
        .map(|r| (errors.text(r, "page").to_string(), errors.text(r, "channel").to_string(), errors.text(r, "fallback").to_string()))
        .collect();
    found.sort();
    found.dedup();
    found
}

/// Counts of `compensation_fallbacks`: all, then per reason.
pub fn fallback_counts(fallbacks: &[(String, String, String)]) -> Vec<Count> {
    let mut counts = vec![Count { table: "errors.csv", key: "fallback".into(), value: fallbacks.len() }];
    let mut by_reason: BTreeMap<&str, usize> = BTreeMap::new();
    for (_, _, reason) in fallbacks {
        *by_reason.entry(reason).or_default() += 1;
    }
    counts.extend(by_reason.into_iter().map(|(reason, value)| Count { table: "errors.csv", key: format!("fallback={reason}"), value }));
    counts
}

/// Pages of `colors.csv` with a flag column set in any channel (`out_of_gamut_r` …).
pub fn flagged_pages(colors: &CsvTable, stem: &str) -> Vec<String> {
    colors
        .rows
        .iter()
        .filter(|r| ["r", "g", "b"].iter().any(|c| colors.text(r, &format!("{stem}_{c}")) == "true"))
        .map(|r| colors.text(r, "page").to_string())
        .collect()
}

/// Pages of `colors.csv` whose spectral colour holds data beyond the data's range.
pub fn extrapolated_pages(colors: &CsvTable) -> Vec<String> {
    colors
        .rows
        .iter()
        .filter(|r| colors.number(r, "extrapolated_share").is_some_and(|s| s > 0.0))
        .map(|r| colors.text(r, "page").to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> CsvTable {
        CsvTable::parse(text.as_bytes()).unwrap()
    }

    #[test]
    fn a_browser_result_reads_as_its_columns_and_says_when_it_is_incomplete() {
        let result = r#"{"format": "nklut-web-bench/1", "user_agent": "UA", "complete": false, "incomplete": "device lost",
            "columns": {"gpu_timing": ["method", "median_ms", "relative_to_exact_dielectric"], "image_errors": ["method", "mean_rel_error"]},
            "gpu_timing": [{"method": "exact", "median_ms": 2.5, "relative_to_exact_dielectric": null, "driver": "Chrome/1"}],
            "image_errors": []}"#;
        let tables = browser_result(result.as_bytes()).unwrap();
        assert_eq!(tables.timing.headers, ["method", "median_ms", "relative_to_exact_dielectric"]);
        assert_eq!(tables.timing.rows, [["exact", "2.5", ""]]);
        assert!(tables.image_errors.is_none(), "no rows: no table");
        assert_eq!(tables.source, "browser: Chrome/1; incomplete: device lost");
        assert!(tables.effects_timing.is_none(), "no effects_timing rows: no table");
        // A result of a scene with reflections: effects rows under their columns, no F-only
        // rows, the browser named from its `user_agent` string.
        let effects = r#"{"format": "nklut-web-bench/1", "user_agent": "Mozilla/5.0 (X11) HeadlessChrome/156.0.1 Safari/537.36", "complete": true,
            "columns": {"gpu_timing": ["method"], "image_errors": ["method"], "effects_timing": ["method", "reflection_depth", "shading_ms"]},
            "gpu_timing": [], "image_errors": [],
            "effects_timing": [{"method": "lut", "reflection_depth": 2, "shading_ms": 0.75}]}"#;
        let tables = browser_result(effects.as_bytes()).unwrap();
        let rows = tables.effects_timing.expect("effects rows");
        assert_eq!(rows.headers, ["method", "reflection_depth", "shading_ms"]);
        assert_eq!(rows.rows, [["lut", "2", "0.75"]]);
        assert_eq!(tables.source, "browser: HeadlessChrome/156.0.1");
        let other = browser_result(br#"{"format": "something else"}"#).err().unwrap();
        assert!(other.to_string().contains("not nklut-web-bench/1"), "{other}");
        assert!(browser_result(b"not json").is_err());
    }

    #[test]
    fn channels_come_from_the_table() {
        let m = table("page,shelf,lambda_red_nm,lambda_green_nm,lambda_blue_nm\na,s,650,550,450\nb,s,650,550,450\n");
        assert_eq!(table_channels(&m).unwrap(), Channels { red_nm: 650.0, green_nm: 550.0, blue_nm: 450.0 });
        let mixed = table("page,shelf,lambda_red_nm,lambda_green_nm,lambda_blue_nm\na,s,650,550,450\nb,s,685,550,450\n");
        assert!(table_channels(&mixed).is_err());
        assert!(table_channels(&table("page,shelf\na,s\n")).unwrap_err().to_string().contains("lambda_red_nm"));
    }

    #[test]
    fn selection_names_every_missing_page() {
        let m = table("page,shelf\n3d/metals/gold,3d\nmain/Au/Johnson,main\n");
        let x = table("page,data_file,reason,line,detail\n3d/plastics/pmma,f,no-visible-coverage,,starts at 437 nm\n");
        let all = select_pages(&m, &x, &Selection::All).unwrap();
        assert_eq!(all, vec!["3d/metals/gold", "main/Au/Johnson"]);
        assert_eq!(select_pages(&m, &x, &Selection::shelf("3d")).unwrap(), vec!["3d/metals/gold"]);
        let wanted = Selection::pages(["3d/plastics/pmma", "nope/x/y", "3d/metals/gold"]);
        let error = select_pages(&m, &x, &wanted).unwrap_err().to_string();
        assert!(error.contains("2 of the selected"), "{error}");
        assert!(error.contains("3d/plastics/pmma (excluded by ingest: no-visible-coverage"), "{error}");
        assert!(error.contains("nope/x/y (not in materials.csv"), "{error}");
        assert!(select_pages(&m, &x, &Selection::shelf("other")).unwrap_err().to_string().contains("shelf other"));
    }

    #[test]
    fn fallbacks_count_f64_page_channels_with_a_reason() {
        let e = table(
            "page,method,precision,channel,fallback\n\
             g,schlick_compensated,f64,green,wrong-sign\n\
             g,schlick_compensated,f32,green,wrong-sign\n\
             g,schlick_compensated,f64,blue,no-decay\n\
             g,schlick_compensated,f64,red,\n\
             g,schlick_nk,f64,green,\n",
        );
        let found = compensation_fallbacks(&e);
        assert_eq!(found.len(), 2);
        let counts = fallback_counts(&found);
        assert_eq!(counts[0].value, 2);
        assert_eq!(counts[1], Count { table: "errors.csv", key: "fallback=no-decay".into(), value: 1 });
        assert_eq!(counts[2], Count { table: "errors.csv", key: "fallback=wrong-sign".into(), value: 1 });
    }
}
