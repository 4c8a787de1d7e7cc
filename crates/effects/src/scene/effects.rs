//! The `effects` section of a scene: which light-transport effects the scene calls for
//! (multiple reflections, multiple refractions), how deep each may go, and how the
//! distance maps that trace them on the GPU are sized and searched (Umenhoffer, Patow and
//! Szirmay-Kalos, "Robust Multiple Specular Reflections and Refractions", GPU Gems 3
//! ch. 17); the diffuse surroundings' colours and patterns, and the one directional light
//! plus ambient that lights them (docs/effects.md). Pure data and checks.
//!
//! ```yaml
//! effects:
//!   reflection: { max_depth: [1, 2, 3] }   # one depth, or several to compare
//!   refraction: { max_depth: 2 }
//!   distance_maps: { size: 256, layers: 3, linear_steps: [15, 80], secant_steps: [1, 10] }
//! light: { direction: [-0.3, -1, -0.5], colour: [1, 1, 1], ambient: [0.2, 0.2, 0.2] }
//! ```

use serde::Deserialize;

use super::error::{Each, FieldProblem, Listing, Range, SceneProblem, Value};

/// A number or a list of numbers in a scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum Numbers {
    One(u32),
    Many(Vec<u32>),
}

impl Numbers {
    /// Sorted, distinct values.
    fn values(&self) -> Vec<u32> {
        let mut values = match self {
            Numbers::One(value) => vec![*value],
            Numbers::Many(values) => values.clone(),
        };
        values.sort_unstable();
        values.dedup();
        values
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBounces {
    max_depth: Numbers,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDistanceMaps {
    #[serde(default = "default_map_size")]
    size: u32,
    #[serde(default = "default_layers")]
    layers: u32,
    #[serde(default = "default_linear_steps")]
    linear_steps: Numbers,
    #[serde(default = "default_secant_steps")]
    secant_steps: Numbers,
}

fn default_map_size() -> u32 {
    256
}
fn default_layers() -> u32 {
    3
}
fn default_linear_steps() -> Numbers {
    Numbers::One(15)
}
fn default_secant_steps() -> Numbers {
    Numbers::One(1)
}

impl Default for RawDistanceMaps {
    fn default() -> Self {
        Self {
            size: default_map_size(),
            layers: default_layers(),
            linear_steps: default_linear_steps(),
            secant_steps: default_secant_steps(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEffects {
    reflection: Option<RawBounces>,
    refraction: Option<RawBounces>,
    #[serde(default)]
    distance_maps: RawDistanceMaps,
    ambient_occlusion: Option<super::surfels::RawAmbientOcclusion>,
    indirect: Option<super::surfels::RawIndirect>,
    metres_per_unit: Option<f64>,
    spectral: Option<RawSpectral>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpectral {
    wavelengths: u32,
}

/// The most wavelengths of a spectral frame: the weighted 1 nm samples of `colors`
/// (360–780 nm).
pub const MAX_WAVELENGTHS: u32 = 421;

/// The spectral reference (`effects.spectral`): the f64 reference traced per wavelength on
/// `wavelengths` bins of the 1 nm grid of `colors`, measured against the three-channel
/// reference (`spectral_errors`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Spectral {
    pub wavelengths: u32,
}

/// The range of `metres_per_unit`: a nanometre to a kilometre per scene unit.
pub const METRES_PER_UNIT_RANGE: (f64, f64) = (1e-9, 1e3);

/// The deepest path a scene may ask for: every extra bounce multiplies the cost of a frame.
pub const MAX_DEPTH: u32 = 8;

/// How many specular bounces one effect may take along a path, one value per configuration
/// to measure (sorted, distinct, each in 1..=[`MAX_DEPTH`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bounces {
    pub max_depth: Vec<u32>,
}

/// One configuration of depths: at most `reflection` reflections and `refraction`
/// refractions along a path (0: the effect is not named). A path ends black when it is
/// still on a specular surface and neither effect has a bounce left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Depths {
    pub reflection: u32,
    pub refraction: u32,
}

/// One configuration of the distance-map search: `linear` steps along the ray, then
/// `secant` refinements between the last two.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SearchSteps {
    pub linear: u32,
    pub secant: u32,
}

/// The layered distance maps: cube maps of `size`×`size` texels per face, `layers` layers
/// (the specular objects' peeled surfaces in all but the last, the diffuse surroundings in
/// the last), and the search configurations to measure.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DistanceMaps {
    pub size: u32,
    pub layers: u32,
    pub steps: Vec<SearchSteps>,
}

/// The effects a scene calls for: at least one of `reflection`, `refraction`,
/// `ambient_occlusion`, `indirect` is named (an AO-only scene is valid).
#[derive(Clone, Debug, PartialEq)]
pub struct Effects {
    pub reflection: Option<Bounces>,
    pub refraction: Option<Bounces>,
    pub distance_maps: DistanceMaps,
    /// Surfel ambient occlusion (`super::surfels`).
    pub ambient_occlusion: Option<super::surfels::AmbientOcclusion>,
    /// Surfel indirect light (`super::surfels`).
    pub indirect: Option<super::surfels::Indirect>,
    /// The length of one scene unit in metres (`metres_per_unit`, default 1): Beer–Lambert
    /// attenuation inside a dielectric, e^(−4πkd/λ), needs the path length d in metres.
    pub metres_per_unit: f64,
    /// The spectral reference and its comparison with the three-channel one.
    pub spectral: Option<Spectral>,
}

/// The families of effects a scene can name, each built by its own parts (its settings
/// here, its CPU computation and reference, its GPU pass, its tables): the one list every
/// stage dispatches on. A family added here is a compile error at each `match` over it —
/// the scene's [`Effects::names`], the effects stage's memory check and run — until it is
/// handled there (docs/extending.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EffectFamily {
    /// Multiple specular reflections and refractions through layered distance maps
    /// (`reflection`, `refraction`, with `distance_maps`).
    SpecularPaths,
    /// Surfel ambient occlusion and indirect light (`ambient_occlusion`, `indirect`).
    Surfels,
}

impl EffectFamily {
    /// Every family, in the order the stages run them. [`EffectFamily::index`] holds the
    /// list complete: a family left out of it fails the build.
    pub const ALL: [EffectFamily; 2] = [EffectFamily::SpecularPaths, EffectFamily::Surfels];

    /// The family's position in [`EffectFamily::ALL`]: one arm per family, each a constant
    /// evaluated when the crate is built, which does not compile until the family is in
    /// `ALL` (write a new arm as the others).
    pub const fn index(self) -> usize {
        match self {
            EffectFamily::SpecularPaths => const { EffectFamily::position(EffectFamily::SpecularPaths) },
            EffectFamily::Surfels => const { EffectFamily::position(EffectFamily::Surfels) },
        }
    }

    /// Where `family` is in [`EffectFamily::ALL`]; evaluated at build time by
    /// [`EffectFamily::index`].
    const fn position(family: EffectFamily) -> usize {
        let mut i = 0;
        while i < EffectFamily::ALL.len() {
            if EffectFamily::ALL[i] as u8 == family as u8 {
                return i;
            }
            i += 1;
        }
        panic!("an EffectFamily is missing from EffectFamily::ALL")
    }

    /// The keys of a scene's `effects` section that name the family.
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            EffectFamily::SpecularPaths => &["reflection", "refraction"],
            EffectFamily::Surfels => &["ambient_occlusion", "indirect"],
        }
    }

