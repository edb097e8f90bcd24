// The accuracy report: every cell method against the long-double bilinear reference on the same seeded rays.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace terracast {

struct AccuracyOptions {
    int64_t rays = 100000;             // total rays, split evenly between camera-like, grazing and shadow-like
    uint64_t seed = 1;                 // random seed: the same seed gives the same rays
    std::vector<CellMethod> methods;   // methods to measure; empty = all but the reference
    bool keepReferenceRays = false;    // return every ray with the reference's answer (for an outside check)
};

// Mean, 99th percentile and maximum of a set of errors.
struct ErrorSummary {
    double mean = 0.0;
    double p99 = 0.0;
    double max = 0.0;
};

// Summarises a set of errors (empty: all zero).
ErrorSummary summariseErrors(std::vector<double> errors);

struct MethodAccuracy {
    CellMethod method = CellMethod::Bilinear;
    double raysPerSecond = 0.0;        // single thread, this run
    int64_t agreements = 0;            // rays with the reference's hit/miss verdict
    int64_t disagreements = 0;         // rays without it
    int64_t unambiguousDisagreements = 0;  // ... among rays the reference does not flag as ambiguous
    int64_t comparedHits = 0;          // rays both hit (the error figures below cover these)
    ErrorSummary tErrorM;              // |t - t_ref| in metres (directions are unit length)
    ErrorSummary tErrorRel;            // |t - t_ref| / t_ref
};

// One traced ray and the reference's answer to it.
struct ReferenceRay {
    Ray ray;
    Interval interval;
    std::optional<double> t;           // the reference's first hit, none for a miss
    bool ambiguous = false;            // the reference flagged it as grazing within float tolerance
};

struct AccuracyReport {
    int64_t rays = 0;
    int64_t cameraRays = 0;
    int64_t grazingRays = 0;
    int64_t shadowRays = 0;
    int64_t referenceHits = 0;
    int64_t ambiguousRays = 0;         // rays the reference flags as grazing within float tolerance
    double grazingToleranceM = 0.0;    // the tolerance of that flag
    std::vector<MethodAccuracy> methods;
    std::vector<ReferenceRay> referenceRays;  // filled only with AccuracyOptions::keepReferenceRays
};

// Traces the same seeded rays with each method and with the reference, and compares.
AccuracyReport measureAccuracy(const HeightGrid& grid, const AccuracyOptions& options);

}  // namespace terracast
