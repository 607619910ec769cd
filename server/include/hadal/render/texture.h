// Base-colour textures (docs/ARCHITECTURE.md, "Cameras"): glTF stores a material's base-colour texture
// as sRGB-encoded 8-bit texels; the renderer works in linear radiometric units, so texels are decoded
// with the sRGB transfer function (IEC 61966-2-1) before they multiply the material's base colour factor.
// Texture coordinates follow geometry::TriangleMesh: texel (i, j) (column i, row j from the image's
// top) has its centre at u = (i + 1/2) / width, v = 1 - (j + 1/2) / height. Sampling is bilinear
// between texel centres in linear values and repeats outside [0, 1] (glTF's default wrap); no
// mip-mapping (a texture seen from far enough that a pixel covers many texels aliases).
#pragma once

#include "hadal/geometry/triangle_mesh.h"
#include "hadal/render/optics.h"

namespace hadal::render {

// sRGB-encoded value in [0, 1] -> linear: c / 12.92 up to 0.04045, ((c + 0.055) / 1.055)^2.4 above.
double srgb_to_linear(double encoded);

// The texture's linear RGB at texture coordinates (u, v) (header); u, v finite. The texture must have
// 3 or 4 channels (RGB or RGBA; alpha is not used) and at least one texel; throws
// std::invalid_argument otherwise.
Rgb sample_texture(const geometry::Texture& texture, float u, float v);

}  // namespace hadal::render
