//! What three colour channels cost over many bounces: the three-channel f64 reference
//! (`super::trace::reference`) against the spectral one (`super::spectral`) on the same
//! frame, per specular object, source of the channel indices and depth — the mean, 95th
//! percentile and largest CIEDE2000 over the object's pixels — and the price: each
//! reference's wall time and rays per second for that frame. Written as `spectral_errors`
//! with pictures of both frames and the ΔE map (false colour, white at [`DELTA_E_SCALE`]) with
//! its legend ([`DELTA_E_LEGEND_FILE`], `crate::colour_bar`).
//!
//! Index sources: `three-wavelength` (n, k at the channel wavelengths, SPEC §3) and
//! `effective` (the fit over angle of `colors`, docs/colors.md: per channel the (n, k) whose
//! exact F is closest to the spectral reference colour's curve). Attenuation inside a
//! dielectric keeps the three-wavelength k under either source: the fitted k is a
//! reflectance shape correction, not a volume property. `engine`: a conductor as F82-tint
//! curves, a dielectric as one IOR; `gulbrandsen`: a conductor as MaterialX's
//! `artistic_ior` takes it (Gulbrandsen 2014: per channel the reflectivity r = the
//! reference colour at normal incidence and the edge tint g fitted to its curve, shaded with
//! the exact F of the (n, k) they give), a dielectric as three-wavelength.

use nklut_tables::effects_tables::spectral_errors;
use std::time::Instant;

use anyhow::Result;

use super::colour_bar;
use super::colour_bar::error_png;
use super::image_error::delta_e_map;
use super::optics::{attenuation_per_unit, inside_index, SpecularOptics, GEOMETRIC_CHANNEL};
use super::pictures::Picture;
use super::spectral::{spectral_reference, WavelengthGrid};
use super::trace::{reference_with, Camera, ObjectOptics, Stage};
use crate::scene::{Depths, Scene};
use nklut_optics::color::{angle_quadrature, fit_effective_index, PreparedSpectrum};
use nklut_optics::fresnel::{LutSpec, Method, Model};
use nklut_optics::spectrum::{ChannelIndex, Index, Kind};
use nklut_tables::output::{SetFile, Table};
use nklut_tables::stats::quantile;

/// Where a three-channel frame's indices come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndexSource {
    ThreeWavelength,
    Effective,
    /// What engines take: a conductor as F82-tint curves (OpenPBR, Adobe Standard Material;
    /// per channel from the three-wavelength index, `fresnel::Method::F82Tint`), a dielectric
    /// as one IOR (the geometric channel's n) for every channel's F, its per-channel
    /// absorption kept.
    Engine,
    /// MaterialX's `artistic_ior` for a conductor: per channel Gulbrandsen's (r, g), r the
    /// reference colour at normal incidence and g fitted to its curve over angle
    /// (`nklut_tables::models::Gulbrandsen::fit`), shaded with the exact F of the (n, k)
    /// they give; a dielectric as three-wavelength (the model is for conductors).
    Gulbrandsen,
}

impl IndexSource {
    pub const ALL: [IndexSource; 4] = [IndexSource::ThreeWavelength, IndexSource::Effective, IndexSource::Engine, IndexSource::Gulbrandsen];

    pub fn name(self) -> &'static str {
        match self {
            IndexSource::ThreeWavelength => "three-wavelength",
            IndexSource::Effective => "effective",
            IndexSource::Engine => "engine",
            IndexSource::Gulbrandsen => "gulbrandsen",
        }
    }
}

/// The folder of the spectral comparison's pictures in the effects' set.
pub const SPECTRAL_DIR: &str = "spectral_frames";

/// ΔE2000 at which the ΔE map's false colour is white (fixed, so maps of every depth and
/// scene compare; ΔE 5 is a difference anyone sees).
pub const DELTA_E_SCALE: f64 = 5.0;
/// The ΔE maps' legend (colour bar with its values), beside them in [`SPECTRAL_DIR`].
pub const DELTA_E_LEGEND_FILE: &str = "delta_e_scale.png";
const DELTA_E_LEGEND_WIDTH: u32 = 384;

/// One row of `spectral_errors`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralErrorRow {
    pub object: String,
    /// The object's position in the scene's `objects` list (two slabs of one mesh and
    /// material at two thicknesses are two objects).
    pub object_index: usize,
    pub material: String,
    pub source: IndexSource,
    pub depths: Depths,
    pub wavelengths: u32,
    pub resolution: [u32; 2],
    pub pixels: usize,
    pub mean_delta_e2000: f64,
    pub p95_delta_e2000: f64,
    pub max_delta_e2000: f64,
    pub spectral_ms: f64,
    pub three_channel_ms: f64,
    pub spectral_wavelength_rays_per_s: f64,
    pub three_channel_rays_per_s: f64,
    pub total_internal_reflections: u64,
}

