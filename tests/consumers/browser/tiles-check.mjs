#!/usr/bin/env node
// tiles-check.mjs REPORT TILESET --view far|street [--tile I_J] [--screenshot PNG] [--clear RRGGBB]
// tiles-check.mjs --solid-png PNG WxH RRGGBB      (writes a picture of one colour: the self-test's blank screenshot)
//
// Checks what tiles.html (3d-tiles-renderer in chromium) reported for a world, with code of its
// own: REPORT is the JSON line run-page.mjs printed, TILESET the world's tileset.json, read here
// and composed with its transforms independently of the reader (plain arithmetic, no three.js).
//   - the page ran: no page error, console error or failed request, loading settled, and the
//     reader raised no load-error
//   - it loaded what the view needs: far (with the camera where the reader must stop at the top
//     HLOD: beyond the distance where its geometricError reaches 16 px, within the root's), the
//     topmost HLOD content(s) loaded and visible, nothing else visible and no leaf tile
//     (tiles/*/city.glb) loaded; street, the tile's city.glb loaded and visible and none of its
//     HLOD ancestors visible (REPLACE)
//   - every tile of tileset.json has the bounding volume the reader computed, and it is the
//     tile's boundingVolume.box composed with the transforms from the root down (centre and
//     half-axes within 1 mm); the reader's bounding sphere holds that box's corners; it reports
//     no tile tileset.json lacks
//   - every content it loaded lies where its box says: the axis-aligned bounds of its meshes as
//     the reader placed them lie within 1 cm inside the tile's box and every ancestor's; a leaf's
//     box (the writer measures it from the content's own vertices) is tight, each face within
//     1 cm of the content (a moved box or swapped axes show); a content's frame origin is the
//     tile's extras.origin (plan metres, z 0)
//   - the screenshot is a picture: at least 5 % of its pixels differ from the clear colour, it
//     has at least 16 distinct colours, and no colour covers more than 95 % of it
// Prints one JSON line (what it measured, and "problems": every check that failed); exit 0 when
// all holds, else exit 1 with one line "tiles-check: FAIL: VIEW view: REASON" (the first
// problem) on stderr; exit 2 on bad arguments.

import fs from 'node:fs';
import process from 'node:process';
import zlib from 'node:zlib';

const VOLUME_TOLERANCE = 0.001;   // m: the reader's volume against the composed box (the page rounds to 0.1 mm)
const PLACE_TOLERANCE = 0.01;     // m: content against its box
const MIN_DIFFERENT = 0.05, MIN_COLOURS = 16, MAX_ONE_COLOUR = 0.95;

function usage(msg) {
  process.stderr.write(`tiles-check: ${msg}\nusage: tiles-check.mjs REPORT TILESET --view far|street [--tile I_J] [--screenshot PNG] [--clear RRGGBB]\n`);
  process.exit(2);
}

