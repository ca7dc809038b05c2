#pragma once
// The machine's processors as Linux describes them (/sys/devices/system): sockets, physical
// cores, hardware threads per core, NUMA nodes, and the CPUs this process may run on, in
// the order a scaling study fills them.
#include <string>
#include <vector>

namespace foton {

struct CpuTopology {
    std::string model = "unknown";  // /proc/cpuinfo's model name
    int logical = 1;                // online logical CPUs (hardware threads)
    int cores = 1;                  // physical cores
    int sockets = 1;
    int threads_per_core = 1;  // SMT
    int numa_nodes = 1;
    // The CPUs of the process's affinity mask: one hardware thread of every physical core
    // first (socket by socket, so the first threads share a socket and its NUMA node), then
    // the cores' second hardware threads, and so on. Thread i of a pinned run goes to
    // cpu_order[i]: 4 threads on a 2-socket machine with 8-core sockets use 4 cores of
    // socket 0, not 2 SMT pairs.
    std::vector<int> cpu_order;
};

// Read once per call (a few small files); falls back to hardware_concurrency() and one socket
// where /sys is missing.
CpuTopology cpu_topology();

}  // namespace foton
