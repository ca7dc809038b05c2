#pragma once
// What `foton scale` writes: a markdown table (stdout), the study as JSON (machine, build,
// scene, settings, every run, the summaries) and an SVG plot of speed-up and efficiency.
#include <string>

#include "engine/core/cpu_topology.h"
#include "scale_metrics.h"

namespace foton::app {

std::string scale_markdown(const ScaleStudy& study);
std::string scale_json(const ScaleStudy& study, const CpuTopology& machine);
std::string scale_svg(const ScaleStudy& study);

}  // namespace foton::app
