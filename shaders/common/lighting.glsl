// Blinn-Phong intensity with a headlight (light at the camera), in eye space, shininess 32 (five
// squarings: pow() is slow on software rasterisers). Returns an intensity in
// [0, 1] that the composite adds or multiplies without changing the hue.
uniform float u_ambient = 0.25;
uniform float u_diffuse = 0.65;
uniform float u_specular = 0.35;

float blinnPhong(vec3 nEye, vec3 toEye) {
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
  return clamp(u_ambient + u_diffuse * d + u_specular * s, 0.0, 1.0);
}
