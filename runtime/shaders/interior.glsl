// Perspective interior mapping for window glass (Undawn, GDC 2024: "Perspective Interior
// Mapping" and "Extended Perspective Interior Mapping"). GLSL 4.50 functions only: include it
// after #version 450. Mirrors runtime/src/interior.cpp formula for formula; the names and the
// constants below are the C++ ones (interior_test.cpp checks kInteriorBackWallShare).
//
// Room space: x = right as seen from outside / width, y = up / height, z = depth / roomDepth;
// the room is [0,1]^3, the glass its z = 0 face. Per vertex: uv0 = position on the front face in
// metres, uv1 = (room depth, room index), uv2 = (room width, room height), so
// faceUv = uv0 / uv2 and roomSize = vec3(uv2, uv1.x).
//
// Textures (from runtime::generateInteriors(), upload as is: row 0 is v = 0, the floor side):
// both GL_SRGB8_ALPHA8, `styles` pictures of roomSize^2 side by side, mipmapped, CLAMP_TO_EDGE,
// GL_TEXTURE_MAX_LEVEL <= log2(roomSize) (levels above it would average neighbouring styles).
//
// Sampling: textureGrad with the gradients of the picture uv itself, taken once, up front.
//  - The picture uv is continuous across the five faces (one perspective picture, not a
//    cubemap), so its screen derivatives are well-behaved everywhere in a window; only the
//    atlas offset (style + uv.x) / styles could jump, and style is constant per room.
//  - The slot clamp below changes the coordinate but must not change the footprint: implicit
//    derivatives of the clamped coordinate would drop to level 0 along the clamped border.
//  - Explicit gradients stay valid if a caller branches (early-out, middle layer) around the
//    fetches; textureLod would also work but gives up anisotropic filtering, which facades seen
//    at grazing angles need.
//  - Seams between styles: mip levels <= log2(roomSize) never mix slots (slot edges align with
//    every level's texel blocks), so only the bilinear footprint can reach the neighbour; u is
//    held half a texel (at the level the gradients select) inside the slot. Anisotropic taps
//    along u can still reach one texel further at the slot's very edge (the glass's side edges).

const float kInteriorBackWallShare = 0.5;  // runtime::kBackWallShare: back wall's share of the picture

// lowbias32 (Chris Wellons): the same 32-bit hash as the C++ side.
uint interiorHash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// runtime::roomStyle(): the style of a room from the building instance id and the room index.
int roomStyle(uint building, uint room, int styles) {
    uint h = interiorHash(building ^ interiorHash(room + 0x9e3779b9u));
    return int(h % uint(styles));
}

// runtime::roomRay(): the view direction (camera -> fragment, world) in room space.
// normalWorld: the glass's outward normal; roomSize = (width, height, depth) in metres.
vec3 roomRay(vec3 viewDirWorld, vec3 normalWorld, vec3 roomSize) {
    vec3 inward = -normalWorld;
    vec3 right = normalize(cross(inward, vec3(0.0, 1.0, 0.0)));
    vec3 up = cross(right, inward);
    return vec3(dot(viewDirWorld, right), dot(viewDirWorld, up), dot(viewDirWorld, inward)) / roomSize;
}

// runtime::roomExit(): the one ray–box exit. For each axis, the distance to the wall the ray
// heads for over |d|; an axis with d = 0 never bounds the ray (mix() with a bvec selects, so the
// 0/0 it discards is harmless). Returns the exit point in xyz and t in w.
vec4 roomExit(vec3 origin, vec3 dir) {
    vec3 dist = mix(origin, 1.0 - origin, greaterThan(dir, vec3(0.0)));
    vec3 tAxis = mix(dist / abs(dir), vec3(3.0e38), equal(dir, vec3(0.0)));
    float t = min(min(tAxis.x, tAxis.y), tAxis.z);
    return vec4(clamp(origin + t * dir, 0.0, 1.0), t);
}

// runtime::roomTextureUv(): where a room point appears in the style's picture.
vec2 roomTextureUv(vec3 roomPoint, float backShare) {
    float s = 1.0 / (1.0 + roomPoint.z * (1.0 / backShare - 1.0));
    return 0.5 + (roomPoint.xy - 0.5) * s;
}

// runtime::middleLayerHit(): the hit with the plane z = depth in xyz, w = 1 if it is ahead and
// inside the box (hence in front of the box exit), else 0.
vec4 middleLayerHit(vec3 origin, vec3 dir, float depth) {
    float t = (depth - origin.z) / dir.z;
    vec3 hit = vec3(origin.xy + t * dir.xy, depth);
    bool inside = t > 0.0 && all(greaterThanEqual(hit.xy, vec2(0.0))) && all(lessThanEqual(hit.xy, vec2(1.0)));
    return vec4(hit, inside ? 1.0 : 0.0);
}

// A picture-space uv (within one style) to the atlas, held half a texel of the sampled level
// inside the style's slot. gradX/gradY: the atlas-space gradients textureGrad will use.
vec2 interiorAtlasUv(sampler2D atlas, vec2 uv, int style, int styles, vec2 gradX, vec2 gradY) {
    float slot = 1.0 / float(styles);
    vec2 atlasUv = vec2((float(style) + uv.x) * slot, uv.y);
    // The level textureGrad will pick: log2 of the larger footprint in texels (isotropic rule).
    vec2 size = vec2(textureSize(atlas, 0));
    float footprint = max(length(gradX * size), length(gradY * size));
    float level = clamp(log2(max(footprint, 1e-8)), 0.0, float(textureQueryLevels(atlas) - 1));
    vec2 halfTexel = 0.5 * exp2(level) / size;
    float lo = float(style) * slot + halfTexel.x;
    float hi = float(style + 1) * slot - halfTexel.x;
    return vec2(clamp(atlasUv.x, lo, max(lo, hi)), clamp(atlasUv.y, halfTexel.y, 1.0 - halfTexel.y));
}

