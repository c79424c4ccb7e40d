// SPDX-License-Identifier: GPL-3.0-or-later
// The window depth of the surface at linear eye depth `linearDepth` (mm), from the projection's terms of eye
// z (eyeDepth: clip z = x z + y, clip w = z z + w): the depth the composite gives the frame.
float windowDepth(vec4 eyeDepth, float linearDepth) {
  float z = -linearDepth; // eye z
  return 0.5 * (eyeDepth.x * z + eyeDepth.y) / (eyeDepth.z * z + eyeDepth.w) + 0.5;
}
