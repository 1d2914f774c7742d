#pragma once
// What the studies that run whole scenes row by row share (study memory, study formats): a
// row's `--set` overrides over one base, and one row's run with its report read back.
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/app/run.h"

namespace texsim {

using StudySet = std::map<std::string, std::string>;  // key -> value, as for --set

// Every row starts from this, so the scenes' own [pipeline] choices (photo's morton layout and
// 32 KB L1) do not mix into the comparison: one unit, a 16 KB 4-way L1 of 64-byte lines,
// tiled texels, flat DRAM, row raster order.
const StudySet& study_base_set();
// `s` with the keys of `more` set (replacing any of s's).
StudySet with(StudySet s, const StudySet& more);
// "key=value" per entry, for RunOptions::overrides.
std::vector<std::string> overrides_of(const StudySet& set);

// Runs o.scene with o.overrides on one thread into `dir`, quietly, and hands its report to
// `read` (a report without a figure `read` expects is an InputError naming it); the directory
// is removed afterwards. `flags` are the run's options as the report's command line shows
// them (e.g. " --reference none").
void run_study_row(RunOptions o, const std::string& dir, const std::string& flags,
                   const std::function<void(const nlohmann::json&)>& read);

}  // namespace texsim
