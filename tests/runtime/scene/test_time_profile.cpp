// TimeProfile::factor (time_profile.cpp): constant, ramp and sinusoid
// profiles, and a profile read from a scene.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scene_test_support.hpp"

namespace {

using scene_test::TempDir;
using tensormass::Scene;
using tensormass::TimeProfile;

TEST(SceneProfile, Constant) {
  const TimeProfile p;
  EXPECT_EQ(p.kind, "constant");
  EXPECT_DOUBLE_EQ(p.factor(-1), 1);
  EXPECT_DOUBLE_EQ(p.factor(0), 1);
  EXPECT_DOUBLE_EQ(p.factor(123), 1);
}

TEST(SceneProfile, Ramp) {
  TimeProfile p;
  p.kind = "ramp";
  p.duration = 2.0;
  EXPECT_DOUBLE_EQ(p.factor(-1), 0);
  EXPECT_DOUBLE_EQ(p.factor(0), 0);
  EXPECT_DOUBLE_EQ(p.factor(0.5), 0.25);
  EXPECT_DOUBLE_EQ(p.factor(2), 1);
  EXPECT_DOUBLE_EQ(p.factor(10), 1);
}

TEST(SceneProfile, Sinusoid) {
  TimeProfile p;
  p.kind = "sinusoid";
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

TEST(SceneProfile, ReadFromTheScene) {
  TempDir dir;
  const std::string text = scene_test::kBaseScene + "loads:\n  profile: sinusoid\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.loads.profile.kind, "sinusoid");
  EXPECT_DOUBLE_EQ(s.loads.profile.period, 1.0);
  EXPECT_NEAR(s.loads.profile.factor(0.5), 1, 1e-15);
}

}  // namespace
