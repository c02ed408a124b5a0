// The Performance panel's recorded renders as CSV, a row a render, for a spreadsheet or a script.
#pragma once
#include "ui/perf_history.h"

#include <deque>
#include <filesystem>
#include <string>

namespace ui {

// Header "frame,interval_ms,cpu_ms,gpu_ms,<pass>_ms...,splats,upload_bytes,first_use_programs" (a column
// per renderer::GpuPass, its name with '_' for spaces), then a row per sample, oldest first. Numbers in
// their shortest form that reads back to the same double (std::to_chars).
std::string perfCsv(const std::deque<PerfSample>& samples);

// perfCsv written atomically (renderer::writeFileAtomically): the file is the old one or the new one,
// never half of one. Throws renderer::LoadError naming `path` on failure.
void writePerfCsv(const std::filesystem::path& path, const std::deque<PerfSample>& samples);

} // namespace ui
