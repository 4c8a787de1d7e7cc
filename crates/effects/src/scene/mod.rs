//! Scene files: which objects to render, with which material and Fresnel method or with which
//! diffuse colour, the camera path of the image-error measurement (docs/precision.md), which
//! experiments to run and, optionally, which light-transport effects the scene calls for
//! (`effects`: multiple reflections and refractions traced in layered distance maps). Plain
//! serde_norway and pure data; lives outside the `gpu` feature so scene files can be checked,
//! and the CPU tracers of `crate` run, without wgpu.
//!
//! ```yaml
//! resolution: [512, 512]          # image-error render targets (width, height)
//! camera: { axis: [1, 1, 1], distance: 2.0, frames: 180, degrees_per_frame: 1.0, fov_y_degrees: 60 }
//! objects:
//!   - { mesh: cube, material: 3d/metals/gold, methods: [schlick, lazanyi] }
//!   - { mesh: ../shared/meshes/nefertiti.obj, material: 3d/liquids/water, method: schlick }
//! measurements: [timing, image_error]
//! timing: { resolution: [1920, 1080], warmup: 5, repeats: 30, subtract: false, amplify: true, seed: 7956572418393243649 }
//! lut: { size: 64 }
//! ```
//!
//! A scene with an `effects` section (see [`effects`]) may also place objects (`position`,
//! `scale`), give objects a diffuse colour instead of a material (the surroundings), use the
//! built-in `room` and `plane`, and set a `light`; without `effects` those fields are errors,
//! so a scene without effects means exactly what it meant before.

pub mod camera;
pub mod effects;
pub mod error;
pub mod gtao;
pub mod lights;
pub mod materials;
pub mod mesh;
pub mod surfels;

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use nklut_optics::fresnel::Method as FresnelMethod;

pub use effects::{Bounces, Depths, Diffuse, DistanceMaps, EffectFamily, Effects, Pattern, SearchSteps, Spectral};
pub use error::{Conflict, Each, FieldProblem, Listing, Range, Required, SceneError, SceneProblem, Value, Values};
pub use lights::{Light, LightSource, MAX_LIGHTS};
pub use materials::{read_materials, SceneMaterial, SpecularMaterial};

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
    /// An equilateral triangular prism (apex angle 60°), fitted to the unit sphere.
    Prism,
    File(PathBuf),
}

