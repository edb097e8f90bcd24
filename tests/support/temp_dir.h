// A fresh folder under the system temporary directory for one test, removed with everything in it.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <iterator>
#include <string>

namespace terracast::testing {

class TempDir {
public:
    explicit TempDir(const std::string& tag = "test") {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                ("terracast-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ignored;
        // A test may have made the folder read-only; give it back before removing it.
        std::filesystem::permissions(path_, std::filesystem::perms::owner_all, std::filesystem::perm_options::add,
                                     ignored);
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    size_t entryCount() const {
        return static_cast<size_t>(std::distance(std::filesystem::directory_iterator(path_), {}));
    }

private:
    std::filesystem::path path_;
};

}  // namespace terracast::testing
