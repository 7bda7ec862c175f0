#version 430 core
// Inverse maps for cv::remap: each output pixel stores the rest position it comes from.

noperspective in vec2 restPosition;
layout(location = 0) out vec2 map;

void main() { map = restPosition; }
