// Binary trace format v1 (traces/FORMAT.md): round trips, streaming memory, and every kind of
// bad input. Corrupt files are made by an independent byte builder that follows FORMAT.md, so
// the writer, the reader and the document are checked against each other.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "testbench/lib/temp_dir.h"
#include "traces/trace_file.h"

// Every operator new of this test program is counted (live bytes and their peak), however it
// is served (brk or mmap), so a reader that kept records would show their full size.
namespace {
std::atomic<size_t> g_live{0};
std::atomic<size_t> g_peak{0};
constexpr size_t kAllocHeader = alignof(std::max_align_t);

void* counted_alloc(size_t n) {
  auto* p = static_cast<unsigned char*>(std::malloc(n + kAllocHeader));
  if (!p) throw std::bad_alloc();
  std::memcpy(p, &n, sizeof n);
  const size_t live = g_live.fetch_add(n) + n;
  size_t peak = g_peak.load();
  while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {
  }
  return p + kAllocHeader;
}
void counted_free(void* q) noexcept {
  if (!q) return;
  unsigned char* p = static_cast<unsigned char*>(q) - kAllocHeader;
  size_t n = 0;
  std::memcpy(&n, p, sizeof n);
  g_live.fetch_sub(n);
  std::free(p);
}
}  // namespace

void* operator new(size_t n) { return counted_alloc(n); }
void* operator new[](size_t n) { return counted_alloc(n); }
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, size_t) noexcept { counted_free(p); }
void operator delete[](void* p, size_t) noexcept { counted_free(p); }

namespace texsim {
namespace {

namespace fs = std::filesystem;

// ---- helpers ---------------------------------------------------------------------------------

bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}
bool same_bits(float a, float b) {
  return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
}

::testing::AssertionResult same_fragment(const Fragment& a, const Fragment& b) {
  const bool ok = a.frame == b.frame && a.prim == b.prim && a.x == b.x && a.y == b.y &&
                  a.tex == b.tex && same_bits(a.u, b.u) && same_bits(a.v, b.v) &&
                  same_bits(a.dudx, b.dudx) && same_bits(a.dvdx, b.dvdx) &&
                  same_bits(a.dudy, b.dudy) && same_bits(a.dvdy, b.dvdy) &&
                  same_bits(a.lod_bias, b.lod_bias) && same_bits(a.view_x, b.view_x) &&
                  same_bits(a.view_y, b.view_y) && same_bits(a.view_z, b.view_z);
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "fragments differ: frame " << a.frame << "/" << b.frame << " u " << a.u << "/" << b.u
         << " dvdy " << a.dvdy << "/" << b.dvdy << " lod_bias " << a.lod_bias << "/" << b.lod_bias;
}

// Finite doubles that stress an exact round trip: signed zeros, subnormals, extremes, and
// arbitrary bit patterns.
double hard_double(std::mt19937_64& rng) {
  static const double special[] = {0.0,
                                   -0.0,
                                   std::numeric_limits<double>::denorm_min(),
                                   -std::numeric_limits<double>::denorm_min(),
                                   std::numeric_limits<double>::min(),
                                   std::numeric_limits<double>::max(),
                                   std::numeric_limits<double>::lowest(),
                                   1e-300,
                                   0.1,
                                   1.0 / 3.0,
                                   0.5};
  const uint64_t pick = rng() % 4;
  if (pick == 0) return special[rng() % std::size(special)];
  if (pick == 1) {
    double d;
    do d = std::bit_cast<double>(rng());
    while (!std::isfinite(d));
    return d;
  }
  return std::uniform_real_distribution<double>(-4.0, 4.0)(rng);
}

std::vector<Fragment> random_fragments(size_t n, bool lod, const std::vector<uint32_t>& tex_ids,
                                       uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Fragment> out(n);
  for (size_t i = 0; i < n; ++i) {
    Fragment& f = out[i];
    f.frame = static_cast<uint32_t>(i / 100);
    f.prim = static_cast<uint32_t>(rng());
    f.x = static_cast<uint32_t>(rng());
    f.y = static_cast<uint32_t>(rng() % 4096);
    f.tex = tex_ids[rng() % tex_ids.size()];
    f.u = hard_double(rng);
    f.v = hard_double(rng);
    f.dudx = hard_double(rng);
    f.dvdx = hard_double(rng);
    f.dudy = hard_double(rng);
    f.dvdy = hard_double(rng);
    if (lod) {
      float b;
      do b = std::bit_cast<float>(static_cast<uint32_t>(rng()));
      while (!std::isfinite(b));
      f.lod_bias = (i % 3 == 0) ? b : static_cast<float>(i % 7) * 0.25f - 1.0f;
    }
  }
  return out;
}

TraceHeader sample_header(bool lod) {
  TraceHeader h;
  h.has_lod_bias = lod;
  h.textures = {{0, "checker", "procedural:checker?size=512&cells=16", 512, 512},
                {7, "bricks wall", "textures/bricks 256.png", 256, 128},
                {1000000, "big", "", 65536, 1}};
  return h;
}

std::vector<Fragment> read_all(const std::string& path, TraceHeader* h = nullptr) {
  return read_trace(path, h);
}

std::vector<unsigned char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

// Expects `fn` to throw InputError whose message contains every one of `parts`.
template <class Fn>
void expect_input_error(Fn&& fn, const std::vector<std::string>& parts) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts) {
      EXPECT_NE(msg.find(p), std::string::npos) << "message lacks \"" << p << "\": " << msg;
    }
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-InputError: " << e.what();
    return;
  }
  ADD_FAILURE() << "no InputError thrown; expected one mentioning \"" << parts.back() << "\"";
}

// ---- independent byte builder following FORMAT.md ------------------------------------------

struct Bytes {
  std::vector<unsigned char> b;
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void raw(const std::string& s) { b.insert(b.end(), s.begin(), s.end()); }
  void raw(const std::vector<unsigned char>& s) { b.insert(b.end(), s.begin(), s.end()); }
};

uint32_t crc(const unsigned char* p, size_t n) {
  return static_cast<uint32_t>(::crc32(0L, p, static_cast<uInt>(n)));
}

struct FieldDef {
  std::string name;
  uint32_t type;  // FORMAT.md type code
  uint32_t offset;
};

std::vector<FieldDef> doc_layout(bool lod) {
  // FORMAT.md "Canonical layout": packed, 5 x u32 then 6 x f64 then optional f32.
  std::vector<FieldDef> f = {{"frame", 3, 0},  {"prim", 3, 4},   {"x", 3, 8},     {"y", 3, 12},
                             {"tex", 3, 16},   {"u", 10, 20},    {"v", 10, 28},   {"dudx", 10, 36},
                             {"dvdx", 10, 44}, {"dudy", 10, 52}, {"dvdy", 10, 60}};
  if (lod) f.push_back({"lod_bias", 9, 68});
  return f;
}

struct FileSpec {
  uint32_t version = 1;
  uint32_t record_size = 72;
  uint32_t records_per_chunk = 4096;
  std::vector<FieldDef> fields = doc_layout(true);
  std::vector<TraceTexture> textures = {
      {0, "checker", "procedural:checker?size=64&cells=8", 64, 64},
      {3, "noise", "procedural:noise", 32, 16}};
  int64_t header_size_override = -1;  // write this header size instead of the true one
  uint32_t field_count_override = 0;
  uint32_t texture_count_override = 0;
};

