//! The surfel effects a scene may call for inside `effects`: ambient occlusion (how many
//! passes, whether through the surfel hierarchy, whether to light with bent normals) and
//! diffuse indirect light (how many bounces), after Bunnell (GPU Gems 2 ch. 14; the method
//! and its measurements in `crate::ao`); and, beside the surfels, screen-space ground-truth
//! AO (GTAO, Jimenez et al. 2016: `crate::ao::gtao`) with its search radius in scene units,
//! slices per pixel and steps per side of a slice. Diffuse albedo is the objects' `diffuse`;
//! the lights are the scene's (`super::lights`: ambient light is what accessibility
//! darkens, directional and point light cast ray-traced shadows and feed the indirect
//! light). Pure data and checks.
//!
//! GTAO names a preset (`crate::scene::gtao::Preset`: `bare`, Algorithm 1, the default;
//! XeGTAO's `xe-low`, `xe-medium`, `xe-high`, `xe-ultra`; or `unreal`) and may override its
//! slices, steps, frames, noise and any heuristic (`crate::scene::gtao::Heuristics`), each checked
//! against its range with a named error; `gtao` may be one block or a list of blocks, each
//! with its radii (every block × radius is one configuration, repeats dropped).
//!
//! ```yaml
//! effects:
//!   ambient_occlusion: { passes: 2, hierarchy: true, bent_normals: true,
//!                        gtao: [{ radius: 0.5, slices: 4, steps: 8 },
//!                               { preset: xe-high, radius: [0.5, 1], frames: 64, thin_occluder: 0.7 }] }
//!   indirect: { bounces: 1 }
//! lights:
//!   - { kind: directional, direction: [-0.3, -1, -0.5], colour: [0.8, 0.8, 0.8] }
//!   - { kind: point, position: [0, 2, 1], intensity: [2, 2, 2] }
//!   - { kind: ambient, colour: [0.3, 0.3, 0.3] }
//! ```

use serde::Deserialize;

use super::error::{Each, FieldProblem, Range, SceneProblem, Value};
use crate::scene::gtao::{Heuristics, Preset};

/// The most passes a scene may ask for (each is a full gather; they converge by 3 or 4).
pub const MAX_PASSES: u32 = 8;
/// The most bounces of indirect light.
pub const MAX_BOUNCES: u32 = 2;
/// The most midpoint subdivisions of an object's mesh (each multiplies its surfels by ~4).
pub const MAX_SUBDIVISIONS: u32 = 6;
/// The most GTAO slices per pixel and steps per side of a slice (engines use 1–4 slices
/// and 4–16 steps; the cost is slices × 2 × steps G-buffer reads per pixel).
pub const MAX_GTAO_SLICES: u32 = 64;
pub const MAX_GTAO_STEPS: u32 = 256;
/// The largest GTAO radius in scene units (scenes are fitted around the unit sphere).
pub const MAX_GTAO_RADIUS: f64 = 100.0;
/// The most frames a scene may accumulate (XeGTAO's noise repeats after 64).
pub const MAX_GTAO_FRAMES: u32 = 1024;
/// The most passes of GTAO's denoiser (XeGTAO's UI: 0 off, 1 sharp, 2 medium, 3 soft).
pub const MAX_DENOISE_PASSES: u32 = 3;
/// The most G-buffer reads per pixel (2 × slices × steps × frames): the bare maximum,
/// 64 slices × 256 steps, so that accumulation cannot make a run unbounded.
pub const MAX_GTAO_READS: u32 = 2 * MAX_GTAO_SLICES * MAX_GTAO_STEPS;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawAmbientOcclusion {
    #[serde(default = "default_passes")]
    passes: u32,
    #[serde(default)]
    hierarchy: bool,
    #[serde(default)]
    bent_normals: bool,
    /// One GTAO block or a list of them (read in `checked`, so that a block's own unknown
    /// fields are named).
    #[serde(default)]
    gtao: Option<serde_norway::Value>,
}

/// One radius or a list of them (each a GTAO configuration, in the order written).
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum Radii {
    One(f64),
    Many(Vec<f64>),
}

