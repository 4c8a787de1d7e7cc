//! The surfel effects a scene may call for inside `effects`: ambient occlusion (how many
//! passes, whether through the surfel hierarchy, whether to light with bent normals) and
//! diffuse indirect light (how many bounces), after Bunnell (GPU Gems 2 ch. 14; the method
//! and its measurements in `crate::effects::ao`). Lights and diffuse albedo are the scene's
//! `light` and the objects' `diffuse`. Pure data and checks.
//!
//! ```yaml
//! effects:
//!   ambient_occlusion: { passes: 2, hierarchy: true, bent_normals: true }
//!   indirect: { bounces: 1 }
//! ```

use serde::Deserialize;

/// The most passes a scene may ask for (each is a full gather; they converge by 3 or 4).
pub const MAX_PASSES: u32 = 8;
/// The most bounces of indirect light.
pub const MAX_BOUNCES: u32 = 2;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawAmbientOcclusion {
    #[serde(default = "default_passes")]
    passes: u32,
    #[serde(default)]
    hierarchy: bool,
    #[serde(default)]
    bent_normals: bool,
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
/// force, lighting with bent normals or the normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AmbientOcclusion {
    pub passes: u32,
    pub hierarchy: bool,
    pub bent_normals: bool,
}

/// Diffuse indirect light from surfels: `bounces` in 1..=[`MAX_BOUNCES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Indirect {
    pub bounces: u32,
}

impl RawAmbientOcclusion {
    pub(crate) fn checked(&self) -> Result<AmbientOcclusion, String> {
        if !(1..=MAX_PASSES).contains(&self.passes) {
            return Err(format!("ambient_occlusion.passes {} must lie in 1..={MAX_PASSES}", self.passes));
        }
        Ok(AmbientOcclusion { passes: self.passes, hierarchy: self.hierarchy, bent_normals: self.bent_normals })
    }
}

impl RawIndirect {
    pub(crate) fn checked(&self) -> Result<Indirect, String> {
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            return Err(format!("indirect.bounces {} must lie in 1..={MAX_BOUNCES}", self.bounces));
        }
        Ok(Indirect { bounces: self.bounces })
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;
    use std::path::Path;

    use super::{AmbientOcclusion, Indirect};

    fn parse(effects: &str) -> Result<Scene, String> {
        let text = format!("measurements: [image_error]\nobjects:\n  - {{ mesh: sphere, material: a/b/c, method: exact }}\n  - {{ mesh: plane, diffuse: [0.8, 0.8, 0.8] }}\neffects: {effects}\n");
        Scene::parse(&text, Path::new("t.yaml")).map_err(|e| e.to_string())
    }

    #[test]
    fn surfel_effects_parse_with_defaults_and_alone() {
        let scene = parse("{ ambient_occlusion: { passes: 3, hierarchy: true }, indirect: {} }").unwrap();
        let effects = scene.effects.unwrap();
        assert_eq!(effects.ambient_occlusion, Some(AmbientOcclusion { passes: 3, hierarchy: true, bent_normals: false }));
        assert_eq!(effects.indirect, Some(Indirect { bounces: 1 }));
        assert_eq!((effects.reflection, effects.refraction), (None, None));
        let plain = parse("{ reflection: { max_depth: 1 } }").unwrap().effects.unwrap();
        assert_eq!((plain.ambient_occlusion, plain.indirect), (None, None));
    }

    #[test]
    fn surfel_effects_name_the_bad_field() {
        let passes = parse("{ ambient_occlusion: { passes: 0 } }").unwrap_err();
        assert!(passes.contains("t.yaml") && passes.contains("effects.ambient_occlusion.passes 0"), "{passes}");
        let bounces = parse("{ indirect: { bounces: 3 } }").unwrap_err();
        assert!(bounces.contains("effects.indirect.bounces 3"), "{bounces}");
        assert!(parse("{ ambient_occlusion: { rays: 2 } }").unwrap_err().contains("rays"));
        assert!(parse("{ }").unwrap_err().contains("name at least one effect"));
    }
}
