// nklut layered distance maps (Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3 ch. 17): the
// search of a ray through one object's map, the WGSL twin of crates/effects/src/distance_map.rs,
// operation for operation in f32. See that file and docs/effects.md for the algorithm:
// cube-map faces in the Vulkan/WebGPU convention, nearest texel; the ray x + R·d walked in
// t ∈ [0, 1] with d = |x|·t/(1 − t); against a layer g = 1 − D/|p|; linear steps find
// front → behind, secant steps refine; a ray that starts on a layer's surface (|g| ≤
// tolerance = 8/size) is neither in front nor behind until it leaves that band; empty
// texels are neither. The nearest hit over the layers wins.
//
// Every map of a frame lives in one buffer, `map_texels`; a `MapView` says where one map
// starts. The functions read only that buffer and their arguments.

// One object's map: its reference point, texels per face edge, layers, and the index of
// its first texel in `map_texels` (layer-major, then face, row, column).
struct MapView {
    centre: vec4<f32>,
    size: u32,
    layers: u32,
    base: u32,
    pad: u32,
}

// Linear and secant step counts of the search.
struct SearchSteps {
    linear: u32,
    secant: u32,
    pad0: u32,
    pad1: u32,
}

// Per texel: (distance, normal.xyz); distance < 0: nothing there.
@group(1) @binding(0) var<storage, read> map_texels: array<vec4<f32>>;

// Texel index within a layer of a direction (major axis, then s = (sc/|ma| + 1)/2, t likewise).
fn map_texel_index(size: u32, d: vec3<f32>) -> u32 {
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
    let n = f32(size);
    let s = 0.5 * (sc / ma + 1.0);
    let t = 0.5 * (tc / ma + 1.0);
    let column = min(u32(max(s * n, 0.0)), size - 1u);
    let row = min(u32(max(t * n, 0.0)), size - 1u);
    return face * size * size + row * size + column;
}

// Where texel `index` of `layer` sits in `map_texels`.
fn map_slot(map: MapView, layer: u32, index: u32) -> u32 {
    return map.base + layer * 6u * map.size * map.size + index;
}

fn map_texel(map: MapView, layer: u32, index: u32) -> vec4<f32> {
    return map_texels[map_slot(map, layer, index)];
}

// One probe at t: g, the texel index read, and whether that texel holds a surface.
struct Probe {
    g: f32,
    index: u32,
    found: bool,
}

fn map_probe(map: MapView, layer: u32, x: vec3<f32>, r: vec3<f32>, scale: f32, t: f32) -> Probe {
    var p: Probe;
    if (t < 1.0) {
        let point = x + r * (scale * t / (1.0 - t));
        p.index = map_texel_index(map.size, point);
        let texel = map_texel(map, layer, p.index);
        p.found = texel.x >= 0.0;
        p.g = 1.0 - texel.x / length(point);
    } else {
        p.index = map_texel_index(map.size, r);
        p.found = map_texel(map, layer, p.index).x >= 0.0;
        p.g = 1.0;
    }
    return p;
}

// The hit in one layer: t (−1: none) and the texel index read there.
struct LayerHit {
    t: f32,
    index: u32,
}

fn map_search_layer(map: MapView, steps: SearchSteps, layer: u32, x: vec3<f32>, r: vec3<f32>) -> LayerHit {
    var none: LayerHit;
    none.t = -1.0;
    let tolerance = 8.0 / f32(map.size);
    let scale = max(length(x), 1e-9);
    let start = map_probe(map, layer, x, r, scale, 0.0);
    var on_surface = start.found && abs(start.g) <= tolerance;
    var has_front = start.found && start.g < -tolerance;
    var ta = 0.0;
    var ga = start.g;
    var tb = 0.0;
    var gb = 0.0;
    var index_b = 0u;
    var bracketed = false;
    for (var k = 1u; k <= steps.linear; k = k + 1u) {
        let t = f32(k) / f32(steps.linear);
        let sample = map_probe(map, layer, x, r, scale, t);
        on_surface = on_surface && sample.found && abs(sample.g) <= tolerance;
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
    for (var i = 0u; i < steps.secant; i = i + 1u) {
        let tm = ta + (tb - ta) * ga / (ga - gb);
        let sample = map_probe(map, layer, x, r, scale, tm);
        if (!sample.found) {
            break;
        }
        hit.t = tm;
        hit.index = sample.index;
        if (i + 1u == steps.secant) {
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

// Where a search ended: the point relative to the map's centre and t in `point.w` (t < 0:
// no hit); the layer and texel index read there.
struct MapHit {
    point: vec4<f32>,
    layer: u32,
    index: u32,
}

// The nearest hit over all layers of the ray x + R·d (x relative to the map's centre).
fn map_search(map: MapView, steps: SearchSteps, x: vec3<f32>, r: vec3<f32>) -> MapHit {
    var best: MapHit;
    best.point = vec4<f32>(0.0, 0.0, 0.0, -1.0);
    best.layer = 0u;
    best.index = 0u;
    for (var layer = 0u; layer < map.layers; layer = layer + 1u) {
        let hit = map_search_layer(map, steps, layer, x, r);
        if (hit.t >= 0.0 && (best.point.w < 0.0 || hit.t < best.point.w)) {
            var point = r * map_texel(map, layer, hit.index).x;
            if (hit.t < 1.0) {
                let scale = max(length(x), 1e-9);
                point = x + r * (scale * hit.t / (1.0 - hit.t));
            }
            best.point = vec4<f32>(point, hit.t);
            best.layer = layer;
            best.index = hit.index;
        }
    }
    return best;
}
