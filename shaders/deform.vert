#version 430 core
// The per-multicage vertex shader (paper §4). The library inserts these constants after the
// #version line for each multicage:
//   GRID_W, GRID_H     node grid (the mesh has one vertex per node)
//   GRID_STEP          pixels between nodes; node k sits at min(k * GRID_STEP, IMAGE - 1)
//   IMAGE_W, IMAGE_H   image size
//   BLOCKS             ceil(c / 4) coefficient blocks (paper Eq. 6)
//   BLOCK_COLS         blocks per texture row (Eq. 6); BLOCKS_PER_LAYER blocks per layer
//   LAYERED            1: coefficients in a 2D texture array (layouts beyond GL_MAX_TEXTURE_SIZE)

#if LAYERED
layout(binding = 0) uniform sampler2DArray coefficients;
#else
layout(binding = 0) uniform sampler2D coefficients;
#endif
// v'_j - v_j for every vertex, two per texel (xy, zw), zero past the last coefficient.
layout(binding = 1) uniform sampler1D poseDelta;
// Output pixel coordinates to clip space: clip = p * toClip.xy + toClip.zw.
layout(location = 0) uniform vec4 toClip;

noperspective out vec2 restPosition;

// Border nodes are pushed out by this many pixels so that pixel centres lying exactly on the
// mesh border are drawn: GL's top-left rule would drop the last row and column, and border
// nodes moved inwards by rounding-sized amounts would drop whole rows. The CPU backend's
// rasterizeMaps (modules/deform/src/mesh_raster.cpp) uses the same value.
const float kBorderNudge = 1.0 / 64.0;

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

void main() {
    const ivec2 g = ivec2(gl_VertexID % GRID_W, gl_VertexID / GRID_W);
    const vec2 x = vec2(min(g * GRID_STEP, ivec2(IMAGE_W - 1, IMAGE_H - 1)));
    // Displacement form p' = x + sum_j CC_j (v'_j - v_j): exact for the rest pose, and
    // accurate with half-float coefficients.
    vec2 p = x;
    for (int b = 0; b < BLOCKS; ++b) {
        const vec4 cc = block(b, g);
        const vec4 d01 = texelFetch(poseDelta, 2 * b, 0);
        const vec4 d23 = texelFetch(poseDelta, 2 * b + 1, 0);
        p += cc.x * d01.xy + cc.y * d01.zw + cc.z * d23.xy + cc.w * d23.zw;
    }
    // Rest and deformed move together, so the rest pose stays the identity (the fragment
    // shaders clamp the source position back into the image).
    const vec2 nudge = vec2(g.x == 0 ? -kBorderNudge : (g.x == GRID_W - 1 ? kBorderNudge : 0.0),
                            g.y == 0 ? -kBorderNudge : (g.y == GRID_H - 1 ? kBorderNudge : 0.0));
    p += nudge;
    restPosition = x + nudge;
    gl_Position = vec4(p * toClip.xy + toClip.zw, 0.0, 1.0);
}
