#include "pipeline/report/provenance.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/sha1.h"
#include "blocks/base/shell_quote.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

InputDigest digest_file(const std::string& role, const std::string& path) {
  InputDigest d{role, path, "", 0};
  struct stat st {};
  // A stream (FIFO, '-') cannot be read twice: it is named without a digest.
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return d;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path, std::string("cannot read for its digest: ") + std::strerror(errno));
  Sha1 sha;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<size_t>(in.gcount());
    sha.append(buf.data(), n);
    d.bytes += n;
  }
  if (in.bad()) throw InputError(path, "read error while computing its digest");
  d.sha1 = sha.hex_digest();
  return d;
}

std::string command_line(int argc, const char* const* argv) {
  std::string line = "texsim";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string::npos;
    if (plain) {
      line += " " + a;
      continue;
    }
    line += ' ';
    line += shell_quote(a);  // argv holds no NUL
  }
  return line;
}

namespace {

using Json = nlohmann::ordered_json;

Json setup_json(const PipelineSetup& s) {
  Json j;
  j["fifo_depth"] = s.fifo_depth;
  j["layout"] = to_string(s.layout);
  j["cache"] = {{"size_bytes", s.cache.size_bytes},
                {"ways", s.cache.ways},
                {"line_bytes", s.cache.line_bytes},
                {"hit_latency", s.cache.hit_latency},
                {"texels_per_cycle", s.cache.texels_per_cycle},
                {"miss_queue", s.cache.miss_queue}};
  if (s.dram_kind == PipelineSetup::DramKind::Flat) {
    j["dram"] = {{"latency", s.dram.latency}, {"bytes_per_cycle", s.dram.bytes_per_cycle}};
  } else {
    static const char* const kMappings[] = {"row_bank_channel", "row_channel_bank", "bank_xor"};
    const BankedDram::Config& b = s.banked;
    j["dram"] = {{"model", "banked"},
                 {"channels", b.channels},
                 {"banks", b.banks},
                 {"row_bytes", b.row_bytes},
                 {"interleave_bytes", b.interleave_bytes},
                 {"mapping", kMappings[static_cast<int>(b.mapping)]},
                 {"page_policy", b.page_policy == BankedDram::PagePolicy::Open ? "open" : "closed"},
                 {"tCL", b.tCL},
                 {"tRCD", b.tRCD},
                 {"tRP", b.tRP},
                 {"tRAS", b.tRAS},
                 {"burst_length", b.burst_length},
                 {"bus_bytes", b.bus_bytes},
                 {"beats_per_cycle", b.beats_per_cycle}};
  }
  j["blend"] = {{"taps_per_cycle", s.blend.taps_per_cycle}};
  // The units and the L2 only when they differ from one unit on its own.
  if (s.units > 1) {
    j["units"] = s.units;
    j["unit_tile"] = s.unit_tile;
  }
  if (s.derivatives != QuadDerivatives::Own)
    j["derivatives"] = s.derivatives == QuadDerivatives::Coarse ? "coarse" : "fine";
  if (s.quad_merge) j["quad_merge"] = true;
  if (s.has_l2) {
    const L2Cache::Config& l = s.l2;
    j["l2"] = {{"size_bytes", l.size_bytes},
               {"ways", l.ways},
               {"line_bytes", l.line_bytes},
               {"slices", l.slices},
               {"ports", l.ports},
               {"hit_latency", l.hit_latency},
               {"mshrs", l.mshrs},
               {"prefetch", l.prefetch == L2Cache::Prefetch::NextLine ? "next_line" : "none"}};
  }
  return j;
}

Json energy_json(const EnergyTable& e) {
  Json j;
  for (int k = 0; k < kOpKinds; ++k) j["op"][std::string(kOpKindNames[k])] = e.op_pj[k];
  j["sram"] = Json::array();
  for (const EnergyTable::SramClass& c : e.sram)
    j["sram"].push_back({{"capacity_bytes", c.capacity_bytes}, {"pj", c.pj}});
  j["sram_access_bytes"] = e.sram_access_bytes;
  j["dram_byte_pj"] = e.dram_byte_pj;
  j["dram_activation_pj"] = e.dram_activation_pj;
  return j;
}

Json tech_json(const TechTable& t) {
  Json j;
  j["clock_mhz"] = t.clock_mhz;
  for (int k = 0; k < kOpKinds; ++k) {
    const std::string name(kOpKindNames[k]);
    j["latency"][name] = t.latency[k];
    j["area"][name] = t.area[k];
  }
  return j;
}

}  // namespace

nlohmann::ordered_json provenance_json(const Provenance& p) {
  Json j;
  j["texsim_version"] = p.version;
  j["command"] = p.command;
  j["inputs"] = Json::array();
  for (const InputDigest& d : p.inputs) {
    Json e = {{"role", d.role}, {"path", d.path}};
    if (!d.sha1.empty()) {
      e["sha1"] = d.sha1;
      e["bytes"] = d.bytes;
    }
    j["inputs"].push_back(e);
  }
  j["pipeline"] = setup_json(p.setup);
  j["tech"] = tech_json(p.tech);
  j["tech"]["energy"] = energy_json(p.energy);
  return j;
}

void provenance_markdown(std::ostream& md, const Provenance& p) {
  md << "\n## Provenance\n\n";
  md << "texsim " << p.version << ", command `" << p.command << "`.\n\n";
  md << "| input | path | SHA-1 | bytes |\n|---|---|---|---|\n";
  for (const InputDigest& d : p.inputs) {
    md << "| " << d.role << " | `" << d.path << "` | "
       << (d.sha1.empty() ? "(not a file)" : "`" + d.sha1 + "`") << " | "
       << (d.sha1.empty() ? std::string("–") : std::to_string(d.bytes)) << " |\n";
  }
  const PipelineSetup& s = p.setup;
  md << "\nResolved configuration (defaults included): FIFO depth " << s.fifo_depth
     << ", texel layout " << to_string(s.layout) << "; cache " << s.cache.size_bytes << " B, "
     << s.cache.ways << "-way, " << s.cache.line_bytes << " B lines, hit latency "
     << s.cache.hit_latency << ", " << s.cache.texels_per_cycle << " texels/cycle, miss queue "
     << s.cache.miss_queue << "; DRAM latency " << s.dram.latency << ", " << s.dram.bytes_per_cycle
     << " B/cycle; blend " << s.blend.taps_per_cycle << " taps/cycle; clock " << p.tech.clock_mhz
     << " MHz.\n\n";
  md << "| operator | latency (cycles) | area |\n|---|---|---|\n";
  for (int k = 0; k < kOpKinds; ++k) {
    md << "| " << kOpKindNames[k] << " | " << p.tech.latency[k] << " | " << p.tech.area[k]
       << " |\n";
  }
}

}  // namespace texsim
