// SPDX-License-Identifier: Zlib
/// @file GaussLegendre.cpp
/// Gauss-Legendre rules on [0, 1] (GaussLegendre.hpp).

#include "hydrostatics/GaussLegendre.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace hydrotex::detail {
namespace {

/// The rule by Newton's method on P_K from Chebyshev starts, each node to the last bit (Abramowitz
/// and Stegun 25.4.29).
GaussRule gaussLegendre(int count) {
  GaussRule rule{};
  const double pi = std::numbers::pi;
  for (int i = 0; i < (count + 1) / 2; ++i) {
    double x = std::cos(pi * (i + 0.75) / (count + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;  // P_0, P_1, then up to P_count by the three-term recurrence
      for (int n = 2; n <= count; ++n) {
        const double p2 = ((2.0 * n - 1.0) * x * p1 - (n - 1.0) * p0) / n;
        p0 = p1;
        p1 = p2;
      }
      derivative = count * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
    // x in (-1, 1) to [0, 1]: the node pair symmetric about 1/2, each half the weight.
    rule.node[i] = 0.5 * (1.0 - x);
    rule.node[count - 1 - i] = 0.5 * (1.0 + x);
    rule.weight[i] = rule.weight[count - 1 - i] = 0.5 * weight;
  }
  return rule;
}

}  // namespace

const GaussRule& gaussRule(int count) {
  static const std::array<GaussRule, kMaxGaussNodes + 1> rules = [] {
    std::array<GaussRule, kMaxGaussNodes + 1> all{};
    for (int k = 1; k <= kMaxGaussNodes; ++k) all[std::size_t(k)] = gaussLegendre(k);
    return all;
  }();
  return rules[std::size_t(std::clamp(count, 1, kMaxGaussNodes))];
}

}  // namespace hydrotex::detail