#[derive(Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGtao {
    #[serde(default)]
    preset: Option<String>,
    #[serde(default = "default_gtao_radius")]
    radius: Radii,
    #[serde(default)]
    slices: Option<u32>,
    #[serde(default)]
    steps: Option<u32>,
    #[serde(default)]
    frames: Option<u32>,
    #[serde(default)]
    noise: Option<bool>,
    #[serde(default)]
    radius_multiplier: Option<f64>,
    #[serde(default)]
    falloff_range: Option<f64>,
    #[serde(default)]
    distribution_power: Option<f64>,
    #[serde(default)]
    start_pixels: Option<f64>,
    #[serde(default)]
    thin_occluder: Option<f64>,
    #[serde(default)]
    thickness_blend: Option<f64>,
    #[serde(default)]
    final_power: Option<f64>,
    #[serde(default)]
    normal_lerp: Option<f64>,
    #[serde(default)]
    min_radius_pixels: Option<f64>,
    #[serde(default)]
    max_radius_pixels: Option<f64>,
    #[serde(default)]
    clamp_to_edge: Option<bool>,
    #[serde(default)]
    denoise_passes: Option<u32>,
    #[serde(default)]
    denoise_beta: Option<f64>,
}

fn default_gtao_radius() -> Radii {
    Radii::One(1.0)
}

fn default_passes() -> u32 {
    2
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawIndirect {
    #[serde(default = "default_bounces")]
    bounces: u32,
}

fn default_bounces() -> u32 {
    1
}

/// Surfel ambient occlusion: `passes` in 1..=[`MAX_PASSES`], through the tree or by brute
/// force, lighting with bent normals or the normals; and GTAO beside it where named, one
/// configuration per radius listed (the first is the one pictured; empty: no GTAO).
#[derive(Clone, Debug, PartialEq)]
pub struct AmbientOcclusion {
    pub passes: u32,
    pub hierarchy: bool,
    pub bent_normals: bool,
    pub gtao: Vec<Gtao>,
}

/// Screen-space GTAO's parameters: occluders within `radius` (scene units, × the
/// heuristics' radius multiplier) of the shaded point count, searched along `slices`
/// directions per pixel with `steps` G-buffer reads on each side, with the heuristics of
/// `preset` (default bare: Algorithm 1, 1.0, 4, 8) and any the scene overrides. `radius`
/// may be a list: one configuration each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gtao {
    pub radius: f64,
    pub slices: u32,
    pub steps: u32,
    pub preset: Preset,
    pub heuristics: Heuristics<f64>,
}

impl Gtao {
    /// Algorithm 1 with `slices` × `steps` within `radius`.
    pub fn bare(radius: f64, slices: u32, steps: u32) -> Gtao {
        Gtao { radius, slices, steps, preset: Preset::Bare, heuristics: Heuristics::BARE }
    }

    /// Whether the scene overrode a heuristic of the preset.
    pub fn modified(&self) -> bool {
        self.heuristics != self.preset.heuristics()
    }

    /// The preset's name, with " (modified)" where the scene overrode one of its heuristics:
    /// the `gtao_preset` and `preset` cells of `ao_errors` and `ao_timing`.
    pub fn preset_label(&self) -> String {
        let modified = if self.modified() { " (modified)" } else { "" };
        format!("{}{modified}", self.preset.name())
    }

    /// A label for logs and pictures: "bare, radius 1, 4×8" or "xe-high, radius 0.5, 3×3,
    /// 64 frames" (and "(modified)" where the scene overrode a heuristic of the preset).
    pub fn label(&self) -> String {
        let mut label = format!("{}, radius {}, {}×{}", self.preset.name(), self.radius, self.slices, self.steps);
        if self.heuristics.noise {
            label += &format!(", {} frames", self.heuristics.frames);
        }
        if self.modified() {
            label += " (modified)";
        }
        label
    }
}

/// Diffuse indirect light from surfels: `bounces` in 1..=[`MAX_BOUNCES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Indirect {
    pub bounces: u32,
}

impl RawAmbientOcclusion {
    pub(crate) fn checked(&self) -> Result<AmbientOcclusion, SceneProblem> {
        if !(1..=MAX_PASSES).contains(&self.passes) {
            let range = Range::Integers { low: 1, high: MAX_PASSES.into() };
            let kind = FieldProblem::OutOfRange { value: Value::Integer(self.passes.into()), range };
            return Err(SceneProblem::field("ambient_occlusion.passes", kind));
        }
        let gtao = match &self.gtao {
            None => Vec::new(),
            Some(serde_norway::Value::Sequence(blocks)) => {
                if blocks.is_empty() {
                    return Err(SceneProblem::field("ambient_occlusion.gtao", FieldProblem::Empty(super::error::Listing::Values)));
                }
                let mut all = Vec::new();
                for (i, block) in blocks.iter().enumerate() {
                    let raw: RawGtao = serde_norway::from_value(block.clone()).map_err(SceneProblem::Syntax)?;
                    for g in raw.checked(&format!("ambient_occlusion.gtao[{i}]"))? {
                        if !all.contains(&g) {
                            all.push(g);
                        }
                    }
                }
                all
            }
            Some(block) => {
                let raw: RawGtao = serde_norway::from_value(block.clone()).map_err(SceneProblem::Syntax)?;
                raw.checked("ambient_occlusion.gtao")?
            }
        };
        Ok(AmbientOcclusion { passes: self.passes, hierarchy: self.hierarchy, bent_normals: self.bent_normals, gtao })
    }
}

