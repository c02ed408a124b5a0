// One place for GLM's configuration: every translation unit includes this before any GLM header, so
// all of them agree on layout (radians, depth range, no SIMD-dependent padding).
#pragma once
#define GLM_FORCE_RADIANS
#define GLM_FORCE_DEPTH_ZERO_TO_ONE
#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>
