// tiles.mjs: the page tiles.html runs. NASA-AMMOS' 3d-tiles-renderer (TilesRenderer, three.js,
// WebGL 2) loads /data/tileset.json (a world from `dawnforge world build`), a camera placed as
// tools/tiles-reader/check.mjs places it, update() and render() each frame until loading settles,
// then one last render for the screenshot. Sets window.consumerDone to a promise of its report.
//
// Query:
//   view=far|street   far (default): above the world looking down, in the band of heights where
//                     the reader must stop at the top HLOD: by default as low as lets the world's
//                     square fill the view, kept within that band (distance=M: M metres above the
//                     top of the root's box instead). street: 10 m above the top of one tile's box,
//                     over the middle of its square, looking down (tile=I_J; default the tile
//                     nearest the world's middle).
//   clear=RRGGBB      the clear colour (default 203040)
//   timeout=S         give up waiting for loading to settle after S seconds (default 90)
//
// The report (all positions in the tileset's frame: x east, y north, z up, metres; the reader's
// group is left at identity):
//   view, camera {position, target, up, fov, width, height, distance_band_m}
//   settled, frames, settle_s, stats (the reader's), render {calls, triangles, last_ms}
//   errors[]   {url, error}: the reader's load-error events (and a failed root tileset)
//   tiles[]    every tile the reader knows (it preprocesses them all once loading settles), in
//              depth-first order: path ("" the root, "0.2" its first child's third child), uri
//              (content.uri or null), state (UNLOADED, QUEUED, LOADING, PARSING, LOADED or FAILED),
//              visible, obb {center, half_axes} (the reader's boundingVolume: its OBB's frame and
//              extents as the reader composed them with the tiles' transforms), sphere
//              {center, radius} (the reader's bounding sphere of it), and for a loaded content
//              content {meshes, triangles, origin, min, max}: where the reader put its frame's
//              origin, and the axis-aligned bounds of its meshes as it placed them (glTF's y-up
//              turned z-up, then the transforms)
//   loaded[], visible[]   content uris, sorted
import * as THREE from 'three';
import { TilesRenderer, LOADED, FAILED } from '3d-tiles-renderer';

const q = new URLSearchParams(location.search);
const VIEW = q.get('view') ?? 'far';
const CLEAR = q.get('clear') ?? '203040';
const TIMEOUT_S = Number(q.get('timeout') ?? 90);
const FOV = 60;
const ERROR_TARGET = 16;   // the reader's default
const STATES = ['UNLOADED', 'QUEUED', 'LOADING', 'PARSING', 'LOADED', 'FAILED'];
const r4 = (x) => Number(x.toFixed(4));
const v3 = (v) => v.toArray().map(r4);
const frame = () => new Promise((resolve) => requestAnimationFrame(resolve));

// The root's transform when it places the world on the globe (a rotation: dawnforge writes east-
// north-up to ECEF). This page works in the root's own frame, as a three.js app does that has no
// globe: the tiles' group gets the inverse, and the camera and the reports are in plan metres.
function globeOf(root) {
  if (!Array.isArray(root.transform) || root.transform.length !== 16) return null;
  const m = new THREE.Matrix4().fromArray(root.transform);
  const linear = new THREE.Matrix3().setFromMatrix4(m);
  return linear.equals(new THREE.Matrix3()) ? null : m;
}
const ownFrame = (tile, isRoot) => (tile.transform && !(isRoot && globeOf(tile))
  ? new THREE.Matrix4().fromArray(tile.transform) : new THREE.Matrix4());

