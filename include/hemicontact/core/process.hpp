#pragma once
/// @file process.hpp  Process-wide settings that make solves faster, applied once by each program
/// that solves (the CLI's main, the Python module when it is imported).

namespace hemicontact {

/// @brief glibc's malloc thresholds (large arrays stay mapped between a solve's phases) and
/// OpenMP's dynamic team sizes (CHOLMOD's fixed teams of 4 threads spin on a 2-core machine); an
/// OMP_DYNAMIC in the environment is left as the user set it. The reasons and measurements are
/// in src/core/process.cpp.
void configure_process_for_solves();

}  // namespace hemicontact
