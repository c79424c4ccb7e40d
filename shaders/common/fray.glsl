// SPDX-License-Identifier: GPL-3.0-or-later
// Uncertainty as fraying threads: every noise cell (a cube of edge u_lod / u_frayCells mm on the implicit
// voxel grid of Eq. 7) turns the in-surface directions by its own angle, drawn from a hash of the cell
// uniformly in [-1, 1] times u_fray times the cone of uncertainty. Where the cone is 0 nothing turns;
// where it is wide, neighbouring cells advect along different directions and the threads break up. The
// mean direction stays the data's (the angles are symmetric about 0). CPU reference: render/fray.h.

// lowbias32 (Chris Wellons' integer hash), chained over the cell's three coordinates.
uint frayHash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// The cell's signed unit draw in [-1, 1] for population `salt`.
float frayDraw(vec3 world, vec3 origin, float lod, float cells, uint salt) {
  ivec3 c = ivec3(floor((world - origin) / lod * cells));
  uint h = frayHash(uint(c.x) ^ frayHash(uint(c.y) ^ frayHash(uint(c.z) ^ frayHash(salt))));
  return float(h >> 8) * (2.0 / 16777215.0) - 1.0;
}

// v (in the tangent plane of unit normal n) turned by `angle` radians about n.
vec3 frayRotate(vec3 v, vec3 n, float angle) {
  return cos(angle) * v + sin(angle) * cross(n, v);
}
