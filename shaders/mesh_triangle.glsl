// A deformed mesh triangle as the CPU backend's rasteriser sets it up (mesh_raster.cpp,
// drawTriangle), in double precision with the same formulas in the same order, for
// raster.comp (which pixels it covers) and gather.comp (the inverse map there). Mirroring the
// CPU operation for operation is what makes GPU and CPU maps agree pixel for pixel; `precise`
// keeps the compiler from fusing multiply-adds, which would round differently.
// Needs mesh_grid.glsl and a Positions buffer `positions` of the deformed mesh vertices.

#include "division.glsl"

double crossD(dvec2 a, dvec2 b) {
    precise double r = a.x * b.y - a.y * b.x;
    return r;
}

// No arrays of doubles and no index chosen at run time. With the set-up in double[3] arrays
// (struct members and locals, indexed in loops) NVIDIA's driver (580, H100) gave every set-up
// value rounded to a float (4,691 of 4,704 triangles, GpuArithmetic.TriangleSetUpIsTheCpus),
// which cost the maps their agreement with the CPU and left pixels on shared edges uncovered;
// with dvec3 members and one call per edge, none. Which of those constructs the driver mishandles
// was not isolated.
struct Triangle {
    dvec2 q0, q1, q2;  // deformed vertices
    dvec3 ax, ay, a0;  // barycentric l_i(x, y) = ax[i] x + ay[i] y + a0[i] (i = 0, 1, 2)
};

// The triangle's vertices; false for one with a vertex at infinity or NaN, which the CPU
// drops through its area test (a GPU need not evaluate that test the IEEE way).
bool loadTriangle(uint t, out Triangle tri) {
    ivec2 e0, e1, e2;
    meshTriangle(t, e0, e1, e2);
    const vec2 f0 = positions[e0.y * MESH_W + e0.x], f1 = positions[e1.y * MESH_W + e1.x],
               f2 = positions[e2.y * MESH_W + e2.x];
    tri.q0 = dvec2(f0);
    tri.q1 = dvec2(f1);
    tri.q2 = dvec2(f2);
    return !(any(isinf(f0)) || any(isnan(f0)) || any(isinf(f1)) || any(isnan(f1)) ||
             any(isinf(f2)) || any(isnan(f2)));
}

// l = (cross(a, b) + x (a.y - b.y) + y (b.x - a.x)) / area for the edge (a, b) opposite a vertex.
void edgeFunction(dvec2 a, dvec2 b, double inv, out double ax, out double ay, out double a0) {
    precise double x = (a.y - b.y) * inv;
    precise double y = (b.x - a.x) * inv;
    precise double c = crossD(a, b) * inv;
    ax = x;
    ay = y;
    a0 = c;
}

// The barycentric functions; false for a degenerate triangle (the CPU's |area| <= 1e-12).
bool setUpTriangle(inout Triangle tri) {
    const double area = crossD(tri.q1 - tri.q0, tri.q2 - tri.q0);
    if (!(abs(area) > 1e-12LF)) return false;
    const double inv = divideRN(1.0LF, area);
    double ax0, ay0, a00, ax1, ay1, a01, ax2, ay2, a02;
    edgeFunction(tri.q1, tri.q2, inv, ax0, ay0, a00);  // opposite q0
    edgeFunction(tri.q2, tri.q0, inv, ax1, ay1, a01);  // opposite q1
    edgeFunction(tri.q0, tri.q1, inv, ax2, ay2, a02);  // opposite q2
    tri.ax = dvec3(ax0, ax1, ax2);
    tri.ay = dvec3(ay0, ay1, ay2);
    tri.a0 = dvec3(a00, a01, a02);
    return true;
}
