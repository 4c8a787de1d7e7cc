//! The bounce loop shared by every CPU renderer of effects, and the f64 reference tracer.
//!
//! A frame: one ray per pixel centre from the camera of the image-error path; the nearest
//! surface it meets is what a rasteriser would show. A diffuse surface shows its lit colour;
//! a specular one starts a path: at each specular surface the path splits into the
//! branches of [`optics::scatter`] (reflection ×F, refraction ×(1 − F), total internal
//! reflection ×1), each traced on to the next surface, until a diffuse surface ends it
//! with its radiance, the ray leaves the scene (black) or no bounce is left (black). This
//! is the loop of Umenhoffer, Patow and Szirmay-Kalos (GPU Gems 3 ch. 17, listing 17-5)
//! with both branches of a dielectric kept instead of one.
//!
//! What finds the next surface is a [`Tracer`]: the exact one here ([`ReferenceTracer`]:
//! the BVH over the same triangles, smooth normals, f64), or a distance map
//! (`super::distance_map`). Pixels are rendered in parallel with rayon.

use anyhow::Result;
use glam::DVec3;
use rayon::prelude::*;

use super::geometry::Geometry;
use super::optics::{scatter, Allowed, SpecularOptics};
use crate::scene::lights::unshadowed;
use crate::scene::mesh::{self, Mesh};
pub use crate::scene::SpecularMaterial;
use crate::scene::{CameraPath, Depths, Diffuse, LightSource, Role, Scene, SceneError, SceneMaterial, SceneProblem};
use nklut_optics::fresnel::{LutSpec, Method};
use nklut_optics::spectrum::{Channels, Index};

/// What a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// A specular object (its index in the scene).
    Specular(usize),
    /// A diffuse surface showing this radiance (linear RGB).
    Diffuse([f64; 3]),
}

/// The surface a ray meets: where, its unit shading normal, the unit normal of the
/// surface's own plane (the triangle's; a distance map knows only its texel's normal and
/// gives that), and what it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub point: DVec3,
    pub normal: DVec3,
    pub geometric: DVec3,
    pub surface: Surface,
    /// The triangle, where the tracer knows it (so a ray leaving it does not hit it again).
    pub triangle: Option<u32>,
}

/// Finds the next surface along a ray.
pub trait Tracer: Sync {
    /// The nearest surface along origin + t·direction (unit direction), leaving the surface
    /// `from` the ray starts on.
    fn trace(&self, origin: DVec3, direction: DVec3, from: &SurfaceHit) -> Option<SurfaceHit>;
}

/// An object as the tracers see it.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectOptics {
    Specular(SpecularMaterial),
    Diffuse(Diffuse),
}

/// A scene ready to trace: its triangles, each object's optics and the light.
pub struct Stage {
    /// Each object's placed mesh, in the scene's order (what the GPU rasterises).
    pub meshes: Vec<Mesh>,
    pub geometry: Geometry,
    pub objects: Vec<ObjectOptics>,
    pub lights: Vec<LightSource>,
    /// The channels' wavelengths (nm; red, green, blue) the materials' indices were taken
    /// at: where the reference attenuates each channel.
    pub channels_nm: [f64; 3],
    /// Metres per scene unit (the scene's `effects.metres_per_unit`, 1 unless it says
    /// otherwise): the length Beer–Lambert attenuation is measured in.
    pub metres_per_unit: f64,
    /// Each object's index on the 1 nm grid of `colors` (360–830 nm), where its material
    /// came with its page's data: what the spectral reference traces (`super::spectral`).
    pub spectra: Vec<Option<Vec<Index>>>,
}