/// The rows and the pictures (camera frame 0 of every depth: the spectral frame, each
/// source's three-channel frame with its |Δ| error image, and its ΔE map).
#[derive(Clone, Debug, Default)]
pub struct SpectralReport {
    pub rows: Vec<SpectralErrorRow>,
    pub pictures: Vec<Picture>,
    pub delta_e_maps: Vec<SetFile>,
}

/// The channel indices of a material of `kind` from `source`: the page's three-wavelength
/// ones, per channel the fit over angle to the spectral reference curve (`colors`' fit), or
/// for a conductor Gulbrandsen's (r, g) fitted to that curve, as (n, k).
pub fn channel_indices(
    three: &ChannelIndex,
    spectrum: Option<&[nklut_optics::spectrum::Index]>,
    kind: Kind,
    source: IndexSource,
) -> ChannelIndex {
    match (source, spectrum) {
        (IndexSource::ThreeWavelength | IndexSource::Engine, _) | (IndexSource::Effective | IndexSource::Gulbrandsen, None) => *three,
        (IndexSource::Gulbrandsen, Some(_)) if kind != Kind::Conductor => *three,
        (IndexSource::Effective, Some(spectrum)) => {
            let quadrature = angle_quadrature();
            let curve = PreparedSpectrum::new(spectrum).curve(&quadrature.cosines);
            std::array::from_fn(|c| {
                let reference: Vec<f64> = curve.iter().map(|rgb| rgb[c]).collect();
                fit_effective_index(&reference, three[c], quadrature).index
            })
        }
        (IndexSource::Gulbrandsen, Some(spectrum)) => {
            let quadrature = angle_quadrature();
            let prepared = PreparedSpectrum::new(spectrum);
            let curve = prepared.curve(&quadrature.cosines);
            let normal = prepared.curve(&[1.0])[0];
            std::array::from_fn(|c| {
                let reference: Vec<f64> = curve.iter().map(|rgb| rgb[c]).collect();
                nklut_tables::models::Gulbrandsen::fit(normal[c], &reference, quadrature).index()
            })
        }
    }
}

/// The reference optics of every object with its indices from `source`.
fn optics_for(stage: &Stage, source: IndexSource) -> Vec<Option<SpecularOptics>> {
    stage
        .objects
        .iter()
        .enumerate()
        .map(|(object, o)| match o {
            ObjectOptics::Diffuse(_) => None,
            ObjectOptics::Specular(m) => {
                let spectrum = stage.spectra.get(object).and_then(|s| s.as_deref());
                let channels = channel_indices(&m.channels, spectrum, m.kind, source);
                let mut optics = SpecularOptics::reference(&channels, m.kind, stage.channels_nm, stage.metres_per_unit);
                if m.kind == Kind::Dielectric {
                    optics.absorption =
                        std::array::from_fn(|c| attenuation_per_unit(m.channels[c].k, stage.channels_nm[c], stage.metres_per_unit));
                }
                if source == IndexSource::Engine {
                    let models = |method: Method, channels: ChannelIndex| {
                        (
                            channels.map(|i| Model::new(i, method, LutSpec::default())),
                            channels.map(|i| Model::new(inside_index(i), method, LutSpec::default())),
                        )
                    };
                    (optics.outside, optics.inside) = match m.kind {
                        Kind::Conductor => models(Method::F82Tint, channels),
                        Kind::Dielectric => models(Method::Exact, [Index::new(channels[GEOMETRIC_CHANNEL].n, 0.0); 3]),
                    };
                }
                Some(optics)
            }
        })
        .collect()
}

fn per_second(count: u64, ms: f64) -> f64 {
    if ms > 0.0 {
        count as f64 / (ms * 1e-3)
    } else {
        0.0
    }
}

