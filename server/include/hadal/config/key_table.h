// Keys declared once (docs/ARCHITECTURE.md, "Keys: one declaration each"). A KeyTable<T> lists the
// keys of one YAML map: for each its name, type, unit, default (read off a default T), range, meaning
// and where it goes in T. From that one list come the strict reader (unknown keys with "did you mean",
// wrong types, ranges, required keys, keys another type does not use: all collected, at file:line:col),
// the key table of configs/REFERENCE.md and the JSON Schema (config/key_doc.h, config/scenario_schema.h).
//
//   const KeyTable<AcousticsSpec>& acoustics_keys() {
//     return declare_keys<AcousticsSpec>([](KeyTable<AcousticsSpec>& t) {
//       t.describe("world.acoustics", "what sonars hear");
//       t.number("seabed_backscatter_db", &AcousticsSpec::seabed_backscatter_db)
//           .unit("dB").range(Range::closed(-80.0, 0.0)).doc("Lambert's mu of the seabed");
//     });
//   }
//
// Where a key goes: a member pointer (&Spec::field) or a function Spec& -> field& (a lambda), so a key
// may fill a nested struct. A field may be std::optional<X>: the key then sets it when given.
// Units: a key reads in its YAML unit; `degrees()` (and `convert()`) turn it into SI on the way in, and
// the reference shows the default in the YAML's unit. Keys are read in declaration order (a preset
// before the keys that override it), the table's selector first; checks run after every key.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "hadal/config/key_doc.h"
#include "hadal/config/key_table_fwd.h"
#include "hadal/config/preset.h"
#include "hadal/config/yaml_reader.h"
#include "hadal/core/units.h"

namespace hadal::config {

struct NoContext {};

// What scenario-level readers know besides their map: the physics rate (a rate key may not exceed it;
// nullopt when world.physics_rate_hz is invalid), the world's seed and its water surface.
struct LoadContext {
  std::optional<double> physics_rate_hz = 500.0;
  std::uint64_t world_seed = 0;
  double water_surface_z = 0.0;  // world.water.surface_z, once the world is read [m]
};

// R = Rz(yaw) Ry(pitch) Rx(roll), angles in radians.
Eigen::Matrix3d rotation_from_rpy(const Eigen::Vector3d& rpy);
// {position: [x, y, z], rpy_deg: [roll, pitch, yaw]}, both optional: X (identity rotation, zero position
// for what is not given). False after reporting.
bool read_pose(const Value& value, Eigen::Isometry3d* X);

// What a table's checks see after its keys were read: the map, and which keys failed.
class KeyReads {
 public:
  KeyReads(const MapReader& map, const std::vector<std::string>& failed) : map_(map), failed_(failed) {}
  const MapReader& map() const { return map_; }
  bool has(const std::string& key) const { return map_.has(key); }
  // The key was read without error (given and valid, or absent and optional).
  bool ok(const std::string& key) const;
  bool all_ok() const { return failed_.empty(); }
  void error_at_key(const std::string& key, const std::string& message) const { map_.error_at_key(key, message); }

 private:
  const MapReader& map_;
  const std::vector<std::string>& failed_;
};

namespace key_detail {
template <class X>
struct Unoptional {
  using type = X;
};
template <class X>
struct Unoptional<std::optional<X>> {
  using type = X;
};
template <class X>
struct IsOptional : std::false_type {};
template <class X>
struct IsOptional<std::optional<X>> : std::true_type {};

// The field a key writes, given its accessor.
template <class T, class A>
using Slot = std::remove_reference_t<std::invoke_result_t<const A&, T&>>;
template <class T, class A>
using FieldValue = typename Unoptional<Slot<T, A>>::type;

// Whether a context knows the physics rate (LoadContext, VehicleContext): a rate key is bounded by it.
template <class C, class = void>
struct HasPhysicsRate : std::false_type {};
template <class C>
struct HasPhysicsRate<C, std::void_t<decltype(std::declval<C&>().physics_rate_hz)>> : std::true_type {};

std::string format_default(double si, double (*from_si)(double), bool approximate);
// A degree key (`*_deg`) given radians is accepted and wrong by a factor 57: warns at `value` when every
// non-zero angle lies within ±2π and one of them is a common angle in radians (a multiple of π/12 = 15°
// within 0.002, not itself a whole number of degrees: 1.5708, 0.7854, 3.1416), e.g. rpy_deg: [0, 0, 1.5708].
// A plain small angle in degrees (a 5° pitch, a 1° beam) is not one.
void warn_if_radians(const Value& value, const double* degrees, std::size_t count);
std::string format_numbers(const double* values, std::size_t count);
}  // namespace key_detail

template <class T, class Ctx>
class KeyTable {
  struct Entry;

 public:
  using ReadKey = std::function<bool(const MapReader& map, const Entry& entry, T& out, Ctx& ctx)>;
  using DefaultOf = std::function<std::string(const Entry& entry, T& defaults)>;
  // Custom key: reads `value` (present) into `out`; false after reporting.
  using ReadValue = std::function<bool(const Value& value, T& out, Ctx& ctx)>;
  // Check after all keys: reports and returns false when the keys do not fit together.
  using Check = std::function<bool(const KeyReads& reads, T& out, Ctx& ctx)>;
  using Note = std::function<std::string(const MapReader& map, const T& out)>;

