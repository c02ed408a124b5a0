// The report's HTML and SVG (report_page.h).
#include "report_page.h"

#include "renderer/oracle/speed_error.h"
#include "ui/speed_error_chart.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string escaped(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

std::string colour(const ui::PointStyle& s) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", s.r, s.g, s.b);
    return buf;
}

// The marker about (0, 0), r px across its middle, as the editor draws it.
std::string marker(const ui::PointStyle& s, double r) {
    const std::string fill = "fill=\"" + colour(s) + "\"";
    const double d = 1.3 * r;
    switch (s.shape) {
    case ui::PointStyle::Circle:
        return "<circle r=\"" + fmt("%.1f", r) + "\" " + fill + "/>";
    case ui::PointStyle::Square:
        return "<rect x=\"" + fmt("%.1f", -r) + "\" y=\"" + fmt("%.1f", -r) + "\" width=\"" +
               fmt("%.1f", 2 * r) + "\" height=\"" + fmt("%.1f", 2 * r) + "\" " + fill + "/>";
    case ui::PointStyle::Diamond:
        return "<polygon points=\"0," + fmt("%.1f", -d) + " " + fmt("%.1f", d) + ",0 0," + fmt("%.1f", d) +
               " " + fmt("%.1f", -d) + ",0\" " + fill + "/>";
    case ui::PointStyle::Triangle:
        return "<polygon points=\"0," + fmt("%.1f", -d) + " " + fmt("%.1f", 1.2 * r) + "," + fmt("%.1f", r) +
               " " + fmt("%.1f", -1.2 * r) + "," + fmt("%.1f", r) + "\" " + fill + "/>";
    case ui::PointStyle::Hexagon: {
        std::string points;
        for (int k = 0; k < 6; ++k)
            points += fmt("%.1f", 1.2 * r * std::cos(k * M_PI / 3.0)) + "," + fmt("%.1f", 1.2 * r * std::sin(k * M_PI / 3.0)) + " ";
        return "<polygon points=\"" + points + "\" " + fill + "/>";
    }
    }
    return "";
}

} // namespace

