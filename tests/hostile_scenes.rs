//! Scene files and flags as an attacker or a careless user writes them, through the
//! `nklut effects` binary: sizes past what the machine holds, coordinates past what f32
//! and the BVH take, special files as meshes, nesting without end — each refused with an
//! error naming the field, at once and before the allocation; never a panic, a hang or an
//! abort. And the effects' outputs published as one set: a later run's frames never mix
//! with an earlier run's tables.

use std::fs;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

mod common;

/// `nklut effects` on `scene` text (written to `dir/scene.yaml`) with `flags`, given two
/// minutes (a hang guard, not a speed target) and a small memory budget where asked.
fn effects(dir: &Path, scene: &str, flags: &[&str], budget: Option<&str>) -> Output {
    run(dir, &["effects"], scene, flags, budget)
}

/// `nklut <command…> dir/scene.yaml <flags…>` as [`effects`] runs it.
fn run(dir: &Path, command_words: &[&str], scene: &str, flags: &[&str], budget: Option<&str>) -> Output {
    let file = dir.join("scene.yaml");
    fs::write(&file, scene).unwrap();
    let mut command = Command::new(common::binary());
    command.arg("--db").arg(common::database_dir()).arg("--out").arg(dir.join("out")).args(command_words).arg(&file).args(flags);
    if let Some(budget) = budget {
        command.env("NKLUT_MEMORY_BUDGET", budget);
    }
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("{command_words:?} still running after two minutes: {scene}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The run failed with status 1 (not a panic or a signal) and its message holds `field`.
fn refused(output: &Output, field: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{:?}: {stderr}", output.status);
    assert!(stderr.contains(field), "the message does not name {field}: {stderr}");
    stderr
}

fn succeeded(output: &Output) {
    assert!(output.status.success(), "{:?}: {}", output.status, String::from_utf8_lossy(&output.stderr));
}

/// An AO scene around one object line (no database needed).
fn ao_scene(object: &str) -> String {
    format!("resolution: [16, 16]\ncamera: {{ frames: 1 }}\nmeasurements: [image_error]\neffects: {{ ambient_occlusion: {{ passes: 1 }} }}\nobjects:\n  - {object}\n  - {{ mesh: plane, diffuse: [0.5, 0.5, 0.5], position: [0, -1, 0] }}\n")
}

/// Finite but huge coordinates are scene errors naming the field, not a panic in
/// the BVH builder; an OBJ whose vertices lie near f32's end is fitted to the unit sphere.
#[test]
fn huge_coordinates_are_named_errors_not_panics() {
    let dir = common::scratch("huge");
    for (object, field) in [
        ("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5], scale: 1e300 }", "objects[0].scale"),
        ("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5], scale: 1e39 }", "objects[0].scale"),
        ("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5], scale: 3.5e38 }", "objects[0].scale"),
        ("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5], position: [1e300, 0, 0] }", "objects[0].position"),
        ("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5], position: [3.5e38, 0, 0] }", "objects[0].position"),
    ] {
        refused(&effects(&dir, &ao_scene(object), &["--ao-rays", "4"], None), field);
    }
    let obj = dir.join("far.obj");
    fs::write(&obj, "v 3.4e38 3.4e38 3.4e38\nv -3.4e38 3.3e38 3.4e38\nv 3.4e38 -3.4e38 -3.3e38\nv -3.4e38 -3.4e38 3.4e38\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n").unwrap();
    let output = effects(&dir, &ao_scene(&format!("{{ mesh: {}, diffuse: [0.5, 0.5, 0.5] }}", obj.display())), &["--ao-rays", "4"], None);
    succeeded(&output);
    for (name, bad) in common::non_finite_tables(&dir.join("out")) {
        assert!(bad.is_empty(), "{name}: {bad:?}");
    }
}

/// Sizes that the fields' ranges allow but the machine does not hold, and counts
/// that would run for ever, are refused before any work, naming the field.
#[test]
fn oversized_requests_are_refused_before_the_allocation() {
    let dir = common::scratch("sizes");
    let plain = ao_scene("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5] }");
    refused(&effects(&dir, &plain, &["--ao-rays", "4294967295"], None), "--ao-rays");
    refused(&effects(&dir, &plain, &["--resolution", "100000x100000"], None), "resolution 100000x100000");
    refused(&effects(&dir, &plain, &["--frames", "4294967295"], None), "camera.frames");
    refused(&effects(&dir, &plain.replace("frames: 1", "frames: 1000000000"), &[], None), "camera.frames");
    let maps = "resolution: [16, 16]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: { reflection: { max_depth: 1 }, distance_maps: { size: 4096, layers: 8 } }\nobjects:\n  - { mesh: sphere, material: 3d/metals/gold, method: exact }\n";
    refused(&effects(&dir, maps, &[], Some("2G")), "effects.distance_maps");
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes/stanford-bunny.obj");
    let subdivided = ao_scene(&format!("{{ mesh: {}, diffuse: [0.5, 0.5, 0.5], subdivide: 6 }}", bunny.display()));
    refused(&effects(&dir, &subdivided, &["--ao-rays", "4"], Some("2G")), "objects[0].subdivide");
    // Nothing was written by any of them.
    assert!(!dir.join("out").join("ao_errors.csv").exists());
}

/// A light of 1e308 would overflow the radiance sums: refused, naming it.
#[test]
fn lights_past_the_radiance_bound_are_refused() {
    let dir = common::scratch("light");
    let scene = "resolution: [16, 16]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: { reflection: { max_depth: 1 } }\nlight: { colour: [1e308, 1, 1] }\nobjects:\n  - { mesh: sphere, material: 3d/metals/gold, method: exact }\n";
    refused(&effects(&dir, scene, &[], None), "light.colour");
    let lights = ao_scene("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5] }") + "lights:\n  - { kind: ambient, colour: [1e308, 1, 1] }\n";
    refused(&effects(&dir, &lights, &[], None), "lights[0].colour");
}

/// Items 4 and 7 for scenes: a FIFO as mesh or scene is refused without waiting for a
/// writer; nesting without end is refused before the YAML parser sees it.
#[cfg(unix)]
#[test]
fn special_files_and_deep_nesting_in_scenes_are_refused_at_once() {
    let dir = common::scratch("special");
    let fifo = dir.join("mesh.obj");
    let name = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: mkfifo reads a NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    refused(
        &effects(&dir, &ao_scene(&format!("{{ mesh: {}, diffuse: [0.5, 0.5, 0.5] }}", fifo.display())), &[], None),
        "not a regular file",
    );
    let deep = format!("objects: {}{}\n", "[".repeat(100_000), "]".repeat(100_000));
    refused(&effects(&dir, &deep, &[], None), "nests");
}

/// The tables and frames of one effects run are one set: a run naming fewer
/// methods leaves no frame of the others, and a killed run leaves the previous set whole.
#[test]
fn effects_tables_and_frames_are_one_set() {
    let dir = common::scratch("set");
    let scene = |methods: &str| {
        format!("resolution: [12, 12]\ncamera: {{ frames: 1 }}\nmeasurements: [image_error]\neffects: {{ reflection: {{ max_depth: 1 }}, distance_maps: {{ size: 8, layers: 2, linear_steps: 4, secant_steps: 1 }} }}\nobjects:\n  - {{ mesh: sphere, scale: 0.5, material: 3d/metals/gold, methods: [{methods}] }}\n  - {{ mesh: room, scale: 2, diffuse: [0.8, 0.8, 0.8] }}\n")
    };
    succeeded(&effects(&dir, &scene("exact, schlick"), &[], None));
    let frames = |dir: &Path| -> Vec<String> {
        let mut names: Vec<String> =
            fs::read_dir(dir.join("out/effects_frames")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    };
    assert!(frames(&dir).iter().any(|f| f.contains("schlick")));
    succeeded(&effects(&dir, &scene("exact"), &[], None));
    assert!(!frames(&dir).iter().any(|f| f.contains("schlick")), "frames of a method the scene no longer names: {:?}", frames(&dir));
    let before = (fs::read(dir.join("out/effects_errors.csv")).unwrap(), frames(&dir));
    fs::write(dir.join("scene.yaml"), scene("exact, lazanyi")).unwrap();
    let killed = Command::new(common::binary())
        .env("NKLUT_CRASH_AT", "staged")
        .arg("--db")
        .arg(common::database_dir())
        .arg("--out")
        .arg(dir.join("out"))
        .arg("effects")
        .arg(dir.join("scene.yaml"))
        .output()
        .unwrap();
    assert!(!killed.status.success());
    assert_eq!((fs::read(dir.join("out/effects_errors.csv")).unwrap(), frames(&dir)), before, "a killed run changed the set");
}

/// Built-in spheres by the thousand (a 500 kB scene of 20 M triangles) and 250 spheres
/// under a 100 MB budget: refused naming `objects` and both sizes, at once, before a mesh
/// is built or the BVH allocates (machine-independent: the budget is set).
#[test]
fn thousands_of_spheres_are_refused_by_name_before_the_bvh_is_built() {
    let dir = tempfile::tempdir().unwrap();
    let scene_of = |spheres: usize| {
        let mut text = String::from("resolution: [8, 8]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: {reflection: {max_depth: 1}, distance_maps: {size: 8, layers: 2}}\nobjects:\n  - {mesh: sphere, material: 3d/glass/BK7, methods: [exact]}\n");
        text.push_str(&"  - {mesh: sphere, scale: 0.01, diffuse: [0.5, 0.5, 0.5]}\n".repeat(spheres));
        text
    };
    let start = std::time::Instant::now();
    let stderr = refused(&effects(dir.path(), &scene_of(5000), &[], Some("4G")), "objects");
    assert!(
        stderr.contains("20484096 triangles") && stderr.contains("more than the memory budget of 4.3 GB (NKLUT_MEMORY_BUDGET)"),
        "{stderr}"
    );
    let stderr = refused(&effects(dir.path(), &scene_of(250), &[], Some("100M")), "objects");
    assert!(stderr.contains("1028096 triangles"), "{stderr}");
    assert!(start.elapsed() < Duration::from_secs(60), "the refusals took {:?}", start.elapsed());
}

/// Bounds stated as they are checked: a GTAO radius of 0 is refused with the range
/// `(0, 100]` (not `[0, 100]`), a position of 1e308 is written `1e308` (not 309 digits),
/// and `--ao-max-brute 2⁶⁴ − 1` is refused instead of brute-forcing any scene.
#[test]
fn small_bounds_are_stated_as_they_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let gtao = "resolution: [16, 16]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 1, gtao: { radius: 0 } } }\nobjects:\n  - { mesh: sphere, diffuse: [0.5, 0.5, 0.5] }\n";
    let stderr = refused(&effects(dir.path(), gtao, &[], None), "ambient_occlusion.gtao.radius");
    assert!(stderr.contains("(0, 100]"), "{stderr}");
    let far = ao_scene("{ mesh: sphere, position: [1e308, 0, 0], diffuse: [0.5, 0.5, 0.5] }");
    let stderr = refused(&effects(dir.path(), &far, &[], None), "position");
    assert!(stderr.contains("1e308") && !stderr.contains(&"0".repeat(100)), "{stderr}");
    let sphere = ao_scene("{ mesh: sphere, diffuse: [0.5, 0.5, 0.5] }");
    let stderr = refused(&effects(dir.path(), &sphere, &["--ao-max-brute", "18446744073709551615"], None), "--ao-max-brute");
    assert!(stderr.contains("must lie in 0..=131072"), "{stderr}");
}

/// An OBJ grid of `cells` × `cells` squares, two triangles each, in the plane z = 0.
fn grid_obj(cells: usize) -> String {
    let mut text = String::new();
    for j in 0..=cells {
        for i in 0..=cells {
            text.push_str(&format!("v {i} {j} 0\n"));
        }
    }
    for j in 0..cells {
        for i in 0..cells {
            let a = j * (cells + 1) + i + 1;
            let c = a + cells + 1;
            text.push_str(&format!("f {a} {} {}\nf {a} {} {c}\n", a + 1, c + 1, c + 1));
        }
    }
    text
}

/// Meshes read from OBJ files count as geometry in every command, the browser bench
/// (`gpu web`, which needs no adapter) as `effects`: a 20 000-triangle grid (0.5 MB of
/// text) is refused under an 8 MiB budget, naming the file and its triangles at 512 bytes
/// each (10.24 MB), counted on the text before it is parsed; two 5 000-triangle grids that
/// fit one at a time (2.56 MB each) are refused together under 4 MiB (5.12 MB), naming the
/// object that passes it. Under the default budget both scenes are accepted.
#[test]
fn meshes_from_files_count_against_the_budget_in_every_command() {
    let dir = common::scratch("obj-geometry");
    fs::write(dir.join("big.obj"), grid_obj(100)).unwrap();
    fs::write(dir.join("half.obj"), grid_obj(50)).unwrap();
    fs::write(dir.join("other.obj"), grid_obj(50)).unwrap();
    let one = "resolution: [8, 8]\ncamera: { frames: 1 }\nmeasurements: [image_error]\nobjects:\n  - { mesh: big.obj, material: 3d/metals/gold, methods: [exact] }\n";
    let two = "resolution: [8, 8]\ncamera: { frames: 1 }\nmeasurements: [image_error]\nobjects:\n  - { mesh: half.obj, material: 3d/metals/gold, methods: [exact] }\n  - { mesh: other.obj, material: 3d/metals/gold, methods: [exact] }\n";
    let traced = |scene: &str| {
        scene.replace(
            "measurements: [image_error]",
            "measurements: [image_error]\neffects: { reflection: { max_depth: 1 }, distance_maps: { size: 8, layers: 2 } }",
        )
    };
    let mut commands: Vec<&[&str]> = vec![&["effects"][..]];
    if cfg!(feature = "gpu") {
        commands.push(&["gpu", "web"][..]);
    }
    for command in commands {
        let cpu = command[0] == "effects";
        let scene = |text: &str| if cpu { traced(text) } else { text.to_string() };
        let flags: &[&str] = if cpu { &["--hero-size", "0"] } else { &[] };
        let stderr = refused(&run(&dir, command, &scene(one), flags, Some("8M")), "big.obj");
        assert!(
            stderr.contains("its 20000 triangles") && stderr.contains("would take about 10 MB, more than the memory budget of 8 MB"),
            "{command:?}: {stderr}"
        );
        let stderr = refused(&run(&dir, command, &scene(two), flags, Some("4M")), "objects[1]");
        assert!(
            stderr.contains(
                "the geometry of objects 0–1 (10000 triangles, other the last) would take about 5 MB, more than the memory budget of 4 MB"
            ),
            "{command:?}: {stderr}"
        );
        succeeded(&run(&dir, command, &scene(one), flags, None));
        succeeded(&run(&dir, command, &scene(two), flags, None));
    }
}
