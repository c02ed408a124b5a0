// Runs a shell command and keeps what it printed: the command-line and editor tests' way to drive the
// real executables.
#pragma once
#include <string>

namespace testing_support {

struct ShellRun {
    int status = -1;     // the exit code; -1 when killed by a signal (a crash) or not started
    std::string output;  // stdout (add 2>&1 to the command for stderr too)
};

ShellRun runShell(const std::string& command);

} // namespace testing_support
