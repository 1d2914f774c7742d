#pragma once
// The parameters `texsim study rtl` builds each RTL block with (docs/rtl/study.md): the block's
// generated parameter set (rtl_model/params/rtl_params.h, the values the lockstep tests verify)
// with the swept widths on top, and the parameters that follow a width recomputed from the C++
// models (V(d) coefficients and breakpoints of the narrower format, the u/v fraction bits and
// minimum denominator). Also the C++ error figure and latency that go with each point.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace texsim {

struct RtlStudyPoint {
  std::vector<std::pair<std::string, int64_t>> params;  // every parameter to set on the module
  std::string max_error;  // exhaustive C++ error at this point (with its unit), or ""
  std::string latency;    // cycles from the C++ timing model, or ""
  std::string problem;    // non-empty: this point cannot be built, and why
};

// `sweep`: the swept parameters the module declares, with this point's values. A module that
// is not one of rtl_params::rtl_blocks() gets exactly `sweep`.
RtlStudyPoint rtl_study_point(const std::string& module,
                              const std::vector<std::pair<std::string, int>>& sweep);

// True for the modules of rtl_params::rtl_blocks() (texsim_sampler is one, although named like
// the shared helpers texsim_*).
bool rtl_study_known_block(const std::string& module);

// True when `params` are exactly the generated ones of `module` (the RTL the lockstep tests
// verify against the C++ model).
bool rtl_study_is_generated(const std::string& module,
                            const std::vector<std::pair<std::string, int64_t>>& params);

// The name the texture unit's reports give the C++ block that `module` implements at its
// generated parameters, or "" when reports list no such block of its own.
std::string rtl_report_block(const std::string& module);

// Largest |BilinearLerp − exact bilinear| in LSBs of a T-bit texel when the sample position is
// rounded to S fraction bits (worst corner texels 0 / 2^T − 1, every rounding-cell corner).
double bilinear_weight_error_lsb(int texel_bits, int sub_bits);

}  // namespace texsim
