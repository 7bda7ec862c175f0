#version 430 core
// The paper's per-multicage vertex shader (§4): each mesh vertex sums its cage coordinates
// times the pose in the vertex shader, the GPU rasterises the deformed mesh, and the fragment
// shader (deform_image.frag or deform_maps.frag) samples the image at the interpolated rest
// position. The compute pipeline (positions.comp, raster.comp, gather.comp) does the same in
// compute shaders; this one stays for drawing into a caller's framebuffer (the editor).
#include "mesh_grid.glsl"
#include "mesh_positions.glsl"

// Output pixel coordinates to clip space: clip = p * toClip.xy + toClip.zw.
layout(location = 0) uniform vec4 toClip;

noperspective out vec2 restPosition;

void main() {
    const ivec2 e = ivec2(gl_VertexID % MESH_W, gl_VertexID / MESH_W);
    // Ring vertices sample the border pixel next to them (the fragment shaders also clamp).
    restPosition = meshSource(e);
    gl_Position = vec4(meshPosition(e) * toClip.xy + toClip.zw, 0.0, 1.0);
}
