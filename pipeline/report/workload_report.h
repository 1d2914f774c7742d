#pragma once
// The workload characterisation in report.json (`workload`), report.md and `texsim trace info`
// (docs/reports.md "workload").
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "pipeline/report/workload_stats.h"

namespace texsim {

void add_workload_json(nlohmann::ordered_json& j, const WorkloadStats& w);
// A short section: per frame (the first 16) and the total, then the total's histograms.
void workload_markdown(std::ostream& md, const WorkloadStats& w);
// One frame's (or the total's) figures as JSON, the same keys as report.json's frames[].
nlohmann::ordered_json workload_frame_json(const FrameWorkload& f);

// The characterisation of a fragment trace: the texture table's sizes, full RGBA8 mip chains,
// tiled4x4 layout (what `texsim run` uses by default).
WorkloadStats trace_workload(const std::string& path);

// `texsim trace info`'s workload lines for a fragment trace (a regular file: it is read a
// second time); prints nothing for a trace without records.
void print_trace_workload(const std::string& path, std::ostream& out);

// Share of line reuses at a distance below `lines` (a power of two: whole histogram bins) of
// all reuses; 0 without reuses.
double reuse_within(const FrameWorkload& f, uint64_t lines);

}  // namespace texsim
