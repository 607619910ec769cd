// One ping of a sonar by ray casting (docs/ARCHITECTURE.md, "Sonars"): the acoustic counterpart of
// render/frame.h, shared by the forward-looking, multibeam and side-scan sonar kinds.
//
// Geometry. A sonar has beams fixed in its frame S; beam k has a unit axis a_k, a unit direction u_k
// across it (the fan's direction for a fan of beams) and v_k = a_k x u_k. Its rays leave S's origin in
//   d_S(a, e) = cos e (cos a a_k + sin a u_k) + sin e v_k,
// a the offset along u and e along v [rad], on a stratified grid over |a| <= w_u / 2 (the -3 dB width) and
// |e| <= s_v / 2 (the sampled extent: by default w_v; wider where the pattern's tail matters, as a
// side-scan's reaching down to nadir, where the pattern W weights the rays): rays_u x rays_v cells, one ray
// per cell where the grid's lines cross, each line at a seeded place within its cell (at the cell's centre
// without jitter); a ray stands for the solid angle dOmega = cos e da de of its cell.
// Beam pattern: the two-way (transmit x receive) intensity pattern's main lobe as a Gaussian,
//   W(a, e) = 2^-((2 a / w_u)^2 + (2 e / w_v)^2)      (-3 dB at the half widths)
// Side lobes are not modelled; neither are multiple reflections or refraction (straight rays).
//
// Echo of one ray (the sonar equation per scattering patch), hitting a surface at range r with incidence
// angle theta (between the ray and the surface normal):
//   Lambert's law        sigma(theta) = mu cos^2 theta      (backscattering per unit area and steradian;
//                                                            mu, linear, from the hit's material)
//   patch area           dA = r^2 dOmega / cos theta
//   transmission loss    TL(r) = N log10 r + alpha r  [dB] one way (N = 20: spherical spreading; alpha the
//                        absorption at the sonar's frequency, physics/seawater.h)
//   echo intensity       I = SL W mu cos theta dOmega r^2 10^(-2 TL(r) / 10)   [uPa^2 at the receiver]
// with SL = 10^(source_level_db / 10) [uPa^2 at 1 m]. Summed over a point-like target's surface this is its
// target strength times 10^(-2 TL / 10): a sphere of radius rho returns SL mu (2 pi rho^2 / 3) 10^(-2 TL(R)/10).
// A ray's first hit is its only echo, so what lies behind a surface stays dark: acoustic shadows.
// The echo arrives over the ranges its patch spans, r +- w / 2, and is shared among the bins of that interval
// in proportion to their overlap (so bins stay filled where rays are sparse in range: far, grazing seabed).
// Along each of the grid's directions w reaches the farther neighbouring ray that hit: its range difference
// where the surface runs on to it (near a curved object's limb that is less than the tangent plane says, on a
// receding seabed more), but where that difference exceeds kFootprintJump times the tangent plane's (an edge:
// the neighbour lies beyond a jump) the plane's, the angle to the neighbour's line times r |n . dd| / |n . d|
// (dd the ray direction's derivative); with no neighbour that hit, the plane over the cell's own angle; at
// most kMaxFootprintBins bins in all.
// Echoes are summed per (beam, range bin); the loss is interpolated linearly in range between bin edges
// (relative error below (bin / r)^2).
//
// Receiver: each bin's echo as a complex amplitude sqrt(I) s plus noise n: s is Rayleigh speckle (complex
// Gaussian, unit mean power; 1 without speckle), n complex Gaussian of mean power 10^(noise_level_db / 10)
// (0 without receiver noise); the received intensity |sqrt(I) s + n|^2 is then multiplied by the time-varied
// gain TVG(r) = 10^((N_tvg log10 r + 2 alpha r) / 10) at the bin's centre (the 2 alpha r term only with
// tvg_absorption). With speckle, |.|^2 is exponential with mean I + noise. Streams: keyed by the sonar's
// key, the ping and the beam, so a ping is bit-identical on any number of threads.
//
// Bottom detection (multibeam), on the beam's profile smoothed over kDetectionSmoothingBins bins (which
// fills speckle's dips and bins between rays): its peak must exceed the TVG-scaled noise by min_snr_db; the
// bins around it down to window_db below the peak are its echo. Amplitude detection: the echo's intensity-weighted
// mean range. Phase detection (a split-aperture sonar's zero crossing): where the echo-weighted mean
// offset a of each bin's rays crosses 0, i.e. where the seabed crosses the beam's axis, interpolated
// between bin centres; used when the echo spans at least kPhaseMinBins bins (oblique beams, whose long
// footprints blur the amplitude centroid). The phase is noise-free here (its noise is not modelled).
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "hadal/core/parallel_for.h"

namespace hadal::geometry {
class EmbreeScene;
struct RayHits;
}  // namespace hadal::geometry

namespace hadal::render {

struct SonarBeam {
  Eigen::Vector3d axis_S = Eigen::Vector3d::UnitX();  // unit
  Eigen::Vector3d u_S = Eigen::Vector3d::UnitY();     // unit, perpendicular to axis_S
  double width_u_rad = 0.0175;                        // -3 dB full width along u
  double width_v_rad = 0.35;                          // -3 dB full width along v
  double sampled_v_rad = 0.0;                         // the rays' full extent along v; 0: width_v_rad

  double extent_v() const { return sampled_v_rad > 0.0 ? sampled_v_rad : width_v_rad; }

