// Sizing of the largest random sweeps. Under the sanitizers (TERRACAST_SANITIZE) code runs several times
// slower; there the sweeps run a tenth of their samples, which still takes every path the sanitizers watch,
// while the plain build keeps their full statistical power.
#pragma once

namespace terracast::testing {

#ifdef TERRACAST_SANITIZED
inline constexpr bool kSanitizedBuild = true;
inline constexpr int kSweepDivisor = 10;
// AddressSanitizer's shadow memory and quarantine inflate resident memory several times over: measurements of
// it say nothing about the plain build's.
inline constexpr bool kResidentMemoryIsMeaningful = false;
#else
inline constexpr bool kSanitizedBuild = false;
inline constexpr int kSweepDivisor = 1;
inline constexpr bool kResidentMemoryIsMeaningful = true;
#endif

}  // namespace terracast::testing
