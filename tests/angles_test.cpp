// Frame and angle conventions (DESIGN §1, core/angles.h): spherical coordinates, the mirror
// direction and Rusinkiewicz's half/difference angles, on hand-computed cases and random pairs.
#include "core/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "core/vec.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::RandomUpperDirection;

// How a round degree value prints (the shortest round trip: "5", "22.5").
std::string FormatNumberForTest(double degrees) {
  std::ostringstream out;
  out << degrees;
  return out.str();
}

// Difference of two azimuths on the circle, in (-π, π].
double AzimuthDifference(double a, double b) {
  double d = std::fmod(a - b, 2.0 * kPi);
  if (d > kPi) d -= 2.0 * kPi;
  if (d <= -kPi) d += 2.0 * kPi;
  return d;
}

void ExpectVecNear(const Vec3& actual, const Vec3& expected, double tolerance) {
  EXPECT_NEAR((actual - expected).norm(), 0.0, tolerance)
      << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

TEST(Angles, DegreesAndRadians) {
  EXPECT_DOUBLE_EQ(DegToRad(180.0), kPi);
  EXPECT_DOUBLE_EQ(RadToDeg(0.5 * kPi), 90.0);
  EXPECT_DOUBLE_EQ(RadToDeg(DegToRad(37.25)), 37.25);
}

TEST(Angles, SphericalDirectionFollowsTheFrame) {
  // z is the normal, x is azimuth 0, phi turns from +x toward +y (DESIGN §1).
  ExpectVecNear(SphericalDirection(0.0, 1.234), Vec3(0, 0, 1), 1e-15);
  ExpectVecNear(SphericalDirection(0.5 * kPi, 0.0), Vec3(1, 0, 0), 1e-15);
  ExpectVecNear(SphericalDirection(0.5 * kPi, 0.5 * kPi), Vec3(0, 1, 0), 1e-15);
  ExpectVecNear(SphericalDirection(kPi, 0.0), Vec3(0, 0, -1), 1e-15);
  const double s = std::sin(DegToRad(30.0)), c = std::cos(DegToRad(30.0));
  ExpectVecNear(SphericalDirection(DegToRad(30.0), DegToRad(180.0)), Vec3(-s, 0, c), 1e-15);
}

TEST(Angles, SphericalRoundTrip) {
  for (int i = 1; i < 60; ++i) {
    const double theta = kPi * i / 60.0;
    for (int j = 0; j < 120; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / 120.0;
      const Vec3 w = SphericalDirection(theta, phi);
      EXPECT_NEAR(w.norm(), 1.0, 1e-15);
      EXPECT_NEAR(Theta(w), theta, 1e-13) << "theta " << theta << " phi " << phi;
      EXPECT_NEAR(Phi(w), phi, 1e-13) << "theta " << theta << " phi " << phi;
      EXPECT_DOUBLE_EQ(CosTheta(w), std::cos(theta));
    }
  }
}

// acos(z) loses everything below ~1e-8 rad near the pole (1 - cos(1e-9) rounds to 0); Theta
// must keep full relative precision there (angles.h: atan2, not acos).
TEST(Angles, ThetaIsAccurateNearThePoles) {
  for (double theta : {1e-9, 3e-12, 1e-15}) {
    for (double phi : {0.0, 1.0, 4.0}) {
      EXPECT_NEAR(Theta(SphericalDirection(theta, phi)), theta, 1e-12 * theta);
      EXPECT_NEAR(Theta(SphericalDirection(kPi - theta, phi)), kPi - theta, 4e-15);
    }
  }
  EXPECT_NEAR(Theta(Vec3(1e-9, 0.0, 1.0)), 1e-9, 1e-21);
  EXPECT_EQ(Theta(Vec3(0, 0, 1)), 0.0);
  EXPECT_DOUBLE_EQ(Theta(Vec3(0, 0, -1)), kPi);
  EXPECT_DOUBLE_EQ(Theta(Vec3(0, 1, 0)), 0.5 * kPi);
}

TEST(Angles, PhiIsInZeroToTwoPi) {
  std::mt19937 rng(1);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int k = 0; k < 10000; ++k) {
    const Vec3 w(normal(rng), normal(rng), normal(rng));
    const double phi = Phi(w);
    EXPECT_GE(phi, 0.0);
    EXPECT_LT(phi, 2.0 * kPi);
    EXPECT_NEAR(std::cos(phi) * std::hypot(w.x(), w.y()), w.x(), 1e-14);
    EXPECT_NEAR(std::sin(phi) * std::hypot(w.x(), w.y()), w.y(), 1e-14);
  }
  // Quadrants by hand, and the documented 0 on the axis.
  EXPECT_DOUBLE_EQ(Phi(Vec3(1, 1, 0)), 0.25 * kPi);
  EXPECT_DOUBLE_EQ(Phi(Vec3(-1, 1, 0)), 0.75 * kPi);
  EXPECT_DOUBLE_EQ(Phi(Vec3(-1, -1, 0)), 1.25 * kPi);
  EXPECT_DOUBLE_EQ(Phi(Vec3(1, -1, 0)), 1.75 * kPi);
  EXPECT_DOUBLE_EQ(Phi(Vec3(-1, 0, 0)), kPi);
  EXPECT_EQ(Phi(Vec3(0, 0, 1)), 0.0);
  EXPECT_EQ(Phi(Vec3(0, 0, -1)), 0.0);
}

