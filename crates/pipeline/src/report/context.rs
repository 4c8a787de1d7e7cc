//! What every page of the report looks up: the loaded tables indexed by page id, the θ
//! grid of the curves and the preview geometry, built once per report.

use std::collections::HashMap;

use anyhow::{bail, Result};

use super::csvdata::CsvTable;
use super::curves::{theta_grid, THETA_POINTS};
use super::inputs::Inputs;
use super::preview::{Environment, SphereLayout, PREVIEW_PX};
use nklut_optics::spectrum::{ChannelIndex, Index, CHANNEL_NAMES};

/// Rows of one table by page id.
pub struct ByPage<'a> {
    pub table: &'a CsvTable,
    rows: HashMap<&'a str, Vec<&'a [String]>>,
}

impl<'a> ByPage<'a> {
    pub fn new(table: &'a CsvTable) -> Self {
        let mut rows: HashMap<&str, Vec<&[String]>> = HashMap::new();
        for row in &table.rows {
            rows.entry(table.text(row, "page")).or_default().push(row);
        }
        Self { table, rows }
    }

    pub fn rows(&self, page: &str) -> &[&'a [String]] {
        self.rows.get(page).map(Vec::as_slice).unwrap_or(&[])
    }

    pub fn first(&self, page: &str) -> Option<&'a [String]> {
        self.rows(page).first().copied()
    }
}

/// The report's shared lookups.
pub struct Context<'a> {
    pub inputs: &'a Inputs,
    pub theta: Vec<f64>,
    pub layout: SphereLayout,
    pub materials: ByPage<'a>,
    pub colors: Option<ByPage<'a>>,
    pub errors: Option<ByPage<'a>>,
    pub params: Option<ByPage<'a>>,
    pub warnings: Option<ByPage<'a>>,
}

impl<'a> Context<'a> {
    pub fn new(inputs: &'a Inputs) -> Self {
        Self {
            inputs,
            theta: theta_grid(THETA_POINTS),
            layout: SphereLayout::new(PREVIEW_PX, THETA_POINTS, Environment::Studio),
            materials: ByPage::new(&inputs.materials),
            colors: inputs.colors.as_ref().map(ByPage::new),
            errors: inputs.errors.as_ref().map(ByPage::new),
            params: inputs.extra.get("engine_params.csv").map(ByPage::new),
            warnings: inputs.warnings.as_ref().map(ByPage::new),
        }
    }
}

/// The three channel indices of a row with columns `n_<channel>`/`k_<channel>`.
pub fn three_channel_index(table: &CsvTable, row: &[String]) -> ChannelIndex {
    CHANNEL_NAMES.map(|c| {
        Index::new(table.number(row, &format!("n_{c}")).unwrap_or(f64::NAN), table.number(row, &format!("k_{c}")).unwrap_or(f64::NAN))
    })
}

/// Per-channel values of `<prefix>_r`, `_g`, `_b`.
pub fn channel_triple(table: &CsvTable, row: &[String], prefix: &str) -> [f64; 3] {
    ["r", "g", "b"].map(|c| table.number(row, &format!("{prefix}_{c}")).unwrap_or(f64::NAN))
}

/// Per-channel flags `<prefix>_r`, `_g`, `_b`.
pub fn channel_flags(table: &CsvTable, row: &[String], prefix: &str) -> [bool; 3] {
    ["r", "g", "b"].map(|c| table.text(row, &format!("{prefix}_{c}")) == "true")
}

/// The fitted channel indices of a `colors.csv` row.
pub fn fitted_index(colors: &CsvTable, row: &[String]) -> ChannelIndex {
    let n = channel_triple(colors, row, "effective_n");
    let k = channel_triple(colors, row, "effective_k");
    [0, 1, 2].map(|c| Index::new(n[c], k[c]))
}

/// Where a material's page lives under `report/`: `materials/<id>.html`, the id's
/// parts as folders, each bounded in length ([`bounded_parts`]). A part that is empty,
/// `.` or `..` would leave the folder: refused.
pub fn material_path(page: &str) -> Result<String> {
    if page.split('/').any(|part| part.is_empty() || part == "." || part == "..") {
        bail!("page id {page:?} cannot name a file under report/materials");
    }
    Ok(format!("materials/{}.html", bounded_parts(page)))
}

/// Where a material's preview image lives under `report/`.
pub fn preview_path(page: &str) -> String {
    format!("previews/{}.png", bounded_parts(page))
}

/// The page id with each '/'-separated part cut to a file name's length
/// ([`crate::output::bounded_stem`]): one long id cannot fail the report.
fn bounded_parts(page: &str) -> String {
    page.split('/').map(|part| crate::output::bounded_stem(part, '~')).collect::<Vec<_>>().join("/")
}

/// The relative path from a material page back to `report/`.
pub fn up_from_material(page: &str) -> String {
    "../".repeat(1 + page.matches('/').count())
}

/// The data shelf of manufacturers' data sheets, whose books' `about.yml` NAMES the maker
/// (`SCHOTT AG`), not the material.
pub const MAKERS_SHELF: &str = "specs/";

/// What a material is called on its page and in the index: the `names` of
/// `materials.csv` (the data's `about.yml`), except where the data file lies on the makers'
/// shelf ([`MAKERS_SHELF`]): there the page's own catalog name (`catalog_name`, `BK7
/// optical glass (crown)`), its page id where that is empty, followed by "by" and the maker
/// (`BK7 optical glass (crown), by SCHOTT AG`).
pub fn display_name(materials: &CsvTable, row: &[String]) -> String {
    let names = materials.text(row, "names");
    if !materials.text(row, "data_file").starts_with(MAKERS_SHELF) {
        return names.to_string();
    }
    let own = match materials.text(row, "catalog_name") {
        "" => materials.text(row, "page_name"),
        name => name,
    };
    if names.is_empty() {
        own.to_string()
    } else {
        format!("{own}, by {names}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3d-shelf glass on a maker's data sheet, a metal on the main shelf, a data sheet page
    /// without a catalog name.
    #[test]
    fn materials_are_named_by_their_page_where_the_data_names_the_maker() {
        let table = CsvTable::parse(
            "page,page_name,names,catalog_name,data_file\n\
3d/glass/BK7,BK7,SCHOTT AG,BK7 optical glass (crown),specs/schott/optical/N-BK7.yml\n\
3d/metals/gold,gold,Gold; Au,Gold (Au),main/Au/nk/Rakic-BB.yml\n\
specs/ohara/X,X,OHARA,,specs/ohara/optical/X.yml\n"
                .as_bytes(),
        )
        .unwrap();
        let names: Vec<String> = table.rows.iter().map(|r| display_name(&table, r)).collect();
        assert_eq!(names, ["BK7 optical glass (crown), by SCHOTT AG", "Gold; Au", "X, by OHARA"]);
    }
}
