// The slab test of a ray segment against an axis-aligned box, one axis at a time: shared by the
// renderer's shadow-ray culling (render/frame.cc) and the ray-cast bodies' pass
// (EmbreeScene::Impl::bodies_within_reach, which computes each ray's 1 / d once for all boxes).
#pragma once

#include <cmath>

namespace hadal::geometry {

inline constexpr float kSlabTinyDirection = 1e-30f;

// 1 / d for clip_to_slab_reciprocal: a direction component smaller than 1e-30 in magnitude (zero
// included) is taken as +-1e-30, so nothing multiplies inf by 0 and the answer for an origin inside or
// outside the slab stands.
inline float slab_reciprocal(float d) {
  const float magnitude = std::fabs(d) < kSlabTinyDirection ? kSlabTinyDirection : std::fabs(d);
  return 1.0f / std::copysign(magnitude, d);
}

// Narrows [t0, t1] to the parameters where o + t d lies in [lo, hi] along one axis, given
// inv_d = slab_reciprocal(d) (t0 > t1 after all three axes: the segment misses the box). Branch-free
// (selects), so that a loop calling it vectorizes.
inline void clip_to_slab_reciprocal(float lo, float hi, float o, float inv_d, float& t0, float& t1) {
  const float ta = (lo - o) * inv_d, tb = (hi - o) * inv_d;
  const float near = tb < ta ? tb : ta, far = ta < tb ? tb : ta;
  t0 = t0 < near ? near : t0;
  t1 = far < t1 ? far : t1;
}

// The same from the direction component d itself.
inline void clip_to_slab(float lo, float hi, float o, float d, float& t0, float& t1) {
  clip_to_slab_reciprocal(lo, hi, o, slab_reciprocal(d), t0, t1);
}

}  // namespace hadal::geometry