impl Stage {
    /// Place every object's mesh; `material` gives the optical constants of a page id.
    pub fn from_scene(scene: &Scene, material: impl Fn(&str) -> Option<SpecularMaterial>) -> Result<Stage> {
        let named = |problem: SceneProblem| SceneError::new(&scene.file, problem);
        let mut meshes = Vec::new();
        let mut objects = Vec::new();
        let budget = nklut_tables::budget::MemoryBudget::of_machine();
        let mut triangles = 0u128;
        for (i, object) in scene.objects.iter().enumerate() {
            let loaded =
                mesh::load(&object.mesh, |p| scene.mesh_path(p)).map_err(|error| named(SceneProblem::Mesh { object: i, error }))?;
            // The geometry so far, this mesh's triangles included, before its copy, the
            // triangles and the BVH are built.
            triangles += loaded.triangles() as u128;
            super::geometry::check_loaded(&budget, i, triangles, &object.mesh.label()).map_err(|e| named(SceneProblem::Memory(e)))?;
            meshes.push(loaded.placed(&object.placement));
            objects.push(match &object.role {
                Role::Specular(s) => ObjectOptics::Specular(
                    material(&s.material).ok_or_else(|| named(SceneProblem::NoOpticalConstants { object: i, page: s.material.clone() }))?,
                ),
                Role::Diffuse(d) => ObjectOptics::Diffuse(d.clone()),
            });
        }
        let geometry = Geometry::new(&meshes).map_err(|e| named(SceneProblem::Geometry(e)))?;
        Ok(Stage {
            meshes,
            geometry,
            objects,
            lights: scene.lights.clone(),
            channels_nm: Channels::default().nanometres(),
            metres_per_unit: scene.effects.as_ref().map_or(1.0, |e| e.metres_per_unit),
            spectra: vec![None; scene.objects.len()],
        })
    }

    /// The Fresnel curves of every specular object for one method (`None` for diffuse ones).
    pub fn optics(&self, method: Method, lut: LutSpec) -> Vec<Option<SpecularOptics>> {
        self.objects
            .iter()
            .map(|o| match o {
                ObjectOptics::Specular(m) => Some(SpecularOptics::new(&m.channels, m.kind, method, lut)),
                ObjectOptics::Diffuse(_) => None,
            })
            .collect()
    }

    /// The f64 reference's optics of every specular object ([`SpecularOptics::reference`]:
    /// exact Fresnel, the transmitted-angle rule from inside, Beer–Lambert attenuation).
    pub fn reference_optics(&self) -> Vec<Option<SpecularOptics>> {
        self.objects
            .iter()
            .map(|o| match o {
                ObjectOptics::Specular(m) => Some(SpecularOptics::reference(&m.channels, m.kind, self.channels_nm, self.metres_per_unit)),
                ObjectOptics::Diffuse(_) => None,
            })
            .collect()
    }

    pub fn is_specular(&self, object: usize) -> bool {
        matches!(self.objects[object], ObjectOptics::Specular(_))
    }

    /// What a ray sees at a geometric hit: a specular object, or a diffuse surface's lit colour.
    pub fn surface(&self, object: usize, point: DVec3, normal: DVec3) -> Surface {
        match &self.objects[object] {
            ObjectOptics::Specular(_) => Surface::Specular(object),
            ObjectOptics::Diffuse(d) => Surface::Diffuse(unshadowed(
                &self.lights,
                d.albedo_at(point.to_array(), normal.to_array()),
                point.to_array(),
                normal.to_array(),
            )),
        }
    }

    /// The nearest surface of the exact geometry.
    pub fn nearest(&self, origin: DVec3, direction: DVec3, leaving: Option<u32>) -> Option<SurfaceHit> {
        let hit = self.geometry.nearest(origin, direction, leaving, |_| true)?;
        Some(SurfaceHit {
            point: hit.point,
            normal: hit.normal,
            geometric: hit.geometric,
            surface: self.surface(hit.object, hit.point, hit.normal),
            triangle: Some(hit.triangle),
        })
    }
}

/// The exact tracer: the BVH over the scene's triangles in f64.
pub struct ReferenceTracer<'a> {
    pub stage: &'a Stage,
}

