#include "tracer/core/surface_method.h"

#include "tracer/core/errors.h"

#include <array>
#include <string>
#include <utility>

namespace terracast {

namespace {
// The direct methods share their names with the cell methods; Embree adds two.
constexpr std::array<std::pair<SurfaceMethod, CellMethod>, 5> kDirect{{
    {SurfaceMethod::Bilinear, CellMethod::Bilinear},
    {SurfaceMethod::BilinearDouble, CellMethod::BilinearDouble},
    {SurfaceMethod::Triangles, CellMethod::Triangles},
    {SurfaceMethod::Nearest, CellMethod::Nearest},
    {SurfaceMethod::Reference, CellMethod::Reference},
}};

constexpr std::array<SurfaceMethod, 7> kAll{SurfaceMethod::Bilinear, SurfaceMethod::BilinearDouble,
                                            SurfaceMethod::Triangles, SurfaceMethod::Nearest,
                                            SurfaceMethod::Reference, SurfaceMethod::Embree,
                                            SurfaceMethod::EmbreeGrid};
}  // namespace

std::span<const SurfaceMethod> surfaceMethods() { return kAll; }

std::optional<CellMethod> directCellMethod(SurfaceMethod m) {
    for (const auto& [surface, cell] : kDirect)
        if (surface == m) return cell;
    return std::nullopt;
}

CellMethod requireDirectMethod(SurfaceMethod m, const std::string& what) {
    if (const auto cell = directCellMethod(m)) return *cell;
    throw InputError("--method: " + what + " traces the grid directly; expected bilinear, bilinear-double, "
                     "triangles, nearest or reference, found '" + surfaceMethodName(m) + "'");
}

std::optional<SurfaceMethod> parseSurfaceMethod(std::string_view name) {
    if (name == "embree") return SurfaceMethod::Embree;
    if (name == "embree-grid") return SurfaceMethod::EmbreeGrid;
    if (const auto cell = parseCellMethod(name))
        for (const auto& [surface, c] : kDirect)
            if (c == *cell) return surface;
    return std::nullopt;
}

const char* surfaceMethodName(SurfaceMethod method) {
    if (method == SurfaceMethod::Embree) return "embree";
    if (method == SurfaceMethod::EmbreeGrid) return "embree-grid";
    return cellMethodName(*directCellMethod(method));
}

const char* surfaceMethodList() {
    static const std::string list = [] {
        std::string s;
        for (const SurfaceMethod m : kAll) s += (s.empty() ? "" : ", ") + std::string(surfaceMethodName(m));
        return s;
    }();
    return list.c_str();
}

}  // namespace terracast