/// Run the comparison on camera frame 0 at `resolution` for every depth configuration of
/// the scene with `wavelengths` bins; `log` receives a line per row.
pub fn spectral_errors(
    scene: &Scene,
    stage: &Stage,
    resolution: [u32; 2],
    wavelengths: u32,
    log: &mut dyn FnMut(&str),
) -> Result<SpectralReport> {
    let mut report = SpectralReport::default();
    let Some(effects) = &scene.effects else { return Ok(report) };
    let grid = WavelengthGrid::new(wavelengths as usize)?;
    let camera = Camera::new(&scene.camera, 0, resolution[0], resolution[1]);
    let sources: Vec<(IndexSource, Vec<Option<SpecularOptics>>)> =
        IndexSource::ALL.into_iter().map(|s| (s, optics_for(stage, s))).collect();
    for depths in effects.depths() {
        let stem = |name: &str| format!("depth{}-{}_{name}", depths.reflection, depths.refraction);
        let start = Instant::now();
        let spectral = spectral_reference(stage, &camera, depths, &grid)?;
        let spectral_ms = start.elapsed().as_secs_f64() * 1e3;
        report.pictures.push(Picture { stem: stem("spectral"), frame: spectral.frame.clone(), reference: None });
        for (source, optics) in &sources {
            let start = Instant::now();
            let three = reference_with(stage, &camera, depths, optics);
            let three_ms = start.elapsed().as_secs_f64() * 1e3;
            let delta_e = delta_e_map(&three, &spectral.frame);
            let (w, h) = (three.width, three.height);
            let map = error_png(w, h, delta_e.iter().map(|&e| colour_bar::colour(e, DELTA_E_SCALE)))?;
            report.delta_e_maps.push(SetFile::new(format!("{}_delta_e.png", stem(source.name())), map));
            report.pictures.push(Picture { stem: stem(source.name()), frame: three.clone(), reference: Some(spectral.frame.clone()) });
            for (object, scene_object) in scene.objects.iter().enumerate() {
                let Some(specular) = scene_object.specular() else { continue };
                let mut values: Vec<f64> =
                    delta_e.iter().zip(&spectral.frame.seen).filter(|(_, seen)| **seen == Some(object)).map(|(e, _)| *e).collect();
                values.sort_by(f64::total_cmp);
                let mean = if values.is_empty() { 0.0 } else { values.iter().sum::<f64>() / values.len() as f64 };
                let row = SpectralErrorRow {
                    object: scene_object.mesh.label(),
                    object_index: object,
                    material: specular.material.clone(),
                    source: *source,
                    depths,
                    wavelengths,
                    resolution,
                    pixels: values.len(),
                    mean_delta_e2000: mean,
                    p95_delta_e2000: if values.is_empty() { 0.0 } else { quantile(&values, 0.95) },
                    max_delta_e2000: values.last().copied().unwrap_or(0.0),
                    spectral_ms,
                    three_channel_ms: three_ms,
                    spectral_wavelength_rays_per_s: per_second(spectral.wavelength_rays, spectral_ms),
                    three_channel_rays_per_s: per_second(three.rays, three_ms),
                    total_internal_reflections: spectral.total_internal_reflections,
                };
                log(&format!(
                    "  spectral {} {} {} depth {}/{}: ΔE2000 mean {:.3}, p95 {:.3}, max {:.3}; spectral {:.0} ms ({:.2} M wavelength-rays/s), three-channel {:.0} ms",
                    row.object,
                    row.material,
                    source.name(),
                    depths.reflection,
                    depths.refraction,
                    row.mean_delta_e2000,
                    row.p95_delta_e2000,
                    row.max_delta_e2000,
                    spectral_ms,
                    row.spectral_wavelength_rays_per_s / 1e6,
                    three_ms
                ));
                report.rows.push(row);
            }
        }
    }
    if !report.delta_e_maps.is_empty() {
        let legend = colour_bar::legend_png(DELTA_E_LEGEND_WIDTH, DELTA_E_SCALE, "CIEDE2000, three channels vs spectral")?;
        report.delta_e_maps.push(SetFile::new(DELTA_E_LEGEND_FILE, legend));
    }
    Ok(report)
}

