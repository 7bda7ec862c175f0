// Deformed mesh vertex positions from the packed cage coordinates (paper §4, Eq. 6-7),
// included by deform.vert (the paper's program) and positions.comp (the compute pipeline).
// Needs mesh_grid.glsl and these constants:
//   BLOCKS             ceil(c / 4) coefficient blocks (paper Eq. 6)
//   BLOCK_COLS         blocks per texture row (Eq. 6); BLOCKS_PER_LAYER blocks per layer
//   LAYERED            1: coefficients in a 2D texture array (layouts beyond GL_MAX_TEXTURE_SIZE)
//   COEFFICIENTS       c, user vertices + 4 frame corners (the last four)

#include "division.glsl"

#if LAYERED
layout(binding = 0) uniform sampler2DArray coefficients;
#else
layout(binding = 0) uniform sampler2D coefficients;
#endif
// v'_j - v_j for every vertex, two per texel (xy, zw), zero past the last coefficient; then
// two texels with the posed frame corners v'_{c-4} .. v'_{c-1} themselves.
layout(binding = 1) uniform sampler1D poseDelta;

// Frame corner k (0: top left, 1: top right, 2: bottom right, 3: bottom left) in the pose.
vec2 frameCorner(int k) {
    const vec4 t = texelFetch(poseDelta, 2 * BLOCKS + k / 2, 0);
    return k % 2 == 0 ? t.xy : t.zw;
}

// v'_j - v_j of coefficient j.
vec2 delta(int j) {
    const vec4 t = texelFetch(poseDelta, j / 2, 0);
    return j % 2 == 0 ? t.xy : t.zw;
}

vec4 block(int b, ivec2 g) {
#if LAYERED
    const int slot = b % BLOCKS_PER_LAYER;
    return texelFetch(coefficients,
                      ivec3(g + ivec2(slot % BLOCK_COLS, slot / BLOCK_COLS) * ivec2(GRID_W, GRID_H),
                            b / BLOCKS_PER_LAYER), 0);
#else
    // Paper Eq. 6: block b at block column b mod cols, block row b div cols.
    return texelFetch(coefficients, g + ivec2(b % BLOCK_COLS, b / BLOCK_COLS) * ivec2(GRID_W, GRID_H), 0);
#endif
}

// The deformed position of mesh vertex e. The arithmetic is the CPU backend's, operation for
// operation (Binding::apply, rasterizeMaps), and `precise` forbids fused multiply-adds, so
// both backends compute the same float positions and so rasterise the same mesh.
vec2 meshPosition(ivec2 e) {
    const ivec2 g = meshNode(e);
    const vec2 x = meshSource(e);
    if (any(notEqual(e, g + 1))) {
        // A ring vertex on the frame follows it as mean value coordinates do on a polygon
        // edge: the frame corners interpolated linearly. It keeps the half-pixel band between
        // the frame and the border nodes covered however those nodes move (mesh_raster.cpp;
        // the frame as frameCorners in backend_contract.hpp).
        const vec2 r = vec2(e.x == 0 ? -0.5 : (e.x == GRID_W + 1 ? float(IMAGE_W) - 0.5 : x.x),
                            e.y == 0 ? -0.5 : (e.y == GRID_H + 1 ? float(IMAGE_H) - 0.5 : x.y));
        precise float u = divideRN(r.x + 0.5, float(IMAGE_W)), v = divideRN(r.y + 0.5, float(IMAGE_H));
        precise vec2 p = (1.0 - u) * (1.0 - v) * frameCorner(0) + u * (1.0 - v) * frameCorner(1) +
                         u * v * frameCorner(2) + (1.0 - u) * v * frameCorner(3);
        return p;
    }
    // Displacement form p' = x + sum_j CC_j (v'_j - v_j): exact for the rest pose, and
    // accurate with half-float coefficients. Summed one coefficient at a time, in order.
    precise vec2 p = x;
    for (int b = 0; b < BLOCKS; ++b) {
        const vec4 cc = block(b, g);
        const vec4 d01 = texelFetch(poseDelta, 2 * b, 0);
        const vec4 d23 = texelFetch(poseDelta, 2 * b + 1, 0);
        p += cc.x * d01.xy;
        p += cc.y * d01.zw;
        p += cc.z * d23.xy;
        p += cc.w * d23.zw;
    }
    return p;
}
