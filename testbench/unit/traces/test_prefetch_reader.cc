// PrefetchReader (traces/prefetch_reader.h): the same chunks as the serial TraceReader, errors of
// the input at the same point of the stream with the same type and message, a bounded read-ahead,
// and a clean stop however early the consumer gives up.
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "blocks/base/input_error.h"
#include "testbench/lib/temp_dir.h"
#include "traces/prefetch_reader.h"
#include "traces/trace_file.h"

namespace texsim {
namespace {

TraceHeader test_header() {
  TraceHeader h;
  h.has_lod_bias = true;
  h.textures = {{0, "checker", "procedural:checker?size=512&cells=16", 512, 512},
                {3, "bricks", "procedural:checker?size=256&cells=8", 256, 256}};
  return h;
}

std::vector<Fragment> test_fragments(size_t n) {
  std::vector<Fragment> out(n);
  for (size_t i = 0; i < n; ++i) {
    Fragment& f = out[i];
    f.frame = static_cast<uint32_t>(i / 1000);
    f.prim = static_cast<uint32_t>(i % 7);
    f.x = static_cast<uint32_t>(i % 640);
    f.y = static_cast<uint32_t>(i / 640);
    f.tex = (i % 3 == 0) ? 3 : 0;
    f.u = 0.001 * static_cast<double>(i) + 1.0 / 3.0;
    f.v = -0.5 + 1e-7 * static_cast<double>(i);
    f.dudx = 1.0 / 512;
    f.dvdx = 1e-5 * static_cast<double>(i % 11);
    f.dudy = -1e-5 * static_cast<double>(i % 13);
    f.dvdy = 1.0 / 256;
    f.lod_bias = static_cast<float>(i % 5) * 0.25f;
  }
  return out;
}

// Writes `n` fragments in chunks of `per_chunk`.
void write_test_trace(const std::string& path, size_t n, uint32_t per_chunk) {
  TraceWriter w(path, test_header(), per_chunk);
  for (const Fragment& f : test_fragments(n)) w.write(f);
  w.close();
}

bool same_fragment(const Fragment& a, const Fragment& b) {
  auto bits = [](double d) { return std::bit_cast<uint64_t>(d); };
  return a.frame == b.frame && a.prim == b.prim && a.x == b.x && a.y == b.y && a.tex == b.tex &&
         bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v) && bits(a.dudx) == bits(b.dudx) &&
         bits(a.dvdx) == bits(b.dvdx) && bits(a.dudy) == bits(b.dudy) &&
         bits(a.dvdy) == bits(b.dvdy) && a.lod_bias == b.lod_bias && a.view_x == b.view_x &&
         a.view_y == b.view_y && a.view_z == b.view_z;
}

// What a consumer sees: every chunk's fragments in order, then the error that ended it (its
// message; empty for a clean end) and whether that error was an InputError.
struct Stream {
  std::vector<std::vector<Fragment>> chunks;
  std::string error;
  bool input_error = false;
};

Stream drain(const std::function<size_t(std::vector<Fragment>&)>& next) {
  Stream s;
  std::vector<Fragment> chunk;
  try {
    while (const size_t n = next(chunk)) {
      EXPECT_EQ(n, chunk.size());
      s.chunks.push_back(chunk);
    }
    EXPECT_TRUE(chunk.empty());
    EXPECT_EQ(next(chunk), 0u) << "stays at the end";
  } catch (const InputError& e) {
    s.error = e.what();
    s.input_error = true;
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return s;
}

Stream serial(const std::string& path) {
  TraceReader r(path);
  return drain([&](std::vector<Fragment>& out) { return r.next_chunk(out); });
}

Stream prefetched(const std::string& path, size_t depth) {
  TraceReader r(path);
  PrefetchReader ahead(r, depth);
  return drain([&](std::vector<Fragment>& out) { return ahead.next_chunk(out); });
}

void expect_same(const Stream& a, const Stream& b) {
  ASSERT_EQ(a.chunks.size(), b.chunks.size());
  for (size_t c = 0; c < a.chunks.size(); ++c) {
    ASSERT_EQ(a.chunks[c].size(), b.chunks[c].size()) << "chunk " << c;
    for (size_t i = 0; i < a.chunks[c].size(); ++i)
      ASSERT_TRUE(same_fragment(a.chunks[c][i], b.chunks[c][i])) << "chunk " << c << " #" << i;
  }
  EXPECT_EQ(a.error, b.error);
  EXPECT_EQ(a.input_error, b.input_error);
}

// Runs `fn` on its own thread and fails (and ends the program) if it has not returned in time,
// so a hang shows as a failure naming the test instead of a timeout of the whole program.
void expect_returns(const std::function<void()>& fn) {
  std::promise<void> done;
  std::future<void> f = done.get_future();
  std::thread([&fn, d = std::move(done)]() mutable {
    fn();
    d.set_value();
  }).detach();
  if (f.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "did not return within 60 s";
    std::fflush(stdout);
    std::abort();
  }
}

void flip_byte(const std::string& path, uint64_t at) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekg(static_cast<std::streamoff>(at));
  const int c = file.get();
  file.seekp(static_cast<std::streamoff>(at));
  file.put(static_cast<char>(c ^ 0x01));
}

void truncate_by(const std::string& path, uint64_t bytes) {
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - bytes);
}