std::vector<unsigned char> build_header(const FileSpec& s) {
  Bytes h;
  h.raw("TEXSIMTR");
  h.u32(s.version);
  h.u32(0);  // header size, patched
  h.u32(s.record_size);
  h.u32(s.records_per_chunk);
  h.u32(s.field_count_override ? s.field_count_override : static_cast<uint32_t>(s.fields.size()));
  h.u32(s.texture_count_override ? s.texture_count_override
                                 : static_cast<uint32_t>(s.textures.size()));
  for (const FieldDef& f : s.fields) {
    std::string name = f.name;
    name.resize(16, '\0');
    h.raw(name);
    h.u32(f.type);
    h.u32(f.offset);
  }
  for (const TraceTexture& t : s.textures) {
    h.u32(t.id);
    h.u32(t.width);
    h.u32(t.height);
    h.u32(static_cast<uint32_t>(t.name.size()));
    h.u32(static_cast<uint32_t>(t.source.size()));
    h.raw(t.name);
    h.raw(t.source);
    if (s.version >= 3) {  // version 3: the storage, length-prefixed
      h.u32(static_cast<uint32_t>(t.storage.size()));
      h.raw(t.storage);
    }
  }
  const uint32_t size = s.header_size_override >= 0 ? static_cast<uint32_t>(s.header_size_override)
                                                    : static_cast<uint32_t>(h.b.size() + 4);
  for (int i = 0; i < 4; ++i)
    h.b[12 + static_cast<size_t>(i)] = static_cast<unsigned char>(size >> (8 * i));
  h.u32(crc(h.b.data(), h.b.size()));
  return h.b;
}

std::vector<unsigned char> encode_record(const Fragment& f, const FileSpec& s) {
  std::vector<unsigned char> r(s.record_size, 0xAB);  // unknown fields keep this filler
  auto put = [&](uint32_t off, const void* p, size_t n) { std::memcpy(r.data() + off, p, n); };
  for (const FieldDef& d : s.fields) {
    const std::string& n = d.name;
    const uint32_t u = n == "frame"  ? f.frame
                       : n == "prim" ? f.prim
                       : n == "x"    ? f.x
                       : n == "y"    ? f.y
                                     : f.tex;
    const double v = n == "u"      ? f.u
                     : n == "v"    ? f.v
                     : n == "dudx" ? f.dudx
                     : n == "dvdx" ? f.dvdx
                     : n == "dudy" ? f.dudy
                                   : f.dvdy;
    if (n == "frame" || n == "prim" || n == "x" || n == "y" || n == "tex") {
      put(d.offset, &u, 4);  // the test host is little-endian, as the format
    } else if (n == "u" || n == "v" || n == "dudx" || n == "dvdx" || n == "dudy" || n == "dvdy") {
      put(d.offset, &v, 8);
    } else if (n == "lod_bias") {
      put(d.offset, &f.lod_bias, 4);
    } else if (n == "view_x") {
      put(d.offset, &f.view_x, 4);
    } else if (n == "view_y") {
      put(d.offset, &f.view_y, 4);
    } else if (n == "view_z") {
      put(d.offset, &f.view_z, 4);
    }
  }
  return r;
}

std::vector<unsigned char> build_chunk(const std::vector<Fragment>& frags, const FileSpec& s) {
  Bytes payload;
  for (const Fragment& f : frags) payload.raw(encode_record(f, s));
  Bytes c;
  c.raw("CHNK");
  c.u32(static_cast<uint32_t>(frags.size()));
  c.u32(crc(payload.b.data(), payload.b.size()));
  c.raw(payload.b);
  return c.b;
}

std::vector<unsigned char> build_trailer(uint64_t chunks, uint64_t records) {
  Bytes body;
  body.u64(chunks);
  body.u64(records);
  Bytes t;
  t.raw("TEND");
  t.u32(crc(body.b.data(), body.b.size()));
  t.raw(body.b);
  return t.b;
}

// A whole valid file: `chunks` chunks of `per_chunk` fragments using textures 0 and 3.
std::vector<unsigned char> build_file(const FileSpec& s, size_t chunks, size_t per_chunk,
                                      std::vector<Fragment>* frags_out = nullptr) {
  std::vector<unsigned char> out = build_header(s);
  const auto frags = random_fragments(chunks * per_chunk, true, {0, 3}, 42);
  for (size_t c = 0; c < chunks; ++c) {
    const std::vector<Fragment> part(frags.begin() + static_cast<long>(c * per_chunk),
                                     frags.begin() + static_cast<long>((c + 1) * per_chunk));
    const auto chunk = build_chunk(part, s);
    out.insert(out.end(), chunk.begin(), chunk.end());
  }
  const auto t = build_trailer(chunks, chunks * per_chunk);
  out.insert(out.end(), t.begin(), t.end());
  if (frags_out != nullptr) *frags_out = frags;
  return out;
}

// ---- round trips -------------------------------------------------------------------------------

TEST(TraceFile, RoundTripWithLodBiasManyChunks) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("many.trc");
  const TraceHeader h = sample_header(true);
  const auto frags = random_fragments(10007, true, {0, 7, 1000000}, 1);
  {
    TraceWriter w(path, h, 97);  // 104 chunks, the last one partial
    for (const Fragment& f : frags) w.write(f);
    w.close();
    EXPECT_EQ(w.records_written(), frags.size());
  }
  TraceReader r(path);
  EXPECT_EQ(r.header().version, 1u);
  EXPECT_TRUE(r.header().has_lod_bias);
  EXPECT_EQ(r.header().record_size, 72u);
  EXPECT_EQ(r.header().records_per_chunk, 97u);
  ASSERT_EQ(r.header().textures.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.header().textures[i].id, h.textures[i].id);
    EXPECT_EQ(r.header().textures[i].name, h.textures[i].name);
    EXPECT_EQ(r.header().textures[i].source, h.textures[i].source);
    EXPECT_EQ(r.header().textures[i].width, h.textures[i].width);
    EXPECT_EQ(r.header().textures[i].height, h.textures[i].height);
  }
  std::vector<Fragment> chunk;
  size_t i = 0, chunks = 0;
  while (size_t n = r.next_chunk(chunk)) {
    EXPECT_LE(n, 97u);
    EXPECT_EQ(n, chunk.size());
    for (const Fragment& f : chunk) ASSERT_TRUE(same_fragment(f, frags[i++])) << "record " << i - 1;
    ++chunks;
  }
  EXPECT_EQ(i, frags.size());
  EXPECT_EQ(chunks, (frags.size() + 96) / 97);
  EXPECT_EQ(r.next_chunk(chunk), 0u);  // stays at the end
  EXPECT_TRUE(chunk.empty());
}

TEST(TraceFile, RoundTripWithoutLodBias) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("nolod.trc");
  auto frags = random_fragments(5000, false, {0, 7}, 2);
  write_trace(path, sample_header(false), frags);
  TraceHeader h;
  const auto back = read_all(path, &h);
  EXPECT_FALSE(h.has_lod_bias);
  EXPECT_EQ(h.record_size, 68u);
  ASSERT_EQ(back.size(), frags.size());
  for (size_t i = 0; i < frags.size(); ++i) ASSERT_TRUE(same_fragment(back[i], frags[i]));
  // Exact file size: header + 2 chunks of 4096/904 records + trailer (FORMAT.md).
  const uint64_t header = 32 + 11 * 24 + 3 * 20 + (7 + 36) + (11 + 23) + 3 + 4;
  EXPECT_EQ(fs::file_size(path), header + uint64_t{2} * 12 + uint64_t{5000} * 68 + 24);
}

TEST(TraceFile, EmptyTraceRoundTrips) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("empty.trc");
  write_trace(path, sample_header(true), {});
  TraceReader r(path);
  std::vector<Fragment> chunk{Fragment{}};
  EXPECT_EQ(r.next_chunk(chunk), 0u);
  EXPECT_TRUE(chunk.empty());
  EXPECT_EQ(r.records_read(), 0u);
}

TEST(TraceFile, WriterOutputMatchesTheDocumentedBytes) {
  // The builder above encodes FORMAT.md independently; the writer must produce the same bytes.
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 5;
  std::vector<Fragment> frags;
  const auto expected = build_file(s, 3, 5, &frags);
  TraceHeader h;
  h.has_lod_bias = true;
  h.textures = s.textures;
  const std::string path = dir.file("doc.trc");
  TraceWriter w(path, h, 5);
  for (const Fragment& f : frags) w.write(f);
  w.close();
  EXPECT_EQ(slurp(path), expected);
}

