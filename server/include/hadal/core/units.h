// Constants and unit conversions shared by every module (docs/ARCHITECTURE.md, "Model and state": SI inside; degrees exist only in
// YAML keys ending in `_deg` and are converted on load with kDegToRad).
#pragma once

namespace hadal {

inline constexpr double kPi = 3.14159265358979323846;  // the double nearest to pi
inline constexpr double kDegToRad = kPi / 180.0;

// An angle in degrees, for what people read (messages, the reference, a GPS fix's latitude); the YAML's
// `_deg` keys are read by the key table's degrees() (config/key_table.h).
constexpr double to_degrees(double rad) { return rad / kDegToRad; }

}  // namespace hadal