impl MeshSource {
    fn parse(text: &str) -> MeshSource {
        match text {
            "cube" => MeshSource::Cube,
            "sphere" => MeshSource::Sphere,
            "room" => MeshSource::Room,
            "plane" => MeshSource::Plane,
            "prism" => MeshSource::Prism,
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
            MeshSource::Prism => "prism".into(),
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
/// measured one drawn on top, difference); `amplify` (default true) lets the runner repeat
/// the F evaluation per pixel until a sample spans enough of the timer's resolution (false:
/// one evaluation, the single-draw design); `seed` seeds the order of the pairs per round.
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
    #[serde(default = "default_amplify")]
    pub amplify: bool,
    #[serde(default = "default_seed")]
    pub seed: u64,
}

fn default_amplify() -> bool {
    true
}
/// The seed of the timed pairs' order when the scene gives none.
pub const DEFAULT_TIMING_SEED: u64 = 0x6e6b_6c75_7400_0001;
fn default_seed() -> u64 {
    DEFAULT_TIMING_SEED
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
        Self {
            resolution: default_timing_resolution(),
            warmup: default_warmup(),
            repeats: default_repeats(),
            subtract: false,
            amplify: default_amplify(),
            seed: default_seed(),
        }
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
    /// The lights of every effect (scenes with `effects`): the scene's `lights`, or `light`
    /// (the default) as a directional and an ambient source.
    pub lights: Vec<LightSource>,
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

/// The shadings a `methods` field names, distinct, in its order.
fn shadings(names: OneOrMany) -> Result<Vec<Shading>, FieldProblem> {
    let names = match names {
        OneOrMany::One(name) => vec![name],
        OneOrMany::Many(names) => names,
    };
    let mut shadings = Vec::new();
    for name in names {
        let shading = Shading::from_name(&name).ok_or_else(|| FieldProblem::Unknown {
            what: "method",
            name: name.clone(),
            known: Shading::ALL.iter().map(|m| m.name()).collect(),
        })?;
        if !shadings.contains(&shading) {
            shadings.push(shading);
        }
    }
    Ok(shadings)
}

impl RawObject {
    /// The object, or what is wrong with it (without the `objects[i]` prefix).
    fn object(self, effects: bool) -> Result<SceneObject, SceneProblem> {
        let needs_effects = |field: &str| SceneProblem::field(field, FieldProblem::NeedsEffects);
        let conflict = |conflict: Conflict| SceneProblem::Conflict { at: String::new(), conflict };
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
            let range = Range::Within { bound: MAX_COORDINATE };
            return Err(SceneProblem::field("position", FieldProblem::OutOfRange { value: Value::Vector(placement.position), range }));
        }
        if placement.scale.iter().any(|s| !(*s >= SCALE_RANGE.0 && *s <= SCALE_RANGE.1)) {
            let range = Range::Closed { low: SCALE_RANGE.0, high: SCALE_RANGE.1, each: Each::Axis };
            return Err(SceneProblem::field("scale", FieldProblem::OutOfRange { value: Value::Vector(placement.scale), range }));
        }
        let subdivisions = self.subdivide.unwrap_or(0);
        if self.subdivide.is_some() && !effects {
            return Err(needs_effects("subdivide"));
        }
        if subdivisions > surfels::MAX_SUBDIVISIONS {
            let range = Range::Integers { low: 0, high: surfels::MAX_SUBDIVISIONS.into() };
            return Err(SceneProblem::field("subdivide", FieldProblem::OutOfRange { value: Value::Integer(subdivisions.into()), range }));
        }
        let role = match (self.material, self.diffuse) {
            (Some(_), Some(_)) => return Err(conflict(Conflict::MaterialAndDiffuse)),
            (None, None) => return Err(SceneProblem::field("material", FieldProblem::Missing(Required::MaterialOrDiffuse))),
            (Some(material), None) => {
                if self.pattern.is_some() {
                    return Err(conflict(Conflict::PatternOnSpecular));
                }
                let names = self.methods.ok_or(SceneProblem::field("methods", FieldProblem::Missing(Required::Methods)))?;
                let shadings = shadings(names).map_err(|kind| SceneProblem::field("methods", kind))?;
                if shadings.is_empty() {
                    return Err(SceneProblem::field("methods", FieldProblem::Empty(Listing::Methods)));
                }
                if material.split('/').count() != 3 {
                    return Err(SceneProblem::field("material", FieldProblem::NotAPageId { value: material }));
                }
                Role::Specular(Specular { material, shadings })
            }
            (None, Some(albedo)) => {
                if !effects {
                    return Err(needs_effects("diffuse"));
                }
                if self.methods.is_some() {
                    return Err(conflict(Conflict::MethodsOnDiffuse));
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
            .map_err(|e| SceneError::new(path, SceneProblem::Unreadable(e)))?;
        Scene::parse(&text, path)
    }

    /// Parse and check scene text; `file` names it in errors and anchors relative mesh paths.
    pub fn parse(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let error = |problem: SceneProblem| SceneError::new(file, problem);
        let conflict = |conflict: Conflict| error(SceneProblem::Conflict { at: String::new(), conflict });
        if let Some(deep) = nklut_optics::db::block_yaml::too_deep(text) {
            return Err(error(SceneProblem::TooDeep(deep)));
        }
        let raw: RawScene = serde_norway::from_str(text).map_err(|e| error(SceneProblem::Syntax(e)))?;
        let with_effects = raw.effects.is_some();
        let mut objects = Vec::new();
        for (i, object) in raw.objects.into_iter().enumerate() {
            objects.push(object.object(with_effects).map_err(|e| error(e.within(&format!("objects[{i}]"))))?);
        }
        let effects = raw.effects.map(|e| e.effects()).transpose().map_err(|e| error(e.within("effects")))?;
        if raw.light.is_some() && effects.is_none() {
            return Err(error(SceneProblem::field("light", FieldProblem::NeedsEffects)));
        }
        if raw.lights.is_some() && effects.is_none() {
            return Err(error(SceneProblem::field("lights", FieldProblem::NeedsEffects)));
        }
        if raw.lights.is_some() && raw.light.is_some() {
            return Err(conflict(Conflict::LightAndLights));
        }
        let surfel_effects = effects.as_ref().is_some_and(|e| e.names(EffectFamily::Surfels));
        if let Some(i) = objects.iter().position(|o: &SceneObject| o.subdivisions > 0) {
            if !surfel_effects {
                return Err(error(SceneProblem::field(
                    format!("objects[{i}].subdivide"),
                    FieldProblem::NeedsFamily(EffectFamily::Surfels),
                )));
            }
        }
        let lights = match raw.lights {
            Some(lights) => {
                if lights.len() > MAX_LIGHTS {
                    let range = Range::Integers { low: 0, high: MAX_LIGHTS as u64 };
                    let kind = FieldProblem::OutOfRange { value: Value::Integer(lights.len() as u64), range };
                    return Err(error(SceneProblem::field("lights", kind)));
                }
                for (i, source) in lights.iter().enumerate() {
                    source.check().map_err(|e| error(e.within(&format!("lights[{i}]"))))?;
                }
                lights
            }
            None => {
                let light = raw.light.unwrap_or_default();
                light.check().map_err(|e| error(e.within("light")))?;
                light.sources()
            }
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
            lights,
        };
        scene.check().map_err(error)?;
        Ok(scene)
    }

    /// The checks of [`Scene::parse`] again, for values changed after loading (the
    /// command line's `--resolution`, `--degrees-per-frame`, …); errors name the file.
    pub fn recheck(&self) -> Result<(), SceneError> {
        self.check().map_err(|problem| SceneError { file: self.file.clone(), values: Values::AfterOverrides, problem: Box::new(problem) })
    }

    fn check(&self) -> Result<(), SceneProblem> {
        let out_of_range = |field: &str, value: Value, range: Range| SceneProblem::field(field, FieldProblem::OutOfRange { value, range });
        if self.objects.is_empty() {
            return Err(SceneProblem::field("objects", FieldProblem::Empty(Listing::Objects)));
        }
        // A scene whose effects are only surfel effects (ambient occlusion, indirect light)
        // needs no specular object; reflections, refractions and the plain F(|N·V|) runs do.
        let surfel_only = self.effects.as_ref().is_some_and(|e| !e.names(EffectFamily::SpecularPaths));
        if !surfel_only && self.specular_objects().next().is_none() {
            return Err(SceneProblem::field("objects", FieldProblem::Empty(Listing::SpecularObjects)));
        }
        if self.experiments.is_empty() {
            return Err(SceneProblem::field("measurements", FieldProblem::Empty(Listing::Measurements)));
        }
        check_resolution("resolution", self.resolution)?;
        check_resolution("timing.resolution", self.timing.resolution)?;
        let camera = &self.camera;
        if camera.axis.iter().map(|a| a * a).sum::<f64>().sqrt() < 1e-9 || camera.axis.iter().any(|a| !a.is_finite()) {
            return Err(SceneProblem::field("camera.axis", FieldProblem::ZeroVector { value: camera.axis }));
        }
        if !(camera.distance > 1.0 && camera.distance.is_finite()) {
            let range = Range::Above { low: 1.0, why: "objects fill the unit sphere" };
            return Err(out_of_range("camera.distance", Value::Number(camera.distance), range));
        }
        let counts = |low: u32, high: u32| Range::Integers { low: low.into(), high: high.into() };
        if !(1..=MAX_FRAMES).contains(&camera.frames) {
            return Err(out_of_range("camera.frames", Value::Integer(camera.frames.into()), counts(1, MAX_FRAMES)));
        }
        if !camera.degrees_per_frame.is_finite() {
            return Err(SceneProblem::field("camera.degrees_per_frame", FieldProblem::NotFinite));
        }
        if !(camera.fov_y_degrees > 0.0 && camera.fov_y_degrees < 180.0) {
            return Err(out_of_range("camera.fov_y_degrees", Value::Number(camera.fov_y_degrees), Range::Open { low: 0.0, high: 180.0 }));
        }
        if !(1..=MAX_REPEATS).contains(&self.timing.repeats) {
            return Err(out_of_range("timing.repeats", Value::Integer(self.timing.repeats.into()), counts(1, MAX_REPEATS)));
        }
        if self.timing.warmup > MAX_REPEATS {
            return Err(out_of_range("timing.warmup", Value::Integer(self.timing.warmup.into()), counts(0, MAX_REPEATS)));
        }
        if !(2..=8192).contains(&self.lut.size) {
            return Err(out_of_range("lut.size", Value::Integer(self.lut.size.into()), counts(2, 8192)));
        }
        Ok(())
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

fn check_resolution(name: &str, [w, h]: [u32; 2]) -> Result<(), SceneProblem> {
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        let range = Range::Sizes { largest: [8192, 8192] };
        return Err(SceneProblem::field(name, FieldProblem::OutOfRange { value: Value::Size([w, h]), range }));
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

    /// One lighting model for every effect: reflections and surfel effects both take
    /// `lights` (every kind), or the shorthand `light`; more than `MAX_LIGHTS` is an error
    /// naming the field.
    #[test]
    fn every_effect_takes_the_scene_s_lights() {
        let specular = "measurements: [image_error]\nobjects: [{mesh: sphere, material: a/b/c, method: exact}]\n";
        let both = "effects: {reflection: {max_depth: 1}, ambient_occlusion: {}}\n";
        let point = "{kind: point, position: [0, 2, 0], intensity: [1, 1, 1]}";
        let scene = parse(&format!("{specular}{both}lights: [{point}, {{kind: ambient, colour: [0.1, 0.1, 0.1]}}]\n")).unwrap();
        assert_eq!(
            scene.lights,
            vec![LightSource::Point { position: [0.0, 2.0, 0.0], intensity: [1.0; 3] }, LightSource::Ambient { colour: [0.1; 3] }]
        );
        let reflection_only = parse(&format!("{specular}effects: {{reflection: {{max_depth: 1}}}}\nlights: [{point}]\n")).unwrap();
        assert_eq!(reflection_only.lights.len(), 1);
        let many = [point; MAX_LIGHTS + 1].join(", ");
        let (field, kind) = field_problem(&format!("{specular}{both}lights: [{many}]\n"));
        let range = Range::Integers { low: 0, high: MAX_LIGHTS as u64 };
        assert_eq!((field.as_str(), kind), ("lights", FieldProblem::OutOfRange { value: Value::Integer(MAX_LIGHTS as u64 + 1), range }));
    }

    /// The problem of scene text that must not parse; its message names the file first.
    fn problem(text: &str) -> SceneProblem {
        let error = parse(text).unwrap_err();
        assert!(error.to_string().starts_with("scene test.yaml: "), "{text:?} gave {error}");
        assert_eq!(error.values, Values::AsWritten);
        *error.problem
    }

    /// The field and its problem, for text whose problem is one field's value.
    fn field_problem(text: &str) -> (String, FieldProblem) {
        match problem(text) {
            SceneProblem::Field { field, kind } => (field, kind),
            other => panic!("{text:?}: not a field's problem: {other:?}"),
        }
    }

    fn out_of_range(value: Value, range: Range) -> FieldProblem {
        FieldProblem::OutOfRange { value, range }
    }

    #[test]
    fn bad_scenes_are_named_errors() {
        let object = "objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [timing]\n";
        let known: Vec<&str> = Shading::ALL.iter().map(|s| s.name()).collect();
        let cases = [
            ("objects: []\nmeasurements: [timing]\n".to_string(), "objects", FieldProblem::Empty(Listing::Objects)),
            (
                "objects: [{mesh: cube, material: a/b/c, method: fast}]\nmeasurements: [timing]\n".to_string(),
                "objects[0].methods",
                FieldProblem::Unknown { what: "method", name: "fast".into(), known: known.clone() },
            ),
            (
                "objects: [{mesh: cube, material: gold, method: exact}]\nmeasurements: [timing]\n".to_string(),
                "objects[0].material",
                FieldProblem::NotAPageId { value: "gold".into() },
            ),
            (format!("{object}camera: {{axis: [0, 0, 0]}}\n"), "camera.axis", FieldProblem::ZeroVector { value: [0.0; 3] }),
            (
                format!("{object}resolution: [0, 4]\n"),
                "resolution",
                out_of_range(Value::Size([0, 4]), Range::Sizes { largest: [8192, 8192] }),
            ),
            (
                format!("{object}timing: {{resolution: [9000, 4]}}\n"),
                "timing.resolution",
                out_of_range(Value::Size([9000, 4]), Range::Sizes { largest: [8192, 8192] }),
            ),
            (
                format!("{object}camera: {{frames: 0}}\n"),
                "camera.frames",
                out_of_range(Value::Integer(0), Range::Integers { low: 1, high: 3600 }),
            ),
            (
                format!("{object}camera: {{distance: 0.5}}\n"),
                "camera.distance",
                out_of_range(Value::Number(0.5), Range::Above { low: 1.0, why: "objects fill the unit sphere" }),
            ),
            (format!("{object}camera: {{degrees_per_frame: .inf}}\n"), "camera.degrees_per_frame", FieldProblem::NotFinite),
            (
                format!("{object}camera: {{fov_y_degrees: 180}}\n"),
                "camera.fov_y_degrees",
                out_of_range(Value::Number(180.0), Range::Open { low: 0.0, high: 180.0 }),
            ),
            (
                format!("{object}timing: {{repeats: 0}}\n"),
                "timing.repeats",
                out_of_range(Value::Integer(0), Range::Integers { low: 1, high: 10_000 }),
            ),
            (
                format!("{object}timing: {{warmup: 10001}}\n"),
                "timing.warmup",
                out_of_range(Value::Integer(10_001), Range::Integers { low: 0, high: 10_000 }),
            ),
            (format!("{object}lut: {{size: 1}}\n"), "lut.size", out_of_range(Value::Integer(1), Range::Integers { low: 2, high: 8192 })),
            (
                "objects: [{mesh: cube, material: a/b/c}]\nmeasurements: [timing]\n".to_string(),
                "objects[0].methods",
                FieldProblem::Missing(Required::Methods),
            ),
            (
                "objects: [{mesh: cube, material: a/b/c, methods: []}]\nmeasurements: [timing]\n".to_string(),
                "objects[0].methods",
                FieldProblem::Empty(Listing::Methods),
            ),
            (
                "objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: []\n".to_string(),
                "measurements",
                FieldProblem::Empty(Listing::Measurements),
            ),
        ];
        for (text, field, expected) in cases {
            assert_eq!(field_problem(&text), (field.to_string(), expected), "{text:?}");
        }
        // What serde_norway refuses is a syntax problem, with its line and column.
        for (text, says, line) in [
            (object.replace("[timing]", "[speed]"), "unknown variant", 2),
            (
                "objects: [{mesh: cube, material: a/b/c, method: exact, colour: red}]\nmeasurements: [timing]\n".to_string(),
                "unknown field",
                1,
            ),
            ("objects: [\n".to_string(), "did not find expected", 2),
        ] {
            match problem(&text) {
                SceneProblem::Syntax(error) => {
                    assert!(error.to_string().contains(says) && error.location().is_some_and(|l| l.line() == line), "{text:?} gave {error}")
                }
                other => panic!("{text:?} gave {other:?}"),
            }
        }
        let deep = format!("objects: {}{}\n", "[".repeat(100), "]".repeat(100));
        assert!(matches!(problem(&deep), SceneProblem::TooDeep(d) if d.line == 1), "{deep}");
    }

    #[test]
    fn messages_name_the_field_the_value_and_the_range() {
        let object = "objects: [{mesh: cube, material: a/b/c, method: exact}]\nmeasurements: [timing]\n";
        let cases = [
            (format!("{object}resolution: [0, 4]\n"), "resolution 0x4 must be between 1x1 and 8192x8192"),
            (format!("{object}camera: {{distance: 0.5}}\n"), "camera.distance 0.5 must be above 1 (objects fill the unit sphere)"),
            (format!("{object}camera: {{fov_y_degrees: 180}}\n"), "camera.fov_y_degrees 180 must lie in (0, 180)"),
            (format!("{object}camera: {{axis: [0, 0, 0]}}\n"), "camera.axis [0.0, 0.0, 0.0] must be a non-zero vector"),
            (
                "objects: [{mesh: cube, material: a/b/c, method: fast}]\nmeasurements: [timing]\n".into(),
                "objects[0].methods: unknown method \"fast\"; known: exact, schlick",
            ),
            (
                "objects: [{mesh: cube, material: gold, method: exact}]\nmeasurements: [timing]\n".into(),
                "objects[0].material \"gold\" is not a page id shelf/book/page",
            ),
            ("objects: []\nmeasurements: [timing]\n".into(), "objects: the scene names no object"),
        ];
        for (text, expected) in cases {
            let message = parse(&text).unwrap_err().to_string();
            assert!(message.starts_with(&format!("scene test.yaml: {expected}")), "{text:?} gave {message:?}");
        }
        // A check after the command line's overrides says so.
        let mut scene = parse(object).unwrap();
        scene.camera.frames = 0;
        let error = scene.recheck().unwrap_err();
        assert_eq!(error.values, Values::AfterOverrides);
        assert_eq!(error.to_string(), "scene test.yaml: camera.frames 0 must lie in 1..=3600 (after command-line overrides)");
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
        let shorthand = Light { direction: [0.0, -1.0, 0.0], ambient: [0.1; 3], ..Light::default() };
        assert_eq!(scene.lights, shorthand.sources(), "`light` is a directional light and ambient, the colour by default");
        assert_eq!(scene.materials(), vec!["3d/metals/silver"]);
        assert_eq!(scene.shadings(), vec![Shading::Fresnel(FresnelMethod::Exact), Shading::Fresnel(FresnelMethod::Schlick)]);
    }

    #[test]
    fn effects_fields_are_errors_naming_the_field() {
        let specular = "  - {mesh: sphere, material: a/b/c, method: exact}\n";
        let plain = "measurements: [image_error]\nobjects:\n";
        let counts = |low: u64, high: u64| Range::Integers { low, high };
        let field_cases = [
            // Fields that need an effects section.
            (format!("{plain}{specular}  - {{mesh: room, diffuse: [1, 1, 1]}}\n"), "objects[1].diffuse", FieldProblem::NeedsEffects),
            (format!("{plain}  - {{mesh: sphere, material: a/b/c, method: exact, position: [1, 0, 0]}}\n"), "objects[0].position", FieldProblem::NeedsEffects),
            (format!("{plain}  - {{mesh: sphere, material: a/b/c, method: exact, scale: 2}}\n"), "objects[0].scale", FieldProblem::NeedsEffects),
            (format!("{plain}  - {{mesh: sphere, material: a/b/c, method: exact, subdivide: 1}}\n"), "objects[0].subdivide", FieldProblem::NeedsEffects),
            (format!("{plain}{specular}light: {{ambient: [0, 0, 0]}}\n"), "light", FieldProblem::NeedsEffects),
            // Bad values.
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room}}\n"), "objects[1].material", FieldProblem::Missing(Required::MaterialOrDiffuse)),
            (
                format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [2, 1, 1]}}\n"),
                "objects[1].diffuse",
                out_of_range(Value::Vector([2.0, 1.0, 1.0]), Range::Closed { low: 0.0, high: 1.0, each: Each::Channel }),
            ),
            (format!("{EFFECTS}objects:\n  - {{mesh: room, diffuse: [1, 1, 1]}}\n"), "objects", FieldProblem::Empty(Listing::SpecularObjects)),
            (
                format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: checker, size: 0, albedo: [0, 0, 0]}}}}\n"),
                "objects[1].pattern.checker.size",
                out_of_range(Value::Number(0.0), Range::Positive),
            ),
            (
                format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: checker, size: 1, albedo: [0, 0, -1]}}}}\n"),
                "objects[1].pattern.checker.albedo",
                out_of_range(Value::Vector([0.0, 0.0, -1.0]), Range::Closed { low: 0.0, high: 1.0, each: Each::Channel }),
            ),
            (
                format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: gradient, axis: [0, 0, 0], albedo: [0, 0, 0]}}}}\n"),
                "objects[1].pattern.gradient.axis",
                FieldProblem::ZeroVector { value: [0.0; 3] },
            ),
            (
                format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, scale: [1, 0, 1]}}\n"),
                "objects[0].scale",
                out_of_range(Value::Vector([1.0, 0.0, 1.0]), Range::Closed { low: 1e-4, high: 1e4, each: Each::Axis }),
            ),
            (
                format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, position: [0, 2e4, 0]}}\n"),
                "objects[0].position",
                out_of_range(Value::Vector([0.0, 2e4, 0.0]), Range::Within { bound: 1e4 }),
            ),
            (
                format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, subdivide: 1}}\n"),
                "objects[0].subdivide",
                FieldProblem::NeedsFamily(EffectFamily::Surfels),
            ),
            (format!("{plain}{specular}effects: {{}}\n"), "effects", FieldProblem::Empty(Listing::Effects)),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 0}}}}\n"), "effects.reflection.max_depth", out_of_range(Value::Integers(vec![0]), counts(1, 8))),
            (
                format!("{plain}{specular}effects: {{refraction: {{max_depth: [1, 9]}}}}\n"),
                "effects.refraction.max_depth",
                out_of_range(Value::Integers(vec![1, 9]), counts(1, 8)),
            ),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: []}}}}\n"), "effects.reflection.max_depth", out_of_range(Value::Integers(vec![]), counts(1, 8))),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{size: 2}}}}\n"),
                "effects.distance_maps.size",
                out_of_range(Value::Integer(2), counts(4, 4096)),
            ),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{layers: 1}}}}\n"),
                "effects.distance_maps.layers",
                out_of_range(Value::Integer(1), Range::Layers { low: 2, high: 8 }),
            ),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{linear_steps: 0}}}}\n"),
                "effects.distance_maps.linear_steps",
                out_of_range(Value::Integers(vec![0]), counts(1, 1024)),
            ),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, distance_maps: {{secant_steps: [1, 65]}}}}\n"),
                "effects.distance_maps.secant_steps",
                out_of_range(Value::Integers(vec![1, 65]), counts(0, 64)),
            ),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}}}\nlight: {{direction: [0, 0, 0]}}\n"),
                "light.direction",
                FieldProblem::ZeroVector { value: [0.0; 3] },
            ),
            (
                format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}}}\nlight: {{ambient: [0, .nan, 0]}}\n"),
                "light.ambient",
                FieldProblem::OutOfRange { value: Value::Vector([0.0, f64::NAN, 0.0]), range: Range::Closed { low: 0.0, high: 1e6, each: Each::Whole } },
            ),
        ];
        for (text, field, expected) in field_cases {
            let (got_field, got) = field_problem(&text);
            assert_eq!(got_field, field, "{text:?}");
            // NaN is not equal to itself: compare what the message shows.
            assert_eq!(format!("{got:?}"), format!("{expected:?}"), "{text:?}");
        }
        let conflicts = [
            (
                format!("{EFFECTS}objects:\n  - {{mesh: room, material: a/b/c, diffuse: [1, 1, 1], method: exact}}\n"),
                "objects[0]",
                Conflict::MaterialAndDiffuse,
            ),
            (
                format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], method: exact}}\n"),
                "objects[1]",
                Conflict::MethodsOnDiffuse,
            ),
            (
                format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, pattern: {{kind: plain}}}}\n"),
                "objects[0]",
                Conflict::PatternOnSpecular,
            ),
        ];
        for (text, at, expected) in conflicts {
            match problem(&text) {
                SceneProblem::Conflict { at: got_at, conflict } => assert_eq!((got_at.as_str(), conflict), (at, expected), "{text:?}"),
                other => panic!("{text:?} gave {other:?}"),
            }
        }
        for (text, says) in [
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: stripes}}}}\n"), "unknown variant `stripes`"),
            (format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [1, 1, 1], pattern: {{kind: checker, size: 1, albedo: [0, 0, 0], tilt: 2}}}}\n"), "unknown field `tilt`"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1, bounces: 2}}}}\n"), "unknown field `bounces`"),
            (format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}, glow: {{}}}}\n"), "unknown field `glow`"),
        ] {
            assert!(matches!(problem(&text), SceneProblem::Syntax(e) if e.to_string().contains(says)), "{text:?}");
        }
        let message = |text: String| parse(&text).unwrap_err().to_string();
        assert!(message(format!("{EFFECTS}objects:\n  - {{mesh: room, material: a/b/c, diffuse: [1, 1, 1], method: exact}}\n"))
            .ends_with("objects[0].material and diffuse: an object is either specular (a material) or diffuse, not both"));
        assert!(message(format!("{plain}{specular}effects: {{}}\n"))
            .ends_with("effects: name at least one effect: reflection, refraction, ambient_occlusion, indirect"));
        assert!(message(format!("{EFFECTS}objects:\n{specular}  - {{mesh: room, diffuse: [2, 1, 1]}}\n"))
            .ends_with("objects[1].diffuse [2.0, 1.0, 1.0] must lie in [0, 1] per channel"));
        assert!(message(format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, scale: [1, 0, 1]}}\n"))
            .ends_with("objects[0].scale [1.0, 0.0, 1.0] must lie in [1e-4, 1e4] on each axis"));
        assert!(message(format!("{EFFECTS}objects:\n  - {{mesh: sphere, material: a/b/c, method: exact, subdivide: 1}}\n"))
            .ends_with("objects[0].subdivide: only surfel effects (ambient_occlusion, indirect) use it"));
        assert!(message(format!("{plain}{specular}effects: {{reflection: {{max_depth: 1}}}}\nlight: {{colour: [1e7, 0, 0]}}\n"))
            .ends_with("light.colour [10000000.0, 0.0, 0.0] must lie in [0, 1e6]"));
    }
}
