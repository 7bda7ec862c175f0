#version 430 core
// Compute pipeline, pass 3 of 3: every output pixel takes the triangle raster.comp left in
// it, evaluates that triangle's inverse map there exactly as the CPU backend does, and
// writes either that map (GATHER_MAPS) or the image sampled bilinearly at it. It resets the
// pixel's owner to 0 for the next pose, which is cheaper than clearing the whole buffer in a
// pass of its own.
// Constants: GATHER_MAPS (1: RG32F maps; 0: the image), OUTPUT_FORMAT (the output image's
// format qualifier), UNCOVERED (the map value of pixels no triangle covers).
#include "mesh_grid.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, binding = 0) readonly buffer Positions { vec2 positions[]; };
layout(std430, binding = 1) buffer Owners { uint owner[]; };
// The size of the image drawn into (raster.comp's outputSize); sources stay in the input's
// IMAGE_W x IMAGE_H.
layout(location = 1) uniform ivec2 outputSize;

#include "mesh_triangle.glsl"

#if GATHER_MAPS
layout(rg32f, binding = 0) writeonly uniform image2D maps;
#else
layout(binding = 2) uniform sampler2D image;  // normalised (8U, 16U) or float texels
layout(OUTPUT_FORMAT, binding = 0) writeonly uniform image2D outputImage;
layout(location = 0) uniform vec4 border;
#endif

void main() {
    const ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (px.x >= outputSize.x || px.y >= outputSize.y) return;
    const uint at = uint(px.y * outputSize.x + px.x);
    const uint o = owner[at];
    if (o == 0u) {
#if GATHER_MAPS
        imageStore(maps, px, vec4(UNCOVERED, UNCOVERED, 0.0, 0.0));
#else
        imageStore(outputImage, px, border);
#endif
        return;
    }
    owner[at] = 0u;
    // The affine map from the deformed triangle to its rest triangle, set up as the CPU's
    // drawTriangle sets it up: r = p2 + l0 (p0 - p2) + l1 (p1 - p2).
    const uint t = o - 1u;
    Triangle tri;
    loadTriangle(t, tri);  // raster.comp only marks pixels of finite, non-degenerate triangles
    setUpTriangle(tri);
    ivec2 e0, e1, e2;
    meshTriangle(t, e0, e1, e2);
    const dvec2 p2 = dvec2(meshSource(e2));
    const dvec2 d0 = dvec2(meshSource(e0)) - p2, d1 = dvec2(meshSource(e1)) - p2;
    precise double mxx = tri.ax.x * d0.x + tri.ax.y * d1.x;
    precise double mxy = tri.ay.x * d0.x + tri.ay.y * d1.x;
    precise double mx0 = p2.x + tri.a0.x * d0.x + tri.a0.y * d1.x;
    precise double myx = tri.ax.x * d0.y + tri.ax.y * d1.y;
    precise double myy = tri.ay.x * d0.y + tri.ay.y * d1.y;
    precise double my0 = p2.y + tri.a0.x * d0.y + tri.a0.y * d1.y;
    precise double bx = mxy * double(px.y) + mx0;
    precise double by = myy * double(px.y) + my0;
    precise double rx = mxx * double(px.x) + bx;
    precise double ry = myx * double(px.x) + by;
    // Clamped to the image, as the CPU clamps (interpolation can round a hair outside).
    const vec2 r = clamp(vec2(float(rx), float(ry)), vec2(0.0), vec2(IMAGE_W - 1, IMAGE_H - 1));
#if GATHER_MAPS
    imageStore(maps, px, vec4(r, 0.0, 0.0));
#else
    // Bilinear weights in float (deform_image.frag explains why not the texture unit's).
    const ivec2 last = ivec2(IMAGE_W - 1, IMAGE_H - 1);
    const vec2 f0 = floor(r);
    const vec2 f = r - f0;
    const ivec2 i0 = ivec2(f0);
    const ivec2 i1 = min(i0 + 1, last);
    const vec4 a = texelFetch(image, i0, 0);
    const vec4 b = texelFetch(image, ivec2(i1.x, i0.y), 0);
    const vec4 c = texelFetch(image, ivec2(i0.x, i1.y), 0);
    const vec4 d = texelFetch(image, i1, 0);
    imageStore(outputImage, px, mix(mix(a, b, f.x), mix(c, d, f.x), f.y));
#endif
}