constexpr uint64_t kChunkHeader = 12;  // "CHNK", record count, CRC (FORMAT.md)
constexpr uint64_t kTrailer = 24;

TEST(PrefetchReader, SameChunksAsTheSerialReader) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("many.trc");
  write_test_trace(path, 10007, 97);  // 104 chunks, the last one partial
  const Stream want = serial(path);
  ASSERT_EQ(want.chunks.size(), 104u);
  ASSERT_TRUE(want.error.empty()) << want.error;
  for (const size_t depth : {size_t{0}, size_t{1}, size_t{2}, size_t{4}}) {
    SCOPED_TRACE("depth " + std::to_string(depth));
    expect_same(want, prefetched(path, depth));
  }
}

TEST(PrefetchReader, SameChunksFromTheCsvForm) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("many.csv");
  write_trace(path, test_header(), test_fragments(9000));
  const Stream want = serial(path);
  ASSERT_GT(want.chunks.size(), 1u);
  expect_same(want, prefetched(path, 2));
}

TEST(PrefetchReader, CrcErrorInAMiddleChunkComesAfterTheGoodChunks) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("crc.trc");
  constexpr uint32_t kPerChunk = 50;
  constexpr uint64_t kChunks = 10;
  write_test_trace(path, kPerChunk * kChunks, kPerChunk);
  const uint64_t chunk_bytes = kChunkHeader + uint64_t{kPerChunk} * canonical_record_size(true);
  const uint64_t first = std::filesystem::file_size(path) - kTrailer - kChunks * chunk_bytes;
  flip_byte(path, first + 6 * chunk_bytes + kChunkHeader + 17);  // a payload byte of chunk 6
  const Stream want = serial(path);
  ASSERT_EQ(want.chunks.size(), 6u);
  ASSERT_TRUE(want.input_error);
  EXPECT_NE(want.error.find("chunk 6"), std::string::npos) << want.error;
  EXPECT_NE(want.error.find("CRC mismatch"), std::string::npos) << want.error;
  for (const size_t depth : {size_t{1}, size_t{3}, size_t{16}}) {
    SCOPED_TRACE("depth " + std::to_string(depth));
    expect_same(want, prefetched(path, depth));
  }
}

