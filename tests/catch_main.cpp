// SPDX-License-Identifier: Zlib
// The single Catch2 (v2) main shared by every test suite.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
