// SPDX-License-Identifier: Zlib
// Compiles and runs against an installed hydrotex: the volume of a unit box through the public API.
#include <cmath>
#include <cstdio>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#ifdef CONSUMER_HAS_BULLET
#include "hydrotex/bullet/BuoyancyController.hpp"
#endif

int main() {
  const hydrotex::Mesh box = hydrotex::primitives::box(Eigen::Vector3d(1.0, 2.0, 3.0));
  const hydrotex::Expected<hydrotex::MassProperties> mass = hydrotex::polyhedralMassProperties(box, 1000.0);
  if (!mass || std::abs(mass->volume - 6.0) > 1e-12) {
    std::fprintf(stderr, "consumer: wrong volume\n");
    return 1;
  }
#ifdef CONSUMER_HAS_BULLET
  // The plugin's settings validate without a world: enough to prove headers and library link.
  hydrotex::bullet::FloatingBodySettings settings;
  settings.mesh = std::make_shared<const hydrotex::Mesh>(box);
  if (!settings.validate()) {
    std::fprintf(stderr, "consumer: default body settings rejected: %s\n", settings.validate().error().message.c_str());
    return 1;
  }
#endif
  std::printf("consumer: installed hydrotex works, volume %.3f m^3\n", mass->volume);
  return 0;
}
