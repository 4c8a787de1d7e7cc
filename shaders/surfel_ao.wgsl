// Surfel accessibility and bent normals on the GPU (Bunnell, "Dynamic Ambient Occlusion and
// Indirect Lighting", GPU Gems 2 ch. 14; the method and its f64 CPU twin in
// crates/effects/src/ao, docs/ao.md). One invocation per receiving surfel; a pass gathers the
// shadow of every emitter (brute force) or of a cut of the surfel tree (hierarchy), each
// emitter weighted by its accessibility of the previous pass:
//
//   S = A · max(0, n_E·v) · min(1, g · max(0, n_R·v)) / (π r² + A)
//   a(i) = clamp(1 − Σ w_j S_ji, 0, 1),   bent(i) = normalise(n_i − Σ w_j S_ji v_ij)
//
// Entry points: cs_node_weights (a tree node's weight: the area-weighted mean accessibility
// of its leaves from the previous pass), cs_brute_force, cs_tree (one pass each),
// cs_shadow_terms (the shadow term alone for a list of configurations, to hold it to its
// CPU twin), and cs_indirect (one bounce of diffuse indirect light, brute force:
// E(i) = Σ_j B_j · F_ij · w_j, F the form factor to emitter j's front, w_j its weight).

#import contracts

const PI: f32 = 3.141592653589793;
const NO_CHILD: u32 = 0xffffffffu;

struct Params {
    count: u32,      // surfels
    nodes: u32,      // tree nodes (0 without a tree)
    gain: f32,       // g of the shadow form
    closeness: f32,  // κ: a node is one emitter when r² ≥ κ·A
    previous: u32,   // offset in `state` of the previous pass's accessibility
    next: u32,       // offset in `state` of this pass's accessibility
    weights: u32,    // offset in `state` of the nodes' weights
    pad: u32,
}

// A disc: centre and area, unit normal (w unused).
struct Disc {
    centre_area: vec4<f32>,
    normal: vec4<f32>,
}

// Per index k: tree node k's [left, right (NO_CHILD for a leaf), first, end) of its leaves
// in leaf order, and (order[k], rank[k], 0, 0): the surfel at leaf position k and the leaf
// position of surfel k.
struct Links {
    node: vec4<u32>,
    leaf: vec4<u32>,
}

// Four storage buffers, the downlevel limit: the discs (the surfels, then the tree's
// nodes), the links, the passes' state (two accessibility buffers that take turns and the
// nodes' weights, at the offsets of `params`) and the output.
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> discs: array<Disc>;
@group(0) @binding(2) var<storage, read> links: array<Links>;
@group(0) @binding(3) var<storage, read_write> state: array<f32>;
@group(0) @binding(4) var<storage, read_write> bent: array<vec4<f32>>;
// The indirect gather's own two (with `discs` and `state`, which holds the emitters'
// weights at `params.previous`): each surfel's radiosity (linear RGB) and what it gathers.
@group(0) @binding(5) var<storage, read> radiosity: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> gathered: array<vec4<f32>>;

// The disc term of an emitter disc (centre e, unit normal n_e, area A) at the point p with
// unit normal n_r, and the unit direction v from p to e: (S, v). `side` 1: the shadow the
// disc's back casts (cos θE = n_e·v); −1: the form factor to its front (cos θE = −n_e·v),
// which carries its light. Zero where the centres coincide, the disc has no area, turns
// the other side to p, or lies below p's horizon.
fn disc_term(e: vec3<f32>, n_e: vec3<f32>, area: f32, p: vec3<f32>, n_r: vec3<f32>, gain: f32, side: f32) -> vec4<f32> {
    let d = e - p;
    let r2 = dot(d, d);
    if !(r2 > 0.0) || !(area > 0.0) {
        return vec4<f32>(0.0);
    }
    let v = d / sqrt(r2);
    let cos_e = max(side * dot(n_e, v), 0.0);
    let cos_r = min(gain * max(dot(n_r, v), 0.0), 1.0);
    let s = area * cos_e * cos_r / (PI * r2 + area);
    return vec4<f32>(s, v);
}

fn shadow_term(e: vec3<f32>, n_e: vec3<f32>, area: f32, p: vec3<f32>, n_r: vec3<f32>, gain: f32) -> vec4<f32> {
    return disc_term(e, n_e, area, p, n_r, gain, 1.0);
}

