// The command line's progress bar (console_progress.h).
#include "console_progress.h"

#include <algorithm>
#include <cstdio>
#include <string>

bool printProgress(double fraction) {
    static int shown = -1;
    const int width = 40, filled = std::clamp(int(fraction * width + 0.5), 0, width);
    if (filled == shown && fraction < 1.0) return true;
    shown = fraction >= 1.0 ? -1 : filled;
    std::fprintf(stderr, "\r  [%s%s] %5.1f%%", std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), '.').c_str(), 100.0 * fraction);
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    return true;
}
