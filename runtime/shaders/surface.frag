#version 450 core
// Buildings, ground and VAT pieces: atlas tiling for every material but glass; window glass
// shows the room behind it (perspective interior mapping) under a front layer and a
// Fresnel reflection of the sky.
#include "common.glsl"
#include "materials.glsl"
#include "atlas.glsl"
#include "interior.glsl"
#include "surface.glsl"
layout(binding = 0) uniform sampler2D atlas;
layout(binding = 1) uniform sampler2D rooms;
layout(binding = 2) uniform sampler2D roomMiddle;
layout(binding = 8) uniform sampler2DArray lightmaps;
#ifdef TREE
#include "leaves.glsl"  // a tree's kGround cards are leaf cards, uv 0..1
#endif
layout(location = 4) uniform int roomStyles;
layout(location = 0) out vec4 outColor;

vec3 fog(vec3 color, vec3 viewDir, float distance) {
    float haze = 1.0 - exp(-distance * 0.0009);
    return mix(color, skyColor(viewDir), haze * 0.85);
}

void main() {
    vec3 toFragment = vWorld - frame.cameraPos.xyz;
    float distance = length(toFragment);
    vec3 V = toFragment / max(distance, 1e-6);
    // Faces seen from behind (interior walls, thin parts) are lit from the side we see.
    vec3 n = normalize(vNormal);
    if (dot(n, V) > 0.0) n = -n;
    float night = frame.sunDir.w;
    // Layer -2: an HLOD mesh, its bake decoded in (TEXCOORD_1, TEXCOORD_2) = (sky, sun bounce, AO, lamps).
    bool vertexBaked = vLight.z < -1.5;
    bool baked = vLight.z >= 0.0 || vertexBaked;
    vec4 bake = vertexBaked ? vec4(vUv1, vUv2) : baked ? decodeBaked(texture(lightmaps, vLight)) : vec4(0.0);
    vec3 color;
    if (vMaterial == kGlass) {
        float cosTheta = clamp(dot(-V, n), 0.0, 1.0);
        float fresnel = 0.04 + 0.96 * pow(1.0 - cosTheta, 5.0);
        vec3 reflection = skyColor(reflect(V, n));
        vec3 behind = vec3(0.02, 0.025, 0.03);
        if (!vertexBaked && vUv2.x > 0.0 && vUv2.y > 0.0 && vUv1.x > 0.0) {
            vec3 roomSize = vec3(vUv2.x, vUv2.y, vUv1.x);
            vec2 faceUv = clamp(vUv0 / vUv2, 0.0, 1.0);
            uint room = uint(vUv1.y + 0.5);
            uint h = interiorHash(vBuilding * 7919u + room);
            int style = roomStyle(vBuilding, room, roomStyles);
            vec4 inside = interiorColor(rooms, roomMiddle, style, roomStyles, faceUv, roomRay(V, n, roomSize), 0.45);
            // Daylight through the window by day; some rooms have their lamps on at night.
            bool lamp = ((h >> 8u) & 255u) < 110u;
            vec3 light = mix(0.5 * (frame.skyHorizon.rgb + frame.skyZenith.rgb) * 0.8,
                             lamp ? vec3(1.6, 1.15, 0.7) : vec3(0.015, 0.015, 0.02), night);
            // Baked: the room's own sky, sun-bounce and lamp levels (its block of the room table).
            if (baked) light = bakedIndirect(bake) + vec3(0.004, 0.004, 0.005);
            behind = inside.rgb * light;
            vec4 front = frontLayer(faceUv, vUv2, h);
            behind = mix(behind, front.rgb * mix(diffuseLight(vWorld, n), light, 0.5), front.a);
        }
        color = mix(behind, reflection, fresnel);
    } else {
        vec3 albedo = sampleAtlas(atlas, vRect, vUv0, vTile).rgb;
#ifdef TREE
        vec4 leaf = texture(leaves, vUv0);  // sampled in uniform control flow, used on leaf cards
        if (vMaterial == kGround) {
            if (leafCut(leaf.a)) discard;
            albedo = leaf.rgb;
        }
#endif
        color = albedo * (baked ? bakedDiffuseLight(vWorld, n, bake) : diffuseLight(vWorld, n));
    }
    outColor = vec4(fog(color, V, distance), 1.0);
}
