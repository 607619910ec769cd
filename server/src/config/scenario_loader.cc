#include "hadal/config/scenario_loader.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <deque>
#include <map>
#include <memory>
#include <utility>

#include "hadal/config/key_table.h"
#include "hadal/config/security_block.h"
#include "hadal/config/vehicle_keys.h"
#include "hadal/config/yaml_reader.h"
#include "hadal/core/data_dir.h"
#include "hadal/physics/control_vector.h"

namespace hadal::config {

const KeyTable<Model, LoadContext>& scenario_keys() {
  Model defaults;
  defaults.world = world_keys().defaults();
  return declare_keys<Model, LoadContext>(std::move(defaults), [](KeyTable<Model, LoadContext>& t) {
    t.describe("scenario", "a Hadal scenario: the world and the vehicles in it");
    t.map("world", &Model::world, world_keys()).required().doc("the world");
    t.list("vehicles", &Model::vehicles, vehicle_entry_keys()).required().min_items(1).read_elsewhere()
        .doc("the vehicles, each defined inline or by `include`");
    t.list("objects", &Model::vehicles, object_entry_keys()).read_elsewhere()
        .doc("free objects (samples, rocks, crates), each defined inline or by `include`; they follow the vehicles");
    t.list("cables", &Model::cables, physics::cable_keys())
        .doc("cables in the water (tethers, umbilicals, lift lines, tow cables), each between two ends");
    t.custom(
         "security",
         [](const Value& value, Model& model, LoadContext&) {
           std::optional<SecurityFiles> files = read_security_block(value);
           if (files) model.security = std::move(*files);
           return files.has_value();
         },
         "", "map")
        .keys_of(security_keys())
        .doc("DDS Security of hadald's participant (docs/dds.md); hadald --security FILE replaces it");
  });
}

namespace {

// Vehicle names become DDS/ROS topic segments (rt/<name>/...).
bool is_valid_vehicle_name(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

class ScenarioLoader {
 public:
  LoadResult load(const std::string& path, const LoadOptions& options);

 private:
  // A `vehicles` entry, or (object) an `objects` entry.
  void read_vehicle(const Value& value, VehicleSpec* vehicle, bool object = false);
  void warn_if_above_surface(const MapReader& map, const VehicleSpec& vehicle);
  // Each cable end's vehicle and link, by name, to their indices; unique cable names.
  void resolve_cables(const Value& cables, Model& model);
  // The definition in `include` (a path relative to the including file), loaded once per resolved path;
  // with an entry's `overrides` that reach into it, read again for that entry alone. nullopt when the file
  // cannot be opened (reported at `include`) or does not parse.
  const std::optional<VehicleDefinition>& included_definition(const Value& include, const std::string& path,
                                                              bool object,
                                                              const std::vector<Override>* overrides = nullptr);
  // Parses LoadOptions::overrides and places each where it applies: at the scenario's own paths
  // (overrides_), or, through a vehicle or object entry with `include`, at the included file's paths for
  // that entry alone (include_overrides_, by the entry's path).
  void place_overrides(const std::vector<std::string>& texts, const YAML::Node& root, const std::string& path);
  void read_schedule(const Value& value, const VehicleDefinition* definition,
                     std::vector<SetpointKeyframe>* schedule);
  VehicleContext vehicle_context() const {
    VehicleContext context;
    context.physics_rate_hz = context_.physics_rate_hz;
    return context;
  }

  DiagnosticSink sink_;
  LoadContext context_;  // physics rate (nullopt when world.physics_rate_hz is invalid) and seed
  struct IncludedFile {
    std::string open_error;                       // set when the file cannot be opened
    std::optional<VehicleDefinition> definition;  // nullopt when it cannot be opened or parsed
  };
  std::map<std::pair<std::string, bool>, IncludedFile> includes_;  // by resolved path, and object or not
  std::vector<Override> overrides_;                               // at the scenario file's paths
  std::map<std::string, std::vector<Override>> include_overrides_;  // by entry path ("vehicles[1]")
  std::deque<IncludedFile> overridden_includes_;  // included files read for one entry, with its overrides
  std::shared_ptr<const std::vector<std::filesystem::path>> roots_;  // where the files named may lie
  std::map<std::string, std::string> vehicle_names_;  // name -> path of the entry that used it first
};

LoadResult ScenarioLoader::load(const std::string& path, const LoadOptions& options) {
  Model model = scenario_keys().defaults();
  model.scenario_file = path;
  std::vector<std::filesystem::path> roots;
  for (const AssetRoot& root : asset_roots(path, options)) {
    if (root.error.empty()) {
      roots.push_back(root.path);
    } else {
      sink_.report(path, YAML::Mark::null_mark(), "", "asset root " + quoted(root.path) + " (" + root.origin +
                                                          ") " + root.error);
    }
  }
  roots_ = std::make_shared<const std::vector<std::filesystem::path>>(std::move(roots));
  std::string open_error;
  const std::optional<YAML::Node> root = parse_yaml_file(path, &sink_, &open_error);
  if (!root && !open_error.empty()) {
    sink_.report(path, YAML::Mark::null_mark(), "", "cannot open scenario file (" + open_error + ")");
  }
  // Rates are checked against the physics rate once the world gave a valid one.
  context_.physics_rate_hz.reset();
  if (root) {
    place_overrides(options.overrides, *root, path);
    const auto source = std::make_shared<const Source>(Source{path, &sink_, roots_, &overrides_, {}});
    const MapReader map(Value::root(*root, source), scenario_keys().names());
    if (map.ok()) {
      scenario_keys().read_map(map, &model, context_);
      if (const auto vehicles = map.optional("vehicles")) {
        if (const auto items = vehicles->list()) {
          if (items->empty()) vehicles->error("must not be empty");
          for (std::size_t i = 0; i < items->size(); ++i) {
            VehicleSpec vehicle;
            read_vehicle((*items)[i], &vehicle);
            model.vehicles.push_back(std::move(vehicle));
          }
        }
      }
      if (const auto objects = map.optional("objects")) {
        if (const auto items = objects->list()) {
          for (std::size_t i = 0; i < items->size(); ++i) {
            VehicleSpec object;
            read_vehicle((*items)[i], &object, true);
            model.vehicles.push_back(std::move(object));
          }
        }
      }
      if (const auto cables = map.optional("cables")) resolve_cables(*cables, model);
    }
  }

  LoadResult result;
  for (Diagnostic& diagnostic : sink_.sorted()) {
    (diagnostic.warning ? result.warnings : result.errors).push_back(std::move(diagnostic));
  }
  if (result.errors.empty()) result.model = std::move(model);
  return result;
}

void ScenarioLoader::resolve_cables(const Value& cables, Model& model) {
  const std::optional<std::vector<Value>> items = cables.list();
  if (!items) return;
  std::map<std::string, std::string> names;
  for (std::size_t i = 0; i < items->size() && i < model.cables.size(); ++i) {
    physics::CableModel& cable = model.cables[i];
    const MapReader map((*items)[i], physics::cable_keys().names());
    if (!map.ok()) continue;
    if (!cable.name.empty() && !names.emplace(cable.name, (*items)[i].path()).second) {
      map.error_at_key("name", "duplicate cable name " + config::quoted(cable.name) + " (first used by " + names[cable.name] + ")");
    }
    for (std::size_t e = 0; e < 2; ++e) {
      physics::CableEndSpec& end = cable.ends[e];
      const std::optional<Value> end_value = map.optional(e == 0 ? "from" : "to");
      if (!end_value) continue;
      const MapReader end_map(*end_value, physics::cable_end_keys().names());
      if (end.winch && end_map.ok()) {  // its drum holds the cable in the water, and it can haul in to min_length
        if (const std::optional<Value> winch_value = end_map.optional("winch")) {
          const MapReader winch_map(*winch_value, physics::winch_keys().names());
          if (end.winch->drum_length < cable.spec.length) {
            winch_map.error_at_key("drum_length", "the drum holds less than the cable's length (" +
                                                      config::format_number(cable.spec.length) + " m in the water)");
          } else if (end.winch->min_length > cable.spec.length) {
            winch_map.error_at_key("min_length", "more than the cable's length (" +
                                                     config::format_number(cable.spec.length) + " m in the water)");
          }
        }
      }
      if (!end.on_vehicle()) continue;
      end.vehicle_index = model.vehicle_index(end.vehicle);
      if (end.vehicle_index < 0) {
        std::string known;
        for (const VehicleSpec& v : model.vehicles) known += (known.empty() ? "'" : ", '") + v.name + "'";
        end_map.error_at_key("vehicle", "unknown vehicle " + config::quoted(end.vehicle) + " (vehicles: " + known + ")");
        continue;
      }
      const VehicleSpec& vehicle = model.vehicles[static_cast<std::size_t>(end.vehicle_index)];
      if (!end.link.empty()) {
        end.link_index = -1;
        std::string known;
        for (std::size_t k = 0; k < vehicle.links.size(); ++k) {
          known += (known.empty() ? "'" : ", '") + vehicle.links[k].name + "'";
          if (vehicle.links[k].name == end.link) end.link_index = static_cast<int>(k);
        }
        if (end.link_index < 0) {
          end_map.error_at_key("link", "vehicle " + config::quoted(vehicle.name) + " has no link " + config::quoted(end.link) +
                                           " (its links: " + known + ")");
          continue;
        }
      }
    }
  }
}

void ScenarioLoader::read_vehicle(const Value& value, VehicleSpec* vehicle, bool object) {
  const auto& entry_keys = object ? object_entry_keys() : vehicle_entry_keys();
  const auto& definition_table = object ? object_definition_keys() : definition_keys();
  const MapReader map(value, entry_keys.names());
  if (!map.ok()) return;

  if (const auto name = map.required("name")) {
    if (const auto text = name->string()) {
      vehicle->name = *text;
      if (!is_valid_vehicle_name(*text)) {
        name->error("must match [A-Za-z][A-Za-z0-9_]* (got " + quoted(*text) + ")");
      } else {
        const auto [it, inserted] = vehicle_names_.emplace(*text, value.path());
        if (!inserted) {
          const bool mixed = object || it->second.rfind("objects[", 0) == 0;
          name->error(std::string("duplicate ") + (object ? "object" : "vehicle") + " name " + quoted(*text) +
                      " (first used by " + it->second + (mixed ? "; vehicles and objects share their names)" : ")"));
        }
      }
    }
  }

  // The definition: either `include` (which the entry may extend with more `sensors` and `lights`, and
  // give a `transponder`) or inline keys, never both.
  static const std::vector<std::string> kExtensions = {"sensors", "lights", "transponder"};
  const auto is_extension = [](const std::string& key) {
    return std::find(kExtensions.begin(), kExtensions.end(), key) != kExtensions.end();
  };
  bool extends = false;
  std::vector<std::string> inline_keys;
  for (const std::string& key : definition_table.names()) {
    if (!map.has(key)) continue;
    if (is_extension(key)) {
      extends = true;
    } else {
      inline_keys.push_back(quoted(key));
    }
  }
  std::optional<VehicleDefinition> inline_definition;
  const VehicleDefinition* definition = nullptr;
  if (const auto include = map.optional("include")) {
    if (!inline_keys.empty()) {
      map.error_at_key("include", "cannot be combined with an inline definition (found " + join_names(inline_keys) +
                                      "; an entry with 'include' may only add 'sensors', 'lights' and a 'transponder')");
    } else if (const auto include_path = include->string()) {
      const auto overridden = include_overrides_.find(value.path());
      const auto& included = included_definition(
          *include, *include_path, object, overridden == include_overrides_.end() ? nullptr : &overridden->second);
      if (included && !object && extends) {
        inline_definition = *included;  // extended by the entry's own lists and transponder
        VehicleContext context = vehicle_context();
        definition_table.read_only(map, &*inline_definition, context, kExtensions);
        definition = &*inline_definition;
      } else if (included) {
        definition = &*included;
      }
    }
  } else if (!inline_keys.empty() || (!object && extends)) {
    inline_definition.emplace();
    inline_definition->source_file = map.value().file();
    VehicleContext context = vehicle_context();
    definition_table.read_map(map, &*inline_definition, context);
    definition = &*inline_definition;
  } else {
    value.error(object ? "needs either 'include' or an inline definition ('links', ...)"
                       : "needs either 'include' or an inline definition ('type', 'links', ...)");
  }
  if (definition) {
    vehicle->source_file = definition->source_file;
    vehicle->type = definition->type;
    vehicle->seabed_contact = definition->seabed_contact;
    vehicle->links = definition->links;
    vehicle->actuators = definition->actuators;
    vehicle->sensors = definition->sensors;
    vehicle->lights = definition->lights;
    vehicle->transponder = definition->transponder;
    vehicle->joint_controllers = definition->joint_controllers;
    vehicle->fluid = definition->fluid;
    for (SensorSpec& sensor : vehicle->sensors) {
      if (sensor.frame_id.empty()) sensor.frame_id = vehicle->name + "/" + sensor.name;
    }
  }

  std::vector<std::string> failed;
  entry_keys.read_map(map, vehicle, context_, &failed);
  if (std::find(failed.begin(), failed.end(), "initial_pose") == failed.end()) warn_if_above_surface(map, *vehicle);
  if (object) return;
  if (const auto schedule = map.optional("schedule")) read_schedule(*schedule, definition, &vehicle->schedule);
}

// A vehicle that works under water (all but a surface vessel) starting more than kAboveSurface_m above the
// surface is most likely a depth written as a height (z is up in W): a warning at its initial_pose, since an
// air drop is possible. The margin leaves a surfaced AUV or glider, whose origin may ride above the surface.
void ScenarioLoader::warn_if_above_surface(const MapReader& map, const VehicleSpec& vehicle) {
  constexpr double kAboveSurface_m = 1.0;
  if (vehicle.type == VehicleType::kSurfaceVessel) return;
  const double height = vehicle.X_WB_initial.translation().z() - context_.water_surface_z;
  const std::optional<Value> pose = map.optional("initial_pose");
  if (!pose || !(height > kAboveSurface_m)) return;
  pose->warn(std::string("a vehicle of type ") + to_string(vehicle.type) + " starting " + format_number(height) +
             " m above the water surface (world.water.surface_z = " + format_number(context_.water_surface_z) +
             " m): z is up in W, so " + format_number(height) + " m down is z: " +
             format_number(context_.water_surface_z - height));
}

const std::optional<VehicleDefinition>& ScenarioLoader::included_definition(const Value& include,
                                                                            const std::string& path, bool object,
                                                                            const std::vector<Override>* overrides) {
  static const std::optional<VehicleDefinition> kRefused;
  std::string resolved;
  if (!include.file_path(path, &resolved)) return kRefused;
  // With overrides, read for this entry alone; otherwise once per file.
  bool first_use = true;
  IncludedFile* included = nullptr;
  if (overrides != nullptr) {
    included = &overridden_includes_.emplace_back();
  } else {
    auto [it, inserted] = includes_.try_emplace(std::make_pair(resolved, object));
    included = &it->second;
    first_use = inserted;
  }
  if (first_use) {
    const std::optional<YAML::Node> root = parse_yaml_file(resolved, &sink_, &included->open_error);
    if (root) {
      const auto source = std::make_shared<const Source>(Source{resolved, &sink_, roots_, overrides, {}});
      const auto& table = object ? object_definition_keys() : definition_keys();
      const MapReader map(Value::root(*root, source), table.names());
      if (map.ok()) {
        included->definition.emplace();
        included->definition->source_file = resolved;
        VehicleContext context = vehicle_context();
        table.read_map(map, &*included->definition, context);
      }
    }
  }
  // Errors inside the file are reported once; a file that cannot be opened at every include naming it.
  if (!included->open_error.empty()) {
    include.error("cannot open " + config::quoted(resolved) + " (" + included->open_error + ")");
  }
  return included->definition;
}

void ScenarioLoader::place_overrides(const std::vector<std::string>& texts, const YAML::Node& root,
                                     const std::string& path) {
  const std::filesystem::path scenario_directory = std::filesystem::path(path).parent_path();
  for (const std::string& text : texts) {
    const std::string label = "--set " + text;
    sink_.add_file(label);
    const auto at = [&](int column, const std::string& key_path, const std::string& message) {
      YAML::Mark mark;
      mark.line = 0;
      mark.column = column;
      sink_.report(label, mark, key_path, message);
    };
    const std::size_t equals = text.find('=');
    if (equals == std::string::npos || equals == 0) {
      at(0, "", "expected KEY.PATH=VALUE, as world.water.current.uniform=[0.4, 0, 0] (got " + quoted(text) + ")");
      continue;
    }
    const std::string key_path = text.substr(0, equals);
    std::vector<std::string> segments;
    std::vector<int> columns;
    bool empty_segment = false;
    for (std::size_t start = 0;;) {
      const std::size_t dot = key_path.find('.', start);
      const std::string segment = key_path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
      if (segment.empty()) {
        at(static_cast<int>(start), key_path, "an empty key in the path");
        empty_segment = true;
        break;
      }
      segments.push_back(segment);
      columns.push_back(static_cast<int>(start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    if (empty_segment) continue;
    YAML::Node value;
    try {
      // Padded so that the value's marks are columns of the whole argument.
      value = YAML::Load(std::string(equals + 1, ' ') + text.substr(equals + 1));
    } catch (const YAML::Exception& e) {
      // At the parser's mark, or the value's start when it has none (an unclosed list ends the input).
      at(std::max(e.mark.column, static_cast<int>(equals + 1)), key_path,
         "the value does not read as YAML (" + e.msg + ")");
      continue;
    }
    // Walk the file's tree by the path: a list's entry by its name (or index); through a vehicle's or
    // object's entry with `include`, a definition key leads into the included file.
    YAML::Node node = root;
    std::string at_path, entry_path;
    std::filesystem::path directory = scenario_directory;
    std::vector<std::pair<std::string, int>> key_columns;
    bool refused = false;
    for (std::size_t i = 0; i < segments.size() && !refused; ++i) {
      const std::string& segment = segments[i];
      const YAML::Node here = node;  // const: reading a key never adds it
      const bool defined = here.IsDefined();  // false for a key the file lacks (calls on it would throw)
      if (defined && here.IsSequence()) {
        std::optional<std::size_t> index;
        std::vector<std::string> names;
        const bool digits = std::all_of(segment.begin(), segment.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
        for (std::size_t k = 0; k < here.size(); ++k) {
          const YAML::Node item = here[k];
          const std::string name = item.IsMap() && item["name"] && item["name"].IsScalar() ? item["name"].Scalar() : "";
          if (!name.empty()) names.push_back(name);
          if (!index && !name.empty() && name == segment) index = k;
        }
        if (!index && digits && std::stoull(segment) < here.size()) index = std::stoull(segment);
        if (!index) {
          at(columns[i], at_path, "no entry " + quoted(segment) + " in " + (at_path.empty() ? "the file" : at_path) +
                                      (names.empty() ? " (its entries have no names: give an index)"
                                                     : " (its entries: " + join_names(names) + ")"));
          refused = true;
          break;
        }
        at_path += "[" + std::to_string(*index) + "]";
        node.reset(here[*index]);  // reset: a YAML::Node's = would overwrite the node it refers to
        const bool object = at_path.rfind("objects[", 0) == 0;
        const YAML::Node entry = node;  // const: reading a key never adds it
        if (entry_path.empty() && (at_path.rfind("vehicles[", 0) == 0 || object) &&
            at_path.find('.') == std::string::npos && entry.IsMap() && entry["include"] &&
            entry["include"].IsScalar() && i + 1 < segments.size()) {
          const std::string& next = segments[i + 1];
          const auto& definition_table = object ? object_definition_keys() : definition_keys();
          const bool own_list = (next == "sensors" || next == "lights") && entry[next] && i + 2 < segments.size() &&
                                [&] {
                                  for (const YAML::Node& item : entry[next]) {
                                    if (item.IsMap() && item["name"] && item["name"].Scalar() == segments[i + 2]) return true;
                                  }
                                  return false;
                                }();
          const std::vector<std::string> definition_names = definition_table.names();
          const bool definition_key =
              std::find(definition_names.begin(), definition_names.end(), next) != definition_names.end();
          if (definition_key && !own_list) {
            const std::string& written = entry["include"].Scalar();
            const std::filesystem::path included = directory / written;
            DiagnosticSink unused;  // the file's own errors (and a refusal) are the entry's to report
            const auto scenario = std::make_shared<const Source>(Source{path, &unused, roots_, nullptr, {}});
            std::string open_error = Value(entry["include"], scenario, "", YAML::Mark()).file_refusal(included, written);
            const std::optional<YAML::Node> included_root =
                open_error.empty() ? parse_yaml_file(included.string(), &unused, &open_error) : std::nullopt;
            if (!included_root) {
              at(columns[i + 1], child_path(at_path, next),
                 "cannot reach into " + quoted(entry["include"].Scalar()) + ", the file " + at_path + " includes (" +
                     (open_error.empty() ? "it does not parse" : open_error) + ")");
              refused = true;
              break;
            }
            entry_path = at_path;
            at_path.clear();
            key_columns.clear();  // paths in the included file from here
            node.reset(*included_root);
            directory = included.parent_path();
          }
        }
      } else {
        at_path = child_path(at_path, segment);
        key_columns.emplace_back(at_path, columns[i]);
        const YAML::Node child = defined && here.IsMap() ? here[segment] : YAML::Node(YAML::NodeType::Undefined);
        // A missing key's node is invalid (reset from it would throw): an undefined one stands for it.
        node.reset(child.IsDefined() ? child : YAML::Node(YAML::NodeType::Undefined));
      }
    }
    if (refused) continue;
    std::vector<Override>& destination = entry_path.empty() ? overrides_ : include_overrides_[entry_path];
    const auto source = std::make_shared<const Source>(Source{label, &sink_, roots_, &destination, directory});
    const YAML::Mark mark = value.IsNull() ? YAML::Mark() : value.Mark();
    destination.push_back(Override{at_path, Value(value, source, at_path, mark), std::move(key_columns)});
  }
}

void ScenarioLoader::read_schedule(const Value& value, const VehicleDefinition* definition,
                                   std::vector<SetpointKeyframe>* schedule) {
  const auto items = value.list();
  if (!items) return;
  std::optional<double> previous_time;
  NoContext none;
  for (const Value& item : *items) {
    const MapReader map(item, keyframe_keys().names());
    if (!map.ok()) continue;
    SetpointKeyframe keyframe;
    std::vector<std::string> failed;
    keyframe_keys().read_map(map, &keyframe, none, &failed);
    const auto ok = [&failed](const char* key) { return std::find(failed.begin(), failed.end(), key) == failed.end(); };
    if (map.has("time_s") && ok("time_s")) {
      if (previous_time && keyframe.time <= *previous_time) {
        map.optional("time_s")->error("must be greater than the previous time_s (" + format_number(*previous_time) +
                                      ") (got " + map.optional("time_s")->node().Scalar() + ")");
      }
      previous_time = keyframe.time;  // compare the next entry with this one, so one misplaced entry is one error
    }
    if (const auto setpoints = map.optional("setpoints")) {
      // Cross-file check: the count comes from the (possibly included) vehicle definition.
      const std::size_t count = setpoints->node().size();
      if (setpoints->node().IsSequence() && definition && definition->control_count &&
          count != *definition->control_count) {
        const std::string names =
            definition->control_names ? " (" + join_names(*definition->control_names) + ")" : "";
        setpoints->error("expected " + std::to_string(*definition->control_count) +
                         " setpoints, one per actuator" + names + " (got " + std::to_string(count) + ")");
      } else if (ok("setpoints") && !keyframe.setpoints.empty() && definition && definition->control_count &&
                 keyframe.setpoints.size() == *definition->control_count) {
        // Each actuator's own check (a drop weight's 0 or 1), as for a command at run time.
        std::size_t failed_index = 0;
        const std::string reason =
            physics::check_actuator_controls(definition->actuators, keyframe.setpoints, &failed_index);
        if (!reason.empty()) setpoints->error(reason + " (" + definition->actuators[failed_index].name + ")");
      }
    }
    schedule->push_back(std::move(keyframe));
  }
}

}  // namespace

std::vector<AssetRoot> asset_roots(const std::string& scenario_path, const LoadOptions& options) {
  namespace fs = std::filesystem;
  std::vector<AssetRoot> roots;
  // A configured root that is not a directory is an error; a default one that is not is left out.
  auto add = [&](const fs::path& dir, const std::string& origin, bool configured) {
    AssetRoot root{dir.string(), origin, ""};
    std::error_code ec;
    const fs::path real = fs::canonical(fs::absolute(dir, ec), ec);
    if (ec || !fs::is_directory(real, ec)) {
      if (!configured) return;
      root.error = "is not a directory";
    } else {
      root.path = real.string();
    }
    roots.push_back(std::move(root));
  };
  // The scenario's tree: its directory, or, in the layout of configs/ (scenarios/, vehicles/, meshes/ side by
  // side), the directory holding scenarios/.
  std::error_code ec;
  fs::path tree = fs::weakly_canonical(fs::absolute(scenario_path, ec), ec).parent_path();
  if (tree.filename() == "scenarios") tree = tree.parent_path();
  add(tree, "the scenario's tree", false);
  // hadal's own configs: installed (or $HADAL_DATA_DIR's), else the source tree's.
  const std::optional<DataDir> data = installed_data_dir();
  if (data && (data->from_environment || fs::is_directory(data->path / "configs", ec))) {
    add(data->path / "configs", data->from_environment ? "hadal's configs, $HADAL_DATA_DIR/configs" : "hadal's configs",
        false);
  } else {
    add(fs::path(HADAL_SOURCE_CONFIGS_DIR), "hadal's configs", false);
  }
  for (const std::string& dir : options.asset_roots) add(dir, "--asset-root", true);
  if (const char* list = std::getenv("HADAL_ASSET_ROOTS"); list != nullptr) {
    std::string text = list;
    for (std::size_t start = 0; start <= text.size();) {
      const std::size_t end = std::min(text.find(':', start), text.size());
      if (end > start) add(text.substr(start, end - start), "$HADAL_ASSET_ROOTS", true);
      start = end + 1;
    }
  }
  return roots;
}

LoadResult load_scenario_file(const std::string& path, const LoadOptions& options) {
  ScenarioLoader loader;
  return loader.load(path, options);
}

}  // namespace hadal::config