  // A declared key, to state its attributes: t.number("z", &S::z).unit("m").doc("...").
  class Key {
   public:
    Key& unit(std::string text) { return set([&](Entry& e) { e.doc.unit = std::move(text); }); }
    Key& doc(std::string text) { return set([&](Entry& e) { e.doc.doc = std::move(text); }); }
    // Numbers, and each number of a list.
    Key& range(const Range& r) { return set([&](Entry& e) { e.doc.range = r; }); }
    Key& required(std::string why = "") {
      return set([&](Entry& e) {
        e.doc.required = true;
        e.doc.required_why = std::move(why);
      });
    }
    Key& only_for(std::vector<std::string> values) { return set([&](Entry& e) { e.doc.only_for = std::move(values); }); }
    Key& required_for(std::vector<std::string> values, std::string why = "") {
      return set([&](Entry& e) {
        e.doc.required_for = std::move(values);
        e.doc.required_why = std::move(why);
      });
    }
    Key& default_text(std::string text) {
      return set([&](Entry& e) {
        e.doc.default_text = std::move(text);
        e.default_of = nullptr;
        e.doc.default_choice.clear();
        e.default_is_contextual = true;
      });
    }
    // A choice whose default the defaults' field does not hold (a preset applied unless another is given).
    Key& default_choice(std::string name) {
      return set([&](Entry& e) {
        e.doc.default_text = "`" + name + "`";
        e.default_of = nullptr;
        e.doc.default_choice = std::move(name);
        e.default_is_contextual = true;
      });
    }
    // The YAML value is in degrees; the field holds radians.
    Key& degrees() {
      return set([&](Entry& e) {
        e.doc.unit = "deg";
        e.to_si = [](double deg) { return deg * kDegToRad; };
        e.from_si = [](double rad) { return to_degrees(rad); };
      });
    }
    // The YAML value in `yaml_unit` becomes the field's SI value by to_si (and back by from_si for the
    // reference's default).
    Key& convert(double (*to_si)(double), double (*from_si)(double), std::string yaml_unit) {
      return set([&](Entry& e) {
        e.to_si = to_si;
        e.from_si = from_si;
        e.doc.unit = std::move(yaml_unit);
      });
    }
    // A rule the range column adds ("<= world.physics_rate_hz", "strictly increasing").
    Key& rule(std::string text) { return set([&](Entry& e) { e.doc.rule = std::move(text); }); }
    Key& json(std::string schema) { return set([&](Entry& e) { e.doc.json = std::move(schema); }); }
    Key& type_text(std::string text) { return set([&](Entry& e) { e.doc.type_text = std::move(text); }); }
    // A list: at least n entries ("needs at least n <word> (got m)"; "must not be empty" for 1).
    Key& min_items(std::size_t n, std::string word = "entries") {
      return set([&](Entry& e) {
        e.doc.min_items = n;
        e.item_word = std::move(word);
      });
    }
    // A custom key whose value is a list of maps of `table`'s keys: shown (reference, schema) as that list.
    template <class S, class C>
    Key& items_of(const KeyTable<S, C>& table) {
      return set([&](Entry& e) {
        e.doc.type = KeyType::kList;
        e.table_of = [&table]() -> const TableDoc& { return table.doc(); };
      });
    }
    // A custom key whose value is a map of `table`'s keys: shown (reference, schema) as that map.
    template <class S, class C>
    Key& keys_of(const KeyTable<S, C>& table) {
      return set([&](Entry& e) {
        e.doc.type = KeyType::kMap;
        e.table_of = [&table]() -> const TableDoc& { return table.doc(); };
      });
    }
    // The key is not read when `other` is given (the table's checks say what the two together mean); a
    // required key is then not required.
    Key& unless(std::string other) { return set([&](Entry& e) { e.doc.unless = std::move(other); }); }
    // A required key that may be left out when `other` is given (the two may also come together: a
    // vehicle's `links` and its `urdf`).
    Key& optional_with(std::string other) { return set([&](Entry& e) { e.doc.optional_with = std::move(other); }); }
    // The key is read by the table's owner (a vehicle entry's `include`: it decides what the other keys
    // mean); the table describes it and allows it.
    Key& read_elsewhere() {
      return set([&](Entry& e) {
        // A missing required key is still reported here.
        e.read = [](const MapReader& map, const Entry& entry, T&, Ctx&) {
          return !entry.doc.required || map.has(entry.doc.name) || (map.required(entry.doc.name), false);
        };
      });
    }
    // A list: entries with errors (reported) are left out instead of kept in their place.
    Key& drop_invalid() { return set([&](Entry& e) { e.drop_invalid = true; }); }
    // Reads the key's value (present) with `f` instead of by its type; the description stays.
    Key& read_with(ReadValue f) {
      return set([&](Entry& e) {
        e.read = [f = std::move(f)](const MapReader& map, const Entry& entry, T& out, Ctx& ctx) {
          const std::optional<Value> value = entry.get(map);
          if (!value) return !entry.doc.required;
          return f(*value, out, ctx);
        };
      });
    }
    // Called after the key was read when it is given (ok: without error), e.g. to pass its value on to
    // later keys through the context.
    Key& on_read(std::function<void(T&, Ctx&, bool ok)> f) { return set([&](Entry& e) { e.on_read = std::move(f); }); }
    // This choice decides which keys apply (their only_for); `phrase` names it in messages ("seabed type").
    Key& selects(std::string phrase) {
      table_->selector_ = index_;
      table_->doc_.selector_phrase = std::move(phrase);
      return set([&](Entry& e) { e.doc.selector = true; });
    }

