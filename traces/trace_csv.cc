#include "traces/trace_csv.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"

namespace texsim {

namespace {

constexpr size_t kReadBufferBytes = 1u << 20;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Trims spaces/tabs; `col` (0-based offset of s in the line) moves with the left edge.
std::string_view trim(std::string_view s, size_t& col) {
  size_t b = 0;
  while (b < s.size() && is_space(s[b])) ++b;
  size_t e = s.size();
  while (e > b && is_space(s[e - 1])) --e;
  col += b;
  return s.substr(b, e - b);
}

std::string shown(std::string_view s) {
  constexpr size_t kMax = 40;
  std::string out;
  out.reserve(kMax + 5);
  out += '\'';
  out.append(s.data(), std::min(s.size(), kMax));
  out.append(s.size() > kMax ? "...'" : "'");
  return out;
}

// Parses a whole token as an unsigned 32-bit integer; returns an error text or "".
std::string parse_u32(std::string_view s, uint32_t& out) {
  if (s.empty()) return "empty value where an unsigned integer is expected";
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec == std::errc::result_out_of_range) return shown(s) + " is out of range for u32";
  if (ec != std::errc() || ptr != s.data() + s.size())
    return shown(s) + " is not an unsigned integer";
  return {};
}

template <class T>
std::string parse_float(std::string_view s, T& out, std::string_view field) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return "empty value where a number is expected";
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec == std::errc::result_out_of_range) {
    return shown(s) + " is out of range for " + (sizeof(T) == 8 ? "f64" : "f32");
  }
  if (ec != std::errc() || ptr != s.data() + s.size()) return shown(s) + " is not a number";
  if (!std::isfinite(out)) {
    return "field '" + std::string(field) + "' is " + (std::isnan(out) ? "NaN" : "infinite");
  }
  return {};
}

// Parses a whole token as an integer in [lo, hi]; returns an error text or "".
std::string parse_int(std::string_view s, int64_t lo, int64_t hi, int64_t& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return "empty value where an integer is expected";
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec != std::errc() || ptr != s.data() + s.size()) return shown(s) + " is not an integer";
  if (out < lo || out > hi)
    return shown(s) + " is outside " + std::to_string(lo) + ".." + std::to_string(hi);
  return {};
}

// Column k of the version-4 operation fields (kOpFieldNames order) into f.
std::string parse_operation_field(size_t k, std::string_view val, std::string_view fname,
                                  Fragment& f) {
  int64_t i = 0;
  std::string err;
  switch (k) {
    case 0:
      return parse_float(val, f.w, fname);
    case 1:
      return parse_float(val, f.dwdx, fname);
    case 2:
      return parse_float(val, f.dwdy, fname);
    case 3:
      return parse_float(val, f.layer, fname);
    case 4:
      return parse_float(val, f.lod, fname);
    case 5:
      return parse_float(val, f.compare_ref, fname);
    case 6:
      err = parse_int(val, 0, 65535, i);
      f.sampler = static_cast<uint16_t>(i);
      return err;
    case 7:
    case 8:
      err = parse_int(val, 0, 255, i);
      (k == 7 ? f.op : f.gather_component) = static_cast<uint8_t>(i);
      return err;
    default:
      err = parse_int(val, -128, 127, i);
      (k == 9 ? f.offset_u : (k == 10 ? f.offset_v : f.offset_w)) = static_cast<int8_t>(i);
      return err;
  }
}

}  // namespace

std::string csv_quote_token(std::string_view s) {
  const bool plain = !s.empty() && std::none_of(s.begin(), s.end(), [](char c) {
    return c == ' ' || c == '\t' || c == '"' || c == '\\';
  });
  if (plain) return std::string(s);
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  q += '"';
  return q;
}

// ---------------------------------------------------------------------------------------------
// Reader

TraceCsvReader::TraceCsvReader(const std::string& path, uint32_t records_per_chunk)
    : path_(path), records_per_chunk_(std::max<uint32_t>(1, records_per_chunk)) {
  file_ = open_trace_input(path_);
  buf_.resize(kReadBufferBytes);
  header_.version = kTraceVersion;
  header_.encoding = TraceEncoding::Csv;
  header_.records_per_chunk = records_per_chunk_;
  std::string_view line;
  while (next_line(line)) {
    size_t col = 0;
    const std::string_view t = trim(line, col);
    if (t.empty()) continue;
    if (t.front() == '#') {
      parse_directive(line);
      continue;
    }
    parse_columns(line);
    ids_ = TextureIdSet(header_.textures);
    return;
  }
  throw InputError(path_, "no column header line (expected a line naming the columns, e.g. " +
                              std::string("frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy)"));
}

