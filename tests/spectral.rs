//! The spectral reference of the effects on the real database: one bounce off a flat
//! mirror of each `3d` metal is `colors`' spectral reference colour; lossless spheres of the
//! pages' n(λ) in a white furnace lose only the depth-truncated share; the spectral frame of
//! the shipped gold-in-gold and prism scenes converges as the wavelength count doubles;
//! total internal reflection happens in the prism scene.

mod common;

use std::path::Path;

use common::database;
use nklut::color::PreparedSpectrum;
use nklut::effects::image_error::delta_e_map;
use nklut::effects::spectral::{spectral_reference, WavelengthGrid};
use nklut::effects::trace::{stage_from_table, Camera};
use nklut::ingest::Config;
use nklut::scene::{read_materials, Depths, Scene};

const METALS: [&str; 10] = ["aluminium", "brass", "copper", "gold", "iron", "mercury", "platinum", "silver", "titanium", "stainless_steel"];

#[test]
fn one_bounce_off_a_flat_mirror_of_each_3d_metal_is_the_colors_reference() {
    // The camera straight above a metal plane in a room whose walls all show radiance 1:
    // a pixel's one reflection sees the ceiling, so on the full 1 nm grid the spectral frame
    // is Σ_λ R(θ, λ) w(λ), `colors`' reference colour at that pixel's angle.
    let db = database();
    for metal in METALS {
        let page = format!("3d/metals/{metal}");
        let text = format!("measurements: [image_error]\ncamera: {{axis: [0, 0, 1], distance: 1.5, fov_y_degrees: 50}}\neffects: {{reflection: {{max_depth: 1}}}}\nlight: {{colour: [0, 0, 0], ambient: [1, 1, 1]}}\nobjects:\n  - {{mesh: plane, scale: 2, position: [0, -0.5, 0], material: {page}, method: exact}}\n  - {{mesh: room, scale: 3, diffuse: [1, 1, 1]}}\n");
        let scene = Scene::parse(&text, Path::new("mirror.yaml")).unwrap();
        let (materials, _) = read_materials(&scene, &db, &Config::default()).unwrap();
        let stage = stage_from_table(&scene, &materials).unwrap();
        let camera = Camera::new(&scene.camera, 0, 9, 9);
        let grid = WavelengthGrid::new(WavelengthGrid::full_count()).unwrap();
        let frame = spectral_reference(&stage, &camera, Depths { reflection: 1, refraction: 0 }, &grid).unwrap().frame;
        let prepared = PreparedSpectrum::new(materials[0].spectrum.as_ref().unwrap());
        let mut worst: f64 = 0.0;
        for y in 0..9 {
            for x in 0..9 {
                let i = (y * 9 + x) as usize;
                assert_eq!(frame.seen[i], Some(0), "{metal}: the plane fills the frame");
                let cos = -camera.ray(x, y).y;
                let expected = prepared.rgb(cos);
                worst = worst.max((0..3).map(|c| (frame.radiance[i][c] - expected[c]).abs()).fold(0.0, f64::max));
            }
        }
        assert!(worst < 1e-9, "{metal}: {worst:e}");
    }
}

/// The spectral frame of a shipped scene at its deepest depths with `count` wavelengths.
fn spectral_frame(file: &str, count: usize, size: u32) -> nklut::effects::trace::TracedFrame {
    let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(file)).unwrap();
    let (materials, _) = read_materials(&scene, &database(), &Config::default()).unwrap();
    let stage = stage_from_table(&scene, &materials).unwrap();
    let camera = Camera::new(&scene.camera, 0, size, size);
    let depths = *scene.effects.as_ref().unwrap().depths().last().unwrap();
    spectral_reference(&stage, &camera, depths, &WavelengthGrid::new(count).unwrap()).unwrap().frame
}

#[test]
fn the_spectral_frame_converges_as_the_wavelength_count_doubles() {
    // Mean and largest ΔE2000 over the specular pixels between the frame at N and at 2N
    // wavelengths; the shipped scenes' count (96) must be within ΔE 0.05 of 192 in the mean.
    // (Past 48 the change halves per doubling, first order: the surroundings' Smits spectra
    // are steps on 34 nm bins, which the bins' midpoints resolve only to O(h).)
    for file in ["gold-in-gold.yaml", "prism.yaml"] {
        let mut curve = Vec::new();
        let counts = [6, 12, 24, 48, 96, 192];
        let frames: Vec<_> = counts.iter().map(|&n| spectral_frame(file, n, 32)).collect();
        for pair in frames.windows(2) {
            let map = delta_e_map(&pair[0], &pair[1]);
            let specular: Vec<f64> = map.iter().zip(&pair[1].seen).filter(|(_, s)| s.is_some()).map(|(e, _)| *e).collect();
            let mean = specular.iter().sum::<f64>() / specular.len() as f64;
            let max = specular.iter().cloned().fold(0.0, f64::max);
            curve.push((mean, max));
        }
        eprintln!("{file}: ΔE2000 (mean, max) between N and 2N wavelengths for N = {:?}: {curve:?}", &counts[..5]);
        assert!(curve[4].0 < 0.05, "{file}: 96 → 192 wavelengths moves the mean by {}", curve[4].0);
    }
}

