// The splatlab executable as the command-line tests run it (test_cli*.cpp).
#pragma once
#include "shell_run.h"
#include "test_paths.h"

#include <string>

namespace testing_support {

using CliRun = ShellRun;

// `splatlab ARGS` with stdout and stderr together. No DISPLAY: render and info must not need an X server.
inline CliRun splatlab(const std::string& args) {
    return runShell("env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 \"" SPLATLAB_EXE "\" " + args + " 2>&1");
}

inline std::string headsq() { return (assetDir() / "volumes" / "headsq.nhdr").string(); }

} // namespace testing_support
