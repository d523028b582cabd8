#include <gtest/gtest.h>
TEST(P4, Builds) { SUCCEED(); }
