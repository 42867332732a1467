// SPDX-License-Identifier: Zlib
// First pass of flat-surface hydrostatics, one invocation per chunk (the GPU form of
// TextureHydrostatics' tile hierarchy, core/src/hydrostatics/TextureHydrostatics.cpp): a chunk whose bounds lie
// wholly above the surface writes a zero partial; one wholly under it writes the partial from its
// pre-summed moments in O(1) (the expansion of HydrostaticSums.cpp, addSubmergedMoments, about the
// chunk's centre); only a chunk that crosses the surface is appended to its run's list, which
// the texel pass (hydrostatics_flat.comp) then runs over through an indirect dispatch.
// With surfaceMode (waves, grids, media: hydrostatics_surface.comp) a chunk is dry only above its
// body's dryLevels entry (the surface's highest point in the body's frame) and every other chunk
// goes to the texel pass: the pressure under such a surface has no pre-summed form.
layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Chunks { Chunk chunks[]; };
layout(std430, binding = 2) readonly buffer Poses { BodyPose poses[]; };
// Per chunk: its partial at chunkIndex and (surfaceMode) its pressure-head partial at headBase + chunkIndex.
layout(std430, binding = 3) writeonly buffer Partials { Partial partials[]; };
layout(std430, binding = 5) readonly buffer Moments { ChunkMoments moments[]; };
layout(std430, binding = 6) writeonly buffer Crossing { uint crossing[]; };
layout(std430, binding = 7) buffer Counters { SegmentCounters counters[]; };
layout(std430, binding = 0) readonly buffer DryLevels { float dryLevels[]; };        // per body (surfaceMode)

uniform uint chunkBase;     // global index of this dispatch's first chunk
uniform uint chunkCount;    // chunks in this dispatch
uniform uint runIndex;      // the storage run these chunks form (its counters and crossing list)
uniform uint listBase;      // where the run's crossing list starts in Crossing
uniform bool surfaceMode;   // not a flat plane: see above
uniform uint headBase;      // where the pressure-head partials start in Partials

void main() {
  uint local = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (local >= chunkCount) return;
  uint chunkIndex = chunkBase + local;
  Chunk chunk = chunks[chunkIndex];
  BodyPose pose = poses[chunk.body];
  vec3 r0 = pose.row0.xyz, r1 = pose.row1.xyz, r2 = pose.row2.xyz;
  vec3 center = vec3(chunk.centerX, chunk.centerY, chunk.centerZ);
  // Posed chunk centre X = R c + offset; the chunk reaches |r1| . half above and below it.
  vec3 X = vec3(dot(r0, center) + pose.row0.w, dot(r1, center) + pose.row1.w, dot(r2, center) + pose.row2.w);
  float reachY = dot(abs(r1), vec3(chunk.halfX, chunk.halfY, chunk.halfZ));
  float dryLevel = surfaceMode ? dryLevels[chunk.body] : 0.0;
  if (X.y - reachY >= dryLevel) {  // wholly above: adds nothing
    for (int k = 0; k < 12; ++k) partials[chunkIndex].value[k] = 0.0;
    if (surfaceMode)
      for (int k = 0; k < 12; ++k) partials[headBase + chunkIndex].value[k] = 0.0;
    return;
  }
  if (surfaceMode || X.y + reachY > 0.0) {  // crosses the surface: texel by texel
    uint slot = atomicAdd(counters[runIndex].crossingGroups, 1u);
    crossing[listBase + slot] = chunkIndex;
    return;
  }
  atomicAdd(counters[runIndex].submergedChunks, 1u);

  // Wholly submerged: every texel has frac = 1, D = -y', Q = y'^2. With x' = X + R q and A' = R A,
  // every sum needed is S0 = sum A'_y, S_i = sum x'_i A'_y = X_i S0 + m_i and
  // S_ij = sum x'_i x'_j A'_y = X_i X_j S0 + X_i m_j + X_j m_i + N_ij, where m_i = r_i . (PA r1)
  // and N_ij = r_i . (P1 r_j), P1 = sum_k r1_k PPA_k (the symmetric q q^T A_k sums).
  float m[32] = moments[chunk.table].value;
  float s0 = dot(r1, vec3(m[1], m[2], m[3]));
  vec3 paR1 = vec3(dot(vec3(m[4], m[5], m[6]), r1), dot(vec3(m[7], m[8], m[9]), r1), dot(vec3(m[10], m[11], m[12]), r1));
  // Pairs xx xy xz yy yz zz at 13 + 3 pair + k.
  float p[6];
  for (int pair = 0; pair < 6; ++pair) p[pair] = dot(r1, vec3(m[13 + 3 * pair], m[14 + 3 * pair], m[15 + 3 * pair]));
  mat3 p1 = mat3(p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5]);  // symmetric
  vec3 mi = vec3(dot(r0, paR1), dot(r1, paR1), dot(r2, paR1));
  vec3 p1r0 = p1 * r0, p1r1 = p1 * r1, p1r2 = p1 * r2;
  float n00 = dot(r0, p1r0), n01 = dot(r0, p1r1), n02 = dot(r0, p1r2);
  float n11 = dot(r1, p1r1), n12 = dot(r1, p1r2), n22 = dot(r2, p1r2);
  float s1x = X.x * s0 + mi.x, s1y = X.y * s0 + mi.y, s1z = X.z * s0 + mi.z;
  float sxy = X.x * X.y * s0 + X.x * mi.y + X.y * mi.x + n01;
  float szy = X.z * X.y * s0 + X.z * mi.y + X.y * mi.z + n12;
  float syy = X.y * X.y * s0 + 2.0 * X.y * mi.y + n11;
  float sxx = X.x * X.x * s0 + 2.0 * X.x * mi.x + n00;
  float sxz = X.x * X.z * s0 + X.x * mi.z + X.z * mi.x + n02;
  float szz = X.z * X.z * s0 + 2.0 * X.z * mi.z + n22;
  // The 11 sums in the texel pass's order (FlatWettedSums).
  partials[chunkIndex].value[0] = -s1y;
  partials[chunkIndex].value[1] = -sxy;
  partials[chunkIndex].value[2] = -szy;
  partials[chunkIndex].value[3] = 0.5 * syy;
  partials[chunkIndex].value[4] = s0;
  partials[chunkIndex].value[5] = s1x;
  partials[chunkIndex].value[6] = s1z;
  partials[chunkIndex].value[7] = sxx;
  partials[chunkIndex].value[8] = sxz;
  partials[chunkIndex].value[9] = szz;
  partials[chunkIndex].value[10] = m[0];
  partials[chunkIndex].value[11] = 0.0;
}