   private:
    friend class KeyTable;
    Key(KeyTable* table, std::size_t index) : table_(table), index_(index) {}
    template <class F>
    Key& set(F&& f) {
      f(table_->entries_[index_]);
      return *this;
    }
    KeyTable* table_;
    std::size_t index_;
  };

  explicit KeyTable(std::string id, std::string title = "", T defaults = T{})
      : defaults_(std::make_shared<T>(std::move(defaults))) {
    doc_.id = std::move(id);
    doc_.title = std::move(title);
  }
  // Built once, kept in a function-local static: nested tables are referred to, never copied.
  KeyTable(const KeyTable&) = delete;
  KeyTable& operator=(const KeyTable&) = delete;
  KeyTable(KeyTable&&) = default;

  // --- declarations ----------------------------------------------------------------------------------

  // The table's id (its reference marker and JSON Schema definition: "world.water") and a one-line title.
  void describe(std::string id, std::string title = "") {
    doc_.id = std::move(id);
    doc_.title = std::move(title);
  }

  // A number (double or int field; an int field takes whole numbers only).
  template <class A>
  Key number(std::string name, A access) {
    using V = key_detail::FieldValue<T, A>;
    static_assert(std::is_same_v<V, double> || std::is_same_v<V, int>, "number(): a double or int field");
    Key key = add(std::move(name), KeyType::kNumber,
                  [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<double> x = value->number(e.doc.range);
                    if (!x) return false;
                    if (e.doc.whole && *x != std::floor(*x)) {
                      value->error("must be a whole number (got " + format_number(*x) + ")");
                      return false;
                    }
                    if (e.doc.unit == "deg") key_detail::warn_if_radians(*value, &*x, 1);
                    std::invoke(access, out) = static_cast<V>(e.to_si ? e.to_si(*x) : *x);
                    return true;
                  },
                  [access](const Entry& e, T& defaults) -> std::string {
                    const auto& slot = std::invoke(access, defaults);
                    if constexpr (key_detail::IsOptional<key_detail::Slot<T, A>>::value) {
                      if (!slot) return "none";
                      return key_detail::format_default(static_cast<double>(*slot), e.from_si, e.from_si != nullptr);
                    } else {
                      return key_detail::format_default(static_cast<double>(slot), e.from_si, e.from_si != nullptr);
                    }
                  });
    if constexpr (std::is_same_v<V, int>) entries_.back().doc.whole = true;
    return key;
  }

  // A rate [Hz]: > 0 and at most the physics rate when the context knows it (LoadContext, VehicleContext).
  template <class A>
  Key rate_hz(std::string name, A access) {
    Key key = add(std::move(name), KeyType::kNumber,
                  [access](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<double> rate = value->number(Range::positive());
                    if (!rate) return false;
                    if constexpr (key_detail::HasPhysicsRate<Ctx>::value) {
                      if (ctx.physics_rate_hz && *rate > *ctx.physics_rate_hz) {
                        value->error("must be <= world.physics_rate_hz (" + format_number(*ctx.physics_rate_hz) +
                                     ") (got " + value->node().Scalar() + ")");
                        return false;
                      }
                    }
                    std::invoke(access, out) = *rate;
                    return true;
                  },
                  [access](const Entry&, T& defaults) { return format_number(std::invoke(access, defaults)); });
    entries_.back().doc.unit = "Hz";
    entries_.back().doc.range = Range::positive();
    entries_.back().doc.rule = "<= `world.physics_rate_hz`";
    return key;
  }

  // A number handed to `set` with the context (a per-sample figure the sample rate turns into a noise
  // density, say); `get` gives the default for the reference, in the YAML's unit (null: "none").
  Key number_into(std::string name, std::function<void(T&, double, Ctx&)> set, std::function<double(T&)> get) {
    return add(std::move(name), KeyType::kNumber,
               [set](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 const std::optional<double> x = value->number(e.doc.range);
                 if (!x) return false;
                 set(out, *x, ctx);
                 return true;
               },
               [get](const Entry&, T& defaults) -> std::string {
                 return get ? format_approximate(get(defaults)) : std::string("none");
               });
  }

