// CSV form of trace format v1 (traces/FORMAT.md, "CSV form"): exact round trips, the liberties
// a hand-written file may take, and every syntax error reported as file:line:column.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "testbench/lib/temp_dir.h"
#include "traces/trace_csv.h"
#include "traces/trace_file.h"

namespace texsim {
namespace {

namespace fs = std::filesystem;

void spit(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

::testing::AssertionResult same_fragment(const Fragment& a, const Fragment& b) {
  const bool ok = a.frame == b.frame && a.prim == b.prim && a.x == b.x && a.y == b.y &&
                  a.tex == b.tex && same_bits(a.u, b.u) && same_bits(a.v, b.v) &&
                  same_bits(a.dudx, b.dudx) && same_bits(a.dvdx, b.dvdx) &&
                  same_bits(a.dudy, b.dudy) && same_bits(a.dvdy, b.dvdy) &&
                  std::bit_cast<uint32_t>(a.lod_bias) == std::bit_cast<uint32_t>(b.lod_bias);
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "fragments differ: u " << a.u << "/" << b.u << " v " << a.v << "/" << b.v
         << " lod_bias " << a.lod_bias << "/" << b.lod_bias;
}

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

std::vector<Fragment> random_fragments(size_t n, bool lod, uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto any_double = [&rng]() {
    double d;
    do d = std::bit_cast<double>(rng());
    while (!std::isfinite(d));
    return d;
  };
  std::vector<Fragment> out(n);
  for (size_t i = 0; i < n; ++i) {
    Fragment& f = out[i];
    f.frame = static_cast<uint32_t>(rng());
    f.prim = static_cast<uint32_t>(i);
    f.x = static_cast<uint32_t>(rng() % 1920);
    f.y = static_cast<uint32_t>(rng() % 1080);
    f.tex = static_cast<uint32_t>(rng() % 2) * 5;  // ids 0 and 5
    // Bit patterns (every exponent, subnormals, -0) and "ordinary" values.
    f.u = (i % 2) ? any_double() : std::uniform_real_distribution<double>(-2, 2)(rng);
    f.v = (i % 3) ? any_double() : -0.0;
    f.dudx = any_double();
    f.dvdx = std::numeric_limits<double>::denorm_min() * static_cast<double>(i % 5);
    f.dudy = (i % 7 == 0) ? std::numeric_limits<double>::max() : any_double();
    f.dvdy = 1.0 / static_cast<double>(i + 3);
    if (lod) {
      float b;
      do b = std::bit_cast<float>(static_cast<uint32_t>(rng()));
      while (!std::isfinite(b));
      f.lod_bias = b;
    }
  }
  return out;
}

TraceHeader header(bool lod) {
  TraceHeader h;
  h.has_lod_bias = lod;
  h.textures = {{0, "checker", "procedural:checker?size=512&cells=16", 512, 512},
                {5, "wall \"old\" bricks", "C:\\textures\\my bricks.png", 256, 128}};
  return h;
}

// ---- round trips -----------------------------------------------------------------------------

TEST(TraceCsv, ExactRoundTripWithAndWithoutLodBias) {
  for (bool lod : {true, false}) {
    SCOPED_TRACE(lod ? "with lod_bias" : "without lod_bias");
    TempDir dir("texsim_trace_csv");
    const std::string path = dir.file("t.csv");
    const auto frags = random_fragments(2000, lod, 21);
    write_trace(path, header(lod), frags);
    TraceHeader h;
    const auto back = read_trace(path, &h);
    EXPECT_EQ(h.encoding, TraceEncoding::Csv);
    EXPECT_EQ(h.has_lod_bias, lod);
    ASSERT_EQ(h.textures.size(), 2u);
    EXPECT_EQ(h.textures[1].name, "wall \"old\" bricks");
    EXPECT_EQ(h.textures[1].source, "C:\\textures\\my bricks.png");
    EXPECT_EQ(h.textures[1].id, 5u);
    EXPECT_EQ(h.textures[1].width, 256u);
    EXPECT_EQ(h.textures[1].height, 128u);
    ASSERT_EQ(back.size(), frags.size());
    for (size_t i = 0; i < frags.size(); ++i)
      ASSERT_TRUE(same_fragment(back[i], frags[i])) << "record " << i;
  }
}

TEST(TraceCsv, StreamsInChunks) {
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("long.csv");
  const auto frags = random_fragments(10000, false, 22);
  write_trace(path, header(false), frags);
  TraceReader r(path);
  EXPECT_EQ(r.header().records_per_chunk, kCsvRecordsPerChunk);
  std::vector<Fragment> chunk;
  std::vector<size_t> sizes;
  size_t i = 0;
  while (size_t n = r.next_chunk(chunk)) {
    sizes.push_back(n);
    for (const Fragment& f : chunk) ASSERT_TRUE(same_fragment(f, frags[i++]));
  }
  EXPECT_EQ(sizes, (std::vector<size_t>{4096, 4096, 1808}));
  EXPECT_EQ(r.records_read(), 10000u);
}

TEST(TraceCsv, CsvToBinaryAndBackIsIdentical) {
  TempDir dir("texsim_trace_csv");
  const auto frags = random_fragments(777, true, 23);
  const std::string a = dir.file("a.csv"), b = dir.file("b.trc"), c = dir.file("c.csv");
  write_trace(a, header(true), frags);
  write_trace(b, header(true), read_trace(a));
  write_trace(c, header(true), read_trace(b));
  EXPECT_EQ(slurp(a), slurp(c));
}

TEST(TraceCsv, HandWrittenLiberties) {
  // Comments anywhere, blank lines, CRLF, spaces around values, a leading '+', columns in any
  // order, an unknown column (skipped), quoted directive values, no newline at the end.
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("hand.csv");
  spit(path,
       "# a comment\r\n"
       "\r\n"
       "  # texture 3 \"my tex\" \"procedural:noise?octaves=4\" 64 32\r\n"
       "#texture 9 plain p.png 1 65536\n"
       "# textures are listed above (a comment: 'textures' is not the directive word)\n"
       "v, u ,depth,frame,prim,x,y,tex,dudx,dvdx,dudy,dvdy\n"
       "0.25, 0.5 ,7.5,1,2,3,4,3,+1e-3,-0,0,1E2\r\n"
       "# between records\n"
       "\n"
       "   -1.5,2,x,0,0,0,0,9,0,0,0,0");
  TraceHeader h;
  const auto frags = read_trace(path, &h);
  ASSERT_EQ(h.textures.size(), 2u);
  EXPECT_EQ(h.textures[0].name, "my tex");
  EXPECT_EQ(h.textures[0].source, "procedural:noise?octaves=4");
  EXPECT_EQ(h.textures[1].height, 65536u);
  EXPECT_FALSE(h.has_lod_bias);
  ASSERT_EQ(h.fields.size(), 12u);
  EXPECT_EQ(h.fields[2].name, "depth");
  ASSERT_EQ(frags.size(), 2u);
  EXPECT_EQ(frags[0].u, 0.5);
  EXPECT_EQ(frags[0].v, 0.25);
  EXPECT_EQ(frags[0].frame, 1u);
  EXPECT_EQ(frags[0].prim, 2u);
  EXPECT_EQ(frags[0].x, 3u);
  EXPECT_EQ(frags[0].y, 4u);
  EXPECT_EQ(frags[0].tex, 3u);
  EXPECT_EQ(frags[0].dudx, 1e-3);
  EXPECT_TRUE(std::signbit(frags[0].dvdx));
  EXPECT_EQ(frags[0].dvdy, 100.0);
  EXPECT_EQ(frags[1].v, -1.5);
  EXPECT_EQ(frags[1].tex, 9u);
  EXPECT_EQ(frags[1].lod_bias, 0.0f);
}

TEST(TraceCsv, StorageIsAnOptionalSixthDirectiveValue) {
  // Version 3: a directive may end with the texture's storage, quoted or not; the writer adds
  // it only to textures that have one and the reader reports version 3.
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("s.csv");
  spit(path,
       "# texture 0 a p.png 8 8 \"compress=bc1_rgb,squish,range\"\n"
       "# texture 1 b q.png 8 8\tformat=rgb565\n"
       "# texture 2 c r.png 8 8\n"
       "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n"
       "0,0,0,0,2,0.5,0.5,0,0,0,0\n");
  TraceHeader h;
  const auto frags = read_trace(path, &h);
  EXPECT_EQ(h.version, 3u);
  ASSERT_EQ(h.textures.size(), 3u);
  EXPECT_EQ(h.textures[0].storage, "compress=bc1_rgb,squish,range");
  EXPECT_EQ(h.textures[1].storage, "format=rgb565");
  EXPECT_EQ(h.textures[2].storage, "");
  const std::string out = dir.file("out.csv");
  write_trace(out, h, frags);
  std::ifstream in(out);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_NE(text.find("format v3"), std::string::npos) << text;
  EXPECT_NE(text.find("# texture 0 a p.png 8 8 compress=bc1_rgb,squish,range\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("# texture 2 c r.png 8 8\n"), std::string::npos) << text;
}

TEST(TraceCsv, OpenedByExtensionOnlyWhenNotBinary) {
  // A binary trace named .csv is still binary (content wins); a CSV named .trc is bad magic.
  TempDir dir("texsim_trace_csv");
  const std::string bin_as_csv = dir.file("really_binary.csv.trc");
  write_trace(bin_as_csv, header(false), random_fragments(3, false, 24));
  const std::string renamed = dir.file("really_binary.csv");
  fs::rename(bin_as_csv, renamed);
  TraceReader r(renamed);
  EXPECT_EQ(r.header().encoding, TraceEncoding::Binary);
  const std::string csv_as_trc = dir.file("text.trc");
  spit(csv_as_trc, "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n");
  expect_input_error([&] { TraceReader t(csv_as_trc); },
                     {csv_as_trc, "bad magic", "not named .csv"});
}

// ---- errors: file:line:column ------------------------------------------------------------------

const char* kHead =
    "# texture 0 t procedural:checker 8 8\n"         // line 1
    "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n";  // line 2

void expect_csv_error(const std::string& body, const std::string& where, const std::string& what,
                      const std::string& head = kHead) {
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("bad.csv");
  spit(path, head + body);
  SCOPED_TRACE(body);
  expect_input_error([&] { read_trace(path); }, {path + ":" + where + ": ", what});
}

TEST(TraceCsvErrors, WrongColumnCount) {
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0\n0,0,0,0,0,0.5,0.5,0,0,0\n", "4:24",
                   "expected 11 columns, found 10");
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,1,2\n", "3:27", "expected 11 columns, found 13");
  expect_csv_error("\n\n# c\n0,0,0,0,0,0.5,0.5,0,0,0,0,\n", "6:27",
                   "expected 11 columns, found 12");
}

TEST(TraceCsvErrors, NotANumber) {
  expect_csv_error("0,0,0,0,0,0.5,abc,0,0,0,0\n", "3:15", "column 'v': 'abc' is not a number");
  expect_csv_error("0,0,0,0,0,0.5,0.5x,0,0,0,0\n", "3:15", "'0.5x' is not a number");
  expect_csv_error("0,0,0,0,0,0.5,,0,0,0,0\n", "3:15", "column 'v': empty value");
  expect_csv_error("0,0,1.5,0,0,0.5,0.5,0,0,0,0\n", "3:5",
                   "column 'x': '1.5' is not an unsigned integer");
  expect_csv_error("0,-1,0,0,0,0.5,0.5,0,0,0,0\n", "3:3",
                   "column 'prim': '-1' is not an unsigned integer");
  expect_csv_error("4294967296,0,0,0,0,0.5,0.5,0,0,0,0\n", "3:1",
                   "'4294967296' is out of range for u32");
  expect_csv_error("0,0,0,0,0,1e999,0.5,0,0,0,0\n", "3:11", "'1e999' is out of range for f64");
}

TEST(TraceCsvErrors, NonFiniteValues) {
  expect_csv_error("0,0,0,0,0,nan,0.5,0,0,0,0\n", "3:11", "field 'u' is NaN");
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,  -inf\n", "3:27", "field 'dvdy' is infinite");
  expect_csv_error("0,0,0,0,0,0.5,0.5,infinity,0,0,0\n", "3:19", "field 'dudx' is infinite");
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,nan\n", "3:27", "field 'lod_bias' is NaN",
                   "# texture 0 t p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,lod_bias\n");
}

TEST(TraceCsvErrors, TextureIdNotInTable) {
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0\n0,0,0,0, 4 ,0.5,0.5,0,0,0,0\n", "4:10",
                   "texture id 4 is not in the texture table");
}

TEST(TraceCsvErrors, ColumnHeaderProblems) {
  expect_csv_error("", "2:1", "missing required column 'dvdy'",
                   "# texture 0 t p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy\n");
  expect_csv_error("", "2:44", "column 'dudx' appears twice",
                   "# texture 0 t p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,dudx\n");
  expect_csv_error("", "1:7", "empty column name", "frame,,prim\n");
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("only_comments.csv");
  spit(path, "# texture 0 t p 8 8\n# nothing else\n\n");
  expect_input_error([&] { TraceReader r(path); }, {path, "no column header line"});
  const std::string empty = dir.file("empty.csv");
  spit(empty, "");
  expect_input_error([&] { TraceReader r(empty); }, {empty, "no column header line"});
}

TEST(TraceCsvErrors, DirectiveProblems) {
  const std::string cols = "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n";
  expect_csv_error("", "1:3", "texture directive needs 5 or 6 values",
                   "# texture 0 t p 8\n" + cols);
  expect_csv_error("", "1:3", "found 7", "# texture 0 t p 8 8 format=r8 x\n" + cols);
  expect_csv_error("", "1:3", "texture 0: storage 'rgb565' is neither",
                   "# texture 0 t p 8 8 rgb565\n" + cols);
  expect_csv_error("", "1:11", "texture id: 'zero' is not an unsigned integer",
                   "# texture zero t p 8 8\n" + cols);
  expect_csv_error("", "1:17", "texture width: '-8'", "# texture 0 t p -8 8\n" + cols);
  expect_csv_error("", "1:3", "texture 0: size 8x65537 is outside 1..65536",
                   "# texture 0 t p 8 65537\n" + cols);
  expect_csv_error("", "1:3", "texture 0: size 0x8 is outside", "# texture 0 t p 0 8\n" + cols);
  expect_csv_error("", "2:11", "texture id 0 appears twice",
                   "# texture 0 t p 8 8\n# texture 0 u q 8 8\n" + cols);
  expect_csv_error("", "1:13", "unterminated quoted value", "# texture 0 \"t p 8 8\n" + cols);
  expect_csv_error("", "1:16", "expected a space after the closing quote",
                   "# texture 0 \"t\"p q 8 8\n" + cols);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0\n# texture 1 late p 8 8\n", "4:3",
                   "texture directive after the column header line");
}

TEST(TraceCsvErrors, OverlongLineDoesNotGrowWithoutBound) {
  const std::string huge(kCsvMaxLineBytes + 10, '1');
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0\n" + huge + "\n", "4:1",
                   "line longer than 65536 bytes");
  expect_csv_error(huge, "3:1", "line longer than 65536 bytes");  // no newline at the end
}

