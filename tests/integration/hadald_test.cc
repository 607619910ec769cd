// End-to-end tests: a real hadald process, real Fast DDS, driven through libhadal_client.
// Each test reserves its own DDS domain (DomainLease), so ctest -j runs them side by side.
#include "hadal/record/topic_tap.h"
#include "hadal_client/client.h"
#include "lockstep_server.h"
#include "server_process.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <set>

namespace hadal::test {
namespace {


double dot_xy(const std::array<double, 3>& a, double x, double y) { return a[0] * x + a[1] * y; }

// Whether process `pid` is running: it exists and is not a zombie (a killed orphan stays one until reaped,
// and a container's first process may never reap it).
bool process_alive(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const auto close = line.rfind(") ");
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z' && line[close + 2] != 'X';
}

// A test that dies leaves no server behind (ServerProcess, PR_SET_PDEATHSIG): a child process starts a lockstep
// hadald and ends without its destructors, as a crashed test does; the server is gone within seconds, not
// left running on a domain whose lease died with the test.
TEST(HadaldTest, AServerDiesWithTheTestThatStartedIt) {
  DomainLease domain;
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(fds[0]);
    auto* server = new ServerProcess({source_path(kClientScenario), "--mode", "lockstep", "--domain-id",
                                      std::to_string(domain.id()), "--no-status-line"});
    const int pid = server->pid();
    const bool written = ::write(fds[1], &pid, sizeof pid) == static_cast<ssize_t>(sizeof pid);
    ::sleep(1);  // hadald is up and running by now
    ::_exit(written ? 0 : 1);  // no destructors: as a crash
  }
  ::close(fds[1]);
  int server_pid = -1;
  const bool got = ::read(fds[0], &server_pid, sizeof server_pid) == static_cast<ssize_t>(sizeof server_pid);
  ::close(fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(got && server_pid > 0);
  const bool gone = wait_until([&] { return !process_alive(server_pid); }, 20.0);
  if (!gone) ::kill(server_pid, SIGKILL);
  // The output files the child's ServerProcess would have removed.
  const std::string prefix = "hadald-test-" + std::to_string(child) + "-";
  for (const auto& entry : std::filesystem::directory_iterator("/tmp")) {
    if (entry.path().filename().string().rfind(prefix, 0) == 0) std::filesystem::remove(entry.path());
  }
  EXPECT_TRUE(gone) << "hadald " << server_pid << " outlived the process that started it";
}

TEST(HadaldTest, ForwardThrustMovesAlongBodyX) {
  LockstepServer s;
  SampleLog<Odometry> odometry;
  s.client().on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  s.connect();

  double t = s.client().step(10);  // one odometry period (50 Hz at 500 Hz), so a sample exists
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry start = odometry.at(t);
  for (int i = 0; i < 10; ++i) {  // 5 s, commands refreshed every 0.5 s (watchdog: 1 s)
    s.client().set_commands("auv", {0.8, 0.0, 0.0});
    t = s.client().step(250);
  }
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry end = odometry.at(t);

  // The scenario yaws the AUV 30 deg: body x in W is (cos 30, sin 30, 0).
  const double cx = std::cos(M_PI / 6.0), cy = std::sin(M_PI / 6.0);
  std::array<double, 3> d{end.p_WB[0] - start.p_WB[0], end.p_WB[1] - start.p_WB[1], end.p_WB[2] - start.p_WB[2]};
  const double along = dot_xy(d, cx, cy);
  const double across = dot_xy(d, -cy, cx);
  // 16.4 N of thrust against ~8 N s^2/m^2 of hull and fin drag (surface fluid model): ~1.4 m/s
  // after ~1.5 s, several metres in 5 s.
  EXPECT_GT(along, 3.0);
  EXPECT_LT(std::abs(across), 0.05 * along);
  EXPECT_GT(end.v_WB_B[0], 1.0);                          // moving forward in its own frame
  EXPECT_LT(std::abs(end.v_WB_B[1]), 0.05 * end.v_WB_B[0]);
  EXPECT_EQ(end.frame_id, "world");
  EXPECT_EQ(end.child_frame_id, "auv/base_link");
}

TEST(HadaldTest, PositiveBuoyancyWithoutThrustRises) {
  LockstepServer s;
  SampleLog<Odometry> odometry;
  s.client().on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  s.connect();
  double t = s.client().step(10);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry start = odometry.at(t);
  t = s.client().step(2500);  // 5 s, no command at all
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry end = odometry.at(t);
  // Net lift ~1.2 N (1025 kg/m^3 x 0.0294 m^3 displaced vs 30 kg) on 30 kg + ~29 kg of heave added
  // mass: ~0.02 m/s^2, ~0.25 m in 5 s before cross-flow drag limits it to ~0.1 m/s.
  EXPECT_GT(end.p_WB[2] - start.p_WB[2], 0.1);
  EXPECT_LT(std::abs(end.p_WB[0] - start.p_WB[0]), 0.05);
}

TEST(HadaldTest, WatchdogStopsThrustersAfterCommandTimeout) {
  LockstepServer s;
  SampleLog<ThrusterStates> thrusters;
  s.client().on_thruster_state("auv", [&](const ThrusterStates& x) { thrusters.add(x); });
  s.connect();

  s.client().set_commands("auv", {1.0, 0.0, 0.0});
  double t = s.client().step(250);  // 0.5 s after the command: still fresh
  ASSERT_TRUE(wait_until([&] { return thrusters.has(t); }, kWait));
  const ThrusterStates fresh = thrusters.at(t);
  EXPECT_EQ(fresh.setpoint[0], 1.0);
  EXPECT_EQ(fresh.command_source, 2);  // client
  EXPECT_GT(fresh.rotor_speed[0], 0.9 * 25.0);  // 1500 rpm = 25 rev/s, tau 0.1 s: > 99 % after 5 tau

  t = s.client().step(300);  // 1.1 s after the command: timed out 0.1 s ago
  ASSERT_TRUE(wait_until([&] { return thrusters.has(t); }, kWait));
  const ThrusterStates timed_out = thrusters.at(t);
  EXPECT_EQ(timed_out.setpoint[0], 0.0);
  EXPECT_LT(timed_out.rotor_speed[0], fresh.rotor_speed[0]);
  ASSERT_TRUE(wait_until(
      [&] {
        auto st = s.client().latest_status();
        return st && st->step_count >= 550 && !st->vehicle_faults.empty() && (st->vehicle_faults[0] & 1u);
      },
      kWait))
      << "status never reported FAULT_COMMAND_TIMEOUT";

  t = s.client().step(500);  // 10 rotor time constants later: stopped
  ASSERT_TRUE(wait_until([&] { return thrusters.has(t); }, kWait));
  EXPECT_LT(std::abs(thrusters.at(t).rotor_speed[0]), 0.01);
  EXPECT_EQ(thrusters.at(t).thrust[0], thrusters.at(t).thrust[0]);  // finite (not NaN)

  s.client().set_commands("auv", {0.5, 0.0, 0.0});  // a fresh command clears the fault
  t = s.client().step(10);
  ASSERT_TRUE(wait_until([&] { return thrusters.has(t); }, kWait));
  EXPECT_EQ(thrusters.at(t).setpoint[0], 0.5);
  ASSERT_TRUE(wait_until(
      [&] {
        auto st = s.client().latest_status();
        return st && st->step_count >= 1060 && (st->vehicle_faults[0] & 1u) == 0;
      },
      kWait));
}

std::map<double, Odometry> lockstep_run(std::uint64_t seed) {
  LockstepServer s(kClientScenario, {"--seed", std::to_string(seed)});
  SampleLog<Odometry> odometry;
  s.client().on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  s.connect();
  const std::vector<std::pair<std::vector<double>, std::uint32_t>> plan = {
      {{0.5, 0.2, -0.3}, 100}, {{0.9, -0.5, 0.4}, 137}, {{-0.2, 0.0, 1.0}, 250}, {{1.0, 1.0, -1.0}, 13},
      {{0.3, -0.1, 0.0}, 500}};
  double t = 0.0;
  for (const auto& [setpoints, steps] : plan) {
    s.client().set_commands("auv", setpoints);
    t = s.client().step(steps);
  }
  // 1000 steps at 500 Hz; odometry at 50 Hz: samples at 0.02 ... 2.00 s.
  EXPECT_NEAR(t, 2.0, 1e-12);
  EXPECT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  std::map<double, Odometry> samples = odometry.all();
  samples.erase(0.0);  // published before the client matched: may or may not have arrived
  return samples;
}

TEST(HadaldTest, LockstepRunsWithSameSeedAndCommandsAreBitIdentical) {
  const std::map<double, Odometry> a = lockstep_run(1234);
  const std::map<double, Odometry> b = lockstep_run(1234);
  ASSERT_EQ(a.size(), 100u);
  ASSERT_EQ(b.size(), 100u);
  auto ia = a.begin();
  auto ib = b.begin();
  for (; ia != a.end(); ++ia, ++ib) {
    ASSERT_EQ(ia->first, ib->first);
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(ia->second.p_WB[k], ib->second.p_WB[k]) << "t = " << ia->first;
      ASSERT_EQ(ia->second.v_WB_B[k], ib->second.v_WB_B[k]) << "t = " << ia->first;
      ASSERT_EQ(ia->second.w_WB_B[k], ib->second.w_WB_B[k]) << "t = " << ia->first;
    }
    for (int k = 0; k < 4; ++k) ASSERT_EQ(ia->second.q_WB[k], ib->second.q_WB[k]) << "t = " << ia->first;
  }
  // The commands did something (the comparison is not between two resting vehicles).
  EXPECT_GT(std::abs(a.rbegin()->second.p_WB[0]) + std::abs(a.rbegin()->second.p_WB[1]), 0.1);
}

// The C++ client's split request: send_step() returns at once, wait_reply() gives what step() would; the
// reply's ground truth equals the odometry sample at its sim time bit for bit, for the last reply waited for.
TEST(HadaldTest, SplitRequestsAndTheGroundTruthTheRepliesCarry) {
  LockstepServer s;
  SampleLog<Odometry> odometry;
  Client& client = s.client();
  client.on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  s.connect();
  EXPECT_THROW(client.reply_odometry("auv"), ClientError);  // no reply yet
  client.attach_commands("auv", {0.8, 0.3, -0.2});
  const std::uint64_t first = client.send_step(50);
  const std::uint64_t second = client.send_step(50);
  EXPECT_NEAR(client.wait_reply(first), 0.1, 1e-12);
  const Odometry at_first = client.reply_odometry("auv");
  EXPECT_NEAR(client.wait_reply(second), 0.2, 1e-12);
  EXPECT_THROW(client.wait_reply(second), ClientError);  // waited for once
  const Odometry at_second = client.reply_odometry("auv");
  for (const Odometry& carried : {at_first, at_second}) {
    ASSERT_TRUE(wait_until([&] { return odometry.has(carried.stamp); }, kWait));
    const Odometry published = odometry.at(carried.stamp);
    EXPECT_EQ(carried.stamp, published.stamp);
    EXPECT_EQ(carried.child_frame_id, "auv/base_link");
    EXPECT_EQ(carried.p_WB, published.p_WB);
    EXPECT_EQ(carried.q_WB, published.q_WB);
    EXPECT_EQ(carried.v_WB_B, published.v_WB_B);
    EXPECT_EQ(carried.w_WB_B, published.w_WB_B);
  }
  EXPECT_GT(at_second.v_WB_B[0], at_first.v_WB_B[0]);  // the thrust acts
  try {
    client.reply_odometry("ghost");
    ADD_FAILURE() << "no UnknownVehicle";
  } catch (const UnknownVehicle& e) {
    EXPECT_EQ(e.vehicle(), "ghost");
  }
  EXPECT_EQ(client.wait_reply(client.send_reset(ResetOptions{}, 0)), 0.0);
  EXPECT_EQ(client.reply_odometry("auv").v_WB_B, (std::array<double, 3>{0.0, 0.0, 0.0}));
}

// The default AUV's depth sensor (configs/vehicles/torpedo_auv.yaml: pressure, 10 Hz, 50 Pa of
// noise, 10 Pa resolution) over 2 s of lockstep: one sample per 0.1 s stamped with its sim time.
std::map<double, FluidPressure> pressure_run(std::uint64_t seed) {
  LockstepServer s(kClientScenario, {"--seed", std::to_string(seed)});
  SampleLog<FluidPressure> pressure;
  s.client().on_fluid_pressure("auv", "depth", [&](const FluidPressure& p) { pressure.add(p); });
  s.connect();
  const double t = s.client().step(1000);
  EXPECT_TRUE(wait_until([&] { return pressure.has(t); }, kWait));
  return pressure.all();
}

// Sensor streams over real DDS: stamps on the 10 Hz schedule, frame auv/depth, absolute pressure at
// ~50 m (sensor 5 cm above B) within 5 sigma of the noise plus the resolution plus 5 cm of water
// (503 Pa: the slightly buoyant AUV rises up to 1/2 (1.2 N / 59 kg) t^2 = 4 cm in 2 s); the same seed
// gives bit-identical samples, another seed other noise.
TEST(HadaldTest, PressureSensorStreamIsPublishedAndDeterministic) {
  const std::map<double, FluidPressure> a = pressure_run(99), b = pressure_run(99), c = pressure_run(100);
  ASSERT_EQ(a.size(), 20u);
  ASSERT_EQ(b.size(), 20u);
  ASSERT_EQ(c.size(), 20u);
  const double rho = 1025.0, g = 9.80665, p_expected = 101325.0 + rho * g * (50.0 - 0.05);
  int k = 1;
  bool any_difference = false;
  for (const auto& [stamp, sample] : a) {
    EXPECT_NEAR(stamp, 0.1 * k++, 1e-9);
    EXPECT_EQ(sample.frame_id, "auv/depth");
    EXPECT_NEAR(sample.pressure, p_expected, 5 * 50.0 + 10.0 + rho * g * 0.05);
    EXPECT_EQ(std::fmod(sample.pressure, 10.0), 0.0);
    EXPECT_NEAR(sample.variance, 50.0 * 50.0 + 100.0 / 12.0, 1e-9);
    EXPECT_EQ(sample.pressure, b.at(stamp).pressure);
    any_difference |= sample.pressure != c.at(stamp).pressure;
  }
  EXPECT_TRUE(any_difference);
}

// The default AUV's IMU over real DDS: 100 Hz samples stamped on schedule in frame auv/imu; at rest
// (no command; the AUV only drifts up at ~1e-2 m/s^2) the accelerometer reads ~+g along z within the
// HG1700-class noise and bias (1 mg bias, ~0.03 m/s^2 white noise at 100 Hz: 0.2 m/s^2 is > 5 sigma)
// and the gyros ~0 (0.01 deg/s vibration only with the propeller turning; noise ~4e-4 rad/s).
TEST(HadaldTest, ImuStreamIsPublished) {
  LockstepServer s;
  SampleLog<Imu> imu;
  s.client().on_imu("auv", "imu", [&](const Imu& m) { imu.add(m); });
  s.connect();
  const double t = s.client().step(500);  // 1 s
  ASSERT_TRUE(wait_until([&] { return imu.has(t); }, kWait));
  const std::map<double, Imu> samples = imu.all();
  ASSERT_GE(samples.size(), 99u);  // 0.01 .. 1.00 s (the first may precede the match)
  for (const auto& [stamp, m] : samples) {
    EXPECT_NEAR(stamp * 100.0, std::round(stamp * 100.0), 1e-6);
    EXPECT_EQ(m.frame_id, "auv/imu");
    EXPECT_NEAR(m.linear_acceleration[2], 9.80665, 0.2);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.angular_velocity[a], 0.0, 0.01);
  }
}

