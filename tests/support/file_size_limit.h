// A full disk for a test: while a FileSizeLimit lives, files may grow to `bytes` and a write past that
// fails (SIGXFSZ ignored) instead of killing the process. The old limit and signal come back after.
#pragma once
#include <sys/resource.h>

#include <csignal>

namespace testing_support {

class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t bytes) : m_previousSignal(std::signal(SIGXFSZ, SIG_IGN)) {
        m_active = getrlimit(RLIMIT_FSIZE, &m_saved) == 0;
        rlimit small = m_saved;
        small.rlim_cur = bytes;
        m_active = m_active && setrlimit(RLIMIT_FSIZE, &small) == 0;
    }
    ~FileSizeLimit() {
        if (m_active) setrlimit(RLIMIT_FSIZE, &m_saved);
        std::signal(SIGXFSZ, m_previousSignal);
    }
    FileSizeLimit(const FileSizeLimit&) = delete;
    FileSizeLimit& operator=(const FileSizeLimit&) = delete;
    bool active() const { return m_active; }   // false: the limit could not be set

private:
    rlimit m_saved{};
    void (*m_previousSignal)(int);
    bool m_active = false;
};

} // namespace testing_support
