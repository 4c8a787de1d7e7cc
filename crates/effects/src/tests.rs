//! Effects end to end on small frames: the reference tracer against values derived by hand,
//! and the distance-map twin against the reference (geometry error) and against itself
//! with another Fresnel method (Fresnel error).

use std::path::{Path, PathBuf};

use super::distance_map::DistanceMap;
use super::experiment::{distance_maps, twin_frame};
use super::image_error::{compare, FrameError};
use super::trace::{reference, stage_from_table, Camera, Stage, TracedFrame};
use crate::scene::{Depths, Scene, SceneMaterial, SearchSteps};
use nklut_optics::fresnel::{exact, LutSpec, Method};
use nklut_optics::spectrum::{Index, Kind};

fn material(page: &str, n: [f64; 3], k: [f64; 3], kind: Kind) -> SceneMaterial {
    SceneMaterial::new(page, std::array::from_fn(|c| Index::new(n[c], k[c])), kind)
}

fn materials() -> Vec<SceneMaterial> {
    vec![
        material("test/metals/silver", [0.15, 0.12, 0.13], [4.5, 3.3, 2.7], Kind::Conductor),
        material("test/metals/gold", [0.16, 0.5, 1.2], [3.8, 2.2, 1.8], Kind::Conductor),
        material("test/glass/crown", [1.5, 1.5, 1.5], [0.0; 3], Kind::Dielectric),
        material("test/liquids/water", [1.331, 1.334, 1.337], [0.0; 3], Kind::Dielectric),
    ]
}