  // A `preset` key: the id of one of `presets` ("unknown <what> preset 'x' (presets: 'a', 'b')"); `apply`
  // copies its figures into the spec, before the keys declared after it override them. The reference
  // lists every preset's product and source under the table.
  template <class Figures>
  Key preset(std::string what, const Presets<Figures>& presets,
             std::type_identity_t<std::function<void(T&, const Preset<Figures>&, Ctx&)>> apply) {
    Key key = add("preset", KeyType::kChoice,
                  [what, &presets, apply](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<std::string> id = value->string();
                    if (!id) return false;
                    if (const Preset<Figures>* preset = find_preset(presets, *id)) {
                      apply(out, *preset, ctx);
                      return true;
                    }
                    std::vector<std::string> listed;
                    for (const Preset<Figures>& p : presets) listed.push_back(config::quoted(std::string(p.id)));
                    value->error("unknown " + what + " preset " + config::quoted(*id) + " (presets: " +
                                 join_names(listed) + ")");
                    return false;
                  },
                  [](const Entry&, T&) -> std::string { return "none"; });
    for (const Preset<Figures>& p : presets) {
      entries_.back().doc.choices.push_back({std::string(p.id), std::string(p.product), std::string(p.source)});
    }
    return key;
  }

  // An integer 0 .. 2^64-1 (std::uint64_t field).
  template <class A>
  Key unsigned_integer(std::string name, A access) {
    return add(std::move(name), KeyType::kUnsigned,
               [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 const std::optional<std::uint64_t> n = value->non_negative_integer();
                 if (n) std::invoke(access, out) = *n;
                 return n.has_value();
               },
               [access](const Entry&, T& defaults) { return std::to_string(std::invoke(access, defaults)); });
  }

  template <class A>
  Key boolean(std::string name, A access) {
    return add(std::move(name), KeyType::kBoolean,
               [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 const std::optional<bool> b = value->boolean();
                 if (b) std::invoke(access, out) = *b;
                 return b.has_value();
               },
               [access](const Entry&, T& defaults) -> std::string {
                 const auto& slot = std::invoke(access, defaults);
                 if constexpr (key_detail::IsOptional<key_detail::Slot<T, A>>::value) {
                   return slot ? (*slot ? "true" : "false") : "none";
                 } else {
                   return slot ? "true" : "false";
                 }
               });
  }

  // A non-empty string.
  template <class A>
  Key string(std::string name, A access) {
    return add(std::move(name), KeyType::kString,
               [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 const std::optional<std::string> s = value->string();
                 if (s) std::invoke(access, out) = *s;
                 return s.has_value();
               },
               [access](const Entry&, T& defaults) -> std::string {
                 const auto& slot = std::invoke(access, defaults);
                 if constexpr (key_detail::IsOptional<key_detail::Slot<T, A>>::value) {
                   return slot ? "`" + *slot + "`" : "none";
                 } else {
                   return slot.empty() ? "none" : "`" + slot + "`";
                 }
               });
  }

  // A file named relative to the file that names it, inside the scenario's roots (Value::file_path); the
  // field gets the resolved path.
  template <class A>
  Key file(std::string name, A access) {
    return add(std::move(name), KeyType::kFile,
               [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 const std::optional<std::string> written = value->string();
                 std::string path;
                 if (!written || !value->file_path(*written, &path)) return false;
                 std::invoke(access, out) = path;
                 return true;
               },
               [](const Entry&, T&) -> std::string { return "none"; });
  }

  // One of named values (an enum, a bool, an int): t.choice("type", &S::type, {{"plane", Type::kPlane,
  // "an infinite horizontal plane"}, ...}). Several names may stand for one value (aliases).
  template <class E>
  struct Named {
    std::string name;
    E value;
    std::string doc = "";
  };
  template <class A>
  Key choice(std::string name, A access, std::vector<Named<key_detail::FieldValue<T, A>>> choices) {
    using E = key_detail::FieldValue<T, A>;
    auto list = std::make_shared<std::vector<std::pair<std::string, E>>>();
    std::vector<KeyChoice> docs;
    for (auto& c : choices) {
      list->emplace_back(c.name, c.value);
      docs.push_back({c.name, c.doc, ""});
    }
    Key key = add(std::move(name), KeyType::kChoice,
                  [access, list](const MapReader& map, const Entry& e, T& out, Ctx&) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<E> chosen = value->choice(*list);
                    if (chosen) std::invoke(access, out) = *chosen;
                    return chosen.has_value();
                  },
                  [access, list](const Entry&, T& defaults) -> std::string {
                    const auto& slot = std::invoke(access, defaults);
                    for (const auto& [choice_name, value] : *list) {
                      if (slot == value) return "`" + choice_name + "`";
                    }
                    return "none";
                  });
    Entry& entry = entries_.back();
    entry.doc.choices = std::move(docs);
    entry.name_of = [access, list](const T& t) -> std::string {
      const auto& slot = std::invoke(access, const_cast<T&>(t));
      for (const auto& [choice_name, value] : *list) {
        if (slot == value) return choice_name;
      }
      return "";
    };
    return key;
  }

