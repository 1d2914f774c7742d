#pragma once
// A small VCD reader for tests: the header's timescale and variables (scope.name -> width),
// and each variable's value changes in time order.
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace vcd_reader {

struct Vcd {
  std::string timescale;
  std::string comment;
  std::map<std::string, int> width;  // "scope.name" -> bits
  // "scope.name" -> (time, value) for every change, $dumpvars included.
  std::map<std::string, std::vector<std::pair<uint64_t, uint64_t>>> changes;
  bool definitions_ended = false;

  // The variable's value at time t (after every change at t); 0 before its first change.
  uint64_t at(const std::string& var, uint64_t t) const {
    uint64_t v = 0;
    const auto it = changes.find(var);
    if (it == changes.end()) return v;
    for (const auto& [time, value] : it->second) {
      if (time > t) break;
      v = value;
    }
    return v;
  }
};

// The text between a keyword and its $end, whitespace-trimmed.
inline std::string until_end(std::istringstream& in) {
  std::string w, text;
  while (in >> w && w != "$end") text += (text.empty() ? "" : " ") + w;
  return text;
}

inline Vcd parse(const std::string& text) {
  Vcd v;
  std::istringstream in(text);
  std::vector<std::string> scope;
  std::map<std::string, std::string> by_id;
  uint64_t t = 0;
  std::string w;
  while (in >> w) {
    if (w == "$timescale") {
      v.timescale = until_end(in);
    } else if (w == "$comment") {
      v.comment = until_end(in);
    } else if (w == "$scope") {
      std::string kind, name;
      in >> kind >> name;
      until_end(in);
      scope.push_back(name);
    } else if (w == "$upscope") {
      until_end(in);
      if (!scope.empty()) scope.pop_back();
    } else if (w == "$var") {
      std::string type, id, name;
      int bits = 0;
      in >> type >> bits >> id >> name;
      until_end(in);
      // "stage.name"; under a unit's scope (texsim_pipeline.unitN.stage) "unitN.stage.name".
      std::string full;
      if (scope.size() >= 3) full.append(scope[scope.size() - 2]).append(".");
      if (!scope.empty()) full.append(scope.back()).append(".");
      full += name;
      v.width[full] = bits;
      by_id[id] = full;
    } else if (w == "$enddefinitions") {
      until_end(in);
      v.definitions_ended = true;
    } else if (w == "$dumpvars" || w == "$end") {
      continue;
    } else if (w[0] == '$') {
      until_end(in);
    } else if (w[0] == '#') {
      t = std::stoull(w.substr(1));
    } else if (w[0] == 'b') {
      std::string id;
      in >> id;
      v.changes[by_id[id]].emplace_back(t, std::stoull(w.substr(1), nullptr, 2));
    } else if (w[0] == '0' || w[0] == '1') {
      v.changes[by_id[w.substr(1)]].emplace_back(t, w[0] == '1' ? 1 : 0);
    }
  }
  return v;
}

}  // namespace vcd_reader