#[test]
fn lossless_water_bk7_and_diamond_spheres_in_a_white_furnace_lose_only_the_truncated_share() {
    // The pages' n(λ) with k set to 0, one sphere each in a closed room of radiance 1.
    // Derived bound: every interface of a lossless dielectric splits a path's weight into F
    // and 1 − F (1 at a total internal reflection), and every path that leaves the sphere
    // meets the room and returns its weight × 1; so at every wavelength of every pixel the
    // returned radiance plus the weight still in flight when the depths run out is exactly 1,
    // whatever the tessellation: 1 − L(λ) = T(λ), the truncated share, to rounding.
    // On a perfect sphere T(λ) = (1 − F)F^(D−1) at depths D/D (F the outside F at the entry
    // angle; every inner hit is at that wavelength's refraction angle, where its F is the
    // same), at most max_F (1 − F)F^(D−1) = (1/D)(1 − 1/D)^(D−1) per pixel (0.049 at D = 8),
    // and it falls with depth (here 4 to 8); the tessellated sphere (64×32) traps a little more.
    use nklut::effects::spectral::spectral_pixel;
    use nklut::fresnel::exact;
    use nklut::spectrum::Index;
    let db = database();
    for page in ["3d/liquids/water", "3d/glass/BK7", "3d/crystals/diamond"] {
        let text = format!("measurements: [image_error]\ncamera: {{axis: [0, 1, 0], distance: 1.2, fov_y_degrees: 52}}\neffects: {{reflection: {{max_depth: 8}}, refraction: {{max_depth: 8}}}}\nlight: {{colour: [0, 0, 0], ambient: [1, 1, 1]}}\nobjects:\n  - {{mesh: sphere, scale: 0.5, material: {page}, method: exact}}\n  - {{mesh: room, scale: 3, diffuse: [1, 1, 1]}}\n");
        let scene = Scene::parse(&text, Path::new("furnace.yaml")).unwrap();
        let (mut materials, _) = read_materials(&scene, &db, &Config::default()).unwrap();
        let lossless: Vec<Index> = materials[0].spectrum.as_ref().unwrap().iter().map(|i| Index::new(i.n, 0.0)).collect();
        materials[0].spectrum = Some(lossless.clone());
        let stage = stage_from_table(&scene, &materials).unwrap();
        let camera = Camera::new(&scene.camera, 0, 16, 16);
        let grid = WavelengthGrid::new(12).unwrap();
        let mut lost_by_depth = Vec::new();
        for depth in [4, 8] {
            let depths = Depths { reflection: depth, refraction: depth };
            let per_pixel_bound = (1.0 / depth as f64) * (1.0 - 1.0 / depth as f64).powi(depth as i32 - 1);
            let (mut lost, mut analytic, mut interior) = (0.0, 0.0, 0);
            for y in 0..16 {
                for x in 0..16 {
                    let pixel = spectral_pixel(&stage, &camera, (x, y), depths, &grid).unwrap();
                    let d = camera.ray(x, y);
                    let along = -camera.eye.dot(d);
                    let miss2 = camera.eye.length_squared() - along * along;
                    for (l, t) in pixel.radiance.iter().zip(&pixel.truncated) {
                        assert!((l + t - 1.0).abs() < 1e-12, "{page} ({x}, {y}) depth {depth}: L {l} + T {t} ≠ 1");
                    }
                    if miss2 >= 0.25 * 0.98 {
                        continue; // the rim, where the tessellation decides what is hit
                    }
                    let cos = (1.0 - miss2 / 0.25).sqrt();
                    for (lane, t) in pixel.truncated.iter().enumerate() {
                        let f = exact(WavelengthGrid::index_at(&lossless, grid.centres[lane]).n, 0.0, cos);
                        let perfect = (1.0 - f) * f.powi(depth as i32 - 1);
                        assert!(perfect <= per_pixel_bound);
                        lost += t / grid.len() as f64;
                        analytic += perfect / grid.len() as f64;
                    }
                    interior += 1;
                }
            }
            assert!(interior > 100);
            let (lost, analytic) = (lost / interior as f64, analytic / interior as f64);
            eprintln!(
                "white furnace, {page} (k = 0), depths {depth}/{depth}: mean truncated share {lost:.3e}, perfect sphere {analytic:.3e}"
            );
            // The tessellation's excess over the perfect sphere, measured: 1.8·10⁻⁴ at most
            // at depth 4, 1.6·10⁻⁵ at 8.
            assert!((lost - analytic).abs() < 3e-4, "{page}: {lost} vs {analytic}");
            lost_by_depth.push(lost);
        }
        assert!(lost_by_depth[1] < lost_by_depth[0], "{page}: deeper paths return more: {lost_by_depth:?}");
    }
}

#[test]
fn total_internal_reflection_happens_in_the_prism_scene() {
    // The shipped prism scene at its deepest depths: wavelengths are turned back inside the
    // prisms (counted per wavelength), which no sphere of glass-sphere.yaml ever does.
    let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/prism.yaml")).unwrap();
    let (materials, _) = read_materials(&scene, &database(), &Config::default()).unwrap();
    let stage = stage_from_table(&scene, &materials).unwrap();
    let camera = Camera::new(&scene.camera, 0, 24, 24);
    let depths = *scene.effects.as_ref().unwrap().depths().last().unwrap();
    let frame = spectral_reference(&stage, &camera, depths, &WavelengthGrid::new(24).unwrap()).unwrap();
    eprintln!("prism scene, 24², 24 wavelengths: {} total internal reflections", frame.total_internal_reflections);
    assert!(frame.total_internal_reflections > 0);
    let glass = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass-sphere.yaml")).unwrap();
    let (materials, _) = read_materials(&glass, &database(), &Config::default()).unwrap();
    let stage = stage_from_table(&glass, &materials).unwrap();
    let camera = Camera::new(&glass.camera, 0, 24, 24);
    let spheres = spectral_reference(&stage, &camera, Depths { reflection: 1, refraction: 3 }, &WavelengthGrid::new(24).unwrap()).unwrap();
    assert_eq!(spheres.total_internal_reflections, 0, "a chord of a sphere meets its surface at the angle it entered at");
}