// Just below the +x axis atan2 returns a tiny negative angle; adding 2π to it rounds to 2π,
// which is outside [0, 2π) and would index one past the end of an azimuth table (a MERL phi_d
// bin, a schedule's phi grid).
TEST(Angles, PhiJustBelowTheXAxisStaysBelowTwoPi) {
  for (double y : {-1e-17, -1e-20, -1e-300, -0.0}) {
    const double phi = Phi(Vec3(1.0, y, 0.0));
    EXPECT_GE(phi, 0.0) << "y = " << y;
    EXPECT_LT(phi, 2.0 * kPi) << "y = " << y;
  }
}

// Read back as the native CSV reader does: degrees -> DegToRad -> SphericalDirection.
Vec3 ReadBackDegrees(const DegreesText& text) {
  return SphericalDirection(DegToRad(std::stod(text.theta)), DegToRad(std::stod(text.phi)));
}

// A schedule's direction made from whole or half degrees prints as those degrees (acos and the
// conversion alone print 29.999999999999996), and reads back to the same bits.
TEST(Angles, DirectionDegreesTextIsShortAndExactForScheduleAngles) {
  const double thetas[] = {0, 5, 15, 22.5, 30, 45, 60, 75, 85, 89.5};
  const double phis[] = {0, 5, 10, 90, 180, 270, 355};
  for (double theta : thetas) {
    for (double phi : phis) {
      const Vec3 w = SphericalDirection(DegToRad(theta), DegToRad(phi));
      const DegreesText text = DirectionDegreesText(w);
      EXPECT_EQ(text.theta, FormatNumberForTest(theta)) << theta << " " << phi;
      if (theta > 0) {
        EXPECT_EQ(text.phi, FormatNumberForTest(phi)) << theta << " " << phi;
      }
      EXPECT_EQ(ReadBackDegrees(text), w) << text.theta << " " << text.phi;
    }
  }
}

// Any other direction keeps the shortest round trip of its degree values: nothing is lost
// that the previous writer kept, and the direction reads back within a few units in the last
// place.
TEST(Angles, DirectionDegreesTextOfArbitraryDirectionsRoundTrips) {
  std::mt19937 rng(7);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 w = RandomUpperDirection(&rng);
    const DegreesText text = DirectionDegreesText(w);
    EXPECT_LE(text.theta.size(), 18u);
    EXPECT_NEAR((ReadBackDegrees(text) - w).norm(), 0.0, 1e-15);
  }
}

