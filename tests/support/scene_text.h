// Scene text for the scene-file tests: a temporary folder holding the files scenes name, parsing in it, and
// the message a scene fails with, and a full scene using every key.
#pragma once

#include "loaders/scene_file.h"
#include "support/temp_dir.h"
#include "tracer/core/errors.h"

#include <fstream>
#include <string>

namespace terracast::testing {

// A folder holding the files scenes name: dem.tif and ortho.tif (the parser checks only that they exist).
class SceneFolder {
public:
    SceneFolder() : dir_("scene") {
        for (const char* name : {"dem.tif", "ortho.tif"}) std::ofstream(dir_.file(name)) << "not read by the parser";
    }
    std::string path() const { return dir_.path().string(); }
    std::string file(const std::string& name) const { return dir_.file(name); }

private:
    TempDir dir_;
};

inline SceneDescription parse(const std::string& text, const SceneFolder& folder) {
    return parseSceneText(text, "scene.toml", folder.path());
}

// The message parsing `text` fails with, or "(no error)".
inline std::string errorOf(const std::string& text) {
    const SceneFolder folder;
    try {
        parse(text, folder);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

// A scene using every section and every key, with values that differ from the defaults; each line numbered
// so that expected locations can be read off.
inline const std::string kFullScene =
    "[camera]\n"                                        // 1
    "type = \"thin-lens\"\n"                            // 2
    "eye = [100, -200, 1500.5]\n"                       // 3
    "look_at = [2000, 3000, 900]\n"                     // 4
    "up = [0, 0.5, 1]\n"                                // 5
    "fov = 35\n"                                        // 6
    "aperture = 0.05\n"                                 // 7
    "focus_distance = 2500\n"                           // 8
    "shutter = [0, 0.02]\n"                             // 9
    "velocity = [1, 2, 3]\n"                            // 10
    "\n"                                                // 11
    "[[material]]\n"                                    // 12
    "name = \"glass\"\n"                                // 13
    "color = [0.9, 1, 0.95]\n"                          // 14
    "kd = 0.1\n"                                        // 15
    "ks = 0.5\n"                                        // 16
    "exponent = 64\n"                                   // 17
    "mirror = 0.25\n"                                   // 18
    "gloss = 100\n"                                     // 19
    "ior_rgb = [1.51, 1.52, 1.53]\n"                    // 20
    "absorption = [0.1, 0.2, 0.3]\n"                    // 21
    "fresnel = \"exact\"\n"                             // 22
    "\n"                                                // 23
    "[[material]]\n"                                    // 24
    "name = \"rock\"\n"                                 // 25
    "terrain = \"slope\"\n"                             // 26
    "\n"                                                // 27
    "[[material]]\n"                                    // 28
    "name = \"photo\"\n"                                // 29
    "drape = \"ortho.tif\"\n"                           // 30
    "mirror = [0.1, 0.2, 0.3]\n"                        // 31
    "\n"                                                // 32
    "[[material]]\n"                                    // 33
    "name = \"lake\"\n"                                 // 34
    "ior = 1.33\n"                                      // 35
    "absorption = 0.5\n"                                // 36
    "\n"                                                // 37
    "[[object]]\n"                                      // 38
    "type = \"heightfield\"\n"                          // 39
    "name = \"valley\"\n"                               // 40
    "file = \"dem.tif\"\n"                              // 41
    "material = \"photo\"\n"                            // 42
    "offset = [10, 20, -5]\n"                           // 43
    "exaggeration = 2\n"                                // 44
    "method = \"embree-grid\"\n"                        // 45
    "cell_size = 30\n"                                  // 46
    "height_scale = 0.1\n"                              // 47
    "\n"                                                // 48
    "[[object]]\n"                                      // 49
    "type = \"sphere\"\n"                               // 50
    "material = \"glass\"\n"                            // 51
    "center = [1, 2, 3]\n"                              // 52
    "radius = 4.5\n"                                    // 53
    "velocity = [0, 0, -1]\n"                           // 54
    "\n"                                                // 55
    "[[object]]\n"                                      // 56
    "type = \"plane\"\n"                                // 57
    "point = [0, 0, 100]\n"                             // 58
    "normal = [0, 1, 1]\n"                              // 59
    "\n"                                                // 60
    "[[object]]\n"                                      // 61
    "type = \"triangle\"\n"                             // 62
    "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n"    // 63
    "\n"                                                // 64
    "[[object]]\n"                                      // 65
    "type = \"polygon\"\n"                              // 66
    "vertices = [[0, 0, 1], [4, 0, 1], [4, 4, 1], [2, 1, 1], [0, 4, 1]]\n"  // 67 (not convex)
    "\n"                                                // 68
    "[[object]]\n"                                      // 69
    "type = \"box\"\n"                                  // 70
    "min = [-1, -2, -3]\n"                              // 71
    "max = [1, 2, 3]\n"                                 // 72
    "\n"                                                // 73
    "[[object]]\n"                                      // 74
    "type = \"water\"\n"                                // 75
    "level = 812.5\n"                                   // 76
    "material = \"lake\"\n"                             // 77
    "\n"                                                // 78
    "[[light]]\n"                                       // 79
    "type = \"sun\"\n"                                  // 80
    "color = [1, 0.9, 0.8]\n"                           // 81
    "intensity = 2\n"                                   // 82
    "time = \"2026-06-21T21:30+02:00\"\n"               // 83
    "angular_radius = 0.5\n"                            // 84
    "\n"                                                // 85
    "[[light]]\n"                                       // 86
    "type = \"point\"\n"                                // 87
    "position = [5, 6, 7]\n"                            // 88
    "intensity = 100\n"                                 // 89
    "\n"                                                // 90
    "[[light]]\n"                                       // 91
    "type = \"sphere\"\n"                               // 92
    "position = [-5, -6, 7]\n"                          // 93
    "radius = 0.5\n"                                    // 94
    "color = [0.5, 0.5, 1]\n"                           // 95
    "\n"                                                // 96
    "[[light]]\n"                                       // 97
    "azimuth = 270\n"                                   // 98
    "elevation = -5\n"                                  // 99
    "\n"                                                // 100
    "[sky]\n"                                           // 101
    "model = \"physical\"\n"                            // 102
    "haze = 2.5\n"                                      // 103
    "aerial_perspective = false\n"                      // 104
    "ambient = 0.3\n"                                   // 105
    "\n"                                                // 106
    "[render]\n"                                        // 107
    "width = 320\n"                                     // 108
    "height = 200\n"                                    // 109
    "samples = 16\n"                                    // 110
    "sampler = \"poisson\"\n"                           // 111
    "filter = \"gaussian\"\n"                           // 112
    "max_depth = 12\n"                                  // 113
    "min_weight = 0.001\n"                              // 114
    "seed = 42\n"                                       // 115
    "threads = 3\n"                                     // 116
    "output = \"out/picture.png\"\n"                    // 117
    "exposure = 1.5\n";                                 // 118

}  // namespace terracast::testing
