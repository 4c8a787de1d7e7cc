//! Surfel ambient occlusion: cost and accuracy.
//!
//! 1. Speed of the ray-traced reference (rays/s, cosine-weighted hemisphere rays on the
//!    Stanford bunny), ray by ray and in packets (asserted to give the same values), against
//!    an anchor measured in the same run: brute-force shadow evaluations per second (one pass
//!    on a 4 k-surfel torus).
//! 2. Accuracy: accessibility against the reference on the bunny and the sculpture
//!    (nefertiti), 1–3 passes, receiver gain g = 1 and 4, hierarchy off and on — the rows of
//!    the `ao_errors` table; the reference's time and noise are printed.
//! 3. Cost over scene size: one pass by brute force and by the hierarchy on tori of growing
//!    surfel count, with the fitted exponent p of time ∝ nᵖ for each.
//!
//! `cargo bench --bench ao` (RAYON_NUM_THREADS sets the cores; NKLUT_AO_SPEED_RAYS the rays
//! per vertex of the speed run, ray by ray and in packets, 1024 by default; NKLUT_AO_RAYS the
//! reference's rays per vertex in the accuracy runs, 1024 by default; NKLUT_AO_MAX_BRUTE the
//! largest n run by brute force, 40 000: the bunny but not the sculpture, tori to 33 k).
//! Results and the predictions: BENCHMARKS.md.

use std::path::Path;
use std::time::Instant;

use nklut::effects::ao::accessibility::{accessibility, BruteForce};
use nklut::effects::ao::errors::{error_rows, Comparison};
use nklut::effects::ao::hierarchy::{Closeness, SurfelTree};
use nklut::effects::ao::reference::{reference_accessibility, RaySettings};
use nklut::effects::ao::shadow::ShadowForm;
use nklut::effects::ao::shapes;
use nklut::effects::ao::surfel::{mesh_defects, surfels, Surfel};
use nklut::effects::geometry::Geometry;
use nklut::scene::mesh::{load_obj, Mesh};

fn timed<T>(work: impl FnOnce() -> T) -> (f64, T) {
    let start = Instant::now();
    let out = work();
    (start.elapsed().as_secs_f64(), out)
}

fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// A torus (ring radius 1, tube 0.6) with `segments` × `segments / 2` quads.
fn torus(segments: u32) -> Mesh {
    shapes::torus(1.0, 0.6, segments, segments / 2)
}

fn accuracy(name: &str, mesh: &Mesh, rays: u32, max_brute: usize) {
    let s = surfels(mesh);
    let geometry = Geometry::new(std::slice::from_ref(mesh)).unwrap();
    let (seconds, reference) = timed(|| reference_accessibility(&geometry, &s, RaySettings { rays, ..RaySettings::default() }));
    println!(
        "  {name}: {} surfels, reference {} rays in {seconds:.2} s ({:.2} M rays/s), σ mean {:.4} max {:.4}, mean accessibility {:.3}",
        s.len(),
        reference.rays,
        reference.rays as f64 / seconds / 1e6,
        reference.mean_standard_error(),
        reference.max_standard_error(),
        reference.values.iter().sum::<f64>() / s.len() as f64
    );
    let comparison = Comparison {
        forms: vec![ShadowForm::FORM_FACTOR, ShadowForm::RECEIVER_GAIN_FOUR],
        passes: 3,
        brute_force: s.len() <= max_brute,
        closeness: Closeness::default(),
    };
    let (seconds, rows) = timed(|| error_rows(name, &s, &mesh_defects(mesh), &reference, &comparison));
    println!("  mesh, g, passes, hierarchy, mean |a − ref|, max |a − ref|  ({seconds:.1} s for all)");
    for r in rows {
        println!(
            "  {name}, {}, {}, {}, {:.4}, {:.4}",
            r.receiver_gain,
            r.passes,
            if r.hierarchy { "on" } else { "off" },
            r.accessibility.per_vertex.mean,
            r.accessibility.per_vertex.max
        );
    }
}

