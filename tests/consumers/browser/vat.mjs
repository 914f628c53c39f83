// Plays a dawnforge VAT (SideFX Labs VAT 3.0, rigid-body dynamics) in three.js, as the Labs
// materials play it in Unity and in Unreal, and checks every decoded vertex against the
// simulation it came from.
//
// Query: vat=FOLDER (under /data/) name=PREFIX decoder=unity|unreal frames=K,K,...
//        sim=FOLDER (under /data/, holding transforms.bin) [mutate=swap-pivot-uvs|lookup-v-from-bottom|swap-y-z]
//
// three's GLTFLoader reads <name>_mesh.glb and its EXRLoader <name>_pos.exr and _rot.exr (as
// 32-bit floats). The mesh then goes through what the engine's glTF importer does to it
// (importMesh), and a RawShaderMaterial runs the engine's Labs decoder (DECODERS) on every
// vertex, one point per vertex, writing the decoded position into a float render target that
// is read back. The reference is transforms.bin applied to the rest pose, here in JavaScript:
// it shares nothing with dawnforge's C++ and nothing with the decoders.
//
// The decoders are written from the Labs 3.0 sources' arithmetic (see ../README.md, *Consumers*):
// only the texture fetch and the inputs the engine hands the material are emulated.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { loadExr, onlyMesh, param } from './page.mjs';
import { runPerVertex } from './per-vertex.mjs';

async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return response.arrayBuffer();
}

// The one mesh of the GLB, with its attributes as three's GLTFLoader named them.
async function loadMesh(url) {
  return onlyMesh(await new GLTFLoader().loadAsync(url), url);
}

// What each engine's glTF importer does: Unity (glTFast) mirrors x and puts V's origin at the
// bottom; Unreal turns glTF's Y-up metres into its Z-up centimetres, (x, z, y) · 100, and
// keeps glTF's V (both put v = 0 at the top). Returns positions and UV sets in engine terms.
function importMesh(geometry, engine) {
  const n = geometry.attributes.position.count;
  const pos = new Float32Array(3 * n);
  const p = geometry.attributes.position.array;
  for (let i = 0; i < n; ++i) {
    const [x, y, z] = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
    const v = engine === 'unity' ? [-x, y, z] : [100 * x, 100 * z, 100 * y];
    pos.set(v, 3 * i);
  }
  const uvSet = (name) => {
    const a = geometry.attributes[name];
    if (!a) throw new Error(`the mesh has no ${name} (TEXCOORD_${name.slice(2)})`);
    const out = new Float32Array(a.array);
    if (engine === 'unity') for (let i = 1; i < out.length; i += 2) out[i] = 1 - out[i];
    return out;
  };
  return { n, pos, uv1: uvSet('uv1'), uv2: uvSet('uv2'), uv3: uvSet('uv3') };
}

const COMMON = /* glsl */ `
uniform sampler2D posTex;
uniform sampler2D rotTex;
uniform float frame;          // the frame shown, from 0
uniform vec3 boundMin;        // the mesh's bounds as the engine computes them (data triangles included)
uniform vec3 boundMax;
uniform float frameCount;     // Unity: the material's _frameCount
in vec3 enginePos;
in vec2 engineUv1;
in vec2 engineUv2;
in vec2 engineUv3;

vec3 rotateByQuat(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }
`;

// Unity, the URP_VAT3 rigid-body graph: texture V from the bottom (Unity's convention, and
// three's for an EXR: its loader puts the file's first row at the top).
const UNITY = /* glsl */ `
vec4 quatUnity(vec3 s, float m) {
  float w = sqrt(max(0.0, 1.0 - dot(s, s)));
  if (m < 0.5) return vec4(s, w);
  if (m < 1.5) return vec4(w, s.y, s.z, s.x);
  if (m < 2.5) return vec4(s.x, -w, s.z, -s.y);
  return vec4(s.x, s.y, -w, -s.z);
}
vec3 decode() {
  if (engineUv1.y <= 0.1) return vec3(0.0);  // the data triangles
  vec2 uv = vec2(engineUv1.x, 1.0 - ((1.0 - engineUv1.y) + frame / frameCount));
  vec4 p = texture(posTex, uv);
  vec4 r = texture(rotTex, uv);
  float m = floor(4.0 * p.a);
  float pscale = 1.0 - (p.a - 0.25 * m) / 0.2495;  // max pscale 1: dawnforge's bounds carry no pscale code
  vec3 pivot = vec3(-engineUv2.x, engineUv3.x, 1.0 - engineUv3.y);
  return rotateByQuat(quatUnity(r.rgb, m), enginePos - pivot) * pscale + p.rgb;
}
`;

