#include "loaders/input_files.h"

#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <string_view>

namespace terracast {

namespace {

// What a file type is called in a message.
const char* kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a pipe (FIFO)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "something that is not a file";
}

}  // namespace

bool isGdalVirtualPath(const std::string& path) { return path.starts_with("/vsi"); }

bool isNetworkPath(const std::string& path) {
    static constexpr std::array<std::string_view, 12> kPrefixes = {
        "/vsicurl", "/vsis3",      "/vsigs",  "/vsiaz",    "/vsiadls", "/vsioss",
        "/vsiswift", "/vsihdfs", "/vsiwebhdfs", "http://", "https://", "ftp://"};
    // Chained paths (/vsizip//vsicurl/...) reach the network too.
    for (const auto prefix : kPrefixes)
        if (path.find(prefix) != std::string::npos) return true;
    return false;
}

void checkInputFile(const std::string& path, const char* what, bool allowEmpty) {
    if (isGdalVirtualPath(path)) return;
    if (path.empty()) throw InputError(fmt::format("expected {}, found an empty path", what));
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        const int error = errno;
        if (error == ENOENT) throw InputError(path + ": no such file");
        if (error == ELOOP) throw InputError(fmt::format("{}: expected {}, found a loop of symbolic links", path, what));
        throw InputError(fmt::format("{}: cannot be read ({})", path, std::strerror(error)));
    }
    if (S_ISDIR(st.st_mode)) throw InputError(path + ": is a directory");
    if (!S_ISREG(st.st_mode))
        throw InputError(fmt::format("{}: expected {} as a regular file, found {}", path, what, kindOf(st.st_mode)));
    if (st.st_size == 0 && !allowEmpty) throw InputError(path + ": file is empty");
    if (::access(path.c_str(), R_OK) != 0)
        throw InputError(fmt::format("{}: cannot be read ({})", path, std::strerror(errno)));
}

std::string readTextFile(const std::string& path, const char* what, int64_t maxBytes) {
    checkInputFile(path, what, true);
    const ExitOnCancel interruptible;
    // Opened without blocking and checked again through the descriptor: the path may have been replaced by a
    // pipe since the check.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw InputError(fmt::format("{}: cannot be read ({})", path, std::strerror(errno)));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw InputError(fmt::format("{}: expected {} as a regular file, found {}", path, what, kindOf(st.st_mode)));
    }
    if (st.st_size > maxBytes) {
        ::close(fd);
        throw InputError(fmt::format("{}: {} bytes, more than the {} ({}) allowed for {}", path, st.st_size, maxBytes,
                                     humanBytes(double(maxBytes)), what));
    }
    std::string text;
    char buffer[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) {
            if (cancelFlag().load()) break;
            continue;
        }
        if (n < 0) {
            const int error = errno;
            ::close(fd);
            throw InputError(fmt::format("{}: read failed ({})", path, std::strerror(error)));
        }
        if (n == 0) break;
        text.append(buffer, size_t(n));
        if (int64_t(text.size()) > maxBytes) {  // the file grew while being read
            ::close(fd);
            throw InputError(fmt::format("{}: more than the {} bytes ({}) allowed for {}", path, maxBytes,
                                         humanBytes(double(maxBytes)), what));
        }
    }
    ::close(fd);
    throwIfCancelled();
    return text;
}

}  // namespace terracast
