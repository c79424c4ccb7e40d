#version 450 core
// Depth pre-pass of the projection: lays down the nearest depth so the expensive projection shader runs
// once per visible pixel (early depth test), as the paper's §3.3 suggests for large surfaces.
void main() {}