TEST(TraceFile, UnknownExtraFieldsAreSkippedAndOrderIsFree) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  // Fields in another order with unknown ones ("depth" f32, "normal_x" f64) in between.
  s.fields = {{"depth", 9, 0},  {"dvdy", 10, 4},      {"tex", 3, 12},   {"u", 10, 16},
              {"v", 10, 24},    {"normal_x", 10, 32}, {"frame", 3, 40}, {"prim", 3, 44},
              {"x", 3, 48},     {"y", 3, 52},         {"dudx", 10, 56}, {"dvdx", 10, 64},
              {"dudy", 10, 72}, {"lod_bias", 9, 80}};
  s.record_size = 96;  // with 12 trailing padding bytes
  std::vector<Fragment> frags;
  const std::string path = dir.file("extra.trc");
  spit(path, build_file(s, 2, 10, &frags));
  TraceHeader h;
  const auto back = read_all(path, &h);
  EXPECT_TRUE(h.has_lod_bias);
  EXPECT_EQ(h.fields.size(), 14u);
  ASSERT_EQ(back.size(), frags.size());
  for (size_t i = 0; i < frags.size(); ++i) ASSERT_TRUE(same_fragment(back[i], frags[i]));
}

// Heap bytes in use (glibc), to show that reading does not grow with the trace length.
// Peak of the bytes allocated by operator new while the whole trace is streamed, above what
// was live when streaming began.
size_t peak_heap_while_streaming(const std::string& path, uint64_t* records) {
  const size_t base = g_live.load();
  g_peak.store(base);
  {
    TraceReader r(path);
    std::vector<Fragment> chunk;
    while (r.next_chunk(chunk) > 0) {
    }
    *records = r.records_read();
  }
  return g_peak.load() - base;
}

// The measurement sees what it is meant to: holding the records of a 400,000-record trace
// shows up as their full size.
TEST(TraceFile, HeapMeasureSeesLargeAllocations) {
  const size_t base = g_live.load();
  g_peak.store(base);
  {
    std::vector<Fragment> kept(400000);
    kept[123].u = 1;
  }
  EXPECT_GE(g_peak.load() - base, 400000 * sizeof(Fragment));
}

TEST(TraceFile, StreamingMemoryDoesNotDependOnLength) {
  TempDir dir("texsim_trace_file");
  const TraceHeader h = sample_header(true);
  const std::string small = dir.file("small.trc"), large = dir.file("large.trc");
  for (const auto& [path, n] :
       {std::pair{small, size_t{20000}}, std::pair{large, size_t{400000}}}) {
    TraceWriter w(path, h, 1024);
    const auto frags = random_fragments(1000, true, {0}, 3);
    for (size_t i = 0; i < n; ++i) w.write(frags[i % frags.size()]);
    w.close();
  }
  uint64_t n_small = 0, n_large = 0;
  const size_t peak_small = peak_heap_while_streaming(small, &n_small);
  const size_t peak_large = peak_heap_while_streaming(large, &n_large);
  EXPECT_EQ(n_small, 20000u);
  EXPECT_EQ(n_large, 400000u);
  // One chunk of records (1024 x 72 bytes) plus one chunk of Fragments (1024 x 72 bytes) plus
  // the reader's own state; a reader that kept records would need 28.8 MB for the large file.
  const size_t bound = size_t{2} * 1024 * sizeof(Fragment) + size_t{64} * 1024;
  EXPECT_GT(peak_small, size_t{1024} * sizeof(Fragment));  // the chunk itself is seen
  EXPECT_LT(peak_small, bound);
  EXPECT_LT(peak_large, bound);
  EXPECT_LT(peak_large > peak_small ? peak_large - peak_small : 0, 16u * 1024u)
      << "reader memory grew with the trace length: " << peak_small << " vs " << peak_large;
}

// ---- bad input: files and headers --------------------------------------------------------------

TEST(TraceFileErrors, MissingFile) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("nope.trc");
  expect_input_error([&] { TraceReader r(path); }, {path, "no such file"});
}

TEST(TraceFileErrors, Directory) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("");
  expect_input_error([&] { TraceReader r(path); }, {path, "is a directory"});
}

TEST(TraceFileErrors, BadMagic) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("text.trc");
  spit(path,
       std::vector<unsigned char>{'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd', '\n'});
  expect_input_error([&] { TraceReader r(path); }, {path, "header", "bad magic"});
  const std::string empty = dir.file("empty.trc");
  spit(empty, {});
  expect_input_error([&] { TraceReader r(empty); }, {empty, "bad magic"});
}

// Writes the header of `s` plus a valid end marker and expects the reader to reject it.
void expect_header_error(const FileSpec& s, const std::vector<std::string>& parts) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("bad_header.trc");
  auto bytes = build_header(s);
  const auto t = build_trailer(0, 0);
  bytes.insert(bytes.end(), t.begin(), t.end());
  spit(path, bytes);
  std::vector<std::string> all = {path, "header"};
  all.insert(all.end(), parts.begin(), parts.end());
  expect_input_error([&] { read_all(path); }, all);
}

TEST(TraceFileErrors, UnknownVersion) {
  FileSpec s;
  s.version = 6;
  expect_header_error(s, {"unknown version 6", "reads versions 1..5"});
  s.version = 0;
  expect_header_error(s, {"unknown version 0"});
}

TEST(TraceFileErrors, AbsurdRecordSize) {
  FileSpec s;
  s.record_size = 0;
  expect_header_error(s, {"record size 0"});
  s.record_size = 4097;
  expect_header_error(s, {"record size 4097"});
}

TEST(TraceFileErrors, AbsurdRecordsPerChunk) {
  FileSpec s;
  s.records_per_chunk = 0;
  expect_header_error(s, {"records per chunk 0"});
  s.records_per_chunk = (1u << 24) + 1;
  expect_header_error(s, {"records per chunk 16777217"});
  s.records_per_chunk = 1u << 24;  // 16M x 72 bytes > 256 MiB per chunk
  expect_header_error(s, {"chunk size"});
}

TEST(TraceFileErrors, AbsurdCounts) {
  FileSpec s;
  s.texture_count_override = 65537;
  expect_header_error(s, {"texture count 65537"});
  FileSpec f;
  f.field_count_override = 100000;
  expect_header_error(f, {"field count 100000"});
  FileSpec z;
  z.fields.clear();
  expect_header_error(z, {"field count 0"});
}

TEST(TraceFileErrors, AbsurdHeaderSizeDoesNotAllocate) {
  FileSpec s;
  s.header_size_override = int64_t{1} << 31;
  expect_header_error(s, {"header size 2147483648"});
  s.header_size_override = 100;  // smaller than its own field table
  expect_header_error(s, {"header size 100"});
  // A header size within limits but past the end of the file: truncated, not allocated blindly.
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("short.trc");
  FileSpec big;
  big.header_size_override = 8u << 20;
  spit(path, build_header(big));
  expect_input_error([&] { TraceReader r(path); }, {path, "header", "truncated"});
}

TEST(TraceFileErrors, TextureSizes) {
  FileSpec s;
  s.textures[1].width = 65537;
  expect_header_error(s, {"texture entry 1", "65537x16"});
  s.textures[1].width = 0;
  expect_header_error(s, {"texture entry 1", "0x16"});
  FileSpec d;
  d.textures[1].id = 0;
  expect_header_error(d, {"texture id 0 appears twice"});
  FileSpec n;
  n.textures[0].name = std::string(300, 'a');
  expect_header_error(n, {"texture entry 0", "name length 300"});
}

TEST(TraceFileErrors, HeaderCrcMismatch) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("crc_header.trc");
  auto bytes = build_file(FileSpec{}, 1, 3);
  bytes[32 + 12 * 24 + 20 + 2] ^= 0x20;  // a letter of the first texture's name
  spit(path, bytes);
  expect_input_error([&] { TraceReader r(path); }, {path, "header", "header CRC mismatch"});
}

