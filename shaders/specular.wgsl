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

// The side a ray meets a surface from and the normal its bounce uses: the rule of `facing`
// in crates/effects/src/optics.rs. The surface's own plane decides the side (`from_inside`,
// found by the caller); the bounce takes the shading `normal` (outward) turned to that side,
// or `plane` (the plane's unit normal facing the ray) where the turned normal faces away
// from the ray — a grazing ray on a coarse mesh.
struct Facing {
    normal: vec3<f32>,
    cos_i: f32,
    from_inside: bool,
}

fn facing(incoming: vec3<f32>, normal: vec3<f32>, plane: vec3<f32>, from_inside: bool) -> Facing {
    var turned = normal;
    if (from_inside) { turned = -normal; }
    let cos_turned = -dot(incoming, turned);
    if (cos_turned > 0.0) {
        return Facing(turned, min(cos_turned, 1.0), from_inside);
    }
    return Facing(plane, clamp(-dot(incoming, plane), 0.0, 1.0), from_inside);
}

// A surface found in a distance map knows only its texel's `normal` (outward), which is its
// plane as well: the side is that of the normal, as on the CPU twin.
fn facing_texel(incoming: vec3<f32>, normal: vec3<f32>) -> Facing {
    let from_inside = dot(incoming, normal) > 0.0;
    return facing(incoming, normal, select(normal, -normal, from_inside), from_inside);
}

// The branches of object `o` hit at `point` on the side `side` by unit `incoming` carrying
// `weight` after `bounces` bounces.
fn scatter(o: SceneObject, point: vec3<f32>, side: Facing, incoming: vec3<f32>, weight: vec3<f32>, bounces: u32) -> Branches {
    var b: Branches;
    b.count = 0u;
    let dielectric = o.role.x == ROLE_DIELECTRIC;
    let from_inside = side.from_inside;
    let toward = side.normal;
    let mirror = mirror_direction(incoming, toward);
    let f = reflectance(side.cos_i, 2u * o.role.y + u32(from_inside && dielectric));
    let can_reflect = bounces < frame.depths.x;
    let can_refract = REFRACTION && bounces < frame.depths.y;
    if (!dielectric) {
        if (can_reflect) { add_branch(&b, point, mirror, weight * f, bounces + 1u); }
        return b;
    }
    var eta = 1.0 / o.geometric_n.x;
    if (from_inside) { eta = o.geometric_n.x; }
    let refracted = refracted_direction(incoming, toward, eta);
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

// Radiance towards −incoming from the specular object `first` seen at `point` from `side`:
// every branch traced through that object's distance map.
fn path_radiance(first: u32, point: vec3<f32>, side: Facing, incoming: vec3<f32>) -> vec3<f32> {
    let map = objects[first].map;
    // PATH_STACK holds every pending branch of the deepest path a scene may ask for.
    var stack: array<PathRay, PATH_STACK>;
    var top = 0u;
    var total = vec3<f32>(0.0);
    var branches = scatter(objects[first], point, side, incoming, vec3<f32>(1.0), 0u);
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
        let side = facing_texel(ray.direction, map_texels[slot].yzw);
        branches = scatter(objects[next], hit.point.xyz + map.centre.xyz, side, ray.direction, ray.weight, ray.bounces);
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
//
// The primary hit's side is the triangle's, as on the CPU twin: every triangle is wound
// counter-clockwise seen from the mesh's outside (`PackedMeshes`), so `front_facing` — the
// sign of the triangle's area on screen, which under a perspective projection is the sign
// of (eye − a) · (b − a) × (c − a) — says the camera sees the outside, exactly where the
// CPU's plane test does (up to the rasteriser's snapping of a triangle seen edge-on). The
// plane's direction, for the bounce of a grazing ray whose shading normal faces away, is
// that of the screen derivatives of the interpolated position, which lie in the plane.
@fragment
fn fs_effect(input: MeshVertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Derivatives before any branch (they need uniform control flow).
    let across = cross(dpdx(input.world), dpdy(input.world));
    let o = objects[input.object];
    let n = normalize(input.normal);
    if (o.role.x == ROLE_DIFFUSE) {
        return vec4<f32>(diffuse_lit(frame.lights, diffuse_albedo(o.surface, input.world, n), input.world, n), 0.0);
    }
    let incoming = normalize(input.world - frame.eye.xyz);
    let span = length(across);
    // The plane's normal facing the ray (the ray's own reverse where the plane is lost).
    var plane = -incoming;
    if (span > 0.0) {
        plane = across / span;
        if (dot(incoming, plane) > 0.0) { plane = -plane; }
    }
    let side = facing(incoming, n, plane, !front);
    return vec4<f32>(path_radiance(input.object, input.world, side, incoming), f32(input.object + 1u));
}