  // A list of numbers into an Eigen vector or array of fixed size N (N numbers), each in range().
  template <class A>
  Key vector(std::string name, A access) {
    using V = key_detail::FieldValue<T, A>;
    static constexpr int kSize = V::SizeAtCompileTime;
    static_assert(kSize > 0, "vector(): a fixed-size Eigen vector or array");
    Key key = add(std::move(name), KeyType::kNumbers,
                  [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<std::vector<double>> values = value->numbers(kSize, e.doc.range);
                    if (!values) return false;
                    if (e.doc.unit == "deg") key_detail::warn_if_radians(*value, values->data(), values->size());
                    V v;
                    for (int i = 0; i < kSize; ++i) v[i] = e.to_si ? e.to_si((*values)[i]) : (*values)[i];
                    std::invoke(access, out) = v;
                    return true;
                  },
                  [access](const Entry& e, T& defaults) -> std::string {
                    const auto& slot = std::invoke(access, defaults);
                    const V* v = nullptr;
                    if constexpr (key_detail::IsOptional<key_detail::Slot<T, A>>::value) {
                      if (!slot) return "none";
                      v = &*slot;
                    } else {
                      v = &slot;
                    }
                    double values[kSize];
                    for (int i = 0; i < kSize; ++i) values[i] = e.from_si ? e.from_si((*v)[i]) : (*v)[i];
                    return key_detail::format_numbers(values, kSize);
                  });
    entries_.back().doc.count = kSize;
    return key;
  }

