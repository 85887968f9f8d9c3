#include <gtest/gtest.h>
TEST(ChiSquareHelper, Placeholder) { GTEST_SKIP() << "being written"; }
