// A preset: a product's (or a material's) published figures, with where they come from. Every kind
// with presets (IMU, DVL, the sonars, the camera's lens, the soil) keeps them as one list of
// Preset<Figures>, written as labelled rows (designated initialisers) in the kind's .cc file; the kind's
// `preset:` key (KeyTable::preset, config/key_table.h) lists them, and the generated reference
// (configs/REFERENCE.md) prints each one's product and source under its table. Where the source is a
// table under docs/reference/, the kind's test recomputes every preset from it.
#pragma once

#include <string_view>
#include <vector>

namespace hadal::config {

template <class Figures>
struct Preset {
  std::string_view id;       // the value of `preset:` in YAML, e.g. "teledyne_workhorse_navigator_600"
  std::string_view product;  // what it is, in words
  std::string_view source;   // the document (and table, row or page) the figures are taken from, and any
                             // assumption beyond it
  Figures figures;
};

template <class Figures>
using Presets = std::vector<Preset<Figures>>;

// The preset with this id, or nullptr.
template <class Figures>
const Preset<Figures>* find_preset(const Presets<Figures>& presets, std::string_view id) {
  for (const Preset<Figures>& preset : presets) {
    if (preset.id == id) return &preset;
  }
  return nullptr;
}

}  // namespace hadal::config
