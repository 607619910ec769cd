// consumer DOMAIN_ID: steps the lockstep hadald on that domain by 100 steps with the default AUV's main
// thruster on, then prints "sim_time=<s> x=<m>" from its odometry. Exit 1 on any client error.
#include <hadal_client/client.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  try {
    hadal::Client client(hadal::ClientOptions{std::atoi(argv[1]), "install_consumer"});
    if (!client.wait_for_server(20.0)) return 1;
    std::atomic<double> stamp{-1.0}, x{0.0};
    client.on_odometry("auv", [&](const hadal::Odometry& o) {
      x = o.p_WB[0];
      stamp = o.stamp;
    });
    client.wait_for_subscriptions(20.0);
    client.set_commands("auv", {0.8, 0.0, 0.0});
    const double t = client.step(500);  // 1 s
    for (int i = 0; i < 2000 && stamp.load() < t - 1e-9; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::printf("sim_time=%.3f x=%.6f\n", stamp.load(), x.load());
    return stamp.load() >= t - 1e-9 ? 0 : 1;
  } catch (const hadal::ClientError& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
