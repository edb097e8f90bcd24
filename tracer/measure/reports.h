// The measurements' reports as JSON (the shapes docs/architecture.md and the README describe): numbers with six
// significant digits and null for non-finite values, strings escaped.
#pragma once

#include "tracer/measure/accuracy.h"
#include "tracer/measure/compare.h"

#include <cstdint>
#include <string>

namespace terracast {

std::string jsonNumber(double v);
std::string jsonString(const std::string& s);
// {"mean": .., "p99": .., "max": ..}
std::string errorJson(const ErrorSummary& e);

// What a report says of the DEM it measured.
struct ReportedDem {
    std::string path;
    int64_t width = 0;   // vertices
    int64_t height = 0;
};

// `accuracy --json`.
std::string accuracyJson(const ReportedDem& dem, uint64_t seed, const AccuracyReport& r);
// `compare --json`.
std::string compareJson(const ReportedDem& dem, const CompareReport& r);

}  // namespace terracast
