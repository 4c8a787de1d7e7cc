// nklut browser bench: the host side of the native runner's F-only measurements
// (crates/gpu/src/runner.rs) and of its specular effects' timing (crates/gpu/src/effects.rs:
// the distance-map update and the shading pass per configuration) in WebGPU. The plan (crates/gpu/src/web.rs) brings every shader
// module composed by the runner's own code, the material uniforms, LUT texels, meshes and
// camera views as bytes (and, for reflection/refraction scenes, every uniform, map layout and
// mesh byte of the effects, crates/gpu/src/web/effects.rs); this script creates the device, buffers and pipelines, runs the
// passes, times them (timestamp queries when granted, else wall time over batches closed by
// onSubmittedWorkDone), reads the targets back and computes the image error of SPEC §6 with
// the rule of crates/gpu/src/image_error.rs (`compare`, `ErrorSummary`) and the median and
// interquartile range of crates/pipeline/src/stats.rs — twins held to the Rust functions by
// tests/web_bench.rs through `window.nklut.twins`.

const planElement = document.getElementById('nklut-plan');
const plan = JSON.parse(planElement.textContent);
const $ = (id) => document.getElementById(id);
const WALL_BATCH = 8;
// The `driver` column: the browser and its version (the whole `userAgent` is in the result).
const BROWSER = (navigator.userAgent.match(/(Edg|Firefox|Chrome|HeadlessChrome|Version)\/[\d.]+( Mobile)?/g) || [navigator.userAgent]).pop();

const result = {
  format: plan.format,
  scene: plan.scene,
  nklut_version: plan.version,
  // FNV-1a 64 of the plan's JSON as embedded (web::plan_hash): two results with the same hash
  // ran the same shaders on the same bytes.
  plan_hash: planElement.dataset.hash || '',
  date: new Date().toISOString(),
  secure_context: window.isSecureContext,
  // 'all' with `?frames=all`, else the first frame of the orbit only (the image error is
  // device-independent to 1e-5; one frame checks it without reading back every frame).
  image_error_frames: null,
  wake_lock: null,
  hidden: [],
  phases: [],
  user_agent: navigator.userAgent,
  adapter: null,
  complete: false,
  incomplete: null,
  compile: [],
  columns: plan.columns,
  gpu_timing: [],
  image_errors: [],
  effects_timing: [],
  ao_timing: [],
  skipped: plan.skipped,
};

// ---- twins of the Rust statistics -------------------------------------------------------

// stats::quantile: linear interpolation between the sorted samples around q·(n − 1).
function quantile(sorted, q) {
  if (sorted.length === 0) return NaN;
  const position = q * (sorted.length - 1);
  const low = Math.floor(position), high = Math.ceil(position);
  return sorted[low] + (sorted[high] - sorted[low]) * (position - low);
}

// stats::median_and_iqr.
function medianAndIqr(samples) {
  const sorted = [...samples].sort((a, b) => a - b);
  return [quantile(sorted, 0.5), quantile(sorted, 0.75) - quantile(sorted, 0.25)];
}

// image_error::compare: covered pixels (reference alpha ≥ ½), |a − r|/r per channel where
// r > 0, the others counted as skipped.
function compare(method, reference) {
  const e = { sum_relative: 0, samples: 0, max_relative: 0, pixels: 0, skipped_zero_reference: 0 };
  for (let i = 0; i < reference.length; i += 4) {
    if (reference[i + 3] < 0.5) continue;
    e.pixels += 1;
    for (let c = 0; c < 3; c++) {
      const r = reference[i + c];
      if (!(r > 0)) { e.skipped_zero_reference += 1; continue; }
      const relative = Math.abs(method[i + c] - r) / r;
      e.sum_relative += relative;
      e.samples += 1;
      e.max_relative = Math.max(e.max_relative, relative);
    }
  }
  return e;
}

// image_error::ErrorSummary: the mean over frames of each frame's mean.
class ErrorSummary {
  constructor() { this.frames = 0; this.sum_of_frame_means = 0; this.frames_with_samples = 0; this.max_relative = 0; this.pixels = 0; this.skipped_zero_reference = 0; }
  add(frame) {
    this.frames += 1;
    if (frame.samples > 0) { this.sum_of_frame_means += frame.sum_relative / frame.samples; this.frames_with_samples += 1; }
    this.max_relative = Math.max(this.max_relative, frame.max_relative);
    this.pixels += frame.pixels;
    this.skipped_zero_reference += frame.skipped_zero_reference;
  }
  meanRelative() { return this.frames_with_samples > 0 ? this.sum_of_frame_means / this.frames_with_samples : null; }
}

window.nklut = { plan, result, done: false, error: null, twins: { quantile, medianAndIqr, compare, ErrorSummary, permutation: (seed, n) => new SplitMix64(seed).permutation(n), resolutionNs }, ramp: null, effectFrame: null };

// ---- page ---------------------------------------------------------------------------------

// A problem the page explains to its reader (no WebGPU, a limit too small, a lost device).
class Problem extends Error {}