impl RawGtao {
    /// The configurations of one block at `path` (one per radius).
    fn checked(&self, path: &str) -> Result<Vec<Gtao>, SceneProblem> {
        let field = |name: &str| format!("{path}.{name}");
        let preset = match &self.preset {
            None => Preset::Bare,
            Some(name) => Preset::named(name).ok_or_else(|| {
                let known = Preset::ALL.iter().map(|p| p.name()).collect();
                SceneProblem::field(field("preset"), FieldProblem::Unknown { what: "GTAO preset", name: name.clone(), known })
            })?,
        };
        let mut radii = match &self.radius {
            Radii::One(r) => vec![*r],
            Radii::Many(list) => list.clone(),
        };
        if radii.is_empty() {
            return Err(SceneProblem::field(field("radius"), FieldProblem::Empty(super::error::Listing::Values)));
        }
        for &radius in &radii {
            if !(radius > 0.0 && radius <= MAX_GTAO_RADIUS) {
                let range = Range::AboveUpTo { low: 0.0, high: MAX_GTAO_RADIUS };
                let kind = FieldProblem::OutOfRange { value: Value::Number(radius), range };
                return Err(SceneProblem::field(field("radius"), kind));
            }
        }
        let mut seen = Vec::new();
        radii.retain(|r| {
            let fresh = !seen.contains(r);
            seen.push(*r);
            fresh
        });
        let [default_slices, default_steps] = preset.slices_steps();
        let (slices, steps) = (self.slices.unwrap_or(default_slices), self.steps.unwrap_or(default_steps));
        let integers = |name: &str, value: u32, low: u32, high: u32| {
            if (low..=high).contains(&value) {
                return Ok(value);
            }
            let kind = FieldProblem::OutOfRange {
                value: Value::Integer(value.into()),
                range: Range::Integers { low: low.into(), high: high.into() },
            };
            Err(SceneProblem::field(field(name), kind))
        };
        integers("slices", slices, 1, MAX_GTAO_SLICES)?;
        integers("steps", steps, 1, MAX_GTAO_STEPS)?;
        let mut h = preset.heuristics();
        h.noise = self.noise.unwrap_or(h.noise);
        h.clamp_to_edge = self.clamp_to_edge.unwrap_or(h.clamp_to_edge);
        h.denoise_passes = integers("denoise_passes", self.denoise_passes.unwrap_or(h.denoise_passes), 0, MAX_DENOISE_PASSES)?;
        // Frames are accumulated only with noise (without it every frame is the same).
        let most_frames = (MAX_GTAO_READS / (2 * slices * steps)).clamp(1, MAX_GTAO_FRAMES);
        h.frames = if h.noise { integers("frames", self.frames.unwrap_or(h.frames), 1, most_frames)? } else { 1 };
        let numbers = [
            ("radius_multiplier", self.radius_multiplier, &mut h.radius_multiplier, GTAO_RANGES.radius_multiplier),
            ("falloff_range", self.falloff_range, &mut h.falloff_range, GTAO_RANGES.falloff_range),
            ("distribution_power", self.distribution_power, &mut h.distribution_power, GTAO_RANGES.distribution_power),
            ("start_pixels", self.start_pixels, &mut h.start_pixels, GTAO_RANGES.start_pixels),
            ("thin_occluder", self.thin_occluder, &mut h.thin_occluder, GTAO_RANGES.thin_occluder),
            ("thickness_blend", self.thickness_blend, &mut h.thickness_blend, GTAO_RANGES.thickness_blend),
            ("final_power", self.final_power, &mut h.final_power, GTAO_RANGES.final_power),
            ("normal_lerp", self.normal_lerp, &mut h.normal_lerp, GTAO_RANGES.normal_lerp),
            ("min_radius_pixels", self.min_radius_pixels, &mut h.min_radius_pixels, GTAO_RANGES.radius_pixels),
            ("max_radius_pixels", self.max_radius_pixels, &mut h.max_radius_pixels, GTAO_RANGES.radius_pixels),
            ("denoise_beta", self.denoise_beta, &mut h.denoise_beta, GTAO_RANGES.denoise_beta),
        ];
        for (name, given, slot, [low, high]) in numbers {
            let Some(value) = given else { continue };
            if !(low <= value && value <= high) {
                let kind = FieldProblem::OutOfRange { value: Value::Number(value), range: Range::Closed { low, high, each: Each::Whole } };
                return Err(SceneProblem::field(field(name), kind));
            }
            *slot = value;
        }
        if h.min_radius_pixels > h.max_radius_pixels {
            let range = Range::Closed { low: 0.0, high: h.max_radius_pixels, each: Each::Whole };
            let kind = FieldProblem::OutOfRange { value: Value::Number(h.min_radius_pixels), range };
            return Err(SceneProblem::field(field("min_radius_pixels"), kind));
        }
        Ok(radii.into_iter().map(|radius| Gtao { radius, slices, steps, preset, heuristics: h }).collect())
    }
}

