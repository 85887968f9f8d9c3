// Samplers: (0,2)-sequence property of the scrambled Sobol' pairs, uniformity of every dimension,
// independence of dimension pairs, strata of the stratified sampler, determinism. (Being written.)
#include "sampling/sampler.h"

#include <gtest/gtest.h>

using namespace symphong;

TEST(Sampler, Placeholder) { GTEST_SKIP() << "being written"; }