TEST(Angles, MirrorDirectionReflectsAboutTheNormal) {
  std::mt19937 rng(2);
  for (int k = 0; k < 100; ++k) {
    const Vec3 wi = RandomUpperDirection(&rng);
    const Vec3 mirror = MirrorDirection(wi);
    EXPECT_EQ(mirror.z(), wi.z());                            // same polar angle
    EXPECT_NEAR((wi + mirror).normalized().z(), 1.0, 1e-15);  // bisected by the normal
    EXPECT_NEAR(std::abs(AzimuthDifference(Phi(mirror), Phi(wi))), kPi, 1e-12);
    ExpectVecNear(MirrorDirection(mirror), wi, 0.0);
  }
}

TEST(AnglesHalfDiff, RoundTripOnRandomPairs) {
  std::mt19937 rng(1998);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 wi = RandomUpperDirection(&rng);
    const Vec3 wo = RandomUpperDirection(&rng);
    const HalfDiff hd = ToHalfDiff(wi, wo);
    // Ranges for directions above the surface.
    EXPECT_GE(hd.theta_h, 0.0);
    EXPECT_LE(hd.theta_h, 0.5 * kPi);
    EXPECT_GE(hd.theta_d, 0.0);
    EXPECT_LE(hd.theta_d, 0.5 * kPi);
    EXPECT_GE(hd.phi_h, 0.0);
    EXPECT_LT(hd.phi_h, 2.0 * kPi);
    EXPECT_GE(hd.phi_d, 0.0);
    EXPECT_LT(hd.phi_d, 2.0 * kPi);
    // theta_h is the half vector's polar angle; theta_d the angle between wi and it.
    const Vec3 half_vector = (wi + wo).normalized();
    EXPECT_NEAR(std::cos(hd.theta_h), half_vector.z(), 1e-12);
    EXPECT_NEAR(std::cos(hd.theta_d), wi.dot(half_vector), 1e-12);
    EXPECT_NEAR(std::cos(hd.theta_d), wo.dot(half_vector), 1e-12);
    Vec3 wi_back, wo_back;
    FromHalfDiff(hd, &wi_back, &wo_back);
    ExpectVecNear(wi_back, wi, 1e-10);
    ExpectVecNear(wo_back, wo, 1e-10);
  }
}

// Swapping wi and wo keeps the half vector and theta_d and turns the difference vector half
// way round about it: phi_d -> phi_d + π. Isotropic tables (MERL) rely on this symmetry.
TEST(AnglesHalfDiff, SwappingDirectionsShiftsPhiDByPi) {
  std::mt19937 rng(4);
  for (int k = 0; k < 500; ++k) {
    const Vec3 wi = RandomUpperDirection(&rng);
    const Vec3 wo = RandomUpperDirection(&rng);
    const HalfDiff forward = ToHalfDiff(wi, wo);
    const HalfDiff backward = ToHalfDiff(wo, wi);
    EXPECT_NEAR(backward.theta_h, forward.theta_h, 1e-12);
    EXPECT_NEAR(AzimuthDifference(backward.phi_h, forward.phi_h), 0.0, 1e-9);
    EXPECT_NEAR(backward.theta_d, forward.theta_d, 1e-12);
    EXPECT_NEAR(std::abs(AzimuthDifference(backward.phi_d, forward.phi_d)), kPi, 1e-9);
  }
}

// wo at the mirror direction of wi: the half vector is the normal, so theta_h = 0 and wi makes
// theta_i with it.
TEST(AnglesHalfDiff, SpecularConfigurationHasZeroThetaH) {
  for (double theta_i_deg : {5.0, 30.0, 60.0, 89.0}) {
    for (double phi_i : {0.0, 1.0, 4.0}) {
      const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), phi_i);
      const HalfDiff hd = ToHalfDiff(wi, MirrorDirection(wi));
      EXPECT_NEAR(hd.theta_h, 0.0, 1e-12);
      EXPECT_NEAR(hd.theta_d, DegToRad(theta_i_deg), 1e-12);
    }
  }
}