    /// The family in words, as messages name it.
    pub fn description(self) -> &'static str {
        match self {
            EffectFamily::SpecularPaths => "specular path effects",
            EffectFamily::Surfels => "surfel effects",
        }
    }
}

// Each family is in `EffectFamily::ALL` once: its entry is at its own index.
const _: () = {
    let mut i = 0;
    while i < EffectFamily::ALL.len() {
        assert!(EffectFamily::ALL[i].index() == i, "EffectFamily::ALL lists a family twice");
        i += 1;
    }
};

impl Effects {
    /// Whether the scene names any effect of `family`.
    pub fn names(&self, family: EffectFamily) -> bool {
        match family {
            EffectFamily::SpecularPaths => self.reflection.is_some() || self.refraction.is_some(),
            EffectFamily::Surfels => self.ambient_occlusion.is_some() || self.indirect.is_some(),
        }
    }
}

impl RawBounces {
    fn bounces(&self, field: &str) -> Result<Bounces, SceneProblem> {
        let max_depth = self.max_depth.values();
        check_counts(&format!("{field}.max_depth"), &max_depth, 1, MAX_DEPTH)?;
        Ok(Bounces { max_depth })
    }
}

impl RawEffects {
    /// The checked section, or what is wrong (without the `effects.` prefix).
    pub(crate) fn effects(self) -> Result<Effects, SceneProblem> {
        let reflection = self.reflection.as_ref().map(|r| r.bounces("reflection")).transpose()?;
        let refraction = self.refraction.as_ref().map(|r| r.bounces("refraction")).transpose()?;
        let ambient_occlusion = self.ambient_occlusion.as_ref().map(|a| a.checked()).transpose()?;
        let indirect = self.indirect.as_ref().map(|i| i.checked()).transpose()?;
        if reflection.is_none() && refraction.is_none() && ambient_occlusion.is_none() && indirect.is_none() {
            // Seen from the file this is `effects: name at least one effect: …`.
            return Err(SceneProblem::Field { field: String::new(), kind: FieldProblem::Empty(Listing::Effects) });
        }
        let maps = &self.distance_maps;
        let out_of_range = |field: &str, value: u32, range: Range| {
            SceneProblem::field(field, FieldProblem::OutOfRange { value: Value::Integer(value.into()), range })
        };
        if !(4..=4096).contains(&maps.size) {
            return Err(out_of_range("distance_maps.size", maps.size, Range::Integers { low: 4, high: 4096 }));
        }
        if !(2..=8).contains(&maps.layers) {
            return Err(out_of_range("distance_maps.layers", maps.layers, Range::Layers { low: 2, high: 8 }));
        }
        let linear = maps.linear_steps.values();
        let secant = maps.secant_steps.values();
        check_counts("distance_maps.linear_steps", &linear, 1, 1024)?;
        check_counts("distance_maps.secant_steps", &secant, 0, 64)?;
        let steps = linear.iter().flat_map(|&linear| secant.iter().map(move |&secant| SearchSteps { linear, secant })).collect();
        let metres_per_unit = self.metres_per_unit.unwrap_or(1.0);
        if !(METRES_PER_UNIT_RANGE.0..=METRES_PER_UNIT_RANGE.1).contains(&metres_per_unit) {
            let range = Range::Closed { low: METRES_PER_UNIT_RANGE.0, high: METRES_PER_UNIT_RANGE.1, each: Each::Whole };
            return Err(SceneProblem::field("metres_per_unit", FieldProblem::OutOfRange { value: Value::Number(metres_per_unit), range }));
        }
        let spectral = match &self.spectral {
            None => None,
            Some(raw) => {
                if reflection.is_none() && refraction.is_none() {
                    return Err(SceneProblem::field("spectral", FieldProblem::NeedsFamily(EffectFamily::SpecularPaths)));
                }
                check_counts("spectral.wavelengths", &[raw.wavelengths], 1, MAX_WAVELENGTHS)?;
                Some(Spectral { wavelengths: raw.wavelengths })
            }
        };
        Ok(Effects {
            metres_per_unit,
            spectral,
            reflection,
            refraction,
            distance_maps: DistanceMaps { size: maps.size, layers: maps.layers, steps },
            ambient_occlusion,
            indirect,
        })
    }
}

