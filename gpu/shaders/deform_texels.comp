// SPDX-License-Identifier: Zlib
// Deforming bodies, second pass: one workgroup per hydrostatics chunk (up to 256 texels, 4 per
// invocation). Each texel's PT, VAT, area and edges from its pieces and their triangles' frames
// (core's SurfaceEvaluator::evaluate, the per-texel half, same float operations), written where
// the hydrostatics pass reads it; then the chunk's bounds (as GlBackend's upload: p +- (|eU| +
// |eV|) / 2, widened), the moment corrections of its texels of several pieces (SurfaceEvaluator:
// Sum_k (c_k - p) A_k^T, same float operations) and its pre-summed moments about the bounds centre,
// corrections included (hydrostatics_classify).
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Texels { HydroTexel texels[]; };
layout(std430, binding = 1) buffer Chunks { Chunk chunks[]; };
// Bindings 2 (frames), 3 (piece starts), 4 (pieces): deform_texel.glsl.
layout(std430, binding = 5) writeonly buffer Moments { ChunkMoments moments[]; };
layout(std430, binding = 6) readonly buffer ChunkFirst { uint chunkFirst[]; };  // per body chunk: first texel
layout(std430, binding = 7) buffer Corrections { TexelCorrection corrections[]; };

uniform uint bodyChunkBegin;  // global index of the body's first chunk
uniform uint chunkBase;       // body-local index of this dispatch's first chunk
uniform uint chunkCount;      // chunks in this dispatch

const uint kGroup = 64u;
const uint kPerInvocation = 4u;
shared float reduction[32][kGroup];

// Sums (or min / max) reduction[0..count) over the group into lane 0; every lane must call it.
void reduceGroup(int count, int minCount, int maxCount) {
  barrier();
  for (uint stride = kGroup / 2u; stride > 0u; stride >>= 1u) {
    uint lane = gl_LocalInvocationID.x;
    if (lane < stride) {
      for (int k = 0; k < count; ++k) {
        float other = reduction[k][lane + stride];
        if (k < minCount) reduction[k][lane] = min(reduction[k][lane], other);
        else if (k < minCount + maxCount) reduction[k][lane] = max(reduction[k][lane], other);
        else reduction[k][lane] += other;
      }
    }
    barrier();
  }
}

