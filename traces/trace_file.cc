#include "traces/trace_file.h"

#include <isa-l/crc.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/sample_op.h"
#include "traces/byte_order.h"
#include "traces/trace_csv.h"

namespace texsim {

// zlib's crc32(0, p, n) (FORMAT.md), computed by ISA-L: crc32_gzip_refl takes and returns the
// CRC in zlib's form (inverted on entry and exit), so 0 starts a CRC as in zlib. Records are
// bounded by the formats' chunk limits (< 4 GiB), so one call covers them.
uint32_t trace_crc32(const unsigned char* p, size_t n) {
  return crc32_gzip_refl(0, p, static_cast<uint64_t>(n));
}

namespace {

constexpr char kChunkTag[4] = {'C', 'H', 'N', 'K'};
constexpr char kEndTag[4] = {'T', 'E', 'N', 'D'};
constexpr uint32_t kFixedHeaderBytes = 32;
constexpr uint32_t kFieldEntryBytes = 24;
constexpr uint32_t kTextureEntryBytes = 20;  // without the name and source bytes
constexpr uint32_t kStorageLenBytes = 4;     // version 3: storage_len after the source
constexpr uint32_t kChunkHeaderBytes = 12;
constexpr uint32_t kTrailerBytes = 24;

// Field indices in trace_field_specs() order.
enum FieldIndex : size_t {
  kFrame,
  kPrim,
  kX,
  kY,
  kTex,
  kU,
  kV,
  kDudx,
  kDvdx,
  kDudy,
  kDvdy,
  kLodBias,
  kViewX,
  kViewY,
  kViewZ,
  kW,  // the version-4 operation fields (kOpFieldNames order)
  kDwdx,
  kDwdy,
  kLayer,
  kLod,
  kCompareRef,
  kSampler,
  kOp,
  kGatherComp,
  kOffsetU,
  kOffsetV,
  kOffsetW
};
static_assert(kW == kFirstOpField);

uint32_t crc_of(const unsigned char* p, size_t n) { return trace_crc32(p, n); }

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08x", v);
  return buf;
}

bool valid_field_name(std::string_view s) {
  if (s.empty() || s.size() >= kTraceFieldNameBytes) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

const char* nonfinite_word(double v) { return std::isnan(v) ? "NaN" : "infinite"; }

}  // namespace

void TraceFileCloser::operator()(std::FILE* f) const {
  if (f != nullptr) std::fclose(f);
}

TraceFilePtr open_trace_input(const std::string& path, uint64_t* size) {
  // Streamed in chunks, so no size limit; a FIFO, device or directory is refused.
  return TraceFilePtr(open_input_file(path, "trace", kNoSizeLimit, size).release());
}

const char* to_string(TraceType t) {
  switch (t) {
    case TraceType::U8:
      return "u8";
    case TraceType::U16:
      return "u16";
    case TraceType::U32:
      return "u32";
    case TraceType::U64:
      return "u64";
    case TraceType::I8:
      return "i8";
    case TraceType::I16:
      return "i16";
    case TraceType::I32:
      return "i32";
    case TraceType::I64:
      return "i64";
    case TraceType::F32:
      return "f32";
    case TraceType::F64:
      return "f64";
  }
  return "?";
}

uint32_t type_size(TraceType t) {
  switch (t) {
    case TraceType::U8:
    case TraceType::I8:
      return 1;
    case TraceType::U16:
    case TraceType::I16:
      return 2;
    case TraceType::U32:
    case TraceType::I32:
    case TraceType::F32:
      return 4;
    case TraceType::U64:
    case TraceType::I64:
    case TraceType::F64:
      return 8;
  }
  return 0;
}

bool is_valid_type_code(uint32_t code) { return code >= 1 && code <= 10; }

const TraceTexture* TraceHeader::find_texture(uint32_t id) const {
  for (const TraceTexture& t : textures) {
    if (t.id == id) return &t;
  }
  return nullptr;
}

const std::vector<TraceFieldSpec>& trace_field_specs() {
  static const std::vector<TraceFieldSpec> specs = {
      {"frame", TraceType::U32, true},
      {"prim", TraceType::U32, true},
      {"x", TraceType::U32, true},
      {"y", TraceType::U32, true},
      {"tex", TraceType::U32, true},
      {"u", TraceType::F64, true},
      {"v", TraceType::F64, true},
      {"dudx", TraceType::F64, true},
      {"dvdx", TraceType::F64, true},
      {"dudy", TraceType::F64, true},
      {"dvdy", TraceType::F64, true},
      {"lod_bias", TraceType::F32, false},
      {"view_x", TraceType::F32, false},
      {"view_y", TraceType::F32, false},
      {"view_z", TraceType::F32, false},
      {"w", TraceType::F64, false},
      {"dwdx", TraceType::F64, false},
      {"dwdy", TraceType::F64, false},
      {"layer", TraceType::F32, false},
      {"lod", TraceType::F32, false},
      {"compare_ref", TraceType::F32, false},
      {"sampler", TraceType::U16, false},
      {"op", TraceType::U8, false},
      {"gather_comp", TraceType::U8, false},
      {"offset_u", TraceType::I8, false},
      {"offset_v", TraceType::I8, false},
      {"offset_w", TraceType::I8, false},
  };
  return specs;
}

std::vector<TraceField> canonical_fields(bool has_lod_bias, bool has_view, bool has_ops) {
  std::vector<TraceField> fields;
  uint32_t offset = 0;
  const auto& specs = trace_field_specs();
  for (size_t k = 0; k < specs.size(); ++k) {
    const TraceFieldSpec& s = specs[k];
    const bool wanted =
        s.required || (k == kLodBias ? has_lod_bias : (k >= kFirstOpField ? has_ops : has_view));
    if (!wanted) continue;
    fields.push_back({std::string(s.name), s.type, offset});
    offset += type_size(s.type);
  }
  return fields;
}

uint32_t canonical_record_size(bool has_lod_bias, bool has_view, bool has_ops) {
  uint32_t size = 0;
  for (const TraceField& f : canonical_fields(has_lod_bias, has_view, has_ops))
    size += type_size(f.type);
  return size;
}

uint32_t written_version(bool has_view, const std::vector<TraceTexture>& textures, bool has_ops,
                         bool has_samplers) {
  const bool storage = std::any_of(textures.begin(), textures.end(),
                                   [](const TraceTexture& t) { return !t.storage.empty(); });
  return has_samplers ? 5 : has_ops ? 4 : storage ? 3 : has_view ? 2 : 1;
}

namespace {

bool has_control_char(std::string_view s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
}

template <size_t N>
std::string code_error(const char* key, uint8_t code, const std::string_view (&names)[N]) {
  if (code < N) return {};
  std::string list;
  for (size_t k = 0; k < N; ++k)
    list += (k ? ", " : "") + std::to_string(k) + " " + std::string(names[k]);
  return std::string(key) + " code " + std::to_string(code) + " is not one of " + list;
}

}  // namespace

std::string check_sampler(const TraceSampler& s) {
  if (s.name.empty() || s.name.size() > kTraceMaxNameBytes)
    return "name length " + std::to_string(s.name.size()) + " is outside 1.." +
           std::to_string(kTraceMaxNameBytes);
  if (has_control_char(s.name)) return "name contains a control character";
  for (const std::string& e : {code_error("mode", s.mode, kTraceFilterNames),
                               code_error("address_u", s.address_u, kTraceAddressNames),
                               code_error("address_v", s.address_v, kTraceAddressNames),
                               code_error("address_w", s.address_w, kTraceAddressNames),
                               code_error("compare", s.compare, kTraceCompareNames),
                               code_error("reduction", s.reduction, kTraceReductionNames),
                               code_error("aniso", s.aniso, kTraceAnisoNames)}) {
    if (!e.empty()) return e;
  }
  if (s.border_kind == 1)
    return "an integer border colour (border kind 1) needs an integer texture format, which "
           "texsim has not";
  if (s.border_kind != 0)
    return "border kind " + std::to_string(s.border_kind) + " is not 0 (float) or 1 (integer)";
  for (int c = 0; c < 4; ++c) {
    if (!std::isfinite(s.border[c]))
      return "border channel " + std::to_string(c) + " is " + nonfinite_word(s.border[c]);
  }
  if (s.max_aniso < 1 || s.max_aniso > 16)
    return "max_aniso " + std::to_string(s.max_aniso) + " is outside 1..16";
  const std::pair<const char*, float> lods[3] = {
      {"lod_bias", s.lod_bias}, {"min_lod", s.min_lod}, {"max_lod", s.max_lod}};
  for (const auto& [key, v] : lods) {
    if (!std::isfinite(v)) return std::string(key) + " is " + nonfinite_word(v);
  }
  if (s.min_lod > s.max_lod)
    return "min_lod " + std::to_string(s.min_lod) + " is above max_lod " +
           std::to_string(s.max_lod);
  if (s.unnormalized > 1)
    return "unnormalized is " + std::to_string(s.unnormalized) + ", not 0 or 1";
  if (s.seamless > 1) return "seamless is " + std::to_string(s.seamless) + ", not 0 or 1";
  if (s.sub_texel_bits < 1 || s.sub_texel_bits > 16)
    return "sub_texel_bits " + std::to_string(s.sub_texel_bits) + " is outside 1..16";
  if (s.mipmap_bits < 1 || s.mipmap_bits > 16)
    return "mipmap_bits " + std::to_string(s.mipmap_bits) + " is outside 1..16";
  return {};
}

void validate_samplers(const std::vector<TraceSampler>& samplers, const std::string& where) {
  if (samplers.size() > kTraceMaxSamplers) {
    throw InputError(where, "sampler table has " + std::to_string(samplers.size()) +
                                " entries, more than the limit " +
                                std::to_string(kTraceMaxSamplers));
  }
  // Names seen, with their ids: a table of 65535 entries is checked in n log n, not n².
  std::map<std::string_view, size_t> names;
  for (size_t i = 0; i < samplers.size(); ++i) {
    const TraceSampler& s = samplers[i];
    const std::string entry =
        "sampler table entry " + std::to_string(i + 1) + " ('" + s.name + "'): ";
    if (const std::string why = check_sampler(s); !why.empty())
      throw InputError(where, has_control_char(s.name)
                                  ? "sampler table entry " + std::to_string(i + 1) + ": " + why
                                  : entry + why);
    const auto [it, added] = names.emplace(s.name, i + 1);
    if (!added)
      throw InputError(where, entry + "the name is that of entry " + std::to_string(it->second));
  }
}

std::string check_operation(const Fragment& f, uint32_t present) {
  auto has = [&](size_t k) { return (present >> (k - kFirstOpField)) & 1u; };
  const double reals[6] = {f.w, f.dwdx, f.dwdy, f.layer, f.lod, f.compare_ref};
  for (size_t i = 0; i < 6; ++i) {
    if (has(kW + i) && !std::isfinite(reals[i])) {
      return "field '" + std::string(kOpFieldNames[i]) + "' is " + nonfinite_word(reals[i]);
    }
  }
  if (!valid_sample_op(f.op))
    return "field 'op' is " + std::to_string(f.op) + ", not an operation code 0.." +
           std::to_string(kSampleOps - 1);
  if (f.gather_component > 3)
    return "field 'gather_comp' is " + std::to_string(f.gather_component) + ", not 0..3";
  const int offsets[3] = {f.offset_u, f.offset_v, f.offset_w};
  for (size_t i = 0; i < 3; ++i) {
    if (offsets[i] < -8 || offsets[i] > 7)
      return "field '" + std::string(kOpFieldNames[kOffsetU - kFirstOpField + i]) + "' is " +
             std::to_string(offsets[i]) + ", outside the texel offsets -8..7";
  }
  const std::string op_name(kSampleOpNames[f.op]);
  if (f.op == static_cast<uint8_t>(SampleOp::kSampleLod) && !has(kLod))
    return "operation '" + op_name + "' needs the field 'lod', which the trace lacks";
  if (f.op == static_cast<uint8_t>(SampleOp::kGather) && !has(kGatherComp))
    return "operation '" + op_name + "' needs the field 'gather_comp', which the trace lacks";
  return {};
}

void check_writable_version(uint32_t version, const std::string& where) {
  if (version < 1 || version > kTraceVersion) {
    throw InputError(where, "cannot write trace version " + std::to_string(version) +
                                " (this writer writes versions 1.." +
                                std::to_string(kTraceVersion) + ")");
  }
}

void validate_textures(const std::vector<TraceTexture>& textures, const std::string& where) {
  if (textures.size() > kTraceMaxTextures) {
    throw InputError(where, "texture table has " + std::to_string(textures.size()) +
                                " entries, more than the limit " +
                                std::to_string(kTraceMaxTextures));
  }
  std::vector<uint32_t> ids;
  ids.reserve(textures.size());
  for (size_t i = 0; i < textures.size(); ++i) {
    const TraceTexture& t = textures[i];
    const std::string entry =
        "texture entry " + std::to_string(i) + " (id " + std::to_string(t.id) + "): ";
    if (t.width < 1 || t.width > kTraceMaxTextureSize || t.height < 1 ||
        t.height > kTraceMaxTextureSize) {
      throw InputError(where, entry + "size " + std::to_string(t.width) + "x" +
                                  std::to_string(t.height) + " is outside 1.." +
                                  std::to_string(kTraceMaxTextureSize));
    }
    if (t.name.empty() || t.name.size() > kTraceMaxNameBytes) {
      throw InputError(where, entry + "name length " + std::to_string(t.name.size()) +
                                  " is outside 1.." + std::to_string(kTraceMaxNameBytes));
    }
    if (t.source.size() > kTraceMaxSourceBytes) {
      throw InputError(where, entry + "source length " + std::to_string(t.source.size()) +
                                  " exceeds " + std::to_string(kTraceMaxSourceBytes));
    }
    // Control characters would break the one-line CSV directive and terminal output.
    auto has_control = [](const std::string& s) {
      return std::any_of(s.begin(), s.end(), [](char c) {
        const auto u = static_cast<unsigned char>(c);
        return u < 0x20 || u == 0x7f;
      });
    };
    if (has_control(t.name)) throw InputError(where, entry + "name contains a control character");
    if (has_control(t.source))
      throw InputError(where, entry + "source contains a control character");
    if (t.storage.size() > kTraceMaxStorageBytes) {
      throw InputError(where, entry + "storage length " + std::to_string(t.storage.size()) +
                                  " exceeds " + std::to_string(kTraceMaxStorageBytes));
    }
    if (has_control(t.storage))
      throw InputError(where, entry + "storage contains a control character");
    const std::string_view st = t.storage;
    const bool kind_ok = st.empty() || (st.starts_with("format=") && st.size() > 7) ||
                         (st.starts_with("compress=") && st.size() > 9);
    if (!kind_ok) {
      throw InputError(where, entry + "storage '" + t.storage +
                                  "' is neither \"format=NAME\" nor "
                                  "\"compress=FORMAT,ENCODER[,QUALITY]\"");
    }
    ids.push_back(t.id);
  }
  std::sort(ids.begin(), ids.end());
  const auto dup = std::adjacent_find(ids.begin(), ids.end());
  if (dup != ids.end()) {
    throw InputError(where,
                     "texture id " + std::to_string(*dup) + " appears twice in the texture table");
  }
}

TextureIdSet::TextureIdSet(const std::vector<TraceTexture>& textures) {
  for (const TraceTexture& t : textures) sorted_.push_back(t.id);
  std::sort(sorted_.begin(), sorted_.end());
  // Small ids (the usual case: 0..N-1) get a direct table so the per-record check is one load.
  if (!sorted_.empty() && sorted_.back() < 65536) {
    dense_.assign(sorted_.back() + 1u, 0);
    for (uint32_t id : sorted_) dense_[id] = 1;
  }
}

bool TextureIdSet::contains(uint32_t id) const {
  if (!dense_.empty()) return id < dense_.size() && dense_[id] != 0;
  return std::binary_search(sorted_.begin(), sorted_.end(), id);
}

std::string check_fragment(const Fragment& f, const TextureIdSet& ids, bool has_lod_bias,
                           bool has_view) {
  const double vals[6] = {f.u, f.v, f.dudx, f.dvdx, f.dudy, f.dvdy};
  for (size_t i = 0; i < 6; ++i) {
    if (!std::isfinite(vals[i])) {
      return std::string("field '") + std::string(trace_field_specs()[kU + i].name) + "' is " +
             nonfinite_word(vals[i]);
    }
  }
  if (has_lod_bias && !std::isfinite(f.lod_bias)) {
    return std::string("field 'lod_bias' is ") + nonfinite_word(f.lod_bias);
  }
  if (has_view) {
    const float view[3] = {f.view_x, f.view_y, f.view_z};
    for (size_t i = 0; i < 3; ++i) {
      if (!std::isfinite(view[i])) {
        return std::string("field '") + std::string(trace_field_specs()[kViewX + i].name) +
               "' is " + nonfinite_word(view[i]) + " (the view vector must be finite)";
      }
    }
    if (!f.has_view()) return "the view vector (view_x, view_y, view_z) is zero";
  }
  if (!ids.contains(f.tex)) {
    return "texture id " + std::to_string(f.tex) + " is not in the texture table";
  }
  return {};
}

bool has_csv_extension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](char c) {
    return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  });
  return ext == ".csv";
}