/// The ranges a scene's GTAO heuristics must lie in, [low, high]: XeGTAO's own UI ranges
/// (`XeGTAO.h`, `GTAOImGuiSettings`) where it gives them — radius multiplier 0.3–3, falloff
/// range 0–1, sample distribution power 1–3, thin-occluder compensation 0–0.7, final power
/// 0.5–5 — Unreal's thickness blend 0–1 (its lerp factor 1 − b² stays in [0, 1]) — and for
/// the rest: a start offset up to 16 px, the |n_φ| lerp 0–1, screen radii
/// up to 4096 px, the denoiser's beta 0.01–10⁴ (XeGTAO sets 10⁴ to turn it off).
pub struct GtaoRanges {
    pub radius_multiplier: [f64; 2],
    pub falloff_range: [f64; 2],
    pub distribution_power: [f64; 2],
    pub start_pixels: [f64; 2],
    pub thin_occluder: [f64; 2],
    pub thickness_blend: [f64; 2],
    pub final_power: [f64; 2],
    pub normal_lerp: [f64; 2],
    pub radius_pixels: [f64; 2],
    pub denoise_beta: [f64; 2],
}

pub const GTAO_RANGES: GtaoRanges = GtaoRanges {
    radius_multiplier: [0.3, 3.0],
    falloff_range: [0.0, 1.0],
    distribution_power: [1.0, 3.0],
    start_pixels: [0.0, 16.0],
    thin_occluder: [0.0, 0.7],
    thickness_blend: [0.0, 1.0],
    final_power: [0.5, 5.0],
    normal_lerp: [0.0, 1.0],
    radius_pixels: [0.0, 4096.0],
    denoise_beta: [0.01, 10000.0],
};

impl RawIndirect {
    pub(crate) fn checked(&self) -> Result<Indirect, SceneProblem> {
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            let range = Range::Integers { low: 1, high: MAX_BOUNCES.into() };
            let kind = FieldProblem::OutOfRange { value: Value::Integer(self.bounces.into()), range };
            return Err(SceneProblem::field("indirect.bounces", kind));
        }
        Ok(Indirect { bounces: self.bounces })
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{Conflict, Each, EffectFamily, FieldProblem, Listing, Range, Scene, SceneProblem, Value};
    use std::path::Path;

    use super::{AmbientOcclusion, Gtao, Indirect};
    use crate::scene::LightSource;

    fn parse(effects: &str) -> Result<Scene, String> {
        let text = format!("measurements: [image_error]\nobjects:\n  - {{ mesh: sphere, material: a/b/c, method: exact }}\n  - {{ mesh: plane, diffuse: [0.8, 0.8, 0.8] }}\neffects: {effects}\n");
        Scene::parse(&text, Path::new("t.yaml")).map_err(|e| e.to_string())
    }

    #[test]
    fn surfel_effects_parse_with_defaults_and_alone() {
        let scene = parse("{ ambient_occlusion: { passes: 3, hierarchy: true }, indirect: {} }").unwrap();
        let effects = scene.effects.unwrap();
        assert_eq!(effects.ambient_occlusion, Some(AmbientOcclusion { passes: 3, hierarchy: true, bent_normals: false, gtao: vec![] }));
        let gtao = parse("{ ambient_occlusion: { gtao: { radius: 0.5, steps: 12 } } }").unwrap().effects.unwrap();
        assert_eq!(gtao.ambient_occlusion.unwrap().gtao, [Gtao::bare(0.5, 4, 12)]);
        // A list of radii: one configuration each, in the order written, repeats dropped.
        let radii = parse("{ ambient_occlusion: { gtao: { radius: [2, 0.5, 2] } } }").unwrap().effects.unwrap();
        let configurations = radii.ambient_occlusion.unwrap().gtao;
        assert_eq!(configurations, [Gtao::bare(2.0, 4, 8), Gtao::bare(0.5, 4, 8)]);
        assert_eq!(effects.indirect, Some(Indirect { bounces: 1 }));
        assert_eq!((effects.reflection, effects.refraction), (None, None));
        let plain = parse("{ reflection: { max_depth: 1 } }").unwrap().effects.unwrap();
        assert_eq!((plain.ambient_occlusion, plain.indirect), (None, None));
    }

