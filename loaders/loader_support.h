// Helpers shared by the loaders' sources (internal: only loaders/*.cpp include this; it pulls in GDAL).
#pragma once

#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <fmt/format.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#include <gdal.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>

namespace terracast::loader_support {

// The first line of a library's error message, without trailing blanks.
inline std::string firstLine(const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    return line;
}

// The folder an output file goes to, after checking that it exists and may be written in; both are the
// user's to fix, so failures are InputErrors naming the path.
inline std::filesystem::path writableFolder(const std::string& path) {
    const std::filesystem::path target(path);
    const std::filesystem::path folder = target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
        throw InputError(fmt::format("{}: folder '{}' does not exist", path, folder.string()));
    if (::access(folder.c_str(), W_OK) != 0)
        throw InputError(fmt::format("{}: folder '{}' is not writable ({})", path, folder.string(), std::strerror(errno)));
    return folder;
}

// Captures what the process writes to stderr while it lives. libpng, under OpenImageIO, prints its errors and
// warnings straight to stderr; capturing them keeps terracast's own one-line message the only line, and lets
// the message quote libpng's reason. Meant for short, single-threaded reads (loading happens before rendering).
class CapturedStderr {
public:
    CapturedStderr() {
        std::fflush(stderr);
        file_ = std::tmpfile();
        saved_ = file_ ? ::dup(STDERR_FILENO) : -1;
        if (saved_ >= 0) ::dup2(::fileno(file_), STDERR_FILENO);
    }
    ~CapturedStderr() { restore(); }
    CapturedStderr(const CapturedStderr&) = delete;
    CapturedStderr& operator=(const CapturedStderr&) = delete;

    // Stops capturing and returns the first line written meanwhile ("" when none).
    std::string firstLineWritten() {
        restore();
        return text_.substr(0, text_.find('\n'));
    }

private:
    void restore() {
        if (saved_ >= 0) {
            std::fflush(stderr);
            ::dup2(saved_, STDERR_FILENO);
            ::close(saved_);
            saved_ = -1;
            std::rewind(file_);
            char buffer[512];
            size_t n = 0;
            while (text_.size() < 4096 && (n = std::fread(buffer, 1, sizeof buffer, file_)) > 0) text_.append(buffer, n);
        }
        if (file_) std::fclose(file_);
        file_ = nullptr;
    }
    std::FILE* file_ = nullptr;
    int saved_ = -1;
    std::string text_;
};

// Registers GDAL's drivers once per process, and bounds how long a network path may keep a read waiting
// (GDAL's own default is to wait without end) unless the user has set GDAL's options.
inline void registerGdalDrivers() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (CPLGetConfigOption("GDAL_HTTP_CONNECTTIMEOUT", nullptr) == nullptr)
            CPLSetConfigOption("GDAL_HTTP_CONNECTTIMEOUT", "20");
        if (CPLGetConfigOption("GDAL_HTTP_TIMEOUT", nullptr) == nullptr) CPLSetConfigOption("GDAL_HTTP_TIMEOUT", "60");
        GDALAllRegister();
    });
}

// Keeps GDAL from printing on this thread while it lives; failures reach the caller as exceptions instead.
class QuietGdalErrors {
public:
    QuietGdalErrors() {
        CPLPushErrorHandler(CPLQuietErrorHandler);
        CPLErrorReset();
    }
    ~QuietGdalErrors() { CPLPopErrorHandler(); }
    QuietGdalErrors(const QuietGdalErrors&) = delete;
    QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;
};

// The temporary file an output is written to before its rename: in the target's folder, named by this process's
// id and a counter only, so that its name stays short whatever the target's length (a 248-byte name plus a
// suffix would pass the file system's 255-byte limit). Temporary files of processes that no longer run (killed
// between writing and renaming) are removed from the folder first.
inline std::filesystem::path temporaryPathFor(const std::filesystem::path& folder, const std::string& extension) {
    static std::atomic<int> counter{0};
    std::error_code ec;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        long pid = 0;
        int n = 0, used = 0;
        if (std::sscanf(name.c_str(), ".terracast-%ld-%d.tmp%n", &pid, &n, &used) == 2 && used > 0 && pid > 0 &&
            pid != long(::getpid()) && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
            std::error_code ignored;
            std::filesystem::remove(it->path(), ignored);
        }
    }
    return folder / fmt::format(".terracast-{}-{}.tmp{}", ::getpid(), counter++, extension);
}

// Makes a written temporary file the target durably: its data flushed to the disk, renamed over the target, and
// the folder's entry flushed, so that a power cut leaves the old file or the new one, never an empty one.
// Returns 0 or the errno of the step that failed.
inline int commitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& target) {
    const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return errno;
    const bool synced = ::fsync(fd) == 0;
    const int syncError = errno;
    ::close(fd);
    if (!synced) return syncError;
    if (::rename(temporary.c_str(), target.c_str()) != 0) return errno;
    const std::filesystem::path folder = target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
    const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);  // some file systems refuse to sync a folder; the file itself is already safe
        ::close(dir);
    }
    return 0;
}

// Removes the file at `path` when destroyed, unless released: the temporary half of write-and-rename.
class TemporaryFile {
public:
    explicit TemporaryFile(std::filesystem::path path) : path_(std::move(path)) {}
    ~TemporaryFile() {
        std::error_code ignored;
        if (!released_) std::filesystem::remove(path_, ignored);
    }
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;
    const std::filesystem::path& path() const { return path_; }
    void release() { released_ = true; }

private:
    std::filesystem::path path_;
    bool released_ = false;
};

}  // namespace terracast::loader_support