// ---------------------------------------------------------------------------------------------
// Writer

namespace {

// The state of a sampler entry after its name (FORMAT.md "Sampler table").
constexpr uint32_t kSamplerStateBytes = 41;

void append_samplers(std::vector<unsigned char>& h, const std::vector<TraceSampler>& samplers) {
  append_le<uint32_t>(h, static_cast<uint32_t>(samplers.size()));
  for (const TraceSampler& s : samplers) {
    append_le<uint32_t>(h, static_cast<uint32_t>(s.name.size()));
    h.insert(h.end(), s.name.begin(), s.name.end());
    for (const uint8_t b : {s.mode, s.address_u, s.address_v, s.address_w, s.border_kind})
      h.push_back(b);
    for (const float c : s.border) append_le<float>(h, c);
    for (const uint8_t b : {s.compare, s.reduction, s.aniso, s.max_aniso}) h.push_back(b);
    for (const float v : {s.lod_bias, s.min_lod, s.max_lod}) append_le<float>(h, v);
    for (const uint8_t b : {s.unnormalized, s.seamless, s.sub_texel_bits, s.mipmap_bits})
      h.push_back(b);
  }
}

}  // namespace

TraceWriter::TraceWriter(const std::string& path, const TraceHeader& header,
                         uint32_t records_per_chunk)
    : path_(path),
      temp_(temp_path_for(path)),
      has_lod_bias_(header.has_lod_bias),
      has_view_(header.has_view),
      has_ops_(header.has_ops),
      record_size_(canonical_record_size(header.has_lod_bias, header.has_view, header.has_ops)),
      records_per_chunk_(records_per_chunk) {
  check_writable_version(header.version, path_);
  if (records_per_chunk_ < 1 || records_per_chunk_ > kTraceMaxRecordsPerChunk ||
      uint64_t{records_per_chunk_} * record_size_ > kTraceMaxChunkBytes) {
    throw InputError(path_, "records per chunk " + std::to_string(records_per_chunk_) +
                                " is outside 1.." +
                                std::to_string(kTraceMaxChunkBytes / record_size_));
  }
  validate_textures(header.textures, path_);
  validate_samplers(header.samplers, path_);
  ids_ = TextureIdSet(header.textures);

  const std::vector<TraceField> fields = canonical_fields(has_lod_bias_, has_view_, has_ops_);
  std::vector<unsigned char> h(kTraceMagic, kTraceMagic + sizeof kTraceMagic);
  const uint32_t version =
      written_version(has_view_, header.textures, has_ops_, !header.samplers.empty());
  append_le<uint32_t>(h, version);
  append_le<uint32_t>(h, 0);  // header size, patched below
  append_le<uint32_t>(h, record_size_);
  append_le<uint32_t>(h, records_per_chunk_);
  append_le<uint32_t>(h, static_cast<uint32_t>(fields.size()));
  append_le<uint32_t>(h, static_cast<uint32_t>(header.textures.size()));
  for (const TraceField& f : fields) {
    // NUL-padded to 16 bytes; canonical names are at most 15 characters.
    char name[kTraceFieldNameBytes] = {};
    std::copy(f.name.begin(), f.name.end(), name);
    h.insert(h.end(), name, name + kTraceFieldNameBytes);
    append_le<uint32_t>(h, static_cast<uint32_t>(f.type));
    append_le<uint32_t>(h, f.offset);
  }
  for (const TraceTexture& t : header.textures) {
    append_le<uint32_t>(h, t.id);
    append_le<uint32_t>(h, t.width);
    append_le<uint32_t>(h, t.height);
    append_le<uint32_t>(h, static_cast<uint32_t>(t.name.size()));
    append_le<uint32_t>(h, static_cast<uint32_t>(t.source.size()));
    h.insert(h.end(), t.name.begin(), t.name.end());
    h.insert(h.end(), t.source.begin(), t.source.end());
    if (version >= 3) {
      append_le<uint32_t>(h, static_cast<uint32_t>(t.storage.size()));
      h.insert(h.end(), t.storage.begin(), t.storage.end());
    }
  }
  if (version >= 5) append_samplers(h, header.samplers);
  const auto header_size = static_cast<uint32_t>(h.size() + 4);
  if (header_size > kTraceMaxHeaderBytes) {
    throw InputError(path_, "header would be " + std::to_string(header_size) +
                                " bytes, more than the limit " +
                                std::to_string(kTraceMaxHeaderBytes));
  }
  store_le<uint32_t>(h.data() + 12, header_size);
  append_le<uint32_t>(h, crc_of(h.data(), h.size()));

  file_.reset(std::fopen(temp_.c_str(), "wb"));
  if (!file_)
    throw InputError(path_, std::string("cannot open for writing: ") + std::strerror(errno));
  chunk_.resize(size_t{records_per_chunk_} * record_size_);
  put(h.data(), h.size());  // on failure put() removes the temporary file
}

