// nklut Fresnel shader library (SPEC §5, issue 7). One function per method, each mapping
// c = cosθ ∈ [0, 1] to F per colour channel (vec3 = red, green, blue), f32 throughout.
// Per-material parameters come from `material`, filled on the CPU (src/gpu/params.rs).
//
// A pipeline is this library + one generated line
//     fn shade(c: f32) -> vec3<f32> { return method_xxx(c); }
// + the shared entry points below (vs_fullscreen/fs_ramp for the cosθ ramp and timing,
// vs_mesh/fs_mesh for rendered objects). Nothing here is copied per method.

struct MaterialParams {
    n: vec4<f32>,                     // rgb = n per channel
    k: vec4<f32>,                     // rgb = k per channel
    f0: vec4<f32>,                    // ((n−1)² + k²)/((n+1)² + k²)
    compensated_exponent: vec4<f32>,  // λ of schlick_compensated
    compensated_scale: vec4<f32>,     // the factor in front of (1 − c)^λ (2n, SPEC §5.4)
    compensated_fallback: vec4<f32>,  // 1 where no real λ exists: plain schlick_nk
    lazanyi_a: vec4<f32>,             // a of lazanyi (α = 6)
    nvidia_bias: vec4<f32>,
    nvidia_scale: vec4<f32>,
    nvidia_power: vec4<f32>,
    constant_colour: vec4<f32>,       // the `constant` baseline (F0)
}

struct View {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,       // camera position (world), w unused
    viewport: vec4<f32>,  // width, height of the target in pixels
}

@group(0) @binding(0) var<uniform> material: MaterialParams;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var lut_texture: texture_2d<f32>;
@group(0) @binding(3) var lut_sampler: sampler;

fn pow5(x: vec3<f32>) -> vec3<f32> {
    let x2 = x * x;
    return x2 * x2 * x;
}

// x^p with 0^p = 0 (pow(0, p) is undefined in WGSL).
fn pow_or_zero(x: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    return select(pow(max(x, vec3<f32>(1e-30)), p), vec3<f32>(0.0), x <= vec3<f32>(0.0));
}

// SPEC §5.1 for one channel, the stable form of src/fresnel.rs::exact: s² = 1 − c²,
// A = n² − k² − s², r = √(A² + 4n²k²); a², b² = the larger of (r ± A)/2 and (nk)²/larger;
// a − c = (a² − c²)/(a + c) when A ≥ 0; Rs = ((a − c)² + b²)/((a + c)² + b²),
// Rp = Rs ((ac − s²)² + b²c²)/((ac + s²)² + b²c²); F = (Rs + Rp)/2. No tanθ.
fn exact_channel(n: f32, k: f32, c_in: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    if (n == 1.0 && k == 0.0) {
        return 0.0;
    }
    let s2 = (1.0 - c) * (1.0 + c);
    let big_a = (n - 1.0) * (n + 1.0) - k * k + c * c;
    let nk = n * k;
    let r = sqrt(big_a * big_a + 4.0 * nk * nk);
    var a2: f32;
    var b2: f32;
    if (big_a >= 0.0) {
        a2 = (r + big_a) * 0.5;
        b2 = select(0.0, nk * nk / a2, a2 > 0.0);
    } else {
        b2 = (r - big_a) * 0.5;
        a2 = select(0.0, nk * nk / b2, b2 > 0.0);
    }
    let a = sqrt(a2);
    if (a + c == 0.0) {
        return 1.0;
    }
    var a_minus_c: f32;
    if (big_a >= 0.0) {
        let r_plus_a = r + big_a;
        let a2_minus_c2 = (n - 1.0) * (n + 1.0) - k * k + select(0.0, 2.0 * nk * nk / r_plus_a, r_plus_a > 0.0);
        a_minus_c = a2_minus_c2 / (a + c);
    } else {
        a_minus_c = a - c;
    }
    let rs = (a_minus_c * a_minus_c + b2) / ((a + c) * (a + c) + b2);
    let ac = a * c;
    let p_num = (ac - s2) * (ac - s2) + b2 * c * c;
    let p_den = (ac + s2) * (ac + s2) + b2 * c * c;
    let rp = select(rs, rs * p_num / p_den, p_den > 0.0);
    return clamp(0.5 * (rs + rp), 0.0, 1.0);
}

