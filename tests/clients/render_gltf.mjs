// Renders every material of a glTF export in a real glTF client — three.js (npm `three`) in
// headless Chromium through SwiftShader's WebGL2 — and measures what it shows.
//
// Usage: node tests/clients/render_gltf.mjs GLTF_FILE OUT_DIR [--only NAME,...] [--blocks DIR] [--timeout SECONDS]
//
// GLTF_FILE holds one sphere node per material, named by page id (`3d/glass/BK7`). The page
// tests/clients/render.html renders each top-level node alone, centred at the origin, seen
// from +z by a 45° camera at distance 4, in front of a black-and-white checkerboard (10×10
// checks of 0.75 units at z = −2.5, unlit, exactly 0 and 1, the sphere's centre in front of
// the middle of a white check), lit by three.js's RoomEnvironment (PMREM, intensity 1), with
// NoToneMapping and sRGB output, 256×256 pixels. Each node is rendered twice into a float
// target (linear values as the shaders computed them, unclamped: highlights above 1 keep
// their colour) — with the board as made and with its colours inverted — and once on the
// canvas as a client displays it (the PNG). One pair without any sphere is the reference.
// The numbers are taken over the central disc of the sphere, of radius 0.4 × its screen
// radius, in the float renders:
//
//   contrast               how much of the board one sees through the sphere:
//                          mean |Y(board) − Y(inverted board)| over the disc, divided by the
//                          same for the reference (Y: linear Rec. 709 luminance). 1 for a
//                          perfectly clear sphere, 0 for an opaque one. Whatever does not come
//                          from behind the sphere (reflections, diffuse light) cancels in the
//                          difference, and it does not care where refraction sends each pixel
//                          (an inverted, magnified or shifted image scores like a straight
//                          one); blur (rough transmission) mixes black and white and lowers it.
//   contrast_aligned       the plain version: (mean where the reference is white − mean where
//                          it is black) / the same in the reference, on the main render only.
//                          Diagnostic only: refraction that moves the checks drives it towards
//                          0 for clear glass, and reflections that happen to fall on white
//                          checks make it large for opaque spheres.
//   transmitted_linear_rgb the per-channel version of `contrast`: the linear colour of a white
//                          background seen through the sphere (absorption, tint).
//   mean_linear_rgb        the mean linear colour of the disc in the main (as made) render.
//   hue_degrees, chroma    HSV hue (red 0°, yellow 60°, green 120°, blue 240°) and chroma
//                          (max − min) of the sRGB encoding of mean_linear_rgb scaled so that
//                          its largest channel is 1 — the colour whatever its brightness; the
//                          chroma is then HSV's saturation (0 for a grey);
//                          lab, lab_hue_degrees, lab_chroma: CIELAB (D65) of the same colour.
//   transmitted_hue_degrees, transmitted_chroma, transmitted_lab_*: the same of
//                          transmitted_linear_rgb.
//   centre_linear, centre_hue_degrees, centre_chroma
//                          the pixel at (128, 128) of the main float render, and its colour.
//   centre_srgb8, centre_srgb8_as_linear
//                          that pixel on the canvas (8-bit sRGB as displayed, clamped at 255).
//   white_mirror_centre_linear, centre_over_white_mirror
//                          the same pixel of a white mirror (MeshStandardMaterial, colour 1,
//                          metalness 1, the material's roughness) in place of the sphere, and
//                          the ratio per channel: for a metal its F0 as the renderer shows it
//                          (both see the same environment, and three.js's split-sum term
//                          F0·A + B at normal incidence has B ≈ 0).
//
// With --blocks DIR (the `params/` folder of the same run), each node whose page has a
// paste-in file there also has its three.js block (`engines.threejs`) evaluated literally in
// the page and rendered the same way on a sphere of the node's size modelled at scale 1
// (the block's thickness is in mesh units): results.json → blocks[node name] holds the same
// measurements, and <node>__threejs_block.png the image.
//
// and what three.js loaded (MeshPhysicalMaterial's properties: transmission, roughness,
// metalness, ior, thickness, attenuation_distance — the string "Infinity" when unset —,
// attenuation_color, specular_*, dispersion, and the glTF material's name and extensions).
//
// Writes OUT_DIR/<node name with '/' → '__'>.png per node, OUT_DIR/reference.png (the board
// alone) and OUT_DIR/results.json; exits 0 when every node rendered, 1 with a message on
// stderr on any failure (no WebGL2, load error, timeout: the whole run is bounded by
// --timeout, default 180 s; 38 materials take about 15 s on two idle cores).
//
// Nothing leaves the machine: a static HTTP server on 127.0.0.1 (port chosen by the system)
// serves the page, three.js and the glTF folder, the browser talks to this script over a
// pipe, and the page may fetch nothing but that server. The browser's profile is a fresh
// folder under the system's temporary directory ($TMPDIR), removed at the end. The run's
// deadline, the server and the browser are tests/clients/harness.mjs's.

import { mkdirSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve, sep } from 'node:path';

import { BrowserRun, here, loadDependencies, modules } from './harness.mjs';

