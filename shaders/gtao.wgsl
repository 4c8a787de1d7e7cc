// Screen-space ground-truth ambient occlusion (GTAO; Jimenez, Wu, Pesce and Jarabo,
// "Practical Real-Time Strategies for Accurate Indirect Occlusion", SIGGRAPH 2016 course,
// §3–4, Algorithm 1) with the heuristics engines add (XeGTAO, Intel 2021: radius
// multiplier, falloff, sample distribution power and start offset, thin-occluder
// compensation, final power, the 5 % lerp of |n_φ|, Hilbert-R2 noise per pixel and frame,
// depth reads clamped to the image's edge; HDRP's screen-radius clamp). The derivation and
// the f64/f32 CPU twin, one body for both, are in crates/effects/src/ao/gtao.rs
// (`pixel_visibility`, `frame_visibility`, `slice_visibility`, `texel_plane_point`,
// `edge_point`, `hilbert_index`, `noise`); this file performs the same operations in the
// same order, function for function, line for line.
//
// Per pixel of a G-buffer of view-space points and unit normals (x right, y up, the camera
// looking down −z): `slices` slice planes turning evenly about the view vector v; in each,
// `steps` samples per side along the slice's image direction out to the projected radius,
// each taking the point where the ray through its own position meets its texel's plane;
// the horizons they raise (within the radius, or weighted by the falloff) give the slice's
// open part by the paper's eq. 10, weighted by the projected normal's length; one frame's
// value is the mean over slices raised to the final power.
//
// Denoising (XeGTAO's edge-aware 3 × 3 filter; the derivation and the CPU twin are in
// crates/effects/src/ao/denoise.rs: `edges`, `denoised`, `centre_weight`): after the frames, one dispatch
// per pass, `cs_denoise_forward` (accessibility → denoised) and `cs_denoise_back` (denoised →
// accessibility) taking turns, each with the centre's weight and the last-pass flag in its
// own uniform.
//
// Accumulation: one dispatch per frame (`params.frame` of `params.frames`). Frame 0 writes
// its value, each later frame adds its own to the running sum in `accessibility`, and the
// last divides by the frame count: the CPU body's `total = total + frame_visibility(…)`
// over frames 0, 1, …, then `total / frames`, the same additions in the same order. Without
// noise there is one frame at the fixed offsets (½, 1). The output is the accessibility, or
// −1 where no surface is.

#import contracts

struct GtaoParams {
    width: u32,
    height: u32,
    slices: u32,
    steps: u32,
    frame: u32,     // this dispatch's frame, 0 … frames − 1
    frames: u32,    // frames accumulated (1 without noise)
    noise: u32,     // 1: per-pixel Hilbert-R2 noise; 0: Algorithm 1's fixed offsets
    clamp_to_edge: u32, // 1: a sample beyond the image's edge reads the edge texel; 0: skipped
    focal: f32,     // focal length in pixels
    radius: f32,    // search radius (view-space units), before the multiplier
    radius_multiplier: f32,
    falloff_range: f32,       // 0: the hard cut
    distribution_power: f32,  // 1: samples evenly spaced
    start_pixels: f32,
    thin_occluder: f32,
    thickness_blend: f32,     // 0: the horizon is the highest sample
    final_power: f32,
    normal_lerp: f32,
    min_radius_pixels: f32,
    max_radius_pixels: f32,   // the largest f32 where unclamped
    denoise_centre: f32,      // a denoiser dispatch: the centre pixel's weight (beta, or beta / 5 before the last pass)
    denoise_last: u32,        // a denoiser dispatch: 1 on the last pass (the result clamped to [0, 1])
    pad0: u32,
    pad1: u32,
}