impl Effects {
    /// Every configuration of depths to measure: the product of the named effects' depths.
    pub fn depths(&self) -> Vec<Depths> {
        let list = |bounces: &Option<Bounces>| bounces.as_ref().map(|b| b.max_depth.clone()).unwrap_or_else(|| vec![0]);
        let refraction = list(&self.refraction);
        list(&self.reflection)
            .into_iter()
            .flat_map(|reflection| refraction.iter().map(move |&refraction| Depths { reflection, refraction }))
            .collect()
    }
}

/// A diffuse surface's albedo pattern over scene positions, e.g.
/// `pattern: { kind: checker, size: 0.5, albedo: [0.1, 0.1, 0.1] }`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Pattern {
    /// The object's `diffuse` albedo everywhere.
    Plain,
    /// A checkerboard of squares of edge `size` across the surface: with (u, v) the two
    /// coordinates other than the normal's largest component, cells where ⌊u/size⌋ +
    /// ⌊v/size⌋ is odd take `albedo`, the others the object's `diffuse`. (A 3D checker would
    /// flip on a wall that lies on a cell boundary, as the walls of a room do.)
    Checker { size: f64, albedo: [f64; 3] },
    /// A linear ramp along `axis`: the object's `diffuse` where p·axis = −1, `albedo` where
    /// p·axis = 1, clamped beyond (the axis's length sets how fast it ramps).
    Gradient { axis: [f64; 3], albedo: [f64; 3] },
}