std::string speedErrorSvg(std::span<const renderer::FilterMeasurement> points,
                          const renderer::SplatSettings& current, int width, int height) {
    const ui::SpeedErrorChart c =
        ui::layoutSpeedErrorChart(points, &current, 50, 12, width - 12, height - 42);
    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
        << "\" font-family=\"sans-serif\" font-size=\"12\" class=\"speed-error\" data-left=\"" << c.left
        << "\" data-right=\"" << c.right << "\" data-top=\"" << c.top << "\" data-bottom=\"" << c.bottom
        << "\" data-ms-lo=\"" << c.timeMs.lo << "\" data-ms-hi=\"" << fmt("%.17g", c.timeMs.hi)
        << "\" data-db-lo=\"" << c.psnrDb.lo << "\" data-db-hi=\"" << c.psnrDb.hi << "\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"#1e2026\"/>\n";
    // 1. Grid, ticks and axis names.
    for (double t : c.timeMs.ticks)
        svg << "<line x1=\"" << fmt("%.2f", c.xAt(t)) << "\" x2=\"" << fmt("%.2f", c.xAt(t)) << "\" y1=\""
            << c.top << "\" y2=\"" << c.bottom << "\" stroke=\"#ffffff30\"/><text x=\""
            << fmt("%.2f", c.xAt(t)) << "\" y=\"" << c.bottom + 15
            << "\" fill=\"#aaa\" text-anchor=\"middle\">" << fmt("%g", t) << "</text>\n";
    for (double t : c.psnrDb.ticks)
        svg << "<line x1=\"" << c.left << "\" x2=\"" << c.right << "\" y1=\"" << fmt("%.2f", c.yAt(t))
            << "\" y2=\"" << fmt("%.2f", c.yAt(t)) << "\" stroke=\"#ffffff30\"/><text x=\"" << c.left - 6
            << "\" y=\"" << fmt("%.2f", c.yAt(t) + 4) << "\" fill=\"#aaa\" text-anchor=\"end\">"
            << fmt("%g", t) << "</text>\n";
    svg << "<text x=\"" << 0.5 * (c.left + c.right) << "\" y=\"" << height - 8
        << "\" fill=\"#aaa\" text-anchor=\"middle\">frame time, ms (median, whisker p10-p90)</text>\n"
        << "<text x=\"12\" y=\"" << 0.5 * (c.top + c.bottom) << "\" fill=\"#aaa\" text-anchor=\"middle\" "
        << "transform=\"rotate(-90 12 " << 0.5 * (c.top + c.bottom) << ")\">PSNR, dB</text>\n";
    // 2. The Pareto front, then each point: whisker, marker, front and current rings, a tooltip.
    for (size_t i = 0; i < c.front.size();) { // a polyline per ground truth
        size_t end = i + 1;
        while (end < c.front.size() && renderer::sameGroundTruth(points[c.front[i]], points[c.front[end]]))
            ++end;
        svg << "<polyline class=\"pareto-front\" fill=\"none\" stroke=\"#ffd250\" stroke-width=\"1.5\" "
               "points=\"";
        for (size_t k = i; k < end; ++k)
            svg << fmt("%.3f", c.points[c.front[k]].x) << "," << fmt("%.3f", c.points[c.front[k]].y) << " ";
        svg << "\"/>\n";
        i = end;
    }
    for (size_t i = 0; i < points.size(); ++i) {
        const renderer::FilterMeasurement& m = points[i];
        const ui::ChartPoint& p = c.points[i];
        const ui::PointStyle style = ui::pointStyle(m);
        svg << "<g class=\"point\" data-setting=\"" << escaped(ui::settingLabel(m)) << "\" data-median-ms=\""
            << fmt("%.17g", m.frameMs) << "\" data-p10-ms=\"" << fmt("%.17g", m.p10Ms) << "\" data-p90-ms=\""
            << fmt("%.17g", m.p90Ms) << "\" data-psnr-db=\"" << fmt("%.17g", m.psnrDb) << "\" data-pareto=\""
            << (p.pareto ? 1 : 0) << "\" data-current=\"" << (p.current ? 1 : 0) << "\">"
            << "<title>" << escaped(ui::settingLabel(m)) << ": " << fmt("%.2f", m.frameMs) << " ms (p10 "
            << fmt("%.2f", m.p10Ms) << ", p90 " << fmt("%.2f", m.p90Ms) << "), " << fmt("%.2f", m.psnrDb)
            << " dB</title>"
            << "<line class=\"whisker\" x1=\"" << fmt("%.3f", p.xLo) << "\" x2=\"" << fmt("%.3f", p.xHi)
            << "\" y1=\"" << fmt("%.3f", p.y) << "\" y2=\"" << fmt("%.3f", p.y) << "\" stroke=\""
            << colour(style) << "\"/>"
            << "<g class=\"marker\" transform=\"translate(" << fmt("%.3f", p.x) << "," << fmt("%.3f", p.y)
            << ")\">" << marker(style, 4.0);
        if (p.pareto) svg << "<circle r=\"7.5\" fill=\"none\" stroke=\"#ffd250\" stroke-width=\"1.5\"/>";
        if (p.current) svg << "<circle r=\"11\" fill=\"none\" stroke=\"#fff\" stroke-width=\"2\"/>";
        svg << "</g></g>\n";
    }
    svg << "</svg>";
    return svg.str();
}

std::string reportHtml(const ReportPage& page) {
    std::ostringstream html;
    html
        << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>SplatLab: speed against "
           "error</title>\n<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;"
           "color:#222}table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:2px "
           "6px;"
           "text-align:right}td:first-child{text-align:left}tr.pareto{background:#fff4cc}img{image-rendering:"
           "pixelated;vertical-align:middle}.chart{display:flex;gap:1em;align-items:flex-start}</style></"
           "head><body>\n"
        << "<h1>Speed against error</h1>\n<p>Generated by <code>splatlab report</code> on <b>"
        << escaped(page.glRenderer) << "</b> (" << escaped(page.machine) << ") in "
        << fmt("%.0f", page.seconds) << " s. Each filter x compositing mode is rendered " << page.repeats
        << " times over the whole view after one untimed frame: the marker is the median wall time of a "
           "frame "
           "(render + glFinish), the whisker its 10th to 90th percentile. PSNR is of the view's centre crop "
           "against the ground truth (the exact integral along Gaussian-weighted rays, computed on the CPU; "
           "one for the attenuating modes, one for X-ray). Gold rings and the gold lines: the Pareto fronts "
           "(no other setting is both at least as fast and at least as close, and better in one; X-ray is "
           "compared with a ground truth of its own, so it has a front of its own). White ring: the settings "
           "the others vary from. Colour: the filter (red reconstruction, green low-pass, blue "
           "EWA, "
           "grey adaptive); shape: the compositing (circle splat-every-sample, square sheets back to front, "
           "diamond sheets front to back, triangle X-ray).</p>\n";
    for (const ReportSection& s : page.sections) {
        const std::vector<bool> front = renderer::paretoFront(s.points);
        html << "<h2>" << escaped(s.name) << "</h2>\n<p>" << escaped(s.view) << "</p>\n<div class=\"chart\">"
             << speedErrorSvg(s.points, s.current, 640, 360) << "\n<div><img src=\"" << escaped(s.viewImage)
             << "\" width=\"256\" alt=\"the view\"><br>the view ("
             << escaped(renderer::filterModeName(s.current.filter)) << ", "
             << renderer::compositingName(s.current.compositing) << ")<br><img src=\""
             << escaped(s.truthImage) << "\" width=\"" << 2 * s.cropWidth
             << "\" alt=\"ground truth\"><br>ground truth of the centre " << s.cropWidth << " x "
             << s.cropHeight << " px</div></div>\n"
             << "<table><tr><th>filter, compositing</th><th>median ms</th><th>p10 ms</th><th>p90 ms</th>"
                "<th>PSNR dB</th><th>RMSE</th><th>Pareto</th><th>crop</th></tr>\n";
        for (size_t i = 0; i < s.points.size(); ++i) {
            const renderer::FilterMeasurement& m = s.points[i];
            html << "<tr" << (front[i] ? " class=\"pareto\"" : "") << "><td>" << escaped(ui::settingLabel(m))
                 << "</td><td>" << fmt("%.2f", m.frameMs) << "</td><td>" << fmt("%.2f", m.p10Ms)
                 << "</td><td>" << fmt("%.2f", m.p90Ms) << "</td><td>" << fmt("%.2f", m.psnrDb) << "</td><td>"
                 << fmt("%.5f", m.rmse) << "</td><td>" << (front[i] ? "yes" : "") << "</td><td><img src=\""
                 << escaped(s.cropImages[i]) << "\" width=\"" << s.cropWidth << "\" alt=\"\"></td></tr>\n";
        }
        html << "</table>\n";
    }
    html << "</body></html>\n";
    return html.str();
}

