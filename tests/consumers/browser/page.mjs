// What the consumer pages share: their query, and files loaded as an engine imports them.

import * as THREE from 'three';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';
import { mergeGeometries } from 'three/addons/utils/BufferGeometryUtils.js';

const query = new URLSearchParams(location.search);

// The query's value of `key`; null when it is optional and absent, else an error.
export function param(key, { optional = false } = {}) {
  const value = query.get(key);
  if (value === null && !optional) throw new Error(`${location.pathname}: the query needs ${key}=`);
  return value;
}

// A texture as the Labs and Pivot Painter import settings want it: nearest filtering, no mips,
// no colour conversion.
export function nearest(texture) {
  texture.minFilter = texture.magFilter = THREE.NearestFilter;
  texture.generateMipmaps = false;
  texture.colorSpace = THREE.NoColorSpace;
  texture.needsUpdate = true;
  return texture;
}

// An EXR as 32-bit floats (a half file's values converted, as a GPU samples them), its first
// row at V = 1: three's EXRLoader flips the rows itself.
export async function loadExr(url) {
  return nearest(await new EXRLoader().setDataType(THREE.FloatType).loadAsync(url));
}

// The one glTF mesh of a loaded glTF, its geometry without an index (one entry per corner):
// three makes a Mesh of each primitive (ours: one per material), merged here in their order.
export function onlyMesh(gltf, url) {
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
  const sources = new Set(meshes.map((m) => gltf.parser.associations.get(m)?.meshes));
  if (meshes.length === 0 || sources.size !== 1) throw new Error(`${url}: ${sources.size} glTF meshes, expected 1`);
  const corners = meshes.map((m) => (m.geometry.index ? m.geometry.toNonIndexed() : m.geometry));
  if (corners.length === 1) return corners[0];
  const merged = mergeGeometries(corners);
  if (!merged) throw new Error(`${url}: its primitives do not have the same attributes`);
  return merged;
}

// An 8-bit PNG as the Labs Non-HDR import settings want it (sRGB off, alpha not transparency,
// no compression): the browser's own decoder, without premultiplying or colour conversion,
// its first row at V = 1 like the EXRs above.
export async function loadPng(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  const bitmap = await createImageBitmap(await response.blob(),
    { premultiplyAlpha: 'none', colorSpaceConversion: 'none', imageOrientation: 'flipY' });
  const texture = new THREE.Texture(bitmap);
  texture.flipY = false;
  texture.premultiplyAlpha = false;
  return nearest(texture);
}

