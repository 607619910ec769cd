// A closed set of kinds (sensor kinds, actuator kinds) as one list of types: the variants the model
// and the state hold, and a compile-time loop over the kinds for the one dispatch each layer makes
// (docs/ARCHITECTURE.md, "Kinds").
#pragma once

#include <variant>

namespace hadal {

template <class T>
struct KindTag {
  using type = T;
};

template <class... Kinds>
struct KindList {
  using Specs = std::variant<typename Kinds::Spec...>;
  using States = std::variant<typename Kinds::State...>;

  // f(KindTag<K>{}) for every kind K, in list order.
  template <class F>
  static void for_each(F&& f) {
    (f(KindTag<Kinds>{}), ...);
  }
};

}  // namespace hadal
