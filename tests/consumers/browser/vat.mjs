// Plays a dawnforge VAT (SideFX Labs VAT 3.0, rigid-body dynamics) in three.js, as the Labs
// materials play it in Unity and in Unreal, and checks every decoded vertex against the
// simulation it came from.
//
// Query: vat=FOLDER (under /data/) name=PREFIX decoder=unity|unreal frames=K,K,...
//        sim=FOLDER (under /data/, holding transforms.bin) [mutate=swap-pivot-uvs|lookup-v-from-bottom|swap-y-z|
//        rotation-alpha-negated|no-second-position-texture]
//
// three's GLTFLoader reads <name>_mesh.glb and its EXRLoader <name>_pos.exr and _rot.exr (as
// 32-bit floats), or the browser's PNG decoder the Non-HDR form's <name>_pos.png, _pos2.png and
// _rot.png (8-bit). The mesh then goes through what the engine's glTF importer does to it
// (importMesh), and a RawShaderMaterial runs the engine's Labs decoder (DECODERS) on every
// vertex, one point per vertex, writing the decoded position into a float render target that
// is read back. The reference is transforms.bin applied to the rest pose, here in JavaScript:
// it shares nothing with dawnforge's C++ and nothing with the decoders.
//
// The decoders are written from the Labs 3.0 sources' arithmetic (see ../README.md, *Consumers*):
// only the texture fetch and the inputs the engine hands the material are emulated.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { loadExr, loadPng, onlyMesh, param } from './page.mjs';
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
uniform sampler2D pos2Tex;     // Non-HDR: the positions' hundredths ("Positions Require Two Textures")
uniform sampler2D rotTex;
uniform bool twoTextures;      // the material's static switch of that name
uniform float frame;          // the frame shown, from 0; between two frames, both are blended
uniform vec3 boundMin;        // the mesh's bounds as the engine computes them (data triangles included)
uniform vec3 boundMax;
uniform float frameCount;     // Unity: the material's _frameCount
uniform vec3 unityBoundMin;   // Unity: the material's _boundMin* and _boundMax*
uniform vec3 unityBoundMax;
in vec3 enginePos;
in vec2 engineUv1;
in vec2 engineUv2;
in vec2 engineUv3;

// Both decoders' Non-HDR position: the texture's fraction of the bounds' box, with the second
// texture's hundredths when the switch is on.
vec3 positionLdr(vec2 uv, vec3 p, vec3 lo, vec3 hi) {
  vec3 unit = twoTextures ? p + texture(pos2Tex, uv).rgb * 0.01 : p;
  return unit * (hi - lo) + lo;
}

vec3 rotateByQuat(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }

struct Frame { vec3 position; vec4 q; float pscale; float turns; };

