// SPDX-License-Identifier: Zlib
// Anchor translation unit for the test support library.
#include "TestPaths.hpp"
