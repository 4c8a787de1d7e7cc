// nklut diffuse surroundings: the albedo pattern of a diffuse surface and its light — the
// WGSL twin of `Diffuse::albedo_at` and `Light::shade` (src/scene/effects.rs), in f32. A
// point of albedo ρ and unit normal N shows ρ·(ambient + colour·max(0, −N·d̂)), d the
// light's direction of travel; no shadows, so a distance map may store the lit colour.

// A diffuse surface: `albedo`, and its pattern — kind.x = 0 plain, 1 checker (cell edge
// `shape.x`, the other cells `second`), 2 gradient (axis `shape.xyz`, `albedo` at p·axis =
// −1 to `second` at +1).
struct DiffuseSurface {
    albedo: vec4<f32>,
    second: vec4<f32>,
    shape: vec4<f32>,
    kind: vec4<u32>,
}

struct Light {
    direction: vec4<f32>,
    colour: vec4<f32>,
    ambient: vec4<f32>,
}

// The albedo at scene position p of a surface with normal n. The checker's cells lie in
// the two coordinates other than the normal's largest component (ties go to the later
// axis, as in the CPU twin).
fn diffuse_albedo(s: DiffuseSurface, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    if (s.kind.x == 1u) {
        let a = abs(n);
        var across = 0u;
        var largest = a.x;
        if (a.y >= largest) { across = 1u; largest = a.y; }
        if (a.z >= largest) { across = 2u; }
        let cells = vec3<i32>(floor(p / s.shape.x));
        var sum = 0;
        for (var i = 0u; i < 3u; i = i + 1u) {
            if (i != across) { sum = sum + cells[i]; }
        }
        if ((sum & 1) == 1) {
            return s.second.rgb;
        }
        return s.albedo.rgb;
    }
    if (s.kind.x == 2u) {
        let w = clamp(0.5 * (dot(p, s.shape.xyz) + 1.0), 0.0, 1.0);
        return s.albedo.rgb + w * (s.second.rgb - s.albedo.rgb);
    }
    return s.albedo.rgb;
}

// Radiance leaving a diffuse point of albedo `albedo` and unit normal `n`.
fn diffuse_lit(light: Light, albedo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let facing = max(-dot(n, light.direction.xyz) / length(light.direction.xyz), 0.0);
    return albedo * (light.ambient.rgb + light.colour.rgb * facing);
}