  // A list of `count` numbers (any count when 0), each in range(), handed to `set` (two fields, say);
  // `get` gives the defaults for the reference (empty: "none").
  Key numbers(std::string name, std::size_t count, std::function<void(T&, const std::vector<double>&)> set,
              std::function<std::vector<double>(T&)> get) {
    Key key = add(std::move(name), KeyType::kNumbers,
                  [set, count](const MapReader& map, const Entry& e, T& out, Ctx&) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<std::vector<double>> values =
                        value->numbers(count > 0 ? std::optional<std::size_t>(count) : std::nullopt, e.doc.range);
                    if (!values) return false;
                    if (e.doc.unit == "deg") key_detail::warn_if_radians(*value, values->data(), values->size());
                    std::vector<double> si = *values;
                    if (e.to_si) {
                      for (double& x : si) x = e.to_si(x);
                    }
                    set(out, si);
                    return true;
                  },
                  [get](const Entry& e, T& defaults) -> std::string {
                    std::vector<double> values = get ? get(defaults) : std::vector<double>();
                    if (values.empty()) return "none";
                    if (e.from_si) {
                      for (double& x : values) x = e.from_si(x);
                    }
                    return key_detail::format_numbers(values.data(), values.size());
                  });
    entries_.back().doc.count = count;
    return key;
  }

  // A non-zero 3-vector, stored normalised ("must be non-zero" below 1e-9).
  template <class A>
  Key direction(std::string name, A access) {
    Key key = add(std::move(name), KeyType::kNumbers,
                  [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                    if (!map.has(e.doc.name) && !e.doc.required) return true;
                    Eigen::Vector3d v;
                    if (!map.read_direction(e.doc.name, e.doc.required ? Need::kRequired : Need::kOptional, &v)) {
                      return false;
                    }
                    std::invoke(access, out) = v;
                    return true;
                  },
                  [access](const Entry&, T& defaults) -> std::string {
                    const Eigen::Vector3d v = std::invoke(access, defaults);
                    return key_detail::format_numbers(v.data(), 3);
                  });
    entries_.back().doc.count = 3;
    entries_.back().doc.type_text = "direction";
    return key;
  }

  // {position, rpy_deg} into an Eigen::Isometry3d.
  template <class A>
  Key pose(std::string name, A access) {
    return add(std::move(name), KeyType::kPose,
               [access](const MapReader& map, const Entry& e, T& out, Ctx&) {
                 const std::optional<Value> value = e.get(map);
                 if (!value) return !e.doc.required;
                 Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
                 if (!read_pose(*value, &X)) return false;
                 std::invoke(access, out) = X;
                 return true;
               },
               [access](const Entry&, T& defaults) -> std::string {
                 const Eigen::Isometry3d& X = std::invoke(access, defaults);
                 return X.matrix().isIdentity(0.0) ? "identity" : "given";
               })
        .unit("m, deg");
  }

  // A nested map read by `table` into a field. The nested table reads with this table's context, or
  // with none.
  template <class A, class S, class C>
  Key map(std::string name, A access, const KeyTable<S, C>& table) {
    Key key = add(std::move(name), KeyType::kMap,
                  [access, &table](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    auto& slot = std::invoke(access, out);
                    if constexpr (key_detail::IsOptional<std::remove_reference_t<decltype(slot)>>::value) {
                      S s = slot ? *slot : table.defaults();
                      const bool ok = table.read(*value, &s, child_context<C>(ctx));
                      if (ok) slot = std::move(s);
                      return ok;
                    } else {
                      return table.read(*value, &slot, child_context<C>(ctx));
                    }
                  },
                  [](const Entry&, T&) -> std::string { return ""; });
    entries_.back().table_of = [&table]() -> const TableDoc& { return table.doc(); };
    return key;
  }

  // A list of maps, each read by `table` into an element appended to a std::vector field. Every element
  // is appended, also one with errors (reported), so that indices keep their meaning.
  template <class A, class S, class C>
  Key list(std::string name, A access, const KeyTable<S, C>& table) {
    Key key = add(std::move(name), KeyType::kList,
                  [access, &table](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    const std::optional<std::vector<Value>> items = value->list();
                    if (!items) return false;
                    bool ok = true;
                    if (items->size() < e.doc.min_items) {
                      value->error(e.doc.min_items == 1 ? std::string("must not be empty")
                                                        : "needs at least " + std::to_string(e.doc.min_items) + " " +
                                                              e.item_word + " (got " + std::to_string(items->size()) +
                                                              ")");
                      ok = false;
                    }
                    auto& slot = std::invoke(access, out);
                    for (const Value& item : *items) {
                      S s = table.defaults();
                      const bool item_ok = table.read(item, &s, child_context<C>(ctx));
                      ok &= item_ok;
                      if (item_ok || !e.drop_invalid) slot.push_back(std::move(s));
                    }
                    return ok;
                  },
                  [](const Entry&, T&) -> std::string { return "none"; });
    entries_.back().table_of = [&table]() -> const TableDoc& { return table.doc(); };
    return key;
  }

  // A key's former name: given, it is an error naming the key that replaced it (and why).
  Key renamed(std::string old_name, std::string new_name, std::string why = "") {
    const std::string message = "key " + config::quoted(old_name) + " was renamed " + config::quoted(new_name) +
                                (why.empty() ? "" : " (" + why + ")");
    Key key = add(std::move(old_name), KeyType::kCustom,
                  [message](const MapReader& map, const Entry& e, T&, Ctx&) {
                    if (!map.has(e.doc.name)) return true;
                    map.error_at_key(e.doc.name, message);
                    return false;
                  },
                  [](const Entry&, T&) -> std::string { return ""; });
    entries_.back().doc.renamed_to = std::move(new_name);
    entries_.back().doc.doc = message;
    return key;
  }

  // A key with its own reader (called when the key is present), its JSON Schema and its reference type.
  Key custom(std::string name, ReadValue read, std::string json_schema, std::string type) {
    Key key = add(std::move(name), KeyType::kCustom,
                  [read = std::move(read)](const MapReader& map, const Entry& e, T& out, Ctx& ctx) {
                    const std::optional<Value> value = e.get(map);
                    if (!value) return !e.doc.required;
                    return read(*value, out, ctx);
                  },
                  [](const Entry&, T&) -> std::string { return "none"; });
    entries_.back().doc.json = std::move(json_schema);
    entries_.back().doc.type_text = std::move(type);
    return key;
  }

  // Called before the keys are read (the map is a map): e.g. to put the defaults into the context.
  void before(std::function<void(T&, Ctx&)> f) { before_ = std::move(f); }
  // A check of keys that must fit together, run after every key was read.
  void check(Check f) { checks_.push_back(std::move(f)); }
  // Appended to "key 'x' is not used by <selector> 'y'" (why the default selection is what it is).
  void unused_note(Note f) { note_ = std::move(f); }
  // Keys the map may hold besides the table's own, read by someone else (a sensor entry's kind keys).
  void allow_keys(const std::vector<std::string>& keys) { extra_keys_.insert(extra_keys_.end(), keys.begin(), keys.end()); }
  // Keys of another table in the same map (an actuator entry: name and link, then its kind's keys), read
  // after this table's own by `read` (which calls table.read_map with what it binds them to); without
  // `read`, the table's owner reads them (a vehicle entry's inline definition).
  template <class S, class C, class F>
  void part(const KeyTable<S, C>& table, F read) {
    parts_.push_back({"", table.names(), [&table]() -> const TableDoc& { return table.doc(); },
                      [&table, read = std::move(read)](const MapReader& map, T& out, Ctx& ctx) {
                        return read(map, table, out, ctx);
                      }});
  }
  template <class S, class C>
  void part(const KeyTable<S, C>& table) {
    parts_.push_back({"", table.names(), [&table]() -> const TableDoc& { return table.doc(); },
                      [](const MapReader&, T&, Ctx&) { return true; }, true});
  }
  // The keys of the variant `value` of this table's selector (a sensor entry's `type`): read after this
  // table's own, like a part, when the selector says `value`; keys of the other variants are then errors
  // ("key 'x' is not used by sensor type 'y'").
  template <class S, class C, class F>
  void variant(std::string value, const KeyTable<S, C>& table, F read) {
    variants_.push_back({std::move(value), table.names(), [&table]() -> const TableDoc& { return table.doc(); },
                         [&table, read = std::move(read)](const MapReader& map, T& out, Ctx& ctx) {
                           return read(map, table, out, ctx);
                         }});
  }


  // --- use -------------------------------------------------------------------------------------------

  // The key names, in declaration order, then the extra ones.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    const auto add = [&out](const std::string& name) {
      if (!contains(out, name)) out.push_back(name);
    };
    for (const Entry& e : entries_) add(e.doc.name);
    for (const Part& part : parts_) {
      for (const std::string& name : part.names) add(name);
    }
    for (const Part& variant : variants_) {
      for (const std::string& name : variant.names) add(name);
    }
    for (const std::string& name : extra_keys_) add(name);
    return out;
  }

  // Reads the map `value` into *out (whose fields not given keep their values: the defaults, or what the
  // caller set). False when something was reported.
  bool read(const Value& value, T* out, Ctx& ctx) const {
    const MapReader map(value, names());
    if (!map.ok()) return false;
    return read_map(map, out, ctx);
  }
  bool read(const Value& value, T* out) const {
    static_assert(std::is_same_v<Ctx, NoContext>, "this table reads with a context");
    NoContext none;
    return read(value, out, none);
  }

  // Reads the table's keys from `map` (already checked for unknown keys by its owner).
  // `failed` (optional) receives the keys that were reported.
  bool read_map(const MapReader& map, T* out, Ctx& ctx, std::vector<std::string>* failed_keys = nullptr) const {
    bool ok = true;
    std::vector<std::string> local_failed;
    std::vector<std::string>& failed = failed_keys ? *failed_keys : local_failed;
    std::optional<std::string> selected;  // nullopt: no selector, or an invalid one
    if (before_) before_(*out, ctx);
    if (selector_) {
      const Entry& s = entries_[*selector_];
      if (s.read(map, s, *out, ctx)) {
        selected = map.has(s.doc.name) ? map.optional(s.doc.name)->node().Scalar() : s.name_of(*out);
      } else {
        ok = false;
        failed.push_back(s.doc.name);
      }
    }
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (selector_ && i == *selector_) continue;
      const Entry& e = entries_[i];
      const KeyDoc& k = e.doc;
      if (!k.unless.empty() && map.allows(k.unless) && map.has(k.unless)) continue;
      if (!k.optional_with.empty() && map.allows(k.optional_with) && map.has(k.optional_with) && !map.has(k.name)) {
        continue;
      }
      if (!k.only_for.empty() || !k.required_for.empty()) {
        if (!selected) continue;  // the selector is invalid (reported): keys that depend on it are not read
      }
      if (!k.only_for.empty() && !contains(k.only_for, *selected)) {
        if (map.has(k.name)) {
          map.error_at_key(k.name, "key " + config::quoted(k.name) + " is not used by " + doc_.selector_phrase + " " +
                                       config::quoted(*selected) + (note_ ? note_(map, *out) : ""));
          ok = false;
          failed.push_back(k.name);
        }
        continue;
      }
      if (selected && contains(k.required_for, *selected) && !map.has(k.name)) {
        map.required(k.name, k.required_why.empty() ? "needed by " + doc_.selector_phrase + " " + config::quoted(*selected)
                                                    : k.required_why);
        ok = false;
        failed.push_back(k.name);
        continue;
      }
      const bool key_ok = e.read(map, e, *out, ctx);
      if (!key_ok) {
        ok = false;
        failed.push_back(k.name);
      }
      if (e.on_read && map.has(k.name)) e.on_read(*out, ctx, key_ok);
    }
    for (const Part& part : parts_) ok &= part.read(map, *out, ctx);
    if (!variants_.empty() && selected) ok &= read_variant(map, *selected, *out, ctx);
    const KeyReads reads(map, failed);
    for (const Check& f : checks_) ok &= f(reads, *out, ctx);
    return ok;
  }

  // Reads only `keys` of the table from `map` (no selector, no checks): an entry that adds to what an
  // included file defined (a vehicle entry's sensors and lights).
  bool read_only(const MapReader& map, T* out, Ctx& ctx, const std::vector<std::string>& keys) const {
    bool ok = true;
    for (const Entry& e : entries_) {
      if (contains(keys, e.doc.name)) ok &= e.read(map, e, *out, ctx);
    }
    return ok;
  }

  const T& defaults() const { return *defaults_; }

  // The description of the keys, defaults filled in (made on first use).
  const TableDoc& doc() const {
    std::call_once(doc_once_->flag, [this] {
      TableDoc& d = doc_once_->doc;
      d = doc_;
      d.keys.clear();
      T defaults = *defaults_;
      for (const Entry& e : entries_) {
        KeyDoc k = e.doc;
        if (!e.default_is_contextual) {
          if (k.required) {
            k.default_text = k.optional_with.empty() ? "required" : "required (unless `" + k.optional_with + "`)";
          } else if (!k.required_for.empty()) {
            k.default_text = "required for " + join_values(k.required_for);
          } else if (e.default_of) {
            k.default_text = e.default_of(e, defaults);
          }
          if (k.type == KeyType::kChoice && e.name_of) k.default_choice = e.name_of(defaults);
        }
        if (e.table_of) k.table = &e.table_of();
        d.keys.push_back(std::move(k));
      }
      for (const Part& part : parts_) {
        for (KeyDoc key : part.doc().keys) {
          if (part.read_elsewhere) key.described_in = part.doc().id;
          d.keys.push_back(std::move(key));
        }
      }
      for (const Part& variant : variants_) d.variants.push_back({variant.value, &variant.doc()});
    });
    return doc_once_->doc;
  }

 private:
  struct Entry {
    KeyDoc doc;
    ReadKey read;
    DefaultOf default_of;
    std::function<std::string(const T&)> name_of;  // kChoice: the name of a value
    std::function<const TableDoc&()> table_of;     // kMap, kList
    double (*to_si)(double) = nullptr;
    double (*from_si)(double) = nullptr;
    bool default_is_contextual = false;
    std::function<void(T&, Ctx&, bool)> on_read;
    std::string item_word = "entries";
    bool drop_invalid = false;

    std::optional<Value> get(const MapReader& map) const {
      return doc.required ? map.required(doc.name, doc.required_why) : map.optional(doc.name);
    }
  };
  struct DocOnce {
    std::once_flag flag;
    TableDoc doc;
  };

  Key add(std::string name, KeyType type, ReadKey read, DefaultOf default_of) {
    Entry e;
    e.doc.name = std::move(name);
    e.doc.type = type;
    e.read = std::move(read);
    e.default_of = std::move(default_of);
    entries_.push_back(std::move(e));
    return Key(this, entries_.size() - 1);
  }
  // Reads the keys of the variant `selected`; reports the keys of the other variants it does not share.
  bool read_variant(const MapReader& map, const std::string& selected, T& out, Ctx& ctx) const {
    const Part* chosen = nullptr;
    for (const Part& variant : variants_) {
      if (variant.value == selected) chosen = &variant;
    }
    if (chosen == nullptr) return true;  // the selector's own choices were checked when it was read
    bool ok = chosen->read(map, out, ctx);
    std::vector<std::string> reported;  // a key of several other variants is reported once
    for (const Part& other : variants_) {
      if (&other == chosen) continue;
      for (const std::string& key : other.names) {
        if (!map.has(key) || contains(chosen->names, key) || contains(reported, key)) continue;
        bool own = false;
        for (const Entry& e : entries_) own |= e.doc.name == key;
        if (own) continue;
        reported.push_back(key);
        map.error_at_key(key, "key " + config::quoted(key) + " is not used by " + doc_.selector_phrase + " " + config::quoted(selected));
        ok = false;
      }
    }
    return ok;
  }

  // The context a nested table of context C reads with: this one's, or none.
  template <class C>
  static C& child_context(Ctx& ctx) {
    if constexpr (std::is_same_v<C, Ctx>) {
      return ctx;
    } else {
      static_assert(std::is_same_v<C, NoContext>, "a nested table reads with its parent's context or none");
      static thread_local NoContext none;
      return none;
    }
  }
  static bool contains(const std::vector<std::string>& list, const std::string& value) {
    for (const std::string& item : list) {
      if (item == value) return true;
    }
    return false;
  }
  static std::string join_values(const std::vector<std::string>& values) {
    std::string out;
    for (std::size_t i = 0; i < values.size(); ++i) out += (i > 0 ? ", `" : "`") + values[i] + "`";
    return out;
  }

  std::vector<Entry> entries_;
  std::vector<Check> checks_;
  std::function<void(T&, Ctx&)> before_;
  Note note_;
  std::vector<std::string> extra_keys_;
  struct Part {
    std::string value;                // a variant's selector value ("" for a part)
    std::vector<std::string> names;  // its keys
    std::function<const TableDoc&()> doc;
    std::function<bool(const MapReader&, T&, Ctx&)> read;
    bool read_elsewhere = false;  // a part the table's owner reads
  };
  std::vector<Part> parts_;
  std::vector<Part> variants_;
  std::optional<std::size_t> selector_;
  std::shared_ptr<T> defaults_;
  TableDoc doc_;
  std::unique_ptr<DocOnce> doc_once_ = std::make_unique<DocOnce>();
};

