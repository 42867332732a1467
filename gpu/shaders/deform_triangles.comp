// SPDX-License-Identifier: Zlib
// Deforming bodies, first pass: per triangle its frame from the moved vertex positions (the
// per-triangle half of core's SurfaceEvaluator::evaluate): vertex 0, edges, area vector, area and
// the texel edges on the surface. In float from float positions (the CPU forms edges in double):
// a triangle's area keeps float rounding relative to its vertices' distance from the body origin.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // x y z per vertex
layout(std430, binding = 1) readonly buffer Triangles { DeformTriangle triangles[]; };
layout(std430, binding = 2) writeonly buffer Frames { TriangleFrame frames[]; };

uniform uint triangleCount;
uniform uint vertexCount;

vec3 vertexAt(uint i) { return vec3(vertices[3u * i], vertices[3u * i + 1u], vertices[3u * i + 2u]); }

void main() {
  uint t = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (t >= triangleCount) return;
  DeformTriangle tri = triangles[t];
  float f[20];
  for (int k = 0; k < 20; ++k) f[k] = 0.0;
  if (tri.vertex0 < vertexCount && tri.vertex1 < vertexCount && tri.vertex2 < vertexCount) {
    vec3 p0 = vertexAt(tri.vertex0);
    vec3 e1 = vertexAt(tri.vertex1) - p0, e2 = vertexAt(tri.vertex2) - p0;
    vec3 a = 0.5 * cross(e1, e2);
    vec3 eu = tri.cu1 * e1 + tri.cu2 * e2, ev = tri.cv1 * e1 + tri.cv2 * e2;
    for (int c = 0; c < 3; ++c) {
      f[c] = p0[c];
      f[3 + c] = e1[c];
      f[6 + c] = e2[c];
      f[9 + c] = a[c];
      f[13 + c] = eu[c];
      f[16 + c] = ev[c];
    }
    f[12] = length(a);
  }  // else: carries nothing (a triangle naming a missing vertex)
  frames[t].value = f;
}
