// SPDX-License-Identifier: Zlib
// Storage layouts of the double-precision final pass (needs GL_ARB_gpu_shader_fp64). Mirrored by
// hydrotex/gpu/ShaderLayouts.hpp, checked by tests/gpu/test_shader_layouts.cpp.

// Geometry-only sums of one 256-texel block of the mass pass (TextureMassIntegrator's): the cone
// covariance terms 3/5 v C (xx yy zz xy xz yz, m^5) and sum |v| (m^3).
struct BlockGeometry {
  double covariance[6];
  double absVolume;
  double unused;
};

// Per-body double sums (hydrostatics: FlatWettedSums in order; mass: mass, first moment times
// 3/4, second moment xx yy zz xy xz yz, lowest density).
struct BodySums {
  double value[12];
};
