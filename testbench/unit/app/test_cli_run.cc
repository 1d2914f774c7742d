// End-to-end tests of the texsim binary: `run` on the built-in scene writes the report keys,
// images and accuracy; `trace gen` round-trips through `run --trace`; bad input gives one
// clear message (file, line:column or record, what is wrong), exit code 2, and no outputs.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)
namespace fs = std::filesystem;

TEST_F(Cli, RunDefaultSceneWritesReportImagesAndAccuracy) {
  const std::string out = path("out");
  const Result r = sh("run --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find(out + "/report.json"), std::string::npos) << r.out;
  for (const char* f : {"report.json", "report.md", "image.png", "reference.png", "error.png"}) {
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  }
  const Json j = load_json(out + "/report.json");
  const double frags = num(j, "fragments");
  EXPECT_GT(frags, 10000);
  EXPECT_GT(num(j, "cycles"), frags);  // trilinear needs two cache cycles per fragment
  EXPECT_GT(num(j, "blocks.lod.ops.lut"), 0);
  EXPECT_EQ(num(j, "blocks.lod.ops.lut"), frags);  // one log2 per fragment
  EXPECT_GT(num(j, "blocks.filter.trilinear.ops.mul"), 0);
  EXPECT_GT(num(j, "blocks.filter.bilinear.ops.mul"), 0);
  EXPECT_EQ(find(j, "blocks.filter.nearest"), nullptr);  // no material uses it: not instantiated
  EXPECT_GT(num(j, "cache.hits"), num(j, "cache.misses"));
  EXPECT_GT(num(j, "cache.misses"), 0);
  // Filtering error against the supersampled ground truth: real, neither zero nor garbage.
  EXPECT_GT(num(j, "accuracy.psnr_db"), 18.0);
  EXPECT_LT(num(j, "accuracy.psnr_db"), 60.0);
  EXPECT_GT(num(j, "accuracy.nmse"), 0.0);
  EXPECT_LT(num(j, "accuracy.nmse"), 0.1);
  EXPECT_GT(num(j, "accuracy.max_abs"), 0.0);
  EXPECT_LE(num(j, "accuracy.max_abs"), 1.0);
}

TEST_F(Cli, PhotoSceneWithAnisotropyAndMortonLayout) {
  // Photographs from Debian's glmark2-data (installed by scripts/setup-debian.sh).
  const std::string out = path("out");
  const Result r =
      sh(std::string("run ") + TEXSIM_SOURCE_DIR + "/scenes/photo.toml --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(out + "/report.json");
  EXPECT_GT(num(j, "fragments"), 50000);
  // Vulkan anisotropic LOD on the floor: several probes per fragment, so more address cycles.
  EXPECT_GT(num(j, "cycles_per_fragment"), 2.0);
  EXPECT_GT(num(j, "accuracy.psnr_db"), 15.0);
}

TEST_F(Cli, FootprintFiltersPerMaterial) {
  // Each material instantiates only its own filter block; the report names who uses what.
  const std::string out = path("out");
  const Result r = sh(std::string("run ") + TEXSIM_SOURCE_DIR +
                      "/scenes/footprint_filters.toml --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(out + "/report.json");
  for (const char* b : {"filter.ewa", "filter.feline", "filter.spaf", "filter.trilinear"}) {
    const Json* e = find(j, std::string("blocks.") + b);
    ASSERT_NE(e, nullptr) << b;
    EXPECT_EQ((*e)["materials"].size(), 1u) << b;
    EXPECT_GT(num(j, std::string("blocks.") + b + ".ops.mul"), 0) << b;
  }
  EXPECT_EQ(find(j, "blocks.filter.multi_probe"), nullptr);      // no material names it
  EXPECT_EQ(find(j, "blocks.lod")->at("materials").size(), 1u);  // only the trilinear one
  // Every method gets comparable pixels: fragment counts within 1 % of each other (the old
  // layout gave 606 to trilinear and SPAF, 16,889 to EWA and Feline).
  double lo = 1e18, hi = 0;
  for (const auto& [name, m] : j.at("materials").items()) {
    lo = std::min(lo, m.at("fragments").get<double>());
    hi = std::max(hi, m.at("fragments").get<double>());
  }
  EXPECT_GT(lo, 1000);
  EXPECT_LT(hi / lo, 1.01) << lo << " " << hi;
  // EWA scans many texels per fragment: far more cycles per fragment than trilinear alone.
  EXPECT_GT(num(j, "cycles_per_fragment"), 4.0);
  // Two footprint filters in one material are rejected with the place.
  write("two.toml",
        "[textures.t]\nsource = \"procedural:checker\"\n[materials.m]\ntexture = \"t\"\n"
        "ewa = {}\nspaf = {}\n[[planes]]\nmaterial = \"m\"\n");
  const Result bad = sh("run " + path("two.toml") + " --out " + path("out2"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("two.toml:6:"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("one footprint filter"), std::string::npos) << bad.out;
}

TEST_F(Cli, ReferencePixelModelIsChosenAndStated) {
  // The same view against both truths: each report names its pixel, the errors differ.
  const std::string box = path("box"), gauss = path("gauss");
  ASSERT_EQ(sh("run --no-progress --out " + box).code, 0);
  const Result r = sh("run --no-progress --set reference.pixel=gaussian --out " + gauss);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json jb = load_json(box + "/report.json"), jg = load_json(gauss + "/report.json");
  EXPECT_EQ(find(jb, "accuracy.pixel")->get<std::string>(), "box");
  EXPECT_EQ(find(jg, "accuracy.pixel")->get<std::string>(), "gaussian");
  EXPECT_NE(find(jg, "accuracy.reference")->get<std::string>().find("Gaussian"), std::string::npos);
  EXPECT_GT(std::fabs(num(jb, "accuracy.psnr_db") - num(jg, "accuracy.psnr_db")), 0.5);
  EXPECT_EQ(num(jb, "cycles"), num(jg, "cycles"));  // the truth does not touch the unit
  // An unknown pixel names the key; relief materials have only the box reference.
  const Result bad = sh("run --set reference.pixel=triangle --out " + path("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("pixel"), std::string::npos) << bad.out;
  const Result relief =
      sh(std::string("run ") + TEXSIM_SOURCE_DIR +
         "/scenes/relief_wall.toml --set reference.pixel=gaussian --out " + path("relief"));
  EXPECT_EQ(relief.code, 2);
  EXPECT_NE(relief.out.find("relief_wall.toml"), std::string::npos) << relief.out;
  EXPECT_FALSE(fs::exists(path("relief") + "/report.json"));
}

TEST_F(Cli, CoordinateUnitsPerMaterial) {
  // Materials with a coords table get their coordinates from their own unit, in a front end
  // the report shows as stages and blocks, with accuracy next to cost per material.
  const std::string out = path("out");
  const Result r = sh(std::string("run ") + TEXSIM_SOURCE_DIR +
                      "/scenes/coords.toml --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(out + "/report.json");
  ASSERT_TRUE(j["stages"].contains("coords"));
  ASSERT_TRUE(j["stages"].contains("derivs"));
  for (const char* b :
       {"coords.heckbert[float]", "coords.incremental[s20.28]", "coords.incremental[s16.16]",
        "coords.constant-depth[float]", "coords.quadratic-32[float]", "derivs.iterative[s20.28]"}) {
    ASSERT_TRUE(j["blocks"].contains(b)) << b;
    EXPECT_GT(j["blocks"][b]["ops"]["add"].get<double>(), 0) << b;
  }
  // Mirror-image strips (same geometry): the s16.16 adders lose the map's precision (G, H keep
  // 8 significant bits, docs/studies/study-coords.md), s20.28 keeps it.
  const double inc = num(j, "materials.incremental.accuracy.psnr_db");
  const double s16 = num(j, "materials.incremental_s16.accuracy.psnr_db");
  const double hk = num(j, "materials.heckbert.accuracy.psnr_db");
  const double cd = num(j, "materials.constant_depth.accuracy.psnr_db");
  EXPECT_GT(inc, s16 + 6) << inc << " vs " << s16;
  EXPECT_NEAR(hk, cd, 1.0);
  EXPECT_EQ(num(j, "materials.incremental.fragments"),
            num(j, "materials.incremental_s16.fragments"));
  EXPECT_EQ(num(j, "front_end.rejected"), 0);
  EXPECT_GT(num(j, "front_end.generated"), 0);
  // Texels per block add up to the cache's texel reads.
  EXPECT_EQ(num(j, "blocks.filter.trilinear.texels"), num(j, "cache.texel_reads"));
  // The same scene from a trace: the trace's coordinates are used, and the log says so.
  const std::string trc = path("coords.trc");
  ASSERT_EQ(
      sh(std::string("trace gen ") + TEXSIM_SOURCE_DIR + "/scenes/coords.toml -o " + trc).code, 0);
  const Result t = sh(std::string("run ") + TEXSIM_SOURCE_DIR +
                      "/scenes/coords.toml --no-progress --trace " + trc + " --out " + path("t"));
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("coords ignored"), std::string::npos) << t.out;
  const Json tj = load_json(path("t") + "/report.json");
  EXPECT_FALSE(tj["stages"].contains("coords"));
}

TEST_F(Cli, OneBlockInTwoConfigurationsIsTwoUnitsAndWeightMapKeysAreRead) {
  write("two_ewa.toml",
        "[textures.t]\nsource = \"procedural:checker?size=64&cells=8\"\n"
        "[materials.lut]\ntexture = \"t\"\newa = { weight = \"lut\" }\n"
        "[materials.map]\ntexture = \"t\"\n"
        "ewa = { weight = \"map\", weight_map = { kind = \"radial_r2\", size = 32, element = "
        "\"u8\" } }\n"
        "[[planes]]\nmaterial = \"lut\"\norigin = [-2.0, 0.0, -1.0]\nedge_u = [2.0, 0.0, "
        "0.0]\nedge_v = [0.0, 0.0, -8.0]\n"
        "[[planes]]\nmaterial = \"map\"\norigin = [0.0, 0.0, -1.0]\nedge_u = [2.0, 0.0, "
        "0.0]\nedge_v = [0.0, 0.0, -8.0]\n");
  const Result r = sh("run " + path("two_ewa.toml") + " --no-progress --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("out") + "/report.json");
  ASSERT_TRUE(j["blocks"].contains("filter.ewa[lut]")) << j["blocks"].dump();
  ASSERT_TRUE(j["blocks"].contains("filter.ewa[map]")) << j["blocks"].dump();
  const std::string map_arith = j["blocks"]["filter.ewa[map]"]["arithmetic"].get<std::string>();
  EXPECT_NE(map_arith.find("32"), std::string::npos) << map_arith;  // the map's size and
  EXPECT_NE(map_arith.find("u8"), std::string::npos) << map_arith;  // element format as set
  // A typo inside the weight map's table is an error, not ignored.
  write("typo.toml",
        "[textures.t]\nsource = \"procedural:checker\"\n[materials.m]\ntexture = \"t\"\n"
        "ewa = { weight = \"map\", weight_map = { sise = 32 } }\n[[planes]]\nmaterial = \"m\"\n");
  const Result bad = sh("run " + path("typo.toml") + " --out " + path("out2"));
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("sise"), std::string::npos) << bad.out;
}

TEST_F(Cli, ErrorMapScaleIsRecordedAndFixedOnRequest) {
  Result r = sh("run --no-progress --out " + path("a"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json a = load_json(path("a/report.json"));
  EXPECT_EQ(num(a, "error_map.scale"), num(a, "accuracy.max_abs"));
  EXPECT_TRUE(a.at("error_map").at("auto").get<bool>());
  r = sh("run --no-progress --error-scale 0.1 --out " + path("b"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json b = load_json(path("b/report.json"));
  EXPECT_EQ(num(b, "error_map.scale"), 0.1);
  EXPECT_FALSE(b.at("error_map").at("auto").get<bool>());
  EXPECT_EQ(num(b, "error_map.bar_rows"), 31);  // 240 / 12 ramp rows + 11 label rows (320 x 240)
  EXPECT_NE(slurp(path("b/report.md")).find("white 0.1 (--error-scale)"), std::string::npos);
  EXPECT_EQ(sh("run --no-progress --error-scale 0 --out " + path("c")).code, 2);
}

TEST_F(Cli, FunctionalModeHasOpsButNoCycles) {
  const std::string out = path("out");
  const Result r = sh("run --functional --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(out + "/report.json");
  EXPECT_EQ(num(j, "cycles"), 0);
  EXPECT_GT(num(j, "blocks.blend.ops.mul"), 0);
}

TEST_F(Cli, UsageErrorsExitTwoAndNameWhatIsWrong) {
  Result r = sh("frob");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("unknown command 'frob'"), std::string::npos) << r.out;
  r = sh("trace frob");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("'frob'"), std::string::npos) << r.out;
  r = sh("run --bogus");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--bogus"), std::string::npos) << r.out;
  r = sh("trace gen default");  // -o missing
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--output"), std::string::npos) << r.out;
  EXPECT_EQ(sh("").code, 2);
  // Control characters in what is echoed back are shown escaped.
  r = sh("\"$(printf 'fr\\033[2Job')\"");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(r.out.find('\033'), std::string::npos) << r.out;
}

TEST_F(Cli, HelpAndVersionExitZero) {
  Result r = sh("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("run"), std::string::npos) << r.out;
  EXPECT_EQ(sh("trace gen --help").code, 0);
  r = sh("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out.rfind("texsim ", 0), 0u) << r.out;
}

// A trace's textures are bound to the scene's materials by name, and each fragment is filtered
// with its own texture: listing the table in another order (ids and fragments consistent)
// changes nothing, and a table without a texture a material uses is refused by name.
TEST_F(Cli, TraceTexturesBindByNameNotPosition) {
  const std::string csv = path("d.csv"), shuffled = path("shuffled.csv"), part = path("part.csv");
  ASSERT_EQ(sh("trace gen default -o " + csv).code, 0);
  // The default scene's table is checker 0, grid 1, noise 2: list it as noise 0, grid 1,
  // checker 2, and swap ids 0 and 2 in the records.
  std::ifstream in(csv);
  std::ofstream out(shuffled), partial(part);
  std::string line;
  std::vector<std::string> table;
  while (std::getline(in, line)) {
    if (line.rfind("# texture ", 0) == 0) {
      table.push_back(line);
      continue;
    }
    if (!table.empty()) {
      ASSERT_EQ(table.size(), 3u);
      for (int id : {2, 1, 0}) {
        std::string e = table[static_cast<size_t>(id)];
        e[10] = static_cast<char>('0' + (2 - id));
        out << e << "\n";
      }
      partial << table[0] << "\n";  // checker only
      table.clear();
    }
    if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) {
      // frame,prim,x,y,tex,...: swap texture ids 0 and 2
      size_t at = 0;
      for (int comma = 0; comma < 4; ++comma) at = line.find(',', at) + 1;
      if (line[at] == '0')
        line[at] = '2';
      else if (line[at] == '2')
        line[at] = '0';
    }
    out << line << "\n";
    if (line.rfind("frame,", 0) == 0 || line[0] == '#') partial << line << "\n";
  }
  out.close();
  partial << "0,0,10,200,0,0.5,0.5,0.01,0,0,0.01\n";
  partial.close();
  Result r = sh("run default --no-progress --trace " + csv + " --out " + path("a"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = sh("run default --no-progress --trace " + shuffled + " --out " + path("b"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json a = load_json(path("a") + "/report.json");
  const Json b = load_json(path("b") + "/report.json");
  EXPECT_EQ(num(a, "fragments"), num(b, "fragments"));
  EXPECT_DOUBLE_EQ(num(a, "accuracy.psnr_db"), num(b, "accuracy.psnr_db"));
  EXPECT_GT(num(a, "accuracy.psnr_db"), 20.0);
  EXPECT_EQ(slurp(path("a") + "/image.png"), slurp(path("b") + "/image.png"));
  // The panel's texture (grid) is missing from a checker-only table.
  r = sh("run default --no-progress --trace " + part + " --out " + path("c"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no texture named 'grid'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("material 'panel'"), std::string::npos) << r.out;
  expect_no_outputs(path("c"));
}

TEST_F(Cli, TraceGenWritesTheFormTheExtensionNames) {
  const std::string csv = path("gen.csv"), trc = path("gen.trc");
  ASSERT_EQ(sh("trace gen default -o " + csv).code, 0);
  ASSERT_EQ(sh("trace gen default -o " + trc).code, 0);
  auto head = [](const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::string s(8, '\0');
    f.read(s.data(), 8);
    return s;
  };
  EXPECT_EQ(head(trc), "TEXSIMTR");
  EXPECT_NE(head(csv), "TEXSIMTR");
  // Both forms hold the same fragments.
  const Result a = sh("trace info " + csv), b = sh("trace info " + trc);
  ASSERT_EQ(a.code, 0) << a.out;
  ASSERT_EQ(b.code, 0) << b.out;
  auto records = [](const std::string& info) {
    const size_t at = info.find("records:");
    return at == std::string::npos ? std::string("none")
                                   : info.substr(at, info.find(" in", at) - at);
  };
  EXPECT_EQ(records(a.out), records(b.out));
  EXPECT_NE(records(a.out), "none") << a.out;
  // --set changes the scene first, as for run: a quarter of the pixels, fewer fragments; a
  // bad key names itself and writes nothing.
  const std::string small = path("small.trc");
  const Result s =
      sh("trace gen default -o " + small + " --set output.width=160 --set output.height=120");
  ASSERT_EQ(s.code, 0) << s.out;
  const Result c = sh("trace info " + small);
  EXPECT_NE(records(c.out), records(b.out)) << c.out;
  const Result bad = sh("trace gen default -o " + path("bad.trc") + " --set output.width=-5");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("width"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(path("bad.trc")));
}

// Streams and special files are written in place: "-" is standard output, and a FIFO or a
// character device stays what it is (temp-then-rename used to replace it with a regular file).
TEST_F(Cli, TraceWritersKeepStreamsAndSpecialFiles) {
  const std::string trc = path("d.trc");
  ASSERT_EQ(sh("trace gen default -o " + trc).code, 0);
  const std::string reference = slurp(trc);
  ASSERT_GT(reference.size(), 1000u);
  // Standard output: the trace's bytes, and the summary line on stderr.
  const std::string piped = path("piped.trc");
  ASSERT_EQ(std::system(
                (std::string(TEXSIM_BINARY) + " trace gen default -o - > " + piped + " 2>/dev/null")
                    .c_str()),
            0);
  EXPECT_EQ(slurp(piped), reference);
  // A FIFO read by another process.
  const std::string fifo = path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string drained = path("drained.trc");
  const std::string reader = "cat " + fifo + " > " + drained + " &";
  ASSERT_EQ(std::system(reader.c_str()), 0);
  ASSERT_EQ(sh("trace gen default -o " + fifo).code, 0);
  for (int i = 0; i < 100 && slurp(drained).size() < reference.size(); ++i) ::usleep(20000);
  EXPECT_EQ(slurp(drained), reference);
  EXPECT_TRUE(fs::is_fifo(fifo));
  ASSERT_EQ(std::system(("cat " + fifo + " > /dev/null &").c_str()), 0);
  EXPECT_EQ(sh("trace convert " + trc + " " + fifo).code, 0);
  EXPECT_TRUE(fs::is_fifo(fifo));
  // A character device (a private node like /dev/null, 1:3); creating one needs root.
  const std::string dev = path("null");
  if (::mknod(dev.c_str(), S_IFCHR | 0600, ::makedev(1, 3)) == 0) {
    EXPECT_EQ(sh("trace gen default -o " + dev).code, 0);
    EXPECT_TRUE(fs::is_character_file(dev));
  }
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST_F(Cli, TraceGenThenRunTraceMatchesSceneRun) {
  const std::string trc = path("default.trc"), csv = path("default.csv");
  Result r = sh("trace gen default -o " + trc);
  ASSERT_EQ(r.code, 0) << r.out;
  r = sh("trace convert " + trc + " " + csv);
  ASSERT_EQ(r.code, 0) << r.out;
  r = sh("trace info " + csv);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("checker"), std::string::npos) << r.out;
  ASSERT_EQ(sh("run --no-progress --out " + path("a")).code, 0);
  // The default scene driven by its own trace: same fragments and materials, so the same
  // cycles, cache behaviour and accuracy as the scene run.
  r = sh("run default --no-progress --trace " + trc + " --out " + path("b"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json a = load_json(path("a") + "/report.json");
  const Json b = load_json(path("b") + "/report.json");
  EXPECT_EQ(num(a, "fragments"), num(b, "fragments"));
  EXPECT_EQ(num(a, "cycles"), num(b, "cycles"));
  EXPECT_EQ(num(a, "cache.misses"), num(b, "cache.misses"));
  EXPECT_DOUBLE_EQ(num(a, "accuracy.psnr_db"), num(b, "accuracy.psnr_db"));
  // Trace alone (one default trilinear/wrap material, footprint ground truth): still sane.
  r = sh("run --no-progress --trace " + csv + " --out " + path("c"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json c = load_json(path("c") + "/report.json");
  EXPECT_EQ(num(a, "fragments"), num(c, "fragments"));
  EXPECT_GT(num(c, "accuracy.psnr_db"), 10.0);
}

TEST_F(Cli, SceneSyntaxErrorNamesLineAndColumn) {
  write("bad.toml", "[output]\nwidth = 320\nheight = = 7\n");
  const Result r = sh("run " + path("bad.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("bad.toml:3:"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

TEST_F(Cli, SceneTypeErrorNamesKeyLineAndColumn) {
  write("bad.toml", "[output]\nwidth = \"wide\"\n");
  const Result r = sh("run " + path("bad.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("bad.toml:2:9"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("width"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("expected an integer"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

// Timing parameters outside their documented ranges are refused with the place, instead of
// overflowing into fewer cycles, a 32-bit wrap, latency 1 or an area of null.
TEST_F(Cli, TimingParametersOutsideTheirRangesAreRefused) {
  const std::string base =
      "[output]\nwidth = 32\nheight = 32\n[textures.t]\nsource = \"procedural:checker\"\n"
      "[materials.m]\ntexture = \"t\"\n[[planes]]\nmaterial = \"m\"\n"
      "origin = [-2.0, -1.0, -4.0]\nedge_u = [4.0, 0.0, 0.0]\nedge_v = [0.0, 2.0, 0.0]\n";
  struct Case {
    std::string table, key;
  };
  for (const Case& c :
       {Case{"[pipeline.dram]\nbytes_per_cycle = 1e-300\n", "bytes_per_cycle"},
        Case{"[pipeline.dram]\nbytes_per_cycle = 1e-10\n", "bytes_per_cycle"},
        Case{"[tech.latency]\nmul = 1e19\n", "mul"}, Case{"[tech.latency]\nmul = 1e7\n", "mul"},
        Case{"[tech.area]\nmul = 1e308\n", "mul"},
        Case{"[tech]\nclock_mhz = 1e300\n", "clock_mhz"}}) {
    write("s.toml", base + c.table);
    const Result r = sh("run " + path("s.toml") + " --no-progress --out " + path("out"));
    EXPECT_EQ(r.code, 2) << c.table << r.out;
    EXPECT_NE(r.out.find("s.toml:14:"), std::string::npos) << c.table << r.out;
    EXPECT_NE(r.out.find(c.key), std::string::npos) << c.table << r.out;
    EXPECT_NE(r.out.find("must be in"), std::string::npos) << c.table << r.out;
    expect_no_outputs(path("out"));
  }
  // At the edge of the ranges a run completes, and its cycles hold the DRAM's busy time.
  write("s.toml", base +
                      "[pipeline.dram]\nbytes_per_cycle = 0.0009765625\n[tech.latency]\n"
                      "mul = 1000\n");
  const Result r = sh("run " + path("s.toml") + " --no-progress --out " + path("edge"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("edge") + "/report.json");
  EXPECT_GE(num(j, "cycles"), num(j, "dram.busy_cycles"));
  EXPECT_GE(num(j, "dram.busy_cycles"), 65536.0);
}

// A scene file whose name is not UTF-8 (TOML itself refuses invalid UTF-8 inside the file)
// still gives a valid report: invalid bytes are replaced in report.json (the JSON writer used
// to throw after the images were in place).
TEST_F(Cli, NonUtf8NamesStillGiveAValidReport) {
  write("s\xff.toml",
        "[output]\nwidth = 32\nheight = 32\n[textures.t]\nsource = \"procedural:checker\"\n"
        "[materials.m]\ntexture = \"t\"\n[[planes]]\nmaterial = \"m\"\n"
        "origin = [-2.0, -1.0, -4.0]\nedge_u = [4.0, 0.0, 0.0]\nedge_v = [0.0, 2.0, 0.0]\n");
  const Result r = sh("run '" + path("s\xff.toml") + "' --no-progress --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("out") + "/report.json");
  EXPECT_GT(num(j, "fragments"), 0);
  EXPECT_TRUE(fs::exists(path("out") + "/report.md"));
}

TEST_F(Cli, SceneUnknownMaterialAndFilter) {
  write("bad.toml",
        "[textures.t]\nsource = \"procedural:checker\"\n[materials.m]\ntexture = \"t\"\n"
        "filter = { mode = \"cubic\" }\n[[planes]]\nmaterial = \"m\"\n");
  Result r = sh("run " + path("bad.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cubic"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bad.toml:5:"), std::string::npos) << r.out;
  write("bad2.toml", "[[planes]]\nmaterial = \"nope\"\n");
  r = sh("run " + path("bad2.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("bad2.toml:2:12: unknown material 'nope'"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

TEST_F(Cli, MissingTextureFileNamesIt) {
  write("s.toml",
        "[textures.t]\nsource = \"no_such.png\"\n[materials.m]\ntexture = "
        "\"t\"\n[[planes]]\nmaterial = \"m\"\n");
  const Result r = sh("run " + path("s.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("s.toml:2:10: textures.t.source: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no_such.png: cannot open texture file: no such file"), std::string::npos)
      << r.out;
  expect_no_outputs(path("out"));
}

// A run never replaces its own input: a scene saved as DIR/report.json run with --out DIR used
// to be overwritten by the report. The scene and the output directory stay as they were.
TEST_F(Cli, RunRefusesToOverwriteItsOwnInput) {
  const std::string scene =
      "[output]\nwidth = 16\nheight = 12\n[textures.t]\nsource = "
      "\"procedural:checker?size=16&cells=2\"\n[materials.m]\ntexture = \"t\"\n"
      "[[planes]]\nmaterial = \"m\"\norigin = [-2.0, -1.0, -4.0]\nedge_u = [4.0, 0.0, 0.0]\n"
      "edge_v = [0.0, 2.0, 0.0]\n";
  fs::create_directories(path("d"));
  write("d/report.json", scene);
  const Result r = sh("run " + path("d/report.json") + " --out " + path("d") + " --reference none");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("report.json: is an input of this run"), std::string::npos) << r.out;
  std::ifstream in(path("d/report.json"));
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, scene);
  EXPECT_FALSE(fs::exists(path("d/image.png")));  // the set moves as a whole or not at all
}

// A trace pixel beyond the largest image (x = 4294967295 after a pixel at (1, 1)) is refused by
// name; it used to wrap into a negative extent and end in an internal error.
TEST_F(Cli, TracePixelBeyondTheLargestImageIsRefused) {
  write("s.toml",
        "[textures.t]\nsource = \"procedural:checker?size=16&cells=2\"\n[materials.m]\n"
        "texture = \"t\"\n");
  for (const char* xy : {"4294967295,1", "1,16384"}) {
    write("t.csv", std::string("# texture 0 t procedural:checker?size=16&cells=2 16 16\n"
                               "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n"
                               "0,0,1,1,0,0.5,0.5,0.01,0,0,0.01\n0,0,") +
                       xy + ",0,0.5,0.5,0.01,0,0,0.01\n");
    const Result r = sh("run " + path("s.toml") + " --trace " + path("t.csv") + " --out " +
                        path("o") + " --reference none");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("t.csv: a fragment lies at "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(std::string(xy)[0] == '1' ? "y = 16384" : "x = 4294967295"),
              std::string::npos)
        << r.out;
  }
}

// `trace convert` onto its own input is refused when the output would replace it.
TEST_F(Cli, TraceConvertOntoItsInputIsRefused) {
  const std::string trc = path("a.trc");
  ASSERT_EQ(sh("trace gen default --set output.width=16 --set output.height=12 -o " + trc).code, 0);
  const auto size = fs::file_size(trc);
  const Result r = sh("trace convert " + trc + " " + trc);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("a.trc: is an input of this run"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(trc), size);
  EXPECT_EQ(sh("trace info " + trc).code, 0);
  EXPECT_EQ(std::distance(fs::directory_iterator(path("")), fs::directory_iterator()), 1);
}

// Inputs that are not regular files get a clear error and never block or read forever.
TEST_F(Cli, SceneThatIsAFifoDirectoryOrDeviceIsRefused) {
  ASSERT_EQ(::mkfifo(path("fifo.toml").c_str(), 0600), 0);
  Result r = sh("run " + path("fifo.toml") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("fifo.toml: cannot read scene file: is a FIFO"), std::string::npos) << r.out;
  r = sh("run /dev/zero --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("/dev/zero: cannot read scene file: is a device"), std::string::npos)
      << r.out;
  r = sh("run " + path("") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("cannot read scene file: is a directory"), std::string::npos) << r.out;
}

// A bad procedural spec names the scene file and the line:column of the value, for run and
// trace gen alike (it used to name only the spec).
TEST_F(Cli, BadProceduralSpecNamesSceneLineAndColumn) {
  write("s.toml",
        "[textures.t]\nsource = \"procedural:checker?size=0\"\n[materials.m]\ntexture = "
        "\"t\"\n[[planes]]\nmaterial = \"m\"\n");
  for (const std::string& cmd : {"run " + path("s.toml") + " --out " + path("out"),
                                 "trace gen " + path("s.toml") + " -o " + path("out/t.trc")}) {
    const Result r = sh(cmd);
    EXPECT_EQ(r.code, 2) << cmd;
    EXPECT_NE(r.out.find("s.toml:2:10: textures.t.source: procedural texture "
                         "'procedural:checker?size=0': size must be an integer in [1, 8192]"),
              std::string::npos)
        << cmd << "\n"
        << r.out;
    expect_no_outputs(path("out"));
  }
}

TEST_F(Cli, UnreadableTextureNamesIt) {
  write("junk.png", "this is not a png");
  write("s.toml",
        "[textures.t]\nsource = \"junk.png\"\n[materials.m]\ntexture = \"t\"\n[[planes]]\nmaterial "
        "= \"m\"\n");
  const Result r = sh("run " + path("s.toml") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("s.toml:2:10: textures.t.source: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("junk.png: cannot read texture"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

TEST_F(Cli, NanCoordinateInTraceNamesRecord) {
  write("t.csv",
        "# texture 0 c \"procedural:checker?size=64\" 64 64\n"
        "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n"
        "0,0,1,1,0,0.5,0.5,0.01,0,0,0.01\n"
        "0,0,2,1,0,nan,0.5,0.01,0,0,0.01\n");
  const Result r = sh("run --trace " + path("t.csv") + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("t.csv:4:11: column 'u': field 'u' is NaN"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

TEST_F(Cli, CorruptedAndTruncatedBinaryTrace) {
  const std::string trc = path("t.trc");
  ASSERT_EQ(sh("trace gen default -o " + trc).code, 0);
  const auto size = fs::file_size(trc);
  {  // flip one byte in the middle of the payload: the chunk checksum must catch it
    std::fstream f(trc, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(size / 2));
    char c = 0;
    f.read(&c, 1);
    c = static_cast<char>(c ^ 0x5A);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.write(&c, 1);
  }
  Result r = sh("run --trace " + trc + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("t.trc"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("chunk"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
  ASSERT_EQ(sh("trace gen default -o " + trc).code, 0);
  fs::resize_file(trc, size - 100);
  r = sh("run --trace " + trc + " --out " + path("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("t.trc"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
}

TEST_F(Cli, UnknownTraceVersion) {
  const std::string trc = path("t.trc");
  ASSERT_EQ(sh("trace gen default -o " + trc).code, 0);
  {  // the version is the u32 after the 8-byte magic
    std::fstream f(trc, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8);
    const char v[4] = {9, 0, 0, 0};
    f.write(v, 4);
  }
  const Result r = sh("trace info " + trc);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("version 9"), std::string::npos) << r.out;
}

TEST_F(Cli, UnwritableOutputDirectory) {
  write("file", "x");
  const Result r = sh("run --no-progress --out " + path("file") + "/sub");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot create output directory"), std::string::npos) << r.out;
  // A directory that exists but takes no files (/proc refuses them, even to root) is found
  // before any work: a study or run stops at once, naming the directory and the reason.
  for (const char* cmd : {"study filters --out /proc", "study coords --out /proc",
                          "study vd --out /proc", "run --no-progress --out /proc"}) {
    const auto t0 = std::chrono::steady_clock::now();
    const Result p = sh(cmd);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(p.code, 2) << cmd << p.out;
    EXPECT_NE(p.out.find("/proc: cannot write in output directory"), std::string::npos)
        << cmd << p.out;
    EXPECT_LT(secs, 5.0) << cmd;  // the studies take 17-77 s when they do run
  }
}

// The CSV trace `in` with column `column` of every record set to `value`.
std::string with_column(const std::string& in, const std::string& column,
                        const std::string& value) {
  std::istringstream lines(in);
  std::string line, out;
  int index = -1;
  while (std::getline(lines, line)) {
    if (line.starts_with('#') || line.empty()) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream cs(line);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    if (index < 0) {
      index = static_cast<int>(std::find(cells.begin(), cells.end(), column) - cells.begin());
    } else if (index < static_cast<int>(cells.size())) {
      cells[static_cast<size_t>(index)] = value;
    }
    for (size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + cells[k];
    out += "\n";
  }
  return out;
}

TEST_F(Cli, SamplerOpsSceneReplaysFromItsTraceAndARecordPicksASampler) {
  // scenes/sampler_ops.toml: trace gen writes the operation fields (version 4); the scene run
  // from the trace (binary or CSV) gives the scene run's figures; a record's `sampler` picks
  // another sampler of the scene's table, and an id outside it is an error naming the record.
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/sampler_ops.toml";
  const std::string small = " --set output.width=96 --set output.height=60";
  const std::string trc = path("ops.trc"), csv = path("ops.csv");
  ASSERT_EQ(sh("trace gen " + scene + small + " -o " + trc).code, 0);
  ASSERT_EQ(sh("trace gen " + scene + small + " -o " + csv).code, 0);
  const Result info = sh("trace info " + trc);
  EXPECT_NE(info.out.find("version 5"), std::string::npos) << info.out;
  const Result a = sh("run " + scene + small + " --no-progress --out " + path("scene"));
  const Result b =
      sh("run " + scene + small + " --trace " + trc + " --no-progress --out " + path("trace"));
  const Result c =
      sh("run " + scene + small + " --trace " + csv + " --no-progress --out " + path("csv"));
  ASSERT_EQ(a.code, 0) << a.out;
  ASSERT_EQ(b.code, 0) << b.out;
  ASSERT_EQ(c.code, 0) << c.out;
  const Json ja = load_json(path("scene") + "/report.json");
  for (const std::string run : {"trace", "csv"}) {
    const Json jb = load_json(path(run) + "/report.json");
    EXPECT_EQ(num(ja, "fragments"), num(jb, "fragments")) << run;
    EXPECT_EQ(num(ja, "cycles"), num(jb, "cycles")) << run;
    EXPECT_EQ(ja["materials"], jb["materials"]) << run;
    EXPECT_EQ(slurp(path("scene") + "/image.png"), slurp(path(run) + "/image.png")) << run;
  }
  for (const std::string op : {"gather.gather", "lod.lod", "grad.grad", "texel.lod"})
    EXPECT_GT(num(ja, "materials." + op.substr(0, op.find('.')) + ".operations" +
                          op.substr(op.find('.')) + ".fragments"),
              0)
        << op;
  // Every record picks sampler 2 (maxred, in name order): another image, the same fragments.
  const std::string text = slurp(csv);
  write("max.csv", with_column(text, "sampler", "2"));
  const Result d = sh("run " + scene + small + " --trace " + path("max.csv") +
                      " --no-progress --out " + path("max"));
  ASSERT_EQ(d.code, 0) << d.out;
  EXPECT_EQ(num(load_json(path("max") + "/report.json"), "fragments"), num(ja, "fragments"));
  EXPECT_NE(slurp(path("scene") + "/image.png"), slurp(path("max") + "/image.png"));
  // An id outside the table, and the unnormalised sampler (5) for a gather: errors naming the
  // record.
  write("bad.csv", with_column(text, "sampler", "6"));
  Result e = sh("run " + scene + small + " --trace " + path("bad.csv") + " --no-progress --out " +
                path("bad"));
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.out.find("record 0: sampler 6 is not in the sampler table (ids 1..5"),
            std::string::npos)
      << e.out;
  write("texel.csv", with_column(text, "sampler", "5"));
  e = sh("run " + scene + small + " --trace " + path("texel.csv") + " --no-progress --out " +
         path("texel"));
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.out.find("texel.csv: record 0: operation 'sample' (implicit LOD) cannot use an "
                       "unnormalised sampler"),
            std::string::npos)
      << e.out;
}

TEST_F(Cli, ARecordsComparingSamplerOnALayeredTextureIsRefused) {
  // The array paths blend their taps (no texel reducer): a record that asks a comparing sampler
  // of a 2-D array is an error naming the record, not a sample that ignores the comparison.
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/arrays.toml";
  const std::string csv = path("arr.csv");
  ASSERT_EQ(
      sh("trace gen " + scene + " --set output.width=16 --set output.height=12 -o " + csv).code, 0);
  std::string text = slurp(csv);
  const size_t at = text.find("frame,prim");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "# sampler pcf compare=less\n");
  write("ok.csv", with_column(text, "sampler", "0"));
  EXPECT_EQ(sh("run --trace " + path("ok.csv") + " --no-progress --out " + path("ok")).code, 0);
  write("cmp.csv", with_column(text, "sampler", "1"));
  const Result e = sh("run --trace " + path("cmp.csv") + " --no-progress --out " + path("cmp"));
  EXPECT_EQ(e.code, 2) << e.out;
  EXPECT_NE(e.out.find("cmp.csv: record 0: texture "), std::string::npos) << e.out;
  EXPECT_NE(e.out.find(") cannot be read with a sampler that compares or reduces"),
            std::string::npos)
      << e.out;
}

TEST_F(Cli, TraceCarriesTheScenesSamplerTable) {
  // trace gen writes the scene's [samplers] (version 5); info lists them; a run without the
  // scene resolves a record's sampler id in the trace's own table; a scene whose table differs
  // is an error naming the sampler.
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/sampler_ops.toml";
  const std::string small = " --set output.width=96 --set output.height=60";
  const std::string trc = path("ops.trc"), csv = path("ops.csv");
  ASSERT_EQ(sh("trace gen " + scene + small + " -o " + trc).code, 0);
  ASSERT_EQ(sh("trace convert " + trc + " " + csv).code, 0);
  const Result info = sh("trace info " + trc);
  EXPECT_NE(info.out.find("version 5"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("samplers:   5"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("id 5  texel mode=bilinear address_u=clamp"), std::string::npos)
      << info.out;
  EXPECT_NE(slurp(csv).find("# sampler pcf mode=bilinear address_u=clamp"), std::string::npos);
  // Without the scene: the default material, and sampler 4 (maxred) from the trace's table.
  const std::string text = slurp(csv);
  write("max.csv", with_column(text, "sampler", "4"));
  const Result a = sh("run --trace " + path("max.csv") + " --no-progress --out " + path("a"));
  ASSERT_EQ(a.code, 0) << a.out;
  write("max0.csv", with_column(text, "sampler", "0"));
  const Result b = sh("run --trace " + path("max0.csv") + " --no-progress --out " + path("b"));
  ASSERT_EQ(b.code, 0) << b.out;
  EXPECT_NE(slurp(path("a") + "/image.png"), slurp(path("b") + "/image.png"));
  write("bad.csv", with_column(text, "sampler", "6"));
  Result e = sh("run --trace " + path("bad.csv") + " --no-progress --out " + path("bad"));
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.out.find("sampler 6 is not in the sampler table (ids 1..5"), std::string::npos)
      << e.out;
  // A scene whose sampler differs from the trace's: an error naming both.
  std::string changed = text;
  const size_t at = changed.find("# sampler mip ");
  ASSERT_NE(at, std::string::npos);
  changed.replace(changed.find("lod_bias=0.5", at), 12, "lod_bias=0.25");
  write("changed.csv", changed);
  e = sh("run " + scene + small + " --trace " + path("changed.csv") + " --no-progress --out " +
         path("changed"));
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.out.find("changed.csv: sampler table entry 3 ('mip') differs from sampler 'mip' "
                       "(id 3) of "),
            std::string::npos)
      << e.out;
  EXPECT_NE(e.out.find("the trace has lod_bias=0.25, the scene lod_bias=0.5"), std::string::npos)
      << e.out;
  // A bad entry in the trace's table: the file and the entry.
  std::string bad = text;
  bad.replace(bad.find("mode=", bad.find("# sampler texel ")), 13, "mode=trilinear");
  write("badtable.csv", bad);
  e = sh("run --trace " + path("badtable.csv") + " --no-progress --out " + path("bt"));
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.out.find("badtable.csv: sampler table entry 5 ('texel'): unnormalized coordinates "
                       "need mode nearest or bilinear"),
            std::string::npos)
      << e.out;
}

TEST_F(Cli, SamplerOpsSceneMeasuresEachOperationAgainstItsOwnTruth) {
  // Each material of scenes/sampler_ops.toml is judged against what its operation asks
  // (docs/texture-types.md §8): a gather is exact (999: no error), the unnormalised fetch
  // leaves only the fixed-point weights, and the comparison, the reduction, the explicit LOD
  // and the gradients are closer to it than to a plain filtered sample's truth (at this size
  // that truth gives floor 6.5, gather 14.5, max 8.9, lod 27.7, grad 23.4 and texel 5.9 dB:
  // every bound below fails on it).
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/sampler_ops.toml";
  const Result a = sh("run " + scene + " --set output.width=160 --set output.height=100" +
                      " --no-progress --out " + path("ops"));
  ASSERT_EQ(a.code, 0) << a.out;
  const Json j = load_json(path("ops") + "/report.json");
  const auto psnr = [&](const std::string& m) {
    return num(j, "materials." + m + ".accuracy.psnr_db");
  };
  EXPECT_EQ(psnr("gather"), 999.0);
  EXPECT_GT(psnr("texel"), 60.0);
  EXPECT_GT(psnr("floor"), 18.0);
  EXPECT_GT(psnr("max"), 13.5);
  EXPECT_GT(psnr("lod"), 30.0);
  EXPECT_GT(psnr("grad"), 40.0);
}

TEST_F(Cli, ReliefTraceCarriesTheViewVectorAndRunsLikeTheScene) {
  // trace gen writes a relief scene's view vectors (version 2); the scene run from that trace
  // gives the scene run's figures, and a version-1 trace of the same fragments falls back to
  // the scene's camera.
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/relief_wall.toml";
  const std::string small = " --set output.width=80 --set output.height=60";
  const std::string trc = path("wall.trc"), csv = path("wall.csv");
  ASSERT_EQ(sh("trace gen " + scene + small + " -o " + trc).code, 0);
  const Result info = sh("trace info " + trc);
  ASSERT_EQ(info.code, 0) << info.out;
  EXPECT_NE(info.out.find("version 2"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("view_x:f32@68"), std::string::npos) << info.out;
  ASSERT_EQ(sh("trace convert " + trc + " " + csv).code, 0);
  EXPECT_NE(slurp(csv).find("format v2"), std::string::npos);
  const Result a = sh("run " + scene + small + " --no-progress --out " + path("scene"));
  const Result b =
      sh("run " + scene + small + " --trace " + trc + " --no-progress --out " + path("trace"));
  const Result c =
      sh("run " + scene + small + " --trace " + csv + " --no-progress --out " + path("csv"));
  ASSERT_EQ(a.code, 0) << a.out;
  ASSERT_EQ(b.code, 0) << b.out;
  ASSERT_EQ(c.code, 0) << c.out;
  const Json ja = load_json(path("scene") + "/report.json");
  const Json jb = load_json(path("trace") + "/report.json");
  const Json jc = load_json(path("csv") + "/report.json");
  EXPECT_EQ(num(ja, "fragments"), num(jb, "fragments"));
  EXPECT_GT(num(jb, "blocks.relief.parallax_iterative.texels"), 0);
  EXPECT_EQ(num(jb, "cycles"), num(jc, "cycles"));
  // The float view vector moves the relief's shifts by a hair at most.
  EXPECT_NEAR(num(ja, "accuracy.psnr_db"), num(jb, "accuracy.psnr_db"), 0.05);
  // Without the view columns (a version-1 trace) the run derives the view from the camera,
  // exactly as the scene run does.
  std::istringstream in(slurp(csv));
  std::string line, v1;
  while (std::getline(in, line)) {
    if (!line.starts_with('#')) {
      size_t cut = 0;
      for (int k = 0; k < 11; ++k) cut = line.find(',', cut) + 1;
      line.resize(cut - 1);
    }
    v1 += line + "\n";
  }
  write("v1.csv", v1);
  const Result d = sh("run " + scene + small + " --trace " + path("v1.csv") +
                      " --no-progress --out " + path("v1"));
  ASSERT_EQ(d.code, 0) << d.out;
  const Json jd = load_json(path("v1") + "/report.json");
  EXPECT_EQ(num(ja, "cycles"), num(jd, "cycles"));
  EXPECT_EQ(num(ja, "accuracy.psnr_db"), num(jd, "accuracy.psnr_db"));
}

}  // namespace