TraceWriter::~TraceWriter() {
  if (!closed_) {
    file_.reset();
    discard_temp(temp_, path_);
  }
}

void TraceWriter::fail(const std::string& what) {
  file_.reset();
  discard_temp(temp_, path_);
  closed_ = true;
  throw InputError(path_, what);
}

void TraceWriter::put(const void* data, size_t n) {
  if (std::fwrite(data, 1, n, file_.get()) != n) {
    fail(std::string("write failed: ") + std::strerror(errno));
  }
}

void TraceWriter::write(const Fragment& f) {
  if (closed_) throw InputError(path_, "write after close");
  std::string bad = check_fragment(f, ids_, has_lod_bias_, has_view_);
  if (bad.empty() && has_ops_) bad = check_operation(f, kAllOpFields);
  if (!bad.empty()) throw InputError(path_ + ": record " + std::to_string(records_), bad);
  // Canonical layout (packed, trace_field_specs() order): 5 x u32, 6 x f64, [f32], [3 x f32].
  unsigned char* p = chunk_.data() + size_t{in_chunk_} * record_size_;
  store_le(p + 0, f.frame);
  store_le(p + 4, f.prim);
  store_le(p + 8, f.x);
  store_le(p + 12, f.y);
  store_le(p + 16, f.tex);
  store_le(p + 20, f.u);
  store_le(p + 28, f.v);
  store_le(p + 36, f.dudx);
  store_le(p + 44, f.dvdx);
  store_le(p + 52, f.dudy);
  store_le(p + 60, f.dvdy);
  if (has_lod_bias_) store_le(p + 68, f.lod_bias);
  if (has_view_) {
    unsigned char* q = p + (has_lod_bias_ ? 72 : 68);
    store_le(q, f.view_x);
    store_le(q + 4, f.view_y);
    store_le(q + 8, f.view_z);
  }
  if (has_ops_) {
    unsigned char* q = p + 68 + (has_lod_bias_ ? 4 : 0) + (has_view_ ? 12 : 0);
    store_le(q, f.w);
    store_le(q + 8, f.dwdx);
    store_le(q + 16, f.dwdy);
    store_le(q + 24, f.layer);
    store_le(q + 28, f.lod);
    store_le(q + 32, f.compare_ref);
    store_le(q + 36, f.sampler);
    store_le(q + 38, f.op);
    store_le(q + 39, f.gather_component);
    store_le(q + 40, f.offset_u);
    store_le(q + 41, f.offset_v);
    store_le(q + 42, f.offset_w);
  }
  ++records_;
  if (++in_chunk_ == records_per_chunk_) flush_chunk();
}

