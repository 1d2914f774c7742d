#pragma once
// Trace files, format v5 (traces/FORMAT.md; v1 to v4 files are read too): the binary writer and
// the streaming reader that also opens the CSV form. The reader holds one chunk at a time, so its
// memory does not depend on the length of the trace; every defect of the input is an InputError
// naming file and record.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "blocks/base/fragment.h"

namespace texsim {

// The newest version: 2 adds the optional view vector (view_x, view_y, view_z), 3 each
// texture's storage, 4 the optional operation fields (op, lod, gather_comp, compare_ref,
// sampler, offsets, w and its derivatives, layer). A writer writes the oldest version that
// holds the trace (written_version), so a trace without any stays a version-1 file.
// 5 adds the optional sampler table after the texture table (TraceSampler).
inline constexpr uint32_t kTraceVersion = 5;
inline constexpr char kTraceMagic[8] = {'T', 'E', 'X', 'S', 'I', 'M', 'T', 'R'};

// Limits that a header must respect; anything beyond is treated as corruption, so a damaged
// length can never make the reader allocate more than these bounds allow.
inline constexpr uint32_t kTraceMaxRecordSize = 4096;
inline constexpr uint32_t kTraceMaxFields = 256;
inline constexpr uint32_t kTraceMaxTextures = 65536;
inline constexpr uint32_t kTraceMaxTextureSize = 65536;
inline constexpr uint32_t kTraceMaxNameBytes = 256;
inline constexpr uint32_t kTraceMaxSourceBytes = 4096;
inline constexpr uint32_t kTraceMaxStorageBytes = 256;
inline constexpr uint32_t kTraceMaxSamplers = 65535;  // a record's `sampler` is a u16
inline constexpr uint32_t kTraceMaxHeaderBytes = 16u << 20;
inline constexpr uint32_t kTraceMaxRecordsPerChunk = 1u << 24;
inline constexpr uint64_t kTraceMaxChunkBytes = 256u << 20;
inline constexpr uint32_t kTraceFieldNameBytes = 16;  // fixed-size, NUL-padded name in the layout

// Type codes of the field layout (FORMAT.md, "Type codes").
enum class TraceType : uint32_t {
  U8 = 1,
  U16 = 2,
  U32 = 3,
  U64 = 4,
  I8 = 5,
  I16 = 6,
  I32 = 7,
  I64 = 8,
  F32 = 9,
  F64 = 10,
};
const char* to_string(TraceType t);
uint32_t type_size(TraceType t);  // bytes; 0 for a code that is not a TraceType
bool is_valid_type_code(uint32_t code);

enum class TraceEncoding { Binary, Csv };

// Closes a stdio file when its owner goes away (also when a constructor throws).
struct TraceFileCloser {
  void operator()(std::FILE* f) const;
};
using TraceFilePtr = std::unique_ptr<std::FILE, TraceFileCloser>;
// Opens an existing regular file for reading, or throws InputError(path, why).
TraceFilePtr open_trace_input(const std::string& path, uint64_t* size = nullptr);

struct TraceField {
  std::string name;
  TraceType type = TraceType::U32;
  uint32_t offset = 0;  // binary: byte offset inside the record; CSV: 0-based column index
};

struct TraceTexture {
  uint32_t id;
  std::string name;
  std::string source;  // file path or procedural spec, e.g. "procedural:checker?size=512&cells=16"
  uint32_t width, height;
  // How the texture is stored once loaded (version 3): "" as loaded, "format=NAME" or
  // "compress=FORMAT,ENCODER[,QUALITY]". The trace checks only its kind (the prefix); the
  // names are the scene's and are checked where the texture is loaded.
  std::string storage = {};
};

// One entry of the sampler table (version 5; FORMAT.md "Sampler table"): the state of a
// scene's `[samplers.NAME]` as codes in the order of the name tables below. Entry k has the id
// k + 1 that a record's `sampler` field names (0 = the record's material's own sampler).
struct TraceSampler {
  std::string name;
  uint8_t mode = 1;                                     // kTraceFilterNames
  uint8_t address_u = 0, address_v = 0, address_w = 0;  // kTraceAddressNames
  // Border colour kind: 0 float (border, linear RGBA; the named VkBorderColor FLOAT_* are
  // (0,0,0,0), (0,0,0,1), (1,1,1,1)); 1 integer (INT_*), which the reader refuses: texsim has
  // no integer texture format.
  uint8_t border_kind = 0;
  float border[4] = {0, 0, 0, 0};
  uint8_t compare = 0;    // kTraceCompareNames
  uint8_t reduction = 0;  // kTraceReductionNames
  uint8_t aniso = 0;      // kTraceAnisoNames
  uint8_t max_aniso = 16;
  float lod_bias = 0, min_lod = 0, max_lod = 1000;
  uint8_t unnormalized = 0, seamless = 1;
  uint8_t sub_texel_bits = 8, mipmap_bits = 8;
  bool operator==(const TraceSampler&) const = default;
};
inline constexpr std::string_view kTraceFilterNames[] = {"nearest", "bilinear", "trilinear"};
inline constexpr std::string_view kTraceAddressNames[] = {"wrap", "clamp", "mirror", "border",
                                                          "mirror_clamp"};
inline constexpr std::string_view kTraceCompareNames[] = {
    "none",  "never", "less", "equal", "less_or_equal", "greater", "not_equal", "greater_or_equal",
    "always"};
inline constexpr std::string_view kTraceReductionNames[] = {"weighted_average", "min", "max"};
inline constexpr std::string_view kTraceAnisoNames[] = {"isotropic", "vulkan"};
// What is wrong with sampler entry s (codes in range, finite LOD values, min_lod <= max_lod,
// flags 0/1, bits 1..16, max_aniso 1..16, a float border; name 1..256 bytes without control
// characters); "" when valid. The sampler's own rules (unnormalised restrictions, comparison
// with a min/max reduction) are checked where it becomes the unit's state.
std::string check_sampler(const TraceSampler& s);
// Checks a header's sampler table; throws InputError(where, "sampler table entry <id> ('<name>'):
// …").
void validate_samplers(const std::vector<TraceSampler>& samplers, const std::string& where);

struct TraceHeader {
  uint32_t version = kTraceVersion;  // read: the file's; write: ignored unless unknown
  bool has_lod_bias = false;
  bool has_view = false;  // records carry the view vector (version 2 or later)
  // Records carry the version-4 operation fields: written, all of them; read, some of them
  // (op_fields, a bit per field of kOpFieldNames).
  bool has_ops = false;
  uint32_t op_fields = 0;
  std::vector<TraceTexture> textures;
  // The sampler table (version 5); empty: the trace carries none (ids index the scene's).
  std::vector<TraceSampler> samplers;
  // Layout info, filled in by TraceReader. Writers always write the canonical layout for
  // has_lod_bias (canonical_fields()) and ignore these.
  TraceEncoding encoding = TraceEncoding::Binary;
  uint32_t record_size = 0;        // binary only
  uint32_t records_per_chunk = 0;  // most records in one chunk (CSV: records per next_chunk)
  std::vector<TraceField> fields;  // every field/column of the input, known or skipped