// A pixel of the G-buffer: view-space point (w: 1 where a surface is, 0 where none) and
// unit normal (w unused).
struct GSample {
    position: vec4<f32>,
    normal: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: GtaoParams;
@group(0) @binding(1) var<storage, read> gbuffer: array<GSample>;
@group(0) @binding(2) var<storage, read_write> accessibility: array<f32>;
// The denoiser's other buffer: its passes take turns reading one and writing the other.
@group(0) @binding(3) var<storage, read_write> denoised: array<f32>;

// Eq. 10: a slice's open fraction weighted by the projected normal's length, between the
// horizons h_minus ≤ 0 ≤ h_plus (angles from v), the normal at angle gamma.
fn slice_visibility(h_minus: f32, h_plus: f32, gamma: f32, projected_length: f32) -> f32 {
    let cos_g = cos(gamma);
    let sin_g = sin(gamma);
    let side_minus = -cos(2.0 * h_minus - gamma) + cos_g + 2.0 * h_minus * sin_g;
    let side_plus = -cos(2.0 * h_plus - gamma) + cos_g + 2.0 * h_plus * sin_g;
    return projected_length * 0.25 * (side_minus + side_plus);
}

// A slice side's horizon cosine after a sample of cosine `sample`: a higher sample raises it
// to the sample, a lower one pulls it toward the sample by blend² (Unreal's thickness blend;
// 0: the larger of the two). The twin of `effects::ao::gtao::raised_horizon`.
fn raised_horizon(horizon: f32, sample: f32, blend: f32) -> f32 {
    if sample > horizon {
        return sample;
    }
    return horizon - blend * blend * (horizon - sample);
}

// The position of pixel (x, y) mod GTAO_HILBERT_WIDTH along the Hilbert curve that fills the
// tile.
fn hilbert_index(px: u32, py: u32) -> u32 {
    var x = px % GTAO_HILBERT_WIDTH;
    var y = py % GTAO_HILBERT_WIDTH;
    var index = 0u;
    var level = GTAO_HILBERT_WIDTH / 2u;
    while level > 0u {
        let right = select(0u, 1u, (x & level) != 0u);
        let up = select(0u, 1u, (y & level) != 0u);
        index += level * level * ((3u * right) ^ up);
        if up == 0u {
            if right == 1u {
                x = GTAO_HILBERT_WIDTH - 1u - x;
                y = GTAO_HILBERT_WIDTH - 1u - y;
            }
            let swap = x;
            x = y;
            y = swap;
        }
        level /= 2u;
    }
    return index;
}

fn fraction(x: f32) -> f32 {
    return x - floor(x);
}

// Pixel (x, y)'s noise in `frame`: (slice rotation, step offset), each in [0, 1).
fn noise(x: u32, y: u32, frame: u32) -> vec2<f32> {
    let index = hilbert_index(x, y) + GTAO_NOISE_FRAME_STRIDE * (frame % GTAO_NOISE_PERIOD);
    let i = f32(index);
    return vec2<f32>(fraction(0.5 + i * GTAO_R2.x), fraction(0.5 + i * GTAO_R2.y));
}

// WGSL's pow written out, as the f32 twin's `power`: exp2(p·log2 m).
fn power(m: f32, p: f32) -> f32 {
    return exp2(p * log2(m));
}

// Where the ray through pixel coordinates (x, y) meets the plane of the texel sample q;
// q's point where the ray grazes that plane (|cos| ≤ 0.1) or meets it behind the eye.
fn texel_plane_point(q: GSample, x: f32, y: f32, width: u32, height: u32, focal: f32) -> vec3<f32> {
    let ray = vec3<f32>((x - 0.5 * f32(width)) / focal, -(y - 0.5 * f32(height)) / focal, -1.0);
    let n = q.normal.xyz;
    let facing = dot(ray, n);
    if !(abs(facing) > 0.1 * sqrt(dot(ray, ray))) {
        return q.position.xyz;
    }
    let t = dot(q.position.xyz, n) / facing;
    if t > 0.0 {
        return ray * t;
    }
    return q.position.xyz;
}

// The G-buffer's index of floored pixel coordinates (x, y), or −1 off the image or where
// no surface is.
fn gtao_texel(x: f32, y: f32) -> i32 {
    if x < 0.0 || y < 0.0 || !(x < f32(params.width)) || !(y < f32(params.height)) {
        return -1;
    }
    let index = u32(y) * params.width + u32(x);
    if gbuffer[index].position.w == 0.0 {
        return -1;
    }
    return i32(index);
}

// Where a sample at pixel coordinates (x, y) beyond the image's edge stands when it reads
// the edge texel q: on the ray through (x, y) at q's view-space depth.
fn edge_point(q: GSample, x: f32, y: f32, width: u32, height: u32, focal: f32) -> vec3<f32> {
    let depth = -q.position.z;
    return vec3<f32>((x - 0.5 * f32(width)) / focal * depth, -(y - 0.5 * f32(height)) / focal * depth, -depth);
}

// Whether floored pixel coordinates (x, y) lie beyond the image's edge.
fn off_image(x: f32, y: f32) -> bool {
    return x < 0.0 || y < 0.0 || x > f32(params.width) - 1.0 || y > f32(params.height) - 1.0;
}

// One frame's accessibility at the covered pixel `here_index` = (x, y) with slice rotation
// offsets.x and step offset offsets.y.
fn frame_visibility(here_index: i32, x: u32, y: u32, offsets: vec2<f32>) -> f32 {
    let px = f32(x);
    let py = f32(y);
    let here = gbuffer[here_index];
    let position = here.position.xyz;
    let distance = sqrt(dot(position, position));
    let depth = -position.z;
    if !(distance > 0.0) || !(depth > 0.0) || params.slices == 0u {
        return 1.0;
    }
    let v = -position / distance;
    let n = here.normal.xyz;
    let radius = params.radius * params.radius_multiplier;
    let radius_pixels_unclamped = radius * params.focal / depth;
    if radius_pixels_unclamped < params.min_radius_pixels {
        return 1.0;
    }
    let radius_pixels = min(radius_pixels_unclamped, params.max_radius_pixels);
    let radius2 = radius * radius;
    let hard_cut = !(params.falloff_range > 0.0);
    let thickness = 1.0 + params.thin_occluder;
    let uniform_steps = params.distribution_power == 1.0;
    let steps = f32(params.steps);
    let last_x = f32(params.width) - 1.0;
    let last_y = f32(params.height) - 1.0;
    let e1_raw = vec3<f32>(1.0, 0.0, 0.0) - v.x * v;
    let e1 = e1_raw / sqrt(dot(e1_raw, e1_raw));
    let e2 = cross(v, e1);
    var total = 0.0;
    for (var slice = 0u; slice < params.slices; slice++) {
        let phi = GTAO_PI * (f32(slice) + offsets.x) / f32(params.slices);
        let ortho = e1 * cos(phi) + sin(phi) * e2;
        let screen_x = ortho.x * depth + position.x * ortho.z;
        let screen_y = -(ortho.y * depth + position.y * ortho.z);
        let screen_length = sqrt(screen_x * screen_x + screen_y * screen_y);
        if !(screen_length > 0.0) {
            continue;
        }
        let c = screen_x / screen_length;
        let s = screen_y / screen_length;
        let axis = cross(v, ortho);
        let projected = n - dot(n, axis) * axis;
        let projected_length = sqrt(dot(projected, projected));
        if !(projected_length > 0.0) {
            continue;
        }
        let cos_gamma = clamp(dot(projected, v) / projected_length, 0.0, 1.0);
        var sign = 1.0;
        if dot(projected, ortho) < 0.0 {
            sign = -1.0;
        }
        let gamma = sign * acos(cos_gamma);
        // Horizon cosines, from the tangent plane: θ = γ + π/2 (plus side), γ − π/2 (minus).
        let low_plus = cos(gamma + GTAO_HALF_PI);
        let low_minus = cos(gamma - GTAO_HALF_PI);
        var cos_plus = low_plus;
        var cos_minus = low_minus;
        for (var step = 0u; step < params.steps; step++) {
            var offset = offsets.y;
            if params.noise != 0u {
                offset = fraction(offsets.y + f32(slice + step * params.steps) * GTAO_R1);
            }
            let position_in_steps = f32(step) + offset;
            var t: f32;
            if uniform_steps {
                t = radius_pixels * position_in_steps / steps;
            } else {
                t = radius_pixels * power(position_in_steps / steps, params.distribution_power);
            }
            t = t + params.start_pixels;
            for (var k = 0u; k < 2u; k++) {
                let side = select(-1.0, 1.0, k == 0u);
                let sample_x = px + 0.5 + side * t * c;
                let sample_y = py + 0.5 + side * t * s;
                let sx = floor(sample_x);
                let sy = floor(sample_y);
                if sx == px && sy == py {
                    continue;
                }
                var point: vec3<f32>;
                let q_index = gtao_texel(sx, sy);
                if q_index >= 0 {
                    point = texel_plane_point(gbuffer[q_index], sample_x, sample_y, params.width, params.height, params.focal);
                } else if params.clamp_to_edge != 0u && off_image(sx, sy) {
                    let edge_index = gtao_texel(clamp(sx, 0.0, last_x), clamp(sy, 0.0, last_y));
                    if edge_index < 0 {
                        continue;
                    }
                    point = edge_point(gbuffer[edge_index], sample_x, sample_y, params.width, params.height, params.focal);
                } else {
                    continue;
                }
                let delta = point - position;
                let d2 = dot(delta, delta);
                if !(d2 > 0.0) {
                    continue;
                }
                // The distance the cut and the falloff see: the depth offset stretched.
                let thick = vec3<f32>(delta.x, delta.y, delta.z * thickness);
                let thick2 = dot(thick, thick);
                var cos_h = dot(delta, v) / sqrt(d2);
                let low = select(low_minus, low_plus, side > 0.0);
                if hard_cut {
                    if !(thick2 < radius2) {
                        continue;
                    }
                } else {
                    let weight = clamp((radius - sqrt(thick2)) / (params.falloff_range * radius), 0.0, 1.0);
                    cos_h = low + weight * (cos_h - low);
                }
                if side > 0.0 {
                    cos_plus = raised_horizon(cos_plus, cos_h, params.thickness_blend);
                } else {
                    cos_minus = raised_horizon(cos_minus, cos_h, params.thickness_blend);
                }
            }
        }
        let h_plus = gamma + min(acos(clamp(cos_plus, -1.0, 1.0)) - gamma, GTAO_HALF_PI);
        let h_minus = gamma + max(-acos(clamp(cos_minus, -1.0, 1.0)) - gamma, -GTAO_HALF_PI);
        let weight = projected_length + params.normal_lerp * (1.0 - projected_length);
        total = total + slice_visibility(h_minus, h_plus, gamma, weight);
    }
    let open = clamp(total / f32(params.slices), 0.0, 1.0);
    if params.final_power == 1.0 {
        return open;
    }
    return power(open, params.final_power);
}

@compute @workgroup_size(8, 8)
fn cs_gtao(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let pixel = id.y * params.width + id.x;
    let here_index = gtao_texel(f32(id.x), f32(id.y));
    if here_index < 0 {
        accessibility[pixel] = -1.0;
        return;
    }
    var offsets = vec2<f32>(0.5, 1.0);
    if params.noise != 0u {
        offsets = noise(id.x, id.y, params.frame);
    }
    var total = frame_visibility(here_index, id.x, id.y, offsets);
    if params.frame > 0u {
        total = accessibility[pixel] + total;
    }
    if params.frame + 1u == params.frames {
        total = total / f32(params.frames);
    }
    accessibility[pixel] = total;
}

// The index of the pixel at (x, y) clamped into the image (the CPU twin's `clamped`).
fn gtao_clamped_index(x: i32, y: i32) -> u32 {
    let cx = u32(clamp(x, 0, i32(params.width) - 1));
    let cy = u32(clamp(y, 0, i32(params.height) - 1));
    return cy * params.width + cx;
}

// The view-space depth of the pixel at (x, y) clamped into the image, or −1 where no
// surface is.
fn gtao_depth(x: i32, y: i32) -> f32 {
    let q = gbuffer[gtao_clamped_index(x, y)];
    if q.position.w == 0.0 {
        return -1.0;
    }
    return -q.position.z;
}

// An edge weight in [0, 1] as its 2 bits store it.
fn gtao_quantised(weight: f32) -> f32 {
    return floor(clamp(weight, 0.0, 1.0) * GTAO_EDGE_LEVELS + 0.5) / 3.0;
}

// Pixel (x, y)'s edge weights toward its left, right, top and bottom neighbours (all 0 where
// no surface is), (x, y) clamped into the image.
fn gtao_edges(px: i32, py: i32) -> vec4<f32> {
    let x = clamp(px, 0, i32(params.width) - 1);
    let y = clamp(py, 0, i32(params.height) - 1);
    let z = gtao_depth(x, y);
    if z < 0.0 {
        return vec4<f32>(0.0);
    }
    let n = array<f32, 4>(gtao_depth(x - 1, y), gtao_depth(x + 1, y), gtao_depth(x, y - 1), gtao_depth(x, y + 1));
    var d: array<f32, 4>;
    var jump: array<f32, 4>;
    for (var k = 0; k < 4; k++) {
        d[k] = n[k] - z;
        jump[k] = abs(d[k]);
    }
    for (var axis = 0; axis < 2; axis++) {
        let low = 2 * axis;
        let high = low + 1;
        if n[low] >= 0.0 && n[high] >= 0.0 {
            let slope = (d[high] - d[low]) * 0.5;
            jump[low] = min(abs(d[low]), abs(d[low] + slope));
            jump[high] = min(abs(d[high]), abs(d[high] - slope));
        }
    }
    let scale = z * GTAO_EDGE_DEPTH_FRACTION;
    var e: array<f32, 4>;
    for (var k = 0; k < 4; k++) {
        e[k] = 0.0;
        if n[k] >= 0.0 {
            e[k] = gtao_quantised(GTAO_EDGE_OFFSET - jump[k] / scale);
        }
    }
    return vec4<f32>(e[0], e[1], e[2], e[3]);
}

// The value a denoiser pass reads at the pixel (x, y) clamped into the image: from
// `denoised` or from `accessibility`; negative where no surface is.
fn gtao_value(x: i32, y: i32, from_denoised: bool) -> f32 {
    let index = gtao_clamped_index(x, y);
    if from_denoised {
        return denoised[index];
    }
    return accessibility[index];
}

// One denoiser pass at pixel (x, y) (its value `centre` ≥ 0): the weighted mean of the
// covered pixels among the nine.
fn denoised_value(x: i32, y: i32, centre: f32, from_denoised: bool) -> f32 {
    let own = gtao_edges(x, y);
    let l = gtao_edges(x - 1, y);
    let r = gtao_edges(x + 1, y);
    let t = gtao_edges(x, y - 1);
    let b = gtao_edges(x, y + 1);
    var e = vec4<f32>(own.x * l.y, own.y * r.x, own.z * t.w, own.w * b.z);
    let sum = e.x + e.y + e.z + e.w;
    let open = 4.0 - GTAO_LEAK_THRESHOLD;
    let leak = clamp(open - sum, 0.0, 1.0) / open * GTAO_LEAK_STRENGTH;
    e = clamp(e + vec4<f32>(leak), vec4<f32>(0.0), vec4<f32>(1.0));
    let corner_tl = GTAO_DIAGONAL_WEIGHT * (e.x * l.z + e.z * t.x);
    let corner_tr = GTAO_DIAGONAL_WEIGHT * (e.z * t.y + e.y * r.z);
    let corner_bl = GTAO_DIAGONAL_WEIGHT * (e.w * b.x + e.x * l.w);
    let corner_br = GTAO_DIAGONAL_WEIGHT * (e.y * r.w + e.w * b.y);
    let offsets = array<vec2<i32>, 8>(
        vec2<i32>(-1, 0), vec2<i32>(1, 0), vec2<i32>(0, -1), vec2<i32>(0, 1),
        vec2<i32>(-1, -1), vec2<i32>(1, -1), vec2<i32>(-1, 1), vec2<i32>(1, 1),
    );
    let weights = array<f32, 8>(e.x, e.y, e.z, e.w, corner_tl, corner_tr, corner_bl, corner_br);
    var total = params.denoise_centre * centre;
    var weight = params.denoise_centre;
    for (var k = 0; k < 8; k++) {
        let v = gtao_value(x + offsets[k].x, y + offsets[k].y, from_denoised);
        if v >= 0.0 {
            total = total + weights[k] * v;
            weight = weight + weights[k];
        }
    }
    let mean = total / weight;
    if params.denoise_last != 0u {
        return clamp(mean, 0.0, 1.0);
    }
    return mean;
}

// One denoiser pass at the pixel `id`, reading `denoised` or `accessibility`: negative
// (no surface) stays as it is.
fn denoised_pixel(id: vec3<u32>, from_denoised: bool) -> f32 {
    let centre = gtao_value(i32(id.x), i32(id.y), from_denoised);
    if centre < 0.0 {
        return centre;
    }
    return denoised_value(i32(id.x), i32(id.y), centre, from_denoised);
}

@compute @workgroup_size(8, 8)
fn cs_denoise_forward(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < params.width && id.y < params.height {
        denoised[id.y * params.width + id.x] = denoised_pixel(id, false);
    }
}

@compute @workgroup_size(8, 8)
fn cs_denoise_back(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < params.width && id.y < params.height {
        accessibility[id.y * params.width + id.x] = denoised_pixel(id, true);
    }
}