TraceCsvReader::~TraceCsvReader() = default;

void TraceCsvReader::fail(size_t column, const std::string& what) const {
  throw InputError(path_ + ":" + std::to_string(line_no_) + ":" + std::to_string(column), what);
}

bool TraceCsvReader::next_line(std::string_view& line) {
  long_line_.clear();
  for (;;) {
    const char* start = buf_.data() + buf_begin_;
    const size_t avail = buf_end_ - buf_begin_;
    const void* nl = std::memchr(start, '\n', avail);
    if (nl != nullptr) {
      const auto len = static_cast<size_t>(static_cast<const char*>(nl) - start);
      ++line_no_;
      if (long_line_.size() + len > kCsvMaxLineBytes) {
        fail(1, "line longer than " + std::to_string(kCsvMaxLineBytes) + " bytes");
      }
      if (long_line_.empty()) {
        line = std::string_view(start, len);
      } else {
        long_line_.append(start, len);
        line = long_line_;
      }
      buf_begin_ += len + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      return true;
    }
    // No newline in the buffer: keep the partial line and refill.
    if (long_line_.size() + avail > kCsvMaxLineBytes) {
      ++line_no_;
      fail(1, "line longer than " + std::to_string(kCsvMaxLineBytes) + " bytes");
    }
    long_line_.append(start, avail);
    buf_begin_ = buf_end_ = 0;
    if (!eof_) {
      const size_t n = std::fread(buf_.data(), 1, buf_.size(), file_.get());
      if (n == 0) {
        if (std::ferror(file_.get())) {
          throw InputError(path_, std::string("read error: ") + std::strerror(errno));
        }
        eof_ = true;
      }
      buf_end_ = n;
      continue;
    }
    if (long_line_.empty()) return false;
    ++line_no_;  // last line without a newline
    line = long_line_;
    if (line.back() == '\r') line.remove_suffix(1);
    return true;
  }
}

void TraceCsvReader::parse_directive(std::string_view line) {
  // "# texture <id> <name> <source> <width> <height> [<storage>]" or "# sampler <name>
  // [key=value ...]"; any other '#' line is a comment. The storage (version 3) is optional:
  // without it, the texture is as loaded.
  size_t i = line.find('#') + 1;
  while (i < line.size() && is_space(line[i])) ++i;
  for (const std::string_view word : {"texture", "sampler"}) {
    if (line.substr(i, word.size()) != word) continue;
    const size_t after = i + word.size();
    if (after < line.size() && !is_space(line[after])) return;  // e.g. "# textures are ..."
    if (!column_field_.empty()) {
      fail(i + 1, std::string(word) +
                      " directive after the column header line (directives must come first)");
    }
    const std::vector<Token> tokens = directive_tokens(line, after);
    if (word == "texture") {
      parse_texture_directive(tokens, i);
    } else {
      parse_sampler_directive(tokens, i);
    }
    return;
  }
}

std::vector<TraceCsvReader::Token> TraceCsvReader::directive_tokens(std::string_view line,
                                                                    size_t after) const {
  std::vector<Token> tokens;
  size_t p = after;
  for (;;) {
    while (p < line.size() && is_space(line[p])) ++p;
    if (p >= line.size()) break;
    Token tok{{}, p + 1};
    if (line[p] == '"') {
      ++p;
      bool closed = false;
      while (p < line.size()) {
        const char c = line[p++];
        if (c == '"') {
          closed = true;
          break;
        }
        if (c == '\\' && p < line.size()) {
          tok.text += line[p++];
        } else {
          tok.text += c;
        }
      }
      if (!closed) fail(tok.column, "unterminated quoted value");
      if (p < line.size() && !is_space(line[p]))
        fail(p + 1, "expected a space after the closing quote");
    } else {
      while (p < line.size() && !is_space(line[p])) tok.text += line[p++];
    }
    tokens.push_back(std::move(tok));
  }
  return tokens;
}

