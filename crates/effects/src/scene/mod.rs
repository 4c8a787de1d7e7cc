//! Scene files: which objects to render, with which material and Fresnel method or with which
//! diffuse colour, the camera path of the image-error measurement (docs/precision.md), which
//! experiments to run and, optionally, which light-transport effects the scene calls for
//! (`effects`: multiple reflections and refractions traced in layered distance maps). Plain
//! serde_yaml and pure data; lives outside the `gpu` feature so scene files can be checked,
//! and the CPU tracers of `crate` run, without wgpu.
//!
//! ```yaml
//! resolution: [512, 512]          # image-error render targets (width, height)
//! camera: { axis: [1, 1, 1], distance: 2.0, frames: 180, degrees_per_frame: 1.0, fov_y_degrees: 60 }
//! objects:
//!   - { mesh: cube, material: 3d/metals/gold, methods: [schlick, lazanyi] }
//!   - { mesh: ../shared/meshes/nefertiti.obj, material: 3d/liquids/water, method: schlick }
//! measurements: [timing, image_error]
//! timing: { resolution: [1920, 1080], warmup: 5, repeats: 30, subtract: false }
//! lut: { size: 64 }
//! ```
//!
//! A scene with an `effects` section (see [`effects`]) may also place objects (`position`,
//! `scale`), give objects a diffuse colour instead of a material (the surroundings), use the
//! built-in `room` and `plane`, and set a `light`; without `effects` those fields are errors,
//! so a scene without effects means exactly what it meant before.

pub mod camera;
pub mod effects;
pub mod materials;
pub mod mesh;
pub mod surfels;

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use nklut_optics::fresnel::Method as FresnelMethod;

pub use effects::{Bounces, Depths, Diffuse, DistanceMaps, EffectFamily, Effects, Light, Pattern, SearchSteps};
pub use materials::{read_materials, SceneMaterial, SpecularMaterial};
pub use surfels::LightSource;

/// How a specular object is shaded: a Fresnel method of the `fresnel` module as the shaders
/// implement it, or one of the two cost baselines. Ordered as the methods, then the
/// baselines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Shading {
    Fresnel(FresnelMethod),
    /// Baseline: a constant colour (F0) per material, no Fresnel at all.
    Constant,
    /// Baseline: one plain texture fetch at a coordinate that does not depend on cosθ.
    Texture,
}

impl Shading {
    /// Every Fresnel method of [`FresnelMethod::ALL`], in its order, then the baselines:
    /// made from the method list, so a method added there is a shading here.
    pub const ALL: [Shading; FresnelMethod::ALL.len() + 2] = {
        let mut all = [Shading::Constant; FresnelMethod::ALL.len() + 2];
        let mut i = 0;
        while i < FresnelMethod::ALL.len() {
            all[i] = Shading::Fresnel(FresnelMethod::ALL[i]);
            i += 1;
        }
        all[i] = Shading::Constant;
        all[i + 1] = Shading::Texture;
        all
    };

    /// The name in scene files and tables: the fresnel module's name for a Fresnel method.
    pub fn name(self) -> &'static str {
        match self {
            Shading::Fresnel(method) => method.name(),
            Shading::Constant => "constant",
            Shading::Texture => "texture",
        }
    }

    pub fn from_name(name: &str) -> Option<Shading> {
        Shading::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The Fresnel method of the fresnel module this shader implements; `None` for the
    /// baselines (`constant`, `texture`).
    pub fn fresnel(self) -> Option<FresnelMethod> {
        match self {
            Shading::Fresnel(method) => Some(method),
            Shading::Constant | Shading::Texture => None,
        }
    }
}

impl fmt::Display for Shading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the runner measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Experiment {
    /// Fullscreen pass per (material, method), timed (`gpu_timing.csv`).
    Timing,
    /// Each object rendered with each method and with `exact` (`image_errors.csv`).
    ImageError,
}

impl Experiment {
    pub fn name(self) -> &'static str {
        match self {
            Experiment::Timing => "timing",
            Experiment::ImageError => "image_error",
        }
    }
}

