//! The scene's lights, one model for every effect: a list of directional, point and
//! ambient sources (`lights`), or the shorthand `light` — one directional light and an
//! ambient term, the default. Light is in radiance scale: a white diffuse surface facing a
//! directional light of colour c shows c. The surfel effects shadow directional and point
//! light by ray casting and darken ambient light by accessibility; the surroundings the
//! distance maps store are lit without shadows ([`unshadowed`], so a map is the same from
//! every viewpoint), the f32 twin being `diffuse_lit` of `shaders/diffuse.wgsl`.
//!
//! ```yaml
//! lights:
//!   - { kind: directional, direction: [-0.3, -1, -0.5], colour: [0.8, 0.8, 0.8] }
//!   - { kind: point, position: [0, 2, 1], intensity: [2, 2, 2] }
//!   - { kind: ambient, colour: [0.3, 0.3, 0.3] }
//! light: { direction: [-0.3, -1, -0.5], colour: [0.8, 0.8, 0.8], ambient: [0.2, 0.2, 0.2] }
//! ```

use serde::Deserialize;

use super::effects::{check_light_term, length};
use super::error::{FieldProblem, Range, SceneProblem, Value};

/// The most lights a scene may name (the GPU passes hold them in one uniform block).
pub const MAX_LIGHTS: usize = 8;

/// One light of the scene.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightSource {
    /// Parallel light travelling along `direction`: `colour` × max(0, −n·d̂), shadowed.
    Directional { direction: [f64; 3], colour: [f64; 3] },
    /// Light from the point `position`: `intensity` × max(0, n·l̂) / d² at distance d
    /// (inverse square), shadowed.
    Point { position: [f64; 3], intensity: [f64; 3] },
    /// Light from the whole sky: `colour` × accessibility (what ambient occlusion darkens).
    Ambient { colour: [f64; 3] },
}

impl LightSource {
    pub(crate) fn check(&self) -> Result<(), SceneProblem> {
        match self {
            LightSource::Directional { direction, colour } => {
                if !(direction.iter().all(|x| x.is_finite()) && direction.iter().map(|x| x * x).sum::<f64>() > 1e-18) {
                    return Err(SceneProblem::field("direction", FieldProblem::ZeroVector { value: *direction }));
                }
                check_light_term("colour", *colour)
            }
            LightSource::Point { position, intensity } => {
                if !position.iter().all(|x| x.abs() <= super::MAX_COORDINATE) {
                    let range = Range::Within { bound: super::MAX_COORDINATE };
                    return Err(SceneProblem::field("position", FieldProblem::OutOfRange { value: Value::Vector(*position), range }));
                }
                check_light_term("intensity", *intensity)
            }
            LightSource::Ambient { colour } => check_light_term("colour", *colour),
        }
    }
}

/// The shorthand `light`: one directional light travelling along `direction` with
/// radiance-scale `colour`, plus `ambient` ([`Light::sources`]).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    #[serde(default = "default_light_direction")]
    pub direction: [f64; 3],
    #[serde(default = "default_light_colour")]
    pub colour: [f64; 3],
    #[serde(default = "default_ambient")]
    pub ambient: [f64; 3],
}

fn default_light_direction() -> [f64; 3] {
    [-0.3, -1.0, -0.5]
}
fn default_light_colour() -> [f64; 3] {
    [0.8, 0.8, 0.8]
}
fn default_ambient() -> [f64; 3] {
    [0.2, 0.2, 0.2]
}

impl Default for Light {
    fn default() -> Self {
        Self { direction: default_light_direction(), colour: default_light_colour(), ambient: default_ambient() }
    }
}

impl Light {
    pub(crate) fn check(&self) -> Result<(), SceneProblem> {
        if !(length(self.direction) > 1e-9 && self.direction.iter().all(|a| a.is_finite())) {
            return Err(SceneProblem::field("direction", FieldProblem::ZeroVector { value: self.direction }));
        }
        check_light_term("colour", self.colour)?;
        check_light_term("ambient", self.ambient)
    }

    /// The lights it stands for.
    pub fn sources(&self) -> Vec<LightSource> {
        vec![LightSource::Directional { direction: self.direction, colour: self.colour }, LightSource::Ambient { colour: self.ambient }]
    }
}