  Eigen::Vector3d v_S() const { return axis_S.cross(u_S); }
  // d_S(a, e) above, unit.
  Eigen::Vector3d direction_S(double a, double e) const;
  // W(a, e) above.
  double pattern(double a, double e) const;
};

// A fan of `count` beams over `fov` [rad] in S's x-y plane: beam k's axis at phi_k = -fov/2 + (k + 1/2) fov /
// count about z_S from x_S, u along the fan (towards y_S at phi = 0), v = z_S; each width_u wide in the fan
// and width_v across it.
std::vector<SonarBeam> fan_beams(int count, double fov, double width_u, double width_v);

// cos and sin of c + delta from cos c and sin c, for |delta| <= kSmallAngleRad: the angle-sum identities with
// cos delta and sin delta by their Taylor series to delta^6 and delta^7 (remainders delta^8 / 8! and delta^9 / 9!,
// below 2.5e-21 and 2.8e-24 at 0.01 rad, so double rounding decides). ping() takes a jittered grid line's cos and sin
// from its centre's, which every beam of a fan shares: a multiply-add chain a line instead of sin and cos.
constexpr double kSmallAngleRad = 0.01;
void cos_sin_near(double cos_c, double sin_c, double delta, double& cos_out, double& sin_out);

struct SonarPingSpec {
  std::vector<SonarBeam> beams;
  double min_range = 0.5;  // the receive window [m]
  double max_range = 50.0;
  int bins = 512;            // range bins of equal size over the window
  int rays_u = 2;            // rays per beam along u
  int rays_v = 256;          // and along v
  bool jitter = true;        // seeded grid lines within the ray cells (else their centres)
  double source_level_db = 210.0;           // SL [dB re 1 uPa at 1 m]
  double noise_level_db = 80.0;             // receiver noise per bin [dB re 1 uPa]
  bool receiver_noise = true;
  bool speckle = true;
  double spreading_db_per_decade = 20.0;     // N in TL(r)
  double tvg_spreading_db_per_decade = 30.0;  // N_tvg in TVG(r)
  bool tvg_absorption = true;

  double bin_size_m() const { return (max_range - min_range) / bins; }
  double bin_centre_m(int bin) const { return min_range + (bin + 0.5) * bin_size_m(); }
  // The bin of range r, or -1 outside [min_range, max_range).
  int bin_of(double r) const;
  // Throws std::invalid_argument naming the first unusable value.
  void validate() const;
};

// The water at the sonar for one ping.
struct SonarWater {
  double sound_speed_m_per_s = 1500.0;
  double absorption_db_per_m = 0.0;  // alpha at the sonar's frequency
  // The sea surface as a reflector (`surface`): the plane through surface_point_W with the unit normal
  // surface_normal_W (up; the waves' tangent plane over the sonar), Lambert's mu (linear). A ray that rises to it
  // before it hits anything echoes from it.
  bool surface = false;
  Eigen::Vector3d surface_point_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d surface_normal_W = Eigen::Vector3d::UnitZ();
  double surface_mu = 0.0;
};

// TL(r) [dB] and TVG(r) [dB] above.
double transmission_loss_db(const SonarPingSpec& spec, const SonarWater& water, double r);
double tvg_db(const SonarPingSpec& spec, const SonarWater& water, double r);

// mu (linear, Lambert's law above) of each of the first `count` rays of `hits` that hit something.
using BackscatterOfHits = std::function<void(const geometry::RayHits& hits, std::size_t count, float* mu)>;

// One beam's echo: per bin, the received intensity after TVG [uPa^2] and the echo-weighted mean offset a
// of the rays that returned in it [rad] (NaN where none did).
struct BeamEcho {
  int beam = 0;
  int bins = 0;
  const float* intensity = nullptr;
  const float* mean_offset_u_rad = nullptr;
};

// Called once per beam, possibly on several threads at once (for different beams).
using BeamEchoSink = std::function<void(const BeamEcho& echo)>;

// Casts one ping from S at X_WS into `scene` (posed at the ping's snapshot; own_body's hull transparent,
// geometry::kNoHit for none) and hands each beam's echo to `sink`. noise_key and ping_index key the
// jitter, speckle and noise streams. Throws std::invalid_argument for an invalid spec.
void ping(const geometry::EmbreeScene& scene, const SonarPingSpec& spec, const Eigen::Isometry3d& X_WS,
          std::int32_t own_body, const SonarWater& water, const BackscatterOfHits& backscatter,
          std::uint64_t noise_key, std::uint64_t ping_index, const ParallelFor& parallel, const BeamEchoSink& sink);

struct BottomDetection {
  bool valid = false;
  double range_m = std::numeric_limits<double>::quiet_NaN();
  double intensity = 0.0;  // the peak bin's, after TVG [uPa^2]
  bool by_phase = false;
};

inline constexpr int kPhaseMinBins = 4;
// A ray's patch spans at most this many range bins (one grazed by its ray, whose echo is weak anyway: it
// carries cos(theta)).
inline constexpr double kMaxFootprintBins = 64.0;
inline constexpr double kFootprintJump = 3.0;
inline constexpr int kDetectionSmoothingBins = 5;

// The bottom in one beam's echo (header).
BottomDetection detect_bottom(const SonarPingSpec& spec, const SonarWater& water, const BeamEcho& echo,
                              double min_snr_db = 10.0, double window_db = 10.0);

}  // namespace hadal::render
