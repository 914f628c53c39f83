// Plays a GLB that `dawnforge anim` wrote, as a three.js app would: GLTFLoader, then the clip
// through an AnimationMixer set to each frame's time (k / fps). Reports every mesh node's
// position and quaternion at every frame, by name; it judges nothing (check.py anim does).
//   query: glb=FILE (under /data/), fps=F, frames=N
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { param } from './page.mjs';

async function play() {
  const url = `/data/${param('glb')}`;
  const fps = Number(param('fps')), frames = Number(param('frames'));
  const gltf = await new GLTFLoader().loadAsync(url);
  if (gltf.animations.length !== 1) throw new Error(`${url}: ${gltf.animations.length} animations, expected 1`);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  // Played once and held at its end, as a destruction is: a repeating action wraps the last
  // frame's time (the clip's duration) back to the first frame.
  const action = mixer.clipAction(gltf.animations[0]);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  // The glTF nodes that show a mesh: the mesh itself, or the group of its primitives (one per
  // material) that three.js makes of a node whose mesh has several.
  const nodes = [];
  gltf.scene.traverse((o) => {
    const association = gltf.parser.associations.get(o);
    if (association?.nodes !== undefined && (o.isMesh || o.children.some((c) => c.isMesh && !gltf.parser.associations.get(c)?.nodes)))
      nodes.push(o);
  });
  const poses = {};
  for (const node of nodes) poses[node.name] = [];
  for (let k = 0; k < frames; ++k) {
    mixer.setTime(k / fps);
    for (const node of nodes) {
      const p = node.position, q = node.quaternion;
      poses[node.name].push([p.x, p.y, p.z, q.x, q.y, q.z, q.w]);
    }
  }
  return { clip: gltf.animations[0].name, duration: gltf.animations[0].duration, tracks: gltf.animations[0].tracks.length, poses };
}

window.consumerDone = play();
