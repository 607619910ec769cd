#include "hadal/physics/joint_servo.h"

#include <gtest/gtest.h>

namespace hadal::physics {
namespace {

// The law of joint_servo.h by hand, with numbers that tell the terms apart.
TEST(JointServoTest, PositionVelocityAndEffortCommandsFollowTheLaw) {
  JointServoSpec spec;
  spec.kp = 100.0;
  spec.kd = 10.0;
  // Position: kp (q* - q) - kd qd = 100 * 0.3 - 10 * 0.1 = 29.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.5, 0.2, 0.1), 29.0);
  // Velocity: kd (qd* - qd) = 10 * (2.5 - 0.1) = 24.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kVelocity, 2.5, 0.2, 0.1), 24.0);
  // Effort: the command itself.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kEffort, -7.5, 0.2, 0.1), -7.5);
}

TEST(JointServoTest, LimitsBoundTheRateAskedForAndTheEffort) {
  JointServoSpec spec;
  spec.kp = 100.0;
  spec.kd = 10.0;
  spec.velocity_limit = 1.0;
  spec.effort_limit = 20.0;
  // Position 0.3 rad away asks 100 * 0.3 / 10 = 3 rad/s, held to 1: 10 * (1 - 0.1) = 9; and the other way.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.5, 0.2, 0.1), 9.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, -0.1, 0.2, 0.1), -11.0);
  // Velocity 2.5 held to 1: 9; -2.5 held to -1: -11.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kVelocity, 2.5, 0.2, 0.1), 9.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kVelocity, -2.5, 0.2, 0.1), -11.0);
  // The effort limit, both signs, every mode.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kEffort, 35.0, 0.0, 0.0), 20.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kEffort, -35.0, 0.0, 0.0), -20.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kVelocity, 0.0, 0.0, 3.0), -20.0);
  // Without kd, position control is kp (q* - q) alone (no rate to bound), still within the effort limit.
  spec.kd = 0.0;
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.3, 0.2, 5.0), 10.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 1.2, 0.2, 5.0), 20.0);
}

// A moving position target (a trajectory's): its rate is fed forward, so a joint on the target at the
// target's rate feels no torque, and the rate asked for (the error's plus the target's) is what the
// velocity limit bounds.
TEST(JointServoTest, APositionTargetsRateIsFedForward) {
  JointServoSpec spec;
  spec.kp = 100.0;
  spec.kd = 10.0;
  // On the target at its rate: no torque.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.2, 0.2, 0.7, 0.7), 0.0);
  // kp (q* - q) + kd (qd* - qd) = 100 * 0.3 + 10 * (0.7 - 0.1) = 36.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.5, 0.2, 0.1, 0.7), 36.0);
  // Rate asked for 3 + 0.7 = 3.7, held to 2: 10 * (2 - 0.1) = 19.
  spec.velocity_limit = 2.0;
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kPosition, 0.5, 0.2, 0.1, 0.7), 19.0);
  // A velocity or effort command ignores it.
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kVelocity, 1.5, 0.2, 0.1, 0.7), 14.0);
  EXPECT_DOUBLE_EQ(joint_servo_torque(spec, JointCommandMode::kEffort, 1.5, 0.2, 0.1, 0.7), 1.5);
}

}  // namespace
}  // namespace hadal::physics