impl Tracer for ReferenceTracer<'_> {
    fn trace(&self, origin: DVec3, direction: DVec3, from: &SurfaceHit) -> Option<SurfaceHit> {
        self.stage.nearest(origin, direction, from.triangle)
    }
}

/// One path's rules: the Fresnel curves per object and how many bounces each effect allows.
#[derive(Clone, Copy)]
pub struct PathRules<'a> {
    pub optics: &'a [Option<SpecularOptics>],
    pub depths: Depths,
}

/// Radiance leaving `hit` towards −`incoming` after `bounces` specular bounces; `rays`
/// counts the rays traced.
pub fn radiance(rules: PathRules, tracer: &dyn Tracer, hit: &SurfaceHit, incoming: DVec3, bounces: u32, rays: &mut u64) -> [f64; 3] {
    let object = match hit.surface {
        Surface::Diffuse(radiance) => return radiance,
        Surface::Specular(object) => object,
    };
    let Some(optics) = &rules.optics[object] else { return [0.0; 3] };
    let allowed = Allowed { reflection: bounces < rules.depths.reflection, refraction: bounces < rules.depths.refraction };
    let mut total = [0.0; 3];
    for branch in scatter(optics, incoming, hit.normal, hit.geometric, allowed) {
        *rays += 1;
        if let Some(next) = tracer.trace(hit.point, branch.direction, hit) {
            let seen = radiance(rules, tracer, &next, branch.direction, bounces + 1, rays);
            let kept = if branch.inside { optics.transmittance(next.point.distance(hit.point)) } else { [1.0; 3] };
            for c in 0..3 {
                total[c] += branch.weight[c] * kept[c] * seen[c];
            }
        }
    }
    total
}

/// A pinhole camera on the image-error path, rays through pixel centres.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_half_y: f64,
    aspect: f64,
    pub width: u32,
    pub height: u32,
    /// Where in its pixel each ray passes, from the centre (pixels, x right, y down).
    shift: [f64; 2],
}

impl Camera {
    /// Frame `frame` of `path` for a `width`×`height` image: the eye of `scene::camera::eye`
    /// looking at the origin with the path's axis up, like `scene::camera::frame`.
    pub fn new(path: &CameraPath, frame: u32, width: u32, height: u32) -> Camera {
        let eye = DVec3::from_array(crate::scene::camera::eye(path, frame));
        let forward = (-eye).normalize();
        let right = forward.cross(DVec3::from_array(path.axis).normalize()).normalize();
        let up = right.cross(forward);
        Camera {
            eye,
            forward,
            right,
            up,
            tan_half_y: (path.fov_y_degrees.to_radians() / 2.0).tan(),
            aspect: width as f64 / height as f64,
            width,
            height,
            shift: [0.0; 2],
        }
    }

    /// The camera whose rays pass `dx`, `dy` pixels (x right, y down) from each pixel's
    /// centre: the frame seen by samples that stray from the centres by as much.
    pub fn shifted(&self, dx: f64, dy: f64) -> Camera {
        Camera { shift: [dx, dy], ..*self }
    }

    /// `point` in view space: x right, y up, the camera at the origin looking down −z.
    pub fn view_point(&self, point: DVec3) -> DVec3 {
        self.view_direction(point - self.eye)
    }

    /// A direction in view space.
    pub fn view_direction(&self, direction: DVec3) -> DVec3 {
        DVec3::new(direction.dot(self.right), direction.dot(self.up), -direction.dot(self.forward))
    }

    /// The focal length in pixels: the view-space point (x, y, z) lies at pixel coordinates
    /// (w/2 + f·x/−z, h/2 − f·y/−z), the inverse of [`Camera::ray`].
    pub fn focal_pixels(&self) -> f64 {
        self.height as f64 / (2.0 * self.tan_half_y)
    }

