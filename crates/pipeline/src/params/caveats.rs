//! Caveats: pages whose class or values rest on a pattern in the data that misleads, each
//! with the numbers that triggered it (the `caveats` column of `engine_params`, the
//! paste-in file's `caveats` and the report's material page):
//!
//! - `conductor_passes_light` — a conductor by the k ≥ 1 rule (`spectrum::Kind`) that some
//!   channel passes (absorption depth ≥ the thin limit, 1 mm): not a metal. The class rule
//!   reads the depths first (`appearance::classify`), so the page is classed by them.
//! - `opaque_low_k` — opaque by its channel depths, yet k < [`LOW_K`] at every nanometre of
//!   390–700 nm: k this small makes an object opaque only from millimetres on, and is
//!   typical of a thin-film model's k (MgF2, LaF3, SiO2, Al2O3 by Rodríguez-de Marcos;
//!   PVP), under which a bulk piece renders black.
//! - `shared_data_file` — on the `main` shelf (one book per substance), the page's data
//!   file lies in another book's folder and is listed under several books: the numbers may
//!   be another substance's (MgO and ZrO2 by Synowicki point at As2S3's file).
//! - `transparent_absorbs` — transparent (every depth ≥ 1 m) but a [`LARGE_OBJECT_M`]
//!   piece keeps less than [`LARGE_OBJECT_KEEPS`] of some channel, e^(−x/δ): a depth
//!   under 1/ln(1/0.7) = 2.80 m (water: red 2.03 m, a 1 m pool passes 61 % of red and
//!   looks cyan).
//!
//! Pure: the pages and their parameters in, one list per page out.

use std::collections::HashMap;

use super::page::EngineParams;
use crate::ingest::KeptPage;
use nklut_optics::appearance::{Appearance, THIN_LIMIT_M};
use nklut_optics::spectrum::Kind;

/// Below this k everywhere in 390–700 nm, an opaque page is flagged.
pub const LOW_K: f64 = 0.01;
/// The size of the large object the `transparent_absorbs` caveat speaks of (m).
pub const LARGE_OBJECT_M: f64 = 1.0;
/// A transparent page whose [`LARGE_OBJECT_M`] piece keeps less than this share of some
/// channel is flagged (30 % lost is a tint anyone sees).
pub const LARGE_OBJECT_KEEPS: f64 = 0.7;

/// The depth under which a channel of a [`LARGE_OBJECT_M`] piece keeps less than
/// [`LARGE_OBJECT_KEEPS`]: x / ln(1/keeps), 2.80 m.
pub fn transparent_depth_limit_m() -> f64 {
    LARGE_OBJECT_M / (1.0 / LARGE_OBJECT_KEEPS).ln()
}

/// The channel names, for the caveats' text.
const CHANNELS: [&str; 3] = ["red", "green", "blue"];

/// One caveat: a code (stable, for scripts) and its sentence with the numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Caveat {
    pub code: &'static str,
    pub text: String,
}

impl Caveat {
    /// "code: text", as the table's cell joins them.
    pub fn line(&self) -> String {
        format!("{}: {}", self.code, self.text)
    }
}

/// The caveats of every page of `kept` (`params` in the same order).
pub fn caveats(kept: &[KeptPage], params: &[EngineParams]) -> Vec<Vec<Caveat>> {
    let books_of_file = main_shelf_books(kept);
    kept.iter()
        .zip(params)
        .map(|(page, p)| {
            let mut found = Vec::new();
            found.extend(conductor_passes_light(page, p));
            found.extend(opaque_low_k(p));
            found.extend(shared_data_file(page, &books_of_file));
            found.extend(transparent_absorbs(p));
            found
        })
        .collect()
}

/// A depth as text: metres, millimetres or micrometres; "infinite" for k = 0.
fn depth(d: f64) -> String {
    if !d.is_finite() {
        "infinite (k = 0)".into()
    } else if d >= 1.0 {
        format!("{d:.3} m")
    } else if d >= 1e-3 {
        format!("{:.3} mm", d * 1e3)
    } else {
        format!("{:.3} µm", d * 1e6)
    }
}

