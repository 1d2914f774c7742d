// The apitrace importer (traces/DRAWS.md, "Import from apitrace") on hand-written dump text
// with blob files, checked against clip positions computed by hand; and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/capture/apitrace_import.h"
#include "testbench/lib/temp_dir.h"
#include "traces/draw_trace.h"

namespace texsim {
namespace {

void write_bytes(const std::string& path, const std::vector<uint8_t>& b) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}
template <class T>
std::vector<uint8_t> bytes_of(const std::vector<T>& v) {
  std::vector<uint8_t> b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

// Frame 0 uploads a 3x2 RGB texture (rows padded to 4 bytes); frame 1 draws a strip through
// an ortho projection and a translated, scaled modelview, then the same vertices rotated;
// frame 2 only clears.
const char* kDump = R"(// process.name = "test"
0 glViewport(0, 0, 64, 32)
1 glMatrixMode(GL_PROJECTION)
2 glLoadIdentity()
3 glOrtho(0, 64, 0, 32, -1, 1)
4 glMatrixMode(GL_MODELVIEW)
5 glLoadIdentity()
6 glTranslatef(8, 4, 0)
7 glScalef(2, 2, 1)
8 glGenTextures(1, &5)
9 glBindTexture(GL_TEXTURE_2D, 5)
10 glPixelStorei(GL_UNPACK_ALIGNMENT, 4)
11 glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, 3, 2, 0, GL_RGB, GL_UNSIGNED_BYTE, blob("blob_call11.bin"))
12 glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR)
13 glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY_EXT, 8)
14 glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
15 glXSwapBuffers(0x1, 2)

16 glEnable(GL_TEXTURE_2D)
17 glTexEnvf(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE)
18 glEnable(GL_DEPTH_TEST)
19 glDepthFunc(GL_LEQUAL)
20 glEnable(GL_BLEND)
21 glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA)
22 glEnable(GL_FOG)
23 glScissor(0, 0, 64, 32)
24 glEnableClientState(GL_VERTEX_ARRAY)
25 glVertexPointer(3, GL_FLOAT, 16, blob("blob_call25.bin")) // fake
26 glClientActiveTextureARB(GL_TEXTURE0)
27 glEnableClientState(GL_TEXTURE_COORD_ARRAY)
28 glTexCoordPointer(2, GL_FLOAT, 0, blob("blob_call28.bin")) // fake
29 glColor4f(1, 0.5, 0, 1)
30 glDrawElements(GL_TRIANGLE_STRIP, 4, GL_UNSIGNED_SHORT, blob("blob_call30.bin"))
31 glPushMatrix()
32 glRotatef(90, 0, 0, 1)
33 glDrawArrays(GL_TRIANGLES, 1, 3)
34 glPopMatrix()
35 glDrawArrays(GL_LINES, 0, 2)
36 glXSwapBuffers(0x1, 2)

37 glClear(GL_COLOR_BUFFER_BIT)
38 glXSwapBuffers(0x1, 2)
)";

