// Renders nklut's Fresnel LUTs through clients/three/nklut-lut.js — three.js (npm `three`) in
// headless Chromium through SwiftShader's WebGL2 — and measures the Fresnel term per pixel
// (tests/clients/render_lut.html says how).
//
// Usage: node tests/clients/render_lut.mjs LUTS_DIR OUT_DIR [--pages ID,...] [--timeout SECONDS]
//
// LUTS_DIR is a bake's luts/ folder (manifest.json and the atlases of the `three-channel`
// source; a link, as `nklut bake` publishes it, is followed). For each of the five encodings
// the atlas is loaded as the module loads it and every page of --pages is rendered; then two
// runs with a wrong setting on purpose, to show that the measurement sees them:
// `unorm8 flipY` (TextureLoader's default flipY = true) and `f16 file-order` (v as if
// EXRLoader kept the file's scanline order). Last, clients/three/demo.html is opened as a
// user would (three.js requested from unpkg is answered from the local copy) and its state
// and a screenshot (OUT_DIR/demo.png) kept. Before it, clients/godot/nklut_lut.gdshaderinc
// is compiled and run as GLSL ES 3.00 on the unorm8 and unorm8-srgb atlases (render_lut.html,
// godot()). Writes OUT_DIR/results.json (godot: [{ encoding, results: { page: { row,
// min_cos, channels: [{ lut_max }] } } }]):
// { three, chromium, webgl, extensions, runs: [{ name, encoding, override, texture_type,
// flip_y, rows, results: { page: { row, kind, v, pixels, min_cos, grazing_pixels,
// max_cos_difference, channels: [{ lut_max, lut_mean, lut_max_at_cos, three_max, three_mean,
// schlick_max, schlick_mean }] } } }], demo: { ready, spheres, error, problems } } — absolute differences from the exact Fresnel curve of
// the row's three-channel (n, k), per channel R G B.
//
// Exits 0 when every run rendered, 1 with a message on stderr otherwise (the whole run is
// bounded by --timeout, default 180 s). Nothing leaves the machine: a static HTTP server on
// 127.0.0.1 serves the page, three.js, clients/ and LUTS_DIR; the browser may fetch nothing
// else; its profile is a fresh folder under $TMPDIR, removed at the end. The run's deadline,
// the server and the browser are tests/clients/harness.mjs's.

import { mkdirSync, readFileSync, realpathSync, writeFileSync } from 'node:fs';
import { extname, join, resolve, sep } from 'node:path';

import { BrowserRun, TYPES, here, loadDependencies, modules, root, servedFile, sleep } from './harness.mjs';

function usage(message) {
  console.error(`render_lut: ${message}`);
  console.error('usage: node tests/clients/render_lut.mjs LUTS_DIR OUT_DIR [--pages ID,...] [--timeout SECONDS]');
  process.exit(2);
}

const positional = [];
let pages = ['3d/metals/copper', '3d/metals/gold', '3d/glass/soda-lime-green', '3d/liquids/water'];
let timeoutSeconds = 180;
for (let i = 2; i < process.argv.length; i++) {
  const arg = process.argv[i];
  if (arg === '--pages') pages = (process.argv[++i] ?? usage('--pages needs a list')).split(',').filter(Boolean);
  else if (arg === '--timeout') timeoutSeconds = Number(process.argv[++i]);
  else if (arg.startsWith('--')) usage(`unknown option ${arg}`);
  else positional.push(arg);
}
if (positional.length !== 2) usage('needs LUTS_DIR and OUT_DIR');
if (!(timeoutSeconds > 0)) usage('--timeout needs a positive number of seconds');
let lutsDir;
try {
  lutsDir = realpathSync(resolve(positional[0]));
} catch {
  usage(`no folder ${positional[0]}`);
}
const outDir = resolve(positional[1]);

/** The runs: every encoding as the module loads it, then the two wrong settings. */
const RUNS = [
  { name: 'unorm8', encoding: 'unorm8' },
  { name: 'unorm8-srgb', encoding: 'unorm8-srgb' },
  { name: 'unorm16', encoding: 'unorm16' },
  { name: 'f16', encoding: 'f16' },
  { name: 'f32', encoding: 'f32' },
  { name: 'unorm8 flipY', encoding: 'unorm8', override: { flipY: true } },
  { name: 'f16 file-order', encoding: 'f16', override: { rowOrder: 'file' } },
];

/** The demo's import-map prefix for three.js, served from the local npm copy. */
const DEMO_CDN = 'https://unpkg.com/three@0.187.0/';