void TraceCsvReader::parse_texture_directive(const std::vector<Token>& tokens, size_t i) {
  if (tokens.size() != 5 && tokens.size() != 6) {
    fail(i + 1,
         "texture directive needs 5 or 6 values <id> <name> <source> <width> <height> "
         "[<storage>], found " +
             std::to_string(tokens.size()));
  }
  TraceTexture t{};
  std::string err;
  if (!(err = parse_u32(tokens[0].text, t.id)).empty())
    fail(tokens[0].column, "texture id: " + err);
  t.name = tokens[1].text;
  t.source = tokens[2].text;
  if (!(err = parse_u32(tokens[3].text, t.width)).empty())
    fail(tokens[3].column, "texture width: " + err);
  if (!(err = parse_u32(tokens[4].text, t.height)).empty())
    fail(tokens[4].column, "texture height: " + err);
  if (tokens.size() == 6) t.storage = tokens[5].text;
  if (header_.find_texture(t.id) != nullptr) {
    fail(tokens[0].column,
         "texture id " + std::to_string(t.id) + " appears twice in the texture table");
  }
  if (header_.textures.size() >= kTraceMaxTextures) {
    fail(i + 1, "more than " + std::to_string(kTraceMaxTextures) + " textures");
  }
  try {
    validate_textures({t}, path_);
  } catch (const InputError& e) {
    // Re-anchor the message at this line; the entry index of a one-element check means nothing.
    const std::string msg = e.what();
    const size_t colon = msg.find("): ");
    fail(i + 1, "texture " + std::to_string(t.id) + ": " +
                    (colon == std::string::npos ? msg : msg.substr(colon + 3)));
  }
  header_.textures.push_back(std::move(t));
}

namespace {

// The code of `value` in names (as TraceSampler stores it), or an error text.
template <size_t N>
std::string sampler_code(std::string_view key, std::string_view value,
                         const std::string_view (&names)[N], uint8_t& out) {
  for (size_t k = 0; k < N; ++k) {
    if (names[k] == value) {
      out = static_cast<uint8_t>(k);
      return {};
    }
  }
  std::string list;
  for (size_t k = 0; k < N; ++k) list += (k ? ", " : "") + std::string(names[k]);
  return std::string(key) + ": " + shown(value) + " is not one of " + list;
}

// One `key=value` of a sampler directive into s; an error text or "".
std::string sampler_key(std::string_view key, std::string_view value, TraceSampler& s) {
  if (key == "mode") return sampler_code(key, value, kTraceFilterNames, s.mode);
  if (key == "address_u") return sampler_code(key, value, kTraceAddressNames, s.address_u);
  if (key == "address_v") return sampler_code(key, value, kTraceAddressNames, s.address_v);
  if (key == "address_w") return sampler_code(key, value, kTraceAddressNames, s.address_w);
  if (key == "compare") return sampler_code(key, value, kTraceCompareNames, s.compare);
  if (key == "reduction") return sampler_code(key, value, kTraceReductionNames, s.reduction);
  if (key == "aniso") return sampler_code(key, value, kTraceAnisoNames, s.aniso);
  if (key == "border") {
    size_t start = 0;
    for (int c = 0; c < 4; ++c) {
      const size_t next = value.find(',', start);
      if ((c < 3) == (next == std::string_view::npos))
        return "border: expected four numbers r,g,b,a";
      const size_t comma = c < 3 ? next : value.size();
      if (std::string e = parse_float(value.substr(start, comma - start), s.border[c], "border");
          !e.empty())
        return "border: " + e;
      start = comma + 1;
    }
    return {};
  }
  if (key == "border_int")
    return "border_int: an integer border colour needs an integer texture format, which texsim "
           "has not";
  if (key == "lod_bias") return parse_float(value, s.lod_bias, key);
  if (key == "min_lod") return parse_float(value, s.min_lod, key);
  if (key == "max_lod") return parse_float(value, s.max_lod, key);
  const std::pair<std::string_view, std::pair<uint8_t*, int64_t>> ints[] = {
      {"max_aniso", {&s.max_aniso, 16}},
      {"unnormalized", {&s.unnormalized, 1}},
      {"seamless", {&s.seamless, 1}},
      {"sub_texel_bits", {&s.sub_texel_bits, 16}},
      {"mipmap_bits", {&s.mipmap_bits, 16}}};
  for (const auto& [name, slot] : ints) {
    if (key != name) continue;
    int64_t v = 0;
    const int64_t lo = slot.second == 1 ? 0 : 1;
    if (std::string e = parse_int(value, lo, slot.second, v); !e.empty())
      return std::string(key) + ": " + e;
    *slot.first = static_cast<uint8_t>(v);
    return {};
  }
  return "unknown sampler key " + shown(key) +
         " (mode, address_u, address_v, address_w, border, compare, reduction, aniso, "
         "max_aniso, lod_bias, min_lod, max_lod, unnormalized, seamless, sub_texel_bits, "
         "mipmap_bits)";
}

}  // namespace

