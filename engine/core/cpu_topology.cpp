#include "cpu_topology.h"

#include <sched.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <tuple>
#include <utility>

namespace foton {

namespace {

int read_int(const std::string& path, int fallback) {
    std::ifstream in(path);
    int v;
    return in >> v ? v : fallback;
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                const auto start = line.find_first_not_of(' ', colon + 1);
                if (start != std::string::npos) return line.substr(start);
            }
        }
    return "unknown";
}

}  // namespace

CpuTopology cpu_topology() {
    namespace fs = std::filesystem;
    CpuTopology t;
    t.model = cpu_model();
    std::vector<int> allowed;
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(0, sizeof mask, &mask) == 0) {
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &mask)) allowed.push_back(c);
    }
    if (allowed.empty())
        for (int c = 0; c < int(std::max(1u, std::thread::hardware_concurrency())); ++c)
            allowed.push_back(c);

    // (socket, core) of each allowed CPU; its rank among the CPUs of its core is its SMT index.
    struct Cpu {
        int id, socket, core, smt = 0;
    };
    std::vector<Cpu> cpus;
    const std::string base = "/sys/devices/system/cpu/cpu";
    for (int c : allowed) {
        const std::string topo = base + std::to_string(c) + "/topology/";
        cpus.push_back(
            {c, read_int(topo + "physical_package_id", 0), read_int(topo + "core_id", c)});
    }
    std::sort(cpus.begin(), cpus.end(), [](const Cpu& a, const Cpu& b) {
        return std::tie(a.socket, a.core, a.id) < std::tie(b.socket, b.core, b.id);
    });
    std::set<std::pair<int, int>> cores;
    std::set<int> sockets;
    int max_smt = 0;
    for (std::size_t i = 0; i < cpus.size(); ++i) {
        if (i > 0 && cpus[i].socket == cpus[i - 1].socket && cpus[i].core == cpus[i - 1].core)
            cpus[i].smt = cpus[i - 1].smt + 1;
        max_smt = std::max(max_smt, cpus[i].smt);
        cores.insert({cpus[i].socket, cpus[i].core});
        sockets.insert(cpus[i].socket);
    }
    std::stable_sort(cpus.begin(), cpus.end(),
                     [](const Cpu& a, const Cpu& b) { return a.smt < b.smt; });
    for (const Cpu& c : cpus) t.cpu_order.push_back(c.id);
    t.logical = int(cpus.size());
    t.cores = int(cores.size());
    t.sockets = int(sockets.size());
    t.threads_per_core = max_smt + 1;
    std::error_code ec;
    int nodes = 0;
    for (const auto& e : fs::directory_iterator("/sys/devices/system/node", ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("node", 0) == 0 && name.size() > 4 &&
            std::all_of(name.begin() + 4, name.end(),
                        [](char ch) { return ch >= '0' && ch <= '9'; }))
            ++nodes;
    }
    t.numa_nodes = std::max(1, nodes);
    return t;
}

}  // namespace foton
