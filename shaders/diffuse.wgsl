// nklut diffuse surroundings: the albedo pattern of a diffuse surface and its lights — the
// WGSL twin of `Diffuse::albedo_at` (crates/effects/src/scene/effects.rs) and
// `lights::unshadowed` (crates/effects/src/scene/lights.rs), in f32. A point p of albedo ρ
// and unit normal N shows ρ·Σ over the scene's lights of: directional, colour·max(0, −N·d̂)
// (d its direction of travel); point, intensity·max(0, N·l̂)/|l|² (l = position − p);
// ambient, colour. No shadows, so a distance map may store the lit colour.

#import contracts

// A diffuse surface: `albedo`, and its pattern — kind.x = 0 plain, 1 checker (cell edge
// `shape.x`, the other cells `second`), 2 gradient (axis `shape.xyz`, `albedo` at p·axis =
// −1 to `second` at +1).
struct DiffuseSurface {
    albedo: vec4<f32>,
    second: vec4<f32>,
    shape: vec4<f32>,
    kind: vec4<u32>,
}

// One light: kind.x is LIGHT_DIRECTIONAL (`vector` its direction of travel), LIGHT_POINT
// (`vector` its position) or LIGHT_AMBIENT; `colour` its colour or intensity.
struct LightItem {
    kind: vec4<u32>,
    vector: vec4<f32>,
    colour: vec4<f32>,
}

// The scene's lights: the first count.x items.
struct Lights {
    count: vec4<u32>,
    items: array<LightItem, MAX_LIGHTS>,
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

// Radiance leaving a diffuse point `p` of albedo `albedo` and unit normal `n`.
fn diffuse_lit(lights: Lights, albedo: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < min(lights.count.x, MAX_LIGHTS); i = i + 1u) {
        let light = lights.items[i];
        var weight = 1.0;
        if (light.kind.x == LIGHT_DIRECTIONAL) {
            weight = max(-dot(n, light.vector.xyz) / length(light.vector.xyz), 0.0);
        } else if (light.kind.x == LIGHT_POINT) {
            let l = light.vector.xyz - p;
            let d2 = dot(l, l);
            weight = 0.0;
            if (d2 > 0.0) {
                weight = max(dot(n, l) / sqrt(d2), 0.0) / d2;
            }
        }
        sum = sum + light.colour.rgb * weight;
    }
    return albedo * sum;
}
