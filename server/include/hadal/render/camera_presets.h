// Calibrations of real underwater cameras, published with their datasets, as lens presets for the
// camera sensor (`preset:` in YAML, configs/REFERENCE.md). Each entry is copied digit for digit from
// its source, named with the numbers (camera_presets.cc). None of the sources says whether the
// calibration was made in water through the housing's port or in air; these are the calibrations the
// datasets' images come with. (A published deep-sea ROV fisheye calibration, UWHandles', is not here:
// its polynomial folds over before the image corners, which lie outside the fisheye's image circle,
// and a Hadal lens needs an inverse at every pixel.)
//
// downscaled() turns a calibration of a W x H image into that of the same camera's image resized by
// 1/s (binned or scaled, s >= 1, W/s and H/s whole numbers): fx/s, fy/s, and, with OpenCV's pixel
// centres at integer coordinates, c' = (c + 0.5)/s - 0.5; the distortion acts on normalised
// coordinates and is unchanged.
#pragma once

#include "hadal/config/preset.h"
#include "hadal/render/lens.h"

namespace hadal::render {

// Each preset's figures are its lens (config/preset.h).
const config::Presets<LensSpec>& camera_presets();

// Throws std::invalid_argument unless s >= 1 and both image sides divide by s into whole numbers.
LensSpec downscaled(const LensSpec& lens, double s);

}  // namespace hadal::render
