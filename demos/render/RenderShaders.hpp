// SPDX-License-Identifier: Zlib
#pragma once
/// @file RenderShaders.hpp
/// The files of demos/render/shaders/, embedded at build time by cmake/EmbedRenderShaders.cmake.

#include <string_view>

namespace hydrotex::render {

/// The text of the shader file `name` (e.g. "body.frag"); empty when there is no such file.
std::string_view renderShader(std::string_view name);

}  // namespace hydrotex::render
