// SPDX-License-Identifier: Zlib
// Storage layouts shared by the compute shaders (std430). Mirrored member for member by the C++
// structs of hydrotex/gpu/ShaderLayouts.hpp; tests/gpu/test_shader_layouts.cpp computes the std430
// offsets of every struct here and compares them with offsetof/sizeof, no context needed.
// One member per line, so that the test can read them.

// One covered texel for the hydrostatics pass: PT, VAT, area and edges (body frame). Scalars only,
// so that the stride is 52 bytes, not 64 (vec3 members would align to 16).
struct HydroTexel {
  float px;
  float py;
  float pz;
  float ax;
  float ay;
  float az;
  float area;
  float ux;
  float uy;
  float uz;
  float vx;
  float vy;
  float vz;
};

// One covered texel for the mass pass: the cone's apex-to-base vector p - c (m) and volume (m^3).
struct MassTexel {
  vec4 offsetAndVolume;
};

// A run of consecutive texels of one body, reduced by one workgroup. Bounds (body frame) let the
// hydrostatics pass skip chunks wholly above the surface.
struct Chunk {
  uint body;
  uint begin;
  uint count;
  float centerX;
  float centerY;
  float centerZ;
  float halfX;
  float halfY;
  float halfZ;
  uint correctionBegin;
  uint correctionCount;
  // Its entry in ChunkMoments (hydrostatics) or BlockGeometry (mass): its own or its model's.
  uint table;
};

// The moment correction of a texel of several pieces (core's SurfaceTextures::momentCorrection):
// Sum_k c_k A_k^T - p A^T (m^3, body frame), row-major [3 i + k], and momentReach (m); `texel` is
// its index within its chunk. A chunk's are correctionCount entries from correctionBegin.
struct TexelCorrection {
  uint texel;
  float moment[9];
  float reach;
};

// A body's pose for this step: rows of the rotation, w = the offset of the body origin from the
// frame origin (t_x, h, t_z), so x' = R p + offset.
struct BodyPose {
  vec4 row0;
  vec4 row1;
  vec4 row2;
};

// A body's chunk range and, for the mass pass, its model this call (mode 0: uniform density,
// 1: density map, 2: not asked this call).
struct BodyRange {
  uint chunkBegin;
  uint chunkEnd;
  uint mode;
  float uniformDensity;
};

// Per-workgroup float partial sums (hydrostatics: the 11 FlatWettedSums; mass: mass, first
// moment, second moment xx yy zz xy xz yz, density-weighted |v|, lowest density).
struct Partial {
  float value[12];
};

// Pre-summed moments of one chunk's texels about its bounds centre c (body frame, q = p - c), for
// the chunks wholly under a flat surface (TextureHydrostatics' tile moments): 0 sum |A| (m^2),
// 1..3 sum A_k (m^2), 4..12 sum q_i A_k at 4 + 3 i + k (m^3), 13..30 sum q_i q_j A_k at
// 13 + 3 pair + k, pairs xx xy xz yy yz zz (m^4), 31 unused.
struct ChunkMoments {
  float value[32];
};

// Per storage run, per step: the indirect dispatch of the texel pass over the chunks that
// cross the surface (x = their count, y = z = 1) and the count of wholly submerged chunks.
struct SegmentCounters {
  uint crossingGroups;
  uint one0;
  uint one1;
  uint submergedChunks;
};

// A deforming body's piece (SurfaceBake's TexelPiece with its share of the texel's UV area), for
// the GPU re-evaluation of PT/VAT (deform_texels.comp), uploaded once.
struct DeformPiece {
  uint triangle;
  float areaFraction;
  float centroidBary1;
  float centroidBary2;
  float uvShare;
};

// A deforming body's triangle: vertex indices and the UV-to-surface map's coefficients
// (SurfaceEvaluator's UvMap: edgeU = cu1 e1 + cu2 e2, edgeV = cv1 e1 + cv2 e2), uploaded once.
struct DeformTriangle {
  uint vertex0;
  uint vertex1;
  uint vertex2;
  float cu1;
  float cu2;
  float cv1;
  float cv2;
};

// Per triangle, per step (deform_triangles.comp): vertex 0, edges e1 e2, area vector, area,
// texel edges on the surface (m, m^2): 0..2 p0, 3..5 e1, 6..8 e2, 9..11 area vector, 12 area,
// 13..15 edgeU, 16..18 edgeV, 19 unused.
struct TriangleFrame {
  float value[20];
};

// One Gerstner wave for the wavy-surface pass (core's GerstnerWaves::Component, in float): wave
// number k (1/m), unit travel direction (x, z), amplitude A (m) and horizontal displacement Q A
// (m). Its phase depends on the body's frame origin and the time: per body, in BodySurface data.
struct GerstnerComponent {
  float waveNumber;
  float dirX;
  float dirZ;
  float amplitude;
  float horizontal;
};

// A body's place on a height grid (HeightGrid): the cell holding its frame origin o, o's offset
// inside that cell (in spacings), the height of the uploaded samples' reference above o_y (m), so
// that the pass works with small numbers wherever the grid and the body lie, and the highest
// sample above o_y (m): texels wholly above it are dry without a look-up.
struct GridFrame {
  int cellX;
  int cellZ;
  float fracX;
  float fracZ;
  float heightOffset;
  float dryLevel;
};

// A GPU-deformed body's geometry sums over one 256-texel mass block (deform_mass.comp), in float:
// 0..5 the cone covariance terms 3/5 v C (xx yy zz xy xz yz, m^5), 6 sum |v| (m^3), 7 sum v
// (m^3), 8 sum |A| (m^2), 9..11 sum |A| d (m^3), 12..17 sum |A| (d d^T + C) (xx yy zz xy xz yz,
// m^4), 18..19 unused; d = p - c, v = d . A / 3, C the texel's patch covariance. The host turns
// them into BlockGeometry and the body's shell sums, as it does from host textures.
struct MassBlock {
  float value[20];
};
