#pragma once
// A number as the reports and study tables print it: printf's %g with `prec` significant
// digits (one definition for report.md, the ledger, the object-space section, the workload
// section and the studies' tables).
#include <cstdio>
#include <string>

namespace texsim {

inline std::string fmt(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

}  // namespace texsim
