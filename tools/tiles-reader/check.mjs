#!/usr/bin/env node
// check.mjs WORLD_DIR [--tile I_J[,I_J...]|all] [--far-distance M] [--timeout SECONDS]
//
// Loads WORLD_DIR/tileset.json (written by `dawnforge world build`) in a public OGC 3D Tiles
// reader, NASA-AMMOS' `3d-tiles-renderer` (TilesRenderer on three.js), headless in Node: no
// browser, no WebGL. WORLD_DIR is served over HTTP on 127.0.0.1 (an ephemeral port) so the
// reader's own `fetch` path loads the tileset and its GLBs, which its GLTFLoader parses.
//
// Two kinds of view, each with a fresh TilesRenderer driven by tiles.update() until loading
// settles (camera: 60 degree vertical field of view, 1920 x 1080, the reader's default error
// target of 16 px):
//   far    - high above the world looking down, by default midway in the band of heights where
//            the reader must stop at the top HLOD (--far-distance M overrides): the topmost HLOD
//            content(s) (hlod/*.glb) must be loaded and visible, and no leaf tile
//            (tiles/*/city.glb) loaded or visible.
//   street - 10 m above the highest point of one tile looking down (--tile I_J, several, or
//            all; default the tile nearest the world's middle): that tile's city.glb must be
//            loaded and visible and none of its HLOD ancestors visible (REPLACE refinement).
// For every content the reader loaded, the world-space vertices of its meshes, as the reader
// placed them (its y-up -> z-up turn of glTF, then the tiles' transforms), must lie within 1 cm
// inside the tile's boundingVolume.box and inside every ancestor's box, both composed here from
// tileset.json independently of the reader; a leaf's box, which the writer takes from the
// content's own vertices, must also be tight (each face within 1 cm of the content), which
// catches mirrored or swapped axes; and the reader's placement of the content's origin must be
// the tile's extras.origin (plan metres).
//
// Prints one JSON line on stdout. Exit 0 when everything holds; otherwise exit 1 with a
// one-line reason on stderr (the JSON line, with "ok": false, still goes to stdout); exit 2 on
// bad arguments.

import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import process from 'node:process';

const started = performance.now();
const TOLERANCE = 0.01;          // metres
const WIDTH = 1920, HEIGHT = 1080, FOV = 60;

// ---- arguments -------------------------------------------------------------------------
function usage(msg) {
	process.stderr.write(`check.mjs: ${msg}\nusage: node check.mjs WORLD_DIR [--tile I_J[,I_J...]|all] [--far-distance M] [--timeout SECONDS]\n`);
	process.exit(2);
}
const args = process.argv.slice(2);
let worldDir = null, timeoutS = 60, farDistanceArg = null;
const tileArgs = [];
for (let i = 0; i < args.length; i++) {
	const a = args[i];
	if (a === '--tile') tileArgs.push(...String(args[++i] ?? '').split(',').filter(Boolean));
	else if (a === '--timeout') timeoutS = Number(args[++i]);
	else if (a === '--far-distance') farDistanceArg = Number(args[++i]);
	else if (a.startsWith('--')) usage(`unknown option ${a}`);
	else if (worldDir === null) worldDir = a;
	else usage(`unexpected argument ${a}`);
}
if (!worldDir) usage('WORLD_DIR is required');
if (!(timeoutS > 0)) usage('--timeout wants a positive number');
if (farDistanceArg !== null && !(farDistanceArg > 0)) usage('--far-distance wants a positive number of metres');
worldDir = path.resolve(worldDir);

// ---- result / failure --------------------------------------------------------------------
const result = { ok: false, world: worldDir, reader: {}, tileset: {}, views: {}, reader_messages: [] };
const messages = new Map();      // what the library logs, deduplicated, with counts
let server = null;

