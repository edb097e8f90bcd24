#include "tracer/core/text.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

namespace terracast {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

std::string escapeControls(std::string_view text, size_t maxBytes) {
    std::string out;
    char hex[8];
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if (out.size() >= maxBytes && (c & 0xC0) != 0x80) {
            out += "...";
            break;
        }
        if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else if (c == '\t') out += "\\t";
        else if (c < 0x20 || c == 0x7F) {
            std::snprintf(hex, sizeof hex, "\\x%02x", c);
            out += hex;
        } else out += ch;
    }
    return out;
}

std::string humanBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 4) {
        bytes /= 1024.0;
        ++u;
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.1f %s", bytes, units[u]);
    return text;
}

}  // namespace terracast
