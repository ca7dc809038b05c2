#pragma once
// `foton scale`: one scene rendered at several thread counts, repeated; the table on stdout,
// the study as JSON and its plot (scale_metrics.h, scale_report.h).
#include "scale_metrics.h"

namespace foton::app {

int run_scale(const ScaleArgs& args);

}  // namespace foton::app