fn stage(text: &str) -> (Scene, Stage) {
    let scene = Scene::parse(text, &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/test.yaml")).unwrap();
    let stage = stage_from_table(&scene, &materials()).unwrap();
    (scene, stage)
}

/// A sphere of radius ½ at the centre of a 6 m room lit by ambient light only, so every
/// wall shows its albedo (0.5, 0.6, 0.7) whatever its normal.
fn ambient_room(sphere: &str, effects: &str) -> String {
    format!(
        "measurements: [image_error]\ncamera: {{axis: [0, 1, 0], distance: 2.0}}\neffects: {effects}\nlight: {{colour: [0, 0, 0], ambient: [1, 1, 1]}}\nobjects:\n  - {{mesh: sphere, scale: 0.5, material: {sphere}, method: exact}}\n  - {{mesh: room, scale: 3, diffuse: [0.5, 0.6, 0.7]}}\n"
    )
}

const ALBEDO: [f64; 3] = [0.5, 0.6, 0.7];

/// The centre pixel of a 9×9 frame, whose ray runs through the sphere's centre.
fn centre_pixel(scene: &Scene, stage: &Stage, depths: Depths) -> [f64; 3] {
    let camera = Camera::new(&scene.camera, 0, 9, 9);
    let frame = reference(stage, &camera, depths);
    assert_eq!(frame.seen[40], Some(0));
    frame.radiance[40]
}

fn close(value: [f64; 3], expected: [f64; 3], tolerance: f64) -> bool {
    value.iter().zip(expected).all(|(v, e)| (v - e).abs() <= tolerance * e)
}

#[test]
fn a_mirror_sphere_shows_f0_times_the_wall_behind_the_camera() {
    // Normal incidence: the ray reflects straight back to the wall behind the camera, so the
    // pixel is F(n, k, cos 0)·albedo per channel. The smooth normal of the tessellated
    // sphere is radial there to ~1e-3 rad, and F is flat at normal incidence (∂F/∂cos = 0).
    let (scene, stage) = stage(&ambient_room("test/metals/silver", "{reflection: {max_depth: 1}}"));
    let expected: [f64; 3] = std::array::from_fn(|c| {
        let index = materials()[0].optics.channels[c];
        exact(index.n, index.k, 1.0) * ALBEDO[c]
    });
    let pixel = centre_pixel(&scene, &stage, Depths { reflection: 1, refraction: 0 });
    assert!(close(pixel, expected, 1e-6), "{pixel:?} vs {expected:?}");
}

#[test]
fn a_glass_sphere_at_depth_two_shows_the_hand_derived_sum_of_its_paths() {
    // Through the centre at normal incidence, F0 = 0.04 from both sides. Depth 2, both
    // effects: reflect to the wall behind the camera (F0), or enter (1 − F0) and leave
    // (1 − F0) to the wall behind the sphere; the path reflected inside is on the glass
    // after two bounces and ends black. Refraction only: (1 − F0)²; reflection only: F0.
    let (scene, stage) = stage(&ambient_room("test/glass/crown", "{reflection: {max_depth: 2}, refraction: {max_depth: 2}}"));
    let f0 = 0.04;
    let cases = [
        (Depths { reflection: 2, refraction: 2 }, f0 + (1.0 - f0) * (1.0 - f0)),
        (Depths { reflection: 0, refraction: 2 }, (1.0 - f0) * (1.0 - f0)),
        (Depths { reflection: 1, refraction: 0 }, f0),
        (Depths { reflection: 0, refraction: 1 }, 0.0),
    ];
    for (depths, weight) in cases {
        let pixel = centre_pixel(&scene, &stage, depths);
        let expected = ALBEDO.map(|a| a * weight);
        assert!(close(pixel, expected, 1e-6) && (weight > 0.0 || pixel == [0.0; 3]), "{depths:?}: {pixel:?} vs {expected:?}");
    }
}

/// A mirror sphere at the centre of a room whose walls carry a linear albedo ramp.
const RAMP_ROOM: &str = "measurements: [image_error]\ncamera: {axis: [0, 1, 0], distance: 1.6, fov_y_degrees: 40}\neffects: {reflection: {max_depth: 1}}\nlight: {direction: [-0.3, -1, -0.5], colour: [0.7, 0.7, 0.7], ambient: [0.3, 0.3, 0.3]}\nobjects:\n  - {mesh: sphere, scale: 0.5, material: test/metals/silver, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.1, 0.1, 0.1], pattern: {kind: gradient, axis: [0.2222222222222222, 0.1111111111111111, 0], albedo: [0.9, 0.9, 0.9]}}\n";

fn twin(stage: &Stage, camera: &Camera, maps: &[Option<DistanceMap>], method: Method, depths: Depths, steps: SearchSteps) -> TracedFrame {
    twin_frame(stage, camera, maps, method, depths, steps, LutSpec::default())
}

fn maps(stage: &Stage, size: u32, layers: u32) -> Vec<Option<DistanceMap>> {
    distance_maps(stage, size, layers)
}

#[test]
fn a_mirror_sphere_at_depth_one_matches_the_reference_to_a_texel() {
    // The sphere sits at the map's centre and the room is the cube around it, so each cube
    // face maps linearly onto its wall: a texel covers a (2h/N)² square of wall (h = 3),
    // whose points lie within √2·h/N of the texel's centre point. The walls' albedo ramps by
    // 0.8 as p·a runs over 2 with a = (2, 1, 0)/9, a gradient of 0.8·|a|/2 = 0.8·√5/18 per
    // unit length, under light of at most ambient + colour = 1: a hit found in its own texel
    // returns radiance within 0.8·(√5/18)·√2·h/N of the truth (F ≤ 1 only shrinks it). The
    // mean over the sphere's pixels is held to that per-pixel bound.
    let (scene, stage) = stage(RAMP_ROOM);
    let camera = Camera::new(&scene.camera, 0, 24, 24);
    let depths = Depths { reflection: 1, refraction: 0 };
    let truth = reference(&stage, &camera, depths);
    let steps = SearchSteps { linear: 80, secant: 10 };
    let mut errors = Vec::new();
    for size in [16, 64] {
        let error = compare(&twin(&stage, &camera, &maps(&stage, size, 2), Method::Exact, depths, steps), &truth);
        let bound = 0.8 * (5f64.sqrt() / 18.0) * 2f64.sqrt() * 3.0 / size as f64;
        assert!(error.pixels > 100, "{error:?}");
        assert!(error.mean_absolute < bound, "size {size}: mean {:.3e} over the bound {bound:.3e}", error.mean_absolute);
        errors.push(error.mean_absolute);
    }
    eprintln!("mirror sphere, depth 1, mean |Δ| at 16² and 64² texels: {errors:?}");
    assert!(errors[1] < errors[0] / 2.0, "four times the texels: {errors:?}");
}

/// The teapot scene's mesh (the shared meshes are part of every checkout's surroundings,
/// CI's included: a missing one is a failure, not a test passed by skipping).
fn teapot() -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/teapot.obj");
    assert!(path.exists(), "{} is missing", path.display());
    path
}

