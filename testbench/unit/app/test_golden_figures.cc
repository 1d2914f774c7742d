// Golden report figures of the shipped scenes and sample traces: fragments, cycles, every
// block's and material's operation counts, stage and cache counters, and PSNR overall and per
// material, held exactly (doubles to 17 digits). Work on the simulator's speed must leave every
// figure bit-identical; a change of the model that moves them on purpose updates the table
// (the failure message prints the new lines). The ground truth uses 2x2 samples per pixel so
// the whole test runs in a few seconds; the figures of the simulated unit do not depend on it.
#include <gtest/gtest.h>

#include <cstdio>
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
  }
  return out.str();
}

class GoldenFigures : public Cli {
 protected:
  // Runs texsim with `input` (a scene path, "--trace FILE", or "" for the built-in scene) and
  // compares its figures with `expected`.
  void check(const std::string& input, const std::string& expected) {
    const std::string out = path("out");
    const Result r =
        sh("run " + input + " --set reference.supersamples=2 --no-progress --out " + out);
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
fragments 65942
cycles 401004
blocks.blend.ops add=6409280 cmp=0 div=0 lut=0 mem=1602320 mul=6409280 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=1602320 mul=0 rcp=0 sqrt=0
blocks.cache.texels 1602320
blocks.coords.constant-depth[float].ops add=27974 cmp=348 div=2 lut=0 mem=0 mul=3464 rcp=346 sqrt=0
blocks.coords.constant-depth[float].texels 0
blocks.coords.heckbert[float].ops add=77682 cmp=12947 div=25894 lut=0 mem=0 mul=77682 rcp=0 sqrt=0
blocks.coords.heckbert[float].texels 0
blocks.coords.incremental[s16.16].ops add=44241 cmp=14057 div=28114 lut=0 mem=0 mul=2070 rcp=0 sqrt=0
blocks.coords.incremental[s16.16].texels 0
blocks.coords.incremental[s20.28].ops add=44241 cmp=14057 div=28114 lut=0 mem=0 mul=2070 rcp=0 sqrt=0
blocks.coords.incremental[s20.28].texels 0
blocks.coords.quadratic-32[float].ops add=32052 cmp=1023 div=2046 lut=0 mem=0 mul=6138 rcp=341 sqrt=0
blocks.coords.quadratic-32[float].texels 0
blocks.derivs.accelerated-fd[float].ops add=59670 cmp=11934 div=23868 lut=0 mem=0 mul=0 rcp=0 sqrt=0
blocks.derivs.accelerated-fd[float].texels 0
blocks.derivs.analytic[float].ops add=51788 cmp=12947 div=0 lut=0 mem=0 mul=129470 rcp=12947 sqrt=0
blocks.derivs.analytic[float].texels 0
blocks.derivs.iterative[s16.16].ops add=72371 cmp=14057 div=0 lut=0 mem=0 mul=86444 rcp=28114 sqrt=0
blocks.derivs.iterative[s16.16].texels 0
blocks.derivs.iterative[s20.28].ops add=72371 cmp=14057 div=0 lut=0 mem=0 mul=86444 rcp=28114 sqrt=0
blocks.derivs.iterative[s20.28].texels 0
blocks.derivs.quad[float].ops add=14918 cmp=657 div=1314 lut=0 mem=0 mul=0 rcp=0 sqrt=0
blocks.derivs.quad[float].texels 0
blocks.filter.trilinear.ops add=5605656 cmp=2063914 div=0 lut=65942 mem=0 mul=7742904 rcp=0 sqrt=0
blocks.filter.trilinear.texels 1602320
blocks.lod.ops add=461594 cmp=527536 div=65942 lut=197826 mem=0 mul=659420 rcp=0 sqrt=65942
blocks.lod.texels 0
stages.address.busy 200290
stages.address.stalls blocked=200365 latency_full=0 multi_cycle=134348 starved=70
stages.blend.busy 200290
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=134348 starved=200708
stages.cache.busy 400580
stages.cache.stalls blocked=0 latency_full=222 multi_cycle=334638 starved=94
stages.coords.busy 83472
stages.coords.stalls blocked=316798 latency_full=0 multi_cycle=17530 starved=0
stages.derivs.busy 69408
stages.derivs.stalls blocked=330614 latency_full=0 multi_cycle=3466 starved=335
stages.lod.busy 65942
stages.lod.stalls blocked=334405 latency_full=0 multi_cycle=0 starved=130
hits 277367
misses 35879
texel_reads 1602320
dram busy_cycles=143516 bytes=2296256 requests=35879
psnr_db 20.564096773715352
max_abs 0.51329612731933594
materials.constant_depth.fragments 12947
materials.constant_depth.ops add=2431590 cmp=501546 div=14263 lut=51788 mem=306336 mul=2839268 rcp=346 sqrt=12947
materials.constant_depth.psnr 22.517763658807265
materials.exact.fragments 5967
materials.exact.ops add=1512427 cmp=286489 div=5967 lut=23868 mem=196984 mul=1795214 rcp=0 sqrt=5967
materials.exact.psnr 19.77306440017491
materials.heckbert.fragments 12947
materials.heckbert.ops add=2530322 cmp=528083 div=38841 lut=51788 mem=307984 mul=3057376 rcp=12947 sqrt=12947
materials.heckbert.psnr 22.534322657921596
materials.incremental.fragments 14057
materials.incremental.ops add=2455581 cmp=537057 div=42171 lut=56228 mem=298088 mul=2865468 rcp=28114 sqrt=14057
materials.incremental.psnr 22.816790383938415
materials.incremental_s16.fragments 14057
materials.incremental_s16.ops add=2455994 cmp=537113 div=42171 lut=56228 mem=298144 mul=2865958 rcp=28114 sqrt=14057
materials.incremental_s16.psnr 17.746968251077
materials.quadratic_32.fragments 5967
materials.quadratic_32.ops add=1587924 cmp=297246 div=31881 lut=23868 mem=194784 mul=1782102 rcp=341 sqrt=5967
materials.quadratic_32.psnr 19.84462277263215
)");
}
TEST_F(GoldenFigures, FootprintFilters) {
  check(scene("footprint_filters"), R"(
fragments 8356
cycles 81320
blocks.blend.ops add=66816 cmp=0 div=0 lut=0 mem=16704 mul=66816 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=268290 mul=0 rcp=0 sqrt=0
blocks.cache.texels 268290
blocks.filter.ewa.ops add=1211254 cmp=343778 div=0 lut=99775 mem=97685 mul=1060803 rcp=6270 sqrt=6270
blocks.filter.ewa.texels 97685
blocks.filter.feline.ops add=914958 cmp=221720 div=0 lut=21748 mem=107104 mul=1062620 rcp=8360 sqrt=6270
blocks.filter.feline.texels 107104
blocks.filter.spaf.ops add=1124260 cmp=827837 div=0 lut=152744 mem=46797 mul=688369 rcp=12528 sqrt=4176
blocks.filter.spaf.texels 46797
blocks.filter.trilinear.ops add=56376 cmp=31320 div=0 lut=0 mem=0 mul=75168 rcp=0 sqrt=0
blocks.filter.trilinear.texels 16704
blocks.lod.ops add=10440 cmp=6264 div=0 lut=2088 mem=0 mul=16704 rcp=0 sqrt=0
blocks.lod.texels 0
stages.address.busy 81157
stages.address.stalls blocked=0 latency_full=0 multi_cycle=72801 starved=14
stages.blend.busy 8356
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=72956
stages.cache.busy 68652
stages.cache.stalls blocked=0 latency_full=3802 multi_cycle=60296 starved=8857
stages.lod.busy 8356
stages.lod.stalls blocked=72647 latency_full=0 multi_cycle=0 starved=0
hits 45101
misses 6358
texel_reads 268290
dram busy_cycles=25432 bytes=406912 requests=6358
psnr_db 18.273772255854468
max_abs 0.6152784526348114
materials.ewa.fragments 2090
materials.ewa.ops add=1211254 cmp=343778 div=0 lut=99775 mem=97685 mul=1060803 rcp=6270 sqrt=6270
materials.ewa.psnr 18.780234147667475
materials.feline.fragments 2090
materials.feline.ops add=914958 cmp=221720 div=0 lut=21748 mem=107104 mul=1062620 rcp=8360 sqrt=6270
materials.feline.psnr 18.398521398147146
materials.spaf.fragments 2088
materials.spaf.ops add=1124260 cmp=827837 div=0 lut=152744 mem=46797 mul=688369 rcp=12528 sqrt=4176
materials.spaf.psnr 18.373892130542583
materials.trilinear.fragments 2088
materials.trilinear.ops add=133632 cmp=37584 div=0 lut=2088 mem=16704 mul=158688 rcp=0 sqrt=0
materials.trilinear.psnr 17.624281598223334
)");
}
TEST_F(GoldenFigures, Photo) {
  check(scene("photo"), R"(
fragments 91005
cycles 944494
blocks.blend.ops add=14949248 cmp=0 div=0 lut=0 mem=3737312 mul=14949248 rcp=0 sqrt=0
blocks.blend.texels 0
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=3737312 mul=0 rcp=0 sqrt=0
blocks.cache.texels 3737312
blocks.filter.trilinear.ops add=12764310 cmp=4463171 div=0 lut=79902 mem=0 mul=17712182 rcp=0 sqrt=0
blocks.filter.trilinear.texels 3737312
blocks.lod.ops add=614829 cmp=672525 div=79902 lut=250809 mem=0 mul=887844 rcp=0 sqrt=79902
blocks.lod.texels 0
stages.address.busy 467164
stages.address.stalls blocked=477023 latency_full=0 multi_cycle=376159 starved=37
stages.blend.busy 467164
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=376159 starved=477324
stages.cache.busy 934328
stages.cache.stalls blocked=0 latency_full=10006 multi_cycle=843323 starved=61
stages.lod.busy 91005
stages.lod.stalls blocked=852987 latency_full=0 multi_cycle=0 starved=0
hits 489101
misses 60105
texel_reads 3737312
dram busy_cycles=240420 bytes=3846720 requests=60105
psnr_db 30.749996861095656
max_abs 0.29517409205436707
materials.floor.fragments 79902
materials.floor.ops add=27706619 cmp=4847018 div=79902 lut=319608 mem=3648488 mul=32883094 rcp=0 sqrt=79902
materials.floor.psnr 31.391347792823268
materials.wall.fragments 11103
materials.wall.ops add=621768 cmp=288678 div=0 lut=11103 mem=88824 mul=666180 rcp=0 sqrt=0
materials.wall.psnr 27.765839017187695
)");
}
TEST_F(GoldenFigures, SubtexelCutoff) {
  check(scene("subtexel_cutoff"), R"(
fragments 33986
cycles 279080
blocks.cache.ops add=0 cmp=0 div=0 lut=0 mem=673727 mul=0 rcp=0 sqrt=0
blocks.cache.texels 673727
blocks.filter.ewa[ewa].ops add=2343454 cmp=662237 div=0 lut=202238 mem=192478 mul=2271309 rcp=29280 sqrt=29280
blocks.filter.ewa[ewa].texels 192478
blocks.filter.ewa[ewa_vd].ops add=3369506 cmp=1416589 div=0 lut=202238 mem=192478 mul=3093656 rcp=131059 sqrt=232838
blocks.filter.ewa[ewa_vd].texels 192478
blocks.filter.spaf[spaf].ops add=3498171 cmp=2723920 div=0 lut=472172 mem=141389 mul=2117277 rcp=43398 sqrt=14466
blocks.filter.spaf[spaf].texels 141389
blocks.filter.spaf[spaf_vd].ops add=3927383 cmp=4005040 div=0 lut=154615 mem=147382 mul=2657111 rcp=72330 sqrt=43398
blocks.filter.spaf[spaf_vd].texels 147382
stages.address.busy 278919
stages.address.stalls blocked=0 latency_full=0 multi_cycle=244933 starved=14
stages.blend.busy 33986
stages.blend.stalls blocked=0 latency_full=0 multi_cycle=0 starved=245086
stages.cache.busy 180648
stages.cache.stalls blocked=0 latency_full=191 multi_cycle=146662 starved=98231
stages.lod.busy 33986
stages.lod.stalls blocked=244833 latency_full=0 multi_cycle=0 starved=0
hits 126197
misses 3432
texel_reads 673727
dram busy_cycles=13728 bytes=219648 requests=3432
psnr_db 19.234016145371825
max_abs 0.53897284716367722
materials.ewa.fragments 9760
materials.ewa.ops add=2343454 cmp=662237 div=0 lut=202238 mem=192478 mul=2271309 rcp=29280 sqrt=29280
materials.ewa.psnr 19.280583606552234
materials.ewa_vd.fragments 9760
materials.ewa_vd.ops add=3369506 cmp=1416589 div=0 lut=202238 mem=192478 mul=3093656 rcp=131059 sqrt=232838
materials.ewa_vd.psnr 19.421015497326497
materials.spaf.fragments 7233
materials.spaf.ops add=3498171 cmp=2723920 div=0 lut=472172 mem=141389 mul=2117277 rcp=43398 sqrt=14466
materials.spaf.psnr 19.088362962412806
materials.spaf_vd.fragments 7233
materials.spaf_vd.ops add=3927383 cmp=4005040 div=0 lut=154615 mem=147382 mul=2657111 rcp=72330 sqrt=43398
materials.spaf_vd.psnr 19.075587231864169
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
