// lookalike.mjs: the page lookalike.html runs. three.js's plain GLTFLoader loads a city.glb that
// `dawnforge city` wrote and draws it as a three.js app would (the loader's own materials,
// nothing of ours), from the cameras of the scene.json that `dawnforge render` drew, under a sun
// and a sky like ours; for each camera it returns its picture and which pixels show geometry.
// Sets window.consumerDone to a promise of its report; it judges nothing (lookalike-check.mjs
// compares the pictures).
//
// Query:
//   scene=FILE        the scene file under /data/ (default scene.json): its "cameras" (position,
//                     target, fov_degrees: vertical, default 50), its "time_of_day" (default 15) and
//                     its "city" folder
//   glb=FILE          the GLB under /data/ to draw (default: the scene's city folder's city.glb)
//   cameras=A,B       the scene's cameras to draw, in order (default: all)
//   exposure_NAME=X   camera NAME's exposure: the linear colour's multiplier before the tone curve
//                     (default 1); lookalike.sh passes the one `dawnforge render --stats` used
//   tone=aces|none|neutral|agx   three's tone mapping (default aces: ACESFilmicToneMapping, the
//                     curve our renderer ends in, Narkowicz's fit of the same ACES RRT + ODT)
//   lod=all|lod0      all (default): every node, as a plain reader draws it (a building's _lod0 and
//                     _lod1 both); lod0: _lod1 nodes hidden
//
// The light, as three's physically based units need it (a Lambert surface of albedo a under
// irradiance E gives a·E/π; ours gives a·E, so each intensity here is ours × π):
//   sun        a DirectionalLight from the sun's direction at the scene's time of day, on the
//              path our docs give (runtime/include/dawnforge/runtime/sky.hpp: rises in the east,
//              +x, at 06:00, crosses the south, +z, at 12:00 at 55°, sets in the west at 18:00),
//              linear colour (3.2, 3.07, 2.88): our afternoon sun; shadows (PCF soft, 4096²)
//              over the city's box (every mesh but the far land)
//   sky        a HemisphereLight, sky (0.45, 0.61, 0.9) (the mean of our zenith and horizon),
//              ground (0.3, 0.28, 0.25), both × 0.9, as our unbaked ambient term has them
//   background our horizon colour (it is not compared: the checker masks the sky out)
// Daylight only: a time of day whose sun is below 5° is refused.
//
// The report: {glb, time_of_day, sun: {direction, elevation_degrees}, tone, lod, load_s,
//   gltf: {nodes, meshes, primitives, triangles, materials[] (names), textures, vertex_colours
//          (materials that take COLOR_0), transparent (materials)},
//   views: {NAME: {camera {position, target, fov, width, height}, exposure, render_ms,
//                  picture (PNG data URL: what the app shows), mask (PNG data URL: white where a
//                  surface was drawn, black where the background shows)}}}
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const q = new URLSearchParams(location.search);
const TONES = { aces: THREE.ACESFilmicToneMapping, none: THREE.NoToneMapping, neutral: THREE.NeutralToneMapping,
  agx: THREE.AgXToneMapping };
const SUN = [3.2, 3.072, 2.88];
const SKY = [0.45, 0.61, 0.9], GROUND = [0.3, 0.28, 0.25], AMBIENT = 0.9;
const HORIZON = [0.68, 0.8, 0.95];
const linear = (c) => new THREE.Color().setRGB(c[0], c[1], c[2], THREE.LinearSRGBColorSpace);
const r4 = (x) => Number(x.toFixed(4));
const frame = () => new Promise((resolve) => requestAnimationFrame(resolve));

async function fetchJson(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return response.json();
}

// The sun's direction (towards it) at `hours`, on the path our docs describe.
function sunAt(hours) {
  const phi = Math.PI * (hours - 6) / 12;
  const elevation = (55 * Math.PI / 180) * Math.sin(phi);
  if (elevation < 5 * Math.PI / 180) throw new Error(`time_of_day ${hours}: the sun is below 5°, and this page draws daylight only`);
  const d = new THREE.Vector3(Math.cos(elevation) * Math.cos(phi), Math.sin(elevation), Math.cos(elevation) * Math.sin(phi));
  return { direction: d.normalize(), elevation };
}

