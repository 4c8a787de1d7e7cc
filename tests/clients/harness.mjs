// The browser harness of the client scripts (render_gltf.mjs, render_lut.mjs): one run bounded
// by a deadline (each step through `bounded`, and a watchdog that stops the process 5 s after
// the deadline whatever hangs), a static HTTP server on 127.0.0.1 (port chosen by the system)
// that serves the script's mounts and nothing outside them, headless Chromium driven by
// puppeteer-core over a pipe (WebGL2 through SwiftShader, a fresh profile under $TMPDIR) whose
// page may fetch nothing but that server, and the shutdown that closes — or kills — the
// browser, stops the server and removes the profile, on success and on failure alike.
//
// three.js and puppeteer-core are taken from $NKLUT_TEST_DEPS/npm/node_modules (default
// .test-deps/ at the repository's root), Chromium from $NKLUT_CHROMIUM (default
// /usr/bin/chromium); `bash scripts/test-deps` installs them. Messages go to stderr, each
// prefixed with the script's name.

import { createServer } from 'node:http';
import { createRequire } from 'node:module';
import { mkdtempSync, readFileSync, rmSync, statSync, createReadStream } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

/** This folder (tests/clients/) and the repository's root. */
export const here = dirname(fileURLToPath(import.meta.url));
export const root = resolve(here, '..', '..');
const deps = process.env.NKLUT_TEST_DEPS ? resolve(process.env.NKLUT_TEST_DEPS) : join(root, '.test-deps');
/** The installed npm packages (three, puppeteer-core). */
export const modules = join(deps, 'npm', 'node_modules');
const chromiumPath = process.env.NKLUT_CHROMIUM || '/usr/bin/chromium';

export const sleep = (ms) => new Promise((resolveSleep) => setTimeout(resolveSleep, ms));

/** The content type of a served file, by its extension. */
export const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.json': 'application/json',
  '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream',
  '.png': 'image/png',
  '.exr': 'image/x-exr',
  '.jpg': 'image/jpeg',
  '.ktx2': 'image/ktx2',
};

/**
 * Checks that the script's own `input` ([what, path]) and the test dependencies (three.js,
 * puppeteer-core, Chromium) exist; returns three.js's version and puppeteer-core.
 */
export function loadDependencies(input) {
  const needed = [
    input,
    ['three.js', join(modules, 'three', 'package.json')],
    ['puppeteer-core', join(modules, 'puppeteer-core', 'package.json')],
    ['Chromium', chromiumPath],
  ];
  needed.forEach(([what, path], i) => {
    try {
      statSync(path);
    } catch {
      throw new Error(`${what} is missing at ${path}${i === 0 ? '' : ': run `bash scripts/test-deps`'}`);
    }
  });
  const threeVersion = JSON.parse(readFileSync(join(modules, 'three', 'package.json'), 'utf8')).version;
  const require = createRequire(join(modules, 'index.js'));
  return { threeVersion, puppeteer: require('puppeteer-core') };
}

/**
 * The file a request path names under one of `mounts`, or null. A mount is [prefix, target]:
 * a prefix ending in '/' serves the folder `target` (which ends in the path separator) and
 * nothing outside it; any other prefix serves the one file `target`.
 */
export function servedFile(mounts, urlPath) {
  let path;
  try {
    path = decodeURIComponent(urlPath.split('?')[0]);
  } catch {
    return null;
  }
  for (const [prefix, target] of mounts) {
    if (path === prefix) return target;
    if (prefix.endsWith('/') && path.startsWith(prefix)) {
      const file = resolve(target, '.' + sep + path.slice(prefix.length));
      if (!file.startsWith(target)) return null; // no way out of the served folder
      return file;
    }
  }
  return null;
}

/** A static HTTP server on 127.0.0.1 for `mounts`: GET of a served file, 404 for the rest. */
function serve(mounts) {
  return new Promise((resolveServer, reject) => {
    const s = createServer((request, response) => {
      const file = servedFile(mounts, request.url);
      let size = -1;
      try {
        if (file && statSync(file).isFile()) size = statSync(file).size;
      } catch {
        // missing: 404 below
      }
      if (request.method !== 'GET' || size < 0) {
        response.writeHead(404, { 'content-type': 'text/plain' });
        response.end(`not found: ${request.url}`);
        return;
      }
      response.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream', 'content-length': size, 'cache-control': 'no-store' });
      createReadStream(file).pipe(response);
    });
    s.on('error', reject);
    s.listen(0, '127.0.0.1', () => resolveServer(s));
  });
}

/**
 * One bounded browser run of the script `name` (the prefix of its messages). Made once the
 * arguments are read: the deadline and the watchdog start then.
 */
export class BrowserRun {
  constructor(name, timeoutSeconds) {
    this.name = name;
    this.timeoutSeconds = timeoutSeconds;
    this.started = Date.now();
    this.deadline = this.started + timeoutSeconds * 1000;
    this.browser = null;
    this.server = null;
    this.profile = null;
    this.dying = false;
    /** Set by `open`: the server's address, the page, and what the page reported. */
    this.origin = null;
    this.page = null;
    this.problems = [];
    // A hard stop a little after the deadline, whatever is hanging.
    this.watchdog = setTimeout(() => this.die(`timed out after ${timeoutSeconds} s (watchdog)`), timeoutSeconds * 1000 + 5000);
  }