TEST(TraceFileErrors, LayoutProblems) {
  FileSpec missing;
  missing.fields.erase(missing.fields.begin() + 10);  // dvdy
  expect_header_error(missing, {"missing required field 'dvdy'"});
  FileSpec type;
  type.fields[5].type = 9;  // u as f32
  expect_header_error(type, {"field 'u' has type f32, expected f64"});
  FileSpec code;
  code.fields[2].type = 77;
  expect_header_error(code, {"field 2", "unknown type code 77"});
  FileSpec past;
  past.fields[11].offset = 70;  // lod_bias past the 72-byte record
  expect_header_error(past, {"field 11", "runs past the record size"});
  FileSpec overlap;
  overlap.fields[6].offset = 24;  // v overlaps u
  expect_header_error(overlap, {"field 6", "overlaps field 'u'"});
  FileSpec twice;
  twice.fields[11].name = "x";
  twice.fields[11].type = 3;
  expect_header_error(twice, {"field 11", "'x' appears twice"});
}

// ---- bad input: chunks, records, trailer ------------------------------------------------------

TEST(TraceFileErrors, TruncatedAtEveryByte) {
  // Cut a valid 3-chunk file at every length: the reader must report it, never crash or hang.
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  const auto bytes = build_file(s, 3, 4);
  const std::string path = dir.file("cut.trc");
  for (size_t len = 0; len < bytes.size(); ++len) {
    spit(path, std::vector<unsigned char>(bytes.begin(), bytes.begin() + static_cast<long>(len)));
    SCOPED_TRACE("cut at " + std::to_string(len) + " of " + std::to_string(bytes.size()));
    expect_input_error([&] { read_all(path); }, {path, len < 8 ? "bad magic" : "truncated"});
  }
  spit(path, bytes);
  EXPECT_EQ(read_all(path).size(), 12u);
}

TEST(TraceFileErrors, MissingEndMarkerNamesTheChunk) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  auto bytes = build_file(s, 3, 4);
  bytes.resize(bytes.size() - 24);
  const std::string path = dir.file("noend.trc");
  spit(path, bytes);
  expect_input_error([&] { read_all(path); },
                     {path, "chunk 3", "truncated", "without the end marker"});
}

TEST(TraceFileErrors, ChunkCrcMismatch) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  auto bytes = build_file(s, 3, 4);
  const size_t hs = build_header(s).size();
  bytes[hs + (12 + 4 * 72) + 12 + 30] ^= 0x01;  // a payload byte of chunk 1
  const std::string path = dir.file("crc.trc");
  spit(path, bytes);
  TraceReader r(path);
  std::vector<Fragment> chunk;
  EXPECT_EQ(r.next_chunk(chunk), 4u);  // chunk 0 is fine
  expect_input_error([&] { r.next_chunk(chunk); }, {path, "chunk 1", "CRC mismatch"});
}

TEST(TraceFileErrors, ChunkCountsAndTags) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  const auto good = build_file(s, 2, 4);
  const size_t hs = build_header(s).size();
  const std::string path = dir.file("count.trc");
  auto patch_u32 = [](std::vector<unsigned char> b, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i)
      b[at + static_cast<size_t>(i)] = static_cast<unsigned char>(v >> (8 * i));
    return b;
  };
  spit(path, patch_u32(good, hs + 4, 5));
  expect_input_error([&] { read_all(path); }, {path, "chunk 0", "record count 5 exceeds"});
  spit(path, patch_u32(good, hs + 4, 0));
  expect_input_error([&] { read_all(path); }, {path, "chunk 0", "empty chunk"});
  spit(path, patch_u32(good, hs + 12 + size_t{4} * 72, 0x4b4e4843u ^ 0x20u));  // "CHNK" -> "cHNK"
  expect_input_error([&] { read_all(path); }, {path, "chunk 1", "bad chunk tag"});
  // A huge count allowed by a huge records-per-chunk must fail as truncation, not allocate.
  FileSpec wide;
  wide.records_per_chunk = 1u << 20;
  auto w = build_file(wide, 1, 4);
  spit(path, patch_u32(w, build_header(wide).size() + 4, 1u << 20));
  expect_input_error([&] { read_all(path); }, {path, "chunk 0", "truncated chunk"});
}

TEST(TraceFileErrors, NonFiniteValuesNameTheRecord) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  const std::string path = dir.file("nan.trc");
  struct Case {
    const char* field;
    double Fragment::*member;
    double value;
    const char* word;
  };
  const Case cases[] = {
      {"u", &Fragment::u, std::nan(""), "NaN"},
      {"v", &Fragment::v, -std::numeric_limits<double>::infinity(), "infinite"},
      {"dudx", &Fragment::dudx, std::numeric_limits<double>::infinity(), "infinite"},
      {"dvdx", &Fragment::dvdx, std::nan(""), "NaN"},
      {"dudy", &Fragment::dudy, std::nan(""), "NaN"},
      {"dvdy", &Fragment::dvdy, std::numeric_limits<double>::infinity(), "infinite"}};
  for (const Case& c : cases) {
    auto frags = random_fragments(12, true, {0, 3}, 5);
    frags[2 * 4 + 3].*c.member = c.value;  // chunk 2, record 3, trace record 11
    auto bytes = build_header(s);
    for (size_t k = 0; k < 3; ++k) {
      const auto ch = build_chunk(
          {frags.begin() + static_cast<long>(4 * k), frags.begin() + static_cast<long>(4 * k + 4)},
          s);
      bytes.insert(bytes.end(), ch.begin(), ch.end());
    }
    const auto t = build_trailer(3, 12);
    bytes.insert(bytes.end(), t.begin(), t.end());
    spit(path, bytes);
    SCOPED_TRACE(c.field);
    expect_input_error([&] { read_all(path); },
                       {path, "chunk 2, record 3", "trace record 11",
                        std::string("field '") + c.field + "' is " + c.word});
  }
  // lod_bias as well.
  auto frags = random_fragments(4, true, {0}, 6);
  frags[1].lod_bias = std::numeric_limits<float>::quiet_NaN();
  auto bytes = build_header(s);
  const auto ch = build_chunk(frags, s);
  bytes.insert(bytes.end(), ch.begin(), ch.end());
  const auto t = build_trailer(1, 4);
  bytes.insert(bytes.end(), t.begin(), t.end());
  spit(path, bytes);
  expect_input_error([&] { read_all(path); }, {path, "chunk 0, record 1", "'lod_bias' is NaN"});
}

TEST(TraceFileErrors, TextureIdNotInTable) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 8;
  auto frags = random_fragments(8, true, {0, 3}, 7);
  frags[5].tex = 2;  // the table has ids 0 and 3
  auto bytes = build_header(s);
  const auto ch = build_chunk(frags, s);
  bytes.insert(bytes.end(), ch.begin(), ch.end());
  const auto t = build_trailer(1, 8);
  bytes.insert(bytes.end(), t.begin(), t.end());
  const std::string path = dir.file("tex.trc");
  spit(path, bytes);
  expect_input_error([&] { read_all(path); },
                     {path, "chunk 0, record 5", "texture id 2 is not in the texture table"});
}

TEST(TraceFileErrors, EndMarkerProblems) {
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 4;
  const std::string path = dir.file("end.trc");
  auto bytes = build_file(s, 2, 4);
  const size_t end = bytes.size() - 24;
  // Counts that disagree with the file (a chunk was lost).
  auto lost = std::vector<unsigned char>(bytes.begin(), bytes.begin() + static_cast<long>(end));
  const auto t = build_trailer(3, 12);
  lost.insert(lost.end(), t.begin(), t.end());
  spit(path, lost);
  expect_input_error([&] { read_all(path); },
                     {path, "end marker", "3 chunks and 12 records", "2 chunks and 8"});
  // Corrupted trailer.
  auto bad = bytes;
  bad[end + 10] ^= 0xff;
  spit(path, bad);
  expect_input_error([&] { read_all(path); }, {path, "end marker", "CRC mismatch"});
  // Garbage after the trailer.
  auto extra = bytes;
  extra.push_back(0);
  spit(path, extra);
  expect_input_error([&] { read_all(path); }, {path, "1 unexpected bytes after the end marker"});
}

