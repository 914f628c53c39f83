// Runs a vertex shader once per vertex and reads back what it computed: each vertex is drawn
// as one point into its own texel of a float render target (gl_VertexID gives the texel), so
// the page sees exactly what the shader made of every vertex, in 32-bit floats.

import * as THREE from 'three';

// The vertex shader ends its main() with emit(value).
const EMIT = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2D;
uniform vec2 perVertexTarget;
out vec4 perVertexValue;
void emit(vec4 value) {
  perVertexValue = value;
  float w = perVertexTarget.x;
  vec2 pixel = vec2(mod(float(gl_VertexID), w), floor(float(gl_VertexID) / w)) + 0.5;
  gl_Position = vec4(pixel / perVertexTarget * 2.0 - 1.0, 0.0, 1.0);
  gl_PointSize = 1.0;
}
`;

const FRAGMENT = /* glsl */ `
precision highp float;
in vec4 perVertexValue;
out vec4 colour;
void main() { colour = perVertexValue; }
`;

// count vertices with `attributes` ({name: THREE.BufferAttribute}); `vertexShader` declares them
// and its uniforms, and calls emit(). Each of `passes` sets the uniforms for one draw; returns
// one Float32Array of 4 × count values per pass.
export function runPerVertex(count, attributes, vertexShader, uniforms, passes) {
  const width = 256, height = Math.ceil(count / width);
  const geometry = new THREE.BufferGeometry();
  for (const [name, attribute] of Object.entries(attributes)) geometry.setAttribute(name, attribute);
  geometry.setDrawRange(0, count);
  const material = new THREE.RawShaderMaterial({
    glslVersion: THREE.GLSL3, vertexShader: EMIT + vertexShader, fragmentShader: FRAGMENT,
    uniforms: { ...uniforms, perVertexTarget: { value: new THREE.Vector2(width, height) } },
  });
  const points = new THREE.Points(geometry, material);
  points.frustumCulled = false;
  const scene = new THREE.Scene();
  scene.add(points);
  const renderer = new THREE.WebGLRenderer();
  const target = new THREE.WebGLRenderTarget(width, height, { type: THREE.FloatType, format: THREE.RGBAFormat,
    minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, depthBuffer: false });
  const out = passes.map((setUp) => {
    setUp(material.uniforms);
    renderer.setRenderTarget(target);
    renderer.render(scene, new THREE.Camera());
    const pixels = new Float32Array(4 * width * height);
    renderer.readRenderTargetPixels(target, 0, 0, width, height, pixels);
    return pixels.subarray(0, 4 * count);
  });
  renderer.setRenderTarget(null);
  renderer.dispose();
  return out;
}
