#version 430 core
// Inverse maps for cv::remap: each output pixel stores the rest position it comes from.

noperspective in vec2 restPosition;
layout(location = 0) out vec2 map;

void main() {
    // Interpolation can round a hair outside the image: clamp, as the CPU does.
    map = clamp(restPosition, vec2(0.0), vec2(IMAGE_W - 1, IMAGE_H - 1));
}
