// SPDX-License-Identifier: Zlib
#pragma once
/// @file TriangleQuadrature.hpp
/// Private to core: a quadrature rule on a triangle, for integrals whose integrand is known only
/// pointwise (the exact path's wave part over a triangle wholly under the surface,
/// PolyhedralHydrostaticsWaves.cpp).

namespace hydrotex::detail {

/// One point of a rule: its weight (a share of the triangle's area) and barycentric coordinates.
struct TriangleQuadraturePoint {
  double weight, a, b, c;
};

/// Strang and Fix's six-point rule as tabulated by Dunavant ("High degree efficient symmetrical
/// Gaussian quadrature rules for the triangle", IJNME 21, 1985, degree 4): the mean over a triangle
/// of any polynomial of degree 4 or less in its plane is the weighted sum of its values at the six
/// points. The weights are positive and sum to 1, so the rule's error on a function f is at most
/// twice the largest |f - T| over the triangle, T any polynomial of degree 4 (test_polyhedral_
/// hydrostatics_waves checks the degree against the monomials' closed-form means).
inline constexpr TriangleQuadraturePoint kTriangleRuleDegree4[6] = {
    {0.223381589678011, 0.108103018168070, 0.445948490915965, 0.445948490915965},
    {0.223381589678011, 0.445948490915965, 0.108103018168070, 0.445948490915965},
    {0.223381589678011, 0.445948490915965, 0.445948490915965, 0.108103018168070},
    {0.109951743655322, 0.816847572980459, 0.091576213509771, 0.091576213509771},
    {0.109951743655322, 0.091576213509771, 0.816847572980459, 0.091576213509771},
    {0.109951743655322, 0.091576213509771, 0.091576213509771, 0.816847572980459},
};

}  // namespace hydrotex::detail