// 1. exact (SPEC §5.1).
fn method_exact(c: f32) -> vec3<f32> {
    let n = material.n;
    let k = material.k;
    return vec3<f32>(exact_channel(n.r, k.r, c), exact_channel(n.g, k.g, c), exact_channel(n.b, k.b, c));
}

// 2. schlick (SPEC §5.2; Schlick 1994): F0 + (1 − F0)(1 − c)⁵, F0 precomputed.
fn method_schlick(c: f32) -> vec3<f32> {
    let f0 = material.f0.rgb;
    return f0 + (vec3<f32>(1.0) - f0) * pow5(vec3<f32>(1.0 - c));
}

// 3. schlick_nk (SPEC §5.3; Lazányi & Szirmay-Kalos 2005):
// ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²), from n and k.
fn method_schlick_nk(c: f32) -> vec3<f32> {
    let n = material.n.rgb;
    let k2 = material.k.rgb * material.k.rgb;
    let nm1 = n - vec3<f32>(1.0);
    let np1 = n + vec3<f32>(1.0);
    return (nm1 * nm1 + 4.0 * n * pow5(vec3<f32>(1.0 - c)) + k2) / (np1 * np1 + k2);
}

// 4. schlick_compensated (SPEC §5.4): schlick_nk − scale·(1 − c)^λ, λ per channel exact at
// θ = 84.26°; where no real λ exists (fallback = 1) plain schlick_nk.
fn method_schlick_compensated(c: f32) -> vec3<f32> {
    let base = method_schlick_nk(c);
    let x = vec3<f32>(1.0 - c);
    let compensated = base - material.compensated_scale.rgb * pow_or_zero(x, material.compensated_exponent.rgb);
    return select(compensated, base, material.compensated_fallback.rgb > vec3<f32>(0.5));
}

// 5. lazanyi (SPEC §5.5; Lazányi & Szirmay-Kalos 2005, the F82 form):
// schlick − a c (1 − c)⁶, a exact at c = 1/7.
fn method_lazanyi(c: f32) -> vec3<f32> {
    let x = 1.0 - c;
    let x6 = x * x * x * x * x * x;
    return method_schlick(c) - material.lazanyi_a.rgb * (c * x6);
}

// 6. nvidia (SPEC §5.6): max(0, min(1, bias + scale (1 − c)^power)), fitted per material.
fn method_nvidia(c: f32) -> vec3<f32> {
    let x = vec3<f32>(1.0 - c);
    let f = material.nvidia_bias.rgb + material.nvidia_scale.rgb * pow_or_zero(x, material.nvidia_power.rgb);
    return clamp(f, vec3<f32>(0.0), vec3<f32>(1.0));
}

// 7. lut (SPEC §5.7): N×1 texture, texel i = F at c = (i + ½)/N, hardware linear filter,
// clamp-to-edge, u = c, v = ½.
fn method_lut(c: f32) -> vec3<f32> {
    return textureSampleLevel(lut_texture, lut_sampler, vec2<f32>(c, 0.5), 0.0).rgb;
}

// Baseline: a constant colour, the floor of any pass.
fn method_constant(c: f32) -> vec3<f32> {
    return material.constant_colour.rgb;
}

// Baseline: one plain texture fetch whose coordinate does not depend on c.
fn method_texture(c: f32) -> vec3<f32> {
    return textureSampleLevel(lut_texture, lut_sampler, vec2<f32>(0.5, 0.5), 0.0).rgb;
}

// The expensive shader of the `--subtract` timing (the study's method): a dependent chain
// of transcendental operations no compiler can fold.
fn method_burner(c: f32) -> vec3<f32> {
    var x = c;
    for (var i = 0; i < 64; i = i + 1) {
        x = sin(x * 1.37 + c) * 0.9 + 0.05;
    }
    return vec3<f32>(x * 1e-3);
}

// ---- shared entry points -------------------------------------------------------------

// One triangle covering the whole target.
@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) @invariant vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - vec2<f32>(1.0), 0.0, 1.0);
}

// The cosθ ramp: pixel column x shades c = (x + ½)/width (frag position x is x + ½).
@fragment
fn fs_ramp(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = position.x / view.viewport.x;
    return vec4<f32>(shade(c), 1.0);
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