TEST(HadaldTest, MalformedCommandsAreRejectedAndTheServerKeepsRunning) {
  LockstepServer s;
  s.connect();
  auto expect_refused = [&](const std::string& vehicle, const std::vector<double>& setpoints,
                            const std::string& reason) {
    s.client().set_commands(vehicle, setpoints);
    try {
      s.client().step(10);
      ADD_FAILURE() << "step with bad setpoints was accepted: " << reason;
    } catch (const ClientError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  expect_refused("auv", {std::nan(""), 0.0, 0.0}, "setpoint[0] is NaN");
  expect_refused("auv", {0.5, 0.0}, "expected 3 setpoints");
  expect_refused("auv", {0.0, 1.5, 0.0}, "outside [-1, 1]");
  expect_refused("ghost", {0.1}, "unknown vehicle 'ghost'");
  // Each refusal is the error it is, with the server's reason.
  s.client().set_commands("auv", {0.5, 0.0});
  try {
    s.client().step(10);
    ADD_FAILURE() << "a wrong setpoint count was accepted";
  } catch (const CommandRejected& e) {
    EXPECT_EQ(e.reason(), "auv: expected 3 setpoints (main, heave, sway), got 2");
  }
  s.client().set_commands("ghost", {0.1});
  EXPECT_THROW(s.client().step(10), UnknownVehicle);

  s.client().set_commands("auv", {0.5, 0.0, 0.0});
  EXPECT_NEAR(s.client().step(10), 0.02, 1e-12);  // nothing was stepped by the refused requests
  EXPECT_TRUE(s.server().running());
  ASSERT_TRUE(wait_until(
      [&] {
        auto st = s.client().latest_status();
        return st && st->rejected_commands >= 6;
      },
      kWait));
  EXPECT_TRUE(wait_until([&] { return s.server().err().find("unknown vehicle 'ghost'") != std::string::npos; },
                         kWait))
      << s.server().err();
}

TEST(HadaldTest, MalformedScenarioExitsBeforeAnythingStarts) {
  const std::string path = "/tmp/hadald-test-bad-" + std::to_string(::getpid()) + ".yaml";
  {
    std::ofstream f(path);
    f << "world:\n  physics_rate_hz: -5\nvehicles: []\n";
  }
  ServerProcess server({path, "--mode", "fast", "--no-status-line"});
  EXPECT_EQ(server.wait(kWait), 1);
  const std::string err = server.err();
  EXPECT_NE(err.find(path + ":2:20: error: world.physics_rate_hz: "), std::string::npos) << err;
  EXPECT_NE(err.find(path + ":3:11: error: vehicles: "), std::string::npos) << err;
  EXPECT_NE(err.find("nothing started"), std::string::npos) << err;
  EXPECT_EQ(server.out(), "");
  std::remove(path.c_str());
}

// A scenario that names a file outside its tree and the asset roots is refused before the file is read,
// and nothing of the file is printed; --asset-root lets a directory in.
TEST(HadaldTest, AScenarioReachesOnlyItsTreeAndTheAssetRoots) {
  const std::string dir = "/tmp/hadald-test-roots-" + std::to_string(::getpid());
  std::filesystem::create_directories(dir + "/a");
  {
    std::ofstream(dir + "/a/s.yaml") << "world: {}\nvehicles:\n  - {name: x, include: /etc/passwd}\n";
    std::ofstream(dir + "/a/up.yaml") << "world: {}\nvehicles:\n  - {name: x, include: ../text.yaml}\n";
    std::ofstream(dir + "/text.yaml") << "root:x:0:0:root:/root:/bin/bash\n";
  }
  ServerProcess refused({dir + "/a/s.yaml", "--mode", "fast", "--no-status-line"});
  EXPECT_EQ(refused.wait(kWait), 1);
  EXPECT_NE(refused.err().find(dir + "/a/s.yaml:3:24: error: vehicles[0].include: '/etc/passwd' lies outside"),
            std::string::npos)
      << refused.err();
  EXPECT_EQ(refused.err().find("root:"), std::string::npos) << refused.err();
  // Let in by --asset-root: read, found not to be YAML keys and values, and still not quoted.
  ServerProcess let_in({dir + "/a/up.yaml", "--mode", "fast", "--no-status-line", "--asset-root", dir});
  EXPECT_EQ(let_in.wait(kWait), 1);
  EXPECT_NE(let_in.err().find(dir + "/a/../text.yaml:1:1: error: expected a map (got a document that is plain text"),
            std::string::npos)
      << let_in.err();
  EXPECT_EQ(let_in.err().find("root:"), std::string::npos) << let_in.err();
  std::filesystem::remove_all(dir);
}

TEST(HadaldTest, FastModeRunsTheDefaultScenarioForItsDurationAndSummarises) {
  DomainLease domain;
  ServerProcess server({source_path("configs/scenarios/default.yaml"), "--duration", "5", "--mode", "fast",
                        "--domain-id", std::to_string(domain.id()), "--no-status-line", "--discovery-wait", "0"});
  ASSERT_EQ(server.wait(120.0), 0) << server.err();
  const std::string out = server.out();
  // 5 s of sim time: clock at 100 Hz and odometry at 50 Hz, both including t = 0.
  EXPECT_NE(out.find("sim time 5.000 s"), std::string::npos) << out;
  EXPECT_NE(out.find("2500 steps"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/clock 501\n"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/auv/odometry 251\n"), std::string::npos) << out;
  EXPECT_NE(out.find("auv: distance travelled "), std::string::npos) << out;
  EXPECT_NE(out.find("altitude 4."), std::string::npos) << out;  // ~4 m over the generated seabed
  // The camera's frames at 10 Hz, each published 0.2 s after its snapshot: those taken at 0.1 .. 4.8 s
  // (the ones taken at 4.9 and 5 s are due after the end) on three topics.
  EXPECT_NE(out.find("rt/auv/camera/image_raw 48\n"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/auv/camera/depth 48\n"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/auv/camera/camera_info 48\n"), std::string::npos) << out;
  // Nobody read the wall-paced side channels, so the server never wrote them (dds/monitor.h, image_preview.h).
  EXPECT_NE(out.find("rt/hadal/monitor 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/auv/camera/preview 0\n"), std::string::npos) << out;
}

// A scenario's objects are vehicles without actuators: the push core publishes its odometry and no actuator
// state, while the ROV publishes its thrusters', its joints and its wrist's wrench (configs/scenarios/
// rov_intervention.yaml, 0.1 s in fast mode: 6 odometry samples at 50 Hz, t = 0 included).
TEST(HadaldTest, AnObjectPublishesItsOdometryAndNoActuatorState) {
  DomainLease domain;
  ServerProcess server({source_path("configs/scenarios/rov_intervention.yaml"), "--duration", "0.1", "--mode", "fast",
                        "--domain-id", std::to_string(domain.id()), "--no-status-line", "--discovery-wait", "0"});
  ASSERT_EQ(server.wait(120.0), 0) << server.err();
  const std::string out = server.out();
  EXPECT_NE(out.find("rt/core/odometry 6\n"), std::string::npos) << out;
  EXPECT_EQ(out.find("rt/core/thrusters/state"), std::string::npos) << out;
  EXPECT_EQ(out.find("rt/core/joint_states"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/rov/thrusters/state"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/rov/joint_states 6\n"), std::string::npos) << out;
  EXPECT_NE(out.find("rt/rov/wrist_ft 10\n"), std::string::npos) << out;  // 100 Hz, from the first step
}

TEST(HadaldTest, SummaryAltitudeIsARayCastToTheSeabed) {
  // The client scenario has a plane seabed at z = -100 and the AUV starts at z = -50 with no command:
  // it only rises (positive buoyancy). The summary's altitude comes from a ray cast straight down
  // through the ray-cast service, so altitude = 50 m + the vertical displacement; both are printed to
  // 1 mm, hence the 2 mm tolerance.
  DomainLease domain;
  ServerProcess server({source_path(kClientScenario), "--duration", "3", "--mode", "fast", "--domain-id",
                        std::to_string(domain.id()), "--no-status-line", "--discovery-wait", "0"});
  ASSERT_EQ(server.wait(120.0), 0) << server.err();
  const std::string out = server.out();
  double travelled = 0.0, net = 0.0, altitude = 0.0;
  const auto at = out.find("auv: distance travelled");
  ASSERT_NE(at, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + at, "auv: distance travelled %lf m (net displacement %lf m), altitude %lf m",
                        &travelled, &net, &altitude),
            3)
      << out;
  EXPECT_GT(net, 0.05);
  EXPECT_NEAR(altitude, 50.0 + net, 0.002);
}

// The summary counts from the last lockstep reset, as its sim time and steps do: the AUV (start
// (0, 0, -50)) is driven for 1 s, then reset 30 m north of where it got to with no step after it, so
// from the reset it has moved exactly nothing. Counted from the scenario's start the net displacement
// would be ~30 m and the distance the 1 s run's path.
TEST(HadaldTest, SummaryAfterAResetCountsFromTheResetPose) {
  LockstepServer s;
  Client& client = s.client();
  s.connect();
  client.attach_commands("auv", {0.8, 0.3, -0.2});
  client.wait_reply(client.send_step(500));
  const Odometry driven = client.reply_odometry("auv");
  ASSERT_GT(std::hypot(driven.p_WB[0], driven.p_WB[1], driven.p_WB[2] + 50.0), 0.01);  // it did move
  ResetOptions reset;
  Pose pose;
  pose.p_WB = {driven.p_WB[0], driven.p_WB[1] + 30.0, driven.p_WB[2]};
  reset.poses = {{"auv", pose}};
  EXPECT_EQ(client.wait_reply(client.send_reset(reset, 0)), 0.0);
  ASSERT_EQ(s.server().stop(SIGINT), 0) << s.server().err();
  const std::string out = s.server().out();
  double travelled = -1.0, net = -1.0;
  const auto at = out.find("auv: distance travelled");
  ASSERT_NE(at, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + at, "auv: distance travelled %lf m (net displacement %lf m)", &travelled,
                        &net),
            2)
      << out;
  EXPECT_EQ(travelled, 0.0) << out;  // printed to 1 mm: exactly "0.000"
  EXPECT_EQ(net, 0.0) << out;
  EXPECT_NE(out.find("resets: 1 (sim time, steps and distances since the last)"), std::string::npos) << out;
}