/// A diffuse surface: an albedo (linear RGB in [0, 1]) and its pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct Diffuse {
    pub albedo: [f64; 3],
    pub pattern: Pattern,
}

/// A list of counts (sorted, distinct) that must be non-empty with each in `low..=high`.
fn check_counts(field: &str, values: &[u32], low: u32, high: u32) -> Result<(), SceneProblem> {
    if values.is_empty() || values.iter().any(|v| !(low..=high).contains(v)) {
        let range = Range::Integers { low: low.into(), high: high.into() };
        return Err(SceneProblem::field(field, FieldProblem::OutOfRange { value: Value::Integers(values.to_vec()), range }));
    }
    Ok(())
}

fn check_albedo(field: &str, albedo: [f64; 3]) -> Result<(), SceneProblem> {
    if albedo.iter().all(|a| (0.0..=1.0).contains(a)) {
        Ok(())
    } else {
        let range = Range::Closed { low: 0.0, high: 1.0, each: Each::Channel };
        Err(SceneProblem::field(field, FieldProblem::OutOfRange { value: Value::Vector(albedo), range }))
    }
}

pub(crate) fn length(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl Diffuse {
    pub(crate) fn check(&self) -> Result<(), SceneProblem> {
        check_albedo("diffuse", self.albedo)?;
        match &self.pattern {
            Pattern::Plain => Ok(()),
            Pattern::Checker { size, albedo } => {
                if !(size.is_finite() && *size > 0.0) {
                    let kind = FieldProblem::OutOfRange { value: Value::Number(*size), range: Range::Positive };
                    return Err(SceneProblem::field("pattern.checker.size", kind));
                }
                check_albedo("pattern.checker.albedo", *albedo)
            }
            Pattern::Gradient { axis, albedo } => {
                if !(length(*axis) > 1e-9 && axis.iter().all(|a| a.is_finite())) {
                    return Err(SceneProblem::field("pattern.gradient.axis", FieldProblem::ZeroVector { value: *axis }));
                }
                check_albedo("pattern.gradient.albedo", *albedo)
            }
        }
    }

    /// The albedo at scene position `p` of a surface with normal `normal`.
    pub fn albedo_at(&self, p: [f64; 3], normal: [f64; 3]) -> [f64; 3] {
        match &self.pattern {
            Pattern::Plain => self.albedo,
            Pattern::Checker { size, albedo } => {
                let across = (0..3).max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs())).unwrap_or(2);
                let cells: i64 = (0..3).filter(|&i| i != across).map(|i| (p[i] / size).floor() as i64).sum();
                if cells.rem_euclid(2) == 1 {
                    *albedo
                } else {
                    self.albedo
                }
            }
            Pattern::Gradient { axis, albedo } => {
                let along = p[0] * axis[0] + p[1] * axis[1] + p[2] * axis[2];
                let w = (0.5 * (along + 1.0)).clamp(0.0, 1.0);
                std::array::from_fn(|i| self.albedo[i] + w * (albedo[i] - self.albedo[i]))
            }
        }
    }
}

