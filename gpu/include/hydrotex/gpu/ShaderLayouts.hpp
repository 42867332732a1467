// SPDX-License-Identifier: Zlib
#pragma once
/// @file ShaderLayouts.hpp
/// C++ mirrors of the std430 storage structs of gpu/shaders/layouts.glsl and layouts_fp64.glsl,
/// member for member, so that buffers are filled and read with plain memcpy. Their offsets are
/// checked against the shader text by tests/gpu/test_shader_layouts.cpp (no context needed).

#include <cstdint>

namespace hydrotex::gpu::layout {

/// One covered texel for the hydrostatics pass (body frame), 52 bytes.
struct HydroTexel {
  float px, py, pz;   ///< PT (m)
  float ax, ay, az;   ///< VAT (m^2)
  float area;         ///< m^2
  float ux, uy, uz;   ///< texel u edge on the surface (m)
  float vx, vy, vz;   ///< texel v edge on the surface (m)
};

/// One covered texel for the mass pass: cone apex-to-base vector (m) and cone volume (m^3).
struct MassTexel {
  float offsetAndVolume[4];  ///< p - c (m) then (p - c) . A / 3 (m^3)
};

/// A run of consecutive texels of one body, reduced by one workgroup.
struct Chunk {
  std::uint32_t body;                 ///< body index
  std::uint32_t begin;                ///< first texel, in its storage segment
  std::uint32_t count;                ///< texels
  float centerX, centerY, centerZ;    ///< bounds centre (m, body frame)
  float halfX, halfY, halfZ;          ///< bounds half extent (m, body frame), conservative
  std::uint32_t correctionBegin;      ///< its texels' first TexelCorrection (hydrostatics chunks)
  std::uint32_t correctionCount;      ///< its texels' TexelCorrections (0 for mass chunks)
  /// Its entry in its pass's per-chunk table (hydrostatics: ChunkMoments; mass: BlockGeometry):
  /// its own, or, for an instance (addInstance), its model's chunk's, so that the tables hold
  /// each model once.
  std::uint32_t table;
};

/// The moment correction of a texel of several pieces (SurfaceTextures::momentCorrection and
/// momentReach), 44 bytes.
struct TexelCorrection {
  std::uint32_t texel;  ///< the texel's index within its chunk
  float moment[9];      ///< Sum_k c_k A_k^T - p A^T (m^3, body frame), row-major [3 i + k]
  float reach;          ///< largest distance from p to a piece's centroid (m)
};

/// A body's pose for one step: rotation rows, w = offset of the body origin from (t_x, h, t_z).
struct BodyPose {
  float row0[4];  ///< R row 0, offset x (m)
  float row1[4];  ///< R row 1, offset y (m)
  float row2[4];  ///< R row 2, offset z (m)
};

/// A body's chunk range and, for the mass pass, its model this call.
struct BodyRange {
  std::uint32_t chunkBegin;  ///< first chunk (global index)
  std::uint32_t chunkEnd;    ///< one past the last chunk
  std::uint32_t mode;        ///< 0 uniform density, 1 density map, 2 not asked this call
  float uniformDensity;      ///< kg/m^3 (mode 0)
};

/// Per-workgroup float partial sums.
struct Partial {
  float value[12];  ///< see layouts.glsl
};

/// Pre-summed moments of one chunk about its bounds centre q = p - c (body frame): [0] sum |A|
/// (m^2), [1..3] sum A_k (m^2), [4 + 3 i + k] sum q_i A_k (m^3), [13 + 3 pair + k] sum q_i q_j A_k
/// for the pairs xx xy xz yy yz zz (m^4), [31] unused.
struct ChunkMoments {
  float value[32];  ///< see above
};

/// Per storage segment and step: the texel pass's indirect dispatch and the submerged count.
struct SegmentCounters {
  std::uint32_t crossingGroups;   ///< chunks crossing the surface (workgroups of the texel pass)
  std::uint32_t one0;             ///< 1 (indirect dispatch y)
  std::uint32_t one1;             ///< 1 (indirect dispatch z)
  std::uint32_t submergedChunks;  ///< chunks wholly under the surface (their moments were added)
};

/// A deforming body's piece: SurfaceBake's TexelPiece and its share of the texel's UV area.
struct DeformPiece {
  std::uint32_t triangle;  ///< mesh triangle index
  float areaFraction;      ///< piece UV area / triangle UV area
  float centroidBary1;     ///< barycentric of the piece's centroid on vertex 1
  float centroidBary2;     ///< ... on vertex 2
  float uvShare;           ///< piece UV area / the texel's covered UV area
};

/// A deforming body's triangle: vertex indices and UV-to-surface map coefficients (per texel).
struct DeformTriangle {
  std::uint32_t vertex0, vertex1, vertex2;  ///< indices into the vertex positions
  float cu1, cu2, cv1, cv2;                 ///< edgeU = cu1 e1 + cu2 e2, edgeV = cv1 e1 + cv2 e2
};

/// Per triangle per step: p0 (m), e1, e2 (m), area vector (m^2), area (m^2), edgeU, edgeV (m).
struct TriangleFrame {
  float value[20];  ///< see layouts.glsl
};

/// One Gerstner wave for the wavy-surface pass (GerstnerWaves::Component in float).
struct GerstnerComponent {
  float waveNumber;  ///< k (1/m)
  float dirX, dirZ;  ///< unit travel direction
  float amplitude;   ///< A (m)
  float horizontal;  ///< Q A (m)
};

/// A body's place on a height grid: the cell of its frame origin o, o's offset in it, the samples'
/// reference height above o_y.
struct GridFrame {
  std::int32_t cellX, cellZ;  ///< cell index of o along x and z
  float fracX, fracZ;         ///< o's offset inside that cell (in spacings)
  float heightOffset;         ///< reference of the uploaded samples minus o_y (m)
  float dryLevel;             ///< highest sample minus o_y (m)
};

/// A GPU-deformed body's float geometry sums over one 256-texel mass block (deform_mass.comp).
struct MassBlock {
  float value[20];  ///< see layouts.glsl
};

/// Geometry-only sums of one mass block: 3/5 v C (m^5) and sum |v| (m^3).
struct BlockGeometry {
  double covariance[6];  ///< xx yy zz xy xz yz
  double absVolume;      ///< m^3
  double unused;         ///< padding to 64 bytes
};

/// Per-body double sums of the final pass.
struct BodySums {
  double value[12];  ///< see layouts_fp64.glsl
};

}  // namespace hydrotex::gpu::layout