fn geometry_errors(text: &str, size: u32, depths: Depths, configurations: &[SearchSteps]) -> Vec<FrameError> {
    let (scene, stage) = stage(text);
    let camera = Camera::new(&scene.camera, 0, 24, 24);
    let truth = reference(&stage, &camera, depths);
    let maps = maps(&stage, size, 3);
    configurations.iter().map(|&steps| compare(&twin(&stage, &camera, &maps, Method::Exact, depths, steps), &truth)).collect()
}

#[test]
fn image_error_falls_as_linear_and_secant_steps_rise_on_the_teapot() {
    let teapot = teapot();
    let text = format!(
        "measurements: [image_error]\ncamera: {{axis: [0, 1, 0.3], distance: 1.8, fov_y_degrees: 50}}\neffects: {{reflection: {{max_depth: 1}}}}\nobjects:\n  - {{mesh: {}, material: test/metals/gold, method: exact}}\n  - {{mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.8], pattern: {{kind: checker, size: 0.5, albedo: [0.15, 0.2, 0.5]}}}}\n",
        teapot.display()
    );
    let steps = [
        SearchSteps { linear: 15, secant: 1 },
        SearchSteps { linear: 15, secant: 10 },
        SearchSteps { linear: 80, secant: 1 },
        SearchSteps { linear: 80, secant: 10 },
    ];
    // Depth 1 on a 128² map: deeper, the teapot's reflections of itself (which a ray leaving
    // a surface cannot find within the start band) and nearest-texel checker edges add
    // errors that do not depend on the steps (BENCHMARKS.md records depth 2).
    let errors = geometry_errors(&text, 128, Depths { reflection: 1, refraction: 0 }, &steps);
    let mean: Vec<f64> = errors.iter().map(|e| e.mean_absolute).collect();
    eprintln!("teapot geometry error (mean absolute) 15/1, 15/10, 80/1, 80/10: {mean:?}");
    assert!(mean[0] > mean[3], "15/1 {} should err more than 80/10 {}", mean[0], mean[3]);
    // More steps of either kind never make it worse.
    assert!(mean[0] >= mean[1] && mean[0] >= mean[2] && mean[1] >= mean[3] && mean[2] >= mean[3], "{mean:?}");
}

#[test]
fn exact_against_itself_has_no_fresnel_error_and_schlick_on_water_compounds_with_depth() {
    // A water sphere reflecting and refracting in a checker room: the Fresnel error is the
    // method against exact on the same distance-map paths.
    let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0.2], distance: 1.6, fov_y_degrees: 45}\neffects: {reflection: {max_depth: [1, 3]}, refraction: {max_depth: [1, 3]}}\nobjects:\n  - {mesh: sphere, scale: 0.6, material: test/liquids/water, methods: [exact, schlick]}\n  - {mesh: room, scale: 3, diffuse: [0.8, 0.8, 0.8], pattern: {kind: checker, size: 0.75, albedo: [0.1, 0.3, 0.6]}}\n";
    let (scene, stage) = stage(text);
    let camera = Camera::new(&scene.camera, 0, 20, 20);
    let maps = maps(&stage, 32, 3);
    let steps = SearchSteps { linear: 30, secant: 4 };
    let fresnel_error = |depth: u32| {
        let depths = Depths { reflection: depth, refraction: depth };
        let exact_frame = twin(&stage, &camera, &maps, Method::Exact, depths, steps);
        assert_eq!(compare(&twin(&stage, &camera, &maps, Method::Exact, depths, steps), &exact_frame).mean_relative, Some(0.0));
        compare(&twin(&stage, &camera, &maps, Method::Schlick, depths, steps), &exact_frame)
    };
    let (depth1, depth3) = (fresnel_error(1), fresnel_error(3));
    eprintln!("schlick on water, Fresnel error: depth 1 {depth1:?}\n  depth 3 {depth3:?}");
    // Each extra bounce multiplies in another Schlick F or 1 − F: the absolute and the colour
    // error grow with depth. (The mean relative error falls: at depth 1 the pixel is mostly
    // F·L, whose relative error is Schlick's own; deeper, transmitted light weighted by
    // 1 − F, which Schlick gets relatively closer, dominates.)
    assert!(depth3.mean_absolute > depth1.mean_absolute, "depth 3 {depth3:?} vs depth 1 {depth1:?}");
    assert!(depth3.mean_delta_e2000 > depth1.mean_delta_e2000, "depth 3 {depth3:?} vs depth 1 {depth1:?}");
}

