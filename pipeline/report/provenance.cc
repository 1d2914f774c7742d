#include "pipeline/report/provenance.h"

#include <OpenImageIO/hash.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include "blocks/base/input_error.h"
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
  OIIO::SHA1 sha;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<size_t>(in.gcount());
    sha.append(buf.data(), n);
    d.bytes += n;
  }
  if (in.bad()) throw InputError(path, "read error while computing its digest");
  d.sha1 = sha.digest();
  for (char& c : d.sha1) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
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
  j["dram"] = {{"latency", s.dram.latency}, {"bytes_per_cycle", s.dram.bytes_per_cycle}};
  j["blend"] = {{"taps_per_cycle", s.blend.taps_per_cycle}};
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
