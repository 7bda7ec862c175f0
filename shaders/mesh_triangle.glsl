// A deformed mesh triangle as the CPU backend's rasteriser sets it up (mesh_raster.cpp,
// drawTriangle), in double precision with the same formulas in the same order, for
// raster.comp (which pixels it covers) and gather.comp (the inverse map there). Mirroring the
// CPU operation for operation is what makes GPU and CPU maps agree pixel for pixel; `precise`
// keeps the compiler from fusing multiply-adds, which would round differently.
// Needs mesh_grid.glsl and a Positions buffer `positions` of the deformed mesh vertices.

double crossD(dvec2 a, dvec2 b) {
    precise double r = a.x * b.y - a.y * b.x;
    return r;
}

struct Triangle {
    dvec2 q0, q1, q2;             // deformed vertices
    double ax[3], ay[3], a0[3];   // barycentric l_i(x, y) = ax x + ay y + a0 (i = 0, 1, 2)
};

// The triangle's vertices; false for one with a vertex at infinity or NaN, which the CPU
// drops through its area test (a GPU need not evaluate that test the IEEE way).
bool loadTriangle(uint t, out Triangle tri) {
    ivec2 e0, e1, e2;
    meshTriangle(t, e0, e1, e2);
    const vec2 f0 = positions[e0.y * MESH_W + e0.x], f1 = positions[e1.y * MESH_W + e1.x],
               f2 = positions[e2.y * MESH_W + e2.x];
    tri.q0 = dvec2(f0), tri.q1 = dvec2(f1), tri.q2 = dvec2(f2);
    return !(any(isinf(f0)) || any(isnan(f0)) || any(isinf(f1)) || any(isnan(f1)) ||
             any(isinf(f2)) || any(isnan(f2)));
}

// The barycentric functions; false for a degenerate triangle (the CPU's |area| <= 1e-12).
bool setUpTriangle(inout Triangle tri) {
    const double area = crossD(tri.q1 - tri.q0, tri.q2 - tri.q0);
    if (!(abs(area) > 1e-12LF)) return false;
    const double inv = 1.0LF / area;
    // l_i = (cross(a, b) + x (a.y - b.y) + y (b.x - a.x)) / area for the edge (a, b)
    // opposite vertex i.
    const dvec2 ea[3] = dvec2[3](tri.q1, tri.q2, tri.q0), eb[3] = dvec2[3](tri.q2, tri.q0, tri.q1);
    for (int k = 0; k < 3; ++k) {
        precise double x = (ea[k].y - eb[k].y) * inv, y = (eb[k].x - ea[k].x) * inv,
                       c = crossD(ea[k], eb[k]) * inv;
        tri.ax[k] = x, tri.ay[k] = y, tri.a0[k] = c;
    }
    return true;
}
