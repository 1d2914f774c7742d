// Golden report figures of the shipped scenes and sample traces: fragments, cycles, every
// block's and material's operation counts, stage and cache counters, and PSNR overall and per
// material, held exactly (doubles to 17 digits). Work on the simulator's speed must leave every
// figure bit-identical; a change of the model that moves them on purpose updates the table
// (the failure message prints the new lines). The ground truth uses a fixed 2x2 grid per pixel
// ([reference] samples = 2, not the adaptive default) so the whole test runs in a few seconds;
// the figures of the simulated unit do not depend on it. Its PSNR figures are those of the
// plane map evaluated in double (flight.toml's moved in the 11th digit from long double).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)

std::string number(const Json& v) {
  if (v.is_number_unsigned()) return std::to_string(v.get<uint64_t>());
  if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v.get<double>());
  return buf;
}

// "path value" for a number, or "path k=v k=v …" for an object's numbers (nested objects
// follow on their own lines), in key order.
void flatten(const Json& j, const std::string& path, std::ostringstream& out) {
  if (j.is_number()) {
    out << path << " " << number(j) << "\n";
    return;
  }
  if (!j.is_object()) return;
  out << path;
  for (const auto& [k, v] : j.items()) {
    if (v.is_number()) out << " " << k << "=" << number(v);
  }
  out << "\n";
  for (const auto& [k, v] : j.items()) {
    if (!v.is_object()) continue;
    std::string sub = path;
    sub += ".";
    sub += k;
    flatten(v, sub, out);
  }
}

// j[k], or null when j is not an object or has no k (a functional run has no stages).
const Json& at(const Json& j, const std::string& k) {
  static const Json none;
  return j.is_object() && j.contains(k) ? j[k] : none;
}

// The figures of one run that must not move: what the unit simulated, and its accuracy.
std::string figures(const Json& r) {
  std::ostringstream out;
  for (const char* k : {"fragments", "cycles"}) flatten(at(r, k), k, out);
  for (const auto& [name, b] : at(r, "blocks").items()) {
    flatten(at(b, "ops"), "blocks." + name + ".ops", out);
    flatten(at(b, "texels"), "blocks." + name + ".texels", out);
  }
  for (const auto& [name, s] : at(r, "stages").items()) {
    flatten(at(s, "busy"), "stages." + name + ".busy", out);
    flatten(at(s, "stalls"), "stages." + name + ".stalls", out);
  }
  for (const char* k : {"hits", "misses", "texel_reads"}) flatten(at(at(r, "cache"), k), k, out);
  flatten(at(r, "dram"), "dram", out);
  flatten(at(at(r, "accuracy"), "psnr_db"), "psnr_db", out);
  flatten(at(at(r, "accuracy"), "max_abs"), "max_abs", out);
  for (const auto& [name, m] : at(r, "materials").items()) {
    flatten(at(m, "fragments"), "materials." + name + ".fragments", out);
    flatten(at(m, "ops"), "materials." + name + ".ops", out);
    flatten(at(at(m, "accuracy"), "psnr_db"), "materials." + name + ".psnr", out);
    // Materials drawn by the object-space pipeline (effect `object_space`).
    flatten(at(m, "object_space"), "materials." + name + ".object_space", out);
  }
  flatten(at(r, "object_space"), "object_space", out);
  return out.str();
}

