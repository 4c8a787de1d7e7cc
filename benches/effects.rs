//! Speed of the effects tracers on the teapot scene (`scenes/teapot-in-a-box.yaml`, three
//! reflective teapots in a checkered box; the triangle count is printed): rays
//! per second of the f64 reference tracer at reflection depths 1–3, against an anchor
//! measured in the same run (primary rays only: depth 0); then the distance-map build and
//! the CPU twin at 15/1 and 80/10 steps.
//!
//! `cargo bench --bench effects` (RAYON_NUM_THREADS sets the cores; the materials come
//! from the database, `make db`). Results and the prediction: BENCHMARKS.md.

use std::path::Path;
use std::time::Instant;

use nklut::db::Database;
use nklut::effects::experiment::{distance_maps, twin_frame};
use nklut::effects::trace::{reference, stage_from_table, Camera, TracedFrame};
use nklut::fresnel::{LutSpec, Method};
use nklut::scene::read_materials;
use nklut::scene::{Depths, Scene, SearchSteps};

/// The best of `runs` timings of `render` (seconds) and its frame.
fn best_of(runs: usize, mut render: impl FnMut() -> TracedFrame) -> (f64, TracedFrame) {
    let mut best = f64::INFINITY;
    let mut frame = None;
    for _ in 0..runs {
        let start = Instant::now();
        let rendered = render();
        best = best.min(start.elapsed().as_secs_f64());
        frame = Some(rendered);
    }
    (best, frame.expect("at least one run"))
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let db = Database::open(root.join("refractiveindex/database")).expect("run `make db` first");
    let scene = Scene::load(&root.join("scenes/teapot-in-a-box.yaml")).expect("the teapot scene (and ../shared/meshes/teapot.obj)");
    let (materials, _) = read_materials(&scene, &db, &Default::default()).unwrap();
    let start = Instant::now();
    let stage = stage_from_table(&scene, &materials).unwrap();
    let build = start.elapsed().as_secs_f64();
    let size: u32 = std::env::var("NKLUT_BENCH_SIZE").ok().and_then(|v| v.parse().ok()).unwrap_or(256);
    let camera = Camera::new(&scene.camera, 0, size, size);
    let lut = LutSpec::default();
    println!(
        "effects bench: {} triangles (BVH built in {build:.3} s), {size}x{size} pixels, {} threads",
        stage.geometry.triangles(),
        rayon::current_num_threads()
    );
    let (anchor_s, anchor) = best_of(3, || reference(&stage, &camera, Depths { reflection: 0, refraction: 0 }));
    let anchor_rate = anchor.rays as f64 / anchor_s;
    println!("  reference, primary rays only (anchor): {} rays in {anchor_s:.3} s = {:.2} M rays/s", anchor.rays, anchor_rate / 1e6);
    for depth in 1..=3 {
        let (seconds, frame) = best_of(3, || reference(&stage, &camera, Depths { reflection: depth, refraction: 0 }));
        let rate = frame.rays as f64 / seconds;
        println!(
            "  reference, reflection depth {depth}: {} rays ({:.2} per pixel) in {seconds:.3} s = {:.2} M rays/s ({:.2}× the anchor's rate)",
            frame.rays,
            frame.rays as f64 / (size * size) as f64,
            rate / 1e6,
            rate / anchor_rate
        );
    }
    let maps_settings = &scene.effects.as_ref().expect("the teapot scene has effects").distance_maps;
    let start = Instant::now();
    let maps = distance_maps(&stage, maps_settings.size, maps_settings.layers);
    let maps_s = start.elapsed().as_secs_f64();
    println!(
        "  distance maps: {} maps of 6x{}² x {} layers in {maps_s:.3} s",
        maps.iter().flatten().count(),
        maps_settings.size,
        maps_settings.layers
    );
    for steps in [SearchSteps { linear: 15, secant: 1 }, SearchSteps { linear: 80, secant: 10 }] {
        let depths = Depths { reflection: 3, refraction: 0 };
        let (seconds, frame) = best_of(3, || twin_frame(&stage, &camera, &maps, Method::Exact, depths, steps, lut));
        println!(
            "  CPU twin {}/{} steps, depth 3: {} rays in {seconds:.3} s = {:.2} M rays/s",
            steps.linear,
            steps.secant,
            frame.rays,
            frame.rays as f64 / seconds / 1e6
        );
    }
}
