// Reads a city tree's Pivot Painter 2 files in three.js as Unreal's Pivot Painter 2 material
// functions do, for every vertex of the species mesh, and compares what they give with the
// tree's node hierarchy in city.glb.
//
// Query: city=FOLDER (under /data/, written by `dawnforge city`) species=NAME
//        [mutate=uv-v-from-bottom|pivots-in-gltf-axes]
//
// three's GLTFLoader reads trees/<species>.glb (the mesh Unreal imports), its EXRLoader
// _pivots.exr (half floats, as Unreal samples them: float values) and an ImageBitmap
// _axes.png (linear, not premultiplied). Per vertex, on the GPU (one point per vertex, three
// passes into a float target): the element index from UV channel 1 (CalculateMeshElementIndex),
// the pivot and the parent index (UnpackIntegerAsFloat) from _pivots.exr, the X axis
// (DecodeAxisVector) and the extent (Decode8BitAlphaAxisExtent) from _axes.png.
// The expected elements come from city.glb, through three's own scene graph: the first tree of
// the species in city.json, its mesh nodes depth first (a parent before its children, each
// node's parent its nearest mesh ancestor, a root its own), each node's transform relative to
// the tree's frame (its foot, yaw and scale in city.json): the pivot is its origin, the X axis
// its +X, the extent the span of its vertices along that axis. Nothing here reads dawnforge's
// _pivots.json.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { loadExr, nearest, onlyMesh, param } from './page.mjs';
import { runPerVertex } from './per-vertex.mjs';

// Both textures end up with the file's first row at V = 1 (EXRLoader flips rows itself; the
// bitmap is flipped on decoding), so the Unreal sampling below is the same for both.
async function loadTextures(base) {
  const pivots = await loadExr(`${base}_pivots.exr`);
  const blob = await (await fetch(`${base}_axes.png`)).blob();
  const bitmap = await createImageBitmap(blob, { imageOrientation: 'flipY', premultiplyAlpha: 'none',
    colorSpaceConversion: 'none' });
  const axes = new THREE.Texture(bitmap);
  axes.flipY = false;
  axes.premultiplyAlpha = false;
  return { pivots, axes: nearest(axes) };
}

// Unreal's glTF import: Y-up metres to Z-up centimetres, (x, z, y) · 100; UVs as they are
// (glTF and Unreal both put v = 0 at the top).
const toUnreal = ([x, y, z]) => [100 * x, 100 * z, 100 * y];

const SHADER = /* glsl */ `
uniform sampler2D pivotTex;
uniform sampler2D axisTex;
uniform vec2 texSize;          // the textures' size, as Unreal's TextureProperty node gives it
uniform int pass;
in vec2 uv1;                   // UV channel 1

vec4 sampleUnreal(sampler2D t, vec2 uv) { return texture(t, vec2(uv.x, 1.0 - uv.y)); }  // Unreal: v = 0 at the top

// ms_PivotPainter2_CalculateMeshElementIndex
float elementIndex(vec2 uv) { return floor(uv.y * texSize.y) * texSize.x + floor(uv.x * texSize.x); }

// ms_PivotPainter2_UnpackIntegerAsFloat: the half the float was sampled from, as bits, minus 1024
float unpackIntegerAsFloat(float n) {
  uint u = floatBitsToUint(n);
  uint sign2 = (u >> 16) & 0x8000u;
  uint exponent2 = (((u >> 23) & 0xffu) - 112u) << 10;
  uint mantissa2 = (u >> 13) & 0x3ffu;
  return float(sign2 | exponent2 | mantissa2) - 1024.0;
}

void main() {
  vec4 p = sampleUnreal(pivotTex, uv1);
  vec4 a = sampleUnreal(axisTex, uv1);
  if (pass == 0) emit(vec4(p.rgb, unpackIntegerAsFloat(p.a)));
  else if (pass == 1) emit(vec4(a.rgb * 2.0 - 1.0, a.a * 2048.0));   // DecodeAxisVector, Decode8BitAlphaAxisExtent
  else emit(vec4(elementIndex(uv1), 0.0, 0.0, 1.0));
}
`;