// What tileset.json says, walked here only to place the camera (as check.mjs does).
function walkTileset(tileset) {
  const leaves = [], topHlods = [];
  (function walk(tile, parentWorld, hlodAbove) {
    const world = parentWorld.clone().multiply(ownFrame(tile, tile === tileset.root));
    const uri = tile.content?.uri ?? null;
    const info = { tile, world, uri };
    if (uri && /city\.glb$/.test(uri)) leaves.push(info);
    if (uri && /^hlod\//.test(uri) && !hlodAbove) topHlods.push(info);
    for (const c of tile.children ?? []) walk(c, world, hlodAbove || Boolean(uri && /^hlod\//.test(uri)));
  })(tileset.root, new THREE.Matrix4(), false);
  return { leaves, topHlods };
}

function aabbOf(box, world) {   // a boundingVolume.box in its tile's frame -> world-space Box3
  const c = new THREE.Vector3(box[0], box[1], box[2]).applyMatrix4(world);
  const linear = new THREE.Matrix3().setFromMatrix4(world);
  const out = new THREE.Box3(c.clone(), c.clone());
  for (let k = 0; k < 3; ++k) {
    const a = new THREE.Vector3(box[3 + 3 * k], box[4 + 3 * k], box[5 + 3 * k]).applyMatrix3(linear);
    const e = new THREE.Vector3(Math.abs(a.x), Math.abs(a.y), Math.abs(a.z));
    out.min.sub(e);
    out.max.add(e);
  }
  return out;
}

function placeCamera(tileset, width, height) {
  const { leaves, topHlods } = walkTileset(tileset);
  const sseDenominator = 2 * Math.tan(THREE.MathUtils.degToRad(FOV / 2)) / height;
  const distanceFor = (e) => e / (ERROR_TARGET * sseDenominator);   // where a tile's error meets the target
  if (VIEW === 'far') {
    if (!topHlods.length) throw new Error('tileset.json has no HLOD content (hlod/*.glb) to show from afar');
    const root = tileset.root;
    const rootBox = aabbOf(root.boundingVolume.box, ownFrame(root, true));
    const low = distanceFor(Math.max(...topHlods.map((h) => h.tile.geometricError)));
    const high = root.content ? Infinity : distanceFor(root.geometricError);
    // the world's square: the top HLODs' extras.area (their box less the far land), else the root box
    const square = new THREE.Box3();
    for (const h of topHlods) {
      const a = h.tile.extras?.area;
      if (Array.isArray(a) && a.length === 4) {
        square.expandByPoint(new THREE.Vector3(a[0], a[1], 0).applyMatrix4(h.world));
        square.expandByPoint(new THREE.Vector3(a[2], a[3], 0).applyMatrix4(h.world));
      }
    }
    if (square.isEmpty()) square.copy(rootBox);
    const centre = square.getCenter(new THREE.Vector3());
    const size = square.getSize(new THREE.Vector3());
    const tan = Math.tan(THREE.MathUtils.degToRad(FOV / 2));
    const fill = Math.max(size.y, size.x * height / width) / 2 / tan / 0.9;   // the square over 90 % of the view
    let distance = q.has('distance') ? Number(q.get('distance'))
      : Math.min(Math.max(fill, 1.5 * low), Number.isFinite(high) ? high / 1.5 : Infinity);
    if (!q.has('distance') && !(1.5 * low < high / 1.5)) distance = Math.sqrt(low * high);
    return {
      position: new THREE.Vector3(centre.x, centre.y, rootBox.max.z + distance), target: new THREE.Vector3(centre.x, centre.y, rootBox.min.z),
      distance_band_m: [r4(low), Number.isFinite(high) ? r4(high) : null], distance_m: r4(distance),
      expect: { top_hlods: topHlods.map((h) => h.uri) },
    };
  }
  if (VIEW === 'street') {
    if (!leaves.length) throw new Error('tileset.json has no leaf tile (tiles/*/city.glb)');
    const index = (l) => l.tile.extras?.tile ?? (/tiles\/(\d+)_(\d+)\//.exec(l.uri) ?? []).slice(1).map(Number);
    let leaf;
    if (q.has('tile')) {
      leaf = leaves.find((l) => l.uri === `tiles/${q.get('tile')}/city.glb`);
      if (!leaf) throw new Error(`tileset.json has no tiles/${q.get('tile')}/city.glb`);
    } else {
      const idx = leaves.map(index);
      const want = [0, 1].map((k) => Math.floor(Math.max(...idx.map((i) => i[k])) / 2));
      leaf = leaves[idx.findIndex((i) => i[0] === want[0] && i[1] === want[1])] ?? leaves[0];
    }
    const box = aabbOf(leaf.tile.boundingVolume.box, leaf.world);
    const area = leaf.tile.extras?.area;
    const mid = Array.isArray(area) && area.length === 4
      ? new THREE.Vector3((area[0] + area[2]) / 2, (area[1] + area[3]) / 2, 0).applyMatrix4(leaf.world)
      : box.getCenter(new THREE.Vector3());
    return {
      position: new THREE.Vector3(mid.x, mid.y, box.max.z + 10), target: new THREE.Vector3(mid.x, mid.y, box.min.z),
      expect: { tile: leaf.uri },
    };
  }
  throw new Error(`unknown view "${VIEW}" (far or street)`);
}

function tileReport(tiles, tile, path) {
  const e = tile.engineData ?? {};
  const r = { path, uri: tile.content?.uri ?? null, state: STATES[tile.internal?.loadingState] ?? String(tile.internal?.loadingState),
    visible: tiles.visibleTiles.has(tile) };
  const bv = e.boundingVolume;
  if (bv) {
    const box = new THREE.Box3(), m = new THREE.Matrix4();
    bv.getOBB(box, m);
    m.premultiply(tiles.group.matrixWorld);   // in the page's frame (the root's own, when it is on the globe)
    const centre = box.getCenter(new THREE.Vector3());
    const half = box.getSize(new THREE.Vector3()).multiplyScalar(0.5);
    const c = centre.clone().applyMatrix4(m);
    const axes = [new THREE.Vector3(half.x, 0, 0), new THREE.Vector3(0, half.y, 0), new THREE.Vector3(0, 0, half.z)]
      .map((a) => v3(a.add(centre).applyMatrix4(m).sub(c)));
    r.obb = { center: v3(c), half_axes: axes };
    const s = new THREE.Sphere();
    bv.getSphere(s);
    s.applyMatrix4(tiles.group.matrixWorld);
    r.sphere = { center: v3(s.center), radius: r4(s.radius) };
  }
  if (tile.internal?.loadingState === LOADED && e.scene) {
    let meshes = 0, triangles = 0;
    e.scene.traverse((o) => {
      if (!o.isMesh) return;
      meshes++;
      const g = o.geometry;
      triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
    });
    // a content not shown is outside the group: measure it under a stand-in for the group
    const detached = e.scene.parent === null, holder = new THREE.Group();
    if (detached) {
      holder.matrixAutoUpdate = false;
      holder.matrix.copy(tiles.group.matrixWorld);
      holder.add(e.scene);
      holder.updateMatrixWorld(true);
    }
    const b = new THREE.Box3().setFromObject(e.scene);
    e.scene.updateWorldMatrix(true, false);
    const origin = new THREE.Vector3().applyMatrix4(e.scene.matrixWorld);
    if (detached) holder.remove(e.scene);
    r.content = { meshes, triangles, origin: v3(origin), ...(b.isEmpty() ? {} : { min: v3(b.min), max: v3(b.max) }) };
  }
  return r;
}

async function main() {
  const started = performance.now();
  const width = innerWidth, height = innerHeight;
  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.setClearColor(new THREE.Color(`#${CLEAR}`), 1);
  document.body.appendChild(renderer.domElement);
  const gl = renderer.getContext();
  const glInfo = { webgl2: typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext };
  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  glInfo.renderer = dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);

  const scene = new THREE.Scene();
  const sky = new THREE.HemisphereLight(0xdfe8ff, 0x6b5a48, 1.6);
  sky.position.set(0, 0, 1);   // z up
  const sun = new THREE.DirectionalLight(0xfff2e0, 2.2);
  sun.position.set(0.45, -0.6, 1);
  scene.add(sky, sun);

  // tileset.json, read here only to place the camera
  const response = await fetch('/data/tileset.json');
  if (!response.ok) throw new Error(`/data/tileset.json: HTTP ${response.status}`);
  const tileset = await response.json();
  const place = placeCamera(tileset, width, height);
  const camera = new THREE.PerspectiveCamera(FOV, width / height, 0.1, 1e6);
  camera.up.set(0, 1, 0);   // north up on the screen
  camera.position.copy(place.position);
  camera.lookAt(place.target);
  camera.updateMatrixWorld(true);

  const tiles = new TilesRenderer('/data/tileset.json');
  tiles.lruCache.maxBytesSize = 4 * 2 ** 30;   // room for every content of a test world
  tiles.lruCache.minBytesSize = 3 * 2 ** 30;
  const errors = [];
  tiles.addEventListener('load-error', (e) => errors.push({ url: String(e.url), error: String(e.error?.message ?? e.error) }));
  tiles.setCamera(camera);
  tiles.setResolutionFromRenderer(camera, renderer);
  const globe = globeOf(tileset.root);
  if (globe) {
    tiles.group.matrixAutoUpdate = false;
    tiles.group.matrix.copy(globe).invert();
  }
  scene.add(tiles.group);

  const t0 = performance.now();
  let frames = 0, stable = 0, lastKey = '', settled = false, lastRenderMs = 0;
  for (;;) {
    tiles.update();
    const r0 = performance.now();
    renderer.render(scene, camera);
    lastRenderMs = performance.now() - r0;
    frames++;
    if (errors.length || tiles.rootLoadingState === FAILED) break;
    const s = tiles.stats;
    const idle = tiles.root && s.queued + s.downloading + s.parsing === 0 && tiles.loadProgress === 1 && !tiles.isLoading;
    const key = [...tiles.visibleTiles].map((t) => t.content?.uri ?? '').sort().join(',') + `|${s.loaded}|${s.used}`;
    stable = idle && key === lastKey ? stable + 1 : 0;
    lastKey = key;
    if (stable >= 10) {
      settled = true;
      break;
    }
    if (performance.now() - t0 > TIMEOUT_S * 1000) break;
    await frame();
  }
  const settleS = (performance.now() - t0) / 1000;
  // the picture: one more frame, then let the compositor present it
  tiles.update();
  renderer.render(scene, camera);
  await frame();
  await frame();

  tiles.group.updateMatrixWorld(true);
  const paths = new Map();   // tile -> "" (the root), "0", "0.2", ...
  const tileList = [];
  tiles.traverse((tile, parent) => {
    const up = parent === null ? null : paths.get(parent);
    const path = up === null ? '' : `${up === '' ? '' : `${up}.`}${parent.children.indexOf(tile)}`;
    paths.set(tile, path);
    tileList.push(tileReport(tiles, tile, path));
    return false;
  }, null, true);
  const loaded = tileList.filter((t) => t.state === 'LOADED' && t.uri).map((t) => t.uri).sort();
  const visible = tileList.filter((t) => t.visible && t.uri).map((t) => t.uri).sort();
  if (tiles.rootLoadingState === FAILED && !errors.length) errors.push({ url: '/data/tileset.json', error: 'the root tileset failed to load' });
  return {
    view: VIEW, reader: { '3d-tiles-renderer': 'TilesRenderer', three: THREE.REVISION, gl: glInfo },
    camera: { position: v3(camera.position), target: v3(place.target), up: v3(camera.up), fov: FOV, width, height,
      ...(place.distance_band_m ? { distance_band_m: place.distance_band_m, distance_m: place.distance_m } : {}) },
    expect: place.expect, clear: CLEAR,
    settled, frames, settle_s: r4(settleS), page_s: r4((performance.now() - started) / 1000),
    stats: { ...tiles.stats }, render: { calls: renderer.info.render.calls, triangles: renderer.info.render.triangles, last_ms: r4(lastRenderMs) },
    errors, loaded, visible, tiles: tileList,
  };
}

window.consumerDone = main().catch((e) => {
  console.error(`tiles.mjs: ${e?.message ?? e}`);
  return { error: String(e?.stack ?? e) };
});
