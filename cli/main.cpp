// terracast: ray tracing of terrain height fields. Each command family (cli/*_command*.cpp) parses its options
// into the typed options of one library function; this file builds the command line and runs the command.
#include "cli/cli_support.h"
#include "tracer/core/text.h"

#include "tracer/core/cancel.h"
#include "heightfield/large_buffer.h"
#include "tracer/core/huge_pages.h"
#include "tracer/core/ranks.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <csignal>

#include <unistd.h>

using namespace terracast;

// SIGINT and SIGTERM ask the running command to stop between tiles; outputs are written only at the end
// (through a temporary file), so nothing partial is left. Inside an ExitOnCancel scope (a read that may block in
// a library, before anything is written) the process ends here and now.
extern "C" void onInterrupt(int) {
    cancelFlag().store(true);
    if (exitOnCancelDepth().load() > 0) {
        static const char message[] = "terracast: interrupted; no output written\n";
        [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, message, sizeof message - 1);
        ::_exit(130);
    }
}

int main(int argc, char** argv) {
    cancelFlag().store(false);  // made before the handlers, so a signal never initialises it
    useHugePagesForLargeBuffers();
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
    CLI::App app{"terracast: ray tracing of terrain height fields, exact or triangulated"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "terracast 0.1.0");

    cli::Commands commands;
    cli::addInfoCommand(app, commands);
    cli::addSceneCommand(app, commands);
    cli::addRenderCommand(app, commands);
    cli::addMapCommands(app, commands);
    cli::addMeasureCommands(app, commands);
    cli::addBenchCommand(app, commands);
    cli::checkNumberOptions(app);

    // A first word that is neither an option nor a command: CLI11 would only say that a command is required.
    std::string names;
    bool known = false;
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        known = known || (argc >= 2 && sub->check_name(argv[1]));
    }
    if (argc < 2 || (argv[1][0] != '-' && !known)) {
        fmt::print(stderr, "terracast: error: {} (expected one of {}; see terracast --help)\n",
                   argc < 2 ? std::string("no command given") : "unknown command '" + cli::oneLine(argv[1]) + "'", names);
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ExtrasError& e) {
        // CLI11 lists the extra words last to first; name the first, as the user typed it.
        for (CLI::App* sub : app.get_subcommands())
            if (!sub->remaining().empty()) {
                const std::string word = sub->remaining().front();
                std::vector<std::string> options;
                for (const CLI::Option* o : sub->get_options())
                    for (const std::string& name : o->get_lnames()) options.push_back("--" + name);
                const auto near = word.starts_with("--") ? nearMiss(word, options) : std::nullopt;
                fmt::print(stderr, "terracast: error: {}: unexpected argument '{}'{} (see terracast {} --help)\n",
                           sub->get_name(), cli::oneLine(word), near ? "; did you mean " + *near + "?" : "",
                           sub->get_name());
                return 2;
            }
        fmt::print(stderr, "terracast: error: {} (see terracast --help)\n", cli::oneLine(e.what()));
        return 2;
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "terracast: error: {} (see terracast --help)\n", cli::oneLine(e.what()));
        return 2;
    }
    // Under mpirun: join the ranks; the map products share their output tiles over them and render its picture's
    // blocks, and the other commands, which would each write the same output, are refused.
    try {
        ranks::start();
    } catch (const std::exception& e) {
        fmt::print(stderr, "terracast: error: {}\n", cli::oneLine(e.what()));
        return 1;
    }
    for (const auto& command : commands) {
        if (!*command.app) continue;
        const std::string name = command.app->get_name();
        if (ranks::size() > 1 && name != "shadow" && name != "horizon" && name != "svf" && name != "insolation" &&
            name != "viewshed" && name != "render") {
            if (ranks::leader())
                fmt::print(stderr, "terracast: error: {}: runs as one process; under mpirun only render, shadow, "
                                   "horizon, svf, insolation and viewshed share their work over the ranks\n", name);
            ranks::finish();
            return 2;
        }
        // A command's --threads bounds the library's passes over whole arrays too (building the grid), so that
        // a job given one core uses one (bench measures its own thread counts).
        if (const CLI::Option* threads = command.app->get_option_no_throw("--threads");
            threads != nullptr && threads->count() > 0 && name != "bench")
            setArrayPassThreads(threads->as<int>());
        const int code = command.run();
        ranks::finish();
        return code;
    }
    return 2;
}
