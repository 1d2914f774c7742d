#include "testbench/conformance/vulkan_ops_conformance.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace texsim {

namespace {

// Vulkan "Wrapping Operation" as the spec states it; -1 stands for a border texel.
long long wrap(long long i, long long size, AddressMode m) {
  auto mod = [](long long a, long long b) { return ((a % b) + b) % b; };
  switch (m) {
    case AddressMode::Wrap:
      return mod(i, size);
    case AddressMode::Clamp:
      return std::min(std::max(i, 0LL), size - 1);
    case AddressMode::Mirror: {
      const long long n = mod(i, 2 * size) - size;
      return (size - 1) - (n >= 0 ? n : -(1 + n));
    }
    case AddressMode::Border:
      return i < 0 || i >= size ? -1 : i;
    case AddressMode::MirrorClamp:
      return std::min(i >= 0 ? i : -(1 + i), size - 1);
  }
  return 0;
}

}  // namespace

bool VulkanOpsConformance::passes(CompareOp op, double reference, double depth) {
  switch (op) {
    case CompareOp::None:
    case CompareOp::Never:
      return false;
    case CompareOp::Less:
      return reference < depth;
    case CompareOp::Equal:
      return reference == depth;
    case CompareOp::LessOrEqual:
      return reference <= depth;
    case CompareOp::Greater:
      return reference > depth;
    case CompareOp::NotEqual:
      return reference != depth;
    case CompareOp::GreaterOrEqual:
      return reference >= depth;
    case CompareOp::Always:
      return true;
  }
  return false;
}

Texture VulkanOpsConformance::compared(const Texture& depth, CompareOp op, double reference) {
  // "Depth Compare Operation": a UNORM depth format's reference is clamped to [0, 1].
  if (format_info(depth.storage()).coding == ChannelCoding::Unorm)
    reference = std::clamp(reference, 0.0, 1.0);
  std::vector<int> ws, hs;
  std::vector<std::vector<float>> levels;
  for (int l = 0; l < depth.levels(); ++l) {
    const int w = depth.width(l), h = depth.height(l);
    ws.push_back(w);
    hs.push_back(h);
    std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const float p = passes(op, reference, depth.texel(l, x, y)[0]) ? 1.0f : 0.0f;
        float* t =
            &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
        t[0] = t[1] = t[2] = p;
        t[3] = 1;
      }
    }
    levels.push_back(std::move(px));
  }
  return Texture::from_levels("compared", ws, hs, levels, TexelFormat::Rgba32f);
}

ConformanceVerdict VulkanOpsConformance::check_compare(const Texture& depth, const VkSampleQuery& q,
                                                       CompareOp op, double reference,
                                                       const Rgba& result) const {
  // A border texel's depth is the border colour's red as the depth format reads it, compared
  // like any texel.
  const StorageFormatInfo& f = format_info(depth.storage());
  double b = filter_.sampler().border[0];
  if (f.coding == ChannelCoding::Unorm) {
    b = std::clamp(b, 0.0, 1.0);
    reference = std::clamp(reference, 0.0, 1.0);
  }
  VkSamplerState s = filter_.sampler();
  s.border[0] = s.border[1] = s.border[2] = passes(op, reference, b) ? 1.0 : 0.0;
  s.border[3] = 1;
  return VulkanConformance(s, filter_.precision()).check(compared(depth, op, reference), q, result);
}

ConformanceVerdict VulkanOpsConformance::check_gather(const Texture& tex, const VkSampleQuery& q,
                                                      int component, int du, int dv,
                                                      const Rgba& result) const {
  ConformanceVerdict v;
  const VkSamplerState& s = filter_.sampler();
  const VkFilterPrecision& p = filter_.precision();
  if (!std::isfinite(q.u) || !std::isfinite(q.v)) {
    v.pass = true;
    v.judged = false;
    v.reason = "not judged: non-finite coordinates (undefined in the spec)";
    return v;
  }
  const long long w = tex.width(0), h = tex.height(0);
  const double lsb = std::ldexp(1.0, -p.sub_texel_bits);
  // i0 = ⌊u·width − ½⌋ within the coordinate's error and one sub-texel LSB.
  const double x = q.u * static_cast<double>(w) - 0.5, y = q.v * static_cast<double>(h) - 0.5;
  const double ex = std::fabs(x) * p.coord_rel_eps + 1e-9 + lsb;
  const double ey = std::fabs(y) * p.coord_rel_eps + 1e-9 + lsb;
  const auto value = [&](long long i, long long j) {
    const long long tx = wrap(i + s.offset_u + du, w, s.address_u);
    const long long ty = wrap(j + s.offset_v + dv, h, s.address_v);
    if (tx < 0 || ty < 0) {
      const StorageFormatInfo& f = format_info(tex.storage());
      if (component >= f.channels) return component == 3 ? 1.0 : 0.0;
      const double b = s.border[component];
      return f.coding == ChannelCoding::Unorm ? std::clamp(b, 0.0, 1.0) : b;
    }
    return static_cast<double>(tex.texel(0, static_cast<int>(tx), static_cast<int>(ty))[component]);
  };
  for (auto i0 = static_cast<long long>(std::floor(x - ex));
       i0 <= static_cast<long long>(std::floor(x + ex)); ++i0) {
    for (auto j0 = static_cast<long long>(std::floor(y - ey));
         j0 <= static_cast<long long>(std::floor(y + ey)); ++j0) {
      const double want[4] = {value(i0, j0 + 1), value(i0 + 1, j0 + 1), value(i0 + 1, j0),
                              value(i0, j0)};
      bool same = true;
      for (int c = 0; c < 4; ++c) {
        same = same && std::fabs(static_cast<double>(result[c]) - want[c]) <=
                           p.color_eps * std::max(1.0, std::fabs(want[c]));
      }
      if (same) {
        v.pass = true;
        v.reason = "ok";
        return v;
      }
    }
  }
  v.reason = "gather result (" + std::to_string(result[0]) + ", " + std::to_string(result[1]) +
             ", " + std::to_string(result[2]) + ", " + std::to_string(result[3]) +
             ") is no footprint's four texels in the spec's order";
  v.miss = 1;
  return v;
}

}  // namespace texsim