/// A mesh: built-in `cube` or `sphere` (fitted to the unit sphere), `room` (the box
/// [−1, 1]³ seen from inside, faces pointing inwards) or `plane` (the square [−1, 1]² in
/// y = 0 facing +y), or an OBJ file (relative paths are taken from the scene file's folder
/// first, then from the working directory; fitted to the unit sphere).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum MeshSource {
    Cube,
    Sphere,
    Room,
    Plane,
    File(PathBuf),
}

impl MeshSource {
    fn parse(text: &str) -> MeshSource {
        match text {
            "cube" => MeshSource::Cube,
            "sphere" => MeshSource::Sphere,
            "room" => MeshSource::Room,
            "plane" => MeshSource::Plane,
            path => MeshSource::File(PathBuf::from(path)),
        }
    }

    /// Short name for tables: `cube`, `sphere`, `room`, `plane` or the file stem (`nefertiti`).
    pub fn label(&self) -> String {
        match self {
            MeshSource::Cube => "cube".into(),
            MeshSource::Sphere => "sphere".into(),
            MeshSource::Room => "room".into(),
            MeshSource::Plane => "plane".into(),
            MeshSource::File(path) => {
                path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
            }
        }
    }
}

/// The camera path of the image-error measurement (docs/precision.md): orbit around `axis` at `distance` (m), looking at the origin,
/// `frames` frames `degrees_per_frame` apart, vertical field of view `fov_y_degrees`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPath {
    #[serde(default = "default_axis")]
    pub axis: [f64; 3],
    #[serde(default = "default_distance")]
    pub distance: f64,
    #[serde(default = "default_frames")]
    pub frames: u32,
    #[serde(default = "default_degrees")]
    pub degrees_per_frame: f64,
    /// 60° makes the unit sphere just fill the height of the frame from 2 m.
    #[serde(default = "default_fov")]
    pub fov_y_degrees: f64,
}

fn default_axis() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}
fn default_distance() -> f64 {
    2.0
}
fn default_frames() -> u32 {
    180
}
fn default_degrees() -> f64 {
    1.0
}
fn default_fov() -> f64 {
    60.0
}

impl Default for CameraPath {
    fn default() -> Self {
        Self {
            axis: default_axis(),
            distance: default_distance(),
            frames: default_frames(),
            degrees_per_frame: default_degrees(),
            fov_y_degrees: default_fov(),
        }
    }
}

/// Timing settings: a fullscreen pass of `resolution`, `warmup` untimed passes, `repeats`
/// timed ones; `subtract` uses the study's method (expensive shader alone, then with the
/// measured one drawn on top, difference).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingSettings {
    #[serde(default = "default_timing_resolution")]
    pub resolution: [u32; 2],
    #[serde(default = "default_warmup")]
    pub warmup: u32,
    #[serde(default = "default_repeats")]
    pub repeats: u32,
    #[serde(default)]
    pub subtract: bool,
}

fn default_timing_resolution() -> [u32; 2] {
    [1920, 1080]
}
fn default_warmup() -> u32 {
    5
}
fn default_repeats() -> u32 {
    30
}

impl Default for TimingSettings {
    fn default() -> Self {
        Self { resolution: default_timing_resolution(), warmup: default_warmup(), repeats: default_repeats(), subtract: false }
    }
}

/// The runner's own LUT (`lut` method): `size` texels over cosθ ∈ [0, 1].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LutSettings {
    #[serde(default = "default_lut_size")]
    pub size: u32,
}

fn default_lut_size() -> u32 {
    64
}

impl Default for LutSettings {
    fn default() -> Self {
        Self { size: default_lut_size() }
    }
}

