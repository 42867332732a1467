// SPDX-License-Identifier: Zlib
// Deforming bodies: one texel's PT, VAT, area and edges from its pieces and their triangles'
// frames (core's SurfaceEvaluator::evaluate, the per-texel half, same float operations). Shared
// by deform_texels.comp (hydrostatics texels) and deform_mass.comp (mass texels), which declare
// nothing at bindings 2..4.

layout(std430, binding = 2) readonly buffer Frames { TriangleFrame frames[]; };
layout(std430, binding = 3) readonly buffer PieceStart { uint pieceStart[]; };  // per body texel + 1
layout(std430, binding = 4) readonly buffer Pieces { DeformPiece pieces[]; };

uniform uint triangleCount;
uniform uint pieceCount;

void evaluateTexel(uint texel, out vec3 p, out vec3 a, out float area, out vec3 eu, out vec3 ev) {
  uint begin = pieceStart[texel], end = min(pieceStart[texel + 1u], pieceCount);
  a = vec3(0.0);
  eu = vec3(0.0);
  ev = vec3(0.0);
  area = 0.0;
  p = vec3(0.0);
  vec3 weighted = vec3(0.0);
  float flux = 0.0;
  bool single = end == begin + 1u && pieces[begin].triangle < triangleCount;
  for (uint k = begin; k < end; ++k) {
    DeformPiece piece = pieces[k];
    if (piece.triangle >= triangleCount) continue;  // a bake of another mesh: skip, never crash
    float f[20] = frames[piece.triangle].value;
    vec3 p0 = vec3(f[0], f[1], f[2]), e1 = vec3(f[3], f[4], f[5]), e2 = vec3(f[6], f[7], f[8]);
    vec3 pieceCentroid = p0 + piece.centroidBary1 * e1 + piece.centroidBary2 * e2;
    vec3 pieceAreaVector = piece.areaFraction * vec3(f[9], f[10], f[11]);
    float pieceArea = piece.areaFraction * f[12];
    a += pieceAreaVector;
    weighted += pieceArea * pieceCentroid;
    flux += dot(pieceCentroid, pieceAreaVector);
    eu += piece.uvShare * vec3(f[13], f[14], f[15]);
    ev += piece.uvShare * vec3(f[16], f[17], f[18]);
    area += pieceArea;
    if (single) p = area > 0.0 ? pieceCentroid : vec3(0.0);
  }
  if (!single) {
    p = area > 0.0 ? weighted / area : vec3(0.0);
    // The shift along A that makes p . A the exact flux, left out where the pieces nearly cancel
    // (SurfaceEvaluator, evaluateSurface).
    float squared = dot(a, a);
    if (squared > 1e-2 * area * area && squared > 0.0) p += a * ((flux - dot(p, a)) / squared);
  }
}