// ---- PNG: a small encoder (solid colour) and decoder (8-bit grey/RGB/RGBA/grey+alpha, not interlaced)
const CRC = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(buf) {
  let c = 0xffffffff;
  for (const b of buf) c = CRC[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function chunk(type, data) {
  const head = Buffer.alloc(8);
  head.writeUInt32BE(data.length, 0);
  head.write(type, 4, 'latin1');
  const crc = Buffer.alloc(4);
  crc.writeUInt32BE(crc32(Buffer.concat([head.subarray(4), data])), 0);
  return Buffer.concat([head, data, crc]);
}
function solidPng(file, w, h, rgb) {
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0), ihdr.writeUInt32BE(h, 4), ihdr[8] = 8, ihdr[9] = 2;
  const raw = Buffer.alloc((3 * w + 1) * h);
  for (let y = 0; y < h; ++y) for (let x = 0; x < w; ++x) raw.set(rgb, y * (3 * w + 1) + 1 + 3 * x);
  fs.writeFileSync(file, Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk('IHDR', ihdr),
    chunk('IDAT', zlib.deflateSync(raw)), chunk('IEND', Buffer.alloc(0))]));
}
function readPng(file) {
  const buf = fs.readFileSync(file);
  if (buf.length < 8 || buf.readUInt32BE(0) !== 0x89504e47) throw new Error(`${file} is not a PNG`);
  let at = 8, w = 0, h = 0, depth = 0, type = 0, interlace = 0;
  const idat = [];
  while (at + 8 <= buf.length) {
    const len = buf.readUInt32BE(at), kind = buf.toString('latin1', at + 4, at + 8), data = buf.subarray(at + 8, at + 8 + len);
    if (kind === 'IHDR') [w, h, depth, type, interlace] = [data.readUInt32BE(0), data.readUInt32BE(4), data[8], data[9], data[12]];
    else if (kind === 'IDAT') idat.push(data);
    else if (kind === 'IEND') break;
    at += 12 + len;
  }
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[type];
  if (depth !== 8 || !channels || interlace) throw new Error(`${file}: a PNG of bit depth ${depth}, colour type ${type}, interlace ${interlace} (this reader takes 8-bit grey, RGB, RGBA, not interlaced)`);
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = w * channels, out = Buffer.alloc(h * stride);
  for (let y = 0; y < h; ++y) {
    const filter = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const row = out.subarray(y * stride, (y + 1) * stride), prev = y ? out.subarray((y - 1) * stride, y * stride) : Buffer.alloc(stride);
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? row[i - channels] : 0, b = prev[i], c = i >= channels ? prev[i - channels] : 0;
      let p = line[i];
      if (filter === 1) p += a;
      else if (filter === 2) p += b;
      else if (filter === 3) p += (a + b) >> 1;
      else if (filter === 4) {
        const e = a + b - c, pa = Math.abs(e - a), pb = Math.abs(e - b), pc = Math.abs(e - c);
        p += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else if (filter !== 0) throw new Error(`${file}: unknown PNG filter ${filter}`);
      row[i] = p & 0xff;
    }
  }
  const rgb = (i) => (channels >= 3 ? [out[i * channels], out[i * channels + 1], out[i * channels + 2]] : [out[i * channels], out[i * channels], out[i * channels]]);
  return { w, h, rgb };
}

// ---- arguments
const argv = process.argv.slice(2);
if (argv[0] === '--solid-png') {
  const m = /^(\d+)x(\d+)$/.exec(argv[2] ?? ''), c = /^[0-9a-fA-F]{6}$/.exec(argv[3] ?? '');
  if (!argv[1] || !m || !c) usage('--solid-png PNG WxH RRGGBB');
  solidPng(argv[1], Number(m[1]), Number(m[2]), [0, 2, 4].map((k) => parseInt(c[0].slice(k, k + 2), 16)));
  process.exit(0);
}
const opt = { view: null, tile: null, screenshot: null, clear: '203040' };
const pos = [];
for (let i = 0; i < argv.length; ++i) {
  const a = argv[i], value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
  if (a === '--view') opt.view = value();
  else if (a === '--tile') opt.tile = value();
  else if (a === '--screenshot') opt.screenshot = value();
  else if (a === '--clear') opt.clear = value();
  else if (a.startsWith('--')) usage(`unknown option ${a}`);
  else pos.push(a);
}
if (pos.length !== 2) usage('REPORT and TILESET are required');
if (opt.view !== 'far' && opt.view !== 'street') usage('--view far or street');
if (opt.view === 'street' && !/^\d+_\d+$/.test(opt.tile ?? '')) usage('--view street needs --tile I_J');
if (!/^[0-9a-fA-F]{6}$/.test(opt.clear)) usage('--clear wants RRGGBB');

const out = { ok: false, view: opt.view };
const problems = [];      // what fails once the report and tileset.json are read: all of it is reported
const problem = (reason) => problems.push(reason);
function fail(reason) {   // the first problem, with how many more
  out.reason = reason;
  if (problems.length) out.problems = problems;
  process.stdout.write(`${JSON.stringify(out)}\n`);
  process.stderr.write(`tiles-check: FAIL: ${opt.view} view: ${reason}\n`);
  process.exit(1);
}

// ---- small vector arithmetic (column-major 4x4, as 3D Tiles writes transforms)
const IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
const mul = (a, b) => Array.from({ length: 16 }, (_, k) => {
  const col = Math.floor(k / 4), row = k % 4;
  let s = 0;
  for (let i = 0; i < 4; ++i) s += a[i * 4 + row] * b[col * 4 + i];
  return s;
});
const point = (m, p) => [0, 1, 2].map((r) => m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]);
const dir = (m, v) => [0, 1, 2].map((r) => m[r] * v[0] + m[4 + r] * v[1] + m[8 + r] * v[2]);
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const len = (a) => Math.hypot(...a);
const fmt = (v) => `[${v.map((x) => Number(x.toFixed(3))).join(', ')}]`;