/// The largest coordinate (scene units, metres) a position may have on any axis. Meshes fit
/// the unit sphere (the room √3), so a placed vertex stays within ±(`MAX_COORDINATE` +
/// √3·`SCALE_RANGE.1`): finite in f32 — the BVH's and the GPU's precision — with room for
/// the products the tracers form, where 1e300 or 3.5e38 made infinities and NaN.
pub const MAX_COORDINATE: f64 = 1e4;
/// The smallest and largest scale on any axis (normals divide by it).
pub const SCALE_RANGE: (f64, f64) = (1e-4, 1e4);
/// The largest light colour, ambient term or point intensity: radiance summed over every
/// bounce of every light stays far from overflow in f64 and in the GPU's f32.
pub const MAX_LIGHT: f64 = 1e6;
/// The most camera frames a scene (or `--frames`) may ask for: ten turns at the study's
/// 1° a frame. Every frame is rendered, so a larger count is a run that never ends.
pub const MAX_FRAMES: u32 = 3600;
/// The most bytes read from a scene file.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
/// The most timed (and untimed) passes per measurement.
pub const MAX_REPEATS: u32 = 10_000;

/// Where an object stands: its mesh scaled per axis by `scale`, then moved by `position`.
/// Only scenes with `effects` place objects; elsewhere every object sits at the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub position: [f64; 3],
    pub scale: [f64; 3],
}

impl Default for Placement {
    fn default() -> Self {
        Self { position: [0.0; 3], scale: [1.0; 3] }
    }
}

impl Placement {
    /// A point of the mesh in the scene.
    pub fn point(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| p[i] * self.scale[i] + self.position[i])
    }

    /// A normal of the mesh in the scene (inverse transpose of the scale), not normalised.
    pub fn normal(&self, n: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| n[i] / self.scale[i])
    }
}

/// A specular object: a material (a page id) and the ways to shade it. A conductor reflects;
/// a dielectric reflects and refracts (the page's kind decides, after ingest).
#[derive(Clone, Debug, PartialEq)]
pub struct Specular {
    pub material: String,
    pub shadings: Vec<Shading>,
}

/// What an object is in the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Role {
    Specular(Specular),
    /// Part of the diffuse surroundings (scenes with `effects` only).
    Diffuse(Diffuse),
}

/// One object: a mesh, where it stands and its role.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    pub mesh: MeshSource,
    pub placement: Placement,
    pub role: Role,
    /// Midpoint subdivisions of the mesh before its surfels are built (`subdivide`; scenes
    /// with effects only): the surface stays, the surfels get smaller.
    pub subdivisions: u32,
}

impl SceneObject {
    pub fn specular(&self) -> Option<&Specular> {
        match &self.role {
            Role::Specular(specular) => Some(specular),
            Role::Diffuse(_) => None,
        }
    }
}

/// A parsed and checked scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The file it came from (for messages and relative mesh paths); empty for inline text.
    pub file: PathBuf,
    pub resolution: [u32; 2],
    pub camera: CameraPath,
    pub objects: Vec<SceneObject>,
    pub experiments: Vec<Experiment>,
    pub timing: TimingSettings,
    pub lut: LutSettings,
    /// The light-transport effects the scene calls for; `None`: F(|N·V|) on bare objects.
    pub effects: Option<Effects>,
    /// The light of the diffuse surroundings (scenes with `effects`).
    pub light: Light,
    /// The lights of the surfel effects: the scene's `lights`, or `light` as a directional
    /// and an ambient source.
    pub lights: Vec<LightSource>,
}

/// A scene file that could not be used: the file and what was wrong.
#[derive(Debug, thiserror::Error)]
#[error("scene {}: {problem}", file.display())]
pub struct SceneError {
    pub file: PathBuf,
    pub problem: String,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum OneOrMany {
    One(String),
    Many(Vec<String>),
}

/// `scale: 2` or `scale: [3, 2, 3]`.
#[derive(Deserialize)]
#[serde(untagged)]
enum RawScale {
    Uniform(f64),
    Axes([f64; 3]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    mesh: String,
    material: Option<String>,
    #[serde(alias = "method")]
    methods: Option<OneOrMany>,
    diffuse: Option<[f64; 3]>,
    pattern: Option<Pattern>,
    position: Option<[f64; 3]>,
    scale: Option<RawScale>,
    subdivide: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default = "default_resolution")]
    resolution: [u32; 2],
    #[serde(default)]
    camera: CameraPath,
    objects: Vec<RawObject>,
    measurements: Vec<Experiment>,
    #[serde(default)]
    timing: TimingSettings,
    #[serde(default)]
    lut: LutSettings,
    effects: Option<effects::RawEffects>,
    light: Option<Light>,
    lights: Option<Vec<LightSource>>,
}

