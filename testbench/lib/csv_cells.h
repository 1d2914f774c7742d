#pragma once
// Test-only: the cells of one CSV line as the studies write it (a quoted cell may hold commas;
// quotes are dropped).
#include <string>
#include <vector>

namespace texsim {

inline std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (const char ch : line) {
    if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

}  // namespace texsim
