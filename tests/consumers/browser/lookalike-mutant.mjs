#!/usr/bin/env node
// lookalike-mutant.mjs IN.glb OUT.glb
//
// The self-test's broken city for consumers.lookalike: IN.glb rewritten, from its bytes, as
// dawnforge wrote GLBs before they had materials a reader understands (issue 40): every
// primitive gets one white material ("dawnforge_atlas", no texture), the textures, images and
// samplers go, and each primitive gets a COLOR_0 (unsigned bytes, normalised, VEC4) that carries
// its vertices' material ID (the custom attribute _MATERIAL_ID) as binary colours:
// id = R + 2G + 4B + 8A, each channel 0 or 255. A plain reader paints that city in pure reds,
// greens, blues and magentas; lookalike-check.mjs must catch it.
// Prints one line: what it rewrote. Exit 1 with a reason when IN.glb is not a GLB whose
// primitives carry _MATERIAL_ID.
import fs from 'node:fs';
import process from 'node:process';

function fail(message) {
  process.stderr.write(`lookalike-mutant: ${message}\n`);
  process.exit(1);
}
if (process.argv.length !== 4) fail('usage: lookalike-mutant.mjs IN.glb OUT.glb');
const [input, output] = process.argv.slice(2);
const glb = fs.readFileSync(input);
if (glb.readUInt32LE(0) !== 0x46546c67 || glb.readUInt32LE(4) !== 2) fail(`${input} is not a glTF 2 binary`);
let off = 12, json = null, bin = null;
while (off < glb.length) {
  const len = glb.readUInt32LE(off), type = glb.readUInt32LE(off + 4);
  if (type === 0x4e4f534a) json = JSON.parse(glb.toString('utf8', off + 8, off + 8 + len));
  else if (type === 0x004e4942) bin = glb.subarray(off + 8, off + 8 + len);
  off += 8 + len;
}
if (!json || !bin) fail(`${input}: no JSON or no BIN chunk`);

const SIZE = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
const BYTES = { 5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4 };
// The accessor's values as numbers (scalars only: _MATERIAL_ID is one).
function readScalars(index) {
  const a = json.accessors[index];
  if (SIZE[a.type] !== 1) fail(`accessor ${index}: _MATERIAL_ID is ${a.type}, not SCALAR`);
  const view = json.bufferViews[a.bufferView];
  const size = BYTES[a.componentType], stride = view.byteStride || size;
  const base = (view.byteOffset || 0) + (a.byteOffset || 0);
  const read = { 5120: 'readInt8', 5121: 'readUInt8', 5122: 'readInt16LE', 5123: 'readUInt16LE', 5125: 'readUInt32LE',
    5126: 'readFloatLE' }[a.componentType];
  const out = new Array(a.count);
  for (let i = 0; i < a.count; ++i) out[i] = bin[read](base + i * stride);
  return out;
}

const extra = [];
let binLength = bin.length;
const colourOf = new Map();   // _MATERIAL_ID accessor -> COLOR_0 accessor
let primitives = 0, vertices = 0;
const ids = new Set();
for (const mesh of json.meshes ?? []) {
  for (const p of mesh.primitives) {
    const idAccessor = p.attributes._MATERIAL_ID;
    if (idAccessor === undefined) fail(`${input}: mesh "${mesh.name}" has a primitive without _MATERIAL_ID`);
    if (!colourOf.has(idAccessor)) {
      const values = readScalars(idAccessor);
      const bytes = Buffer.alloc(4 * values.length);
      values.forEach((v, i) => {
        const id = Math.round(v);
        ids.add(id);
        for (let k = 0; k < 4; ++k) bytes[4 * i + k] = (id >> k) & 1 ? 255 : 0;
      });
      const pad = (4 - (binLength % 4)) % 4;
      if (pad) extra.push(Buffer.alloc(pad));
      binLength += pad;
      json.bufferViews.push({ buffer: 0, byteOffset: binLength, byteLength: bytes.length, target: 34962 });
      extra.push(bytes);
      binLength += bytes.length;
      json.accessors.push({ bufferView: json.bufferViews.length - 1, componentType: 5121, normalized: true,
        count: values.length, type: 'VEC4' });
      colourOf.set(idAccessor, json.accessors.length - 1);
      vertices += values.length;
    }
    p.attributes.COLOR_0 = colourOf.get(idAccessor);
    p.material = 0;
    ++primitives;
  }
}
json.materials = [{ name: 'dawnforge_atlas', pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0.9 } }];
delete json.textures;
delete json.images;
delete json.samplers;
for (const key of ['extensionsUsed', 'extensionsRequired']) {
  if (json[key]) json[key] = json[key].filter((e) => e !== 'KHR_texture_transform');
}
const pad = (4 - (binLength % 4)) % 4;
if (pad) extra.push(Buffer.alloc(pad));
binLength += pad;
json.buffers[0].byteLength = binLength;

let text = Buffer.from(JSON.stringify(json), 'utf8');
text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
const header = Buffer.alloc(12), jsonHead = Buffer.alloc(8), binHead = Buffer.alloc(8);
header.writeUInt32LE(0x46546c67, 0);
header.writeUInt32LE(2, 4);
header.writeUInt32LE(12 + 8 + text.length + 8 + binLength, 8);
jsonHead.writeUInt32LE(text.length, 0);
jsonHead.writeUInt32LE(0x4e4f534a, 4);
binHead.writeUInt32LE(binLength, 0);
binHead.writeUInt32LE(0x004e4942, 4);
fs.writeFileSync(output, Buffer.concat([header, jsonHead, text, binHead, bin, ...extra]));
process.stdout.write(`lookalike-mutant: ${primitives} primitives on one white material, COLOR_0 on ${vertices} vertices ` +
  `from _MATERIAL_ID (ids ${[...ids].sort((a, b) => a - b).join(' ')})\n`);