function usage(message) {
  console.error(`render_gltf: ${message}`);
  console.error('usage: node tests/clients/render_gltf.mjs GLTF_FILE OUT_DIR [--only NAME,...] [--blocks DIR] [--timeout SECONDS]');
  process.exit(2);
}

const positional = [];
let only = null;
let timeoutSeconds = 180;
let blocksDir = null;
for (let i = 2; i < process.argv.length; i++) {
  const arg = process.argv[i];
  if (arg === '--only') only = (process.argv[++i] ?? usage('--only needs a list')).split(',').filter(Boolean);
  else if (arg === '--timeout') timeoutSeconds = Number(process.argv[++i]);
  else if (arg === '--blocks') blocksDir = resolve(process.argv[++i] ?? usage('--blocks needs a folder'));
  else if (arg.startsWith('--')) usage(`unknown option ${arg}`);
  else positional.push(arg);
}
if (positional.length !== 2) usage('needs GLTF_FILE and OUT_DIR');
if (!(timeoutSeconds > 0)) usage('--timeout needs a positive number of seconds');
const [gltfFile, outDir] = positional.map((p) => resolve(p));

const browser = new BrowserRun('render_gltf', timeoutSeconds);
const bounded = (promise, what) => browser.bounded(promise, what);

/** What the server serves. */
const MOUNTS = [
  ['/render.html', join(here, 'render.html')],
  ['/three/', join(modules, 'three') + sep],
  ['/model/', dirname(gltfFile) + sep],
];

async function main() {
  const { threeVersion, puppeteer } = loadDependencies(['the glTF file', gltfFile]);
  mkdirSync(outDir, { recursive: true });

  // The page may reach this script's server and nothing else.
  const chromium = await browser.open(puppeteer, MOUNTS);
  const { page, problems, withProblems } = browser;
  await browser.loadHarness('/render.html');

  const gltfUrl = `/model/${encodeURIComponent(gltfFile.slice(dirname(gltfFile).length + 1))}`;
  const setup = await bounded(page.evaluate((url) => window.harness.setup(url), gltfUrl), 'loading the glTF file').catch(withProblems);
  writeFileSync(join(outDir, 'reference.png'), Buffer.from(setup.reference_png, 'base64'));
  console.error(`render_gltf: three ${threeVersion} (r${setup.three}), ${chromium}, WebGL: ${setup.webgl}; ${setup.nodes.length} nodes`);
  if (!/swiftshader/i.test(setup.webgl)) console.error(`render_gltf: note: the WebGL renderer is not SwiftShader (${setup.webgl})`);

  const wanted = only ?? setup.nodes;
  const missing = wanted.filter((name) => !setup.nodes.includes(name));
  if (missing.length) throw new Error(`no node named ${missing.join(', ')} in ${gltfFile}`);
  // The three.js block of each page, by page id, from the paste-in files.
  const threeBlocks = new Map();
  if (blocksDir) {
    for (const file of readdirSync(blocksDir).filter((f) => f.endsWith('.json')).sort()) {
      const paste = JSON.parse(readFileSync(join(blocksDir, file), 'utf8'));
      if (typeof paste?.engines?.threejs === 'string') threeBlocks.set(paste.page, paste.engines.threejs);
    }
  }
  const materials = {};
  const blocks = {};
  for (const name of wanted) {
    const index = setup.nodes.indexOf(name);
    const t0 = Date.now();
    const rendered = await bounded(page.evaluate((i) => window.harness.render(i), index), `rendering ${name}`);
    writeFileSync(join(outDir, `${name.replaceAll('/', '__')}.png`), Buffer.from(rendered.png, 'base64'));
    materials[name] = rendered.result;
    const r = rendered.result;
    console.error(
      `render_gltf: ${name}: contrast ${r.contrast.toFixed(3)}, mean ${r.mean_linear_rgb.map((v) => v.toFixed(3)).join(' ')}, ` +
        `hue ${r.hue_degrees.toFixed(0)}° chroma ${r.chroma.toFixed(3)} (${Date.now() - t0} ms)`,
    );
    const text = threeBlocks.get(name);
    if (text !== undefined) {
      const block = await bounded(page.evaluate((i, t) => window.harness.renderBlock(i, t), index, text), `rendering the three.js block of ${name}`);
      writeFileSync(join(outDir, `${name.replaceAll('/', '__')}__threejs_block.png`), Buffer.from(block.png, 'base64'));
      blocks[name] = block.result;
    }
  }
  if (problems.length) throw new Error(`the page reported: ${problems.join('; ')}`);

  const results = {
    three: threeVersion,
    chromium,
    webgl: setup.webgl,
    size: setup.size,
    seconds: (Date.now() - browser.started) / 1000,
    materials,
    blocks,
  };
  writeFileSync(join(outDir, 'results.json'), JSON.stringify(results, null, 1) + '\n');
  await browser.finish();
  console.error(`render_gltf: ${wanted.length} materials in ${results.seconds.toFixed(1)} s; ${join(outDir, 'results.json')}`);
}

main().catch((error) => browser.die(error?.message ?? String(error)));
