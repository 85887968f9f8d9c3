// util/cpu_time.h — the CPU time this process has used, all its threads together
// (CLOCK_PROCESS_CPUTIME_ID). Unlike wall time it does not grow when other programs take the cores: a
// render's CPU time is what the render itself executed, so an efficiency that divides by it is the same
// on a quiet machine and on a busy one (the study's default cost, study/config.h). It still counts what
// the render's own threads spend waiting busily (oneTBB's workers spin briefly before they sleep).
#pragma once

#include <ctime>

namespace symphong {

/// Seconds of CPU time used by every thread of this process so far.
inline double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace symphong
