// Drives the default scenario's AUV forward and prints its odometry.
//   build/bin/hadald configs/scenarios/default.yaml &      # any mode but lockstep
//   build/bin/drive_auv [--vehicle auv] [--seconds 10] [--thrust 0.6] [--domain-id 0]
#include "hadal_client/client.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

int main(int argc, char** argv) {
  std::string vehicle = "auv";
  double seconds = 10.0, thrust = 0.6;
  std::optional<int> domain_id;  // unset: $ROS_DOMAIN_ID, else 0 (hadal::resolve_domain_id), as every Hadal tool
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--vehicle") vehicle = argv[i + 1];
    else if (key == "--seconds") seconds = std::atof(argv[i + 1]);
    else if (key == "--thrust") thrust = std::atof(argv[i + 1]);
    else if (key == "--domain-id") domain_id = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: drive_auv [--vehicle NAME] [--seconds S] [--thrust X] [--domain-id N]\n");
      return 2;
    }
  }
  hadal::Client client({domain_id, "drive_auv"});
  if (!client.wait_for_server(10.0)) {
    std::fprintf(stderr, "drive_auv: no hadald on DDS domain %d\n", hadal::resolve_domain_id(domain_id));
    return 1;
  }
  std::mutex print_mutex;
  double last_print = -1.0;
  client.on_odometry(vehicle, [&](const hadal::Odometry& o) {
    std::lock_guard<std::mutex> lock(print_mutex);
    if (o.stamp - last_print < 0.5) return;
    last_print = o.stamp;
    std::printf("t %8.3f s  p_WB [%8.3f %8.3f %8.3f] m  v_WB_B [%6.3f %6.3f %6.3f] m/s\n", o.stamp, o.p_WB[0],
                o.p_WB[1], o.p_WB[2], o.v_WB_B[0], o.v_WB_B[1], o.v_WB_B[2]);
    std::fflush(stdout);
  });
  // The thruster count (and order) comes from the server's thruster state topic.
  std::atomic<std::size_t> thrusters{0};
  client.on_thruster_state(vehicle, [&](const hadal::ThrusterStates& s) { thrusters = s.names.size(); });
  for (int i = 0; i < 200 && thrusters == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (thrusters == 0) {
    std::fprintf(stderr, "drive_auv: no thruster state for vehicle '%s'\n", vehicle.c_str());
    return 1;
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    std::vector<double> setpoints(thrusters.load(), 0.0);
    setpoints[0] = thrust;
    client.set_commands(vehicle, setpoints);  // refreshed at 10 Hz: the server's watchdog wants fresh commands
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  client.set_commands(vehicle, std::vector<double>(thrusters.load(), 0.0));
  return 0;
}