void TraceCsvReader::parse_sampler_directive(const std::vector<Token>& tokens, size_t i) {
  // "# sampler <name> [key=value ...]": the next entry of the sampler table (ids from 1, in
  // the order of the directives); a key left out keeps the scene's default.
  if (tokens.empty()) fail(i + 1, "sampler directive needs a name, then key=value pairs");
  if (header_.samplers.size() >= kTraceMaxSamplers)
    fail(i + 1, "more than " + std::to_string(kTraceMaxSamplers) + " samplers");
  TraceSampler s;
  s.name = tokens[0].text;
  std::vector<std::string_view> seen;
  for (size_t k = 1; k < tokens.size(); ++k) {
    const std::string_view t = tokens[k].text;
    const size_t eq = t.find('=');
    if (eq == std::string_view::npos || eq == 0)
      fail(tokens[k].column, "expected key=value, found " + shown(t));
    const std::string_view key = t.substr(0, eq);
    if (std::find(seen.begin(), seen.end(), key) != seen.end())
      fail(tokens[k].column, "sampler key '" + std::string(key) + "' appears twice");
    seen.push_back(key);
    if (const std::string e = sampler_key(key, t.substr(eq + 1), s); !e.empty())
      fail(tokens[k].column, "sampler '" + s.name + "': " + e);
  }
  const std::string id = std::to_string(header_.samplers.size() + 1);
  if (const std::string e = check_sampler(s); !e.empty())
    fail(tokens[0].column, "sampler table entry " + id + ": " + e);
  if (!sampler_names_.insert(s.name).second)
    fail(tokens[0].column, "sampler table entry " + id + ": the name '" + s.name +
                               "' appears twice in the sampler table");
  header_.samplers.push_back(std::move(s));
}

std::string csv_sampler_directive(const TraceSampler& s) {
  std::string d = "# sampler " + csv_quote_token(s.name);
  const auto num = [&d](std::string_view key, auto v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    d.append(" ").append(key).append("=").append(buf, r.ptr);
  };
  const auto name = [&d](std::string_view key, std::string_view v) {
    d.append(" ").append(key).append("=").append(v);
  };
  name("mode", kTraceFilterNames[s.mode]);
  name("address_u", kTraceAddressNames[s.address_u]);
  name("address_v", kTraceAddressNames[s.address_v]);
  name("address_w", kTraceAddressNames[s.address_w]);
  d += " border=";
  for (int c = 0; c < 4; ++c) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, s.border[c]);
    d.append(c ? "," : "").append(buf, r.ptr);
  }
  name("compare", kTraceCompareNames[s.compare]);
  name("reduction", kTraceReductionNames[s.reduction]);
  name("aniso", kTraceAnisoNames[s.aniso]);
  num("max_aniso", int{s.max_aniso});
  num("lod_bias", s.lod_bias);
  num("min_lod", s.min_lod);
  num("max_lod", s.max_lod);
  num("unnormalized", int{s.unnormalized});
  num("seamless", int{s.seamless});
  num("sub_texel_bits", int{s.sub_texel_bits});
  num("mipmap_bits", int{s.mipmap_bits});
  return d;
}