// A crawler's tracks sink into the soil: its origin (on the tracks' ground line) ends below the seabed's
// surface, which the summary reports as a negative altitude (the ray straight up meets the seabed): the
// scenario's 3.9 cm of sinkage, to the 1 mm printed and 3 % of the closed form.
TEST(HadaldTest, SummaryAltitudeOfASunkCrawlerIsNegative) {
  DomainLease domain;
  ServerProcess server({source_path("configs/scenarios/crawler.yaml"), "--duration", "2", "--mode", "fast",
                        "--domain-id", std::to_string(domain.id()), "--no-status-line", "--discovery-wait", "0"});
  ASSERT_EQ(server.wait(120.0), 0) << server.err();
  const std::string out = server.out();
  double travelled = 0.0, net = 0.0, altitude = 0.0;
  const auto at = out.find("crawler: distance travelled");
  ASSERT_NE(at, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + at,
                        "crawler: distance travelled %lf m (net displacement %lf m), altitude %lf m",
                        &travelled, &net, &altitude),
            3)
      << out;
  EXPECT_NEAR(altitude, -0.039, 0.0012 + 0.0005) << out;
  EXPECT_NE(out.find("(its origin below the seabed's surface)"), std::string::npos) << out;
}

std::set<std::string> fastdds_shm_files() {
  std::set<std::string> names;
  if (DIR* dir = ::opendir("/dev/shm")) {
    while (dirent* e = ::readdir(dir)) {
      const std::string name = e->d_name;
      if (name.rfind("fastrtps_", 0) == 0 || name.rfind("sem.fastrtps_", 0) == 0) names.insert(name);
    }
    ::closedir(dir);
  }
  return names;
}

