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
//! ```yaml
//! effects:
//!   ambient_occlusion: { passes: 2, hierarchy: true, bent_normals: true,
//!                        gtao: { radius: 0.5, slices: 4, steps: 8 } }
//!   indirect: { bounces: 1 }
//! lights:
//!   - { kind: directional, direction: [-0.3, -1, -0.5], colour: [0.8, 0.8, 0.8] }
//!   - { kind: point, position: [0, 2, 1], intensity: [2, 2, 2] }
//!   - { kind: ambient, colour: [0.3, 0.3, 0.3] }
//! ```

use serde::Deserialize;

use super::error::{FieldProblem, Range, SceneProblem, Value};

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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawAmbientOcclusion {
    #[serde(default = "default_passes")]
    passes: u32,
    #[serde(default)]
    hierarchy: bool,
    #[serde(default)]
    bent_normals: bool,
    #[serde(default)]
    gtao: Option<RawGtao>,
}

/// One radius or a list of them (each a GTAO configuration, in the order written).
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum Radii {
    One(f64),
    Many(Vec<f64>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGtao {
    #[serde(default = "default_gtao_radius")]
    radius: Radii,
    #[serde(default = "default_gtao_slices")]
    slices: u32,
    #[serde(default = "default_gtao_steps")]
    steps: u32,
}

fn default_gtao_radius() -> Radii {
    Radii::One(1.0)
}

fn default_gtao_slices() -> u32 {
    4
}

fn default_gtao_steps() -> u32 {
    8
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

/// Screen-space GTAO's parameters: occluders within `radius` (scene units) of the shaded
/// point count, searched along `slices` directions per pixel with `steps` G-buffer reads
/// on each side (defaults 1.0, 4, 8). `radius` may be a list: one configuration each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gtao {
    pub radius: f64,
    pub slices: u32,
    pub steps: u32,
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
        let gtao = self.gtao.as_ref().map(RawGtao::checked).transpose()?.unwrap_or_default();
        Ok(AmbientOcclusion { passes: self.passes, hierarchy: self.hierarchy, bent_normals: self.bent_normals, gtao })
    }
}

impl RawGtao {
    fn checked(&self) -> Result<Vec<Gtao>, SceneProblem> {
        let mut radii = match &self.radius {
            Radii::One(r) => vec![*r],
            Radii::Many(list) => list.clone(),
        };
        if radii.is_empty() {
            return Err(SceneProblem::field("ambient_occlusion.gtao.radius", FieldProblem::Empty(super::error::Listing::Values)));
        }
        for &radius in &radii {
            if !(radius > 0.0 && radius <= MAX_GTAO_RADIUS) {
                let range = Range::AboveUpTo { low: 0.0, high: MAX_GTAO_RADIUS };
                let kind = FieldProblem::OutOfRange { value: Value::Number(radius), range };
                return Err(SceneProblem::field("ambient_occlusion.gtao.radius", kind));
            }
        }
        let mut seen = Vec::new();
        radii.retain(|r| {
            let fresh = !seen.contains(r);
            seen.push(*r);
            fresh
        });
        for (field, value, high) in [("slices", self.slices, MAX_GTAO_SLICES), ("steps", self.steps, MAX_GTAO_STEPS)] {
            if !(1..=high).contains(&value) {
                let range = Range::Integers { low: 1, high: high.into() };
                let kind = FieldProblem::OutOfRange { value: Value::Integer(value.into()), range };
                return Err(SceneProblem::field(format!("ambient_occlusion.gtao.{field}"), kind));
            }
        }
        Ok(radii.into_iter().map(|radius| Gtao { radius, slices: self.slices, steps: self.steps }).collect())
    }
}

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
        assert_eq!(gtao.ambient_occlusion.unwrap().gtao, [Gtao { radius: 0.5, slices: 4, steps: 12 }]);
        // A list of radii: one configuration each, in the order written, repeats dropped.
        let radii = parse("{ ambient_occlusion: { gtao: { radius: [2, 0.5, 2] } } }").unwrap().effects.unwrap();
        let configurations = radii.ambient_occlusion.unwrap().gtao;
        assert_eq!(configurations, [Gtao { radius: 2.0, slices: 4, steps: 8 }, Gtao { radius: 0.5, slices: 4, steps: 8 }]);
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