  const TraceTexture* find_texture(uint32_t id) const;
};

// The fields every trace carries, then the optional ones (name, type).
struct TraceFieldSpec {
  std::string_view name;
  TraceType type;
  bool required;
};
const std::vector<TraceFieldSpec>& trace_field_specs();
// Canonical binary layout written by TraceWriter (packed, in trace_field_specs() order).
std::vector<TraceField> canonical_fields(bool has_lod_bias, bool has_view = false,
                                         bool has_ops = false);
uint32_t canonical_record_size(bool has_lod_bias, bool has_view = false, bool has_ops = false);
// The version-4 operation fields, in trace_field_specs() order after the view vector; bit k
// of TraceHeader::op_fields is kOpFieldNames[k].
inline constexpr size_t kFirstOpField = 15;
inline constexpr std::string_view kOpFieldNames[] = {
    "w",       "dwdx", "dwdy",        "layer",    "lod",      "compare_ref",
    "sampler", "op",   "gather_comp", "offset_u", "offset_v", "offset_w"};
inline constexpr uint32_t kAllOpFields = (1u << 12) - 1;
// Checks a fragment's operation fields, of which `present` (bits as op_fields) are in the
// trace: finite values, a known op, a gather component 0..3, offsets in −8..7, and the fields
// the operation needs (op "lod" the lod, op "gather" the gather_comp). Empty when valid.
std::string check_operation(const Fragment& f, uint32_t present);
// The version a writer writes: 5 with a sampler table, 4 with the operation fields, 3 when
// some texture has a storage, else 2 with the view vector, else 1.
uint32_t written_version(bool has_view, const std::vector<TraceTexture>& textures,
                         bool has_ops = false, bool has_samplers = false);
// Throws InputError(where, ...) unless a writer can write `version` (1..kTraceVersion).
void check_writable_version(uint32_t version, const std::string& where);

// Checks a header's texture table (count, unique ids, sizes, name/source/storage lengths and
// characters, the storage's kind); throws InputError(where, ...) naming the entry.
void validate_textures(const std::vector<TraceTexture>& textures, const std::string& where);

// Texture ids of a header, for the per-record "id is in the table" check.
class TextureIdSet {
 public:
  TextureIdSet() = default;
  explicit TextureIdSet(const std::vector<TraceTexture>& textures);
  bool contains(uint32_t id) const;

