// nklut specular effects: multiple reflections and refractions through layered distance
// maps (Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3 ch. 17, listing 17-5), with F from
// the scene's Fresnel method — the WGSL twin of the bounce loop of crates/effects/src/trace.rs
// and the bounce rule of crates/effects/src/optics.rs, traced by the search of
// shaders/distance_map.wgsl.
//
// A fragment of a diffuse object shows its lit colour. A fragment of a specular object
// starts a path: at every specular surface it splits into a reflected branch (weight ×F)
// and, for a dielectric, a refracted one (×(1 − F)); a ray from inside sees the relative
// index 1/η (its own Fresnel curve, with total internal reflection) and where no refracted
// direction exists the refracted share turns back as a mirror reflection with weight 1.
// Branches are traced through the distance map of the object the fragment shows, depth
// first on a small stack, until a diffuse surface ends them with its lit colour, the ray
// finds nothing (black) or no bounce is left (black). Directions follow the n of the green
// channel; weights are per channel.
//
// A pipeline is this file plus two generated lines (crates/gpu/src/passes/specular.rs):
//     const REFRACTION: bool = …;     // the effect: reflection only, or with refraction
//     fn reflectance(c: f32, curve: u32) -> vec3<f32> { return fresnel_xxx(…); }
// where curve 2m is material m seen from outside and 2m + 1 from inside.

#import contracts
#import fresnel
#import distance_map
#import diffuse
#import scene_mesh
#import lut_sample

struct EffectFrame {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    lights: Lights,
    steps: SearchSteps,
    // x = the reflection's max depth, y = the refraction's
    depths: vec4<u32>,
}

// Per object of the scene.
struct SceneObject {
    surface: DiffuseSurface,
    // x: ROLE_DIFFUSE, ROLE_CONDUCTOR or ROLE_DIELECTRIC (contracts); y: its material
    role: vec4<u32>,
    // x: n of the geometric (green) channel, for Snell's law
    geometric_n: vec4<f32>,
    // a specular object's distance map
    map: MapView,
}

@group(0) @binding(0) var<uniform> frame: EffectFrame;
@group(0) @binding(1) var<storage, read> objects: array<SceneObject>;
// Curve 2m: material m from outside (η); 2m + 1: from inside (conj(1/η)).
@group(0) @binding(2) var<storage, read> materials: array<MaterialParams>;
// The `lut` method's curves, one row per curve (a 1×1 blank for the other methods).
@group(0) @binding(3) var lut_atlas: texture_2d<f32>;
@group(0) @binding(4) var lut_sampler: sampler;
// Per texel of `map_texels`: rgb = a diffuse surface's lit colour, a = the specular
// object's index (−1: diffuse).
@group(1) @binding(1) var<storage, read> map_surfaces: array<vec4<f32>>;


// A ray of a path: where it leaves, its unit direction, its weight per channel and the
// bounces taken to get there.
struct PathRay {
    origin: vec3<f32>,
    bounces: u32,
    direction: vec3<f32>,
    weight: vec3<f32>,
}

// Mirror direction of unit v about unit n: v − 2(v·n)n.
fn mirror_direction(v: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return v - n * (2.0 * dot(v, n));
}

// Snell's law for unit v against unit n facing it, relative index eta = n_from/n_to:
// ηv + (η cosθᵢ − cosθₜ)n in xyz, w = 1; w = 0 past the critical angle.
fn refracted_direction(v: vec3<f32>, n: vec3<f32>, eta: f32) -> vec4<f32> {
    let cos_i = -dot(v, n);
    let cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if (cos_t2 < 0.0) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(normalize(v * eta + n * (eta * cos_i - sqrt(cos_t2))), 1.0);
}

// The (at most two) branches leaving a specular surface.
struct Branches {
    count: u32,
    rays: array<PathRay, 2>,
}

fn add_branch(b: ptr<function, Branches>, origin: vec3<f32>, direction: vec3<f32>, weight: vec3<f32>, bounces: u32) {
    (*b).rays[(*b).count] = PathRay(origin, bounces, direction, weight);
    (*b).count = (*b).count + 1u;
}