TEST(TraceFileErrors, RandomCorruptionNeverCrashes) {
  // Flip random bytes of a valid file: every outcome is a clean read or an InputError.
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.records_per_chunk = 8;
  const auto good = build_file(s, 4, 8);
  const std::string path = dir.file("fuzz.trc");
  std::mt19937_64 rng(11);
  int errors = 0;
  for (int iter = 0; iter < 1500; ++iter) {
    auto b = good;
    const size_t flips = 1 + rng() % 3;
    std::vector<uint64_t> bits;  // distinct bits, so two flips never cancel out
    while (bits.size() < flips) {
      const uint64_t bit = rng() % (b.size() * 8);
      if (std::find(bits.begin(), bits.end(), bit) == bits.end()) bits.push_back(bit);
    }
    for (uint64_t bit : bits) b[bit / 8] ^= static_cast<unsigned char>(1u << (bit % 8));
    spit(path, b);
    try {
      read_all(path);
    } catch (const InputError& e) {
      ++errors;
      ASSERT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  // Every flip is caught: the header, each chunk and the trailer carry a CRC, and a flipped
  // chunk header breaks a count, a tag or the CRC.
  EXPECT_EQ(errors, 1500);
}

// ---- writer failures -------------------------------------------------------------------------

TEST(TraceWriterFailure, BadRecordLeavesNoFile) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("out.trc");
  {
    TraceWriter w(path, sample_header(true), 16);
    const auto frags = random_fragments(100, true, {0, 7}, 8);
    for (const Fragment& f : frags) w.write(f);  // several chunks already on disk
    Fragment bad = frags[0];
    bad.dudy = std::nan("");
    expect_input_error([&] { w.write(bad); }, {path, "record 100", "'dudy' is NaN"});
    Fragment unknown = frags[0];
    unknown.tex = 3;
    expect_input_error([&] { w.write(unknown); }, {path, "texture id 3"});
  }  // destroyed without close()
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(dir.entries(), 0u) << "temporary file left behind";
}

TEST(TraceWriterFailure, FailedWriteKeepsThePreviousFile) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("keep.trc");
  write_trace(path, sample_header(false), random_fragments(10, false, {0}, 9));
  const auto before = slurp(path);
  {
    TraceWriter w(path, sample_header(false));
    w.write(random_fragments(1, false, {0}, 10)[0]);
  }
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(dir.entries(), 1u);
  auto frags = random_fragments(10, false, {0}, 12);
  frags[9].u = std::numeric_limits<double>::infinity();
  expect_input_error([&] { write_trace(path, sample_header(false), frags); },
                     {path, "record 9", "'u' is infinite"});
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(dir.entries(), 1u);
}

TEST(TraceWriterFailure, UnwritableDestinations) {
  TempDir dir("texsim_trace_file");
  const std::string nodir = dir.file("missing/dir/out.trc");
  expect_input_error([&] { TraceWriter w(nodir, sample_header(true)); },
                     {nodir, "cannot open for writing"});
  EXPECT_FALSE(fs::exists(nodir));
  // The destination is a directory: the rename at close() fails and the temporary goes away.
  const std::string isdir = dir.file("adir");
  fs::create_directory(isdir);
  expect_input_error(
      [&] {
        TraceWriter w(isdir, sample_header(true));
        w.write(random_fragments(1, true, {0}, 13)[0]);
        w.close();
      },
      {isdir, "cannot write output file"});
  EXPECT_TRUE(fs::is_directory(isdir));
  EXPECT_EQ(dir.entries(), 1u);
}

TEST(TraceWriterFailure, BadHeaderOrChunkSizeIsRejectedBeforeWriting) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("h.trc");
  TraceHeader h = sample_header(true);
  h.textures[0].height = 0;
  expect_input_error([&] { TraceWriter w(path, h); }, {path, "texture entry 0", "0 is outside"});
  h = sample_header(true);
  h.textures.push_back(h.textures[1]);
  expect_input_error([&] { TraceWriter w(path, h); }, {path, "texture id 7 appears twice"});
  h = sample_header(true);
  h.textures[1].name = "a\nb";
  expect_input_error([&] { TraceWriter w(path, h); }, {path, "control character"});
  h = sample_header(true);
  h.version = 6;
  expect_input_error([&] { TraceWriter w(path, h); }, {path, "version 6"});
  expect_input_error([&] { TraceWriter w(path, sample_header(true), 0); },
                     {path, "records per chunk 0"});
  EXPECT_EQ(dir.entries(), 0u);
}

// ---- version 2: the optional view vector -----------------------------------------------------

std::vector<Fragment> with_views(std::vector<Fragment> frags) {
  for (size_t i = 0; i < frags.size(); ++i) {
    frags[i].view_x = 0.25F * static_cast<float>(i % 5) - 0.5F;
    frags[i].view_y = -0.125F * static_cast<float>(i % 3);
    frags[i].view_z = 0.75F;
  }
  return frags;
}

// A version-2 layout: the canonical fields, then view_x, view_y, view_z.
FileSpec view_spec(uint32_t version, int view_fields = 3) {
  FileSpec s;
  s.version = version;
  s.fields = doc_layout(false);
  const char* names[3] = {"view_x", "view_y", "view_z"};
  for (int i = 0; i < view_fields; ++i)
    s.fields.push_back({names[i], 9, 68 + 4 * static_cast<uint32_t>(i)});
  s.record_size = 80;
  return s;
}

std::vector<unsigned char> view_file(const FileSpec& s, const std::vector<Fragment>& frags) {
  std::vector<unsigned char> out = build_header(s);
  const auto c = build_chunk(frags, s);
  out.insert(out.end(), c.begin(), c.end());
  const auto t = build_trailer(1, frags.size());
  out.insert(out.end(), t.begin(), t.end());
  return out;
}

TEST(TraceViewVector, RoundTripsAsVersion2InBothForms) {
  for (const bool lod : {false, true}) {
    for (const char* name : {"v.trc", "v.csv"}) {
      SCOPED_TRACE(std::string(name) + (lod ? " with lod_bias" : ""));
      TempDir dir("texsim_trace_file");
      const std::string path = dir.file(name);
      TraceHeader h = sample_header(lod);
      h.has_view = true;
      const auto frags = with_views(random_fragments(300, lod, {0, 7}, 5));
      write_trace(path, h, frags);
      TraceHeader back;
      const auto got = read_all(path, &back);
      EXPECT_EQ(back.version, 2u);
      EXPECT_TRUE(back.has_view);
      EXPECT_EQ(back.has_lod_bias, lod);
      if (back.encoding == TraceEncoding::Binary) {
        EXPECT_EQ(back.record_size, lod ? 84u : 80u);
      }
      ASSERT_EQ(got.size(), frags.size());
      for (size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(same_fragment(got[i], frags[i])) << i;
    }
  }
}

TEST(TraceViewVector, WithoutItTheWriterWritesVersion1) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("v1.trc");
  TraceHeader h = sample_header(false);
  h.version = 2;  // the version written is the lowest that describes the file
  write_trace(path, h, random_fragments(10, false, {0}, 3));
  TraceHeader back;
  (void)read_all(path, &back);
  EXPECT_EQ(back.version, 1u);
  EXPECT_FALSE(back.has_view);
  EXPECT_EQ(back.record_size, 68u);
}

