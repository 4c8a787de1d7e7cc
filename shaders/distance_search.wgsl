// nklut distance-map search pass: runs `map_search` (shaders/distance_map.wgsl) for a batch
// of rays against one map, so the WGSL can be held to its CPU twin ray by ray
// (crates/gpu/src/distance_search.rs).

#import distance_map

struct SearchBatch {
    map: MapView,
    steps: SearchSteps,
    count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// A ray relative to the map's centre.
struct SearchRay {
    origin: vec4<f32>,
    direction: vec4<f32>,
}

// point.xyz and t in point.w (t < 0: no hit); at.x = layer, at.y = texel index.
struct SearchHit {
    point: vec4<f32>,
    at: vec4<u32>,
}

@group(0) @binding(0) var<uniform> batch: SearchBatch;
@group(0) @binding(1) var<storage, read> rays: array<SearchRay>;
@group(0) @binding(2) var<storage, read_write> hits: array<SearchHit>;

@compute @workgroup_size(64)
fn cs_search(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= batch.count) {
        return;
    }
    let hit = map_search(batch.map, batch.steps, rays[id.x].origin.xyz, rays[id.x].direction.xyz);
    var out: SearchHit;
    out.point = hit.point;
    out.at = vec4<u32>(hit.layer, hit.index, 0u, 0u);
    hits[id.x] = out;
}
