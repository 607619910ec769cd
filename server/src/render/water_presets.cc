#include "hadal/render/water_presets.h"

#include <array>

namespace hadal::render {
namespace {

struct Row {
  JerlovType type;
  std::string_view name;
  double red, green, blue;  // band means of Kd [1/m] (header)
};

constexpr std::array<Row, 10> kJerlov = {{
    {JerlovType::kI, "I", 0.389138, 0.085475, 0.0198375},     // Austin & Petzold 1984
    {JerlovType::kIA, "IA", 0.392512, 0.0890875, 0.027775},
    {JerlovType::kIB, "IB", 0.396612, 0.0934875, 0.037425},
    {JerlovType::kII, "II", 0.411525, 0.109375, 0.0725125},
    {JerlovType::kIII, "III", 0.439275, 0.138975, 0.137787},
    {JerlovType::k1C, "1C", 0.467012, 0.168588, 0.203075},
    {JerlovType::k3C, "3C", 0.485, 0.21875, 0.43},            // Jerlov 1976, Table XXVII
    {JerlovType::k5C, "5C", 0.5675, 0.33, 0.625},
    {JerlovType::k7C, "7C", 0.6625, 0.485, 0.9725},
    {JerlovType::k9C, "9C", 0.795, 0.69625, 1.60625},
}};

const Row& row(JerlovType type) {
  for (const Row& r : kJerlov) {
    if (r.type == type) return r;
  }
  return kJerlov[0];
}

}  // namespace

std::string_view to_string(JerlovType type) { return row(type).name; }

bool jerlov_type_from_string(std::string_view name, JerlovType* type) {
  for (const Row& r : kJerlov) {
    if (r.name == name) {
      *type = r.type;
      return true;
    }
  }
  return false;
}

Rgb jerlov_Kd_per_m(JerlovType type) {
  const Row& r = row(type);
  return Rgb(r.red, r.green, r.blue);
}

Rgb pure_water_absorption_per_m() { return Rgb(0.374408, 0.06897, 0.00903713); }  // Pope & Fry 1997

}  // namespace hadal::render
