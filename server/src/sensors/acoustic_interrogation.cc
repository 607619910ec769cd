#include "hadal/sensors/acoustic_interrogation.h"

#include <algorithm>
#include <optional>

#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal::sensors {

Occluded occlusion_of(const SampleContext& context) {
  if (context.rays == nullptr) return {};
  return [&context](const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb, int body) {
    return AcousticChannel::occluded(*context.rays, context.state, p_Wa, context.own_ray_body(), p_Wb, body);
  };
}

void interrogate(InterrogationState& state, double t, const Eigen::Vector3d& p_W,
                 const std::vector<Responder>& responders) {
  const std::uint64_t index = state.interrogations++;
  for (std::size_t k = 0; k < responders.size(); ++k) {
    if (!responders[k].present) continue;
    InterrogationState::Exchange& exchange = state.exchanges.emplace_back();
    exchange.responder = static_cast<int>(k);
    exchange.interrogation = index;
    exchange.t_interrogation = t;
    exchange.p_Winterrogation = p_W;
  }
}

std::vector<ReceivedReply> advance_interrogations(InterrogationState& state, const AcousticChannel& channel,
                                                  const InterrogatorAcoustics& acoustics, double t1,
                                                  const Eigen::Vector3d& p_W1, const std::vector<Responder>& responders,
                                                  const Occluded& occluded) {
  using Phase = InterrogationState::Exchange::Phase;
  std::vector<ReceivedReply> received;
  const std::size_t n = responders.size();
  // The positions the next step starts from (in place: no allocation at a step).
  const auto remember = [&] {
    state.t_previous = t1;
    state.p_W_previous = p_W1;
    state.responders_previous.resize(n);
    for (std::size_t k = 0; k < n; ++k) state.responders_previous[k] = responders[k].p_W;
  };
  if (!state.has_previous || !(t1 > state.t_previous) || state.responders_previous.size() != n ||
      state.exchanges.empty()) {
    state.has_previous = true;
    remember();
    return received;
  }
  const double t0 = state.t_previous;
  const Eigen::Vector3d p_W0 = state.p_W_previous;
  const auto between = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) -> Eigen::Vector3d {
    return a + (t - t0) / (t1 - t0) * (b - a);
  };
  const auto clear = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Responder& r) {
    return !occluded || !occluded(a, b, r.ray_body);
  };
  // The band's noise (a 65-point integral, ~10 us; a constant of the run): worked out at the first arrival.
  const auto noise_db = [&] {
    if (!state.noise_db) state.noise_db = channel.noise_level_db(acoustics.frequency_hz, acoustics.bandwidth_hz);
    return *state.noise_db;
  };
  // An exchange older than this has lost its reply (the two-way time of max_range at 1400 m/s, the longest
  // turnaround included).
  const double give_up_s = 2.0 * acoustics.max_range / 1400.0 + 11.0;
  std::size_t kept = 0;  // the exchanges still in flight are moved to the front
  for (std::size_t e = 0; e < state.exchanges.size(); ++e) {
    InterrogationState::Exchange& exchange = state.exchanges[e];
    const std::size_t k = static_cast<std::size_t>(exchange.responder);
    const Responder& responder = responders[k];
    const Eigen::Vector3d& p_k0 = state.responders_previous[k];
    const Eigen::Vector3d& p_k1 = responder.p_W;
    bool done = !responder.present;
    if (!done && exchange.phase == Phase::kOutbound) {
      const std::optional<double> heard =
          channel.arrival(exchange.t_interrogation, exchange.p_Winterrogation, t0, p_k0, t1, p_k1);
      if (heard) {
        const Eigen::Vector3d p = between(p_k0, p_k1, *heard);
        const double snr = acoustics.source_level_db -
                           channel.transmission_loss_db(exchange.p_Winterrogation, p, acoustics.frequency_hz) -
                           noise_db();
        if (snr >= responder.detection_threshold_db && clear(exchange.p_Winterrogation, p, responder)) {
          exchange.phase = Phase::kTurnaround;
          exchange.t_reply = *heard + responder.turnaround_s;
        } else {
          done = true;
        }
      }
    }
    if (!done && exchange.phase == Phase::kTurnaround && exchange.t_reply <= t1) {
      exchange.p_Wreply = between(p_k0, p_k1, std::max(exchange.t_reply, t0));
      exchange.phase = Phase::kInbound;
    }
    if (!done && exchange.phase == Phase::kInbound) {
      const std::optional<double> arrived = channel.arrival(exchange.t_reply, exchange.p_Wreply, t0, p_W0, t1, p_W1);
      if (arrived) {
        done = true;  // received or lost
        const Eigen::Vector3d p_Wf = between(p_W0, p_W1, *arrived);
        const double snr = responder.source_level_db -
                           channel.transmission_loss_db(exchange.p_Wreply, p_Wf, acoustics.frequency_hz) - noise_db() +
                           acoustics.directivity_index_db;
        if (snr >= acoustics.detection_threshold_db && (exchange.p_Wreply - p_Wf).norm() <= acoustics.max_range &&
            clear(p_Wf, exchange.p_Wreply, responder)) {
          ReceivedReply& reply = received.emplace_back();
          reply.responder = exchange.responder;
          reply.interrogation = exchange.interrogation;
          reply.interrogation_time = exchange.t_interrogation;
          reply.reception_time = *arrived;
          reply.travel_time = *arrived - exchange.t_interrogation - responder.turnaround_s;
          reply.p_Wreply = exchange.p_Wreply;
          reply.p_Wreceived = p_Wf;
          reply.range = channel.mean_sound_speed(exchange.p_Wreply, p_Wf) * reply.travel_time / 2.0;
          reply.snr_db = snr;
        }
      }
    }
    if (!done && t1 - exchange.t_interrogation > give_up_s) done = true;
    if (!done) state.exchanges[kept++] = exchange;
  }
  state.exchanges.resize(kept);
  remember();
  return received;
}

void interrogation_links(const InterrogationState& state, const Eigen::Vector3d& p_W, const std::string& self,
                         const std::vector<Responder>& responders, const std::vector<std::string>& names,
                         std::vector<AcousticLink>& out) {
  using Phase = InterrogationState::Exchange::Phase;
  for (const InterrogationState::Exchange& exchange : state.exchanges) {
    const auto k = static_cast<std::size_t>(exchange.responder);
    if (exchange.phase == Phase::kTurnaround || k >= responders.size() || k >= names.size()) continue;
    AcousticLink& link = out.emplace_back();
    if (exchange.phase == Phase::kOutbound) {
      link.kind = AcousticLink::Kind::kInterrogation;
      link.source = self;
      link.target = names[k];
      link.p_Wemit = exchange.p_Winterrogation;
      link.p_Wtarget = responders[k].p_W;
      link.emit_time = exchange.t_interrogation;
    } else {
      link.kind = AcousticLink::Kind::kReply;
      link.source = names[k];
      link.target = self;
      link.p_Wemit = exchange.p_Wreply;
      link.p_Wtarget = p_W;
      link.emit_time = exchange.t_reply;
    }
  }
}

}  // namespace hadal::sensors
