// The lens models a camera may have (render/lens.h models them).
#pragma once

namespace hadal::render {

enum class LensModel { kPinhole, kRadialTangential, kEquidistant };
}  // namespace hadal::render