void TraceWriter::flush_chunk() {
  if (in_chunk_ == 0) return;
  const size_t bytes = size_t{in_chunk_} * record_size_;
  unsigned char h[kChunkHeaderBytes];
  std::memcpy(h, kChunkTag, 4);
  store_le<uint32_t>(h + 4, in_chunk_);
  store_le<uint32_t>(h + 8, crc_of(chunk_.data(), bytes));
  put(h, sizeof h);
  put(chunk_.data(), bytes);
  ++chunks_;
  in_chunk_ = 0;
}

void TraceWriter::close() {
  if (closed_) return;
  flush_chunk();
  unsigned char t[kTrailerBytes];
  std::memcpy(t, kEndTag, 4);
  store_le<uint64_t>(t + 8, chunks_);
  store_le<uint64_t>(t + 16, records_);
  store_le<uint32_t>(t + 4, crc_of(t + 8, 16));
  put(t, sizeof t);
  if (std::fflush(file_.get()) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  std::FILE* f = file_.release();
  if (std::fclose(f) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  closed_ = true;
  commit_temp(temp_, path_);  // removes the temporary file itself if the rename fails
}

// ---------------------------------------------------------------------------------------------
// Reader

TraceReader::TraceReader(const std::string& path) : path_(path) {
  file_ = open_trace_input(path_, &file_size_);
  unsigned char magic[sizeof kTraceMagic] = {};
  const size_t n = std::fread(magic, 1, sizeof magic, file_.get());
  if (n == sizeof magic && std::memcmp(magic, kTraceMagic, sizeof magic) == 0) {
    pos_ = n;
    open_binary();
    return;
  }
  file_.reset();
  if (has_csv_extension(path_)) {
    csv_ = std::make_unique<TraceCsvReader>(path_);
    header_ = csv_->header();
    return;
  }
  throw InputError(path_ + ": header",
                   "bad magic: not a texsim binary trace (expected \"TEXSIMTR\" in the first 8 "
                   "bytes) and not named .csv");
}

TraceReader::~TraceReader() = default;

void TraceReader::read_exact(void* dst, size_t n, const std::string& where, const char* what) {
  if (n > file_size_ - pos_) {
    throw InputError(where, std::string("truncated file: ") + what + " needs " + std::to_string(n) +
                                " bytes, only " + std::to_string(file_size_ - pos_) + " remain");
  }
  if (std::fread(dst, 1, n, file_.get()) != n) {
    throw InputError(where,
                     std::string("cannot read ") + what +
                         (std::ferror(file_.get()) ? std::string(": ") + std::strerror(errno)
                                                   : std::string(": file shrank while reading")));
  }
  pos_ += n;
}

namespace {

// The fixed part of a binary header, after the magic.
struct FixedHeader {
  uint32_t version, header_size, record_size, records_per_chunk, field_count, texture_count;
};

// Decodes and checks the fixed header (h: its kFixedHeaderBytes bytes); each count within its
// limit, and the header size large enough for them.
FixedHeader parse_fixed_header(const unsigned char* h, const std::string& where) {
  const FixedHeader fh{load_le<uint32_t>(h + 8),  load_le<uint32_t>(h + 12),
                       load_le<uint32_t>(h + 16), load_le<uint32_t>(h + 20),
                       load_le<uint32_t>(h + 24), load_le<uint32_t>(h + 28)};
  if (fh.version < 1 || fh.version > kTraceVersion) {
    throw InputError(where, "unknown version " + std::to_string(fh.version) +
                                " (this reader reads versions 1.." + std::to_string(kTraceVersion) +
                                ")");
  }
  if (fh.record_size < 1 || fh.record_size > kTraceMaxRecordSize) {
    throw InputError(where, "record size " + std::to_string(fh.record_size) + " is outside 1.." +
                                std::to_string(kTraceMaxRecordSize));
  }
  const uint32_t rpc = fh.records_per_chunk;
  if (rpc < 1 || rpc > kTraceMaxRecordsPerChunk) {
    throw InputError(where, "records per chunk " + std::to_string(rpc) + " is outside 1.." +
                                std::to_string(kTraceMaxRecordsPerChunk));
  }
  if (uint64_t{rpc} * fh.record_size > kTraceMaxChunkBytes) {
    throw InputError(where, "chunk size " + std::to_string(uint64_t{rpc} * fh.record_size) +
                                " bytes exceeds the limit " + std::to_string(kTraceMaxChunkBytes));
  }
  if (fh.field_count < 1 || fh.field_count > kTraceMaxFields) {
    throw InputError(where, "field count " + std::to_string(fh.field_count) + " is outside 1.." +
                                std::to_string(kTraceMaxFields));
  }
  if (fh.texture_count > kTraceMaxTextures) {
    throw InputError(where, "texture count " + std::to_string(fh.texture_count) +
                                " exceeds the limit " + std::to_string(kTraceMaxTextures));
  }
  const uint32_t entry_bytes = kTextureEntryBytes + (fh.version >= 3 ? kStorageLenBytes : 0);
  const uint64_t least = uint64_t{kFixedHeaderBytes} + uint64_t{fh.field_count} * kFieldEntryBytes +
                         uint64_t{fh.texture_count} * entry_bytes + 4 +
                         (fh.version >= 5 ? 4 : 0);  // version 5: the sampler count
  if (fh.header_size < least || fh.header_size > kTraceMaxHeaderBytes) {
    throw InputError(where, "header size " + std::to_string(fh.header_size) + " is outside " +
                                std::to_string(least) + ".." +
                                std::to_string(kTraceMaxHeaderBytes) + " (for " +
                                std::to_string(fh.field_count) + " fields and " +
                                std::to_string(fh.texture_count) + " textures)");
  }
  return fh;
}

// Reads the field layout at p (advanced past it): names valid and unique, types known, each
// field inside the record and overlapping no other.
std::vector<TraceField> parse_fields(const unsigned char*& p, const FixedHeader& fh,
                                     const std::string& where) {
  std::vector<TraceField> fields;
  for (uint32_t i = 0; i < fh.field_count; ++i, p += kFieldEntryBytes) {
    const std::string fw = where + ", field " + std::to_string(i);
    const auto* name_bytes = reinterpret_cast<const char*>(p);
    const size_t len = strnlen(name_bytes, kTraceFieldNameBytes);
    const std::string name(name_bytes, len);
    if (len == kTraceFieldNameBytes || !valid_field_name(name)) {
      throw InputError(fw,
                       "bad field name (1-15 characters of [A-Za-z0-9_], NUL-padded to 16 bytes)");
    }
    const auto code = load_le<uint32_t>(p + 16);
    const auto offset = load_le<uint32_t>(p + 20);
    if (!is_valid_type_code(code)) {
      throw InputError(fw, "field '" + name + "' has unknown type code " + std::to_string(code));
    }
    const auto type = static_cast<TraceType>(code);
    if (uint64_t{offset} + type_size(type) > fh.record_size) {
      throw InputError(fw, "field '" + name + "' at byte " + std::to_string(offset) + " (" +
                               to_string(type) + ") runs past the record size " +
                               std::to_string(fh.record_size));
    }
    for (const TraceField& other : fields) {
      if (other.name == name) throw InputError(fw, "field '" + name + "' appears twice");
      const bool overlap =
          offset < other.offset + type_size(other.type) && other.offset < offset + type_size(type);
      if (overlap) {
        throw InputError(fw, "field '" + name + "' overlaps field '" + other.name + "'");
      }
    }
    fields.push_back({name, type, offset});
  }
  return fields;
}

// Reads the texture table from p (advanced past it) to end, which it must fill exactly.
// Version 3 entries end with the storage (u32 length, then its bytes).
std::vector<TraceTexture> parse_textures(const unsigned char*& p, const unsigned char* end,
                                         uint32_t count, uint32_t version,
                                         const std::string& where) {
  std::vector<TraceTexture> textures;
  for (uint32_t i = 0; i < count; ++i) {
    const std::string tw = where + ", texture entry " + std::to_string(i);
    if (static_cast<size_t>(end - p) < kTextureEntryBytes) {
      throw InputError(tw, "entry runs past the end of the header");
    }
    TraceTexture t;
    t.id = load_le<uint32_t>(p);
    t.width = load_le<uint32_t>(p + 4);
    t.height = load_le<uint32_t>(p + 8);
    const auto name_len = load_le<uint32_t>(p + 12);
    const auto source_len = load_le<uint32_t>(p + 16);
    p += kTextureEntryBytes;
    if (name_len > kTraceMaxNameBytes || source_len > kTraceMaxSourceBytes) {
      throw InputError(tw, "name length " + std::to_string(name_len) + " or source length " +
                               std::to_string(source_len) + " exceeds the limits " +
                               std::to_string(kTraceMaxNameBytes) + " / " +
                               std::to_string(kTraceMaxSourceBytes));
    }
    if (static_cast<size_t>(end - p) < size_t{name_len} + source_len) {
      throw InputError(tw, "name and source run past the end of the header");
    }
    t.name.assign(reinterpret_cast<const char*>(p), name_len);
    p += name_len;
    t.source.assign(reinterpret_cast<const char*>(p), source_len);
    p += source_len;
    if (version >= 3) {
      if (static_cast<size_t>(end - p) < kStorageLenBytes) {
        throw InputError(tw, "storage length runs past the end of the header");
      }
      const auto storage_len = load_le<uint32_t>(p);
      p += kStorageLenBytes;
      if (storage_len > kTraceMaxStorageBytes) {
        throw InputError(tw, "storage length " + std::to_string(storage_len) +
                                 " exceeds the limit " + std::to_string(kTraceMaxStorageBytes));
      }
      if (static_cast<size_t>(end - p) < storage_len) {
        throw InputError(tw, "storage runs past the end of the header");
      }
      t.storage.assign(reinterpret_cast<const char*>(p), storage_len);
      p += storage_len;
    }
    textures.push_back(std::move(t));
  }
  if (version < 5 && p != end) {
    throw InputError(where, std::to_string(end - p) + " unexplained bytes after the texture table");
  }
  return textures;
}

// Reads the sampler table (version 5) from p to end, which it must fill exactly; each entry
// checked (check_sampler) and named by its id.
std::vector<TraceSampler> parse_samplers(const unsigned char* p, const unsigned char* end,
                                         const std::string& where) {
  if (static_cast<size_t>(end - p) < 4)
    throw InputError(where, "the sampler count runs past the end of the header");
  const auto count = load_le<uint32_t>(p);
  p += 4;
  if (count > kTraceMaxSamplers) {
    throw InputError(where, "sampler count " + std::to_string(count) + " exceeds the limit " +
                                std::to_string(kTraceMaxSamplers));
  }
  std::vector<TraceSampler> samplers;
  for (uint32_t i = 0; i < count; ++i) {
    const std::string sw = where + ", sampler entry " + std::to_string(i + 1);
    if (static_cast<size_t>(end - p) < 4)
      throw InputError(sw, "entry runs past the end of the header");
    const auto name_len = load_le<uint32_t>(p);
    p += 4;
    if (name_len < 1 || name_len > kTraceMaxNameBytes) {
      throw InputError(sw, "name length " + std::to_string(name_len) + " is outside 1.." +
                               std::to_string(kTraceMaxNameBytes));
    }
    if (static_cast<size_t>(end - p) < size_t{name_len} + kSamplerStateBytes)
      throw InputError(sw, "name and state run past the end of the header");
    TraceSampler s;
    s.name.assign(reinterpret_cast<const char*>(p), name_len);
    p += name_len;
    uint8_t* const head[5] = {&s.mode, &s.address_u, &s.address_v, &s.address_w, &s.border_kind};
    for (uint8_t* b : head) *b = *p++;
    for (float& c : s.border) {
      c = load_le<float>(p);
      p += 4;
    }
    uint8_t* const mid[4] = {&s.compare, &s.reduction, &s.aniso, &s.max_aniso};
    for (uint8_t* b : mid) *b = *p++;
    float* const lods[3] = {&s.lod_bias, &s.min_lod, &s.max_lod};
    for (float* v : lods) {
      *v = load_le<float>(p);
      p += 4;
    }
    uint8_t* const tail[4] = {&s.unnormalized, &s.seamless, &s.sub_texel_bits, &s.mipmap_bits};
    for (uint8_t* b : tail) *b = *p++;
    samplers.push_back(std::move(s));
  }
  if (p != end) {
    throw InputError(where, std::to_string(end - p) + " unexplained bytes after the sampler table");
  }
  validate_samplers(samplers, where);
  return samplers;
}

// The record offset of each known field (trace_field_specs() order; -1 = absent). Unknown
// fields are skipped; a known field of the wrong type or a missing required one is an error.
// The operation fields the layout has (o[k] >= 0), into f; the others stay 0.
void load_operation(const unsigned char* p, const int64_t* o, Fragment& f) {
  if (o[kW] >= 0) f.w = load_le<double>(p + o[kW]);
  if (o[kDwdx] >= 0) f.dwdx = load_le<double>(p + o[kDwdx]);
  if (o[kDwdy] >= 0) f.dwdy = load_le<double>(p + o[kDwdy]);
  if (o[kLayer] >= 0) f.layer = load_le<float>(p + o[kLayer]);
  if (o[kLod] >= 0) f.lod = load_le<float>(p + o[kLod]);
  if (o[kCompareRef] >= 0) f.compare_ref = load_le<float>(p + o[kCompareRef]);
  if (o[kSampler] >= 0) f.sampler = load_le<uint16_t>(p + o[kSampler]);
  if (o[kOp] >= 0) f.op = load_le<uint8_t>(p + o[kOp]);
  if (o[kGatherComp] >= 0) f.gather_component = load_le<uint8_t>(p + o[kGatherComp]);
  if (o[kOffsetU] >= 0) f.offset_u = load_le<int8_t>(p + o[kOffsetU]);
  if (o[kOffsetV] >= 0) f.offset_v = load_le<int8_t>(p + o[kOffsetV]);
  if (o[kOffsetW] >= 0) f.offset_w = load_le<int8_t>(p + o[kOffsetW]);
}

std::vector<int64_t> known_field_offsets(const std::vector<TraceField>& fields, uint32_t version,
                                         const std::string& where) {
  const auto& specs = trace_field_specs();
  std::vector<int64_t> offsets(specs.size(), -1);
  for (size_t s = 0; s < specs.size(); ++s) {
    // Version 1 does not know the view vector: fields of those names are skipped there.
    if (version < 2 && s >= kViewX) continue;
    // Versions before 4 do not know the operation fields either.
    if (version < 4 && s >= kFirstOpField) continue;
    for (const TraceField& f : fields) {
      if (f.name != specs[s].name) continue;
      if (f.type != specs[s].type) {
        throw InputError(where, "field '" + f.name + "' has type " + to_string(f.type) +
                                    ", expected " + to_string(specs[s].type));
      }
      offsets[s] = f.offset;
    }
    if (offsets[s] < 0 && specs[s].required) {
      throw InputError(where, "missing required field '" + std::string(specs[s].name) + "'");
    }
  }
  const int views = (offsets[kViewX] >= 0) + (offsets[kViewY] >= 0) + (offsets[kViewZ] >= 0);
  if (views != 0 && views != 3) {
    throw InputError(where, "the view vector needs all three fields view_x, view_y, view_z (" +
                                std::to_string(views) + " present)");
  }
  return offsets;
}

}  // namespace

void TraceReader::open_binary() {
  const std::string where = path_ + ": header";
  std::vector<unsigned char> h(kFixedHeaderBytes);
  std::memcpy(h.data(), kTraceMagic, sizeof kTraceMagic);
  read_exact(h.data() + pos_, kFixedHeaderBytes - pos_, where, "fixed header");
  const FixedHeader fh = parse_fixed_header(h.data(), where);
  const uint32_t header_size = fh.header_size;
  h.resize(header_size);  // bounded by kTraceMaxHeaderBytes, and read_exact checks the file size
  read_exact(h.data() + kFixedHeaderBytes, header_size - kFixedHeaderBytes, where, "header");
  const auto stored_crc = load_le<uint32_t>(h.data() + header_size - 4);
  const uint32_t crc = crc_of(h.data(), header_size - 4);
  if (stored_crc != crc) {
    throw InputError(where, "header CRC mismatch (stored " + hex32(stored_crc) + ", computed " +
                                hex32(crc) + ")");
  }

  header_.version = fh.version;
  header_.encoding = TraceEncoding::Binary;
  header_.record_size = fh.record_size;
  header_.records_per_chunk = fh.records_per_chunk;
  const unsigned char* p = h.data() + kFixedHeaderBytes;
  header_.fields = parse_fields(p, fh, where);
  header_.textures =
      parse_textures(p, h.data() + header_size - 4, fh.texture_count, fh.version, where);
  if (fh.version >= 5) header_.samplers = parse_samplers(p, h.data() + header_size - 4, where);
  validate_textures(header_.textures, where);
  ids_ = TextureIdSet(header_.textures);
  offsets_ = known_field_offsets(header_.fields, fh.version, where);
  header_.has_lod_bias = offsets_[kLodBias] >= 0;
  header_.has_view = offsets_[kViewX] >= 0;
  for (size_t k = kFirstOpField; k < offsets_.size(); ++k)
    if (offsets_[k] >= 0) header_.op_fields |= 1u << (k - kFirstOpField);
  header_.has_ops = header_.op_fields != 0;
}

std::string TraceReader::chunk_where() const {
  return path_ + ": chunk " + std::to_string(chunks_) + " at byte " + std::to_string(pos_);
}

std::string TraceReader::record_where(uint32_t r) const {
  return path_ + ": chunk " + std::to_string(chunks_) + ", record " + std::to_string(r) +
         " (trace record " + std::to_string(records_ + r) + ")";
}

size_t TraceReader::next_chunk(std::vector<Fragment>& out) {
  out.clear();
  if (csv_) {
    const size_t n = csv_->next_chunk(out);
    if (n > 0) {
      ++chunks_;
      records_ += n;
    }
    return n;
  }
  if (done_) return 0;
  return next_binary_chunk(out);
}

size_t TraceReader::next_binary_chunk(std::vector<Fragment>& out) {
  const std::string where = chunk_where();
  if (pos_ == file_size_) {
    throw InputError(where, "truncated file: ends after " + std::to_string(chunks_) + " chunks (" +
                                std::to_string(records_) + " records) without the end marker");
  }
  unsigned char tag[4];
  read_exact(tag, 4, where, "chunk tag");
  if (std::memcmp(tag, kEndTag, 4) == 0) {
    check_trailer();
    done_ = true;
    return 0;
  }
  if (std::memcmp(tag, kChunkTag, 4) != 0) {
    throw InputError(where, "bad chunk tag " + hex32(load_le<uint32_t>(tag)) +
                                " (expected \"CHNK\" or \"TEND\"): corrupt file");
  }
  unsigned char ch[8];
  read_exact(ch, 8, where, "chunk header");
  const auto count = load_le<uint32_t>(ch);
  const auto stored_crc = load_le<uint32_t>(ch + 4);
  if (count == 0) throw InputError(where, "empty chunk (record count 0)");
  if (count > header_.records_per_chunk) {
    throw InputError(where, "record count " + std::to_string(count) +
                                " exceeds the header's records per chunk " +
                                std::to_string(header_.records_per_chunk));
  }
  const size_t bytes = size_t{count} * header_.record_size;
  if (bytes > file_size_ - pos_) {  // checked before allocating
    throw InputError(where, "truncated chunk: " + std::to_string(count) + " records need " +
                                std::to_string(bytes) + " bytes, only " +
                                std::to_string(file_size_ - pos_) + " remain");
  }
  payload_.resize(bytes);
  read_exact(payload_.data(), bytes, where, "chunk payload");
  const uint32_t crc = crc_of(payload_.data(), bytes);
  if (crc != stored_crc) {
    throw InputError(
        where, "CRC mismatch (stored " + hex32(stored_crc) + ", computed " + hex32(crc) + ")");
  }

  out.resize(count);
  const size_t rs = header_.record_size;
  const int64_t* o = offsets_.data();
  const bool lod = header_.has_lod_bias;
  const bool view = header_.has_view;
  for (uint32_t r = 0; r < count; ++r) {
    const unsigned char* p = payload_.data() + r * rs;
    Fragment& f = out[r];
    f.frame = load_le<uint32_t>(p + o[kFrame]);
    f.prim = load_le<uint32_t>(p + o[kPrim]);
    f.x = load_le<uint32_t>(p + o[kX]);
    f.y = load_le<uint32_t>(p + o[kY]);
    f.tex = load_le<uint32_t>(p + o[kTex]);
    f.u = load_le<double>(p + o[kU]);
    f.v = load_le<double>(p + o[kV]);
    f.dudx = load_le<double>(p + o[kDudx]);
    f.dvdx = load_le<double>(p + o[kDvdx]);
    f.dudy = load_le<double>(p + o[kDudy]);
    f.dvdy = load_le<double>(p + o[kDvdy]);
    f.lod_bias = lod ? load_le<float>(p + o[kLodBias]) : 0.0f;
    // One combined test on the hot path; the message is only built for a bad record.
    const bool finite = std::isfinite(f.u) && std::isfinite(f.v) && std::isfinite(f.dudx) &&
                        std::isfinite(f.dvdx) && std::isfinite(f.dudy) && std::isfinite(f.dvdy) &&
                        std::isfinite(f.lod_bias);
    if (!finite || !ids_.contains(f.tex)) {
      throw InputError(record_where(r), check_fragment(f, ids_, lod, view));
    }
    if (view) {
      f.view_x = load_le<float>(p + o[kViewX]);
      f.view_y = load_le<float>(p + o[kViewY]);
      f.view_z = load_le<float>(p + o[kViewZ]);
      const std::string bad = check_fragment(f, ids_, lod, view);
      if (!bad.empty()) throw InputError(record_where(r), bad);
    }
    if (header_.has_ops) {
      load_operation(p, o, f);
      const std::string bad = check_operation(f, header_.op_fields);
      if (!bad.empty()) throw InputError(record_where(r), bad);
    }
  }
  ++chunks_;
  records_ += count;
  return count;
}

void TraceReader::check_trailer() {
  const std::string where = path_ + ": end marker at byte " + std::to_string(pos_ - 4);
  unsigned char t[kTrailerBytes - 4];
  read_exact(t, sizeof t, where, "end marker");
  const auto stored_crc = load_le<uint32_t>(t);
  const uint32_t crc = crc_of(t + 4, 16);
  if (stored_crc != crc) {
    throw InputError(where, "end marker CRC mismatch (stored " + hex32(stored_crc) + ", computed " +
                                hex32(crc) + ")");
  }
  const auto chunks = load_le<uint64_t>(t + 4);
  const auto records = load_le<uint64_t>(t + 12);
  if (chunks != chunks_ || records != records_) {
    throw InputError(where, "end marker counts " + std::to_string(chunks) + " chunks and " +
                                std::to_string(records) + " records, but the file holds " +
                                std::to_string(chunks_) + " chunks and " +
                                std::to_string(records_) + " records (chunks lost)");
  }
  if (pos_ != file_size_) {
    throw InputError(where,
                     std::to_string(file_size_ - pos_) + " unexpected bytes after the end marker");
  }
}

// ---------------------------------------------------------------------------------------------

void write_trace(const std::string& path, const TraceHeader& header,
                 const std::vector<Fragment>& fragments) {
  if (has_csv_extension(path)) {
    TraceCsvWriter w(path, header);
    for (const Fragment& f : fragments) w.write(f);
    w.close();
  } else {
    TraceWriter w(path, header);
    for (const Fragment& f : fragments) w.write(f);
    w.close();
  }
}

std::vector<Fragment> read_trace(const std::string& path, TraceHeader* header) {
  TraceReader r(path);
  std::vector<Fragment> all, chunk;
  while (r.next_chunk(chunk) > 0) all.insert(all.end(), chunk.begin(), chunk.end());
  if (header != nullptr) *header = r.header();
  return all;
}

}  // namespace texsim
