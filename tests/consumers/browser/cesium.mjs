// CesiumJS loads a dawnforge world (/data/tileset.json) where its root transform puts it on the
// globe, and reports what it did, in its own terms (the checks are in ../check.py cesium):
//   origin     the cartographic position (degrees, metres) Cesium computes for the plan's (0, 0, 0):
//              the root's computed transform applied to it, then Cesium's own ECEF -> WGS84
//   views      per camera: the contents Cesium loaded and the ones it drew (tileVisible), whether
//              tilesLoaded settled, and failures. `far`: 3,000 m above the world's centre, where
//              the HLOD is enough; `near`: 40 m above it, where Cesium refines to the tiles.
//   pick       a building of tile 0_0 seen from above: what Cesium's scene.pick at the screen's
//              centre gives (the feature's properties: EXT_mesh_features + EXT_structural_metadata)
//              against the building in that tile's city.json
// The cameras are placed in the plan's east-north-up frame through Cesium's own
// Transforms.eastNorthUpToFixedFrame at the origin tileset.json's extras name, looking down,
// north up. No globe, no imagery, no Ion: everything is served from 127.0.0.1.
/* global Cesium */

const frame = () => new Promise((resolve) => requestAnimationFrame(resolve));

async function settle(widget, tileset, seconds) {
  const t0 = performance.now();
  let stable = 0;
  while (performance.now() - t0 < seconds * 1000) {
    widget.render();
    stable = tileset.tilesLoaded ? stable + 1 : 0;
    if (stable >= 8) return true;
    await frame();
  }
  return false;
}

function enuPoint(enu, x, y, z) {
  return Cesium.Matrix4.multiplyByPoint(enu, new Cesium.Cartesian3(x, y, z), new Cesium.Cartesian3());
}

async function view(widget, tileset, enu, centre, height, name) {
  const loaded = new Set(), visible = new Set(), failed = [];
  const onLoad = tileset.tileLoad.addEventListener((tile) => loaded.add(tile.content.url));
  const onVisible = tileset.tileVisible.addEventListener((tile) => visible.add(tile.content.url));
  const onFail = tileset.tileFailed.addEventListener((e) => failed.push(`${e.url}: ${e.message}`));
  const down = Cesium.Matrix4.multiplyByPointAsVector(enu, new Cesium.Cartesian3(0, 0, -1), new Cesium.Cartesian3());
  const north = Cesium.Matrix4.multiplyByPointAsVector(enu, new Cesium.Cartesian3(0, 1, 0), new Cesium.Cartesian3());
  widget.camera.setView({ destination: enuPoint(enu, centre[0], centre[1], height),
    orientation: { direction: Cesium.Cartesian3.normalize(down, down), up: Cesium.Cartesian3.normalize(north, north) } });
  const settled = await settle(widget, tileset, 90);
  visible.clear();   // what the settled frame draws
  widget.render();
  onLoad(); onVisible(); onFail();
  const short = (url) => url.replace(/^.*\/data\//, '').replace(/\?.*$/, '');
  return { name, height, settled, loaded: [...loaded].map(short).sort(), visible: [...visible].map(short).sort(), failed };
}

// The inside test of a polygon [[x, y], ...] (even-odd).
function inside([x, y], polygon) {
  let odd = false;
  for (let i = 0, j = polygon.length - 1; i < polygon.length; j = i++) {
    const [xi, yi] = polygon[i], [xj, yj] = polygon[j];
    if ((yi > y) !== (yj > y) && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) odd = !odd;
  }
  return odd;
}

// Picks the tallest building of tile 0_0 (its city.json: plan metres) whose footprint holds the
// mean of its corners: a camera 40 m above its roof looks down on that point, and Cesium's
// scene.pick at the screen's centre must give the building's feature and its properties.
async function pickBuilding(widget, tileset, enu) {
  const city = await (await fetch('/data/tiles/0_0/city.json')).json();
  const candidates = city.buildings.map((b) => {
    const c = b.footprint.reduce(([sx, sy], [x, y]) => [sx + x / b.footprint.length, sy + y / b.footprint.length], [0, 0]);
    return { b, c };
  }).filter(({ b, c }) => inside(c, b.footprint)).sort((p, q) => q.b.height - p.b.height);
  if (!candidates.length) return { expected: null, got: null };
  const { b, c } = candidates[0];
  const v = await view(widget, tileset, enu, c, b.height + 40, 'pick');
  const canvas = widget.scene.canvas;
  const picked = widget.scene.pick(new Cesium.Cartesian2(canvas.clientWidth / 2, canvas.clientHeight / 2));
  const names = ['id', 'floors', 'height', 'roof', 'wall_material'];
  const got = picked instanceof Cesium.Cesium3DTileFeature ? Object.fromEntries(names.map((n) => [n, picked.getProperty(n)])) : null;
  return { at: c, view: v, expected: { id: b.id, floors: b.floors, height: b.height, roof: b.roof, wall_material: b.wall_material },
    got, picked: picked ? String(picked.constructor?.name ?? typeof picked) : null };
}

async function run() {
  const widget = new Cesium.CesiumWidget('view', {
    globe: false, baseLayer: false, skyBox: false, skyAtmosphere: false, useDefaultRenderLoop: false,
    requestRenderMode: false, shadows: false,
  });
  const tileset = await Cesium.Cesium3DTileset.fromUrl('/data/tileset.json',
    { maximumScreenSpaceError: 16, foveatedScreenSpaceError: false, cullRequestsWhileMoving: false });
  widget.scene.primitives.add(tileset);
  widget.resize();   // the default render loop would; this page renders on its own
  const json = await (await fetch('/data/tileset.json')).json();
  const o = json.extras.origin;
  const enu = Cesium.Transforms.eastNorthUpToFixedFrame(Cesium.Cartesian3.fromDegrees(o.longitude, o.latitude, o.height));
  const corner = Cesium.Matrix4.multiplyByPoint(tileset.root.computedTransform, Cesium.Cartesian3.ZERO, new Cesium.Cartesian3());
  const c = Cesium.Cartographic.fromCartesian(corner);
  const box = json.root.boundingVolume.box;
  const area = json.root.children.map((t) => t.extras?.area).find(Boolean) ?? [0, 0, box[0] * 2, box[1] * 2];
  const centre = [(area[0] + area[2]) / 2, (area[1] + area[3]) / 2];
  const views = [];
  views.push(await view(widget, tileset, enu, centre, 3000, 'far'));
  views.push(await view(widget, tileset, enu, centre, 40, 'near'));
  const pick = await pickBuilding(widget, tileset, enu);
  const contents = [];
  (function walk(t) {
    if (t.content?.uri) contents.push(t.content.uri);
    (t.children ?? []).forEach(walk);
  })(json.root);
  // Cesium has no cartographic position for a point near the Earth's centre (a tileset without
  // its root transform): then null, and the check says so
  const origin = c ? { longitude: Cesium.Math.toDegrees(c.longitude), latitude: Cesium.Math.toDegrees(c.latitude), height: c.height }
    : null;
  return { cesium: Cesium.VERSION, origin, ecef_origin: [corner.x, corner.y, corner.z], expected_origin: o,
    contents: contents.sort(), views, pick };
}

window.consumerDone = run();