fn default_resolution() -> [u32; 2] {
    [512, 512]
}

fn shadings(names: OneOrMany) -> Result<Vec<Shading>, String> {
    let names = match names {
        OneOrMany::One(name) => vec![name],
        OneOrMany::Many(names) => names,
    };
    let mut shadings = Vec::new();
    for name in names {
        let shading = Shading::from_name(&name).ok_or_else(|| {
            let known: Vec<&str> = Shading::ALL.iter().map(|m| m.name()).collect();
            format!("unknown method {name:?}; known: {}", known.join(", "))
        })?;
        if !shadings.contains(&shading) {
            shadings.push(shading);
        }
    }
    Ok(shadings)
}

impl RawObject {
    /// The object, or what is wrong with it (without the `objects[i]` prefix).
    fn object(self, effects: bool) -> Result<SceneObject, String> {
        let needs_effects = |field: &str| format!("{field}: only a scene with an `effects` section may use it");
        let placement = Placement {
            position: self.position.unwrap_or([0.0; 3]),
            scale: match self.scale {
                None => [1.0; 3],
                Some(RawScale::Uniform(s)) => [s; 3],
                Some(RawScale::Axes(axes)) => axes,
            },
        };
        if !effects && placement != Placement::default() {
            return Err(needs_effects(if self.position.is_some() { "position" } else { "scale" }));
        }
        if placement.position.iter().any(|x| !(x.abs() <= MAX_COORDINATE)) {
            return Err(format!("position {:?} must lie within ±{MAX_COORDINATE:e} on each axis", placement.position));
        }
        if placement.scale.iter().any(|s| !(*s >= SCALE_RANGE.0 && *s <= SCALE_RANGE.1)) {
            return Err(format!("scale {:?} must lie in [{:e}, {:e}] on each axis", placement.scale, SCALE_RANGE.0, SCALE_RANGE.1));
        }
        let subdivisions = self.subdivide.unwrap_or(0);
        if self.subdivide.is_some() && !effects {
            return Err(needs_effects("subdivide"));
        }
        if subdivisions > surfels::MAX_SUBDIVISIONS {
            return Err(format!("subdivide {subdivisions} must lie in 0..={}", surfels::MAX_SUBDIVISIONS));
        }
        let role = match (self.material, self.diffuse) {
            (Some(_), Some(_)) => return Err("material and diffuse: an object is either specular (a material) or diffuse, not both".into()),
            (None, None) => return Err("material: name a page id (a specular object) or a `diffuse` colour".into()),
            (Some(material), None) => {
                if self.pattern.is_some() {
                    return Err("pattern: only a diffuse object has a pattern".into());
                }
                let names = self.methods.ok_or("methods: a specular object needs at least one method")?;
                let shadings = shadings(names).map_err(|e| format!("methods: {e}"))?;
                if shadings.is_empty() {
                    return Err("methods: no method named".into());
                }
                if material.split('/').count() != 3 {
                    return Err(format!("material {material:?} is not a page id shelf/book/page"));
                }
                Role::Specular(Specular { material, shadings })
            }
            (None, Some(albedo)) => {
                if !effects {
                    return Err(needs_effects("diffuse"));
                }
                if self.methods.is_some() {
                    return Err("methods: a diffuse object has no Fresnel method".into());
                }
                let diffuse = Diffuse { albedo, pattern: self.pattern.unwrap_or(Pattern::Plain) };
                diffuse.check()?;
                Role::Diffuse(diffuse)
            }
        };
        Ok(SceneObject { mesh: MeshSource::parse(&self.mesh), placement, role, subdivisions })
    }
}