// wi = wo (retroreflection): the half vector is wi itself, theta_h = theta_i, theta_d = 0.
TEST(AnglesHalfDiff, RetroreflectionHasZeroThetaD) {
  for (double theta_i_deg : {0.0, 5.0, 30.0, 60.0, 89.0}) {
    const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 2.5);
    const HalfDiff hd = ToHalfDiff(wi, wi);
    EXPECT_NEAR(hd.theta_h, DegToRad(theta_i_deg), 1e-12);
    EXPECT_NEAR(hd.theta_d, 0.0, 1e-12);
  }
}

// By hand: wi = (sin 30°, 0, cos 30°), wo = (-sin 30°, 0, cos 30°). wi + wo = (0, 0, 2 cos 30°),
// so h = z: theta_h = 0, phi_h = 0 (on the axis), and the difference vector is wi unrotated:
// theta_d = 30°, phi_d = 0.
TEST(AnglesHalfDiff, HandComputedInPlaneMirror) {
  const double s = std::sin(DegToRad(30.0)), c = std::cos(DegToRad(30.0));
  const HalfDiff hd = ToHalfDiff(Vec3(s, 0, c), Vec3(-s, 0, c));
  EXPECT_NEAR(hd.theta_h, 0.0, 1e-15);
  EXPECT_NEAR(hd.phi_h, 0.0, 1e-15);
  EXPECT_NEAR(hd.theta_d, DegToRad(30.0), 1e-15);
  EXPECT_NEAR(hd.phi_d, 0.0, 1e-15);
}

// By hand: wi on the normal, wo = (theta, phi). h bisects them: theta_h = theta/2, phi_h = phi.
// Rotating wi = z by -phi_h about z leaves it; by -theta_h about y takes it to
// (-sin(theta/2), 0, cos(theta/2)): theta_d = theta/2 and phi_d = π (the rotation convention of
// MERL's reference code, std_coords_to_half_diff_coords).
TEST(AnglesHalfDiff, HandComputedNormalIncidence) {
  const double theta = DegToRad(50.0), phi = DegToRad(70.0);
  const HalfDiff hd = ToHalfDiff(Vec3(0, 0, 1), SphericalDirection(theta, phi));
  EXPECT_NEAR(hd.theta_h, 0.5 * theta, 1e-14);
  EXPECT_NEAR(hd.phi_h, phi, 1e-14);
  EXPECT_NEAR(hd.theta_d, 0.5 * theta, 1e-14);
  EXPECT_NEAR(hd.phi_d, kPi, 1e-14);
}

// FromHalfDiff on chosen angles gives unit directions that map back to the same angles.
TEST(AnglesHalfDiff, FromHalfDiffIsTheInverse) {
  for (double theta_h : {0.1, 0.4, 0.8}) {
    for (double theta_d : {0.05, 0.3, 0.6}) {
      for (double phi_d : {0.2, 1.7, 3.0, 5.5}) {
        const HalfDiff hd{theta_h, 2.0, theta_d, phi_d};
        Vec3 wi, wo;
        FromHalfDiff(hd, &wi, &wo);
        EXPECT_NEAR(wi.norm(), 1.0, 1e-14);
        EXPECT_NEAR(wo.norm(), 1.0, 1e-14);
        ASSERT_GT(wi.z(), 0.0);  // theta_h + theta_d < π/2 keeps both above the surface
        ASSERT_GT(wo.z(), 0.0);
        const HalfDiff back = ToHalfDiff(wi, wo);
        EXPECT_NEAR(back.theta_h, theta_h, 1e-12);
        EXPECT_NEAR(back.phi_h, 2.0, 1e-12);
        EXPECT_NEAR(back.theta_d, theta_d, 1e-12);
        EXPECT_NEAR(back.phi_d, phi_d, 1e-12);
      }
    }
  }
}

}  // namespace
}  // namespace brdf