// A table declared once, on first use: a table's owner writes
//   const KeyTable<AcousticsSpec>& acoustics_keys() {
//     return declare_keys<AcousticsSpec>([](KeyTable<AcousticsSpec>& t) {
//       t.describe("world.acoustics", "what sonars hear");
//       t.number(...)...;
//     });
//   }
// (with the defaults first when they are not a default-constructed T). Each call site's lambda has a type of
// its own, so each table is a function-local static of its own.
template <class T, class Ctx = NoContext, class Declare>
const KeyTable<T, Ctx>& declare_keys(T defaults, Declare declare) {
  static const KeyTable<T, Ctx> table = [&] {
    KeyTable<T, Ctx> t("", "", std::move(defaults));
    declare(t);
    return t;
  }();
  return table;
}
template <class T, class Ctx = NoContext, class Declare>
const KeyTable<T, Ctx>& declare_keys(Declare declare) {
  return declare_keys<T, Ctx>(T{}, std::move(declare));
}

// The vocabulary of a key declaration, for the .cc that declares a table: `using namespace config::keys;`.
namespace keys {
using config::declare_keys;
using config::KeyReads;
using config::KeyTable;
using config::LoadContext;
using config::MapReader;
using config::NoContext;
using config::Range;
using config::Value;
}  // namespace keys

}  // namespace hadal::config