/// A light colour, ambient term or intensity: each channel in [0, [`super::MAX_LIGHT`]].
pub(crate) fn check_light_term(field: &str, value: [f64; 3]) -> Result<(), SceneProblem> {
    if value.iter().all(|v| v.is_finite() && *v >= 0.0 && *v <= super::MAX_LIGHT) {
        Ok(())
    } else {
        let range = Range::Closed { low: 0.0, high: super::MAX_LIGHT, each: Each::Whole };
        Err(SceneProblem::field(field, FieldProblem::OutOfRange { value: Value::Vector(value), range }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_by_cell_parity() {
        let surface = Diffuse { albedo: [1.0; 3], pattern: Pattern::Checker { size: 0.5, albedo: [0.0; 3] } };
        let up = [0.0, 1.0, 0.0];
        assert_eq!(surface.albedo_at([0.1, 0.1, 0.1], up), [1.0; 3]); // cells (x, z) = (0, 0): even
        assert_eq!(surface.albedo_at([0.6, 0.1, 0.1], up), [0.0; 3]); // (1, 0): odd
        assert_eq!(surface.albedo_at([-0.1, 0.1, 0.1], up), [0.0; 3]); // (−1, 0): odd
        assert_eq!(surface.albedo_at([0.6, 0.1, 0.6], up), [1.0; 3]); // (1, 1): even
                                                                      // A floor on a cell boundary (y = −2 = −4 cells) reads the same just above and below.
        assert_eq!(surface.albedo_at([0.1, -2.0 + 1e-12, 0.1], up), surface.albedo_at([0.1, -2.0 - 1e-12, 0.1], up));
        // On a wall facing x the cells run over (y, z).
        assert_eq!(surface.albedo_at([3.0, 0.6, 0.1], [-0.9, 0.3, 0.1]), [0.0; 3]);
    }

    #[test]
    fn gradient_runs_from_diffuse_to_albedo_along_the_axis() {
        let surface = Diffuse { albedo: [0.0, 0.2, 1.0], pattern: Pattern::Gradient { axis: [0.0, 2.0, 0.0], albedo: [1.0, 0.2, 0.0] } };
        assert_eq!(surface.albedo_at([5.0, -1.0, 3.0], [0.0, 1.0, 0.0]), [0.0, 0.2, 1.0]);
        assert_eq!(surface.albedo_at([5.0, 0.0, 3.0], [0.0, 1.0, 0.0]), [0.5, 0.2, 0.5]);
        assert_eq!(surface.albedo_at([0.0, 7.0, 0.0], [0.0, 1.0, 0.0]), [1.0, 0.2, 0.0]);
    }

    #[test]
    fn depth_configurations_are_the_product_of_the_named_effects() {
        let effects = RawEffects {
            reflection: Some(RawBounces { max_depth: Numbers::Many(vec![3, 1, 3]) }),
            refraction: None,
            distance_maps: RawDistanceMaps {
                linear_steps: Numbers::Many(vec![80, 15]),
                secant_steps: Numbers::Many(vec![10, 1]),
                ..Default::default()
            },
            ambient_occlusion: None,
            indirect: None,
            metres_per_unit: None,
            spectral: None,
        }
        .effects()
        .unwrap();
        assert_eq!(effects.depths(), vec![Depths { reflection: 1, refraction: 0 }, Depths { reflection: 3, refraction: 0 }]);
        let steps: Vec<(u32, u32)> = effects.distance_maps.steps.iter().map(|s| (s.linear, s.secant)).collect();
        assert_eq!(steps, vec![(15, 1), (15, 10), (80, 1), (80, 10)]);
    }
}