// ---- the run and the report
let line;
try {
  line = JSON.parse(fs.readFileSync(pos[0], 'utf8').trim().split('\n').filter(Boolean).pop() ?? '');
} catch (e) {
  fail(`no report from run-page.mjs in ${pos[0]} (${e.message.split('\n')[0]})`);
}
const r = line.result;
out.page_s = line.seconds;
if (r?.errors?.length) fail(`the reader failed to load ${r.errors[0].url}: ${r.errors[0].error}${r.errors.length > 1 ? ` (and ${r.errors.length - 1} more)` : ''}`);
if (line.pageErrors?.length) fail(`the page threw: ${line.pageErrors[0]}`);
if (line.failedRequests?.length) fail(`a request failed: ${line.failedRequests[0]}`);
if (line.consoleErrors?.length) fail(`the page logged an error: ${line.consoleErrors[0]}`);
if (!line.ok || !r) fail('run-page.mjs did not finish the page');
if (r.error) fail(`the page failed: ${r.error.split('\n')[0]}`);
if (!r.settled) fail(`loading did not settle in ${r.settle_s} s (stats ${JSON.stringify(r.stats)})`);
if (!r.reader?.gl?.webgl2) fail(`the page had no WebGL 2 (renderer ${r.reader?.gl?.renderer})`);

// ---- tileset.json, composed here
let tileset;
try {
  tileset = JSON.parse(fs.readFileSync(pos[1], 'utf8'));
} catch (e) {
  fail(`cannot read ${pos[1]}: ${e.message}`);
}
const byPath = new Map(), byUri = new Map();
(function walk(tile, parentWorld, path, ancestors) {
  if (tile.transform && tile.transform.length !== 16) fail(`tileset.json: tile "${path}" has a transform of ${tile.transform.length} numbers`);
  // the root's transform when it turns is the world's place on the globe: the page works in the root's frame
  const globe = path === '' && Array.isArray(tile.transform) && [0, 1, 2, 4, 5, 6, 8, 9, 10].some((k, i) => tile.transform[k] !== IDENTITY[k]);
  const world = mul(parentWorld, globe ? IDENTITY : tile.transform ?? IDENTITY);
  const box = tile.boundingVolume?.box;
  if (!Array.isArray(box) || box.length !== 12) fail(`tileset.json: tile "${path}" has no boundingVolume.box of 12 numbers`);
  const centre = point(world, box.slice(0, 3));
  const axes = [0, 1, 2].map((k) => dir(world, box.slice(3 + 3 * k, 6 + 3 * k)));
  const extent = [0, 1, 2].map((i) => axes.reduce((s, a) => s + Math.abs(a[i]), 0));   // the box's AABB half-size
  const aligned = axes.every((a) => a.filter((x) => Math.abs(x) > 1e-9).length <= 1);
  const uri = tile.content?.uri ?? null;
  const info = { path, uri, world, centre, axes, lo: centre.map((c, i) => c - extent[i]), hi: centre.map((c, i) => c + extent[i]), aligned, ancestors, tile };
  byPath.set(path, info);
  if (uri) {
    if (byUri.has(uri)) fail(`tileset.json lists ${uri} twice`);
    byUri.set(uri, info);
  }
  (tile.children ?? []).forEach((c, i) => walk(c, world, path === '' ? `${i}` : `${path}.${i}`, [...ancestors, info]));
})(tileset.root, IDENTITY, '', []);
const isLeaf = (i) => /(^|\/)city\.glb$/.test(i.uri ?? '');
const isHlod = (i) => /^hlod\//.test(i.uri ?? '');
const topHlods = [...byUri.values()].filter((i) => isHlod(i) && !i.ancestors.some(isHlod)).map((i) => i.uri);
out.tileset = { tiles: byPath.size, contents: byUri.size, top_hlods: topHlods };