/// Radiance leaving a diffuse point at `point` of albedo `albedo` and unit normal `normal`
/// under `lights`, unshadowed: ρ·Σ (directional: colour·max(0, −N·d̂); point:
/// intensity·max(0, N·l̂)/|l|², l from the point to the light, nothing at |l| = 0; ambient:
/// colour).
pub fn unshadowed(lights: &[LightSource], albedo: [f64; 3], point: [f64; 3], normal: [f64; 3]) -> [f64; 3] {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut sum = [0.0; 3];
    for light in lights {
        let (colour, weight) = match light {
            LightSource::Directional { direction, colour } => (colour, (-dot(normal, *direction) / length(*direction)).max(0.0)),
            LightSource::Point { position, intensity } => {
                let l = [position[0] - point[0], position[1] - point[1], position[2] - point[2]];
                let d2 = dot(l, l);
                (intensity, if d2 > 0.0 { (dot(normal, l) / d2.sqrt()).max(0.0) / d2 } else { 0.0 })
            }
            LightSource::Ambient { colour } => (colour, 1.0),
        };
        for c in 0..3 {
            sum[c] += colour[c] * weight;
        }
    }
    std::array::from_fn(|c| albedo[c] * sum[c])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-derived radiance: a white point facing up under each kind of light.
    #[test]
    fn each_kind_of_light_lights_as_its_formula() {
        let up = [0.0, 1.0, 0.0];
        let white = [1.0; 3];
        // Directional along (0, −1, −1)/√2: cos 45° = 1/√2.
        let tilted = [LightSource::Directional { direction: [0.0, -2.0, -2.0], colour: [0.5, 1.0, 2.0] }];
        let r = unshadowed(&tilted, white, [0.0; 3], up);
        for (c, want) in [0.5, 1.0, 2.0].iter().enumerate() {
            assert!((r[c] - want / 2f64.sqrt()).abs() < 1e-15, "{r:?}");
        }
        // A point light 2 above and 2 across: cos = 1/√2 at distance² 8.
        let point = [LightSource::Point { position: [2.0, 2.0, 0.0], intensity: [8.0; 3] }];
        let r = unshadowed(&point, [0.5; 3], [0.0; 3], up);
        assert!((r[0] - 0.5 / 2f64.sqrt()).abs() < 1e-15, "{r:?}");
        // Behind the surface, at the point itself: nothing. Ambient adds its colour.
        let behind = [
            LightSource::Point { position: [0.0, -1.0, 0.0], intensity: [1.0; 3] },
            LightSource::Point { position: [0.0; 3], intensity: [1.0; 3] },
        ];
        assert_eq!(unshadowed(&behind, white, [0.0; 3], up), [0.0; 3]);
        let ambient = [LightSource::Ambient { colour: [0.25; 3] }];
        assert_eq!(unshadowed(&ambient, [0.5; 3], [3.0; 3], up), [0.125; 3]);
    }

    #[test]
    fn light_is_lambert_plus_ambient() {
        let light = Light { direction: [0.0, -2.0, 0.0], colour: [0.5, 1.0, 1.0], ambient: [0.1, 0.0, 0.2] };
        // Facing the light: ρ(ambient + colour); 60° away: cos = ½; facing away: ambient only.
        assert_eq!(unshadowed(&light.sources(), [1.0, 0.5, 1.0], [0.0; 3], [0.0, 1.0, 0.0]), [0.6, 0.5, 1.2]);
        let tilted = [3f64.sqrt() / 2.0, 0.5, 0.0];
        let shaded = unshadowed(&light.sources(), [1.0; 3], [0.0; 3], tilted);
        assert!((shaded[1] - 0.5).abs() < 1e-15 && (shaded[0] - 0.35).abs() < 1e-15);
        assert_eq!(unshadowed(&light.sources(), [1.0; 3], [0.0; 3], [0.0, -1.0, 0.0]), [0.1, 0.0, 0.2]);
    }

    /// The shorthand is one directional light and an ambient term: ρ·(ambient + colour·cos).
    #[test]
    fn the_shorthand_is_a_directional_light_and_ambient() {
        let light = Light { direction: [0.0, -1.0, 0.0], colour: [0.8; 3], ambient: [0.2; 3] };
        assert_eq!(unshadowed(&light.sources(), [0.5; 3], [0.0; 3], [0.0, 1.0, 0.0]), [0.5; 3]);
        assert_eq!(unshadowed(&light.sources(), [0.5; 3], [0.0; 3], [0.0, -1.0, 0.0]), [0.1; 3]);
    }
}