// The branches of object `o` hit at `point` with unit shading `normal` (outward) by unit
// `incoming` carrying `weight` after `bounces` bounces.
fn scatter(o: SceneObject, point: vec3<f32>, normal: vec3<f32>, incoming: vec3<f32>, weight: vec3<f32>, bounces: u32) -> Branches {
    var b: Branches;
    b.count = 0u;
    let dielectric = o.role.x == ROLE_DIELECTRIC;
    let from_inside = dot(incoming, normal) > 0.0;
    var facing = normal;
    if (from_inside) { facing = -normal; }
    let cos_i = min(-dot(incoming, facing), 1.0);
    let mirror = mirror_direction(incoming, facing);
    let f = reflectance(cos_i, 2u * o.role.y + u32(from_inside && dielectric));
    let can_reflect = bounces < frame.depths.x;
    let can_refract = REFRACTION && bounces < frame.depths.y;
    if (!dielectric) {
        if (can_reflect) { add_branch(&b, point, mirror, weight * f, bounces + 1u); }
        return b;
    }
    var eta = 1.0 / o.geometric_n.x;
    if (from_inside) { eta = o.geometric_n.x; }
    let refracted = refracted_direction(incoming, facing, eta);
    if (refracted.w > 0.0) {
        if (can_reflect) { add_branch(&b, point, mirror, weight * f, bounces + 1u); }
        if (can_refract) { add_branch(&b, point, refracted.xyz, weight * (vec3<f32>(1.0) - f), bounces + 1u); }
    } else if (can_refract) {
        add_branch(&b, point, mirror, weight, bounces + 1u);
    } else if (can_reflect) {
        add_branch(&b, point, mirror, weight * f, bounces + 1u);
    }
    return b;
}

// Radiance towards −incoming from the specular object `first` seen at `point`: every
// branch traced through that object's distance map.
fn path_radiance(first: u32, point: vec3<f32>, normal: vec3<f32>, incoming: vec3<f32>) -> vec3<f32> {
    let map = objects[first].map;
    // PATH_STACK holds every pending branch of the deepest path a scene may ask for.
    var stack: array<PathRay, PATH_STACK>;
    var top = 0u;
    var total = vec3<f32>(0.0);
    var branches = scatter(objects[first], point, normal, incoming, vec3<f32>(1.0), 0u);
    loop {
        for (var i = 0u; i < branches.count; i = i + 1u) {
            stack[top] = branches.rays[i];
            top = top + 1u;
        }
        branches.count = 0u;
        if (top == 0u) {
            break;
        }
        top = top - 1u;
        let ray = stack[top];
        let hit = map_search(map, frame.steps, ray.origin - map.centre.xyz, ray.direction);
        if (hit.point.w < 0.0) {
            continue;
        }
        let slot = map_slot(map, hit.layer, hit.index);
        let surface = map_surfaces[slot];
        if (surface.a < 0.0) {
            total = total + ray.weight * surface.rgb;
            continue;
        }
        let next = u32(surface.a);
        branches = scatter(objects[next], hit.point.xyz + map.centre.xyz, map_texels[slot].yzw, ray.direction, ray.weight, ray.bounces);
    }
    return total;
}

// The draw's instance index is the object's index in the scene.
@vertex
fn vs_effect(input: MeshVertexIn, @builtin(instance_index) object: u32) -> MeshVertexOut {
    var out: MeshVertexOut;
    out.clip = frame.view_proj * vec4<f32>(input.position, 1.0);
    out.world = input.position;
    out.normal = input.normal;
    out.object = object;
    return out;
}

// rgb = radiance (linear); a = 1 + the specular object shown, 0 for a diffuse surface.
@fragment
fn fs_effect(input: MeshVertexOut) -> @location(0) vec4<f32> {
    let o = objects[input.object];
    let n = normalize(input.normal);
    if (o.role.x == ROLE_DIFFUSE) {
        return vec4<f32>(diffuse_lit(frame.lights, diffuse_albedo(o.surface, input.world, n), input.world, n), 0.0);
    }
    let incoming = normalize(input.world - frame.eye.xyz);
    return vec4<f32>(path_radiance(input.object, input.world, n, incoming), f32(input.object + 1u));
}