    fn parse_file(text: &str) -> Result<Scene, String> {
        Scene::parse(text, Path::new("ao.yaml")).map_err(|e| e.to_string())
    }

    #[test]
    fn an_ao_only_scene_needs_no_specular_object_and_has_its_lights() {
        let text = "measurements: [image_error]\neffects: { ambient_occlusion: { passes: 2 } }\nobjects:\n  - { mesh: sphere, diffuse: [0.8, 0.8, 0.8], subdivide: 1 }\n  - { mesh: plane, diffuse: [0.5, 0.5, 0.5] }\nlights:\n  - { kind: directional, direction: [0, -1, 0], colour: [1, 1, 1] }\n  - { kind: point, position: [0, 2, 0], intensity: [2, 1, 1] }\n  - { kind: ambient, colour: [0.3, 0.3, 0.3] }\n";
        let scene = parse_file(text).unwrap();
        assert_eq!(scene.specular_objects().count(), 0);
        assert_eq!((scene.objects[0].subdivisions, scene.objects[1].subdivisions), (1, 0));
        assert_eq!(
            scene.lights,
            vec![
                LightSource::Directional { direction: [0.0, -1.0, 0.0], colour: [1.0; 3] },
                LightSource::Point { position: [0.0, 2.0, 0.0], intensity: [2.0, 1.0, 1.0] },
                LightSource::Ambient { colour: [0.3; 3] },
            ]
        );
        // Without `lights`, `light` gives the directional source and the ambient one.
        let plain = parse_file("measurements: [image_error]\neffects: { indirect: {} }\nobjects: [{ mesh: plane, diffuse: [1, 1, 1] }]\nlight: { direction: [0, -2, 0], colour: [0.5, 0.5, 0.5], ambient: [0.1, 0.1, 0.1] }\n").unwrap();
        assert_eq!(
            plain.lights,
            vec![LightSource::Directional { direction: [0.0, -2.0, 0.0], colour: [0.5; 3] }, LightSource::Ambient { colour: [0.1; 3] }]
        );
    }

    /// The problem of scene text that must not parse, its message naming `ao.yaml`.
    fn problem(text: &str) -> SceneProblem {
        let error = Scene::parse(text, Path::new("ao.yaml")).unwrap_err();
        assert!(error.to_string().starts_with("scene ao.yaml: "), "{error}");
        *error.problem
    }

