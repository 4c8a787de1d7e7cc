// Screen-space ground-truth ambient occlusion (GTAO; Jimenez, Wu, Pesce and Jarabo,
// "Practical Real-Time Strategies for Accurate Indirect Occlusion", SIGGRAPH 2016 course,
// §3–4, Algorithm 1). The derivation and the f64/f32 CPU twin, one body for both, are in
// crates/effects/src/ao/gtao.rs (`pixel_visibility`, `slice_visibility`,
// `texel_plane_point`); this file performs the same operations in the same order.
//
// Per pixel of a G-buffer of view-space points and unit normals (x right, y up, the camera
// looking down −z): `slices` slice planes turning evenly about the view vector v; in each,
// `steps` samples per side along the slice's image direction out to the projected radius,
// each taking the point where the ray through its own position meets its texel's plane;
// the horizons they raise (within `radius`) give the slice's open part by the paper's
// eq. 10, weighted by the projected normal's length; the result is the mean over slices.
// One invocation per pixel; the output is the accessibility, or −1 where no surface is.

struct GtaoParams {
    width: u32,
    height: u32,
    slices: u32,
    steps: u32,
    focal: f32,   // focal length in pixels
    radius: f32,  // occluders within this distance count (view-space units)
    pad0: f32,
    pad1: f32,
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

const GTAO_PI: f32 = 3.141592653589793;
const GTAO_HALF_PI: f32 = 1.5707963267948966;

// Eq. 10: a slice's open fraction weighted by the projected normal's length, between the
// horizons h_minus ≤ 0 ≤ h_plus (angles from v), the normal at angle gamma.
fn slice_visibility(h_minus: f32, h_plus: f32, gamma: f32, projected_length: f32) -> f32 {
    let cos_g = cos(gamma);
    let sin_g = sin(gamma);
    let side_minus = -cos(2.0 * h_minus - gamma) + cos_g + 2.0 * h_minus * sin_g;
    let side_plus = -cos(2.0 * h_plus - gamma) + cos_g + 2.0 * h_plus * sin_g;
    return projected_length * 0.25 * (side_minus + side_plus);
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

fn pixel_visibility(x: u32, y: u32) -> f32 {
    let px = f32(x);
    let py = f32(y);
    let here_index = gtao_texel(px, py);
    if here_index < 0 {
        return -1.0;
    }
    let here = gbuffer[here_index];
    let position = here.position.xyz;
    let distance = sqrt(dot(position, position));
    let depth = -position.z;
    if !(distance > 0.0) || !(depth > 0.0) || params.slices == 0u {
        return 1.0;
    }
    let v = -position / distance;
    let n = here.normal.xyz;
    let radius_pixels = params.radius * params.focal / depth;
    let radius2 = params.radius * params.radius;
    let e1_raw = vec3<f32>(1.0, 0.0, 0.0) - v.x * v;
    let e1 = e1_raw / sqrt(dot(e1_raw, e1_raw));
    let e2 = cross(v, e1);
    var total = 0.0;
    for (var slice = 0u; slice < params.slices; slice++) {
        let phi = GTAO_PI * (f32(slice) + 0.5) / f32(params.slices);
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
        var cos_plus = cos(gamma + GTAO_HALF_PI);
        var cos_minus = cos(gamma - GTAO_HALF_PI);
        for (var step = 1u; step <= params.steps; step++) {
            let t = radius_pixels * f32(step) / f32(params.steps);
            for (var k = 0u; k < 2u; k++) {
                let side = select(-1.0, 1.0, k == 0u);
                let sample_x = px + 0.5 + side * t * c;
                let sample_y = py + 0.5 + side * t * s;
                let sx = floor(sample_x);
                let sy = floor(sample_y);
                if sx == px && sy == py {
                    continue;
                }
                let q_index = gtao_texel(sx, sy);
                if q_index < 0 {
                    continue;
                }
                let q = gbuffer[q_index];
                let delta = texel_plane_point(q, sample_x, sample_y, params.width, params.height, params.focal) - position;
                let d2 = dot(delta, delta);
                if d2 > 0.0 && d2 < radius2 {
                    let cos_h = dot(delta, v) / sqrt(d2);
                    if side > 0.0 {
                        cos_plus = max(cos_plus, cos_h);
                    } else {
                        cos_minus = max(cos_minus, cos_h);
                    }
                }
            }
        }
        let h_plus = gamma + min(acos(clamp(cos_plus, -1.0, 1.0)) - gamma, GTAO_HALF_PI);
        let h_minus = gamma + max(-acos(clamp(cos_minus, -1.0, 1.0)) - gamma, -GTAO_HALF_PI);
        total = total + slice_visibility(h_minus, h_plus, gamma, projected_length);
    }
    return clamp(total / f32(params.slices), 0.0, 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_gtao(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    accessibility[id.y * params.width + id.x] = pixel_visibility(id.x, id.y);
}