// Unreal, the Labs material function Houdini_VAT_RigidBodyDynamics (UE 5.4 content; its Custom
// HLSL and node graph): the codes it reads from the object's bounds (decimetres, rounded to
// 1e-4), the three pivot forms of TexCoord[2] and [3], the lookup in TexCoord[1] with v from the
// top (Unreal's convention, so the fetch turns it for three's textures), frames from 1 in
// "Display Frame", interframe interpolation off (the material's default).
const UNREAL = /* glsl */ `
uint halfBitsTruncated(float f) {
  uint a = floatBitsToUint(f);
  return ((a >> 16) & 0x8000u) | ((((a >> 23) & 0xffu) - 112u) << 10) | ((a >> 13) & 0x3ffu);
}
// "Decode Magnitude" / "Decode Up": 13 bits from each of two halves make a float's top 26 bits.
float decodeSplit(float hi, float lo) {
  uint a = halfBitsTruncated(hi), b = halfBitsTruncated(lo);
  a = (a & 0x8000u) | ((a << 2) & 0x7ff8u);
  b = (b & 0x8000u) | ((b << 2) & 0x7ff8u);
  return uintBitsToFloat((a << 16) | (b << 3));
}
vec3 pivotUnreal(vec2 tc2, vec2 tc3) {
  vec3 h;  // Houdini axes, metres
  if (abs(tc2.y) <= 0.001) h = vec3(tc2.x, tc3.x, tc3.y);                            // unencoded
  else if (abs(tc3.y) < 2.0) h = vec3(tc2.x, decodeSplit(tc2.y, tc3.y), tc3.x);      // Very High, y split
  else h = vec3(tc2.x, sqrt(max(0.0, 1.0 - (tc2.x * tc2.x + tc3.x * tc3.x))), tc3.x) * decodeSplit(tc2.y, tc3.y);
  return 100.0 * h.xzy;
}
vec4 quatUnreal(vec3 s, float m) {
  float w = sqrt(max(0.0, 1.0 - dot(s, s)));
  if (m < 0.5) return vec4(s, w);
  if (m < 1.5) return vec4(-w, s.y, s.z, -s.x);
  if (m < 2.5) return vec4(s.x, s.y, -w, -s.z);
  return vec4(s.x, -w, s.z, -s.y);
}
vec3 decode() {
  if (engineUv1.y >= 0.9) return vec3(0.0);  // the data triangles
  vec3 bmax = round(boundMax / 1e-4) * 1e-4 * 0.1, bmin = round(boundMin / 1e-4) * 1e-4 * 0.1;
  float code = fract(bmax.y);
  float c = round(100.0 * code);
  float hundreds = 0.0;
  if (mod(c, 25.0) > 0.05 && mod(c, 10.0) > 0.05) {
    float t = 25.0 - abs(mod(c, 50.0) - 25.0);
    hundreds = round(t - floor(t / 10.0));
  }
  float rows = round(100.0 * (ceil(bmin.z) - bmin.z)) + 100.0 * hundreds;
  float ratioY = 1.0 - (ceil(bmin.x) - bmin.x), ratioX = 1.0 - (ceil(bmin.y) - bmin.y);
  float frames = round(float(textureSize(posTex, 0).y) * ratioY) / rows;
  float maxPscale = 1.0 / (1.0 - fract(bmax.z));
  float displayFrame = frame + 1.0;
  float k = mod(floor(displayFrame) - 1.0, frames);
  vec2 uv = vec2(engineUv1.x * ratioX, (engineUv1.y + k / frames) * ratioY);
  vec2 glUv = vec2(uv.x, 1.0 - uv.y);
  vec4 p = texture(posTex, glUv);
  vec4 r = texture(rotTex, glUv);
  if (code < 0.5) return vec3(-1e9);  // not HDR: dawnforge writes only HDR, so this is a broken bound
  float m = floor(4.0 * p.a);
  float pscale = (1.0 - fract(4.0 * p.a)) * maxPscale;
  return rotateByQuat(quatUnreal(r.rgb, m), enginePos - pivotUnreal(engineUv2, engineUv3)) * pscale + p.rgb;
}
`;

const DECODERS = { unity: UNITY, unreal: UNREAL };

const VERTEX_MAIN = /* glsl */ `
void main() { emit(vec4(decode(), 1.0)); }
`;

function boundsOf(pos) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < pos.length; ++i) {
    min[i % 3] = Math.min(min[i % 3], pos[i]);
    max[i % 3] = Math.max(max[i % 3], pos[i]);
  }
  return { min, max };
}

// Decodes every vertex at each frame on the GPU; returns one Float32Array (xyzw per vertex) per frame.
function decodeOnGpu(engine, mesh, textures, meta, frames) {
  const bounds = boundsOf(mesh.pos);
  const attributes = { enginePos: new THREE.BufferAttribute(mesh.pos, 3) };
  for (const k of ['1', '2', '3']) attributes[`engineUv${k}`] = new THREE.BufferAttribute(mesh[`uv${k}`], 2);
  const uniforms = {
    posTex: { value: textures.pos }, rotTex: { value: textures.rot }, frame: { value: 0 },
    boundMin: { value: new THREE.Vector3(...bounds.min) }, boundMax: { value: new THREE.Vector3(...bounds.max) },
    frameCount: { value: meta.unity_material?._frameCount ?? 0 },
  };
  return runPerVertex(mesh.n, attributes, COMMON + DECODERS[engine] + VERTEX_MAIN, uniforms,
    frames.map((k) => (u) => { u.frame.value = k; }));
}