/// `spectral_errors.*`: one row per (object, material, index source, depths).
pub fn spectral_error_table(rows: &[SpectralErrorRow]) -> Table {
    let text = |f: &dyn Fn(&SpectralErrorRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let integer = |f: &dyn Fn(&SpectralErrorRow) -> i64| rows.iter().map(f).collect::<Vec<_>>();
    let float = |f: &dyn Fn(&SpectralErrorRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(spectral_errors::OBJECT, text(&|r| r.object.clone()))
        .put(spectral_errors::OBJECT_INDEX, integer(&|r| r.object_index as i64))
        .put(spectral_errors::MATERIAL, text(&|r| r.material.clone()))
        .put(spectral_errors::INDEX_SOURCE, text(&|r| r.source.name().into()))
        .put(spectral_errors::REFLECTION_DEPTH, integer(&|r| r.depths.reflection as i64))
        .put(spectral_errors::REFRACTION_DEPTH, integer(&|r| r.depths.refraction as i64))
        .put(spectral_errors::WAVELENGTHS, integer(&|r| r.wavelengths as i64))
        .put(spectral_errors::RESOLUTION, text(&|r| format!("{}x{}", r.resolution[0], r.resolution[1])))
        .put(spectral_errors::PIXELS, integer(&|r| r.pixels as i64))
        .put(spectral_errors::MEAN_DELTA_E2000, float(&|r| r.mean_delta_e2000))
        .put(spectral_errors::P95_DELTA_E2000, float(&|r| r.p95_delta_e2000))
        .put(spectral_errors::MAX_DELTA_E2000, float(&|r| r.max_delta_e2000))
        .put(spectral_errors::SPECTRAL_MS, float(&|r| r.spectral_ms))
        .put(spectral_errors::THREE_CHANNEL_MS, float(&|r| r.three_channel_ms))
        .put(spectral_errors::SPECTRAL_WAVELENGTH_RAYS_PER_S, float(&|r| r.spectral_wavelength_rays_per_s))
        .put(spectral_errors::THREE_CHANNEL_RAYS_PER_S, float(&|r| r.three_channel_rays_per_s))
        .put(spectral_errors::TOTAL_INTERNAL_REFLECTIONS, integer(&|r| r.total_internal_reflections as i64));
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneMaterial;
    use crate::trace::stage_from_table;
    use nklut_optics::spectrum::{spectral_wavelength_nm, Index, SPECTRAL_SAMPLES};
    use std::path::Path;

    fn material(page: &str, kind: Kind, index: impl Fn(f64) -> Index) -> SceneMaterial {
        let spectrum: Vec<Index> = (0..SPECTRAL_SAMPLES).map(|i| index(spectral_wavelength_nm(i))).collect();
        SceneMaterial::new(page, [685.0, 535.0, 475.0].map(&index), kind).with_spectrum(spectrum)
    }

    #[test]
    fn a_flat_material_costs_nothing_and_a_coloured_one_grows_with_depth() {
        // A flat metal: three channels are the spectrum, ΔE 0 at depth 1 (deeper, it shows the
        // other metal's reflections, which are not flat). A metal whose k
        // falls across the spectrum (reflecting red more than blue, like gold): each bounce
        // multiplies in F(λ) again, so three channels err more as the depth grows.
        let table = vec![
            material("t/metals/flat", Kind::Conductor, |_| Index::new(0.4, 2.8)),
            material("t/metals/warm", Kind::Conductor, |nm| {
                Index::new(0.2 + 1.2 * (700.0 - nm).max(0.0) / 300.0, 1.5 + 3.0 * (nm - 400.0).max(0.0) / 300.0)
            }),
        ];
        let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0.3], distance: 2.2, fov_y_degrees: 50}\neffects: {reflection: {max_depth: [1, 4]}, spectral: {wavelengths: 24}}\nlight: {direction: [-0.3, -1, -0.5], colour: [0.7, 0.7, 0.7], ambient: [0.3, 0.3, 0.3]}\nobjects:\n  - {mesh: sphere, scale: 0.45, position: [-0.5, 0, 0], material: t/metals/flat, method: exact}\n  - {mesh: sphere, scale: 0.45, position: [0.5, 0, 0], material: t/metals/warm, method: exact}\n  - {mesh: plane, scale: 1.2, position: [0, -0.45, 0], material: t/metals/warm, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.85, 0.85, 0.8], pattern: {kind: checker, size: 0.5, albedo: [0.15, 0.2, 0.45]}}\n";
        let scene = Scene::parse(text, Path::new("t.yaml")).unwrap();
        let stage = stage_from_table(&scene, &table).unwrap();
        let report = spectral_errors(&scene, &stage, [20, 16], 24, &mut |_| {}).unwrap();
        // 2 depths × 4 sources × 3 specular objects.
        assert_eq!(report.rows.len(), 24);
        let row = |object: &str, material: &str, source: IndexSource, depth: u32| {
            report
                .rows
                .iter()
                .find(|r| r.object == object && r.material == material && r.source == source && r.depths.reflection == depth)
                .unwrap()
        };
        let flat = row("sphere", "t/metals/flat", IndexSource::ThreeWavelength, 1);
        assert!(flat.pixels > 0 && flat.max_delta_e2000 < 1e-6, "{flat:?}");
        let (shallow, deep) = (
            row("sphere", "t/metals/warm", IndexSource::ThreeWavelength, 1),
            row("sphere", "t/metals/warm", IndexSource::ThreeWavelength, 4),
        );
        assert!(deep.mean_delta_e2000 > shallow.mean_delta_e2000 && shallow.mean_delta_e2000 > 0.1, "{shallow:?} {deep:?}");
        assert!(deep.p95_delta_e2000 <= deep.max_delta_e2000 && deep.mean_delta_e2000 <= deep.max_delta_e2000);
        assert!(deep.spectral_ms > 0.0 && deep.spectral_wavelength_rays_per_s > 0.0 && deep.three_channel_rays_per_s > 0.0);
        // The effective fit is closer than three wavelengths at depth 1 (it fits one bounce).
        let effective = row("sphere", "t/metals/warm", IndexSource::Effective, 1);
        assert!(effective.mean_delta_e2000 < shallow.mean_delta_e2000, "{effective:?} vs {shallow:?}");
        // The engine's F82-tint curve is not the flat metal's exact curve (it matches it at 0°
        // and 82° only): a colour error where three wavelengths have none.
        let engine = row("sphere", "t/metals/flat", IndexSource::Engine, 1);
        assert!(engine.mean_delta_e2000 > 1e-3, "{engine:?}");
        // Gulbrandsen's (r, g) is a change of variables of (n, k) (r ≤ 0.99): fitted to the
        // flat metal's exact curve it gives back its (n, k), so no colour error at depth 1,
        // where F82-tint has one.
        let gulbrandsen = row("sphere", "t/metals/flat", IndexSource::Gulbrandsen, 1);
        assert!(gulbrandsen.mean_delta_e2000 < 0.01 && gulbrandsen.mean_delta_e2000 < engine.mean_delta_e2000, "{gulbrandsen:?}");
        // Pictures: per depth the spectral frame and each source's frame; a ΔE map per source.
        // Two depths × four sources: a ΔE map each, and the legend once.
        assert_eq!((report.pictures.len(), report.delta_e_maps.len()), (10, 9));
        assert_eq!(report.delta_e_maps.last().map(|f| f.name.as_str()), Some(DELTA_E_LEGEND_FILE));
        let table = spectral_error_table(&report.rows);
        assert_eq!(table.rows(), 24);
        eprintln!(
            "warm metal three-wavelength ΔE mean: depth 1 {:.3}, depth 4 {:.3}; effective depth 1 {:.3}; flat metal engine {:.4}, gulbrandsen {:.2e}",
            shallow.mean_delta_e2000, deep.mean_delta_e2000, effective.mean_delta_e2000, engine.mean_delta_e2000, gulbrandsen.mean_delta_e2000
        );
    }

    #[test]
    fn the_engine_s_one_ior_glass_is_exact_without_dispersion_and_not_with_it() {
        // One IOR for every channel: for a glass whose n is the same at every wavelength the
        // engine's frame is the three-wavelength frame exactly; for a dispersive one (BK7's
        // Cauchy fit) the green n in red and blue's F is a colour error of its own. One
        // sphere per scene, so no path of one glass passes through the other.
        let frames = |glass: SceneMaterial| {
            let text = format!("measurements: [image_error]\ncamera: {{axis: [0, 1, 0.3], distance: 2.2, fov_y_degrees: 50}}\neffects: {{reflection: {{max_depth: 2}}, refraction: {{max_depth: 2}}, spectral: {{wavelengths: 24}}}}\nlight: {{direction: [-0.3, -1, -0.5], colour: [0.7, 0.7, 0.7], ambient: [0.3, 0.3, 0.3]}}\nobjects:\n  - {{mesh: sphere, scale: 0.6, material: {}, method: exact}}\n  - {{mesh: room, scale: 3, diffuse: [0.85, 0.85, 0.8], pattern: {{kind: checker, size: 0.5, albedo: [0.15, 0.2, 0.45]}}}}\n", glass.page);
            let scene = Scene::parse(&text, Path::new("t.yaml")).unwrap();
            let stage = stage_from_table(&scene, &[glass]).unwrap();
            let report = spectral_errors(&scene, &stage, [20, 16], 24, &mut |_| {}).unwrap();
            let frame = |source: IndexSource| {
                report.pictures.iter().find(|p| p.stem == format!("depth2-2_{}", source.name())).unwrap().frame.clone()
            };
            let (three, engine) = (frame(IndexSource::ThreeWavelength), frame(IndexSource::Engine));
            assert!(three.seen.contains(&Some(0)), "the sphere is in view");
            three.radiance.iter().zip(&engine.radiance).filter(|(a, b)| a != b).count()
        };
        assert_eq!(frames(material("t/glass/flat", Kind::Dielectric, |_| Index::new(1.5, 0.0))), 0, "flat glass: the same frame");
        let dispersive = frames(material("t/glass/dispersive", Kind::Dielectric, |nm| Index::new(1.5046 + 4200.0 / (nm * nm), 0.0)));
        assert!(dispersive > 0, "dispersive glass: one IOR changes the colour");
    }
}