// Per vertex of the species mesh: pivot and parent, axis and extent, element index (4 floats each).
function decodeOnGpu(geometry, textures) {
  const n = geometry.attributes.position.count;
  const uniforms = { pivotTex: { value: textures.pivots }, axisTex: { value: textures.axes }, pass: { value: 0 },
    texSize: { value: new THREE.Vector2(textures.pivots.image.width, textures.pivots.image.height) } };
  const [pivotParent, axisExtent, element] = runPerVertex(n, { uv1: geometry.attributes.uv1 }, SHADER, uniforms,
    [0, 1, 2].map((pass) => (u) => { u.pass.value = pass; }));
  return { n, pivotParent, axisExtent, element };
}

// The tree's mesh nodes depth first, with their parent, their transform relative to the tree's
// root, and their vertex count and extent.
async function expectedElements(gltf, tree) {
  const root = gltf.scene.getObjectByName(tree.name);
  if (!root) throw new Error(`city.glb has no node ${tree.name}`);
  gltf.scene.updateMatrixWorld(true);
  // The species' frame in the city: at the root's origin (the tree's foot), turned by the tree's
  // yaw about +Y (city.json), scaled by the root's scale. city.json's foot and scale are rounded
  // to millimetres and thousandths; the root's own are exact.
  const yaw = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0, 1, 0), THREE.MathUtils.degToRad(tree.yaw_degrees));
  const toTree = new THREE.Matrix4().compose(root.position, yaw, root.scale).invert();
  const json = gltf.parser.json;
  const elements = [];
  const visit = (object, parentElement) => {
    const node = gltf.parser.associations.get(object)?.nodes;
    let self = parentElement;
    if (node !== undefined && json.nodes[node].mesh !== undefined) {
      self = elements.length;
      const m = new THREE.Matrix4().multiplyMatrices(toTree, object.matrixWorld);
      const axis = new THREE.Vector3().setFromMatrixColumn(m, 0).normalize();
      const pivot = new THREE.Vector3().setFromMatrixPosition(m);
      let lo = Infinity, hi = -Infinity, vertices = 0;
      const v = new THREE.Vector3();
      const primitives = object.isMesh ? [object] : object.children.filter((c) => c.isMesh && !gltf.parser.associations.get(c)?.nodes);
      for (const mesh of primitives) {
        const toElement = new THREE.Matrix4().multiplyMatrices(toTree, mesh.matrixWorld);
        const position = mesh.geometry.attributes.position;
        for (let i = 0; i < position.count; ++i) {
          const t = v.fromBufferAttribute(position, i).applyMatrix4(toElement).sub(pivot).dot(axis);
          [lo, hi] = [Math.min(lo, t), Math.max(hi, t)];
        }
        vertices += mesh.geometry.index ? mesh.geometry.index.count : position.count;
      }
      elements.push({ name: object.name, parent: parentElement < 0 ? self : parentElement, pivot: pivot.toArray(),
        axis: axis.toArray(), extent: hi - lo, vertices });
    }
    for (const child of object.children) visit(child, self);
  };
  visit(root, -1);
  return elements;
}

// The most a vector can move when each component is rounded to the nearest half float.
function halfRounding(v) {
  const step = (c) => 2 ** (Math.max(Math.floor(Math.log2(Math.abs(c) || 2 ** -14)), -14) - 10);
  return Math.hypot(...v.map((c) => step(c) / 2));
}

