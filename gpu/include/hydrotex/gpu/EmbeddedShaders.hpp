// SPDX-License-Identifier: Zlib
#pragma once
/// @file EmbeddedShaders.hpp
/// The files of gpu/shaders/, embedded into the library at build time by
/// gpu/cmake/EmbedShaders.cmake.

#include <string_view>

namespace hydrotex::gpu {

/// The text of the shader file `name` (e.g. "hydrostatics_flat.comp", "layouts.glsl"); empty when
/// there is no such file.
std::string_view embeddedShader(std::string_view name);

}  // namespace hydrotex::gpu