void TraceCsvReader::parse_columns(std::string_view line) {
  const auto& specs = trace_field_specs();
  std::vector<bool> seen(specs.size(), false);
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    const size_t end = comma == std::string_view::npos ? line.size() : comma;
    size_t col = start;
    const std::string_view name = trim(line.substr(start, end - start), col);
    if (name.empty()) fail(col + 1, "empty column name");
    int idx = -1;
    for (size_t s = 0; s < specs.size(); ++s) {
      if (specs[s].name == name) idx = static_cast<int>(s);
    }
    for (const TraceField& f : header_.fields) {
      if (f.name == name) fail(col + 1, "column '" + std::string(name) + "' appears twice");
    }
    const TraceType type = idx >= 0 ? specs[static_cast<size_t>(idx)].type : TraceType::F64;
    header_.fields.push_back(
        {std::string(name), type, static_cast<uint32_t>(column_field_.size())});
    column_field_.push_back(idx);
    if (idx >= 0) seen[static_cast<size_t>(idx)] = true;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  for (size_t s = 0; s < specs.size(); ++s) {
    if (specs[s].required && !seen[s]) {
      fail(1, "missing required column '" + std::string(specs[s].name) + "'");
    }
  }
  header_.has_lod_bias = seen[11];
  const int views = seen[12] + seen[13] + seen[14];
  if (views != 0 && views != 3) {
    fail(1, "the view vector needs all three columns view_x, view_y, view_z (" +
                std::to_string(views) + " present)");
  }
  header_.has_view = views == 3;
  for (size_t k = kFirstOpField; k < specs.size(); ++k)
    if (seen[k]) header_.op_fields |= 1u << (k - kFirstOpField);
  header_.has_ops = header_.op_fields != 0;
  header_.version = written_version(header_.has_view, header_.textures, header_.has_ops,
                                    !header_.samplers.empty());
}

