//! The numbers Rust and WGSL share, written once, here: the shaders read them from the
//! module `contracts`, which [`wgsl`] generates from these definitions and
//! [`crate::compose`] serves to `#import contracts`. A value changed here changes both
//! sides; nothing is repeated in `shaders/` (the constants of the Fresnel methods, such as
//! μ̄ = `fresnel::LAZANYI_COS`, come from `nklut_optics` the same way).

use nklut_effects::ao::gtao::{HILBERT_WIDTH, NOISE_FRAME_STRIDE, R1, R2};
use nklut_effects::scene::effects::MAX_DEPTH;
use nklut_effects::scene::{LightSource, MAX_LIGHTS};
use nklut_optics::fresnel::LAZANYI_COS;

/// What an object of an effects scene is to `shaders/specular.wgsl` (`SceneObject.role.x`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObjectRole {
    Diffuse,
    Conductor,
    Dielectric,
}

impl ObjectRole {
    pub const ALL: [ObjectRole; 3] = [ObjectRole::Diffuse, ObjectRole::Conductor, ObjectRole::Dielectric];

    /// The code the shader reads.
    pub fn code(self) -> u32 {
        match self {
            ObjectRole::Diffuse => 0,
            ObjectRole::Conductor => 1,
            ObjectRole::Dielectric => 2,
        }
    }

    /// The WGSL constant's name.
    fn constant(self) -> &'static str {
        match self {
            ObjectRole::Diffuse => "ROLE_DIFFUSE",
            ObjectRole::Conductor => "ROLE_CONDUCTOR",
            ObjectRole::Dielectric => "ROLE_DIELECTRIC",
        }
    }
}

/// What a light of the scene is to `shaders/diffuse.wgsl` (`LightItem.kind.x`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    Directional,
    Point,
    Ambient,
}

impl LightKind {
    pub const ALL: [LightKind; 3] = [LightKind::Directional, LightKind::Point, LightKind::Ambient];

    /// The kind of a scene's light.
    pub fn of(light: &LightSource) -> LightKind {
        match light {
            LightSource::Directional { .. } => LightKind::Directional,
            LightSource::Point { .. } => LightKind::Point,
            LightSource::Ambient { .. } => LightKind::Ambient,
        }
    }

    /// The code the shader reads.
    pub fn code(self) -> u32 {
        match self {
            LightKind::Directional => 0,
            LightKind::Point => 1,
            LightKind::Ambient => 2,
        }
    }

    /// The WGSL constant's name.
    fn constant(self) -> &'static str {
        match self {
            LightKind::Directional => "LIGHT_DIRECTIONAL",
            LightKind::Point => "LIGHT_POINT",
            LightKind::Ambient => "LIGHT_AMBIENT",
        }
    }
}

/// The branch stack of the specular pass's depth-first path walk. A hit pushes at most two
/// branches (reflected, refracted) and the walk pops one at a time, so at most one
/// pending sibling waits per bounce level: a path of `MAX_DEPTH` bounces (the most a
/// scene may ask) holds at most `MAX_DEPTH + 1` rays at once (`tests` walk the full
/// binary tree). No branch is ever dropped.
pub const PATH_STACK: usize = MAX_DEPTH as usize + 1;

/// The node stack of the surfel tree's traversal (`cs_tree`): a tree deeper than this is
/// an error before the pass runs (`passes::ao`).
pub const SURFEL_STACK: usize = 64;

/// The frames after which GTAO's noise repeats (XeGTAO `vaGTAO.hlsl`: `NoiseIndex =
/// frameIndex % 64`), as `effects::ao::gtao::noise` takes them; `tests` hold this to that
/// body (frame f and f + this give the same noise, f + half of it not).
pub const GTAO_NOISE_PERIOD: u32 = 64;

