// Running the terracast executable from tests, capturing its exit code and output.
#pragma once

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

namespace terracast::testing {

struct CommandResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Runs `terracast <args>` through the shell (args are passed as written) and returns its results.
inline CommandResult runTerracast(const std::string& args) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path();
    const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(std::rand());
    const fs::path out = dir / ("terracast-out-" + tag), err = dir / ("terracast-err-" + tag);
    const std::string cmd =
        std::string("'") + TERRACAST_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

// How runTerracastArgs runs the executable.
struct RunSettings {
    std::filesystem::path workDir;    // the child's working folder (the test's own); empty: this process's
    double timeoutS = 60.0;           // then SIGKILL, and the result says hung
    // Send `signal` this long after the child has installed its handler for it (< 0: never): counted from
    // then, so that a slow start (a loaded machine, the sanitizers) does not meet the default action.
    double interruptAfterS = -1.0;
    std::filesystem::path interruptWhenExists;  // or as soon as this file exists (empty: never)
    int signal = SIGINT;
    std::string stdinPath = "/dev/null";
};

struct ArgsResult : CommandResult {
    bool hung = false;       // killed at the timeout
    int termSignal = 0;      // the signal that ended it, if one did
    double seconds = 0.0;    // from start to exit
    double stopSeconds = 0.0;  // from the interrupting signal to exit (0 when none was sent)
    double peakBytes = 0.0;  // the child's peak resident memory (getrusage's ru_maxrss)
};

// True when process `pid` runs `exe` (a canonical path) and has installed a handler for `sig` (its SigCgt mask
// in /proc). Until the exec, the child is a copy of this test process, whose handlers (Catch's, for SIGINT among
// others) the exec then resets.
inline bool catchesSignal(pid_t pid, const std::filesystem::path& exe, int sig) {
    std::error_code ec;
    const std::string proc = "/proc/" + std::to_string(pid);
    if (std::filesystem::read_symlink(proc + "/exe", ec) != exe || ec) return false;
    std::ifstream status(proc + "/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1u;
    return false;
}

// Runs the executable with `args` (no shell: each argument is passed as it is, newlines and all), its output
// captured in files beside the test's working folder.
inline ArgsResult runTerracastArgs(const std::vector<std::string>& args, const RunSettings& settings = {}) {
    namespace fs = std::filesystem;
    const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(std::rand());
    const fs::path out = fs::temp_directory_path() / ("terracast-out-" + tag),
                   err = fs::temp_directory_path() / ("terracast-err-" + tag);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (!settings.workDir.empty() && ::chdir(settings.workDir.c_str()) != 0) ::_exit(126);
        const int in = ::open(settings.stdinPath.c_str(), O_RDONLY);
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (in < 0 || o < 0 || e < 0) ::_exit(126);
        ::dup2(in, 0);
        ::dup2(o, 1);
        ::dup2(e, 2);
        std::vector<char*> argv;
        std::string exe = TERRACAST_CLI_PATH;
        argv.push_back(exe.data());
        std::vector<std::string> copy = args;
        for (auto& a : copy) argv.push_back(a.data());
        argv.push_back(nullptr);
        // A test runner may start jobs with SIGINT ignored; the executable must see the default disposition.
        ::signal(SIGINT, SIG_DFL);
        ::signal(SIGTERM, SIG_DFL);
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    ArgsResult r;
    int status = 0;
    bool signalled = false;
    double caughtAt = -1.0, signalledAt = 0.0;  // when the child was first seen catching the signal; sent it
    std::error_code exeError;
    const fs::path exePath = fs::canonical(TERRACAST_CLI_PATH, exeError);
    struct rusage usage {};
    for (;;) {
        const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
        if (done == pid) break;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (settings.interruptAfterS >= 0.0 && caughtAt < 0.0 && catchesSignal(pid, exePath, settings.signal))
            caughtAt = elapsed;
        std::error_code ec;
        if (!signalled && ((caughtAt >= 0.0 && elapsed >= caughtAt + settings.interruptAfterS) ||
                           (!settings.interruptWhenExists.empty() && fs::exists(settings.interruptWhenExists, ec)))) {
            ::kill(pid, settings.signal);
            signalled = true;
            signalledAt = elapsed;
        }
        if (elapsed >= settings.timeoutS) {
            ::kill(pid, SIGKILL);
            ::wait4(pid, &status, 0, &usage);
            r.hung = true;
            break;
        }
        ::usleep(2000);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (signalled) r.stopSeconds = r.seconds - signalledAt;
    r.peakBytes = double(usage.ru_maxrss) * 1024.0;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.termSignal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

// Number of lines in a text (a final line without a newline counts).
inline int lineCount(const std::string& text) {
    int n = 0;
    for (char c : text) n += c == '\n';
    if (!text.empty() && text.back() != '\n') ++n;
    return n;
}

}  // namespace terracast::testing
