#!/usr/bin/env node
// run-page.mjs PAGE DATA_DIR [--query K=V]... [--screenshot PNG] [--size WxH] [--browser PATH] [--timeout SECONDS]
//
// Opens PAGE (an .html file in this folder) in Debian's chromium, headless, through
// puppeteer-core, with WebGL 2 on SwiftShader (Chromium's CPU GL), and prints what the page
// reports. Everything is served over HTTP on 127.0.0.1 (an ephemeral port):
//   /            this folder: the pages and node_modules (three, 3d-tiles-renderer), which the
//                pages import through an import map
//   /data/       DATA_DIR: the files under test (a VAT folder, a world, ...)
// The page's query string carries each --query K=V. The page sets `window.consumerDone` to a
// promise of a JSON-able object (its report); a page that throws, logs a console error, or
// requests a file that fails, fails the run.
//
// Prints one JSON line on stdout: {ok, result, consoleErrors, pageErrors, failedRequests,
// seconds}. Exit 0 when the page finished without error (whatever its result says: the caller
// checks the result); exit 1 otherwise, with a one-line reason on stderr; exit 2 on bad
// arguments. --screenshot PNG writes the viewport as a picture.

import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import process from 'node:process';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.png': 'image/png', '.exr': 'image/x-exr',
  '.bin': 'application/octet-stream', '.wasm': 'application/wasm', '.css': 'text/css',
};

function usage(message) {
  process.stderr.write(`run-page: ${message}\nusage: run-page.mjs PAGE DATA_DIR [--query K=V]... ` +
    '[--screenshot PNG] [--size WxH] [--browser PATH] [--timeout SECONDS]\n');
  process.exit(2);
}

function parseArgs(argv) {
  const args = { page: null, data: null, query: new URLSearchParams(), screenshot: null, width: 640, height: 480,
    timeout: 120, browser: process.env.CHROMIUM || '/usr/bin/chromium' };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === '--query') {
      const kv = value();
      const eq = kv.indexOf('=');
      if (eq <= 0) usage(`--query wants K=V (got "${kv}")`);
      args.query.append(kv.slice(0, eq), kv.slice(eq + 1));
    } else if (a === '--screenshot') args.screenshot = value();
    else if (a === '--size') {
      const m = /^(\d+)x(\d+)$/.exec(value());
      if (!m) usage('--size wants WxH');
      [args.width, args.height] = [Number(m[1]), Number(m[2])];
    } else if (a === '--browser') args.browser = value();
    else if (a === '--timeout') args.timeout = Number(value());
    else if (a.startsWith('--')) usage(`unknown option ${a}`);
    else if (args.page === null) args.page = a;
    else if (args.data === null) args.data = a;
    else usage(`unexpected argument "${a}"`);
  }
  if (args.page === null || args.data === null) usage('PAGE and DATA_DIR are required');
  if (!fs.existsSync(path.join(HERE, args.page))) usage(`${args.page} is not a page of ${HERE}`);
  if (!fs.statSync(args.data, { throwIfNoEntry: false })?.isDirectory()) usage(`${args.data} is not a folder`);
  if (!(args.timeout > 0)) usage('--timeout wants a positive number of seconds');
  return args;
}

// Serves HERE at / and DATA_DIR at /data/; nothing outside them.
function serve(dataDir) {
  const roots = [['/data/', path.resolve(dataDir)], ['/', HERE]];
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    if (url === '/favicon.ico') {  // the browser asks for it by itself
      res.writeHead(204).end();
      return;
    }
    const [prefix, root] = roots.find(([p]) => url.startsWith(p));
    const file = path.join(root, url.slice(prefix.length));
    if (!file.startsWith(root) || !fs.statSync(file, { throwIfNoEntry: false })?.isFile()) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] || 'application/octet-stream' });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const started = performance.now();
  const server = await serve(args.data);
  const url = `http://127.0.0.1:${server.address().port}/${args.page}?${args.query}`;
  const browser = await puppeteer.launch({
    executablePath: args.browser, headless: true,
    args: [...(process.getuid?.() === 0 ? ['--no-sandbox'] : []), '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--ignore-gpu-blocklist', `--window-size=${args.width},${args.height}`],
  });
  const seen = { consoleErrors: [], pageErrors: [], failedRequests: [] };
  let result = null, failure = null;
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: args.width, height: args.height });
    page.on('console', (m) => { if (m.type() === 'error') seen.consoleErrors.push(m.text()); });
    page.on('pageerror', (e) => seen.pageErrors.push(String(e.message || e)));
    page.on('requestfailed', (r) => seen.failedRequests.push(`${r.url()}: ${r.failure()?.errorText}`));
    page.on('response', (r) => { if (r.status() >= 400) seen.failedRequests.push(`${r.url()}: HTTP ${r.status()}`); });
    page.setDefaultTimeout(args.timeout * 1000);
    await page.goto(url, { waitUntil: 'load' });
    await page.waitForFunction(() => window.consumerDone !== undefined);
    result = await page.evaluate(() => window.consumerDone);
    if (args.screenshot) await page.screenshot({ path: args.screenshot });
  } catch (e) {
    failure = String(e.message || e).split('\n')[0];
  } finally {
    await browser.close();
    server.close();
  }
  failure ??= seen.pageErrors[0] ?? seen.consoleErrors[0] ?? seen.failedRequests[0] ?? null;
  const report = { ok: failure === null, result, ...seen, seconds: Number(((performance.now() - started) / 1000).toFixed(2)) };
  process.stdout.write(`${JSON.stringify(report)}\n`);
  if (failure !== null) {
    process.stderr.write(`run-page: ${args.page}: ${failure}\n`);
    process.exit(1);
  }
}

main().catch((e) => {
  process.stderr.write(`run-page: ${String(e.message || e).split('\n')[0]}\n`);
  process.exit(1);
});