function finish(reason) {
	if (reason) reason = String(reason).replace(/\s*\n\s*/g, ' ');
	result.ok = !reason;
	if (reason) result.reason = reason;
	result.reader_messages = [...messages.entries()].map(([text, count]) => ({ text, count }));
	result.http_requests = requests.length;
	result.http_failures = requests.filter(r => r.status !== 200);
	result.run_s = Number(((performance.now() - started) / 1000).toFixed(2));
	process.stdout.write(JSON.stringify(result) + '\n');
	if (reason) process.stderr.write(`check.mjs: FAIL: ${reason}\n`);
	if (server) server.close();
	process.exit(reason ? 1 : 0);
}
class Failure extends Error {}
const fail = msg => { throw new Failure(msg); };

// ---- capture the library's console output (it goes into the JSON, not onto the terminal) --
for (const level of ['log', 'info', 'warn', 'error', 'debug']) {
	console[level] = (...parts) => {
		const text = `${level}: ` + parts.map(p => (p instanceof Error ? `${p.name}: ${p.message}` : String(p))).join(' ');
		messages.set(text, (messages.get(text) || 0) + 1);
	};
}

// ---- a tiny static HTTP server over WORLD_DIR ------------------------------------------------
const requests = [];
function serve(root) {
	return new Promise((resolve, reject) => {
		const s = http.createServer((req, res) => {
			// WORLD_DIR is served under /world/ (a tileset at a server's root makes this reader
			// ask for "//hlod/..."; under a folder it asks for "/world/hlod/...")
			let rel = req.url.split('?')[0];
			try { rel = decodeURIComponent(rel); } catch { /* keep it as sent */ }
			const entry = { path: rel, status: 200 };
			requests.push(entry);
			const file = rel.startsWith('/world/') ? path.resolve(root, '.' + rel.slice('/world'.length)) : null;
			if (!file || !file.startsWith(root + path.sep)) { entry.status = 404; res.writeHead(404).end(); return; }
			fs.readFile(file, (err, data) => {
				if (err) { entry.status = 404; res.writeHead(404).end(); return; }
				const type = file.endsWith('.json') ? 'application/json' : file.endsWith('.glb') ? 'model/gltf-binary' : 'application/octet-stream';
				res.writeHead(200, { 'Content-Type': type, 'Content-Length': data.length });
				res.end(data);
			});
		});
		s.on('error', reject);
		s.listen(0, '127.0.0.1', () => resolve(s));
	});
}

// ---- headless shims: the reader resolves URLs against window.location and schedules its
// queues with requestAnimationFrame; three's GLTFLoader fetches a material's picture (a tile's
// textures/*.png, over HTTP like the rest) and decodes it with createImageBitmap, which Node
// lacks: a picture is fetched, not decoded (nothing is drawn here).
function installShims(base) {
	if (typeof globalThis.window === 'undefined') globalThis.window = { location: { href: base } };
	if (typeof globalThis.self === 'undefined') globalThis.self = globalThis;
	if (typeof globalThis.ImageBitmap === 'undefined')
		globalThis.ImageBitmap = class ImageBitmap { constructor(bytes) { this.width = 1; this.height = 1; this.bytes = bytes; } close() {} };
	if (typeof globalThis.createImageBitmap === 'undefined')
		globalThis.createImageBitmap = async (blob) => new globalThis.ImageBitmap(blob.size);
	if (typeof globalThis.requestAnimationFrame === 'undefined') {
		globalThis.requestAnimationFrame = cb => setTimeout(() => cb(performance.now()), 1);
		globalThis.cancelAnimationFrame = h => clearTimeout(h);
	}
}

const sleep = ms => new Promise(r => setTimeout(r, ms));