async function run() {
  const sceneFile = q.get('scene') ?? 'scene.json';
  const scene = await fetchJson(`/data/${sceneFile}`);
  const hours = scene.time_of_day ?? 15;
  const glb = q.get('glb') ?? `${scene.city}/city.glb`;
  const tone = q.get('tone') ?? 'aces';
  const lod = q.get('lod') ?? 'all';
  if (!(tone in TONES)) throw new Error(`tone=${tone}: not one of ${Object.keys(TONES).join(', ')}`);
  if (lod !== 'all' && lod !== 'lod0') throw new Error(`lod=${lod}: not all or lod0`);
  const wanted = q.get('cameras') ? q.get('cameras').split(',') : (scene.cameras ?? []).map((c) => c.name);
  const cameras = wanted.map((name) => {
    const c = (scene.cameras ?? []).find((k) => k.name === name);
    if (!c) throw new Error(`${sceneFile} has no camera "${name}"`);
    return c;
  });
  if (!cameras.length) throw new Error(`${sceneFile}: no camera to draw`);

  // ---- the app: a canvas filling the page, sRGB output, the loader's materials as they come
  const width = window.innerWidth, height = window.innerHeight;
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = TONES[tone];
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE.PCFSoftShadowMap;
  document.body.appendChild(renderer.domElement);

  const t0 = performance.now();
  const gltf = await new GLTFLoader().loadAsync(`/data/${glb}`);
  const loadS = (performance.now() - t0) / 1000;
  const world = new THREE.Scene();
  world.add(gltf.scene);

  const info = { nodes: 0, meshes: 0, primitives: 0, triangles: 0, materials: new Set(), textures: new Set(),
    vertex_colours: new Set(), transparent: new Set() };
  const box = new THREE.Box3();
  gltf.scene.updateMatrixWorld(true);
  gltf.scene.traverse((o) => {
    ++info.nodes;
    if (lod === 'lod0' && /_lod1$/.test(o.name)) o.visible = false;
    if (!o.isMesh) return;
    ++info.primitives;
    o.castShadow = o.receiveShadow = true;
    const g = o.geometry;
    info.triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
    for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
      info.materials.add(m.name || '(unnamed)');
      if (m.map) info.textures.add(m.map.uuid);
      if (m.vertexColors) info.vertex_colours.add(m.name || m.uuid);
      if (m.transparent) info.transparent.add(m.name || m.uuid);
    }
    // the shadow's box: everything but the far land around the city
    if (!/^land_/.test(o.name) && !/^land_/.test(o.parent?.name ?? '')) box.expandByObject(o);
  });
  info.meshes = (gltf.parser.json.meshes ?? []).length;

  // ---- the light
  const sun = sunAt(hours);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getBoundingSphere(new THREE.Sphere()).radius;
  const light = new THREE.DirectionalLight(linear(SUN), Math.PI);
  light.position.copy(centre).addScaledVector(sun.direction, 2 * radius);
  light.target.position.copy(centre);
  light.castShadow = true;
  light.shadow.mapSize.set(4096, 4096);
  Object.assign(light.shadow.camera, { left: -radius, right: radius, top: radius, bottom: -radius, near: radius * 0.5, far: radius * 3.5 });
  light.shadow.bias = -0.0003;
  light.shadow.normalBias = 0.03;
  light.shadow.camera.updateProjectionMatrix();
  world.add(light, light.target);
  world.add(new THREE.HemisphereLight(linear(SKY), linear(GROUND), AMBIENT * Math.PI));

  // ---- each camera: its mask (every surface white on black, unlit), then its picture
  const mask = new THREE.MeshBasicMaterial({ color: 0xffffff, side: THREE.DoubleSide });
  mask.toneMapped = false;
  const background = linear(HORIZON);
  const views = {};
  for (const c of cameras) {
    const camera = new THREE.PerspectiveCamera(c.fov_degrees ?? 50, width / height, 0.1, 20000);
    camera.position.fromArray(c.position ?? [0, 0, 0]);
    camera.up.set(0, 1, 0);
    camera.lookAt(new THREE.Vector3().fromArray(c.target ?? [0, 0, -1]));
    camera.updateMatrixWorld(true);
    const exposure = Number(q.get(`exposure_${c.name}`) ?? 1);
    if (!(exposure > 0)) throw new Error(`exposure_${c.name}=${q.get(`exposure_${c.name}`)}: not a positive number`);

    world.overrideMaterial = mask;
    world.background = new THREE.Color(0x000000);
    renderer.render(world, camera);
    const maskUrl = renderer.domElement.toDataURL('image/png');

    world.overrideMaterial = null;
    world.background = background;
    renderer.toneMappingExposure = exposure;
    const t = performance.now();
    renderer.render(world, camera);
    const renderMs = performance.now() - t;
    await frame();
    renderer.render(world, camera);
    views[c.name] = {
      camera: { position: camera.position.toArray().map(r4), target: c.target, fov: camera.fov, width, height },
      exposure, render_ms: Number(renderMs.toFixed(1)),
      picture: renderer.domElement.toDataURL('image/png'), mask: maskUrl,
    };
  }
  return {
    glb, time_of_day: hours, sun: { direction: sun.direction.toArray().map(r4), elevation_degrees: r4(sun.elevation * 180 / Math.PI) },
    tone, lod, load_s: Number(loadS.toFixed(2)),
    gltf: { nodes: info.nodes, meshes: info.meshes, primitives: info.primitives, triangles: info.triangles,
      materials: [...info.materials].sort(), textures: info.textures.size, vertex_colours: info.vertex_colours.size,
      transparent: info.transparent.size },
    views,
  };
}

window.consumerDone = run();
