// TimeProfile::factor and profile_kind_name (model/time_profile.cpp):
// constant, ramp and sinusoid profiles.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tensormass/model/model_spec.hpp"

namespace {

using tensormass::ProfileKind;
using tensormass::TimeProfile;

TEST(TimeProfile, Constant) {
  const TimeProfile p;
  EXPECT_EQ(p.kind, ProfileKind::constant);
  EXPECT_DOUBLE_EQ(p.factor(-1), 1);
  EXPECT_DOUBLE_EQ(p.factor(0), 1);
  EXPECT_DOUBLE_EQ(p.factor(123), 1);
}

TEST(TimeProfile, Ramp) {
  TimeProfile p;
  p.kind = ProfileKind::ramp;
  p.duration = 2.0;
  EXPECT_DOUBLE_EQ(p.factor(-1), 0);
  EXPECT_DOUBLE_EQ(p.factor(0), 0);
  EXPECT_DOUBLE_EQ(p.factor(0.5), 0.25);
  EXPECT_DOUBLE_EQ(p.factor(2), 1);
  EXPECT_DOUBLE_EQ(p.factor(10), 1);
}

TEST(TimeProfile, Sinusoid) {
  TimeProfile p;
  p.kind = ProfileKind::sinusoid;
  p.period = 4.0;
  EXPECT_NEAR(p.factor(0), 0, 1e-15);
  EXPECT_NEAR(p.factor(1), 0.5, 1e-15);
  EXPECT_NEAR(p.factor(2), 1, 1e-15);
  EXPECT_NEAR(p.factor(4), 0, 1e-15);
  EXPECT_NEAR(p.factor(0.7), (1 - std::cos(2 * std::numbers::pi * 0.7 / 4)) / 2, 1e-15);
  p.phase = 1.0;
  EXPECT_NEAR(p.factor(0), 0.5, 1e-15);
  EXPECT_NEAR(p.factor(1), 1, 1e-15);
}

TEST(TimeProfile, KindNamesAreTheScenes) {
  EXPECT_EQ(tensormass::profile_kind_name(ProfileKind::constant), "constant");
  EXPECT_EQ(tensormass::profile_kind_name(ProfileKind::ramp), "ramp");
  EXPECT_EQ(tensormass::profile_kind_name(ProfileKind::sinusoid), "sinusoid");
}

}  // namespace