// Both Labs decoders' interframe blend: the position and pscale linearly, the rotation by a
// slerp through the rotation alpha's signed turns (a negative alpha: towards -q1).
Frame blend(Frame a, Frame b, float t) {
  Frame r = a;
  r.position = mix(a.position, b.position, t);
  r.pscale = mix(a.pscale, b.pscale, t);
  if (abs(a.turns) > 1e-5) {
    const float pi = 3.14159265358979;
    float f = fract(abs(a.turns)), g = fract(abs(a.turns) * t);
    r.q = normalize((sin(pi * (f - g)) * a.q + sin(pi * g) * sign(a.turns) * b.q) / sin(pi * f));
  }
  return r;
}
`;

// Unity, the URP_VAT3 rigid-body graph: texture V from the bottom (Unity's convention, and
// three's for an EXR: its loader puts the file's first row at the top); _B_interpolate on, as
// dawnforge's _data.json sets it. HDR when frac(10 _boundMaxZ) >= 0.5; else the Non-HDR
// texels: rotation (rot - 0.5) * 2, its alpha times the largest turns per frame
// 1 / (1 - frac(-10 _boundMinX)), positions through the material's bounds.
const UNITY = /* glsl */ `
vec4 quatUnity(vec3 s, float m) {
  float w = sqrt(max(0.0, 1.0 - dot(s, s)));
  if (m < 0.5) return vec4(s, w);
  if (m < 1.5) return vec4(w, s.y, s.z, s.x);
  if (m < 2.5) return vec4(s.x, -w, s.z, -s.y);
  return vec4(s.x, s.y, -w, -s.z);
}
Frame unityFrame(float k) {
  vec2 uv = vec2(engineUv1.x, 1.0 - ((1.0 - engineUv1.y) + k / frameCount));
  vec4 p = texture(posTex, uv);
  vec4 r = texture(rotTex, uv);
  bool hdr = fract(10.0 * unityBoundMax.z) >= 0.5;
  vec3 position = hdr ? p.rgb : positionLdr(uv, p.rgb, unityBoundMin, unityBoundMax);
  if (!hdr) r = (r - 0.5) * 2.0;
  float turns = hdr ? r.a : r.a / (1.0 - fract(-10.0 * unityBoundMin.x));
  float m = floor(4.0 * p.a);
  float pscale = (1.0 - fract(4.0 * p.a)) / (1.0 - fract(10.0 * unityBoundMax.y));  // "Piece Scales Are in Position Alpha"
  return Frame(position, quatUnity(r.rgb, m), pscale, turns);
}
vec3 decode() {
  if (engineUv1.y <= 0.1) return vec3(0.0);  // the data triangles
  float k = floor(frame);
  Frame f = unityFrame(k);
  if (frame > k) f = blend(f, unityFrame(k + 1.0), frame - k);
  vec3 pivot = vec3(-engineUv2.x, engineUv3.x, 1.0 - engineUv3.y);
  return rotateByQuat(f.q, enginePos - pivot) * f.pscale + f.position;
}
`;

// Unreal, the Labs material function Houdini_VAT_RigidBodyDynamics (UE 5.4 content; its Custom
// HLSL and node graph): the codes it reads from the object's bounds (decimetres, rounded to
// 1e-4), the three pivot forms of TexCoord[2] and [3], the lookup in TexCoord[1] with v from the
// top (Unreal's convention, so the fetch turns it for three's textures), frames from 1 in
// "Display Frame", its "Interframe Interpolation" switched on where the frame is fractional.
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
// What the bounds carry: x frames and the largest turns per frame, y the HDR flag, z the
// largest pscale; the active area.
struct Codes { float frames; bool hdr; float maxPscale; float maxTurns; vec2 ratio; };
Codes boundCodes() {
  vec3 bmax = round(boundMax / 1e-4) * 1e-4 * 0.1, bmin = round(boundMin / 1e-4) * 1e-4 * 0.1;
  float code = fract(bmax.y);
  float c = round(100.0 * code);
  float hundreds = 0.0;
  if (mod(c, 25.0) > 0.05 && mod(c, 10.0) > 0.05) {
    float t = 25.0 - abs(mod(c, 50.0) - 25.0);
    hundreds = round(t - floor(t / 10.0));
  }
  float rows = round(100.0 * (ceil(bmin.z) - bmin.z)) + 100.0 * hundreds;
  vec2 ratio = vec2(1.0 - (ceil(bmin.y) - bmin.y), 1.0 - (ceil(bmin.x) - bmin.x));
  float frames = round(float(textureSize(posTex, 0).y) * ratio.y) / rows;
  return Codes(frames, code >= 0.5, 1.0 / (1.0 - fract(bmax.z)), 1.0 / (1.0 - fract(bmax.x)), ratio);
}
// Non-HDR: "Position Texture RGB transformed by the object local bounds", the rotation
// (rot - 0.5) * 2, "the A channel stores the normalized RPFs" (times the max RPF).
Frame unrealFrame(float displayFrame, Codes codes) {
  float k = mod(floor(displayFrame) - 1.0, codes.frames);
  vec2 uv = vec2(engineUv1.x, engineUv1.y + k / codes.frames) * codes.ratio;
  vec2 at = vec2(uv.x, 1.0 - uv.y);
  vec4 p = texture(posTex, at);
  vec4 r = texture(rotTex, at);
  vec3 position = codes.hdr ? p.rgb : positionLdr(at, p.rgb, boundMin, boundMax);
  if (!codes.hdr) r = (r - 0.5) * 2.0;
  float m = floor(4.0 * p.a);
  return Frame(position, quatUnreal(r.rgb, m), (1.0 - fract(4.0 * p.a)) * codes.maxPscale, r.a * codes.maxTurns);
}
vec3 decode() {
  if (engineUv1.y >= 0.9) return vec3(0.0);  // the data triangles
  Codes codes = boundCodes();
  float displayFrame = frame + 1.0, k = floor(displayFrame);
  Frame f = unrealFrame(k, codes);
  if (displayFrame > k) f = blend(f, unrealFrame(k + 1.0, codes), displayFrame - k);
  return rotateByQuat(f.q, enginePos - pivotUnreal(engineUv2, engineUv3)) * f.pscale + f.position;
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
  const unity = meta.unity_material ?? {};
  const uniforms = {
    posTex: { value: textures.pos }, pos2Tex: { value: textures.pos2 ?? textures.pos }, rotTex: { value: textures.rot },
    twoTextures: { value: Boolean(textures.pos2) }, frame: { value: 0 },
    boundMin: { value: new THREE.Vector3(...bounds.min) }, boundMax: { value: new THREE.Vector3(...bounds.max) },
    frameCount: { value: unity._frameCount ?? 0 },
    unityBoundMin: { value: new THREE.Vector3(unity._boundMinX, unity._boundMinY, unity._boundMinZ) },
    unityBoundMax: { value: new THREE.Vector3(unity._boundMaxX, unity._boundMaxY, unity._boundMaxZ) },
  };
  return runPerVertex(mesh.n, attributes, COMMON + DECODERS[engine] + VERTEX_MAIN, uniforms,
    frames.map((k) => (u) => { u.frame.value = k; }));
}

// The simulation, read from its own files: transforms.bin is frames × pieces × (px py pz qx qy
// qz qw), turns.bin frames × pieces signed turns to the next frame, both float32 little-endian
// in glTF axes and metres; frame 0 is the rest pose with identity orientations.
class Simulation {
  constructor(transforms, turns, pieces) {
    [this.transforms, this.turns, this.pieces] = [new DataView(transforms), new DataView(turns), pieces];
  }
  position(k, j) { return [0, 1, 2].map((c) => this.transforms.getFloat32(4 * (7 * (k * this.pieces + j) + c), true)); }
  orientation(k, j) { return [3, 4, 5, 6].map((c) => this.transforms.getFloat32(4 * (7 * (k * this.pieces + j) + c), true)); }
  turnsAfter(k, j) { return this.turns.getFloat32(4 * (k * this.pieces + j), true); }

  // Piece j's pivot and orientation at a frame, between two frames as a VAT can show it: the
  // pivot on the straight line, the orientation on the great circle between the two poses, the
  // way round and the whole turns the simulated path took (turns.bin). pathMismatch: how far
  // the path's angle is from the poses' (the axis turned within the frame).
  pose(frame, j) {
    const k = Math.floor(frame), t = frame - k;
    if (t === 0) return { p: this.position(k, j), q: this.orientation(k, j) };
    const [p0, p1] = [this.position(k, j), this.position(k + 1, j)];
    const q0 = this.orientation(k, j), turns = this.turnsAfter(k, j);
    const q1 = this.orientation(k + 1, j).map((c) => (turns < 0 ? -c : c));
    const delta = multiply(q1, conjugate(q0));
    const axisLength = Math.hypot(delta[0], delta[1], delta[2]);
    const poses = 2 * Math.atan2(axisLength, delta[3]);  // radians, in [0, 2 pi]
    const whole = Math.max(0, Math.round(Math.abs(turns) - poses / (2 * Math.PI)));
    const half = 0.5 * t * (poses + 2 * Math.PI * whole);
    const step = axisLength < 1e-9 ? [0, 0, 0, 1] : [...delta.slice(0, 3).map((c) => (c / axisLength) * Math.sin(half)), Math.cos(half)];
    return { p: p0.map((c, i) => c + t * (p1[i] - c)), q: multiply(step, q0),
      pathMismatch: Math.abs(poses + 2 * Math.PI * whole - 2 * Math.PI * Math.abs(turns)) };
  }
}

function multiply([ax, ay, az, aw], [bx, by, bz, bw]) {
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}
const conjugate = ([x, y, z, w]) => [-x, -y, -z, w];

// A vertex at rest moved by its piece's `pose` (Simulation.pose); p0 is the piece's rest pivot.
function moved({ p, q: [qx, qy, qz, qw] }, p0, rest) {
  const v = [0, 1, 2].map((c) => rest[c] - p0[c]);
  // v + 2 q × (q × v + w v), written out
  const cx = qy * v[2] - qz * v[1] + qw * v[0], cy = qz * v[0] - qx * v[2] + qw * v[1], cz = qx * v[1] - qy * v[0] + qw * v[2];
  const r = [v[0] + 2 * (qy * cz - qz * cy), v[1] + 2 * (qz * cx - qx * cz), v[2] + 2 * (qx * cy - qy * cx)];
  return [0, 1, 2].map((c) => r[c] + p[c]);
}

const toEngine = { unity: ([x, y, z]) => [-x, y, z], unreal: ([x, y, z]) => [100 * x, 100 * z, 100 * y] };

function compare(engine, pieceIds, rest, decoded, sim, meta, frames) {
  const perFrame = [];
  let dataVertices = 0, dataOffOrigin = 0;  // off the origin: counted at every frame
  frames.forEach((k, f) => {
    let worst = 0, worstVertex = -1, worstPath = 0;
    for (let i = 0; i < pieceIds.length; ++i) {
      const got = decoded[f].subarray(4 * i, 4 * i + 3);
      const piece = Math.round(pieceIds[i]);
      if (piece >= meta.pieces) {  // a data triangle: the decoder must hide it at the origin
        if (f === 0) dataVertices += 1;
        if (Math.hypot(...got) > 1e-6) dataOffOrigin += 1;
        continue;
      }
      const pose = sim.pose(k, piece);
      const want = toEngine[engine](moved(pose, sim.position(0, piece), rest.subarray(3 * i, 3 * i + 3)));
      worstPath = Math.max(worstPath, pose.pathMismatch ?? 0);
      const error = Math.hypot(got[0] - want[0], got[1] - want[1], got[2] - want[2]);
      if (!(error <= worst)) [worst, worstVertex] = [error, i];  // NaN counts as worst
    }
    perFrame.push({ frame: k, max_error: Number.isNaN(worst) ? null : worst, worst_vertex: worstVertex,
      turns_against_poses_rad: worstPath });
  });
  return { perFrame, dataVertices, dataOffOrigin };
}

// mutate=...: the files as a broken writer would have written them, to prove that the check sees it.
function breakFile(mutation, geometry, textures) {
  if (mutation === null) return;
  const a = geometry.attributes, rotation = textures.rot;
  if (mutation === 'swap-pivot-uvs') [a.uv2, a.uv3] = [a.uv3, a.uv2];
  else if (mutation === 'no-second-position-texture') {
    if (!textures.pos2) throw new Error('vat.mjs: no-second-position-texture needs a Non-HDR VAT');
    delete textures.pos2;
  }
  else if (mutation === 'rotation-alpha-negated') {
    for (let i = 3; i < rotation.image.data.length; i += 4) rotation.image.data[i] = -rotation.image.data[i];
    rotation.needsUpdate = true;
  }
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
  const ldr = meta.texture_format === 'ldr';
  const load = (file) => (ldr ? loadPng : loadExr)(`/data/${vatDir}/${file}`);
  const [geometry, pos, rot, pos2, transforms, turns] = await Promise.all([loadMesh(`${base}_mesh.glb`),
    load(meta.textures.position), load(meta.textures.rotation), meta.textures.position2 ? load(meta.textures.position2) : null,
    fetchBytes(`/data/${simDir}/transforms.bin`), fetchBytes(`/data/${simDir}/turns.bin`)]);
  const rest = geometry.attributes.position.array.slice();
  const textures = { pos, rot, ...(pos2 ? { pos2 } : {}) };
  breakFile(param('mutate', { optional: true }), geometry, textures);
  const mesh = importMesh(geometry, engine);
  const decoded = decodeOnGpu(engine, mesh, textures, meta, frames);
  const result = compare(engine, geometry.attributes._piece_id.array, rest, decoded, new Simulation(transforms, turns, meta.pieces),
    meta, frames);
  return { engine, name, preset: meta.preset, precision: meta.precision, vertices: mesh.n, pieces: meta.pieces,
    units: engine === 'unreal' ? 'centimetres' : 'metres', declared_max_vertex_error_m: meta.max_vertex_error,
    texture: [pos.image.width, pos.image.height], frames: result.perFrame,
    data_vertices: result.dataVertices, data_vertices_off_origin: result.dataOffOrigin };
}

window.consumerDone = run();
