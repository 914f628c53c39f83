// Wind from Pivot Painter 2 data (native preset: exporters/pivot_painter.hpp): every element
// of a tree turns about its own pivot, towards where the wind blows, by an angle that grows
// with the wind's speed and with the element's level (trunk 0, branches 1, twigs 2), gusting
// with a phase of its own. A vertex is turned by its element first, then by each parent up
// to the trunk, so a child's pivot moves exactly as its parent carries it.
layout(binding = 9) uniform sampler2D pivotTexture;  // RGB pivot (m, tree space), A parent index (a root: its own)
layout(binding = 10) uniform sampler2D axisTexture;  // RGB unit X axis, A extent (m)

ivec2 pivotTexel(int index, int width) { return ivec2(index % width, index / width); }

// p turned by `angle` radians about the unit axis `k` (Rodrigues).
vec3 turnAbout(vec3 p, vec3 k, float angle) {
    float c = cos(angle), s = sin(angle);
    return p * c + cross(k, p) * s + k * dot(k, p) * (1.0 - c);
}

// Radians an element of `level` bends at wind speed `speed` (m/s) at `time`: stiff trunks,
// supple twigs; gusts at a frequency that rises with the level.
float windAngle(int level, vec3 pivot, float speed, float time, float phase) {
    const float perMetrePerSecond[3] = float[3](0.004, 0.012, 0.03);
    const float hertz[3] = float[3](0.25, 0.6, 1.3);
    int l = min(level, 2);
    float gust = 0.65 + 0.35 * sin(6.2831853 * hertz[l] * time + phase + dot(pivot, vec3(1.7, 0.9, 2.3)));
    return perMetrePerSecond[l] * speed * gust;
}

// Moves tree-space position p and normal n of a vertex whose element's texel is at uv1.
// windDir: unit, in tree space; speed 0 leaves both exactly as they are.
void windBend(inout vec3 p, inout vec3 n, vec2 uv1, vec3 windDir, float speed, float time, float phase) {
    if (speed <= 0.0) return;
    ivec2 size = textureSize(pivotTexture, 0);
    int element = int(floor(uv1.x * float(size.x))) + int(floor(uv1.y * float(size.y))) * size.x;
    int depth = 0;
    for (int i = element, k = 0; k < 8; ++k) {
        int parent = int(texelFetch(pivotTexture, pivotTexel(i, size.x), 0).a + 0.5);
        if (parent == i) break;
        i = parent;
        ++depth;
    }
    int i = element;
    for (int level = depth; level >= 0; --level) {
        vec4 pivot = texelFetch(pivotTexture, pivotTexel(i, size.x), 0);
        vec3 axis = texelFetch(axisTexture, pivotTexel(i, size.x), 0).xyz;
        vec3 k = cross(axis, windDir);  // turning about it carries the element's X towards the wind
        float s = length(k);
        float angle = windAngle(level, pivot.xyz, speed, time, phase) * s;
        if (s > 1e-4 && angle != 0.0) {
            k /= s;
            p = pivot.xyz + turnAbout(p - pivot.xyz, k, angle);
            n = turnAbout(n, k, angle);
        }
        i = int(pivot.a + 0.5);
    }
}