TEST(PrefetchReader, ErrorWaitsForASlowConsumer) {
  // The reader thread meets the bad chunk long before the consumer asks; it still comes last.
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("crc.trc");
  write_test_trace(path, 200, 50);
  const uint64_t chunk_bytes = kChunkHeader + uint64_t{50} * canonical_record_size(true);
  flip_byte(path, std::filesystem::file_size(path) - kTrailer - chunk_bytes + kChunkHeader + 3);
  TraceReader r(path);
  PrefetchReader ahead(r, 4);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::vector<Fragment> chunk;
  for (int c = 0; c < 3; ++c) ASSERT_EQ(ahead.next_chunk(chunk), 50u) << "chunk " << c;
  EXPECT_THROW(ahead.next_chunk(chunk), InputError);
  EXPECT_TRUE(chunk.empty());
  EXPECT_THROW(ahead.next_chunk(chunk), InputError) << "the error stays";
}

TEST(PrefetchReader, TruncatedFileFailsAtTheSamePoint) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("cut.trc");
  write_test_trace(path, 1000, 64);
  truncate_by(path, kTrailer);  // no end marker
  const Stream want = serial(path);
  ASSERT_EQ(want.chunks.size(), 16u);
  EXPECT_NE(want.error.find("without the end marker"), std::string::npos) << want.error;
  expect_same(want, prefetched(path, 2));
  truncate_by(path, 100);  // inside the last chunk's payload
  const Stream cut = serial(path);
  ASSERT_EQ(cut.chunks.size(), 15u);
  EXPECT_NE(cut.error.find("truncated chunk"), std::string::npos) << cut.error;
  expect_same(cut, prefetched(path, 2));
}

TEST(PrefetchReader, OneChunkAndEmptyTraces) {
  TempDir dir("texsim_prefetch");
  const std::string tiny = dir.file("tiny.trc");
  write_test_trace(tiny, 3, 4096);
  const Stream want = serial(tiny);
  ASSERT_EQ(want.chunks.size(), 1u);
  ASSERT_EQ(want.chunks[0].size(), 3u);
  expect_same(want, prefetched(tiny, 3));

  const std::string empty = dir.file("empty.trc");
  write_test_trace(empty, 0, 4096);
  TraceReader r(empty);
  PrefetchReader ahead(r);
  std::vector<Fragment> chunk{Fragment{}};
  EXPECT_EQ(ahead.next_chunk(chunk), 0u);
  EXPECT_TRUE(chunk.empty());
  EXPECT_EQ(ahead.next_chunk(chunk), 0u);
}

TEST(PrefetchReader, ReadsAtMostDepthChunksAhead) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("many.trc");
  write_test_trace(path, 5000, 50);  // 100 chunks
  TraceReader r(path);
  {
    PrefetchReader ahead(r, 2);
    std::vector<Fragment> chunk;
    ASSERT_EQ(ahead.next_chunk(chunk), 50u);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // time to run ahead, if it would
  }
  // Read once the thread has stopped: the chunk handed out plus at most 2 more.
  EXPECT_GE(r.chunks_read(), 1u);
  EXPECT_LE(r.chunks_read(), 3u);
}

TEST(PrefetchReader, StopsCleanlyWhenTheConsumerGivesUp) {
  TempDir dir("texsim_prefetch");
  const std::string path = dir.file("many.trc");
  write_test_trace(path, 20000, 100);
  for (const int taken : {0, 1, 5}) {
    SCOPED_TRACE("chunks taken " + std::to_string(taken));
    expect_returns([&] {
      TraceReader r(path);
      PrefetchReader ahead(r, 2);
      std::vector<Fragment> chunk;
      for (int c = 0; c < taken; ++c) ahead.next_chunk(chunk);
    });
  }
  // A run that throws midway: the exception passes the reader, which stops on the way out.
  expect_returns([&] {
    try {
      TraceReader r(path);
      PrefetchReader ahead(r, 4);
      std::vector<Fragment> chunk;
      ahead.next_chunk(chunk);
      throw std::runtime_error("record 7: bad primitive");
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "record 7: bad primitive");
    }
  });
  // Destroyed at once, before the thread has read anything.
  expect_returns([&] {
    TraceReader r(path);
    const PrefetchReader ahead(r);
  });
}

}  // namespace
}  // namespace texsim