// transforms.bin: frames × pieces × (px py pz qx qy qz qw), float32 little-endian, glTF axes and
// metres; frame 0 is the rest pose with identity orientations.
function referenceAt(transforms, pieces, k, piece, rest) {
  const t = (f, j, c) => transforms.getFloat32(4 * (7 * (f * pieces + j) + c), true);
  const v = [0, 1, 2].map((c) => rest[c] - t(0, piece, c));
  const [qx, qy, qz, qw] = [3, 4, 5, 6].map((c) => t(k, piece, c));
  // v + 2 q × (q × v + w v), written out
  const cx = qy * v[2] - qz * v[1] + qw * v[0], cy = qz * v[0] - qx * v[2] + qw * v[1], cz = qx * v[1] - qy * v[0] + qw * v[2];
  const r = [v[0] + 2 * (qy * cz - qz * cy), v[1] + 2 * (qz * cx - qx * cz), v[2] + 2 * (qx * cy - qy * cx)];
  return [0, 1, 2].map((c) => r[c] + t(k, piece, c));
}

const toEngine = { unity: ([x, y, z]) => [-x, y, z], unreal: ([x, y, z]) => [100 * x, 100 * z, 100 * y] };

function compare(engine, pieceIds, rest, decoded, transforms, meta, frames) {
  const perFrame = [];
  let dataVertices = 0, dataOffOrigin = 0;  // off the origin: counted at every frame
  frames.forEach((k, f) => {
    let worst = 0, worstVertex = -1;
    for (let i = 0; i < pieceIds.length; ++i) {
      const got = decoded[f].subarray(4 * i, 4 * i + 3);
      const piece = Math.round(pieceIds[i]);
      if (piece >= meta.pieces) {  // a data triangle: the decoder must hide it at the origin
        if (f === 0) dataVertices += 1;
        if (Math.hypot(...got) > 1e-6) dataOffOrigin += 1;
        continue;
      }
      const want = toEngine[engine](referenceAt(transforms, meta.pieces, k, piece, rest.subarray(3 * i, 3 * i + 3)));
      const error = Math.hypot(got[0] - want[0], got[1] - want[1], got[2] - want[2]);
      if (!(error <= worst)) [worst, worstVertex] = [error, i];  // NaN counts as worst
    }
    perFrame.push({ frame: k, max_error: Number.isNaN(worst) ? null : worst, worst_vertex: worstVertex });
  });
  return { perFrame, dataVertices, dataOffOrigin };
}

// mutate=...: the mesh as a broken writer would have written it, to prove that the check sees it.
function breakFile(mutation, geometry) {
  if (mutation === null) return;
  const a = geometry.attributes;
  if (mutation === 'swap-pivot-uvs') [a.uv2, a.uv3] = [a.uv3, a.uv2];
  else if (mutation === 'lookup-v-from-bottom') for (let i = 1; i < a.uv1.array.length; i += 2) a.uv1.array[i] = 1 - a.uv1.array[i];
  else if (mutation === 'swap-y-z') for (let i = 0; i < a.position.array.length; i += 3) {
    [a.position.array[i + 1], a.position.array[i + 2]] = [a.position.array[i + 2], a.position.array[i + 1]];
  } else throw new Error(`vat.mjs: no mutation "${mutation}"`);
}

async function run() {
  const [vatDir, name, engine, simDir] = ['vat', 'name', 'decoder', 'sim'].map(param);
  if (!DECODERS[engine]) throw new Error(`vat.mjs: no decoder "${engine}"`);
  const base = `/data/${vatDir}/${name}`;
  const meta = await (await fetch(`${base}_data.json`)).json();
  const frames = param('frames').split(',').map(Number);
  const [geometry, pos, rot, transforms] = await Promise.all([loadMesh(`${base}_mesh.glb`), loadExr(`${base}_pos.exr`),
    loadExr(`${base}_rot.exr`), fetchBytes(`/data/${simDir}/transforms.bin`)]);
  const rest = geometry.attributes.position.array.slice();
  breakFile(param('mutate', { optional: true }), geometry);
  const mesh = importMesh(geometry, engine);
  const decoded = decodeOnGpu(engine, mesh, { pos, rot }, meta, frames);
  const result = compare(engine, geometry.attributes._piece_id.array, rest, decoded, new DataView(transforms), meta, frames);
  return { engine, name, preset: meta.preset, precision: meta.precision, vertices: mesh.n, pieces: meta.pieces,
    units: engine === 'unreal' ? 'centimetres' : 'metres', declared_max_vertex_error_m: meta.max_vertex_error,
    texture: [pos.image.width, pos.image.height], frames: result.perFrame,
    data_vertices: result.dataVertices, data_vertices_off_origin: result.dataOffOrigin };
}

window.consumerDone = run();
