// nklut distance-map search (Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3 ch. 17): the
// WGSL twin of src/effects/distance_map.rs, operation for operation in f32. See that file
// and docs/effects.md for the algorithm: cube-map faces in the Vulkan/WebGPU convention,
// nearest texel; the ray x + R·d walked in t ∈ [0, 1] with d = |x|·t/(1 − t); against a
// layer g = 1 − D/|p|; linear steps find front → behind, secant steps refine; a ray that
// starts on a layer's surface (|g| ≤ tolerance) is neither in front nor behind until it
// leaves that band; empty texels are neither. The nearest hit over the layers wins.

struct SearchParams {
    size: u32,
    layers: u32,
    linear: u32,
    secant: u32,
    count: u32,
    tolerance: f32,
    pad0: u32,
    pad1: u32,
}

// A ray relative to the map's centre.
struct SearchRay {
    origin: vec4<f32>,
    direction: vec4<f32>,
}

// point.xyz and t in point.w (t < 0: no hit); where.x = layer, where.y = texel index.
struct SearchHit {
    point: vec4<f32>,
    at: vec4<u32>,
}

@group(0) @binding(0) var<uniform> search: SearchParams;
// Per layer, 6·size² texels: (distance, normal.xyz); distance < 0: nothing there.
@group(0) @binding(1) var<storage, read> texels: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> rays: array<SearchRay>;
@group(0) @binding(3) var<storage, read_write> hits: array<SearchHit>;

// Face and texel index of a direction (major axis, then s = (sc/|ma| + 1)/2, t likewise).
fn texel_index(d: vec3<f32>) -> u32 {
    let a = abs(d);
    var face = 0u;
    var sc = 0.0;
    var tc = 0.0;
    var ma = 1.0;
    if (a.x >= a.y && a.x >= a.z) {
        ma = a.x;
        tc = -d.y;
        if (d.x > 0.0) { face = 0u; sc = -d.z; } else { face = 1u; sc = d.z; }
    } else if (a.y >= a.z) {
        ma = a.y;
        sc = d.x;
        if (d.y > 0.0) { face = 2u; tc = d.z; } else { face = 3u; tc = -d.z; }
    } else {
        ma = a.z;
        tc = -d.y;
        if (d.z > 0.0) { face = 4u; sc = d.x; } else { face = 5u; sc = -d.x; }
    }
    let n = f32(search.size);
    let s = 0.5 * (sc / ma + 1.0);
    let t = 0.5 * (tc / ma + 1.0);
    let column = min(u32(max(s * n, 0.0)), search.size - 1u);
    let row = min(u32(max(t * n, 0.0)), search.size - 1u);
    return face * search.size * search.size + row * search.size + column;
}

fn texel_at(layer: u32, index: u32) -> vec4<f32> {
    return texels[layer * 6u * search.size * search.size + index];
}

// One probe at t: g in x, the texel index in y (as bits), 1 in z when the texel holds a surface.
struct Probe {
    g: f32,
    index: u32,
    found: bool,
}

fn probe(layer: u32, x: vec3<f32>, r: vec3<f32>, scale: f32, t: f32) -> Probe {
    var p: Probe;
    if (t < 1.0) {
        let point = x + r * (scale * t / (1.0 - t));
        p.index = texel_index(point);
        let texel = texel_at(layer, p.index);
        p.found = texel.x >= 0.0;
        p.g = 1.0 - texel.x / length(point);
    } else {
        p.index = texel_index(r);
        p.found = texel_at(layer, p.index).x >= 0.0;
        p.g = 1.0;
    }
    return p;
}

// The hit in one layer: t in w (−1: none), the texel index in the second value.
struct LayerHit {
    t: f32,
    index: u32,
}

fn search_layer(layer: u32, x: vec3<f32>, r: vec3<f32>) -> LayerHit {
    var none: LayerHit;
    none.t = -1.0;
    let scale = max(length(x), 1e-9);
    let start = probe(layer, x, r, scale, 0.0);
    var on_surface = start.found && abs(start.g) <= search.tolerance;
    var has_front = start.found && start.g < -search.tolerance;
    var ta = 0.0;
    var ga = start.g;
    var tb = 0.0;
    var gb = 0.0;
    var index_b = 0u;
    var bracketed = false;
    for (var k = 1u; k <= search.linear; k = k + 1u) {
        let t = f32(k) / f32(search.linear);
        let sample = probe(layer, x, r, scale, t);
        on_surface = on_surface && sample.found && abs(sample.g) <= search.tolerance;
        if (on_surface) {
            continue;
        }
        if (!sample.found) {
            has_front = false;
        } else if (sample.g < 0.0) {
            has_front = true;
            ta = t;
            ga = sample.g;
        } else if (has_front) {
            tb = t;
            gb = sample.g;
            index_b = sample.index;
            bracketed = true;
            break;
        }
    }
    if (!bracketed) {
        return none;
    }
    var hit: LayerHit;
    hit.t = tb;
    hit.index = index_b;
    for (var i = 0u; i < search.secant; i = i + 1u) {
        let tm = ta + (tb - ta) * ga / (ga - gb);
        let sample = probe(layer, x, r, scale, tm);
        if (!sample.found) {
            break;
        }
        hit.t = tm;
        hit.index = sample.index;
        if (i + 1u == search.secant) {
            break;
        }
        if (sample.g < 0.0) {
            ta = tm;
            ga = sample.g;
        } else {
            tb = tm;
            gb = sample.g;
        }
    }
    return hit;
}

@compute @workgroup_size(64)
fn cs_search(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= search.count) {
        return;
    }
    let x = rays[id.x].origin.xyz;
    let r = rays[id.x].direction.xyz;
    var best: SearchHit;
    best.point = vec4<f32>(0.0, 0.0, 0.0, -1.0);
    best.at = vec4<u32>(0u);
    for (var layer = 0u; layer < search.layers; layer = layer + 1u) {
        let hit = search_layer(layer, x, r);
        if (hit.t >= 0.0 && (best.point.w < 0.0 || hit.t < best.point.w)) {
            var point = r * texel_at(layer, hit.index).x;
            if (hit.t < 1.0) {
                let scale = max(length(x), 1e-9);
                point = x + r * (scale * hit.t / (1.0 - hit.t));
            }
            best.point = vec4<f32>(point, hit.t);
            best.at = vec4<u32>(layer, hit.index, 0u, 0u);
        }
    }
    hits[id.x] = best;
}
