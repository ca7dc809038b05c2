#include "scale_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include <embree3/rtcore_config.h>
#include <tbb/version.h>

#include "build_info.h"
#include "kernels/simd.h"

namespace foton::app {

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string hex(uint64_t h) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

// Text inside SVG: the markup characters escaped.
std::string xml_text(const std::string& t) {
    std::string o;
    for (const char c : t) {
        if (c == '&')
            o += "&amp;";
        else if (c == '<')
            o += "&lt;";
        else if (c == '>')
            o += "&gt;";
        else
            o += c;
    }
    return o;
}

const char* compiler() {
#ifdef __clang__
    return "clang " __clang_version__;
#else
    return "gcc " __VERSION__;
#endif
}

const char* mode(const ScaleStudy& s) {
    return s.args.time ? "throughput" : s.args.weak ? "weak" : "strong";
}

}  // namespace

std::string scale_markdown(const ScaleStudy& s) {
    std::string md = "## " + s.args.scene + ": " + s.integrator + ", " + mode(s) + " scaling, " +
                     std::to_string(s.width) + " x " + std::to_string(s.height) + ", median of " +
                     std::to_string(s.args.repeats) + (s.args.pin ? ", pinned" : "") +
                     "\n\n| threads | wall s | min | max | speed-up | efficiency | Karp-Flatt | "
                     "samples/s |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const ScalePoint& p : s.points)
        md += "| " + std::to_string(p.threads) + " | " + fmt("%.3f", p.wall_median) + " | " +
              fmt("%.3f", p.wall_min) + " | " + fmt("%.3f", p.wall_max) + " | " +
              fmt("%.2f", p.speedup) + " | " + fmt("%.2f", p.efficiency) + " | " +
              (p.threads > s.points.front().threads ? fmt("%.3f", p.karp_flatt) : "-") + " | " +
              fmt("%.4g", p.rate) + " |\n";
    if (!s.points.empty() && !s.points.front().stage_efficiency.empty()) {
        md += "\nPer stage: efficiency (thread-seconds of the first count over these";
        md += s.args.weak ? ", per unit of work)" : ")";
        md += "\n\n| stage |";
        std::string rule = "|---|";
        for (const ScalePoint& p : s.points) {
            md.append(" ").append(std::to_string(p.threads)).append(" |");
            rule += "---:|";
        }
        md += " thread-s at " + std::to_string(s.points.back().threads) + " |\n" + rule + "---:|\n";
        const ScalePoint& last = s.points.back();
        for (std::size_t i = 0; i < s.points.front().stage_efficiency.size(); ++i) {
            const std::string& name = s.points.front().stage_efficiency[i].first;
            md += "| " + name + " |";
            for (const ScalePoint& p : s.points) {
                double e = 0.0;
                for (const auto& [n, v] : p.stage_efficiency)
                    if (n == name) e = v;
                md.append(" ").append(fmt("%.2f", e)).append(" |");
            }
            double ts = 0.0;
            for (const auto& [n, v] : last.stage_thread_seconds)
                if (n == name) ts = v;
            md.append(" ").append(fmt("%.3f", ts)).append(" |\n");
        }
        if (!s.worst_stage.empty())
            md += "\nScales worst at " + std::to_string(last.threads) +
                  " threads: " + s.worst_stage + "\n";
    }
    if (s.images_identical)
        md += std::string("\nImages across thread counts: ") +
              (*s.images_identical ? "bit-identical" : "DIFFERENT") + "\n";
    return md;
}

