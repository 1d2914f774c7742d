#pragma once
// BC1, BC2 and BC3 blocks from libsquish (Debian's libsquish 1.15): its three colour fits.
#include <string>

#include "pipeline/image_io/encoder_input.h"

namespace texsim {

enum class SquishFit {
  Range,             // kColourRangeFit: endpoints from the colours' range, fastest
  Cluster,           // kColourClusterFit: the library's default
  IterativeCluster,  // kColourIterativeClusterFit: best and slowest
};

// "range", "cluster", "iterative-cluster".
const char* squish_fit_name(SquishFit fit);

// Encodes `img` (padded to whole blocks first, encoder_input.h) as BC1_UNORM, BC2_UNORM or
// BC3_UNORM; any other format, or a bad image, throws InputError. BC1 blocks are the opaque
// 4-colour kind unless a texel's alpha is below 128 (libsquish then uses the 3-colour kind
// with transparent black). Colour error is weighted equally across R, G and B (libsquish's
// perceptual weights are not used).
EncodedLevel squish_encode(const Rgba8Image& img, FileBlockFormat format, SquishFit fit);

}  // namespace texsim
