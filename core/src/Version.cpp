#include "hydrotex/Version.hpp"

namespace hydrotex {
const char* versionString() { return "0.1.0"; }
}  // namespace hydrotex
