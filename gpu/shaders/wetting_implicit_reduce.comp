// SPDX-License-Identifier: Zlib
// Finishes a dot product of wetting_implicit.comp (its per-work-group partials, in double) and
// updates the conjugate gradient's scalars on the GPU, so that no iteration waits for the host:
// after the start rz = rz0 = r.z; after applying the matrix alpha = rz / p.Ap; after the update
// beta = r.z / rz, rz = r.z.
layout(local_size_x = 64) in;

layout(std430, binding = 6) buffer Scalars { double scalars[]; };  // rz, pAp, alpha, beta, rz0, then partials

const uint kAfterStart = 0u, kAfterApply = 1u, kAfterUpdate = 2u;
uniform uint mode;
uniform uint partialCount;
const uint kPartials = 8u;

shared double partial[64];

void main() {
  uint local = gl_LocalInvocationID.x;
  double sum = 0.0LF;
  for (uint g = local; g < partialCount; g += 64u) sum += scalars[kPartials + g];
  partial[local] = sum;
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1u) {
    if (local < stride) partial[local] += partial[local + stride];
    barrier();
  }
  if (local != 0u) return;
  double total = partial[0];
  if (mode == kAfterStart) {
    scalars[0] = total;
    scalars[4] = total;
  } else if (mode == kAfterApply) {
    scalars[1] = total;
    scalars[2] = total != 0.0LF ? scalars[0] / total : 0.0LF;
  } else {
    scalars[3] = scalars[0] != 0.0LF ? total / scalars[0] : 0.0LF;
    scalars[0] = total;
  }
}