/// Least-squares slope of ln t over ln n.
fn exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|(n, t)| (n.ln(), t.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = (logs.iter().map(|p| p.0).sum::<f64>() / k, logs.iter().map(|p| p.1).sum::<f64>() / k);
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let meshes = root.join("../shared/meshes");
    let rays = env_number("NKLUT_AO_RAYS", 1024) as u32;
    let max_brute = env_number("NKLUT_AO_MAX_BRUTE", 40_000) as usize;
    println!("ao bench: {} threads, {rays} reference rays per vertex", rayon::current_num_threads());

    // 1. Reference speed against the shadow-evaluation anchor.
    let anchor_surfels: Vec<Surfel> = surfels(&torus(90));
    let (anchor_s, anchor) = timed(|| accessibility(&BruteForce { surfels: &anchor_surfels, form: ShadowForm::default() }, 1));
    let anchor_rate = anchor.interactions as f64 / anchor_s;
    println!("  anchor: {} shadow evaluations in {anchor_s:.3} s = {:.1} M/s", anchor.interactions, anchor_rate / 1e6);
    let bunny = load_obj(&meshes.join("stanford-bunny.obj")).expect("../shared/meshes/stanford-bunny.obj");
    let bunny_surfels = surfels(&bunny);
    let geometry = Geometry::new(std::slice::from_ref(&bunny)).unwrap();
    let speed_rays = env_number("NKLUT_AO_SPEED_RAYS", 1024) as u32;
    let (one_s, one_by_one) = timed(|| {
        reference_accessibility(&geometry, &bunny_surfels, RaySettings { rays: speed_rays, packets: false, ..RaySettings::default() })
    });
    let (seconds, speed) =
        timed(|| reference_accessibility(&geometry, &bunny_surfels, RaySettings { rays: speed_rays, ..RaySettings::default() }));
    assert_eq!(speed.values, one_by_one.values, "packets count what their rays count one by one");
    let (one_rate, rate) = (one_by_one.rays as f64 / one_s, speed.rays as f64 / seconds);
    println!("  reference on the bunny, {speed_rays} rays per vertex, ray by ray: {} rays in {one_s:.3} s = {:.2} M rays/s ({:.3}× the anchor's rate)", one_by_one.rays, one_rate / 1e6, one_rate / anchor_rate);
    println!(
        "  reference on the bunny, in packets: {seconds:.3} s = {:.2} M rays/s ({:.3}× the anchor's rate, {:.2}× ray by ray; same values)",
        rate / 1e6,
        rate / anchor_rate,
        rate / one_rate
    );

    // 2. Accuracy (the ao_errors rows).
    println!("accuracy against the reference ({rays} rays per vertex):");
    accuracy("bunny", &bunny, rays, max_brute);
    if let Ok(sculpture) = load_obj(&meshes.join("nefertiti.obj")) {
        accuracy("sculpture", &sculpture, rays, max_brute);
    }

    // 3. Cost over scene size.
    println!("one pass over surfel count: n, brute force s, hierarchy s, ratio, tree work / n");
    let (mut brute_points, mut tree_points) = (Vec::new(), Vec::new());
    for segments in [46, 90, 180, 256, 362, 512] {
        let s = surfels(&torus(segments));
        let n = s.len();
        let brute_s = (n <= max_brute).then(|| timed(|| accessibility(&BruteForce { surfels: &s, form: ShadowForm::default() }, 1)).0);
        let tree = SurfelTree::new(&s, ShadowForm::default(), Closeness::default());
        let (tree_s, result) = timed(|| accessibility(&tree, 1));
        if let Some(b) = brute_s {
            brute_points.push((n as f64, b));
        }
        tree_points.push((n as f64, tree_s));
        let ratio = brute_s.map(|b| format!("{:.1}", b / tree_s)).unwrap_or_else(|| "-".into());
        let brute = brute_s.map(|b| format!("{b:.3}")).unwrap_or_else(|| "-".into());
        println!("  {n}, {brute}, {tree_s:.3}, {ratio}, {:.0}", result.interactions as f64 / n as f64);
    }
    println!("  fitted exponents: brute force {:.2}, hierarchy {:.2}", exponent(&brute_points), exponent(&tree_points));
}