// Real time never waits for the renderer: a camera whose frames cannot be ready by their due step
// (1600 x 1200 at 20 Hz, no latency: due 2 ms after their snapshot, where a frame takes a good fraction
// of a second on any CPU) has them dropped and counted in rt/hadal/status; the server keeps stepping
// in real time and summarises the count.
TEST(HadaldTest, LateCameraFramesAreDroppedAndCountedInTheStatus) {
  const std::string path = "/tmp/hadald-test-late-camera-" + std::to_string(::getpid()) + ".yaml";
  {
    std::ofstream f(path);
    f << "world:\n  physics_rate_hz: 500\n  seabed: {type: plane, z: -100.0}\n"
         "vehicles:\n  - name: auv\n    include: " << source_path("configs/vehicles/torpedo_auv.yaml") << "\n"
         "    initial_pose: {position: [0.0, 0.0, -96.0]}\n"
         "    sensors:\n      - {name: camera, type: camera, link: hull, rate_hz: 20, latency_s: 0.0,"
         " width: 1600, height: 1200, pose: {rpy_deg: [0.0, 30.0, 0.0]}}\n";
  }
  DomainLease domain;
  ServerProcess server({path, "--mode", "realtime", "--domain-id", std::to_string(domain.id())});
  Client client(ClientOptions{domain.id(), "hadald_test"});
  ASSERT_TRUE(client.wait_for_server(kWait)) << server.err();
  ASSERT_TRUE(wait_until(
      [&] {
        auto st = client.latest_status();
        return st && st->dropped_captures >= 3 && st->sim_time > 0.5;
      },
      kWait))
      << server.err();
  EXPECT_TRUE(server.running());
  // Said at the start: a zero latency publishes nothing in real time (app::mode_warnings).
  EXPECT_NE(server.err().find("hadald: warning: auv/camera: latency_s 0 s is less than one physics step"),
            std::string::npos)
      << server.err();
  EXPECT_EQ(server.stop(SIGTERM), 0) << server.err();
  const std::string out = server.out();
  const auto at = out.find("late captures dropped: ");
  ASSERT_NE(at, std::string::npos) << out;
  EXPECT_GE(std::atoi(out.c_str() + at + 23), 3) << out;
  std::remove(path.c_str());
}