const started = performance.now();
const clock = (ms) => { const s = Math.round(ms / 1000); return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`; };
let phase = { name: 'starting', since: started };
// A new phase of the run (its start recorded in the result).
function enter(name) {
  phase = { name, since: performance.now() };
  result.phases.push({ phase: name, at_s: Math.round((phase.since - started) / 100) / 10 });
}
// The status line: the phase, the text, the time elapsed and, with `fraction` of the run
// done, an estimate of what is left.
function status(text, fraction) {
  const now = performance.now();
  let line = `${phase.name}: ${text} — ${clock(now - started)} elapsed`;
  if (fraction > 0.02 && fraction < 1) line += `, about ${clock(((now - started) * (1 - fraction)) / fraction)} left`;
  $('status').textContent = line;
}
function progress(done, total) { $('progress').max = Math.max(total, 1); $('progress').value = done; }
function problem(text) { const p = $('problem'); p.hidden = false; p.textContent = text; }
// The page itself says a run did not finish: a banner and the title.
function markIncomplete(text) {
  const banner = $('incomplete');
  banner.hidden = false;
  banner.textContent = `Incomplete: ${text} The rows below are those measured before it stopped; the download is marked incomplete.`;
  document.title = `[incomplete] ${document.title}`;
}

// A wake lock keeps a phone's screen (and its GPU) on while the run lasts, where granted;
// a tab sent to the background is noted with the phase it interrupted.
async function keepAwake() {
  if (!('wakeLock' in navigator)) { result.wake_lock = 'unsupported'; return; }
  try {
    await navigator.wakeLock.request('screen');
    result.wake_lock = 'granted';
  } catch (error) {
    result.wake_lock = `refused: ${error && error.message ? error.message : error}`;
  }
}
document.addEventListener('visibilitychange', () => {
  if (window.nklut.done) return;
  // A wake lock is released while the tab is hidden: ask again on return.
  if (document.visibilityState === 'visible') { if (result.wake_lock === 'granted') keepAwake(); return; }
  result.hidden.push({ phase: phase.name, at_s: Math.round((performance.now() - started) / 100) / 10 });
  const note = $('hidden-note');
  note.hidden = false;
  note.textContent = `The tab was hidden during ${result.hidden.map((h) => h.phase).join(', ')}: a browser slows a background tab, so samples taken then may be long. Keep the page in front until it is done.`;
});

function bytes(base64) {
  const text = atob(base64);
  const out = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) out[i] = text.charCodeAt(i);
  return out;
}

const resolutionText = ([w, h]) => `${w}x${h}`;
// Rows of a readback copy are padded to 256 bytes (render::padded_row_bytes).
const paddedRow = (width, bytesPerPixel) => Math.ceil((width * bytesPerPixel) / 256) * 256;

// What the plan needs of the device, each with what asks it and how to need less.
function requirements() {
  const needs = [];
  const texture = (size, what) => needs.push({ limit: 'maxTextureDimension2D', size: Math.max(...size), what, remedy: 'lower the resolution' });
  if (plan.timing) texture(plan.timing.resolution, `the ${resolutionText(plan.timing.resolution)} timing target`);
  if (plan.image_error) {
    const [w, h] = plan.image_error.resolution;
    texture(plan.image_error.resolution, `the ${resolutionText(plan.image_error.resolution)} image-error targets`);
    for (const object of plan.image_error.objects) {
      const size = paddedRow(w, 16) * h * (object.methods.length + 1);
      needs.push({ limit: 'maxBufferSize', size, what: `the readback of ${object.methods.length + 1} RGBA32Float ${w}x${h} images of one object`, remedy: 'lower the resolution or name fewer methods per object' });
    }
    for (const mesh of plan.meshes) {
      needs.push({ limit: 'maxBufferSize', size: (mesh.vertices.length * 3) / 4, what: `the vertices of mesh ${mesh.label}`, remedy: 'use a smaller mesh' });
    }
  }
  if (plan.effects) {
    const e = plan.effects;
    texture(e.resolution, `the ${resolutionText(e.resolution)} effects target`);
    texture([e.maps.size], `distance maps of ${e.maps.size}² texels per face`);
    needs.push({ limit: 'maxTextureArrayLayers', size: e.maps.face_layers, what: 'the six faces of a distance-map layer and a spare', remedy: 'use another device' });
    for (const limit of ['maxStorageBufferBindingSize', 'maxBufferSize']) {
      needs.push({ limit, size: e.maps.buffer_bytes, what: `${e.maps.cube_maps} distance maps of 6×${e.maps.size}²×${e.maps.layers} texels`, remedy: 'lower effects.distance_maps.size or layers' });
    }
    needs.push({ limit: 'maxBufferSize', size: (e.meshes.vertices.length * 3) / 4, what: 'the scene\'s vertices', remedy: 'use coarser meshes' });
  }
  return needs;
}

async function openDevice() {
  // An insecure context first: there navigator.gpu is absent whatever the browser.
  if (window.isSecureContext === false) {
    throw new Problem('This page is not in a secure context, and WebGPU exists only in one: open it from https:// or file://, '
      + `not http on a LAN address (this address: ${location.protocol}//${location.host}). Copy the file to the device and open it `
      + 'there, or serve it over https.');
  }
  if (!('gpu' in navigator) || !navigator.gpu) {
    throw new Problem('This browser has no WebGPU: navigator.gpu is missing. Open the page in a browser with WebGPU '
      + '(Chrome or Edge 113+ on Windows, macOS, ChromeOS and Android 12+; Safari 26+; Firefox 141+ on Windows), '
      + 'from file:// or https:// (WebGPU needs a secure context). On Linux, Chromium needs --enable-unsafe-webgpu.');
  }
  const adapter = await navigator.gpu.requestAdapter({ powerPreference: 'high-performance' });
  if (!adapter) {
    throw new Problem('navigator.gpu is here but requestAdapter() returned no adapter: WebGPU is disabled for this GPU or '
      + 'this browser (blocklisted driver, or a flag such as --enable-unsafe-webgpu is needed; see chrome://gpu).');
  }
  const requiredLimits = {};
  for (const need of requirements()) {
    const allowed = adapter.limits[need.limit];
    if (need.size > allowed) {
      throw new Problem(`This device's ${need.limit} is ${allowed}, but the scene asks ${need.size} for ${need.what}; ${need.remedy}.`);
    }
    requiredLimits[need.limit] = Math.max(requiredLimits[need.limit] || 0, need.size);
  }
  // `?timer=wall` in the address forces wall time where timestamps exist (to measure what
  // the wall timer adds on one adapter).
  const timestamps = adapter.features.has('timestamp-query') && new URLSearchParams(location.search).get('timer') !== 'wall';
  const device = await adapter.requestDevice({ requiredFeatures: timestamps ? ['timestamp-query'] : [], requiredLimits });
  const info = adapter.info || {};
  const name = [info.vendor, info.architecture, info.device, info.description].filter(Boolean).join(' ') || 'unknown adapter';
  const fallback = Boolean(info.isFallbackAdapter ?? adapter.isFallbackAdapter);
  const software = /swiftshader|llvmpipe|lavapipe|warp|software/i.test(name);
  result.adapter = {
    name, vendor: info.vendor || '', architecture: info.architecture || '', device: info.device || '', description: info.description || '',
    is_fallback_adapter: fallback,
    // WebGPU names no device type: a fallback or a known software rasteriser is `cpu`.
    adapter_type: info.type || (fallback || software ? 'cpu' : 'gpu'),
    backend: 'WebGPU', timestamp_query: timestamps, limits_used: requiredLimits,
    limits: Object.fromEntries(['maxTextureDimension2D', 'maxTextureArrayLayers', 'maxBufferSize', 'maxStorageBufferBindingSize'].map((l) => [l, adapter.limits[l]])),
  };
  return { device, timestamps };
}

// ---- device work --------------------------------------------------------------------------

let lost = null;
let lostPromise = null;

function checkLost() {
  if (lost) throw new Problem(`The device was lost (${lost}); the rows measured before are kept and marked incomplete.`);
}

async function scoped(device, what, body) {
  device.pushErrorScope('out-of-memory');
  device.pushErrorScope('validation');
  const value = body();
  const validation = await device.popErrorScope();
  const memory = await device.popErrorScope();
  const error = validation || memory;
  if (error) throw new Problem(`${what}: ${error.message}`);
  return value;
}

async function compileChecks(device, progressOf) {
  // The F-only pass's modules by shading, for its pipelines; every module by name, for the
  // effects' pipelines.
  const modules = {};
  const named = {};
  for (const m of plan.checks) {
    checkLost();
    const module = device.createShaderModule({ label: m.name, code: m.wgsl });
    if (progressOf) progressOf(result.compile.length + 1);
    const info = await module.getCompilationInfo();
    const of = (type) => info.messages.filter((x) => x.type === type).map((x) => `${x.lineNum}:${x.linePos} ${x.message}`);
    result.compile.push({ module: m.name, errors: of('error'), warnings: of('warning') });
    if (m.shade) modules[m.shade] = module;
    named[m.name] = module;
  }
  const failed = result.compile.filter((c) => c.errors.length > 0);
  if (failed.length > 0) throw new Problem(`WGSL did not compile on this browser: ${failed.map((c) => `${c.module}: ${c.errors[0]}`).join('; ')}`);
  return { modules, named };
}

