// Runs a browser-bench page (`nklut gpu web SCENE`) in the system Chromium through
// puppeteer-core and writes what it produced as JSON.
//
// Usage: node tests/clients/run_web_bench.mjs PAGE OUT_JSON [--webgpu on|off|absent] [--query Q]
//            [--ramp INDEX,METHOD,WIDTH,HEIGHT,VIEW_BASE64] [--effect-frame INDEX] [--twin INPUT_JSON]
//            [--timeout SECONDS] [--viewport WIDTH] [--hide-at MS] [--insecure]
//
//   --webgpu on      (default) WebGPU on SwiftShader: --enable-unsafe-webgpu
//                    --use-webgpu-adapter=swiftshader (it grants timestamp-query)
//   --webgpu hardware  WebGPU on this machine's GPU where Chromium reaches it (Vulkan,
//                    blocklist ignored); the result's adapter says whether it did
//   --webgpu off     no WebGPU flags: Chromium on Linux then gives no adapter
//   --webgpu absent  navigator.gpu removed before the page's script runs
//   --ramp           after the run, the page's read-back cosθ ramp of METHOD for material
//                    INDEX (window.nklut.ramp), as `ramp` in the output
//   --screenshot     a PNG of the whole page once it is done, for a look
//   --query          text appended to the page's address after `?` (`timer=wall`)
//   --effect-frame   after the run, the page's read-back frame of effects configuration INDEX
//                    (window.nklut.effectFrame: maps updated, then the shading pass), as
//                    `effect_frame` (RGBA f32 pixels, top row first)
//   --viewport       the page's width in CSS pixels (a phone: 390); `layout` in the output
//                    gives the document's scroll width and each table box's overflow
//   --hide-at        MS after the page opens, it is told the tab went to the background (its
//                    visibilityState reads `hidden` and a visibilitychange event fires)
//   --insecure       the page served over http from a name that is not localhost
//                    (nklut.test, mapped to 127.0.0.1): not a secure context
//   --twin           a JSON file {"method": [...], "reference": [...], "samples": [...]}: the
//                    page's twins of image_error::compare and stats::median_and_iqr on it,
//                    as `twin` in the output
//
// The output holds `result` (the page's result JSON, what its download link offers),
// `download` (the link's file name), `problem` (the text of the page's problem box, null if
// hidden), `status`, `tables` (the cell texts of the page's result tables by id) and the
// optional `ramp`, `effect_frame` and `twin`. The page is opened from file://, nothing is fetched; the
// browser profile is a fresh temporary folder, removed at the end. Exits 1 with a message
// on a browser or timeout failure (default --timeout 300 s).

import { createServer } from 'node:http';
import { createRequire } from 'node:module';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, '..', '..');
const deps = process.env.NKLUT_TEST_DEPS ? resolve(process.env.NKLUT_TEST_DEPS) : join(root, '.test-deps');
const chromiumPath = process.env.NKLUT_CHROMIUM || '/usr/bin/chromium';

function fail(message) {
  console.error(`run_web_bench: ${message}`);
  process.exit(1);
}

const args = process.argv.slice(2);
if (args.length < 2) fail('usage: run_web_bench.mjs PAGE OUT_JSON [--webgpu on|off|absent] [--ramp ...] [--twin FILE] [--timeout S]');
const [pagePath, outPath] = args;
const option = (name, fallback) => { const i = args.indexOf(name); return i >= 0 && i + 1 < args.length ? args[i + 1] : fallback; };
const webgpu = option('--webgpu', 'on');
const rampSpec = option('--ramp', null);
const twinFile = option('--twin', null);
const effectFrame = option('--effect-frame', null);
const query = option('--query', null);
const screenshot = option('--screenshot', null);
const timeoutMs = Number(option('--timeout', '300')) * 1000;
const viewport = option('--viewport', null);
const hideAt = option('--hide-at', null);
const insecure = args.includes('--insecure');

const require = createRequire(join(deps, 'npm', 'node_modules', 'noop.js'));
let puppeteer;
try {
  puppeteer = require('puppeteer-core');
} catch (error) {
  fail(`puppeteer-core is not installed under ${deps}/npm (scripts/test-deps installs it): ${error.message}`);
}