// The room behind the glass, rgb linear (sRGB textures), a = 1.
// faceUv: room (x, y) on the glass in [0,1]^2 (uv0 / (width, height)); roomDir: roomRay(...);
// middleDepth: z of the middle layer's plane (e.g. 0.45).
vec4 interiorColor(sampler2D rooms, sampler2D middle, int style, int styles, vec2 faceUv, vec3 roomDir, float middleDepth) {
    // Helper lanes just outside the window extrapolate faceUv; clamping keeps their uv sane.
    vec3 origin = vec3(clamp(faceUv, 0.0, 1.0), 0.0);
    vec3 dir = vec3(roomDir.xy, max(roomDir.z, 1e-6));  // back faces / grazing: keep going inwards
    vec4 exitHit = roomExit(origin, dir);
    vec2 uv = roomTextureUv(exitHit.xyz, kInteriorBackWallShare);
    vec4 mid = middleLayerHit(origin, dir, middleDepth);

    // All derivatives here, in uniform control flow, from the unclamped continuous coordinates.
    vec2 toAtlas = vec2(1.0 / float(styles), 1.0);
    vec2 roomDx = dFdx(uv) * toAtlas, roomDy = dFdy(uv) * toAtlas;
    vec2 midDx = dFdx(mid.xy) * toAtlas, midDy = dFdy(mid.xy) * toAtlas;

    vec3 room = textureGrad(rooms, interiorAtlasUv(rooms, uv, style, styles, roomDx, roomDy), roomDx, roomDy).rgb;
    vec4 cutout = textureGrad(middle, interiorAtlasUv(middle, clamp(mid.xy, 0.0, 1.0), style, styles, midDx, midDy), midDx, midDy);
    float alpha = cutout.a * mid.w;
    return vec4(mix(room, cutout.rgb, alpha), 1.0);
}

// The front layer, from the face uv only: curtains at the sides (per-window choice from `seed`,
// e.g. roomStyle's hash of building and room) over a glass tint with a reflection band.
// Straight alpha, rgb linear; blend over interiorColor(): mix(interior, front.rgb, front.a).
// Curtains are unlit colours, like the room pictures: light them as the interior is lit.
vec4 frontLayer(vec2 faceUv, vec2 roomSizeMetres, uint seed) {
    uint h = interiorHash(seed ^ 0x5bd1e995u);
    float r0 = float(h & 0xffu) / 255.0;
    float r1 = float((h >> 8) & 0xffu) / 255.0;
    float r2 = float((h >> 16) & 0xffu) / 255.0;
    uint kind = (h >> 24) & 3u;  // 0: none, 1: both sides, 2: left only, 3: both, drawn further in

    // Curtains: folds every ~18 cm, the inner edge swaying a little, a rod along the top.
    float xm = faceUv.x * roomSizeMetres.x;
    float ym = faceUv.y * roomSizeMetres.y;
    float reach = (kind == 3u ? 0.28 : 0.1) + 0.12 * r0;  // share of the width each curtain covers
    float sway = 0.015 * sin(ym * 3.1 + r1 * 6.2831);
    float leftIn = reach + sway - faceUv.x;
    float rightIn = faceUv.x - (1.0 - reach - sway);
    float inner = kind == 0u ? -1.0 : (kind == 2u ? leftIn : max(leftIn, rightIn));
    float edge = 1.5 / max(roomSizeMetres.x * 100.0, 1.0);  // ~1.5 cm soft edge, in face units
    float curtainA = smoothstep(-edge, edge, inner);
    vec3 palette[4] = vec3[4](vec3(0.60, 0.14, 0.10), vec3(0.72, 0.66, 0.52), vec3(0.16, 0.26, 0.42), vec3(0.30, 0.42, 0.24));
    vec3 cloth = palette[int(r2 * 3.999)];
    float fold = 0.5 + 0.5 * cos(6.2831853 * xm / 0.18 + r1 * 6.2831853);
    vec3 curtain = cloth * (0.65 + 0.35 * fold) * (0.85 + 0.15 * faceUv.y);
    float rod = kind == 0u ? 0.0 : smoothstep(0.97, 0.975, faceUv.y) * (1.0 - smoothstep(0.985, 0.99, faceUv.y));
    curtain = mix(curtain, vec3(0.08, 0.07, 0.06), rod);
    curtainA = max(curtainA * (kind == 3u ? 0.85 : 0.97), rod);

    // Glass: a faint tint and a soft diagonal reflection band (position varies per window).
    float d = faceUv.x * 0.55 + faceUv.y - (0.55 + 0.5 * r0);
    float band = exp(-d * d / 0.008) + 0.5 * exp(-(d - 0.22) * (d - 0.22) / 0.0015);
    vec3 glassRgb = mix(vec3(0.42, 0.52, 0.56), vec3(0.9, 0.94, 1.0), clamp(band, 0.0, 1.0));
    float glassA = 0.12 + 0.22 * clamp(band, 0.0, 1.0);

    // Glass over curtain (the glass is outermost), straight alpha out.
    float a = glassA + curtainA * (1.0 - glassA);
    vec3 rgb = (glassRgb * glassA + curtain * curtainA * (1.0 - glassA)) / max(a, 1e-6);
    return vec4(rgb, a);
}