#[test]
fn the_experiment_renders_only_what_the_scene_names() {
    use super::experiment::{image_errors, Settings};
    // One specular object among diffuse ones: one cube map; reflection depths {1, 2} × one
    // search configuration × one frame: two reference frames; exact plus schlick: the exact
    // twin is shared, so two twin frames per configuration.
    let text = "resolution: [6, 6]\ncamera: {axis: [0, 1, 0], distance: 2.0, frames: 1}\neffects: {reflection: {max_depth: [1, 2]}, distance_maps: {size: 8, layers: 2}}\nobjects:\n  - {mesh: sphere, scale: 0.5, material: test/metals/gold, methods: [exact, schlick]}\n  - {mesh: room, scale: 3, diffuse: [0.5, 0.5, 0.5]}\n  - {mesh: plane, position: [0, -1, 0], diffuse: [0.2, 0.2, 0.2]}\nmeasurements: [image_error]\n";
    let (scene, staged) = stage(text);
    let report = image_errors(&scene, &staged, Settings::of(&scene), &mut |_| {});
    assert_eq!(report.stats.cube_maps, 1);
    assert_eq!(report.stats.layers, 2);
    assert_eq!(report.stats.reference_frames, 2);
    assert_eq!(report.stats.twin_frames, 4);
    assert_eq!(report.rows.len(), 4, "(exact, schlick) × depths 1, 2");
    // 1 reference + 2 methods per depth configuration at the last search configuration.
    assert_eq!(report.pictures.len(), 6);
    // Without effects nothing is traced: no cube map, no frame.
    let (plain, plain_stage) =
        stage("camera: {frames: 1}\nobjects: [{mesh: sphere, material: test/metals/gold, method: exact}]\nmeasurements: [image_error]\n");
    let nothing = image_errors(&plain, &plain_stage, Settings::of(&plain), &mut |_| {});
    assert_eq!((nothing.stats, nothing.rows.len(), nothing.pictures.len()), (Default::default(), 0, 0));
}

#[test]
fn a_grazing_ray_on_a_coarse_mesh_takes_its_side_from_the_triangle() {
    use super::geometry::Geometry;
    use super::optics::{facing, scatter, Allowed, SpecularOptics, Turn};
    use crate::scene::mesh::Mesh;
    use glam::DVec3;
    // One triangle in z = 0 whose vertex normals lean 45° towards +x, as a coarse mesh's
    // averaged normals do near a silhouette. A ray travelling along (1, 0, −0.2) meets the
    // triangle's front (its plane normal +z faces the ray) while the interpolated normal
    // (1, 0, 1)/√2 points along the ray: read from the interpolated normal it would arrive
    // from inside (and, in glass, turn back by total internal reflection).
    let lean = [std::f32::consts::FRAC_1_SQRT_2, 0.0, std::f32::consts::FRAC_1_SQRT_2];
    let mesh =
        Mesh { positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]], normals: vec![lean; 3], indices: vec![0, 1, 2] };
    let geometry = Geometry::new(&[mesh]).unwrap();
    let direction = DVec3::new(1.0, 0.0, -0.2).normalize();
    let hit = geometry.nearest(DVec3::new(-1.0, 0.0, 0.2), direction, None, |_| true).expect("the triangle");
    assert!(direction.dot(hit.normal) > 0.0, "the interpolated normal faces away from the ray");
    assert!((hit.geometric - DVec3::Z).length() < 1e-15, "{:?}", hit.geometric);
    let (inside, normal, cos_i) = facing(direction, hit.normal, hit.geometric);
    let cos_expected = 0.2 / 1.04f64.sqrt();
    assert!(!inside && (normal - DVec3::Z).length() < 1e-15 && (cos_i - cos_expected).abs() < 1e-15);
    // Glass from outside: reflection up with F(1.5, cosθᵢ), refraction down into the glass.
    let glass = SpecularOptics::new(&[Index::new(1.5, 0.0); 3], Kind::Dielectric, Method::Exact, LutSpec::default());
    let branches = scatter(&glass, direction, hit.normal, hit.geometric, Allowed { reflection: true, refraction: true });
    assert_eq!(branches.iter().map(|b| b.turn).collect::<Vec<_>>(), [Turn::Reflection, Turn::Refraction]);
    assert!(branches[0].direction.z > 0.0 && branches[1].direction.z < 0.0);
    assert!((branches[0].weight[1] - exact(1.5, 0.0, cos_expected)).abs() < 1e-15);
    // sinθₜ = sinθᵢ/1.5 along +x.
    let sin_i = (1.0 - cos_expected * cos_expected).sqrt();
    assert!((branches[1].direction.x - sin_i / 1.5).abs() < 1e-15);
}

