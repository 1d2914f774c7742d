// The number-format registry (rtl_model/number/number_format.h): names, types, dispatch, and
// the blocks' choices (their config spellings map onto registry formats).
#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/probe_setup_fx.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"
#include "rtl_model/number/number_format.h"

namespace texsim {
namespace {

TEST(NumberFormat, NamesAreUniqueAndVisitGivesTheType) {
  for (int i = 0; i < kNumberFormats; ++i) {
    for (int j = i + 1; j < kNumberFormats; ++j) {
      EXPECT_NE(kNumberFormatNames[static_cast<size_t>(i)],
                kNumberFormatNames[static_cast<size_t>(j)]);
    }
  }
  const auto name_of = [](NumberFormat f) {
    return visit_number_format(f, [](auto t) { return format_name<decltype(t)>(); });
  };
  EXPECT_EQ(name_of(NumberFormat::Float), "float");
  EXPECT_EQ(name_of(NumberFormat::Double), "double");
  EXPECT_EQ(name_of(NumberFormat::S16_16), "s16.16");
  EXPECT_EQ(name_of(NumberFormat::S20_28), "s20.28");
  EXPECT_EQ(name_of(NumberFormat::S24_36), "s24.36");
  EXPECT_EQ(name_of(NumberFormat::S18_30), "s18.30");
  EXPECT_EQ(name_of(NumberFormat::S20_28HalfUp), "s20.28");
  EXPECT_EQ(name_of(NumberFormat::Fx16), "u0.16");
  EXPECT_EQ(name_of(NumberFormat::Fx8), "u0.8");
}

TEST(NumberFormat, CoordinateFormatsAreTheDefaultFixedTypes) {
  static_assert(std::is_same_v<number_format_t<NumberFormat::S16_16>, Fixed<16, 16>>);
  static_assert(std::is_same_v<number_format_t<NumberFormat::S20_28>, Fixed<20, 28>>);
  static_assert(std::is_same_v<number_format_t<NumberFormat::S24_36>, Fixed<24, 36>>);
  for (int i = 0; i < 5; ++i) {
    const NumberFormat f = kCoordFormats.at(i);
    EXPECT_EQ(kCoordFormats.key_of(f), number_format_name(f));
    EXPECT_EQ(kCoordFormats.index_of(f), i);
  }
}

TEST(NumberFormat, BlockChoicesKeepTheirSpellings) {
  static_assert(std::is_same_v<EwaQFixed, number_format_t<NumberFormat::S18_30>>);
  static_assert(std::is_same_v<SpafFixed, number_format_t<NumberFormat::S20_28HalfUp>>);
  static_assert(std::is_same_v<ProbeFx::Deriv, number_format_t<NumberFormat::S16_24HalfUp>>);
  EXPECT_EQ(EwaFilter::kArith.key_of(NumberFormat::S18_30), "fixed");
  EXPECT_EQ(SpafFilter::kArith.key_of(NumberFormat::S20_28HalfUp), "fixed");
  EXPECT_EQ(kProbeArith.key_of(NumberFormat::S16_24HalfUp), "fixed");
  EXPECT_EQ(kVdFormats.key_of(NumberFormat::Fx12), "fx12");
  // A block's visit instantiates only its own formats.
  const std::string fx = EwaFilter::kArith.visit(NumberFormat::S18_30,
                                                 [](auto t) { return format_name<decltype(t)>(); });
  EXPECT_EQ(fx, "s18.30");
  const std::string vd =
      visit_vd_format(NumberFormat::Fx16, [](auto fmt) { return decltype(fmt)::name(); });
  EXPECT_EQ(vd, VdFx16::name());
}

}  // namespace
}  // namespace texsim
