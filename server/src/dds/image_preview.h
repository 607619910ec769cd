// Previews (sensors/sensor_kind.h, TopicHasPreview): rt/<vehicle>/<camera>/preview carries the camera's
// image at half resolution (each output pixel the mean of a 2 x 2 block, rounded; an odd last row or column
// dropped), same header and encoding; a topic that draws its own (TopicDrawsPreview: the forward-looking
// sonar's fan) fills it instead. Written at most every kPreviewInterval of wall time and only while a reader
// is matched. A side channel for monitors: paced in wall time, so not part of a lockstep
// run's deterministic output.
#pragma once

#include <sensor_msgs.h>

#include <chrono>

namespace hadal::dds {

inline constexpr std::chrono::milliseconds kPreviewInterval{200};

// The half-resolution image of `in` into *out; false (and *out unchanged) for an encoding other than rgb8,
// bgr8 and mono8, an image smaller than 2 x 2, or data shorter than step x height.
bool half_resolution(const sensor_msgs::msg::Image& in, sensor_msgs::msg::Image* out);

}  // namespace hadal::dds