function compare(expected, decoded) {
  const worst = { pivot_cm: 0, pivot_over_half_step: 0, axis: 0, extent_cm: 0, parent_mismatches: 0, index_out_of_range: 0 };
  const counts = new Array(expected.length).fill(0);
  for (let i = 0; i < decoded.n; ++i) {
    const e = decoded.element[4 * i];
    if (!(e >= 0 && e < expected.length && Number.isInteger(e))) {
      worst.index_out_of_range += 1;
      continue;
    }
    counts[e] += 1;
    const want = expected[e];
    const at = (array) => array.subarray(4 * i, 4 * i + 4);
    const [px, py, pz, parent] = at(decoded.pivotParent);
    const [ax, ay, az, extent] = at(decoded.axisExtent);
    const wp = toUnreal(want.pivot), wa = toUnreal(want.axis).map((c) => c / 100);
    const pivotError = Math.hypot(px - wp[0], py - wp[1], pz - wp[2]);
    worst.pivot_cm = Math.max(worst.pivot_cm, Number.isNaN(pivotError) ? Infinity : pivotError);
    worst.pivot_over_half_step = Math.max(worst.pivot_over_half_step, pivotError / halfRounding(wp));
    worst.axis = Math.max(worst.axis, Math.abs(ax - wa[0]), Math.abs(ay - wa[1]), Math.abs(az - wa[2]));
    worst.extent_cm = Math.max(worst.extent_cm, Math.abs(extent - Math.max(8, 100 * want.extent)));
    if (parent !== want.parent) worst.parent_mismatches += 1;
  }
  const countMismatches = expected.filter((e, i) => e.vertices !== counts[i]).map((e, i) => ({ name: e.name,
    want: e.vertices, got: counts[expected.indexOf(e)] }));
  return { worst, countMismatches };
}

// mutate=...: the files as a broken writer would have written them, to prove that the check sees it.
function breakFiles(mutation, geometry, textures) {
  if (mutation === null) return;
  if (mutation === 'uv-v-from-bottom') {
    const uv = geometry.attributes.uv1.array;
    for (let i = 1; i < uv.length; i += 2) uv[i] = 1 - uv[i];
  } else if (mutation === 'pivots-in-gltf-axes') {  // y and z not swapped into Unreal's
    const data = textures.pivots.image.data;
    for (let i = 0; i < data.length; i += 4) [data[i + 1], data[i + 2]] = [data[i + 2], data[i + 1]];
    textures.pivots.needsUpdate = true;
  } else throw new Error(`pivots.mjs: no mutation "${mutation}"`);
}

async function run() {
  const [cityDir, species] = ['city', 'species'].map(param);
  const report = await (await fetch(`/data/${cityDir}/city.json`)).json();
  const tree = report.trees.find((t) => t.species === species);
  if (!tree) throw new Error(`city.json has no tree of species ${species}`);
  const loader = new GLTFLoader();
  const base = `/data/${cityDir}/trees/${species}`;
  const [city, speciesGltf, textures] = await Promise.all([loader.loadAsync(`/data/${cityDir}/city.glb`),
    loader.loadAsync(`${base}.glb`), loadTextures(base)]);
  const expected = await expectedElements(city, tree);
  const geometry = onlyMesh(speciesGltf, `${species}.glb`);
  if (!geometry.attributes.uv1) throw new Error(`${species}.glb has no TEXCOORD_1`);
  breakFiles(param('mutate', { optional: true }), geometry, textures);
  const decoded = decodeOnGpu(geometry, textures);
  const { worst, countMismatches } = compare(expected, decoded);
  return { species, tree: tree.name, elements: expected.length, vertices: decoded.n,
    texture: [textures.pivots.image.width, textures.pivots.image.height],
    levels: Math.max(...expected.map((e) => { let d = 0; for (let p = e; p.parent !== expected.indexOf(p); p = expected[p.parent]) d += 1; return d; })) + 1,
    largest_pivot_cm: Math.max(...expected.map((e) => 100 * Math.hypot(...e.pivot))),
    worst, vertex_count_mismatches: countMismatches };
}

window.consumerDone = run();
