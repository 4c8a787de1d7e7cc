// nklut F-only pass: the bindings and entry points shared by every Fresnel pipeline —
// vs_fullscreen/fs_ramp for the cosθ ramp and timing, vs_mesh/fs_mesh for rendered objects.
// A pipeline is this file (with the library it imports) + one generated line
//     fn shade(c: f32) -> vec3<f32> { return fresnel_xxx(c, material); }
// that picks the method (crates/gpu/src/render.rs).

#import fresnel

struct View {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,       // camera position (world), w unused
    viewport: vec4<f32>,  // width, height of the target in pixels
}

@group(0) @binding(0) var<uniform> material: MaterialParams;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var lut_texture: texture_2d<f32>;
@group(0) @binding(3) var lut_sampler: sampler;

// ---- shared entry points -------------------------------------------------------------

// One triangle covering the whole target.
@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) @invariant vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - vec2<f32>(1.0), 0.0, 1.0);
}

// The cosθ ramp: pixel column x shades c = (x + ½)/width (frag position x is x + ½).
// The timing's amplification: F is evaluated viewport.z times (at least once) at c,
// c + φ, c + 2φ … mod 1 (φ = 0.618034, so no two repeats share an argument and none can be
// folded or hoisted) and the mean written, which keeps every repeat live; once, it is
// shade(c) exactly (crates/gpu/src/sampling.rs).
@fragment
fn fs_ramp(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = position.x / view.viewport.x;
    let repeats = max(u32(view.viewport.z), 1u);
    var sum = shade(c);
    for (var i = 1u; i < repeats; i = i + 1u) {
        sum = sum + shade(fract(c + f32(i) * 0.618034));
    }
    return vec4<f32>(sum / f32(repeats), 1.0);
}

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct MeshOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_mesh(input: MeshIn) -> MeshOut {
    var out: MeshOut;
    out.clip = view.view_proj * vec4<f32>(input.position, 1.0);
    out.world = input.position;
    out.normal = input.normal;
    return out;
}

// F for c = |N·V|, no lighting; alpha 1 marks the pixels the object covers.
@fragment
fn fs_mesh(input: MeshOut) -> @location(0) vec4<f32> {
    let to_eye = normalize(view.eye.xyz - input.world);
    let c = clamp(abs(dot(normalize(input.normal), to_eye)), 0.0, 1.0);
    return vec4<f32>(shade(c), 1.0);
}