/// A scene of one specular object in a room whose walls all show radiance `wall` (ambient
/// light only), `effects` naming depths and anything else.
fn furnace(object: &str, wall: f64, effects: &str, distance: f64, fov: f64) -> String {
    format!(
        "measurements: [image_error]\ncamera: {{axis: [0, 1, 0], distance: {distance}, fov_y_degrees: {fov}}}\neffects: {effects}\nlight: {{colour: [0, 0, 0], ambient: [1, 1, 1]}}\nobjects:\n  - {object}\n  - {{mesh: room, scale: 3, diffuse: [{wall}, {wall}, {wall}]}}\n"
    )
}

#[test]
fn light_through_an_absorbing_slab_falls_as_beer_lambert_says() {
    // A cube of glass (n = 1.5 in every channel, k per channel) seen face on through its
    // centre, refraction only: in (1 − F0), a straight path of the cube's thickness d, out
    // (1 − F0), then the wall: (1 − F0)² e^(−αd) with α = 4πk/λ at each channel's
    // wavelength, d in metres (the scene's unit is the centimetre).
    let k = [1e-5, 2e-5, 4e-5];
    let mut table = materials();
    table.push(material("test/glass/tinted", [1.5; 3], k, Kind::Dielectric));
    let text = furnace(
        "{mesh: cube, scale: 0.5, material: test/glass/tinted, method: exact}",
        0.8,
        "{refraction: {max_depth: 2}, metres_per_unit: 0.01}",
        2.0,
        30.0,
    );
    let scene = Scene::parse(&text, Path::new("t.yaml")).unwrap();
    let stage = stage_from_table(&scene, &table).unwrap();
    let camera = Camera::new(&scene.camera, 0, 9, 9);
    let frame = reference(&stage, &camera, Depths { reflection: 0, refraction: 2 });
    assert_eq!(frame.seen[40], Some(0));
    // The placed cube's extent along the ray (+z: the eye sits at (0, 0, −2)).
    let z: Vec<f64> = stage.meshes[0].positions.iter().map(|p| f64::from(p[2])).collect();
    let thickness = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - z.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!((thickness - 1.0 / 3f64.sqrt()).abs() < 1e-7, "{thickness}");
    let f0 = 0.04;
    for c in 0..3 {
        let alpha = 4.0 * std::f64::consts::PI * k[c] / ([685e-9, 535e-9, 475e-9][c]) * 0.01;
        let expected = (1.0 - f0) * (1.0 - f0) * (-alpha * thickness).exp() * 0.8;
        assert!((frame.radiance[40][c] / expected - 1.0).abs() < 1e-9, "channel {c}: {} vs {expected}", frame.radiance[40][c]);
    }
    // Green: α = 4π·2e-5/535 nm = 469.7 m⁻¹, over 5.774 mm: e^(−2.712) = 0.0664.
    assert!((frame.radiance[40][1] / (0.96 * 0.96 * 0.8) - 0.0664).abs() < 1e-4);
}

/// Whether the pixel's ray from the camera meets a perfect sphere of radius `radius` at the
/// origin, and the cosine of its angle of incidence there.
fn analytic_cos_incidence(camera: &Camera, x: u32, y: u32, radius: f64) -> Option<f64> {
    let d = camera.ray(x, y);
    let along = -camera.eye.dot(d);
    let miss2 = camera.eye.length_squared() - along * along;
    (miss2 < radius * radius).then(|| (1.0 - miss2 / (radius * radius)).sqrt())
}

