// The splatlab executable as the command-line tests run it (test_cli*.cpp).
#pragma once
#include "shell_run.h"
#include "test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace testing_support {

using CliRun = ShellRun;

// `splatlab ARGS` with stdout and stderr together. No DISPLAY: render and info must not need an X server.
inline CliRun splatlab(const std::string& args) {
    return runShell("env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 \"" SPLATLAB_EXE "\" " + args + " 2>&1");
}

inline std::string headsq() { return (assetDir() / "volumes" / "headsq.nhdr").string(); }

// `splatlab editor FLAGS` under Xvfb for three frames; the session it closed with (--session-out; empty
// on failure).
inline nlohmann::json editorClosingSession(const std::string& flags, const std::filesystem::path& out) {
    std::filesystem::remove(out);
    const std::string command = "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" "
                                "xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor " + flags +
                                " --frames 3 --size 1280x800 --session-out \"" + out.string() + "\"";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(out);
    return in ? nlohmann::json::parse(in) : nlohmann::json();
}

} // namespace testing_support
