// nklut distance-map rendering: one face of one layer of a specular object's layered
// distance map, rasterised (Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3 ch. 17). The
// face's projection sends a point p (relative to the reference point) to NDC (sc/|ma|,
// −tc/|ma|) with (sc, tc, ma) of the Vulkan/WebGPU cube-map face table, so pixel (column,
// row) is the texel whose centre direction `face_direction` gives on the CPU
// (crates/effects/src/distance_map.rs): rasterising at pixel centres is casting the texel's ray.
// Each fragment writes its distance from the reference point and its smooth normal, and
// what it is: a specular object (its index) or a diffuse surface's lit colour. Layers
// below the last peel specular surfaces: layer L keeps, per texel, the nearest fragment
// farther than layer L − 1's, and none where layer L − 1 is empty (depth peeling); the last layer holds the first diffuse
// surface. The host draws only the objects a layer holds.

#import diffuse
#import scene_mesh

// One face of one layer: the reference point, the face (0..5 = +x, −x, +y, −y, +z, −z),
// whether an earlier layer is peeled away, and the projection's near and far distances.
struct MapFace {
    centre: vec4<f32>,
    face: u32,
    peel: u32,
    near: f32,
    far: f32,
}

// Per object (the draw's instance index): its diffuse surface (unused for specular ones).
struct MapObject {
    surface: DiffuseSurface,
    specular: vec4<u32>,   // x = 1 for a specular object
}

@group(0) @binding(0) var<uniform> map_face: MapFace;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(0) @binding(2) var<storage, read> map_objects: array<MapObject>;
// The previous layer's six faces (distance in x; < 0: empty).
@group(0) @binding(3) var previous: texture_2d_array<f32>;

// (sc, tc, ma) of relative position q on face `face`: s = (sc/ma + 1)/2, t = (tc/ma + 1)/2.
fn face_coordinates(face: u32, q: vec3<f32>) -> vec3<f32> {
    switch face {
        case 0u: { return vec3<f32>(-q.z, -q.y, q.x); }
        case 1u: { return vec3<f32>(q.z, -q.y, -q.x); }
        case 2u: { return vec3<f32>(q.x, q.z, q.y); }
        case 3u: { return vec3<f32>(q.x, -q.z, -q.y); }
        case 4u: { return vec3<f32>(q.x, -q.y, q.z); }
        default: { return vec3<f32>(-q.x, -q.y, -q.z); }
    }
}

@vertex
fn vs_map(input: MeshVertexIn, @builtin(instance_index) object: u32) -> MeshVertexOut {
    let c = face_coordinates(map_face.face, input.position - map_face.centre.xyz);
    let a = map_face.far / (map_face.far - map_face.near);
    var out: MeshVertexOut;
    out.clip = vec4<f32>(c.x, -c.y, c.z * a - map_face.near * a, c.z);
    out.world = input.position;
    out.normal = input.normal;
    out.object = object;
    return out;
}

struct MapTexelOut {
    // (distance, normal.xyz)
    @location(0) geometry: vec4<f32>,
    // rgb = a diffuse surface's lit colour; a = the specular object's index, or −1
    @location(1) surface: vec4<f32>,
}

@fragment
fn fs_map(input: MeshVertexOut) -> MapTexelOut {
    let distance = length(input.world - map_face.centre.xyz);
    if (map_face.peel == 1u) {
        let before = textureLoad(previous, vec2<i32>(input.clip.xy), i32(map_face.face), 0).x;
        if (before < 0.0 || distance <= before * (1.0 + 1e-5)) {
            discard;
        }
    }
    let n = normalize(input.normal);
    var out: MapTexelOut;
    out.geometry = vec4<f32>(distance, n);
    let object = map_objects[input.object];
    if (object.specular.x == 1u) {
        out.surface = vec4<f32>(0.0, 0.0, 0.0, f32(input.object));
    } else {
        let albedo = diffuse_albedo(object.surface, input.world, n);
        out.surface = vec4<f32>(diffuse_lit(lights, albedo, input.world, n), -1.0);
    }
    return out;
}