TEST(TraceViewVector, Version1FilesSkipFieldsOfThoseNames) {
  // Before version 2 the names meant nothing: a version-1 file's view_* fields are skipped.
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("old.trc");
  const auto frags = with_views(random_fragments(20, false, {0, 3}, 9));
  spit(path, view_file(view_spec(1), frags));
  TraceHeader h;
  const auto got = read_all(path, &h);
  EXPECT_EQ(h.version, 1u);
  EXPECT_FALSE(h.has_view);
  ASSERT_EQ(got.size(), frags.size());
  EXPECT_FALSE(got[0].has_view());
  // The same bytes as version 2 carry it.
  spit(path, view_file(view_spec(2), frags));
  const auto v2 = read_all(path, &h);
  EXPECT_TRUE(h.has_view);
  for (size_t i = 0; i < v2.size(); ++i) ASSERT_TRUE(same_fragment(v2[i], frags[i])) << i;
}

TEST(TraceViewVector, BadViewVectorsNameFileRecordAndField) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("bad.trc");
  // Only two of the three fields: a header error.
  spit(path, view_file(view_spec(2, 2), with_views(random_fragments(4, false, {0}, 1))));
  expect_input_error([&] { read_all(path); }, {path, "header", "view_x, view_y, view_z"});
  // A NaN component, and a zero vector: record errors.
  auto frags = with_views(random_fragments(6, false, {0}, 1));
  frags[4].view_y = std::numeric_limits<float>::quiet_NaN();
  spit(path, view_file(view_spec(2), frags));
  expect_input_error([&] { read_all(path); }, {path, "record 4", "field 'view_y' is NaN"});
  frags[4].view_y = 0;
  frags[4].view_x = frags[4].view_z = 0;
  spit(path, view_file(view_spec(2), frags));
  expect_input_error([&] { read_all(path); }, {path, "record 4", "view vector", "is zero"});
  // The writers refuse them too.
  TraceHeader h = sample_header(false);
  h.has_view = true;
  for (const char* name : {"w.trc", "w.csv"}) {
    const std::string out = dir.file(name);
    expect_input_error([&] { write_trace(out, h, frags); }, {out, "record 4", "is zero"});
  }
}

TEST(TraceViewVector, CsvViewColumnsComeTogetherAndMustBeFinite) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("c.csv");
  const std::string head = "# texture 0 t procedural:checker 8 8\n";
  std::ofstream(path) << head << "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,view_x,view_z\n";
  expect_input_error([&] { read_all(path); }, {path, "view_x, view_y, view_z", "2 present"});
  std::ofstream(path) << head << "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,view_x,view_y,view_z\n"
                      << "0,0,1,1,0,0.5,0.5,0,0,0,0,0.1,nan,0.9\n";
  expect_input_error([&] { read_all(path); }, {path + ":3:", "view_y"});
  std::ofstream(path) << head << "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,view_x,view_y,view_z\n"
                      << "0,0,1,1,0,0.5,0.5,0,0,0,0,0,0,0\n";
  expect_input_error([&] { read_all(path); }, {path + ":3:", "is zero"});
}

// ---- version 3: each texture's storage -------------------------------------------------------

TEST(TraceStorage, RoundTripsAsVersion3InBothForms) {
  for (const bool view : {false, true}) {
    for (const char* name : {"s.trc", "s.csv"}) {
      SCOPED_TRACE(std::string(name) + (view ? " with the view vector" : ""));
      TempDir dir("texsim_trace_file");
      const std::string path = dir.file(name);
      TraceHeader h = sample_header(true);
      h.has_view = view;
      h.textures[0].storage = "compress=bc1_rgb,squish,range";
      h.textures[1].storage = "format=rgb565";  // texture 2 stays as loaded
      const auto frags = with_views(random_fragments(50, true, {0, 7}, 11));
      write_trace(path, h, view ? frags : random_fragments(50, true, {0, 7}, 11));
      TraceHeader back;
      const auto got = read_all(path, &back);
      EXPECT_EQ(back.version, 3u);
      EXPECT_EQ(back.has_view, view);
      ASSERT_EQ(back.textures.size(), 3u);
      EXPECT_EQ(back.textures[0].storage, "compress=bc1_rgb,squish,range");
      EXPECT_EQ(back.textures[1].storage, "format=rgb565");
      EXPECT_EQ(back.textures[2].storage, "");
      EXPECT_EQ(back.textures[1].name, "bricks wall");
      ASSERT_EQ(got.size(), 50u);
      if (view) {
        for (size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(same_fragment(got[i], frags[i]));
      }
    }
  }
}

TEST(TraceStorage, WrittenAsFormatSaysAndReadFromAnIndependentBuilder) {
  // The writer's bytes are those FORMAT.md describes: the same as the byte builder's.
  TempDir dir("texsim_trace_file");
  FileSpec s;
  s.version = 3;
  s.textures[0].storage = "format=r8";
  const auto frags = random_fragments(30, true, {0, 3}, 4);
  const std::string built = dir.file("built.trc"), written = dir.file("written.trc");
  spit(built, view_file(s, frags));
  TraceHeader h;
  h.has_lod_bias = true;
  h.textures = s.textures;
  write_trace(written, h, frags);
  EXPECT_EQ(slurp(built), slurp(written));
  TraceHeader back;
  const auto got = read_all(built, &back);
  EXPECT_EQ(back.version, 3u);
  EXPECT_EQ(back.textures[0].storage, "format=r8");
  EXPECT_EQ(back.textures[1].storage, "");
  ASSERT_EQ(got.size(), frags.size());
  // Without any storage the writer writes version 1, byte for byte the old form.
  h.textures[0].storage.clear();
  write_trace(written, h, frags);
  s.version = 1;
  s.textures[0].storage.clear();
  spit(built, view_file(s, frags));
  EXPECT_EQ(slurp(built), slurp(written));
}

TEST(TraceStorage, BadEntriesNameFileAndEntry) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("bad.trc");
  FileSpec s;
  s.version = 3;
  const auto frags = random_fragments(3, true, {0}, 2);
  s.textures[1].storage = "gzip=9";
  spit(path, view_file(s, frags));
  expect_input_error([&] { read_all(path); },
                     {path, "header", "texture entry 1 (id 3)", "storage 'gzip=9' is neither"});
  s.textures[1].storage = "format=";
  spit(path, view_file(s, frags));
  expect_input_error([&] { read_all(path); }, {path, "texture entry 1", "storage 'format='"});
  s.textures[1].storage = "format=r8\x01";
  spit(path, view_file(s, frags));
  expect_input_error([&] { read_all(path); }, {path, "entry 1", "storage contains a control"});
  s.textures[1].storage = std::string(257, 'f');
  spit(path, view_file(s, frags));
  expect_input_error([&] { read_all(path); }, {path, "texture entry 1", "storage length 257"});
  // A version-2 table read as version 3: its entries lack the storage length.
  s.textures[1].storage.clear();
  s.version = 2;
  auto bytes = view_file(s, frags);
  bytes[8] = 3;
  const size_t hs = bytes[12] | (size_t{bytes[13]} << 8);
  const uint32_t c = crc(bytes.data(), hs - 4);
  for (size_t i = 0; i < 4; ++i) bytes[hs - 4 + i] = static_cast<unsigned char>(c >> (8 * i));
  spit(path, bytes);
  expect_input_error([&] { read_all(path); }, {path, "header, texture entry"});
  // The writer refuses what the reader would.
  TraceHeader h = sample_header(false);
  h.textures[2].storage = "compress";
  const std::string out = dir.file("w.trc");
  expect_input_error([&] { TraceWriter w(out, h); }, {out, "texture entry 2", "neither"});
}

}  // namespace
}  // namespace texsim