impl Scene {
    /// Read and check a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = nklut_optics::db::file::read_regular_text(path, MAX_SCENE_BYTES)
            .map_err(|e| SceneError { file: path.into(), problem: format!("cannot read: {e}") })?;
        Scene::parse(&text, path)
    }

    /// Parse and check scene text; `file` names it in errors and anchors relative mesh paths.
    pub fn parse(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let error = |problem: String| SceneError { file: file.into(), problem };
        if let Some(deep) = nklut_optics::db::block_yaml::too_deep(text) {
            return Err(error(deep.to_string()));
        }
        let raw: RawScene = serde_yaml::from_str(text).map_err(|e| error(e.to_string()))?;
        let with_effects = raw.effects.is_some();
        let mut objects = Vec::new();
        for (i, object) in raw.objects.into_iter().enumerate() {
            objects.push(object.object(with_effects).map_err(|e| error(format!("objects[{i}].{e}")))?);
        }
        let effects = raw.effects.map(|e| e.effects()).transpose().map_err(|e| error(format!("effects.{e}")))?;
        if raw.light.is_some() && effects.is_none() {
            return Err(error("light: only a scene with an `effects` section may use it".into()));
        }
        if raw.lights.is_some() && effects.is_none() {
            return Err(error("lights: only a scene with an `effects` section may use it".into()));
        }
        if raw.lights.is_some() && raw.light.is_some() {
            return Err(error("light and lights: name the lights once, in `lights` (directional, point, ambient) or in `light`".into()));
        }
        let distance_map_effects = effects.as_ref().is_some_and(|e| e.names(EffectFamily::SpecularPaths));
        if raw.lights.is_some() && distance_map_effects {
            return Err(error("lights: reflection and refraction light their surroundings with `light`; `lights` is for ambient_occlusion and indirect alone".into()));
        }
        let surfel_effects = effects.as_ref().is_some_and(|e| e.names(EffectFamily::Surfels));
        if let Some(i) = objects.iter().position(|o: &SceneObject| o.subdivisions > 0) {
            if !surfel_effects {
                return Err(error(format!("objects[{i}].subdivide: only surfel effects (ambient_occlusion, indirect) use it")));
            }
        }
        let light = raw.light.unwrap_or_default();
        let lights = match raw.lights {
            Some(lights) => {
                for (i, source) in lights.iter().enumerate() {
                    source.check().map_err(|e| error(format!("lights[{i}].{e}")))?;
                }
                lights
            }
            None => vec![
                LightSource::Directional { direction: light.direction, colour: light.colour },
                LightSource::Ambient { colour: light.ambient },
            ],
        };
        let scene = Scene {
            file: file.into(),
            resolution: raw.resolution,
            camera: raw.camera,
            objects,
            experiments: raw.measurements,
            timing: raw.timing,
            lut: raw.lut,
            effects,
            light,
            lights,
        };
        scene.check().map_err(error)?;
        Ok(scene)
    }

    /// The checks of [`Scene::parse`] again, for values changed after loading (the
    /// command line's `--resolution`, `--degrees-per-frame`, …); errors name the file.
    pub fn recheck(&self) -> Result<(), SceneError> {
        self.check().map_err(|problem| SceneError { file: self.file.clone(), problem: format!("{problem} (after command-line overrides)") })
    }

    fn check(&self) -> Result<(), String> {
        if self.objects.is_empty() {
            return Err("objects: the scene names no object".into());
        }
        // A scene whose effects are only surfel effects (ambient occlusion, indirect light)
        // needs no specular object; reflections, refractions and the plain F(|N·V|) runs do.
        let surfel_only = self.effects.as_ref().is_some_and(|e| !e.names(EffectFamily::SpecularPaths));
        if !surfel_only && self.specular_objects().next().is_none() {
            return Err("objects: the scene names no specular object (one with a material)".into());
        }
        if self.experiments.is_empty() {
            return Err("measurements: name at least one of timing, image_error".into());
        }
        check_resolution("resolution", self.resolution)?;
        check_resolution("timing.resolution", self.timing.resolution)?;
        let camera = &self.camera;
        if camera.axis.iter().map(|a| a * a).sum::<f64>().sqrt() < 1e-9 || camera.axis.iter().any(|a| !a.is_finite()) {
            return Err(format!("camera.axis {:?} must be a non-zero vector", camera.axis));
        }
        if !(camera.distance > 1.0 && camera.distance.is_finite()) {
            return Err(format!("camera.distance {} must be above 1 (objects fill the unit sphere)", camera.distance));
        }
        if !(1..=MAX_FRAMES).contains(&camera.frames) {
            return Err(format!("camera.frames {} must lie in 1..={MAX_FRAMES}", camera.frames));
        }
        if !camera.degrees_per_frame.is_finite() {
            return Err("camera.degrees_per_frame must be finite".into());
        }
        if !(camera.fov_y_degrees > 0.0 && camera.fov_y_degrees < 180.0) {
            return Err(format!("camera.fov_y_degrees {} must lie in (0, 180)", camera.fov_y_degrees));
        }
        if !(1..=MAX_REPEATS).contains(&self.timing.repeats) {
            return Err(format!("timing.repeats {} must lie in 1..={MAX_REPEATS}", self.timing.repeats));
        }
        if self.timing.warmup > MAX_REPEATS {
            return Err(format!("timing.warmup {} must lie in 0..={MAX_REPEATS}", self.timing.warmup));
        }
        if !(2..=8192).contains(&self.lut.size) {
            return Err(format!("lut.size {} must lie in 2..=8192", self.lut.size));
        }
        self.light.check().map_err(|e| format!("light.{e}"))
    }

    /// Whether the scene names any effect of `family`.
    pub fn names_effect(&self, family: EffectFamily) -> bool {
        self.effects.as_ref().is_some_and(|e| e.names(family))
    }

    pub fn wants(&self, experiment: Experiment) -> bool {
        self.experiments.contains(&experiment)
    }

    /// The specular objects with their material and shadings, in file order.
    pub fn specular_objects(&self) -> impl Iterator<Item = (&SceneObject, &Specular)> {
        self.objects.iter().filter_map(|o| o.specular().map(|s| (o, s)))
    }

    /// Distinct material page ids in order of first appearance.
    pub fn materials(&self) -> Vec<String> {
        let mut pages: Vec<String> = Vec::new();
        for (_, specular) in self.specular_objects() {
            if !pages.contains(&specular.material) {
                pages.push(specular.material.clone());
            }
        }
        pages
    }

    /// Distinct shadings in the order of `Shading::ALL`.
    pub fn shadings(&self) -> Vec<Shading> {
        Shading::ALL.into_iter().filter(|m| self.specular_objects().any(|(_, s)| s.shadings.contains(m))).collect()
    }

    /// Distinct (material, shading) pairs, the units of the timing measurement.
    pub fn material_shadings(&self) -> Vec<(String, Shading)> {
        let mut pairs: Vec<(String, Shading)> = Vec::new();
        for material in self.materials() {
            for shading in Shading::ALL {
                if self.specular_objects().any(|(_, s)| s.material == material && s.shadings.contains(&shading)) {
                    pairs.push((material.clone(), shading));
                }
            }
        }
        pairs
    }

    /// Where a mesh file is: relative to the scene file's folder if it exists there, else
    /// as given (relative to the working directory).
    pub fn mesh_path(&self, path: &Path) -> PathBuf {
        if path.is_relative() {
            if let Some(dir) = self.file.parent() {
                let candidate = dir.join(path);
                if candidate.exists() {
                    return candidate;
                }
            }
        }
        path.to_path_buf()
    }
}