void main() {
  uint local = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (local >= chunkCount) return;  // the same for the whole workgroup
  uint bodyChunk = chunkBase + local;
  uint chunkIndex = bodyChunkBegin + bodyChunk;
  Chunk chunk = chunks[chunkIndex];
  uint lane = gl_LocalInvocationID.x;

  vec3 pos[kPerInvocation], area3[kPerInvocation];
  float areas[kPerInvocation];
  vec3 low = vec3(3.0e38), high = vec3(-3.0e38);
  for (uint n = 0u; n < kPerInvocation; ++n) {
    pos[n] = vec3(0.0);
    area3[n] = vec3(0.0);
    areas[n] = 0.0;
    uint i = lane + n * kGroup;
    if (i >= chunk.count) continue;
    uint texel = chunkFirst[bodyChunk] + i;
    vec3 p, a, eu, ev;
    float area;
    evaluateTexel(texel, p, a, area, eu, ev);
    texels[chunk.begin + i] = HydroTexel(p.x, p.y, p.z, a.x, a.y, a.z, area, eu.x, eu.y, eu.z, ev.x, ev.y, ev.z);
    pos[n] = p;
    area3[n] = a;
    areas[n] = area;
    vec3 reach = 0.5 * (abs(eu) + abs(ev));
    low = min(low, p - reach);
    high = max(high, p + reach);
  }
  // The moment corrections of the chunk's texels of several pieces (SurfaceEvaluator's float
  // formula: Sum_k (c_k - p) A_k^T and the reach max |c_k - p|), written for the hydrostatics
  // passes; the pieces lie within the reach of p, which the bounds take in.
  vec3 correctionPosition[kPerInvocation];  // this lane's corrections: p and dM, for the moments
  mat3 correctionMoment[kPerInvocation];
  for (uint j = lane; j < chunk.correctionCount; j += kGroup) {
    uint slot = chunk.correctionBegin + j;
    uint texelInChunk = corrections[slot].texel;
    uint texel = chunkFirst[bodyChunk] + texelInChunk;
    vec3 p, a, eu, ev;
    float area;
    evaluateTexel(texel, p, a, area, eu, ev);
    mat3 dm = mat3(0.0);  // column k: Sum_k (c_k - p) A_k[k]
    float pieceReach = 0.0;
    uint begin = pieceStart[texel], end = min(pieceStart[texel + 1u], pieceCount);
    for (uint k = begin; k < end; ++k) {
      DeformPiece piece = pieces[k];
      if (piece.triangle >= triangleCount) continue;
      float f[20] = frames[piece.triangle].value;
      vec3 pieceCentroid = vec3(f[0], f[1], f[2]) + piece.centroidBary1 * vec3(f[3], f[4], f[5]) +
                           piece.centroidBary2 * vec3(f[6], f[7], f[8]);
      vec3 pieceAreaVector = piece.areaFraction * vec3(f[9], f[10], f[11]);
      dm += outerProduct(pieceCentroid - p, pieceAreaVector);
      pieceReach = max(pieceReach, length(pieceCentroid - p));
    }
    for (int row = 0; row < 3; ++row)
      for (int k = 0; k < 3; ++k) corrections[slot].moment[3 * row + k] = dm[k][row];
    corrections[slot].reach = pieceReach;
    correctionPosition[j / kGroup] = p;
    correctionMoment[j / kGroup] = dm;
    low = min(low, p - vec3(pieceReach));
    high = max(high, p + vec3(pieceReach));
  }

  // Bounds, widened as GlBackend's upload widens them (float rounding of the centre and of the
  // classification's dot products).
  for (int c = 0; c < 3; ++c) {
    reduction[c][lane] = low[c];
    reduction[3 + c][lane] = high[c];
  }
  reduceGroup(6, 3, 3);
  vec3 lowAll = vec3(reduction[0][0], reduction[1][0], reduction[2][0]);
  vec3 highAll = vec3(reduction[3][0], reduction[4][0], reduction[5][0]);
  vec3 center = 0.5 * (lowAll + highAll);
  vec3 halfExtent = 0.5 * (highAll - lowAll) * (1.0 + 1e-5) + vec3(1e-5 * length(center) + 1e-9);
  barrier();

  // Moments about the centre: area, A, q A^T (9), q q^T A (18 of the 6 pairs).
  float m[32];
  for (int k = 0; k < 32; ++k) m[k] = 0.0;
  for (uint n = 0u; n < kPerInvocation; ++n) {
    vec3 q = pos[n] - center, a = area3[n];
    float pairs[6] = float[6](q.x * q.x, q.x * q.y, q.x * q.z, q.y * q.y, q.y * q.z, q.z * q.z);
    m[0] += areas[n];
    for (int k = 0; k < 3; ++k) {
      m[1 + k] += a[k];
      for (int row = 0; row < 3; ++row) m[4 + 3 * row + k] += q[row] * a[k];
      for (int pair = 0; pair < 6; ++pair) m[13 + 3 * pair + k] += pairs[pair] * a[k];
    }
  }
  // This lane's corrections added to the moments as core's tiles add them: q A^T gains dM,
  // q_i q_j A_k gains q_i dM_jk + dM_ik q_j.
  for (uint j = lane; j < chunk.correctionCount; j += kGroup) {
    vec3 q = correctionPosition[j / kGroup] - center;
    for (int k = 0; k < 3; ++k) {
      vec3 dmk = correctionMoment[j / kGroup][k];  // dM(:, k)
      for (int row = 0; row < 3; ++row) m[4 + 3 * row + k] += dmk[row];
      m[13 + 3 * 0 + k] += 2.0 * q.x * dmk.x;
      m[13 + 3 * 1 + k] += q.x * dmk.y + dmk.x * q.y;
      m[13 + 3 * 2 + k] += q.x * dmk.z + dmk.x * q.z;
      m[13 + 3 * 3 + k] += 2.0 * q.y * dmk.y;
      m[13 + 3 * 4 + k] += q.y * dmk.z + dmk.y * q.z;
      m[13 + 3 * 5 + k] += 2.0 * q.z * dmk.z;
    }
  }
  for (int k = 0; k < 32; ++k) reduction[k][lane] = m[k];
  reduceGroup(31, 0, 0);
  if (lane == 0u) {
    float total[32];
    for (int k = 0; k < 32; ++k) total[k] = k < 31 ? reduction[k][0] : 0.0;
    moments[chunks[chunkIndex].table].value = total;
    chunks[chunkIndex].centerX = center.x;
    chunks[chunkIndex].centerY = center.y;
    chunks[chunkIndex].centerZ = center.z;
    chunks[chunkIndex].halfX = halfExtent.x;
    chunks[chunkIndex].halfY = halfExtent.y;
    chunks[chunkIndex].halfZ = halfExtent.z;
  }
}
