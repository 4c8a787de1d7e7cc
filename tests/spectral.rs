//! The spectral reference of the effects on the real database: one bounce off a flat
//! mirror of each `3d` metal is `colors`' spectral reference colour; the spectral frame of
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
