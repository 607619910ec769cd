#include "hadal/sensors/sensor_kind.h"

#include "hadal/config/yaml_reader.h"

namespace hadal::sensors {

using config::format_number;
using config::Need;
using config::Range;

void read_range_figures(const config::MapReader& map, double& min_range, double& max_range,
                        double& noise_stddev, double& resolution) {
  map.read_number("min_range", Need::kOptional, Range::non_negative(), &min_range);
  if (map.read_number("max_range", Need::kOptional, Range::positive(), &max_range) && !(max_range > min_range)) {
    map.error_at_key(map.has("max_range") ? "max_range" : "min_range",
                     "max_range (" + format_number(max_range) + " m) must exceed min_range (" +
                         format_number(min_range) + " m)");
  }
  map.read_number("noise_stddev", Need::kOptional, Range::non_negative(), &noise_stddev);
  map.read_number("resolution", Need::kOptional, Range::non_negative(), &resolution);
}

}  // namespace hadal::sensors
