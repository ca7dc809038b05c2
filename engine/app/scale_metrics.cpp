#include "scale_metrics.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/params.h"

namespace foton::app {

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::vector<int> thread_counts(const std::string& spec, int hardware) {
    std::vector<int> out;
    if (spec.empty() || spec == "all") {
        for (int n = 1; n < hardware; n *= 2) out.push_back(n);
        out.push_back(hardware);
        return out;
    }
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const int n = int(integer_or_fail(item, 1, 4096, "--threads", 0, "a thread count"));
        if (!out.empty() && n <= out.back())
            throw InputError("--threads", 0, "thread counts must increase: '" + spec + "'");
        out.push_back(n);
    }
    if (out.empty()) throw InputError("--threads", 0, "no thread count in '" + spec + "'");
    return out;
}

void summarise(ScaleStudy& study) {
    study.points.clear();
    const bool throughput = study.args.time.has_value();
    const bool weak = study.args.weak;
    std::map<int, std::vector<const ScaleRun*>> by;
    for (const ScaleRun& r : study.runs) by[r.threads].push_back(&r);
    for (const auto& [n, runs] : by) {
        ScalePoint p;
        p.threads = n;
        std::vector<double> wall, rate;
        for (const ScaleRun* r : runs) {
            wall.push_back(r->wall_seconds);
            rate.push_back(r->wall_seconds > 0 ? double(r->samples) / r->wall_seconds : 0.0);
        }
        p.wall_median = median(wall);
        p.wall_min = *std::min_element(wall.begin(), wall.end());
        p.wall_max = *std::max_element(wall.begin(), wall.end());
        p.rate = median(rate);
        std::map<std::string, std::vector<double>> stages;
        std::vector<std::string> order;
        for (const ScaleRun* r : runs)
            for (const auto& [name, ts] : r->stage_thread_seconds) {
                if (!stages.count(name)) order.push_back(name);
                stages[name].push_back(ts);
            }
        for (const std::string& name : order)
            p.stage_thread_seconds.push_back({name, median(stages[name])});
        study.points.push_back(p);
    }
    if (study.points.empty()) return;
    const ScalePoint base = study.points.front();
    const double t0 = base.threads;
    for (ScalePoint& p : study.points) {
        const double n = p.threads;
        if (throughput)
            p.speedup = base.rate > 0 ? t0 * p.rate / base.rate : 0.0;
        else if (weak)
            p.speedup = p.wall_median > 0 ? n * base.wall_median / p.wall_median : 0.0;
        else
            p.speedup = p.wall_median > 0 ? t0 * base.wall_median / p.wall_median : 0.0;
        p.efficiency = p.speedup / n;
        p.karp_flatt = n > 1 && p.speedup > 0 ? (1.0 / p.speedup - 1.0 / n) / (1.0 - 1.0 / n) : 0.0;
        // Per stage, thread-seconds for the same work: ideally constant (strong), or growing
        // with the work (weak, where the work is n / t0 times the first count's).
        for (const auto& [name, ts] : p.stage_thread_seconds) {
            double ts0 = 0.0;
            for (const auto& [bn, bts] : base.stage_thread_seconds)
                if (bn == name) ts0 = bts;
            const double work = weak ? n / t0 : 1.0;
            double eff = ts > 0.0 && ts0 > 0.0 ? ts0 * work / ts : 0.0;
            if (throughput) {
                // With --time the runs did different work: compare per sample.
                const auto per = [&](const ScalePoint& q, double t) {
                    const double samples = q.rate * q.wall_median;
                    return samples > 0 ? t / samples : 0.0;
                };
                const double a = per(base, ts0), b = per(p, ts);
                eff = a > 0 && b > 0 ? a / b : 0.0;
            }
            p.stage_efficiency.push_back({name, eff});
        }
    }
    // The stage that scales worst at the largest count (among those worth 1 % of the time).
    const ScalePoint& last = study.points.back();
    double total = 0.0, worst = 2.0;
    for (const auto& [name, ts] : last.stage_thread_seconds) total += ts;
    study.worst_stage.clear();
    for (std::size_t i = 0; i < last.stage_efficiency.size(); ++i)
        if (last.stage_thread_seconds[i].second >= 0.01 * total &&
            last.stage_efficiency[i].second < worst) {
            worst = last.stage_efficiency[i].second;
            study.worst_stage = last.stage_efficiency[i].first;
        }
}

}  // namespace foton::app
