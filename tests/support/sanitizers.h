// Sizing of the largest random sweeps. Under the sanitizers (TERRACAST_SANITIZE) code runs several times
// slower; there the sweeps run a tenth of their samples, which still takes every path the sanitizers watch,
// while the plain build keeps their full statistical power.
#pragma once

namespace terracast::testing {

#ifdef TERRACAST_SANITIZED
inline constexpr int kSweepDivisor = 10;
#else
inline constexpr int kSweepDivisor = 1;
#endif

}  // namespace terracast::testing
