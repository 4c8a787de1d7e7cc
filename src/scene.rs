//! Scene files for the GPU runner (issue 7): which objects, materials and Fresnel methods to
//! render, the camera path of the image-error measurement (SPEC §6) and which measurements
//! to take. Plain serde_yaml; lives outside the `gpu` feature so scene files can be checked
//! without wgpu.
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

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::fresnel::Method as FresnelMethod;

/// A Fresnel method of SPEC §5 as the shaders implement it, plus the two cost baselines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Exact,
    Schlick,
    SchlickNk,
    SchlickCompensated,
    Lazanyi,
    Nvidia,
    Lut,
    /// Baseline: a constant colour (F0) per material, no Fresnel at all.
    Constant,
    /// Baseline: one plain texture fetch at a coordinate that does not depend on cosθ.
    Texture,
}

impl Method {
    pub const ALL: [Method; 9] = [
        Method::Exact,
        Method::Schlick,
        Method::SchlickNk,
        Method::SchlickCompensated,
        Method::Lazanyi,
        Method::Nvidia,
        Method::Lut,
        Method::Constant,
        Method::Texture,
    ];

    /// The name in scene files and tables: the fresnel module's name for a SPEC §5 method.
    pub fn name(self) -> &'static str {
        match self.fresnel() {
            Some(method) => method.name(),
            None if self == Method::Constant => "constant",
            None => "texture",
        }
    }

    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The SPEC §5 method of the fresnel module this shader implements; `None` for the
    /// baselines (`constant`, `texture`).
    pub fn fresnel(self) -> Option<FresnelMethod> {
        Some(match self {
            Method::Exact => FresnelMethod::Exact,
            Method::Schlick => FresnelMethod::Schlick,
            Method::SchlickNk => FresnelMethod::SchlickNk,
            Method::SchlickCompensated => FresnelMethod::SchlickCompensated,
            Method::Lazanyi => FresnelMethod::Lazanyi,
            Method::Nvidia => FresnelMethod::Nvidia,
            Method::Lut => FresnelMethod::Lut,
            Method::Constant | Method::Texture => return None,
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the runner measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measurement {
    /// Fullscreen pass per (material, method), timed (`gpu_timing.csv`).
    Timing,
    /// Each object rendered with each method and with `exact` (`image_errors.csv`).
    ImageError,
}

impl Measurement {
    pub fn name(self) -> &'static str {
        match self {
            Measurement::Timing => "timing",
            Measurement::ImageError => "image_error",
        }
    }
}

/// A mesh: built-in `cube` or `sphere`, or an OBJ file (relative paths are taken from the
/// scene file's folder first, then from the working directory).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum MeshSource {
    Cube,
    Sphere,
    File(PathBuf),
}

impl MeshSource {
    fn parse(text: &str) -> MeshSource {
        match text {
            "cube" => MeshSource::Cube,
            "sphere" => MeshSource::Sphere,
            path => MeshSource::File(PathBuf::from(path)),
        }
    }

    /// Short name for tables: `cube`, `sphere` or the file stem (`nefertiti`).
    pub fn label(&self) -> String {
        match self {
            MeshSource::Cube => "cube".into(),
            MeshSource::Sphere => "sphere".into(),
            MeshSource::File(path) => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string()),
        }
    }
}

/// The camera path of SPEC §6: orbit around `axis` at `distance` (m), looking at the origin,
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
        Self { axis: default_axis(), distance: default_distance(), frames: default_frames(), degrees_per_frame: default_degrees(), fov_y_degrees: default_fov() }
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

/// One object: a mesh with one material (a page id) and the methods to render it with.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    pub mesh: MeshSource,
    pub material: String,
    pub methods: Vec<Method>,
}

/// A parsed and checked scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The file it came from (for messages and relative mesh paths); empty for inline text.
    pub file: PathBuf,
    pub resolution: [u32; 2],
    pub camera: CameraPath,
    pub objects: Vec<SceneObject>,
    pub measurements: Vec<Measurement>,
    pub timing: TimingSettings,
    pub lut: LutSettings,
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    mesh: String,
    material: String,
    #[serde(alias = "method")]
    methods: OneOrMany,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default = "default_resolution")]
    resolution: [u32; 2],
    #[serde(default)]
    camera: CameraPath,
    objects: Vec<RawObject>,
    measurements: Vec<Measurement>,
    #[serde(default)]
    timing: TimingSettings,
    #[serde(default)]
    lut: LutSettings,
}

fn default_resolution() -> [u32; 2] {
    [512, 512]
}

