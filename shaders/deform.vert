#version 430 core
// The per-multicage vertex shader (paper §4). The library inserts these constants after the
// #version line for each multicage:
//   GRID_W, GRID_H     node grid (the mesh has one vertex per node)
//   GRID_STEP          pixels between nodes; node k sits at min(k * GRID_STEP, IMAGE - 1)
//   IMAGE_W, IMAGE_H   image size
//   BLOCKS             ceil(c / 4) coefficient blocks (paper Eq. 6)
//   BLOCK_COLS         blocks per texture row (Eq. 6); BLOCKS_PER_LAYER blocks per layer
//   LAYERED            1: coefficients in a 2D texture array (layouts beyond GL_MAX_TEXTURE_SIZE)
//   COEFFICIENTS       c, user vertices + 4 frame corners (the last four)
// The mesh is the node grid plus a ring of vertices on the image frame around it:
// (GRID_W + 2) x (GRID_H + 2) vertices, vertex (ex, ey) being node (ex - 1, ey - 1).

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

void main() {
    const ivec2 e = ivec2(gl_VertexID % (GRID_W + 2), gl_VertexID / (GRID_W + 2));
    const ivec2 g = clamp(e - 1, ivec2(0), ivec2(GRID_W - 1, GRID_H - 1));
    const vec2 x = vec2(min(g * GRID_STEP, ivec2(IMAGE_W - 1, IMAGE_H - 1)));
    // Ring vertices sample the border pixel next to them (the fragment shaders also clamp).
    restPosition = x;
    vec2 p;
    if (any(notEqual(e, g + 1))) {
        // A ring vertex on the frame follows it as mean value coordinates do on a polygon
        // edge: the frame corners interpolated linearly. It keeps the half-pixel band between
        // the frame and the border nodes covered however those nodes move (mesh_raster.cpp).
        const vec2 r = vec2(e.x == 0 ? -0.5 : (e.x == GRID_W + 1 ? float(IMAGE_W) - 0.5 : x.x),
                            e.y == 0 ? -0.5 : (e.y == GRID_H + 1 ? float(IMAGE_H) - 0.5 : x.y));
        const vec2 uv = (r + 0.5) / vec2(IMAGE_W, IMAGE_H);
        p = r + (1.0 - uv.x) * (1.0 - uv.y) * delta(COEFFICIENTS - 4) +
            uv.x * (1.0 - uv.y) * delta(COEFFICIENTS - 3) + uv.x * uv.y * delta(COEFFICIENTS - 2) +
            (1.0 - uv.x) * uv.y * delta(COEFFICIENTS - 1);
    } else {
        // Displacement form p' = x + sum_j CC_j (v'_j - v_j): exact for the rest pose, and
        // accurate with half-float coefficients.
        p = x;
        for (int b = 0; b < BLOCKS; ++b) {
            const vec4 cc = block(b, g);
            const vec4 d01 = texelFetch(poseDelta, 2 * b, 0);
            const vec4 d23 = texelFetch(poseDelta, 2 * b + 1, 0);
            p += cc.x * d01.xy + cc.y * d01.zw + cc.z * d23.xy + cc.w * d23.zw;
        }
    }
    gl_Position = vec4(p * toClip.xy + toClip.zw, 0.0, 1.0);
}
