// Wall-clock time for frame statistics (private to the core).
#pragma once

#include <chrono>

namespace facet {

inline double elapsed_ms(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
        .count();
}

}  // namespace facet