class ApitraceImportTest : public ::testing::Test {
 protected:
  TempDir dir{"apitrace_import"};
  std::string dump = dir.file("dump.txt");
  std::string out = dir.file("out.draws");
  void SetUp() override {
    write_text(kDump);
    std::vector<uint8_t> rgb = {1, 2,  3,  4,  5,  6,  7,  8,  9,  0, 0,
                                0, 10, 11, 12, 13, 14, 15, 16, 17, 18};
    write_bytes(dir.file("blob_call11.bin"), rgb);
    // Stride 16: x, y, z and a float of padding (the last vertex needs only 12 bytes).
    write_bytes(dir.file("blob_call25.bin"),
                bytes_of<float>({0, 0, 0, 99, 1, 0, 0, 99, 1, 1, 0, 99, 0, 1, 0.5f}));
    write_bytes(dir.file("blob_call28.bin"), bytes_of<float>({0, 0, 1, 0, 1, 1, 0, 1}));
    write_bytes(dir.file("blob_call30.bin"), bytes_of<uint16_t>({0, 1, 3, 2}));
  }
  void write_text(const std::string& text) {
    std::ofstream o(dump);
    o << text;
  }
  std::string error_of(uint32_t first, uint32_t last) {
    try {
      import_apitrace_dump(dump, dir.file("."), first, last, out, "cap.trace");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  void replace(const std::string& from, const std::string& to) {
    std::string t = kDump;
    const size_t at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    write_text(t);
  }
};

void expect_clip(const Draw& d, uint32_t v, double x, double y, double z, double w) {
  EXPECT_NEAR(d.position[4 * v + 0], x, 1e-6) << "vertex " << v;
  EXPECT_NEAR(d.position[4 * v + 1], y, 1e-6) << "vertex " << v;
  EXPECT_NEAR(d.position[4 * v + 2], z, 1e-6) << "vertex " << v;
  EXPECT_NEAR(d.position[4 * v + 3], w, 1e-6) << "vertex " << v;
}

TEST_F(ApitraceImportTest, ClipPositionsStateAndTexturesMatchHandComputation) {
  const ImportSummary s = import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  const DrawTrace t = read_draw_trace(out);
  ASSERT_EQ(t.frames.size(), 1u);
  EXPECT_EQ(t.frames[0].number, 1u);
  ASSERT_EQ(t.frames[0].draws.size(), 2u);

  // Ortho(0, 64, 0, 32, -1, 1): x/32 - 1, y/16 - 1, -z. Modelview: (2x + 8, 2y + 4, z).
  const Draw& a = t.frames[0].draws[0];
  ASSERT_EQ(a.vertex_count, 4u);
  expect_clip(a, 0, -0.75, -0.75, 0, 1);
  expect_clip(a, 1, -0.6875, -0.75, 0, 1);
  expect_clip(a, 2, -0.6875, -0.625, 0, 1);
  expect_clip(a, 3, -0.75, -0.625, -0.5, 1);
  // The strip 0, 1, 3, 2 as triangles, the odd one with its first two swapped.
  EXPECT_EQ(a.indices, (std::vector<uint32_t>{0, 1, 3, 3, 1, 2}));
  EXPECT_EQ(a.color[0], 255);
  EXPECT_EQ(a.color[1], 128);
  EXPECT_EQ(a.color[2], 0);
  EXPECT_EQ(a.st[0], (std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}));
  ASSERT_EQ(a.units.size(), 1u);
  EXPECT_EQ(a.units[0].texture, 0u);
  EXPECT_EQ(a.units[0].min_filter, 0x2601u);
  EXPECT_EQ(a.units[0].wrap_s, 0x812Fu);
  EXPECT_EQ(a.units[0].wrap_t, 0x2901u);
  EXPECT_FLOAT_EQ(a.units[0].max_anisotropy, 8);
  EXPECT_EQ(a.units[0].env_mode, 0x1E01u);
  EXPECT_TRUE(a.state.depth_test);
  EXPECT_EQ(a.state.depth_func, 0x0203u);
  EXPECT_TRUE(a.state.blend);
  EXPECT_EQ(a.state.blend_src, 0x0302u);
  EXPECT_EQ(a.state.blend_dst, 0x0303u);
  EXPECT_EQ(a.state.viewport_w, 64u);
  EXPECT_EQ(a.state.viewport_h, 32u);

  // Rotated 90 degrees about z first: (x, y) -> (-y, x); vertices 1..3 renumbered 0..2.
  const Draw& b = t.frames[0].draws[1];
  ASSERT_EQ(b.vertex_count, 3u);
  expect_clip(b, 0, -0.75, -0.625, 0, 1);
  expect_clip(b, 1, -0.8125, -0.625, 0, 1);
  expect_clip(b, 2, -0.8125, -0.75, -0.5, 1);
  EXPECT_EQ(b.indices, (std::vector<uint32_t>{0, 1, 2}));

  // The texture: 3x2 RGB with rows padded to 4 bytes, expanded to RGBA; only its base level
  // (the min filter does not use mipmaps).
  ASSERT_EQ(t.textures.size(), 1u);
  EXPECT_EQ(t.textures[0].width, 3u);
  EXPECT_EQ(t.textures[0].height, 2u);
  ASSERT_EQ(t.textures[0].levels.size(), 1u);
  EXPECT_EQ(t.textures[0].levels[0],
            (std::vector<uint8_t>{1,  2,  3,  255, 4,  5,  6,  255, 7,  8,  9,  255,
                                  10, 11, 12, 255, 13, 14, 15, 255, 16, 17, 18, 255}));

  // What was not interpreted is counted, in the summary and in the trace.
  const CallCounts want = {
      {"glEnable(GL_FOG)", 1}, {"glScissor", 1}, {"glDrawArrays[points or lines]", 1}};
  EXPECT_EQ(t.frames[0].uninterpreted, want);
  EXPECT_EQ(s.frames.at(1).uninterpreted, want);
  EXPECT_EQ(s.frames.at(1).draws, 2u);
  EXPECT_EQ(s.frames.at(1).triangles, 3u);
}

// Frame 1's arrays and indices in buffer objects instead of client memory: the same draws.
// The vertex buffer is bound only while the pointers are set (GL takes the binding then); the
// data arrives by glBufferSubData at offsets, the indices 2 bytes into an element buffer.
class ApitraceBufferTest : public ApitraceImportTest {
 protected:
  void use_buffers(const std::string& draw_indices = "0x2") {
    std::string t = kDump;
    auto swap = [&](const std::string& from, const std::string& to) {
      const size_t at = t.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      t.replace(at, from.size(), to);
    };
    swap("25 glVertexPointer(3, GL_FLOAT, 16, blob(\"blob_call25.bin\")) // fake",
         "240 glGenBuffers(2, {3, 4})\n"
         "241 glBindBuffer(GL_ARRAY_BUFFER, 3)\n"
         "242 glBufferData(GL_ARRAY_BUFFER, 128, NULL, GL_STATIC_DRAW)\n"
         "243 glBufferSubData(GL_ARRAY_BUFFER, 16, 60, blob(\"blob_call243.bin\"))\n"
         "244 glBufferSubData(GL_ARRAY_BUFFER, 80, 32, blob(\"blob_call244.bin\"))\n"
         "25 glVertexPointer(3, GL_FLOAT, 16, 0x10)");
    swap("28 glTexCoordPointer(2, GL_FLOAT, 0, blob(\"blob_call28.bin\")) // fake",
         "28 glTexCoordPointer(2, GL_FLOAT, 0, 0x50)\n"
         "245 glBindBuffer(GL_ARRAY_BUFFER, 0)\n"
         "246 glBindBufferARB(GL_ELEMENT_ARRAY_BUFFER, 4)\n"
         "247 glBufferDataARB(GL_ELEMENT_ARRAY_BUFFER, 10, blob(\"blob_call247.bin\"), "
         "GL_STATIC_DRAW)");
    swap("GL_UNSIGNED_SHORT, blob(\"blob_call30.bin\"))",
         "GL_UNSIGNED_SHORT, " + draw_indices + ")");
    write_text(t);
    write_bytes(dir.file("blob_call243.bin"),
                bytes_of<float>({0, 0, 0, 99, 1, 0, 0, 99, 1, 1, 0, 99, 0, 1, 0.5f}));
    write_bytes(dir.file("blob_call244.bin"), bytes_of<float>({0, 0, 1, 0, 1, 1, 0, 1}));
    write_bytes(dir.file("blob_call247.bin"), bytes_of<uint16_t>({77, 0, 1, 3, 2}));
  }
};

TEST_F(ApitraceBufferTest, BufferObjectsGiveTheClientArraysDraws) {
  import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  const DrawTrace client = read_draw_trace(out);
  use_buffers();
  const std::string out2 = dir.file("buffered.draws");  // `out` is now an input of the test
  const ImportSummary s = import_apitrace_dump(dump, dir.file("."), 1, 1, out2, "cap.trace");
  const DrawTrace buffered = read_draw_trace(out2);
  ASSERT_EQ(client.frames[0].draws.size(), 2u);
  ASSERT_EQ(buffered.frames[0].draws.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Draw& a = client.frames[0].draws[i];
    const Draw& b = buffered.frames[0].draws[i];
    EXPECT_EQ(a.position, b.position) << i;
    EXPECT_EQ(a.st[0], b.st[0]) << i;
    EXPECT_EQ(a.indices, b.indices) << i;
    EXPECT_EQ(a.color, b.color) << i;
  }
  EXPECT_EQ(s.frames.at(1).uninterpreted, client.frames[0].uninterpreted);
}

TEST_F(ApitraceBufferTest, MappedContentsAreCountedAndBadRangesAreErrors) {
  use_buffers();  // then the vertex buffer mapped before its pointer is set
  std::string t;
  {
    std::ifstream in(dump);
    t.assign(std::istreambuf_iterator<char>(in), {});
  }
  t.replace(t.find("25 glVertexPointer"), 0, "248 glMapBuffer(GL_ARRAY_BUFFER, GL_WRITE_ONLY)\n");
  write_text(t);
  const ImportSummary s = import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  EXPECT_EQ(s.frames.at(1).draws, 0u);  // the contents written through the mapping are unknown
  EXPECT_EQ(s.frames.at(1).uninterpreted.at("glMapBuffer"), 1u);
  EXPECT_EQ(s.frames.at(1).uninterpreted.at("glDrawElements[buffer object contents unknown]"), 1u);

  std::filesystem::remove(out);
  use_buffers("0x6");  // 4 indices from byte 6 of a 10-byte buffer
  std::string e = error_of(1, 1);
  EXPECT_NE(e.find("call 30 (glDrawElements), frame 1: indices of 4 bytes, 4 indices need 8"),
            std::string::npos)
      << e;
  use_buffers();
  write_bytes(dir.file("blob_call244.bin"), bytes_of<float>({0, 0, 1, 0}));  // short blob
  e = error_of(1, 1);
  EXPECT_NE(e.find("call 244 (glBufferSubData), frame 1"), std::string::npos) << e;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// Deleted names: a draw reading a deleted buffer, or with its texture deleted, is counted.
TEST_F(ApitraceBufferTest, DeletedBuffersAndTexturesLeaveTheDrawOut) {
  use_buffers();
  std::string t;
  {
    std::ifstream in(dump);
    t.assign(std::istreambuf_iterator<char>(in), {});
  }
  t.replace(t.find("29 glColor4f"), 0, "249 glDeleteBuffers(1, &3)\n");
  write_text(t);
  ImportSummary s = import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  EXPECT_EQ(s.frames.at(1).draws, 0u);
  EXPECT_EQ(s.frames.at(1).uninterpreted.at("glDrawElements[buffer object contents unknown]"), 1u);
  std::filesystem::remove(out);
  replace("29 glColor4f", "249 glDeleteTextures(2, {7, 5})\n29 glColor4f");
  s = import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  EXPECT_EQ(s.frames.at(1).draws, 0u);
  uint64_t left_out = 0;
  for (const auto& [name, n] : s.frames.at(1).uninterpreted)
    if (name.starts_with("glDrawElements[")) left_out += n;
  EXPECT_EQ(left_out, 1u);
}

// The texture matrix: frame 1's first draw with s, t scaled by 2 and shifted by (0.5, 0.25);
// with a projective matrix (q = 2 s + 1) the draw is counted, not written.
TEST_F(ApitraceImportTest, TextureMatrixMovesTheCoordinates) {
  replace("29 glColor4f(1, 0.5, 0, 1)",
          "290 glMatrixMode(GL_TEXTURE)\n291 glTranslatef(0.5, 0.25, 0)\n292 glScalef(2, 2, 1)\n"
          "293 glMatrixMode(GL_MODELVIEW)\n29 glColor4f(1, 0.5, 0, 1)");
  import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  const DrawTrace t = read_draw_trace(out);
  ASSERT_GE(t.frames[0].draws.size(), 1u);
  EXPECT_EQ(t.frames[0].draws[0].st[0],
            (std::vector<float>{0.5f, 0.25f, 2.5f, 0.25f, 2.5f, 2.25f, 0.5f, 2.25f}));
  std::filesystem::remove(out);
  replace(
      "29 glColor4f(1, 0.5, 0, 1)",
      "290 glMatrixMode(GL_TEXTURE)\n291 glLoadMatrixf({1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, "
      "0, 1})\n293 glMatrixMode(GL_MODELVIEW)\n29 glColor4f(1, 0.5, 0, 1)");
  const ImportSummary s = import_apitrace_dump(dump, dir.file("."), 1, 1, out, "cap.trace");
  EXPECT_EQ(s.frames.at(1).uninterpreted.at("glDrawElements[projective texture coordinates]"), 1u);
}

TEST_F(ApitraceImportTest, FramesBeyondTheCaptureAreAnError) {
  const std::string e = error_of(2, 5);
  EXPECT_NE(e.find("cap.trace: the capture ends in frame 3"), std::string::npos) << e;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(ApitraceImportTest, IndexPastTheVertexArrayNamesCallAndFrame) {
  write_bytes(dir.file("blob_call30.bin"), bytes_of<uint16_t>({0, 1, 3, 9}));
  const std::string e = error_of(1, 1);
  EXPECT_NE(e.find("cap.trace: call 30 (glDrawElements), frame 1"), std::string::npos) << e;
  EXPECT_NE(e.find("ends before vertex 4"), std::string::npos) << e;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(ApitraceImportTest, BadDumpsAreClearErrors) {
  replace("blob(\"blob_call30.bin\")", "blob(8)");
  EXPECT_NE(error_of(1, 1).find("--blobs"), std::string::npos);
  replace("34 glPopMatrix()", "34 glPopMatrix()\n34 glPopMatrix()");
  EXPECT_NE(error_of(1, 1).find("call 34 (glPopMatrix), frame 1: matrix stack underflow"),
            std::string::npos);
  replace("blob(\"blob_call28.bin\")", "blob(\"../etc/passwd\")");
  EXPECT_NE(error_of(1, 1).find("is not the call's"), std::string::npos);
  replace("8 glGenTextures(1, &5)", "garbage line");
  EXPECT_NE(error_of(1, 1).find("not a call"), std::string::npos);
  replace("6 glTranslatef(8, 4, 0)", "6 glTranslatef(8, 4)");
  EXPECT_NE(error_of(1, 1).find("2 arguments, expected 3"), std::string::npos);
  write_text(kDump);
  write_bytes(dir.file("blob_call25.bin"),
              bytes_of<float>({0, 0, 0, 99, NAN, 0, 0, 99, 1, 1, 0, 99, 0, 1, 0.5f}));
  // A NaN in the application's vertex array: an error naming the call, not a NaN in the trace.
  EXPECT_NE(error_of(1, 1).find("clip-space position is not a finite"), std::string::npos);
}

TEST_F(ApitraceImportTest, FrameRanges) {
  uint32_t a = 0, b = 0;
  parse_frame_range("3-7", a, b);
  EXPECT_EQ(a, 3u);
  EXPECT_EQ(b, 7u);
  parse_frame_range("4", a, b);
  EXPECT_EQ(a, 4u);
  EXPECT_EQ(b, 4u);
  EXPECT_THROW(parse_frame_range("7-3", a, b), InputError);
  EXPECT_THROW(parse_frame_range("x", a, b), InputError);
  EXPECT_THROW(parse_frame_range("-3", a, b), InputError);
}

// The shipped sample (traces/samples/README.md) reads back through the strict reader.
TEST(ApitraceSample, ShippedDrawTraceReads) {
  const DrawTrace t =
      read_draw_trace(std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/openarena-aggressor.draws");
  ASSERT_EQ(t.frames.size(), 3u);
  for (const DrawFrame& f : t.frames) EXPECT_GT(f.draws.size(), 10u);
  EXPECT_GT(t.textures.size(), 5u);
}

}  // namespace
}  // namespace texsim
