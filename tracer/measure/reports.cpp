#include "tracer/measure/reports.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace terracast {

std::string jsonNumber(double v) {
    if (!std::isfinite(v)) return "null";
    return fmt::format("{:.6g}", v);
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (static_cast<unsigned char>(c) < 0x20) {
            out += fmt::format("\\u{:04x}", int(c));
            continue;
        }
        out += c;
    }
    return out + "\"";
}

std::string errorJson(const ErrorSummary& e) {
    return fmt::format("{{\"mean\": {}, \"p99\": {}, \"max\": {}}}", jsonNumber(e.mean), jsonNumber(e.p99),
                       jsonNumber(e.max));
}

std::string accuracyJson(const ReportedDem& dem, uint64_t seed, const AccuracyReport& r) {
    std::string j = fmt::format(
        "{{\"dem\": {}, \"width\": {}, \"height\": {}, \"rays\": {}, \"seed\": {}, "
        "\"camera_rays\": {}, \"grazing_rays\": {}, \"shadow_rays\": {}, \"reference\": \"reference\", "
        "\"reference_hits\": {}, \"ambiguous_rays\": {}, \"grazing_tolerance_m\": {},\n \"methods\": [",
        jsonString(dem.path), dem.width, dem.height, r.rays, seed, r.cameraRays, r.grazingRays, r.shadowRays,
        r.referenceHits, r.ambiguousRays, jsonNumber(r.grazingToleranceM));
    for (size_t k = 0; k < r.methods.size(); ++k) {
        const auto& m = r.methods[k];
        j += fmt::format(
            "{}\n  {{\"name\": \"{}\", \"rays_per_s\": {}, \"primary_rays_per_s\": {}, \"hit_agreement\": {}, "
            "\"disagreements\": {}, \"unambiguous_disagreements\": {}, \"compared_hits\": {}, "
            "\"t_error_m\": {}, \"t_error_rel\": {}}}",
            k ? "," : "", cellMethodName(m.method), jsonNumber(m.raysPerSecond), jsonNumber(m.raysPerSecond),
            jsonNumber(double(m.agreements) / double(r.rays)), m.disagreements, m.unambiguousDisagreements,
            m.comparedHits, errorJson(m.tErrorM), errorJson(m.tErrorRel));
    }
    return j + "\n ]}\n";
}

std::string compareJson(const ReportedDem& dem, const CompareReport& r) {
    std::string j = fmt::format("{{\"dem\": {}, \"width\": {}, \"height\": {}, \"image_width\": {}, "
                                "\"image_height\": {}, \"rays\": {}, \"reference\": \"{}\",\n \"methods\": [",
                                jsonString(dem.path), dem.width, dem.height, r.width, r.height, r.rays,
                                surfaceMethodName(r.reference));
    for (size_t k = 0; k < r.methods.size(); ++k) {
        const auto& m = r.methods[k];
        j += fmt::format(
            "{}\n  {{\"name\": \"{}\", \"build_s\": {}, \"memory_bytes\": {}, \"primary_rays\": {}, "
            "\"shadow_rays\": {}, \"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, \"hit_agreement\": {}, "
            "\"t_error_m\": {}, \"t_error_rel\": {}, \"image_rmse\": {}, \"image_psnr_db\": {}, "
            "\"ratio_to_embree\": {{\"primary\": {}, \"shadow\": {}}}{}}}",
            k ? "," : "", comparisonName(m), jsonNumber(m.buildSeconds), m.memoryBytes, m.primaryRays,
            m.shadowRays, jsonNumber(m.primaryRaysPerSecond), jsonNumber(m.shadowRaysPerSecond),
            jsonNumber(m.hitAgreement), errorJson(m.tErrorM), errorJson(m.tErrorRel), jsonNumber(m.imageRmse),
            // identical images have infinite PSNR; JSON has no infinity, so it is capped at 999 dB
            jsonNumber(std::min(m.imagePsnrDb, 999.0)), jsonNumber(m.ratioToEmbreePrimary),
            jsonNumber(m.ratioToEmbreeShadow), m.tileLoads >= 0 ? fmt::format(", \"tile_loads\": {}", m.tileLoads) : "");
    }
    return j + "\n ]}\n";
}

}  // namespace terracast