#[test]
fn a_lossless_dispersive_sphere_in_a_white_furnace_loses_only_what_the_depth_truncates() {
    // A BK7-like sphere (n per channel at 685/535/475 nm, k = 0) in a room of radiance 1
    // everywhere. On a perfect sphere every inner hit meets the surface at the green
    // refraction angle, where (transmitted-angle rule) each channel's F is its outside F at
    // the entry angle θᵢ: a path enters (1 − F), reflects m times inside (F each) and leaves
    // (1 − F), or reflects off the outside (F). Depths 8/8 allow m ≤ 6, so the pixel returns
    // F + (1 − F)(1 − F⁷) = 1 − (1 − F)F⁷: the truncated share (1 − F)F⁷ is all that is lost.
    let n = [1.5131, 1.5195, 1.5228];
    let mut table = materials();
    table.push(material("test/glass/bk7", n, [0.0; 3], Kind::Dielectric));
    let text = furnace(
        "{mesh: sphere, scale: 0.5, material: test/glass/bk7, method: exact}",
        1.0,
        "{reflection: {max_depth: 8}, refraction: {max_depth: 8}}",
        1.2,
        52.0,
    );
    let scene = Scene::parse(&text, Path::new("t.yaml")).unwrap();
    let stage = stage_from_table(&scene, &table).unwrap();
    let camera = Camera::new(&scene.camera, 0, 48, 48);
    let depths = Depths { reflection: 8, refraction: 8 };
    let frame = reference(&stage, &camera, depths);
    let (mut rendered, mut analytic, mut pixels) = ([0.0; 3], [0.0; 3], 0);
    for y in 0..48 {
        for x in 0..48 {
            let i = (y * 48 + x) as usize;
            let value = frame.radiance[i];
            // Energy is conserved bounce by bounce in every channel: never more than 1.
            assert!(value.iter().all(|v| *v <= 1.0 + 1e-12), "({x}, {y}): {value:?}");
            if frame.seen[i] != Some(0) {
                continue;
            }
            let Some(cos) = analytic_cos_incidence(&camera, x, y, 0.5) else { continue };
            pixels += 1;
            for c in 0..3 {
                let f = exact(n[c], 0.0, cos);
                rendered[c] += value[c];
                analytic[c] += 1.0 - (1.0 - f) * f.powi(7);
            }
        }
    }
    let rendered = rendered.map(|v| v / pixels as f64);
    let analytic = analytic.map(|v| v / pixels as f64);
    eprintln!("white furnace, BK7-like sphere, depths 8/8, {pixels} pixels: rendered {rendered:?}, perfect sphere {analytic:?}");
    for c in 0..3 {
        assert!((rendered[c] - analytic[c]).abs() < 2e-3, "channel {c}: {} vs {}", rendered[c], analytic[c]);
    }
    // The GPU algorithm's rule (each channel's inside curve at the angle of incidence, on
    // the green direction) traps blue at the rim: past asin(n_g/n_b) from outside, blue
    // meets F = 1 at every inner hit while green leaves. The reference's rule does not.
    let inside_curve = stage.optics(Method::Exact, LutSpec::default());
    let tracer = super::trace::ReferenceTracer { stage: &stage };
    let gpu_rule = super::trace::render(&stage, &camera, super::trace::PathRules { optics: &inside_curve, depths }, |_| &tracer);
    let gap = |f: &TracedFrame| f.radiance.iter().map(|v| v[1] - v[2]).fold(0.0f64, f64::max);
    eprintln!("largest green − blue: transmitted-angle rule {:.4}, inside-curve rule {:.4}", gap(&frame), gap(&gpu_rule));
    assert!(gap(&gpu_rule) > 0.1 && gap(&frame) < 0.02, "{} {}", gap(&gpu_rule), gap(&frame));
}