function setup(device, modules) {
  const visibility = GPUShaderStage.VERTEX | GPUShaderStage.FRAGMENT;
  const layout = device.createBindGroupLayout({
    entries: [
      { binding: 0, visibility, buffer: { type: 'uniform' } },
      { binding: 1, visibility, buffer: { type: 'uniform' } },
      { binding: 2, visibility, texture: { sampleType: 'float' } },
      { binding: 3, visibility, sampler: { type: 'filtering' } },
    ],
  });
  const pipelineLayout = device.createPipelineLayout({ bindGroupLayouts: [layout] });
  const sampler = device.createSampler({ magFilter: 'linear', minFilter: 'linear', addressModeU: 'clamp-to-edge', addressModeV: 'clamp-to-edge' });
  const texture = (base64, width) => {
    const t = device.createTexture({ size: [width, 1], format: plan.formats.lut, usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
    device.queue.writeTexture({ texture: t }, bytes(base64), { bytesPerRow: 8 * width }, [width, 1]);
    return t;
  };
  const blank = texture(plan.blank_lut, 1);
  const uniform = (data, label) => {
    const b = device.createBuffer({ label, size: data.byteLength, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(b, 0, data);
    return b;
  };
  const viewBytes = bytes(plan.timing ? plan.timing.view : plan.image_error.frames[0]);
  const materials = plan.materials.map((m) => {
    const view = uniform(viewBytes, `view ${m.page}`);
    const lut = m.lut ? texture(m.lut, m.lut_width) : blank;
    const group = device.createBindGroup({
      layout,
      entries: [
        { binding: 0, resource: { buffer: uniform(bytes(m.uniform), m.page) } },
        { binding: 1, resource: { buffer: view } },
        { binding: 2, resource: lut.createView() },
        { binding: 3, resource: sampler },
      ],
    });
    return { ...m, view, group };
  });
  const pipelines = new Map();
  // render::Renderer::create_pipeline: fullscreen (optionally blended additively over the
  // burner) or mesh (float target, depth test, no culling).
  const pipeline = (shade, draw, format) => {
    const key = `${shade} ${draw} ${format}`;
    if (!pipelines.has(key)) {
      const module = modules[shade];
      const additive = { srcFactor: 'one', dstFactor: 'one', operation: 'add' };
      const mesh = draw === 'mesh';
      pipelines.set(key, device.createRenderPipeline({
        label: key,
        layout: pipelineLayout,
        vertex: {
          module, entryPoint: mesh ? 'vs_mesh' : 'vs_fullscreen',
          buffers: mesh ? [{ arrayStride: 24, attributes: [{ shaderLocation: 0, offset: 0, format: 'float32x3' }, { shaderLocation: 1, offset: 12, format: 'float32x3' }] }] : [],
        },
        fragment: {
          module, entryPoint: mesh ? 'fs_mesh' : 'fs_ramp',
          targets: [{ format: mesh ? plan.formats.float : format, blend: draw === 'over' ? { color: additive, alpha: additive } : undefined }],
        },
        primitive: { topology: 'triangle-list', cullMode: 'none' },
        depthStencil: mesh ? { format: plan.formats.depth, depthWriteEnabled: true, depthCompare: 'less' } : undefined,
      }));
    }
    return pipelines.get(key);
  };
  return { materials, pipeline };
}

function target(device, [width, height], format, depth) {
  const colour = device.createTexture({ size: [width, height], format, usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC });
  const depthTexture = depth ? device.createTexture({ size: [width, height], format: plan.formats.depth, usage: GPUTextureUsage.RENDER_ATTACHMENT }) : null;
  return { width, height, colour, view: colour.createView(), depth: depthTexture && depthTexture.createView() };
}

// render::Target::begin: clear colour to 0 and depth to 1.
function begin(encoder, t, timestampWrites) {
  return encoder.beginRenderPass({
    colorAttachments: [{ view: t.view, clearValue: [0, 0, 0, 0], loadOp: 'clear', storeOp: 'store' }],
    depthStencilAttachment: t.depth ? { view: t.depth, depthClearValue: 1, depthLoadOp: 'clear', depthStoreOp: 'discard' } : undefined,
    timestampWrites,
  });
}

function copyOut(encoder, t, buffer, offset) {
  encoder.copyTextureToBuffer({ texture: t.colour }, { buffer, offset, bytesPerRow: paddedRow(t.width, 16), rowsPerImage: t.height }, [t.width, t.height]);
}

// RGBA f32 pixels without the row padding (render::Target::decode).
function decode(mapped, offset, t) {
  const row = paddedRow(t.width, 16) / 4;
  const all = new Float32Array(mapped, offset, row * t.height);
  const out = new Float32Array(t.width * t.height * 4);
  for (let y = 0; y < t.height; y++) out.set(all.subarray(y * row, y * row + t.width * 4), y * t.width * 4);
  return out;
}

async function readBuffer(buffer) {
  await buffer.mapAsync(GPUMapMode.READ);
  const copy = buffer.getMappedRange().slice(0);
  buffer.unmap();
  return copy;
}

// ---- sampling: twins of crates/gpu/src/sampling.rs (its constants come in plan.timing.sampling)

// sampling::SplitMix64 over BigInt (the seed is a decimal string: it may pass 2^53).
class SplitMix64 {
  constructor(seed) { this.state = BigInt.asUintN(64, BigInt(seed)); }
  next() {
    this.state = BigInt.asUintN(64, this.state + 0x9e3779b97f4a7c15n);
    let z = this.state;
    z = BigInt.asUintN(64, (z ^ (z >> 30n)) * 0xbf58476d1ce4e5b9n);
    z = BigInt.asUintN(64, (z ^ (z >> 27n)) * 0x94d049bb133111ebn);
    return z ^ (z >> 31n);
  }
  below(n) { return Number((this.next() * BigInt(n)) >> 64n); }
  permutation(n) {
    const order = Array.from({ length: n }, (_, i) => i);
    for (let i = n - 1; i > 0; i--) { const j = this.below(i + 1); [order[i], order[j]] = [order[j], order[i]]; }
    return order;
  }
}

// sampling::resolution_ns: the greatest common divisor of the readings' differences from the
// first (BigInt ns), at least the nominal tick; null while every reading is equal.
function resolutionNs(readings, tickNs) {
  if (readings.length === 0) return null;
  const gcd = (a, b) => { while (b !== 0n) [a, b] = [b, a % b]; return a; };
  const first = readings[0];
  let divisor = 0n;
  for (const r of readings) divisor = gcd(divisor, r > first ? r - first : first - r);
  return divisor > 0n ? Math.max(Number(divisor), tickNs) : null;
}

function targetMs(resolution, floorMs) {
  const s = plan.timing.sampling;
  return Math.max((s.span_over_resolution * resolution) / 1e6, s.span_over_floor * floorMs, HOOK.minSampleMs ?? s.min_sample_ms);
}

// sampling::settled: fewer than two warm-up rounds, or the last round's total not below
// `settled` × the median total of the (at most `settle_window`) rounds before it.
function settled(totals) {
  if (totals.length < 2) return true;
  const s = plan.timing.sampling;
  const before = totals.slice(Math.max(0, totals.length - 1 - s.settle_window), totals.length - 1);
  return totals[totals.length - 1] >= s.settled * medianAndIqr(before)[0];
}

function nextEvaluations(evaluations, cheapestMs, target) {
  const factor = cheapestMs > 0 ? Math.min(Math.max(Math.ceil((1.2 * target) / cheapestMs), 2), 64) : 64;
  return Math.min(Math.floor(evaluations * factor), plan.timing.sampling.max_evaluations);
}

// The page's test hooks: `?quantum_us=Q` floors every timer reading to Q µs, `?floor_ms=F`
// makes no wall-timed pass read less than F ms (a browser's coarse timer and its
// submit round trip, on an adapter whose own are fine); `?amplify=0` keeps one evaluation
// per pixel (the single-draw design); `?lose_after=K` destroys the device right after the
// submit of the timed round after K (a lost device with a map pending); `?frames=all`
// reads back every frame of the image error's orbit; `?min_sample_ms=M` raises the
// shortest sample (a comparison at the span another timer needs).
const HOOK = (() => {
  const q = new URLSearchParams(location.search);
  const quantumNs = BigInt(Math.max(1, Math.round(Number(q.get('quantum_us') || 0) * 1000)));
  const loseAfter = q.get('lose_after');
  return {
    quantumNs, floorMs: Number(q.get('floor_ms') || 0), amplify: q.get('amplify') !== '0', allFrames: q.get('frames') === 'all',
    loseAfter: loseAfter === null ? null : Number(loseAfter),
    minSampleMs: q.get('min_sample_ms') === null ? null : Number(q.get('min_sample_ms')),
  };
})();
const quantise = (ns) => ns - (ns % HOOK.quantumNs);
const nowNs = () => quantise(BigInt(Math.round(performance.now() * 1e6)));

// sampling::measure, one submit per round: a throwaway pass clears the target, then every
// pair's pass in the round's seeded order (timestamps around each); without timestamps one
// submit per pair (a throwaway and the pass), the wall clock around it, closed by
// onSubmittedWorkDone. With `subtract`, the burner alone and the burner with the pair on
// top, the sample their difference.
async function runTiming(device, timestamps, gpu, step) {
  const t = plan.timing;
  const rules = t.sampling;
  const display = target(device, t.resolution, plan.formats.display, false);
  const draws = t.pairs.map((pair) => ({
    pair,
    material: gpu.materials[pair.material],
    group: gpu.materials[pair.material].group,
    pipeline: gpu.pipeline(pair.shade, t.subtract ? 'over' : 'full', plan.formats.display),
  }));
  const baseline = draws.map((d) => d.pair.baseline);
  const burner = t.subtract ? gpu.pipeline('burner', 'full', plan.formats.display) : null;
  const passes = (d) => (t.subtract ? [[[burner, d.group]], [[burner, d.group], [d.pipeline, d.group]]] : [[[d.pipeline, d.group]]]);
  const perPair = t.subtract ? 2 : 1;
  const encode = (encoder, list, writes) => {
    const pass = begin(encoder, display, writes);
    for (const [pipeline, group] of list) { pass.setPipeline(pipeline); pass.setBindGroup(0, group); pass.draw(3); }
    pass.end();
  };
  const throwaway = (encoder) => begin(encoder, display, undefined).end();
  const view = bytes(t.view);
  let written = null;
  const writeEvaluations = (n) => {
    if (written === n) return;
    const v = new Float32Array(view.buffer.slice(0));
    v[22] = n; // View.viewport.z (mat4 16 + eye 4 + viewport.x, .y)
    for (const m of gpu.materials) device.queue.writeBuffer(m.view, 0, v);
    written = n;
  };
  const count = draws.length * perPair * 2;
  let query = null;
  if (timestamps) {
    const set = device.createQuerySet({ type: 'timestamp', count });
    const resolve = device.createBuffer({ size: count * 8, usage: GPUBufferUsage.QUERY_RESOLVE | GPUBufferUsage.COPY_SRC });
    const read = device.createBuffer({ size: count * 8, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    query = { set, resolve, read };
  }
  const readings = [];
  let loseNow = false;
  // One round in `order` at `n` evaluations: the raw sample (ms) of every pair.
  const round = async (order, n) => {
    checkLost();
    writeEvaluations(n);
    const times = new Array(draws.length);
    if (query) {
      const encoder = device.createCommandEncoder();
      throwaway(encoder);
      order.forEach((i) => passes(draws[i]).forEach((list, j) => {
        const index = 2 * (i * perPair + j);
        encode(encoder, list, { querySet: query.set, beginningOfPassWriteIndex: index, endOfPassWriteIndex: index + 1 });
      }));
      encoder.resolveQuerySet(query.set, 0, count, query.resolve, 0);
      encoder.copyBufferToBuffer(query.resolve, 0, query.read, 0, count * 8);
      device.queue.submit([encoder.finish()]);
      if (loseNow) device.destroy();
      const ticks = new BigUint64Array(await readBuffer(query.read));
      const raw = Array.from(ticks, quantise);
      readings.push(...raw);
      const ms = (k) => Number(raw[2 * k + 1] - raw[2 * k]) / 1e6;
      for (const i of order) times[i] = t.subtract ? ms(i * perPair + 1) - ms(i * perPair) : ms(i * perPair);
    } else {
      for (const i of order) {
        const wall = [];
        for (const list of passes(draws[i])) {
          const encoder = device.createCommandEncoder();
          throwaway(encoder);
          encode(encoder, list, undefined);
          const start = nowNs();
          device.queue.submit([encoder.finish()]);
          if (loseNow) device.destroy();
          await device.queue.onSubmittedWorkDone();
          checkLost();
          const end = nowNs();
          readings.push(start, end);
          wall.push(Math.max(Number(end - start) / 1e6, HOOK.floorMs));
        }
        times[i] = t.subtract ? wall[1] - wall[0] : wall[0];
      }
    }
    return times;
  };
  const cheapestOf = (times) => {
    const fresnel = times.filter((_, i) => !baseline[i] || baseline.every(Boolean));
    return Math.min(...fresnel);
  };
  // sampling::PassClock::floor_ms: the median round trip of five empty submits (wall only).
  let floorMs = 0;
  if (!query) {
    const trips = [];
    for (let k = 0; k < 5; k++) {
      const start = nowNs();
      device.queue.submit([device.createCommandEncoder().finish()]);
      await device.queue.onSubmittedWorkDone();
      trips.push(Math.max(Number(nowNs() - start) / 1e6, HOOK.floorMs));
    }
    floorMs = medianAndIqr(trips)[0];
  }
  const tickNs = 1;
  const rng = new SplitMix64(t.seed);
  // As the native runner: the study's subtraction is timed with one evaluation per pixel.
  const amplify = t.amplify && !t.subtract && HOOK.amplify;
  let evaluations = 1;
  let target_ = targetMs(tickNs, floorMs);
  let capped = false;
  const calibration = [];
  status('timing: choosing the amplification (F evaluations per pixel)…');
  if (amplify && draws.length > 0) {
    // A cold round first: a pipeline's first use is no measure.
    await round(rng.permutation(draws.length), evaluations);
    for (let attempt = 0; ; attempt++) {
      const cheapest = cheapestOf(await round(rng.permutation(draws.length), evaluations));
      calibration.push([evaluations, cheapest]);
      const resolution = resolutionNs(readings, tickNs);
      target_ = targetMs(resolution === null ? Infinity : resolution, floorMs);
      if (cheapest >= target_ && cheapest > 0) break;
      if (evaluations >= rules.max_evaluations || attempt + 1 >= rules.max_calibration_rounds) { capped = true; break; }
      evaluations = nextEvaluations(evaluations, cheapest, Number.isFinite(target_) ? target_ : rules.min_sample_ms);
      step(0, `timing: calibration ${attempt + 1}, ${evaluations} evaluations per pixel next`);
    }
  }
  // sampling::measure's warm-up: the scene's rounds, then more until `settled`.
  const totals = [];
  while (totals.length < t.warmup || (!settled(totals) && totals.length < t.warmup + rules.max_extra_warmup)) {
    const times = await round(rng.permutation(draws.length), evaluations);
    totals.push(times.reduce((x, y) => x + y, 0));
    step(totals.length <= t.warmup ? draws.length : 0, `timing: warm-up round ${totals.length} at ${evaluations} evaluations per pixel`);
  }
  const samples = draws.map(() => []);
  const measurement = () => {
    const resolution = resolutionNs(readings, tickNs);
    return { evaluations, resolution_ns: resolution === null ? tickNs : resolution, floor_ms: floorMs, target_ms: target_, capped, calibration, warmup_rounds: totals.length, seed: t.seed, amplified: amplify };
  };
  for (let r = 0; r < t.repeats; r++) {
    loseNow = HOOK.loseAfter !== null && r === HOOK.loseAfter;
    const times = await round(rng.permutation(draws.length), evaluations);
    times.forEach((x, i) => samples[i].push(x));
    step(draws.length, `timing: round ${r + 1} of ${t.repeats} at ${evaluations} evaluations per pixel`);
    // Rows so far, so a lost device keeps them.
    result.timing_sampling = measurement();
    result.gpu_timing = timingRows(draws, samples, timestamps, result.timing_sampling);
  }
  writeEvaluations(1);
}

// sampling::stats and runner::relate: per pair the mean, median, IQR and true count, ns per F
// evaluation per pixel, the near-resolution flag and the ratios to exact and to the bare
// fetch on the same material and to exact on the first dielectric material.
function timingRows(draws, samples, timestamps, m) {
  const t = plan.timing;
  const a = result.adapter;
  const pixels = t.resolution[0] * t.resolution[1];
  const near = Math.max((t.sampling.near_resolution * m.resolution_ns) / 1e6, t.sampling.near_floor * m.floor_ms);
  const rows = draws.filter((_, i) => samples[i].length > 0).map((d) => {
    const s = samples[draws.indexOf(d)];
    const [median, spread] = medianAndIqr(s);
    const material = plan.materials[d.pair.material];
    return {
      adapter: a.name, backend: a.backend, driver: BROWSER, timer: timestamps ? 'timestamp' : 'wall',
      method: d.pair.method, formula: d.pair.formula, material: material.page, resolution: resolutionText(t.resolution),
      evaluations: m.evaluations, timer_resolution_ns: m.resolution_ns, seed: m.seed, repeats: s.length,
      mean_ms: s.reduce((x, y) => x + y, 0) / s.length, median_ms: median, spread_ms: spread,
      ns_per_evaluation: (median * 1e6) / (m.evaluations * pixels),
      relative_to_exact: null, relative_to_fetch: null, relative_to_exact_dielectric: null,
      near_resolution: median > near ? 'no' : 'yes', samples_ms: s.map((x) => x.toFixed(6)).join(' '), kind: material.kind,
    };
  });
  const medianOf = (material, method) => { const r = rows.find((x) => x.material === material && x.method === method); return r && r.median_ms > 0 ? r.median_ms : null; };
  const reference = rows.find((r) => r.method === 'exact' && r.kind === 'dielectric');
  for (const r of rows) {
    const exact = medianOf(r.material, 'exact'), fetch = medianOf(r.material, 'texture');
    if (exact) r.relative_to_exact = r.median_ms / exact;
    if (fetch) r.relative_to_fetch = r.median_ms / fetch;
    if (reference && reference.median_ms > 0) r.relative_to_exact_dielectric = r.median_ms / reference.median_ms;
    delete r.kind;
  }
  return rows;
}

// runner::run_image_error: per object, the exact render and each method's, every frame,
// read back and compared.
async function runImageError(device, gpu, step) {
  const plan_ = plan.image_error;
  const [w, h] = plan_.resolution;
  const imageBytes = paddedRow(w, 16) * h;
  const meshes = plan.meshes.map((m) => {
    const make = (data, usage) => { const b = device.createBuffer({ size: Math.ceil(data.byteLength / 4) * 4, usage: usage | GPUBufferUsage.COPY_DST }); device.queue.writeBuffer(b, 0, data); return b; };
    return { ...m, vertexBuffer: make(bytes(m.vertices), GPUBufferUsage.VERTEX), indexBuffer: make(bytes(m.indices), GPUBufferUsage.INDEX) };
  });
  const frames = (HOOK.allFrames ? plan_.frames : plan_.frames.slice(0, 1)).map(bytes);
  for (const object of plan_.objects) {
    const mesh = meshes[object.mesh];
    const material = gpu.materials[object.material];
    const shades = ['exact', ...object.methods];
    const pipelines = shades.map((s) => gpu.pipeline(s, 'mesh'));
    const targets = shades.map(() => target(device, plan_.resolution, plan.formats.float, true));
    const buffer = device.createBuffer({ size: imageBytes * shades.length, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    const summaries = object.methods.map(() => new ErrorSummary());
    for (const view of frames) {
      checkLost();
      device.queue.writeBuffer(material.view, 0, view);
      const encoder = device.createCommandEncoder();
      targets.forEach((t, i) => {
        const pass = begin(encoder, t);
        pass.setPipeline(pipelines[i]);
        pass.setBindGroup(0, material.group);
        pass.setVertexBuffer(0, mesh.vertexBuffer);
        pass.setIndexBuffer(mesh.indexBuffer, 'uint32');
        pass.drawIndexed(mesh.index_count);
        pass.end();
        copyOut(encoder, t, buffer, imageBytes * i);
      });
      device.queue.submit([encoder.finish()]);
      const mapped = await readBuffer(buffer);
      const reference = decode(mapped, 0, targets[0]);
      summaries.forEach((s, m) => s.add(compare(decode(mapped, imageBytes * (m + 1), targets[m + 1]), reference)));
      step(1, `image error: ${mesh.label} ${material.page}`);
    }
    object.methods.forEach((method, m) => {
      const s = summaries[m];
      result.image_errors.push({
        material: material.page, method, object: mesh.label, frames: s.frames, resolution: resolutionText(plan_.resolution),
        mean_rel_error: s.meanRelative(), max_rel_error: s.max_relative, pixels: s.pixels, skipped_zero_reference: s.skipped_zero_reference,
      });
    });
    buffer.destroy();
    targets.forEach((t) => t.colour.destroy());
  }
}

// The cosθ ramp of `method` for material `index` (c = (x + ½)/width), read back: what the
// tests compare with the native runner's render::ramp. `view` is the base64 `View` of a
// fullscreen pass of width × height (web::fullscreen_view).
function ramp(device, gpu) {
  return async (index, method, width, height, view) => {
    const material = gpu.materials[index];
    const t = target(device, [width, height], plan.formats.float, false);
    device.queue.writeBuffer(material.view, 0, bytes(view));
    const buffer = device.createBuffer({ size: paddedRow(width, 16) * height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    const encoder = device.createCommandEncoder();
    const pass = begin(encoder, t);
    pass.setPipeline(gpu.pipeline(method, 'full', plan.formats.float));
    pass.setBindGroup(0, material.group);
    pass.draw(3);
    pass.end();
    copyOut(encoder, t, buffer, 0);
    device.queue.submit([encoder.finish()]);
    return Array.from(decode(await readBuffer(buffer), 0, t));
  };
}

// ---- specular effects ---------------------------------------------------------------------

// The bind group layouts of a pass's declared bindings (passes/interface.rs, `binding_type`),
// one per group in group order.
function bindGroupLayouts(device, bindings, stages) {
  const visibility = stages || (GPUShaderStage.VERTEX | GPUShaderStage.FRAGMENT);
  const entry = (b) => {
    switch (b.kind) {
      case 'uniform': case 'read-only-storage': case 'storage': return { buffer: { type: b.kind } };
      case 'float-2d': return { texture: { sampleType: 'float', viewDimension: '2d' } };
      case 'unfilterable-float-2d-array': return { texture: { sampleType: 'unfilterable-float', viewDimension: '2d-array' } };
      case 'filtering': return { sampler: { type: 'filtering' } };
      default: throw new Problem(`the plan names a binding kind this page does not know: ${b.kind}`);
    }
  };
  const groups = [...new Set(bindings.map((b) => b.group))].sort((a, b) => a - b);
  return groups.map((g) => device.createBindGroupLayout({ entries: bindings.filter((b) => b.group === g).map((b) => ({ binding: b.binding, visibility, ...entry(b) })) }));
}

// A bind group of `group` from `resources` by the bindings' WGSL names.
function bindGroup(device, layouts, bindings, group, resources) {
  return device.createBindGroup({
    layout: layouts[group],
    entries: bindings.filter((b) => b.group === group).map((b) => {
      const r = resources[b.name];
      if (r === undefined) throw new Problem(`no resource for the binding ${b.name}`);
      return { binding: b.binding, resource: r instanceof GPUBuffer ? { buffer: r } : r };
    }),
  });
}

// Buffers, textures, pipelines and bind groups of the map update and the shading pass
// (passes/distance_maps.rs MapRenderer, passes/specular.rs SpecularPass), from the plan's
// bytes; `encodeMaps` and `encodeShading` record their passes.
function setupEffects(device, named) {
  const e = plan.effects;
  const usage = GPUBufferUsage;
  const upload = (base64, flags, label) => {
    const data = bytes(base64);
    const b = device.createBuffer({ label, size: Math.max(16, Math.ceil(data.byteLength / 4) * 4), usage: flags | usage.COPY_DST });
    device.queue.writeBuffer(b, 0, data);
    return b;
  };
  const vertices = upload(e.meshes.vertices, usage.VERTEX, 'scene vertices');
  const indices = upload(e.meshes.indices, usage.INDEX, 'scene indices');
  const vertexLayout = { arrayStride: e.meshes.stride, attributes: e.meshes.attributes.map((a) => ({ shaderLocation: a.location, offset: a.offset, format: a.format })) };
  // distance_maps::mesh_pipeline: scene meshes, depth tested, no culling.
  const meshPipeline = (label, layouts, module, vertex, fragment, formats) => device.createRenderPipeline({
    label,
    layout: device.createPipelineLayout({ bindGroupLayouts: layouts }),
    vertex: { module, entryPoint: vertex, buffers: [vertexLayout] },
    fragment: { module, entryPoint: fragment, targets: formats.map((format) => ({ format })) },
    primitive: { topology: 'triangle-list', cullMode: 'none' },
    depthStencil: { format: plan.formats.depth, depthWriteEnabled: true, depthCompare: 'less' },
  });
  // SceneMeshes::draw: the objects `include` takes, each as instance `object`.
  const draw = (pass, include) => {
    pass.setVertexBuffer(0, vertices);
    pass.setIndexBuffer(indices, 'uint32');
    for (const d of e.meshes.draws) if (include(d.object)) pass.drawIndexed(d.index_count, 1, d.first_index, d.base_vertex, d.object);
  };
  const moduleOf = (name) => { if (!named[name]) throw new Problem(`the plan names a module it does not hold: ${name}`); return named[name]; };

  // The map update.
  const m = e.maps;
  const mapBuffer = (label) => device.createBuffer({ label, size: m.buffer_bytes, usage: usage.STORAGE | usage.COPY_DST | usage.COPY_SRC });
  const maps = { geometry: mapBuffer('map geometry'), surfaces: mapBuffer('map surfaces') };
  const texture = (label, layers, format, flags) => device.createTexture({ label, size: [m.size, m.size, layers], format, usage: flags });
  const attachment = GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC;
  const layer = { geometry: texture('map layer geometry', m.face_layers, m.format, attachment), surfaces: texture('map layer surfaces', m.face_layers, m.format, attachment) };
  const previous = texture('previous map layer', m.face_layers, m.format, GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST);
  const depth = texture('map depth', 1, plan.formats.depth, GPUTextureUsage.RENDER_ATTACHMENT).createView();
  const face = (t, f) => t.createView({ dimension: '2d', baseArrayLayer: f, arrayLayerCount: 1 });
  const faces = { geometry: [0, 1, 2, 3, 4, 5].map((f) => face(layer.geometry, f)), surfaces: [0, 1, 2, 3, 4, 5].map((f) => face(layer.surfaces, f)) };
  const mapLayouts = bindGroupLayouts(device, m.pass.bindings);
  const mapPipeline = meshPipeline('distance-map faces', mapLayouts, moduleOf(m.pass.module), m.pass.vertex, m.pass.fragment, [m.format, m.format]);
  const lights = upload(m.lights, usage.UNIFORM, 'lights');
  const mapObjects = upload(m.objects, usage.STORAGE, 'map objects');
  const previousView = previous.createView({ dimension: '2d-array' });
  const faceGroups = m.steps.flatMap((step) => step.faces.map((f) => bindGroup(device, mapLayouts, m.pass.bindings, 0, {
    map_face: upload(f, usage.UNIFORM, 'map face'), lights, map_objects: mapObjects, previous: previousView,
  })));
  // MapRenderer::encode: 6 passes per layer step, the layer copied into the map buffers (and,
  // below the diffuse layer, into `previous`); `writes(first, last)` gives a pass's timestamps.
  const encodeMaps = (encoder, writes) => {
    const total = faceGroups.length;
    const whole = [m.size, m.size, 6];
    m.steps.forEach((step, s) => {
      for (let f = 0; f < 6; f++) {
        const n = s * 6 + f;
        const pass = encoder.beginRenderPass({
          label: 'distance-map face',
          colorAttachments: [
            { view: faces.geometry[f], clearValue: m.geometry_clear, loadOp: 'clear', storeOp: 'store' },
            { view: faces.surfaces[f], clearValue: m.surface_clear, loadOp: 'clear', storeOp: 'store' },
          ],
          depthStencilAttachment: { view: depth, depthClearValue: 1, depthLoadOp: 'clear', depthStoreOp: 'discard' },
          timestampWrites: writes ? writes(n === 0, n + 1 === total) : undefined,
        });
        pass.setPipeline(mapPipeline);
        pass.setBindGroup(0, faceGroups[n]);
        draw(pass, (object) => step.draw.includes(object));
        pass.end();
      }
      if (step.keep) encoder.copyTextureToTexture({ texture: layer.geometry }, { texture: previous }, whole);
      for (const which of ['geometry', 'surfaces']) {
        encoder.copyTextureToBuffer({ texture: layer[which] }, { buffer: maps[which], offset: step.offset, bytesPerRow: m.size * 16, rowsPerImage: m.size }, whole);
      }
    });
  };

  // The shading pass.
  const s = e.shading;
  const shadingLayouts = bindGroupLayouts(device, s.bindings);
  const lutTexture = (base64, width, rows) => {
    const t = device.createTexture({ size: [width, rows], format: plan.formats.lut, usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
    device.queue.writeTexture({ texture: t }, bytes(base64), { bytesPerRow: 8 * width, rowsPerImage: rows }, [width, rows]);
    return t;
  };
  const lut = s.lut ? lutTexture(s.lut, s.lut_width, s.lut_rows) : lutTexture(plan.blank_lut, 1, 1);
  const common = {
    objects: upload(s.objects, usage.STORAGE, 'effect objects'),
    materials: upload(s.materials, usage.STORAGE, 'effect materials'),
    lut_atlas: lut.createView(),
    lut_sampler: device.createSampler({ magFilter: 'linear', minFilter: 'linear', addressModeU: 'clamp-to-edge', addressModeV: 'clamp-to-edge', addressModeW: 'clamp-to-edge' }),
  };
  const mapsGroup = bindGroup(device, shadingLayouts, s.bindings, 1, { map_texels: maps.geometry, map_surfaces: maps.surfaces });
  const pipelines = new Map();
  const configurations = e.configurations.map((c) => {
    if (!pipelines.has(c.module)) pipelines.set(c.module, meshPipeline(c.module, shadingLayouts, moduleOf(c.module), s.vertex, s.fragment, [plan.formats.float]));
    const frame = upload(c.frame, usage.UNIFORM, 'effect frame');
    return { ...c, pipeline: pipelines.get(c.module), group: bindGroup(device, shadingLayouts, s.bindings, 0, { frame, ...common }) };
  });
  const shadingTarget = target(device, e.resolution, plan.formats.float, true);
  // SpecularPass::encode: every object rasterised, the bounce loop through the maps.
  const encodeShading = (encoder, i, timestampWrites) => {
    const c = configurations[i];
    const pass = begin(encoder, shadingTarget, timestampWrites);
    pass.setPipeline(c.pipeline);
    pass.setBindGroup(0, c.group);
    pass.setBindGroup(1, mapsGroup);
    draw(pass, () => true);
    pass.end();
  };
  return { configurations, encodeMaps, encodeShading, shadingTarget };
}

// effects::time_effects: warm-up rounds, then rounds that time one map update and the
// shading pass of every configuration in turn. Timestamps at the start of the update's first
// pass and the end of its last, and around each shading pass; else wall time per pass (one
// pass per submit, closed by onSubmittedWorkDone).
async function runEffects(device, timestamps, effects, step) {
  const e = plan.effects;
  const n = effects.configurations.length;
  let query = null;
  if (timestamps) {
    const count = 2 * (1 + n);
    query = {
      count,
      set: device.createQuerySet({ type: 'timestamp', count }),
      resolve: device.createBuffer({ size: count * 8, usage: GPUBufferUsage.QUERY_RESOLVE | GPUBufferUsage.COPY_SRC }),
      read: device.createBuffer({ size: count * 8, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ }),
    };
  }
  const update = [];
  const shading = effects.configurations.map(() => []);
  const wall = async (record) => {
    const encoder = device.createCommandEncoder();
    record(encoder);
    const start = performance.now();
    device.queue.submit([encoder.finish()]);
    await device.queue.onSubmittedWorkDone();
    return performance.now() - start;
  };
  for (let round = 0; round < e.warmup + e.repeats; round++) {
    checkLost();
    let times;
    if (query) {
      const encoder = device.createCommandEncoder();
      effects.encodeMaps(encoder, (first, last) => (first || last ? { querySet: query.set, beginningOfPassWriteIndex: first ? 0 : undefined, endOfPassWriteIndex: last ? 1 : undefined } : undefined));
      for (let i = 0; i < n; i++) effects.encodeShading(encoder, i, { querySet: query.set, beginningOfPassWriteIndex: 2 * (i + 1), endOfPassWriteIndex: 2 * (i + 1) + 1 });
      encoder.resolveQuerySet(query.set, 0, query.count, query.resolve, 0);
      encoder.copyBufferToBuffer(query.resolve, 0, query.read, 0, query.count * 8);
      device.queue.submit([encoder.finish()]);
      const ticks = new BigUint64Array(await readBuffer(query.read));
      times = Array.from({ length: n + 1 }, (_, k) => Number(ticks[2 * k + 1] - ticks[2 * k]) / 1e6);
    } else {
      times = [await wall((encoder) => effects.encodeMaps(encoder, null))];
      for (let i = 0; i < n; i++) times.push(await wall((encoder) => effects.encodeShading(encoder, i, undefined)));
    }
    if (round >= e.warmup) {
      update.push(times[0]);
      times.slice(1).forEach((x, i) => shading[i].push(x));
    }
    step(1 + n, `effects: round ${round + 1} of ${e.warmup + e.repeats}`);
    // Rows so far, so a lost device keeps them.
    result.effects_timing = effectRows(effects, update, shading, timestamps);
  }
}

// effects::timing_table's rows: the plan's cells of each configuration and the measured ones.
function effectRows(effects, update, shading, timestamps) {
  if (update.length === 0) return [];
  const a = result.adapter;
  const [mapUpdate] = medianAndIqr(update);
  return effects.configurations.map((c, i) => {
    const [median, spread] = medianAndIqr(shading[i]);
    return {
      ...c.row, adapter: a.name, backend: a.backend, timer: timestamps ? 'timestamp' : 'wall',
      map_update_ms: mapUpdate, shading_ms: median, shading_spread_ms: spread, frame_ms: mapUpdate + median,
    };
  });
}

// The frame of configuration `index` (maps updated, then the shading pass), read back as
// RGBA f32 pixels: what the tests compare with the native runner's SpecularPass::render.
function effectFrame(device, effects) {
  return async (index) => {
    const t = effects.shadingTarget;
    const buffer = device.createBuffer({ size: paddedRow(t.width, 16) * t.height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    const encoder = device.createCommandEncoder();
    effects.encodeMaps(encoder, null);
    effects.encodeShading(encoder, index, undefined);
    copyOut(encoder, t, buffer, 0);
    device.queue.submit([encoder.finish()]);
    return Array.from(decode(await readBuffer(buffer), 0, t));
  };
}

// ---- ambient occlusion ---------------------------------------------------------------------

// Buffers, pipelines and bind groups of the surfel pass (passes/ao.rs SurfelAoPass) and the
// GTAO pass (passes/gtao.rs GtaoPass), from the plan's bytes; `encodeSurfels` and
// `encodeGtao` record one timed sample, as ao_timing's `sample` and GTAO's one frame with its
// denoiser passes.
function setupAo(device, named) {
  const a = plan.ao;
  const compute = (bindings) => bindGroupLayouts(device, bindings, GPUShaderStage.COMPUTE);
  const init = (data, usage) => {
    const buffer = device.createBuffer({ size: Math.max(4, Math.ceil(data.byteLength / 4) * 4), usage: usage | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(buffer, 0, data);
    return buffer;
  };
  const pipeline = (module, layouts, entryPoint) => device.createComputePipeline({
    layout: device.createPipelineLayout({ bindGroupLayouts: layouts }), compute: { module: named[module], entryPoint },
  });
  const s = a.surfels;
  const surfelLayouts = compute(s.bindings);
  const discs = init(bytes(s.discs), GPUBufferUsage.STORAGE);
  const links = init(bytes(s.links), GPUBufferUsage.STORAGE);
  const state = device.createBuffer({ size: s.state_bytes, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST | GPUBufferUsage.COPY_SRC });
  const bent = device.createBuffer({ size: s.bent_bytes, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST | GPUBufferUsage.COPY_SRC });
  const surfelGroups = s.params.map((p) => bindGroup(device, surfelLayouts, s.bindings, 0, { params: init(bytes(p), GPUBufferUsage.UNIFORM), discs, links, state, bent }));
  const surfelPipelines = {
    brute_force: pipeline(s.module, surfelLayouts, 'cs_brute_force'),
    node_weights: pipeline(s.module, surfelLayouts, 'cs_node_weights'),
    tree: pipeline(s.module, surfelLayouts, 'cs_tree'),
  };
  const ones = new Float32Array(s.count).fill(1);
  const WORKGROUP = 64;
  // SurfelAoPass::encode: the bent normals cleared, the accessibility set to 1, then per pass
  // (the bind groups taking turns) the gather, through the tree preceded by the nodes' weights.
  const encodeSurfels = (encoder, kind, passes, timestampWrites) => {
    device.queue.writeBuffer(state, 0, ones);
    encoder.clearBuffer(bent);
    const pass = encoder.beginComputePass(timestampWrites ? { timestampWrites } : {});
    for (let k = 0; k < passes; k++) {
      pass.setBindGroup(0, surfelGroups[k % 2]);
      if (kind === 'brute_force') {
        pass.setPipeline(surfelPipelines.brute_force);
        pass.dispatchWorkgroups(Math.ceil(s.count / WORKGROUP));
      } else {
        pass.setPipeline(surfelPipelines.node_weights);
        pass.dispatchWorkgroups(Math.ceil(s.nodes / WORKGROUP));
        pass.setPipeline(surfelPipelines.tree);
        pass.dispatchWorkgroups(Math.ceil(s.count / WORKGROUP));
      }
    }
    pass.end();
  };
  let encodeGtao = null;
  const g = a.gtao;
  if (g) {
    const gtaoLayouts = compute(g.bindings);
    const gbuffer = init(bytes(g.gbuffer), GPUBufferUsage.STORAGE);
    const image = () => device.createBuffer({ size: g.width * g.height * 4, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
    const output = image();
    const denoised = image();
    const gtaoPipeline = pipeline(g.module, gtaoLayouts, 'cs_gtao');
    const denoisePipelines = ['cs_denoise_forward', 'cs_denoise_back'].map((entry) => pipeline(g.module, gtaoLayouts, entry));
    // Per configuration, the bind groups of its timed frame and of each denoiser pass: their
    // uniforms at slot × stride (GtaoPass::encode_frames).
    const groups = g.configurations.map((c) => {
      const uniforms = init(bytes(c.uniforms), GPUBufferUsage.UNIFORM);
      const at = (slot) => bindGroup(device, gtaoLayouts, g.bindings, 0, {
        params: { buffer: uniforms, offset: slot * g.stride, size: g.uniform_size }, gbuffer, accessibility: output, denoised,
      });
      return { frame: at(c.timed_frame), denoise: Array.from({ length: c.denoise_passes }, (_, j) => at(c.frames + j)) };
    });
    const TILE = 8;
    encodeGtao = (encoder, configuration, timestampWrites) => {
      const pass = encoder.beginComputePass(timestampWrites ? { timestampWrites } : {});
      const size = [Math.ceil(g.width / TILE), Math.ceil(g.height / TILE)];
      pass.setPipeline(gtaoPipeline);
      pass.setBindGroup(0, groups[configuration].frame);
      pass.dispatchWorkgroups(...size);
      groups[configuration].denoise.forEach((group, j) => {
        pass.setPipeline(denoisePipelines[j % 2]);
        pass.setBindGroup(0, group);
        pass.dispatchWorkgroups(...size);
      });
      pass.end();
    };
  }
  return { encodeSurfels, encodeGtao };
}

// ao_timing's `timed`: per row, warm-up samples, then timed ones (timestamps around the
// compute pass, else the wall clock around submit and onSubmittedWorkDone), one per submit.
async function runAo(device, timestamps, ao, step) {
  const a = plan.ao;
  let query = null;
  if (timestamps) {
    query = {
      set: device.createQuerySet({ type: 'timestamp', count: 2 }),
      resolve: device.createBuffer({ size: 16, usage: GPUBufferUsage.QUERY_RESOLVE | GPUBufferUsage.COPY_SRC }),
      read: device.createBuffer({ size: 16, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ }),
    };
  }
  const sample = async (record) => {
    const encoder = device.createCommandEncoder();
    record(encoder, query ? { querySet: query.set, beginningOfPassWriteIndex: 0, endOfPassWriteIndex: 1 } : undefined);
    if (query) {
      encoder.resolveQuerySet(query.set, 0, 2, query.resolve, 0);
      encoder.copyBufferToBuffer(query.resolve, 0, query.read, 0, 16);
    }
    const start = performance.now();
    device.queue.submit([encoder.finish()]);
    await device.queue.onSubmittedWorkDone();
    const wall = performance.now() - start;
    if (!query) return wall;
    const ticks = new BigUint64Array(await readBuffer(query.read));
    return Number(ticks[1] - ticks[0]) / 1e6;
  };
  for (const row of a.rows) {
    const record = row.kind === 'gtao'
      ? (encoder, writes) => ao.encodeGtao(encoder, row.configuration, writes)
      : (encoder, writes) => ao.encodeSurfels(encoder, row.kind, row.passes, writes);
    const samples = [];
    for (let round = 0; round < a.warmup + a.repeats; round++) {
      checkLost();
      const ms = await sample(record);
      if (round >= a.warmup) samples.push(ms);
      step(1, `ambient occlusion: ${row.kind}${row.kind === 'gtao' ? ` ${row.row.preset}` : `, ${row.passes} passes`}, sample ${round + 1} of ${a.warmup + a.repeats}`);
    }
    const [median, spread] = medianAndIqr(samples);
    // Rows so far, so a lost device keeps them.
    result.ao_timing.push({
      ...row.row, adapter: result.adapter.name, driver: BROWSER, timer: timestamps ? 'timestamp' : 'wall',
      median_ms: median, spread_ms: spread, convergence_ms: row.kind === 'gtao' ? median * row.frames : null,
    });
  }
}

// ---- results ------------------------------------------------------------------------------

function cell(row, text) { const td = document.createElement('td'); td.textContent = text; row.appendChild(td); }

function table(id, headers, rows) {
  const t = $(id);
  t.textContent = '';
  const head = t.createTHead().insertRow();
  for (const h of headers) { const th = document.createElement('th'); th.textContent = h; head.appendChild(th); }
  const body = t.createTBody();
  for (const r of rows) { const tr = body.insertRow(); for (const x of r) cell(tr, x); }
}

const fixed = (x, digits) => (x === null || x === undefined || !Number.isFinite(x) ? '—' : x.toFixed(digits));

// The ratio of each row's median to exact's on the same material (none without exact).
function ratios() {
  return result.gpu_timing.map((r) => {
    const exact = result.gpu_timing.find((x) => x.material === r.material && x.method === 'exact');
    return { ...r, ratio: exact ? r.median_ms / exact.median_ms : null };
  });
}

// A horizontal bar chart into the element `id`: one bar per item ({label, value, text,
// grey}); lengths linear in value, or with `floor` logarithmic from floor to the largest.
function bars(id, items, aria, floor) {
  const svgNs = 'http://www.w3.org/2000/svg';
  const barHeight = 18, left = 260, width = 640, room = width - left - 80;
  const largest = Math.max(...items.map((x) => x.value), floor ? floor * 10 : 1);
  const length = (v) => Math.max(1, floor ? (room * Math.log(Math.max(v, floor) / floor)) / Math.log(largest / floor) : (room * v) / largest);
  const svg = document.createElementNS(svgNs, 'svg');
  svg.setAttribute('viewBox', `0 0 ${width} ${items.length * barHeight + 8}`);
  svg.setAttribute('width', width); svg.setAttribute('height', items.length * barHeight + 8);
  svg.setAttribute('role', 'img'); svg.setAttribute('aria-label', aria);
  items.forEach((x, i) => {
    const y = i * barHeight;
    const label = document.createElementNS(svgNs, 'text');
    label.setAttribute('x', left - 6); label.setAttribute('y', y + 13); label.setAttribute('text-anchor', 'end');
    label.textContent = x.label;
    const bar = document.createElementNS(svgNs, 'rect');
    bar.setAttribute('x', left); bar.setAttribute('y', y + 2); bar.setAttribute('height', barHeight - 4);
    bar.setAttribute('width', length(x.value));
    bar.setAttribute('class', x.grey ? 'bar exact' : 'bar');
    const value = document.createElementNS(svgNs, 'text');
    value.setAttribute('x', left + length(x.value) + 4); value.setAttribute('y', y + 13);
    value.textContent = x.text;
    svg.append(label, bar, value);
  });
  $(id).textContent = '';
  $(id).appendChild(svg);
}

function charts(rows) {
  bars('chart', rows.filter((r) => r.ratio !== null).map((r) => ({ label: `${r.material} ${r.method}`, value: r.ratio, text: `${r.ratio.toFixed(2)}×`, grey: r.method === 'exact' })),
    'pass time relative to exact per material and method');
  // Image error on a log scale from 1e-5 (exact against itself, 0, is left out).
  const errors = result.image_errors.filter((r) => r.method !== 'exact' && r.mean_rel_error !== null);
  bars('error-chart', errors.map((r) => ({ label: `${r.object} ${r.material} ${r.method}`, value: r.mean_rel_error, text: `${(100 * r.mean_rel_error).toPrecision(3)} %` })),
    'mean relative image error against exact per object, material and method (log scale)', 1e-5);
}

function fileName() {
  const slug = (result.adapter ? result.adapter.name : 'no-adapter').toLowerCase().replace(/[^a-z0-9]+/g, '-').replace(/^-|-$/g, '');
  const scene = plan.scene.toLowerCase().replace(/[^a-z0-9]+/g, '-').replace(/^-|-$/g, '') || 'scene';
  const time = result.date.slice(0, 19).replace(/[-:]/g, '').replace('T', '-');
  return `device-${slug || 'adapter'}-${scene}-${time}${result.complete ? '' : '-incomplete'}.json`;
}

function publish() {
  const rows = ratios();
  table('timing', ['material', 'method', 'timer', 'F per pixel', 'n', 'median ms', 'IQR ms', 'ns per F', '× exact', '× bare fetch', '× exact (dielectric)', 'resolved'],
    rows.map((r) => [r.material, r.method + (r.formula ? ` (${r.formula})` : ''), r.timer, String(r.evaluations), String(r.repeats), fixed(r.median_ms, 4), fixed(r.spread_ms, 4),
      fixed(r.ns_per_evaluation, 4), fixed(r.ratio, 3), fixed(r.relative_to_fetch, 3), fixed(r.relative_to_exact_dielectric, 3), r.near_resolution === 'yes' ? 'no: within 10× the timer\'s resolution or 2× its floor' : 'yes']));
  charts(rows);
  table('errors', ['material', 'method', 'object', 'frames', 'mean rel. error', 'max rel. error', 'pixels'],
    result.image_errors.map((r) => [r.material, r.method, r.object, String(r.frames), r.mean_rel_error === null ? '—' : r.mean_rel_error.toExponential(3), r.max_rel_error.toExponential(3), String(r.pixels)]));
  table('effects', ['method', 'effect', 'depths (reflection/refraction)', 'steps (linear/secant)', 'timer', 'map update ms', 'shading ms', 'IQR ms'],
    result.effects_timing.map((r) => [r.method, r.effect, `${r.reflection_depth}/${r.refraction_depth}`, `${r.linear_steps}/${r.secant_steps}`, r.timer, fixed(r.map_update_ms, 4), fixed(r.shading_ms, 4), fixed(r.shading_spread_ms, 4)]));
  $('effects-section').hidden = result.effects_timing.length === 0;
  table('ao', ['emitters', 'passes', 'preset', 'radius', 'slices × steps', 'frames', 'pixels', 'timer', 'median ms', 'IQR ms', 'to convergence ms'],
    result.ao_timing.map((r) => [r.emitters, String(r.passes), r.preset || '—', r.radius === null ? '—' : String(r.radius), r.emitters === 'gtao' ? `${r.slices} × ${r.steps}` : '—',
      String(r.frames), r.emitters === 'gtao' ? `${r.width}x${r.height}` : '—', r.timer, fixed(r.median_ms, 4), fixed(r.spread_ms, 4), r.convergence_ms === null ? '—' : fixed(r.convergence_ms, 4)]));
  $('ao-section').hidden = result.ao_timing.length === 0;
  table('modules', ['module', 'errors', 'warnings'], result.compile.map((c) => [c.module, String(c.errors.length), String(c.warnings.length)]));
  $('skipped').textContent = '';
  for (const s of result.skipped) { const li = document.createElement('li'); li.textContent = `Not measured here: ${s}`; $('skipped').appendChild(li); }
  const json = JSON.stringify(result, null, 1);
  const link = $('download');
  link.href = URL.createObjectURL(new Blob([json], { type: 'application/json' }));
  link.download = fileName();
  $('results').hidden = false;
}

async function main() {
  enter('opening the GPU');
  status('requesting an adapter…');
  const { device, timestamps } = await openDevice();
  lostPromise = device.lost.then((info) => { lost = `${info.reason}: ${info.message}`; });
  device.addEventListener('uncapturederror', (event) => { lost = lost || `uncaptured error: ${event.error.message}`; });
  keepAwake();
  enter('compiling');
  status(`${plan.checks.length} shader modules on ${result.adapter.name}…`);
  const { modules, named } = await compileChecks(device, (k) => status(`module ${k} of ${plan.checks.length}`, 0));
  let fresnel = null;
  if (plan.timing || plan.image_error) {
    fresnel = await scoped(device, 'creating the buffers, textures and pipelines', () => setup(device, modules));
    window.nklut.ramp = ramp(device, fresnel);
  }
  let effects = null;
  if (plan.effects) {
    effects = await scoped(device, 'creating the effects\' buffers, textures and pipelines', () => setupEffects(device, named));
    window.nklut.effectFrame = effectFrame(device, effects);
  }
  let ao = null;
  if (plan.ao) ao = await scoped(device, 'creating the ambient-occlusion buffers and pipelines', () => setupAo(device, named));
  const frames = plan.image_error ? (HOOK.allFrames ? plan.image_error.frames.length : 1) : 0;
  result.image_error_frames = plan.image_error ? (HOOK.allFrames ? 'all' : 'first') : null;
  const total = (plan.timing ? (plan.timing.warmup + plan.timing.repeats) * plan.timing.pairs.length : 0)
    + (plan.image_error ? frames * plan.image_error.objects.length : 0)
    + (plan.effects ? (plan.effects.warmup + plan.effects.repeats) * (1 + plan.effects.configurations.length) : 0)
    + (plan.ao ? (plan.ao.warmup + plan.ao.repeats) * plan.ao.rows.length : 0);
  let done = 0;
  const step = (n, text) => { done += n; progress(done, total); status(`${text} (${done} of ${total} steps)`, done / total); };
  if (plan.timing) { enter('timing'); await runTiming(device, timestamps, fresnel, step); }
  if (plan.image_error) { enter('image error'); await runImageError(device, fresnel, step); }
  if (effects) { enter('effects timing'); await runEffects(device, timestamps, effects, step); }
  if (ao) { enter('ambient-occlusion timing'); await runAo(device, timestamps, ao, step); }
  checkLost();
  result.complete = true;
  enter('done');
  status(` ${result.gpu_timing.length} timing rows, ${result.image_errors.length} image-error rows, ${result.effects_timing.length} effects-timing rows, ${result.ao_timing.length} ambient-occlusion rows on ${result.adapter.name} (timer: ${timestamps ? 'GPU timestamps' : 'wall time'}).`);
}

main()
  .catch(async (error) => {
    // A lost device rejects the pending mapAsync before device.lost resolves: give it a
    // moment, so the reader gets the lost-device message and not the map's.
    if (!(error instanceof Problem) && lostPromise && !lost) await Promise.race([lostPromise, new Promise((r) => setTimeout(r, 1500))]);
    let text;
    if (lost) text = `The device was lost (${lost}); the rows measured before are kept and marked incomplete.`;
    else if (error instanceof Problem) text = error.message;
    else text = `Unexpected error: ${error && error.message ? error.message : error}`;
    result.incomplete = text;
    window.nklut.error = text;
    problem(text);
    if (result.adapter) markIncomplete(text);
    status('stopped.');
  })
  .finally(() => {
    if (result.adapter) publish();
    window.nklut.done = true;
  });