const profile = mkdtempSync(join(tmpdir(), 'nklut-web-bench-'));
const flags = ['--no-sandbox', '--no-first-run', '--no-default-browser-check', `--user-data-dir=${profile}`];
if (webgpu === 'hardware') flags.push('--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-angle=vulkan', '--ignore-gpu-blocklist', '--enable-gpu');
else if (webgpu !== 'off') flags.push('--enable-unsafe-webgpu', '--use-webgpu-adapter=swiftshader');
let server = null;
if (insecure) {
  const html = readFileSync(resolve(pagePath));
  server = createServer((_, response) => { response.writeHead(200, { 'content-type': 'text/html; charset=utf-8' }); response.end(html); });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  flags.push('--host-resolver-rules=MAP nklut.test 127.0.0.1');
}
const browser = await puppeteer.launch({ executablePath: chromiumPath, headless: true, args: flags, pipe: true, protocolTimeout: timeoutMs });
const timer = setTimeout(async () => {
  await browser.close().catch(() => {});
  rmSync(profile, { recursive: true, force: true });
  fail(`the page did not finish within ${timeoutMs / 1000} s`);
}, timeoutMs);
try {
  const page = await browser.newPage();
  const console_ = [];
  page.on('console', (m) => console_.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => console_.push(`pageerror: ${e.message}`));
  if (webgpu === 'absent') {
    await page.evaluateOnNewDocument(() => { Object.defineProperty(Navigator.prototype, 'gpu', { get: () => undefined, configurable: true }); });
  }
  if (viewport) await page.setViewport({ width: Number(viewport), height: 844, isMobile: true, deviceScaleFactor: 1 });
  const address = server ? `http://nklut.test:${server.address().port}/page.html` : pathToFileURL(resolve(pagePath)).href;
  await page.goto(address + (query ? `?${query}` : ''));
  if (hideAt !== null) {
    setTimeout(() => page.evaluate(() => {
      Object.defineProperty(document, 'visibilityState', { get: () => 'hidden', configurable: true });
      document.dispatchEvent(new Event('visibilitychange'));
      delete document.visibilityState;
    }).catch(() => {}), Number(hideAt));
  }
  // Poll (rather than one long waitForFunction, which a busy page can outlast the
  // protocol's timeout in); the page's status line goes to stderr every 30 s.
  let said = 0;
  for (;;) {
    const state = await page.evaluate(() => ({ done: Boolean(window.nklut && window.nklut.done), status: document.getElementById('status')?.textContent }));
    if (state.done) break;
    if (Date.now() - said > 30000) { console.error(`run_web_bench: ${state.status}`); said = Date.now(); }
    await new Promise((r) => setTimeout(r, 250));
  }
  const out = await page.evaluate(() => {
    const texts = (id) => [...document.querySelectorAll(`#${id} tr`)].map((tr) => [...tr.children].map((c) => c.textContent));
    const problem = document.getElementById('problem');
    return {
      result: window.nklut.result,
      download: document.getElementById('download').getAttribute('download'),
      problem: problem.hidden ? null : problem.textContent,
      status: document.getElementById('status').textContent,
      tables: { timing: texts('timing'), errors: texts('errors'), effects: texts('effects'), modules: texts('modules') },
      chart_bars: document.querySelectorAll('#chart rect').length,
      title: document.title,
      incomplete: document.getElementById('incomplete').hidden ? null : document.getElementById('incomplete').textContent,
      hidden_note: document.getElementById('hidden-note').hidden ? null : document.getElementById('hidden-note').textContent,
      layout: {
        viewport: window.innerWidth,
        scroll_width: document.documentElement.scrollWidth,
        boxes: [...document.querySelectorAll('.scroll, .chart')].map((b) => ({ id: b.firstElementChild ? b.firstElementChild.id || b.id : b.id, width: b.getBoundingClientRect().width, right: b.getBoundingClientRect().right })),
      },
      error_bars: document.querySelectorAll('#error-chart rect').length,
    };
  });
  if (screenshot) {
    await page.setViewport({ width: 1000, height: 800 });
    await page.screenshot({ path: screenshot, fullPage: true });
  }
  if (rampSpec) {
    const [index, method, width, height, view] = rampSpec.split(',');
    out.ramp = await page.evaluate((i, m, w, h, v) => window.nklut.ramp(i, m, w, h, v), Number(index), method, Number(width), Number(height), view);
  }
  if (effectFrame !== null) {
    out.effect_frame = await page.evaluate((i) => window.nklut.effectFrame(i), Number(effectFrame));
  }
  if (twinFile) {
    const input = JSON.parse(readFileSync(twinFile, 'utf8'));
    out.twin = await page.evaluate((input) => {
      const t = window.nklut.twins;
      const summary = new t.ErrorSummary();
      const frame = t.compare(input.method, input.reference);
      summary.add(frame);
      summary.add(t.compare(input.reference, input.reference));
      const [median, iqr] = t.medianAndIqr(input.samples);
      const permutation = t.permutation(input.seed, input.n);
      const resolution = t.resolutionNs(input.readings.map((r) => BigInt(r)), 1);
      return { frame, summary_mean: summary.meanRelative(), median, iqr, permutation, resolution };
    }, input);
  }
  out.console = console_;
  writeFileSync(outPath, JSON.stringify(out));
} catch (error) {
  fail(error.stack || error.message);
} finally {
  clearTimeout(timer);
  if (server) server.close();
  await browser.close().catch(() => {});
  rmSync(profile, { recursive: true, force: true });
}
