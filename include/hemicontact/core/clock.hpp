#pragma once
/// @file clock.hpp  The wall clock of every timing in reports and logs (Solution::timings,
/// setup_timings, adapt.history, the benchmarks' phases): one definition instead of one per file.

#include <chrono>

namespace hemicontact {

/// Monotonic: timings never jump with the system clock.
using clk = std::chrono::steady_clock;

/// @return seconds elapsed since @p t0.
inline double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

}  // namespace hemicontact
