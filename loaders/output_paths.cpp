#include "loaders/output_paths.h"

#include "loaders/image_io.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <fmt/format.h>

#include <filesystem>

namespace terracast {

namespace fs = std::filesystem;

void checkNotInput(const std::string& output, const std::string& input, const char* what, const char* inputName) {
    std::error_code ec;
    if (fs::exists(output, ec) && fs::exists(input, ec) && fs::equivalent(output, input, ec))
        throw InputError(fmt::format("{}: {} is {}; refusing to overwrite it", output, what, inputName));
}

void checkOutputFolder(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw InputError(fmt::format("{}: is a directory; expected the name of a file to write", path));
    const auto dir = fs::path(path).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError(fmt::format("{}: output folder '{}' does not exist", path, dir.string()));
}

void checkOutputPath(const std::string& output, const std::string& input, std::initializer_list<const char*> allowed,
                     const char* inputName) {
    checkNotInput(output, input, "output path", inputName);
    const std::string ext = lowerExtension(output);
    bool ok = false;
    std::string expected;
    for (const char* a : allowed) {
        ok = ok || ext == a;
        expected += (expected.empty() ? "" : " or ") + std::string(a);
    }
    if (!ok) throw InputError(fmt::format("{}: unsupported output format '{}' (expected {})", output, ext, expected));
    checkOutputFolder(output);
    checkCanWrite(output);
}

void checkReportPath(const std::string& path, const std::string& input) {
    checkOutputFolder(path);
    checkNotInput(path, input, "--json");
}

}  // namespace terracast