TEST(TraceCsvErrors, LineNumbersStayRightAcrossReadBuffers) {
  // More than one 1 MiB read buffer of valid lines, then a bad one.
  std::string body;
  const std::string line = "0,0,0,0,0,0.5,0.5,0,0,0,0\n";
  const size_t n = (3u << 20) / line.size();
  for (size_t i = 0; i < n; ++i) body += line;
  body += "0,0,0,0,0,0.5,0.5,0,0,0,oops\n";
  expect_csv_error(body, std::to_string(n + 3) + ":25", "'oops' is not a number");
}

// ---- writer ---------------------------------------------------------------------------------

TEST(TraceCsvWriter, FailedWriteLeavesNoFile) {
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("out.csv");
  {
    TraceCsvWriter w(path, header(true));
    auto f = random_fragments(2, true, 25);
    w.write(f[0]);
    f[1].lod_bias = std::numeric_limits<float>::infinity();
    expect_input_error([&] { w.write(f[1]); }, {path, "record 1", "'lod_bias' is infinite"});
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(dir.entries(), 0u);
  const std::string nodir = dir.file("no/such/dir.csv");
  expect_input_error([&] { TraceCsvWriter w(nodir, header(false)); },
                     {nodir, "cannot open for writing"});
  EXPECT_EQ(dir.entries(), 0u);
}

TEST(TraceCsvWriter, QuotesOnlyWhatNeedsQuoting) {
  EXPECT_EQ(csv_quote_token("plain.png"), "plain.png");
  EXPECT_EQ(csv_quote_token("procedural:checker?size=512&cells=16"),
            "procedural:checker?size=512&cells=16");
  EXPECT_EQ(csv_quote_token(""), "\"\"");
  EXPECT_EQ(csv_quote_token("a b"), "\"a b\"");
  EXPECT_EQ(csv_quote_token("say \"hi\"\\"), "\"say \\\"hi\\\"\\\\\"");
}

}  // namespace
}  // namespace texsim

