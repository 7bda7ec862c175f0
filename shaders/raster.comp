#version 430 core
// Compute pipeline, pass 2 of 3: rasterise the deformed mesh. Each invocation takes one
// triangle (RASTER_SLICES invocations per triangle share its rows, for grid steps where a
// triangle covers many pixels) and marks every pixel centre it covers with atomicMax of its
// triangle number + 1, so that where triangles overlap (a fold-over, or a pixel centre on a
// shared edge) the later triangle in drawing order wins, as in the CPU backend.
//
// Which pixels a triangle covers is decided exactly as mesh_raster.cpp's drawTriangle decides
// it, in double precision with the same formulas and the same edge tolerance: GPU and CPU
// maps cover the same pixels and pick the same triangle (mesh_triangle.glsl).
#include "mesh_grid.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec2 positions[]; };
layout(std430, binding = 1) buffer Owners { uint owner[]; };  // 0: uncovered
// The size of the image drawn into: the input's, or a resize pose's new size (the frame on
// another size's frame, frameOutputSize in backend_contract.hpp). A uniform, not a constant,
// so that a new size costs no new program.
layout(location = 1) uniform ivec2 outputSize;

#include "mesh_triangle.glsl"

// Row y's span [left, right] narrowed to where the edge function l(x) = ax x + c >= eps.
void clipToEdge(double ax, double ay, double a0, double invAx, int y, double eps,
                inout double left, inout double right) {
    precise double c = a0 + ay * double(y);
    precise double bound = (eps - c) * invAx;
    if (ax > 0.0LF) left = max(left, bound);
    else if (ax < 0.0LF) right = min(right, bound);
    else if (c < eps) right = -1.0LF;
}

void main() {
    const uint i = gl_GlobalInvocationID.x;  // triangle within its row of cells
    const uint cellRow = gl_GlobalInvocationID.y / uint(RASTER_SLICES);
    const int slice = int(gl_GlobalInvocationID.y % uint(RASTER_SLICES));
    if (i >= uint(2 * CELLS_W) || cellRow >= uint(CELLS_H)) return;
    const uint t = cellRow * uint(2 * CELLS_W) + i;
    Triangle tri;
    if (!loadTriangle(t, tri)) return;
    const dvec2 q0 = tri.q0, q1 = tri.q1, q2 = tri.q2;
    const double minY = min(min(q0.y, q1.y), q2.y), maxY = max(max(q0.y, q1.y), q2.y);
    if (!(maxY >= 0.0LF && minY <= double(outputSize.y - 1))) return;
    const int ya = int(ceil(max(minY, 0.0LF)));
    const int yb = int(floor(min(maxY, double(outputSize.y - 1))));
    if (ya > yb) return;
    const double minX = min(min(q0.x, q1.x), q2.x), maxX = max(max(q0.x, q1.x), q2.x);
    if (!(maxX >= 0.0LF && minX <= double(outputSize.x - 1))) return;
    const int xa = int(ceil(max(minX, 0.0LF)));
    const int xb = int(floor(min(maxX, double(outputSize.x - 1))));
    if (xa > xb) return;
    if (!setUpTriangle(tri)) return;
    const double eps = -1e-7LF;
    const dvec3 invAx = dvec3(tri.ax.x != 0.0LF ? divideRN(1.0LF, tri.ax.x) : 0.0LF,
                              tri.ax.y != 0.0LF ? divideRN(1.0LF, tri.ax.y) : 0.0LF,
                              tri.ax.z != 0.0LF ? divideRN(1.0LF, tri.ax.z) : 0.0LF);
    for (int y = ya + slice; y <= yb; y += RASTER_SLICES) {
        double left = double(xa), right = double(xb);
        clipToEdge(tri.ax.x, tri.ay.x, tri.a0.x, invAx.x, y, eps, left, right);
        clipToEdge(tri.ax.y, tri.ay.y, tri.a0.y, invAx.y, y, eps, left, right);
        clipToEdge(tri.ax.z, tri.ay.z, tri.a0.z, invAx.z, y, eps, left, right);
        if (!(left <= right)) continue;
        const int xl = int(ceil(left)), xr = int(floor(right));
        for (int x = xl; x <= xr; ++x) atomicMax(owner[y * outputSize.x + x], t + 1u);
    }
}
