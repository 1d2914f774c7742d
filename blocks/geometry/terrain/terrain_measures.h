#pragma once
// Measures of a finite-function height evaluator that the terrain tests and `texsim study
// terrain` share (docs/derivations/terrain.md §3–4): the partition-of-unity ripple on flat
// terrain, the slope jumps at the nodes, and the terrace measure on a long monotone slope.
// Arithmetic: double.
#include "blocks/geometry/terrain/terrain_height_evaluator.h"

namespace texsim {

// Largest |y - 1| on a flat 8 × 8 grid of ones over one cell, sampled at 1/256.
double flat_ripple(const TerrainHeightEvaluator& e);

// Largest |S(x) - 1| of the three-term sum S(x) = f(x - 1) + f(x) + f(x + 1), x ∈ [-1/2, 1/2],
// sampled at 1/4096 (variant 1's 1-D partition of unity).
double ripple_1d(const FiniteBasis& f);

// Slope jumps at the nodes of random data (seeded, heights in [0, 10]) that varies along x
// only: |y'(i+) - y'(i-)| / |Δ²y_i| over ten interior nodes. Returns the largest ratio; `lo`
// gets the smallest and `max_jump` (if given) the largest |y'(i+) - y'(i-)|.
double slope_jump_ratio(const TerrainHeightEvaluator& e, double& lo, double* max_jump = nullptr);

// Terrace measure on heights h_i = i (slope 1) along x, sampled at z = 1.5 over one cell at
// 1/512: T = 1 - (smallest slope / largest slope) (1: flat steps at the nodes; 0: a straight
// ramp; > 1: the slope changes sign). `dev` gets the largest |y - x|.
double terrace_measure(const TerrainHeightEvaluator& e, double& dev);

}  // namespace texsim
