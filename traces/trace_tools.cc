#include "traces/trace_tools.h"

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "traces/draw_trace.h"
#include "traces/prefetch_reader.h"
#include "traces/trace_csv.h"

namespace texsim {

namespace {

std::string fmt_range(const TraceRange& r) {
  if (r.empty) return "-";
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.9g, %.9g]", r.lo, r.hi);
  return buf;
}

// Pixel coordinates are 32-bit integers: printed exactly (%g would give 4.29497e+09).
std::string fmt_pixels(const TraceRange& r) {
  if (r.empty) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "[%.0f, %.0f]", r.lo, r.hi);
  return buf;
}

}  // namespace

TraceSummary summarize_trace(const std::string& path, bool read_ahead) {
  TraceSummary s;
  TraceReader reader(path);
  s.header = reader.header();
  std::error_code ec;
  s.file_bytes = std::filesystem::file_size(path, ec);
  for (const TraceTexture& t : s.header.textures) s.per_texture[t.id] = 0;
  std::vector<Fragment> chunk;
  std::unique_ptr<PrefetchReader> ahead;
  if (read_ahead) ahead = std::make_unique<PrefetchReader>(reader);
  // The per-texture map never grows here: the reader has already checked every id is in it.
  while ((ahead ? ahead->next_chunk(chunk) : reader.next_chunk(chunk)) > 0) {
    for (const Fragment& f : chunk) {
      if (s.records == 0) {
        s.frame_min = s.frame_max = f.frame;
        s.prim_min = s.prim_max = f.prim;
      }
      s.frame_min = std::min(s.frame_min, f.frame);
      s.frame_max = std::max(s.frame_max, f.frame);
      s.prim_min = std::min(s.prim_min, f.prim);
      s.prim_max = std::max(s.prim_max, f.prim);
      auto it = s.frames.find(f.frame);
      if (it != s.frames.end()) {
        ++it->second;
      } else if (s.frames.size() < TraceSummary::kMaxFrames) {
        s.frames.emplace(f.frame, 1);
      } else {
        s.frames_overflow = true;
      }
      ++s.per_texture[f.tex];
      s.x.add(f.x);
      s.y.add(f.y);
      s.u.add(f.u);
      s.v.add(f.v);
      s.dudx.add(f.dudx);
      s.dvdx.add(f.dvdx);
      s.dudy.add(f.dudy);
      s.dvdy.add(f.dvdy);
      if (s.header.has_lod_bias) s.lod_bias.add(f.lod_bias);
      ++s.records;
    }
  }
  ahead.reset();  // its thread stopped: the reader is ours again
  s.chunks = reader.chunks_read();
  return s;
}

int trace_info(const std::string& path, std::ostream& out) {
  if (is_draw_trace(path)) return draw_trace_info(path, out);
  const TraceSummary s = summarize_trace(path);
  const TraceHeader& h = s.header;
  const bool csv = h.encoding == TraceEncoding::Csv;
  out << "trace:      " << path << " (" << s.file_bytes << " bytes)\n";
  out << "format:     " << (csv ? "CSV" : "binary") << ", version " << h.version;
  if (!csv)
    out << ", record " << h.record_size << " bytes, up to " << h.records_per_chunk
        << " records/chunk";
  out << "\n";
  out << (csv ? "columns:   " : "fields:    ");
  for (const TraceField& f : h.fields) {
    bool known = false;
    for (const TraceFieldSpec& spec : trace_field_specs()) known = known || spec.name == f.name;
    out << " " << f.name;
    if (csv) {
      if (!known) out << "(skipped)";
    } else {
      out << ":" << to_string(f.type) << "@" << f.offset << (known ? "" : "(skipped)");
    }
  }
  out << "\nlod_bias:   " << (h.has_lod_bias ? "present" : "absent") << "\n";
  if (h.has_view) out << "view:       present (view_x, view_y, view_z)\n";
  if (h.has_ops) out << "operations: present (version-4 operation fields)\n";
  out << "textures:   " << h.textures.size() << "\n";
  for (const TraceTexture& t : h.textures) {
    out << "  id " << t.id << "  " << t.name << "  " << t.width << "x" << t.height << "  "
        << (t.source.empty() ? "(no source)" : t.source)
        << (t.storage.empty() ? "" : "  stored " + t.storage) << "  fragments "
        << s.per_texture.at(t.id) << "\n";
  }
  if (!h.samplers.empty()) {
    // The sampler table (version 5), one entry a line as its CSV directive says it.
    out << "samplers:   " << h.samplers.size() << " (a record's sampler id; 0 = its material's)\n";
    for (size_t k = 0; k < h.samplers.size(); ++k) {
      const std::string d = csv_sampler_directive(h.samplers[k]);
      out << "  id " << k + 1 << "  " << d.substr(sizeof "# sampler " - 1) << "\n";
    }
  }
  out << "records:    " << s.records << " in " << s.chunks << " chunks\n";
  if (s.records == 0) return 0;
  out << "frames:     " << (s.frames_overflow ? "more than " : "") << s.frames.size()
      << " distinct, " << s.frame_min << ".." << s.frame_max << "\n";
  size_t listed = 0;
  for (const auto& [frame, n] : s.frames) {
    if (listed++ == 16) {
      out << "  ...\n";
      break;
    }
    out << "  frame " << frame << ": " << n << " fragments\n";
  }
  out << "primitives: " << s.prim_min << ".." << s.prim_max << "\n";
  out << "pixel bbox: x " << fmt_pixels(s.x) << ", y " << fmt_pixels(s.y) << "\n";
  out << "u:          " << fmt_range(s.u) << "\n";
  out << "v:          " << fmt_range(s.v) << "\n";
  out << "du/dx:      " << fmt_range(s.dudx) << "\n";
  out << "dv/dx:      " << fmt_range(s.dvdx) << "\n";
  out << "du/dy:      " << fmt_range(s.dudy) << "\n";
  out << "dv/dy:      " << fmt_range(s.dvdy) << "\n";
  if (h.has_lod_bias) out << "lod_bias:   " << fmt_range(s.lod_bias) << "\n";
  return 0;
}

void trace_convert(const std::string& in, const std::string& out) {
  TraceReader reader(in);
  TraceHeader h;
  h.has_lod_bias = reader.header().has_lod_bias;
  h.has_view = reader.header().has_view;
  h.has_ops = reader.header().has_ops;
  h.textures = reader.header().textures;
  h.samplers = reader.header().samplers;
  write_trace(out, h, [&](auto& writer) {
    std::vector<Fragment> chunk;
    while (reader.next_chunk(chunk) > 0) {
      for (const Fragment& f : chunk) writer.write(f);
    }
  });
}

}  // namespace texsim