class GoldenFigures : public Cli {
 protected:
  // Runs texsim with `input` (a scene path, "--trace FILE", or "" for the built-in scene) and
  // compares its figures with `expected`.
  void check(const std::string& input, const std::string& expected) {
    const std::string out = path("out");
    const Result r = sh("run " + input + " --set reference.samples=2 --no-progress --out " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string got = figures(load_json(out + "/report.json"));
    // The table starts on the line after R"( for readability.
    const std::string want = expected.substr(expected.starts_with('\n') ? 1 : 0);
    EXPECT_EQ(got, want) << "new figures of '" << input << "':\n" << got;
  }
  static std::string scene(const char* name) {
    return std::string(TEXSIM_SOURCE_DIR) + "/scenes/" + name + ".toml";
  }
};

TEST_F(GoldenFigures, DefaultScene) {
  check("", R"(
fragments 50286
cycles 116950
blocks.blend.ops add=1555744 cmp=0 div=0 lut=0 mem=388936 mul=1555744 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=388936 mul=0 rcp=0 sqrt=0
blocks.cache.texels 388936
blocks.filter.bilinear.ops add=33380 cmp=40056 div=0 lut=0 mem=0 mul=20028 rcp=0 sqrt=0
blocks.filter.bilinear.texels 13352
blocks.filter.trilinear.ops add=1467684 cmp=770916 div=0 lut=0 mem=0 mul=1690128 rcp=0 sqrt=0
blocks.filter.trilinear.texels 375584
blocks.lod.ops add=251430 cmp=150858 div=0 lut=50286 mem=0 mul=402288 rcp=0 sqrt=0
blocks.lod.texels 0
stages.address.busy 50286
stages.address.stalls blocked=66574 latency_full=0 multi_cycle=0 starved=14
stages.blend.busy 50286
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=66656
stages.cache.busy 97234
stages.cache.stalls blocked=0 latency_full=19663 multi_cycle=46948 starved=42
stages.lod.busy 50286
stages.lod.stalls blocked=66512 latency_full=0 multi_cycle=0 starved=0
hits 143672
misses 2222
texel_reads 388936
dram busy_cycles=8888 bytes=142208 requests=2222
psnr_db 19.839462884506208
max_abs 0.52403008937835693
materials.floor.fragments 38611
materials.floor.ops add=2471104 cmp=694998 div=0 lut=38611 mem=308888 mul=2934436 rcp=0 sqrt=0
materials.floor.psnr 18.852837914833596
materials.panel.fragments 3338
materials.panel.ops add=103478 cmp=50070 div=0 lut=3338 mem=13352 mul=100140 rcp=0 sqrt=0
materials.panel.psnr 22.593593027625076
materials.wall.fragments 8337
materials.wall.ops add=733656 cmp=216762 div=0 lut=8337 mem=66696 mul=633612 rcp=0 sqrt=0
materials.wall.psnr 41.514287091535081
)");
}
TEST_F(GoldenFigures, DefaultSceneFunctional) {
  check("--functional", R"(
fragments 50286
cycles 0
blocks.blend.ops add=1555744 cmp=0 div=0 lut=0 mem=388936 mul=1555744 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=388936 mul=0 rcp=0 sqrt=0
blocks.cache.texels 388936
blocks.filter.bilinear.ops add=33380 cmp=40056 div=0 lut=0 mem=0 mul=20028 rcp=0 sqrt=0
blocks.filter.bilinear.texels 13352
blocks.filter.trilinear.ops add=1467684 cmp=770916 div=0 lut=0 mem=0 mul=1690128 rcp=0 sqrt=0
blocks.filter.trilinear.texels 375584
blocks.lod.ops add=251430 cmp=150858 div=0 lut=50286 mem=0 mul=402288 rcp=0 sqrt=0
blocks.lod.texels 0
hits 0
misses 0
texel_reads 0
dram busy_cycles=0 bytes=0 requests=0
psnr_db 19.839462884506208
max_abs 0.52403008937835693
materials.floor.fragments 38611
materials.floor.ops add=2471104 cmp=694998 div=0 lut=38611 mem=308888 mul=2934436 rcp=0 sqrt=0
materials.floor.psnr 18.852837914833596
materials.panel.fragments 3338
materials.panel.ops add=103478 cmp=50070 div=0 lut=3338 mem=13352 mul=100140 rcp=0 sqrt=0
materials.panel.psnr 22.593593027625076
materials.wall.fragments 8337
materials.wall.ops add=733656 cmp=216762 div=0 lut=8337 mem=66696 mul=633612 rcp=0 sqrt=0
materials.wall.psnr 41.514287091535081
)");
}
TEST_F(GoldenFigures, Coords) {
  check(scene("coords"), R"(
fragments 65940
cycles 400988
blocks.blend.ops add=6409024 cmp=0 div=0 lut=0 mem=1602256 mul=6409024 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=1602256 mul=0 rcp=0 sqrt=0
blocks.cache.texels 1602256
blocks.coords.constant-depth[float].ops add=27972 cmp=348 div=2 lut=0 mem=0 mul=3464 rcp=346 sqrt=0
blocks.coords.constant-depth[float].texels 0
blocks.coords.heckbert[float].ops add=77676 cmp=12946 div=25892 lut=0 mem=0 mul=77676 rcp=0 sqrt=0
blocks.coords.heckbert[float].texels 0
blocks.coords.incremental[s16.16].ops add=44241 cmp=14057 div=28114 lut=0 mem=0 mul=2070 rcp=0 sqrt=0
blocks.coords.incremental[s16.16].texels 0
blocks.coords.incremental[s20.28].ops add=44241 cmp=14057 div=28114 lut=0 mem=0 mul=2070 rcp=0 sqrt=0
blocks.coords.incremental[s20.28].texels 0
blocks.coords.quadratic-32[float].ops add=32052 cmp=1023 div=2046 lut=0 mem=0 mul=6138 rcp=341 sqrt=0
blocks.coords.quadratic-32[float].texels 0
blocks.derivs.accelerated-fd[float].ops add=59670 cmp=11934 div=23868 lut=0 mem=0 mul=0 rcp=0 sqrt=0
blocks.derivs.accelerated-fd[float].texels 0
blocks.derivs.analytic[float].ops add=51784 cmp=12946 div=0 lut=0 mem=0 mul=129460 rcp=12946 sqrt=0
blocks.derivs.analytic[float].texels 0
blocks.derivs.iterative[s16.16].ops add=72371 cmp=14057 div=0 lut=0 mem=0 mul=86444 rcp=28114 sqrt=0
blocks.derivs.iterative[s16.16].texels 0
blocks.derivs.iterative[s20.28].ops add=72371 cmp=14057 div=0 lut=0 mem=0 mul=86444 rcp=28114 sqrt=0
blocks.derivs.iterative[s20.28].texels 0
blocks.derivs.quad[float].ops add=14920 cmp=658 div=1316 lut=0 mem=0 mul=0 rcp=0 sqrt=0
blocks.derivs.quad[float].texels 0
blocks.filter.trilinear.ops add=5605434 cmp=2063836 div=0 lut=65940 mem=0 mul=7742596 rcp=0 sqrt=0
blocks.filter.trilinear.texels 1602256
blocks.lod.ops add=461580 cmp=527520 div=65940 lut=197820 mem=0 mul=659400 rcp=0 sqrt=65940
blocks.lod.texels 0
stages.address.busy 200282
stages.address.stalls blocked=200357 latency_full=0 multi_cycle=134342 starved=70
stages.blend.busy 200282
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=134342 starved=200700
stages.cache.busy 400564
stages.cache.stalls blocked=0 latency_full=222 multi_cycle=334624 starved=94
stages.coords.busy 83470
stages.coords.stalls blocked=316784 latency_full=0 multi_cycle=17530 starved=0
stages.derivs.busy 69406
stages.derivs.stalls blocked=330600 latency_full=0 multi_cycle=3466 starved=335
stages.lod.busy 65940
stages.lod.stalls blocked=334391 latency_full=0 multi_cycle=0 starved=130
hits 277353
misses 35877
texel_reads 1602256
dram busy_cycles=143508 bytes=2296128 requests=35877
psnr_db 20.564136471872757
max_abs 0.51329612731933594
materials.constant_depth.fragments 12946
materials.constant_depth.ops add=2431403 cmp=501508 div=14264 lut=51784 mem=306312 mul=2839046 rcp=346 sqrt=12946
materials.constant_depth.psnr 22.517428211367076
materials.exact.fragments 5967
materials.exact.ops add=1512368 cmp=286481 div=5967 lut=23868 mem=196976 mul=1795144 rcp=0 sqrt=5967
materials.exact.psnr 19.773849858784686
materials.heckbert.fragments 12946
materials.heckbert.ops add=2530125 cmp=528042 div=38838 lut=51784 mem=307960 mul=3057138 rcp=12946 sqrt=12946
materials.heckbert.psnr 22.533987210223284
materials.incremental.fragments 14057
materials.incremental.ops add=2455581 cmp=537057 div=42171 lut=56228 mem=298088 mul=2865468 rcp=28114 sqrt=14057
materials.incremental.psnr 22.816790383938415
materials.incremental_s16.fragments 14057
materials.incremental_s16.ops add=2455994 cmp=537113 div=42171 lut=56228 mem=298144 mul=2865958 rcp=28114 sqrt=14057
materials.incremental_s16.psnr 17.746968251077
materials.quadratic_32.fragments 5967
materials.quadratic_32.ops add=1587865 cmp=297238 div=31881 lut=23868 mem=194776 mul=1782032 rcp=341 sqrt=5967
materials.quadratic_32.psnr 19.845429536735491
)");
}
TEST_F(GoldenFigures, FootprintFilters) {
  check(scene("footprint_filters"), R"(
fragments 8356
cycles 81308
blocks.blend.ops add=66816 cmp=0 div=0 lut=0 mem=16704 mul=66816 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=268284 mul=0 rcp=0 sqrt=0
blocks.cache.texels 268284
blocks.filter.ewa.ops add=1211128 cmp=343717 div=0 lut=99774 mem=97684 mul=1060796 rcp=6270 sqrt=6270
blocks.filter.ewa.texels 97684
blocks.filter.feline.ops add=914892 cmp=221705 div=0 lut=21747 mem=107096 mul=1062545 rcp=8360 sqrt=6270
blocks.filter.feline.texels 107096
blocks.filter.spaf.ops add=1124379 cmp=827973 div=0 lut=152755 mem=46800 mul=688401 rcp=12528 sqrt=4176
blocks.filter.spaf.texels 46800
blocks.filter.trilinear.ops add=56376 cmp=31320 div=0 lut=0 mem=0 mul=75168 rcp=0 sqrt=0
blocks.filter.trilinear.texels 16704
blocks.lod.ops add=10440 cmp=6264 div=0 lut=2088 mem=0 mul=16704 rcp=0 sqrt=0
blocks.lod.texels 0
stages.address.busy 81145
stages.address.stalls blocked=0 latency_full=0 multi_cycle=72789 starved=14
stages.blend.busy 8356
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=72944
stages.cache.busy 68650
stages.cache.stalls blocked=0 latency_full=3809 multi_cycle=60294 starved=8840
stages.lod.busy 8356
stages.lod.stalls blocked=72635 latency_full=0 multi_cycle=0 starved=0
hits 45089
misses 6365
texel_reads 268284
dram busy_cycles=25460 bytes=407360 requests=6365
psnr_db 18.273778857430599
max_abs 0.6152784526348114
materials.ewa.fragments 2090
materials.ewa.ops add=1211128 cmp=343717 div=0 lut=99774 mem=97684 mul=1060796 rcp=6270 sqrt=6270
materials.ewa.psnr 18.780237853653031
materials.feline.fragments 2090
materials.feline.ops add=914892 cmp=221705 div=0 lut=21747 mem=107096 mul=1062545 rcp=8360 sqrt=6270
materials.feline.psnr 18.39853000279496
materials.spaf.fragments 2088
materials.spaf.ops add=1124379 cmp=827973 div=0 lut=152755 mem=46800 mul=688401 rcp=12528 sqrt=4176
materials.spaf.psnr 18.373907223248892
materials.trilinear.fragments 2088
materials.trilinear.ops add=133632 cmp=37584 div=0 lut=2088 mem=16704 mul=158688 rcp=0 sqrt=0
materials.trilinear.psnr 17.624281598223334
)");
}
TEST_F(GoldenFigures, Photo) {
  check(scene("photo"), R"(
fragments 91005
cycles 944510
blocks.blend.ops add=14949568 cmp=0 div=0 lut=0 mem=3737392 mul=14949568 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=3737392 mul=0 rcp=0 sqrt=0
blocks.cache.texels 3737392
blocks.filter.trilinear.ops add=12764591 cmp=4463243 div=0 lut=79903 mem=0 mul=17712582 rcp=0 sqrt=0
blocks.filter.trilinear.texels 3737392
blocks.lod.ops add=614831 cmp=672530 div=79903 lut=250811 mem=0 mul=887846 rcp=0 sqrt=79903
blocks.lod.texels 0
stages.address.busy 467174
stages.address.stalls blocked=477029 latency_full=0 multi_cycle=376169 starved=37
stages.blend.busy 467174
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=376169 starved=477330
stages.cache.busy 934348
stages.cache.stalls blocked=0 latency_full=10002 multi_cycle=843343 starved=61
stages.lod.busy 91005
stages.lod.stalls blocked=853003 latency_full=0 multi_cycle=0 starved=0
hits 489113
misses 60106
texel_reads 3737392
dram busy_cycles=240424 bytes=3846784 requests=60106
psnr_db 30.750034902571382
max_abs 0.29517409205436707
materials.floor.fragments 79903
materials.floor.ops add=27707278 cmp=4847121 div=79903 lut=319612 mem=3648576 mul=32883876 rcp=0 sqrt=79903
materials.floor.psnr 31.391376992820629
materials.wall.fragments 11102
materials.wall.ops add=621712 cmp=288652 div=0 lut=11102 mem=88816 mul=666120 rcp=0 sqrt=0
materials.wall.psnr 27.765683250393081
)");
}
TEST_F(GoldenFigures, SubtexelCutoff) {
  check(scene("subtexel_cutoff"), R"(
fragments 33986
cycles 279060
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=673697 mul=0 rcp=0 sqrt=0
blocks.cache.texels 673697
blocks.filter.ewa[ewa].ops add=2343701 cmp=662307 div=0 lut=202259 mem=192498 mul=2271547 rcp=29283 sqrt=29283
blocks.filter.ewa[ewa].texels 192498
blocks.filter.ewa[ewa_vd].ops add=3369843 cmp=1416722 div=0 lut=202259 mem=192498 mul=3093962 rcp=131070 sqrt=232857
blocks.filter.ewa[ewa_vd].texels 192498
blocks.filter.spaf[spaf].ops add=3497413 cmp=2723298 div=0 lut=472071 mem=141355 mul=2116845 rcp=43392 sqrt=14464
blocks.filter.spaf[spaf].texels 141355
blocks.filter.spaf[spaf_vd].ops add=3926545 cmp=4004192 div=0 lut=154578 mem=147346 mul=2656589 rcp=72320 sqrt=43392
blocks.filter.spaf[spaf_vd].texels 147346
stages.address.busy 278899
stages.address.stalls blocked=0 latency_full=0 multi_cycle=244913 starved=14
stages.blend.busy 33986
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=245066
stages.cache.busy 180640
stages.cache.stalls blocked=0 latency_full=191 multi_cycle=146654 starved=98219
stages.lod.busy 33986
stages.lod.stalls blocked=244813 latency_full=0 multi_cycle=0 starved=0
hits 126193
misses 3432
texel_reads 673697
dram busy_cycles=13728 bytes=219648 requests=3432
psnr_db 19.234016495581429
max_abs 0.53897284716367722
materials.ewa.fragments 9761
materials.ewa.ops add=2343701 cmp=662307 div=0 lut=202259 mem=192498 mul=2271547 rcp=29283 sqrt=29283
materials.ewa.psnr 19.281028524838312
materials.ewa_vd.fragments 9761
materials.ewa_vd.ops add=3369843 cmp=1416722 div=0 lut=202259 mem=192498 mul=3093962 rcp=131070 sqrt=232857
materials.ewa_vd.psnr 19.421460440579239
materials.spaf.fragments 7232
materials.spaf.ops add=3497413 cmp=2723298 div=0 lut=472071 mem=141355 mul=2116845 rcp=43392 sqrt=14464
materials.spaf.psnr 19.087763805606986
materials.spaf_vd.fragments 7232
materials.spaf_vd.ops add=3926545 cmp=4004192 div=0 lut=154578 mem=147346 mul=2656589 rcp=72320 sqrt=43392
materials.spaf_vd.psnr 19.074987078462325
)");
}
TEST_F(GoldenFigures, Cube) {
  check(scene("cube"), R"(
fragments 21438
cycles 130795
blocks.blend.ops add=1883904 cmp=0 div=0 lut=0 mem=470976 mul=1883904 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=470976 mul=0 rcp=0 sqrt=0
blocks.cache.texels 470976
blocks.filter.trilinear.ops add=1182882 cmp=1092018 div=0 lut=21438 mem=0 mul=1338060 rcp=0 sqrt=0
blocks.filter.trilinear.texels 470976
blocks.lod.ops add=150066 cmp=171504 div=21438 lut=64314 mem=0 mul=214380 rcp=0 sqrt=21438
blocks.lod.texels 0
stages.address.busy 58872
stages.address.stalls blocked=71672 latency_full=0 multi_cycle=37434 starved=37
stages.blend.busy 58872
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=37434 starved=71916
stages.cache.busy 117744
stages.cache.stalls blocked=0 latency_full=12896 multi_cycle=96306 starved=59
stages.lod.busy 21438
stages.lod.stalls blocked=108966 latency_full=0 multi_cycle=0 starved=0
hits 69444
misses 25301
texel_reads 470976
dram busy_cycles=101204 bytes=1619264 requests=25301
psnr_db 31.916107460723708
max_abs 0.19431997835636139
materials.crate.fragments 21438
materials.crate.ops add=3216852 cmp=1263522 div=21438 lut=85752 mem=470976 mul=3436344 rcp=0 sqrt=21438
materials.crate.psnr 31.916107460723708
)");
}
TEST_F(GoldenFigures, Bunny) {
  check(scene("bunny"), R"(
fragments 23575
cycles 68449
blocks.blend.ops add=754400 cmp=0 div=0 lut=0 mem=188600 mul=754400 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=188600 mul=0 rcp=0 sqrt=0
blocks.cache.texels 188600
blocks.filter.trilinear.ops add=636525 cmp=353625 div=0 lut=0 mem=0 mul=848700 rcp=0 sqrt=0
blocks.filter.trilinear.texels 188600
blocks.lod.ops add=117875 cmp=70725 div=0 lut=23575 mem=0 mul=188600 rcp=0 sqrt=0
blocks.lod.texels 0
stages.address.busy 23575
stages.address.stalls blocked=44716 latency_full=0 multi_cycle=0 starved=14
stages.blend.busy 23575
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=44866
stages.cache.busy 47150
stages.cache.stalls blocked=0 latency_full=21216 multi_cycle=23575 starved=38
stages.lod.busy 23575
stages.lod.stalls blocked=44650 latency_full=0 multi_cycle=0 starved=0
hits 70827
misses 2905
texel_reads 188600
dram busy_cycles=11620 bytes=185920 requests=2905
psnr_db 39.387176238245196
max_abs 0.19143196940422058
materials.fur.fragments 23575
materials.fur.ops add=1508800 cmp=424350 div=0 lut=23575 mem=188600 mul=1791700 rcp=0 sqrt=0
materials.fur.psnr 39.387176238245196
)");
}
TEST_F(GoldenFigures, Flight) {
  check(scene("flight"), R"(
fragments 54859
cycles 443944
blocks.blend.ops add=7042144 cmp=0 div=0 lut=0 mem=1760536 mul=7042144 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=1760536 mul=0 rcp=0 sqrt=0
blocks.cache.texels 1760536
blocks.filter.trilinear.ops add=6106386 cmp=2144549 div=0 lut=54859 mem=0 mul=8472264 rcp=0 sqrt=0
blocks.filter.trilinear.texels 1760536
blocks.lod.ops add=384013 cmp=438872 div=54859 lut=164577 mem=0 mul=548590 rcp=0 sqrt=54859
blocks.lod.texels 0
stages.address.busy 220067
stages.address.stalls blocked=223619 latency_full=0 multi_cycle=165208 starved=37
stages.blend.busy 220067
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=165208 starved=223870
stages.cache.busy 440134
stages.cache.stalls blocked=0 latency_full=3642 multi_cycle=385275 starved=61
stages.lod.busy 54859
stages.lod.stalls blocked=388699 latency_full=0 multi_cycle=0 starved=0
hits 233210
misses 20529
texel_reads 1760536
dram busy_cycles=82116 bytes=1313856 requests=20529
psnr_db 27.538387233039337
max_abs 0.25679367780685425
materials.ground.fragments 54859
materials.ground.ops add=13532543 cmp=2583421 div=54859 lut=219436 mem=1760536 mul=16062998 rcp=0 sqrt=54859
materials.ground.psnr 27.538387233039337
)");
}
TEST_F(GoldenFigures, ReliefWall) {
  check(scene("relief_wall"), R"(
fragments 47622
cycles 881188
blocks.blend.ops add=3137792 cmp=0 div=0 lut=0 mem=784448 mul=3137792 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=3149996 mul=0 rcp=0 sqrt=0
blocks.cache.texels 3149996
blocks.filter.trilinear.ops add=2722308 cmp=1117802 div=0 lut=24932 mem=0 mul=3730612 rcp=0 sqrt=0
blocks.filter.trilinear.texels 784448
blocks.lighting.blinn_phong.ops add=619086 cmp=428598 div=0 lut=47622 mem=0 mul=857196 rcp=47622 sqrt=47622
blocks.lighting.blinn_phong.texels 0
blocks.lighting.normal_unit.ops add=439808 cmp=47622 div=0 lut=0 mem=190488 mul=630296 rcp=47622 sqrt=47622
blocks.lighting.normal_unit.texels 0
blocks.lod.ops add=287974 cmp=267526 div=24932 lut=97486 mem=0 mul=430840 rcp=0 sqrt=24932
blocks.lod.texels 0
blocks.relief.parallax_iterative.ops add=5761766 cmp=643493 div=0 lut=0 mem=2274788 mul=2229663 rcp=49864 sqrt=24932
blocks.relief.parallax_iterative.texels 2274788
blocks.relief.parallax_offset.ops add=272280 cmp=68070 div=0 lut=0 mem=90760 mul=363040 rcp=45380 sqrt=22690
blocks.relief.parallax_offset.texels 90760
stages.address.busy 98056
stages.address.stalls blocked=655490 latency_full=0 multi_cycle=50434 starved=127381
stages.blend.busy 98056
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=50434 starved=783067
stages.cache.busy 196112
stages.cache.stalls blocked=0 latency_full=612886 multi_cycle=148490 starved=72022
stages.lighting.busy 47622
stages.lighting.stalls blocked=0 latency_full=0 multi_cycle=0 starved=833510
stages.lod.busy 47622
stages.lod.stalls blocked=584423 latency_full=0 multi_cycle=0 starved=248710
stages.relief.busy 591387
stages.relief.stalls blocked=289304 latency_full=0 multi_cycle=543765 starved=0
hits 404608
misses 219972
texel_reads 3149996
dram busy_cycles=879888 bytes=14078208 requests=219972
psnr_db 26.231085247406185
max_abs 0.39585393667221069
materials.floor.fragments 22690
materials.floor.ops add=2110170 cmp=703390 div=0 lut=45380 mem=363040 mul=2677420 rcp=90760 sqrt=68070
materials.floor.psnr 23.320616543745114
materials.wall.fragments 24932
materials.wall.ops add=11130844 cmp=1869721 div=24932 lut=124660 mem=2977444 mul=8702019 rcp=99728 sqrt=99728
materials.wall.psnr 35.048862333608625
)");
}
TEST_F(GoldenFigures, TerrainFlyover) {
  check(scene("terrain_flyover"), R"(
fragments 26069
cycles 2294252
blocks.blend.ops add=2189920 cmp=0 div=0 lut=0 mem=547480 mul=2189920 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=9723720 mul=0 rcp=0 sqrt=0
blocks.cache.texels 9723720
blocks.filter.trilinear.ops add=1378472 cmp=1277443 div=0 lut=26069 mem=0 mul=1557708 rcp=0 sqrt=0
blocks.filter.trilinear.texels 547480
blocks.lighting.blinn_phong.ops add=338897 cmp=234621 div=0 lut=26069 mem=0 mul=469242 rcp=26069 sqrt=26069
blocks.lighting.blinn_phong.texels 0
blocks.lighting.normal_unit.ops add=104276 cmp=26069 div=0 lut=0 mem=104276 mul=208552 rcp=26069 sqrt=26069
blocks.lighting.normal_unit.texels 0
blocks.lod.ops add=182483 cmp=208552 div=26069 lut=78207 mem=0 mul=260690 rcp=0 sqrt=26069
blocks.lod.texels 0
blocks.relief.terrain_ray_marcher.ops add=30474505 cmp=8993757 div=52138 lut=4588120 mem=9176240 mul=14259671 rcp=26069 sqrt=26069
blocks.relief.terrain_ray_marcher.texels 9176240
stages.address.busy 68435
stages.address.stalls blocked=0 latency_full=0 multi_cycle=42366 starved=2225619
stages.blend.busy 68435
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=42366 starved=2225753
stages.cache.busy 136870
stages.cache.stalls blocked=0 latency_full=0 multi_cycle=110801 starved=2157208
stages.lighting.busy 26069
stages.lighting.stalls blocked=0 latency_full=0 multi_cycle=0 starved=2268127
stages.lod.busy 26069
stages.lod.stalls blocked=0 latency_full=0 multi_cycle=0 starved=2267947
stages.relief.busy 2294060
stages.relief.stalls blocked=0 latency_full=0 multi_cycle=2267991 starved=0
hits 384993
misses 98435
texel_reads 9723720
dram busy_cycles=393740 bytes=6299840 requests=98435
psnr_db 27.752407985214589
max_abs 0.33504432439804077
materials.ground.fragments 26069
materials.ground.ops add=34668553 cmp=10740442 div=78207 lut=4718465 mem=9827996 mul=18945783 rcp=78207 sqrt=104276
materials.ground.psnr 27.752407985214589
)");
}
TEST_F(GoldenFigures, TerrainDem) {
  // The DEM ships with matplotlib's sample data (scenes/terrain_dem.toml).
  if (!std::filesystem::exists(
          "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz"))
    GTEST_SKIP() << "the DEM of scenes/terrain_dem.toml is not installed";
  check(scene("terrain_dem"), R"(
fragments 27986
cycles 5236956
blocks.blend.ops add=2362336 cmp=0 div=0 lut=0 mem=590584 mul=2362336 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=21538064 mul=0 rcp=0 sqrt=0
blocks.cache.texels 21538064
blocks.filter.trilinear.ops add=1486595 cmp=1377070 div=0 lut=27986 mem=0 mul=1680078 rcp=0 sqrt=0
blocks.filter.trilinear.texels 590584
blocks.lighting.blinn_phong.ops add=363818 cmp=251874 div=0 lut=27986 mem=0 mul=503748 rcp=27986 sqrt=27986
blocks.lighting.blinn_phong.texels 0
blocks.lighting.normal_unit.ops add=111944 cmp=27986 div=0 lut=0 mem=111944 mul=223888 rcp=27986 sqrt=27986
blocks.lighting.normal_unit.texels 0
blocks.lod.ops add=195902 cmp=223888 div=27986 lut=83958 mem=0 mul=279860 rcp=0 sqrt=27986
blocks.lod.texels 0
blocks.relief.terrain_ray_marcher.ops add=68778960 cmp=20751578 div=55972 lut=10473740 mem=20947480 mul=31952954 rcp=27986 sqrt=27986
blocks.relief.terrain_ray_marcher.texels 20947480
stages.address.busy 73823
stages.address.stalls blocked=0 latency_full=0 multi_cycle=45837 starved=5162931
stages.blend.busy 73823
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=45837 starved=5163069
stages.cache.busy 147646
stages.cache.stalls blocked=0 latency_full=0 multi_cycle=119660 starved=5089132
stages.lighting.busy 27986
stages.lighting.stalls blocked=0 latency_full=0 multi_cycle=0 starved=5208914
stages.lod.busy 27986
stages.lod.stalls blocked=0 latency_full=0 multi_cycle=0 starved=5208730
stages.relief.busy 5236870
stages.relief.stalls blocked=0 latency_full=0 multi_cycle=5208884 starved=0
hits 649573
misses 425915
texel_reads 21538064
dram busy_cycles=1703660 bytes=27258560 requests=425915
psnr_db 26.414190274866087
max_abs 0.62768715620040894
materials.ground.fragments 27986
materials.ground.ops add=73299555 cmp=22632396 div=83958 lut=10613670 mem=21650008 mul=37002864 rcp=83958 sqrt=111944
materials.ground.psnr 26.414190274866087
)");
}
TEST_F(GoldenFigures, ObjectSpace) {
  check(scene("object_space"), R"(
fragments 6671
cycles 36004
blocks.blend.ops add=574080 cmp=0 div=0 lut=0 mem=143520 mul=574080 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=143520 mul=0 rcp=0 sqrt=0
blocks.cache.texels 143520
blocks.filter.trilinear.ops add=360873 cmp=333737 div=0 lut=6671 mem=0 mul=408022 rcp=0 sqrt=0
blocks.filter.trilinear.texels 143520
blocks.lod.ops add=46697 cmp=53368 div=6671 lut=20013 mem=0 mul=66710 rcp=0 sqrt=6671
blocks.lod.texels 0
stages.address.busy 17940
stages.address.stalls blocked=17850 latency_full=0 multi_cycle=11269 starved=37
stages.blend.busy 17940
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=11269 starved=18057
stages.cache.busy 35880
stages.cache.stalls blocked=0 latency_full=0 multi_cycle=29209 starved=61
stages.lod.busy 6671
stages.lod.stalls blocked=28991 latency_full=0 multi_cycle=0 starved=0
hits 26358
misses 2905
texel_reads 143520
dram busy_cycles=11620 bytes=185920 requests=2905
psnr_db 25.872692271755721
max_abs 0.61447843909263611
materials.crate_os.fragments 0
materials.crate_os.ops add=0 cmp=0 div=0 lut=0 mem=0 mul=0 rcp=0 sqrt=0
materials.crate_os.psnr 0
materials.crate_ss.fragments 6671
materials.crate_ss.ops add=981650 cmp=387105 div=6671 lut=26684 mem=143520 mul=1048812 rcp=0 sqrt=6671
materials.crate_ss.psnr 25.836907050101559
materials.floor_os.fragments 41349
materials.floor_os.ops add=76268944 cmp=23651682 div=1968 lut=693265 mem=8365944 mul=75069767 rcp=740085 sqrt=22
materials.floor_os.psnr 25.878493369106739
materials.floor_os.object_space band_ratio=2 bands=3 clipped_away=0 culled=0 degenerate=0 dram_bytes=1370624 edge_on=0 edge_samples=5704 grid_samples=687558 lanes=1 lod_mean=0.50036676981017092 max_step_px=0.75 pixels_shown=41349 primitives=1 samples=693262 samples_per_pixel=16.766112844325136 texels=5546096
materials.floor_os.object_space.cache accesses=2168694 fill_bytes=1370624 hits=2147278 misses=21416
materials.floor_os.object_space.cycles projection=693262 raster=694232 resolve=19200 setup=69 splat=693262 texture=1486767 total=1506036
materials.floor_os.object_space.holes covered=46428 holes=0 shown=0
materials.floor_os.object_space.ops
materials.floor_os.object_space.ops.geometry.polygon_rotation add=338 cmp=63 div=14 lut=0 mem=0 mul=382 rcp=2 sqrt=2
materials.floor_os.object_space.ops.geometry.sample_projection add=5546132 cmp=693262 div=0 lut=0 mem=0 mul=6239439 rcp=693265 sqrt=0
materials.floor_os.object_space.ops.raster.object_space add=2089536 cmp=697173 div=1954 lut=3 mem=0 mul=9808 rcp=18 sqrt=20
materials.floor_os.object_space.ops.raster.splat_resolve add=24264170 cmp=9782468 div=0 lut=0 mem=2819848 mul=16132226 rcp=46800 sqrt=0
materials.floor_os.object_space.ops.texture add=44368768 cmp=12478716 div=0 lut=693262 mem=5546096 mul=52687912 rcp=0 sqrt=0
materials.floor_os.object_space.splat_buffer bytes=134029824 depth_dropped=0 depth_resets=0 offscreen=25560 resolve_read_bytes=1843200 resolve_written_bytes=307200 splat_read_bytes=65939712 splat_written_bytes=65939712 targets=2747488
materials.floor_ss.fragments 0
materials.floor_ss.ops add=0 cmp=0 div=0 lut=0 mem=0 mul=0 rcp=0 sqrt=0
materials.floor_ss.psnr 0
object_space cycles=1506036 frame_cycles=1542040 screen_space_cycles=36004
)");
}
TEST_F(GoldenFigures, SampleTrace) {
  check(std::string("--trace ") + TEXSIM_SOURCE_DIR + "/traces/samples/basic.trc", R"(
fragments 8
cycles 307
blocks.blend.ops add=256 cmp=0 div=0 lut=0 mem=64 mul=256 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=64 mul=0 rcp=0 sqrt=0
blocks.cache.texels 64
blocks.filter.trilinear.ops add=216 cmp=120 div=0 lut=0 mem=0 mul=288 rcp=0 sqrt=0
blocks.filter.trilinear.texels 64
blocks.lod.ops add=40 cmp=24 div=0 lut=8 mem=0 mul=64 rcp=0 sqrt=0
blocks.lod.texels 0
stages.address.busy 8
stages.address.stalls blocked=0 latency_full=0 multi_cycle=0 starved=14
stages.blend.busy 8
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=291
stages.cache.busy 16
stages.cache.stalls blocked=0 latency_full=0 multi_cycle=8 starved=38
stages.lod.busy 8
stages.lod.stalls blocked=0 latency_full=0 multi_cycle=0 starved=0
hits 20
misses 40
texel_reads 64
dram busy_cycles=160 bytes=2560 requests=40
psnr_db 18.017173379982758
max_abs 0.38817483186721802
materials.default.fragments 8
materials.default.ops add=512 cmp=144 div=0 lut=8 mem=64 mul=608 rcp=0 sqrt=0
materials.default.psnr 18.017173379982758
)");
}

}  // namespace
