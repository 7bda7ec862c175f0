#version 430 core
// Texture mapping (paper §4): each output pixel samples the source image bilinearly at the
// rest position the mesh interpolates for it. The bilinear weights are computed here in
// float rather than by the texture unit, whose 8-bit weights would cost precision.

layout(binding = 2) uniform sampler2D image;  // normalised (8U, 16U) or float texels

noperspective in vec2 restPosition;
layout(location = 0) out vec4 color;

void main() {
    const ivec2 last = textureSize(image, 0) - 1;
    const vec2 f0 = floor(restPosition);
    const vec2 f = restPosition - f0;
    const ivec2 i0 = clamp(ivec2(f0), ivec2(0), last);
    const ivec2 i1 = clamp(ivec2(f0) + 1, ivec2(0), last);
    const vec4 a = texelFetch(image, i0, 0);
    const vec4 b = texelFetch(image, ivec2(i1.x, i0.y), 0);
    const vec4 c = texelFetch(image, ivec2(i0.x, i1.y), 0);
    const vec4 d = texelFetch(image, i1, 0);
    color = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}