    /// Unit direction through the centre of pixel (x, y), y down (moved by
    /// [`Camera::shifted`]'s offset).
    pub fn ray(&self, x: u32, y: u32) -> DVec3 {
        let ndc_x = 2.0 * (x as f64 + 0.5 + self.shift[0]) / self.width as f64 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y as f64 + 0.5 + self.shift[1]) / self.height as f64;
        (self.forward + self.right * (ndc_x * self.tan_half_y * self.aspect) + self.up * (ndc_y * self.tan_half_y)).normalize()
    }
}

/// A rendered frame: linear RGB radiance per pixel (row-major, top row first), the
/// specular object each pixel shows (where the effect is; `None`: a diffuse surface or
/// nothing), and the rays it took.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedFrame {
    pub width: u32,
    pub height: u32,
    pub radiance: Vec<[f64; 3]>,
    pub seen: Vec<Option<usize>>,
    pub rays: u64,
}

/// Render one frame: the nearest surface of the exact geometry per pixel (what rasterising
/// shows), then the path through `tracer_for(object)` of the specular object seen.
pub fn render<'t, F>(stage: &Stage, camera: &Camera, rules: PathRules, tracer_for: F) -> TracedFrame
where
    F: Sync + Fn(usize) -> &'t dyn Tracer,
{
    let rows: Vec<TracedFrame> = (0..camera.height)
        .into_par_iter()
        .map(|y| {
            let mut rays = 0;
            let mut radiance_row = Vec::with_capacity(camera.width as usize);
            let mut seen_row = Vec::with_capacity(camera.width as usize);
            for x in 0..camera.width {
                let direction = camera.ray(x, y);
                rays += 1;
                let (value, seen) = match stage.nearest(camera.eye, direction, None) {
                    None => ([0.0; 3], None),
                    Some(hit) => match hit.surface {
                        Surface::Diffuse(radiance) => (radiance, None),
                        Surface::Specular(object) => (radiance(rules, tracer_for(object), &hit, direction, 0, &mut rays), Some(object)),
                    },
                };
                radiance_row.push(value);
                seen_row.push(seen);
            }
            TracedFrame { width: camera.width, height: 1, radiance: radiance_row, seen: seen_row, rays }
        })
        .collect();
    TracedFrame::stack(camera.width, rows)
}

impl TracedFrame {
    /// The frame of `rows` (each one row of `width` pixels, top first), their rays summed.
    pub fn stack(width: u32, rows: Vec<TracedFrame>) -> TracedFrame {
        let mut frame = TracedFrame { width, height: rows.len() as u32, radiance: Vec::new(), seen: Vec::new(), rays: 0 };
        for row in rows {
            frame.radiance.extend(row.radiance);
            frame.seen.extend(row.seen);
            frame.rays += row.rays;
        }
        frame
    }
}

/// The f64 reference frame: exact geometry, exact Fresnel, the transmitted-angle rule
/// from inside and Beer–Lambert attenuation ([`Stage::reference_optics`]).
pub fn reference(stage: &Stage, camera: &Camera, depths: Depths) -> TracedFrame {
    reference_with(stage, camera, depths, &stage.reference_optics())
}

/// The reference tracer's frame with the given optics per object (another source of the
/// channel indices, say).
pub fn reference_with(stage: &Stage, camera: &Camera, depths: Depths, optics: &[Option<SpecularOptics>]) -> TracedFrame {
    let tracer = ReferenceTracer { stage };
    render(stage, camera, PathRules { optics, depths }, |_| &tracer)
}

/// A scene file's stage with the optical constants of its materials.
pub fn stage_from_table(scene: &Scene, table: &[SceneMaterial]) -> Result<Stage> {
    let mut stage = Stage::from_scene(scene, |page| table.iter().find(|m| m.page == page).map(|m| m.optics))?;
    stage.spectra = scene
        .objects
        .iter()
        .map(|o| o.specular().and_then(|s| table.iter().find(|m| m.page == s.material)).and_then(|m| m.spectrum.clone()))
        .collect();
    Ok(stage)
}
