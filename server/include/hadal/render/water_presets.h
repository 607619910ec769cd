// Published water optics as camera channels (docs/ARCHITECTURE.md, "Cameras"): Jerlov water types'
// diffuse attenuation Kd for daylight (render/optics.h, Daylight) and pure water's absorption a_w.
//
// Channels are bands: blue 400-500 nm, green 500-600 nm, red 600-700 nm; a channel's value is the
// band mean of the tabulated spectrum (trapezoids over the table's wavelengths, divided by 100 nm).
// Sources, in docs/reference/optics/ (the test recomputes every value from these files):
//   oceanic types I, IA, IB, II, III and coastal 1C: Austin & Petzold (1984)'s revision of Jerlov's
//     Kd (austin_petzold1984_jerlov_update_Kd.csv), 400-700 nm;
//   coastal 3C, 5C, 7C, 9C: Jerlov (1976), Marine Optics, Table XXVII (jerlov1976_tableXXVII_Kd.csv);
//   pure water absorption: Pope & Fry (1997) (pope_fry_1997_pure_water_absorption.txt).
#pragma once

#include <string_view>

#include "hadal/render/optics.h"

namespace hadal::render {

enum class JerlovType { kI, kIA, kIB, kII, kIII, k1C, k3C, k5C, k7C, k9C };

// "I", "IA", "IB", "II", "III", "1C", "3C", "5C", "7C", "9C"; and back (false for an unknown name).
std::string_view to_string(JerlovType type);
bool jerlov_type_from_string(std::string_view name, JerlovType* type);

// Kd [1/m] per channel (R, G, B) of a Jerlov water type.
Rgb jerlov_Kd_per_m(JerlovType type);

// Absorption of pure water [1/m] per channel (R, G, B): the floor of any water's absorption.
Rgb pure_water_absorption_per_m();

}  // namespace hadal::render