  /** A message on stderr, prefixed with the script's name. */
  log(message) {
    console.error(`${this.name}: ${message}`);
  }

  /** What is left of the run in ms, at least 1 s: the timeout of one browser step. */
  left() {
    return Math.max(this.deadline - Date.now(), 1000);
  }

  /** `promise`, or a rejection naming `what` once the run's deadline has passed. */
  bounded(promise, what) {
    let timer;
    const timeout = new Promise((_, reject) => {
      timer = setTimeout(() => reject(new Error(`timed out after ${this.timeoutSeconds} s while ${what}`)), Math.max(this.deadline - Date.now(), 0));
    });
    return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
  }

  /** For `.catch`: rethrows `error` with what the page has reported so far. */
  withProblems = (error) => {
    throw new Error(`${error.message}${this.problems.length ? `; ${this.problems.join('; ')}` : ''}`);
  };

  /**
   * Closes Chromium — asking it to close when `graceful`, else (or when that takes over 5 s)
   * killing its process group (puppeteer starts it as a group leader) — then the server and
   * the profile.
   */
  async shutDown(graceful) {
    const child = this.browser?.process();
    if (this.browser && graceful) await Promise.race([this.browser.close().catch(() => {}), sleep(5000)]);
    this.browser = null;
    if (child && child.exitCode === null && child.signalCode === null) {
      const exited = new Promise((resolveExit) => child.once('exit', resolveExit));
      try {
        process.kill(-child.pid, 'SIGKILL');
      } catch {
        child.kill('SIGKILL');
      }
      await Promise.race([exited, sleep(5000)]);
    }
    this.server?.close();
    this.server = null;
    try {
      if (this.profile) rmSync(this.profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 });
    } catch (error) {
      this.log(`could not remove the browser profile ${this.profile}: ${error.message}`);
    }
    this.profile = null;
  }

  /** Says `message`, shuts everything down and exits 1 (once, whoever calls first). */
  async die(message) {
    if (this.dying) return;
    this.dying = true;
    this.log(message);
    setTimeout(() => process.exit(1), 15000).unref();
    await this.shutDown(false);
    process.exit(1);
  }

  /** The end of a successful run: Chromium closed, server stopped, profile removed. */
  async finish() {
    await this.shutDown(true);
    clearTimeout(this.watchdog);
  }

  /**
   * Starts the server for `mounts` and Chromium, and opens a page that collects console
   * errors and page errors in `problems` and may reach the server and nothing else (data: and
   * blob: URLs aside). `answer(request, url)` may answer a request itself first: it returns
   * true when it has (responded or aborted). Returns Chromium's version.
   */
  async open(puppeteer, mounts, answer = () => false) {
    this.server = await this.bounded(serve(mounts), 'starting the HTTP server');
    this.origin = `http://127.0.0.1:${this.server.address().port}`;
    this.profile = mkdtempSync(join(tmpdir(), `${this.name.replaceAll('_', '-')}-chromium-`));
    this.browser = await this.bounded(
      puppeteer.launch({
        executablePath: chromiumPath,
        headless: true,
        pipe: true,
        protocolTimeout: this.left(),
        timeout: this.left(),
        args: [
          '--headless=new',
          '--no-sandbox',
          '--disable-gpu-sandbox',
          '--use-angle=swiftshader',
          '--enable-unsafe-swiftshader',
          '--disable-background-networking',
          '--disable-component-update',
          '--no-first-run',
          '--disable-sync',
          '--disable-quic',
          `--user-data-dir=${this.profile}`,
        ],
      }),
      'starting Chromium',
    );
    const chromium = await this.bounded(this.browser.version(), 'asking Chromium its version');
    const page = await this.bounded(this.browser.newPage(), 'opening a page');
    this.page = page;
    page.on('console', (message) => {
      if (message.type() === 'error') this.problems.push(`console: ${message.text()}`);
    });
    page.on('pageerror', (error) => this.problems.push(`page error: ${error.message}`));
    await this.bounded(page.setRequestInterception(true), 'setting up request filtering');
    page.on('request', (request) => {
      const url = request.url();
      if (answer(request, url)) return;
      if (url.startsWith(this.origin + '/') || url.startsWith('data:') || url.startsWith('blob:')) request.continue();
      else {
        this.problems.push(`blocked request to ${url}`);
        request.abort();
      }
    });
    return chromium;
  }

  /** Opens the harness page at `path` of the server and waits until its three.js is loaded. */
  async loadHarness(path) {
    await this.bounded(this.page.goto(`${this.origin}${path}`, { waitUntil: 'load', timeout: this.left() }), 'loading the page');
    await this.bounded(this.page.waitForFunction('window.harness && window.harness.ready', { timeout: this.left() }), 'loading three.js').catch(this.withProblems);
  }
}
