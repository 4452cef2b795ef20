// The benchmarks' knobs from the environment (OBSCURA_BENCH_WIDTH, ..._RADIUS, ...).
#pragma once
#include <cstdlib>

namespace obscura::bench {

// A positive integer from `name`, else `fallback`.
inline int envInt(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v && std::atoi(v) > 0 ? std::atoi(v) : fallback;
}

// A positive number from `name`, else `fallback`.
inline float envFloat(const char* name, float fallback) {
    const char* v = std::getenv(name);
    return v && std::atof(v) > 0 ? (float)std::atof(v) : fallback;
}

} // namespace obscura::bench
