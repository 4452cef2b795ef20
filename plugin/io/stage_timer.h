// Times a stage of a frame (read, camera, compute, write, ...) into the report, by scope.
#pragma once
#include "core/operator.h"

#include <chrono>
#include <string>
#include <vector>

namespace obscura {

struct StageTimer {
    using Clock = std::chrono::steady_clock;
    std::vector<StageTiming>* stages;  // nullptr: not timed
    std::string name;
    Clock::time_point t0 = Clock::now();
    ~StageTimer() {
        if (stages) stages->push_back({name, std::chrono::duration<double>(Clock::now() - t0).count()});
    }
};

} // namespace obscura