namespace texsim {
namespace {

// ---- version 4: the operation fields -------------------------------------------------------

std::vector<Fragment> with_operations(std::vector<Fragment> frags) {
  for (size_t i = 0; i < frags.size(); ++i) {
    Fragment& f = frags[i];
    f.op = static_cast<uint8_t>(i % 4);
    f.lod = 0.25F * static_cast<float>(i % 9) - 1.0F;
    f.gather_component = static_cast<uint8_t>(i % 4);
    f.compare_ref = 1.0F / static_cast<float>(i + 3);
    f.sampler = static_cast<uint16_t>(i * 977 % 65536);
    f.offset_u = static_cast<int8_t>(static_cast<int>(i % 16) - 8);
    f.offset_v = static_cast<int8_t>(7 - static_cast<int>(i % 16));
    f.offset_w = static_cast<int8_t>(i % 3);
    f.w = 1.0 / static_cast<double>(i + 1);
    f.dwdx = -1e-300 * static_cast<double>(i);
    f.dwdy = 3.5;
    f.layer = static_cast<float>(i % 6) + 0.5F;
  }
  return frags;
}

::testing::AssertionResult same_operation(const Fragment& a, const Fragment& b) {
  const bool ok = a.op == b.op && same_bits(a.lod, b.lod) &&
                  a.gather_component == b.gather_component &&
                  same_bits(a.compare_ref, b.compare_ref) && a.sampler == b.sampler &&
                  a.offset_u == b.offset_u && a.offset_v == b.offset_v &&
                  a.offset_w == b.offset_w && same_bits(a.w, b.w) && same_bits(a.dwdx, b.dwdx) &&
                  same_bits(a.dwdy, b.dwdy) && same_bits(a.layer, b.layer);
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "operation fields differ: op " << int{a.op} << "/"
                                       << int{b.op} << " lod " << a.lod << "/" << b.lod;
}

TEST(TraceVersion4, RoundTripsInBothFormsAndBetweenThem) {
  for (const bool view : {false, true}) {
    TempDir dir("texsim_trace_file");
    TraceHeader h = sample_header(true);
    h.has_view = view;
    h.has_ops = true;
    auto frags = with_operations(random_fragments(300, true, {0, 7}, 11));
    if (view) frags = with_views(frags);
    for (const char* name : {"o.trc", "o.csv"}) {
      SCOPED_TRACE(std::string(name) + (view ? " with the view vector" : ""));
      const std::string path = dir.file(name);
      write_trace(path, h, frags);
      TraceHeader back;
      const auto got = read_all(path, &back);
      EXPECT_EQ(back.version, 4u);
      EXPECT_TRUE(back.has_ops);
      EXPECT_EQ(back.op_fields, kAllOpFields);
      if (back.encoding == TraceEncoding::Binary) {
        EXPECT_EQ(back.record_size, (view ? 84u : 72u) + 43u);
      }
      ASSERT_EQ(got.size(), frags.size());
      for (size_t i = 0; i < got.size(); ++i) {
        ASSERT_TRUE(same_fragment(got[i], frags[i])) << i;
        ASSERT_TRUE(same_operation(got[i], frags[i])) << i;
      }
    }
  }
}

TEST(TraceVersion4, WriterRefusesBadOperationsNamingTheRecord) {
  TempDir dir("texsim_trace_file");
  TraceHeader h = sample_header(false);
  h.has_ops = true;
  auto frags = with_operations(random_fragments(5, false, {0}, 2));
  frags[3].op = 9;
  expect_input_error([&] { write_trace(dir.file("bad.trc"), h, frags); },
                     {"record 3", "field 'op' is 9"});
  frags[3].op = 1;
  frags[2].gather_component = 4;
  expect_input_error([&] { write_trace(dir.file("bad.csv"), h, frags); },
                     {"record 2", "'gather_comp' is 4"});
  frags[2].gather_component = 0;
  frags[1].layer = std::numeric_limits<float>::infinity();
  expect_input_error([&] { write_trace(dir.file("bad.trc"), h, frags); },
                     {"record 1", "'layer' is infinite"});
  // Without operation fields nothing changes: version 1, 68-byte records, op 0 read back.
  h.has_ops = false;
  write_trace(dir.file("v1.trc"), h, random_fragments(5, false, {0}, 2));
  TraceHeader back;
  const auto got = read_all(dir.file("v1.trc"), &back);
  EXPECT_EQ(back.version, 1u);
  EXPECT_EQ(back.record_size, 68u);
  EXPECT_FALSE(back.has_ops);
  EXPECT_EQ(got[0].op, 0);
}

// The sampler table (version 5): two entries with every field away from its default.
std::vector<TraceSampler> sample_samplers() {
  TraceSampler a;
  a.name = "pcf";
  a.mode = 2;
  a.address_u = 3;
  a.address_v = 4;
  a.address_w = 1;
  a.border[0] = 0.25f;
  a.border[1] = -1.5f;
  a.border[2] = 1e-3f;
  a.border[3] = 1;
  a.compare = 4;
  a.aniso = 1;
  a.max_aniso = 8;
  a.lod_bias = -0.75f;
  a.min_lod = 0.5f;
  a.max_lod = 6;
  a.seamless = 0;
  a.sub_texel_bits = 4;
  a.mipmap_bits = 12;
  TraceSampler b;
  b.name = "texel fetch";  // quoted in CSV
  b.address_u = b.address_v = 1;
  b.reduction = 2;
  b.unnormalized = 1;
  b.max_lod = 0;
  return {a, b};
}

TEST(TraceSamplers, RoundTripAsVersion5InBothForms) {
  TempDir dir("texsim_trace_file");
  TraceHeader h = sample_header(true);
  h.has_ops = true;
  h.samplers = sample_samplers();
  auto frags = with_operations(random_fragments(40, true, {0, 7}, 5));
  for (const char* name : {"s.trc", "s.csv"}) {
    SCOPED_TRACE(name);
    write_trace(dir.file(name), h, frags);
    TraceHeader back;
    const auto got = read_all(dir.file(name), &back);
    EXPECT_EQ(back.version, 5u);
    ASSERT_EQ(back.samplers.size(), 2u);
    EXPECT_TRUE(back.samplers == h.samplers);
    ASSERT_EQ(got.size(), frags.size());
    for (size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(same_operation(got[i], frags[i])) << i;
  }
  // Without a sampler table the writer writes what it wrote before: version 4 here.
  h.samplers.clear();
  write_trace(dir.file("v4.trc"), h, frags);
  TraceHeader back;
  read_all(dir.file("v4.trc"), &back);
  EXPECT_EQ(back.version, 4u);
  EXPECT_TRUE(back.samplers.empty());
}

TEST(TraceSamplers, WrittenAsFormatSays) {
  // The table ends the header: u32 count, then per entry u32 name_len, the name and 41 bytes of
  // state in FORMAT.md's order; built here by hand.
  TempDir dir("texsim_trace_file");
  TraceHeader h = sample_header(false);
  h.samplers = sample_samplers();
  write_trace(dir.file("s.trc"), h, random_fragments(3, false, {0}, 2));
  const auto bytes = slurp(dir.file("s.trc"));
  std::vector<unsigned char> want;
  const auto u32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) want.push_back(static_cast<unsigned char>(v >> (8 * k)));
  };
  const auto f32 = [&](float v) { u32(std::bit_cast<uint32_t>(v)); };
  u32(2);
  for (const TraceSampler& s : h.samplers) {
    u32(static_cast<uint32_t>(s.name.size()));
    want.insert(want.end(), s.name.begin(), s.name.end());
    want.insert(want.end(), {s.mode, s.address_u, s.address_v, s.address_w, s.border_kind});
    for (const float c : s.border) f32(c);
    want.insert(want.end(), {s.compare, s.reduction, s.aniso, s.max_aniso});
    f32(s.lod_bias);
    f32(s.min_lod);
    f32(s.max_lod);
    want.insert(want.end(), {s.unnormalized, s.seamless, s.sub_texel_bits, s.mipmap_bits});
  }
  uint32_t header_size = 0;
  std::memcpy(&header_size, bytes.data() + 12, 4);
  ASSERT_GE(header_size, want.size() + 4);
  EXPECT_EQ(bytes[8], 5);  // version
  const auto end = static_cast<std::ptrdiff_t>(header_size) - 4;
  const std::vector<unsigned char> table(
      bytes.begin() + (end - static_cast<std::ptrdiff_t>(want.size())), bytes.begin() + end);
  EXPECT_EQ(table, want);
}

// Rewrites byte `at` of the sampler table's region (counted back from the header CRC) and
// fixes the header CRC, so the reader sees a well-formed header with one bad value.
void patch_header(std::vector<unsigned char>& bytes, size_t back, unsigned char value) {
  uint32_t header_size = 0;
  std::memcpy(&header_size, bytes.data() + 12, 4);
  bytes[header_size - 4 - back] = value;
  const auto crc = static_cast<uint32_t>(crc32(0, bytes.data(), header_size - 4));
  std::memcpy(bytes.data() + header_size - 4, &crc, 4);
}

TEST(TraceSamplers, BadEntriesNameFileEntryAndField) {
  TempDir dir("texsim_trace_file");
  TraceHeader h = sample_header(false);
  h.samplers = {sample_samplers()[0]};  // 'pcf', the last entry: its state is the last 41 bytes
  const std::string good = dir.file("good.trc"), path = dir.file("bad.trc");
  write_trace(good, h, random_fragments(3, false, {0}, 2));
  const auto bytes = slurp(good);
  const auto expect_bad = [&](size_t back, unsigned char v, const std::vector<std::string>& parts) {
    auto b = bytes;
    patch_header(b, back, v);
    spit(path, b);
    std::vector<std::string> all = {path, "header", "sampler table entry 1 ('pcf')"};
    all.insert(all.end(), parts.begin(), parts.end());
    expect_input_error([&] { read_all(path); }, all);
  };
  expect_bad(41, 7, {"mode code 7 is not one of 0 nearest"});
  expect_bad(39, 5, {"address_v code 5"});
  expect_bad(37, 1, {"integer border colour"});
  expect_bad(37, 2, {"border kind 2"});
  expect_bad(33, 0xff, {"border channel 0 is infinite"});  // border r's top byte: -inf
  expect_bad(20, 9, {"compare code 9"});
  expect_bad(19, 3, {"reduction code 3"});
  expect_bad(17, 0, {"max_aniso 0 is outside 1..16"});
  expect_bad(5, 0xff, {"max_lod is NaN"});
  expect_bad(4, 2, {"unnormalized is 2"});
  expect_bad(3, 9, {"seamless is 9"});
  expect_bad(2, 0, {"sub_texel_bits 0"});
  expect_bad(1, 17, {"mipmap_bits 17"});
  // min_lod above max_lod: min_lod's top byte 0x7f0... gives a huge finite value.
  expect_bad(9, 0x7e, {"min_lod", "is above max_lod"});
  // A name length past the header, and a count past the header: no read beyond it.
  auto b = bytes;
  uint32_t header_size = 0;
  std::memcpy(&header_size, b.data() + 12, 4);
  const size_t entry = header_size - 4 - 41 - 3 - 4;  // u32 name_len of 'pcf'
  patch_header(b, header_size - 4 - entry, 200);
  spit(path, b);
  expect_input_error([&] { read_all(path); }, {path, "sampler entry 1", "past the end"});
  b = bytes;
  patch_header(b, header_size - 4 - (entry - 4), 9);  // the count: 9 entries
  spit(path, b);
  expect_input_error([&] { read_all(path); }, {path, "past the end of the header"});
  // The writer refuses what the reader would.
  h.samplers[0].max_aniso = 0;
  expect_input_error([&] { write_trace(path, h, {}); },
                     {path, "sampler table entry 1 ('pcf')", "max_aniso 0"});
  h.samplers = sample_samplers();
  h.samplers[1].name = "pcf";
  expect_input_error([&] { write_trace(dir.file("bad.csv"), h, {}); },
                     {"sampler table entry 2 ('pcf')", "name is that of entry 1"});
}

TEST(TraceSamplers, CorruptTablesNeverCrash) {
  // Random bytes anywhere in the sampler table, the header CRC fixed: an InputError or a table
  // that passed every check, never anything else.
  TempDir dir("texsim_trace_file");
  TraceHeader h = sample_header(false);
  h.samplers = sample_samplers();
  const std::string good = dir.file("good.trc"), path = dir.file("bad.trc");
  write_trace(good, h, random_fragments(2, false, {0}, 2));
  const auto bytes = slurp(good);
  uint32_t header_size = 0;
  std::memcpy(&header_size, bytes.data() + 12, 4);
  const size_t table = 4 + 2 * (4 + 41) + 3 + 11;  // the count and both entries
  std::mt19937 rng(27);
  std::uniform_int_distribution<size_t> at(1, table);
  std::uniform_int_distribution<int> byte(0, 255);
  int refused = 0;
  for (int k = 0; k < 60; ++k) {
    auto b = bytes;
    for (int n = 0; n < 1 + k % 3; ++n)
      patch_header(b, at(rng), static_cast<unsigned char>(byte(rng)));
    spit(path, b);
    try {
      TraceHeader back;
      read_all(path, &back);
      for (const TraceSampler& s : back.samplers) EXPECT_EQ(check_sampler(s), "");
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 15);
}

TEST(TraceSamplers, CsvDirectivesAreCheckedAtLineAndColumn) {
  TempDir dir("texsim_trace_file");
  const std::string path = dir.file("s.csv");
  const std::string head = "# texture 0 t procedural:checker?size=64 64 64\n";
  const std::string cols =
      "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n0,0,1,2,0,0.5,0.5,0,0,0,0\n";
  // Keys left out keep the defaults.
  std::ofstream(path) << head << "# sampler a mode=nearest address_u=clamp\n" << cols;
  TraceHeader back;
  read_all(path, &back);
  ASSERT_EQ(back.samplers.size(), 1u);
  EXPECT_EQ(back.version, 5u);
  EXPECT_EQ(back.samplers[0].mode, 0);
  EXPECT_EQ(back.samplers[0].address_u, 1);
  EXPECT_EQ(back.samplers[0].address_v, 0);
  EXPECT_EQ(back.samplers[0].max_lod, 1000.0f);
  const std::pair<std::string, std::vector<std::string>> bad[] = {
      {"# sampler a mode=cubic", {":2:13:", "sampler 'a': mode: 'cubic' is not one of nearest"}},
      {"# sampler a mdoe=nearest", {":2:13:", "unknown sampler key 'mdoe'"}},
      {"# sampler a mode=nearest mode=bilinear", {":2:26:", "'mode' appears twice"}},
      {"# sampler a border=1,2,3", {":2:13:", "four numbers"}},
      {"# sampler a border=1,2,3,nan", {":2:13:", "NaN"}},
      {"# sampler a border_int=1,2,3,4", {":2:13:", "integer border colour"}},
      {"# sampler a max_aniso=17", {":2:13:", "max_aniso: '17' is outside 1..16"}},
      {"# sampler a seamless=2", {":2:13:", "outside 0..1"}},
      {"# sampler a min_lod=3 max_lod=1", {":2:11:", "entry 1: min_lod", "above max_lod"}},
      {"# sampler a nokey", {":2:13:", "expected key=value"}},
      {"# sampler", {":2:3:", "needs a name"}},
  };
  for (const auto& [line, parts] : bad) {
    SCOPED_TRACE(line);
    std::ofstream(path) << head << line << "\n" << cols;
    std::vector<std::string> all = {path};
    all.insert(all.end(), parts.begin(), parts.end());
    expect_input_error([&] { read_all(path); }, all);
  }
  std::ofstream(path) << head << "# sampler a\n# sampler a\n" << cols;
  expect_input_error([&] { read_all(path); }, {":3:11:", "'a' appears twice"});
  std::ofstream(path) << head << cols << "# sampler b\n";
  expect_input_error([&] { read_all(path); }, {":4:3:", "sampler directive after the column"});
}

}  // namespace
}  // namespace texsim
