#version 430 core
// Compute pipeline, pass 1 of 3: the deformed position of every mesh vertex (the coefficient
// sum of the paper's vertex shader, in a compute shader so that it runs on every
// multiprocessor of the GPU, not only the graphics-capable ones). It reads each packed
// coefficient once: this pass is bound by memory bandwidth.
#include "mesh_grid.glsl"
#include "mesh_positions.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, binding = 0) writeonly buffer Positions { vec2 positions[]; };

void main() {
    const ivec2 e = ivec2(gl_GlobalInvocationID.xy);
    if (e.x >= MESH_W || e.y >= MESH_H) return;
    positions[e.y * MESH_W + e.x] = meshPosition(e);
}
