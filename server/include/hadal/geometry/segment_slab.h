// The slab test of a ray segment against an axis-aligned box, one axis at a time: shared by the
// renderer's shadow-ray culling (render/frame.cc) and the ray-cast bodies' pass
// (EmbreeScene::Impl::bodies_within_reach, whose vectorized loop does the same operations with 1 / d
// computed first).
#pragma once

#include <cmath>

namespace hadal::geometry {

inline constexpr float kSlabTinyDirection = 1e-30f;

// Narrows [t0, t1] to the parameters where o + t d lies in [lo, hi] along one axis (t0 > t1 after
// all three axes: the segment misses the box). A direction component smaller than 1e-30 in magnitude
// (zero included) is taken as +-1e-30, so nothing multiplies inf by 0 and the answer for an origin
// inside or outside the slab stands. Branch-free (selects), so that a loop calling it vectorizes.
inline void clip_to_slab(float lo, float hi, float o, float d, float& t0, float& t1) {
  const float magnitude = std::fabs(d) < kSlabTinyDirection ? kSlabTinyDirection : std::fabs(d);
  const float inv = 1.0f / std::copysign(magnitude, d);
  const float ta = (lo - o) * inv, tb = (hi - o) * inv;
  const float near = tb < ta ? tb : ta, far = ta < tb ? tb : ta;
  t0 = t0 < near ? near : t0;
  t1 = far < t1 ? far : t1;
}

}  // namespace hadal::geometry