// Accessibility and bent normal from the summed weighted shadow and direction.
fn finish(receiver: u32, occlusion: vec4<f32>) {
    let n = discs[receiver].normal.xyz;
    let a = clamp(1.0 - occlusion.x, 0.0, 1.0);
    state[params.next + receiver] = a;
    let b = n - occlusion.yzw;
    let len2 = dot(b, b);
    var unit = n;
    if len2 > 0.0 {
        unit = b / sqrt(len2);
    }
    bent[receiver] = vec4<f32>(a, unit);
}

fn add(occlusion: vec4<f32>, emitter: Disc, weight: f32, me: Disc) -> vec4<f32> {
    let t = shadow_term(emitter.centre_area.xyz, emitter.normal.xyz, emitter.centre_area.w, me.centre_area.xyz, me.normal.xyz, params.gain);
    return occlusion + weight * t.x * vec4<f32>(1.0, t.yzw);
}

@compute @workgroup_size(64)
fn cs_brute_force(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.count {
        return;
    }
    let me = discs[i];
    var occlusion = vec4<f32>(0.0);
    for (var j = 0u; j < params.count; j++) {
        if j != i {
            occlusion = add(occlusion, discs[j], state[params.previous + j], me);
        }
    }
    finish(i, occlusion);
}

@compute @workgroup_size(64)
fn cs_node_weights(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= params.nodes {
        return;
    }
    let node = links[k].node;
    var weighted = 0.0;
    var area = 0.0;
    var plain = 0.0;
    for (var p = node.z; p < node.w; p++) {
        let s = links[p].leaf.x;
        let a = discs[s].centre_area.w;
        let w = state[params.previous + s];
        weighted += a * w;
        area += a;
        plain += w;
    }
    if area > 0.0 {
        state[params.weights + k] = weighted / area;
    } else {
        state[params.weights + k] = plain / f32(max(node.w - node.z, 1u));
    }
}

// Invocation k takes the surfel at leaf position k, so neighbouring invocations (one SIMD
// group) walk neighbouring receivers down nearly the same cut of the tree.
@compute @workgroup_size(64)
fn cs_tree(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.count {
        return;
    }
    let i = links[id.x].leaf.x;
    let me = discs[i];
    let mine = id.x;
    var occlusion = vec4<f32>(0.0);
    var stack: array<u32, SURFEL_STACK>;
    var top = 0u;
    if params.nodes > 0u {
        stack[0] = 0u;
        top = 1u;
    }
    while top > 0u {
        top -= 1u;
        let k = stack[top];
        let node = links[k].node;
        let disc = discs[params.count + k];
        if node.y == NO_CHILD {
            if links[node.z].leaf.x != i {
                occlusion = add(occlusion, disc, state[params.weights + k], me);
            }
            continue;
        }
        let d = disc.centre_area.xyz - me.centre_area.xyz;
        let far = dot(d, d) >= params.closeness * disc.centre_area.w;
        let holds = mine >= node.z && mine < node.w;
        if far && !holds {
            occlusion = add(occlusion, disc, state[params.weights + k], me);
        } else if top + 2u <= SURFEL_STACK {
            // Left then right, so the right child is taken first, as on the CPU.
            stack[top] = node.x;
            stack[top + 1u] = node.y;
            top += 2u;
        }
    }
    finish(i, occlusion);
}

// The shadow term alone: configuration i is the emitter surfels[2i] and the receiver
// surfels[2i + 1] (its centre the point, its normal the receiver's); the result (S, v)
// goes to bent[i].
@compute @workgroup_size(64)
fn cs_shadow_terms(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 2u * i + 1u >= params.count {
        return;
    }
    let e = discs[2u * i];
    let r = discs[2u * i + 1u];
    bent[i] = shadow_term(e.centre_area.xyz, e.normal.xyz, e.centre_area.w, r.centre_area.xyz, r.normal.xyz, params.gain);
}

// One bounce of indirect light: receiver i gathers every other surfel's radiosity through
// the form factor to its front, weighted by the emitter's weight (its accessibility, or 1).
@compute @workgroup_size(64)
fn cs_indirect(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.count {
        return;
    }
    let me = discs[i];
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < params.count; j++) {
        if j != i {
            let e = discs[j];
            let f = disc_term(e.centre_area.xyz, e.normal.xyz, e.centre_area.w, me.centre_area.xyz, me.normal.xyz, params.gain, -1.0).x;
            sum += radiosity[j].xyz * (f * state[params.previous + j]);
        }
    }
    gathered[i] = vec4<f32>(sum, 0.0);
}