    #[test]
    fn surfel_scene_contradictions_name_file_and_field() {
        let diffuse = "objects: [{ mesh: plane, diffuse: [1, 1, 1] }]\nmeasurements: [image_error]\n";
        let ao = "effects: { ambient_occlusion: {} }\n";
        let light_range = Range::Closed { low: 0.0, high: 1e6, each: Each::Whole };
        let fields = [
            // Reflections still need a specular object.
            (format!("{diffuse}effects: {{ reflection: {{ max_depth: 1 }} }}\n"), "objects", FieldProblem::Empty(Listing::SpecularObjects)),
            (
                format!("{diffuse}{ao}lights: [{{ kind: ambient, colour: [1, 1, 1] }}, {{ kind: point, position: [0, 1, 0], intensity: [1, -1, 1] }}]\n"),
                "lights[1].intensity",
                FieldProblem::OutOfRange { value: Value::Vector([1.0, -1.0, 1.0]), range: light_range.clone() },
            ),
            (
                format!("{diffuse}{ao}lights: [{{ kind: point, position: [0, 1e5, 0], intensity: [1, 1, 1] }}]\n"),
                "lights[0].position",
                FieldProblem::OutOfRange { value: Value::Vector([0.0, 1e5, 0.0]), range: Range::Within { bound: 1e4 } },
            ),
            (
                format!("{diffuse}{ao}lights: [{{ kind: directional, direction: [0, 0, 0], colour: [1, 1, 1] }}]\n"),
                "lights[0].direction",
                FieldProblem::ZeroVector { value: [0.0; 3] },
            ),
            (
                format!("{diffuse}{ao}lights: [{{ kind: ambient, colour: [1e7, 0, 0] }}]\n"),
                "lights[0].colour",
                FieldProblem::OutOfRange { value: Value::Vector([1e7, 0.0, 0.0]), range: light_range },
            ),
            ("objects: [{ mesh: sphere, material: a/b/c, method: exact }]\nmeasurements: [image_error]\nlights: []\n".to_string(), "lights", FieldProblem::NeedsEffects),
            (
                "objects: [{ mesh: sphere, material: a/b/c, method: exact, subdivide: 1 }]\nmeasurements: [image_error]\neffects: { reflection: { max_depth: 1 } }\n".to_string(),
                "objects[0].subdivide",
                FieldProblem::NeedsFamily(EffectFamily::Surfels),
            ),
            (
                "objects: [{ mesh: plane, diffuse: [1, 1, 1], subdivide: 9 }]\nmeasurements: [image_error]\neffects: { indirect: {} }\n".to_string(),
                "objects[0].subdivide",
                FieldProblem::OutOfRange { value: Value::Integer(9), range: Range::Integers { low: 0, high: 6 } },
            ),
        ];
        for (text, field, expected) in fields {
            match problem(&text) {
                SceneProblem::Field { field: got_field, kind } => assert_eq!((got_field.as_str(), kind), (field, expected), "{text:?}"),
                other => panic!("{text:?} gave {other:?}"),
            }
        }
        let conflicts = [(
            format!("{diffuse}{ao}light: {{ ambient: [0, 0, 0] }}\nlights: [{{ kind: ambient, colour: [1, 1, 1] }}]\n"),
            Conflict::LightAndLights,
        )];
        for (text, expected) in conflicts {
            assert!(matches!(problem(&text), SceneProblem::Conflict { at, conflict } if at.is_empty() && conflict == expected), "{text:?}");
        }
        for (text, says) in [
            (format!("{diffuse}{ao}lights: [{{ kind: spot, colour: [1, 1, 1] }}]\n"), "unknown variant `spot`"),
            (
                format!("{diffuse}{ao}lights: [{{ kind: point, position: [0, 1, 0], intensity: [1, 1, 1], radius: 2 }}]\n"),
                "unknown field `radius`",
            ),
        ] {
            assert!(matches!(problem(&text), SceneProblem::Syntax(e) if e.to_string().contains(says)), "{text:?}");
        }
        let message =
            parse_file(&format!("{diffuse}{ao}light: {{ ambient: [0, 0, 0] }}\nlights: [{{ kind: ambient, colour: [1, 1, 1] }}]\n"))
                .unwrap_err();
        assert!(
            message.ends_with("light and lights: name the lights once, in `lights` (directional, point, ambient) or in `light`"),
            "{message}"
        );
    }

    #[test]
    fn gtao_presets_parse_with_their_numbers_and_overrides() {
        use crate::scene::gtao::{Heuristics, Preset};
        let configurations = |effects: &str| parse(effects).unwrap().effects.unwrap().ambient_occlusion.unwrap().gtao;
        // XeGTAO High: 3 slices × 3 steps, its defaults, 64 frames of noise.
        let high = configurations("{ ambient_occlusion: { gtao: { preset: xe-high, radius: [0.5, 1] } } }");
        assert_eq!(high.len(), 2);
        assert_eq!((high[0].radius, high[0].slices, high[0].steps, high[0].preset), (0.5, 3, 3, Preset::XeHigh));
        assert_eq!(high[0].heuristics, Heuristics::XE);
        assert_eq!((high[0].heuristics.radius_multiplier, high[0].heuristics.final_power, high[0].heuristics.frames), (1.457, 2.2, 64));
        for (name, slices, steps) in [("xe-low", 1, 2), ("xe-medium", 2, 2), ("xe-ultra", 9, 3), ("bare", 4, 8)] {
            let g = configurations(&format!("{{ ambient_occlusion: {{ gtao: {{ preset: {name} }} }} }}"))[0];
            assert_eq!((g.preset.name(), g.slices, g.steps, g.radius), (name, slices, steps, 1.0));
        }
        // Overrides, and a list of blocks: one configuration per block and radius.
        let list = configurations(
            "{ ambient_occlusion: { gtao: [{ radius: 1 }, { preset: xe-high, radius: [1, 2], frames: 16, thin_occluder: 0.7, steps: 4 }, { radius: 1 }] } }",
        );
        assert_eq!(list.len(), 3);
        assert_eq!(list[0], Gtao::bare(1.0, 4, 8));
        let mut expected = Heuristics::XE;
        expected.frames = 16;
        expected.thin_occluder = 0.7;
        assert_eq!(list[2], Gtao { radius: 2.0, slices: 3, steps: 4, preset: Preset::XeHigh, heuristics: expected });
        assert_eq!(list[1].label(), "xe-high, radius 1, 3×4, 16 frames (modified)");
        // Without noise the frames are all the same: one.
        let quiet = configurations("{ ambient_occlusion: { gtao: { preset: xe-medium, noise: false, frames: 64 } } }");
        assert_eq!((quiet[0].heuristics.noise, quiet[0].heuristics.frames), (false, 1));
        assert!(configurations("{ ambient_occlusion: { gtao: { radius: 1 } } }")[0].heuristics.is_bare());
        // XeGTAO's depth reads clamp to the image's edge; a scene may skip such samples instead.
        let edge = configurations("{ ambient_occlusion: { gtao: [{ preset: xe-high }, { preset: xe-high, clamp_to_edge: false }] } }");
        assert!(edge[0].heuristics.clamp_to_edge && !edge[1].heuristics.clamp_to_edge);
        assert!(!configurations("{ ambient_occlusion: { gtao: { radius: 1 } } }")[0].heuristics.clamp_to_edge);
        assert!(edge[1].label().ends_with("(modified)"), "{}", edge[1].label());
        // XeGTAO denoises once with beta 1.2; a scene may turn it off or soften it.
        let denoised = configurations("{ ambient_occlusion: { gtao: [{ preset: xe-high }, { preset: xe-high, denoise_passes: 3, denoise_beta: 2 }, { radius: 1 }] } }");
        let passes: Vec<(u32, f64)> = denoised.iter().map(|g| (g.heuristics.denoise_passes, g.heuristics.denoise_beta)).collect();
        assert_eq!(passes, [(1, 1.2), (3, 2.0), (0, 1.2)]);
    }