// Captured sensors with their default latency (one sample period) publish in real time: each of the five
// captured kinds in tests/integration/scenarios/captured_realtime.yaml (small, 5 Hz, no latency_s) has
// samples on its topic within a few seconds. With latency 0, as before, real time published none of them.
// Counts only that samples arrive: how many captures the workers finish in time depends on the machine.
TEST(HadaldTest, EveryCapturedKindPublishesInRealTimeWithItsDefaultLatency) {
  DomainLease domain;
  ServerProcess server({source_path("tests/integration/scenarios/captured_realtime.yaml"), "--mode", "realtime",
                        "--domain-id", std::to_string(domain.id()), "--no-status-line"});
  const std::vector<std::string> topics = {"rt/auv/profiler", "rt/auv/camera/image_raw", "rt/auv/fls",
                                           "rt/auv/multibeam", "rt/auv/sidescan/port"};
  std::mutex mutex;  // before the tap, whose callback uses them: destroyed after it
  std::map<std::string, int> samples;
  record::TopicTap tap(domain.id(), "captured_realtime_test");
  ASSERT_TRUE(tap.discover(kWait)) << server.err();
  ASSERT_TRUE(tap.subscribe(
      [&](const record::TappedSample& sample) {
        std::lock_guard<std::mutex> lock(mutex);
        ++samples[sample.topic];
      },
      kWait, false,
      [&](const std::string& topic, const record::TappedWriter&) {
        return std::find(topics.begin(), topics.end(), topic) != topics.end();
      }))
      << server.err();
  const auto all_published = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    for (const std::string& topic : topics) {
      if (samples[topic] < 2) return false;
    }
    return true;
  };
  const bool published = wait_until(all_published, kWait);
  std::map<std::string, int> got;
  {
    std::lock_guard<std::mutex> lock(mutex);
    got = samples;
  }
  for (const std::string& topic : topics) EXPECT_GE(got[topic], 2) << topic << "; stderr:\n" << server.err();
  EXPECT_TRUE(published);
  EXPECT_EQ(server.err().find("latency_s"), std::string::npos) << server.err();  // no zero-latency warning
  EXPECT_TRUE(server.running());
}