async function main() {
	// ---- read tileset.json ourselves: the reference the reader's placement is checked against
	const tilesetPath = path.join(worldDir, 'tileset.json');
	let tileset;
	try { tileset = JSON.parse(fs.readFileSync(tilesetPath, 'utf8')); }
	catch (e) { fail(`cannot read ${tilesetPath}: ${e.message}`); }

	const THREE = await import('three');
	const { Matrix3, Matrix4, Vector3, PerspectiveCamera } = THREE;

	// The root's transform when it turns: the world's place on the globe (east-north-up to ECEF).
	// The check works in the root's own frame (plan metres), as a reader without a globe does:
	// the reader's group gets the inverse.
	const globe = (() => {
		const t = tileset.root.transform;
		if (!Array.isArray(t) || t.length !== 16) return null;
		return new Matrix3().setFromMatrix4(new Matrix4().fromArray(t)).equals(new Matrix3()) ? null : new Matrix4().fromArray(t);
	})();

	// uri -> { world (Matrix4: tile frame -> tileset frame), box, kind, depth, ancestors, json }
	const byUri = new Map();
	const leaves = [];
	const topHlods = [];
	let maxDepth = 0;
	(function walk(tile, parentWorld, depth, ancestors) {
		const local = new Matrix4();
		if (tile.transform) {
			if (tile.transform.length !== 16) fail(`a tile's transform has ${tile.transform.length} numbers, not 16`);
			if (!(depth === 0 && globe)) local.fromArray(tile.transform);   // column-major, as 3D Tiles writes it
		}
		const world = parentWorld.clone().multiply(local);
		const uri = tile.content?.uri ?? null;
		maxDepth = Math.max(maxDepth, depth);
		if (uri) {
			if (byUri.has(uri)) fail(`content uri ${uri} appears twice`);
			const kind = /^hlod\//.test(uri) ? 'hlod' : /city\.glb$/.test(uri) ? 'leaf' : 'other';
			const info = { uri, world, box: tile.boundingVolume?.box ?? null, kind, depth, ancestors, json: tile };
			byUri.set(uri, info);
			if (kind === 'leaf') leaves.push(info);
			if (kind === 'hlod' && !ancestors.some(a => byUri.get(a)?.kind === 'hlod')) topHlods.push(info);
		}
		for (const c of tile.children ?? []) walk(c, world, depth + 1, uri ? [...ancestors, uri] : ancestors);
	})(tileset.root, new Matrix4(), 0, []);
	result.tileset = {
		asset: tileset.asset, contents: byUri.size, leaves: leaves.length,
		hlods: [...byUri.values()].filter(i => i.kind === 'hlod').length, depth: maxDepth + 1,
		root_transform: tileset.root.transform ?? null, root_geometric_error: tileset.root.geometricError,
	};
	if (leaves.length === 0) fail('tileset.json has no leaf tile (tiles/*/city.glb)');
	for (const i of byUri.values()) if (!i.box || i.box.length !== 12) fail(`tile ${i.uri} has no boundingVolume.box of 12 numbers`);

	// ---- serve WORLD_DIR and load the reader
	server = await serve(worldDir);
	const base = `http://127.0.0.1:${server.address().port}/world/`;
	installShims(base);
	const { TilesRenderer, LOADED, FAILED } = await import('3d-tiles-renderer');
	const pkg = p => JSON.parse(fs.readFileSync(new URL(`./node_modules/${p}/package.json`, import.meta.url), 'utf8')).version;
	result.reader = { '3d-tiles-renderer': pkg('3d-tiles-renderer'), three: pkg('three'), node: process.version };

	// ---- geometry helpers
	const camTan = Math.tan(THREE.MathUtils.degToRad(FOV / 2));
	const sseDenominator = 2 * camTan / HEIGHT;   // as the reader computes it for a perspective camera
	const errorTarget = 16;                       // the reader's default, left as it is
	function worldBox(info) {                     // the OBB in the tileset frame
		const b = info.box, m = info.world;
		const c = new Vector3(b[0], b[1], b[2]).applyMatrix4(m);
		const linear = new Matrix3().setFromMatrix4(m);   // half-axes are directions: no translation
		const axes = [0, 1, 2].map(k => new Vector3(b[3 + 3 * k], b[4 + 3 * k], b[5 + 3 * k]).applyMatrix3(linear));
		return { c, axes };
	}
	function aabbOfObb({ c, axes }) {
		const lo = c.clone(), hi = c.clone();
		for (const a of axes) for (const k of ['x', 'y', 'z']) { lo[k] -= Math.abs(a[k]); hi[k] += Math.abs(a[k]); }
		return { lo, hi };
	}

	// The world-space vertices of a parsed content, as the reader placed them (its y-up -> z-up
	// turn of glTF and the tiles' transforms), with mesh and triangle counts.
	function collect(scene) {
		scene.updateMatrixWorld(true);
		let meshes = 0, triangles = 0, vertices = 0, other = 0;
		const lods = {};
		const chunks = [];
		scene.traverse(o => {
			if (!o.isMesh && !o.isLine && !o.isPoints) return;
			if (!o.isMesh) other++;
			const g = o.geometry, pos = g?.attributes?.position;
			if (!pos) return;
			if (o.isMesh) {
				meshes++;
				const tris = (g.index ? g.index.count : pos.count) / 3;
				triangles += tris;
				// dawnforge names a building's two meshes building_N_lod0 / _lod1 (both in the scene)
				const lod = (/_(lod\d+)$/.exec(o.name) || /_(lod\d+)$/.exec(o.parent?.name ?? '') || [])[1];
				if (lod) {
					lods[lod] ??= { meshes: 0, triangles: 0 };
					lods[lod].meshes++, lods[lod].triangles += tris;
				}
			}
			vertices += pos.count;
			const out = new Float64Array(pos.count * 3), v = new Vector3();
			for (let i = 0; i < pos.count; i++) v.fromBufferAttribute(pos, i).applyMatrix4(o.matrixWorld).toArray(out, 3 * i);
			chunks.push(out);
		});
		const lo = new Vector3(Infinity, Infinity, Infinity), hi = new Vector3(-Infinity, -Infinity, -Infinity), v = new Vector3();
		for (const c of chunks) for (let i = 0; i < c.length; i += 3) { v.fromArray(c, i); lo.min(v); hi.max(v); }
		return { meshes, triangles, vertices, other, lods, chunks, lo, hi };
	}
	// How the points sit in a tile's box: outside (how far they poke out of a face; > 0 is out)
	// and slack (the widest gap left between the points and a face), in metres.
	function fit(points, info) {
		const obb = worldBox(info);
		const halves = obb.axes.map(a => a.length());
		const units = obb.axes.map(a => a.clone().normalize());
		const uLo = [Infinity, Infinity, Infinity], uHi = [-Infinity, -Infinity, -Infinity];
		const cx = obb.c.x, cy = obb.c.y, cz = obb.c.z;
		for (const c of points.chunks) for (let i = 0; i < c.length; i += 3) {
			const dx = c[i] - cx, dy = c[i + 1] - cy, dz = c[i + 2] - cz;
			for (let k = 0; k < 3; k++) {
				const u = dx * units[k].x + dy * units[k].y + dz * units[k].z;
				if (u < uLo[k]) uLo[k] = u;
				if (u > uHi[k]) uHi[k] = u;
			}
		}
		const outside = Math.max(...[0, 1, 2].map(k => Math.max(uHi[k] - halves[k], -halves[k] - uLo[k])));
		const slack = Math.max(...[0, 1, 2].map(k => Math.max(halves[k] - uHi[k], uLo[k] + halves[k])));
		return { outside, slack, aabb: aabbOfObb(obb) };
	}
	const r4 = x => Number(x.toFixed(4));
	const bounds = (lo, hi) => ({ min: lo.toArray().map(r4), max: hi.toArray().map(r4) });

	// Checks one loaded content; returns its report.
	// A content not shown is outside the reader's group: measured under a stand-in for it.
	function checkContent(name, t, visible) {
		const scene = t.engineData?.scene, holder = new THREE.Group();
		const detached = scene && !scene.parent && globe;
		if (detached) {
			holder.matrixAutoUpdate = false;
			holder.matrix.copy(globe).invert();
			holder.add(scene);
			holder.updateMatrixWorld(true);
		}
		try {
			return checkContentInGroup(name, t, visible);
		} finally {
			if (detached) holder.remove(scene);
		}
	}

	function checkContentInGroup(name, t, visible) {
		const uri = t.content.uri;
		const info = byUri.get(uri);
		if (!info) fail(`${name} view: the reader loaded ${uri}, which tileset.json does not list`);
		const scene = t.engineData?.scene;
		if (!scene) fail(`${name} view: ${uri} is loaded but has no parsed scene`);
		if (visible && !scene.parent) fail(`${name} view: ${uri} is visible but not in the reader's scene graph`);
		const pts = collect(scene);
		if (pts.meshes === 0 || pts.triangles === 0) fail(`${name} view: ${uri} parsed to no triangles`);
		const own = fit(pts, info);
		const m = {
			visible, meshes: pts.meshes, triangles: pts.triangles, vertices: pts.vertices,
			...(pts.other ? { non_triangle_objects: pts.other } : {}),
			...(Object.keys(pts.lods).length ? { by_lod_suffix: pts.lods } : {}),
			...(info.kind === 'hlod' && info.json.extras?.triangles !== undefined ? { extras_triangles: info.json.extras.triangles } : {}),
			content_bounds: bounds(pts.lo, pts.hi), box_bounds: bounds(own.aabb.lo, own.aabb.hi),
			outside_box_m: r4(own.outside), box_slack_m: r4(own.slack),
		};
		const where = `(content ${JSON.stringify(m.content_bounds)}, box ${JSON.stringify(m.box_bounds)})`;
		if (own.outside > TOLERANCE) fail(`${name} view: ${uri}'s meshes reach ${m.outside_box_m} m outside its boundingVolume.box ${where}`);
		if (info.kind === 'leaf' && own.slack > TOLERANCE)
			fail(`${name} view: ${uri}'s boundingVolume.box is ${m.box_slack_m} m larger than its meshes on some face ${where}: the reader places the content elsewhere than the writer measured it`);
		// spatial coherence: a tile's content lies inside every ancestor's box too
		let worst = 0;
		for (const a of info.ancestors) {
			const f = fit(pts, byUri.get(a));
			worst = Math.max(worst, f.outside);
			if (f.outside > TOLERANCE) fail(`${name} view: ${uri}'s meshes reach ${r4(f.outside)} m outside its ancestor ${a}'s boundingVolume.box (content ${JSON.stringify(m.content_bounds)}, ancestor box ${JSON.stringify(bounds(f.aabb.lo, f.aabb.hi))})`);
		}
		if (info.ancestors.length) m.outside_ancestor_boxes_m = r4(worst);
		// the frame: the reader's placement of the content's origin against extras.origin (plan metres)
		const origin = info.json.extras?.origin;
		if (Array.isArray(origin)) {
			const o = new Vector3().applyMatrix4(scene.matrixWorld);
			const err = Math.hypot(o.x - origin[0], o.y - origin[1], o.z);
			m.frame_origin = o.toArray().map(r4);
			if (err > TOLERANCE) fail(`${name} view: the reader puts ${uri}'s frame origin at ${JSON.stringify(m.frame_origin)}, not at its extras.origin ${JSON.stringify(origin)} (plan metres)`);
		}
		return m;
	}

	// ---- one view: a fresh reader, a camera, update() until settled
	async function view(name, position, target, up) {
		const tiles = new TilesRenderer(base + 'tileset.json');
		tiles.lruCache.maxBytesSize = 8 * 2 ** 30;   // room for every content of a test world
		tiles.lruCache.minBytesSize = 6 * 2 ** 30;
		if (globe) {                                 // the root's frame, not the globe's
			tiles.group.matrixAutoUpdate = false;
			tiles.group.matrix.copy(globe).invert();
		}
		tiles.group.updateMatrixWorld(true);         // else identity: the scene's world frame is the tileset frame
		const errors = [];
		tiles.addEventListener('load-error', e => errors.push(`${e.url}: ${e.error?.message ?? e.error}`));
		const camera = new PerspectiveCamera(FOV, WIDTH / HEIGHT, 0.1, 1e6);
		camera.up.copy(up);
		camera.position.copy(position);
		camera.lookAt(target);
		camera.updateMatrixWorld(true);
		camera.updateProjectionMatrix();
		tiles.setCamera(camera);
		tiles.setResolution(camera, WIDTH, HEIGHT);

		const t0 = performance.now();
		let frames = 0, stable = 0, lastKey = '';
		for (;;) {
			tiles.update();
			frames++;
			if (errors.length) fail(`${name} view: the reader failed to load ${errors[0]}`);
			if (tiles.rootLoadingState === FAILED) fail(`${name} view: the reader failed to load tileset.json`);
			const s = tiles.stats;
			const idle = tiles.root && s.queued + s.downloading + s.parsing === 0 && tiles.loadProgress === 1 && !tiles.isLoading;
			const key = [...tiles.visibleTiles].map(t => t.content?.uri ?? '(no content)').sort().join(',') + `|${s.loaded}|${s.used}`;
			stable = idle && key === lastKey ? stable + 1 : 0;
			lastKey = key;
			if (stable >= 20) break;
			if (performance.now() - t0 > timeoutS * 1000)
				fail(`${name} view: loading did not settle in ${timeoutS} s (stats ${JSON.stringify(s)}, loadProgress ${tiles.loadProgress})`);
			await sleep(5);
		}
		tiles.group.updateMatrixWorld(true);

		const loaded = [], visible = [];
		const contents = {};
		tiles.traverse(t => {
			if (t.internal?.loadingState === LOADED && t.content?.uri) {
				const shown = tiles.visibleTiles.has(t);
				loaded.push(t.content.uri);
				if (shown) visible.push(t.content.uri);
				contents[t.content.uri] = checkContent(name, t, shown);
			}
			return false;
		}, null, false);
		for (const t of tiles.visibleTiles)
			if (t.content?.uri && !visible.includes(t.content.uri)) fail(`${name} view: ${t.content.uri} is visible but not loaded`);
		loaded.sort(), visible.sort();
		const r = {
			camera: { position: position.toArray().map(x => Number(x.toFixed(2))), target: target.toArray().map(x => Number(x.toFixed(2))), fov: FOV, resolution: [WIDTH, HEIGHT] },
			frames, settle_s: Number(((performance.now() - t0) / 1000).toFixed(2)),
			stats: { ...tiles.stats }, loaded, visible, contents,
		};
		tiles.dispose();
		return r;
	}

	// ---- (a) far above the world, looking down (north up)
	if (topHlods.length === 0) fail('tileset.json has no HLOD content (hlod/*.glb): nothing to expect from far away');
	const rootInfo = { box: tileset.root.boundingVolume.box,
		world: globe ? new Matrix4() : new Matrix4().fromArray(tileset.root.transform ?? new Matrix4().elements) };
	const rootAabb = aabbOfObb(worldBox(rootInfo));
	const topError = Math.max(...topHlods.map(i => i.json.geometricError));
	const rootError = tileset.root.content ? Infinity : tileset.root.geometricError;
	// distance (to the box) at which a tile's screen-space error equals the reader's target
	const dFor = e => e / (errorTarget * sseDenominator);
	const dLow = dFor(topError), dHigh = dFor(rootError);
	if (farDistanceArg === null && !(dLow < dHigh)) fail(`no camera height can show the top HLOD: its geometricError ${topError} is not below the content-less root's ${rootError}`);
	// by default midway (geometrically) in the band of heights where the reader must show the top HLOD
	const farDistance = farDistanceArg ?? (Number.isFinite(dHigh) ? Math.sqrt(dLow * dHigh) : 4 * dLow);
	const centre = rootAabb.lo.clone().add(rootAabb.hi).multiplyScalar(0.5);
	const far = await view('far',
		new Vector3(centre.x, centre.y, rootAabb.hi.z + farDistance), new Vector3(centre.x, centre.y, rootAabb.lo.z), new Vector3(0, 1, 0));
	far.camera.distance_band_m = [Number(dLow.toFixed(1)), Number.isFinite(dHigh) ? Number(dHigh.toFixed(1)) : null];
	result.views.far = far;
	for (const h of topHlods) {
		if (!far.loaded.includes(h.uri)) fail(`far view: the top HLOD ${h.uri} was not loaded (loaded: ${far.loaded.join(' ') || 'nothing'})`);
		if (!far.visible.includes(h.uri)) fail(`far view: the top HLOD ${h.uri} is loaded but not visible (visible: ${far.visible.join(' ') || 'nothing'})`);
	}
	const farLeaves = far.loaded.filter(u => byUri.get(u)?.kind === 'leaf');
	if (farLeaves.length) fail(`far view: leaf tiles were loaded: ${farLeaves.join(' ')}`);
	const farOther = far.visible.filter(u => !topHlods.some(h => h.uri === u));
	if (farOther.length) fail(`far view: more than the top HLOD is visible: ${farOther.join(' ')}`);

	// ---- (b) close above one tile (or each of several), looking down
	let tileSize = null;
	try { tileSize = JSON.parse(fs.readFileSync(path.join(worldDir, 'plan.json'), 'utf8')).tile_size ?? null; } catch { /* optional */ }
	const indexOf = l => l.json.extras?.tile ?? (l.uri.match(/tiles\/(\d+)_(\d+)\//) ?? []).slice(1).map(Number);
	let picked;
	if (tileArgs.includes('all')) picked = leaves;
	else if (tileArgs.length) picked = tileArgs.map(a => leaves.find(l => l.uri === `tiles/${a}/city.glb`) ?? fail(`--tile ${a}: tileset.json has no tiles/${a}/city.glb`));
	else {
		const idx = leaves.map(indexOf);
		const nx = Math.max(...idx.map(i => i[0])) + 1, ny = Math.max(...idx.map(i => i[1])) + 1;
		const want = [Math.floor((nx - 1) / 2), Math.floor((ny - 1) / 2)];
		picked = [leaves[idx.findIndex(i => i[0] === want[0] && i[1] === want[1])] ?? leaves[0]];
	}
	result.views.street = [];
	for (const leaf of picked) {
		const leafAabb = aabbOfObb(worldBox(leaf));
		// the middle of the tile's own square: its frame's origin is its south-west corner (plan.json)
		const o = new Vector3().applyMatrix4(leaf.world);
		const mid = tileSize ? new Vector3(o.x + tileSize / 2, o.y + tileSize / 2, 0)
			: leafAabb.lo.clone().add(leafAabb.hi).multiplyScalar(0.5);
		const street = await view(`street (${leaf.uri})`,
			new Vector3(mid.x, mid.y, leafAabb.hi.z + 10), new Vector3(mid.x, mid.y, leafAabb.lo.z), new Vector3(0, 1, 0));
		street.tile = leaf.uri;
		street.ancestors = leaf.ancestors;
		result.views.street.push(street);
		const label = `street view over ${leaf.uri}`;
		if (!street.loaded.includes(leaf.uri)) fail(`${label}: it was not loaded (loaded: ${street.loaded.join(' ') || 'nothing'})`);
		if (!street.visible.includes(leaf.uri)) fail(`${label}: it is loaded but not visible (visible: ${street.visible.join(' ') || 'nothing'})`);
		const shownAncestors = leaf.ancestors.filter(a => street.visible.includes(a));
		if (shownAncestors.length) fail(`${label}: it is visible but so is its HLOD ancestor ${shownAncestors.join(' ')} (REPLACE not honoured)`);
	}
}

main().then(() => finish(null), e => finish(e instanceof Failure ? e.message : `unexpected error: ${e?.stack?.split('\n').slice(0, 3).join(' | ') ?? e}`));