fn check_resolution(name: &str, [w, h]: [u32; 2]) -> Result<(), String> {
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        return Err(format!("{name} {w}x{h} must be between 1x1 and 8192x8192"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, Path::new("test.yaml"))
    }

    #[test]
    fn minimal_scene_takes_the_study_defaults() {
        let scene = parse("objects: [{mesh: cube, material: 3d/metals/gold, method: schlick}]\nmeasurements: [image_error]\n").unwrap();
        assert_eq!(scene.camera, CameraPath::default());
        assert_eq!(scene.camera.frames, 180);
        assert_eq!(scene.timing.resolution, [1920, 1080]);
        assert_eq!(scene.objects[0].specular().unwrap().shadings, vec![Shading::Fresnel(FresnelMethod::Schlick)]);
        assert_eq!((scene.effects.clone(), scene.objects[0].placement), (None, Placement::default()));
        assert_eq!(scene.objects[0].mesh, MeshSource::Cube);
    }

    #[test]
    fn shading_names_match_serde_and_the_fresnel_module() {
        for method in Shading::ALL {
            assert_eq!(Shading::from_name(method.name()), Some(method));
            assert_eq!(method.fresnel().map(|m| m.name()).unwrap_or(method.name()), method.name());
        }
        assert_eq!(Shading::ALL.iter().filter(|m| m.fresnel().is_none()).count(), 2);
    }

    #[test]
    fn pairs_and_methods_are_distinct() {
        let scene = parse(
            "objects:\n  - {mesh: cube, material: a/b/c, methods: [lut, exact, lut]}\n  - {mesh: sphere, material: a/b/c, methods: [exact]}\n  - {mesh: x.obj, material: d/e/f, methods: [schlick]}\nmeasurements: [timing]\n",
        )
        .unwrap();
        assert_eq!(scene.materials(), vec!["a/b/c", "d/e/f"]);
        assert_eq!(
            scene.shadings(),
            vec![Shading::Fresnel(FresnelMethod::Exact), Shading::Fresnel(FresnelMethod::Schlick), Shading::Fresnel(FresnelMethod::Lut)]
        );
        assert_eq!(scene.material_shadings().len(), 3);
        assert_eq!(scene.objects[2].mesh.label(), "x");
    }

    #[test]
    fn bad_scenes_are_named_errors() {
        let cases = [
            ("objects: []\nmeasurements: [timing]\n", "no object"),
            ("objects: [{mesh: cube, material: a/b/c, method: fast}]\nmeasurements: [timing]\n", "unknown method \"fast\""),
            ("objects: [{mesh: cube, material: gold, method: exact}]\nmeasurements: [timing]\n", "not a page id"),
            ("objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [speed]\n", "unknown variant"),
            ("objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [timing]\ncamera: {axis: [0, 0, 0]}\n", "camera.axis"),
            ("objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [timing]\nresolution: [0, 4]\n", "resolution 0x4"),
            ("objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [timing]\ncamera: {frames: 0}\n", "frames"),
            ("objects: [{mesh: cube, material: a/b/c, method: exact, colour: red}]\nmeasurements: [timing]\n", "unknown field"),
            (": : :", "test.yaml"),
            ("objects: [{mesh: cube, material: a/b/c}]\nmeasurements: [timing]\n", "objects[0].methods"),
        ];
        for (text, expected) in cases {
            let message = parse(text).unwrap_err().to_string();
            assert!(message.contains(expected) && message.contains("test.yaml"), "{text:?} gave {message:?}");
        }
    }

    const EFFECTS: &str = "measurements: [image_error]\neffects:\n  reflection: {max_depth: [1, 3]}\n  distance_maps: {size: 64, layers: 3, linear_steps: 15, secant_steps: [1, 10]}\n";

    #[test]
    fn an_effects_scene_has_roles_placements_and_configurations() {
        let text = format!(
            "{EFFECTS}light: {{direction: [0, -1, 0], ambient: [0.1, 0.1, 0.1]}}\nobjects:\n  - {{mesh: sphere, material: 3d/metals/silver, methods: [exact, schlick], position: [0, 0.5, 0]}}\n  - {{mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.8], pattern: {{kind: checker, size: 0.5, albedo: [0.1, 0.1, 0.1]}}}}\n  - {{mesh: plane, scale: 2, diffuse: [0.2, 0.5, 0.2]}}\n"
        );
        let scene = parse(&text).unwrap();
        let effects = scene.effects.as_ref().unwrap();
        assert_eq!(effects.reflection.as_ref().unwrap().max_depth, vec![1, 3]);
        assert!(effects.refraction.is_none());
        assert_eq!(effects.distance_maps.steps, vec![SearchSteps { linear: 15, secant: 1 }, SearchSteps { linear: 15, secant: 10 }]);
        assert_eq!(scene.objects[0].placement.position, [0.0, 0.5, 0.0]);
        assert_eq!(scene.objects[1].placement.scale, [3.0, 2.0, 3.0]);
        assert_eq!(scene.objects[2].placement.scale, [2.0; 3]);
        assert_eq!((scene.objects[1].mesh.clone(), scene.objects[2].mesh.clone()), (MeshSource::Room, MeshSource::Plane));
        match &scene.objects[1].role {
            Role::Diffuse(d) => assert_eq!(d.pattern, Pattern::Checker { size: 0.5, albedo: [0.1; 3] }),
            other => panic!("{other:?}"),
        }
        assert_eq!(scene.light.ambient, [0.1; 3]);
        assert_eq!(scene.light.colour, Light::default().colour);
        assert_eq!(scene.materials(), vec!["3d/metals/silver"]);
        assert_eq!(scene.shadings(), vec![Shading::Fresnel(FresnelMethod::Exact), Shading::Fresnel(FresnelMethod::Schlick)]);
    }

    #[test]
    fn effects_fields_are_errors_naming_the_field() {
        let specular = "  - {mesh: sphere, material: a/b/c, method: exact}\n";
        let plain = "measurements: [image_error]\nobjects:\n";
        let cases = [
            // Fields that need an effects section.
            (format!("{plain}{specular}  - {{mesh: room, diffuse: [1, 1, 1]}}\n"), "objects[1].diffuse: only a scene with an `effects` section"),
            (format!("{plain}  - {{mesh: sphere, material: a/b/c, method: exact, position: [1, 0, 0]}}\n"), "objects[0].position"),
            (format!("{plain}  - {{mesh: sphere, material: a/b/c, method: exact, scale: 2}}\n"), "objects[0].scale"),
            (format!("{plain}{specular}light: {{ambient: [0, 0, 0]}}\n"), "light: only a scene with an `effects`"),
            // Contradictions and bad values.
            (format!("{EFFECTS}objects:\n  - {{mesh: room, material: a/b/c, diffuse: [1, 1, 1], method: exact}}\n"), "objects[0].material and diffuse"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], method: exact}}\n"), "objects[1].methods: a diffuse object"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room}}\n"), "objects[1].material: name a page id"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [2, 1, 1]}}\n"), "objects[1].diffuse [2.0, 1.0, 1.0] must lie in [0, 1]"),
            (format!("{EFFECTS}objects:\n  - {{mesh: room, diffuse: [1, 1, 1]}}\n"), "no specular object"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: checker, size: 0, albedo: [0, 0, 0]}}}}\n"), "pattern.checker.size"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: stripes}}}}\n"), "unknown variant `stripes`"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: checker, size: 1, albedo: [0, 0, 0], tilt: 2}}}}\n"), "unknown field `tilt`"),
            (format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, scale: [1, 0, 1]}}\n"), "objects[0].scale"),
            (format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, pattern: {{kind: plain}}}}\n"), "objects[0].pattern"),
            (format!("{plain}{specular}effects: {{}}\n"), "effects.reflection, refraction, ambient_occlusion, indirect: name at least one"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 0}}}}\n"), "effects.reflection.max_depth"),
            (format!("{plain}{specular}effects: {{refraction: {{max_depth: [1, 9]}}}}\n"), "effects.refraction.max_depth"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1, bounces: 2}}}}\n"), "unknown field `bounces`"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, glow: {{}}}}\n"), "unknown field `glow`"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{layers: 1}}}}\n"), "effects.distance_maps.layers 1"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{linear_steps: 0}}}}\n"), "effects.distance_maps.linear_steps"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}}}\nlight: {{direction: [0, 0, 0]}}\n"), "light.direction"),
        ];
        for (text, expected) in cases {
            let message = parse(&text).unwrap_err().to_string();
            assert!(message.contains(expected) && message.contains("test.yaml"), "{text:?} gave {message:?}");
        }
    }
}
