#include "hadal/geometry/seabed_spec.h"

#include <memory>
#include <utility>

#include "hadal/config/key_table.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_transform.h"
#include "hadal/geometry/terrain.h"

namespace hadal::geometry {
namespace {

using namespace config::keys;

// Samples a procedural or heightmap seabed may have (16 M: 64 MB of float heights, ~32 M triangles).
constexpr double kMaxSeabedSamples = 16777216.0;

// Builds the surface of a seabed whose keys were read without error; reports at the file's value or the map.
void build_seabed_mesh(const config::MapReader& map, SeabedSpec* seabed) {
  switch (seabed->type) {
    case SeabedType::kPlane:
      return;
    case SeabedType::kProcedural: {
      seabed->procedural.z_datum = seabed->z;
      const double samples = (seabed->procedural.size_x / seabed->procedural.resolution + 1.0) *
                             (seabed->procedural.size_y / seabed->procedural.resolution + 1.0);
      if (samples > kMaxSeabedSamples) {
        map.value().error("size / resolution gives " + config::format_approximate(samples) +
                          " height samples; at most 16777216 are allowed");
        return;
      }
      seabed->mesh = std::make_shared<const TriangleMesh>(heightfield_to_mesh(procedural_seabed(seabed->procedural)));
      return;
    }
    case SeabedType::kHeightmap: {
      const HeightmapLoad load = load_heightmap(seabed->heightmap);
      if (!load.field) {
        map.optional("file")->error(load.error);
        return;
      }
      seabed->mesh = std::make_shared<const TriangleMesh>(heightfield_to_mesh(*load.field));
      return;
    }
    case SeabedType::kMesh: {
      ImportResult imported = import_mesh(seabed->file, seabed->import);
      if (!imported.mesh) {
        map.optional("file")->error(imported.error);
        return;
      }
      transform_mesh(seabed->X_WM, &*imported.mesh);
      seabed->mesh = std::make_shared<const TriangleMesh>(std::move(*imported.mesh));
      return;
    }
  }
}

}  // namespace

const KeyTable<SeabedSpec, LoadContext>& seabed_keys() {
  return declare_keys<SeabedSpec, LoadContext>([](KeyTable<SeabedSpec, LoadContext>& t) {
    t.describe("world.seabed", "the seabed: a plane, a mesh file, a heightmap or procedural");
    t.choice("type", &SeabedSpec::type,
             {{"plane", SeabedType::kPlane, "an infinite horizontal plane"},
              {"mesh", SeabedType::kMesh, "a mesh file"},
              {"heightmap", SeabedType::kHeightmap, "a grey-scale image"},
              {"procedural", SeabedType::kProcedural, "seeded bathymetry"}})
        .selects("seabed type")
        .doc("what the seabed is");
    t.number("z", &SeabedSpec::z).only_for({"plane", "procedural"}).unit("m")
        .doc("`plane`: its height in W; `procedural`: the height of the sediment plain");
    t.file("file", &SeabedSpec::file).only_for({"mesh", "heightmap"}).required_for({"mesh", "heightmap"})
        .doc("`mesh`: GLB, glTF (+ .bin), OBJ, STL; `heightmap`: 8- or 16-bit single-channel PNG or TIFF");
    t.number("scale", [](SeabedSpec& s) -> double& { return s.import.scale; }).only_for({"mesh"})
        .range(Range::positive()).doc("file units to metres");
    t.choice("up_axis", [](SeabedSpec& s) -> UpAxis& { return s.import.up_axis; },
             {{"z", UpAxis::kZ}, {"y", UpAxis::kY, "glTF's convention, rotated +90° about x into Hadal's z up"}})
        .only_for({"mesh"}).doc("the file's up axis");
    t.pose("pose", &SeabedSpec::X_WM).only_for({"mesh"}).doc("pose of the file's frame in W");
    t.number("meters_per_pixel", [](SeabedSpec& s) -> double& { return s.heightmap.meters_per_pixel; })
        .only_for({"heightmap"}).required_for({"heightmap"}).unit("m").range(Range::positive())
        .doc("pixel spacing; the map is centred on W's origin, image row 0 is its north (+y) edge");
    t.numbers(
         "height_range", 2,
         [](SeabedSpec& s, const std::vector<double>& v) {
           s.heightmap.height_min = v[0];
           s.heightmap.height_max = v[1];
         },
         nullptr)
        .only_for({"heightmap"}).required_for({"heightmap"}).unit("m").rule("[min, max], max > min")
        .doc("z of pixel value 0 and of full scale (65535 or 255)");
    t.numbers(
         "size", 2,
         [](SeabedSpec& s, const std::vector<double>& v) {
           s.procedural.size_x = v[0];
           s.procedural.size_y = v[1];
         },
         [](SeabedSpec& s) { return std::vector<double>{s.procedural.size_x, s.procedural.size_y}; })
        .only_for({"procedural"}).unit("m").range(Range::left_open(0.0, 100000.0))
        .doc("extent along x and y, centred on W's origin");
    t.number("resolution", [](SeabedSpec& s) -> double& { return s.procedural.resolution; }).only_for({"procedural"})
        .unit("m").range(Range::positive()).doc("sample spacing; at most 16 777 216 samples");
    t.number("relief", [](SeabedSpec& s) -> double& { return s.procedural.relief; }).only_for({"procedural"})
        .unit("m").range(Range::non_negative()).doc("amplitude of the fractal (5-octave value-noise) relief");
    t.number("ridge_height", [](SeabedSpec& s) -> double& { return s.procedural.ridge_height; })
        .only_for({"procedural"}).unit("m").range(Range::non_negative()).doc("height of the ridges");
    t.number("slope_deg", [](SeabedSpec& s) -> double& { return s.procedural.slope; }).only_for({"procedural"})
        .degrees().range(Range::right_open(0.0, 60.0)).doc("regional slope in a seeded direction");
    t.number("plain_radius", [](SeabedSpec& s) -> double& { return s.procedural.plain_radius; })
        .only_for({"procedural"}).unit("m").range(Range::non_negative())
        .doc("flat sediment plain around the origin, blending into the rough terrain between r and 2r");
    t.unsigned_integer("seed", [](SeabedSpec& s) -> std::uint64_t& { return s.procedural.seed; })
        .only_for({"procedural"}).default_text("`world.seed`").doc("seeds the bathymetry");
    t.check([](const KeyReads& reads, SeabedSpec& seabed, LoadContext& context) {
      bool ok = true;
      if (seabed.type == SeabedType::kHeightmap && reads.ok("height_range") && reads.has("height_range") &&
          !(seabed.heightmap.height_max > seabed.heightmap.height_min)) {
        reads.map().optional("height_range")->error(
            "must be [min, max] with max > min (got [" + config::format_number(seabed.heightmap.height_min) + ", " +
            config::format_number(seabed.heightmap.height_max) + "])");
        return false;
      }
      seabed.heightmap.file = seabed.file;
      if (!reads.has("seed")) seabed.procedural.seed = context.world_seed;
      if (ok && reads.all_ok()) build_seabed_mesh(reads.map(), &seabed);
      return ok;
    });
  });
}

}  // namespace hadal::geometry
