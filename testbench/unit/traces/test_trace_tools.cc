// `trace info` / `trace convert` back ends and the sample traces (traces/FORMAT.md).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "testbench/lib/temp_dir.h"
#include "traces/trace_file.h"
#include "traces/trace_tools.h"

namespace texsim {
namespace {

namespace fs = std::filesystem;

const std::string kSamples = std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void spit(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string message_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(TraceTools, SampleSummaryMatchesTheHandWrittenFile) {
  for (const char* name : {"basic.csv", "basic.trc"}) {
    SCOPED_TRACE(name);
    const TraceSummary s = summarize_trace(kSamples + name);
    EXPECT_EQ(s.records, 8u);
    EXPECT_EQ(s.chunks, 1u);
    EXPECT_TRUE(s.header.has_lod_bias);
    ASSERT_EQ(s.header.textures.size(), 2u);
    EXPECT_EQ(s.header.textures[0].source, "procedural:checker?size=512&cells=16");
    EXPECT_EQ(s.frames, (std::map<uint32_t, uint64_t>{{0, 5}, {1, 3}}));
    EXPECT_EQ(s.per_texture, (std::map<uint32_t, uint64_t>{{0, 4}, {1, 4}}));
    EXPECT_EQ(s.prim_min, 0u);
    EXPECT_EQ(s.prim_max, 2u);
    EXPECT_EQ(s.x.lo, 10);
    EXPECT_EQ(s.x.hi, 301);
    EXPECT_EQ(s.y.lo, 7);
    EXPECT_EQ(s.y.hi, 64);
    EXPECT_EQ(s.u.lo, -0.25);
    EXPECT_EQ(s.u.hi, 2.75);
    EXPECT_EQ(s.v.lo, -3.125);
    EXPECT_EQ(s.v.hi, 1.5);
    EXPECT_EQ(s.dudy.lo, -0.00048828);
    EXPECT_EQ(s.lod_bias.lo, -1.0);
    EXPECT_EQ(s.lod_bias.hi, 0.5);
  }
}

TEST(TraceTools, BinarySampleIsTheConvertedCsvSample) {
  // Keeps traces/samples/basic.trc in step with basic.csv and with the writer.
  TempDir dir("texsim_trace_tools");
  const std::string out = dir.file("basic.trc");
  trace_convert(kSamples + "basic.csv", out);
  EXPECT_EQ(slurp(out), slurp(kSamples + "basic.trc"));
}

TEST(TraceTools, InfoPrintsHeaderTexturesCountsAndRanges) {
  std::ostringstream bin, csv;
  EXPECT_EQ(trace_info(kSamples + "basic.trc", bin), 0);
  EXPECT_EQ(trace_info(kSamples + "basic.csv", csv), 0);
  const std::string b = bin.str();
  for (const char* part :
       {"format:     binary, version 1, record 72 bytes", "lod_bias:f32@68", "textures:   2",
        "id 0  checker  512x512  procedural:checker?size=512&cells=16  fragments 4",
        "records:    8 in 1 chunks", "frames:     2 distinct, 0..1", "frame 0: 5 fragments",
        "pixel bbox: x [10, 301], y [7, 64]", "u:          [-0.25, 2.75]",
        "lod_bias:   [-1, 0.5]"}) {
    EXPECT_NE(b.find(part), std::string::npos) << "missing \"" << part << "\" in\n" << b;
  }
  EXPECT_NE(csv.str().find("format:     CSV, version 1"), std::string::npos) << csv.str();
  // Everything after the format lines is the same for both forms.
  EXPECT_EQ(b.substr(b.find("textures:")), csv.str().substr(csv.str().find("textures:")));
}

TEST(TraceTools, ConvertRoundTripsBytesAndDropsUnknownColumns) {
  TempDir dir("texsim_trace_tools");
  const std::string csv = dir.file("in.csv"), bin = dir.file("mid.trc"), csv2 = dir.file("out.csv"),
                    bin2 = dir.file("again.trc");
  spit(csv,
       "# texture 2 a \"procedural:checker?size=8&cells=2\" 8 8\n"
       "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,depth\n"
       "0,1,2,3,2,0.1,0.2,0.3,0.4,0.5,0.6,9\n"
       "1,1,2,3,2,-0.1,1e-300,3e300,0,-0,0.6,9\n");
  trace_convert(csv, bin);
  TraceHeader h;
  const auto frags = read_trace(bin, &h);
  EXPECT_EQ(h.fields.size(), 11u);  // "depth" is not carried over
  EXPECT_FALSE(h.has_lod_bias);
  ASSERT_EQ(frags.size(), 2u);
  EXPECT_EQ(frags[1].v, 1e-300);
  EXPECT_EQ(frags[1].dudx, 3e300);
  trace_convert(bin, csv2);
  trace_convert(csv2, bin2);
  EXPECT_EQ(slurp(bin), slurp(bin2));
  EXPECT_EQ(slurp(csv2).find("depth"), std::string::npos);
}

TEST(TraceTools, FailedConvertLeavesNoOutput) {
  TempDir dir("texsim_trace_tools");
  const std::string csv = dir.file("bad.csv"), out = dir.file("out.trc");
  std::string text = "# texture 0 a p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n";
  for (int i = 0; i < 5000; ++i) text += "0,0,0,0,0,0.5,0.5,0,0,0,0\n";
  text += "0,0,0,0,0,0.5,0.5,0,0,0\n";  // line 5003: one column short
  spit(csv, text);
  const std::string msg = message_of([&] { trace_convert(csv, out); });
  EXPECT_NE(msg.find(csv + ":5003:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 11 columns, found 10"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(dir.entries(), 1u) << "temporary file left behind";
}

TEST(TraceTools, InfoOnBadInputThrowsNamingTheFile) {
  TempDir dir("texsim_trace_tools");
  const std::string missing = dir.file("missing.trc");
  std::ostringstream out;
  EXPECT_NE(message_of([&] { trace_info(missing, out); }).find(missing + ": cannot open trace"),
            std::string::npos);
}

TEST(TraceTools, FrameListIsBounded) {
  TempDir dir("texsim_trace_tools");
  const std::string path = dir.file("frames.trc");
  TraceHeader h;
  h.textures = {{0, "t", "p", 8, 8}};
  {
    TraceWriter w(path, h);
    Fragment f;
    for (uint32_t i = 0; i < TraceSummary::kMaxFrames + 100; ++i) {
      f.frame = i;
      w.write(f);
    }
    w.close();
  }
  const TraceSummary s = summarize_trace(path);
  EXPECT_EQ(s.frames.size(), TraceSummary::kMaxFrames);
  EXPECT_TRUE(s.frames_overflow);
  EXPECT_EQ(s.frame_max, TraceSummary::kMaxFrames + 99);
  std::ostringstream out;
  trace_info(path, out);
  EXPECT_NE(out.str().find("frames:     more than 65536 distinct"), std::string::npos) << out.str();
}

// Read ahead (the run's first pass with more than one thread): the same summary over many
// chunks, and a damaged chunk's error with the same message.
TEST(TraceTools, ReadAheadGivesTheSameSummaryAndErrors) {
  TempDir dir("texsim_trace_tools");
  const std::string path = dir.file("many.trc");
  TraceHeader h;
  h.textures = {{0, "t", "p", 8, 8}, {3, "s", "p", 4, 4}};
  {
    TraceWriter w(path, h);
    Fragment f;
    for (uint32_t i = 0; i < 50000; ++i) {
      f.frame = i / 7000;
      f.prim = i % 13;
      f.x = i % 640;
      f.y = i / 640;
      f.tex = i % 3 == 0 ? 3 : 0;
      f.u = 0.001 * i - 7;
      f.dvdy = 1.0 / (1 + i);
      w.write(f);
    }
    w.close();
  }
  const TraceSummary a = summarize_trace(path), b = summarize_trace(path, true);
  EXPECT_GT(a.chunks, 2u);
  EXPECT_EQ(a.records, b.records);
  EXPECT_EQ(a.chunks, b.chunks);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.per_texture, b.per_texture);
  EXPECT_EQ(a.prim_max, b.prim_max);
  EXPECT_EQ(a.x.hi, b.x.hi);
  EXPECT_EQ(a.y.hi, b.y.hi);
  EXPECT_EQ(a.u.lo, b.u.lo);
  EXPECT_EQ(a.u.hi, b.u.hi);
  EXPECT_EQ(a.dvdy.lo, b.dvdy.lo);
  // A byte of the last chunk's payload flipped: its CRC fails after every good chunk.
  std::string bytes = slurp(path);
  bytes[bytes.size() - 100] = static_cast<char>(bytes[bytes.size() - 100] ^ 0x5a);
  const std::string bad = dir.file("bad.trc");
  spit(bad, bytes);
  const std::string m = message_of([&] { summarize_trace(bad); });
  EXPECT_NE(m.find("CRC mismatch"), std::string::npos) << m;
  EXPECT_EQ(message_of([&] { summarize_trace(bad, true); }), m);
}

// Pixel coordinates of 10^9 and more are printed as the integers they are, not in %g form.
TEST(TraceTools, InfoPrintsLargePixelCoordinatesExactly) {
  TempDir dir("texsim_trace_tools");
  const std::string path = dir.file("far.trc");
  TraceHeader h;
  h.textures = {{0, "t", "p", 8, 8}};
  {
    TraceWriter w(path, h);
    Fragment f;
    f.x = f.y = 1;
    w.write(f);
    f.x = 4294967295u;
    f.y = 1000000000u;
    w.write(f);
    w.close();
  }
  std::ostringstream out;
  trace_info(path, out);
  EXPECT_NE(out.str().find("pixel bbox: x [1, 4294967295], y [1, 1000000000]"), std::string::npos)
      << out.str();
}

}  // namespace
}  // namespace texsim