std::string scale_json(const ScaleStudy& s, const CpuTopology& m) {
    using J = nlohmann::ordered_json;
    auto stages = [](const std::vector<std::pair<std::string, double>>& v) {
        J o = J::object();
        for (const auto& [name, value] : v) o[name] = value;
        return o;
    };
    J j;
    j["schema"] = "foton-scale";
    j["schema_version"] = 1;
    j["machine"] = {{"cpu", m.model},
                    {"sockets", m.sockets},
                    {"cores", m.cores},
                    {"logical_cpus", m.logical},
                    {"threads_per_core", m.threads_per_core},
                    {"numa_nodes", m.numa_nodes},
                    {"simd", simd::Arch::name()},
                    {"simd_width", simd::kWidth}};
    j["build"] = {{"version", FOTON_VERSION},
                  {"git_commit", git_commit()},
                  {"compiler", compiler()},
                  {"onetbb", TBB_VERSION_STRING},
                  {"embree", RTC_VERSION_STRING}};
    j["scene"] = {{"path", s.args.scene}, {"fnv1a", hex(s.scene_hash)}};
    j["settings"] = {{"integrator", s.integrator},
                     {"renderer", s.settings},
                     {"accelerator", s.accel},
                     {"width", s.width},
                     {"height", s.height},
                     {"mode", mode(s)},
                     {"time", s.args.time ? J(*s.args.time) : J(nullptr)},
                     {"repeats", s.args.repeats},
                     {"pinned", s.args.pin},
                     {"command_line", s.args.command_line}};
    j["images_identical"] = s.images_identical ? J(*s.images_identical) : J(nullptr);
    j["worst_stage"] = s.worst_stage.empty() ? J(nullptr) : J(s.worst_stage);
    J points = J::array();
    for (const ScalePoint& p : s.points)
        points.push_back({{"threads", p.threads},
                          {"wall_median", p.wall_median},
                          {"wall_min", p.wall_min},
                          {"wall_max", p.wall_max},
                          {"samples_per_second", p.rate},
                          {"speedup", p.speedup},
                          {"efficiency", p.efficiency},
                          {"karp_flatt", p.karp_flatt},
                          {"stage_thread_seconds", stages(p.stage_thread_seconds)},
                          {"stage_efficiency", stages(p.stage_efficiency)}});
    j["points"] = std::move(points);
    J runs = J::array();
    for (const ScaleRun& r : s.runs)
        runs.push_back({{"threads", r.threads},
                        {"repeat", r.repeat},
                        {"wall_seconds", r.wall_seconds},
                        {"build_seconds", r.build_seconds},
                        {"samples", r.samples},
                        {"passes", r.passes},
                        {"image_fnv1a", hex(r.image_hash)},
                        {"stage_thread_seconds", stages(r.stage_thread_seconds)}});
    j["runs"] = std::move(runs);
    // Invalid UTF-8 (a file name) is replaced, never thrown.
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string scale_svg(const ScaleStudy& s) {
    // Two panels: speed-up against threads (with the ideal line), and efficiency (overall,
    // bold, and per stage).
    const double W = 1080, H = 380, pw = 360, ph = 270, top = 50, left[2] = {70, 520};
    const int nmax = s.points.empty() ? 1 : s.points.back().threads;
    const int nmin = s.points.empty() ? 1 : s.points.front().threads;
    double smax = nmax;
    for (const ScalePoint& p : s.points) smax = std::max(smax, p.speedup);
    double emax = 1.0;
    for (const ScalePoint& p : s.points)
        for (const auto& [n, e] : p.stage_efficiency) emax = std::max(emax, std::min(e, 2.0));
    // Round axis tops and a step of 1, 2, 2.5 or 5 times a power of ten, four or five ticks.
    auto step_for = [](double top_value) {
        const double raw = top_value / 4, mag = std::pow(10.0, std::floor(std::log10(raw)));
        for (const double m : {1.0, 2.0, 2.5, 5.0})
            if (m * mag >= raw) return m * mag;
        return 10 * mag;
    };
    const double step[2] = {step_for(smax), step_for(emax)};
    const double vtop[2] = {std::ceil(smax / step[0] - 1e-9) * step[0],
                            std::ceil(emax / step[1] - 1e-9) * step[1]};
    // Thread counts from 1 to 64 read best on a log2 axis once they span a factor of 8.
    const bool log_x = nmax >= 8 * nmin;
    auto X = [&](int panel, double n) {
        const double f = nmax == nmin ? 0.5
                         : log_x      ? std::log2(n / nmin) / std::log2(double(nmax) / nmin)
                                      : (n - nmin) / double(nmax - nmin);
        return left[panel] + f * pw;
    };
    auto Y = [&](double v, double vmax) { return top + ph - std::min(v, vmax) / vmax * ph; };
    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt("%g", W) +
                      "\" height=\"" + fmt("%g", H) +
                      "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" "
                      "height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + fmt("%g", W / 2) +
           "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" + xml_text(s.args.scene) + ": " +
           s.integrator + ", " + mode(s) + " scaling</text>\n";
    const char* palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
    for (int panel = 0; panel < 2; ++panel) {
        const double vmax = vtop[panel];
        svg += "<rect x=\"" + fmt("%g", left[panel]) + "\" y=\"" + fmt("%g", top) + "\" width=\"" +
               fmt("%g", pw) + "\" height=\"" + fmt("%g", ph) +
               "\" fill=\"none\" stroke=\"black\"/>\n";
        for (const ScalePoint& p : s.points)
            svg += "<text x=\"" + fmt("%.1f", X(panel, p.threads)) + "\" y=\"" +
                   fmt("%g", top + ph + 16) + "\" text-anchor=\"middle\">" +
                   std::to_string(p.threads) + "</text>\n";
        for (double v = 0.0; v <= vmax + 1e-9; v += step[panel]) {
            svg += "<text x=\"" + fmt("%g", left[panel] - 6) + "\" y=\"" +
                   fmt("%.1f", Y(v, vmax) + 4) + "\" text-anchor=\"end\">" + fmt("%g", v) +
                   "</text>\n<line x1=\"" + fmt("%g", left[panel]) + "\" x2=\"" +
                   fmt("%g", left[panel] + pw) + "\" y1=\"" + fmt("%.1f", Y(v, vmax)) + "\" y2=\"" +
                   fmt("%.1f", Y(v, vmax)) + "\" stroke=\"#ddd\"/>\n";
        }
        svg += "<text x=\"" + fmt("%g", left[panel] + pw / 2) + "\" y=\"" +
               fmt("%g", top + ph + 34) + "\" text-anchor=\"middle\">threads" +
               (log_x ? " (log scale)" : "") + "</text>\n<text x=\"" + fmt("%g", left[panel]) +
               "\" y=\"" + fmt("%g", top - 8) + "\">" +
               (panel == 0 ? "speed-up" : "parallel efficiency") + "</text>\n";
        auto polyline = [&](const std::vector<std::pair<double, double>>& pts, const char* color,
                            double width, const char* dash) {
            std::string line = "<polyline fill=\"none\" stroke=\"" + std::string(color) +
                               "\" stroke-width=\"" + fmt("%g", width) + "\"" +
                               (dash[0] ? std::string(" stroke-dasharray=\"") + dash + "\"" : "") +
                               " points=\"";
            for (const auto& [n, v] : pts)
                line += fmt("%.1f", X(panel, n)) + "," + fmt("%.1f", Y(v, vmax)) + " ";
            return line + "\"/>\n";
        };
        std::vector<std::pair<double, double>> ideal, measured;
        for (const ScalePoint& p : s.points) {
            ideal.push_back({double(p.threads), panel == 0 ? double(p.threads) : 1.0});
            measured.push_back({double(p.threads), panel == 0 ? p.speedup : p.efficiency});
        }
        svg += polyline(ideal, "#999", 1.5, "6,4");
        svg += polyline(measured, "black", 2.5, "");
        if (panel == 0)
            svg += "<text x=\"" + fmt("%g", left[0] + 10) + "\" y=\"" + fmt("%g", top + 18) +
                   "\">measured (bold), ideal (dashed)</text>\n";
        if (panel == 1 && !s.points.empty()) {
            const auto& names = s.points.front().stage_efficiency;
            for (std::size_t i = 0; i < names.size(); ++i) {
                std::vector<std::pair<double, double>> pts;
                for (const ScalePoint& p : s.points)
                    for (const auto& [n, e] : p.stage_efficiency)
                        if (n == names[i].first) pts.push_back({double(p.threads), e});
                const char* c = palette[i % 10];
                svg += polyline(pts, c, 1.2, "");
                svg += "<text x=\"" + fmt("%g", left[1] + pw + 8) + "\" y=\"" +
                       fmt("%g", top + 12 + 14 * double(i)) + "\" fill=\"" + c + "\">" +
                       xml_text(names[i].first) + "</text>\n";
            }
        }
    }
    return svg + "</svg>\n";
}

}  // namespace foton::app
