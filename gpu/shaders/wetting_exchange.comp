// SPDX-License-Identifier: Zlib
// Absorption, sources and evaporation of the liquid texture, one texel per invocation: core's
// Wetting::exchangeRange (core/src/wetting/Wetting.cpp) with the same float equations.
//  - Under a flat liquid surface (pressure rho g depth), or under any other surface with the
//    pressure the host evaluated per texel (core's liquidPressureAtTexels): Darcy's law against
//    the pores' back-pressure (paper eq. 9), S -> capacity exactly exponentially,
//    tau = mu L C / (k P).
//  - In the air: the sources' supply up to capacity (rain on the texel's projection across the
//    fall, spheres inside their radius) with its pigment, then Hall and Hoff's evaporation (paper eq. 10):
//    constant rate down to the critical content, then first order, both integrated exactly.
// Volumes moved (change * area) are summed per work group in shared memory and written as one
// partial per group; the host adds the partials in double.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Liquid { float liquid[]; };                   // m
layout(std430, binding = 1) readonly buffer Material { vec2 material[]; };       // per texel: capacity (m), permeability (m^2)
layout(std430, binding = 2) readonly buffer Pressure { float texelPressure[]; };  // hostPressure mode: Pa under the liquid, -1 in the air
layout(std430, binding = 3) readonly buffer Area { float area[]; };              // m^2
layout(std430, binding = 4) readonly buffer Geometry { float geometry[]; };      // per texel: centroid x, y, z (m, body), unit normal x, y, z
layout(std430, binding = 5) buffer Pigment { float pigment[]; };                 // m of pigment (read only withPigment)
layout(std430, binding = 6) buffer Submerged { uint submerged[]; };              // 1 under the liquid
layout(std430, binding = 7) writeonly buffer Partials { float partials[]; };     // per group: absorbed, evaporated, submerged

const int kMaxSources = 8;
uniform uint texelCount;
uniform bool absorbing;         // false: evaporation alone, under the last absorption's mask
uniform bool withLiquid;        // a liquid surface is present
uniform bool hostPressure;      // its pressure per texel is in Pressure (not flat); else flat: heightRow
uniform vec4 heightRow;         // second row of the pose; w: translation y - surface height (m)
uniform float pressurePerDepth; // rho g (Pa/m)
uniform float capillary;        // Pa
uniform float darcyFactor;      // dt / (mu L)
uniform float evaporationDepth; // constant-rate evaporation over the step (m)
uniform float criticalSaturation;
uniform int sourceCount;
uniform int sourceRain[kMaxSources];       // 1 rain, 0 sphere
uniform vec3 sourceVector[kMaxSources];    // rain: against the fall (body); sphere: centre (m, body)
uniform float sourceRadiusSquared[kMaxSources];
uniform float sourceDepth[kMaxSources];    // supply over the step (m)
uniform float sourcePigment[kMaxSources];  // pigment volume fraction of the supplied liquid
uniform bool withPigment;                  // the texture has a pigment channel

shared float sharedAbsorbed[64];
shared float sharedEvaporated[64];
shared float sharedSubmerged[64];

// exp(-x), x >= 0, as the CPU's expNegative: range reduction by ln 2 and a degree-6 series.
float expNegative(float x) {
  x = min(max(x, 0.0), 80.0);
  const float kLn2 = 0.693147181, kInvLn2 = 1.44269504;
  int k = int(x * kInvLn2 + 0.5);
  float r = float(k) * kLn2 - x;
  float p = 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  return p * intBitsToFloat((127 - k) << 23);
}

float oneMinusExpNegative(float x) {
  if (x < 0.03) return x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0))));
  return 1.0 - expNegative(x);
}

void main() {
  uint local = gl_LocalInvocationID.x;
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint i = group * 64u + local;
  float absorbedVolume = 0.0, evaporatedVolume = 0.0, isUnder = 0.0;
  if (i < texelCount && area[i] > 0.0) {
    float held = liquid[i], full = material[i].x, a = area[i];
    vec3 p = vec3(geometry[6u * i], geometry[6u * i + 1u], geometry[6u * i + 2u]);
    bool under = false;
    float pressure = 0.0;
    if (withLiquid && hostPressure) {
      pressure = max(texelPressure[i], 0.0);
      under = texelPressure[i] >= 0.0;
    } else if (withLiquid) {
      pressure = -pressurePerDepth * (dot(heightRow.xyz, p) + heightRow.w);
      under = pressure > 0.0;
    } else if (!absorbing) {
      under = submerged[i] != 0u;
    }
    if (absorbing) submerged[i] = under ? 1u : 0u;
    float current = held;
    float inverseFull = 1.0 / (full > 0.0 ? full : 1.0);
    if (under) {
      isUnder = 1.0;
      if (absorbing && full > held) {
        float exponent = material[i].y * (pressure + capillary) * darcyFactor * inverseFull;  // dt / tau
        current = min(full, held + (full - held) * oneMinusExpNegative(exponent));
      }
    } else {
      if (absorbing) {
        vec3 n = vec3(geometry[6u * i + 3u], geometry[6u * i + 4u], geometry[6u * i + 5u]);
        for (int s = 0; s < sourceCount; ++s) {
          float supply = 0.0;
          if (sourceRain[s] != 0) {
            float facing = dot(sourceVector[s], n);
            supply = facing > 0.0 ? sourceDepth[s] * facing : 0.0;
          } else {
            vec3 d = p - sourceVector[s];
            supply = dot(d, d) <= sourceRadiusSquared[s] ? sourceDepth[s] : 0.0;
          }
          float stored = min(current + supply, full);
          if (stored > current) {
            // The supply's pigment, added source by source as the CPU does.
            if (withPigment) pigment[i] += (stored - current) * sourcePigment[s];
            current = stored;
          }
        }
      }
      absorbedVolume = (current - held) * a;
      if (evaporationDepth > 0.0) {
        float critical = criticalSaturation * full;
        float constantNext = current - evaporationDepth;
        float next;
        if (constantNext >= critical || critical <= 0.0) {
          next = max(0.0, constantNext);
        } else {
          float fallingExponent = (evaporationDepth - max(0.0, current - critical)) * inverseFull / criticalSaturation;
          next = min(current, critical) * expNegative(fallingExponent);
        }
        evaporatedVolume = (current - next) * a;
        current = next;
      }
    }
    if (under) absorbedVolume = (current - held) * a;
    liquid[i] = current;
  }
  sharedAbsorbed[local] = absorbedVolume;
  sharedEvaporated[local] = evaporatedVolume;
  sharedSubmerged[local] = isUnder;
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1u) {
    if (local < stride) {
      sharedAbsorbed[local] += sharedAbsorbed[local + stride];
      sharedEvaporated[local] += sharedEvaporated[local + stride];
      sharedSubmerged[local] += sharedSubmerged[local + stride];
    }
    barrier();
  }
  if (local == 0u) {
    partials[3u * group] = sharedAbsorbed[0];
    partials[3u * group + 1u] = sharedEvaporated[0];
    partials[3u * group + 2u] = sharedSubmerged[0];
  }
}