/// The module `contracts` of the shaders.
pub fn wgsl() -> String {
    let mut text = String::from("// Generated from crates/gpu/src/contracts.rs: the numbers Rust and WGSL share.\n");
    for role in ObjectRole::ALL {
        text.push_str(&format!("const {}: u32 = {}u;\n", role.constant(), role.code()));
    }
    text.push_str(&format!("const PATH_STACK: u32 = {PATH_STACK}u;\nconst SURFEL_STACK: u32 = {SURFEL_STACK}u;\n"));
    for kind in LightKind::ALL {
        text.push_str(&format!("const {}: u32 = {}u;\n", kind.constant(), kind.code()));
    }
    text.push_str(&format!("const MAX_LIGHTS: u32 = {MAX_LIGHTS}u;\n"));
    // μ̄ of `f82_tint` and the cosine where `lazanyi` is exact (`fresnel::LAZANYI_COS`), as
    // the f32 the shader computes in: the shortest decimal that reads back as that f32.
    text.push_str(&format!("const LAZANYI_COS: f32 = {:?};\n", LAZANYI_COS as f32));
    // GTAO's noise (`effects::ao::gtao::noise`) and angles, as the f32 twin rounds them.
    text.push_str(&format!(
        "const GTAO_HILBERT_WIDTH: u32 = {HILBERT_WIDTH}u;\nconst GTAO_NOISE_FRAME_STRIDE: u32 = {NOISE_FRAME_STRIDE}u;\nconst GTAO_NOISE_PERIOD: u32 = {GTAO_NOISE_PERIOD}u;\n"
    ));
    text.push_str(&format!("const GTAO_R2: vec2<f32> = vec2<f32>({:?}, {:?});\n", R2[0] as f32, R2[1] as f32));
    text.push_str(&format!("const GTAO_R1: f32 = {:?};\n", R1 as f32));
    text.push_str(&format!("const GTAO_PI: f32 = {:?};\n", std::f64::consts::PI as f32));
    text.push_str(&format!("const GTAO_HALF_PI: f32 = {:?};\n", std::f64::consts::FRAC_PI_2 as f32));
    // The GTAO denoiser's constants (`effects::ao::denoise`), as the f32 twin rounds them.
    {
        use nklut_effects::ao::denoise::{DIAGONAL_WEIGHT, EDGE_DEPTH_FRACTION, EDGE_LEVELS, EDGE_OFFSET, LEAK_STRENGTH, LEAK_THRESHOLD};
        let constants = [
            ("GTAO_EDGE_DEPTH_FRACTION", EDGE_DEPTH_FRACTION),
            ("GTAO_EDGE_OFFSET", EDGE_OFFSET),
            ("GTAO_EDGE_LEVELS", EDGE_LEVELS),
            ("GTAO_DIAGONAL_WEIGHT", DIAGONAL_WEIGHT),
            ("GTAO_LEAK_THRESHOLD", LEAK_THRESHOLD),
            ("GTAO_LEAK_STRENGTH", LEAK_STRENGTH),
        ];
        for (name, value) in constants {
            text.push_str(&format!("const {name}: f32 = {:?};\n", value as f32));
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The specular pass's walk, on the CPU: the most rays its stack holds for a full
    /// binary tree of `depth` bounces (every hit splits in two while bounces are left).
    fn deepest_stack(depth: u32) -> usize {
        let mut stack: Vec<u32> = Vec::new();
        let mut deepest = 0;
        // The first hit's branches, at 1 bounce.
        let mut branches = if depth > 0 { vec![1, 1] } else { vec![] };
        loop {
            stack.append(&mut branches);
            deepest = deepest.max(stack.len());
            let Some(bounces) = stack.pop() else { break };
            if bounces < depth {
                branches = vec![bounces + 1, bounces + 1];
            }
        }
        deepest
    }

    #[test]
    fn the_path_stack_holds_every_branch_of_the_deepest_path() {
        assert_eq!(deepest_stack(1), 2);
        assert_eq!(deepest_stack(3), 4);
        assert_eq!(deepest_stack(MAX_DEPTH), PATH_STACK);
    }

    /// GTAO's noise repeats after [`GTAO_NOISE_PERIOD`] frames in the CPU body, and not
    /// after half as many; the module's constants read back as the f32 the twin computes in.
    #[test]
    fn the_gtao_constants_are_the_cpu_body_s() {
        use nklut_effects::ao::gtao::noise;
        for (x, y) in [(0, 0), (5, 9), (63, 17)] {
            for frame in [0, 3, 40] {
                assert_eq!(noise::<f32>(x, y, frame), noise::<f32>(x, y, frame + GTAO_NOISE_PERIOD));
                assert_ne!(noise::<f32>(x, y, frame), noise::<f32>(x, y, frame + GTAO_NOISE_PERIOD / 2));
            }
        }
        let text = wgsl();
        let value = |name: &str| {
            text.lines().find_map(|l| l.strip_prefix(&format!("const {name}: f32 = "))).unwrap().trim_end_matches(';').to_string()
        };
        assert_eq!(value("GTAO_R1").parse::<f32>().unwrap(), R1 as f32);
        assert_eq!(value("GTAO_HALF_PI").parse::<f32>().unwrap(), std::f32::consts::FRAC_PI_2);
        assert!(text.contains(&format!("const GTAO_R2: vec2<f32> = vec2<f32>({:?}, {:?});", R2[0] as f32, R2[1] as f32)));
        assert!(text.contains("const GTAO_HILBERT_WIDTH: u32 = 64u;") && text.contains("const GTAO_NOISE_FRAME_STRIDE: u32 = 288u;"));
    }

    #[test]
    fn the_generated_module_names_each_number_once() {
        let text = wgsl();
        assert!(text.contains("const ROLE_CONDUCTOR: u32 = 1u;") && text.contains("const ROLE_DIELECTRIC: u32 = 2u;"));
        assert!(text.contains(&format!("const PATH_STACK: u32 = {}u;", MAX_DEPTH + 1)));
        let point = LightSource::Point { position: [0.0; 3], intensity: [1.0; 3] };
        assert!(text.contains(&format!("const LIGHT_POINT: u32 = {}u;", LightKind::of(&point).code())));
        assert!(text.contains(&format!("const MAX_LIGHTS: u32 = {MAX_LIGHTS}u;")));
        // μ̄ = 1/7 reads back as the f32 nearest 1/7, the value `1.0 / 7.0` folds to in WGSL.
        let mu = text.lines().find_map(|l| l.strip_prefix("const LAZANYI_COS: f32 = ")).unwrap();
        assert_eq!(mu.trim_end_matches(';').parse::<f32>().unwrap(), (1.0_f64 / 7.0) as f32);
        for line in text.lines().filter(|l| l.starts_with("const ")) {
            let name = line.split(':').next().unwrap();
            assert_eq!(text.matches(&format!("{name}:")).count(), 1, "{name}");
        }
    }
}
