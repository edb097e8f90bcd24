// Checks on input paths, made before any reader touches them: a reader handed a pipe, a device or a link loop
// can block forever or read without end, so only regular files (after links) are read, and text inputs are read
// with a bound on their size. GDAL's virtual paths (/vsizip/, /vsicurl/, ...) are left to GDAL, which opens them
// itself; the network ones are recognised so that a scene file can be refused them.
#pragma once

#include <cstdint>
#include <string>

namespace terracast {

// Refuses (InputError naming the path and what was found) anything at `path` but a non-empty regular file that
// can be read: a missing path, a folder, a pipe, a device, a socket, a link loop, an unreadable file. `what`
// names the item in messages ("a DEM", "a scene file"). An empty file is refused unless `allowEmpty`. GDAL
// virtual paths pass unchecked.
void checkInputFile(const std::string& path, const char* what, bool allowEmpty = false);

// True for GDAL virtual paths (they start with /vsi).
bool isGdalVirtualPath(const std::string& path);

// True for paths that make GDAL reach a network (/vsicurl/, /vsis3/, ... and http://, https://, ftp://).
bool isNetworkPath(const std::string& path);

// The whole of a regular text file (empty allowed), after checkInputFile; refuses (InputError) files larger than `maxBytes`.
std::string readTextFile(const std::string& path, const char* what, int64_t maxBytes);

}  // namespace terracast
