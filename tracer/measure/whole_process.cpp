#include "tracer/measure/whole_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>

extern char** environ;

namespace terracast {

ProcessRun runTimedProcess(const std::vector<std::string>& argv, const std::string& folder, const std::string& logPath) {
    if (argv.empty()) throw std::runtime_error("runTimedProcess: no program");
    // Checked here: behind GNU time, a program that cannot start would only show as its exit status 127. Made
    // absolute, as the child starts in `folder`.
    std::string program = argv[0].find('/') == std::string::npos ? findOnPath(argv[0]) : argv[0];
    if (program.empty() || ::access(program.c_str(), X_OK) != 0)
        throw std::runtime_error("cannot start " + argv[0] + ": no such executable");
    program = std::filesystem::absolute(program).string();
    // GNU time forks the program from its own small process and reports the program's peak (%M, KiB) alone.
    static const std::string gnuTime = ::access("/usr/bin/time", X_OK) == 0 ? "/usr/bin/time" : "";
    const std::string peakFile = logPath + ".peak";
    std::vector<std::string> command;
    const std::string peakPath = std::filesystem::absolute(peakFile).string();
    if (!gnuTime.empty()) command = {gnuTime, "-f", "%M", "-o", peakPath};
    command.push_back(program);
    command.insert(command.end(), argv.begin() + 1, argv.end());
    std::vector<char*> args;
    for (const auto& a : command) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    const std::string log = std::filesystem::absolute(logPath).string();
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    if (!folder.empty()) posix_spawn_file_actions_addchdir_np(&actions, folder.c_str());

    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int failed = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (failed != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(failed));

    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error("waiting for " + argv[0] + ": " + std::strerror(errno));
    ProcessRun run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.peakBytes = std::numeric_limits<double>::quiet_NaN();
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
    if (!gnuTime.empty()) {
        // Its last line is the number ("Command exited with non-zero status N" may come before it).
        std::ifstream in(peakPath);
        std::string line, last;
        while (std::getline(in, line))
            if (!line.empty()) last = line;
        char* end = nullptr;
        const double kib = std::strtod(last.c_str(), &end);
        if (end != last.c_str() && kib > 0.0) run.peakBytes = kib * 1024.0;
        std::error_code ec;
        std::filesystem::remove(peakPath, ec);
    }
    return run;
}

std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (path == nullptr || name.empty()) return {};
    const std::string list = path;
    size_t begin = 0;
    while (begin <= list.size()) {
        const size_t end = std::min(list.find(':', begin), list.size());
        const std::string dir = end > begin ? list.substr(begin, end - begin) : ".";
        const std::string candidate = dir + "/" + name;
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
            return std::filesystem::absolute(candidate).string();
        begin = end + 1;
    }
    return {};
}

std::string selfExecutablePath() {
    std::error_code ec;
    const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : p.string();
}

}  // namespace terracast