const browser = new BrowserRun('render_lut', timeoutSeconds);
const bounded = (promise, what) => browser.bounded(promise, what);

/** What the server serves. */
const MOUNTS = [
  ['/render_lut.html', join(here, 'render_lut.html')],
  ['/three/', join(modules, 'three') + sep],
  ['/clients/', join(root, 'clients') + sep],
  ['/luts/', lutsDir + sep],
];

async function main() {
  const { threeVersion, puppeteer } = loadDependencies(['the manifest', join(lutsDir, 'manifest.json')]);
  mkdirSync(outDir, { recursive: true });

  const chromium = await browser.open(puppeteer, MOUNTS, (request, url) => {
    if (!url.startsWith(DEMO_CDN)) return false;
    // The demo's import map names three.js on unpkg: answered from the local copy.
    const file = servedFile(MOUNTS, '/three/' + url.slice(DEMO_CDN.length));
    if (file) request.respond({
        status: 200,
        contentType: TYPES[extname(file)] ?? 'text/javascript',
        headers: { 'access-control-allow-origin': '*' },
        body: readFileSync(file),
      });
    else request.abort();
    return true;
  });
  const { page, problems, origin, withProblems } = browser;
  await browser.loadHarness('/render_lut.html');
  const setup = await bounded(page.evaluate(() => window.harness.setup('/luts/manifest.json')), 'setting up').catch(withProblems);
  console.error(`render_lut: three ${threeVersion} (r${setup.three}), ${chromium}, WebGL: ${setup.webgl}; ${JSON.stringify(setup.extensions)}`);

  const runs = [];
  for (const run of RUNS) {
    const t0 = Date.now();
    const options = { baseUrl: '/luts/', source: 'three-channel', encoding: run.encoding, override: run.override ?? {} };
    const result = await bounded(page.evaluate((o, p) => window.harness.run(o, p), options, pages), `rendering ${run.name}`).catch(withProblems);
    runs.push({ name: run.name, override: run.override ?? null, ...result });
    const worst = Object.entries(result.results)
      .map(([id, r]) => `${id.split('/').pop()} ${Math.max(...r.channels.map((c) => c.lut_max)).toExponential(2)}`)
      .join(', ');
    console.error(`render_lut: ${run.name}: max |F_LUT - F_exact| ${worst} (${Date.now() - t0} ms)`);
  }
  const godot = [];
  for (const encoding of ['unorm8', 'unorm8-srgb']) {
    const options = { baseUrl: '/luts/', source: 'three-channel', encoding };
    const result = await bounded(page.evaluate((o, p) => window.harness.godot(o, p), options, pages), `running the Godot include (${encoding})`).catch(withProblems);
    godot.push(result);
    console.error(`render_lut: Godot include, ${encoding}: ${Object.entries(result.results).map(([id, r]) => `${id.split('/').pop()} ${Math.max(...r.channels.map((c) => c.lut_max)).toExponential(2)}`).join(', ')}`);
  }
  if (problems.length) throw new Error(`the page reported: ${problems.join('; ')}`);

  // The demo page as a user opens it (three.js from the local copy, see above).
  const demoUrl = `${origin}/clients/three/demo.html?luts=/luts/&encoding=unorm8-srgb&pages=${encodeURIComponent(pages.join(','))}`;
  await bounded(page.goto(demoUrl, { waitUntil: 'load', timeout: browser.left() }), 'loading the demo');
  // 30 s at most: a failed import never runs the page's script.
  await bounded(page.waitForFunction('window.nklutDemo && window.nklutDemo.ready', { timeout: Math.min(browser.left(), 30000) }), 'running the demo').catch(withProblems);
  await sleep(500);
  const demo = await bounded(page.evaluate(() => window.nklutDemo), 'reading the demo state');
  demo.problems = problems.splice(0);
  await bounded(page.screenshot({ path: join(outDir, 'demo.png') }), 'taking the demo screenshot');
  console.error(`render_lut: demo: ${JSON.stringify(demo)}`);

  const results = { three: threeVersion, chromium, webgl: setup.webgl, extensions: setup.extensions, pages, seconds: (Date.now() - browser.started) / 1000, runs, godot, demo };
  writeFileSync(join(outDir, 'results.json'), JSON.stringify(results, null, 1) + '\n');
  await browser.finish();
  console.error(`render_lut: ${runs.length} runs in ${results.seconds.toFixed(1)} s; ${join(outDir, 'results.json')}`);
}

main().catch((error) => browser.die(error?.message ?? String(error)));
