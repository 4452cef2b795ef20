// Lets the kernels/*.glsl files compile as C++17 through GLM.
// The kernels are written in the common subset of GLSL 4.3 and C++:
//  - every float literal carries an `f` suffix (GLSL accepts it; C++ needs it to stay in float);
//  - out/inout parameters are spelled OUT(T) / INOUT(T); a struct read only, IN(T) (C++: by
//    reference, so a call the compiler keeps out of line copies no registers of lanes);
//  - backend access (loads, image size) goes through functions the backend defines.
// The C++ backend #includes a kernel inside a struct, so the backend's access
// functions and parameter block are members the kernel calls unqualified.
#pragma once
#define GLM_FORCE_INLINE
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <cstdint>

namespace obscura::glsl {
using namespace glm;
using uint = std::uint32_t;
} // namespace obscura::glsl

#define IN(T) const T&
#define OUT(T) T&
#define INOUT(T) T&
#define CONST_GLOBAL static constexpr
// A function a lane group seldom calls, kept out of the loop that calls it: inlined, its
// registers would crowd the loop's for every sample.
#define OUT_OF_LINE __attribute__((noinline))