fn conductor_passes_light(page: &KeptPage, p: &EngineParams) -> Option<Caveat> {
    if page.material.kind != Kind::Conductor || p.volume.appearance == Appearance::Metal {
        return None;
    }
    let passing: Vec<String> = (0..3)
        .filter(|&c| p.volume.depths_m[c] >= THIN_LIMIT_M)
        .map(|c| format!("{} depth {}", CHANNELS[c], depth(p.volume.depths_m[c])))
        .collect();
    Some(Caveat {
        code: "conductor_passes_light",
        text: format!(
            "a conductor by the k >= 1 rule (k {:.3} at {} nm) but light passes: {} (a metal absorbs every channel within {} mm), so it is classed by its depths as {}, not as a metal",
            p.volume.k_peak.k,
            p.volume.k_peak.nm,
            passing.join(", "),
            THIN_LIMIT_M * 1e3,
            p.volume.appearance.name()
        ),
    })
}

fn opaque_low_k(p: &EngineParams) -> Option<Caveat> {
    if p.volume.appearance != Appearance::Opaque || p.volume.k_peak.k >= LOW_K {
        return None;
    }
    let depths: Vec<String> = (0..3).map(|c| format!("{} {}", CHANNELS[c], depth(p.volume.depths_m[c]))).collect();
    Some(Caveat {
        code: "opaque_low_k",
        text: format!(
            "opaque by its depths ({}, all under {} mm) yet k < {LOW_K} everywhere in 390-700 nm (largest {:.5} at {} nm): values typical of a thin-film model's k, under which a bulk piece renders black, while a bulk sample may be clear",
            depths.join(", "),
            THIN_LIMIT_M * 1e3,
            p.volume.k_peak.k,
            p.volume.k_peak.nm
        ),
    })
}

/// Per data file, the `main`-shelf pages (ids) that list it and their books.
fn main_shelf_books(kept: &[KeptPage]) -> HashMap<&str, Vec<(&str, String)>> {
    let mut map: HashMap<&str, Vec<(&str, String)>> = HashMap::new();
    for page in kept.iter().filter(|p| p.page.shelf == "main") {
        map.entry(page.page.data.as_str()).or_default().push((page.page.book.as_str(), page.id()));
    }
    map
}

fn shared_data_file(page: &KeptPage, books_of_file: &HashMap<&str, Vec<(&str, String)>>) -> Option<Caveat> {
    if page.page.shelf != "main" {
        return None;
    }
    let users = books_of_file.get(page.page.data.as_str())?;
    let mut books: Vec<&str> = users.iter().map(|(book, _)| *book).collect();
    books.sort_unstable();
    books.dedup();
    // The folder the file lies in: `main/<book>/…`.
    let owner = page.page.data.split('/').nth(1).unwrap_or("");
    if books.len() < 2 || page.page.book == owner {
        return None;
    }
    let others: Vec<&str> = users.iter().map(|(_, id)| id.as_str()).filter(|id| *id != page.id()).collect();
    Some(Caveat {
        code: "shared_data_file",
        text: format!(
            "the data file {} lies in the book {owner}'s folder and is listed under {} books of the main shelf ({}): the numbers may be another substance's",
            page.page.data,
            books.len(),
            others.join(", ")
        ),
    })
}

fn transparent_absorbs(p: &EngineParams) -> Option<Caveat> {
    if p.volume.appearance != Appearance::Transparent {
        return None;
    }
    let kept = p.volume.depths_m.map(|d| if d.is_finite() { (-LARGE_OBJECT_M / d).exp() } else { 1.0 });
    if kept.iter().all(|k| *k >= LARGE_OBJECT_KEEPS) {
        return None;
    }
    let short: Vec<String> = (0..3)
        .filter(|&c| kept[c] < LARGE_OBJECT_KEEPS)
        .map(|c| format!("{} depth {}", CHANNELS[c], depth(p.volume.depths_m[c])))
        .collect();
    Some(Caveat {
        code: "transparent_absorbs",
        text: format!(
            "transparent at the 1 m scene scale, but {} (under {:.2} m): a {LARGE_OBJECT_M} m piece passes red {:.3}, green {:.3}, blue {:.3} of the light (e^(-x/depth) at the channel wavelengths, less than {LARGE_OBJECT_KEEPS} in some channel) and looks tinted",
            short.join(", "),
            transparent_depth_limit_m(),
            kept[0],
            kept[1],
            kept[2]
        ),
    })
}
