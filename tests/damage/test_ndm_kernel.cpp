#include "pnc/damage/ndm.hpp"
#include <gtest/gtest.h>
TEST(Smoke, Builds) { EXPECT_NEAR(pnc::damage::critical_stretch(), 1.24446, 1e-5); }
