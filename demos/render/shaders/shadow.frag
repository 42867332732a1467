#version 430 core
// SPDX-License-Identifier: Zlib
void main() {}
