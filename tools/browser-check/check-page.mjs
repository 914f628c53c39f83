#!/usr/bin/env node
// check-page.mjs FILE [--min-images N] [--min-svgs N] [--no-scripts] [--screenshot PNG] [--browser PATH] [--timeout SECONDS]
//
// Opens FILE (a self-contained page such as the demo's report.html) in Debian's chromium,
// headless, through puppeteer-core, and checks that it stands on its own:
//   - no console message of type error, no uncaught page error;
//   - no failed request, and no request other than the page itself and data: URIs (a page
//     that reaches for another file or the network is not self-contained);
//   - every <img> decoded (complete, naturalWidth > 0), and at least --min-images of them (0);
//   - every inline <svg> has drawn content (a path, polyline, rect, line or circle with a
//     non-empty geometry), and at least --min-svgs of them (0);
//   - with --no-scripts, no <script> element (the page must read without running code).
// --screenshot PNG writes the whole page as a picture. The browser is --browser, else
// $CHROMIUM, else /usr/bin/chromium; as root it runs with --no-sandbox.
//
// Prints one JSON line on stdout. Exit 0 when everything holds; otherwise exit 1 with a
// one-line reason on stderr (the JSON line, with "ok": false, still goes to stdout); exit 2 on
// bad arguments.

import fs from 'node:fs';
import path from 'node:path';
import process from 'node:process';
import { pathToFileURL } from 'node:url';
import puppeteer from 'puppeteer-core';

function usage(message) {
  process.stderr.write(`check-page: ${message}\nusage: check-page.mjs FILE [--min-images N] [--min-svgs N] ` +
    '[--no-scripts] [--screenshot PNG] [--browser PATH] [--timeout SECONDS]\n');
  process.exit(2);
}

function parseArgs(argv) {
  const args = { file: null, minImages: 0, minSvgs: 0, noScripts: false, screenshot: null, timeout: 60,
    browser: process.env.CHROMIUM || '/usr/bin/chromium' };
  const number = (name, text) => {
    const v = Number(text);
    if (!Number.isFinite(v) || v < 0) usage(`${name} needs a number >= 0 (got "${text}")`);
    return v;
  };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === '--min-images') args.minImages = number(a, value());
    else if (a === '--min-svgs') args.minSvgs = number(a, value());
    else if (a === '--no-scripts') args.noScripts = true;
    else if (a === '--screenshot') args.screenshot = value();
    else if (a === '--browser') args.browser = value();
    else if (a === '--timeout') args.timeout = number(a, value());
    else if (a.startsWith('--')) usage(`unknown option ${a}`);
    else if (args.file === null) args.file = a;
    else usage(`one FILE only (got "${a}" too)`);
  }
  if (args.file === null) usage('FILE is missing');
  if (!fs.existsSync(args.file)) usage(`${args.file} does not exist`);
  return args;
}

// What the page did while loading: console errors, page errors, requests and their failures.
function watch(page, pageUrl) {
  const seen = { consoleErrors: [], pageErrors: [], failedRequests: [], foreignRequests: [], requests: 0 };
  page.on('console', (m) => { if (m.type() === 'error') seen.consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => seen.pageErrors.push(String(e.message || e)));
  page.on('requestfailed', (r) => seen.failedRequests.push(`${r.url().slice(0, 120)}: ${r.failure()?.errorText}`));
  page.on('request', (r) => {
    seen.requests += 1;
    const url = r.url();
    if (url !== pageUrl && !url.startsWith('data:')) seen.foreignRequests.push(url.slice(0, 120));
  });
  return seen;
}

// Runs in the page: every image's decode state and every SVG's drawn elements.
function inspectPage() {
  const images = [...document.images].map((img) => ({
    alt: img.alt, complete: img.complete, width: img.naturalWidth, height: img.naturalHeight }));
  const drawn = 'path[d]:not([d=""]), polyline[points]:not([points=""]), rect, line, circle';
  const svgs = [...document.querySelectorAll('svg')].map((svg) => ({
    label: svg.getAttribute('aria-label') || '', drawn: svg.querySelectorAll(drawn).length,
    box: svg.getBoundingClientRect().width * svg.getBoundingClientRect().height }));
  return { title: document.title, images, svgs, scripts: document.scripts.length };
}

function verdict(args, seen, page) {
  const problems = [];
  if (seen.consoleErrors.length) problems.push(`console error: ${seen.consoleErrors[0]}`);
  if (seen.pageErrors.length) problems.push(`page error: ${seen.pageErrors[0]}`);
  if (seen.failedRequests.length) problems.push(`failed request: ${seen.failedRequests[0]}`);
  if (seen.foreignRequests.length) problems.push(`request outside the page: ${seen.foreignRequests[0]}`);
  const broken = page.images.filter((i) => !i.complete || i.width <= 0);
  if (broken.length) problems.push(`${broken.length} image(s) did not decode, the first "${broken[0].alt}"`);
  if (page.images.length < args.minImages) problems.push(`${page.images.length} images, fewer than ${args.minImages}`);
  const empty = page.svgs.filter((s) => s.drawn === 0 || s.box <= 0);
  if (empty.length) problems.push(`${empty.length} SVG(s) draw nothing, the first "${empty[0].label}"`);
  if (page.svgs.length < args.minSvgs) problems.push(`${page.svgs.length} SVGs, fewer than ${args.minSvgs}`);
  if (args.noScripts && page.scripts > 0) problems.push(`${page.scripts} <script> element(s)`);
  return problems;
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const started = performance.now();
  const root = typeof process.getuid === 'function' && process.getuid() === 0;
  const browser = await puppeteer.launch({
    executablePath: args.browser, headless: true, timeout: args.timeout * 1000,
    args: [...(root ? ['--no-sandbox'] : []), '--disable-gpu', '--disable-dev-shm-usage', '--no-first-run'],
  });
  let result;
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1280, height: 900 });
    const url = pathToFileURL(path.resolve(args.file)).href;
    const seen = watch(page, url);
    await page.goto(url, { waitUntil: 'load', timeout: args.timeout * 1000 });
    const found = await page.evaluate(inspectPage);
    if (args.screenshot) await page.screenshot({ path: args.screenshot, fullPage: true });
    const problems = verdict(args, seen, found);
    result = { ok: problems.length === 0, file: args.file, title: found.title, images: found.images.length,
      svgs: found.svgs.length, scripts: found.scripts, requests: seen.requests, problems, seconds: +((performance.now() - started) / 1000).toFixed(2) };
  } finally {
    await browser.close();
  }
  process.stdout.write(JSON.stringify(result) + '\n');
  if (!result.ok) {
    process.stderr.write(`check-page: ${result.problems.join('; ')}\n`);
    process.exit(1);
  }
}

main().catch((e) => {
  process.stdout.write(JSON.stringify({ ok: false, problems: [String(e.message || e)] }) + '\n');
  process.stderr.write(`check-page: ${String(e.message || e).split('\n')[0]}\n`);
  process.exit(1);
});
