#include "shell_run.h"

#include <array>
#include <cstdio>
#include <sys/wait.h>

namespace testing_support {

ShellRun runShell(const std::string& command) {
    ShellRun r;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf;
    while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) r.output.append(buf.data(), n);
    const int status = pclose(pipe);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

} // namespace testing_support