void TraceCsvReader::parse_record(std::string_view line, Fragment& f) {
  f = Fragment{};
  size_t start = 0;
  size_t column = 0;
  size_t tex_col = 1;
  for (;;) {
    const size_t comma = line.find(',', start);
    const size_t end = comma == std::string_view::npos ? line.size() : comma;
    if (column >= column_field_.size()) {
      // Count them all for the message.
      size_t n = column_field_.size() + 1;
      for (size_t q = end; q < line.size(); ++q) n += line[q] == ',' ? 1 : 0;
      fail(start + 1, "expected " + std::to_string(column_field_.size()) + " columns, found " +
                          std::to_string(n));
    }
    size_t col = start;
    const std::string_view val = trim(line.substr(start, end - start), col);
    const int idx = column_field_[column];
    std::string err;
    if (idx >= 0) {
      const std::string_view fname = trace_field_specs()[static_cast<size_t>(idx)].name;
      switch (idx) {
        case 0:
          err = parse_u32(val, f.frame);
          break;
        case 1:
          err = parse_u32(val, f.prim);
          break;
        case 2:
          err = parse_u32(val, f.x);
          break;
        case 3:
          err = parse_u32(val, f.y);
          break;
        case 4:
          err = parse_u32(val, f.tex);
          tex_col = col + 1;
          break;
        case 5:
          err = parse_float(val, f.u, fname);
          break;
        case 6:
          err = parse_float(val, f.v, fname);
          break;
        case 7:
          err = parse_float(val, f.dudx, fname);
          break;
        case 8:
          err = parse_float(val, f.dvdx, fname);
          break;
        case 9:
          err = parse_float(val, f.dudy, fname);
          break;
        case 10:
          err = parse_float(val, f.dvdy, fname);
          break;
        case 11:
          err = parse_float(val, f.lod_bias, fname);
          break;
        case 12:
          err = parse_float(val, f.view_x, fname);
          break;
        case 13:
          err = parse_float(val, f.view_y, fname);
          break;
        case 14:
          err = parse_float(val, f.view_z, fname);
          break;
        default:
          err = parse_operation_field(static_cast<size_t>(idx) - kFirstOpField, val, fname, f);
          break;
      }
      if (!err.empty()) fail(col + 1, "column '" + std::string(fname) + "': " + err);
    }
    ++column;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (column != column_field_.size()) {
    fail(line.size() + 1, "expected " + std::to_string(column_field_.size()) + " columns, found " +
                              std::to_string(column));
  }
  if (!ids_.contains(f.tex)) {
    fail(tex_col, "texture id " + std::to_string(f.tex) + " is not in the texture table");
  }
  if (header_.has_view && !f.has_view())
    fail(1, "the view vector (view_x, view_y, view_z) is zero");
  if (header_.has_ops) {
    const std::string bad = check_operation(f, header_.op_fields);
    if (!bad.empty()) fail(1, bad);
  }
}

size_t TraceCsvReader::next_chunk(std::vector<Fragment>& out) {
  out.clear();
  std::string_view line;
  while (out.size() < records_per_chunk_ && next_line(line)) {
    size_t col = 0;
    const std::string_view t = trim(line, col);
    if (t.empty()) continue;
    if (t.front() == '#') {
      parse_directive(line);  // a texture directive here is an error; comments pass
      continue;
    }
    out.emplace_back();
    parse_record(line, out.back());
  }
  return out.size();
}

// ---------------------------------------------------------------------------------------------
// Writer

TraceCsvWriter::TraceCsvWriter(const std::string& path, const TraceHeader& header)
    : path_(path),
      temp_(temp_path_for(path)),
      has_lod_bias_(header.has_lod_bias),
      has_view_(header.has_view),
      has_ops_(header.has_ops) {
  check_writable_version(header.version, path_);
  validate_textures(header.textures, path_);
  validate_samplers(header.samplers, path_);
  ids_ = TextureIdSet(header.textures);
  std::string h = "# texsim trace, format v" +
                  std::to_string(written_version(has_view_, header.textures, has_ops_,
                                                 !header.samplers.empty())) +
                  ", CSV form (traces/FORMAT.md)\n";
  for (const TraceTexture& t : header.textures) {
    h += "# texture " + std::to_string(t.id) + " " + csv_quote_token(t.name) + " " +
         csv_quote_token(t.source) + " " + std::to_string(t.width) + " " + std::to_string(t.height);
    if (!t.storage.empty()) h.append(" ").append(csv_quote_token(t.storage));
    h += '\n';
  }
  for (const TraceSampler& s : header.samplers) h += csv_sampler_directive(s) + '\n';
  bool first = true;
  for (const TraceField& f : canonical_fields(has_lod_bias_, has_view_, has_ops_)) {
    if (!first) h += ',';
    h += f.name;
    first = false;
  }
  h += '\n';
  file_.reset(std::fopen(temp_.c_str(), "wb"));
  if (!file_)
    throw InputError(path_, std::string("cannot open for writing: ") + std::strerror(errno));
  put(h);
}

TraceCsvWriter::~TraceCsvWriter() {
  if (!closed_) {
    file_.reset();
    discard_temp(temp_, path_);
  }
}

void TraceCsvWriter::fail(const std::string& what) {
  file_.reset();
  discard_temp(temp_, path_);
  closed_ = true;
  throw InputError(path_, what);
}

void TraceCsvWriter::put(std::string_view s) {
  if (std::fwrite(s.data(), 1, s.size(), file_.get()) != s.size()) {
    fail(std::string("write failed: ") + std::strerror(errno));
  }
}

void TraceCsvWriter::write(const Fragment& f) {
  if (closed_) throw InputError(path_, "write after close");
  std::string bad = check_fragment(f, ids_, has_lod_bias_, has_view_);
  if (bad.empty() && has_ops_) bad = check_operation(f, kAllOpFields);
  if (!bad.empty()) throw InputError(path_ + ": record " + std::to_string(records_), bad);
  line_.clear();
  // Shortest text that reads back to the same value: exact CSV <-> binary round trips.
  auto num = [this](auto v, char sep) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // 64 bytes hold any double
    line_.append(buf, r.ptr);
    line_ += sep;
  };
  num(f.frame, ',');
  num(f.prim, ',');
  num(f.x, ',');
  num(f.y, ',');
  num(f.tex, ',');
  num(f.u, ',');
  num(f.v, ',');
  num(f.dudx, ',');
  num(f.dvdx, ',');
  num(f.dudy, ',');
  num(f.dvdy, has_lod_bias_ || has_view_ || has_ops_ ? ',' : '\n');
  if (has_lod_bias_) num(f.lod_bias, has_view_ || has_ops_ ? ',' : '\n');
  if (has_view_) {
    num(f.view_x, ',');
    num(f.view_y, ',');
    num(f.view_z, has_ops_ ? ',' : '\n');
  }
  if (has_ops_) {
    num(f.w, ',');
    num(f.dwdx, ',');
    num(f.dwdy, ',');
    num(f.layer, ',');
    num(f.lod, ',');
    num(f.compare_ref, ',');
    num(f.sampler, ',');
    num(static_cast<unsigned>(f.op), ',');
    num(static_cast<unsigned>(f.gather_component), ',');
    num(static_cast<int>(f.offset_u), ',');
    num(static_cast<int>(f.offset_v), ',');
    num(static_cast<int>(f.offset_w), '\n');
  }
  put(line_);
  ++records_;
}

void TraceCsvWriter::close() {
  if (closed_) return;
  if (std::fflush(file_.get()) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  std::FILE* f = file_.release();
  if (std::fclose(f) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  closed_ = true;
  commit_temp(temp_, path_);
}

}  // namespace texsim