// Two hadald on one DDS domain: each says so on stderr, naming the other process (its pid and scenario), and
// both keep running (DDS allows it; a client there would get both servers' topics).
TEST(HadaldTest, ASecondServerOnTheDomainIsNamedLoudly) {
  DomainLease domain;
  ServerProcess first({source_path(kClientScenario), "--mode", "lockstep", "--domain-id", std::to_string(domain.id()),
                       "--no-status-line"});
  Client client(ClientOptions{domain.id(), "hadald_test"});
  ASSERT_TRUE(client.wait_for_server(kWait)) << first.err();
  ServerProcess second({source_path("tests/integration/scenarios/sonar.yaml"), "--mode", "lockstep", "--domain-id",
                        std::to_string(domain.id()), "--no-status-line"});
  const std::string about_first = "hadald: warning: another hadald is on DDS domain " + std::to_string(domain.id()) +
                                  " (pid " + std::to_string(first.pid()) + " on ";
  const std::string about_second = "(pid " + std::to_string(second.pid()) + " on ";
  ASSERT_TRUE(wait_until([&] { return second.err().find(about_first) != std::string::npos; }, kWait))
      << second.err();
  EXPECT_NE(second.err().find("scenarios/auv_client.yaml, mode lockstep): clients there see both servers' topics"),
            std::string::npos)
      << second.err();
  ASSERT_TRUE(wait_until([&] { return first.err().find(about_second) != std::string::npos; }, kWait)) << first.err();
  EXPECT_NE(first.err().find("scenarios/sonar.yaml"), std::string::npos) << first.err();
  EXPECT_TRUE(first.running());
  EXPECT_TRUE(second.running());
}

