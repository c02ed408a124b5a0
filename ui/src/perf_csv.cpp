// The recorded renders as CSV (perf_csv.h).
#include "ui/perf_csv.h"

#include "renderer/io/atomic_file.h"

#include <charconv>

namespace ui {

namespace {

template <class Number> void appendNumber(std::string& out, Number value) {
    char text[32];
    const auto [end, error] = std::to_chars(text, text + sizeof text, value);
    out.append(text, error == std::errc() ? end : text);
}

} // namespace

std::string perfCsv(const std::deque<PerfSample>& samples) {
    std::string csv = "frame,interval_ms,cpu_ms,gpu_ms";
    for (int p = 0; p < renderer::kGpuPasses; ++p) {
        std::string name = renderer::gpuPassName(renderer::GpuPass(p));
        for (char& c : name)
            if (c == ' ') c = '_';
        csv += "," + name + "_ms";
    }
    csv += ",splats,upload_bytes,first_use_programs\n";
    for (const PerfSample& s : samples) {
        appendNumber(csv, s.frame);
        for (double ms : {s.intervalMs, s.cpuMs, s.gpuMs})
            csv += ',', appendNumber(csv, ms);
        for (double ms : s.passMs)
            csv += ',', appendNumber(csv, ms);
        csv += ',', appendNumber(csv, s.splats);
        csv += ',', appendNumber(csv, s.uploadBytes);
        csv += ',', appendNumber(csv, s.firstUsePrograms);
        csv += '\n';
    }
    return csv;
}

void writePerfCsv(const std::filesystem::path& path, const std::deque<PerfSample>& samples) {
    renderer::writeFileAtomically(path, perfCsv(samples));
}

} // namespace ui