/// The camera's view space is the inverse of its rays: a point along the ray through the
/// centre of pixel (x, y) lands, in view space, at pixel coordinates (x + ½, y + ½) by the
/// focal length (what GTAO's G-buffer relies on), for a wide, non-square frame.
#[test]
fn view_space_points_project_back_to_their_pixels() {
    let path = crate::scene::CameraPath { axis: [-0.3, 1.0, 0.1], distance: 2.4, fov_y_degrees: 55.0, ..Default::default() };
    let camera = Camera::new(&path, 3, 37, 23);
    let f = camera.focal_pixels();
    for (x, y) in [(0, 0), (36, 22), (18, 11), (5, 20)] {
        for t in [0.5, 2.0, 7.0] {
            let p = camera.view_point(camera.eye + camera.ray(x, y) * t);
            assert!(p.z < 0.0);
            let px = 37.0 / 2.0 + f * p.x / -p.z;
            let py = 23.0 / 2.0 - f * p.y / -p.z;
            assert!((px - (x as f64 + 0.5)).abs() < 1e-9 && (py - (y as f64 + 0.5)).abs() < 1e-9, "({x}, {y}) → ({px}, {py})");
            assert!((p.length() - t).abs() < 1e-12, "distance kept");
        }
    }
}

/// `stage` with every length times `k`: mesh corners (rounded to f32 as a placed mesh is),
/// checker sizes and gradient axes (÷ k: a gradient ramps over p·axis), point lights'
/// positions, and the metres per unit (÷ k, so Beer–Lambert sees the same path in metres);
/// point lights' intensities times k² (inverse square). The same scene at another size.
fn scaled(stage: &Stage, k: f64) -> Stage {
    use super::geometry::Geometry;
    use super::trace::ObjectOptics;
    use crate::scene::{Diffuse, LightSource, Pattern};
    let meshes: Vec<_> = stage
        .meshes
        .iter()
        .map(|m| {
            let mut m = m.clone();
            m.positions.iter_mut().for_each(|p| *p = p.map(|x| (x as f64 * k) as f32));
            m
        })
        .collect();
    let objects = stage
        .objects
        .iter()
        .map(|o| match o {
            ObjectOptics::Diffuse(d) => ObjectOptics::Diffuse(Diffuse {
                albedo: d.albedo,
                pattern: match d.pattern {
                    Pattern::Plain => Pattern::Plain,
                    Pattern::Checker { size, albedo } => Pattern::Checker { size: size * k, albedo },
                    Pattern::Gradient { axis, albedo } => Pattern::Gradient { axis: axis.map(|a| a / k), albedo },
                },
            }),
            specular => specular.clone(),
        })
        .collect();
    let lights = stage
        .lights
        .iter()
        .map(|l| match l {
            LightSource::Point { position, intensity } => {
                LightSource::Point { position: position.map(|x| x * k), intensity: intensity.map(|i| i * k * k) }
            }
            other => other.clone(),
        })
        .collect();
    Stage {
        geometry: Geometry::new(&meshes).unwrap(),
        meshes,
        objects,
        lights,
        channels_nm: stage.channels_nm,
        metres_per_unit: stage.metres_per_unit / k,
        spectra: stage.spectra.clone(),
    }
}

