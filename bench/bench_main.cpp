// Entry point of foton_bench_kernels: Google Benchmark's main plus the context a reader of
// the JSON needs to interpret the numbers (ISA, SIMD width, threads, library versions).
#include <benchmark/benchmark.h>
#include <embree3/rtcore_config.h>
#include <tbb/task_arena.h>
#include <nanoflann.hpp>

#include <sstream>
#include <string>

#include "kernels/point_kdtree.h"
#include "kernels/simd.h"

int main(int argc, char** argv) {
    benchmark::AddCustomContext("foton_simd_isa", foton::simd::Arch::name());
    benchmark::AddCustomContext("foton_simd_width", std::to_string(foton::simd::kWidth));
    benchmark::AddCustomContext("foton_kd_bucket", std::to_string(foton::kern::kKdBucket));
    benchmark::AddCustomContext("foton_threads",
                                std::to_string(tbb::this_task_arena::max_concurrency()));
    benchmark::AddCustomContext("embree_version", RTC_VERSION_STRING);
    std::ostringstream nf;
    nf << std::hex << NANOFLANN_VERSION;
    benchmark::AddCustomContext("nanoflann_version", nf.str());
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