namespace texsim {
namespace {

// Version 4: operation columns, each optional; a record whose operation needs a column the
// trace lacks, and out-of-range values, are errors naming the line and column.
TEST(TraceCsvVersion4, OperationColumns) {
  const std::string head =
      "# texture 0 t p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,op,lod,offset_u\n";
  TempDir dir("texsim_trace_csv");
  const std::string path = dir.file("ops.csv");
  spit(path, head + "0,0,0,0,0,0.5,0.5,0,0,0,0,1,2.5,-8\n0,0,1,0,0,0.5,0.5,0,0,0,0,2,0,7\n");
  TraceHeader h;
  const std::vector<Fragment> got = read_trace(path, &h);
  EXPECT_EQ(h.version, 4u);
  EXPECT_TRUE(h.has_ops);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].op, 1);
  EXPECT_EQ(got[0].lod, 2.5f);
  EXPECT_EQ(got[0].offset_u, -8);
  EXPECT_EQ(got[1].op, 2);
  EXPECT_EQ(got[1].offset_u, 7);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,3,0,0\n", "3:1",
                   "operation 'gather' needs the field 'gather_comp', which the trace lacks", head);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,4,0,0\n", "3:1", "field 'op' is 4", head);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,1,0,8\n", "3:1", "outside the texel offsets", head);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,1,nan,0\n", "3:29", "field 'lod' is NaN", head);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,1,0,-129\n", "3:31", "'-129' is outside -128..127",
                   head);
  expect_csv_error("0,0,0,0,0,0.5,0.5,0,0,0,0,1\n", "3:1",
                   "operation 'lod' needs the field 'lod', which the trace lacks",
                   "# texture 0 t p 8 8\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,op\n");
}

}  // namespace
}  // namespace texsim
