// SPDX-License-Identifier: GPL-3.0-or-later
// Blinn-Phong intensity with a headlight (light at the camera), in eye space, shininess 32 (five
// squarings: pow() is slow on software rasterisers). Returns an intensity in
// [0, 1] that the composite adds or multiplies without changing the hue.
// material: ambient, diffuse and specular weights.
float blinnPhong(vec3 nEye, vec3 toEye, vec3 material) {
  vec3 n = nEye;
  vec3 l = toEye; // headlight
  vec3 h = normalize(l + toEye);
  float d = max(dot(n, l), 0.0);
  float s = d > 0.0 ? max(dot(n, h), 0.0) : 0.0;
  s *= s;
  s *= s;
  s *= s;
  s *= s;
  s *= s;
  return clamp(material.x + material.y * d + material.z * s, 0.0, 1.0);
}
