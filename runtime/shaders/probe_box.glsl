// The proxy boxes as the probe passes read them (probes.cpp's GpuBox): an oriented box with
// one flat albedo per face (+u, -u, +y, -y, +w, -w), and the capture's cube faces.
struct ProxyBox {
    vec4 centre;    // xyz; w: unused
    vec4 u;         // unit plan axis u; w: half size along u
    vec4 w;         // unit plan axis w; w: half size along w
    vec4 up;        // xyz (0, 1, 0); w: half size along y
    vec4 colours[6];
};
layout(std430, binding = 0) readonly buffer Boxes { ProxyBox boxes[]; };

// Cube face f (+X, -X, +Y, -Y, +Z, -Z): forward and up; right = cross(forward, up). Texel
// (x, y) of a size² face (GL rows: y = 0 at the bottom) looks along
// forward + sx · right + sy · up, with sx, sy its centre in [-1, 1].
const vec3 kFaceForward[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 kFaceUp[6] = vec3[6](vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 0, -1), vec3(0, 0, 1), vec3(0, 1, 0), vec3(0, 1, 0));