// ---- what the view must load
const loaded = new Set(r.loaded), visible = new Set(r.visible);
out.loaded = r.loaded, out.visible = r.visible;
if (opt.view === 'far') {
  if (!topHlods.length) fail('tileset.json has no HLOD content to show from afar');
  // the camera must stand where the reader has to stop at the top HLOD: far enough that its
  // error is under the reader's target (16 px), near enough that the content-less root's is not
  const { position, fov, height } = r.camera ?? {};
  if (!position || !fov || !height) fail('the report has no camera');
  const perMetre = 16 * 2 * Math.tan((fov * Math.PI) / 360) / height;
  const boxDistance = (i) => Math.hypot(...[0, 1, 2].map((k) => Math.max(i.lo[k] - position[k], 0, position[k] - i.hi[k])));
  for (const u of topHlods) {
    const i = byUri.get(u), d = boxDistance(i), low = i.tile.geometricError / perMetre;
    if (!(d > low)) problem(`the page put the far camera ${d.toFixed(1)} m from ${u}'s box, nearer than the ${low.toFixed(1)} m where the reader refines it`);
  }
  const root = byPath.get('');
  if (!root.uri) {
    const d = boxDistance(root), high = root.tile.geometricError / perMetre;
    if (!(d < high)) problem(`the page put the far camera ${d.toFixed(1)} m from the root's box, farther than the ${high.toFixed(1)} m where the reader stops refining the content-less root`);
  }
  for (const u of topHlods) {
    if (!loaded.has(u)) problem(`the top HLOD ${u} was not loaded (loaded: ${r.loaded.join(' ') || 'nothing'})`);
    if (!visible.has(u)) problem(`the top HLOD ${u} is loaded but not visible (visible: ${r.visible.join(' ') || 'nothing'})`);
  }
  const leaves = r.loaded.filter((u) => isLeaf(byUri.get(u) ?? { uri: u }));
  if (leaves.length) problem(`leaf tiles were loaded from afar: ${leaves.join(' ')}`);
  const others = r.visible.filter((u) => !topHlods.includes(u));
  if (others.length) problem(`more than the top HLOD is visible from afar: ${others.join(' ')}`);
} else {
  const uri = `tiles/${opt.tile}/city.glb`, info = byUri.get(uri);
  if (!info) fail(`tileset.json has no ${uri}`);
  if (r.expect?.tile !== uri) problem(`the page looked at ${r.expect?.tile}, not ${uri}`);
  if (!loaded.has(uri)) problem(`${uri} was not loaded (loaded: ${r.loaded.join(' ') || 'nothing'})`);
  if (!visible.has(uri)) problem(`${uri} is loaded but not visible (visible: ${r.visible.join(' ') || 'nothing'})`);
  const shown = info.ancestors.filter((a) => a.uri && visible.has(a.uri)).map((a) => a.uri);
  if (shown.length) problem(`${uri} is visible and so is its HLOD ancestor ${shown.join(' ')} (REPLACE not honoured)`);
}
for (const u of r.loaded) if (!byUri.has(u)) problem(`the reader loaded ${u}, which tileset.json does not list`);

// ---- the reader's bounding volumes against the composed boxes
const reported = new Map(r.tiles.map((t) => [t.path, t]));
let worstVolume = 0;
for (const [path, info] of byPath) {
  const t = reported.get(path);
  const name = info.uri ?? (path === '' ? 'the root tile' : `tile "${path}"`);
  if (!t?.obb) {
    problem(`the reader reports no bounding volume for ${name}`);
    continue;
  }
  if (t.uri !== info.uri) problem(`the reader's tile "${path}" has content ${t.uri}, tileset.json ${info.uri}`);
  const dc = dist(t.obb.center, info.centre);
  const da = Math.max(...[0, 1, 2].map((k) => dist(t.obb.half_axes[k], info.axes[k])));
  worstVolume = Math.max(worstVolume, dc, da);
  if (dc > VOLUME_TOLERANCE || da > VOLUME_TOLERANCE)
    problem(`the reader's box of ${name} (centre ${fmt(t.obb.center)}, half-axes ${t.obb.half_axes.map(fmt).join(' ')}) is not tileset.json's composed with its transforms (centre ${fmt(info.centre)}, half-axes ${info.axes.map(fmt).join(' ')})`);
  if (t.sphere) {   // it must hold the box's eight corners
    let reach = 0;
    for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1]) {
      const corner = info.centre.map((c, i) => c + sx * info.axes[0][i] + sy * info.axes[1][i] + sz * info.axes[2][i]);
      reach = Math.max(reach, dist(corner, t.sphere.center));
    }
    if (reach > t.sphere.radius + VOLUME_TOLERANCE)
      problem(`the reader's bounding sphere of ${name} (centre ${fmt(t.sphere.center)}, radius ${t.sphere.radius}) does not hold its box: a corner is ${reach.toFixed(3)} m from its centre`);
  }
}
for (const path of reported.keys()) if (!byPath.has(path)) problem(`the reader reports a tile "${path}" that tileset.json does not have`);
out.volumes = { tiles: byPath.size, worst_m: Number(worstVolume.toFixed(5)) };

