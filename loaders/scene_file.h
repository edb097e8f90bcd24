// Scene files: TOML text (docs/scene-format.md is the reference) parsed into the plain SceneDescription.
// Every key is checked: unknown keys, keys of another object type, wrong types, out-of-range values, missing
// files and unknown material names are InputErrors of one line, "scene.toml:LINE:COL: message".
#pragma once

#include "tracer/scene/scene_description.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace terracast {

// Bounds on what reaches the TOML parser: a scene file's size, and how deep its keys, tables and arrays nest.
inline constexpr int64_t kMaxSceneFileBytes = int64_t(64) << 20;
inline constexpr int kMaxSceneNesting = 64;

// Reads and parses the scene file at `path`; relative paths inside it resolve against its folder. Throws
// InputError for a missing, unreadable or invalid file. A scene file may come from anyone: unless `anyPath`,
// the files it names (height fields, drapes, its output) must lie in its own folder, and GDAL virtual,
// network and absolute paths are refused (docs/scene-format.md, "Paths").
SceneDescription loadSceneFile(const std::string& path, bool anyPath = false);

// Parses scene text. `pathForMessages` starts every error message; `baseDir` is the folder relative paths in
// the scene resolve against (empty: the working directory). Throws InputError for any invalid input and
// nothing else, whatever the bytes: this is also the entry point for fuzzing.
SceneDescription parseSceneText(std::string_view text, const std::string& pathForMessages, const std::string& baseDir,
                                bool anyPath = false);

}  // namespace terracast
