// Two-way acoustic ranging, what the USBL (sensors/usbl_sensor.h) and the LBL (sensors/lbl_sensor.h) share: an
// interrogator emits a ping; each responder (a vehicle's transponder, a seabed beacon) that hears it replies
// after its turnaround; the replies travel back. Everything in flight is part of the sensor's state, followed
// step by step through the acoustic channel (sensors/acoustic_channel.h; docs/ARCHITECTURE.md, "Acoustic
// positioning"):
//   1. the interrogation emitted at t_i from p_i reaches responder k at t_a, when its wavefront meets k's
//      track (linear over each step); k hears it when SL_i - TL - NL >= k's detection threshold and the path
//      is clear;
//   2. k replies at t_r = t_a + turnaround_k from where it is then;
//   3. the reply reaches the interrogator (moving too) at t_f, with SNR = SL_k - TL - NL + DI; a reply below
//      the interrogator's detection threshold, blocked, or from farther than its max_range is lost.
// A received reply reports t_i, t_f, the two-way time tau = t_f - t_i - turnaround_k, the range it gives
// (c_bar tau / 2, c_bar the harmonic-mean sound speed of the reply's path: the mean of the two legs when
// either end moves), where it came from and where it was received, and its SNR; the kind turns it into its
// measurement (a fix, a range) and applies its own acceptance (a USBL's cone).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hadal::sensors {

struct AcousticLink;
class AcousticChannel;
struct SampleContext;

// A responder as the interrogator sees it at the end of a step.
struct Responder {
  bool present = false;  // false: not interrogated (a vehicle without a transponder, the interrogator's own)
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // [m]
  int ray_body = -2;  // its ray body (occlusion); -2 (geometry::kNoHit): none, a beacon fixed in W
  double source_level_db = 185.0;
  double detection_threshold_db = 10.0;
  double turnaround_s = 0.0;
};

// The interrogator's acoustics.
struct InterrogatorAcoustics {
  double frequency_hz = 26000.0;
  double bandwidth_hz = 10000.0;
  double source_level_db = 190.0;
  double directivity_index_db = 0.0;
  double detection_threshold_db = 10.0;
  double max_range = 4000.0;  // [m]: no reply from farther; an exchange is given up after the two-way time of
                              // this range at 1400 m/s
};

struct ReceivedReply {
  int responder = -1;
  std::uint64_t interrogation = 0;
  double interrogation_time = 0.0;  // t_i [s]
  double reception_time = 0.0;      // t_f [s]
  double travel_time = 0.0;         // tau [s]
  Eigen::Vector3d p_Wreply = Eigen::Vector3d::Zero();     // where the responder replied from
  Eigen::Vector3d p_Wreceived = Eigen::Vector3d::Zero();  // the interrogator at t_f
  double range = 0.0;  // c_bar tau / 2 [m], before the kind's noise
  double snr_db = 0.0;
};

struct InterrogationState {
  struct Exchange {
    enum class Phase { kOutbound, kTurnaround, kInbound };
    Phase phase = Phase::kOutbound;
    int responder = -1;
    std::uint64_t interrogation = 0;
    double t_interrogation = 0.0;
    Eigen::Vector3d p_Winterrogation = Eigen::Vector3d::Zero();
    double t_reply = 0.0;                                // kTurnaround, kInbound
    Eigen::Vector3d p_Wreply = Eigen::Vector3d::Zero();  // kInbound
  };
  std::uint64_t interrogations = 0;
  std::vector<Exchange> exchanges;  // oldest first
  // The interrogator's and every responder's position at the end of the previous step.
  bool has_previous = false;
  double t_previous = 0.0;
  Eigen::Vector3d p_W_previous = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> responders_previous;
  // The ambient noise level in the interrogator's band [dB re 1 uPa^2], a constant of the run worked out on
  // first use (sensors/acoustic_channel.h).
  std::optional<double> noise_db;
};

// Whether the straight path between the interrogator at p_Wa and a responder on ray body `body` at p_Wb is
// blocked.
using Occluded = std::function<bool(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb, int body)>;
// AcousticChannel::occluded in the context's ray-cast world, from the sensor's own ray body; empty without a
// world.
Occluded occlusion_of(const SampleContext& context);

// An interrogation of every present responder from p_W at time t.
void interrogate(InterrogationState& state, double t, const Eigen::Vector3d& p_W, const std::vector<Responder>& responders);

// Follows everything in flight over the step that ends at t1 with the interrogator at p_W1 and the responders
// as given (the same list, in the same order, at every step); returns the replies received within the step,
// in the order of their exchanges. `occluded` may be empty (no ray-cast world: nothing blocks).
std::vector<ReceivedReply> advance_interrogations(InterrogationState& state, const AcousticChannel& channel,
                                                  const InterrogatorAcoustics& acoustics, double t1,
                                                  const Eigen::Vector3d& p_W1, const std::vector<Responder>& responders,
                                                  const Occluded& occluded);

// A link per interrogation on its way to a responder and per reply on its way back (sensor_kind.h), `self` and
// `names` (one per responder) naming the ends.
void interrogation_links(const InterrogationState& state, const Eigen::Vector3d& p_W, const std::string& self,
                         const std::vector<Responder>& responders, const std::vector<std::string>& names,
                         std::vector<AcousticLink>& out);

}  // namespace hadal::sensors
