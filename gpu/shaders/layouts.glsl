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