/// A scene at the ends of the range of scene sizes — 10⁻⁴ and 10⁴ times a scene a few units
/// across — renders the image of the scene at scale 1 through the f64 reference tracer,
/// every pixel. The scaled scene is not exactly similar: its corners are rounded to f32 after
/// scaling, which moves each by up to 2⁻²⁴ of its coordinates (≤ 6·10⁻⁸R, R = 3 the room's
/// half-width), about 4·10⁻⁶ of a pixel here (a pixel spans 2·1.8·tan 30°/48 ≈ 0.043 units at
/// the scene's centre). So each pixel is held to the scale-1 image at its centre or at a ray
/// [`SCALE_STRAY`] pixels from it (a pixel whose centre lies that close to an edge may
/// show either side), to [`SCALE_BOUND`]: the barycentrics of a hit move by the corner
/// shift over the edge length (6·10⁻⁸·3/0.05 ≈ 4·10⁻⁶), so do the interpolated normals (by
/// that times their spread across a triangle, ≲ 0.1 rad) and with them F and the bounce
/// directions; over three bounces that stays under 10⁻⁴ of the radiance.
#[test]
fn a_scene_scaled_to_either_end_of_the_range_renders_the_image_at_scale_one() {
    use crate::scene::CameraPath;
    let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0.2], distance: 1.8}\neffects:\n  reflection: {max_depth: 3}\n  refraction: {max_depth: 3}\n\
        lights:\n  - {kind: directional, direction: [-0.3, -1, -0.5], colour: [0.5, 0.5, 0.5]}\n  - {kind: point, position: [0.5, 0.8, -0.5], intensity: [0.6, 0.5, 0.4]}\n  - {kind: ambient, colour: [0.2, 0.2, 0.2]}\n\
        objects:\n  - {mesh: sphere, scale: 0.5, position: [0.2, 0, 0], material: test/glass/crown, method: exact}\n  - {mesh: cube, scale: 0.25, position: [-0.6, -0.2, 0.3], material: test/metals/gold, method: exact}\n\
        \x20 - {mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75], pattern: {kind: checker, size: 0.5, albedo: [0.1, 0.3, 0.6]}}\n";
    let (scene, stage) = stage(text);
    let depths = Depths { reflection: 3, refraction: 3 };
    let camera = |k: f64| Camera::new(&CameraPath { distance: scene.camera.distance * k, ..scene.camera.clone() }, 0, 48, 48);
    let strays = [(0.0, 0.0), (SCALE_STRAY, 0.0), (-SCALE_STRAY, 0.0), (0.0, SCALE_STRAY), (0.0, -SCALE_STRAY)];
    let base: Vec<TracedFrame> = strays.iter().map(|&(dx, dy)| reference(&stage, &camera(1.0).shifted(dx, dy), depths)).collect();
    assert!(base[0].seen.iter().filter(|s| s.is_some()).count() > 300, "the glass and the gold fill part of the frame");
    let distance = |a: [f64; 3], b: [f64; 3]| (0..3).map(|c| (a[c] - b[c]).abs() / (1.0 + b[c].abs())).fold(0.0, f64::max);
    for k in [1e-4, 1e4] {
        let big = scaled(&stage, k);
        assert!((big.geometry.size() / stage.geometry.size() / k - 1.0).abs() < 1e-6);
        let frame = reference(&big, &camera(k), depths);
        let (mut centre_worst, mut worst, mut at) = (0.0f64, 0.0f64, 0);
        for p in 0..frame.radiance.len() {
            let near =
                |b: &TracedFrame| if b.seen[p] == frame.seen[p] { distance(frame.radiance[p], b.radiance[p]) } else { f64::INFINITY };
            centre_worst = centre_worst.max(near(&base[0]));
            let best = base.iter().map(near).fold(f64::INFINITY, f64::min);
            if best > worst {
                (worst, at) = (best, p);
            }
        }
        eprintln!(
            "scale {k:e}: largest difference at a pixel centre {centre_worst:.3e}; with rays {SCALE_STRAY} px away {worst:.3e} at {:?}",
            (at % 48, at / 48)
        );
        assert!(worst <= SCALE_BOUND, "scale {k}: {worst} at pixel {at}");
    }
}

const SCALE_STRAY: f64 = 1e-4;
const SCALE_BOUND: f64 = 1e-4;

/// Each table's writer puts the columns `nklut_tables::effects_tables` lists for it, in that
/// order (the report reads them through the same constants).
#[test]
fn every_table_is_written_with_the_columns_its_reader_names() {
    use nklut_tables::effects_tables::{ao_errors, ao_histogram, effects_cpu_timing, effects_errors, effects_hero, spectral_errors};
    let names = |table: nklut_tables::output::Table| table.columns.into_iter().map(|c| c.name).collect::<Vec<_>>();
    assert_eq!(names(super::experiment::error_table(&[])), effects_errors::NAMES);
    assert_eq!(names(super::experiment::timing_table(&[])), effects_cpu_timing::NAMES);
    assert_eq!(names(super::hero::hero_table(&[])), effects_hero::NAMES);
    assert_eq!(names(super::spectral_errors::spectral_error_table(&[])), spectral_errors::NAMES);
    assert_eq!(names(crate::ao::errors::ao_errors_table(&[])), ao_errors::NAMES);
    assert_eq!(names(crate::ao::histogram::ao_histogram_table(&[])), ao_histogram::NAMES);
}
