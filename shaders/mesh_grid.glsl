// The deformation mesh (included by deform.vert, positions.comp, raster.comp, gather.comp).
// Constants inserted by the library for each multicage:
//   GRID_W, GRID_H     node grid; node k sits at min(k * GRID_STEP, IMAGE - 1)
//   GRID_STEP          pixels between nodes
//   IMAGE_W, IMAGE_H   image size
// The mesh is the node grid plus a ring of vertices on the image frame around it: MESH_W x
// MESH_H vertices, vertex (ex, ey) being node (ex - 1, ey - 1). Each cell (a, b, c, d) =
// ((x, y), (x+1, y), (x, y+1), (x+1, y+1)) holds the triangles (a, b, c) and (b, d, c), in
// row-major cell order, the later triangle winning a pixel two triangles cover: the rule
// kCellTriangles states once for C++ (modules/core/internal/.../backend_contract.hpp).

#define MESH_W (GRID_W + 2)
#define MESH_H (GRID_H + 2)
#define CELLS_W (MESH_W - 1)
#define CELLS_H (MESH_H - 1)

// The node under mesh vertex e (ring vertices: the nearest border node).
ivec2 meshNode(ivec2 e) {
    return clamp(e - 1, ivec2(0), ivec2(GRID_W - 1, GRID_H - 1));
}

// Where mesh vertex e samples the image: its node's rest position, so ring vertices sample
// the border pixel next to them.
vec2 meshSource(ivec2 e) {
    return vec2(min(meshNode(e) * GRID_STEP, ivec2(IMAGE_W - 1, IMAGE_H - 1)));
}

// The vertices of triangle t (0-based, in drawing order) as mesh vertex coordinates.
void meshTriangle(uint t, out ivec2 e0, out ivec2 e1, out ivec2 e2) {
    const uint row = t / uint(2 * CELLS_W), i = t % uint(2 * CELLS_W);
    const ivec2 a = ivec2(int(i / 2u), int(row));
    if (i % 2u == 0u) {
        e0 = a, e1 = a + ivec2(1, 0), e2 = a + ivec2(0, 1);  // (a, b, c)
    } else {
        e0 = a + ivec2(1, 0), e1 = a + ivec2(1, 1), e2 = a + ivec2(0, 1);  // (b, d, c)
    }
}
