//! The materials a scene names, read from the database: each page id with its channel
//! indices (n, k at the channel wavelengths, SPEC §3) and whether it conducts. Both the
//! GPU runner and the CPU tracers of the effects take them from here.

use anyhow::{anyhow, Result};

use super::Scene;
use nklut_optics::db::Database;
use nklut_optics::spectrum::{ChannelIndex, Index, Kind};
use nklut_tables::ingest::{self, Selection};

/// A specular object's optical constants: (n, k) per channel and conductor or dielectric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularMaterial {
    pub channels: ChannelIndex,
    pub kind: Kind,
}

/// A material of a scene: the page id it names and what that page gives.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneMaterial {
    pub page: String,
    pub optics: SpecularMaterial,
    /// n, k on the 1 nm grid 360–830 nm of `colors` (`color::sample_spectrum`), where the
    /// page's data were read: what the spectral reference traces.
    pub spectrum: Option<Vec<Index>>,
}

impl SceneMaterial {
    pub fn new(page: impl Into<String>, channels: ChannelIndex, kind: Kind) -> Self {
        Self { page: page.into(), optics: SpecularMaterial { channels, kind }, spectrum: None }
    }

    /// With its spectrum on the 1 nm grid.
    pub fn with_spectrum(mut self, spectrum: Vec<Index>) -> Self {
        self.spectrum = Some(spectrum);
        self
    }
}

/// The materials of a scene with how many pages were read: ingests exactly the pages the
/// scene names, read with `config`; a page the filter drops is an error naming the scene
/// file and why.
pub fn read_materials(scene: &Scene, db: &Database, config: &ingest::Config) -> Result<(Vec<SceneMaterial>, usize)> {
    let pages = scene.materials();
    if pages.is_empty() {
        // A scene of diffuse objects alone (surfel effects) reads no page.
        return Ok((Vec::new(), 0));
    }
    let selection = Selection::pages(pages.iter().cloned());
    let result = ingest::ingest(db, &selection, config).map_err(|e| anyhow!("scene {}: {e:#}", scene.file.display()))?;
    result.check_strict()?;
    let materials = pages
        .into_iter()
        .map(|page| match result.find(&page) {
            Some(kept) => Ok(SceneMaterial::new(page, kept.material.channels, kept.material.kind)
                .with_spectrum(nklut_optics::color::sample_spectrum(&kept.material.data).0)),
            None => {
                let why = result.excluded.iter().find(|e| e.page == page).map(|e| e.error.to_string()).unwrap_or_else(|| "not kept".into());
                Err(anyhow!("scene {}: material {page} cannot be used: {why}", scene.file.display()))
            }
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((materials, result.selected))
}