// ---- where the reader placed each loaded content
const contents = {};
for (const t of r.tiles) {
  if (t.state !== 'LOADED' || !t.uri) continue;
  const info = byUri.get(t.uri), c = t.content;
  if (!c?.min || !(c.triangles > 0)) {
    problem(`${t.uri} is loaded but has no triangles`);
    continue;
  }
  const where = `(content ${fmt(c.min)}..${fmt(c.max)}, box ${fmt(info.lo)}..${fmt(info.hi)})`;
  const outside = (b) => Math.max(...[0, 1, 2].map((i) => Math.max(b.lo[i] - c.min[i], c.max[i] - b.hi[i])));
  const own = outside(info);
  if (own > PLACE_TOLERANCE) problem(`the reader places ${t.uri} up to ${own.toFixed(3)} m outside its boundingVolume.box ${where}`);
  for (const a of info.ancestors) {
    const o = outside(a);
    if (o > PLACE_TOLERANCE) problem(`the reader places ${t.uri} up to ${o.toFixed(3)} m outside its ancestor ${a.uri ?? `"${a.path}"`}'s box (content ${fmt(c.min)}..${fmt(c.max)}, ancestor box ${fmt(a.lo)}..${fmt(a.hi)})`);
  }
  const m = { triangles: c.triangles, outside_m: Number(own.toFixed(4)) };
  if (isLeaf(info) && info.aligned) {
    const slack = Math.max(...[0, 1, 2].map((i) => Math.max(c.min[i] - info.lo[i], info.hi[i] - c.max[i])));
    m.slack_m = Number(slack.toFixed(4));
    if (slack > PLACE_TOLERANCE) problem(`${t.uri}'s boundingVolume.box is ${slack.toFixed(3)} m larger than the content the reader placed on some face ${where}`);
  }
  const origin = info.tile.extras?.origin;
  if (Array.isArray(origin) && c.origin) {
    const d = dist(c.origin, [origin[0], origin[1], 0]);
    if (d > PLACE_TOLERANCE) problem(`the reader puts ${t.uri}'s frame origin at ${fmt(c.origin)}, not at its extras.origin ${fmt(origin)}`);
  }
  contents[t.uri] = m;
}
out.contents = contents;

// ---- the screenshot
if (opt.screenshot) {
  let png;
  try {
    png = readPng(opt.screenshot);
  } catch (e) {
    fail(`screenshot: ${e.message}`);
  }
  const clear = [0, 2, 4].map((k) => parseInt(opt.clear.slice(k, k + 2), 16));
  const counts = new Map();
  let different = 0;
  const n = png.w * png.h;
  for (let i = 0; i < n; ++i) {
    const [R, G, B] = png.rgb(i);
    if (Math.max(Math.abs(R - clear[0]), Math.abs(G - clear[1]), Math.abs(B - clear[2])) > 8) different++;
    const key = (R << 16) | (G << 8) | B;
    counts.set(key, (counts.get(key) ?? 0) + 1);
  }
  const top = Math.max(...counts.values()) / n;
  out.screenshot = { size: [png.w, png.h], not_clear: Number((different / n).toFixed(4)), colours: counts.size, most_common: Number(top.toFixed(4)) };
  if (different / n < MIN_DIFFERENT) problem(`screenshot ${opt.screenshot}: only ${(100 * different / n).toFixed(2)} % of its pixels differ from the clear colour #${opt.clear}`);
  if (counts.size < MIN_COLOURS) problem(`screenshot ${opt.screenshot}: only ${counts.size} distinct colours`);
  if (top > MAX_ONE_COLOUR) problem(`screenshot ${opt.screenshot}: one colour covers ${(100 * top).toFixed(1)} % of it`);
}

if (problems.length) fail(problems[0] + (problems.length > 1 ? ` (and ${problems.length - 1} more: see "problems" in the JSON line)` : ''));
out.ok = true;
process.stdout.write(`${JSON.stringify(out)}\n`);