 private:
  std::vector<uint32_t> sorted_;
  std::vector<uint8_t> dense_;  // used when ids are small: dense_[id] != 0
};

// Checks one fragment (finite coordinates/derivatives/lod_bias, with has_view a finite,
// non-zero view vector, texture id in the table); returns an empty string when it is valid,
// else what is wrong.
std::string check_fragment(const Fragment& f, const TextureIdSet& ids, bool has_lod_bias,
                           bool has_view = false);

// Binary trace writer; writes to a temporary name and renames on close() (no half-written
// file). The destructor without close() removes the temporary file.
class TraceWriter {
 public:
  TraceWriter(const std::string& path, const TraceHeader& header,
              uint32_t records_per_chunk = 4096);
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  void write(const Fragment& f);  // throws InputError for a NaN/Inf value or unknown texture id
  void close();
  uint64_t records_written() const { return records_; }

 private:
  void flush_chunk();
  void put(const void* data, size_t n);
  [[noreturn]] void fail(const std::string& what);

  std::string path_, temp_;
  TraceFilePtr file_;
  bool has_lod_bias_ = false;
  bool has_view_ = false;
  bool has_ops_ = false;
  uint32_t record_size_ = 0;
  uint32_t records_per_chunk_ = 0;
  TextureIdSet ids_;
  std::vector<unsigned char> chunk_;  // records_per_chunk_ * record_size_ bytes
  uint32_t in_chunk_ = 0;
  uint64_t chunks_ = 0;
  uint64_t records_ = 0;
  bool closed_ = false;
};

class TraceCsvReader;

// Streaming reader of a binary (.trc) trace or its CSV form. A file that starts with the magic
// is binary; otherwise a name ending in .csv is read as CSV; anything else is "bad magic".
class TraceReader {
 public:
  explicit TraceReader(const std::string& path);
  ~TraceReader();
  TraceReader(const TraceReader&) = delete;
  TraceReader& operator=(const TraceReader&) = delete;

  const TraceHeader& header() const { return header_; }
  // Replaces `out` with the next chunk's fragments (CSV: up to records_per_chunk lines) and
  // returns their count; 0 at the end, after the trailer has been checked.
  size_t next_chunk(std::vector<Fragment>& out);
  uint64_t records_read() const { return records_; }
  uint64_t chunks_read() const { return chunks_; }
  const std::string& path() const { return path_; }

 private:
  void open_binary();
  void read_exact(void* dst, size_t n, const std::string& where, const char* what);
  size_t next_binary_chunk(std::vector<Fragment>& out);
  void check_trailer();
  std::string chunk_where() const;
  std::string record_where(uint32_t r) const;

  std::string path_;
  TraceHeader header_;
  std::unique_ptr<TraceCsvReader> csv_;
  TraceFilePtr file_;
  uint64_t file_size_ = 0;
  uint64_t pos_ = 0;
  bool done_ = false;
  uint64_t chunks_ = 0;
  uint64_t records_ = 0;
  std::vector<unsigned char> payload_;
  TextureIdSet ids_;
  // Byte offsets of the known fields in a record, in trace_field_specs() order (-1 = absent).
  std::vector<int64_t> offsets_;
};

// Writes a whole trace, binary or CSV by the extension of `path` (".csv" = CSV).
void write_trace(const std::string& path, const TraceHeader& header,
                 const std::vector<Fragment>& fragments);
// Reads a whole trace into memory (for small traces and tests; pipelines stream instead).
std::vector<Fragment> read_trace(const std::string& path, TraceHeader* header = nullptr);

bool has_csv_extension(const std::string& path);

}  // namespace texsim