impl Scene {
    /// Read and check a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError { file: path.into(), problem: format!("cannot read: {e}") })?;
        Scene::parse(&text, path)
    }

    /// Parse and check scene text; `file` names it in errors and anchors relative mesh paths.
    pub fn parse(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let error = |problem: String| SceneError { file: file.into(), problem };
        let raw: RawScene = serde_yaml::from_str(text).map_err(|e| error(e.to_string()))?;
        let mut objects = Vec::new();
        for (i, object) in raw.objects.into_iter().enumerate() {
            let names = match object.methods {
                OneOrMany::One(name) => vec![name],
                OneOrMany::Many(names) => names,
            };
            let mut methods = Vec::new();
            for name in names {
                let method = Method::from_name(&name).ok_or_else(|| {
                    let known: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                    error(format!("objects[{i}]: unknown method {name:?}; known: {}", known.join(", ")))
                })?;
                if !methods.contains(&method) {
                    methods.push(method);
                }
            }
            objects.push(SceneObject { mesh: MeshSource::parse(&object.mesh), material: object.material, methods });
        }
        let scene = Scene {
            file: file.into(),
            resolution: raw.resolution,
            camera: raw.camera,
            objects,
            measurements: raw.measurements,
            timing: raw.timing,
            lut: raw.lut,
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
        if self.measurements.is_empty() {
            return Err("measurements: name at least one of timing, image_error".into());
        }
        for (i, object) in self.objects.iter().enumerate() {
            if object.methods.is_empty() {
                return Err(format!("objects[{i}]: no method named"));
            }
            if object.material.split('/').count() != 3 {
                return Err(format!("objects[{i}]: material {:?} is not a page id shelf/book/page", object.material));
            }
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
        if camera.frames == 0 {
            return Err("camera.frames must be at least 1".into());
        }
        if !camera.degrees_per_frame.is_finite() {
            return Err("camera.degrees_per_frame must be finite".into());
        }
        if !(camera.fov_y_degrees > 0.0 && camera.fov_y_degrees < 180.0) {
            return Err(format!("camera.fov_y_degrees {} must lie in (0, 180)", camera.fov_y_degrees));
        }
        if self.timing.repeats == 0 {
            return Err("timing.repeats must be at least 1".into());
        }
        if !(2..=8192).contains(&self.lut.size) {
            return Err(format!("lut.size {} must lie in 2..=8192", self.lut.size));
        }
        Ok(())
    }

    pub fn wants(&self, measurement: Measurement) -> bool {
        self.measurements.contains(&measurement)
    }

    /// Distinct material page ids in order of first appearance.
    pub fn materials(&self) -> Vec<String> {
        let mut pages: Vec<String> = Vec::new();
        for object in &self.objects {
            if !pages.contains(&object.material) {
                pages.push(object.material.clone());
            }
        }
        pages
    }

    /// Distinct methods in the order of `Method::ALL`.
    pub fn methods(&self) -> Vec<Method> {
        Method::ALL.into_iter().filter(|m| self.objects.iter().any(|o| o.methods.contains(m))).collect()
    }

    /// Distinct (material, method) pairs, the units of the timing measurement.
    pub fn material_methods(&self) -> Vec<(String, Method)> {
        let mut pairs: Vec<(String, Method)> = Vec::new();
        for material in self.materials() {
            for method in Method::ALL {
                if self.objects.iter().any(|o| o.material == material && o.methods.contains(&method)) {
                    pairs.push((material.clone(), method));
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
        assert_eq!(scene.objects[0].methods, vec![Method::Schlick]);
        assert_eq!(scene.objects[0].mesh, MeshSource::Cube);
    }

    #[test]
    fn method_names_match_serde_and_the_fresnel_module() {
        for method in Method::ALL {
            assert_eq!(Method::from_name(method.name()), Some(method));
            assert_eq!(serde_yaml::to_string(&method).unwrap().trim(), method.name());
            assert_eq!(method.fresnel().map(|m| m.name()).unwrap_or(method.name()), method.name());
        }
        assert_eq!(Method::ALL.iter().filter(|m| m.fresnel().is_none()).count(), 2);
    }

    #[test]
    fn pairs_and_methods_are_distinct() {
        let scene = parse(
            "objects:\n  - {mesh: cube, material: a/b/c, methods: [lut, exact, lut]}\n  - {mesh: sphere, material: a/b/c, methods: [exact]}\n  - {mesh: x.obj, material: d/e/f, methods: [schlick]}\nmeasurements: [timing]\n",
        )
        .unwrap();
        assert_eq!(scene.materials(), vec!["a/b/c", "d/e/f"]);
        assert_eq!(scene.methods(), vec![Method::Exact, Method::Schlick, Method::Lut]);
        assert_eq!(scene.material_methods().len(), 3);
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
        ];
        for (text, expected) in cases {
            let message = parse(text).unwrap_err().to_string();
            assert!(message.contains(expected) && message.contains("test.yaml"), "{text:?} gave {message:?}");
        }
    }
}
