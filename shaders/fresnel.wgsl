// nklut Fresnel shader library. Each Fresnel method's function maps c = cosθ ∈ [0, 1] and
// the per-channel parameters of one index η = n + ik (a value of `MaterialParams`) to F per
// colour channel (vec3 = red, green, blue), f32 throughout; the `lut` method takes its
// texture and sampler. No function reads a global, so the same function evaluates a ray
// arriving from outside (the page's η) and from inside (the relative index conj(1/η),
// which has its own curve with total internal reflection): the caller passes the
// parameters of that index.
//
// The methods' functions and `MaterialParams` come from the generated module
// `fresnel_methods` (crates/gpu/src/params.rs writes it from each method's unit under
// crates/optics/src/fresnel/methods/, where the WGSL sits beside its f32 twin); this file
// holds what they share and the timing's baselines. Passes import it (`#import fresnel`,
// resolved by crates/gpu/src/compose.rs). The numbers it shares with Rust
// (μ̄ = LAZANYI_COS) come from the generated module `contracts` (crates/gpu/src/contracts.rs).

#import contracts
#import fresnel_methods

// Every method's function mirrors its f32 twin in crates/optics/src/fresnel (the same
// generic body the f64 reference runs, evaluated in f32) operation by operation: c clamped
// to [0, 1] first (but in fresnel_lut, whose clamp-to-edge sampler does it), integer powers
// as products (m⁵ = m²·m²·m, m⁶ = m⁵·m), a real power as exp2(p·log2 m).

fn pow5(m: vec3<f32>) -> vec3<f32> {
    let m2 = m * m;
    return m2 * m2 * m;
}

// fresnel::approx::shader_pow: exp2(p·log2 m), 0 at m = 0 (log2(0) is outside WGSL's
// domain, so guard it instead of relying on exp2(−∞) = 0).
fn shader_pow(m: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    return select(exp2(p * log2(max(m, vec3<f32>(1e-30)))), vec3<f32>(0.0), m <= vec3<f32>(0.0));
}

// SPEC §5.1 for one channel: fresnel::exact_f32 (see crates/optics/src/fresnel/exact.rs for the stable
// forms). a0 = (n − 1)(n + 1) − k²; A = (n² − k²) − s² if c² > ½ else a0 + c²;
// r = √(A² + 4(nk)²); the larger of a², b² is (r + |A|)/2, the other (nk)²/larger;
// a − c = (a0 + b²)/(a + c) when A ≥ 0;
// F = ((a−c)² + b²)((ac+s²)² + b²c² + (ac−s²)² + b²c²) / (2((a+c)² + b²)((ac+s²)² + b²c²)).
fn exact_channel(n: f32, k: f32, c_in: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    if (n == 1.0 && k == 0.0) {
        return 0.0;
    }
    let nk = n * k;
    let nk2 = nk * nk;
    let a0 = (n - 1.0) * (n + 1.0) - k * k;
    let sin2 = (1.0 - c) * (1.0 + c);
    let c2 = c * c;
    let big_a = select(a0 + c2, (n * n - k * k) - sin2, c2 > 0.5);
    let r = sqrt(big_a * big_a + 4.0 * nk2);
    let larger = 0.5 * (r + abs(big_a));
    let smaller = select(0.0, nk2 / larger, larger > 0.0);
    let a2 = select(smaller, larger, big_a >= 0.0);
    let b2 = select(larger, smaller, big_a >= 0.0);
    let a = sqrt(a2);
    let a_plus_c = a + c;
    let a_minus_c = select(a - c, (a0 + b2) / a_plus_c, big_a >= 0.0 && a_plus_c > 0.0);
    let s_num = a_minus_c * a_minus_c + b2;
    let s_den = a_plus_c * a_plus_c + b2;
    let ac = a * c;
    let b2c2 = b2 * c2;
    let p_num = (ac - sin2) * (ac - sin2) + b2c2;
    let p_den = (ac + sin2) * (ac + sin2) + b2c2;
    let denominator = 2.0 * s_den * p_den;
    if (!(denominator > 0.0)) {
        return 1.0;
    }
    return clamp(s_num * (p_den + p_num) / denominator, 0.0, 1.0);
}

// exact for a dielectric (SPEC §5.1 with k = 0; the real-index form of Cook & Torrance
// 1982 and Walter et al. 2007, the study's dielectric anchor): g² = n² − 1 + c²;
// F = ½ ((g − c)/(g + c))² (1 + ((c (g + c) − 1)/(c (g − c) + 1))²), and 1 where g² < 0
// (total internal reflection). The timing's anchor for dielectric materials; k is ignored.
fn exact_dielectric_channel(n: f32, c_in: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    if (n == 1.0) {
        return 0.0;
    }
    let g2 = n * n - 1.0 + c * c;
    if (!(g2 > 0.0)) {
        return 1.0;
    }
    let g = sqrt(g2);
    let s = (g - c) / (g + c);
    let t = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return clamp(0.5 * s * s * (1.0 + t * t), 0.0, 1.0);
}

fn fresnel_exact_dielectric(c: f32, p: MaterialParams) -> vec3<f32> {
    let n = p.n;
    return vec3<f32>(exact_dielectric_channel(n.r, c), exact_dielectric_channel(n.g, c), exact_dielectric_channel(n.b, c));
}

// Baseline: a constant colour, the floor of any pass.
fn fresnel_constant(c: f32, p: MaterialParams) -> vec3<f32> {
    return p.constant_colour.rgb;
}

// Baseline: one plain texture fetch whose coordinate does not depend on c in value: u is
// 0.5 + c·1e-30, which rounds to 0.5 in f32 for every c in [0, 1] (the term is below half an
// ulp of 0.5), yet no compiler may fold it, so an amplified pass fetches once per repeat
// instead of hoisting one fetch out of its loop.
fn fresnel_texture(c: f32, curve: texture_2d<f32>, curve_sampler: sampler) -> vec3<f32> {
    return textureSampleLevel(curve, curve_sampler, vec2<f32>(0.5 + c * 1e-30, 0.5), 0.0).rgb;
}

// The expensive shader of the `--subtract` timing (the study's method): a dependent chain
// of transcendental operations no compiler can fold.
fn fresnel_burner(c: f32) -> vec3<f32> {
    var x = c;
    for (var i = 0; i < 64; i = i + 1) {
        x = sin(x * 1.37 + c) * 0.9 + 0.05;
    }
    return vec3<f32>(x * 1e-3);
}