std::string reportMarkdown(const ReportPage& page) {
    std::ostringstream md;
    md << "Generated by `splatlab report` on " << page.glRenderer << " (" << page.machine << "), "
       << page.repeats << " timed frames per setting after one untimed: the median frame (render + glFinish) "
       << "and its 10th to 90th percentile, then the PSNR of the view's centre crop against its ground truth "
          "(X-ray's own); **Pareto**: no other setting is both at least as fast and at least as close.\n";
    for (const ReportSection& s : page.sections) {
        const std::vector<bool> front = renderer::paretoFront(s.points);
        md << "\n**" << s.name << "**: " << s.view << ".\n\n"
           << "| filter, compositing | median ms (p10-p90) | PSNR dB | Pareto |\n|---|---|---|---|\n";
        for (size_t i = 0; i < s.points.size(); ++i) {
            const renderer::FilterMeasurement& m = s.points[i];
            md << "| " << ui::settingLabel(m) << " | " << fmt("%.2f", m.frameMs) << " (" << fmt("%.2f", m.p10Ms)
               << "-" << fmt("%.2f", m.p90Ms) << ") | " << fmt("%.2f", m.psnrDb) << " | " << (front[i] ? "yes" : "")
               << " |\n";
        }
    }
    return md.str();
}

std::string reportSummaryMarkdown(const ReportPage& page) {
    if (page.sections.empty()) return {};
    // Sheets front to back: the editor's starting mode, and `render`'s default.
    constexpr renderer::Compositing shown = renderer::Compositing::SheetFrontToBack;
    std::ostringstream md;
    md << "Generated by `splatlab report` on " << page.glRenderer << " (" << page.machine << "): median of "
       << page.repeats << " frames and the PSNR of the view's centre crop against its ground truth, "
       << renderer::compositingName(shown) << "; the Pareto front over every compositing mode.\n\n"
       << "| scan | voxels, TF, image |";
    constexpr renderer::FilterMode kFilters[] = {renderer::FilterMode::Ewa, renderer::FilterMode::Adaptive,
                                                 renderer::FilterMode::Reconstruction, renderer::FilterMode::LowPass};
    for (renderer::FilterMode f : kFilters) md << " " << renderer::filterModeName(f) << " |";
    md << " Pareto front |\n|---|---|---|---|---|---|---|\n";
    for (const ReportSection& s : page.sections) {
        md << "| " << s.name << " | " << s.brief << " |";
        for (renderer::FilterMode f : kFilters) {
            std::string cell = " - ";
            for (const renderer::FilterMeasurement& m : s.points)
                if (m.filter == f && m.compositing == shown && m.slabThickness == 0.0)
                    cell = " " + fmt("%.2f", m.frameMs) + " ms, " + fmt("%.2f", m.psnrDb) + " dB ";
            md << cell << "|";
        }
        const std::vector<bool> front = renderer::paretoFront(s.points);
        std::string onFront;
        for (size_t i = 0; i < s.points.size(); ++i)
            if (front[i]) onFront += (onFront.empty() ? "" : "; ") + ui::settingLabel(s.points[i]);
        md << " " << onFront << " |\n";
    }
    return md.str();
}