TEST(HadaldTest, SigtermStopsARealtimeServerCleanly) {
  DomainLease domain;
  const std::set<std::string> before = fastdds_shm_files();
  {
    ServerProcess server({source_path("configs/scenarios/default.yaml"), "--mode", "realtime", "--domain-id",
                          std::to_string(domain.id())});
    {
      Client client(ClientOptions{domain.id(), "hadald_test"});
      ASSERT_TRUE(client.wait_for_server(kWait)) << server.err();
      ASSERT_TRUE(wait_until(
          [&] {
            auto st = client.latest_status();
            return st && st->sim_time > 1.0;
          },
          kWait));
    }
    EXPECT_EQ(server.stop(SIGTERM), 0) << server.err();
    EXPECT_NE(server.out().find("hadald summary"), std::string::npos);
    EXPECT_NE(server.err().find("RTF"), std::string::npos);  // the per-second status line
  }
  // Shared-memory port segments of this test's domain (ports 7400 + 250 d ... + 249, e.g.
  // fastrtps_port21660, ..._el, sem.fastrtps_port21660_mutex) must be gone once both processes have
  // exited. Segments of other domains belong to concurrently running tests and are not looked at.
  const int base = 7400 + 250 * domain.id();
  std::set<std::string> leftovers;
  for (const auto& name : fastdds_shm_files()) {
    const auto at = name.find("fastrtps_port");
    if (at == std::string::npos || before.count(name) != 0) continue;
    const int port = std::atoi(name.c_str() + at + 13);
    if (port >= base && port < base + 250) leftovers.insert(name);
  }
  EXPECT_TRUE(leftovers.empty()) << "left in /dev/shm: " << *leftovers.begin();
}

}  // namespace
}  // namespace hadal::test