    #[test]
    fn the_shipped_gtao_comparison_scene_names_every_preset() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/ao-bunny-gtao.yaml");
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = Scene::parse(&text, &path).unwrap();
        let gtao = scene.effects.unwrap().ambient_occlusion.unwrap().gtao;
        assert_eq!(gtao[0], Gtao::bare(1.0, 4, 8));
        for preset in crate::scene::gtao::Preset::ALL {
            assert!(gtao.iter().any(|g| g.preset == preset), "{preset:?}");
        }
        assert_eq!(gtao.len(), 10);
    }

    #[test]
    fn gtao_heuristics_name_the_bad_field() {
        let closed = |value: f64, low: f64, high: f64| FieldProblem::OutOfRange {
            value: Value::Number(value),
            range: Range::Closed { low, high, each: crate::scene::Each::Whole },
        };
        let integers = |value: u64, low: u64, high: u64| FieldProblem::OutOfRange {
            value: Value::Integer(value),
            range: Range::Integers { low, high },
        };
        let known = vec!["bare", "xe-low", "xe-medium", "xe-high", "xe-ultra", "unreal"];
        for (gtao, field, expected) in [
            (
                "{ preset: xe-extreme }",
                "effects.ambient_occlusion.gtao.preset",
                FieldProblem::Unknown { what: "GTAO preset", name: "xe-extreme".into(), known: known.clone() },
            ),
            ("{ preset: xe-high, falloff_range: 1.5 }", "effects.ambient_occlusion.gtao.falloff_range", closed(1.5, 0.0, 1.0)),
            ("{ thin_occluder: -0.1 }", "effects.ambient_occlusion.gtao.thin_occluder", closed(-0.1, 0.0, 0.7)),
            ("{ preset: unreal, thickness_blend: 1.5 }", "effects.ambient_occlusion.gtao.thickness_blend", closed(1.5, 0.0, 1.0)),
            ("{ final_power: 9 }", "effects.ambient_occlusion.gtao.final_power", closed(9.0, 0.5, 5.0)),
            ("{ distribution_power: 0.5 }", "effects.ambient_occlusion.gtao.distribution_power", closed(0.5, 1.0, 3.0)),
            ("{ radius_multiplier: 10 }", "effects.ambient_occlusion.gtao.radius_multiplier", closed(10.0, 0.3, 3.0)),
            ("{ normal_lerp: 2 }", "effects.ambient_occlusion.gtao.normal_lerp", closed(2.0, 0.0, 1.0)),
            (
                "{ start_pixels: .nan }",
                "effects.ambient_occlusion.gtao.start_pixels",
                FieldProblem::OutOfRange {
                    value: Value::Number(f64::NAN),
                    range: Range::Closed { low: 0.0, high: 16.0, each: crate::scene::Each::Whole },
                },
            ),
            ("{ max_radius_pixels: 5000 }", "effects.ambient_occlusion.gtao.max_radius_pixels", closed(5000.0, 0.0, 4096.0)),
            (
                "{ min_radius_pixels: 30, max_radius_pixels: 20 }",
                "effects.ambient_occlusion.gtao.min_radius_pixels",
                closed(30.0, 0.0, 20.0),
            ),
            ("{ preset: xe-high, frames: 0 }", "effects.ambient_occlusion.gtao.frames", integers(0, 1, 1024)),
            ("{ preset: xe-high, denoise_passes: 4 }", "effects.ambient_occlusion.gtao.denoise_passes", integers(4, 0, 3)),
            ("{ denoise_beta: 0 }", "effects.ambient_occlusion.gtao.denoise_beta", closed(0.0, 0.01, 10000.0)),
            // 2 × 64 × 256 reads per pixel at most: 64 slices × 256 steps leave one frame.
            ("{ noise: true, slices: 64, steps: 256, frames: 2 }", "effects.ambient_occlusion.gtao.frames", integers(2, 1, 1)),
            ("[{ radius: 1 }, { preset: xe-high, steps: 0 }]", "effects.ambient_occlusion.gtao[1].steps", integers(0, 1, 256)),
            ("[]", "effects.ambient_occlusion.gtao", FieldProblem::Empty(Listing::Values)),
        ] {
            let text = format!(
                "measurements: [image_error]\nobjects:\n  - {{ mesh: plane, diffuse: [1, 1, 1] }}\neffects: {{ ambient_occlusion: {{ gtao: {gtao} }} }}\n"
            );
            match problem(&text) {
                // NaN ≠ NaN: compare the printed form.
                SceneProblem::Field { field: got_field, kind } => {
                    assert_eq!((got_field.as_str(), format!("{kind:?}")), (field, format!("{expected:?}")), "{gtao}")
                }
                other => panic!("{gtao} gave {other:?}"),
            }
        }
        let message = parse("{ ambient_occlusion: { gtao: { preset: xe-extreme } } }").unwrap_err();
        assert!(
            message.ends_with("t.yaml: effects.ambient_occlusion.gtao.preset: unknown GTAO preset \"xe-extreme\"; known: bare, xe-low, xe-medium, xe-high, xe-ultra, unreal"),
            "{message}"
        );
        // A block's own unknown field is named.
        let typo = parse("{ ambient_occlusion: { gtao: [{ preset: xe-high, falloff: 1 }] } }").unwrap_err();
        assert!(typo.contains("unknown field `falloff`"), "{typo}");
    }

    #[test]
    fn surfel_effects_name_the_bad_field() {
        let integers = |value: u64, low: u64, high: u64| FieldProblem::OutOfRange {
            value: Value::Integer(value),
            range: Range::Integers { low, high },
        };
        for (effects, field, expected) in [
            ("{ ambient_occlusion: { passes: 0 } }", "effects.ambient_occlusion.passes", integers(0, 1, 8)),
            ("{ indirect: { bounces: 3 } }", "effects.indirect.bounces", integers(3, 1, 2)),
            ("{ ambient_occlusion: { gtao: { slices: 0 } } }", "effects.ambient_occlusion.gtao.slices", integers(0, 1, 64)),
            ("{ ambient_occlusion: { gtao: { steps: 300 } } }", "effects.ambient_occlusion.gtao.steps", integers(300, 1, 256)),
            (
                "{ ambient_occlusion: { gtao: { radius: [] } } }",
                "effects.ambient_occlusion.gtao.radius",
                FieldProblem::Empty(Listing::Values),
            ),
            (
                "{ ambient_occlusion: { gtao: { radius: -1 } } }",
                "effects.ambient_occlusion.gtao.radius",
                FieldProblem::OutOfRange { value: Value::Number(-1.0), range: Range::AboveUpTo { low: 0.0, high: 100.0 } },
            ),
            ("{ }", "effects", FieldProblem::Empty(Listing::Effects)),
        ] {
            let text = format!(
                "measurements: [image_error]\nobjects:\n  - {{ mesh: sphere, material: a/b/c, method: exact }}\neffects: {effects}\n"
            );
            match problem(&text) {
                SceneProblem::Field { field: got_field, kind } => assert_eq!((got_field.as_str(), kind), (field, expected), "{effects}"),
                other => panic!("{effects} gave {other:?}"),
            }
        }
        let passes = parse("{ ambient_occlusion: { passes: 0 } }").unwrap_err();
        assert!(passes.ends_with("t.yaml: effects.ambient_occlusion.passes 0 must lie in 1..=8"), "{passes}");
        assert!(parse("{ ambient_occlusion: { rays: 2 } }").unwrap_err().contains("unknown field `rays`"));
    }
}
