// What every sonar's spec holds (sensors/sonar.h): its acoustics and, for the imaging kinds, the
// encoding of its samples. Their keys: sensors/sonar_keys.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

namespace hadal::render {
struct SonarPingSpec;
}

namespace hadal::sensors {

struct SonarAcoustics {
  double frequency_hz = 400e3;
  double min_range = 0.5;  // [m]
  double max_range = 50.0;  // [m]
  int bins = 512;
  double source_level_db = 210.0;
  double noise_level_db = 70.0;
  bool speckle = true;
  bool receiver_noise = true;
  double spreading_db_per_decade = 20.0;
  double tvg_db_per_decade = 30.0;
  bool tvg_absorption = true;
};

struct SonarImageEncoding {
  bool float32 = false;  // else uint8
  double display_min_db = 100.0;
  double display_max_db = 170.0;

  std::size_t bytes_per_sample() const { return float32 ? 4 : 1; }
  // Writes one sample of intensity I [uPa^2] (above) at `out` (bytes_per_sample() bytes, little-endian).
  void encode(float intensity, std::uint8_t* out) const;
  // The grey level 0..255 of the sample at `sample`: a uint8 sample as it is, a float32 one over the display
  // window as uint8 encodes it (for people: previews, figures).
  std::uint8_t grey(const std::uint8_t* sample) const;
};
}  // namespace hadal::sensors
